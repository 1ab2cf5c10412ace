//! `SegmentTable`: a fitted curve as a list of cubic segments in power form, in f64.
//!
//! Segment i covers the parameter interval [t_i, t_{i+1}] (length Δ_i) and is written in its
//! local parameter u = (t − t_i)/Δ_i in [0, 1] as
//!
//! ```text
//! P_i(u) = A u^3 + B u^2 + C u + D          (each of A..D a vector of `dim` coordinates)
//! dP/dt  = (3A u^2 + 2B u + C) / Δ_i
//! d2P/dt2 = (6A u + 2B) / Δ_i^2
//! ```
//!
//! Every curve kind ends up here: the uniform families as `[u^3 u^2 u 1] · M · X` with the
//! product M·X formed on the host (`fit::uniform`), interpolating splines from their solved
//! coefficients. The GPU evaluator reads these coefficients (rounded to f32 only after they were
//! formed in f64), and the CPU reference evaluates them in f64.
//!
//! A weighted NURBS's segments are rational: P(u) = D + (A u³ + B u² + C u) / W(u), with the
//! cubic W of each segment held beside the table ([`Denominator`], module
//! [`rational`](crate::rational)); the polynomial case is W ≡ 1.

use std::sync::OnceLock;

use crate::error::InputError;
use crate::locator::Locator;
use crate::rational::{Denominator, quotient};

/// One curve's segments in power form, with the parameter value of every knot.
///
/// `Default` is an empty table, for a fit to fill in place (the interpolating fits reuse one
/// table across curves).
#[derive(Clone, Debug, Default)]
pub struct SegmentTable {
    dim: usize,
    /// `segments + 1` strictly increasing parameter values.
    knots: Vec<f64>,
    /// Per segment `4 * dim` values: A (dim values), B, C, D.
    coeffs: Vec<f64>,
    /// The curve's extent E: the largest per-axis (max − min) over its input points.
    extent: f64,
    /// Per segment its denominator, for a rational curve; empty for a polynomial one.
    denominators: Vec<Denominator>,
    /// Buckets over the knots for locating many scattered t, made on first use (and `None`
    /// where they cannot be formed): derived from `knots`, so ignored by `==`.
    locator: OnceLock<Option<Locator>>,
}

/// Tables are equal when their dimension, knots, coefficients and extent are.
impl PartialEq for SegmentTable {
    fn eq(&self, other: &Self) -> bool {
        (
            self.dim,
            &self.knots,
            &self.coeffs,
            self.extent,
            &self.denominators,
        ) == (
            other.dim,
            &other.knots,
            &other.coeffs,
            other.extent,
            &other.denominators,
        )
    }
}

/// A borrowed view of one segment of a [`SegmentTable`].
#[derive(Clone, Copy, Debug)]
pub struct Segment<'a> {
    /// A, B, C, D, each `dim` values.
    coeffs: &'a [f64],
    dim: usize,
    t0: f64,
    dt: f64,
    /// W(u), for a rational segment.
    denominator: Option<Denominator>,
}

impl SegmentTable {
    /// A table from its parts. `coeffs` holds `4 * dim` values per segment (A, B, C, D) and
    /// `knots` one more value than there are segments. The parts come from this crate's fits,
    /// which guarantee these shapes.
    pub(crate) fn from_parts(dim: usize, knots: Vec<f64>, coeffs: Vec<f64>, extent: f64) -> Self {
        debug_assert_eq!(coeffs.len(), 4 * dim * (knots.len() - 1));
        Self {
            dim,
            knots,
            coeffs,
            extent,
            denominators: Vec::new(),
            locator: OnceLock::new(),
        }
    }

