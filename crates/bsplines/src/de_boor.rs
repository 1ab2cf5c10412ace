//! B-splines evaluated as SciPy evaluates them (`BSpline.__call__` on the CPU): at each x the
//! k + 1 B-splines of its knot span by the Cox-de Boor recurrence, summed with their
//! coefficients. Exact zeros off a basis function's support, NaN only where a coefficient
//! that is NaN reaches, and SciPy's span at the ends (an empty end interval included), which
//! the polynomial pieces the context evaluates cannot all give.
//!
//! The span of x is l = clamp(#{t_j <= x} - 1, k, n - 1) (n = len(t) - k - 1). Degrees rise
//! from B_{l,0} = 1 to k - nu by
//!     B_{i,p}(x) = (x - t_i) / (t_{i+p} - t_i) B_{i,p-1} + (t_{i+p+1} - x) / (t_{i+p+1} - t_{i+1}) B_{i+1,p-1},
//! and each of the last nu degrees takes the derivative instead,
//!     B'_{i,p} = p B_{i,p-1} / (t_{i+p} - t_i) - p B_{i+1,p-1} / (t_{i+p+1} - t_{i+1}),
//! a term over a zero width being zero. [`cubic_span_polynomials`] runs the same recursion on
//! polynomials: a cubic span's four B-splines as cubics in the span's u (the splinegpu crate's
//! rational "nurbs" segments are made from them).

use rayon::prelude::*;

/// Points per task when the work is spread over the pool.
const CHUNK: usize = 4096;

/// The nu-th derivatives of the B-splines B_{l-k,k} .. B_{l,k} at x into `values` (k + 1),
/// `scratch` the same length; returns l.
pub fn basis(
    t: &[f64],
    k: usize,
    x: f64,
    nu: usize,
    values: &mut [f64],
    scratch: &mut [f64],
) -> usize {
    let n = t.len() - k - 1;
    let l = t
        .partition_point(|&v| v <= x)
        .saturating_sub(1)
        .clamp(k, n - 1);
    basis_in(t, k, x, l, nu, values, scratch);
    l
}

/// `basis` in the span l that x is known to fall in (t_l <= x < t_{l+1}, or x at the last
/// span's end).
pub fn basis_in(
    t: &[f64],
    k: usize,
    x: f64,
    l: usize,
    nu: usize,
    values: &mut [f64],
    scratch: &mut [f64],
) {
    values.fill(0.0);
    if nu > k {
        return;
    }
    values[0] = 1.0;
    for p in 1..=k {
        for r in 0..=p {
            let i = l + r - p;
            let lower = if r > 0 { values[r - 1] } else { 0.0 };
            let upper = if r < p { values[r] } else { 0.0 };
            let left = t[i + p] - t[i];
            let right = t[i + p + 1] - t[i + 1];
            scratch[r] = if p <= k - nu {
                let a = if left > 0.0 { (x - t[i]) / left } else { 0.0 };
                let b = if right > 0.0 {
                    (t[i + p + 1] - x) / right
                } else {
                    0.0
                };
                a * lower + b * upper
            } else {
                let a = if left > 0.0 { p as f64 / left } else { 0.0 };
                let b = if right > 0.0 { p as f64 / right } else { 0.0 };
                a * lower - b * upper
            };
        }
        values[..=p].copy_from_slice(&scratch[..=p]);
    }
}

