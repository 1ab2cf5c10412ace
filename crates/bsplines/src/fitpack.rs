//! Smoothing splines with FITPACK's knot placement (SciPy's `make_splrep` and
//! `make_splprep`, the curfit and parcur algorithms of Dierckx), non-periodic: the spline s
//! of degree k with the fewest knots FITPACK's search finds such that
//!     fp = sum_i w_i^2 |y_i - s(x_i)|^2 <= s_target   (|.| over the curve's d coordinates),
//! then, on those knots, the smoothest spline with fp = s_target.
//!
//! 1. Knots: from none inside [xb, xe], least squares fits, adding knots where the residual
//!    is largest (`new_knot`: the middle data point of the knot interval whose share of the
//!    residual is largest), nplus at a time (FITPACK's rule from how fp fell), until fp is
//!    within s_target's tolerance, the knots reach `nest`, or they would interpolate (then
//!    the not-a-knot knots).
//! 2. Smoothness: minimise the jumps of s^(k) at the inner knots (the discontinuity rows,
//!    `discontinuity`) weighted by 1/p against fp: the data triangle of the least squares fit
//!    with the jump rows / p rotated in, for p found by FITPACK's rational root finder
//!    (`root_rati`) where fp(p) = s_target (within s_target / 1000).
//!
//! Every step, tolerance and tie as SciPy's `_fitpack_repro` (SciPy 1.17), so that the same
//! data and s give the same knots and coefficients. SciPy's legacy doors (splrep, splprep,
//! UnivariateSpline) run FITPACK's Fortran itself, whose bookkeeping places knots elsewhere:
//! `curfit` reproduces that one.

use crate::InputError;
use crate::interp::not_a_knot;
use crate::lsq::{self, BasisRows, Triangle};

/// FITPACK's tolerance on fp (relative to s) and its most root-finding iterations.
pub const TOLERANCE: f64 = 0.001;
const MAX_ITERATIONS: usize = 20;

/// One curve's data: x increasing, y (m rows of d), w >= 0, the interval [xb, xe].
#[derive(Clone, Copy, Debug)]
pub struct Data<'a> {
    /// The abscissae, non-decreasing.
    pub x: &'a [f64],
    /// The values, len(x) rows of d.
    pub y: &'a [f64],
    /// Coordinates per point.
    pub d: usize,
    /// One weight per x (>= 0).
    pub w: &'a [f64],
    /// The interval's start (<= x_0).
    pub xb: f64,
    /// The interval's end (>= x_last).
    pub xe: f64,
}

/// Why a fit failed.
#[derive(Debug, PartialEq)]
pub enum Failure {
    /// A least-squares system was singular (FITPACK's ier = 1 territory).
    Singular,
}

/// A fitted spline: knots and coefficients (len(t) - k - 1 rows of d), and FITPACK's ier of
/// the root finder (0 converged, 2 or 3 stopped; SciPy warns, the spline stands).
#[derive(Clone, Debug)]
pub struct Spline {
    /// The knots.
    pub t: Vec<f64>,
    /// The coefficients, len(t) - k - 1 rows of d.
    pub c: Vec<f64>,
    /// The root finder's ier.
    pub ier: u8,
}

/// Each point's w_i^2 |y_i - s(x_i)|^2 and their sum, for the spline with coefficients c
/// (rows of d) on the knots of `rows`.
pub fn residuals(data: &Data<'_>, rows: &BasisRows, c: &[f64]) -> (Vec<f64>, f64) {
    let d = data.d;
    let mut out = Vec::with_capacity(data.x.len());
    let mut total = 0.0;
    for i in 0..data.x.len() {
        let (first, h) = rows.row(i);
        let mut sum = 0.0;
        for col in 0..d {
            let value: f64 = h
                .iter()
                .enumerate()
                .map(|(r, b)| b * c[(first + r) * d + col])
                .sum();
            let delta = data.y[i * d + col] - value;
            sum += delta * delta;
        }
        let r = data.w[i] * data.w[i] * sum;
        total += r;
        out.push(r);
    }
    (out, total)
}

