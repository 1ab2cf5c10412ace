//! Curves on the GPU: the kernel's ABI and packing (`abi`, `pack`), dispatch and evaluation
//! (`dispatch`, `eval`), the renderer's recording (`record`), and the kernel's f32 CPU twin
//! (`interpret`, tests only).

pub(crate) mod abi;
pub(crate) mod dispatch;
pub(crate) mod eval;
#[cfg(test)]
mod interpret;
pub(crate) mod pack;
pub(crate) mod record;