/// `basis_in` for k = 3, nu = 0 at a knot x = t_l that starts span l (t_l < t_{l+1}), as
/// [B_{l-3}, B_{l-2}, B_{l-1}, B_l = 0]: at x = t_l every term of the recursion on a zero
/// value is zero, so only the others are formed, each with `basis_in`'s operations in its
/// order (7 divisions where it makes 18): its values bit for bit. The widths divided by are
/// t_{l+1} - t_m for m = l - 2 ..= l and t_{l+2} - t_{l-1}, positive with t_l < t_{l+1}.
pub fn cubic_at_knot(t: &[f64], l: usize) -> [f64; 4] {
    let x = t[l];
    // Degree 1: B_{l-1} (B_l is zero at its first knot).
    let v0 = (t[l + 1] - x) / (t[l + 1] - t[l]);
    // Degree 2: B_{l-2}, B_{l-1}.
    let w0 = (t[l + 1] - x) / (t[l + 1] - t[l - 1]) * v0;
    let w1 = (x - t[l - 1]) / (t[l + 1] - t[l - 1]) * v0;
    // Degree 3: B_{l-3}, B_{l-2}, B_{l-1}.
    let z0 = (t[l + 1] - x) / (t[l + 1] - t[l - 2]) * w0;
    let z1 =
        (x - t[l - 2]) / (t[l + 1] - t[l - 2]) * w0 + (t[l + 2] - x) / (t[l + 2] - t[l - 1]) * w1;
    let z2 = (x - t[l - 1]) / (t[l + 2] - t[l - 1]) * w1;
    [z0, z1, z2, 0.0]
}

/// The spline's Taylor coefficients f^(d)(at) / d! (d = 0..=k, m values each, row-major)
/// from the span `at` falls in.
fn taylor(t: &[f64], c: &[f64], m: usize, k: usize, at: f64) -> Vec<f64> {
    let (mut values, mut scratch) = (vec![0.0; k + 1], vec![0.0; k + 1]);
    let mut out = vec![0.0; (k + 1) * m];
    let mut factorial = 1.0;
    for d in 0..=k {
        factorial *= d.max(1) as f64;
        let l = basis(t, k, at, d, &mut values, &mut scratch);
        for (r, &weight) in values.iter().enumerate() {
            for j in 0..m {
                out[d * m + j] += weight * c[(l - k + r) * m + j] / factorial;
            }
        }
    }
    out
}

/// sum_r B^(nu)_{l-k+r,k}(x) c_{l-k+r} at each x into `out` (len(x) rows of m); c holds at
/// least n rows of m values. With `ends_in_powers`, x past the base interval [t_k, t_n] takes
/// the end polynomial in powers of x - t_k (or x - t_n) instead: the same polynomial, without
/// the cancellation de Boor's blending suffers far from the knots (for end intervals that are
/// not empty). Large calls are spread over the pool.
#[expect(
    clippy::too_many_arguments,
    reason = "the spline, the points, the order and the output of one call"
)]
pub fn evaluate(
    t: &[f64],
    c: &[f64],
    m: usize,
    k: usize,
    x: &[f64],
    nu: usize,
    ends_in_powers: bool,
    out: &mut [f64],
) {
    if m == 0 {
        return;
    }
    let n = t.len() - k - 1;
    let (lo, hi) = (t[k], t[n]);
    // Each end's expansion only where some x needs it.
    let end = |needed: bool, at: f64| (ends_in_powers && needed).then(|| taylor(t, c, m, k, at));
    let left = end(x.iter().any(|&at| at < lo), lo);
    let right = end(x.iter().any(|&at| at > hi), hi);
    let run = |x: &[f64], out: &mut [f64]| {
        let (mut values, mut scratch) = (vec![0.0; k + 1], vec![0.0; k + 1]);
        for (row, &at) in out.chunks_exact_mut(m).zip(x) {
            if at.is_nan() {
                // NaN, also where the derivative's weights do not depend on x (nu = k).
                row.fill(f64::NAN);
                continue;
            }
            row.fill(0.0);
            let past = match (&left, &right) {
                (Some(left), _) if at < lo => Some((left, at - lo)),
                (_, Some(right)) if at > hi => Some((right, at - hi)),
                _ => None,
            };
            if let Some((coefficients, v)) = past {
                // sum_{d >= nu} a_d d! / (d - nu)! v^(d - nu), by Horner from d = k.
                for d in (nu..=k).rev() {
                    let factor: f64 = (d - nu + 1..=d).map(|j| j as f64).product();
                    for (o, &a) in row.iter_mut().zip(&coefficients[d * m..(d + 1) * m]) {
                        *o = *o * v + a * factor;
                    }
                }
                continue;
            }
            let l = basis(t, k, at, nu, &mut values, &mut scratch);
            for (r, &weight) in values.iter().enumerate() {
                let coefficients = &c[(l - k + r) * m..(l - k + r + 1) * m];
                for (o, &cj) in row.iter_mut().zip(coefficients) {
                    *o += weight * cj;
                }
            }
        }
    };
    if x.len() <= CHUNK {
        run(x, out);
    } else {
        out.par_chunks_mut(CHUNK * m)
            .zip(x.par_chunks(CHUNK))
            .for_each(|(out, x)| run(x, out));
    }
}

