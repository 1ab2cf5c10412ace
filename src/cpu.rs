//! The CPU evaluators: the f64 reference (the twin of `shaders/eval.wgsl`) and a fast
//! evaluator that writes f32 or f64 into a caller's memory on every thread.
//!
//! Both use the kernel's Horner order, D + u(C + u(B + uA)), and its derivatives
//! (C + u(2B + 3uA))/Δ and (2B + 6uA)/Δ², every step in f64; the fast one rounds to its output
//! type only when it stores.

use crate::job::EvalJob;
use crate::samples::Samples;
use crate::sampling::SamplePlan;
use crate::segment::{Segment, SegmentTable};

/// Evaluates every curve of `job` in f64 on one thread, straight from the
/// [`SamplePlan`]s (sample by sample through [`SamplePlan::loc`]): the reference the GPU and
/// the fast evaluator are tested against.
#[must_use]
pub fn evaluate(job: &EvalJob) -> Samples<f64> {
    let mut samples = Samples::for_job(job);
    let order = job.derivatives().order();
    for c in 0..job.len() {
        let (table, plan) = (job.table(c), job.plan(c));
        let dim = table.dim();
        let base = samples.value_offset(c);
        let [points, d1, d2] = samples.planes_mut();
        for i in 0..plan.len() {
            let loc = plan.loc(i);
            let segment = table.segment(loc.segment);
            let at = base + i * dim..base + (i + 1) * dim;
            segment.eval(loc.u, &mut points[at.clone()]);
            if order >= 1 {
                segment.deriv(loc.u, &mut d1[at.clone()]);
            }
            if order >= 2 {
                segment.deriv2(loc.u, &mut d2[at]);
            }
        }
    }
    samples
}

/// A number type the fast evaluator writes: f64, or f32 (rounded from f64).
pub trait OutputFloat: Copy + Default + Send + Sync {
    /// `v` rounded to this type.
    fn from_f64(v: f64) -> Self;
}

impl OutputFloat for f64 {
    fn from_f64(v: f64) -> Self {
        v
    }
}

impl OutputFloat for f32 {
    fn from_f64(v: f64) -> Self {
        v as f32
    }
}

/// The machine's threads, the default for [`evaluate_into`].
#[must_use]
pub fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// Evaluates `job` into `samples` (laid out for it first, reusing its memory) on `threads`
/// threads. With `F = f64` the values equal [`evaluate`]'s exactly.
pub fn evaluate_into<F: OutputFloat>(job: &EvalJob, samples: &mut Samples<F>, threads: usize) {
    samples.prepare(job);
    let [points, d1, d2] = samples.planes_mut();
    evaluate_values_into(job, [points, d1, d2], threads);
}

/// Evaluates `job` into a caller's planes, laid out as [`Samples`] lays them out: curve after
/// curve, `dim` values per sample, positions in `planes[0]` and, when the job asks for them,
/// first and second derivatives in `planes[1]` and `planes[2]` (pass empty slices otherwise).
/// Nothing is allocated per sample; the samples are split into one contiguous range per
/// thread.
///
/// # Panics
/// If a plane the job needs is not exactly as long as the job's values.
pub fn evaluate_values_into<F: OutputFloat>(job: &EvalJob, planes: [&mut [F]; 3], threads: usize) {
    // value_offsets[c]: where curve c starts in each plane; sample_offsets likewise in samples.
    let mut sample_offsets = vec![0usize];
    let mut value_offsets = vec![0usize];
    for c in 0..job.len() {
        let n = job.plan(c).len();
        sample_offsets.push(sample_offsets[c] + n);
        value_offsets.push(value_offsets[c] + n * job.table(c).dim());
    }
    let (total, values) = (sample_offsets[job.len()], value_offsets[job.len()]);
    let order = job.derivatives().order();
    for (o, plane) in planes.iter().enumerate() {
        let expected = if order >= o { values } else { 0 };
        assert!(
            plane.len() == expected || (expected == 0 && plane.is_empty()),
            "plane {o} holds {} values, the job {expected}",
            plane.len()
        );
    }
    // The value offset of global sample i.
    let value_at = |i: usize| {
        let c = sample_offsets
            .partition_point(|&s| s <= i)
            .saturating_sub(1)
            .min(job.len().saturating_sub(1));
        value_offsets[c] + (i - sample_offsets[c]) * job.table(c).dim().max(1)
    };
    let threads = threads.clamp(1, total.max(1));
    let [mut points, mut d1, mut d2] = planes;
    std::thread::scope(|scope| {
        let mut start = 0;
        for t in 0..threads {
            let end = if t + 1 == threads {
                total
            } else {
                total * (t + 1) / threads
            };
            let (v0, v1) = (
                value_at(start).min(values),
                if end == total { values } else { value_at(end) },
            );
            let parts = [&mut points, &mut d1, &mut d2].map(|plane| take_front(plane, v1 - v0));
            let (job, sample_offsets) = (job, &sample_offsets);
            let work = move || evaluate_range(job, sample_offsets, start..end, parts);
            if t + 1 == threads {
                work();
            } else {
                scope.spawn(work);
            }
            start = end;
        }
    });
}

/// The first `n` values of `plane` (none of an empty plane), leaving the rest in `plane`.
fn take_front<'a, F>(plane: &mut &'a mut [F], n: usize) -> &'a mut [F] {
    let n = if plane.is_empty() { 0 } else { n };
    let (head, tail) = std::mem::take(plane).split_at_mut(n);
    *plane = tail;
    head
}

/// `plane[range]`, or an empty plane as it is.
fn sub<F>(plane: &mut [F], range: std::ops::Range<usize>) -> &mut [F] {
    if plane.is_empty() {
        plane
    } else {
        &mut plane[range]
    }
}

