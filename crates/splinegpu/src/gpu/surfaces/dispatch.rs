//! Surfaces evaluated on the GPU: a job's surfaces grouped so that their packed patches fit one
//! storage binding, each group's vertices cut into dispatches whose every binding fits the
//! device's limits ([`DispatchBudget`]), each dispatch's planes copied straight into the
//! surfaces' samples.

use std::ops::Range;

use crate::error::GpuError;
use crate::gpu::GpuContext;
use crate::gpu::kernel::{Kernel, workgroup_grid};
use crate::gpu::surfaces::abi::{
    GpuVertex, SURFACE_BINDINGS, SURFACE_WG_SIZE, SURFACE_WGSL, SurfaceParams,
};
use crate::gpu::surfaces::pack::{NORMAL_NET_FLOATS, PackedPatches};
use crate::gpu::timing::Timestamps;
#[cfg(feature = "profiling")]
use crate::gpu::timing::{DeviceTime, TimingMethod};
use crate::job::Derivatives;
use crate::surface::{PatchTable, SurfaceChunk, SurfaceJob, SurfacePlan, SurfaceSamples};

/// The output planes of a vertex of a job: positions, then the derivatives asked for, then
/// normals.
pub(crate) fn plane_count(derivatives: Derivatives, normals: bool) -> usize {
    1 + match derivatives.order() {
        0 => 0,
        1 => 2,
        _ => 5,
    } + usize::from(normals)
}

impl GpuContext {
    pub(crate) fn surface_pipeline(&self) -> &Kernel {
        self.surface.get_or_init(|| {
            Kernel::new(
                &self.device,
                "surface.wgsl",
                SURFACE_WGSL,
                &SURFACE_BINDINGS,
            )
        })
    }

    /// Evaluates every surface of `job` on the GPU in f32, in dispatches that fit the
    /// device's limits: positions, the derivatives asked for (d/du, d/dv in the surface's
    /// parameters) and unit normals (3-D surfaces). Within the contract's surface promise of the
    /// f64 reference ([`SurfaceJob::evaluate_cpu`]).
    ///
    /// # Errors
    /// [`GpuError`] when the device is lost or a buffer cannot be mapped, or
    /// [`GpuError::TooLarge`] for a surface whose patches alone exceed one storage binding.
    pub fn evaluate_surfaces(
        &self,
        job: &SurfaceJob,
    ) -> Result<Vec<SurfaceSamples<f32>>, GpuError> {
        self.evaluate_surface_chunk(job, &SurfaceChunk::whole(0..job.len()))
    }

    /// [`GpuContext::evaluate_surfaces`] of one chunk of [`SurfaceJob::chunks`] (whole
    /// surfaces or a piece of one, evaluated and written one chunk at a time), a sample list
    /// per part as [`SurfaceJob::try_evaluate_cpu_chunk`] gives them.
    ///
    /// # Errors
    /// As [`GpuContext::evaluate_surfaces`].
    ///
    /// # Panics
    /// If the chunk is not of `job`.
    pub fn evaluate_surface_chunk(
        &self,
        job: &SurfaceJob,
        chunk: &SurfaceChunk,
    ) -> Result<Vec<SurfaceSamples<f32>>, GpuError> {
        Ok(self.surfaces_on_device(job, chunk, false)?.0)
    }

    /// [`GpuContext::evaluate_surfaces`], also measuring how long the dispatches ran on the
    /// device: by timestamp queries where the device has `TIMESTAMP_QUERY`, else from each
    /// dispatch's submission to its completion.
    ///
    /// # Errors
    /// As [`GpuContext::evaluate_surfaces`].
    #[cfg(feature = "profiling")]
    pub fn evaluate_surfaces_timed(
        &self,
        job: &SurfaceJob,
    ) -> Result<(Vec<SurfaceSamples<f32>>, DeviceTime), GpuError> {
        let (samples, seconds) =
            self.surfaces_on_device(job, &SurfaceChunk::whole(0..job.len()), true)?;
        let method = TimingMethod::of(&self.device);
        Ok((samples, DeviceTime { seconds, method }))
    }

