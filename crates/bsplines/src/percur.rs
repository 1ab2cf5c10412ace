//! FITPACK's own periodic smoothing fits, percur (a periodic function) and clocur (a closed
//! curve of d coordinates) (Dierckx 1993, ch. 6; fpperi, fpclos), step for step as the
//! routines SciPy's `splrep(per=1)` and `splprep(per=1)` call: the same method as `curfit`'s
//! on a periodic spline space, with FITPACK's own bookkeeping (see `curfit` for where it
//! differs from SciPy's `make_splrep`, which `periodic` reproduces).
//!
//! The period is x_{m-1} - x_0; the last point stands for the first (its value is not
//! fitted). The knots t_k = x_0 and t_{n-k-1} = x_{m-1}, each end's k outer knots the inner
//! ones shifted by the period, and the last k coefficients equal to the first k (**): the
//! spline is periodic. Least squares then rotate each point's row into a triangle in two
//! parts: a1 (an upper triangular band over the first n7 - k coefficients) and a2 (the
//! columns of the last k, which the wrapped B-splines reach), solved by `wrapped_back`.
//!
//! Part 1 (the knots): the least-squares constant first (ier -2 where it meets s), then one
//! inner knot at the middle data point, then knots added as curfit adds them (fpknot), up
//! to nest (ier 1) or interpolation (n = m + 2k). Part 2 (the smoothness): the jumps of the
//! k-th derivative at the inner knots, weighted 1/p, rotated into the same two-part
//! triangle, p found as curfit finds it (`curfit::find_p`).

use crate::curfit::{
    Door, Fit, MAX_ITERATIONS, Search, add_knots, basis, discontinuity, find_p, givens,
    knots_to_add, rotate, value_at,
};
use crate::fitpack::{Data, TOLERANCE};

/// A least-squares fit on periodic knots: the two-part triangle (a1: n7 rows of width
/// k + 1; a2: n7 rows of k columns), its right-hand sides z (n7 rows of d), the B-splines at
/// each point but the last (k + 1 a point), the coefficients (n - k - 1 rows of d, the last
/// k repeating the first) and fp, the sum of the squares the rotations leave over.
struct LeastSquares {
    a1: Vec<f64>,
    a2: Vec<f64>,
    z: Vec<f64>,
    q: Vec<f64>,
    c: Vec<f64>,
    fp: f64,
}

/// Back substitution of a two-part triangle (fpbacp): a (n rows, width wa) over the first
/// n - k unknowns, b (n rows, k columns) over the last k; right-hand sides z (n rows of d).
fn wrapped_back(
    a: &[f64],
    wa: usize,
    b: &[f64],
    k: usize,
    z: &[f64],
    n: usize,
    d: usize,
) -> Vec<f64> {
    let mut c = vec![0.0; n * d];
    let n2 = n as isize - k as isize;
    for col in 0..d {
        let at = |row: usize| row * d + col;
        // The last k unknowns, from b's bottom rows (1-based l from n down).
        let mut l = n;
        let mut done = false;
        for i in 1..=k {
            let mut store = z[at(l - 1)];
            let j = k + 2 - i;
            if i != 1 {
                let mut l0 = l;
                for l1 in j..=k {
                    l0 += 1;
                    store -= c[at(l0 - 1)] * b[(l - 1) * k + l1 - 1];
                }
            }
            c[at(l - 1)] = store / b[(l - 1) * k + j - 2];
            l -= 1;
            if l == 0 {
                done = true;
                break;
            }
        }
        if done || n2 <= 0 {
            continue;
        }
        let n2 = n2 as usize;
        for i in 1..=n2 {
            let mut store = z[at(i - 1)];
            let mut l = n2;
            for j in 1..=k {
                l += 1;
                store -= c[at(l - 1)] * b[(i - 1) * k + j - 1];
            }
            c[at(i - 1)] = store;
        }
        let mut i = n2;
        c[at(i - 1)] /= a[(i - 1) * wa];
        for j in 2..=n2 {
            i -= 1;
            let mut store = c[at(i - 1)];
            let i1 = if j <= k { j - 1 } else { k };
            let mut l = i;
            for l0 in 1..=i1 {
                l += 1;
                store -= c[at(l - 1)] * a[(i - 1) * wa + l0];
            }
            c[at(i - 1)] = store / a[(i - 1) * wa];
        }
    }
    c
}

