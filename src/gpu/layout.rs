//! The buffers shared with `shaders/eval.wgsl`: Pod twins of its structs, and `pack`, which
//! turns an [`EvalJob`] into segment, coefficient and run tables split into dispatches.
//!
//! Each struct here has a twin of the same field order in the WGSL file; `tests/shader.rs`
//! compares their sizes and offsets through naga.

use std::ops::Range;

use bytemuck::{Pod, Zeroable};

use super::KernelShape;
use crate::error::GpuError;
use crate::job::EvalJob;
use crate::sampling::SamplePlan;

/// Coefficient terms per segment: a, b, c, d_lo, d_hi.
pub const TERMS: usize = 5;

/// Vec4s in the coefficient block of a segment in `dim` dimensions: the floats
/// `a[0..dim], b[0..dim], c[0..dim], d_lo[0..dim], d_hi[0..dim], 1/Δ`, end to end, padded to a
/// whole vec4 (a 3-D segment's 16 floats are 4 vec4s).
///
/// Blocks are packed without per-term padding because a CPU adapter pays for every float a
/// shader loads from a storage buffer: lavapipe 22.3 loads each one through its own loop over
/// the SIMD lanes.
#[must_use]
pub const fn block_vec4s(dim: usize) -> usize {
    (TERMS * dim + 1).div_ceil(4)
}

/// Per-dispatch uniforms. WGSL twin: `Params` in `shaders/eval.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct Params {
    /// Runs in this dispatch.
    pub run_count: u32,
    /// Invocations per row of the 2-D dispatch.
    pub row_width: u32,
    /// Floats per output plane (a multiple of 4).
    pub plane_stride: u32,
    /// 0, 1 or 2.
    pub derivatives: u32,
    /// Float where this dispatch's output starts in the bound buffer (a multiple of 4).
    pub out_base: u32,
    /// WGSL uniform structs are padded to 16 bytes.
    pub _padding: [u32; 3],
}

/// One segment. WGSL twin: `Segment` in `shaders/eval.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct GpuSegment {
    /// Index of the first vec4 of its coefficient block (see [`block_vec4s`]).
    pub coeff_offset: u32,
    /// Coordinates per point.
    pub dim: u32,
}

/// A run: `count` samples at u = u0 + j·du of each of `segments` consecutive segments, one
/// segment's block after the other. WGSL twin: `Run`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub struct Run {
    /// Index into the segment table of its first segment.
    pub segment: u32,
    /// Consecutive segments (of one curve) it covers.
    pub segments: u32,
    /// The float where its first sample's values go, relative to the dispatch's output.
    pub out_offset: u32,
    /// Samples per segment.
    pub count: u32,
    /// How the run is written: [`MODE_SCALAR`], [`MODE_VECTOR`] or [`MODE_EXPLICIT`].
    pub mode: u32,
    /// u of the first sample.
    pub u0: f32,
    /// u step between samples.
    pub du: f32,
    /// For an explicit run, where its samples' places start in [`Packed::locs`].
    pub first_loc: u32,
}

/// [`Run::mode`]: each float written on its own (any dimension and alignment).
pub const MODE_SCALAR: u32 = 0;
/// [`Run::mode`]: 4 samples at a time as `dim` whole vec4s (dim <= 4; out_offset, count and
/// count·dim multiples of 4).
pub const MODE_VECTOR: u32 = 1;
/// [`Run::mode`]: `count` samples, each at its own segment and u from [`Packed::locs`]
/// (explicit t; `segment`, `segments`, `u0` and `du` are unused).
pub const MODE_EXPLICIT: u32 = 2;

/// One explicitly placed sample. WGSL twin: `Loc` in `shaders/eval.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub struct GpuLoc {
    /// Index into the segment table.
    pub segment: u32,
    /// Local parameter, located in f64 on the host.
    pub u: f32,
}

/// One dispatch: a range of runs whose output is the float range `values` of each plane.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Batch {
    /// Indices into [`Packed::runs`].
    pub runs: Range<usize>,
    /// Floats (of each output plane) this dispatch writes; starts at a multiple of 4.
    pub values: Range<usize>,
}

/// How much one dispatch may hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BatchLimits {
    /// Output floats per plane.
    pub values: usize,
    /// Runs.
    pub runs: usize,
}

/// A job as the kernel reads it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Packed {
    /// Every curve's segments, curve after curve.
    pub segments: Vec<GpuSegment>,
    /// Per segment, its coefficient block of [`block_vec4s`]`(dim)` vec4s.
    pub coeffs: Vec<[f32; 4]>,
    /// Runs; `out_offset` is relative to the start of the run's batch.
    pub runs: Vec<Run>,
    /// The places of explicitly sampled curves' samples.
    pub locs: Vec<GpuLoc>,
    /// Dispatches, in output order.
    pub batches: Vec<Batch>,
    /// Where each curve's samples start in the GPU output plane (a multiple of 4 floats, so
    /// that vector runs are aligned), and, last, the plane's length.
    pub curve_offsets: Vec<usize>,
}