/// The least-squares fit on t: its coefficients, residuals and their sum; by the normal
/// equations where they are positive definite (`lsq::normal_fit`: the knot search reads only
/// the residuals), by Givens rotations otherwise.
fn least_squares(
    data: &Data<'_>,
    t: &[f64],
    k: usize,
) -> Result<(Vec<f64>, Vec<f64>, f64), Failure> {
    let rows = BasisRows::new(data.x, t, k);
    let columns = t.len() - k - 1;
    let c = match lsq::normal_fit(&rows, data.y, data.d, data.w, columns) {
        Some(c) => c,
        None => {
            let (tri, _) = lsq::triangle(&rows, data.y, data.d, data.w, columns, k + 1);
            tri.back_substitute().ok_or(Failure::Singular)?
        }
    };
    let (each, total) = residuals(data, &rows, &c);
    if total.is_nan() {
        return Err(Failure::Singular);
    }
    Ok((c, each, total))
}

/// FITPACK's new knot: the residuals split into the knot intervals [t_k, ..., t_{n-k-1}]
/// (the point at an inner knot shared half and half, the last point in the last interval;
/// checked against SciPy's `_dierckx.fpknot` on 3,000 random knot vectors, ends inside and
/// outside the data);
/// of the intervals holding more than one data index, the first with the largest share; its
/// middle data point (rounded up) is the knot, inserted in order.
pub fn with_new_knot(x: &[f64], t: &[f64], k: usize, residuals: &[f64]) -> Vec<f64> {
    let bounds = &t[k..t.len() - k];
    // Each knot's first data index (the last point's at most, where xe lies past the data).
    let last = x.len() - 1;
    let index: Vec<usize> = bounds
        .iter()
        .map(|&b| x.partition_point(|&v| v < b).min(last))
        .collect();
    let intervals = index.len() - 1;
    let mut parts: Vec<f64> = (0..intervals)
        .map(|i| residuals[index[i]..index[i + 1]].iter().sum())
        .collect();
    for i in 0..intervals.saturating_sub(1) {
        let carry = residuals.get(index[i + 1]).copied().unwrap_or(0.0) / 2.0;
        parts[i] += carry;
        parts[i + 1] -= carry;
    }
    parts[intervals - 1] += residuals[residuals.len() - 1];
    let mut best: Option<usize> = None;
    for i in 0..intervals {
        if index[i + 1] - index[i] > 1 && best.is_none_or(|b| parts[i] > parts[b]) {
            best = Some(i);
        }
    }
    // An interval of more than one data index always exists while knots can be added (the
    // callers stop at m + k + 1 knots).
    let i = best.unwrap_or(intervals - 1);
    let knot = x[(index[i] + index[i + 1]).div_ceil(2)];
    let at = t.partition_point(|&v| v < knot);
    let mut out = Vec::with_capacity(t.len() + 1);
    out.extend_from_slice(&t[..at]);
    out.push(knot);
    out.extend_from_slice(&t[at..]);
    out
}

/// Where FITPACK's knot search stands: its knots, the fp of the set before them and the
/// number of knots it added last (curfit's fpint(n - 1) and nrdata(n)).
#[derive(Clone, Debug)]
pub struct Search {
    /// The knots where the search stands.
    pub t: Vec<f64>,
    /// fp of the knot set before `t`.
    pub fpold: f64,
    /// The knots the search added last.
    pub nplus: usize,
}

/// The knots of FITPACK's search for fp <= s from the polynomial (step 1 of the module's
/// description).
pub fn knots(data: &Data<'_>, k: usize, s: f64, nest: usize) -> Result<Vec<f64>, Failure> {
    let m = data.x.len();
    let t: Vec<f64> = std::iter::repeat_n(data.xb, k + 1)
        .chain(std::iter::repeat_n(data.xe, k + 1))
        .collect();
    let rules = Rules {
        s,
        nest,
        nmax: m + k + 1,
        least_squares: &|t| least_squares(data, t, k).map(|(_, each, fp)| (each, fp)),
        ends: &|_| {},
        interpolation: &|| not_a_knot(data.x, k),
    };
    let start = Search {
        t,
        fpold: 0.0,
        nplus: 1,
    };
    Ok(search(data.x, k, &rules, start)?.t)
}

/// A least-squares fit on knots t: each point's residual and their sum, fp.
pub type LeastSquares<'a> = dyn Fn(&[f64]) -> Result<(Vec<f64>, f64), Failure> + 'a;

/// What differs between curfit's knot search and percur's (`search`): the least-squares
/// fit on t (each point's residual and fp), the knots outside [xb, xe] set before each fit
/// (percur's periodic ends), and the knots of interpolation; s, nest and nmax.
#[expect(
    missing_debug_implementations,
    reason = "it holds the closures of one search"
)]
pub struct Rules<'a> {
    /// The smoothing target.
    pub s: f64,
    /// The most knots the search may place.
    pub nest: usize,
    /// The knots of interpolation (the search stops there).
    pub nmax: usize,
    /// The least-squares fit on given knots: each point's residual and fp.
    pub least_squares: &'a LeastSquares<'a>,
    /// Sets the knots outside [xb, xe] before each fit.
    pub ends: &'a dyn Fn(&mut [f64]),
    /// The knots of interpolation.
    pub interpolation: &'a dyn Fn() -> Vec<f64>,
}

