//! Answers as columns: the contract's arrays, as the command line's NPZ and the Python
//! package's NumPy arrays hold them (indices int64; -1 for "none", NaN where a ray meets
//! nothing).

use crate::query::intersect::Intersection;
use crate::query::surfaces::{RayHit, SurfacePoint};

/// Closest points on surfaces as columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfacePointColumns {
    /// Per query, the surface.
    pub surface: Vec<i64>,
    /// Per query, the patch of a patch list; -1 on a net.
    pub patch: Vec<i64>,
    /// Per query, the surface's parameters.
    pub u: Vec<f64>,
    /// See `u`.
    pub v: Vec<f64>,
    /// Per query, the point (D values, flat).
    pub point: Vec<f64>,
    /// Per query, the distance.
    pub distance: Vec<f64>,
}

impl SurfacePointColumns {
    /// The columns of `answers`.
    #[must_use]
    pub fn new(answers: &[SurfacePoint]) -> Self {
        Self {
            surface: answers.iter().map(|a| a.surface as i64).collect(),
            patch: answers
                .iter()
                .map(|a| a.patch.map_or(-1, |p| p as i64))
                .collect(),
            u: answers.iter().map(|a| a.u).collect(),
            v: answers.iter().map(|a| a.v).collect(),
            point: answers
                .iter()
                .flat_map(|a| a.point.iter().copied())
                .collect(),
            distance: answers.iter().map(|a| a.distance).collect(),
        }
    }
}

/// Rays' first hits as columns: where a ray meets nothing, `hit` false, -1 and NaN.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RayHitColumns {
    /// Per ray, whether it meets a surface.
    pub hit: Vec<bool>,
    /// Per ray, the surface.
    pub surface: Vec<i64>,
    /// Per ray, the patch of a patch list (-1 on a net).
    pub patch: Vec<i64>,
    /// Per ray, the surface's parameters.
    pub u: Vec<f64>,
    /// See `u`.
    pub v: Vec<f64>,
    /// Per ray, the distance along it.
    pub s: Vec<f64>,
    /// Per ray, the point (3 values, flat).
    pub point: Vec<f64>,
    /// Per ray, the unit normal (3 values, flat).
    pub normal: Vec<f64>,
}

impl RayHitColumns {
    /// The columns of `hits`.
    #[must_use]
    pub fn new(hits: &[Option<RayHit>]) -> Self {
        let nan = f64::NAN;
        let scalar =
            |f: fn(&RayHit) -> f64| hits.iter().map(|h| h.as_ref().map_or(nan, f)).collect();
        let vector = |f: fn(&RayHit) -> [f64; 3]| {
            hits.iter()
                .flat_map(|h| h.as_ref().map_or([nan; 3], f))
                .collect()
        };
        Self {
            hit: hits.iter().map(Option::is_some).collect(),
            surface: hits
                .iter()
                .map(|h| h.as_ref().map_or(-1, |h| h.surface as i64))
                .collect(),
            patch: hits
                .iter()
                .map(|h| h.as_ref().and_then(|h| h.patch).map_or(-1, |p| p as i64))
                .collect(),
            u: scalar(|h| h.u),
            v: scalar(|h| h.v),
            s: scalar(|h| h.s),
            point: vector(|h| h.point),
            normal: vector(|h| h.normal),
        }
    }
}

/// Intersections as columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IntersectionColumns {
    /// Per meeting, the first curve.
    pub i: Vec<i64>,
    /// Per meeting, the second curve.
    pub j: Vec<i64>,
    /// Per meeting, curve i's parameter.
    pub t_i: Vec<f64>,
    /// Per meeting, curve j's parameter.
    pub t_j: Vec<f64>,
    /// Per meeting, the point (2 values, flat).
    pub point: Vec<f64>,
    /// Per meeting, whether the curves touch there.
    pub tangent: Vec<bool>,
    /// Per meeting, whether it ends an overlap.
    pub overlap: Vec<bool>,
}

impl IntersectionColumns {
    /// The columns of `found`.
    #[must_use]
    pub fn new(found: &[Intersection]) -> Self {
        Self {
            i: found.iter().map(|x| x.i as i64).collect(),
            j: found.iter().map(|x| x.j as i64).collect(),
            t_i: found.iter().map(|x| x.t_i).collect(),
            t_j: found.iter().map(|x| x.t_j).collect(),
            point: found.iter().flat_map(|x| x.point).collect(),
            tangent: found.iter().map(|x| x.tangent).collect(),
            overlap: found.iter().map(|x| x.overlap).collect(),
        }
    }
}
