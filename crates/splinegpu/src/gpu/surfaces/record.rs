//! The renderer path for surfaces: a [`SurfaceRecording`] keeps a set of surfaces' plans and
//! patches on the device, records their evaluation into a renderer's command encoder, writing
//! positions and unit normals straight into the renderer's vertex buffer and the triangles into
//! its index buffer (nothing is read back), and takes new patches each frame
//! ([`SurfaceRecording::refit`]) without touching the plans: a moving net costs its fit and
//! one upload of its coefficients.

use wgpu::util::DeviceExt;

use crate::error::{GpuError, InputError};
use crate::surface::{PatchTable, SurfaceChunk, SurfaceJob, SurfacePlan};

use crate::gpu::GpuContext;
use crate::gpu::kernel::workgroup_grid;
use crate::gpu::surfaces::abi::{GpuVertex, SURFACE_WG_SIZE, SurfaceParams};
use crate::gpu::surfaces::pack::PackedPatches;

/// Where a recording writes: byte offsets from the target's offset, and each surface's first
/// vertex and first index. Positions are `dim` f32 per vertex, then (3-D) normals, 3 f32 per
/// vertex; indices are u32, numbered over all surfaces' vertices (one draw call draws all).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SurfaceOutputLayout {
    /// Byte offset of the positions.
    pub positions: u64,
    /// Byte offset of the normals, when recorded.
    pub normals: Option<u64>,
    /// Bytes the vertex data take.
    pub bytes: u64,
    /// Each surface's first vertex, and the total at the end.
    pub vertex_starts: Vec<u32>,
    /// Each surface's first index, and the total at the end.
    pub index_starts: Vec<u32>,
}

/// Surfaces kept on the device for recording, frame after frame (see the module docs).
#[derive(Debug)]
pub struct SurfaceRecording {
    layout: SurfaceOutputLayout,
    params: wgpu::Buffer,
    patches: wgpu::Buffer,
    coeffs: wgpu::Buffer,
    vertices: wgpu::Buffer,
    indices: Vec<u32>,
    vertex_count: u32,
    /// (patches, dim, rational) of each table, which a refit must keep.
    shapes: Vec<(usize, usize, bool)>,
    coeff_floats: usize,
    /// Whether the patches carry their normal nets.
    normals: bool,
}

impl GpuContext {
    /// A recording of the surfaces of `job` (positions, and unit normals when the job forms
    /// them; derivatives are not recorded), their plans and patches uploaded once.
    ///
    /// # Errors
    /// [`GpuError::TooLarge`] when the patches, the vertex data or the vertex records (16
    /// bytes each) exceed one storage binding.
    pub fn surface_recording(&self, job: &SurfaceJob) -> Result<SurfaceRecording, GpuError> {
        let normals = job.normals();
        let whole = SurfaceChunk::whole(0..job.len());
        let planned = job.chunk_plans(&whole);
        let surfaces: Vec<(&PatchTable, &SurfacePlan)> =
            planned.iter().map(|(t, p)| (*t, p.as_ref())).collect();
        let tables: Vec<&PatchTable> = surfaces.iter().map(|(t, _)| *t).collect();
        let packed = PackedPatches::new(&tables, normals);
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let (mut vertex_starts, mut index_starts) = (vec![0u32], vec![0u32]);
        let mut floats = 0usize;
        for (s, (table, plan)) in surfaces.iter().enumerate() {
            let first = vertices.len() as u32;
            for v in &plan.vertices {
                vertices.push(GpuVertex {
                    patch_index: packed.first_patch[s] + v.patch,
                    out: floats as u32,
                    u: v.local[0] as f32,
                    v: v.local[1] as f32,
                });
                floats += table.dim();
            }
            for t in plan.triangles.as_deref().unwrap_or_default() {
                indices.extend(t.map(|i| first + i));
            }
            vertex_starts.push(vertices.len() as u32);
            index_starts.push(indices.len() as u32);
        }
        let limits = self.device.limits();
        let limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let planes = 1 + usize::from(normals);
        let bytes = (planes * floats * 4) as u64;
        for (table, size) in [
            ("patch coefficients", (packed.coeffs.len() * 4) as u64),
            ("surface vertices", bytes),
            (
                "surface vertex records",
                std::mem::size_of_val(&vertices[..]) as u64,
            ),
        ] {
            if size > limit {
                return Err(GpuError::TooLarge {
                    table,
                    bytes: size,
                    limit,
                });
            }
        }
        let (across, _) = workgroup_grid(&self.device, vertices.len() as u32, SURFACE_WG_SIZE);
        let params =
            SurfaceParams::new(vertices.len(), across * SURFACE_WG_SIZE, floats, 0, normals);
        let init = |label: &str, contents: &[u8], usage| {
            self.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage,
                })
        };
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let one = [GpuVertex::default()];
        Ok(SurfaceRecording {
            layout: SurfaceOutputLayout {
                positions: 0,
                normals: normals.then_some((floats * 4) as u64),
                bytes,
                vertex_starts,
                index_starts,
            },
            params: init(
                "surface params",
                bytemuck::bytes_of(&params),
                wgpu::BufferUsages::UNIFORM,
            ),
            patches: init("patches", bytemuck::cast_slice(&packed.patches), storage),
            coeffs: init(
                "patch coeffs",
                bytemuck::cast_slice(&packed.coeffs),
                storage,
            ),
            vertices: init(
                "vertices",
                bytemuck::cast_slice(if vertices.is_empty() { &one } else { &vertices }),
                storage,
            ),
            indices,
            vertex_count: params.vertex_count,
            shapes: tables
                .iter()
                .map(|t| (t.len(), t.dim(), t.is_rational()))
                .collect(),
            coeff_floats: packed.coeffs.len(),
            normals,
        })
    }
}

