//! Store-only kernels: what any kernel that writes a given number of bytes can reach on a
//! device, measured beside the evaluator in the same run.
//!
//! Invocation i writes vec4s `i·run .. (i+1)·run` of one buffer with values that depend on both
//! indices, so that nothing can be folded away. With `run = 1` neighbouring invocations write
//! neighbouring vec4s (a GPU's best store pattern: the bench's "gpu-memset"); with
//! [`STORE_CEILING_RUN`] each invocation writes a run as the evaluator's looping shape does (the
//! bench's "gpu-store-ceiling", the bound for that shape on lavapipe).

use super::GpuContext;
use super::timing::Timestamps;
use crate::error::GpuError;

/// The kernel (shaders/store_only.wgsl).
const KERNEL: &str = include_str!("../../shaders/store_only.wgsl");

/// Vec4s per invocation of the store ceiling: w1's 8 segments of 32 three-dimensional samples,
/// one looping run of the evaluator.
pub const STORE_CEILING_RUN: u32 = 8 * 32 * 3 / 4;

/// A store-only kernel compiled for a byte count, with its buffer, ready to be timed.
#[derive(Debug)]
pub struct StoreKernel {
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    groups: u32,
    /// The buffer is written this many times (a byte count past one storage binding is split).
    dispatches: usize,
}

impl GpuContext {
    /// A store-only kernel writing `bytes` (rounded up to whole runs) in `run` vec4s per
    /// invocation, through one buffer of at most one storage binding, rewritten as many times as
    /// the byte count needs.
    ///
    /// # Errors
    /// [`GpuError::Device`] if the device refuses the buffer or the pipeline.
    pub fn store_kernel(&self, bytes: u64, run: u32) -> Result<StoreKernel, GpuError> {
        let device = &self.device;
        let limits = device.limits();
        let run_bytes = 16 * u64::from(run.max(1));
        let most = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let most = most / run_bytes * run_bytes;
        let dispatches = bytes.div_ceil(most.max(run_bytes)).max(1);
        let invocations = bytes.div_ceil(dispatches).div_ceil(run_bytes);
        let invocations = u32::try_from(invocations)
            .map_err(|_| GpuError::device(format!("{bytes} bytes: too many invocations")))?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("store only"),
            source: wgpu::ShaderSource::Wgsl(KERNEL.into()),
        });
        let constants = [
            ("RUN", f64::from(run.max(1))),
            ("INVOCATIONS", f64::from(invocations)),
        ];
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("store only"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            },
            cache: None,
        });
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("store only"),
            size: u64::from(invocations) * run_bytes,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("store only"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: out.as_entire_binding(),
            }],
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::device(e));
        }
        Ok(StoreKernel {
            pipeline,
            bind_group,
            groups: invocations.div_ceil(64),
            dispatches: dispatches as usize,
        })
    }
}

impl StoreKernel {
    /// Runs the kernel once: seconds on the device by timestamp queries where `gpu` has them,
    /// else from submission to completion.
    ///
    /// # Errors
    /// [`GpuError::Device`] if the device is lost.
    pub fn time(&self, gpu: &GpuContext) -> Result<f64, GpuError> {
        let device = &gpu.device;
        let stamps = (device.features())
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| Timestamps::new(device, self.dispatches));
        let mut encoder = device.create_command_encoder(&Default::default());
        for d in 0..self.dispatches {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("store only"),
                timestamp_writes: stamps.as_ref().map(|s| s.writes(d)),
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.dispatch_workgroups(self.groups.min(65535), self.groups.div_ceil(65535), 1);
        }
        if let Some(stamps) = &stamps {
            stamps.resolve(&mut encoder);
        }
        let start = std::time::Instant::now();
        gpu.queue.submit([encoder.finish()]);
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(GpuError::device)?;
        let wall = start.elapsed().as_secs_f64();
        match stamps {
            Some(stamps) => stamps.read(device, gpu.queue.get_timestamp_period()),
            None => Ok(wall),
        }
    }
}
