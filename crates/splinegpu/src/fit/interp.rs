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
//! - a second derivative v given at an end (the natural end is v = 0): from the Hermite piece's
//!   S''(t_0) = (6q_0 − 4m_0 − 2m_1)/Δ_0, 2m_0 + m_1 = 3q_0 − vΔ_0/2, and at the last knot
//!   m_{n−2} + 2m_{n−1} = 3q_{n−2} + vΔ_{n−2}/2; each end may be given on its own
//!   ([`EndCondition::Each`], SciPy's bc_type pairs);
//! - not-a-knot (the course notes "Cubic spline curves", §9): S''' continuous at t_1 and
//!   t_{n−2}, which gives
//!   Δ_1 m_0 + (Δ_0 + Δ_1) m_1 = ((Δ_0 + 2(Δ_0 + Δ_1)) Δ_1 q_0 + Δ_0² q_1)/(Δ_0 + Δ_1)
//!   and its mirror image;
//! - periodic (Eberly §4): f_{n−1} = f_0, and the interior row also holds at t_0 with the
//!   indices taken cyclically over the n − 1 segments. Eberly notes that eliminating its
//!   block system directly is ill-conditioned; here the cyclic tridiagonal slope system, which
//!   is strictly diagonally dominant, goes through Sherman–Morrison
//!   ([`Fitter::solve_periodic`]).
//!
//! Every system is made strictly diagonally dominant (a not-a-knot end's row is taken out by
//! its neighbour's, see [`DominantRows`]) and solved by elimination without pivoting in blocks
//! on every thread ([`solve_blocked`]), once for all D coordinates. Segment i is then the
//! cubic Hermite piece of (f_i, m_i, f_{i+1}, m_{i+1}), in local u = (t − t_i)/Δ_i:
//!
//! ```text
//! A = 2(f_i − f_{i+1}) + Δ_i (m_i + m_{i+1})     B = 3(f_{i+1} − f_i) − Δ_i (2m_i + m_{i+1})
//! C = Δ_i m_i                                     D = f_i
//! ```

use super::blocked::{BlockedScratch, Rows, SOLVE_BLOCK, solve_blocked};
use super::tridiag::{Tridiagonal, solve_tridiagonal};
use crate::checks::{Order, check_increasing};
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
    /// Each end on its own: a first or second derivative, or not-a-knot (SciPy's
    /// `bc_type=((1, a), (2, b))` and its pairs of names). n >= 2, or 3 with a not-a-knot end
    /// (4 with two).
    Each {
        /// The condition at t_0.
        start: End,
        /// The condition at t_{n−1}.
        end: End,
    },
}

/// One end of an interpolating spline given on its own ([`EndCondition::Each`]).
#[derive(Clone, Debug, PartialEq)]
pub enum End {
    /// dP/dt there: D values.
    FirstDerivative(Vec<f64>),
    /// d²P/dt² there: D values (zeros: the natural end).
    SecondDerivative(Vec<f64>),
    /// The third derivative continuous at the knot next to this end.
    NotAKnot,
}

