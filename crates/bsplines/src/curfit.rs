//! FITPACK's own smoothing fits, curfit (a function) and parcur (a curve of d coordinates)
//! (Dierckx, "Curve and Surface Fitting with Splines", 1993, ch. 5), step for step as the
//! routines SciPy's legacy doors call (`splrep`, `splprep`, `UnivariateSpline`), so that their
//! knots, coefficients, fp and ier are FITPACK's. SciPy's `make_splrep` re-derives the same
//! method with other bookkeeping and places knots elsewhere for the same data (`fitpack`
//! reproduces that one); the two differ in these places, all kept here as FITPACK has them:
//!
//! - a round adds nplus knots from one fit's residuals: after each knot the residual share of
//!   the interval it split is divided between its halves in proportion to their data points
//!   (fpknot), not fitted again;
//! - the knot intervals' data counts (nrdata) are carried from knot to knot, and from call to
//!   call when a search goes on (iopt = 1);
//! - fp of a least-squares fit is the sum of the squares the Givens rotations leave over,
//!   the coefficients by back substitution of the rotated triangle;
//! - the root finder for p and its rational step as fpcurf writes them.
//!
//! The fit, in two parts. Part 1 (the knots): from none inside [xb, xe] (or from where an
//! earlier search stopped), the weighted least-squares spline s_inf on the knots and
//! fp = sum_i (w_i (y_i - s_inf(x_i)))^2; stop when |fp - s| < s/1000, go to part 2 when
//! fp < s, else add knots at data points in the intervals whose share of fp is largest and fit
//! again (up to nest knots: ier 1; at m + k + 1 knots the spline interpolates: ier -1; the
//! polynomial already meets s: ier -2). Part 2 (the smoothness): on those knots, the spline
//! minimising
//!     sum_i (w_i (y_i - s(x_i)))^2 / p-weighted against sum_j (jump of s^(k) at t_j)^2
//! with p found where fp(p) = s by rational interpolation of f(p) = fp(p) - s (ier 2: f is
//! not monotone; ier 3: 20 iterations).

use crate::fitpack::{Data, TOLERANCE};

/// The most iterations of part 2's root finder (FITPACK's maxit).
pub(crate) const MAX_ITERATIONS: usize = 20;

/// Which of FITPACK's fit routines runs: they differ in how part 2 sums fp at the data
/// (curfit's and percur's sum_i (w_i (s_i - y_i))^2, or parcur's and clocur's
/// sum_i w_i^2 sum_j (s_ij - x_ij)^2: the same value, rounded otherwise) and in the root
/// finder's step constants (`steps`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Door {
    /// curfit (splrep, UnivariateSpline).
    Curfit,
    /// parcur (splprep).
    Parcur,
    /// percur (splrep with per=1).
    Percur,
    /// clocur (splprep with per=1).
    Clocur,
}

impl Door {
    /// The root finder's step constants (con1, con9, con4): 0.1, 0.9 and 0.04, which
    /// fppara.f, fpperi.f and fpclos.f write as single precision literals (`0.1e0`:
    /// 0.10000000149011612 in f64; with doubles their fits land 1e-10 from SciPy's);
    /// fpcurf.f's are double.
    pub(crate) fn steps(self) -> (f64, f64, f64) {
        match self {
            Door::Curfit => (0.1, 0.9, 0.04),
            Door::Parcur | Door::Percur | Door::Clocur => {
                (f64::from(0.1_f32), f64::from(0.9_f32), f64::from(0.04_f32))
            }
        }
    }

    /// fp with point it's residual added as the door adds it in part 2: the spline there
    /// from its B-splines q and the coefficients from l0 on.
    pub(crate) fn add_residual(
        self,
        mut fp: f64,
        q: &[f64],
        c: &[f64],
        l0: usize,
        data: &Data<'_>,
        it: usize,
    ) -> f64 {
        let (d, w) = (data.d, data.w[it]);
        if matches!(self, Door::Parcur | Door::Clocur) {
            let mut term = 0.0;
            for col in 0..d {
                let delta = value_at(q, c, d, l0, col) - data.y[it * d + col];
                term += delta * delta;
            }
            fp + term * w * w
        } else {
            for col in 0..d {
                fp += (w * (value_at(q, c, d, l0, col) - data.y[it * d + col])).powi(2);
            }
            fp
        }
    }
}

