//! `Points`: a curve's input points in D dimensions, checked finite, and the helpers every
//! stage uses on point-major coordinates (finiteness, the extent E that scales the promise).

use glam::{DVec2, DVec3, Vec3};

use crate::error::{InputError, Shown};

/// The largest number of coordinates per point.
pub const MAX_DIM: usize = 64;

/// `$f::<D>` for `$dim` coordinates, as a function pointer: one to four coordinates have
/// builds of their own (`D` = the dimension, so that the loops over a point's coordinates
/// unroll and vectorise); any other dimension takes the general build `$f::<$general>`, which
/// reads the dimension at run time (`$general` is 0, or [`MAX_DIM`] for a build that keeps a
/// point in a stack array).
macro_rules! for_dimension {
    ($dim:expr, $f:ident, $general:expr) => {
        match $dim {
            1 => $f::<1>,
            2 => $f::<2>,
            3 => $f::<3>,
            4 => $f::<4>,
            _ => $f::<{ $general }>,
        }
    };
}
pub(crate) use for_dimension;

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
pub(crate) fn check_finite(coords: &[f64], dim: usize) -> Result<(), InputError> {
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
/// search alone measured slower on a million-knot fit's values: docs/benchmarks.md).
#[must_use]
pub(crate) fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, v| ok & v.is_finite())
}

/// The extent E of point-major `coords` with `dim` coordinates per point: the largest per-axis
/// (max − min). NaN coordinates are ignored.
#[must_use]
pub(crate) fn extent(coords: &[f64], dim: usize) -> f64 {
    extent_and_finite(coords, dim).0
}

/// [`extent`], and whether every coordinate is finite ([`all_finite`]), in one pass.
#[must_use]
pub(crate) fn extent_and_finite(coords: &[f64], dim: usize) -> (f64, bool) {
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
    // with the dimension known at compile time for the common ones (docs/benchmarks.md).
    for_dimension!(dim, extent_of, MAX_DIM)(coords, dim)
}

/// [`extent_and_finite`] of `dim`-dimensional points, `dim` <= `D`. The points are finite
/// when no coordinate is NaN and every bound is finite (an infinity would be one).
fn extent_of<const D: usize>(coords: &[f64], dim: usize) -> (f64, bool) {
    // A dimension known at compile time (every build but the general one) is the chunk size
    // the loops below unroll by.
    let dim = if D == MAX_DIM { dim } else { D };
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