/// How one end enters the slope system: a slope, a second derivative (`None`: zero) or
/// not-a-knot.
#[derive(Clone, Copy, Debug)]
enum Side<'a> {
    Slope(&'a [f64]),
    Curvature(Option<&'a [f64]>),
    NotAKnot,
}

impl<'a> Side<'a> {
    fn of(end: &'a End) -> Self {
        match end {
            End::FirstDerivative(v) => Side::Slope(v),
            End::SecondDerivative(v) => Side::Curvature(Some(v)),
            End::NotAKnot => Side::NotAKnot,
        }
    }
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
    /// The condition SciPy's `CubicSpline` resolves this one into on `x` (`y`: `dim` values a
    /// point) where there are too few points for it: not-a-knot on 2 or 3 points is the line
    /// or the parabola through them, periodic on 2 (equal) points the constant; every other
    /// condition, and these on more points, is itself.
    ///
    /// # Errors
    /// A periodic spline of 2 points that differ (field "points").
    pub fn on_few_points_as_scipy(
        &self,
        x: &[f64],
        y: &[f64],
        dim: usize,
    ) -> Result<EndCondition, InputError> {
        Ok(match self {
            EndCondition::NotAKnot => scipy_not_a_knot(x, y, dim),
            EndCondition::Periodic => scipy_periodic(x, y, dim)?,
            other => other.clone(),
        })
    }

    /// The condition without its data, as [`CardinalBasis`](super::cardinal::CardinalBasis) takes
    /// it; `None` for [`EndCondition::Each`], which has no cardinal basis.
    #[must_use]
    pub fn kind(&self) -> Option<EndKind> {
        Some(match self {
            EndCondition::Natural => EndKind::Natural,
            EndCondition::Clamped { .. } => EndKind::Clamped,
            EndCondition::Periodic => EndKind::Periodic,
            EndCondition::NotAKnot => EndKind::NotAKnot,
            EndCondition::Each { .. } => return None,
        })
    }

    /// The two ends' rows of the slope system; `None` for a periodic spline, which has none.
    fn sides(&self) -> Option<[Side<'_>; 2]> {
        Some(match self {
            EndCondition::Natural => [Side::Curvature(None); 2],
            EndCondition::Clamped { start, end } => [Side::Slope(start), Side::Slope(end)],
            EndCondition::NotAKnot => [Side::NotAKnot; 2],
            EndCondition::Each { start, end } => [Side::of(start), Side::of(end)],
            EndCondition::Periodic => return None,
        })
    }

    /// The contract's name of the condition ("natural", "clamped", ...).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            EndCondition::Natural => "natural",
            EndCondition::Clamped { .. } => "clamped",
            EndCondition::Periodic => "periodic",
            EndCondition::NotAKnot => "not-a-knot",
            EndCondition::Each { .. } => "per-end",
        }
    }

    /// The fewest points the condition accepts.
    #[must_use]
    pub fn min_points(&self) -> usize {
        match self {
            EndCondition::Natural | EndCondition::Clamped { .. } => 2,
            EndCondition::Periodic => 3,
            EndCondition::NotAKnot => 4,
            EndCondition::Each { start, end } => {
                2 + usize::from(*start == End::NotAKnot) + usize::from(*end == End::NotAKnot)
            }
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
    check_increasing("t", t, Order::Strictly)?;
    if !points_finite() {
        crate::points::check_finite(values, dim)?;
    }
    // The end derivatives given, each of D finite values.
    fn given(end: &End) -> Option<&[f64]> {
        match end {
            End::FirstDerivative(v) | End::SecondDerivative(v) => Some(v),
            End::NotAKnot => None,
        }
    }
    let ends = match condition {
        EndCondition::Clamped { start, end } => [Some(start.as_slice()), Some(end.as_slice())],
        EndCondition::Each { start, end } => [given(start), given(end)],
        _ => [None, None],
    };
    for (field, v) in ["start_derivative", "end_derivative"].into_iter().zip(ends) {
        let Some(v) = v else { continue };
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
    if *condition == EndCondition::Periodic {
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
    /// A periodic fit's blocked solution: each row's slopes, then z's entry.
    cyclic: Vec<f64>,
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
        match condition.sides() {
            Some(sides) => self.solve_dominant(t, values, dim, sides),
            None => self.solve_periodic(t, values, dim),
        }
        let segments = t.len() - 1;
        let (knots, coeffs) = out.parts_mut(dim, extent);
        // Every value is written below, on the pool: a table refilled at the same size is
        // not zeroed first, a new one is not written twice.
        crate::memory::resize_for_overwrite(knots, t.len());
        crate::memory::resize_for_overwrite(coeffs, 4 * dim * segments);
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

    /// Non-periodic ends: the slope system ([`DominantRows`]) is strictly diagonally dominant
    /// by rows, so the Thomas algorithm (elimination without pivoting) is stable; it runs in
    /// blocks on every thread ([`solve_blocked`]). The rows are built inside the sweeps, which
    /// read the knots and points once. A not-a-knot end's slope is found afterwards from its
    /// neighbour's ([`not_a_knot_slopes`]).
    fn solve_dominant(&mut self, t: &[f64], values: &[f64], dim: usize, sides: [Side<'_>; 2]) {
        let rows = DominantRows {
            t,
            values,
            dim,
            sides,
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
        not_a_knot_slopes(t, values, dim, sides, &mut self.slopes);
    }

    /// Periodic ends: the cyclic system of the n − 1 distinct slopes ([`PeriodicRows`]), by
    /// Sherman–Morrison over the blocked solve: with N = n − 1 rows and γ = −A[0][0],
    ///
    /// ```text
    /// A = T + u vᵀ,  u = (γ, 0, .., 0, A[N−1][0]),  v = (1, 0, .., 0, A[0][N−1]/γ)
    /// solve T Y = B and T z = u (one solve, z as one more column), then X = Y − z (vᵀY)/(1 + vᵀz)
    /// ```
    ///
    /// T, A without its corners and with its first and last diagonals grown, is strictly
    /// diagonally dominant as A is, so the blocks' elimination without pivoting is stable.
    fn solve_periodic(&mut self, t: &[f64], values: &[f64], dim: usize) {
        let n = t.len();
        let rows = n - 1;
        if rows == 2 {
            // Two segments: both neighbours of each row are the other unknown.
            self.solve_two_periodic(t, values, dim);
            return;
        }
        let system = PeriodicRows::new(t, values, dim);
        let cols = dim + 1;
        let threads = crate::available_threads();
        let solved = &mut self.cyclic;
        solve_blocked(
            rows,
            cols,
            SOLVE_BLOCK,
            &system,
            solved,
            &mut self.blocked,
            threads,
        );
        let (first, last) = (&solved[..cols], &solved[(rows - 1) * cols..]);
        let ratio = system.corner_ratio;
        let denominator = 1.0 + first[dim] + ratio * last[dim];
        let mut factor = [0.0; crate::MAX_DIM];
        for k in 0..dim {
            factor[k] = (first[k] + ratio * last[k]) / denominator;
        }
        // X = Y − factor z, row by row on every thread; m_{n−1} = m_0.
        crate::memory::resize_for_overwrite(&mut self.slopes, n * dim);
        let per_thread = rows.div_ceil(threads).max(PARALLEL_SEGMENTS);
        let parts: Vec<_> = self.slopes[..rows * dim]
            .chunks_mut(per_thread * dim)
            .zip(solved.chunks(per_thread * cols))
            .collect();
        crate::parallel::fan_out(parts, |(x, y)| {
            for (x, y) in x.chunks_exact_mut(dim).zip(y.chunks_exact(cols)) {
                for k in 0..dim {
                    x[k] = y[k] - factor[k] * y[dim];
                }
            }
        });
        let (head, tail) = self.slopes.split_at_mut(rows * dim);
        tail.copy_from_slice(&head[..dim]);
    }

    /// A periodic spline of two segments: its 2 × 2 slope system, each row's two neighbours
    /// the other unknown.
    fn solve_two_periodic(&mut self, t: &[f64], values: &[f64], dim: usize) {
        let (a, rhs) = (&mut self.system, &mut self.slopes);
        a.reset(2);
        rhs.clear();
        rhs.resize(3 * dim, 0.0);
        let mut row = vec![0.0; dim];
        let system = PeriodicRows::new(t, values, dim);
        for i in 0..2 {
            let (sub, diag, sup) = system.cyclic_row(i, &mut row);
            (a.sub[i], a.diag[i], a.sup[i]) = (0.0, diag, 0.0);
            // Both off-diagonal entries of the row multiply the other slope.
            if i == 0 {
                a.sup[0] = sub + sup;
            } else {
                a.sub[1] = sub + sup;
            }
            rhs[i * dim..(i + 1) * dim].copy_from_slice(&row);
        }
        let solved = solve_tridiagonal(a, &mut rhs[..2 * dim], dim, &mut self.fill);
        // Strictly increasing knots make the system nonsingular.
        debug_assert!(solved.is_ok(), "singular spline system: {solved:?}");
        let (head, tail) = rhs.split_at_mut(2 * dim);
        tail.copy_from_slice(&head[..dim]);
    }
}

/// The slope system of a spline's non-periodic ends, row by row (each row scaled by its Δs,
/// as the interior rows are):
///
/// ```text
/// first:    S'' = v: 2 m_0 + m_1 = 3 q_0 − vΔ_0/2;                 slope: m_0 = start
/// interior: Δ_i m_{i−1} + 2(Δ_{i−1} + Δ_i) m_i + Δ_{i−1} m_{i+1} = 3(Δ_i q_{i−1} + Δ_{i−1} q_i)
/// last:     S'' = v: m_{n−2} + 2 m_{n−1} = 3 q_{n−2} + vΔ_{n−2}/2;   slope: m_{n−1} = end
/// ```
///
/// with q_i = (f_{i+1} − f_i)/Δ_i, the chord slopes. Every such row is strictly diagonally
/// dominant. A not-a-knot end's row (the third derivative continuous at t_1; s = Δ_0 + Δ_1)
///
/// ```text
/// row 0:    Δ_1 m_0 + s m_1 = ((Δ_0 + 2s) Δ_1 q_0 + Δ_0² q_1) / s
/// ```
///
/// is not (s > Δ_1), so it is taken out: row 1 less row 0,
///
/// ```text
/// row 1':   s m_1 + Δ_0 m_2 = (Δ_1² q_0 + Δ_0 (2Δ_0 + 3Δ_1) q_1) / s
/// ```
///
/// is dominant (s > Δ_0) and holds no m_0; row 0 becomes m_0 = 0, solved apart from the rest,
/// and m_0 is then row 0 solved for it, m_0 = (r_0 − s m_1)/Δ_1 ([`not_a_knot_slopes`]).
/// This is the first step of elimination with partial pivoting on the whole system (rows 0
/// and 1 both lead with Δ_1), as SciPy's banded solve takes it. The last end mirrors it (e =
/// Δ_{n−3} + Δ_{n−2}): row n−2 less row n−1 gives
/// Δ_{n−2} m_{n−3} + e m_{n−2} = (Δ_{n−2} (3Δ_{n−3} + 2Δ_{n−2}) q_{n−3} + Δ_{n−3}² q_{n−2}) / e.
struct DominantRows<'a> {
    t: &'a [f64],
    values: &'a [f64],
    dim: usize,
    /// Each a slope or a second derivative.
    sides: [Side<'a>; 2],
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
        if i <= 1 || i + 2 >= n || carry.at != i || dim > 4 {
            // An end row or its neighbour (a not-a-knot end's rows), a sweep's first row, or
            // wide points: built whole, and the chords to the next row formed for it.
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
        // A second derivative v at an end moves its row's right side by ∓vΔ/2.
        let curvature = |rhs: &mut [f64], v: Option<&[f64]>, dt: f64| {
            if let Some(v) = v {
                for k in 0..dim {
                    rhs[k] += v[k] * dt;
                }
            }
        };
        match (i, self.sides) {
            (0, [Side::NotAKnot, _]) => {
                rhs.fill(0.0);
                (0.0, 1.0, 0.0)
            }
            (i, [_, Side::NotAKnot]) if i == n - 1 => {
                rhs.fill(0.0);
                (0.0, 1.0, 0.0)
            }
            (1, [Side::NotAKnot, _]) => {
                let (d0, d1) = (t[1] - t[0], t[2] - t[1]);
                let s = d0 + d1;
                // Each product of two spacings divided by s first: the product alone
                // underflows for knots 1e-160 apart (overflows for 1e160).
                let (w0, w1) = (d1 / s * d1, d0 / s * (2.0 * d0 + 3.0 * d1));
                let (f0, f1, f2) = (point(0), point(1), point(2));
                for k in 0..dim {
                    rhs[k] = w0 * ((f1[k] - f0[k]) / d0) + w1 * ((f2[k] - f1[k]) / d1);
                }
                (0.0, s, d0)
            }
            (i, [_, Side::NotAKnot]) if i == n - 2 => {
                let (dm, dl) = (t[i] - t[i - 1], t[i + 1] - t[i]);
                let e = dm + dl;
                let (wm, wl) = (dl / e * (3.0 * dm + 2.0 * dl), dm / e * dm);
                let (fm, f, fl) = (point(i - 1), point(i), point(i + 1));
                for k in 0..dim {
                    rhs[k] = wm * ((f[k] - fm[k]) / dm) + wl * ((fl[k] - f[k]) / dl);
                }
                (dl, e, 0.0)
            }
            (0, [Side::Slope(start), _]) => {
                rhs.copy_from_slice(start);
                (0.0, 1.0, 0.0)
            }
            (0, [start, _]) => {
                chords(rhs, 0);
                if let Side::Curvature(v) = start {
                    curvature(rhs, v, -0.5 * (t[1] - t[0]));
                }
                (0.0, 2.0, 1.0)
            }
            (i, [_, Side::Slope(end)]) if i == n - 1 => {
                rhs.copy_from_slice(end);
                (0.0, 1.0, 0.0)
            }
            (i, [_, end]) if i == n - 1 => {
                chords(rhs, i - 1);
                if let Side::Curvature(v) = end {
                    curvature(rhs, v, 0.5 * (t[i] - t[i - 1]));
                }
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

/// A periodic spline's cyclic slope system over its N = n − 1 distinct slopes: every row the
/// interior row of [`DominantRows`], its indices taken modulo N, so that row 0's sub and
/// row N − 1's sup are the corners A[0][N−1] and A[N−1][0]. As [`Rows`] it is T of
/// [`Fitter::solve_periodic`] (corners left out, the two diagonals grown), with u as one
/// more right-hand side.
struct PeriodicRows<'a> {
    t: &'a [f64],
    values: &'a [f64],
    dim: usize,
    /// γ = −A[0][0].
    gamma: f64,
    /// A[0][N−1]/γ (formed first: the corners' product underflows for knots 1e-160 apart).
    corner_ratio: f64,
    /// A[N−1][0].
    bottom_left: f64,
}

impl<'a> PeriodicRows<'a> {
    fn new(t: &'a [f64], values: &'a [f64], dim: usize) -> Self {
        let rows = t.len() - 1;
        let (first, last) = (t[1] - t[0], t[rows] - t[rows - 1]);
        let gamma = -2.0 * (last + first);
        Self {
            t,
            values,
            dim,
            gamma,
            corner_ratio: first / gamma,
            bottom_left: t[rows - 1] - t[rows - 2],
        }
    }

    /// Row i of A (sub, diag, sup), its right-hand sides into `rhs`.
    fn cyclic_row(&self, i: usize, rhs: &mut [f64]) -> (f64, f64, f64) {
        let (t, dim) = (self.t, self.dim);
        let rows = t.len() - 1;
        let prev = if i == 0 { rows - 1 } else { i - 1 };
        let (d_prev, d_here) = (t[prev + 1] - t[prev], t[i + 1] - t[i]);
        let point = |i: usize| &self.values[i * dim..(i + 1) * dim];
        let (f_prev, f_prev_next, f, f_next) =
            (point(prev), point(prev + 1), point(i), point(i + 1));
        for k in 0..dim {
            let (q_prev, q) = (
                (f_prev_next[k] - f_prev[k]) / d_prev,
                (f_next[k] - f[k]) / d_here,
            );
            rhs[k] = 3.0 * (d_here * q_prev + d_prev * q);
        }
        (d_here, 2.0 * (d_prev + d_here), d_prev)
    }
}

impl Rows for PeriodicRows<'_> {
    type Carry = ();

    fn row(&self, i: usize, rhs: &mut [f64]) -> (f64, f64, f64) {
        let (rows, dim) = (self.t.len() - 1, self.dim);
        let (sub, mut diag, sup) = self.cyclic_row(i, &mut rhs[..dim]);
        rhs[dim] = 0.0;
        if i == 0 {
            diag -= self.gamma;
            rhs[dim] = self.gamma;
        }
        if i == rows - 1 {
            diag -= self.bottom_left * self.corner_ratio;
            rhs[dim] = self.bottom_left;
        }
        (sub, diag, sup)
    }

    #[inline(always)]
    fn next_row(&self, i: usize, (): &mut (), rhs: &mut [f64]) -> (f64, f64, f64) {
        self.row(i, rhs)
    }
}

/// The slope of each not-a-knot end, from the solved system (where it was set to zero): its
/// own row solved for it, m_0 = (r_0 − s m_1)/Δ_1 at the start (see [`DominantRows`]),
/// m_{n−1} = (r_{n−1} − e m_{n−2})/Δ_{n−3} at the end.
fn not_a_knot_slopes(
    t: &[f64],
    values: &[f64],
    dim: usize,
    sides: [Side<'_>; 2],
    slopes: &mut [f64],
) {
    let n = t.len();
    let dt = |i: usize| t[i + 1] - t[i];
    let q = |i: usize, k: usize| (values[(i + 1) * dim + k] - values[i * dim + k]) / dt(i);
    if let Side::NotAKnot = sides[0] {
        let (d0, d1) = (dt(0), dt(1));
        let s = d0 + d1;
        // Each product of two spacings divided by s first: the spacings' product alone
        // underflows for knots 1e-160 apart (overflows for 1e160).
        let (w0, w1) = ((d0 + 2.0 * s) / s * d1, d0 / s * d0);
        for k in 0..dim {
            let r = w0 * q(0, k) + w1 * q(1, k);
            slopes[k] = (r - s * slopes[dim + k]) / d1;
        }
    }
    if let Side::NotAKnot = sides[1] {
        let (dm, dl) = (dt(n - 3), dt(n - 2));
        let e = dl + dm;
        let (wm, wl) = (dl / e * dl, (2.0 * e + dl) / e * dm);
        for k in 0..dim {
            let r = wm * q(n - 3, k) + wl * q(n - 2, k);
            slopes[(n - 1) * dim + k] = (r - e * slopes[(n - 2) * dim + k]) / dm;
        }
    }
}

/// SciPy's periodic spline on 2 points: equal points give the constant (the one periodic
/// cubic through them), which is the spline clamped to slopes zero; elsewhere the condition
/// itself (the fit checks it).
fn scipy_periodic(x: &[f64], y: &[f64], dim: usize) -> Result<EndCondition, InputError> {
    if x.len() != 2 || y.len() != 2 * dim {
        return Ok(EndCondition::Periodic);
    }
    if y[..dim] != y[dim..] {
        return Err(InputError::field(
            "points",
            "of a periodic spline must end where they start (2 points: equal)",
        ));
    }
    Ok(EndCondition::Clamped {
        start: vec![0.0; dim],
        end: vec![0.0; dim],
    })
}

/// SciPy's not-a-knot condition at `x` for `y` (`dim` values a point). On 2 or 3 points SciPy
/// gives the line or the parabola through them; each is the clamped spline with that
/// polynomial's slopes at its ends (the one cubic spline that meets them). With divided
/// differences d_i = (y_{i+1} − y_i)/h_i, the line's slope is d_0; the parabola's is d_0 at the
/// middle of the first interval and changes by (d_1 − d_0)/((h_0 + h_1)/2) per unit of x, so
/// at its ends it is d_0 − (d_1 − d_0)·h_0/(h_0 + h_1) and d_1 + (d_1 − d_0)·h_1/(h_0 + h_1).
/// On 4 or more points, or where x and y disagree in length (the fit names that), the
/// condition itself.
fn scipy_not_a_knot(x: &[f64], y: &[f64], dim: usize) -> EndCondition {
    if !matches!(x.len(), 2 | 3) || y.len() != x.len() * dim {
        return EndCondition::NotAKnot;
    }
    let slope = |i: usize, k: usize| (y[(i + 1) * dim + k] - y[i * dim + k]) / (x[i + 1] - x[i]);
    let (start, end) = if x.len() == 2 {
        let line: Vec<f64> = (0..dim).map(|k| slope(0, k)).collect();
        (line.clone(), line)
    } else {
        let (h0, h1) = (x[1] - x[0], x[2] - x[1]);
        let bend = |k: usize| slope(1, k) - slope(0, k);
        (
            (0..dim)
                .map(|k| slope(0, k) - bend(k) * h0 / (h0 + h1))
                .collect(),
            (0..dim)
                .map(|k| slope(1, k) + bend(k) * h1 / (h0 + h1))
                .collect(),
        )
    };
    EndCondition::Clamped { start, end }
}