/// Where a knot search stopped, from which another search for another s goes on (curfit's
/// iopt = 1: SciPy's `set_smoothing_factor` and splrep's task = 1): the knots, each knot
/// interval's count of data points strictly inside it, fp of the polynomial (fp0), fp of the
/// knot set before the last (fpold), the knots added last (nplus), and ier as it stood.
#[derive(Clone, Debug, PartialEq)]
pub struct Search {
    /// The knots, 2k + 2 of them at the ends.
    pub t: Vec<f64>,
    /// Data points strictly inside each knot interval of [xb, xe].
    pub nrdata: Vec<usize>,
    /// fp of the least-squares polynomial.
    pub fp0: f64,
    /// fp of the knot set before the last.
    pub fpold: f64,
    /// The knots the last round added.
    pub nplus: usize,
    /// FITPACK's ier when it stopped.
    pub ier: i32,
}

/// A fit: the knots, the coefficients (len(t) - k - 1 rows of d), the weighted sum of squared
/// residuals fp, FITPACK's ier (-2 the least-squares polynomial, -1 interpolation, 0 fp
/// within s/1000 of s, 1 nest knots were not enough (the least-squares spline on them),
/// 2 and 3 part 2 stopped short), and where its knot search stopped.
#[derive(Clone, Debug)]
pub struct Fit {
    /// The knots.
    pub t: Vec<f64>,
    /// The coefficients, rows of d.
    pub c: Vec<f64>,
    /// sum_i (w_i |y_i - s(x_i)|)^2.
    pub fp: f64,
    /// FITPACK's ier.
    pub ier: i32,
    /// The search's state, for a search that goes on from here.
    pub search: Search,
}

/// FITPACK's Givens rotation (fpgivs) that zeroes piv against ww: (cos, sin), ww replaced by
/// sqrt(piv^2 + ww^2) computed without overflow. `lsq::givens` (one square root of the sum,
/// one division) is faster and rounds otherwise; FITPACK's knots follow these roundings.
pub(crate) fn givens(piv: f64, ww: &mut f64) -> (f64, f64) {
    let store = piv.abs();
    let dd = if store >= *ww {
        store * (1.0 + (*ww / piv) * (*ww / piv)).sqrt()
    } else {
        *ww * (1.0 + (piv / *ww) * (piv / *ww)).sqrt()
    };
    let rotation = (*ww / dd, piv / dd);
    *ww = dd;
    rotation
}

/// Applies a Givens rotation to the pair (a, b) (fprota).
pub(crate) fn rotate((cos, sin): (f64, f64), a: &mut f64, b: &mut f64) {
    let rotated = cos * *a - sin * *b;
    *b = cos * *b + sin * *a;
    *a = rotated;
}

/// The k + 1 B-splines not zero at x in [t_l, t_{l+1}) (l 0-based), by the Cox–de Boor
/// recurrence as fpbspl runs it (a zero where two knots coincide; `lsq::BasisRows` runs
/// de Boor's BSPLVB form, rounded otherwise).
pub(crate) fn basis(t: &[f64], k: usize, x: f64, l: usize, h: &mut [f64; 6]) {
    let mut hh = [0.0; 6];
    h[0] = 1.0;
    for j in 1..=k {
        hh[..j].copy_from_slice(&h[..j]);
        h[0] = 0.0;
        for i in 1..=j {
            let (li, lj) = (l + i, l + i - j);
            if t[li] == t[lj] {
                h[i] = 0.0;
            } else {
                let f = hh[i - 1] / (t[li] - t[lj]);
                h[i - 1] += f * (t[li] - x);
                h[i] = f * (x - t[lj]);
            }
        }
    }
}

/// An upper triangular band matrix of `rows` rows and `width` columns a row (the diagonal
/// first), with d right-hand sides a row.
#[derive(Clone)]
struct Band {
    width: usize,
    a: Vec<f64>,
    z: Vec<f64>,
}

impl Band {
    fn zeroed(rows: usize, width: usize, d: usize) -> Self {
        Self {
            width,
            a: vec![0.0; rows * width],
            z: vec![0.0; rows * d],
        }
    }

