//! Timing an evaluation on the device: [`DeviceTime`], measured by timestamp queries around
//! each dispatch's compute pass where the device has them ([`Timestamps`]), else from each
//! dispatch's submission to its completion.

use super::readback::map_read;
use crate::error::GpuError;

/// How long the evaluation dispatches ran on the device.
#[cfg_attr(
    not(feature = "profiling"),
    expect(unreachable_pub, reason = "public through the profiling feature")
)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviceTime {
    /// Seconds, summed over the job's dispatches.
    pub seconds: f64,
    /// How they were measured.
    pub method: TimingMethod,
}

/// How [`DeviceTime`] was measured.
#[cfg_attr(
    not(feature = "profiling"),
    expect(unreachable_pub, reason = "public through the profiling feature")
)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingMethod {
    /// Timestamp queries at the start and end of every compute pass.
    Timestamps,
    /// Wall clock from each dispatch's submission to its completion (adapters without
    /// timestamp queries); includes submission overhead.
    SubmitToCompletion,
}

impl TimingMethod {
    /// How `device`'s dispatches are timed: by timestamps where it has `TIMESTAMP_QUERY`.
    #[cfg(feature = "profiling")]
    pub(super) fn of(device: &wgpu::Device) -> Self {
        if device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            Self::Timestamps
        } else {
            Self::SubmitToCompletion
        }
    }
}

/// A timestamp at the start and the end of each dispatch's compute pass.
pub(super) struct Timestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    download: wgpu::Buffer,
    count: u32,
}

impl Timestamps {
    pub(super) fn new(device: &wgpu::Device, dispatches: usize) -> Self {
        let count = 2 * dispatches as u32;
        let bytes = u64::from(count) * size_of::<u64>() as u64;
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("dispatch times"),
                ty: wgpu::QueryType::Timestamp,
                count,
            }),
            resolve: buffer(
                "timestamps",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            download: buffer(
                "timestamps download",
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            ),
            count,
        }
    }

    /// The pass timestamps of dispatch `b`.
    pub(super) fn writes(&self, b: usize) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(2 * b as u32),
            end_of_pass_write_index: Some(2 * b as u32 + 1),
        }
    }

    pub(super) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..self.count, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.download, 0, self.resolve.size());
    }

    /// Seconds between each pass's two timestamps, summed; `period` is nanoseconds per tick.
    pub(super) fn read(&self, device: &wgpu::Device, period: f32) -> Result<f64, GpuError> {
        let ticks: Vec<u64> = map_read(device, &self.download, |bytes| {
            bytemuck::cast_slice(bytes).to_vec()
        })?;
        let total: u64 = ticks
            .chunks_exact(2)
            .map(|t| t[1].saturating_sub(t[0]))
            .sum();
        Ok(total as f64 * f64::from(period) * 1e-9)
    }
}
