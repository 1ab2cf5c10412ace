//! A geometry job's meshes on the GPU: tubes and ribbons, dashed or not, through
//! `shaders/geometry.wgsl` in groups whose every binding fits the device's limits, strokes made
//! on the host (their kernel is to come) and rounded to f32 once; every vertex's t and the
//! triangles made on the host, as the CPU makes them.

use rayon::prelude::*;

use crate::error::GpuError;
use crate::geometry::job::SweptPlan;
use crate::geometry::job::split_planes;
use crate::geometry::mesh::MeshOut;
use crate::geometry::{GeometryJob, MeshPlanes, Meshes};
use crate::gpu::GpuContext;
use crate::gpu::geometry::abi::{
    GEOMETRY_BINDINGS, GEOMETRY_WG_SIZE, GEOMETRY_WGSL, GeometryParams, VERTEX_FLOATS,
};
use crate::gpu::geometry::pack::{PackedGeometry, binding_bytes};
use crate::gpu::kernel::{Kernel, workgroup_grid};
use crate::gpu::pool::Lease;
use crate::gpu::surfaces::dispatch::nonempty;

impl GpuContext {
    pub(crate) fn geometry_kernel(&self) -> &Kernel {
        self.geometry.get_or_init(|| {
            Kernel::new(
                &self.device,
                "geometry.wgsl",
                GEOMETRY_WGSL,
                &GEOMETRY_BINDINGS,
            )
        })
    }

    /// Every mesh of `job` with f32 positions and normals: tubes and ribbons, dashed or not,
    /// made on the GPU (one invocation a curve carrying its frame along its cross-sections),
    /// strokes on the host (their kernel is not built yet); t and the triangles as the
    /// CPU makes them, bit for bit. Positions within the curve's GPU position bound plus
    /// 1e-5 of the radius or width of [`GeometryJob::evaluate_cpu`]'s, normals within 1e-3
    /// radians (the contract's promise, tested on lavapipe).
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
        let mut meshes = Meshes {
            points: vec![0.0f32; 3 * v],
            normals: vec![0.0f32; 3 * v],
            t: vec![0.0; v],
            triangles: vec![[0; 3]; f],
            vertex_offsets,
            triangle_offsets,
        };
        // Every curve's t and triangles, and the host-made meshes, on every thread; the swept
        // curves' plans kept in order for the kernel, with their place in `curves`.
        let vertex_offsets = meshes.vertex_offsets.clone();
        let mut outs = split(&mut meshes);
        let swept: Vec<Option<(usize, SweptPlan<'_>)>> = curves
            .clone()
            .into_par_iter()
            .zip(outs.par_iter_mut())
            .map(|(c, out)| match job.swept(c) {
                Some(plan) => {
                    plan.topology(out.t, out.triangles);
                    Some((c, plan))
                }
                None => {
                    job.make_into(c, out);
                    None
                }
            })
            .collect();
        let places: Vec<usize> = (0..swept.len()).filter(|&i| swept[i].is_some()).collect();
        let on_device: Vec<(usize, SweptPlan<'_>)> = swept.iter().flatten().copied().collect();
        let limits = self.device.limits();
        let binding = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let mut done = 0;
        for group in binding_groups(&on_device, binding)? {
            let mine = &places[done..done + group.len()];
            done += group.len();
            // The group's curves' outputs (disjoint), and where each one's values start.
            let mut targets: Vec<&mut MeshOut<'_, f32>> = Vec::with_capacity(mine.len());
            let mut wanted = mine.iter().peekable();
            for (i, out) in outs.iter_mut().enumerate() {
                if wanted.peek() == Some(&&i) {
                    targets.push(out);
                    wanted.next();
                }
            }
            let starts: Vec<usize> = mine
                .iter()
                .scan(0, |at, &i| {
                    let start = *at;
                    *at += VERTEX_FLOATS * range(&vertex_offsets, i).len();
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
        let kernel = self.geometry_kernel();
        let grid = workgroup_grid(device, packed.curves.len() as u32, GEOMETRY_WG_SIZE);
        let params = GeometryParams {
            curve_count: packed.curves.len() as u32,
            row_width: grid.0 * GEOMETRY_WG_SIZE,
            out_base: 0,
            _padding0: 0,
        };
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
            bytemuck::bytes_of(&params),
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
        let resources = [&uniform, &curves, &blocks, &sections, &output]
            .iter()
            .map(|b| b.as_entire_binding())
            .collect();
        kernel.record(device, &mut encoder, "geometry", resources, grid, None);
        encoder.copy_buffer_to_buffer(&output, 0, &download, 0, bytes);
        self.queue.submit([encoder.finish()]);
        crate::gpu::readback::map_read(device, &download, |bytes| {
            consume(&bytemuck::cast_slice::<u8, f32>(bytes)[..floats]);
        })
    }
}

fn range(offsets: &[u64], c: usize) -> std::ops::Range<usize> {
    offsets[c] as usize..offsets[c + 1] as usize
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
    split_planes(planes, &meshes.vertex_offsets, &meshes.triangle_offsets)
}

/// The swept curves cut into consecutive groups whose every binding (curve records, blocks,
/// sections, output) fits `binding` bytes.
///
/// # Errors
/// [`GpuError::TooLarge`] for a curve that alone does not fit.
fn binding_groups<'p, 'a>(
    swept: &'p [(usize, SweptPlan<'a>)],
    binding: u64,
) -> Result<Vec<&'p [(usize, SweptPlan<'a>)]>, GpuError> {
    const TABLES: [&str; 4] = [
        "geometry curve records",
        "geometry blocks",
        "geometry sections",
        "geometry output",
    ];
    let mut groups = Vec::new();
    let (mut start, mut held) = (0, [0u64; 4]);
    for (i, (_, plan)) in swept.iter().enumerate() {
        let bytes = binding_bytes(plan);
        if let Some(k) = (0..4).find(|&k| bytes[k] > binding) {
            return Err(GpuError::TooLarge {
                table: TABLES[k],
                bytes: bytes[k],
                limit: binding,
            });
        }
        if (0..4).any(|k| held[k] + bytes[k] > binding) {
            groups.push(&swept[start..i]);
            (start, held) = (i, [0; 4]);
        }
        for k in 0..4 {
            held[k] += bytes[k];
        }
    }
    if start < swept.len() {
        groups.push(&swept[start..]);
    }
    Ok(groups)
}
