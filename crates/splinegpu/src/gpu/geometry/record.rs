//! The renderer path for tubes, ribbons and strokes: a [`GeometryRecording`] keeps a job's
//! packed curves on the device and records the kernel into a renderer's command encoder,
//! writing each vertex (position, then unit normal: 6 f32, a 24-byte stride) straight into the
//! renderer's vertex buffer; the triangles go into its index buffer once
//! ([`GeometryRecording::indices`]). Moving curves are refitted on the host
//! ([`GeometryJob::refit`]) and their tables (a stroke's vertex offsets too) uploaded in place
//! ([`GeometryRecording::refit`]): nothing is allocated or read back per frame.

use wgpu::util::DeviceExt;

use crate::error::{GpuError, InputError};
use crate::geometry::GeometryJob;
use crate::geometry::job::KernelPlan;
use crate::geometry::stroke::StrokeTopology;
use crate::gpu::GpuContext;
use crate::gpu::geometry::abi::VERTEX_FLOATS;
use crate::gpu::geometry::dispatch::Launch;
use crate::gpu::geometry::pack::PackedGeometry;
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

/// A job's tubes, ribbons and strokes kept on the device for recording, frame after frame (see the
/// module docs).
#[derive(Debug)]
pub struct GeometryRecording {
    layout: GeometryOutputLayout,
    params: wgpu::Buffer,
    curves: wgpu::Buffer,
    blocks: wgpu::Buffer,
    sections: wgpu::Buffer,
    stroke_vertices: wgpu::Buffer,
    indices: Vec<u32>,
    launch: Launch,
    /// The packed tables' lengths, which a refit must keep.
    sizes: [usize; 4],
    /// Every stroke's pieces' topologies, in order: a refit must keep them (the indices
    /// were made from them).
    strokes: Vec<StrokeTopology>,
}

/// `job`'s curves packed for the kernel, and its strokes' topologies.
fn packed(job: &GeometryJob) -> Result<(PackedGeometry, Vec<StrokeTopology>), GpuError> {
    let plans: Vec<(usize, KernelPlan<'_>)> =
        (0..job.len()).map(|c| (c, job.kernel_plan(c))).collect();
    let strokes = plans
        .iter()
        .flat_map(|(_, p)| p.stroke_topology())
        .collect();
    Ok((PackedGeometry::new(&plans)?, strokes))
}

impl PackedGeometry {
    /// The lengths of the packed tables (curves, blocks, sections, stroke vertices).
    fn sizes(&self) -> [usize; 4] {
        [
            self.curves.len(),
            self.blocks.len(),
            self.sections.len(),
            self.stroke_vertices.len(),
        ]
    }
}

impl GpuContext {
    /// A recording of `job`'s meshes, its curves packed and uploaded once.
    ///
    /// # Errors
    /// [`GpuError::OutOfRange`] for coefficients beyond f32, [`GpuError::TooLarge`] when a
    /// table or the vertices exceed one storage binding.
    pub fn geometry_recording(&self, job: &GeometryJob) -> Result<GeometryRecording, GpuError> {
        let (packed, strokes) = packed(job)?;
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
            (
                "geometry stroke vertices",
                std::mem::size_of_val(&packed.stroke_vertices[..]),
            ),
        ] {
            if size as u64 > limit {
                return Err(GpuError::TooLarge {
                    table,
                    bytes: size as u64,
                    limit,
                });
            }
        }
        let launch = Launch::new(&self.device, &packed);
        let meshes_triangles = job.triangle_count() as usize;
        let mut indices = Vec::with_capacity(3 * meshes_triangles);
        let mut triangles = vec![[0u32; 3]; meshes_triangles];
        let mut t = vec![0.0; job.vertex_count() as usize];
        for c in 0..job.len() {
            let (v, f) = (
                range(job.vertex_offsets(), c),
                range(job.triangle_offsets(), c),
            );
            job.topology(c, &mut t[v.clone()], &mut triangles[f.clone()]);
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
                bytemuck::bytes_of(&launch.params),
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
            stroke_vertices: init(
                "geometry stroke vertices",
                bytemuck::cast_slice(&nonempty(&packed.stroke_vertices)),
                storage,
            ),
            indices,
            launch,
            sizes: packed.sizes(),
            strokes,
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
    /// CPU's: for the renderer's index buffer, written once. (A stroke's triangles are turned
    /// by its positions when the recording was made; a refit keeps them.)
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
    /// another number of segments or kind), or a stroke whose joins or caps changed (its
    /// triangles with them), naming "job"; the recording is then unchanged.
    pub fn refit(&mut self, gpu: &GpuContext, job: &GeometryJob) -> Result<(), InputError> {
        let (packed, strokes) = packed(job).map_err(|e| InputError::field("job", e.to_string()))?;
        let sizes = packed.sizes();
        if sizes != self.sizes {
            return Err(InputError::field(
                "job",
                format!(
                    "packs {sizes:?} (curves, blocks, sections, stroke vertices) where the \
                     recording holds {:?}",
                    self.sizes
                ),
            ));
        }
        if let Some(k) = (0..strokes.len()).find(|&k| strokes[k] != self.strokes[k]) {
            return Err(InputError::field(
                "job",
                format!(
                    "stroke piece {k} has other joins or caps than when recorded ({:?}, was \
                     {:?}): its triangles changed, make the recording again",
                    strokes[k], self.strokes[k]
                ),
            ));
        }
        for (buffer, bytes) in [
            (&self.curves, bytemuck::cast_slice::<_, u8>(&packed.curves)),
            (&self.blocks, bytemuck::cast_slice(&packed.blocks)),
            (&self.sections, bytemuck::cast_slice(&packed.sections)),
            (
                &self.stroke_vertices,
                bytemuck::cast_slice(&packed.stroke_vertices),
            ),
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
        let resources = [
            self.params.as_entire_binding(),
            self.curves.as_entire_binding(),
            self.blocks.as_entire_binding(),
            self.sections.as_entire_binding(),
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: target,
                offset,
                size: std::num::NonZeroU64::new(needed),
            }),
            self.stroke_vertices.as_entire_binding(),
        ];
        gpu.record_geometry(encoder, "geometry recording", &resources, &self.launch);
        Ok(())
    }
}
