//! Queries: where things are on many curves at once, certified: the closest point of a set of
//! curves to many points ([`CurveIndex`]), and every point where 2-D curves meet one another
//! or themselves ([`intersections`]).
//!
//! Both walk box trees over pieces of the curves' segments (`tree`, `pieces`) and exclude by
//! proven bounds (a piece lies in its control points' box); closest points finish on each
//! piece left with an exact solve (the roots of a polynomial, `roots`), intersections with
//! the Krawczyk test and subdivision (`intersect`, on the enclosures of `planar`). The
//! argument that nothing is missed is in docs/queries.md.

mod checks;
mod closest;
mod columns;
mod intersect;
mod nets;
pub(crate) mod pieces;
mod planar;
mod roots;
mod surfaces;
pub(crate) mod tree;

pub use closest::{ClosestPoint, ClosestPoints, CurveIndex, closest_on_segment};
pub use columns::{IntersectionColumns, RayHitColumns, SurfacePointColumns};
pub use intersect::{Intersection, Pairs, intersections};
pub(crate) use surfaces::CheckedRay;
pub use surfaces::{RayHit, SurfaceIndex, SurfacePoint};

/// Why a query on the GPU was not answered: its input, or the device.
#[derive(Debug, thiserror::Error)]
pub enum QueryError {
    /// A query point (or the set) the query refuses, as the CPU's query does.
    #[error(transparent)]
    Input(#[from] crate::error::InputError),
    /// The device failed, or the set does not fit it.
    #[error(transparent)]
    Gpu(#[from] crate::error::GpuError),
}
