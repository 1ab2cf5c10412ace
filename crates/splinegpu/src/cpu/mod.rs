//! The CPU evaluators: the f64 reference, and a fast evaluator that writes f32 or f64 into a
//! caller's memory on every thread.
//!
//! Both evaluate the f64 power form with the formulas of [`segment`](crate::segment)
//! (D + u(C + u(B + uA)), (C + u(2B + 3uA))/Δ, (2B + 6uA)/Δ²), every step in f64; the fast one
//! rounds to its output type only when it stores, so with f64 output the two agree bit for
//! bit. Neither is the GPU kernel's twin: the kernel reads f32 coefficients with D split in two
//! and applies 1/Δ before Horner. Its line-by-line twin is the f32 interpreter in
//! `gpu::interpret`.

pub(crate) mod at;

use crate::job::EvalJob;
use crate::job::planes::Planes;
use crate::job::samples::{SampleFloat, Samples};
use crate::parallel::{even_ranges, fan_out, take_front};
use crate::sampling::runs::Runs;
use crate::sampling::{Filling, LOC_BLOCK, Plan, SampleLoc, SamplePlan, t_at};
use crate::segment::{Segment, SegmentTable, first_derivative, position, second_derivative};
use bsplines::lanes::Isa;

/// Evaluates every curve of `job` in f64 on one thread, sample by sample through
/// [`SamplePlan::loc`]: the reference the GPU and the fast evaluator are tested against.
#[must_use]
pub fn evaluate_reference(job: &EvalJob) -> Samples<f64> {
    let mut samples = Samples::for_job(job);
    let order = job.derivatives().order();
    for c in 0..job.len() {
        let (table, plan) = (job.table(c), job.plan(c));
        let dim = table.dim();
        let base = job.layout().values_of(c).start;
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

/// The threads of the pool this crate's parallel stages run on (at least 1; rayon's global
/// pool: one per CPU this process may use, or `RAYON_NUM_THREADS`): the default for the
/// `threads` arguments of this crate. Cheap: the pool's size is read once, where
/// `std::thread::available_parallelism` reads the cgroup's limits on every call (more than a
/// small call's whole work; docs/benchmarks.md).
#[must_use]
pub fn available_threads() -> usize {
    rayon::current_num_threads().max(1)
}

/// Evaluates every curve of `job` on `threads` threads into new [`Samples`], f32 or f64. With
/// `F = f64` the values equal [`evaluate_reference`]'s exactly.
#[must_use]
pub fn evaluate_cpu<F: SampleFloat>(job: &EvalJob, threads: usize) -> Samples<F> {
    let mut samples = Samples::for_job(&EvalJob::new(job.derivatives()));
    evaluate_cpu_into(job, samples.planes_for(job), threads);
    samples
}

/// The fewest samples worth a thread of their own: a thread's start and join (tens of
/// microseconds) is the time of about this many samples.
const MIN_PART_SAMPLES: usize = 16_384;

/// Evaluates `job` into a caller's [`Planes`] on `threads` threads (at most one per
/// 16,384 samples): each sample's t when they
/// hold it, the positions and the derivatives the job asks for. Nothing is allocated per
/// sample; the samples are split into one contiguous range per thread, and an arc-length or
/// tolerance sample's place is computed once for its t and its values. Through
/// [`Samples::planes_for`] repeated jobs reuse one `Samples`' memory.
///
/// # Panics
/// If a plane's presence or length does not match the job (see [`Planes`]).
pub fn evaluate_cpu_into<F: SampleFloat>(job: &EvalJob, planes: Planes<'_, F>, threads: usize) {
    let (mut params, planes) = planes.checked(job);
    let layout = job.layout();
    let [mut points, mut d1, mut d2] = planes;
    // One contiguous range of samples per thread, with its part of every plane; a small job
    // stays on the calling thread, since starting a thread costs more than it would take.
    let threads = threads.min(layout.samples().div_ceil(MIN_PART_SAMPLES));
    let parts: Vec<_> = even_ranges(layout.samples(), threads)
        .map(|range| {
            let n = layout.value_of_sample(range.end) - layout.value_of_sample(range.start);
            let planes = [&mut points, &mut d1, &mut d2].map(|plane| take_front(plane, n));
            let params = take_front(&mut params, range.len());
            (range, params, planes)
        })
        .collect();
    fan_out(parts, |(range, params, planes)| {
        F::evaluate_range(job, range, params, planes);
    });
}

/// `plane[range]`, or an empty plane as it is.
fn sub<F>(plane: &mut [F], range: std::ops::Range<usize>) -> &mut [F] {
    if plane.is_empty() {
        plane
    } else {
        &mut plane[range]
    }
}

/// The sealed evaluator of each number type ([`SampleFloat`]'s supertrait): the CPU's.
macro_rules! evaluated_here {
    ($($float:ty),*) => {$(
        impl crate::job::samples::sealed::Sealed for $float {
            fn evaluate_range(
                job: &EvalJob,
                range: std::ops::Range<usize>,
                t: &mut [f64],
                out: [&mut [Self]; 3],
            ) {
                evaluate_range_fastest(job, range, t, out);
            }
        }
    )*};
}
evaluated_here!(f32, f64);

/// [`evaluate_range`] compiled for the widest vectors this CPU has: AVX-512 (8 f64 lanes),
/// else AVX2 (4), else the x86-64 baseline's SSE2 (2). Every build does the same IEEE
/// operations in the same order (Rust never fuses a multiply and an add on its own), so all
/// give the same bits (docs/benchmarks.md has each one's time on w1).
pub(crate) fn evaluate_range_fastest<F: SampleFloat>(
    job: &EvalJob,
    range: std::ops::Range<usize>,
    t: &mut [f64],
    out: [&mut [F]; 3],
) {
    evaluate_range_with(Isa::widest(), job, range, t, out);
}

/// [`evaluate_range`] as compiled for `isa`, which this CPU must run.
fn evaluate_range_with<F: SampleFloat>(
    isa: Isa,
    job: &EvalJob,
    range: std::ops::Range<usize>,
    t: &mut [f64],
    out: [&mut [F]; 3],
) {
    // One of the crate's five unsafe blocks (the others are the geometry's mesh writer's and
    // closing-up's, the same dispatch, and memory/'s madvise and getrlimit): a function
    // compiled for an instruction set may only be called where the CPU has it.
    #[allow(
        unsafe_code,
        reason = "a function compiled for an instruction set is called only where the CPU has it"
    )]
    match isa {
        Isa::Baseline => evaluate_range(job, range, t, out),
        // SAFETY: `Isa::widest` and `available` name AVX2 only where the CPU has it.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { evaluate_range_avx2(job, range, t, out) },
        // SAFETY: as for AVX2, with AVX-512F (and VL).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { evaluate_range_avx512(job, range, t, out) },
    }
}

