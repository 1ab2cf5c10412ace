//! The surface kernel's ABI (`shaders/surface.wgsl`): its source, its workgroup size and the
//! Pod twins of its structs, each named as its WGSL struct (checked against naga's layout by
//! `gpu::abi_tests`).

use bytemuck::{Pod, Zeroable};

/// `shaders/surface.wgsl`.
pub(crate) const SURFACE_WGSL: &str = include_str!("../../../shaders/surface.wgsl");

/// The kernel's workgroup size; `const WG_SIZE` in `shaders/surface.wgsl` (checked by a test).
pub(crate) const SURFACE_WG_SIZE: u32 = 64;

/// The kernel's bindings, in order: the uniform, then patches, coefficients, vertices (read)
/// and the output (read-write).
pub(crate) const SURFACE_BINDINGS: [wgpu::BufferBindingType; 5] = [
    wgpu::BufferBindingType::Uniform,
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: true },
    wgpu::BufferBindingType::Storage { read_only: false },
];

/// Per-dispatch uniforms. WGSL twin: `SurfaceParams` in `shaders/surface.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct SurfaceParams {
    pub vertex_count: u32,
    pub row_width: u32,
    pub plane_stride: u32,
    pub derivatives: u32,
    pub normals: u32,
    pub _padding: [u32; 3],
}

impl SurfaceParams {
    /// A dispatch of `vertices` vertices in rows of `row_width` invocations, `floats` floats a
    /// plane, derivatives of `order` (0, 1 or 2), normals when `normals`.
    pub(crate) fn new(
        vertices: usize,
        row_width: u32,
        floats: usize,
        order: usize,
        normals: bool,
    ) -> Self {
        SurfaceParams {
            vertex_count: vertices as u32,
            row_width,
            plane_stride: floats as u32,
            derivatives: order as u32,
            normals: u32::from(normals),
            _padding: [0; 3],
        }
    }
}

/// One patch. WGSL twin: `GpuPatch`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GpuPatch {
    pub coeff_offset: u32,
    pub dim: u32,
    pub rational: u32,
    pub normal_offset: u32,
    pub inv_du: f32,
    pub inv_dv: f32,
    pub _padding1: [u32; 2],
}

/// One vertex. WGSL twin: `GpuVertex`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GpuVertex {
    pub patch_index: u32,
    pub out: u32,
    pub u: f32,
    pub v: f32,
}