/// FITPACK's count of knots to add next, from the count added last (nplus), how far fp is
/// above s (fpms) and how far the last knots brought it down (delta): in proportion where fp
/// fell by more than the tolerance acc, else twice as many; at most twice, at least half
/// the last count and 1.
fn knots_to_add(nplus: usize, fpms: f64, delta: f64, acc: f64) -> usize {
    let npl1 = if delta > acc {
        // Python's int(): toward zero (fpms / delta > 0 here); saturating.
        (nplus as f64 * fpms / delta) as usize
    } else {
        nplus * 2
    };
    (nplus * 2).min(npl1.max(nplus / 2).max(1))
}

/// FITPACK's knot search (fpcurf's and fpperi's part 1) from `start` (its knots; the fp
/// before them and the count of knots added last, as `Search` keeps them): fit, stop where
/// fp is within s's tolerance or below it, else add `knots_to_add` knots one at a time
/// (`with_new_knot`, each on the last fit's residuals), until the knots would interpolate
/// (then interpolation's) or reach nest; at most len(x) rounds.
pub fn search(x: &[f64], k: usize, rules: &Rules<'_>, start: Search) -> Result<Search, Failure> {
    let acc = rules.s * TOLERANCE;
    let nmin = 2 * (k + 1);
    let Search {
        mut t,
        fpold: mut fp,
        mut nplus,
    } = start;
    let mut chosen = t.clone();
    for _ in 0..x.len() {
        (rules.ends)(&mut t);
        chosen.clone_from(&t);
        let fpold = fp;
        let (mut each, total) = (rules.least_squares)(&t)?;
        fp = total;
        let fpms = fp - rules.s;
        if fpms.abs() < acc || fpms < 0.0 {
            return Ok(Search { t, fpold, nplus });
        }
        nplus = if t.len() == nmin {
            1
        } else {
            knots_to_add(nplus, fpms, fpold - fp, acc)
        };
        for j in 0..nplus {
            // The ends are set at the round's top only, as SciPy's.
            t = with_new_knot(x, &t, k, &each);
            if t.len() >= rules.nmax {
                let t = (rules.interpolation)();
                return Ok(Search {
                    t,
                    fpold: fp,
                    nplus,
                });
            }
            if t.len() >= rules.nest {
                return Ok(Search {
                    t,
                    fpold: fp,
                    nplus,
                });
            }
            if j + 1 < nplus {
                each = (rules.least_squares)(&t)?.0;
            }
        }
    }
    Ok(Search {
        t: chosen,
        fpold: fp,
        nplus,
    })
}

/// FITPACK's discontinuity rows (fpdisc): row j (an inner knot t_{j+k+1}) holds, for the
/// k + 2 B-splines from j on, the jump of their k-th derivative there, scaled by
/// ((t_{n-k-1} - t_k) / nrint)^k.
pub fn discontinuity(t: &[f64], k: usize) -> Vec<[f64; 8]> {
    let n = t.len();
    let intervals = n - 2 * k - 1;
    let scale = ((t[n - k - 1] - t[k]) / intervals as f64).powi(k as i32);
    (0..intervals - 1)
        .map(|row| {
            let j = row + k + 1;
            let mut out = [0.0; 8];
            for (ii, o) in out.iter_mut().enumerate().take(k + 2) {
                let i = row + ii;
                let product: f64 = (0..k + 2)
                    .filter(|&s| i + s != j)
                    .map(|s| t[j] - t[i + s])
                    .product();
                *o = (t[i + k + 1] - t[i]) / product * scale;
            }
            out
        })
        .collect()
}

/// FITPACK's fprati: the p where the rational function through (p1, f1), (p2, f2), (p3, f3)
/// (p3 may be infinite) crosses zero.
fn fprati(p1: f64, f1: f64, p2: f64, f2: f64, p3: f64, f3: f64) -> f64 {
    let h1 = f1 * (f2 - f3);
    let h2 = f2 * (f3 - f1);
    let h3 = f3 * (f1 - f2);
    if p3 == f64::INFINITY {
        return -(p2 * h1 + p1 * h2) / h3;
    }
    -(p1 * p2 * h3 + p2 * p3 * h1 + p1 * p3 * h2) / (p1 * h1 + p2 * h2 + p3 * h3)
}

