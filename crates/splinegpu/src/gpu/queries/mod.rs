//! Queries on the GPU: `shaders/closest.wgsl` answers many closest-point queries on a set of
//! curves (of mixed kinds, rational or not) in one dispatch, one query per invocation walking
//! the `CurveIndex`'s box tree, in f32 with the contract's bound (docs/queries.md, "On the
//! GPU"). The same discipline as the evaluation kernels: Pod twins checked against the shader
//! by naga, an f32 CPU twin of the kernel, the promise tested on lavapipe.
//!
//! The kernel's ABI (`abi`), the index packed for it in its own frame (`pack`), the queries
//! in dispatches within the device's limits (`dispatch`), and the kernel's f32 CPU twin
//! (`twin`, tests only).

pub(crate) mod abi;
pub(crate) mod dispatch;
pub(crate) mod pack;
#[cfg(test)]
mod twin;