/// The coefficients n7.. n7 + k - 1 repeat the first k (condition (**)).
fn wrapped(mut c: Vec<f64>, n7: usize, k: usize, d: usize) -> Vec<f64> {
    c.resize((n7 + k) * d, 0.0);
    for i in 0..k * d {
        c[n7 * d + i] = c[i];
    }
    c
}

/// The least-squares periodic spline on the knots t (fpperi's and fpclos's part 1 fit).
fn least_squares(data: &Data<'_>, t: &[f64], k: usize) -> LeastSquares {
    let (k1, d, n) = (k + 1, data.d, t.len());
    let m1 = data.x.len() - 1;
    let nk1 = n - k1;
    let n7 = nk1 - k;
    let n10 = n7 as isize - k as isize;
    let mut a1 = vec![0.0; nk1 * k1];
    let mut a2 = vec![0.0; n7 * k];
    let mut z = vec![0.0; nk1 * d];
    let mut q = vec![0.0; m1 * k1];
    let (mut fp, mut l, mut wrapping) = (0.0, k, false);
    let (mut h, mut rhs) = ([0.0; 6], [0.0; 10]);
    for it in 0..m1 {
        let (xi, wi) = (data.x[it], data.w[it]);
        for (r, &y) in rhs.iter_mut().zip(&data.y[it * d..(it + 1) * d]) {
            *r = y * wi;
        }
        while xi >= t[l + 1] {
            l += 1;
        }
        basis(t, k, xi, l, &mut h);
        q[it * k1..(it + 1) * k1].copy_from_slice(&h[..k1]);
        for v in &mut h[..k1] {
            *v *= wi;
        }
        // l5: the first B-spline's index (0-based) = 1-based l - k1.
        let l5 = l as isize - k as isize;
        if l5 < n10 {
            // None of the wrapped B-splines is non-zero here: a plain band row.
            for i in 0..k1 {
                let row = l5 as usize + i;
                let piv = h[i];
                if piv == 0.0 {
                    continue;
                }
                let rotation = givens(piv, &mut a1[row * k1]);
                for (r, zv) in rhs[..d].iter_mut().zip(&mut z[row * d..(row + 1) * d]) {
                    rotate(rotation, r, zv);
                }
                for i1 in i + 1..k1 {
                    rotate(rotation, &mut h[i1], &mut a1[row * k1 + i1 - i]);
                }
            }
        } else {
            if !wrapping {
                // a2 starts as the columns of a1's rows that reach the last k unknowns.
                for (i, jk) in (1..=k).zip(n10 + 1..) {
                    let mut ik = jk;
                    for j in 1..=k1 {
                        if ik <= 0 {
                            break;
                        }
                        let row = ik as usize - 1;
                        a2[row * k + i - 1] = a1[row * k1 + j - 1];
                        ik -= 1;
                    }
                }
                wrapping = true;
            }
            // The row with (**) applied: h1 over a1's unknowns, h2 over the last k.
            let (mut h1, mut h2) = ([0.0; 7], [0.0; 6]);
            for (j, &hv) in (l5 - n10 + 1..).zip(&h[..k1]) {
                let mut l0 = j;
                loop {
                    let l1 = l0 - k as isize;
                    if l1 <= 0 {
                        h2[l0 as usize - 1] += hv;
                        break;
                    }
                    if l1 <= n10 {
                        h1[l1 as usize - 1] = hv;
                        break;
                    }
                    l0 = l1 - n10;
                }
            }
            if n10 > 0 {
                let n10 = n10 as usize;
                for j in 1..=n10 {
                    let piv = h1[0];
                    if piv == 0.0 {
                        h1.copy_within(1..=k, 0);
                        h1[k] = 0.0;
                        continue;
                    }
                    let row = j - 1;
                    let rotation = givens(piv, &mut a1[row * k1]);
                    for (r, zv) in rhs[..d].iter_mut().zip(&mut z[row * d..(row + 1) * d]) {
                        rotate(rotation, r, zv);
                    }
                    for (i, hv) in h2.iter_mut().enumerate().take(k) {
                        rotate(rotation, hv, &mut a2[row * k + i]);
                    }
                    if j == n10 {
                        break;
                    }
                    let i2 = (n10 - j).min(k);
                    for i in 1..=i2 {
                        rotate(rotation, &mut h1[i], &mut a1[row * k1 + i]);
                        h1[i - 1] = h1[i];
                    }
                    h1[i2] = 0.0;
                }
            }
            for j in 1..=k {
                let ij = n10 + j as isize;
                if ij <= 0 {
                    continue;
                }
                let piv = h2[j - 1];
                if piv == 0.0 {
                    continue;
                }
                let row = ij as usize - 1;
                let rotation = givens(piv, &mut a2[row * k + j - 1]);
                for (r, zv) in rhs[..d].iter_mut().zip(&mut z[row * d..(row + 1) * d]) {
                    rotate(rotation, r, zv);
                }
                for i in j + 1..=k {
                    rotate(rotation, &mut h2[i - 1], &mut a2[row * k + i - 1]);
                }
            }
        }
        for r in &rhs[..d] {
            fp += r * r;
        }
    }
    let c = wrapped(wrapped_back(&a1, k1, &a2, k, &z, n7, d), n7, k, d);
    LeastSquares {
        a1,
        a2,
        z,
        q,
        c,
        fp,
    }
}

