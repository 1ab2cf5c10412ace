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
///
/// A weighted NURBS span Σ w_j N_j P_j / Σ w_j N_j is held relative to its start O = P(0):
///
/// ```text
/// P(u) = D + N(u) / W(u)      D = O, N(u) = A u³ + B u² + C u (Segment::power's A, B, C)
/// R' = (N' − R W') / W,  R'' = (N'' − 2 R' W' − R W'') / W      (R = N / W)
/// ```
///
/// so that N and W are of the size of the span, not of its distance from the origin, and
/// W ≡ 1 is the polynomial case.
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

    /// |N^(k)(m)| (Euclidean) and W^(k)(m), k = 0..=3.
    fn at_middle(&self, m: f64) -> ([f64; 4], [f64; 4]) {
        let mut n = [0.0; 4];
        for k in 0..self.dim() {
            let (a, b, c) = (self.a[k], self.b[k], self.c[k]);
            let terms = [
                m * (c + m * (b + m * a)),
                c + m * (2.0 * b + 3.0 * m * a),
                2.0 * b + 6.0 * m * a,
                6.0 * a,
            ];
            for (n, t) in n.iter_mut().zip(terms) {
                *n += t * t;
            }
        }
        (n.map(f64::sqrt), self.w.at(m))
    }

    /// A bound on max |R''| over the cell [m − r, m + r].
    ///
    /// A cubic's k-th derivative on the cell is at most Σ_{j>=k} |f^(j)(m)| r^(j−k)/(j−k)!
    /// (Taylor at m, exact for a cubic); W is at least W(m) minus its bound on the change, and
    /// at least 1 everywhere. N = R·W differentiated (module docs) then bounds |R^(k)| on the
    /// cell one order after the other, and |R''(u)| <= |R''(m)| + r max|R'''|.
    fn cell_bound(&self, m: f64, r: f64) -> f64 {
        let (n, w) = self.at_middle(m);
        let over = |f: [f64; 4], k: usize| -> f64 {
            let mut sum = 0.0;
            let mut factor = 1.0;
            for (j, &value) in f.iter().enumerate().skip(k) {
                sum += value.abs() * factor;
                factor *= r / (j + 1 - k) as f64;
            }
            sum
        };
        let w_low = (w[0] - (over(w, 0) - w[0].abs())).max(1.0);
        let (n1, n2, n3) = (over(n, 1), over(n, 2), over(n, 3));
        let (w1, w2, w3) = (over(w, 1), over(w, 2), over(w, 3));
        let r0 = over(n, 0) / w_low;
        let r1 = (n1 + r0 * w1) / w_low;
        let r2 = (n2 + 2.0 * r1 * w1 + r0 * w2) / w_low;
        let r3 = (n3 + 3.0 * r2 * w1 + 3.0 * r1 * w2 + r0 * w3) / w_low;
        r2.min(self.norm_at(m, 2) + r * r3)
    }

    /// A proven bound M̂ on max |R''(u)| over [0, 1] (in u): [0, 1] is cut into n cells, each
    /// bounded by [`Self::cell_bound`]. n doubles from 16 until M̂ is at most twice the largest
    /// |R''| at the cells' middles (a lower bound of the true maximum, so then
    /// M̂ <= 2 max|R''|), or n reaches 2^12 (then M̂ is still a bound, only a looser one).
    pub(crate) fn second_derivative_bound(&self) -> f64 {
        let mut n = 16usize;
        loop {
            let r = 0.5 / n as f64;
            let (mut bound, mut seen) = (0.0f64, 0.0f64);
            for i in 0..n {
                let m = (2 * i + 1) as f64 * r;
                bound = bound.max(self.cell_bound(m, r));
                seen = seen.max(self.norm_at(m, 2));
            }
            if bound <= 2.0 * seen || n >= MAX_BOUND_INTERVALS || !bound.is_finite() {
                return bound;
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
