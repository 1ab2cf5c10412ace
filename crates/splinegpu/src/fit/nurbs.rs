//! Cubic B-splines on their own knot vector (kind "nurbs"): each non-empty span becomes a
//! power-form segment, so the kernel evaluates them as any other kind, and with weights a
//! rational one (a numerator and a denominator in power form).
//!
//! On span i ([k_i, k_{i+1}], Δ = k_{i+1} − k_i > 0, 3 <= i < n) the curve is
//! Σ_{j=i−3..i} N_{j,3}(t) P_j. With t = k_i + Δu, each basis function there is a cubic in u,
//! formed by the Cox–de Boor recursion on polynomials (`bsplines::de_boor`'s, the workspace's
//! one; a term whose denominator is 0 is 0):
//!
//! ```text
//! N_{j,0} = 1 for j = i, else 0
//! N_{j,p} = ((k_i − k_j) + Δu)/(k_{j+p} − k_j) · N_{j,p−1} + ((k_{j+p+1} − k_i) − Δu)/(k_{j+p+1} − k_{j+1}) · N_{j+1,p−1}
//! ```
//!
//! and the segment's A, B, C, D are the sums of the u³, u², u, 1 coefficients times the points.
//! Without weights this is `scipy.interpolate.BSpline(knots, points, 3)` on [k_3, k_n], and the
//! same cubic comes cheaper from its derivatives at the span's start (`Taylor`).
//!
//! With weights the span is rational, Σ w_j N_j P_j / Σ w_j N_j, written as
//! [`rational`](crate::rational) holds it: with ω_j = w_j / (the smallest of the span's four
//! weights) and the origin O = P(u = 0), the numerator Σ ω_j N_j (P_j − O) (whose constant
//! term is zero) and the denominator Σ ω_j N_j.

use crate::error::{InputError, Shown};
use crate::rational::Denominator;
use crate::segment::SegmentTable;

/// Checks a knot vector for `n` control points: n >= 4, n + 4 finite non-decreasing knots,
/// knots[3] < knots[n], no value more than 4 times, none strictly inside (knots[3], knots[n])
/// more than 3 times; weights, where given, n finite values > 0.
///
/// # Errors
/// The first rule broken, naming "points", "knots" or "weights" and the value.
pub(crate) fn check(knots: &[f64], weights: Option<&[f64]>, n: usize) -> Result<(), InputError> {
    if n < 4 {
        return Err(InputError::field(
            "points",
            format!("needs at least 4 points for a nurbs curve, got {n}"),
        ));
    }
    if let Some(weights) = weights {
        if weights.len() != n {
            return Err(InputError::field(
                "weights",
                format!("must have one value per point ({n}), got {}", weights.len()),
            ));
        }
        if let Some(i) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(InputError::field(
                "weights",
                format!(
                    "must be finite and > 0: weights[{i}] = {}",
                    Shown(weights[i])
                ),
            ));
        }
    }
    if knots.len() != n + 4 {
        return Err(InputError::field(
            "knots",
            format!(
                "must have n + 4 = {} values for {n} points, got {}",
                n + 4,
                knots.len()
            ),
        ));
    }
    crate::checks::check_increasing("knots", knots, crate::checks::Order::NonDecreasing)?;
    let (lo, hi) = (knots[3], knots[n]);
    if lo >= hi {
        return Err(InputError::field(
            "knots",
            format!(
                "must have knots[3] < knots[n]: knots[3] = {} and knots[{n}] = {}",
                Shown(lo),
                Shown(hi)
            ),
        ));
    }
    let mut start = 0;
    while start < knots.len() {
        let v = knots[start];
        let count = knots[start..].iter().take_while(|&&k| k == v).count();
        let inside = v > lo && v < hi;
        if count > 4 || (inside && count > 3) {
            let most = if inside {
                "3 times inside (knots[3], knots[n])"
            } else {
                "4 times"
            };
            return Err(InputError::field(
                "knots",
                format!(
                    "a value may appear at most {most}: {} appears {count} times from knots[{start}]",
                    Shown(v)
                ),
            ));
        }
        start += count;
    }
    Ok(())
}

