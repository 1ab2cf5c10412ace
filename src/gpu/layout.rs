//! The buffers shared with `shaders/eval.wgsl`: Pod twins of its structs, and `pack`, which
//! turns an [`EvalJob`] into segment, coefficient and run tables split into dispatches.
//!
//! Each struct here has a twin of the same field order in the WGSL file; `tests/shader.rs`
//! compares their sizes and offsets through naga.

use std::ops::Range;

use bytemuck::{Pod, Zeroable};

use crate::error::GpuError;
use crate::job::EvalJob;
use crate::sampling::SamplePlan;

/// f32 values per coordinate of a segment: a, b, c, d_lo, d_hi.
pub const COEFFS_PER_COORD: usize = 5;

/// Per-dispatch uniforms. WGSL twin: `Params` in `shaders/eval.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Zeroable, Pod)]
#[repr(C)]
pub struct Params {
    /// Runs in this dispatch.
    pub run_count: u32,
    /// Invocations per row of the 2-D dispatch.
    pub row_width: u32,
    /// Values per output plane.
    pub plane_stride: u32,
    /// 0, 1 or 2.
    pub derivatives: u32,
}

/// One segment. WGSL twin: `Segment` in `shaders/eval.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub struct GpuSegment {
    /// Index of its first coefficient in the coefficient table.
    pub coeff_offset: u32,
    /// Coordinates per point.
    pub dim: u32,
    /// 1 / Δ, for the t-derivatives.
    pub inv_dt: f32,
}

/// A run of samples of one segment at u = u0 + j·du, j < count. WGSL twin: `Run`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub struct Run {
    /// Index into the segment table.
    pub segment: u32,
    /// Where its first sample's values go, relative to the dispatch's output.
    pub out_offset: u32,
    /// Number of samples.
    pub count: u32,
    /// u of the first sample.
    pub u0: f32,
    /// u step between samples.
    pub du: f32,
}

/// One dispatch: a range of runs whose output is the value range `values` of each plane.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Batch {
    /// Indices into [`Packed::runs`].
    pub runs: Range<usize>,
    /// Values (of each output plane) this dispatch writes.
    pub values: Range<usize>,
}

/// A job as the kernel reads it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Packed {
    /// Every curve's segments, curve after curve.
    pub segments: Vec<GpuSegment>,
    /// [a, b, c, d_lo, d_hi] per coordinate per segment.
    pub coeffs: Vec<f32>,
    /// Runs; `out_offset` is relative to the start of the run's batch.
    pub runs: Vec<Run>,
    /// Dispatches, in output order.
    pub batches: Vec<Batch>,
}

/// How much one dispatch may hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BatchLimits {
    /// Output values per plane.
    pub values: usize,
    /// Runs.
    pub runs: usize,
}

/// Packs `job` into runs of at most `run_len` samples, and cuts them into dispatches that stay
/// within `limits`.
///
/// The power coefficients are rounded to f32 only here, after M·X was formed in f64; D is
/// split as d_hi = f32(D), d_lo = f32(D − d_hi), so a curve far from the origin keeps its
/// shape to f32 precision of its size, not of its distance from the origin.
///
/// # Errors
/// A coefficient, or 1/Δ, outside the f32 range ([`GpuError::OutOfRange`]).
pub fn pack(job: &EvalJob, run_len: u32, limits: BatchLimits) -> Result<Packed, GpuError> {
    let mut packed = Packed::default();
    let mut all_runs = Vec::new();
    let mut value_base = 0usize;
    for c in 0..job.len() {
        let (table, plan) = (job.table(c), job.plan(c));
        let dim = table.dim();
        let first_segment = packed.segments.len() as u32;
        for s in 0..table.len() {
            let segment = table.segment(s);
            let inv_dt = (1.0 / segment.dt()) as f32;
            check_f32(c, "1/Δ of a segment", inv_dt)?;
            packed.segments.push(GpuSegment {
                coeff_offset: packed.coeffs.len() as u32,
                dim: dim as u32,
                inv_dt,
            });
            let [a, b, cc, d] = segment.power();
            for k in 0..dim {
                let d_hi = d[k] as f32;
                let values = [
                    a[k] as f32,
                    b[k] as f32,
                    cc[k] as f32,
                    (d[k] - f64::from(d_hi)) as f32,
                    d_hi,
                ];
                for v in values {
                    check_f32(c, "a coordinate or power coefficient", v)?;
                }
                packed.coeffs.extend_from_slice(&values);
            }
        }
        push_runs(&mut all_runs, plan, first_segment, value_base, dim, run_len);
        value_base += plan.len() * dim;
    }
    // Cut into dispatches; out_offset becomes relative to the dispatch's first value.
    let mut start = 0;
    while start < all_runs.len() {
        let first_value = all_runs[start].1;
        let mut end = start;
        while end < all_runs.len()
            && end - start < limits.runs
            && all_runs[end].2 - first_value <= limits.values
        {
            end += 1;
        }
        let end = end.max(start + 1);
        let last_value = all_runs[end - 1].2;
        for (run, begin, _) in &all_runs[start..end] {
            packed.runs.push(Run {
                out_offset: (begin - first_value) as u32,
                ..*run
            });
        }
        packed.batches.push(Batch {
            runs: start..end,
            values: first_value..last_value,
        });
        start = end;
    }
    Ok(packed)
}

/// Appends one curve's runs as (run, first value, end value) with absolute value offsets.
fn push_runs(
    runs: &mut Vec<(Run, usize, usize)>,
    plan: &SamplePlan,
    first_segment: u32,
    value_base: usize,
    dim: usize,
    run_len: u32,
) {
    let mut push = |segment: usize, sample: usize, count: u32, u0: f64, du: f64| {
        let begin = value_base + sample * dim;
        let run = Run {
            segment: first_segment + segment as u32,
            out_offset: 0,
            count,
            u0: u0 as f32,
            du: du as f32,
        };
        runs.push((run, begin, begin + count as usize * dim));
    };
    match plan {
        SamplePlan::PerSegment { k, knots } => {
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
            push(segments - 1, segments * k as usize, 1, 1.0, 0.0);
        }
        SamplePlan::At(locs) => {
            for (i, loc) in locs.iter().enumerate() {
                push(loc.segment, i, 1, loc.u, 0.0);
            }
        }
    }
}

fn check_f32(curve: usize, what: &'static str, v: f32) -> Result<(), GpuError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(GpuError::OutOfRange { curve, what })
    }
}
