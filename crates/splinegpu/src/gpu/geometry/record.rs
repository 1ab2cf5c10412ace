//! The renderer path for tubes and ribbons: a [`GeometryRecording`] keeps a job's packed curves
//! on the device and records the kernel into a renderer's command encoder, writing each vertex
//! (position, then unit normal: 6 f32, a 24-byte stride) straight into the renderer's vertex
//! buffer; the triangles go into its index buffer once ([`GeometryRecording::indices`]).
//! Moving curves are refitted on the host ([`GeometryJob::refit`]) and their tables uploaded
//! in place ([`GeometryRecording::refit`]): nothing is allocated or read back per frame.

use wgpu::util::DeviceExt;

use crate::error::{GpuError, InputError};
use crate::geometry::{Geometry, GeometryJob};
use crate::gpu::GpuContext;
use crate::gpu::geometry::abi::{GEOMETRY_WG_SIZE, GeometryParams, VERTEX_FLOATS};
use crate::gpu::geometry::pack::PackedGeometry;
use crate::gpu::kernel::workgroup_grid;
use crate::gpu::surfaces::dispatch::nonempty;

/// Where a geometry recording writes: `stride` bytes a vertex (position x, y, z, then normal
/// x, y, z, f32), every mesh's vertices one after the other, and each mesh's first vertex and
/// first index (indices are u32 over all the meshes' vertices: one draw call draws them all).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeometryOutputLayout {
    /// Bytes a vertex: 24.
    pub stride: u64,
    /// Bytes the vertices take.
    pub bytes: u64,
    /// Each mesh's first vertex, and the total at the end.
    pub vertex_starts: Vec<u32>,
    /// Each mesh's first index, and the total at the end.
    pub index_starts: Vec<u32>,
}

/// A job's tubes and ribbons kept on the device for recording, frame after frame (see the
/// module docs).
#[derive(Debug)]
pub struct GeometryRecording {
    layout: GeometryOutputLayout,
    params: wgpu::Buffer,
    curves: wgpu::Buffer,
    blocks: wgpu::Buffer,
    sections: wgpu::Buffer,
    indices: Vec<u32>,
    curve_count: u32,
    /// The packed tables' lengths, which a refit must keep.
    sizes: [usize; 3],
}

/// `job`'s curves packed for the kernel, or the first that it does not make.
fn packed(job: &GeometryJob) -> Result<PackedGeometry, GpuError> {
    let mut plans = Vec::with_capacity(job.len());
    for c in 0..job.len() {
        match job.swept(c) {
            Some(plan) => plans.push((c, plan)),
            None => {
                let what = match job.geometry(c) {
                    Geometry::Stroke(_) => "a stroke",
                    _ => unreachable!("every tube and ribbon is swept"),
                };
                return Err(GpuError::NotRecordable { curve: c, what });
            }
        }
    }
    PackedGeometry::new(&plans)
}

impl GpuContext {
    /// A recording of `job`'s meshes, its curves packed and uploaded once.
    ///
    /// # Errors
    /// [`GpuError::NotRecordable`] for a stroke or a dashed curve, [`GpuError::OutOfRange`] for
    /// coefficients beyond f32, [`GpuError::TooLarge`] when a table or the vertices exceed one
    /// storage binding.
    pub fn geometry_recording(&self, job: &GeometryJob) -> Result<GeometryRecording, GpuError> {
        let packed = packed(job)?;
        let limits = self.device.limits();
        let limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let bytes = (packed.vertices * VERTEX_FLOATS * 4) as u64;
        for (table, size) in [
            (
                "geometry curve records",
                std::mem::size_of_val(&packed.curves[..]),
            ),
            ("geometry blocks", std::mem::size_of_val(&packed.blocks[..])),
            (
                "geometry sections",
                std::mem::size_of_val(&packed.sections[..]),
            ),
            ("geometry vertices", bytes as usize),
        ] {
            if size as u64 > limit {
                return Err(GpuError::TooLarge {
                    table,
                    bytes: size as u64,
                    limit,
                });
            }
        }
        let grid = workgroup_grid(&self.device, packed.curves.len() as u32, GEOMETRY_WG_SIZE);
        let params = GeometryParams {
            curve_count: packed.curves.len() as u32,
            row_width: grid.0 * GEOMETRY_WG_SIZE,
            out_base: 0,
            _padding0: 0,
        };
        let meshes_triangles = job.triangle_count() as usize;
        let mut indices = Vec::with_capacity(3 * meshes_triangles);
        let mut triangles = vec![[0u32; 3]; meshes_triangles];
        let mut t = vec![0.0; job.vertex_count() as usize];
        for c in 0..job.len() {
            let plan = job.swept(c).expect("checked when packed");
            let (v, f) = (
                range(job.vertex_offsets(), c),
                range(job.triangle_offsets(), c),
            );
            plan.topology(&mut t[v.clone()], &mut triangles[f.clone()]);
            let first = v.start as u32;
            indices.extend(triangles[f].iter().flatten().map(|&i| first + i));
        }
        let to_u32 = |o: &[u64]| -> Vec<u32> { o.iter().map(|&x| x as u32).collect() };
        let init = |label: &str, contents: &[u8], usage| {
            self.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage,
                })
        };
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        Ok(GeometryRecording {
            layout: GeometryOutputLayout {
                stride: (VERTEX_FLOATS * 4) as u64,
                bytes,
                vertex_starts: to_u32(job.vertex_offsets()),
                index_starts: to_u32(job.triangle_offsets())
                    .iter()
                    .map(|&f| 3 * f)
                    .collect(),
            },
            params: init(
                "geometry params",
                bytemuck::bytes_of(&params),
                wgpu::BufferUsages::UNIFORM,
            ),
            curves: init(
                "geometry curves",
                bytemuck::cast_slice(&nonempty(&packed.curves)),
                storage,
            ),
            blocks: init(
                "geometry blocks",
                bytemuck::cast_slice(&nonempty(&packed.blocks)),
                storage,
            ),
            sections: init(
                "geometry sections",
                bytemuck::cast_slice(&nonempty(&packed.sections)),
                storage,
            ),
            indices,
            curve_count: params.curve_count,
            sizes: [
                packed.curves.len(),
                packed.blocks.len(),
                packed.sections.len(),
            ],
        })
    }
}

