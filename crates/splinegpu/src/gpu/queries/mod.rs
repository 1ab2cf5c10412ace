//! Queries on the GPU: `shaders/closest.wgsl` answers many closest-point queries on a set of
//! curves (of mixed kinds, rational or not) in one dispatch, one query per invocation walking
//! the `CurveIndex`'s box tree, in f32 with the contract's bound (docs/queries.md, "On the
//! GPU"); `shaders/surface_queries.wgsl` does the same for closest points on surfaces and the
//! first hits of rays. The same discipline as the evaluation kernels: Pod twins checked against the shader
//! by naga, an f32 CPU twin of the kernel, the promise tested on lavapipe.
//!
//! The kernels' ABI (`abi`), the indexes packed for them in their own frame (`pack`), what
//! every query kernel does on the device (`device`), closest points on curves (`dispatch`) and
//! on surfaces and rays (`surfaces`) in dispatches within the device's limits, and the kernels'
//! f32 CPU twins (`twin`, `surfaces_twin`, tests only).

pub(crate) mod abi;
pub(crate) mod device;
pub(crate) mod dispatch;
pub(crate) mod pack;
pub(crate) mod surfaces;
#[cfg(test)]
mod surfaces_twin;
#[cfg(test)]
mod twin;
