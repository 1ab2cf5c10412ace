//! The renderer path: [`GpuContext::record_into`] records an evaluation into a caller's
//! encoder, writing the samples into the caller's buffer as [`OutputLayout`] lays them out.

use wgpu::util::DeviceExt;

use super::dispatch::{F32, Tables, Target};
use super::pack::{self, check_size};
use crate::error::GpuError;
use crate::gpu::GpuContext;
use crate::job::EvalJob;

impl GpuContext {
    /// Where [`GpuContext::record_into`] puts `job`'s samples, to size the caller's buffer.
    #[must_use]
    pub fn output_layout(&self, job: &EvalJob) -> OutputLayout {
        OutputLayout::new(job)
    }

    /// Records the evaluation of `job` into the caller's `encoder`, writing the f32 samples
    /// into the caller's `buffer` from byte `offset` on, laid out as [`OutputLayout`] says:
    /// nothing is read back, so a renderer can draw them (as vertices, with `buffer` made with
    /// `STORAGE | VERTEX` usage) in the same submission.
    ///
    /// The job's tables go into buffers of their own that the recorded commands keep alive,
    /// so the call may be repeated before the encoder is submitted.
    ///
    /// # Errors
    /// [`GpuError::Target`] when `buffer` lacks `STORAGE` usage, is too small from `offset`, or
    /// `offset` is not a multiple of the device's `min_storage_buffer_offset_alignment`; the
    /// job's output larger than one storage binding ([`GpuError::TooLarge`]); a value outside
    /// the f32 range ([`GpuError::OutOfRange`]).
    pub fn record_into(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        job: &EvalJob,
        buffer: &wgpu::Buffer,
        offset: u64,
    ) -> Result<OutputLayout, GpuError> {
        let layout = OutputLayout::new(job);
        let limits = self.device.limits();
        check_size(
            "output",
            layout.bytes,
            limits.max_storage_buffer_binding_size,
        )?;
        self.check_target(buffer, offset, layout.bytes)?;
        if layout.bytes == 0 {
            return Ok(layout);
        }
        let packed = self.pack(job)?;
        let tables = Tables::upload(&packed, |role, contents| {
            Ok(self
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(role.0),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                }))
        })?;
        let target = |b: &pack::Batch| Target {
            binding: wgpu::BufferBinding {
                buffer,
                offset,
                size: std::num::NonZeroU64::new(layout.bytes),
            },
            out_base: b.base as u32,
            plane_stride: packed.device_values as u32,
        };
        self.encode(encoder, &packed, &tables, target, None, |_, _| Ok(()))?;
        self.keep_packing(packed);
        Ok(layout)
    }
}

/// Where [`GpuContext::record_into`] writes a job's samples, in bytes from its `offset`:
/// positions first (curve c's `counts[c]` samples of `dims[c]` f32 values, tightly packed, from
/// `curve_starts[c]` on; each curve starts 16-byte aligned), then, when the job asks for them,
/// the first derivatives at `plane_bytes` further, and the second at twice that.
///
/// To draw curve c as a line strip of vec`dims[c]` vertices: bind the buffer from
/// `offset + curve_starts[c]` with a stride of `4 * dims[c]` bytes and draw `counts[c]`
/// vertices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputLayout {
    /// Byte offset of each curve's first sample, relative to the write's `offset`.
    pub curve_starts: Vec<u64>,
    /// Samples of each curve.
    pub counts: Vec<u64>,
    /// Coordinates per sample of each curve.
    pub dims: Vec<u32>,
    /// Bytes from one plane to the next (positions, dP/dt, d2P/dt2).
    pub plane_bytes: u64,
    /// Bytes written in all, from `offset` on.
    pub bytes: u64,
}

impl OutputLayout {
    /// The device planes of `job`'s layout, in bytes.
    fn new(job: &EvalJob) -> Self {
        let layout = job.layout();
        let plane_bytes = layout.device_values() as u64 * F32;
        Self {
            curve_starts: (0..job.len())
                .map(|c| layout.device_start(c) as u64 * F32)
                .collect(),
            counts: (0..job.len())
                .map(|c| layout.samples_of(c).len() as u64)
                .collect(),
            dims: (0..job.len()).map(|c| layout.dim(c) as u32).collect(),
            plane_bytes,
            bytes: plane_bytes * (job.derivatives().order() as u64 + 1),
        }
    }
}
