//! splinegpu: cubic splines fitted in f64 on the host and evaluated in bulk on the GPU.
//!
//! A [`Curve`] (a family, an end convention and its points) is fitted into a [`SegmentTable`]
//! of cubic segments in power form, formed in f64. A [`Sampling`] resolves into a
//! [`SamplePlan`]; many curves with their plans make an [`EvalJob`], whose [`JobLayout`] says
//! where every sample goes. The GPU ([`GpuContext::evaluate`], f32 samples), the fast CPU
//! evaluator ([`evaluate_cpu`], f32 or f64 on every thread) and the f64 reference
//! ([`evaluate_reference`]) evaluate it with the same indexing; each backend's `*_into` call
//! ([`evaluate_cpu_into`], [`GpuContext::evaluate_into`]) writes into a caller's [`Planes`]
//! instead, and [`GpuContext::record_into`] into a renderer's buffer. The f32 results meet
//! the accuracy promise stated in [`accuracy`].
//!
//! The families follow A. R. Smith, "Spline Tutorial Notes" (Lucasfilm Technical Memo 77,
//! 1983); the interpolating fits follow D. Eberly, "Fitting a Natural Spline to Samples of the
//! Form (t, f(t))" and the course notes "Cubic spline curves" (relaxed uniform B-splines,
//! clamped and periodic ends).
//!
//! # Bulk tessellation
//!
//! ```
//! use splinegpu::{Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, Points, Sampling};
//!
//! // A Catmull-Rom curve through four 2-D points, sampled 8 times per segment.
//! let points = Points::new(2, vec![0.0, 0.0, 1.0, 1.0, 2.0, 0.0, 3.0, 1.0])?;
//! let kind = CurveKind::Uniform { basis: Basis::CatmullRom, ends: Ends::Repeat };
//! let curve = Curve::new(kind, points)?;
//!
//! let mut job = EvalJob::new(Derivatives::First);
//! job.push(&curve, &Sampling::PerSegment(8))?;
//!
//! // f64 on every thread; `GpuContext::new()?.evaluate(&job)?` gives the same in f32.
//! let samples = splinegpu::evaluate_cpu::<f64>(&job, splinegpu::available_threads());
//! let c = samples.curve(0);
//! assert_eq!(c.t.len(), 3 * 8 + 1);
//! assert_eq!(&c.points[..2], &[0.0, 0.0]); // Catmull-Rom passes through its points
//! # Ok::<(), splinegpu::InputError>(())
//! ```
//!
//! # Interpolation
//!
//! ```
//! use splinegpu::{Curve, CurveKind, Derivatives, EndCondition, EvalJob, Points, Sampling};
//!
//! // A natural cubic spline through (t, y) = (0, 0), (1, 1), (3, 0), evaluated at t = 2.
//! let kind = CurveKind::Interpolating {
//!     condition: EndCondition::Natural,
//!     t: Some(vec![0.0, 1.0, 3.0]),
//! };
//! let curve = Curve::new(kind, Points::new(1, vec![0.0, 1.0, 0.0])?)?;
//! let mut job = EvalJob::new(Derivatives::Second);
//! job.push(&curve, &Sampling::At(vec![1.0, 2.0]))?;
//! let samples = splinegpu::evaluate_reference(&job);
//! let s = samples.curve(0);
//! assert_eq!(s.points[0], 1.0); // it passes through its knots
//! assert!(s.d2.unwrap()[0] < 0.0); // and bends down over the peak
//! # Ok::<(), splinegpu::InputError>(())
//! ```
//!
//! # Renderer integration
//!
//! [`GpuContext::from_device`] wraps a renderer's device and queue, and
//! [`GpuContext::record_into`] records the evaluation into the renderer's command encoder,
//! writing the samples into the renderer's own buffer (made with `STORAGE | VERTEX` usage) as
//! [`OutputLayout`] lays them out; nothing is read back. This example needs a GPU adapter
//! (lavapipe counts) and skips itself without one.
//!
//! ```
//! use splinegpu::{Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, GpuContext, Points, Sampling};
//!
//! let Ok(gpu) = GpuContext::new() else { return Ok(()) };
//! // The renderer's device and queue; here the context's own stand in for them.
//! let (device, queue) = (gpu.device().clone(), gpu.queue().clone());
//! let context = GpuContext::from_device(&device, &queue);
//!
//! let points = Points::new(2, vec![0.0, 0.0, 1.0, 1.0, 2.0, 0.0, 3.0, 1.0])?;
//! let curve = Curve::new(CurveKind::Uniform { basis: Basis::BSpline, ends: Ends::Repeat }, points)?;
//! let mut job = EvalJob::new(Derivatives::None);
//! job.push(&curve, &Sampling::PerSegment(16))?;
//!
//! let layout = context.output_layout(&job);
//! let vertices = device.create_buffer(&wgpu::BufferDescriptor {
//!     label: Some("curve vertices"),
//!     size: layout.bytes,
//!     usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
//!     mapped_at_creation: false,
//! });
//! let mut encoder = device.create_command_encoder(&Default::default());
//! context.record_into(&mut encoder, &job, &vertices, 0)?;
//! // ... record a render pass that draws `layout.counts[0]` vertices of 8 bytes from
//! // `layout.curve_starts[0]` as a line strip, then:
//! queue.submit([encoder.finish()]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Features
//!
//! - `profiling` (off by default): the knobs benchmarks turn ([`profiling`]: kernel shapes,
//!   dispatch limits, device timing, the store-only ceiling kernel). Not a stable API.
//!
//! The command line (`splinegpu tessellate`, its JSON document, streaming CSV/JSON/NPZ output
//! and `splinegpu bench`) is the crate `splinegpu-cli`; this crate is the fitter, the samplings
//! and the evaluators, with wgpu, glam, bytemuck and pollster.

