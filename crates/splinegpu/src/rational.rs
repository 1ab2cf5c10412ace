//! Rational cubic segments (kind "nurbs" with weights): the quotient, its derivatives by the
//! quotient rule, and the bounds the samplings need, in f64.
//!
//! A weighted span is P(t) = Σ w_j N_j P_j / Σ w_j N_j. The fit writes it relative to a local
//! origin O = P(u = 0), with the weights divided by the smallest of the span's four:
//!
//! ```text
//! P(u) = O + R(u),   R(u) = N(u) / W(u)
//! N(u) = A u³ + B u² + C u          (Σ (w_j/w_min) N_j(u) (P_j − O): zero at u = 0)
//! W(u) = a u³ + b u² + c u + d      (Σ (w_j/w_min) N_j(u) >= 1 on [0, 1])
//! ```
//!
//! so that the segment's power form keeps its meaning (D = O, and W ≡ 1 is the polynomial
//! case) and large coordinates cost nothing: N and W are of the size of the span, not of its
//! distance from the origin. Differentiating N = R·W:
//!
//! ```text
//! R'   = (N'   − R W') / W
//! R''  = (N''  − 2 R' W' − R W'') / W
//! R''' = (N''' − 3 R'' W' − 3 R' W'' − R W''') / W
//! ```
//!
//! (u-derivatives; d/dt divides the k-th by Δ^k). The kernel, its f32 twin and the CPU
//! evaluators all use these formulas in this order.

/// A rational segment's denominator W(u) = a u³ + b u² + c u + d (the weights divided by the
/// smallest of the segment's four control points' weights, so W >= 1 on [0, 1]), and ρ, the
/// largest of those weights over the smallest (the factor of the GPU promise on the segment).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Denominator {
    /// a, b, c, d: the u³, u², u and 1 coefficients.
    pub coeffs: [f64; 4],
    /// The largest weight of the segment's four control points over the smallest (>= 1).
    pub rho: f64,
}

impl Denominator {
    /// W and its first three u-derivatives at u.
    #[inline(always)]
    #[must_use]
    pub(crate) fn at(&self, u: f64) -> [f64; 4] {
        let [a, b, c, d] = self.coeffs;
        [
            d + u * (c + u * (b + u * a)),
            c + u * (2.0 * b + 3.0 * u * a),
            2.0 * b + 6.0 * u * a,
            6.0 * a,
        ]
    }

    /// Bounds on max |W^(k)| over [0, 1], k = 1, 2, 3 (the triangle inequality on the power
    /// form: |W'| <= 3|a| + 2|b| + |c|, |W''| <= 6|a| + 2|b|, |W'''| = 6|a|).
    fn derivative_bounds(&self) -> [f64; 3] {
        let [a, b, c, _] = self.coeffs.map(f64::abs);
        [3.0 * a + 2.0 * b + c, 6.0 * a + 2.0 * b, 6.0 * a]
    }
}

/// R and its u-derivatives up to `ORDER` (at most 3) in one coordinate, from N's coefficients
/// (A, B, C) and W's values `w` = [W, W', W'', W'''] at u (see the module docs).
#[inline(always)]
#[must_use]
pub(crate) fn quotient<const ORDER: usize>(
    a: f64,
    b: f64,
    c: f64,
    u: f64,
    w: &[f64; 4],
) -> [f64; 4] {
    let inv = 1.0 / w[0];
    let r = u * (c + u * (b + u * a)) * inv;
    let mut out = [r, 0.0, 0.0, 0.0];
    if ORDER >= 1 {
        out[1] = ((c + u * (2.0 * b + 3.0 * u * a)) - r * w[1]) * inv;
    }
    if ORDER >= 2 {
        out[2] = ((2.0 * b + 6.0 * u * a) - 2.0 * out[1] * w[1] - r * w[2]) * inv;
    }
    if ORDER >= 3 {
        out[3] = (6.0 * a - 3.0 * out[2] * w[1] - 3.0 * out[1] * w[2] - r * w[3]) * inv;
    }
    out
}

