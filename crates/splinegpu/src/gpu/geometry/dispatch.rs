//! A geometry job's meshes on the GPU: tubes and ribbons (dashed or not) and strokes through
//! `shaders/geometry.wgsl` in groups whose every binding fits the device's limits; every
//! vertex's t and the triangles made on the host, as the CPU makes them.

use rayon::prelude::*;

use crate::error::GpuError;
use crate::geometry::job::{KernelPlan, split_planes};
use crate::geometry::mesh::MeshOut;
use crate::geometry::{GeometryJob, MeshPlanes, Meshes};
use crate::gpu::GpuContext;
use crate::gpu::geometry::abi::{
    GEOMETRY_BINDINGS, GEOMETRY_WG_SIZE, GEOMETRY_WGSL, GeometryParams, SHAPE_STROKE, VERTEX_FLOATS,
};
use crate::gpu::geometry::pack::{PackedGeometry, binding_bytes};
use crate::gpu::kernel::{Kernel, workgroup_grid};
use crate::gpu::pool::Lease;
use crate::gpu::surfaces::dispatch::nonempty;

/// A dispatch of packed curves: its uniforms, and each entry point's grid where it has work
/// (`main` over the curves, when any is a tube or ribbon; `strokes` over the stroke vertices).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Launch {
    pub(crate) params: GeometryParams,
    main: Option<(u32, u32)>,
    strokes: Option<(u32, u32)>,
}

impl Launch {
    pub(crate) fn new(device: &wgpu::Device, packed: &PackedGeometry) -> Self {
        let curves = packed.curves.len() as u32;
        let stroke_vertices = packed.stroke_vertices.len() as u32;
        let grid = workgroup_grid(device, curves, GEOMETRY_WG_SIZE);
        let stroke_grid = workgroup_grid(device, stroke_vertices, GEOMETRY_WG_SIZE);
        let swept = packed.curves.iter().any(|c| c.shape != SHAPE_STROKE);
        Self {
            params: GeometryParams {
                curve_count: curves,
                row_width: grid.0 * GEOMETRY_WG_SIZE,
                stroke_vertex_count: stroke_vertices,
                stroke_row_width: stroke_grid.0 * GEOMETRY_WG_SIZE,
                ..GeometryParams::default()
            },
            main: swept.then_some(grid),
            strokes: (stroke_vertices > 0).then_some(stroke_grid),
        }
    }
}

