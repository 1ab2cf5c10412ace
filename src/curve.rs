//! `Curve`: a spline family, its end convention and its points, checked once on construction.

use glam::{DVec2, DVec3, Vec3};

use crate::basis::{Basis, Rows, bezier_rows};
use crate::error::{InputError, Shown};
use crate::fit::interp::{self, EndCondition, Fitter};
use crate::segment::SegmentTable;

/// The largest number of coordinates per point.
pub const MAX_DIM: usize = 64;

/// Points in D dimensions, 1 <= D <= [`MAX_DIM`], stored flat (point i is
/// `coords[i*D..(i+1)*D]`), all finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Points {
    dim: usize,
    coords: Vec<f64>,
}

impl Points {
    /// Points from flat coordinates, `dim` per point.
    ///
    /// # Errors
    /// `dim` outside 1..=64, a length that is not a multiple of `dim`, or a non-finite value
    /// (the error names `"points"` and the first bad coordinate).
    pub fn new(dim: usize, coords: Vec<f64>) -> Result<Self, InputError> {
        if dim == 0 || dim > MAX_DIM {
            return Err(InputError::field(
                "points",
                format!("must have 1 to {MAX_DIM} coordinates per point, got {dim}"),
            ));
        }
        if !coords.len().is_multiple_of(dim) {
            return Err(InputError::field(
                "points",
                format!(
                    "{} values are not a whole number of {dim}-D points",
                    coords.len()
                ),
            ));
        }
        check_finite(&coords, dim)?;
        Ok(Self { dim, coords })
    }

    /// Coordinates per point.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.coords.len() / self.dim
    }

    /// True when there are no points.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }

    /// All coordinates, point after point.
    #[must_use]
    pub fn coords(&self) -> &[f64] {
        &self.coords
    }

    /// Point `i`.
    #[must_use]
    pub fn point(&self, i: usize) -> &[f64] {
        &self.coords[i * self.dim..(i + 1) * self.dim]
    }

    /// The extent E: the largest per-axis (max − min) over the points.
    #[must_use]
    pub fn extent(&self) -> f64 {
        extent(&self.coords, self.dim)
    }
}

/// Checks that point-major `coords` (`dim` per point) are all finite.
///
/// # Errors
/// The first that is not, named as `points[i][k]`.
pub fn check_finite(coords: &[f64], dim: usize) -> Result<(), InputError> {
    if all_finite(coords) {
        return Ok(());
    }
    match coords.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(InputError::field(
            "points",
            format!(
                "must be finite: points[{}][{}] = {}",
                i / dim,
                i % dim,
                Shown(coords[i])
            ),
        )),
    }
}

/// True when every value is finite: one pass without an early exit, which the compiler turns
/// into vector compares (a search for the first bad value runs only when there is one; the
/// search alone measured about 3x slower on a million-knot fit's values).
#[must_use]
pub fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, v| ok & v.is_finite())
}

/// The extent E of point-major `coords` with `dim` coordinates per point: the largest per-axis
/// (max − min). NaN coordinates are ignored.
#[must_use]
pub fn extent(coords: &[f64], dim: usize) -> f64 {
    extent_and_finite(coords, dim).0
}

/// [`extent`], and whether every coordinate is finite ([`all_finite`]), in one pass.
#[must_use]
pub fn extent_and_finite(coords: &[f64], dim: usize) -> (f64, bool) {
    if dim > MAX_DIM {
        // Wide data (a cardinal basis's identity matrix, say): one axis at a time.
        let extent = (0..dim)
            .map(|k| {
                let axis = coords.iter().skip(k).step_by(dim);
                let (lo, hi) = axis.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                    (l.min(v), h.max(v))
                });
                hi - lo
            })
            .fold(0.0, f64::max);
        return (extent, all_finite(coords));
    }
    // Stack arrays and plain comparisons: this runs over every point of million-knot fits,
    // with the dimension known at compile time for the common ones (about 3x faster on a
    // million 3-D points).
    match dim {
        1 => extent_of::<1>(coords, 1),
        2 => extent_of::<2>(coords, 2),
        3 => extent_of::<3>(coords, 3),
        4 => extent_of::<4>(coords, 4),
        _ => extent_of::<MAX_DIM>(coords, dim),
    }
}