/// Packs `job` into runs of at most `shape.run_len` samples, and cuts them into dispatches that
/// stay within `limits` (`limits.values` should hold several runs: 2 · 4 · `run_len` · 64
/// floats always suffice).
///
/// The power coefficients are rounded to f32 only here, after M·X was formed in f64; D is
/// split as d_hi = f32(D), d_lo = f32(D − d_hi), so a curve far from the origin keeps its
/// shape to f32 precision of its size, not of its distance from the origin.
///
/// # Errors
/// A coefficient, or 1/Δ, outside the f32 range ([`GpuError::OutOfRange`]).
pub fn pack(job: &EvalJob, shape: KernelShape, limits: BatchLimits) -> Result<Packed, GpuError> {
    let mut packed = Packed::default();
    let mut all_runs = Vec::new();
    let mut value_base = 0usize;
    for c in 0..job.len() {
        let (table, plan) = (job.table(c), job.plan(c));
        let dim = table.dim();
        let block_len = block_vec4s(dim);
        let first_segment = packed.segments.len() as u32;
        for s in 0..table.len() {
            let segment = table.segment(s);
            let inv_dt = (1.0 / segment.dt()) as f32;
            check_f32(c, "1/Δ of a segment", inv_dt)?;
            packed.segments.push(GpuSegment {
                coeff_offset: packed.coeffs.len() as u32,
                dim: dim as u32,
            });
            // The coordinate k of term t is float t·dim + k of the block; 1/Δ follows the
            // terms. d_hi = f32(D), d_lo = f32(D − d_hi).
            let [a, b, cc, d] = segment.power();
            let at = packed.coeffs.len();
            packed.coeffs.resize(at + block_len, [0.0; 4]);
            let block: &mut [f32] = bytemuck::cast_slice_mut(&mut packed.coeffs[at..]);
            for k in 0..dim {
                let hi = d[k] as f32;
                let values = [
                    a[k] as f32,
                    b[k] as f32,
                    cc[k] as f32,
                    (d[k] - f64::from(hi)) as f32,
                    hi,
                ];
                for (t, v) in values.into_iter().enumerate() {
                    block[t * dim + k] = v;
                }
            }
            block[TERMS * dim] = inv_dt;
            if block.iter().any(|v| !v.is_finite()) {
                return Err(GpuError::OutOfRange {
                    curve: c,
                    what: "a coordinate or power coefficient",
                });
            }
        }
        push_runs(
            &mut all_runs,
            &mut packed.locs,
            plan,
            first_segment,
            value_base,
            dim,
            shape,
        );
        value_base = (value_base + plan.len() * dim).next_multiple_of(4);
    }
    packed.curve_offsets = curve_offsets(job);
    debug_assert_eq!(packed.curve_offsets[job.len()], value_base);
    cut_batches(&mut packed, &all_runs, limits);
    Ok(packed)
}

/// Where each curve's samples start in the GPU's output plane: each at a multiple of 4 floats
/// (so that vector runs are aligned), and, last, the plane's length.
#[must_use]
pub fn curve_offsets(job: &EvalJob) -> Vec<usize> {
    let mut offsets = vec![0];
    for c in 0..job.len() {
        let end = offsets[c] + job.plan(c).len() * job.table(c).dim();
        offsets.push(end.next_multiple_of(4));
    }
    offsets
}

/// Cuts the runs (with absolute float offsets) into dispatches within `limits`, each starting
/// at an aligned run, and makes `out_offset` relative to its dispatch's first float.
fn cut_batches(packed: &mut Packed, all_runs: &[(Run, usize, usize)], limits: BatchLimits) {
    let mut start = 0;
    while start < all_runs.len() {
        let first_value = all_runs[start].1;
        debug_assert_eq!(first_value % 4, 0, "dispatches start at aligned runs");
        // Extend to the last run that fits; then back off to just before an aligned run.
        let mut end = start + 1;
        while end < all_runs.len()
            && end - start < limits.runs
            && all_runs[end].2 - first_value <= limits.values
        {
            end += 1;
        }
        if end < all_runs.len() {
            match (start + 1..=end)
                .rev()
                .find(|&i| all_runs[i].1.is_multiple_of(4))
            {
                Some(aligned) => end = aligned,
                // Only a head run begins unaligned, and the run after it is aligned.
                None => {
                    while end < all_runs.len() && !all_runs[end].1.is_multiple_of(4) {
                        end += 1;
                    }
                }
            }
        }
        for (run, begin, _) in &all_runs[start..end] {
            packed.runs.push(Run {
                out_offset: (begin - first_value) as u32,
                ..*run
            });
        }
        packed.batches.push(Batch {
            runs: start..end,
            values: first_value..all_runs[end - 1].2,
        });
        start = end;
    }
}