/// The smoothing spline on the knots t with fp = s (step 2 of the module's description).
pub fn smooth(data: &Data<'_>, t: &[f64], k: usize, s: f64) -> Result<Spline, Failure> {
    let nc = t.len() - k - 1;
    let d = data.d;
    if t.len() == 2 * (k + 1) {
        // The returned coefficients by rotations, as SciPy's.
        let fit = lsq::fit(data.x, data.y, d, data.w, t, k).ok_or(Failure::Singular)?;
        return Ok(Spline {
            t: t.to_vec(),
            c: fit.c,
            ier: 0,
        });
    }
    let rows = BasisRows::new(data.x, t, k);
    // The data's triangle and what its rotations left over: fp of any c on these knots is
    // that plus base.misfit(c), without evaluating the spline at the data (but see below).
    let (base, left_over) = lsq::triangle(&rows, data.y, d, data.w, nc, k + 2);
    // Where the weights span more than 1e3, z and R c carry the heavy points' scale and their
    // difference cancels: there fp is summed at the data, as SciPy sums it.
    let (mut lightest, mut heaviest) = (f64::INFINITY, 0.0_f64);
    for &w in data.w.iter().filter(|&&w| w > 0.0) {
        lightest = lightest.min(w);
        heaviest = heaviest.max(w);
    }
    let balanced = heaviest <= 1e3 * lightest;
    let fpinf = if balanced {
        left_over
    } else {
        least_squares(data, t, k)?.2
    } - s;
    let diagonal_sum: f64 = (0..nc).map(|i| base.r[i * (k + 2)]).sum();
    let polynomial: Vec<f64> = std::iter::repeat_n(data.xb, k + 1)
        .chain(std::iter::repeat_n(data.xe, k + 1))
        .collect();
    let fp0 = least_squares(data, &polynomial, k)?.2 - s;
    let jumps = discontinuity(t, k);
    // f(p) = fp(p) - s, keeping the spline of the last p tried.
    let mut last: Option<Vec<f64>> = None;
    let mut f = |p: f64| -> Result<f64, Failure> {
        let mut tri: Triangle = base.clone();
        let mut rhs = vec![0.0; d];
        for (row, jump) in jumps.iter().enumerate() {
            let h: Vec<f64> = jump[..k + 2].iter().map(|v| v / p).collect();
            rhs.fill(0.0);
            tri.rotate_in(row, &h, &mut rhs);
        }
        let c = tri.back_substitute().ok_or(Failure::Singular)?;
        let fp = if balanced {
            left_over + base.misfit(&c)
        } else {
            residuals(data, &rows, &c).1
        };
        last = Some(c);
        Ok(fp - s)
    };
    let ier = root_rati(
        &mut f,
        nc as f64 / diagonal_sum,
        (0.0, fp0),
        (f64::INFINITY, fpinf),
        s * TOLERANCE,
    )?;
    let c = last.ok_or(Failure::Singular)?;
    Ok(Spline {
        t: t.to_vec(),
        c,
        ier,
    })
}

/// FITPACK's search for the root of f (decreasing in p) from p0 within the bracket
/// (p1, f1), (p3, f3), to |f| < acc: rational interpolation once both sides are found,
/// steps of 25x out until then (SciPy's `root_rati`). Its ier: 0, or 2 (f not monotone) or 3
/// (20 iterations), when the last p stands.
pub fn root_rati(
    f: &mut dyn FnMut(f64) -> Result<f64, Failure>,
    p0: f64,
    (mut p1, mut f1): (f64, f64),
    (mut p3, mut f3): (f64, f64),
    acc: f64,
) -> Result<u8, Failure> {
    let (con1, con9, con4) = (0.1, 0.9, 0.04);
    let (mut ich1, mut ich3) = (false, false);
    let mut p = p0;
    for _ in 0..MAX_ITERATIONS {
        let (p2, f2) = (p, f(p)?);
        if f2.abs() < acc {
            return Ok(0);
        }
        if !ich3 {
            if f2 - f3 <= acc {
                (p3, f3) = (p2, f2);
                p *= con4;
                if p <= p1 {
                    p = p1 * con9 + p2 * con1;
                }
                continue;
            }
            if f2 < 0.0 {
                ich3 = true;
            }
        }
        if !ich1 {
            if f1 - f2 <= acc {
                (p1, f1) = (p2, f2);
                p /= con4;
                if p3 != f64::INFINITY && p <= p3 {
                    p = p2 * con1 + p3 * con9;
                }
                continue;
            }
            if f2 > 0.0 {
                ich1 = true;
            }
        }
        if f1 <= f2 || f2 <= f3 {
            return Ok(2);
        }
        p = fprati(p1, f1, p2, f2, p3, f3);
        if f2 < 0.0 {
            (p3, f3) = (p2, f2);
        } else {
            (p1, f1) = (p2, f2);
        }
    }
    Ok(3)
}

