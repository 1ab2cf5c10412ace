//! What every query kernel does on the device: the index's tables uploaded once per call, then
//! for each dispatch its uniform and its queries uploaded, the kernel run over them, and its
//! outputs copied into one download buffer, mapped and handed back.

use crate::error::GpuError;
use crate::gpu::GpuContext;
use crate::gpu::kernel::{Kernel, workgroup_grid};
use crate::gpu::timing::Timestamps;

/// An index's tables on the device, each within one storage binding.
pub(crate) struct DeviceTables {
    buffers: Vec<wgpu::Buffer>,
}

impl GpuContext {
    /// The largest storage binding (and buffer) this device takes.
    pub(crate) fn binding_limit(&self) -> u64 {
        let limits = self.device.limits();
        limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
    }

    /// `tables` (named for their errors) uploaded as read-only storage buffers.
    ///
    /// # Errors
    /// [`GpuError::TooLarge`] for a table beyond one storage binding.
    pub(crate) fn upload_query_tables(
        &self,
        tables: &[(&'static str, &[u8])],
    ) -> Result<DeviceTables, GpuError> {
        use wgpu::util::DeviceExt;
        let limit = self.binding_limit();
        let buffers = tables
            .iter()
            .map(|&(label, bytes)| {
                if bytes.len() as u64 > limit {
                    return Err(GpuError::TooLarge {
                        table: label,
                        bytes: bytes.len() as u64,
                        limit,
                    });
                }
                // A binding holds at least one element.
                let contents: &[u8] = if bytes.is_empty() { &[0; 16] } else { bytes };
                Ok(self
                    .device
                    .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(label),
                        contents,
                        usage: wgpu::BufferUsages::STORAGE,
                    }))
            })
            .collect::<Result<_, _>>()?;
        Ok(DeviceTables { buffers })
    }

    /// One dispatch of `kernel` (workgroups of `size`) over `count` queries: bindings are the
    /// uniform `params`, the `tables`, the `queries` and one read-write buffer per output,
    /// each filled from the kernel's. Returns the seconds it ran on the device when `timed`
    /// (timestamps where the device has them, else submission to completion), else 0.
    pub(crate) fn dispatch_queries(
        &self,
        (kernel, size, count): (&Kernel, u32, usize),
        params: &[u8],
        tables: &DeviceTables,
        queries: &[f32],
        outputs: &mut [&mut [u8]],
        timed: bool,
    ) -> Result<f64, GpuError> {
        use wgpu::util::DeviceExt;
        let device = &self.device;
        let storage = wgpu::BufferUsages::STORAGE;
        let init = |label, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let uniform = init("query params", params, wgpu::BufferUsages::UNIFORM);
        let query_bytes: &[u8] = bytemuck::cast_slice(queries);
        let query_buffer = init(
            "queries",
            if query_bytes.is_empty() {
                &[0; 16]
            } else {
                query_bytes
            },
            storage,
        );
        let sizes: Vec<u64> = outputs.iter().map(|o| (o.len() as u64).max(4)).collect();
        let output_buffers: Vec<wgpu::Buffer> = sizes
            .iter()
            .map(|&size| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("query answers"),
                    size,
                    usage: storage | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            })
            .collect();
        let download = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("query download"),
            size: sizes.iter().sum(),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let has_timestamps = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let stamps = (timed && has_timestamps).then(|| Timestamps::new(device, 1));
        let mut encoder = device.create_command_encoder(&Default::default());
        let resources = std::iter::once(&uniform)
            .chain(&tables.buffers)
            .chain(std::iter::once(&query_buffer))
            .chain(&output_buffers)
            .map(wgpu::Buffer::as_entire_binding)
            .collect();
        kernel.record(
            device,
            &mut encoder,
            "queries",
            resources,
            workgroup_grid(device, count as u32, size),
            stamps.as_ref().map(|s| s.writes(0)),
        );
        let mut at = 0;
        for (buffer, &size) in output_buffers.iter().zip(&sizes) {
            encoder.copy_buffer_to_buffer(buffer, 0, &download, at, size);
            at += size;
        }
        if let Some(stamps) = &stamps {
            stamps.resolve(&mut encoder);
        }
        let submitted = std::time::Instant::now();
        self.queue.submit([encoder.finish()]);
        crate::gpu::readback::map_read(device, &download, |bytes| {
            let mut at = 0;
            for (output, &size) in outputs.iter_mut().zip(&sizes) {
                let len = output.len();
                output.copy_from_slice(&bytes[at..at + len]);
                at += size as usize;
            }
        })?;
        Ok(match (&stamps, timed) {
            (Some(stamps), _) => stamps.read(device, self.queue.get_timestamp_period())?,
            (None, true) => submitted.elapsed().as_secs_f64(),
            (None, false) => 0.0,
        })
    }
}

/// The row width (invocations) of a dispatch of `count` queries in workgroups of `size`, as
/// [`GpuContext::dispatch_queries`] lays them out.
pub(crate) fn row_width(context: &GpuContext, count: usize, size: u32) -> u32 {
    workgroup_grid(&context.device, count as u32, size).0 * size
}