    /// The same rows in a wider band (the new columns zero).
    fn widened(&self, width: usize, d: usize) -> Self {
        let rows = self.a.len() / self.width;
        let mut out = Self::zeroed(rows, width, d);
        for (to, from) in out
            .a
            .chunks_exact_mut(width)
            .zip(self.a.chunks_exact(self.width))
        {
            to[..self.width].copy_from_slice(from);
        }
        out.z.copy_from_slice(&self.z);
        out
    }

    /// The coefficients by back substitution (fpback), rows of d.
    fn back_substitute(&self, d: usize) -> Vec<f64> {
        let rows = self.a.len() / self.width;
        let mut c = vec![0.0; rows * d];
        for col in 0..d {
            for i in (0..rows).rev() {
                let row = &self.a[i * self.width..(i + 1) * self.width];
                let mut store = self.z[i * d + col];
                for l in 1..self.width.min(rows - i) {
                    store -= c[(i + l) * d + col] * row[l];
                }
                c[i * d + col] = store / row[0];
            }
        }
        c
    }
}

/// One least-squares fit on the knots t: the rotated triangle, the B-splines at each point
/// (q, k + 1 a point, unweighted) and fp, the sum of the squares the rotations leave over.
struct LeastSquares {
    band: Band,
    q: Vec<f64>,
    fp: f64,
}

fn least_squares(data: &Data<'_>, t: &[f64], k: usize) -> LeastSquares {
    let (k1, d, n) = (k + 1, data.d, t.len());
    let nk1 = n - k1;
    let mut band = Band::zeroed(nk1, k1, d);
    let mut q = vec![0.0; data.x.len() * k1];
    let (mut fp, mut l) = (0.0, k);
    let mut h = [0.0; 6];
    let mut rhs = [0.0; 10];
    for (it, &xi) in data.x.iter().enumerate() {
        let wi = data.w[it];
        for (r, &y) in rhs.iter_mut().zip(&data.y[it * d..(it + 1) * d]) {
            *r = y * wi;
        }
        while !(xi < t[l + 1] || l + 1 == nk1) {
            l += 1;
        }
        basis(t, k, xi, l, &mut h);
        q[it * k1..(it + 1) * k1].copy_from_slice(&h[..k1]);
        for v in &mut h[..k1] {
            *v *= wi;
        }
        let first = l - k;
        for i in 0..k1 {
            let j = first + i;
            let piv = h[i];
            if piv == 0.0 {
                continue;
            }
            let row = &mut band.a[j * k1..(j + 1) * k1];
            let rotation = givens(piv, &mut row[0]);
            for (r, z) in rhs[..d].iter_mut().zip(&mut band.z[j * d..(j + 1) * d]) {
                rotate(rotation, r, z);
            }
            for i1 in i + 1..k1 {
                rotate(rotation, &mut h[i1], &mut row[i1 - i]);
            }
        }
        for r in &rhs[..d] {
            fp += r * r;
        }
    }
    LeastSquares { band, q, fp }
}

/// The spline's value at point it (its B-splines q, the first of its k + 1 coefficients l0),
/// coordinate col.
pub(crate) fn value_at(q: &[f64], c: &[f64], d: usize, l0: usize, col: usize) -> f64 {
    let mut fac = 0.0;
    for (j, b) in q.iter().enumerate() {
        fac += c[(l0 + j) * d + col] * b;
    }
    fac
}

/// Each knot interval's share of fp (fpint): a point at an inner knot counts half to each
/// side, the points past the last inner knot to the last interval.
fn shares(data: &Data<'_>, t: &[f64], k: usize, fit: &LeastSquares, c: &[f64]) -> Vec<f64> {
    let (k1, d) = (k + 1, data.d);
    let nk1 = t.len() - k1;
    let mut out = Vec::with_capacity(nk1 - k);
    let (mut fpart, mut l) = (0.0, k + 1);
    for (it, &x) in data.x.iter().enumerate() {
        let new = x >= t[l] && l < nk1;
        if new {
            l += 1;
        }
        let q = &fit.q[it * k1..(it + 1) * k1];
        let mut term = 0.0;
        for col in 0..d {
            let fac = value_at(q, c, d, l - k - 1, col);
            term += (data.w[it] * (fac - data.y[it * d + col])).powi(2);
        }
        fpart += term;
        if new {
            let store = term * 0.5;
            out.push(fpart - store);
            fpart = store;
        }
    }
    out.push(fpart);
    out
}