/// [`evaluate_range`] with AVX2 enabled; everything it calls per sample is inlined into it,
/// so all of it is compiled with the wider vectors.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn evaluate_range_avx2<F: SampleFloat>(
    job: &EvalJob,
    range: std::ops::Range<usize>,
    t: &mut [f64],
    out: [&mut [F]; 3],
) {
    evaluate_range(job, range, t, out);
}

/// [`evaluate_range`] with AVX-512F enabled, as [`evaluate_range_avx2`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f")]
fn evaluate_range_avx512<F: SampleFloat>(
    job: &EvalJob,
    range: std::ops::Range<usize>,
    t: &mut [f64],
    out: [&mut [F]; 3],
) {
    evaluate_range(job, range, t, out);
}

/// Evaluates the job's samples `range` into `out` (each plane starting at the range's first
/// value), and their parameters into `t` unless it is empty.
#[inline(always)]
fn evaluate_range<F: SampleFloat>(
    job: &EvalJob,
    range: std::ops::Range<usize>,
    t: &mut [f64],
    mut out: [&mut [F]; 3],
) {
    if range.is_empty() {
        return;
    }
    let layout = job.layout();
    let mut written = 0;
    for c in layout.curve_of_sample(range.start)..job.len() {
        let samples = layout.samples_of(c);
        if samples.start >= range.end {
            break;
        }
        let (lo, hi) = (samples.start.max(range.start), samples.end.min(range.end));
        if lo >= hi {
            continue;
        }
        let table = job.table(c);
        let values = (hi - lo) * table.dim();
        let [p, a, b] = &mut out;
        let at = written..written + values;
        let parts = [sub(p, at.clone()), sub(a, at.clone()), sub(b, at)];
        curve_range(
            table,
            job.plan(c),
            lo - samples.start..hi - samples.start,
            sub(t, lo - range.start..hi - range.start),
            parts,
        );
        written += values;
    }
}