/// Each knot interval's share of fp (fpperi's fpint): as curfit's, but the first point's
/// residual counts to the last interval too (the period wraps), whole.
fn shares(data: &Data<'_>, t: &[f64], k: usize, fit: &LeastSquares) -> Vec<f64> {
    let (k1, k2, d) = (k + 1, k + 2, data.d);
    let m1 = data.x.len() - 1;
    let nrint = t.len() - 2 * k - 1;
    let mut fpint = vec![0.0; nrint];
    let (mut fpart, mut i, mut l) = (0.0, 0, k1);
    for it in 0..m1 {
        let new = data.x[it] >= t[l - 1];
        if new {
            l += 1;
        }
        let q = &fit.q[it * k1..(it + 1) * k1];
        let mut term = 0.0;
        for col in 0..d {
            let fac = value_at(q, &fit.c, d, l - k2, col);
            term += (data.w[it] * (fac - data.y[it * d + col])).powi(2);
        }
        fpart += term;
        if !new {
            continue;
        }
        if l <= k2 {
            fpint[nrint - 1] = term;
            continue;
        }
        let store = term * 0.5;
        fpint[i] = fpart - store;
        i += 1;
        fpart = store;
    }
    fpint[nrint - 1] += fpart;
    fpint
}

/// The knots outside [x_0, x_{m-1}]: t_k = x_0, t_{n-k-1} = x_{m-1}, and the k beyond each
/// end the inner ones shifted by the period, in fpperi's order.
fn set_ends(t: &mut [f64], k: usize, x0: f64, x1: f64) {
    let per = x1 - x0;
    let nk1 = t.len() - k - 1;
    t[k] = x0;
    t[nk1] = x1;
    for j in 1..=k {
        t[nk1 + j] = t[k + j] + per;
        t[k - j] = t[nk1 - j] - per;
    }
}

/// The knots of periodic interpolation (n = m + 2k): the inner data for odd k, the midpoints
/// for even k (the ends as `set_ends` makes them).
fn interpolation_knots(x: &[f64], k: usize) -> Vec<f64> {
    let m = x.len();
    let mut t = vec![0.0; m + 2 * k];
    for i in 1..m - 1 {
        t[i + k] = if k.is_multiple_of(2) {
            (x[i] + x[i - 1]) * 0.5
        } else {
            x[i]
        };
    }
    t
}

