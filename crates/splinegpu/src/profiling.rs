//! The knobs benchmarks turn, behind the `profiling` feature: not a stable API.
//!
//! - [`KernelShape`]: how the kernel spreads a job over invocations, chosen per adapter type;
//!   [`GpuContext::with_shape`](crate::GpuContext::with_shape) overrides it.
//! - [`GpuContext::with_max_dispatch_values`](crate::GpuContext::with_max_dispatch_values):
//!   cuts jobs into smaller dispatches (to test the cut, or to bound a dispatch's time).
//! - [`GpuContext::evaluate_timed`](crate::GpuContext::evaluate_timed) and [`DeviceTime`]:
//!   the device's own time of an evaluation, by timestamp queries where the adapter has them.
//! - [`StoreKernel`] and [`STORE_CEILING_RUN`]: a kernel that only stores, the ceiling any
//!   kernel writing the same bytes can reach on a device, timed beside the evaluator.

pub use crate::gpu::KernelShape;
pub use crate::gpu::ceiling::{STORE_CEILING_RUN, StoreKernel};
pub use crate::gpu::timing::{DeviceTime, TimingMethod};
