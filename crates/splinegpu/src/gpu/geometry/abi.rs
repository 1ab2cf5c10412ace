//! The geometry kernel's ABI (`shaders/geometry.wgsl`): its source, its workgroup size, its
//! bindings and the Pod twins of its structs, each named as its WGSL struct (checked against
//! naga's layout by `gpu::curves::abi_tests`).

use bytemuck::{Pod, Zeroable};

/// `shaders/geometry.wgsl`.
pub(crate) const GEOMETRY_WGSL: &str = include_str!("../../../shaders/geometry.wgsl");

/// The kernel's workgroup size; `const WG_SIZE` in `shaders/geometry.wgsl` (checked by a test).
pub(crate) const GEOMETRY_WG_SIZE: u32 = 64;

/// Floats a vertex takes in the kernel's output: its position, then its unit normal.
pub(crate) const VERTEX_FLOATS: usize = 6;

/// The kernel's bindings, in order: the uniform, then curves, blocks, sections (read), the
/// output (read-write) and the strokes' vertices (read); both entry points take them all.
pub(crate) const GEOMETRY_BINDINGS: [wgpu::BufferBindingType; 6] = [
    wgpu::BufferBindingType::Uniform,
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: false },
    wgpu::BufferBindingType::Storage { read_only: true },
];

/// Per-dispatch uniforms. WGSL twin: `GeometryParams`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GeometryParams {
    pub curve_count: u32,
    pub row_width: u32,
    pub out_base: u32,
    pub stroke_vertex_count: u32,
    pub stroke_row_width: u32,
    pub _padding0: u32,
    pub _padding1: u32,
    pub _padding2: u32,
}

/// One curve's mesh. WGSL twin: `GpuMeshCurve` (its fields' meaning there).
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GpuMeshCurve {
    pub first_block: u32,
    pub block_vec4s: u32,
    pub rational: u32,
    pub first_section: u32,
    pub sections: u32,
    pub shape: u32,
    pub sides: u32,
    pub _padding2: u32,
    pub closed: u32,
    pub first_vertex: u32,
    pub _padding0: u32,
    pub _padding1: u32,
    pub origin_hi: [f32; 4],
    pub origin_lo: [f32; 4],
    pub n0: [f32; 4],
    pub t_first: [f32; 4],
}

/// [`GpuMeshCurve::shape`] of a tube.
pub(crate) const SHAPE_TUBE: u32 = 0;
/// [`GpuMeshCurve::shape`] of a ribbon.
pub(crate) const SHAPE_RIBBON: u32 = 1;
/// [`GpuMeshCurve::shape`] of a stroke (its vertices are [`GpuStrokeVertex`]es).
pub(crate) const SHAPE_STROKE: u32 = 2;

/// One stroke vertex: C + h v at (segment, u) of its curve. WGSL twin: `GpuStrokeVertex`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GpuStrokeVertex {
    pub curve: u32,
    pub vertex: u32,
    pub segment: u32,
    pub u: f32,
    pub v: [f32; 2],
}

/// One cross-section and what is made there. WGSL twin: `GpuSection` (its fields' meaning
/// there).
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GpuSection {
    pub segment: u32,
    pub u: f32,
    pub along: f32,
    pub first_vertex: u32,
    pub cap_vertex: u32,
    pub cap_sign: i32,
    pub _padding0: u32,
    pub _padding1: u32,
}

/// [`GpuSection::first_vertex`] and `cap_vertex` where nothing is made. WGSL twin: `NONE`.
pub(crate) const NONE: u32 = u32::MAX;