/// Part 2 on the periodic knots t (fp - s = fpms > 0 at p = 0, < 0 at infinity).
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
    let m1 = data.x.len() - 1;
    let nk1 = t.len() - k1;
    let n7 = nk1 - k;
    let n10 = n7 as isize - k as isize;
    let n11 = n10 - 1;
    let n8 = n7 - 1;
    let jumps = discontinuity(t, k);
    // The first p: n7 over the sum of the triangle's diagonal (a2's last rows, then a1's).
    let mut diagonal = 0.0;
    let mut l = n7;
    let mut all_in_a2 = false;
    for i in 1..=k {
        diagonal += fit.a2[(l - 1) * k + k - i];
        l -= 1;
        if l == 0 {
            all_in_a2 = true;
            break;
        }
    }
    if !all_in_a2 && n10 > 0 {
        for i in 0..n10 as usize {
            diagonal += fit.a1[i * k1];
        }
    }
    let spline_for = |p: f64| {
        let pinv = 1.0 / p;
        // g1: a1 widened by a column; g2: a1's corner column then a2.
        let mut c = fit.z[..n7 * d].to_vec();
        let mut g1 = vec![0.0; n7 * k2];
        let mut g2 = vec![0.0; n7 * k1];
        for i in 0..n7 {
            g1[i * k2..i * k2 + k1].copy_from_slice(&fit.a1[i * k1..(i + 1) * k1]);
            g2[i * k1 + 1..(i + 1) * k1].copy_from_slice(&fit.a2[i * k..(i + 1) * k]);
        }
        let mut l = n10;
        for j in 0..k1 {
            if l <= 0 {
                break;
            }
            let row = l as usize - 1;
            g2[row * k1] = fit.a1[row * k1 + j];
            l -= 1;
        }
        let mut rhs = [0.0; 10];
        for it in 1..=n8 {
            let jump = &jumps[it - 1];
            rhs[..d].fill(0.0);
            let (mut h1, mut h2) = ([0.0; 8], [0.0; 7]);
            let first_row;
            if (it as isize) <= n11 {
                first_row = it;
                for (j, l0) in (1..=k2).zip(it as isize..) {
                    if l0 == n10 {
                        for (slot, l1) in (j..=k2).enumerate() {
                            h2[slot] = jump[l1 - 1] * pinv;
                        }
                        break;
                    }
                    h1[j - 1] = jump[j - 1] * pinv;
                }
            } else {
                first_row = 1;
                for (i, &b) in (it as isize - n10 + 1..).zip(&jump[..k2]) {
                    let mut l0 = i;
                    loop {
                        let l1 = l0 - k1 as isize;
                        if l1 <= 0 {
                            h2[l0 as usize - 1] += b * pinv;
                            break;
                        }
                        if l1 <= n11 {
                            h1[l1 as usize - 1] = b * pinv;
                            break;
                        }
                        l0 = l1 - n11;
                    }
                }
            }
            if n11 > 0 {
                let n11 = n11 as usize;
                for j in first_row..=n11 {
                    let row = j - 1;
                    let rotation = givens(h1[0], &mut g1[row * k2]);
                    for (r, cv) in rhs[..d].iter_mut().zip(&mut c[row * d..(row + 1) * d]) {
                        rotate(rotation, r, cv);
                    }
                    for (i, hv) in h2.iter_mut().enumerate().take(k1) {
                        rotate(rotation, hv, &mut g2[row * k1 + i]);
                    }
                    if j == n11 {
                        break;
                    }
                    let i2 = (n11 - j).min(k1);
                    for i in 1..=i2 {
                        rotate(rotation, &mut h1[i], &mut g1[row * k2 + i]);
                        h1[i - 1] = h1[i];
                    }
                    h1[i2] = 0.0;
                }
            }
            for j in 1..=k1 {
                let ij = n11 + j as isize;
                if ij <= 0 {
                    continue;
                }
                let row = ij as usize - 1;
                let rotation = givens(h2[j - 1], &mut g2[row * k1 + j - 1]);
                for (r, cv) in rhs[..d].iter_mut().zip(&mut c[row * d..(row + 1) * d]) {
                    rotate(rotation, r, cv);
                }
                for i in j + 1..=k1 {
                    rotate(rotation, &mut h2[i - 1], &mut g2[row * k1 + i - 1]);
                }
            }
        }
        let c = wrapped(wrapped_back(&g1, k2, &g2, k1, &c, n7, d), n7, k, d);
        let (mut fp, mut l) = (0.0, k1);
        for it in 0..m1 {
            if data.x[it] >= t[l - 1] {
                l += 1;
            }
            fp = door.add_residual(fp, &fit.q[it * k1..(it + 1) * k1], &c, l - k2, data, it);
        }
        (c, fp)
    };
    find_p(
        spline_for,
        n7 as f64 / diagonal,
        (fp0, fpms),
        (s, TOLERANCE * s),
        door.steps(),
        MAX_ITERATIONS,
    )
}