    /// The parts of `chunk` of `job` on the device, and the dispatches' device seconds when
    /// `timed`.
    fn surfaces_on_device(
        &self,
        job: &SurfaceJob,
        chunk: &SurfaceChunk,
        timed: bool,
    ) -> Result<(Vec<SurfaceSamples<f32>>, f64), GpuError> {
        let (derivatives, normals) = (job.derivatives(), job.normals());
        let planned = job.chunk_plans(chunk);
        let surfaces: Vec<(&PatchTable, &SurfacePlan)> =
            planned.iter().map(|(t, p)| (*t, p.as_ref())).collect();
        // Groups of surfaces whose packed patches fit one storage binding.
        let limits = self.device.limits();
        let limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        // The patches each part's vertices use (a piece of a large surface: a few rows).
        let bytes = |(t, plan): (&PatchTable, &SurfacePlan)| -> u64 {
            let per_patch = 17 * t.dim()
                + if t.is_rational() { 16 } else { 0 }
                + if normals { NORMAL_NET_FLOATS } else { 0 };
            (used_patches(plan).len() * per_patch * 4) as u64
        };
        let mut out = Vec::with_capacity(surfaces.len());
        let mut seconds = 0.0;
        let mut start = 0;
        while start < surfaces.len() {
            let mut end = start;
            let mut total = 0u64;
            while end < surfaces.len() && total + bytes(surfaces[end]) <= limit {
                total += bytes(surfaces[end]);
                end += 1;
            }
            if end == start {
                return Err(GpuError::TooLarge {
                    table: "patch coefficients",
                    bytes: bytes(surfaces[start]),
                    limit,
                });
            }
            let group = &surfaces[start..end];
            out.extend(self.evaluate_binding_group(
                group,
                derivatives,
                normals,
                timed,
                &mut seconds,
            )?);
            start = end;
        }
        Ok((out, seconds))
    }

    /// [`GpuContext::evaluate_surfaces`] of surfaces whose patches fit one binding; when
    /// `timed`, each dispatch's device seconds added to `seconds`.
    fn evaluate_binding_group(
        &self,
        surfaces: &[(&PatchTable, &SurfacePlan)],
        derivatives: Derivatives,
        normals: bool,
        timed: bool,
        seconds: &mut f64,
    ) -> Result<Vec<SurfaceSamples<f32>>, GpuError> {
        let limits = self.device.limits();
        let binding = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let budget = DispatchBudget::for_binding(binding, plane_count(derivatives, normals));
        evaluate_group_with(
            surfaces,
            derivatives,
            normals,
            budget,
            &mut |packed, vertices, floats, consume| {
                *seconds += self.dispatch_surfaces(
                    packed,
                    vertices,
                    (floats, consume),
                    derivatives,
                    normals,
                    timed,
                )?;
                Ok(())
            },
        )
    }

    /// One dispatch of `vertices` (`floats` values per plane), its planes handed to `consume`
    /// from the mapped read-back buffer; when `timed`, the seconds it ran on the device
    /// (timestamps around its pass where the device has them, else from its submission to the
    /// end of its read-back), else 0.
    fn dispatch_surfaces(
        &self,
        packed: &PackedPatches,
        vertices: &[GpuVertex],
        (floats, consume): (usize, Consume<'_>),
        derivatives: Derivatives,
        normals: bool,
        timed: bool,
    ) -> Result<f64, GpuError> {
        let planes = plane_count(derivatives, normals);
        use wgpu::util::DeviceExt;
        let device = &self.device;
        let pipeline = self.surface_pipeline();
        let (across, rows) = workgroup_grid(&self.device, vertices.len() as u32, SURFACE_WG_SIZE);
        let params = SurfaceParams::new(
            vertices.len(),
            across * SURFACE_WG_SIZE,
            floats,
            derivatives.order(),
            normals,
        );
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let uniform = init(
            "surface params",
            bytemuck::bytes_of(&params),
            wgpu::BufferUsages::UNIFORM,
        );
        // Empty tables still need a binding of at least one element.
        let patches = init(
            "patches",
            bytemuck::cast_slice(&nonempty(&packed.patches)),
            storage,
        );
        let coeffs = init(
            "patch coeffs",
            bytemuck::cast_slice(&nonempty(&packed.coeffs)),
            storage,
        );
        let vertex_buffer = init("vertices", bytemuck::cast_slice(vertices), storage);
        let bytes = (planes * floats * 4).max(4) as u64;
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("surface samples"),
            size: bytes,
            usage: storage | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let download = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("surface download"),
            size: bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let has_timestamps = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let stamps = (timed && has_timestamps).then(|| Timestamps::new(device, 1));
        let mut encoder = device.create_command_encoder(&Default::default());
        let resources = [&uniform, &patches, &coeffs, &vertex_buffer, &output]
            .iter()
            .map(|b| b.as_entire_binding())
            .collect();
        pipeline.record(
            device,
            &mut encoder,
            "surfaces",
            resources,
            (across, rows),
            stamps.as_ref().map(|s| s.writes(0)),
        );
        encoder.copy_buffer_to_buffer(&output, 0, &download, 0, bytes);
        if let Some(stamps) = &stamps {
            stamps.resolve(&mut encoder);
        }
        let submitted = std::time::Instant::now();
        self.queue.submit([encoder.finish()]);
        crate::gpu::readback::map_read(device, &download, |bytes| {
            consume(&bytemuck::cast_slice::<u8, f32>(bytes)[..planes * floats]);
        })?;
        Ok(match (&stamps, timed) {
            (Some(stamps), _) => stamps.read(device, self.queue.get_timestamp_period())?,
            (None, true) => submitted.elapsed().as_secs_f64(),
            (None, false) => 0.0,
        })
    }
}

/// What one dispatch may hold so that every binding it makes fits the device's storage-binding
/// limit: the vertex records (16 bytes each) and each output plane (`floats` values).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct DispatchBudget {
    /// Floats per output plane.
    pub floats: usize,
    /// Vertex records.
    pub vertices: usize,
}

