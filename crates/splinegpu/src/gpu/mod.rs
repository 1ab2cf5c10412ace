//! The GPU evaluator: a `GpuContext` (device, queue, compiled pipelines) made once and reused.
//!
//! Getting a device is kept apart from doing the work: [`GpuContext::new`] picks an adapter,
//! [`GpuContext::from_device`] takes a caller's device and queue, and
//! [`GpuContext::evaluate`] (in `eval.rs`) runs a job and reads the samples back.

#[cfg(feature = "profiling")]
pub(crate) mod ceiling;
pub(crate) mod curves;
pub(crate) mod geometry;
pub(crate) mod kernel;
// The kernel's f32 twin on the CPU: the tests check the packer and every kernel shape with it
// where no GPU is needed.
pub(crate) mod pool;
pub(crate) mod queries;
pub(crate) mod readback;
pub(crate) mod surfaces;
pub(crate) mod timing;

pub use curves::record::OutputLayout;
pub use geometry::record::{GeometryOutputLayout, GeometryRecording};
pub use surfaces::record::{SurfaceOutputLayout, SurfaceRecording};

use crate::error::GpuError;

/// How the kernel spreads a job over invocations.
///
/// A job is cut into runs of at most `run_len` consecutive samples (of one segment, or of
/// several short consecutive segments of one curve); `lanes` invocations share a run, each
/// taking every `lanes`-th sample (or group of 4). On a CPU adapter (lavapipe) one invocation
/// looping over a long run is fastest (`lanes = 1`: long runs amortise the per-segment
/// coefficient loads, which dominate there); a GPU wants one sample per invocation so that
/// neighbouring invocations write neighbouring addresses (`lanes = run_len`). The README's
/// bench table has the current figures.
#[cfg_attr(
    not(feature = "profiling"),
    expect(unreachable_pub, reason = "public through the profiling feature")
)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KernelShape {
    /// Invocations per run (>= 1).
    pub lanes: u32,
    /// Samples per run (>= 1).
    pub run_len: u32,
}

#[cfg_attr(
    not(feature = "profiling"),
    expect(unreachable_pub, reason = "public through the profiling feature")
)]
impl KernelShape {
    /// Long runs, one invocation each: for CPU adapters such as lavapipe.
    pub const LOOPING: KernelShape = KernelShape {
        lanes: 1,
        run_len: 256,
    };
    /// One sample per invocation: for GPUs.
    pub const PER_SAMPLE: KernelShape = KernelShape {
        lanes: 32,
        run_len: 32,
    };

    /// The shapes the unit tests run the packer and the kernel's twin in: a GPU's, a CPU
    /// adapter's, and awkward ones (runs not a multiple of 4, one sample per run, many lanes).
    #[cfg(test)]
    pub(crate) const TESTED: [KernelShape; 5] = [
        KernelShape::LOOPING,
        KernelShape::PER_SAMPLE,
        KernelShape {
            lanes: 4,
            run_len: 7,
        },
        KernelShape {
            lanes: 1,
            run_len: 1,
        },
        KernelShape {
            lanes: 8,
            run_len: 64,
        },
    ];

    /// The default shape for an adapter of this type.
    #[must_use]
    pub fn for_device_type(device_type: wgpu::DeviceType) -> Self {
        match device_type {
            wgpu::DeviceType::Cpu => Self::LOOPING,
            _ => Self::PER_SAMPLE,
        }
    }
}

/// A device, its queue and the compiled evaluation pipelines (one per run mode).
///
/// `GpuContext` is `Send + Sync`: one context may serve many threads at once. Each evaluation
/// takes its own buffers out of the context's pool (and gives them back when it is done), so
/// concurrent calls never share a buffer; wgpu orders their submissions on the queue.
#[derive(Debug)]
pub struct GpuContext {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    shape: KernelShape,
    /// At most this many output values per plane in one dispatch (besides the device's limit).
    max_dispatch_values: usize,
    bind_group_layout: wgpu::BindGroupLayout,
    /// The kernel compiled for each run mode (indexed by `curves::pack::MODE_*`).
    pipelines: [wgpu::ComputePipeline; curves::abi::MODES],
    /// Whether the kernel's output buffer is mapped and read itself (a CPU adapter with
    /// `MAPPABLE_PRIMARY_BUFFERS`, where device memory is host memory), instead of copied into
    /// a download buffer first (on lavapipe that copy was a large share of w1's time end to
    /// end: docs/benchmarks.md).
    map_output: bool,
    /// Buffers kept between calls, so that repeated jobs neither allocate nor page-fault.
    pool: std::sync::Mutex<pool::BufferPool>,
    /// Host-side packings kept between calls, for the same reason (one per concurrent call).
    packings: std::sync::Mutex<Vec<curves::pack::Packed>>,
    /// The surface kernel, compiled on first use.
    surface: std::sync::OnceLock<kernel::Kernel>,
    /// The geometry kernel's entry points (tubes and ribbons; strokes), each compiled on first
    /// use.
    geometry: std::sync::OnceLock<kernel::Kernel>,
    geometry_strokes: std::sync::OnceLock<kernel::Kernel>,
    /// The query kernels, each compiled on first use.
    closest: std::sync::OnceLock<kernel::Kernel>,
    surface_closest: std::sync::OnceLock<kernel::Kernel>,
    rays: std::sync::OnceLock<kernel::Kernel>,
}