impl GpuContext {
    /// Records `launch`'s entry points into `encoder`, bound to `resources` (in the order of
    /// `GEOMETRY_BINDINGS`).
    pub(crate) fn record_geometry(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        resources: &[wgpu::BindingResource<'_>],
        launch: &Launch,
    ) {
        let kernels = [
            (launch.main, &self.geometry, "main"),
            (launch.strokes, &self.geometry_strokes, "strokes"),
        ];
        for (grid, kernel, entry) in kernels {
            let Some(grid) = grid else { continue };
            let kernel = kernel.get_or_init(|| {
                Kernel::with_entry(
                    &self.device,
                    "geometry.wgsl",
                    GEOMETRY_WGSL,
                    entry,
                    &GEOMETRY_BINDINGS,
                )
            });
            kernel.record(&self.device, encoder, label, resources.to_vec(), grid, None);
        }
    }

    /// Every mesh of `job` with f32 positions and normals made on the GPU: tubes and ribbons
    /// (dashed or not; one invocation a curve carrying its frame along its cross-sections)
    /// and strokes (one invocation a vertex); t and the triangles as the CPU makes them, bit
    /// for bit (a stroke's triangles are turned by its f64 positions, so the host makes its
    /// f64 mesh for them). Positions within the curve's GPU position bound plus 1e-5 of the
    /// radius or width of [`GeometryJob::evaluate_cpu`]'s, normals within 1e-3 radians (the
    /// contract's promise, tested on lavapipe).
    ///
    /// # Errors
    /// [`GpuError`] when the device is lost or a buffer cannot be mapped,
    /// [`GpuError::OutOfRange`] for a curve whose coefficients do not fit f32, or
    /// [`GpuError::TooLarge`] for one curve whose tables alone exceed a storage binding.
    pub fn evaluate_geometry(&self, job: &GeometryJob) -> Result<Meshes<f32>, GpuError> {
        self.evaluate_geometry_group(job, 0..job.len())
    }

    /// [`GpuContext::evaluate_geometry`] of the curves of `curves` (a group of
    /// [`GeometryJob::groups`], made and written one at a time): their offsets start at 0.
    ///
    /// # Errors
    /// As [`GpuContext::evaluate_geometry`].
    ///
    /// # Panics
    /// If `curves` is not within the job.
    pub fn evaluate_geometry_group(
        &self,
        job: &GeometryJob,
        curves: std::ops::Range<usize>,
    ) -> Result<Meshes<f32>, GpuError> {
        let from = |offsets: &[u64]| -> Vec<u64> {
            offsets[curves.start..=curves.end]
                .iter()
                .map(|o| o - offsets[curves.start])
                .collect()
        };
        let (vertex_offsets, triangle_offsets) =
            (from(job.vertex_offsets()), from(job.triangle_offsets()));
        let v = usize::try_from(vertex_offsets[curves.len()]).expect("checked against memory");
        let f = usize::try_from(triangle_offsets[curves.len()]).expect("checked against memory");
        // Checked against the memory the job may take when it was grouped; fresh pages on
        // huge pages.
        let mut meshes = Meshes {
            points: crate::memory::zeroed(3 * v),
            normals: crate::memory::zeroed(3 * v),
            t: crate::memory::zeroed(v),
            triangles: crate::memory::zeroed(f),
            vertex_offsets,
            triangle_offsets,
        };
        // Every curve's t and triangles on every thread.
        let mut outs = split(&mut meshes);
        curves
            .clone()
            .into_par_iter()
            .zip(outs.par_iter_mut())
            .for_each(|(c, out)| job.topology(c, out.t, out.triangles));
        let plans: Vec<(usize, KernelPlan<'_>)> =
            curves.clone().map(|c| (c, job.kernel_plan(c))).collect();
        let limits = self.device.limits();
        let binding = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let mut outs = outs.iter_mut();
        for group in binding_groups(&plans, binding)? {
            // The group's curves' outputs (disjoint), and where each one's values start.
            let mut targets: Vec<&mut MeshOut<'_, f32>> = outs.by_ref().take(group.len()).collect();
            let starts: Vec<usize> = targets
                .iter()
                .scan(0, |at, out| {
                    let start = *at;
                    *at += VERTEX_FLOATS * out.t.len();
                    Some(start)
                })
                .collect();
            self.dispatch_geometry(&PackedGeometry::new(group)?, &mut |values| {
                targets
                    .par_iter_mut()
                    .zip(&starts)
                    .for_each(|(out, &start)| deinterleave(&values[start..], out));
            })?;
        }
        Ok(meshes)
    }

    /// One dispatch of `packed`'s curves, their vertices' positions and normals (interleaved)
    /// handed to `consume` from the mapped read-back buffer; its buffers leased from the
    /// context's pool (fresh pages are what a large call pays most for on a CPU adapter).
    fn dispatch_geometry(
        &self,
        packed: &PackedGeometry,
        consume: &mut dyn FnMut(&[f32]),
    ) -> Result<(), GpuError> {
        use wgpu::util::DeviceExt;
        let device = &self.device;
        let launch = Launch::new(device, packed);
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let uniform = init(
            "geometry params",
            bytemuck::bytes_of(&launch.params),
            wgpu::BufferUsages::UNIFORM,
        );
        let mut lease = Lease::new(&self.pool, device);
        let mut table = |role: &'static str, contents: &[u8]| {
            let buffer = lease.take(
                (role, 0),
                contents.len() as u64,
                storage | wgpu::BufferUsages::COPY_DST,
            );
            self.queue.write_buffer(&buffer, 0, contents);
            buffer
        };
        let curves = table(
            "geometry curves",
            bytemuck::cast_slice(&nonempty(&packed.curves)),
        );
        let blocks = table(
            "geometry blocks",
            bytemuck::cast_slice(&nonempty(&packed.blocks)),
        );
        let sections = table(
            "geometry sections",
            bytemuck::cast_slice(&nonempty(&packed.sections)),
        );
        let stroke_vertices = table(
            "geometry stroke vertices",
            bytemuck::cast_slice(&nonempty(&packed.stroke_vertices)),
        );
        let floats = VERTEX_FLOATS * packed.vertices;
        let bytes = (4 * floats).max(4) as u64;
        let output = lease.take(
            ("geometry vertices", 0),
            bytes,
            storage | wgpu::BufferUsages::COPY_SRC,
        );
        let download = lease.take(
            ("geometry download", 0),
            bytes,
            wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        );
        let mut encoder = device.create_command_encoder(&Default::default());
        let resources: Vec<_> = [
            &uniform,
            &curves,
            &blocks,
            &sections,
            &output,
            &stroke_vertices,
        ]
        .iter()
        .map(|b| b.as_entire_binding())
        .collect();
        self.record_geometry(&mut encoder, "geometry", &resources, &launch);
        encoder.copy_buffer_to_buffer(&output, 0, &download, 0, bytes);
        self.queue.submit([encoder.finish()]);
        crate::gpu::readback::map_read(device, &download, |bytes| {
            consume(&bytemuck::cast_slice::<u8, f32>(bytes)[..floats]);
        })
    }
}

/// Interleaved vertices (position, normal) from the start of `values` into `out`'s planes.
fn deinterleave(values: &[f32], out: &mut MeshOut<'_, f32>) {
    for ((p, n), vertex) in out
        .points
        .chunks_exact_mut(3)
        .zip(out.normals.chunks_exact_mut(3))
        .zip(values.chunks_exact(VERTEX_FLOATS))
    {
        p.copy_from_slice(&vertex[..3]);
        n.copy_from_slice(&vertex[3..]);
    }
}

/// `meshes`' planes cut into each curve's part.
fn split(meshes: &mut Meshes<f32>) -> Vec<MeshOut<'_, f32>> {
    let planes = MeshPlanes {
        points: &mut meshes.points,
        normals: &mut meshes.normals,
        t: &mut meshes.t,
        triangles: &mut meshes.triangles,
    };
    split_planes(
        planes,
        &meshes.vertex_offsets,
        &meshes.triangle_offsets,
        true,
    )
}