/// [`extent_and_finite`] of `dim`-dimensional points, `dim` <= `D`. The points are finite
/// when no coordinate is NaN and every bound is finite (an infinity would be one).
fn extent_of<const D: usize>(coords: &[f64], dim: usize) -> (f64, bool) {
    let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
    let mut nan = false;
    for point in coords.chunks_exact(dim) {
        for ((l, h), &v) in lo.iter_mut().zip(hi.iter_mut()).zip(point) {
            if v < *l {
                *l = v;
            }
            if v > *h {
                *h = v;
            }
            nan |= v.is_nan();
        }
    }
    let (lo, hi) = (&lo[..dim], &hi[..dim]);
    let extent = (0..dim).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let bounded = lo.iter().chain(hi).all(|v| v.is_finite());
    (extent, coords.is_empty() || (!nan && bounded))
}

impl TryFrom<&[DVec2]> for Points {
    type Error = InputError;
    fn try_from(points: &[DVec2]) -> Result<Self, InputError> {
        Points::new(2, points.iter().flat_map(|p| p.to_array()).collect())
    }
}

impl TryFrom<&[DVec3]> for Points {
    type Error = InputError;
    fn try_from(points: &[DVec3]) -> Result<Self, InputError> {
        Points::new(3, points.iter().flat_map(|p| p.to_array()).collect())
    }
}

impl TryFrom<&[Vec3]> for Points {
    type Error = InputError;
    fn try_from(points: &[Vec3]) -> Result<Self, InputError> {
        Points::new(
            3,
            points
                .iter()
                .flat_map(|p| p.as_dvec3().to_array())
                .collect(),
        )
    }
}

/// How a sliding-window family treats the ends of its point list (contract: "ends").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Ends {
    /// The memo's convention: n >= 4 points give n − 3 segments, the first and the last point
    /// only steer the ends; t in [0, n − 3].
    #[default]
    Control,
    /// The first and the last point are doubled before windowing (the memo's "double the first
    /// and last knots"): n >= 2 points give n − 1 segments; t in [0, n − 1].
    Repeat,
    /// Cyclic, windowing P_{n−1}, P_0, ..., P_{n−1}, P_0, P_1 (the memo's cyclic spline):
    /// n >= 3 points give n segments; t in [0, n].
    Closed,
}

impl Ends {
    /// The fewest points this convention accepts.
    #[must_use]
    pub fn min_points(self) -> usize {
        match self {
            Ends::Control => 4,
            Ends::Repeat => 2,
            Ends::Closed => 3,
        }
    }

    /// Number of segments for `n` points (n >= `min_points`).
    #[must_use]
    pub fn segments(self, n: usize) -> usize {
        match self {
            Ends::Control => n - 3,
            Ends::Repeat => n - 1,
            Ends::Closed => n,
        }
    }

    /// Indices into the n points of segment i's window of four.
    fn window(self, n: usize, i: usize) -> [usize; 4] {
        // Position j of the extended sequence, mapped back to a point index.
        let at = |j: usize| -> usize {
            match self {
                Ends::Control => j,
                // [P0, P0, P1, ..., P_{n-1}, P_{n-1}]
                Ends::Repeat => j.saturating_sub(1).min(n - 1),
                // [P_{n-1}, P0, ..., P_{n-1}, P0, P1]
                Ends::Closed => (j + n - 1) % n,
            }
        };
        [at(i), at(i + 1), at(i + 2), at(i + 3)]
    }
}

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
    /// An interpolation solve at knots `t`.
    Solve {
        condition: EndCondition,
        t: Vec<f64>,
    },
}

