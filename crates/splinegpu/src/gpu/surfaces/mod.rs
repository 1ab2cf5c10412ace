//! Surfaces on the GPU: `shaders/surface.wgsl` evaluates every vertex of many surfaces (of mixed
//! kinds, rational or not) in one dispatch, from patches packed in f32, with the same discipline
//! as the curve kernel: Pod twins checked against the shader by naga, an f32 CPU twin of the
//! kernel, the promise tested on lavapipe. Each vertex is its patch, its local (u, v) in f32 and
//! where its values go. The pipeline is compiled on first use, so that curve-only callers never
//! pay for it.
//!
//! The kernel's ABI (`abi`), the patches packed for it (`pack`), evaluation in dispatches within the device's limits (`dispatch`), the
//! renderer's recording (`record`), and the kernel's f32 CPU twin (`twin`, tests only).

pub(crate) mod abi;
pub(crate) mod dispatch;
pub(crate) mod pack;
pub(crate) mod record;
#[cfg(test)]
mod twin;
