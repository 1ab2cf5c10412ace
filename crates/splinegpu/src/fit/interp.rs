//! Interpolating cubic splines through (t_i, f_i), f_i in R^D: natural, clamped, periodic and
//! not-a-knot ends, any strictly increasing knots, solved in f64 in O(n) time and memory.
//!
//! The unknowns are the slopes m_i = S'(t_i). With Δ_i = t_{i+1} − t_i and
//! q_i = (f_{i+1} − f_i)/Δ_i, C2 continuity at an interior knot reads (D. Eberly, "Fitting a
//! Natural Spline to Samples of the Form (t, f(t))", eq. 26 with its index typo corrected)
//!
//! ```text
//! Δ_i m_{i−1} + 2(Δ_{i−1} + Δ_i) m_i + Δ_{i−1} m_{i+1} = 3(Δ_i q_{i−1} + Δ_{i−1} q_i)
//! ```
//!
//! and the ends add one row each:
//! - natural (Eberly §2, "free"): S''(t_0) = 0 gives 2m_0 + m_1 = 3q_0; likewise at the end;
//! - clamped (Eberly §3): m_0 = σ_0 and m_{n−1} = σ_1, derivatives with respect to t;
//! - not-a-knot (the course notes "Cubic spline curves", §9): S''' continuous at t_1 and
//!   t_{n−2}, which gives
//!   Δ_1 m_0 + (Δ_0 + Δ_1) m_1 = ((Δ_0 + 2(Δ_0 + Δ_1)) Δ_1 q_0 + Δ_0² q_1)/(Δ_0 + Δ_1)
//!   and its mirror image;
//! - periodic (Eberly §4): f_{n−1} = f_0, and the interior row also holds at t_0 with the
//!   indices taken cyclically over the n − 1 segments. Eberly notes that eliminating its
//!   block system directly is ill-conditioned; here the cyclic tridiagonal slope system, which
//!   is strictly diagonally dominant, goes through Sherman–Morrison ([`solve_cyclic`]).
//!
//! Every system is solved by banded elimination with partial pivoting, once for all D
//! coordinates. Segment i is then the cubic Hermite piece of (f_i, m_i, f_{i+1}, m_{i+1}), in
//! local u = (t − t_i)/Δ_i:
//!
//! ```text
//! A = 2(f_i − f_{i+1}) + Δ_i (m_i + m_{i+1})     B = 3(f_{i+1} − f_i) − Δ_i (2m_i + m_{i+1})
//! C = Δ_i m_i                                     D = f_i
//! ```

use super::blocked::{BlockedScratch, Rows, SOLVE_BLOCK, solve_blocked};
use super::tridiag::{CyclicScratch, Tridiagonal, solve_cyclic, solve_tridiagonal};
use crate::error::{InputError, Shown};
use crate::fit::hermite::hermite_segments_for;
use crate::segment::SegmentTable;

/// How an interpolating spline behaves at its two ends.
#[derive(Clone, Debug, PartialEq)]
pub enum EndCondition {
    /// Second derivative zero at both ends (the "relaxed" or "free" spline). n >= 2.
    Natural,
    /// Given first derivatives (with respect to t) at both ends, D values each. n >= 2.
    Clamped {
        /// dP/dt at t_0.
        start: Vec<f64>,
        /// dP/dt at t_{n−1}.
        end: Vec<f64>,
    },
    /// First and last point equal (within 1e-12 of the curve's extent); value, slope and
    /// curvature match across the seam. n >= 3.
    Periodic,
    /// Third derivative continuous at the second and the next-to-last knot. n >= 4.
    NotAKnot,
}

/// An end condition without its data, for [`CardinalBasis`](super::cardinal::CardinalBasis):
/// a clamped spline's end derivatives are then inputs like the points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndKind {
    /// See [`EndCondition::Natural`].
    Natural,
    /// See [`EndCondition::Clamped`].
    Clamped,
    /// See [`EndCondition::Periodic`].
    Periodic,
    /// See [`EndCondition::NotAKnot`].
    NotAKnot,
}