impl DispatchBudget {
    /// The budget under a binding limit of `binding` bytes with `planes` output planes (the
    /// output buffer holds every plane, so each gets a share of it).
    pub(crate) fn for_binding(binding: u64, planes: usize) -> Self {
        let binding = usize::try_from(binding).unwrap_or(usize::MAX);
        Self {
            floats: (binding / 4 / planes).clamp(1, 1 << 26),
            vertices: (binding / std::mem::size_of::<GpuVertex>()).clamp(1, 1 << 26),
        }
    }
}

/// Takes a dispatch's planes.
pub(crate) type Consume<'a> = &'a mut dyn FnMut(&[f32]);

/// Runs one dispatch: its packed patches, its vertices and the floats of each plane, then
/// hands its planes (`floats` apart) to the last argument.
pub(crate) type Dispatch<'a> = dyn FnMut(&PackedPatches, &[GpuVertex], usize, &mut dyn FnMut(&[f32])) -> Result<(), GpuError>
    + 'a;

/// Packs `surfaces` (whose patches fit one binding), runs their vertices through `dispatch`
/// in dispatches within `budget` (floats per plane and vertex records), and copies each dispatch's planes
/// straight into the surfaces' samples (made by [`SurfaceSamples::for_plan`]).
pub(crate) fn evaluate_group_with(
    surfaces: &[(&PatchTable, &SurfacePlan)],
    derivatives: Derivatives,
    normals: bool,
    budget: DispatchBudget,
    dispatch: &mut Dispatch<'_>,
) -> Result<Vec<SurfaceSamples<f32>>, GpuError> {
    let used: Vec<(&PatchTable, Range<usize>)> = surfaces
        .iter()
        .map(|(t, plan)| (*t, used_patches(plan)))
        .collect();
    let packed = PackedPatches::of_ranges(&used, normals);
    let mut out: Vec<SurfaceSamples<f32>> = surfaces
        .iter()
        .map(|(table, plan)| SurfaceSamples::for_plan(table, plan, derivatives, normals))
        .collect();
    // A dispatch's vertices and the runs of them it holds: (surface, first vertex, count).
    let mut chunk: Vec<GpuVertex> = Vec::new();
    let mut pieces: Vec<(usize, usize, usize)> = Vec::new();
    let mut flush = |chunk: &mut Vec<GpuVertex>,
                     pieces: &mut Vec<(usize, usize, usize)>,
                     floats: usize,
                     out: &mut [SurfaceSamples<f32>]|
     -> Result<(), GpuError> {
        if chunk.is_empty() {
            return Ok(());
        }
        dispatch(&packed, chunk, floats, &mut |values| {
            let mut at = 0;
            for &(s, first, count) in pieces.iter() {
                let samples = &mut out[s];
                // Every plane holds `dim` floats a vertex (normals are asked of 3-D only).
                let width = count * samples.dim;
                let target = first * samples.dim..first * samples.dim + width;
                for (p, plane) in samples.value_planes().into_iter().enumerate() {
                    let from = p * floats + at;
                    plane[target.clone()].copy_from_slice(&values[from..from + width]);
                }
                at += width;
            }
        })?;
        chunk.clear();
        pieces.clear();
        Ok(())
    };
    let mut floats = 0usize;
    for (s, (table, plan)) in surfaces.iter().enumerate() {
        let (dim, first_patch, start) = (table.dim(), packed.first_patch[s], used[s].1.start);
        for (i, vertex) in plan.vertices.iter().enumerate() {
            if floats + dim > budget.floats || chunk.len() == budget.vertices {
                flush(&mut chunk, &mut pieces, floats, &mut out)?;
                floats = 0;
            }
            match pieces.last_mut() {
                Some((piece, first, count)) if *piece == s && *first + *count == i => *count += 1,
                _ => pieces.push((s, i, 1)),
            }
            chunk.push(GpuVertex {
                patch_index: first_patch + (vertex.patch - start as u32),
                out: floats as u32,
                u: vertex.local[0] as f32,
                v: vertex.local[1] as f32,
            });
            floats += dim;
        }
    }
    flush(&mut chunk, &mut pieces, floats, &mut out)?;
    Ok(out)
}

/// The patches a plan's vertices are evaluated on, first to last.
fn used_patches(plan: &SurfacePlan) -> Range<usize> {
    let (low, high) = plan
        .vertices
        .iter()
        .fold((u32::MAX, 0), |(l, h), v| (l.min(v.patch), h.max(v.patch)));
    if low > high {
        return 0..0;
    }
    low as usize..high as usize + 1
}

/// `items`, or one default element where there is none (a binding needs at least one).
pub(crate) fn nonempty<T: Copy + Default>(items: &[T]) -> Vec<T> {
    if items.is_empty() {
        vec![T::default()]
    } else {
        items.to_vec()
    }
}
