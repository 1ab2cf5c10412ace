//! `Curve`: a spline family, its end convention and its points, checked once on construction.

use crate::basis::{Basis, Rows, bezier_rows};
use crate::error::InputError;
use crate::fit::hermite::{self, HermiteSlopes};
use crate::fit::interp::{self, EndCondition, Fitter};
use crate::fit::local_beta;
use crate::fit::nurbs;
use crate::fit::tcb::{self, PerPoint, Tcb};
use crate::fit::uniform;
use crate::points::Points;
use crate::segment::SegmentTable;

pub use crate::conventions::Ends;

/// What family a curve belongs to.
#[derive(Clone, Debug, PartialEq)]
pub enum CurveKind {
    /// A uniform 4x4-matrix family on a sliding window of four points; segment i spans
    /// t in [i, i + 1].
    Uniform {
        /// The basis matrix.
        basis: Basis,
        /// The end convention.
        ends: Ends,
    },
    /// Barsky and Beatty's Beta-spline with local bias and tension (the discretely shaped
    /// Beta-spline, the memo's "Future"): joint j (the start of segment j; an open curve's last
    /// joint is its end) carries its own bias b1_j > 0 and tension b2_j >= 0, and the curve is
    /// G2 there in the Beta-spline sense, R'(0) = b1_j L'(1), R''(0) = b1_j² L''(1) + b2_j L'(1).
    /// Each segment is a cubic of its window of four points, as for
    /// [`CurveKind::Uniform`]; with every joint's values equal it is the memo's B_{b1,b2}.
    /// Segment i spans t in [i, i + 1].
    LocalBeta {
        /// The end convention (the joints: n − 2 for control ends, n for repeat and closed).
        ends: Ends,
        /// Bias b1 (> 0): one value for every joint, or one per joint.
        bias: PerPoint,
        /// Tension b2 (>= 0): one value for every joint, or one per joint.
        tension: PerPoint,
    },
    /// Cubic Bezier segments sharing end points: 3k + 1 points make k segments, segment i
    /// from points 3i..3i+3 over t in [i, i + 1].
    Bezier,
    /// An interpolating spline through every point, solved on the host
    /// (natural, clamped, periodic or not-a-knot ends; see [`EndCondition`]); segment i spans
    /// [t_i, t_{i+1}].
    Interpolating {
        /// The end condition.
        condition: EndCondition,
        /// One strictly increasing parameter value per point; `None` means 0, 1, ..., n − 1.
        t: Option<Vec<f64>>,
    },
    /// Cubic Hermite pieces through every point, with the derivative at each point given
    /// ("hermite"'s tangents) or computed by a shape-preserving rule ("pchip", "akima"); see
    /// [`HermiteSlopes`]. Segment i spans [t_i, t_{i+1}].
    Hermite {
        /// Where the derivatives at the points come from.
        slopes: HermiteSlopes,
        /// One strictly increasing parameter value per point; `None` means 0, 1, ..., n − 1.
        t: Option<Vec<f64>>,
    },
    /// A cubic B-spline on its own knot vector ("nurbs"): n control points, n + 4 knots;
    /// segments are its non-empty spans in `[knots[3], knots[n]]`, t the knot parameter.
    /// With `weights` the curve is rational, Σ w_j N_j P_j / Σ w_j N_j.
    Nurbs {
        /// n + 4 non-decreasing knots.
        knots: Vec<f64>,
        /// One finite weight > 0 per control point; `None` means all 1 (a polynomial curve).
        weights: Option<Vec<f64>>,
    },
    /// A Kochanek–Bartels spline: the points windowed as `ends` windows them, each segment the
    /// Hermite piece of the tangents its tension, continuity and bias give (see [`Tcb`]).
    /// Without `t`, segment i spans [i, i + 1]; with it, the segments span the given values.
    KochanekBartels {
        /// The end convention.
        ends: Ends,
        /// Tension, continuity and bias.
        tcb: Tcb,
        /// One strictly increasing value per point (n + 1 for closed ends), with Kochanek and
        /// Bartels' adjustment for uneven keys; `None` means uniform keys.
        t: Option<Vec<f64>>,
    },
}