/// The most local parameters of a segment held at once (64 KiB).
const CACHED_US: usize = 8192;

/// Samples `range` of one curve into `out`, segment by segment with the coefficients hoisted,
/// and their parameters into `t` unless it is empty.
#[inline(always)]
fn curve_range<F: SampleFloat>(
    table: &SegmentTable,
    plan: &SamplePlan,
    range: std::ops::Range<usize>,
    t: &mut [f64],
    out: [&mut [F]; 3],
) {
    let dim = table.dim();
    let [points, d1, d2] = out;
    if !t.is_empty() && !plan.is_computed() {
        // Read off the plan segment by segment (a grid's t per sample would cost two integer
        // divisions each).
        plan.extend_t(range.clone(), &mut Filling::new(t));
    }
    match &plan.0 {
        Plan::Grid(grid) => {
            let k = grid.k as usize;
            let closing = grid.closing();
            // u = j/k, divided exactly as the plan divides it: once per range for ordinary k,
            // block by block for a k too large to hold (nothing per sample of a whole segment
            // is allocated).
            let u = |j: usize| j as f64 / k as f64;
            let cached: Vec<f64> = if k <= CACHED_US {
                (0..k).map(u).collect()
            } else {
                Vec::new()
            };
            let mut scratch = Vec::new();
            let (g0, g1) = (grid.first + range.start, grid.first + range.end);
            let mut g = g0;
            while g < g1 {
                let (segment, us): (usize, &[f64]) = if g == closing {
                    (grid.segments() - 1, &[1.0])
                } else {
                    let (s, j) = (g / k, g % k);
                    let n = (k - j).min(g1 - g);
                    if cached.is_empty() {
                        scratch.clear();
                        scratch.extend((j..j + n.min(CACHED_US)).map(u));
                        (s, &scratch)
                    } else {
                        (s, &cached[j..j + n])
                    }
                };
                let at = (g - g0) * dim..(g - g0 + us.len()) * dim;
                let parts = [sub(points, at.clone()), sub(d1, at.clone()), sub(d2, at)];
                segment_block(&table.segment(segment), us, parts);
                g += us.len();
            }
        }
        Plan::At(locs) => at_places(table, &locs[range], [points, d1, d2]),
        // Arc length and tolerance: places computed block by block, each segment's samples
        // evaluated together.
        Plan::Arc(_) | Plan::Tolerance(_) => {
            let mut runs = Runs::default();
            for start in range.clone().step_by(LOC_BLOCK) {
                let end = (start + LOC_BLOCK).min(range.end);
                runs.clear();
                let knots = plan.runs_into(start..end, &mut runs);
                let mut at = start - range.start;
                for (segment, us) in runs.iter() {
                    let samples = at..at + us.len();
                    if !t.is_empty() {
                        for (t, &u) in t[samples.clone()].iter_mut().zip(us) {
                            *t = t_at(knots, segment, u);
                        }
                    }
                    let values = samples.start * dim..samples.end * dim;
                    let parts = [
                        sub(points, values.clone()),
                        sub(d1, values.clone()),
                        sub(d2, values),
                    ];
                    segment_block(&table.segment(segment), us, parts);
                    at = samples.end;
                }
            }
        }
    }
}

/// Samples at `locs` into `out`, one after the other, with the dimension known at compile time
/// for D <= 4. Each sample reads its segment's coefficients straight from the table: going
/// through [`segment_block`] per sample (a `Segment`, its slices and a one-element block) cost
/// more than the arithmetic on eval-at (docs/benchmarks.md).
#[inline(always)]
fn at_places<F: SampleFloat>(table: &SegmentTable, locs: &[SampleLoc], out: [&mut [F]; 3]) {
    if table.is_rational() {
        let dim = table.dim();
        let [points, d1, d2] = out;
        for (i, loc) in locs.iter().enumerate() {
            let at = i * dim..(i + 1) * dim;
            let parts = [sub(points, at.clone()), sub(d1, at.clone()), sub(d2, at)];
            block_rational(&table.segment(loc.segment), &[loc.u], parts);
        }
        return;
    }
    match table.dim() {
        1 => places::<1, F>(table, locs, out),
        2 => places::<2, F>(table, locs, out),
        3 => places::<3, F>(table, locs, out),
        4 => places::<4, F>(table, locs, out),
        _ => {
            let dim = table.dim();
            let [points, d1, d2] = out;
            for (i, loc) in locs.iter().enumerate() {
                let at = i * dim..(i + 1) * dim;
                let parts = [sub(points, at.clone()), sub(d1, at.clone()), sub(d2, at)];
                block_any(&table.segment(loc.segment), &[loc.u], parts);
            }
        }
    }
}