    /// A polynomial table from its power form, as [`Segment::power`] and [`Self::knots`] give
    /// it back: `knots` (segments + 1 strictly increasing finite values), `coeffs` (per
    /// segment A, B, C, D, `dim` values each, finite) and the extent E of the accuracy promise
    /// (finite, >= 0). A table saved as these parts is restored bit for bit (the Python
    /// package pickles its splines this way).
    ///
    /// # Errors
    /// The first part that breaks a rule, naming "points", "knots", "coefficients" or
    /// "extent" and the value.
    pub fn from_power(
        dim: usize,
        knots: Vec<f64>,
        coeffs: Vec<f64>,
        extent: f64,
    ) -> Result<Self, InputError> {
        use crate::error::Shown;
        if dim == 0 || dim > crate::points::MAX_DIM {
            return Err(InputError::field(
                "points",
                format!(
                    "must have 1 to {} coordinates, got {dim}",
                    crate::points::MAX_DIM
                ),
            ));
        }
        if knots.len() < 2 {
            return Err(InputError::field(
                "knots",
                format!("needs at least 2 values, got {}", knots.len()),
            ));
        }
        crate::checks::check_increasing("knots", &knots, crate::checks::Order::Strictly)?;
        let wanted = 4 * dim * (knots.len() - 1);
        if coeffs.len() != wanted {
            return Err(InputError::field(
                "coefficients",
                format!(
                    "must have 4 * {dim} values per segment ({wanted}), got {}",
                    coeffs.len()
                ),
            ));
        }
        if let Some(i) = coeffs.iter().position(|c| !c.is_finite()) {
            return Err(InputError::field(
                "coefficients",
                format!("must be finite: coefficients[{i}] = {}", Shown(coeffs[i])),
            ));
        }
        if !(extent.is_finite() && extent >= 0.0) {
            return Err(InputError::field(
                "extent",
                format!("must be finite and >= 0, got {}", Shown(extent)),
            ));
        }
        Ok(Self::from_parts(dim, knots, coeffs, extent))
    }

    /// The knot and coefficient buffers as they are, for a fit to resize and refill (keeping
    /// their allocations); sets the dimension and extent, and makes the table polynomial.
    pub(crate) fn parts_mut(&mut self, dim: usize, extent: f64) -> (&mut Vec<f64>, &mut Vec<f64>) {
        self.dim = dim;
        self.extent = extent;
        self.locator = OnceLock::new();
        self.denominators.clear();
        (&mut self.knots, &mut self.coeffs)
    }

    /// [`Self::parts_mut`] for a rational curve, with its denominators' buffer besides.
    pub(crate) fn rational_parts_mut(
        &mut self,
        dim: usize,
        extent: f64,
    ) -> (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<Denominator>) {
        self.dim = dim;
        self.extent = extent;
        self.locator = OnceLock::new();
        (&mut self.knots, &mut self.coeffs, &mut self.denominators)
    }

    /// Segments `range` as a table of their own (same dimension and extent), knots included.
    ///
    /// # Panics
    /// If the range is empty or reaches past the last segment.
    #[must_use]
    pub fn slice(&self, range: std::ops::Range<usize>) -> Self {
        assert!(
            !range.is_empty() && range.end <= self.len(),
            "bad segment range {range:?}"
        );
        let n = 4 * self.dim;
        Self {
            dim: self.dim,
            knots: self.knots[range.start..=range.end].to_vec(),
            coeffs: self.coeffs[range.start * n..range.end * n].to_vec(),
            extent: self.extent,
            denominators: if self.is_rational() {
                self.denominators[range].to_vec()
            } else {
                Vec::new()
            },
            locator: OnceLock::new(),
        }
    }

    /// Whether the curve is rational (a weighted NURBS): its segments have a [`Denominator`].
    #[must_use]
    pub fn is_rational(&self) -> bool {
        !self.denominators.is_empty()
    }

    /// Number of coordinates of each point.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of segments (at least 1, but for an empty `Default` table).
    #[must_use]
    pub fn len(&self) -> usize {
        self.knots.len().saturating_sub(1)
    }

    /// True only for an empty `Default` table.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The locator over the knots, made on the first call (`None` where it cannot be formed).
    pub(crate) fn locator(&self) -> Option<&Locator> {
        self.locator
            .get_or_init(|| Locator::new(&self.knots))
            .as_ref()
    }