/// A curve ready to fit: its kind and its points, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    kind: CurveKind,
    points: Points,
    /// How the curve is fitted, checked.
    fit: FitMethod,
}

/// What `Curve::new` resolved a kind into.
#[derive(Clone, Debug, PartialEq)]
enum FitMethod {
    /// A 4x4 basis matrix on sliding windows of four points (`ends`), or, with `ends` None,
    /// on Bezier windows that step by three points.
    Windows { rows: Rows, ends: Option<Ends> },
    /// One basis matrix per segment (a Beta-spline with local bias and tension) on the sliding
    /// windows of `ends`.
    LocalWindows { rows: Vec<Rows>, ends: Ends },
    /// An interpolation solve at knots `t`.
    Solve {
        condition: EndCondition,
        t: Vec<f64>,
    },
    /// Hermite pieces at knots `t`.
    Hermite { slopes: HermiteSlopes, t: Vec<f64> },
    /// The non-empty spans of a knot vector; rational where `weights` are given.
    Knots {
        knots: Vec<f64>,
        weights: Option<Vec<f64>>,
    },
    /// Kochanek–Bartels pieces on the windows of `ends`.
    Tcb {
        ends: Ends,
        tcb: Tcb,
        t: Option<Vec<f64>>,
    },
}

impl Curve {
    /// A checked curve.
    ///
    /// # Errors
    /// Too few points for the kind (or, for Bezier, a count that is not 3k + 1), a basis
    /// parameter that is out of its domain (see [`Basis::try_rows`]), or interpolation data
    /// that break a rule of interpolation (t strictly increasing and one per point, enough
    /// points for the end condition, periodic ends equal, clamped derivatives of D values), or
    /// Hermite data that break theirs (at least 2 points, t as above, tangents one per point of
    /// D finite values).
    pub fn new(kind: CurveKind, points: Points) -> Result<Self, InputError> {
        let n = points.len();
        let fit = match &kind {
            CurveKind::Uniform { basis, ends } => {
                let rows = basis.try_rows()?;
                ends.check_points(n)?;
                FitMethod::Windows {
                    rows,
                    ends: Some(*ends),
                }
            }
            CurveKind::LocalBeta {
                ends,
                bias,
                tension,
            } => FitMethod::LocalWindows {
                rows: local_beta::checked_rows(*ends, bias, tension, n)?,
                ends: *ends,
            },
            CurveKind::Bezier => {
                if n < 4 || !(n - 1).is_multiple_of(3) {
                    return Err(InputError::field(
                        "points",
                        format!("a bezier curve needs 3k+1 points (k >= 1), got {n}"),
                    ));
                }
                FitMethod::Windows {
                    rows: bezier_rows(),
                    ends: None,
                }
            }
            CurveKind::Interpolating { condition, t } => {
                let t = t
                    .clone()
                    .unwrap_or_else(|| (0..n).map(|i| i as f64).collect());
                interp::check(&t, points.coords(), points.dim(), condition)?;
                FitMethod::Solve {
                    condition: condition.clone(),
                    t,
                }
            }
            CurveKind::Nurbs { knots, weights } => {
                nurbs::check(knots, weights.as_deref(), n)?;
                crate::points::check_finite(points.coords(), points.dim())?;
                FitMethod::Knots {
                    knots: knots.clone(),
                    weights: weights.clone(),
                }
            }
            CurveKind::KochanekBartels { ends, tcb, t } => {
                tcb::check(*ends, tcb, t.as_deref(), n)?;
                FitMethod::Tcb {
                    ends: *ends,
                    tcb: tcb.clone(),
                    t: t.clone(),
                }
            }
            CurveKind::Hermite { slopes, t } => {
                let t = t
                    .clone()
                    .unwrap_or_else(|| (0..n).map(|i| i as f64).collect());
                hermite::check(&t, points.coords(), points.dim(), slopes)?;
                FitMethod::Hermite {
                    slopes: slopes.clone(),
                    t,
                }
            }
        };
        Ok(Self { kind, points, fit })
    }