impl EndCondition {
    /// The condition without its data.
    #[must_use]
    pub fn kind(&self) -> EndKind {
        match self {
            EndCondition::Natural => EndKind::Natural,
            EndCondition::Clamped { .. } => EndKind::Clamped,
            EndCondition::Periodic => EndKind::Periodic,
            EndCondition::NotAKnot => EndKind::NotAKnot,
        }
    }

    /// The contract's name of the condition ("natural", "clamped", ...).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            EndCondition::Natural => "natural",
            EndCondition::Clamped { .. } => "clamped",
            EndCondition::Periodic => "periodic",
            EndCondition::NotAKnot => "not-a-knot",
        }
    }

    /// The fewest points the condition accepts.
    #[must_use]
    pub fn min_points(&self) -> usize {
        match self {
            EndCondition::Natural | EndCondition::Clamped { .. } => 2,
            EndCondition::Periodic => 3,
            EndCondition::NotAKnot => 4,
        }
    }
}

/// Checks the data of an interpolating spline: n >= the condition's minimum, one strictly
/// increasing finite t per point, finite values, end derivatives of dimension `dim`, and for a
/// periodic spline a last point equal to the first within 1e-12 of the extent.
///
/// # Errors
/// The first rule broken, naming the field ("points", "t", "start_derivative",
/// "end_derivative") and the value.
pub(crate) fn check(
    t: &[f64],
    values: &[f64],
    dim: usize,
    condition: &EndCondition,
) -> Result<(), InputError> {
    check_with(t, values, dim, condition, || {
        crate::points::all_finite(values)
    })
}

/// Checks parameter values "t": every one finite and each greater than the one before.
/// Branch-free passes first (vectorized); the searches for the first bad value run only when
/// there is one.
///
/// # Errors
/// The first value that is not finite, or the first that does not increase, naming "t".
pub(crate) fn check_parameters(t: &[f64]) -> Result<(), InputError> {
    let finite = crate::points::all_finite(t);
    if let Some(i) = (!finite)
        .then(|| t.iter().position(|v| !v.is_finite()))
        .flatten()
    {
        return Err(InputError::field(
            "t",
            format!("must be finite: t[{i}] = {}", Shown(t[i])),
        ));
    }
    let increasing = t.windows(2).fold(true, |ok, w| ok & (w[1] > w[0]));
    if let Some(i) = (!increasing)
        .then(|| (1..t.len()).find(|&i| t[i] <= t[i - 1]))
        .flatten()
    {
        return Err(InputError::field(
            "t",
            format!(
                "must be strictly increasing: t[{i}] = {} follows t[{}] = {}",
                Shown(t[i]),
                i - 1,
                Shown(t[i - 1])
            ),
        ));
    }
    Ok(())
}

