//! The kernel's ABI: what the Rust side shares with `shaders/eval.wgsl`.
//!
//! Each Pod struct here has a twin of the same field order in the WGSL file, and [`BINDINGS`]
//! lists the kernel's bindings in order; the tests (`abi_tests.rs`) parse the shader with naga
//! and compare sizes, offsets, binding types and the shared constants, so that neither side can
//! drift.

use bytemuck::{Pod, Zeroable};

/// `shaders/eval.wgsl`: evaluates runs of samples from power-form coefficients.
pub(crate) const EVAL_WGSL: &str = include_str!("../../../shaders/eval.wgsl");

/// The kernel's workgroup size; `const WG_SIZE` in `shaders/eval.wgsl` (checked by a test).
pub(crate) const WG_SIZE: u32 = 64;

/// The kernel's entry point.
pub(crate) const ENTRY_POINT: &str = "main";

/// The pipeline-overridable constant naming how many invocations share a run.
pub(crate) const LANES_CONSTANT: &str = "LANES";

/// The pipeline-overridable constant naming the one run mode a pipeline evaluates.
pub(crate) const MODE_CONSTANT: &str = "MODE";

/// The pipeline-overridable constant saying whether a pipeline's segments are rational.
pub(crate) const RATIONAL_CONSTANT: &str = "RATIONAL";

/// Coefficient terms per segment: a, b, c, d_lo, d_hi.
pub(crate) const TERMS: usize = 5;

/// Vec4s in the coefficient block of a segment in `dim` dimensions: the floats
/// `a[0..dim], b[0..dim], c[0..dim], d_lo[0..dim], d_hi[0..dim], 1/Δ`, end to end, then for a
/// `rational` segment its denominator's `a, b, c, d` (see [`crate::rational`]), padded to a
/// whole vec4 (a 3-D segment's 16 floats are 4 vec4s). Only derivatives use 1/Δ: a job of
/// positions has 0 there, so that knots closer than 1/`f32::MAX` do not refuse it.
///
/// Blocks are packed without per-term padding because a CPU adapter pays for every float a
/// shader loads from a storage buffer: lavapipe 22.3 loads each one through its own loop over
/// the SIMD lanes.
#[must_use]
pub(crate) const fn block_vec4s(dim: usize, rational: bool) -> usize {
    (TERMS * dim + 1 + if rational { 4 } else { 0 }).div_ceil(4)
}

/// Per-dispatch uniforms. WGSL twin: `Params` in `shaders/eval.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct Params {
    /// Runs in this dispatch.
    pub run_count: u32,
    /// Invocations per row of the 2-D dispatch.
    pub row_width: u32,
    /// Floats per output plane (a multiple of 4).
    pub plane_stride: u32,
    /// 0, 1 or 2.
    pub derivatives: u32,
    /// Float the runs' `out_offset`s count from in the bound buffer (a multiple of 4): 0 for
    /// a buffer of the dispatch's own, [`Batch::base`] in a whole job's buffer.
    pub out_base: u32,
    /// The dispatch's first run in the bound run table (its batch's runs of one mode).
    pub first_run: u32,
    /// WGSL uniform structs are padded to 16 bytes.
    pub _padding: [u32; 2],
}

/// One segment. WGSL twin: `Segment` in `shaders/eval.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GpuSegment {
    /// Index of the first vec4 of its coefficient block (see [`block_vec4s`]).
    pub coeff_offset: u32,
    /// Coordinates per point.
    pub dim: u32,
}

/// A run: `count` samples at u = u0 + j·du of each of `segments` consecutive segments, one
/// segment's block after the other. WGSL twin: `Run`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct Run {
    /// Index into the segment table of its first segment.
    pub segment: u32,
    /// Consecutive segments (of one curve) it covers.
    pub segments: u32,
    /// The float where its first sample's values go, relative to the dispatch's output.
    pub out_offset: u32,
    /// Samples per segment.
    pub count: u32,
    /// How the run is written: [`MODE_SCALAR`], [`MODE_VECTOR`], [`MODE_EXPLICIT`] or
    /// [`MODE_ARC`]. The kernel does not read it: a batch's runs of one mode are dispatched
    /// together with the pipeline compiled for that mode ([`Batch::modes`]).
    pub mode: u32,
    /// u of the first sample.
    pub u0: f32,
    /// u step between samples.
    pub du: f32,
    /// For an explicit run, where its samples' places start in [`Packed::locs`]; for an
    /// arc-length run, where the kernel writes the places it computes there.
    pub first_loc: u32,
    /// For an arc-length run, the vec4 of [`Packed::arcs`] where its curve's table starts.
    pub arc: u32,
    /// For an arc-length run, the index of its first sample in its curve's sampling.
    pub first: u32,
}