/// FITPACK's periodic smoothing fit with s > 0 (percur's, or clocur's with `Door::Clocur`)
/// of the data (x strictly increasing, w > 0, the last point standing for the first), with
/// at most `nest` knots, from the constant, or on from `from` (iopt = 1), as the module
/// describes. The caller has checked the data, s > 0, 1 <= k <= 5, d <= 10 and
/// nest > 2k + 2.
pub fn smoothing_fit(
    data: &Data<'_>,
    k: usize,
    s: f64,
    nest: usize,
    from: Option<&Search>,
    door: Door,
) -> Fit {
    let (k1, d, m) = (k + 1, data.d, data.x.len());
    let m1 = m - 1;
    let (x0, x1) = (data.x[0], data.x[m1]);
    let per = x1 - x0;
    let (nmin, nmax) = (2 * k1, m + 2 * k);
    let acc = TOLERANCE * s;
    let mut ier = 0;
    let (mut t, mut nrdata, mut fp0, mut fpold, mut nplus);
    if let Some(earlier) = from.filter(|e| e.t.len() != nmin && e.fp0 > s) {
        t = earlier.t.clone();
        nrdata = earlier.nrdata.clone();
        (fp0, fpold, nplus, ier) = (earlier.fp0, earlier.fpold, earlier.nplus, earlier.ier);
    } else {
        // The least-squares constant, fp0 its fp.
        let (mut d1, mut c1, mut rhs) = (0.0, [0.0; 10], [0.0; 10]);
        fp0 = 0.0;
        for it in 0..m1 {
            let wi = data.w[it];
            let rotation = givens(wi, &mut d1);
            for col in 0..d {
                rhs[col] = data.y[it * d + col] * wi;
                rotate(rotation, &mut rhs[col], &mut c1[col]);
                fp0 += rhs[col] * rhs[col];
            }
        }
        if fp0 - s < acc || nmax == nmin || nmin >= nest {
            let t: Vec<f64> = (0..k1)
                .map(|i| x0 - (k - i) as f64 * per)
                .chain((0..k1).map(|i| x1 + i as f64 * per))
                .collect();
            let c = (0..k1)
                .flat_map(|_| c1[..d].iter().map(|v| v / d1))
                .collect();
            let ier = if fp0 - s < acc || nmax == nmin { -2 } else { 1 };
            return Fit::stopped(t, (c, fp0, ier), vec![0], (fp0, 0.0, 0));
        }
        fpold = fp0;
        // One inner knot, at the middle data point.
        nplus = 1;
        t = vec![0.0; nmin + 1];
        let mm = m.div_ceil(2);
        t[k + 1] = data.x[mm - 1];
        nrdata = vec![mm - 2, m1 - mm];
    }
    let mut round = 0;
    loop {
        let n = t.len();
        set_ends(&mut t, k, x0, x1);
        let fit = least_squares(data, &t, k);
        let fpms = fit.fp - s;
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
            nplus = knots_to_add(nplus, fpms, fpold - fit.fp, acc);
            fpold = fit.fp;
            let mut fpint = shares(data, &t, k, &fit);
            let interpolation = || interpolation_knots(data.x, k);
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
            // No interval has a data point inside (see `curfit`): part 2 on these knots.
            None
        };
        let answer = match ending {
            Some(ier) => (fit.c.clone(), fit.fp, ier),
            None => smooth(data, &t, k, s, (fp0, fpms), &fit, door),
        };
        return Fit::stopped(t, answer, nrdata, kept);
    }
}