/// FITPACK's new knot (fpknot): the data point in the middle of the first interval of the
/// largest share among those with data inside; its share and count split between the halves
/// in proportion to their counts. False, adding nothing, where no interval holds a point
/// inside (see `smoothing_fit`).
pub(crate) fn add_knot(
    x: &[f64],
    t: &mut Vec<f64>,
    k: usize,
    fpint: &mut Vec<f64>,
    nrdata: &mut Vec<usize>,
) -> bool {
    let (mut fpmax, mut found) = (0.0, None);
    let mut jbegin = 0;
    for (j, (&share, &count)) in fpint.iter().zip(nrdata.iter()).enumerate() {
        if fpmax < share && count != 0 {
            fpmax = share;
            found = Some((j, jbegin));
        }
        jbegin += count + 1;
    }
    let Some((number, maxbeg)) = found else {
        return false;
    };
    let maxpt = nrdata[number];
    let ihalf = maxpt / 2 + 1;
    let (left, right) = (ihalf - 1, maxpt - ihalf);
    let am = maxpt as f64;
    nrdata[number] = left;
    nrdata.insert(number + 1, right);
    fpint[number] = fpmax * left as f64 / am;
    fpint.insert(number + 1, fpmax * right as f64 / am);
    t.insert(number + k + 1, x[maxbeg + ihalf]);
    true
}

/// Adds up to `nplus` knots one at a time (`add_knot`, on the shares fpint and counts nrdata):
/// at `nmax` knots the knots of interpolation take over (`interpolation`), at `nest` it stops.
/// Returns whether any knot was added (none where no interval has a point inside).
pub(crate) fn add_knots(
    x: &[f64],
    t: &mut Vec<f64>,
    k: usize,
    (fpint, nrdata): (&mut Vec<f64>, &mut Vec<usize>),
    nplus: usize,
    (nmax, nest): (usize, usize),
    interpolation: impl Fn() -> Vec<f64>,
) -> bool {
    let before = t.len();
    for _ in 0..nplus {
        if !add_knot(x, t, k, fpint, nrdata) {
            break;
        }
        if t.len() == nmax {
            *t = interpolation();
            break;
        }
        if t.len() == nest {
            break;
        }
    }
    t.len() > before
}

impl Fit {
    /// A finished fit on the knots t, the search's state as FITPACK keeps it from the last
    /// least-squares fit (`kept`: fp0, fpold, nplus) with the fit's ier.
    pub(crate) fn stopped(
        t: Vec<f64>,
        (c, fp, ier): (Vec<f64>, f64, i32),
        nrdata: Vec<usize>,
        (fp0, fpold, nplus): (f64, f64, usize),
    ) -> Self {
        let search = Search {
            t: t.clone(),
            nrdata,
            fp0,
            fpold,
            nplus,
            ier,
        };
        Self {
            t,
            c,
            fp,
            ier,
            search,
        }
    }
}

/// The knots of interpolation (m + k + 1): the data inside for odd k, their midpoints for
/// even k, k / 2 + 1 of them left out at each end; the ends as the caller sets them.
pub(crate) fn interpolation_knots(x: &[f64], k: usize, xb: f64, xe: f64) -> Vec<f64> {
    let m = x.len();
    let mut t = vec![xb; k + 1];
    let start = k / 2 + 1;
    for j in start..start + (m - k - 1) {
        t.push(if k.is_multiple_of(2) {
            (x[j] + x[j - 1]) * 0.5
        } else {
            x[j]
        });
    }
    t.extend(std::iter::repeat_n(xe, k + 1));
    t
}

