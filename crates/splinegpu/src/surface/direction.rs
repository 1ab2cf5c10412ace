//! One direction of a tensor-product surface: the curve rule along u (or v), and the fit of
//! many lines of the net at once by that rule.
//!
//! Every surface kind is a tensor product: S(u, v) = Σ_ij B_i(u) C_j(v) P_ij, with B and C the
//! curve rule's basis functions in each direction (the uniform families' windows, Bezier's,
//! a knot vector's, or an interpolating fit, which is linear in its data too). So the surface
//! is fitted as curves are, twice: along u, the n_u rows of the net are the points of one curve
//! of n_v·D coordinates, which gives every u-segment's power coefficients for every column;
//! then along v, those coefficients are the points of one curve of (u-segments · 4 · D)
//! coordinates. Each pass is the curve fit of its kind, O(n) per line (the interpolating fits
//! solve their banded systems once for all lines), never a dense or a global solve.

use crate::basis::{Basis, Rows, bezier_rows};
use crate::checks::{Order, check_increasing};
use crate::curve::Ends;
use crate::error::InputError;
use crate::fit::interp::{EndCondition, Fitter};
use crate::fit::{nurbs, uniform};
use crate::segment::SegmentTable;

/// The curve rule along one direction of a surface.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Direction {
    /// A uniform 4x4 basis on sliding windows of four lines, windowed by `ends`.
    Windows { rows: Rows, ends: Ends },
    /// Bezier windows: 3k + 1 lines make k segments sharing their end lines.
    Bezier,
    /// An interpolating spline through every line at parameters `t`.
    Interpolating {
        condition: EndCondition,
        t: Vec<f64>,
    },
    /// A cubic B-spline on its knot vector (n + 4 knots).
    Knots { knots: Vec<f64> },
}

impl Direction {
    /// The uniform rule of `basis` with `ends`.
    pub(crate) fn windows(basis: &Basis, ends: Ends) -> Result<Self, InputError> {
        Ok(Direction::Windows {
            rows: basis.try_rows()?,
            ends,
        })
    }

    /// Checks that `n` lines suit this rule; `axis` names the direction ("u" or "v") in the
    /// message.
    pub(crate) fn check_lines(&self, n: usize, axis: &str) -> Result<(), InputError> {
        let (fewest, shape) = match self {
            Direction::Windows { ends, .. } => (ends.min_points(), ends.name().to_string()),
            Direction::Bezier => {
                if n >= 4 && (n - 1).is_multiple_of(3) {
                    return Ok(());
                }
                return Err(InputError::field(
                    "points",
                    format!("a bezier net needs 3k+1 points along {axis} (k >= 1), got {n}"),
                ));
            }
            Direction::Interpolating { condition, .. } => {
                (condition.min_points(), condition.name().to_string())
            }
            Direction::Knots { .. } => (4, "nurbs".to_string()),
        };
        if n < fewest {
            return Err(InputError::field(
                "points",
                format!("needs at least {fewest} points along {axis} for \"{shape}\", got {n}"),
            ));
        }
        Ok(())
    }

    /// Number of segments for `n` lines.
    pub(crate) fn segments(&self, n: usize) -> usize {
        match self {
            Direction::Windows { ends, .. } => ends.segments(n),
            Direction::Bezier => (n - 1) / 3,
            Direction::Interpolating { .. } => n - 1,
            Direction::Knots { knots } => nurbs::spans(knots, n).count(),
        }
    }

    /// Whether the direction closes on itself (closed ends, periodic condition): its last
    /// segment ends where its first begins.
    pub(crate) fn is_closed(&self) -> bool {
        matches!(
            self,
            Direction::Windows {
                ends: Ends::Closed,
                ..
            } | Direction::Interpolating {
                condition: EndCondition::Periodic,
                ..
            }
        )
    }

    /// Fits `lines` (n lines of `width` values each, line-major) by this rule into `out`:
    /// every segment's power coefficients (A, B, C, D: the u³, u², u and 1 terms), `width`
    /// values each, and the segments' knots. `extent` is carried into the table.
    pub(crate) fn fit_lines(
        &self,
        lines: &[f64],
        width: usize,
        extent: f64,
        out: &mut SegmentTable,
    ) {
        let n = lines.len() / width;
        let segments = self.segments(n);
        match self {
            Direction::Windows { rows, ends } => uniform::from_windows(
                width,
                lines,
                |_| rows,
                segments,
                extent,
                |i| ends.window(n, i),
                out,
            ),
            Direction::Bezier => {
                let rows = bezier_rows();
                uniform::from_windows(
                    width,
                    lines,
                    |_| &rows,
                    segments,
                    extent,
                    |i| [3 * i, 3 * i + 1, 3 * i + 2, 3 * i + 3],
                    out,
                );
            }
            Direction::Interpolating { condition, t } => {
                Fitter::new().fit_checked(t, lines, width, condition, out);
            }
            Direction::Knots { knots } => nurbs::fit_into(knots, None, lines, width, extent, out),
        }
    }
}

/// The interpolating conditions a surface takes in each direction.
pub(crate) fn check_condition(condition: &EndCondition) -> Result<(), InputError> {
    match condition {
        EndCondition::Natural | EndCondition::NotAKnot | EndCondition::Periodic => Ok(()),
        other => Err(InputError::field(
            "conditions",
            format!(
                "must be \"natural\", \"not-a-knot\" or \"periodic\" in each direction, got \"{}\"",
                other.name()
            ),
        )),
    }
}

/// Checks a direction's parameters (`axis`: "u" or "v"): finite, strictly increasing, one per
/// line of `n`.
pub(crate) fn check_parameters(t: &[f64], n: usize, axis: &str) -> Result<(), InputError> {
    if t.len() != n {
        return Err(InputError::field(
            axis,
            format!(
                "must have one value per point along {axis} ({n}), got {}",
                t.len()
            ),
        ));
    }
    check_increasing(axis, t, Order::Strictly)
}