/// The power form of N (A, B, C, each `dim` values) and W of one segment, for the bounds.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RationalCubic<'a> {
    pub a: &'a [f64],
    pub b: &'a [f64],
    pub c: &'a [f64],
    pub w: Denominator,
}

impl RationalCubic<'_> {
    fn dim(&self) -> usize {
        self.a.len()
    }

    /// |R^(k)(u)| (Euclidean, in u), k = `order` <= 3.
    pub(crate) fn norm_at(&self, u: f64, order: usize) -> f64 {
        let w = self.w.at(u);
        (0..self.dim())
            .map(|k| quotient::<3>(self.a[k], self.b[k], self.c[k], u, &w)[order].powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// Bounds on max |R^(k)| over [0, 1], k = 0..=3, from N = R·W differentiated (module
    /// docs) and W >= 1: |R| <= |A| + |B| + |C|, then each |R^(k)| <= |N^(k)| + Σ binom ·
    /// |R^(j)| |W^(k−j)|, with the norms of N's derivatives by the triangle inequality.
    fn derivative_bounds(&self) -> [f64; 4] {
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let (a, b, c) = (norm(self.a), norm(self.b), norm(self.c));
        let n = [a + b + c, 3.0 * a + 2.0 * b + c, 6.0 * a + 2.0 * b, 6.0 * a];
        let [w1, w2, w3] = self.w.derivative_bounds();
        let r0 = n[0];
        let r1 = n[1] + r0 * w1;
        let r2 = n[2] + 2.0 * r1 * w1 + r0 * w2;
        let r3 = n[3] + 3.0 * r2 * w1 + 3.0 * r1 * w2 + r0 * w3;
        [r0, r1, r2, r3]
    }

    /// A proven bound M̂ on max |R''(u)| over [0, 1] (in u): the largest |R''| on a grid of
    /// n + 1 points plus the most it can grow between them, h/2 · max|R'''| with h = 1/n and
    /// max|R'''| bounded as in [`Self::derivative_bounds`]. The grid doubles from 16 points
    /// until that margin is at most the grid's maximum (then M̂ <= 2 max|R''|), or 2^12
    /// intervals are reached (then M̂ is still a bound, only a looser one).
    pub(crate) fn second_derivative_bound(&self) -> f64 {
        let third = self.derivative_bounds()[3];
        let mut n = 16usize;
        loop {
            let grid = (0..=n)
                .map(|i| self.norm_at(i as f64 / n as f64, 2))
                .fold(0.0f64, f64::max);
            let margin = 0.5 * third / n as f64;
            if margin <= grid || n >= MAX_BOUND_INTERVALS || !margin.is_finite() {
                return grid + margin;
            }
            n *= 2;
        }
    }
}

/// The finest grid [`RationalCubic::second_derivative_bound`] evaluates.
const MAX_BOUND_INTERVALS: usize = 1 << 12;

/// The rational Bezier form of a segment: control points Q_0..Q_3 (`dim` values each) and
/// their weights ω_0..ω_3, with P(u) = Σ ω_i B_i(u) Q_i / Σ ω_i B_i(u), B_i the Bernstein
/// polynomials. The weights are W's Bernstein coefficients, the homogeneous points
/// (ω_i Q_i − ω_i O) N's, so Q_i = O + N_i / ω_i.
#[must_use]
pub(crate) fn bezier(
    a: &[f64],
    b: &[f64],
    c: &[f64],
    origin: &[f64],
    w: &Denominator,
) -> ([Vec<f64>; 4], [f64; 4]) {
    // Power (u³, u², u, 1) to Bernstein: b0 = d, b1 = d + c/3, b2 = d + (2c + b)/3,
    // b3 = a + b + c + d.
    let bernstein =
        |a: f64, b: f64, c: f64, d: f64| [d, d + c / 3.0, d + (2.0 * c + b) / 3.0, a + b + c + d];
    let [wa, wb, wc, wd] = w.coeffs;
    let weights = bernstein(wa, wb, wc, wd);
    let points = std::array::from_fn(|i| {
        (0..a.len())
            .map(|k| origin[k] + bernstein(a[k], b[k], c[k], 0.0)[i] / weights[i])
            .collect()
    });
    (points, weights)
}