/// FITPACK's discontinuity rows (fpdisc): for each inner knot, the jumps of the k-th
/// derivatives of the k + 2 B-splines around it, scaled by (nrint / (xe - xb))^k.
pub(crate) fn discontinuity(t: &[f64], k: usize) -> Vec<[f64; 7]> {
    let (k1, k2, n) = (k + 1, k + 2, t.len());
    let nk1 = n - k1;
    let fac = (nk1 - k) as f64 / (t[nk1] - t[k]);
    let mut rows = Vec::with_capacity(nk1 - k1);
    for l in k1..nk1 {
        let mut h = [0.0; 12];
        for j in 0..k1 {
            h[j] = t[l] - t[l + j - k1];
            h[j + k1] = t[l] - t[l + j + 1];
        }
        let mut row = [0.0; 7];
        for (j, b) in row.iter_mut().enumerate().take(k2) {
            let mut prod = h[j];
            for hh in &h[j + 1..j + 1 + k] {
                prod = prod * hh * fac;
            }
            let lp = l - k1 + j;
            *b = (t[lp + k1] - t[lp]) / prod;
        }
        rows.push(row);
    }
    rows
}

/// FITPACK's rational step (fprati): the zero of the r(p) = (u p + v) / (p + w) through the
/// three points (p3 < 0 standing for infinity); then (p1, f1) or (p3, f3) becomes (p2, f2),
/// keeping f1 > 0 > f3.
fn rational_step(p1: &mut f64, f1: &mut f64, p2: f64, f2: f64, p3: &mut f64, f3: &mut f64) -> f64 {
    let p = if *p3 > 0.0 {
        let h1 = *f1 * (f2 - *f3);
        let h2 = f2 * (*f3 - *f1);
        let h3 = *f3 * (*f1 - f2);
        -(*p1 * p2 * h3 + p2 * *p3 * h1 + *p3 * *p1 * h2) / (*p1 * h1 + p2 * h2 + *p3 * h3)
    } else {
        (*p1 * (*f1 - *f3) * f2 - p2 * (f2 - *f3) * *f1) / ((*f1 - f2) * *f3)
    };
    if f2 < 0.0 {
        (*p3, *f3) = (p2, f2);
    } else {
        (*p1, *f1) = (p2, f2);
    }
    p
}

/// fp at the data of the spline with coefficients c, summed as the door sums it.
fn sum_at_data(data: &Data<'_>, t: &[f64], k: usize, q: &[f64], c: &[f64], door: Door) -> f64 {
    let k1 = k + 1;
    let nk1 = t.len() - k1;
    let (mut fp, mut l) = (0.0, k + 1);
    for (it, &x) in data.x.iter().enumerate() {
        if x >= t[l] && l < nk1 {
            l += 1;
        }
        fp = door.add_residual(fp, &q[it * k1..(it + 1) * k1], c, l - k - 1, data, it);
    }
    fp
}

/// Part 2: on the knots t (whose least-squares fit is `fit`, fp - s = fpms > 0 at p = 0 and
/// < 0 at infinity), the spline with fp(p) within s/1000 of s. Returns (c, fp, ier).
fn smooth(
    data: &Data<'_>,
    t: &[f64],
    k: usize,
    s: f64,
    (fp0, fpms): (f64, f64),
    fit: &LeastSquares,
    door: Door,
) -> (Vec<f64>, f64, i32) {
    let (k1, k2, d) = (k + 1, k + 2, data.d);
    let nk1 = t.len() - k1;
    let n8 = t.len() - 2 * k1;
    let jumps = discontinuity(t, k);
    let diagonal: f64 = (0..nk1).map(|i| fit.band.a[i * k1]).sum();
    let spline_for = |p: f64| {
        let pinv = 1.0 / p;
        let mut g = fit.band.widened(k2, d);
        let mut rhs = [0.0; 10];
        for (it, jump) in jumps.iter().enumerate() {
            let mut h = [0.0; 7];
            for (hv, b) in h.iter_mut().zip(&jump[..k2]) {
                *hv = b * pinv;
            }
            rhs[..d].fill(0.0);
            for j in it..nk1 {
                let row = &mut g.a[j * k2..(j + 1) * k2];
                let rotation = givens(h[0], &mut row[0]);
                for (r, c) in rhs[..d].iter_mut().zip(&mut g.z[j * d..(j + 1) * d]) {
                    rotate(rotation, r, c);
                }
                if j + 1 == nk1 {
                    break;
                }
                let i2 = if j + 1 > n8 { nk1 - j - 1 } else { k1 };
                for i in 1..=i2 {
                    rotate(rotation, &mut h[i], &mut row[i]);
                    h[i - 1] = h[i];
                }
                h[i2] = 0.0;
            }
        }
        let c = g.back_substitute(d);
        let fp = sum_at_data(data, t, k, &fit.q, &c, door);
        (c, fp)
    };
    find_p(
        spline_for,
        nk1 as f64 / diagonal,
        (fp0, fpms),
        (s, TOLERANCE * s),
        door.steps(),
        MAX_ITERATIONS,
    )
}