#[cfg(test)]
mod tests {
    use super::smoothing_fit;
    use crate::BSpline;
    use crate::curfit::Door;
    use crate::fitpack::Data;

    /// 120 points over one period of sin with a deterministic wobble, the last the first's.
    fn wobbly() -> (Vec<f64>, Vec<f64>) {
        let x: Vec<f64> = (0..120).map(|i| f64::from(i) / 119.0 * 10.0).collect();
        let mut y: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| {
                (v * 0.2 * std::f64::consts::PI).sin()
                    + 0.1 * ((i * 7919 % 101) as f64 / 50.0 - 1.0)
            })
            .collect();
        y[119] = y[0];
        (x, y)
    }

    /// Constant data: the least-squares constant meets any s > 0 (ier -2), every coefficient
    /// that constant, the knots past the ends a period apart.
    #[test]
    fn constant_data_is_the_constant() {
        let x: Vec<f64> = (0..30).map(f64::from).collect();
        let (y, w) = (vec![2.5; 30], vec![1.0; 30]);
        let data = Data {
            x: &x,
            y: &y,
            d: 1,
            w: &w,
            xb: 0.0,
            xe: 29.0,
        };
        let fit = smoothing_fit(&data, 3, 0.1, 40, None, Door::Percur);
        assert_eq!(fit.ier, -2);
        assert_eq!(
            fit.t,
            vec![-87.0, -58.0, -29.0, 0.0, 29.0, 58.0, 87.0, 116.0]
        );
        assert!(fit.c.iter().all(|c| (c - 2.5).abs() < 1e-14), "{:?}", fit.c);
    }

    /// A periodic smoothing fit meets s within FITPACK's tolerance, its fp is the residual
    /// at the points but the last, and the spline closes up: value and first k - 1
    /// derivatives equal at both ends.
    #[test]
    fn fits_meet_s_and_close_up() {
        let (x, y) = wobbly();
        let w = vec![1.0; x.len()];
        let data = Data {
            x: &x,
            y: &y,
            d: 1,
            w: &w,
            xb: x[0],
            xe: x[119],
        };
        for k in [1, 2, 3, 5] {
            let fit = smoothing_fit(&data, k, 0.5, 200, None, Door::Percur);
            assert_eq!(fit.ier, 0, "k {k}");
            assert!((fit.fp - 0.5).abs() < 5e-4, "k {k}: fp {}", fit.fp);
            let spline = BSpline::new(fit.t.clone(), fit.c.clone(), k, 1).unwrap();
            let values = spline.evaluate(&x[..119], 0);
            let residual: f64 = values.iter().zip(&y).map(|(s, y)| (y - s).powi(2)).sum();
            assert!(
                (residual - fit.fp).abs() < 1e-9,
                "k {k}: {residual} {}",
                fit.fp
            );
            for nu in 0..k {
                let ends = spline.evaluate(&[x[0], x[119]], nu);
                assert!(
                    (ends[0] - ends[1]).abs() < 1e-9 * (1.0 + ends[0].abs()),
                    "k {k} nu {nu}: {ends:?}"
                );
            }
        }
    }
}