/// One series' data checked as SciPy's FITPACK doors check it, in SciPy's words: x ordered,
/// enough points for the degree, weights >= 0 and not all zero, y finite, a periodic series'
/// ends equal (NumPy's `allclose(y[0], y[-1], atol=1e-15)`), and `xb <= x[0] < x[-1] <= xe`.
pub fn check(data: &Data<'_>, k: usize, periodic: bool) -> Result<(), InputError> {
    let x = data.x;
    if let Some(i) = lsq::first_unordered(x) {
        return Err(InputError::new("x", "Expect `x` to be an ordered 1D sequence.").at(i));
    }
    if periodic && x.len() < 2 {
        return Err(InputError::new(
            "x",
            "a periodic fit needs at least 2 points (the last repeats the first)",
        ));
    }
    if !periodic && x.len() <= k {
        return Err(InputError::new(
            "x",
            "m > k must hold (more points than the degree)",
        ));
    }
    if let Some(i) = data.w.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(InputError::new("w", "Weights must be non-negative").at(i));
    }
    if data.w.iter().all(|&v| v == 0.0) {
        return Err(InputError::new("w", "All weights are zero."));
    }
    if let Some(i) = data.y.iter().position(|v| !v.is_finite()) {
        return Err(InputError::new("y", "must be finite (NaN or infinity found)").at(i));
    }
    let (first, last) = (&data.y[..data.d], &data.y[data.y.len() - data.d..]);
    let apart = |(a, b): (&f64, &f64)| (a - b).abs() > 1e-15 + 1e-5 * b.abs();
    if periodic && first.iter().zip(last).any(apart) {
        return Err(InputError::new(
            "y",
            "First and last points does not match which is required for `bc_type='periodic'`.",
        ));
    }
    if !(data.xb <= x[0] && data.xe >= x[x.len() - 1] && data.xb < data.xe) {
        return Err(InputError::new(
            "xb",
            "must satisfy xb <= x[0] < x[-1] <= xe",
        ));
    }
    Ok(())
}

/// FITPACK's default room for knots: interpolation's count (m + 2k periodic, m + k + 1 not),
/// at least 2k + 3.
pub fn default_nest(m: usize, k: usize, periodic: bool) -> usize {
    let interpolation = if periodic { m + 2 * k } else { m + k + 1 };
    interpolation.max(2 * k + 3)
}

#[cfg(test)]
mod tests {
    use super::{Data, knots, smooth};
    use crate::interp::not_a_knot;

    /// Data on a straight line is fitted by the line with no inner knot (fp = 0 < s at once).
    #[test]
    fn a_line_needs_no_knots() {
        let x: Vec<f64> = (0..20).map(f64::from).collect();
        let y: Vec<f64> = x.iter().map(|v| 0.5 * v + 1.0).collect();
        let w = vec![1.0; 20];
        let data = Data {
            x: &x,
            y: &y,
            d: 1,
            w: &w,
            xb: 0.0,
            xe: 19.0,
        };
        let spline = smooth(&data, &knots(&data, 3, 0.1, 24).unwrap(), 3, 0.1).unwrap();
        assert_eq!(spline.t.len(), 8);
        // The line's B-spline coefficients on [0]*4 + [19]*4: its values at 0, 19/3, 38/3, 19.
        for (j, c) in spline.c.iter().enumerate() {
            let at = 19.0 * j as f64 / 3.0;
            assert!((c - (0.5 * at + 1.0)).abs() < 1e-12, "{j}: {c}");
        }
    }

    #[test]
    fn not_a_knot_drops_points_next_to_the_ends() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(
            not_a_knot(&x, 3),
            vec![0.0, 0.0, 0.0, 0.0, 2.0, 3.0, 5.0, 5.0, 5.0, 5.0]
        );
        assert_eq!(
            not_a_knot(&x, 2),
            vec![0.0, 0.0, 0.0, 1.5, 2.5, 3.5, 5.0, 5.0, 5.0]
        );
    }
}