/// The non-empty spans i (3 <= i < n, knots[i] < knots[i + 1]), in order.
pub(crate) fn spans(knots: &[f64], n: usize) -> impl Iterator<Item = usize> + '_ {
    (3..n).filter(move |&i| knots[i] < knots[i + 1])
}

/// The curve's segments into `out`, one per non-empty span (data already [`check`]ed):
/// rational where `weights` are given.
pub(crate) fn fit_into(
    knots: &[f64],
    weights: Option<&[f64]>,
    points: &[f64],
    dim: usize,
    extent: f64,
    out: &mut SegmentTable,
) {
    match weights {
        None => fit_polynomial(knots, points, dim, extent, out),
        Some(weights) => fit_rational(knots, weights, points, dim, extent, out),
    }
}

/// The polynomial B-spline's segments into `out`, each from its Taylor expansion at the
/// span's start (see [`Taylor`]).
fn fit_polynomial(knots: &[f64], points: &[f64], dim: usize, extent: f64, out: &mut SegmentTable) {
    let n = points.len() / dim;
    let spans: Vec<usize> = spans(knots, n).collect();
    let (table_knots, coeffs) = out.parts_mut(dim, extent);
    table_knots.clear();
    table_knots.extend(spans.iter().map(|&i| knots[i]));
    table_knots.push(knots[spans[spans.len() - 1] + 1]);
    coeffs.resize(4 * dim * spans.len(), 0.0);
    for (&i, c) in spans.iter().zip(coeffs.chunks_exact_mut(4 * dim)) {
        let taylor = Taylor::new(knots, i);
        let p = &points[(i - 3) * dim..][..4 * dim];
        for k in 0..dim {
            let segment = taylor.segment([p[k], p[dim + k], p[2 * dim + k], p[3 * dim + k]]);
            for (row, v) in segment.into_iter().enumerate() {
                c[row * dim + k] = v;
            }
        }
    }
}

/// Span i's factors for a polynomial segment from its four points P_0..P_3 (= P_{i−3..i}),
/// by the derivative's B-spline form (de Boor): f' = Σ Q_j N_{j,2} with
/// Q_j = 3 (P_j − P_{j−1}) / (k_{j+3} − k_j), f'' = Σ R_j N_{j,1} with
/// R_j = 2 (Q_j − Q_{j−1}) / (k_{j+2} − k_j), f''' = (R_i − R_{i−1}) / Δ on the span. At
/// u = 0 only N_{i−3..i−1,3}, N_{i−2..i−1,2} and N_{i−1,1} (= 1) are not zero:
///
/// ```text
/// f   = P_1 + α (P_0 − P_1) + β (P_2 − P_1),
///       α = Δ² / ((k_{i+1} − k_{i−2}) (k_{i+1} − k_{i−1})),
///       β = (k_i − k_{i−1})² / ((k_{i+2} − k_{i−1}) (k_{i+1} − k_{i−1}))
/// f'  = (Δ Q_{i−2} + (k_i − k_{i−1}) Q_{i−1}) / (k_{i+1} − k_{i−1})
/// f'' = R_{i−1}
/// ```
///
/// and the segment is D = f, C = Δ f', B = Δ² f'' / 2, A = Δ³ f''' / 6. Every denominator
/// spans [k_i, k_{i+1}], so none is below Δ > 0 (repeated knots need no special case), and
/// the Δ powers undo the divisions' scale: each coefficient's rounding stays within a few
/// ulps of the points' spread. A fraction of the Cox–de Boor recursion's arithmetic, which
/// the rational spans still use (`bsplines::de_boor::cubic_span_polynomials`).
struct Taylor {
    /// 3 / (k_{j+3} − k_j) for j = i−2, i−1, i.
    first: [f64; 3],
    /// 2 Δ² / (k_{j+2} − k_j) for j = i−1, i: R's factor with B's and A's Δ² in it.
    second: [f64; 2],
    /// α and β.
    value: [f64; 2],
    /// Δ² / (k_{i+1} − k_{i−1}) and Δ (k_i − k_{i−1}) / (k_{i+1} − k_{i−1}): C from Q.
    slope: [f64; 2],
}