// One context serves many threads (see its docs): checked at compile time.
const _: fn() = || {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<GpuContext>();
};

impl GpuContext {
    /// A context on the adapter wgpu's environment conventions pick: `WGPU_BACKEND` limits the
    /// backends, `WGPU_ADAPTER_NAME` (a case-insensitive substring of the adapter's name)
    /// picks one by name, and otherwise `WGPU_POWER_PREF` (`low`, `high` or `none`; default
    /// `high`) guides wgpu's choice.
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] when there is none (or none matches the name);
    /// [`GpuError::RequestDevice`] when the adapter refuses a device.
    pub fn new() -> Result<Self, GpuError> {
        let instance = new_instance();
        let adapter = match std::env::var("WGPU_ADAPTER_NAME") {
            Ok(name) => {
                // wgpu's helper panics when the name matches nothing: that is an error here.
                let wanted = name.to_lowercase();
                let adapters =
                    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
                if !adapters
                    .iter()
                    .any(|a| a.get_info().name.to_lowercase().contains(&wanted))
                {
                    return Err(GpuError::NoAdapter(format!(
                        "no adapter matches WGPU_ADAPTER_NAME={name}"
                    )));
                }
                pollster::block_on(wgpu::util::initialize_adapter_from_env(&instance, None))
            }
            Err(_) => pollster::block_on(
                instance.request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env()
                        .unwrap_or(wgpu::PowerPreference::HighPerformance),
                    ..Default::default()
                }),
            ),
        }
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        Self::from_adapter(&adapter)
    }

    /// A context on `adapter`, with the largest limits it offers.
    ///
    /// # Errors
    /// [`GpuError::RequestDevice`] when the adapter refuses a device.
    pub fn from_adapter(adapter: &wgpu::Adapter) -> Result<Self, GpuError> {
        let info = adapter.get_info();
        // Timestamp queries, where the adapter has them, time dispatches on the device; a CPU
        // adapter's buffers are host memory, so its output buffers are mapped directly.
        let mut wanted = wgpu::Features::TIMESTAMP_QUERY;
        if info.device_type == wgpu::DeviceType::Cpu {
            wanted |= wgpu::Features::MAPPABLE_PRIMARY_BUFFERS;
        }
        let required_features = adapter.features() & wanted;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("splinegpu"),
            required_features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|source| GpuError::RequestDevice {
            adapter: info.name.clone(),
            source,
        })?;
        Ok(Self::with_parts(device, queue, info))
    }

    /// The "auto" backend's choice: a context on the [`hardware_adapter`] when there is one,
    /// else `None` (evaluate on the CPU then; on a CPU adapter such as lavapipe the CPU
    /// evaluator is the faster of the two).
    ///
    /// # Errors
    /// [`GpuError::RequestDevice`] when the hardware adapter refuses a device.
    pub fn auto() -> Result<Option<Self>, GpuError> {
        hardware_adapter()
            .map(|adapter| Self::from_adapter(&adapter))
            .transpose()
    }

    /// A context on a caller's device and queue (a renderer's, say); nothing is copied.
    #[must_use]
    pub fn from_device(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        Self::with_parts(device.clone(), queue.clone(), device.adapter_info())
    }

    fn with_parts(device: wgpu::Device, queue: wgpu::Queue, info: wgpu::AdapterInfo) -> Self {
        let shape = KernelShape::for_device_type(info.device_type);
        let entries: Vec<_> = curves::abi::BINDINGS
            .iter()
            .enumerate()
            .map(|(i, (ty, _, min_size))| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: *ty,
                    has_dynamic_offset: false,
                    min_binding_size: std::num::NonZeroU64::new(*min_size),
                },
                count: None,
            })
            .collect();
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("eval"),
            entries: &entries,
        });
        let pipelines = compile(&device, &bind_group_layout, shape);
        let map_output = info.device_type == wgpu::DeviceType::Cpu
            && (device.features()).contains(wgpu::Features::MAPPABLE_PRIMARY_BUFFERS);
        Self {
            device,
            queue,
            info,
            shape,
            max_dispatch_values: usize::MAX,
            map_output,
            bind_group_layout,
            pipelines,
            pool: std::sync::Mutex::default(),
            packings: std::sync::Mutex::default(),
            surface: std::sync::OnceLock::new(),
            geometry: std::sync::OnceLock::new(),
            geometry_strokes: std::sync::OnceLock::new(),
            closest: std::sync::OnceLock::new(),
            surface_closest: std::sync::OnceLock::new(),
            rays: std::sync::OnceLock::new(),
        }
    }

    /// The same context with another kernel shape (recompiles the pipelines).
    ///
    /// # Panics
    /// If `shape.lanes` or `shape.run_len` is 0.
    #[cfg(feature = "profiling")]
    #[must_use]
    pub fn with_shape(mut self, shape: KernelShape) -> Self {
        assert!(
            shape.lanes >= 1 && shape.run_len >= 1,
            "a kernel shape needs lanes and run_len >= 1"
        );
        self.pipelines = compile(&self.device, &self.bind_group_layout, shape);
        self.shape = shape;
        self
    }

    /// The same context, cutting jobs into dispatches of at most `values` output values per
    /// plane (the device's storage-binding limit always applies). Smaller dispatches bound the
    /// GPU memory a job holds at once; results are the same.
    ///
    /// # Panics
    /// If `values` is 0.
    #[must_use]
    pub fn with_max_dispatch_values(mut self, values: usize) -> Self {
        assert!(values >= 1, "a dispatch must hold at least one value");
        self.max_dispatch_values = values;
        self
    }

    /// The adapter this context runs on.
    #[must_use]
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.info
    }

    /// The kernel shape in use.
    #[cfg(feature = "profiling")]
    #[must_use]
    pub fn shape(&self) -> KernelShape {
        self.shape
    }

    /// Whether `target` can take `needed` bytes from byte `offset` on as a storage binding:
    /// the renderer paths' one check of a caller's buffer.
    ///
    /// # Errors
    /// [`TargetError`]: no `STORAGE` usage, an offset not a multiple of the device's
    /// storage-offset alignment, or too few bytes from the offset on.
    pub(crate) fn check_target(
        &self,
        target: &wgpu::Buffer,
        offset: u64,
        needed: u64,
    ) -> Result<(), crate::error::TargetError> {
        use crate::error::TargetError;
        let alignment = u64::from(self.device.limits().min_storage_buffer_offset_alignment);
        if !target.usage().contains(wgpu::BufferUsages::STORAGE) {
            return Err(TargetError::MissingStorageUsage);
        }
        if !offset.is_multiple_of(alignment) {
            return Err(TargetError::MisalignedOffset { offset, alignment });
        }
        if offset.saturating_add(needed) > target.size() {
            return Err(TargetError::TooSmall {
                available: target.size().saturating_sub(offset),
                needed,
            });
        }
        Ok(())
    }

    /// The device.
    #[must_use]
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue.
    #[must_use]
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }
}