/// [`Run::mode`]: each float written on its own (any dimension and alignment).
pub(crate) const MODE_SCALAR: u32 = 0;
/// [`Run::mode`]: 4 samples at a time as `dim` whole vec4s (dim <= 4; out_offset, count and
/// count·dim multiples of 4).
pub(crate) const MODE_VECTOR: u32 = 1;
/// [`Run::mode`]: `count` samples, each at its own segment and u from [`Packed::locs`]
/// (explicit t; `segment`, `segments`, `u0` and `du` are unused).
pub(crate) const MODE_EXPLICIT: u32 = 2;
/// [`Run::mode`]: samples `first .. first + count` of an arc-length sampling of the curve
/// whose `segments` segments start at `segment`, each placed by the kernel from the curve's
/// table at [`Run::arc`] (see `write_arc_table`) and its place written to
/// `locs[first_loc + j]` (`u0` and `du` are unused).
pub(crate) const MODE_ARC: u32 = 3;

/// [`Run::mode`]: [`MODE_SCALAR`]'s samples of a rational segment.
pub(crate) const MODE_RATIONAL_SCALAR: u32 = 4;
/// [`Run::mode`]: [`MODE_EXPLICIT`]'s samples of a rational curve.
pub(crate) const MODE_RATIONAL_EXPLICIT: u32 = 5;
/// [`Run::mode`]: [`MODE_ARC`]'s samples of a rational curve.
pub(crate) const MODE_RATIONAL_ARC: u32 = 6;
/// [`Run::mode`]: [`MODE_VECTOR`]'s samples of rational segments.
pub(crate) const MODE_RATIONAL_VECTOR: u32 = 7;

/// How many run modes there are: `MODE_SCALAR` to `MODE_RATIONAL_VECTOR`.
pub(crate) const MODES: usize = 8;

/// The kernel's `MODE` and `RATIONAL` for run mode `mode`: a rational mode is its polynomial
/// mode's code with the quotient.
#[must_use]
pub(crate) const fn kernel_mode(mode: u32) -> (u32, bool) {
    match mode {
        MODE_RATIONAL_SCALAR => (MODE_SCALAR, true),
        MODE_RATIONAL_EXPLICIT => (MODE_EXPLICIT, true),
        MODE_RATIONAL_ARC => (MODE_ARC, true),
        MODE_RATIONAL_VECTOR => (MODE_VECTOR, true),
        _ => (mode, false),
    }
}

/// The run mode for the samples of polynomial run mode `mode` on a curve that is `rational`.
#[must_use]
pub(crate) const fn mode_for(mode: u32, rational: bool) -> u32 {
    match (mode, rational) {
        (MODE_SCALAR, true) => MODE_RATIONAL_SCALAR,
        (MODE_VECTOR, true) => MODE_RATIONAL_VECTOR,
        (MODE_EXPLICIT, true) => MODE_RATIONAL_EXPLICIT,
        (MODE_ARC, true) => MODE_RATIONAL_ARC,
        _ => mode,
    }
}

/// Whether the kernel places the samples of a run of mode `mode` by arc length.
#[must_use]
pub(crate) const fn is_arc(mode: u32) -> bool {
    kernel_mode(mode).0 == MODE_ARC
}

/// One explicitly placed sample. WGSL twin: `Loc` in `shaders/eval.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct GpuLoc {
    /// Index into the segment table.
    pub segment: u32,
    /// Local parameter, located in f64 on the host.
    pub u: f32,
}

/// The bindings of `shaders/eval.wgsl`, in binding order: (buffer type, role, the least bytes
/// a binding holds: the uniform struct's size, or one element of a storage array). A test
/// checks these against the shader's declarations through naga.
pub(crate) const BINDINGS: [(wgpu::BufferBindingType, &str, u64); 8] = {
    const READ: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: true };
    [
        (
            wgpu::BufferBindingType::Uniform,
            "params",
            size_of::<Params>() as u64,
        ),
        (READ, "segments", size_of::<GpuSegment>() as u64),
        (READ, "coeffs", size_of::<[f32; 4]>() as u64),
        (READ, "runs", size_of::<Run>() as u64),
        (
            wgpu::BufferBindingType::Storage { read_only: false },
            "samples",
            size_of::<[f32; 4]>() as u64,
        ),
        // Explicit places are read, arc-length places written.
        (
            wgpu::BufferBindingType::Storage { read_only: false },
            "locs",
            size_of::<GpuLoc>() as u64,
        ),
        // The coefficients again, as floats.
        (READ, "coeff_floats", size_of::<f32>() as u64),
        (READ, "arcs", size_of::<[u32; 4]>() as u64),
    ]
};

#[cfg(test)]
#[path = "abi_tests.rs"]
mod tests;