/// The cubic B-splines N_{i−3,3} .. N_{i,3} on span i ([k_i, k_{i+1}], Δ = k_{i+1} − k_i > 0)
/// as cubics in u = (t − k_i)/Δ, coefficients of 1, u, u², u³: the Cox–de Boor recursion on
/// polynomials, N_{i,0} = 1 and
/// N_{j,p} = ((k_i − k_j) + Δu)/(k_{j+p} − k_j) · N_{j,p−1} + ((k_{j+p+1} − k_i) − Δu)/(k_{j+p+1} − k_{j+1}) · N_{j+1,p−1},
/// a term whose denominator is 0 being 0.
#[must_use]
pub fn cubic_span_polynomials(knots: &[f64], i: usize) -> [[f64; 4]; 4] {
    let dt = knots[i + 1] - knots[i];
    // level[m] is N_{i−3+m, p} for m in 0..5 (m = 4 is N_{i+1}, zero on this span).
    let mut level = [[0.0; 4]; 5];
    level[3][0] = 1.0;
    // One function per degree, so that its loops have constant bounds and the levels stay
    // in registers (faster than one loop over the degrees, the same arithmetic bit for bit;
    // docs/benchmarks.md has the figure).
    let level = raise::<1>(knots, i, dt, &level);
    let level = raise::<2>(knots, i, dt, &level);
    let level = raise::<3>(knots, i, dt, &level);
    [level[0], level[1], level[2], level[3]]
}

/// Level P of [`cubic_span_polynomials`]' recursion from level P − 1:
/// N_{j,P} = ((k_i − k_j) + Δu) / (k_{j+P} − k_j) · N_{j,P−1}
///         + ((k_{j+P+1} − k_i) − Δu) / (k_{j+P+1} − k_{j+1}) · N_{j+1,P−1}.
#[inline(always)]
fn raise<const P: usize>(knots: &[f64], i: usize, dt: f64, level: &[[f64; 4]; 5]) -> [[f64; 4]; 5] {
    let mut next = [[0.0; 4]; 5];
    for m in 3 - P..4 {
        let poly = &mut next[m];
        let j = i - 3 + m;
        // ((k_i − k_j) + Δu) / (k_{j+p} − k_j) · N_{j,p−1}
        let left = knots[j + P] - knots[j];
        if left > 0.0 {
            add_times_linear(poly, &level[m], (knots[i] - knots[j]) / left, dt / left);
        }
        // ((k_{j+p+1} − k_i) − Δu) / (k_{j+p+1} − k_{j+1}) · N_{j+1,p−1}
        let right = knots[j + P + 1] - knots[j + 1];
        if right > 0.0 {
            let c0 = (knots[j + P + 1] - knots[i]) / right;
            add_times_linear(poly, &level[m + 1], c0, -dt / right);
        }
    }
    next
}