/// [`check`], asking `points_finite` whether every value is finite when it comes to them (a
/// large fit finds out on another thread while this one checks t).
fn check_with(
    t: &[f64],
    values: &[f64],
    dim: usize,
    condition: &EndCondition,
    points_finite: impl FnOnce() -> bool,
) -> Result<(), InputError> {
    let n = values.len() / dim;
    let (name, min) = (condition.name(), condition.min_points());
    if n < min {
        return Err(InputError::field(
            "points",
            format!("needs at least {min} points for a {name} spline, got {n}"),
        ));
    }
    if t.len() != n {
        return Err(InputError::field(
            "t",
            format!("must have one value per point ({n}), got {}", t.len()),
        ));
    }
    check_parameters(t)?;
    if !points_finite() {
        crate::points::check_finite(values, dim)?;
    }
    match condition {
        EndCondition::Clamped { start, end } => {
            for (field, v) in [("start_derivative", start), ("end_derivative", end)] {
                if v.len() != dim {
                    return Err(InputError::field(
                        field,
                        format!(
                            "must have {dim} values (the points' dimension), got {}",
                            v.len()
                        ),
                    ));
                }
                if let Some(k) = v.iter().position(|x| !x.is_finite()) {
                    return Err(InputError::field(
                        field,
                        format!("must be finite: {field}[{k}] = {}", Shown(v[k])),
                    ));
                }
            }
        }
        EndCondition::Periodic => {
            let extent = crate::points::extent(values, dim);
            let (first, last) = (&values[..dim], &values[(n - 1) * dim..]);
            if let Some(k) = (0..dim).find(|&k| (first[k] - last[k]).abs() > 1e-12 * extent) {
                return Err(InputError::field(
                    "points",
                    format!(
                        "of a periodic spline must end where they start: points[{}][{k}] = {} but points[0][{k}] = {}",
                        n - 1,
                        Shown(last[k]),
                        Shown(first[k])
                    ),
                ));
            }
        }
        EndCondition::Natural | EndCondition::NotAKnot => {}
    }
    Ok(())
}

/// Reusable scratch space for fits: a caller fitting many curves, or one large curve again and
/// again, allocates nothing after the first fit of each size.
#[derive(Clone, Debug, Default)]
pub struct Fitter {
    system: Tridiagonal,
    slopes: Vec<f64>,
    blocked: BlockedScratch,
    fill: Vec<f64>,
    cyclic: CyclicScratch,
}

/// Segments below which forming the coefficients stays on the calling thread.
const PARALLEL_SEGMENTS: usize = 1 << 16;

impl Fitter {
    /// A fitter with empty scratch space.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Fits the spline through `values` (n points of `dim` coordinates, point-major) at knots
    /// `t` into `out`, reusing `out`'s buffers.
    ///
    /// Cost: O(n·D) time and memory; forming the coefficients of a large fit is spread over the
    /// machine's threads.
    ///
    /// # Errors
    /// The data break a rule of interpolation (t strictly increasing and one per point, enough
    /// points for the end condition, periodic ends equal, clamped derivatives of D values).
    pub fn fit_into(
        &mut self,
        t: &[f64],
        values: &[f64],
        dim: usize,
        condition: &EndCondition,
        out: &mut SegmentTable,
    ) -> Result<(), InputError> {
        let extent = if t.len() > PARALLEL_SEGMENTS {
            // The points' extent and finiteness on the pool while this thread checks the rest;
            // where the points are not finite, the checks run again in order, so that the
            // first broken rule is the one reported.
            let ((extent, finite), checked) = rayon::join(
                || crate::points::extent_and_finite(values, dim),
                || check_with(t, values, dim, condition, || true),
            );
            if finite {
                checked?;
            } else {
                check_with(t, values, dim, condition, || false)?;
            }
            extent
        } else {
            check(t, values, dim, condition)?;
            crate::points::extent(values, dim)
        };
        self.fit_with_extent(t, values, dim, condition, extent, out);
        Ok(())
    }

    /// [`Fitter::fit_into`] for data that already passed [`check`].
    pub(crate) fn fit_checked(
        &mut self,
        t: &[f64],
        values: &[f64],
        dim: usize,
        condition: &EndCondition,
        out: &mut SegmentTable,
    ) {
        let extent = crate::points::extent(values, dim);
        self.fit_with_extent(t, values, dim, condition, extent, out);
    }