// The stages of the data path, drawn in docs/ARCHITECTURE.md: points, curve, fit, segment,
// sampling, job, then the cpu and gpu evaluators.
pub mod accuracy;
pub mod basis;
mod checks;
mod conventions;
mod cpu;
mod curve;
mod error;
mod fit;
pub mod geometry;
mod gpu;
mod job;
pub mod kinds;
mod locator;
mod memory;
mod parallel;
mod points;
pub mod query;
mod rational;
mod sampling;
mod segment;
pub mod surface;

#[cfg(feature = "profiling")]
pub mod profiling;

/// The wgpu this crate is built against, for renderers that hand it their device and buffers.
pub use wgpu;

pub use basis::Basis;
pub use cpu::at::{evaluate_at_into, evaluate_curves_at_into};
pub use cpu::{available_threads, evaluate_cpu, evaluate_cpu_into, evaluate_reference};
pub use curve::{Curve, CurveKind, Ends};
pub use error::{GpuError, InputError, Location, TargetError};
pub use fit::cardinal::CardinalBasis;
pub use fit::hermite::HermiteSlopes;
pub use fit::interp::{End, EndCondition, EndKind, Fitter};
pub use fit::shape::pchip_slopes_into;
pub use fit::tcb::{PerPoint, Tcb};
pub use gpu::{
    GeometryOutputLayout, GeometryRecording, GpuContext, OutputLayout, SurfaceOutputLayout,
    SurfaceRecording, adapters, hardware_adapter, new_instance,
};
pub use job::layout::JobLayout;
pub use job::planes::Planes;
pub use job::samples::{CurveSamples, SampleFloat, Samples};
pub use job::{Chunk, Derivatives, EvalJob, Piece};
pub use memory::available_memory;
pub use points::{MAX_DIM, Points};
pub use rational::Denominator;
pub use sampling::arc_length::DEFAULT_ARCLEN_ACCURACY;
pub use sampling::tolerance::{MAX_SAMPLES_PER_SEGMENT, wang_count};
pub use sampling::{SampleLoc, SamplePlan, Sampling};
pub use segment::{Segment, SegmentTable};

// The unit tests of the kernels' twins share the integration tests' helpers (and shapes, and
// the surface queries' checks), which name this crate `splinegpu`.
#[cfg(test)]
extern crate self as splinegpu;
#[cfg(test)]
#[path = "../tests/it/shapes.rs"]
mod shapes;
#[cfg(test)]
#[path = "../tests/it/support.rs"]
mod support;
#[cfg(test)]
#[path = "../tests/it/query/surface_checks.rs"]
mod surface_checks;

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
