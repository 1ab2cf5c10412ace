//! Queries: where things are on many curves at once (closest points), certified.
//!
//! Each query walks a box tree over the curves' segments ([`tree`]) and finishes on each
//! segment it cannot exclude with an exact solve (the roots of a polynomial, [`roots`]); the
//! argument that no nearer point is missed is in docs/queries.md.

mod closest;
mod roots;
mod tree;

pub use closest::{ClosestPoint, ClosestPoints, CurveIndex, closest_on_segment};