/// The curves cut into consecutive groups whose every binding (curve records, blocks,
/// sections, output, stroke vertices) fits `binding` bytes.
///
/// # Errors
/// [`GpuError::TooLarge`] for a curve that alone does not fit.
fn binding_groups<'p, 'a>(
    plans: &'p [(usize, KernelPlan<'a>)],
    binding: u64,
) -> Result<Vec<&'p [(usize, KernelPlan<'a>)]>, GpuError> {
    const TABLES: [&str; 5] = [
        "geometry curve records",
        "geometry blocks",
        "geometry sections",
        "geometry output",
        "geometry stroke vertices",
    ];
    let mut groups = Vec::new();
    let (mut start, mut held) = (0, [0u64; 5]);
    for (i, (_, plan)) in plans.iter().enumerate() {
        let bytes = binding_bytes(plan);
        if let Some(k) = (0..5).find(|&k| bytes[k] > binding) {
            return Err(GpuError::TooLarge {
                table: TABLES[k],
                bytes: bytes[k],
                limit: binding,
            });
        }
        if (0..5).any(|k| held[k] + bytes[k] > binding) {
            groups.push(&plans[start..i]);
            (start, held) = (i, [0; 5]);
        }
        for k in 0..5 {
            held[k] += bytes[k];
        }
    }
    if start < plans.len() {
        groups.push(&plans[start..]);
    }
    Ok(groups)
}