    /// [`Fitter::fit_checked`] given the points' extent.
    fn fit_with_extent(
        &mut self,
        t: &[f64],
        values: &[f64],
        dim: usize,
        condition: &EndCondition,
        extent: f64,
        out: &mut SegmentTable,
    ) {
        match condition {
            EndCondition::Natural | EndCondition::Clamped { .. } => {
                self.solve_dominant(t, values, dim, condition);
            }
            EndCondition::NotAKnot | EndCondition::Periodic => {
                self.solve_general(t, values, dim, condition)
            }
        }
        let segments = t.len() - 1;
        let (knots, coeffs) = out.parts_mut(dim, extent);
        // Resized, not cleared: a table refilled at the same size is not zeroed first.
        crate::memory::reserve_on_huge_pages(knots, t.len());
        crate::memory::reserve_on_huge_pages(coeffs, 4 * dim * segments);
        knots.resize(t.len(), 0.0);
        coeffs.resize(4 * dim * segments, 0.0);
        // Each thread copies its segments' first knots too; the last knot is copied here.
        let (knots, last) = knots.split_at_mut(segments);
        last[0] = t[segments];
        let slopes = &self.slopes;
        let threads = crate::available_threads();
        let per_thread = segments.div_ceil(threads).max(PARALLEL_SEGMENTS);
        let hermite = hermite_segments_for(dim);
        let fill = move |c: usize, (coeffs, knots): (&mut [f64], &mut [f64])| {
            let first = c * per_thread;
            knots.copy_from_slice(&t[first..first + knots.len()]);
            hermite(t, values, slopes, dim, first, coeffs);
        };
        let parts = coeffs.chunks_mut(per_thread * 4 * dim);
        let parts: Vec<_> = parts
            .zip(knots.chunks_mut(per_thread))
            .enumerate()
            .collect();
        crate::parallel::fan_out(parts, |(c, part)| fill(c, part));
    }

    /// Natural and clamped ends: every row is strictly diagonally dominant, so the Thomas
    /// algorithm (elimination without pivoting) is stable; it runs in blocks on every thread
    /// ([`solve_blocked`]). The rows are built inside the sweeps, which read the knots and
    /// points once.
    fn solve_dominant(&mut self, t: &[f64], values: &[f64], dim: usize, condition: &EndCondition) {
        let rows = DominantRows {
            t,
            values,
            dim,
            condition,
        };
        let threads = crate::available_threads();
        solve_blocked(
            t.len(),
            dim,
            SOLVE_BLOCK,
            &rows,
            &mut self.slopes,
            &mut self.blocked,
            threads,
        );
    }

    /// Not-a-knot and periodic ends: the rows are assembled, then solved by banded elimination
    /// with partial pivoting (not-a-knot's end rows are not diagonally dominant) or by
    /// Sherman–Morrison (periodic).
    fn solve_general(&mut self, t: &[f64], values: &[f64], dim: usize, condition: &EndCondition) {
        let n = t.len();
        let periodic = matches!(condition, EndCondition::Periodic);
        // A periodic spline has n − 1 distinct slopes (m_{n−1} = m_0).
        let rows = if periodic { n - 1 } else { n };
        let (a, rhs) = (&mut self.system, &mut self.slopes);
        a.reset(rows);
        rhs.clear();
        rhs.resize(n * dim, 0.0);
        let dt = |i: usize| t[i + 1] - t[i];
        let q = |i: usize, k: usize| (values[(i + 1) * dim + k] - values[i * dim + k]) / dt(i);
        // Interior rows (all rows of a periodic spline, indices modulo n − 1).
        let interior = if periodic { 0..rows } else { 1..n - 1 };
        for i in interior {
            let prev = if i == 0 { rows - 1 } else { i - 1 };
            let (d_prev, d_here) = (dt(prev), dt(i));
            a.sub[i] = d_here;
            a.diag[i] = 2.0 * (d_prev + d_here);
            a.sup[i] = d_prev;
            for k in 0..dim {
                rhs[i * dim + k] = 3.0 * (d_here * q(prev, k) + d_prev * q(i, k));
            }
        }
        let solved = if periodic {
            if rows == 2 {
                // Two segments: both neighbours of each row are the other unknown.
                let s = a.sub[0] + a.sup[0];
                (a.sup[0], a.sub[1]) = (s, s);
                solve_tridiagonal(a, &mut rhs[..rows * dim], dim, &mut self.fill)
            } else {
                // a.sub[0] and a.sup[rows − 1] are the corners A[0][rows−1] and A[rows−1][0].
                solve_cyclic(a, &mut rhs[..rows * dim], dim, &mut self.cyclic)
            }
        } else {
            end_rows(a, rhs, t, values, dim, condition);
            solve_tridiagonal(a, rhs, dim, &mut self.fill)
        };
        // Strictly increasing knots make every one of these systems nonsingular.
        debug_assert!(solved.is_ok(), "singular spline system: {solved:?}");
        if periodic {
            let (head, tail) = rhs.split_at_mut((n - 1) * dim);
            tail.copy_from_slice(&head[..dim]);
        }
    }
}