/// out += (c0 + c1 u) · poly (degrees stay within 3 on a cubic's recursion).
#[inline(always)]
fn add_times_linear(out: &mut [f64; 4], poly: &[f64; 4], c0: f64, c1: f64) {
    for d in 0..4 {
        out[d] += c0 * poly[d];
        if d + 1 < 4 {
            out[d + 1] += c1 * poly[d];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{basis_in, cubic_at_knot, cubic_span_polynomials, evaluate};

    /// On every span of uneven knots with repeated ones, the four polynomials sum to 1 (their
    /// coefficients to [1, 0, 0, 0]) and equal the pointwise recursion at u = 0, 0.3, 1.
    #[test]
    fn a_spans_polynomials_are_the_pointwise_recursion() {
        let t = [0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 3.0, 3.1, 7.0, 7.0, 7.0, 7.0];
        let (mut values, mut scratch) = ([0.0; 4], [0.0; 4]);
        for i in 3..t.len() - 4 {
            if t[i + 1] <= t[i] {
                continue;
            }
            let polys = cubic_span_polynomials(&t, i);
            for d in 0..4 {
                let sum: f64 = polys.iter().map(|p| p[d]).sum();
                let want = if d == 0 { 1.0 } else { 0.0 };
                assert!((sum - want).abs() < 1e-13, "span {i}, u^{d}: {sum}");
            }
            for u in [0.0, 0.3, 1.0] {
                let x = t[i] + u * (t[i + 1] - t[i]);
                basis_in(&t, 3, x, i, 0, &mut values, &mut scratch);
                for (j, p) in polys.iter().enumerate() {
                    let at = p[0] + u * (p[1] + u * (p[2] + u * p[3]));
                    assert!((at - values[j]).abs() < 1e-13, "span {i}, u {u}, N_{j}");
                }
            }
        }
    }

    /// At each knot that starts a span, clamped ends included, `cubic_at_knot` gives
    /// `basis_in`'s values bit for bit.
    #[test]
    fn the_cubic_at_a_knot_is_the_recursion() {
        let mut x: Vec<f64> = vec![0.0];
        let mut seed = 7_u64;
        for _ in 0..40 {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            let step = ((seed >> 11) as f64 / (1_u64 << 53) as f64) * 3.0 + 1e-6;
            x.push(x[x.len() - 1] + step);
        }
        let n = x.len();
        let t: Vec<f64> = [x[0]; 3]
            .iter()
            .chain(&x)
            .chain(&[x[n - 1]; 3])
            .copied()
            .collect();
        let (mut values, mut scratch) = ([0.0; 4], [0.0; 4]);
        for l in 3..n + 2 {
            basis_in(&t, 3, t[l], l, 0, &mut values, &mut scratch);
            let fast = cubic_at_knot(&t, l);
            assert_eq!(fast.map(f64::to_bits), values.map(f64::to_bits), "span {l}");
        }
    }

    /// The clamped quadratic on knots 0 0 0 1 2 2 2 with coefficients 0 1 2 3 is x (its
    /// control points at the Greville abscissae 0, 0.5, 1.5, 2): values and slopes inside
    /// and past both ends, the second derivative zero.
    #[test]
    fn a_line_in_the_quadratic_basis() {
        let t = [0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0];
        let c = [0.0, 0.5, 1.5, 2.0];
        let x = [-1.0, 0.0, 0.3, 1.0, 1.7, 2.0, 3.0];
        let mut out = [0.0; 7];
        for powers in [false, true] {
            evaluate(&t, &c, 1, 2, &x, 0, powers, &mut out);
            for (o, &at) in out.iter().zip(&x) {
                assert!((o - at).abs() < 1e-15, "{o} at {at}");
            }
            evaluate(&t, &c, 1, 2, &x, 1, powers, &mut out);
            assert!(out.iter().all(|&o| (o - 1.0).abs() < 1e-15));
            evaluate(&t, &c, 1, 2, &x, 2, powers, &mut out);
            assert!(out.iter().all(|&o| o.abs() < 1e-15));
            evaluate(&t, &c, 1, 2, &x, 3, powers, &mut out);
            assert!(out.iter().all(|&o| o == 0.0));
            let mut one = [0.0];
            evaluate(&t, &c, 1, 2, &[f64::NAN], 2, powers, &mut one);
            assert!(one[0].is_nan());
        }
    }
}