/// Part 2's search for p (FITPACK's, in every fit routine alike): from p0, the spline of p
/// (`spline_for`: coefficients and fp) until |fp - s| < acc, stepping by the routine's
/// constants (con1, con9, con4) until p is bracketed between f1 = fp0 - s > 0 (p1 = 0) and
/// f3 < 0 (p3, at first infinity: fpms), then by the rational step. Returns (c, fp, ier):
/// ier 0, 2 (f not decreasing as theory says) or 3 (maxit iterations), the last spline
/// standing.
pub(crate) fn find_p(
    mut spline_for: impl FnMut(f64) -> (Vec<f64>, f64),
    p0: f64,
    (fp0, fpms): (f64, f64),
    (s, acc): (f64, f64),
    (con1, con9, con4): (f64, f64, f64),
    maxit: usize,
) -> (Vec<f64>, f64, i32) {
    let (mut p1, mut f1, mut p3, mut f3) = (0.0, fp0 - s, -1.0, fpms);
    let (mut ich1, mut ich3) = (false, false);
    let mut p = p0;
    let mut iteration = 1;
    loop {
        let (c, fp) = spline_for(p);
        let f2 = fp - s;
        if f2.abs() < acc {
            return (c, fp, 0);
        }
        if iteration == maxit {
            return (c, fp, 3);
        }
        iteration += 1;
        let p2 = p;
        if !ich3 {
            if f2 - f3 > acc {
                ich3 = f2 < 0.0;
            } else {
                // p too large.
                (p3, f3) = (p2, f2);
                p *= con4;
                if p <= p1 {
                    p = p1 * con9 + p2 * con1;
                }
                continue;
            }
        }
        if !ich1 {
            if f1 - f2 > acc {
                ich1 = f2 > 0.0;
            } else {
                // p too small.
                (p1, f1) = (p2, f2);
                p /= con4;
                if p3 >= 0.0 && p >= p3 {
                    p = p2 * con1 + p3 * con9;
                }
                continue;
            }
        }
        if f2 >= f1 || f2 <= f3 {
            return (c, fp, 2);
        }
        p = rational_step(&mut p1, &mut f1, p2, f2, &mut p3, &mut f3);
    }
}

/// FITPACK's count of knots to add next (fpcurf): in proportion to how far fp is above s
/// against how far the last knots brought it down, at most twice and at least half the last
/// count and 1.
pub(crate) fn knots_to_add(nplus: usize, fpms: f64, fall: f64, acc: f64) -> usize {
    let npl1 = if fall > acc {
        let val = nplus as f64 * fpms / fall;
        if val > f64::from(i32::MAX) {
            i32::MAX as usize
        } else {
            val as usize
        }
    } else {
        nplus * 2
    };
    (nplus * 2).min(npl1.max(nplus / 2).max(1))
}