/// Evaluates global samples `range` into `out` (each plane starting at the range's first value).
fn evaluate_range<F: OutputFloat>(
    job: &EvalJob,
    sample_offsets: &[usize],
    range: std::ops::Range<usize>,
    mut out: [&mut [F]; 3],
) {
    let mut written = 0;
    let first_curve = sample_offsets
        .partition_point(|&s| s <= range.start)
        .saturating_sub(1);
    for c in first_curve..job.len() {
        let (lo, hi) = (
            sample_offsets[c].max(range.start),
            sample_offsets[c + 1].min(range.end),
        );
        if lo >= hi {
            if sample_offsets[c] >= range.end {
                break;
            }
            continue;
        }
        let (table, plan) = (job.table(c), job.plan(c));
        let values = (hi - lo) * table.dim();
        let [p, a, b] = &mut out;
        let at = written..written + values;
        let parts = [sub(p, at.clone()), sub(a, at.clone()), sub(b, at)];
        curve_range(
            table,
            plan,
            lo - sample_offsets[c]..hi - sample_offsets[c],
            parts,
        );
        written += values;
    }
}

/// Samples `range` of one curve into `out`, segment by segment with the coefficients hoisted.
fn curve_range<F: OutputFloat>(
    table: &SegmentTable,
    plan: &SamplePlan,
    range: std::ops::Range<usize>,
    out: [&mut [F]; 3],
) {
    let dim = table.dim();
    let [points, d1, d2] = out;
    match plan {
        SamplePlan::PerSegment { k, .. } => {
            let k = *k as usize;
            let segments = table.len();
            // u = j/k, divided exactly as SamplePlan::loc divides.
            let us: Vec<f64> = (0..k).map(|j| j as f64 / k as f64).collect();
            let mut i = range.start;
            while i < range.end {
                let (segment, us) = if i == segments * k {
                    (segments - 1, &[1.0][..])
                } else {
                    let j = i % k;
                    (i / k, &us[j..k.min(j + range.end - i)])
                };
                let at = (i - range.start) * dim..(i - range.start + us.len()) * dim;
                let parts = [sub(points, at.clone()), sub(d1, at.clone()), sub(d2, at)];
                segment_block(&table.segment(segment), us, parts);
                i += us.len();
            }
        }
        SamplePlan::At(locs) => {
            for i in range.clone() {
                let at = (i - range.start) * dim..(i - range.start + 1) * dim;
                let parts = [sub(points, at.clone()), sub(d1, at.clone()), sub(d2, at)];
                segment_block(&table.segment(locs[i].segment), &[locs[i].u], parts);
            }
        }
    }
}

/// One segment at the local parameters `us` into `out`, with its dimension known at compile
/// time for D <= 4 (the common cases).
fn segment_block<F: OutputFloat>(segment: &Segment<'_>, us: &[f64], out: [&mut [F]; 3]) {
    match segment.power()[0].len() {
        1 => block::<1, F>(segment, us, out),
        2 => block::<2, F>(segment, us, out),
        3 => block::<3, F>(segment, us, out),
        4 => block::<4, F>(segment, us, out),
        _ => block_any(segment, us, out),
    }
}

/// [`block_any`] for a dimension fixed at compile time. The coefficients as arrays let the
/// compiler drop the bounds checks and vectorize: measured on w1, 13.8 ms against 19 to 21 ms
/// for `block_any` inlined with a constant dimension, so the two bodies stay separate.
fn block<const D: usize, F: OutputFloat>(segment: &Segment<'_>, us: &[f64], out: [&mut [F]; 3]) {
    let arr = |v: &[f64]| -> [f64; D] { v.try_into().expect("D coordinates") };
    let [a, b, c, d] = segment.power().map(arr);
    let inv_dt = 1.0 / segment.dt();
    let [points, d1, d2] = out;
    for (&u, o) in us.iter().zip(points.chunks_exact_mut(D)) {
        for k in 0..D {
            o[k] = F::from_f64(d[k] + u * (c[k] + u * (b[k] + u * a[k])));
        }
    }
    for (&u, o) in us.iter().zip(d1.chunks_exact_mut(D)) {
        for k in 0..D {
            o[k] = F::from_f64((c[k] + u * (2.0 * b[k] + 3.0 * u * a[k])) * inv_dt);
        }
    }
    for (&u, o) in us.iter().zip(d2.chunks_exact_mut(D)) {
        for k in 0..D {
            o[k] = F::from_f64((2.0 * b[k] + 6.0 * u * a[k]) * inv_dt * inv_dt);
        }
    }
}

/// One segment of any dimension at the local parameters `us` into `out`: Horner in f64,
/// rounded to `F` on the store.
fn block_any<F: OutputFloat>(segment: &Segment<'_>, us: &[f64], out: [&mut [F]; 3]) {
    let [a, b, c, d] = segment.power();
    let dim = a.len();
    let inv_dt = 1.0 / segment.dt();
    let [points, d1, d2] = out;
    for (&u, o) in us.iter().zip(points.chunks_exact_mut(dim)) {
        for k in 0..dim {
            o[k] = F::from_f64(d[k] + u * (c[k] + u * (b[k] + u * a[k])));
        }
    }
    for (&u, o) in us.iter().zip(d1.chunks_exact_mut(dim)) {
        for k in 0..dim {
            o[k] = F::from_f64((c[k] + u * (2.0 * b[k] + 3.0 * u * a[k])) * inv_dt);
        }
    }
    for (&u, o) in us.iter().zip(d2.chunks_exact_mut(dim)) {
        for k in 0..dim {
            o[k] = F::from_f64((2.0 * b[k] + 6.0 * u * a[k]) * inv_dt * inv_dt);
        }
    }
}