/// [`at_places`] for `D` coordinates.
#[inline(always)]
fn places<const D: usize, F: SampleFloat>(
    table: &SegmentTable,
    locs: &[SampleLoc],
    out: [&mut [F]; 3],
) {
    let (coeffs, knots) = (table.power_coefficients(), table.knots());
    let [points, d1, d2] = out;
    for (loc, o) in locs.iter().zip(points.chunks_exact_mut(D)) {
        let c = &coeffs[4 * D * loc.segment..][..4 * D];
        for k in 0..D {
            o[k] = F::from_f64(position(c[k], c[D + k], c[2 * D + k], c[3 * D + k], loc.u));
        }
    }
    for (order, plane) in [(1, d1), (2, d2)] {
        for (loc, o) in locs.iter().zip(plane.chunks_exact_mut(D)) {
            let c = &coeffs[4 * D * loc.segment..][..4 * D];
            let inv_dt = 1.0 / (knots[loc.segment + 1] - knots[loc.segment]);
            for k in 0..D {
                o[k] = F::from_f64(if order == 1 {
                    first_derivative(c[k], c[D + k], c[2 * D + k], loc.u, inv_dt)
                } else {
                    second_derivative(c[k], c[D + k], loc.u, inv_dt)
                });
            }
        }
    }
}

/// One segment at the local parameters `us` into `out`, with its dimension known at compile
/// time for D <= 4 (the common cases).
#[inline(always)]
fn segment_block<F: SampleFloat>(segment: &Segment<'_>, us: &[f64], out: [&mut [F]; 3]) {
    if segment.denominator().is_some() {
        return block_rational(segment, us, out);
    }
    match segment.power()[0].len() {
        1 => block::<1, F>(segment, us, out),
        2 => block::<2, F>(segment, us, out),
        3 => block::<3, F>(segment, us, out),
        4 => block::<4, F>(segment, us, out),
        _ => block_any(segment, us, out),
    }
}

/// [`block_any`] for a dimension fixed at compile time. The coefficients as arrays let the
/// compiler drop the bounds checks and vectorize: on w1 this measured faster than `block_any`
/// inlined with a constant dimension (docs/benchmarks.md), so the two bodies stay separate (the
/// formulas themselves are written once, in `segment`).
#[inline(always)]
fn block<const D: usize, F: SampleFloat>(segment: &Segment<'_>, us: &[f64], out: [&mut [F]; 3]) {
    let arr = |v: &[f64]| -> [f64; D] { v.try_into().expect("D coordinates") };
    let [a, b, c, d] = segment.power().map(arr);
    let inv_dt = 1.0 / segment.dt();
    let [points, d1, d2] = out;
    for (&u, o) in us.iter().zip(points.chunks_exact_mut(D)) {
        for k in 0..D {
            o[k] = F::from_f64(position(a[k], b[k], c[k], d[k], u));
        }
    }
    for (&u, o) in us.iter().zip(d1.chunks_exact_mut(D)) {
        for k in 0..D {
            o[k] = F::from_f64(first_derivative(a[k], b[k], c[k], u, inv_dt));
        }
    }
    for (&u, o) in us.iter().zip(d2.chunks_exact_mut(D)) {
        for k in 0..D {
            o[k] = F::from_f64(second_derivative(a[k], b[k], u, inv_dt));
        }
    }
}

