//! Tubes and ribbons on the GPU: `shaders/geometry.wgsl` makes the vertices and unit normals of
//! many curves' meshes (of mixed kinds, rational or not) in one dispatch, one invocation a
//! curve walking its cross-sections with the frame (docs/geometry.md, "On the GPU"), with the
//! discipline of the curve and surface kernels: Pod twins checked against the shader by naga,
//! an f32 CPU twin of the kernel, the promise tested on lavapipe. The host plans in f64 (the
//! places, N_0, each closed curve's arc-length fractions) and makes each vertex's t and the
//! triangles, which do not depend on the positions.
//!
//! The kernel's ABI (`abi`), the curves packed for it (`pack`), evaluation in dispatches within
//! the device's limits (`dispatch`), the renderer's recording (`record`), and the kernel's f32
//! CPU twin (`twin`, tests only).

pub(crate) mod abi;
pub(crate) mod dispatch;
pub(crate) mod pack;
pub(crate) mod record;
#[cfg(test)]
mod twin;