impl Taylor {
    #[inline(always)]
    fn new(knots: &[f64], i: usize) -> Self {
        let k = |m: usize| knots[i + m - 2];
        // k(2) is k_i.
        let delta = k(3) - k(2);
        let before = k(2) - k(1);
        let (wide0, wide1, wide2) = (k(3) - k(0), k(4) - k(1), k(5) - k(2));
        let (near0, near1) = (k(3) - k(1), k(4) - k(2));
        let square = delta * delta;
        Self {
            first: [3.0 / wide0, 3.0 / wide1, 3.0 / wide2],
            second: [2.0 * square / near0, 2.0 * square / near1],
            value: [square / (wide0 * near0), before * before / (wide1 * near0)],
            slope: [square / near0, delta * before / near0],
        }
    }

    /// A, B, C, D (the u³, u², u, 1 coefficients) of one coordinate.
    #[inline(always)]
    fn segment(&self, p: [f64; 4]) -> [f64; 4] {
        let q = [
            (p[1] - p[0]) * self.first[0],
            (p[2] - p[1]) * self.first[1],
            (p[3] - p[2]) * self.first[2],
        ];
        // Δ² R_{i−1} and Δ² R_i.
        let r = [
            (q[1] - q[0]) * self.second[0],
            (q[2] - q[1]) * self.second[1],
        ];
        let f = p[1] + self.value[0] * (p[0] - p[1]) + self.value[1] * (p[2] - p[1]);
        let slope = self.slope[0] * q[0] + self.slope[1] * q[1];
        [(r[1] - r[0]) / 6.0, r[0] / 2.0, slope, f]
    }
}

/// The rational B-spline's segments into `out` (see the module docs).
fn fit_rational(
    knots: &[f64],
    weights: &[f64],
    points: &[f64],
    dim: usize,
    extent: f64,
    out: &mut SegmentTable,
) {
    let n = points.len() / dim;
    let spans: Vec<usize> = spans(knots, n).collect();
    let (table_knots, coeffs, denominators) = out.rational_parts_mut(dim, extent);
    table_knots.clear();
    table_knots.extend(spans.iter().map(|&i| knots[i]));
    table_knots.push(knots[spans[spans.len() - 1] + 1]);
    coeffs.resize(4 * dim * spans.len(), 0.0);
    denominators.clear();
    let mut origin = vec![0.0; dim];
    for (&i, c) in spans.iter().zip(coeffs.chunks_exact_mut(4 * dim)) {
        let basis = bsplines::de_boor::cubic_span_polynomials(knots, i);
        let w = &weights[i - 3..=i];
        let smallest = w.iter().copied().fold(f64::INFINITY, f64::min);
        let largest = w.iter().copied().fold(0.0, f64::max);
        let omega: [f64; 4] = std::array::from_fn(|j| w[j] / smallest);
        // W's coefficients (u³, u², u, 1), and O = Σ ω_j N_j(0) P_j / W(0).
        let mut den = [0.0; 4];
        for (poly, &o) in basis.iter().zip(&omega) {
            for row in 0..4 {
                den[row] += o * poly[3 - row];
            }
        }
        origin.fill(0.0);
        for (j, (poly, &o)) in basis.iter().zip(&omega).enumerate() {
            let p = &points[(i - 3 + j) * dim..][..dim];
            for k in 0..dim {
                origin[k] += o * poly[0] * p[k];
            }
        }
        for v in &mut origin {
            *v /= den[3];
        }
        // A, B, C of Σ ω_j N_j (P_j − O); its constant term is zero (O is P(0)); D holds O.
        c.fill(0.0);
        for (j, (poly, &o)) in basis.iter().zip(&omega).enumerate() {
            let p = &points[(i - 3 + j) * dim..][..dim];
            for row in 0..3 {
                for k in 0..dim {
                    c[row * dim + k] += o * poly[3 - row] * (p[k] - origin[k]);
                }
            }
        }
        c[3 * dim..].copy_from_slice(&origin);
        denominators.push(Denominator {
            coeffs: den,
            rho: largest / smallest,
        });
    }
}