/// A wgpu instance configured from the environment (`WGPU_BACKEND`, `WGPU_DEBUG`, ...).
#[must_use]
pub fn new_instance() -> wgpu::Instance {
    wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env())
}

/// Every adapter wgpu finds, on every backend.
#[must_use]
pub fn adapters() -> Vec<wgpu::AdapterInfo> {
    let instance = new_instance();
    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
        .iter()
        .map(wgpu::Adapter::get_info)
        .collect()
}

/// The hardware adapter (discrete, integrated or virtual GPU, in that order of preference) that
/// [`GpuContext::auto`] (the CLI's `--backend auto`) uses, if there is one.
#[must_use]
pub fn hardware_adapter() -> Option<wgpu::Adapter> {
    let rank = |t: wgpu::DeviceType| match t {
        wgpu::DeviceType::DiscreteGpu => Some(0),
        wgpu::DeviceType::IntegratedGpu => Some(1),
        wgpu::DeviceType::VirtualGpu => Some(2),
        wgpu::DeviceType::Cpu | wgpu::DeviceType::Other => None,
    };
    let instance = new_instance();
    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
        .into_iter()
        .filter_map(|a| rank(a.get_info().device_type).map(|r| (r, a)))
        .min_by_key(|(r, _)| *r)
        .map(|(_, a)| a)
}

/// The kernel's pipeline for each run mode, for `shape`.
fn compile(
    device: &wgpu::Device,
    bind_group_layout: &wgpu::BindGroupLayout,
    shape: KernelShape,
) -> [wgpu::ComputePipeline; curves::abi::MODES] {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("eval.wgsl"),
        source: wgpu::ShaderSource::Wgsl(curves::abi::EVAL_WGSL.into()),
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("eval"),
        bind_group_layouts: &[Some(bind_group_layout)],
        immediate_size: 0,
    });
    std::array::from_fn(|mode| {
        let (kernel_mode, rational) = curves::abi::kernel_mode(mode as u32);
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("eval"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(curves::abi::ENTRY_POINT),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &[
                    (curves::abi::LANES_CONSTANT, f64::from(shape.lanes)),
                    (curves::abi::MODE_CONSTANT, f64::from(kernel_mode)),
                    (
                        curves::abi::RATIONAL_CONSTANT,
                        f64::from(u8::from(rational)),
                    ),
                ],
                ..Default::default()
            },
            cache: None,
        })
    })
}