/// One segment of any dimension at the local parameters `us` into `out`: Horner in f64,
/// rounded to `F` on the store.
#[inline(always)]
fn block_any<F: SampleFloat>(segment: &Segment<'_>, us: &[f64], out: [&mut [F]; 3]) {
    let [a, b, c, d] = segment.power();
    let dim = a.len();
    let inv_dt = 1.0 / segment.dt();
    let [points, d1, d2] = out;
    for (&u, o) in us.iter().zip(points.chunks_exact_mut(dim)) {
        for k in 0..dim {
            o[k] = F::from_f64(position(a[k], b[k], c[k], d[k], u));
        }
    }
    for (&u, o) in us.iter().zip(d1.chunks_exact_mut(dim)) {
        for k in 0..dim {
            o[k] = F::from_f64(first_derivative(a[k], b[k], c[k], u, inv_dt));
        }
    }
    for (&u, o) in us.iter().zip(d2.chunks_exact_mut(dim)) {
        for k in 0..dim {
            o[k] = F::from_f64(second_derivative(a[k], b[k], u, inv_dt));
        }
    }
}

/// One rational segment at the local parameters `us` into `out`, by the quotient rule of
/// [`rational`](crate::rational) with the same operations in the same order as
/// [`Segment::eval`] and its siblings (so the reference's bits), the dimension known at compile
/// time for D <= 4: W(u) once per sample, one division per sample.
#[inline(always)]
fn block_rational<F: SampleFloat>(segment: &Segment<'_>, us: &[f64], out: [&mut [F]; 3]) {
    match segment.power()[0].len() {
        1 => rational::<1, F>(segment, us, out),
        2 => rational::<2, F>(segment, us, out),
        3 => rational::<3, F>(segment, us, out),
        4 => rational::<4, F>(segment, us, out),
        _ => rational::<0, F>(segment, us, out),
    }
}

/// Samples of a rational segment whose 1/W are formed together.
const RATIONAL_BLOCK: usize = 64;