/// FITPACK's smoothing fit with s > 0 (curfit's, or parcur's with `Door::Parcur`) of the data
/// (x increasing, w > 0 where parcur asks, [xb, xe] around x), with at most `nest` knots, from
/// the polynomial, or on from `from` (iopt = 1), as the module describes. The caller has
/// checked the data as FITPACK does (`fitpack::check`), s > 0, 1 <= k <= 5, d <= 10 and
/// nest >= 2k + 2.
pub fn smoothing_fit(
    data: &Data<'_>,
    k: usize,
    s: f64,
    nest: usize,
    from: Option<&Search>,
    door: Door,
) -> Fit {
    let (k1, m) = (k + 1, data.x.len());
    let (nmin, nmax) = (2 * k1, m + k1);
    let acc = TOLERANCE * s;
    let mut t = vec![data.xb; k1];
    t.resize(nmin, data.xe);
    let (mut nrdata, mut fp0, mut fpold, mut nplus, mut ier) =
        (vec![m.saturating_sub(2)], 0.0, 0.0, 0, 0);
    if let Some(earlier) = from.filter(|e| e.t.len() != nmin && e.fp0 > s) {
        t.clone_from(&earlier.t);
        nrdata.clone_from(&earlier.nrdata);
        (fp0, fpold, nplus, ier) = (earlier.fp0, earlier.fpold, earlier.nplus, earlier.ier);
    }
    // Every round adds a knot or stops, and n stops at nest or m + k + 1: FITPACK's bound of
    // m rounds is a guard (past it, part 2 on the last fit's knots, as FITPACK goes on).
    let mut round = 0;
    loop {
        let n = t.len();
        if n == nmin {
            ier = -2;
        }
        t[..k1].fill(data.xb);
        t[n - k1..].fill(data.xe);
        let fit = least_squares(data, &t, k);
        if ier == -2 {
            fp0 = fit.fp;
        }
        let c = fit.band.back_substitute(data.d);
        let fpms = fit.fp - s;
        // What FITPACK keeps of this fit for a search that goes on (fpint(n), fpint(n - 1),
        // nrdata(n)).
        let kept = (fp0, fpold, nplus);
        let ending = if fpms.abs() < acc {
            Some(ier)
        } else if fpms < 0.0 || round == m {
            None
        } else if n == nmax {
            Some(-1)
        } else if n == nest {
            Some(1)
        } else {
            if ier == 0 {
                nplus = knots_to_add(nplus, fpms, fpold - fit.fp, acc);
            } else {
                (nplus, ier) = (1, 0);
            }
            fpold = fit.fp;
            let mut fpint = shares(data, &t, k, &fit, &c);
            let interpolation = || interpolation_knots(data.x, k, data.xb, data.xe);
            let shares = (&mut fpint, &mut nrdata);
            if add_knots(
                data.x,
                &mut t,
                k,
                shares,
                nplus,
                (nmax, nest),
                interpolation,
            ) {
                round += 1;
                continue;
            }
            // No interval has a data point inside: part 2 on these knots (fp > s, so it
            // stops short: ier 2 or 3).
            None
        };
        let answer = match ending {
            Some(ier) => (c, fit.fp, ier),
            None if ier == -2 => (c, fit.fp, ier),
            None => smooth(data, &t, k, s, (fp0, fpms), &fit, door),
        };
        return Fit::stopped(t, answer, nrdata, kept);
    }
}

#[cfg(test)]
mod tests {
    use super::{Door, Fit, smoothing_fit};
    use crate::BSpline;
    use crate::fitpack::Data;

    /// 200 points of sin x with a deterministic wobble of about 0.1.
    fn wobbly() -> (Vec<f64>, Vec<f64>) {
        let x: Vec<f64> = (0..200).map(|i| f64::from(i) * 0.05).collect();
        let y = x
            .iter()
            .enumerate()
            .map(|(i, v)| v.sin() + 0.1 * ((i * 7919 % 101) as f64 / 50.0 - 1.0))
            .collect();
        (x, y)
    }

