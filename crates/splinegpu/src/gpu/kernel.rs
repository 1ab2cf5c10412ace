//! A kernel of one entry point ("main", or one named) and one bind group, compiled once per
//! context on first use: the surface, geometry and query kernels' pipelines and bind group
//! layouts.

/// A compiled kernel and its bind group layout.
#[derive(Debug)]
pub(crate) struct Kernel {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl Kernel {
    /// Compiles the WGSL `source` (named `label`) whose bindings, in group 0, are `bindings`
    /// in order.
    pub(crate) fn new(
        device: &wgpu::Device,
        label: &str,
        source: &str,
        bindings: &[wgpu::BufferBindingType],
    ) -> Self {
        Self::with_entry(device, label, source, "main", bindings)
    }

    /// [`Kernel::new`] for the entry point `entry` of a source that has several.
    pub(crate) fn with_entry(
        device: &wgpu::Device,
        label: &str,
        source: &str,
        entry: &str,
        bindings: &[wgpu::BufferBindingType],
    ) -> Self {
        let entries: Vec<_> = bindings
            .iter()
            .enumerate()
            .map(|(i, ty)| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: *ty,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        Self { layout, pipeline }
    }

    /// Records one pass of the kernel into `encoder`: binding i is `resources[i]`, and
    /// `workgroups` (x, y) of them run (see [`workgroup_grid`]), with `timestamps` around the
    /// pass where given.
    pub(crate) fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        resources: Vec<wgpu::BindingResource<'_>>,
        workgroups: (u32, u32),
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
            .into_iter()
            .enumerate()
            .map(|(i, resource)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource,
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &self.layout,
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(workgroups.0, workgroups.1, 1);
    }
}

/// The workgroups (x, y) that run `invocations` in groups of `size`, x within the device's
/// per-dimension limit (at least one workgroup): the kernel's row width is x · size.
pub(crate) fn workgroup_grid(device: &wgpu::Device, invocations: u32, size: u32) -> (u32, u32) {
    let groups = invocations.div_ceil(size).max(1);
    let across = groups.min(device.limits().max_compute_workgroups_per_dimension);
    (across, groups.div_ceil(across))
}
