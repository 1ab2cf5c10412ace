//! Getting samples off the device and tables onto it through mappings: the readback sequence
//! (map, read, unmap) written once, the copy of device planes into a caller's packed planes,
//! and the mapped writes a CPU adapter's tables take instead of a staging buffer.

use std::sync::mpsc;

use crate::error::GpuError;
use crate::job::layout::JobLayout;
use crate::parallel::fan_out_map;

/// Copies every curve's values from planes in the device layout (`values`, plane p from
/// `p · stride` on, each the job layout's `device_values()` long) into `planes`, packed as
/// `layout` says.
pub(super) fn unpack_device_planes(
    values: &[f32],
    layout: &JobLayout,
    stride: usize,
    planes: [&mut [f32]; 3],
) {
    let device_values = layout.device_values();
    for (p, plane) in planes.into_iter().enumerate() {
        if plane.is_empty() {
            continue;
        }
        let device_plane = &values[p * stride..p * stride + device_values];
        // Curves split evenly between the threads, each copying its own.
        layout.per_thread_curves(plane, crate::available_threads(), |curves, part| {
            let Some(first) = curves.clone().next() else {
                return;
            };
            let host_start = layout.values_of(first).start;
            for c in curves {
                let host = layout.values_of(c);
                let at = layout.device_start(c);
                part[host.start - host_start..host.end - host_start]
                    .copy_from_slice(&device_plane[at..at + host.len()]);
            }
        });
    }
}

/// The readback sequence, written once: map the whole buffer for reading, hand the mapped
/// bytes to `read`, drop the view, unmap.
pub(super) fn map_read<T>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    read: impl FnOnce(&[u8]) -> T,
) -> Result<T, GpuError> {
    map_whole(device, buffer, wgpu::MapMode::Read)?;
    let result = {
        let view = buffer.get_mapped_range(..).map_err(GpuError::device)?;
        read(&view)
    };
    buffer.unmap();
    Ok(result)
}

/// Writes `contents` to the start of `buffer` (with `MAP_WRITE` usage) through a mapping:
/// map the whole buffer for writing, copy, unmap. A large table (w1's 30 MB of coefficients)
/// is split between the threads, each copying its part through a view of its own.
pub(super) fn map_write(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    contents: &[u8],
) -> Result<(), GpuError> {
    map_whole(device, buffer, wgpu::MapMode::Write)?;
    let threads = if contents.len() < PARALLEL_COPY_BYTES {
        1
    } else {
        crate::available_threads()
    };
    // Parts start on multiples of wgpu::MAP_ALIGNMENT.
    let part = contents
        .len()
        .div_ceil(threads)
        .next_multiple_of(wgpu::MAP_ALIGNMENT as usize);
    let copy = |at: usize, from: &[u8]| -> Result<(), GpuError> {
        let range = at as u64..(at + from.len()) as u64;
        let mut view = buffer
            .get_mapped_range_mut(range)
            .map_err(GpuError::device)?;
        view.copy_from_slice(from);
        Ok(())
    };
    let parts: Vec<_> = contents.chunks(part).enumerate().collect();
    let copied = fan_out_map(parts, |(i, from)| copy(i * part, from))
        .into_iter()
        .collect();
    buffer.unmap();
    copied
}

/// Below this many bytes a table is copied into its mapped buffer on one thread.
const PARALLEL_COPY_BYTES: usize = 1 << 20;

/// map_async on the whole buffer, then polls the device until the callback has run.
fn map_whole(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    mode: wgpu::MapMode,
) -> Result<(), GpuError> {
    let (tx, rx) = mpsc::channel();
    buffer.map_async(mode, .., move |result| {
        // The receiver outlives the poll below; a failed send cannot happen.
        let _ = tx.send(result);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(GpuError::device)?;
    rx.recv()
        .map_err(GpuError::device)?
        .map_err(GpuError::device)
}