    fn data<'a>(x: &'a [f64], y: &'a [f64], w: &'a [f64]) -> Data<'a> {
        Data {
            x,
            y,
            d: 1,
            w,
            xb: x[0],
            xe: x[x.len() - 1],
        }
    }

    /// sum (w_i (y_i - s(x_i)))^2 by de Boor's evaluation, independent of the rotations.
    fn residual(fit: &Fit, x: &[f64], y: &[f64], k: usize) -> f64 {
        let spline = BSpline::new(fit.t.clone(), fit.c.clone(), k, 1).unwrap();
        let values = spline.evaluate(x, 0);
        values.iter().zip(y).map(|(s, y)| (y - s).powi(2)).sum()
    }

    /// Data on a line: the least-squares polynomial already meets s (ier -2), its coefficients
    /// the line's values at the Greville abscissae.
    #[test]
    fn a_line_is_its_own_polynomial() {
        let x: Vec<f64> = (0..20).map(f64::from).collect();
        let y: Vec<f64> = x.iter().map(|v| 0.5 * v + 1.0).collect();
        let w = vec![1.0; 20];
        let fit = smoothing_fit(&data(&x, &y, &w), 3, 0.1, 24, None, Door::Curfit);
        assert_eq!((fit.t.len(), fit.ier), (8, -2));
        for (j, c) in fit.c.iter().enumerate() {
            let at = 19.0 * j as f64 / 3.0;
            assert!((c - (0.5 * at + 1.0)).abs() < 1e-12, "{j}: {c}");
        }
    }

    /// A smoothing fit meets s within FITPACK's tolerance, and its fp is the residual at the
    /// data; going on with a larger s keeps the knots (iopt = 1), with a smaller one adds.
    #[test]
    fn fits_meet_s_and_a_search_goes_on_from_its_knots() {
        let (x, y) = wobbly();
        let w = vec![1.0; x.len()];
        let data = data(&x, &y, &w);
        for k in [1, 3, 5] {
            let s = 1.0;
            let fit = smoothing_fit(&data, k, s, x.len() + k + 1, None, Door::Curfit);
            assert_eq!(fit.ier, 0);
            assert!((fit.fp - s).abs() < 1e-3 * s, "k {k}: fp {}", fit.fp);
            let independent = residual(&fit, &x, &y, k);
            assert!(
                (independent - fit.fp).abs() < 1e-9 * s,
                "{independent} {}",
                fit.fp
            );
            let larger = smoothing_fit(&data, k, 2.0 * s, 300, Some(&fit.search), Door::Curfit);
            assert_eq!(larger.t, fit.t);
            assert!((larger.fp - 2.0 * s).abs() < 2e-3 * s);
            let smaller = smoothing_fit(&data, k, s / 2.0, 300, Some(&fit.search), Door::Curfit);
            assert!(fit.t.iter().all(|v| smaller.t.contains(v)));
            assert!(smaller.t.len() > fit.t.len());
        }
    }

    /// Too little room for knots: the least-squares spline on nest knots, ier 1; going on
    /// with room for all of them reaches s.
    #[test]
    fn too_little_room_stops_at_nest_and_goes_on() {
        let (x, y) = wobbly();
        let w = vec![1.0; x.len()];
        let data = data(&x, &y, &w);
        let cramped = smoothing_fit(&data, 3, 0.2, 12, None, Door::Curfit);
        assert_eq!((cramped.t.len(), cramped.ier), (12, 1));
        assert!(cramped.fp > 0.2);
        let roomy = smoothing_fit(&data, 3, 0.2, 204, Some(&cramped.search), Door::Curfit);
        assert_eq!(roomy.ier, 0);
        assert!((roomy.fp - 0.2).abs() < 2e-4);
    }

    /// Spikes on zeros, k = 1 (SciPy's gh-3691): every interval with a point inside fits it
    /// exactly, so no knot can be placed where FITPACK would look; the fit stays finite.
    #[test]
    fn no_interval_left_to_split_keeps_the_fit_finite() {
        let x: Vec<f64> = (0..109).map(f64::from).collect();
        let y = [
            0., 0., 0., 0., 0., 10.9, 0., 11., 0., 0., 0., 10.9, 0., 0., 0., 0., 0., 0., 10.9, 0.,
            0., 0., 11., 0., 0., 0., 10.9, 0., 0., 0., 10.5, 0., 0., 0., 10.7, 0., 0., 0., 11., 0.,
            0., 0., 0., 0., 0., 10.9, 0., 0., 10.7, 0., 0., 0., 10.6, 0., 0., 0., 10.5, 0., 0.,
            10.7, 0., 0., 10.5, 0., 0., 11.5, 0., 0., 0., 10.7, 0., 0., 10.7, 0., 0., 10.9, 0., 0.,
            10.8, 0., 0., 0., 10.7, 0., 0., 10.6, 0., 0., 0., 10.4, 0., 0., 10.6, 0., 0., 10.5, 0.,
            0., 0., 10.7, 0., 0., 0., 10.4, 0., 0., 0., 10.8, 0.,
        ];
        let w = vec![1.0; 109];
        let data = data(&x, &y, &w);
        let first = smoothing_fit(&data, 1, 109.0, 54, None, Door::Curfit);
        let fit = smoothing_fit(&data, 1, 109.0, 111, Some(&first.search), Door::Curfit);
        assert!(fit.c.iter().all(|c| c.is_finite()));
        assert!((residual(&fit, &x, &y, 1) - fit.fp).abs() < 1e-9 * fit.fp);
    }
}