impl Curve {
    /// A checked curve.
    ///
    /// # Errors
    /// Too few points for the kind (or, for Bezier, a count that is not 3k + 1), a basis
    /// parameter that is out of its domain (see [`Basis::try_rows`]), or interpolation data
    /// that break a rule of interpolation (t strictly increasing and one per point, enough
    /// points for the end condition, periodic ends equal, clamped derivatives of D values).
    pub fn new(kind: CurveKind, points: Points) -> Result<Self, InputError> {
        let n = points.len();
        let fit = match &kind {
            CurveKind::Uniform { basis, ends } => {
                let rows = basis.try_rows()?;
                if n < ends.min_points() {
                    return Err(InputError::field(
                        "points",
                        format!(
                            "needs at least {} points with ends \"{}\", got {n}",
                            ends.min_points(),
                            ends_name(*ends)
                        ),
                    ));
                }
                FitMethod::Windows {
                    rows,
                    ends: Some(*ends),
                }
            }
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
            CurveKind::Uniform { ends, .. } => ends.segments(n),
            CurveKind::Bezier => (n - 1) / 3,
            CurveKind::Interpolating { .. } => n - 1,
        }
    }

    /// The parameter range [t_start, t_end].
    #[must_use]
    pub fn t_range(&self) -> (f64, f64) {
        match &self.fit {
            FitMethod::Solve { t, .. } => (t[0], t[t.len() - 1]),
            FitMethod::Windows { .. } => (0.0, self.segment_count() as f64),
        }
    }

    /// The curve's segments in power form, formed in f64 (see [`SegmentTable`]).
    #[must_use]
    pub fn fit(&self) -> SegmentTable {
        let (dim, n) = (self.points.dim(), self.points.len());
        let coords = self.points.coords();
        let extent = self.points.extent();
        let segments = self.segment_count();
        match &self.fit {
            FitMethod::Solve { condition, t } => {
                let mut table = SegmentTable::default();
                Fitter::new().fit_checked(t, coords, dim, condition, &mut table);
                table
            }
            FitMethod::Windows {
                rows,
                ends: Some(ends),
            } => SegmentTable::from_windows(dim, coords, rows, segments, extent, |i| {
                ends.window(n, i)
            }),
            FitMethod::Windows { rows, ends: None } => {
                SegmentTable::from_windows(dim, coords, rows, segments, extent, |i| {
                    [3 * i, 3 * i + 1, 3 * i + 2, 3 * i + 3]
                })
            }
        }
    }
}

/// The contract's name of an end convention.
#[must_use]
pub fn ends_name(ends: Ends) -> &'static str {
    match ends {
        Ends::Control => "control",
        Ends::Repeat => "repeat",
        Ends::Closed => "closed",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every dimension's path (the ones known at compile time and the general ones) gives the
    /// largest per-axis range, worked out axis by axis here, with NaNs ignored.
    #[test]
    fn extent_is_the_largest_axis_range_in_every_dimension() {
        for dim in [1, 2, 3, 4, 5, 17, MAX_DIM, MAX_DIM + 3] {
            let mut coords: Vec<f64> = (0..dim * 11)
                .map(|i| ((i * 7919) % 101) as f64 * if i % dim == 0 { 3.0 } else { 1.0 })
                .collect();
            coords[dim] = f64::NAN;
            let want = (0..dim)
                .map(|k| {
                    let axis: Vec<f64> = (0..11)
                        .map(|p| coords[p * dim + k])
                        .filter(|v| !v.is_nan())
                        .collect();
                    axis.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                        - axis.iter().copied().fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max);
            assert_eq!(extent_and_finite(&coords, dim), (want, false), "dim {dim}");
            // Finite only when no coordinate is NaN or infinite, wherever it is.
            coords[dim] = 1.5;
            assert_eq!(
                extent_and_finite(&coords, dim),
                (extent(&coords, dim), true)
            );
            for (at, bad) in [(0, f64::INFINITY), (dim * 11 - 1, f64::NEG_INFINITY)] {
                let mut coords = coords.clone();
                coords[at] = bad;
                assert!(
                    !extent_and_finite(&coords, dim).1,
                    "dim {dim}: {bad} at {at}"
                );
            }
        }
        assert_eq!(extent_and_finite(&[], 3), (0.0, true));
    }
}
