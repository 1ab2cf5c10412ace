//! splinegpu: cubic splines fitted in f64 on the host and evaluated in bulk on the GPU.
//!
//! A [`Curve`] (a family, an end convention and its points) is fitted into a [`SegmentTable`]
//! of cubic segments in power form, formed in f64. A [`Sampling`] resolves into a
//! [`SamplePlan`]; many curves with their plans make an [`EvalJob`], which the GPU
//! ([`GpuContext::evaluate`], f32 samples) and the CPU reference ([`cpu::evaluate`], f64)
//! evaluate with the same indexing.
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
//! // The f64 reference; `GpuContext::new()?.evaluate(&job)?` gives the same in f32.
//! let samples = splinegpu::cpu::evaluate(&job);
//! let c = samples.curve(0);
//! assert_eq!(c.t.len(), 3 * 8 + 1);
//! assert_eq!(&c.points[..2], &[0.0, 0.0]); // Catmull-Rom passes through its points
//! # Ok::<(), splinegpu::InputError>(())
//! ```

pub mod accuracy;
pub mod basis;
pub mod bench;
pub mod cpu;
pub mod curve;
pub mod doc;
pub mod error;
pub mod fit;
pub mod gpu;
pub mod job;
pub mod npz;
pub mod output;
pub mod samples;
pub mod sampling;
pub mod segment;
pub mod stream;

pub use basis::Basis;
pub use curve::{Curve, CurveKind, Ends, MAX_DIM, Points};
pub use doc::{DocumentError, parse_document};
pub use error::{GpuError, InputError, Location};
pub use fit::cardinal::CardinalBasis;
pub use fit::interp::{EndCondition, EndKind, Fitter};
pub use gpu::{DeviceTime, GpuContext, KernelShape, OutputLayout, TimingMethod};
pub use job::{Chunk, Derivatives, EvalJob, Piece};
pub use samples::{CurveSamples, Samples};
pub use sampling::{SampleLoc, SamplePlan, Sampling};
pub use segment::{Segment, SegmentTable};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
