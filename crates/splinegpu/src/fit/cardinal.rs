//! Cardinal basis functions of interpolating splines that share their knots (the course notes
//! "Cubic spline curves", §8).
//!
//! An interpolating spline is linear in its data, so for fixed knots t and end condition there
//! are functions f_0..f_{m−1} with P(t) = Σ_j f_j(t) S_j, where f_j is the spline through the
//! data e_j (1 at point j, 0 elsewhere). The inputs S_j are the n points (n − 1 for a periodic
//! spline, whose last point repeats the first) and, for a clamped spline, its start and end
//! derivatives. Computing the f_j once and combining them per curve serves many curves on the
//! same knots (an animation rig's channels): each curve costs a linear combination, not a solve.
//!
//! The f_j are fitted together as one spline of dimension m, so the table holds
//! O(n · m) = O(n²) coefficients: meant for keyframe counts in the hundreds, not millions.

use super::interp::{EndCondition, EndKind, Fitter, check};
use crate::error::{InputError, Shown};
use crate::points::Points;
use crate::sampling::SampleLoc;
use crate::segment::SegmentTable;

/// The cardinal basis functions of one knot vector and end condition.
#[derive(Clone, Debug, PartialEq)]
pub struct CardinalBasis {
    kind: EndKind,
    points: usize,
    /// m = number of inputs; coordinate j of this table is f_j.
    table: SegmentTable,
}

impl CardinalBasis {
    /// The basis functions for knots `t` (one per point) and ends of kind `kind`.
    ///
    /// # Errors
    /// Too few knots for the end condition, or knots that are not strictly increasing and
    /// finite (the error names `"t"`).
    pub fn new(t: &[f64], kind: EndKind) -> Result<Self, InputError> {
        let n = t.len();
        let inputs = match kind {
            EndKind::Periodic => n.saturating_sub(1),
            EndKind::Clamped => n + 2,
            EndKind::Natural | EndKind::NotAKnot => n,
        };
        // Input j's data: e_j at point j (periodic: the last point repeats input 0).
        let mut values = vec![0.0; n * inputs];
        for i in 0..n {
            let j = if kind == EndKind::Periodic {
                i % inputs.max(1)
            } else {
                i
            };
            if j < inputs {
                values[i * inputs + j] = 1.0;
            }
        }
        let condition = match kind {
            EndKind::Natural => EndCondition::Natural,
            EndKind::Periodic => EndCondition::Periodic,
            EndKind::NotAKnot => EndCondition::NotAKnot,
            EndKind::Clamped => {
                let unit = |j: usize| (0..inputs).map(|k| f64::from(u8::from(k == j))).collect();
                EndCondition::Clamped {
                    start: unit(n),
                    end: unit(n + 1),
                }
            }
        };
        check(t, &values, inputs.max(1), &condition)?;
        let mut table = SegmentTable::default();
        Fitter::new().fit_checked(t, &values, inputs, &condition, &mut table);
        Ok(Self {
            kind,
            points: n,
            table,
        })
    }

    /// Number of inputs m: the points (n − 1 for periodic ends), plus the two end derivatives of
    /// a clamped spline.
    #[must_use]
    pub fn inputs(&self) -> usize {
        self.table.dim()
    }

    /// The basis functions as one table of dimension m: coordinate j is f_j.
    #[must_use]
    pub fn table(&self) -> &SegmentTable {
        &self.table
    }

    /// The weights f_0(t)..f_{m−1}(t): P(t) = Σ_j `weights[j]` · input_j.
    ///
    /// # Errors
    /// `t` outside the knots' range (the error names `"t"`).
    pub fn weights_at(&self, t: f64) -> Result<Vec<f64>, InputError> {
        let SampleLoc { segment, u, .. } = crate::sampling::locate(self.table.knots(), t)
            .ok_or_else(|| {
                let (lo, hi) = self.table.t_range();
                InputError::field(
                    "t",
                    format!(
                        "must lie in the knots' range [{}, {}], got {}",
                        Shown(lo),
                        Shown(hi),
                        Shown(t)
                    ),
                )
            })?;
        let mut weights = vec![0.0; self.inputs()];
        self.table.segment(segment).eval(u, &mut weights);
        Ok(weights)
    }

    /// The spline through `points` (and, for clamped ends, with end derivatives `derivatives`)
    /// as a linear combination of the basis functions: the same curve as a direct fit.
    ///
    /// # Errors
    /// A point count other than the knots', derivatives missing for clamped ends (or given for
    /// other ends, or of the wrong dimension), or a periodic curve that does not close.
    pub fn combine(
        &self,
        points: &Points,
        derivatives: Option<(&[f64], &[f64])>,
    ) -> Result<SegmentTable, InputError> {
        let (n, dim) = (points.len(), points.dim());
        if n != self.points {
            return Err(InputError::field(
                "points",
                format!("must number {} (one per knot), got {n}", self.points),
            ));
        }
        let condition = match (self.kind, derivatives) {
            (EndKind::Clamped, Some((start, end))) => EndCondition::Clamped {
                start: start.to_vec(),
                end: end.to_vec(),
            },
            (EndKind::Natural, None) => EndCondition::Natural,
            (EndKind::Periodic, None) => EndCondition::Periodic,
            (EndKind::NotAKnot, None) => EndCondition::NotAKnot,
            (EndKind::Clamped, None) => {
                return Err(InputError::field(
                    "start_derivative",
                    "is required for clamped ends",
                ));
            }
            (_, Some(_)) => {
                return Err(InputError::field(
                    "start_derivative",
                    "applies to clamped ends only",
                ));
            }
        };
        check(self.table.knots(), points.coords(), dim, &condition)?;
        // Input j's coordinates: point j, then the clamped derivatives.
        let input = |j: usize| -> &[f64] {
            match (&condition, j.checked_sub(n)) {
                (EndCondition::Clamped { start, .. }, Some(0)) => start,
                (EndCondition::Clamped { end, .. }, Some(1)) => end,
                _ => points.point(j),
            }
        };
        let m = self.inputs();
        let mut coeffs = Vec::with_capacity(self.table.len() * 4 * dim);
        for s in 0..self.table.len() {
            for basis_term in self.table.segment(s).power() {
                for k in 0..dim {
                    coeffs.push((0..m).map(|j| basis_term[j] * input(j)[k]).sum());
                }
            }
        }
        Ok(SegmentTable::from_parts(
            dim,
            self.table.knots().to_vec(),
            coeffs,
            points.extent(),
        ))
    }
}