impl SurfaceRecording {
    /// Where the recording writes.
    #[must_use]
    pub fn layout(&self) -> &SurfaceOutputLayout {
        &self.layout
    }

    /// Every surface's triangles as u32 indices over all vertices (the layout's
    /// `index_starts` say whose): for the renderer's index buffer, written once.
    #[must_use]
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// New patches for the same surfaces (a moving net, refitted): uploaded in place; the
    /// plans stay.
    ///
    /// # Errors
    /// A table whose patch count, dimension or kind (rational or not) differs from the one it
    /// replaces (the plans were made for those), naming "points" and the surface.
    pub fn refit(&mut self, gpu: &GpuContext, tables: &[&PatchTable]) -> Result<(), InputError> {
        let shapes: Vec<_> = tables
            .iter()
            .map(|t| (t.len(), t.dim(), t.is_rational()))
            .collect();
        if let Some(s) =
            (0..shapes.len().max(self.shapes.len())).find(|&s| shapes.get(s) != self.shapes.get(s))
        {
            return Err(InputError::field(
                "points",
                "a refit must keep the surface's patches, dimension and weights",
            )
            .in_surface(s));
        }
        let packed = PackedPatches::new(tables, self.normals);
        debug_assert_eq!(packed.coeffs.len(), self.coeff_floats);
        gpu.queue
            .write_buffer(&self.coeffs, 0, bytemuck::cast_slice(&packed.coeffs));
        Ok(())
    }

    /// Records the evaluation into `encoder`, writing the vertex data into `target` from byte
    /// `offset` on (as [`SurfaceRecording::layout`] lays it out); the caller submits.
    ///
    /// # Errors
    /// [`GpuError::Target`] as the curve path reports it: a target without `STORAGE` usage, an
    /// offset not a multiple of the device's storage-offset alignment, or too small a target.
    pub fn record_into(
        &self,
        gpu: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Buffer,
        offset: u64,
    ) -> Result<(), GpuError> {
        let needed = self.layout.bytes.max(4);
        gpu.check_target(target, offset, needed)?;
        if self.vertex_count == 0 {
            return Ok(());
        }
        let resources = vec![
            self.params.as_entire_binding(),
            self.patches.as_entire_binding(),
            self.coeffs.as_entire_binding(),
            self.vertices.as_entire_binding(),
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: target,
                offset,
                size: std::num::NonZeroU64::new(needed),
            }),
        ];
        let grid = workgroup_grid(&gpu.device, self.vertex_count, SURFACE_WG_SIZE);
        gpu.surface_pipeline().record(
            &gpu.device,
            encoder,
            "surface recording",
            resources,
            grid,
            None,
        );
        Ok(())
    }
}