/// Appends one curve's runs as (run, first float, end float) with absolute float offsets.
///
/// Each chunk of at most `run_len` samples of a segment is split into a head of fewer than 4
/// samples, after which the floats start at a multiple of 4, then (for dim <= 4) a body of
/// whole groups of 4 samples written as vec4s, then a tail.
fn push_runs(
    runs: &mut Vec<(Run, usize, usize)>,
    locs: &mut Vec<GpuLoc>,
    plan: &SamplePlan,
    first_segment: u32,
    value_base: usize,
    dim: usize,
    shape: KernelShape,
) {
    let run_len = shape.run_len;
    if let SamplePlan::At(places) = plan {
        // Explicit t: runs of up to run_len samples, each with its own segment and u.
        for (c, chunk) in places.chunks(run_len as usize).enumerate() {
            let begin = value_base + c * run_len as usize * dim;
            let run = Run {
                segment: 0,
                segments: 1,
                out_offset: 0,
                count: chunk.len() as u32,
                mode: MODE_EXPLICIT,
                u0: 0.0,
                du: 0.0,
                first_loc: locs.len() as u32,
            };
            locs.extend(chunk.iter().map(|l| GpuLoc {
                segment: first_segment + l.segment as u32,
                u: l.u as f32,
            }));
            runs.push((run, begin, begin + chunk.len() * dim));
        }
        return;
    }
    if let SamplePlan::PerSegment { k, knots, closing } = plan {
        let (segments, k) = (knots.len() - 1, *k);
        // Short segments whose blocks all stay vec4-aligned share runs, several segments
        // each, so that one looping invocation writes up to `run_len` samples.
        let per_run = (run_len / k) as usize;
        if shape.lanes == 1
            && dim <= 4
            && k % 4 == 0
            && per_run >= 2
            && value_base.is_multiple_of(4)
        {
            let mut s = 0;
            while s < segments {
                let n = per_run.min(segments - s);
                let begin = value_base + s * k as usize * dim;
                let run = Run {
                    segment: first_segment + s as u32,
                    segments: n as u32,
                    out_offset: 0,
                    count: k,
                    mode: MODE_VECTOR,
                    u0: 0.0,
                    du: (1.0 / f64::from(k)) as f32,
                    first_loc: 0,
                };
                runs.push((run, begin, begin + n * k as usize * dim));
                s += n;
            }
            if !closing {
                return;
            }
            // The final point, u = 1 on the last segment, on its own.
            let begin = value_base + segments * k as usize * dim;
            let run = Run {
                segment: first_segment + segments as u32 - 1,
                segments: 1,
                out_offset: 0,
                count: 1,
                mode: MODE_SCALAR,
                u0: 1.0,
                du: 0.0,
                first_loc: 0,
            };
            runs.push((run, begin, begin + dim));
            return;
        }
    }
    let mut push = |segment: usize, sample: usize, count: u32, u0: f64, du: f64| {
        let begin = value_base + sample * dim;
        let head = (0..4u32.min(count + 1))
            .find(|&j| (begin + j as usize * dim).is_multiple_of(4))
            .unwrap_or(count);
        let body = if dim <= 4 { (count - head) / 4 * 4 } else { 0 };
        let pieces = [
            (0, head, MODE_SCALAR),
            (head, body, MODE_VECTOR),
            (head + body, count - head - body, MODE_SCALAR),
        ];
        for (j0, n, mode) in pieces {
            if n == 0 {
                continue;
            }
            let first = begin + j0 as usize * dim;
            let run = Run {
                segment: first_segment + segment as u32,
                segments: 1,
                out_offset: 0,
                count: n,
                mode,
                u0: (u0 + f64::from(j0) * du) as f32,
                du: du as f32,
                first_loc: 0,
            };
            runs.push((run, first, first + n as usize * dim));
        }
    };
    match plan {
        SamplePlan::PerSegment { k, knots, closing } => {
            let segments = knots.len() - 1;
            let k = *k;
            for s in 0..segments {
                for j0 in (0..k).step_by(run_len as usize) {
                    let count = run_len.min(k - j0);
                    let sample = s * k as usize + j0 as usize;
                    push(
                        s,
                        sample,
                        count,
                        f64::from(j0) / f64::from(k),
                        1.0 / f64::from(k),
                    );
                }
            }
            if *closing {
                push(segments - 1, segments * k as usize, 1, 1.0, 0.0);
            }
        }
        // Explicit plans returned above.
        SamplePlan::At(_) => {}
    }
}

fn check_f32(curve: usize, what: &'static str, v: f32) -> Result<(), GpuError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(GpuError::OutOfRange { curve, what })
    }
}