/// The slope system of natural and clamped ends, row by row (each row scaled by its Δs, as
/// the interior rows are):
///
/// ```text
/// first:    natural 2 m_0 + m_1 = 3 q_0;                clamped m_0 = start
/// interior: Δ_i m_{i−1} + 2(Δ_{i−1} + Δ_i) m_i + Δ_{i−1} m_{i+1} = 3(Δ_i q_{i−1} + Δ_{i−1} q_i)
/// last:     natural m_{n−2} + 2 m_{n−1} = 3 q_{n−2};    clamped m_{n−1} = end
/// ```
///
/// with q_i = (f_{i+1} − f_i)/Δ_i, the chord slopes.
struct DominantRows<'a> {
    t: &'a [f64],
    values: &'a [f64],
    dim: usize,
    condition: &'a EndCondition,
}

/// What a sweep down [`DominantRows`] carries: the chord slopes q_{i−1} of the row it reaches,
/// row i (up to four coordinates; `at` is i, or 0 when nothing is carried).
#[derive(Default)]
struct Chords {
    at: usize,
    q: [f64; 4],
}

impl Rows for DominantRows<'_> {
    type Carry = Chords;

    #[inline(always)]
    fn next_row(&self, i: usize, carry: &mut Chords, rhs: &mut [f64]) -> (f64, f64, f64) {
        let (t, dim, n) = (self.t, self.dim, self.t.len());
        if i == 0 || i + 1 >= n || carry.at != i || dim > 4 {
            // An end row, a sweep's first row, or wide points: built whole, and the chords to
            // the next row formed for it.
            let row = self.row(i, rhs);
            if i + 1 < n && dim <= 4 {
                let inv = 1.0 / (t[i + 1] - t[i]);
                let (f, f_next) = (&self.values[i * dim..], &self.values[(i + 1) * dim..]);
                for k in 0..dim {
                    carry.q[k] = (f_next[k] - f[k]) * inv;
                }
                carry.at = i + 1;
            }
            return row;
        }
        // An interior row: q_{i−1} is carried, q_i formed and carried on.
        let (d_prev, d_here) = (t[i] - t[i - 1], t[i + 1] - t[i]);
        let inv_here = 1.0 / d_here;
        let (f, f_next) = (&self.values[i * dim..], &self.values[(i + 1) * dim..]);
        for k in 0..dim {
            let q = (f_next[k] - f[k]) * inv_here;
            rhs[k] = 3.0 * (d_here * carry.q[k] + d_prev * q);
            carry.q[k] = q;
        }
        carry.at = i + 1;
        (d_here, 2.0 * (d_prev + d_here), d_prev)
    }

    #[inline(always)]
    fn row(&self, i: usize, rhs: &mut [f64]) -> (f64, f64, f64) {
        let (t, dim, n) = (self.t, self.dim, self.t.len());
        let point = |i: usize| &self.values[i * dim..(i + 1) * dim];
        let chords = |rhs: &mut [f64], i: usize| {
            let (f0, f1, inv) = (point(i), point(i + 1), 1.0 / (t[i + 1] - t[i]));
            for k in 0..dim {
                rhs[k] = 3.0 * (f1[k] - f0[k]) * inv;
            }
        };
        match (i, self.condition) {
            (0, EndCondition::Clamped { start, .. }) => {
                rhs.copy_from_slice(start);
                (0.0, 1.0, 0.0)
            }
            (0, _) => {
                chords(rhs, 0);
                (0.0, 2.0, 1.0)
            }
            (i, EndCondition::Clamped { end, .. }) if i == n - 1 => {
                rhs.copy_from_slice(end);
                (0.0, 1.0, 0.0)
            }
            (i, _) if i == n - 1 => {
                chords(rhs, i - 1);
                (1.0, 2.0, 0.0)
            }
            (i, _) => {
                let (d_prev, d_here) = (t[i] - t[i - 1], t[i + 1] - t[i]);
                let (inv_prev, inv_here) = (1.0 / d_prev, 1.0 / d_here);
                let (f_prev, f, f_next) = (point(i - 1), point(i), point(i + 1));
                for k in 0..dim {
                    rhs[k] = 3.0
                        * (d_here * (f[k] - f_prev[k]) * inv_prev
                            + d_prev * (f_next[k] - f[k]) * inv_here);
                }
                (d_here, 2.0 * (d_prev + d_here), d_prev)
            }
        }
    }
}