/// [`block_rational`] for `D` coordinates (0: read at run time).
#[inline(always)]
fn rational<const D: usize, F: SampleFloat>(segment: &Segment<'_>, us: &[f64], out: [&mut [F]; 3]) {
    let [a, b, c, d] = segment.power();
    let dim = if D == 0 { a.len() } else { D };
    let w = segment.denominator().expect("a rational segment");
    let [points, d1, d2] = out;
    // 1/W(u) for a block of samples first: a loop of divisions alone, which vectorizes
    // (docs/benchmarks.md has w1-nurbs with one division inside each sample's loop).
    let [wa, wb, wc, wd] = w.coeffs;
    let mut inv = [0.0; RATIONAL_BLOCK];
    for (us, points) in us
        .chunks(RATIONAL_BLOCK)
        .zip(points.chunks_mut(RATIONAL_BLOCK * dim))
    {
        for (inv, &u) in inv.iter_mut().zip(us) {
            *inv = 1.0 / (wd + u * (wc + u * (wb + u * wa)));
        }
        for ((&u, &inv), o) in us.iter().zip(&inv).zip(points.chunks_exact_mut(dim)) {
            for k in 0..dim {
                o[k] = F::from_f64(d[k] + u * (c[k] + u * (b[k] + u * a[k])) * inv);
            }
        }
    }
    let inv_dt = 1.0 / segment.dt();
    for (order, plane) in [(1, d1), (2, d2)] {
        for (&u, o) in us.iter().zip(plane.chunks_exact_mut(dim)) {
            let at = w.at(u);
            for k in 0..dim {
                o[k] = F::from_f64(crate::segment::rational_derivative(
                    order, a[k], b[k], c[k], d[k], u, inv_dt, &at,
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Basis, Curve, CurveKind, Derivatives, Ends, Points, Sampling};

    /// Curves of every dimension the evaluator specializes (1-4) and one it does not, polynomial
    /// and rational, under every kind of sampling, with both derivatives.
    fn job() -> EvalJob {
        let mut job = EvalJob::new(Derivatives::Second);
        let samplings = [
            Sampling::PerSegment(37),
            Sampling::At(vec![0.0, 0.3, 1.7, 2.5, 4.0, 5.0]),
            Sampling::ArcLength(41),
            Sampling::Tolerance(1e-3),
        ];
        for dim in 1..=5 {
            for (i, sampling) in samplings.iter().enumerate() {
                let coords = (0..7 * dim)
                    .map(|v| ((v * 3 + i) as f64 * 0.9).sin() * 10.0)
                    .collect();
                let kind = CurveKind::Uniform {
                    basis: Basis::CatmullRom,
                    ends: Ends::Repeat,
                };
                let points = Points::new(dim, coords).unwrap();
                let curve = Curve::new(kind, points.clone()).unwrap();
                job.push(&curve, sampling).unwrap();
                // The same points as a rational B-spline.
                let kind = CurveKind::Nurbs {
                    knots: vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.5, 2.6, 5.0, 5.0, 5.0, 5.0],
                    weights: Some((0..7).map(|j| 0.5 + (j * j % 5) as f64).collect()),
                };
                job.push(&Curve::new(kind, points).unwrap(), sampling)
                    .unwrap();
            }
        }
        job
    }

    /// Computed plans (arc length, tolerance) of more samples than a block of places, on
    /// threads whose ranges start and end inside them, give what [`SamplePlan::loc`] gives
    /// one sample at a time: the reference's values and the places' t, bit for bit.
    #[test]
    fn computed_places_in_ranges_cut_anywhere_are_the_ones_found_one_by_one() {
        let mut job = EvalJob::new(Derivatives::First);
        let coords: Vec<f64> = (0..60).map(|v| (f64::from(v) * 2.59).sin() * 5.0).collect();
        let points = Points::new(3, coords).unwrap();
        let kind = CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Repeat,
        };
        let curve = Curve::new(kind, points.clone()).unwrap();
        job.push(&curve, &Sampling::ArcLength(20_011)).unwrap();
        job.push(&curve, &Sampling::Tolerance(1e-7)).unwrap();
        let knots: Vec<f64> = [0.0; 4]
            .into_iter()
            .chain((1..17).map(|k| f64::from(k) * f64::from(k)))
            .chain([289.0; 4])
            .collect();
        let kind = CurveKind::Nurbs {
            knots,
            weights: Some((0..20).map(|j| 0.5 + f64::from(j % 4)).collect()),
        };
        job.push(
            &Curve::new(kind, points).unwrap(),
            &Sampling::ArcLength(9_001),
        )
        .unwrap();
        let plans: Vec<usize> = (0..job.len()).map(|c| job.plan(c).len()).collect();
        assert!(
            plans[1] > 2 * LOC_BLOCK,
            "the tolerance sampling spans blocks: {plans:?}"
        );
        let want_t: Vec<f64> = (0..job.len())
            .flat_map(|c| (0..job.plan(c).len()).map(move |i| (c, i)))
            .map(|(c, i)| job.plan(c).loc(i).t)
            .collect();
        let (_, _, want) = evaluate_reference(&job).into_parts();
        for threads in 1..=3 {
            let mut fast = Samples::<f64>::for_job(&job);
            evaluate_cpu_into(&job, fast.planes_for(&job), threads);
            let (_, t, got) = fast.into_parts();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert!(bits(&t) == bits(&want_t), "t on {threads} threads");
            for plane in 0..2 {
                assert!(
                    bits(&got[plane]) == bits(&want[plane]),
                    "plane {plane} on {threads} threads"
                );
            }
        }
    }

    /// Every instruction set's build gives the reference's bits in f64 and the reference
    /// rounded once in f32, so the one a CPU picks never changes an answer.
    #[test]
    fn every_vector_width_gives_the_reference_bits() {
        let job = job();
        let (_, _, reference) = evaluate_reference(&job).into_parts();
        let total = job.layout().samples();
        for isa in Isa::available() {
            let mut fast = Samples::<f64>::for_job(&job);
            let [p, d1, d2] = fast.planes_mut();
            evaluate_range_with(isa, &job, 0..total, &mut [], [p, d1, d2]);
            let mut narrow = Samples::<f32>::for_job(&job);
            let [p, d1, d2] = narrow.planes_mut();
            evaluate_range_with(isa, &job, 0..total, &mut [], [p, d1, d2]);
            let (_, _, fast) = fast.into_parts();
            let (_, _, narrow) = narrow.into_parts();
            for plane in 0..3 {
                let (want, got, got32) = (&reference[plane], &fast[plane], &narrow[plane]);
                assert!(!want.is_empty() && want.len() == got.len());
                for (v, ((&w, &g), &g32)) in want.iter().zip(got).zip(got32).enumerate() {
                    assert_eq!(w.to_bits(), g.to_bits(), "{isa:?}: plane {plane} value {v}");
                    assert_eq!((w as f32).to_bits(), g32.to_bits(), "{isa:?}: f32 {v}");
                }
            }
        }
    }
}