    /// The locator if one was made: `Some(None)` where it could not be formed, `None` where
    /// nobody asked yet.
    pub(crate) fn built_locator(&self) -> Option<Option<&Locator>> {
        self.locator.get().map(Option::as_ref)
    }

    /// Every segment's power-form coefficients, segment after segment, each as A, B, C, D
    /// (`dim` values each): what [`Segment::power`] slices.
    pub(crate) fn power_coefficients(&self) -> &[f64] {
        &self.coeffs
    }

    /// Whether every coefficient is finite (a fit whose slopes overflow f64 makes some
    /// infinite or NaN).
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.coeffs.iter().all(|c| c.is_finite())
    }

    /// The knots t_0 < t_1 < ... < t_len.
    #[must_use]
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The parameter range [t_0, t_len].
    #[must_use]
    pub fn t_range(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// The curve's extent E, the largest per-axis (max − min) over its input points; the scale
    /// of the GPU accuracy promise.
    #[must_use]
    pub fn extent(&self) -> f64 {
        self.extent
    }

    /// Checks that every sample of the curve, and of its derivatives up to `derivatives`, is
    /// finite in f64: per segment and coordinate, |A| + |B| + |C| + |D| bounds |P(u)|,
    /// (3|A| + 2|B| + |C|)/Δ bounds |dP/dt| and (6|A| + 2|B|)/Δ² bounds |d2P/dt2|. On a
    /// rational segment the derivatives' bounds are multiplied by (1 + 3|a| + 2|b| + |c|)^2
    /// and ^3 (W >= 1 and the quotient rule, see [`Denominator`](crate::Denominator)).
    ///
    /// # Errors
    /// The first segment whose bound overflows, naming `"points"` (the input's values are too
    /// large, or its knots too close, for f64).
    pub fn check_range(&self, derivatives: crate::Derivatives) -> Result<(), InputError> {
        let order = derivatives.order();
        for i in 0..self.len() {
            let segment = self.segment(i);
            let [a, b, c, d] = segment.power();
            let inv_dt = 1.0 / segment.dt();
            let growth = segment.denominator.map_or(1.0, |w| {
                let [wa, wb, wc, _] = w.coeffs.map(f64::abs);
                1.0 + 3.0 * wa + 2.0 * wb + wc
            });
            for k in 0..self.dim {
                let (a, b, c, d) = (a[k].abs(), b[k].abs(), c[k].abs(), d[k].abs());
                let bounds = [
                    a + b + c + d,
                    (3.0 * a + 2.0 * b + c) * inv_dt * growth * growth,
                    (6.0 * a + 2.0 * b) * inv_dt * inv_dt * growth * growth * growth,
                ];
                if let Some(o) = (0..=order).find(|&o| !bounds[o].is_finite()) {
                    let what = ["positions", "first derivatives", "second derivatives"][o];
                    return Err(InputError::field(
                        "points",
                        format!(
                            "give {what} beyond the float64 range on segment {i} \
                             (coordinate {k}): the values are too large for this curve"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Segment `i`.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    #[inline]
    #[must_use]
    pub fn segment(&self, i: usize) -> Segment<'_> {
        let n = 4 * self.dim;
        Segment {
            coeffs: &self.coeffs[i * n..(i + 1) * n],
            dim: self.dim,
            t0: self.knots[i],
            dt: self.knots[i + 1] - self.knots[i],
            denominator: self.denominators.get(i).copied(),
        }
    }
}

impl SegmentTable {
    /// The uniform cubic B-spline control points B_0..B_n of the curve (flat, `dim` values
    /// each), when its knots are evenly spaced (within 1e-12 relative): every C2 cubic spline
    /// on uniform knots is a uniform B-spline. Segment i's Bezier points are
    /// (S_i, 2/3 B_i + 1/3 B_{i+1}, 1/3 B_i + 2/3 B_{i+1}, S_{i+1}) (the course notes "Cubic spline curves", §4), so
    /// B_i = 2 P1_i − P2_i and B_n = 2 P2_{n−1} − P1_{n−1}. For a natural spline this is those
    /// notes' relaxed B-spline, with B_0 = S_0 and B_n = S_n.
    ///
    /// `None` for uneven knots, for a curve that is only C1 (then no B-spline matches every
    /// segment, and the points returned would describe another curve), or for a rational one.
    #[must_use]
    pub fn bspline_control_points(&self) -> Option<Vec<f64>> {
        if self.is_rational() {
            return None;
        }
        let n = self.len();
        let h = self.knots[1] - self.knots[0];
        if (0..n).any(|i| ((self.knots[i + 1] - self.knots[i]) - h).abs() > 1e-12 * h) {
            return None;
        }
        let dim = self.dim;
        let mut b = Vec::with_capacity((n + 1) * dim);
        for i in 0..n {
            let [_, p1, p2, _] = self.segment(i).polynomial_bezier_points();
            b.extend((0..dim).map(|k| 2.0 * p1[k] - p2[k]));
        }
        let [_, p1, p2, _] = self.segment(n - 1).polynomial_bezier_points();
        b.extend((0..dim).map(|k| 2.0 * p2[k] - p1[k]));
        // The B_i must also reproduce the joints S_i = (B_{i−1} + 4B_i + B_{i+1})/6.
        let scale = self.coeffs.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        for i in 1..n {
            let [s, ..] = self.segment(i).polynomial_bezier_points();
            for k in 0..dim {
                let joint =
                    (b[(i - 1) * dim + k] + 4.0 * b[i * dim + k] + b[(i + 1) * dim + k]) / 6.0;
                if (joint - s[k]).abs() > 1e-9 * scale {
                    return None;
                }
            }
        }
        Some(b)
    }
}

impl Segment<'_> {
    /// The coefficients as Eberly writes them ("Fitting a Natural Spline to Samples of the Form
    /// (t, f(t))"), in t rather than u:
    /// S_i(t) = a + b (t − t_i) + c (t − t_i)² + d (t − t_i)³, i.e. a = D, b = C/Δ, c = B/Δ²,
    /// d = A/Δ³. Returns [a, b, c, d], `dim` values each.
    #[must_use]
    pub fn t_power(&self) -> [Vec<f64>; 4] {
        let [a, b, c, d] = self.power();
        let dt = self.dt;
        [
            d.to_vec(),
            c.iter().map(|v| v / dt).collect(),
            b.iter().map(|v| v / (dt * dt)).collect(),
            a.iter().map(|v| v / (dt * dt * dt)).collect(),
        ]
    }

    /// The segment's cubic Bezier control points P0..P3 (`dim` values each): P0 = D,
    /// P1 = D + C/3, P2 = D + (2C + B)/3, P3 = A + B + C + D. `None` for a rational segment,
    /// whose Bezier form is [`Segment::rational_bezier`].
    #[must_use]
    pub fn bezier_points(&self) -> Option<[Vec<f64>; 4]> {
        if self.denominator.is_some() {
            return None;
        }
        Some(self.polynomial_bezier_points())
    }

    /// The segment's rational Bezier control points Q0..Q3 (`dim` values each) and their
    /// weights ω0..ω3 (> 0): P(u) = Σ ω_i B_i(u) Q_i / Σ ω_i B_i(u), B_i the cubic Bernstein
    /// polynomials. A polynomial segment gives its Bezier points with weights 1.
    #[must_use]
    pub fn rational_bezier(&self) -> ([Vec<f64>; 4], [f64; 4]) {
        match &self.denominator {
            None => (self.polynomial_bezier_points(), [1.0; 4]),
            Some(w) => {
                let [a, b, c, d] = self.power();
                crate::rational::bezier(a, b, c, d, w)
            }
        }
    }

    /// W(u) of a rational segment (with the segment's weight ratio ρ); `None` for a
    /// polynomial one.
    #[must_use]
    pub fn denominator(&self) -> Option<Denominator> {
        self.denominator
    }

    /// [`Segment::bezier_points`] of a segment known to be polynomial.
    fn polynomial_bezier_points(&self) -> [Vec<f64>; 4] {
        let [a, b, c, d] = self.power();
        let k = 0..self.dim;
        [
            d.to_vec(),
            k.clone().map(|k| d[k] + c[k] / 3.0).collect(),
            k.clone()
                .map(|k| d[k] + (2.0 * c[k] + b[k]) / 3.0)
                .collect(),
            k.map(|k| a[k] + b[k] + c[k] + d[k]).collect(),
        ]
    }

    /// The power coefficient vectors (A, B, C, D), each `dim` values. On a rational segment
    /// these are its numerator's A, B, C and its origin D (see [`Denominator`](crate::Denominator)).
    #[inline]
    #[must_use]
    pub fn power(&self) -> [&[f64]; 4] {
        let d = self.dim;
        [
            &self.coeffs[..d],
            &self.coeffs[d..2 * d],
            &self.coeffs[2 * d..3 * d],
            &self.coeffs[3 * d..],
        ]
    }

    /// The start of the segment's parameter interval, t_i.
    #[inline]
    #[must_use]
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// The length Δ_i of the segment's parameter interval.
    #[inline]
    #[must_use]
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// P(u) into `out` (`dim` values), by Horner: D + u(C + u(B + uA)) (rational: D + R(u)).
    pub fn eval(&self, u: f64, out: &mut [f64]) {
        self.derivative_into(0, u, out);
    }

    /// dP/dt at local u into `out`: (C + u(2B + 3uA)) / Δ (rational: R'(u)/Δ).
    pub fn deriv(&self, u: f64, out: &mut [f64]) {
        self.derivative_into(1, u, out);
    }

    /// d2P/dt2 at local u into `out`: (2B + 6uA) / Δ^2 (rational: R''(u)/Δ²).
    pub fn deriv2(&self, u: f64, out: &mut [f64]) {
        self.derivative_into(2, u, out);
    }

    /// P, dP/dt and d2P/dt2 at local u into `p`, `d1` and `d2` at once: the values
    /// [`Segment::eval`], [`Segment::deriv`] and [`Segment::deriv2`] give, bit for bit, with
    /// the segment's coefficients read once.
    #[inline]
    pub(crate) fn jet(&self, u: f64, p: &mut [f64], d1: &mut [f64], d2: &mut [f64]) {
        if self.denominator.is_some() {
            for (order, out) in [p, d1, d2].into_iter().enumerate() {
                self.derivative_into(order, u, out);
            }
            return;
        }
        let [a, b, c, d] = self.power();
        let inv_dt = 1.0 / self.dt;
        for k in 0..self.dim {
            p[k] = position(a[k], b[k], c[k], d[k], u);
            d1[k] = first_derivative(a[k], b[k], c[k], u, inv_dt);
            d2[k] = second_derivative(a[k], b[k], u, inv_dt);
        }
    }

    /// d^order P/dt^order (order 0..=3) at local u into `out`, by the formulas of
    /// [`position`] and its siblings, or of [`rational`](crate::rational) on a rational
    /// segment.
    #[inline]
    pub(crate) fn derivative_into(&self, order: usize, u: f64, out: &mut [f64]) {
        let [a, b, c, d] = self.power();
        let inv_dt = 1.0 / self.dt;
        match &self.denominator {
            None => {
                for k in 0..self.dim {
                    out[k] = match order {
                        0 => position(a[k], b[k], c[k], d[k], u),
                        1 => first_derivative(a[k], b[k], c[k], u, inv_dt),
                        2 => second_derivative(a[k], b[k], u, inv_dt),
                        _ => third_derivative(a[k], inv_dt),
                    };
                }
            }
            Some(w) => {
                let w = w.at(u);
                for k in 0..self.dim {
                    out[k] = rational_derivative(order, a[k], b[k], c[k], d[k], u, inv_dt, &w);
                }
            }
        }
    }
}

/// One coordinate of d^order P/dt^order (order 0..=3) of a rational segment at u, with
/// `w` = [W, W', W'', W'''] at u: D + R, R'/Δ, R''/Δ² or R'''/Δ³ (see
/// [`rational`](crate::rational)).
#[expect(
    clippy::too_many_arguments,
    reason = "one coordinate's terms, inlined into loops"
)]
#[inline(always)]
pub(crate) fn rational_derivative(
    order: usize,
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    u: f64,
    inv_dt: f64,
    w: &[f64; 4],
) -> f64 {
    match order {
        0 => d + quotient::<0>(a, b, c, u, w)[0],
        1 => quotient::<1>(a, b, c, u, w)[1] * inv_dt,
        2 => quotient::<2>(a, b, c, u, w)[2] * inv_dt * inv_dt,
        _ => quotient::<3>(a, b, c, u, w)[3] * inv_dt * inv_dt * inv_dt,
    }
}

/// One coordinate of P(u) = A u^3 + B u^2 + C u + D by Horner, D + u(C + u(B + uA)): the order
/// every f64 evaluator of this crate uses, so that they agree bit for bit.
#[inline(always)]
pub(crate) fn position(a: f64, b: f64, c: f64, d: f64, u: f64) -> f64 {
    d + u * (c + u * (b + u * a))
}

/// One coordinate of dP/dt = (C + u(2B + 3uA)) / Δ, with `inv_dt` = 1/Δ.
#[inline(always)]
pub(crate) fn first_derivative(a: f64, b: f64, c: f64, u: f64, inv_dt: f64) -> f64 {
    (c + u * (2.0 * b + 3.0 * u * a)) * inv_dt
}

/// One coordinate of d2P/dt2 = (2B + 6uA) / Δ², with `inv_dt` = 1/Δ.
#[inline(always)]
pub(crate) fn second_derivative(a: f64, b: f64, u: f64, inv_dt: f64) -> f64 {
    (2.0 * b + 6.0 * u * a) * inv_dt * inv_dt
}

/// One coordinate of d³P/dt³ = 6A / Δ³ (constant on the segment), with `inv_dt` = 1/Δ.
#[inline(always)]
pub(crate) fn third_derivative(a: f64, inv_dt: f64) -> f64 {
    6.0 * a * inv_dt * inv_dt * inv_dt
}

#[cfg(test)]
mod tests {
    use crate::{Basis, Curve, CurveKind, Ends, Points};

    /// `jet` gives what eval, deriv and deriv2 give, bit for bit, on a polynomial curve and a
    /// rational one (a weighted NURBS of two spans), at the ends and inside each segment.
    #[test]
    fn a_jet_is_eval_deriv_and_deriv2_at_once() {
        let catmull_rom = CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Closed,
        };
        let points = vec![0.0, 0.0, 1.0, 2.0, 3.0, -1.0, 4.0, 0.5, 2.0, 3.0];
        let polynomial = Curve::new(catmull_rom, Points::new(2, points).unwrap()).unwrap();
        let nurbs = CurveKind::Nurbs {
            knots: vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0],
            weights: Some(vec![1.0, 0.5, 2.0, 1.5, 1.0]),
        };
        let control = vec![1.0, 0.0, 1.0, 1.0, 0.0, 1.0, -1.0, 2.0, -2.0, 0.5];
        let rational = Curve::new(nurbs, Points::new(2, control).unwrap()).unwrap();
        for curve in [&polynomial, &rational] {
            let table = curve.fit();
            for i in 0..table.len() {
                let segment = table.segment(i);
                for u in [0.0, 0.125, 0.5, 0.875, 1.0] {
                    let (mut p, mut d1, mut d2) = ([0.0; 2], [0.0; 2], [0.0; 2]);
                    segment.jet(u, &mut p, &mut d1, &mut d2);
                    let mut expected = [[0.0; 2]; 3];
                    segment.eval(u, &mut expected[0]);
                    segment.deriv(u, &mut expected[1]);
                    segment.deriv2(u, &mut expected[2]);
                    assert_eq!([p, d1, d2], expected, "segment {i} at u = {u}");
                }
            }
        }
        assert!(rational.fit().is_rational());
    }
}