/// The first and last rows of a non-periodic slope system, each scaled like its neighbours.
fn end_rows(
    a: &mut Tridiagonal,
    rhs: &mut [f64],
    t: &[f64],
    values: &[f64],
    dim: usize,
    condition: &EndCondition,
) {
    let n = t.len();
    let dt = |i: usize| t[i + 1] - t[i];
    let q = |i: usize, k: usize| (values[(i + 1) * dim + k] - values[i * dim + k]) / dt(i);
    let (first, last) = (0, n - 1);
    match condition {
        EndCondition::Natural => {
            // Δ (2 m_0 + m_1) = 3 Δ q_0, and Δ (m_{n−2} + 2 m_{n−1}) = 3 Δ q_{n−2}.
            let (d0, dl) = (dt(0), dt(n - 2));
            (a.diag[first], a.sup[first]) = (2.0 * d0, d0);
            (a.sub[last], a.diag[last]) = (dl, 2.0 * dl);
            for k in 0..dim {
                rhs[k] = 3.0 * d0 * q(0, k);
                rhs[last * dim + k] = 3.0 * dl * q(n - 2, k);
            }
        }
        EndCondition::Clamped { start, end } => {
            let (d0, dl) = (dt(0), dt(n - 2));
            (a.diag[first], a.sup[first]) = (d0, 0.0);
            (a.sub[last], a.diag[last]) = (0.0, dl);
            for k in 0..dim {
                rhs[k] = d0 * start[k];
                rhs[last * dim + k] = dl * end[k];
            }
        }
        EndCondition::NotAKnot => {
            let (d0, d1) = (dt(0), dt(1));
            let s = d0 + d1;
            (a.diag[first], a.sup[first]) = (d1, s);
            let (dl, dm) = (dt(n - 2), dt(n - 3));
            let e = dl + dm;
            (a.sub[last], a.diag[last]) = (e, dm);
            // Each product of two spacings divided by s or e first: the spacings' product
            // alone underflows for knots 1e-160 apart (overflows for 1e160).
            let (w0, w1) = ((d0 + 2.0 * s) / s * d1, d0 / s * d0);
            let (wm, wl) = (dl / e * dl, (2.0 * e + dl) / e * dm);
            for k in 0..dim {
                rhs[k] = w0 * q(0, k) + w1 * q(1, k);
                rhs[last * dim + k] = wm * q(n - 3, k) + wl * q(n - 2, k);
            }
        }
        // A cyclic system has no end rows: its first and last rows are interior rows.
        EndCondition::Periodic => {}
    }
}
