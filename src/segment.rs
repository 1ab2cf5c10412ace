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
//! product M·X formed on the host (this module), interpolating splines from their solved
//! coefficients. The GPU evaluator reads these coefficients (rounded to f32 only after they were
//! formed in f64), and the CPU reference evaluates them in f64.

use crate::basis::Rows;

/// One curve's segments in power form, with the parameter value of every knot.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentTable {
    dim: usize,
    /// `segments + 1` strictly increasing parameter values.
    knots: Vec<f64>,
    /// Per segment `4 * dim` values: A (dim values), B, C, D.
    coeffs: Vec<f64>,
    /// The curve's extent E: the largest per-axis (max − min) over its input points.
    extent: f64,
}

/// A borrowed view of one segment of a [`SegmentTable`].
#[derive(Clone, Copy, Debug)]
pub struct Segment<'a> {
    /// A, B, C, D, each `dim` values.
    coeffs: &'a [f64],
    dim: usize,
    t0: f64,
    dt: f64,
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
        }
    }

    /// Segments of a uniform 4x4-matrix spline: segment i is `U · M · X_i`, its knots i and i+1.
    ///
    /// `window(i)` gives the indices (into `points`, `dim` values each) of segment i's four
    /// control points. The power coefficients are M·X in f64: row r of M times the window gives
    /// the coefficient of u^(3−r).
    pub(crate) fn from_windows(
        dim: usize,
        points: &[f64],
        rows: &Rows,
        segments: usize,
        extent: f64,
        window: impl Fn(usize) -> [usize; 4],
    ) -> Self {
        let mut coeffs = Vec::with_capacity(segments * 4 * dim);
        for i in 0..segments {
            let w = window(i);
            for row in rows {
                for k in 0..dim {
                    let mut v = 0.0;
                    for (m, &p) in row.iter().zip(&w) {
                        v += m * points[p * dim + k];
                    }
                    coeffs.push(v);
                }
            }
        }
        let knots = (0..=segments).map(|i| i as f64).collect();
        Self::from_parts(dim, knots, coeffs, extent)
    }

    /// Number of coordinates of each point.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of segments (at least 1).
    #[must_use]
    pub fn len(&self) -> usize {
        self.knots.len() - 1
    }

    /// Always false: a table has at least one segment.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
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

    /// Segment `i`.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    #[must_use]
    pub fn segment(&self, i: usize) -> Segment<'_> {
        let n = 4 * self.dim;
        Segment {
            coeffs: &self.coeffs[i * n..(i + 1) * n],
            dim: self.dim,
            t0: self.knots[i],
            dt: self.knots[i + 1] - self.knots[i],
        }
    }
}

impl Segment<'_> {
    /// The power coefficient vectors (A, B, C, D), each `dim` values.
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
    #[must_use]
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// The length Δ_i of the segment's parameter interval.
    #[must_use]
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// P(u) into `out` (`dim` values), by Horner: D + u(C + u(B + uA)).
    pub fn eval(&self, u: f64, out: &mut [f64]) {
        let [a, b, c, d] = self.power();
        for k in 0..self.dim {
            out[k] = d[k] + u * (c[k] + u * (b[k] + u * a[k]));
        }
    }

    /// dP/dt at local u into `out`: (C + u(2B + 3uA)) / Δ.
    pub fn deriv(&self, u: f64, out: &mut [f64]) {
        let [a, b, c, _] = self.power();
        let inv_dt = 1.0 / self.dt;
        for k in 0..self.dim {
            out[k] = (c[k] + u * (2.0 * b[k] + 3.0 * u * a[k])) * inv_dt;
        }
    }

    /// d2P/dt2 at local u into `out`: (2B + 6uA) / Δ^2.
    pub fn deriv2(&self, u: f64, out: &mut [f64]) {
        let [a, b, _, _] = self.power();
        let inv_dt = 1.0 / self.dt;
        for k in 0..self.dim {
            out[k] = (2.0 * b[k] + 6.0 * u * a[k]) * inv_dt * inv_dt;
        }
    }
}