fn range(offsets: &[u64], c: usize) -> std::ops::Range<usize> {
    offsets[c] as usize..offsets[c + 1] as usize
}

impl GeometryRecording {
    /// Where the recording writes.
    #[must_use]
    pub fn layout(&self) -> &GeometryOutputLayout {
        &self.layout
    }

    /// Every mesh's triangles as u32 indices over all vertices, counter-clockwise as the
    /// CPU's: for the renderer's index buffer, written once.
    #[must_use]
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// Uploads the tables of `job`, the job this recording was made from after
    /// [`GeometryJob::refit`] moved some of its curves (their counts kept, so the vertices and
    /// indices stay where they are).
    ///
    /// # Errors
    /// A job whose packed tables are not the recording's size (another job, or curves of
    /// another number of segments or kind), naming "job"; the recording is then unchanged.
    pub fn refit(&mut self, gpu: &GpuContext, job: &GeometryJob) -> Result<(), InputError> {
        let packed = packed(job).map_err(|e| InputError::field("job", e.to_string()))?;
        let sizes = [
            packed.curves.len(),
            packed.blocks.len(),
            packed.sections.len(),
        ];
        if sizes != self.sizes {
            return Err(InputError::field(
                "job",
                format!(
                    "packs {sizes:?} (curves, blocks, sections) where the recording holds {:?}",
                    self.sizes
                ),
            ));
        }
        for (buffer, bytes) in [
            (&self.curves, bytemuck::cast_slice::<_, u8>(&packed.curves)),
            (&self.blocks, bytemuck::cast_slice(&packed.blocks)),
            (&self.sections, bytemuck::cast_slice(&packed.sections)),
        ] {
            if !bytes.is_empty() {
                gpu.queue.write_buffer(buffer, 0, bytes);
            }
        }
        Ok(())
    }

    /// Records the kernel into `encoder`, writing the vertices into `target` from byte
    /// `offset` on (as [`GeometryRecording::layout`] lays them out); the caller submits.
    ///
    /// # Errors
    /// [`GpuError::Target`]: a target without `STORAGE` usage, an offset not a multiple of the
    /// device's storage-offset alignment, or too small a target.
    pub fn record_into(
        &self,
        gpu: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Buffer,
        offset: u64,
    ) -> Result<(), GpuError> {
        let needed = self.layout.bytes.max(4);
        gpu.check_target(target, offset, needed)?;
        if self.curve_count == 0 {
            return Ok(());
        }
        let resources = vec![
            self.params.as_entire_binding(),
            self.curves.as_entire_binding(),
            self.blocks.as_entire_binding(),
            self.sections.as_entire_binding(),
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: target,
                offset,
                size: std::num::NonZeroU64::new(needed),
            }),
        ];
        let grid = workgroup_grid(&gpu.device, self.curve_count, GEOMETRY_WG_SIZE);
        gpu.geometry_kernel().record(
            &gpu.device,
            encoder,
            "geometry recording",
            resources,
            grid,
            None,
        );
        Ok(())
    }
}