    /// The curve's kind.
    #[must_use]
    pub fn kind(&self) -> &CurveKind {
        &self.kind
    }

    /// The curve's points.
    #[must_use]
    pub fn points(&self) -> &Points {
        &self.points
    }

    /// Number of segments.
    #[must_use]
    pub fn segment_count(&self) -> usize {
        let n = self.points.len();
        match &self.kind {
            CurveKind::Uniform { ends, .. }
            | CurveKind::LocalBeta { ends, .. }
            | CurveKind::KochanekBartels { ends, .. } => ends.segments(n),
            CurveKind::Bezier => (n - 1) / 3,
            CurveKind::Interpolating { .. } | CurveKind::Hermite { .. } => n - 1,
            CurveKind::Nurbs { knots, .. } => nurbs::spans(knots, n).count(),
        }
    }

    /// The parameter range [t_start, t_end].
    #[must_use]
    pub fn t_range(&self) -> (f64, f64) {
        match &self.fit {
            FitMethod::Solve { t, .. } | FitMethod::Hermite { t, .. } => (t[0], t[t.len() - 1]),
            FitMethod::Tcb {
                ends, t: Some(t), ..
            } => {
                let first = usize::from(*ends == Ends::Control);
                (t[first], t[first + self.segment_count()])
            }
            FitMethod::Knots { knots, .. } => (knots[3], knots[self.points.len()]),
            FitMethod::Windows { .. }
            | FitMethod::LocalWindows { .. }
            | FitMethod::Tcb { t: None, .. } => (0.0, self.segment_count() as f64),
        }
    }

    /// The curve's segments in power form, formed in f64 (see [`SegmentTable`]).
    #[must_use]
    pub fn fit(&self) -> SegmentTable {
        let mut table = SegmentTable::default();
        self.fit_into(&mut table);
        table
    }

    /// [`Curve::fit`] into `out`, reusing its buffers: a curve refitted every frame (a
    /// renderer's moving points) allocates nothing.
    pub fn fit_into(&self, out: &mut SegmentTable) {
        let (dim, n) = (self.points.dim(), self.points.len());
        let coords = self.points.coords();
        let extent = self.points.extent();
        let segments = self.segment_count();
        match &self.fit {
            FitMethod::Solve { condition, t } => {
                Fitter::new().fit_checked(t, coords, dim, condition, out);
            }
            FitMethod::Hermite { slopes, t } => {
                hermite::fit_into(t, coords, dim, slopes, extent, out);
            }
            FitMethod::Knots { knots, weights } => {
                nurbs::fit_into(knots, weights.as_deref(), coords, dim, extent, out);
            }
            FitMethod::Tcb { ends, tcb, t } => {
                let window = |i| ends.window(n, i);
                tcb::fit_into(
                    coords,
                    dim,
                    tcb,
                    t.as_deref(),
                    *ends,
                    segments,
                    extent,
                    window,
                    out,
                );
            }
            FitMethod::Windows {
                rows,
                ends: Some(ends),
            } => uniform::from_windows(
                dim,
                coords,
                |_| rows,
                segments,
                extent,
                |i| ends.window(n, i),
                out,
            ),
            FitMethod::LocalWindows { rows, ends } => uniform::from_windows(
                dim,
                coords,
                |i| &rows[i],
                segments,
                extent,
                |i| ends.window(n, i),
                out,
            ),
            FitMethod::Windows { rows, ends: None } => uniform::from_windows(
                dim,
                coords,
                |_| rows,
                segments,
                extent,
                |i| [3 * i, 3 * i + 1, 3 * i + 2, 3 * i + 3],
                out,
            ),
        }
    }
}
