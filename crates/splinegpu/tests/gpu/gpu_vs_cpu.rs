//! The f32 GPU evaluator against the f64 CPU reference, under the contract's accuracy promise
//! (`splinegpu::accuracy::gpu_bound`). Runs on whatever adapter wgpu finds; in CI that is lavapipe.

use crate::shapes::nurbs_circle;
#[cfg(feature = "profiling")]
use crate::support::compare;
use crate::support::{Rng, assert_gpu_matches_cpu, bases, gpu, local_beta};
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, GpuContext, Points, Samples, Sampling,
};

const DIMS: [usize; 6] = [1, 2, 3, 4, 6, 30];

/// Every family with every end convention (local bias and tension too), and Bezier, in every dimension of `DIMS`, with
/// points at `center` ± `span`.
fn every_curve(rng: &mut Rng, center: f64, span: f64) -> Vec<Curve> {
    let mut curves = Vec::new();
    for &dim in &DIMS {
        for basis in bases() {
            for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
                let points = rng.points(7, dim, center - span, center + span);
                curves.push(
                    Curve::new(
                        CurveKind::Uniform {
                            basis: basis.clone(),
                            ends,
                        },
                        points,
                    )
                    .unwrap(),
                );
            }
        }
        for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
            let kind = local_beta(rng, ends, 7);
            let points = rng.points(7, dim, center - span, center + span);
            curves.push(Curve::new(kind, points).unwrap());
        }
        curves.push(
            Curve::new(
                CurveKind::Bezier,
                rng.points(7, dim, center - span, center + span),
            )
            .unwrap(),
        );
    }
    curves
}

/// Explicit t values over a curve's range: its ends, every knot, and random values.
fn explicit_ts(rng: &mut Rng, curve: &Curve) -> Vec<f64> {
    let (lo, hi) = curve.t_range();
    let mut ts: Vec<f64> = (0..=curve.segment_count()).map(|i| lo + i as f64).collect();
    ts.extend((0..20).map(|_| rng.range(lo, hi)));
    ts.push(hi);
    ts
}

fn check_every_curve(center: f64, span: f64) {
    let mut rng = Rng(101);
    let curves = every_curve(&mut rng, center, span);
    for derivatives in [Derivatives::None, Derivatives::First, Derivatives::Second] {
        let mut per_segment = EvalJob::new(derivatives);
        let mut at = EvalJob::new(derivatives);
        for curve in &curves {
            per_segment.push(curve, &Sampling::PerSegment(7)).unwrap();
            at.push(curve, &Sampling::At(explicit_ts(&mut rng, curve)))
                .unwrap();
        }
        for (name, job) in [("per_segment", per_segment), ("at", at)] {
            let Some(worst) = assert_gpu_matches_cpu(&job) else {
                return;
            };
            eprintln!(
                "center {center:e}, {derivatives:?}, {name}: worst fraction of the bound {:.3?} \
                 (positions, d1, d2)",
                worst.per_order
            );
        }
    }
}

pub(crate) fn gpu_matches_cpu_for_every_family_end_and_dimension() {
    check_every_curve(0.0, 10.0);
}

pub(crate) fn gpu_matches_cpu_near_one_million() {
    // Points near 1e6 spanning about 1: f32 spacing there is 0.0625, so only coefficients
    // formed in f64 relative to the segment's own origin keep positions and derivatives.
    check_every_curve(1.0e6, 0.5);
    check_every_curve(-3.0e6, 2.0);
}

pub(crate) fn gpu_matches_cpu_on_2000_mixed_curves_in_one_call() {
    let mut rng = Rng(2000);
    let mut job = EvalJob::new(Derivatives::Second);
    let bases = bases();
    for i in 0..2000 {
        let dim = [1, 2, 3, 3, 3, 4, 6, 30][i % 8];
        let center = if i % 7 == 0 { 1.0e6 } else { 0.0 };
        let curve = if i % 11 == 0 {
            Curve::new(
                CurveKind::Bezier,
                rng.points(3 * (1 + i % 4) + 1, dim, center - 5.0, center + 5.0),
            )
        } else {
            let ends = [Ends::Control, Ends::Repeat, Ends::Closed][i % 3];
            let n = 4 + i % 13;
            let kind = CurveKind::Uniform {
                basis: bases[i % bases.len()].clone(),
                ends,
            };
            Curve::new(kind, rng.points(n, dim, center - 5.0, center + 5.0))
        }
        .unwrap();
        let sampling = if i % 5 == 0 {
            Sampling::At(explicit_ts(&mut rng, &curve))
        } else {
            Sampling::PerSegment(1 + (i % 20) as u32)
        };
        job.push(&curve, &sampling).unwrap();
    }
    if let Some(worst) = assert_gpu_matches_cpu(&job) {
        eprintln!(
            "2000 mixed curves: worst fraction of the bound {:.3?}",
            worst.per_order
        );
    }
}

/// A job of a few hundred thousand values, for the dispatch and shape tests.
fn medium_job() -> EvalJob {
    let mut rng = Rng(77);
    let mut job = EvalJob::new(Derivatives::Second);
    for i in 0..60 {
        let kind = CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Repeat,
        };
        let curve = Curve::new(kind, rng.points(20 + i, 3, -1.0, 1.0)).unwrap();
        job.push(&curve, &Sampling::PerSegment(37)).unwrap();
    }
    job
}

pub(crate) fn jobs_split_into_many_dispatches_give_the_same_samples() {
    let Some(shared) = gpu() else { return };
    let job = medium_job();
    let whole = shared.evaluate(&job).unwrap();
    let split = GpuContext::new().unwrap().with_max_dispatch_values(1000);
    let pieces = split.evaluate(&job).unwrap();
    // Same runs, same arithmetic: only the dispatch boundaries differ.
    assert_eq!(whole, pieces);
}

pub(crate) fn values_into_a_callers_planes_equal_evaluates() {
    let Some(context) = gpu() else { return };
    let mut job = medium_job();
    let mut rng = Rng(78);
    let kind = CurveKind::Uniform {
        basis: Basis::BSpline,
        ends: Ends::Closed,
    };
    let curve = Curve::new(kind, rng.points(9, 3, -1.0, 1.0)).unwrap();
    for sampling in [
        Sampling::ArcLength(101),
        Sampling::Tolerance(1e-3),
        Sampling::At(vec![0.5, 2.0, 1.25]),
    ] {
        job.push(&curve, &sampling).unwrap();
    }
    let whole = context.evaluate(&job).unwrap();
    let values = job.layout().values();
    let mut planes = [vec![1.0f32; values], vec![2.0; values], vec![3.0; values]];
    let [p, d1, d2] = &mut planes;
    let into = splinegpu::Planes::new(p).with_d1(d1).with_d2(d2);
    context.evaluate_into(&job, into).unwrap();
    for c in 0..job.len() {
        let (curve, range) = (whole.curve(c), job.layout().values_of(c));
        assert_eq!(&planes[0][range.clone()], curve.points, "curve {c}");
        assert_eq!(&planes[1][range.clone()], curve.d1.unwrap(), "curve {c}");
        assert_eq!(&planes[2][range], curve.d2.unwrap(), "curve {c}");
    }
}

/// A timed evaluation forms t after the device is done rather than while it works: the same
/// samples, t included, as an untimed one.
#[cfg(feature = "profiling")]
pub(crate) fn timed_evaluations_give_what_untimed_ones_give() {
    let Some(context) = gpu() else { return };
    let mut rng = Rng(79);
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Repeat,
    };
    let curve = Curve::new(kind, rng.points(7, 3, -1.0, 1.0)).unwrap();
    // Every t known on the host (grid, tolerance and explicit), then arc length too (whose t
    // the host forms from the places the kernel found).
    let samplings = [
        Sampling::Tolerance(1e-3),
        Sampling::At(vec![0.5, 2.0, 1.25]),
        Sampling::ArcLength(33),
    ];
    for with_arc_length in [false, true] {
        let mut job = medium_job();
        for sampling in &samplings[..if with_arc_length { 3 } else { 2 }] {
            job.push(&curve, sampling).unwrap();
        }
        let whole = context.evaluate(&job).unwrap();
        // Laid out for an empty job: its t are formed by the evaluation, not by `for_job`.
        let mut timed = Samples::for_job(&EvalJob::new(Derivatives::Second));
        let time = context
            .evaluate_timed(&job, timed.planes_for(&job))
            .unwrap();
        assert!(time.seconds > 0.0, "{time:?}");
        assert_eq!(timed, whole, "arc length: {with_arc_length}");
    }
}

#[cfg(feature = "profiling")]
pub(crate) fn every_kernel_shape_meets_the_promise() {
    if gpu().is_none() {
        return;
    }
    use splinegpu::profiling::KernelShape;
    let job = medium_job();
    let cpu = splinegpu::evaluate_reference(&job);
    // A GPU's shape and a CPU adapter's, and an awkward one: runs not a multiple of 4 (the
    // kernel twin's tests go through more).
    let shapes = [
        KernelShape::LOOPING,
        KernelShape::PER_SAMPLE,
        KernelShape {
            lanes: 4,
            run_len: 7,
        },
    ];
    for shape in shapes {
        let context = GpuContext::new().unwrap().with_shape(shape);
        let worst = compare(&job, &cpu, &context.evaluate(&job).unwrap());
        assert!(worst.ratio <= 1.0, "{shape:?}: {worst:?}");
    }
}

pub(crate) fn empty_sample_lists_give_empty_curves() {
    let Some(context) = gpu() else { return };
    let kind = CurveKind::Uniform {
        basis: Basis::BSpline,
        ends: Ends::Control,
    };
    let curve = Curve::new(kind, Points::new(1, vec![0.0, 1.0, 2.0, 3.0]).unwrap()).unwrap();
    let mut job = EvalJob::new(Derivatives::First);
    job.push(&curve, &Sampling::At(vec![])).unwrap();
    let samples = context.evaluate(&job).unwrap();
    assert!(samples.curve(0).points.is_empty());
    job.push(&curve, &Sampling::At(vec![0.5])).unwrap();
    let samples = context.evaluate(&job).unwrap();
    assert!(samples.curve(0).points.is_empty());
    assert_eq!(samples.curve(1).points.len(), 1);
}

/// Knots from `start` with spacings drawn log-uniformly over a factor `ratio`.
fn random_knots(rng: &mut Rng, n: usize, start: f64, ratio: f64) -> Vec<f64> {
    let mut t = vec![start];
    for i in 1..n {
        let spacing = ratio.powf(rng.range(-0.5, 0.5));
        t.push(t[i - 1] + spacing);
    }
    t
}

pub(crate) fn gpu_matches_cpu_on_10000_interpolating_curves_with_their_own_knots() {
    use splinegpu::EndCondition;
    let mut rng = Rng(10_000);
    let mut job = EvalJob::new(Derivatives::Second);
    for i in 0..10_000 {
        let dim = [1, 2, 3, 3, 7][i % 5];
        let n = 4 + i % 17;
        let condition = match i % 4 {
            0 => EndCondition::Natural,
            1 => EndCondition::Clamped {
                start: (0..dim).map(|_| rng.range(-3.0, 3.0)).collect(),
                end: (0..dim).map(|_| rng.range(-3.0, 3.0)).collect(),
            },
            2 => EndCondition::Periodic,
            _ => EndCondition::NotAKnot,
        };
        let start = 1.0e4 * rng.range(0.5, 1.5);
        let t = random_knots(&mut rng, n, start, [1.0, 1e3, 1e6][i % 3]);
        let center = if i % 9 == 0 { 1.0e6 } else { 0.0 };
        let mut coords: Vec<f64> = (0..n * dim)
            .map(|_| center + rng.range(-5.0, 5.0))
            .collect();
        if condition == EndCondition::Periodic {
            let first = coords[..dim].to_vec();
            coords[(n - 1) * dim..].copy_from_slice(&first);
        }
        let points = Points::new(dim, coords).unwrap();
        let curve = Curve::new(
            CurveKind::Interpolating {
                condition,
                t: Some(t.clone()),
            },
            points,
        )
        .unwrap();
        let sampling = if i % 2 == 0 {
            Sampling::PerSegment(6)
        } else {
            Sampling::At(
                (0..12)
                    .map(|_| rng.range(t[0], t[n - 1]))
                    .chain([t[1], t[n - 1]])
                    .collect(),
            )
        };
        job.push(&curve, &sampling).unwrap();
    }
    if let Some(worst) = assert_gpu_matches_cpu(&job) {
        eprintln!(
            "10,000 interpolating curves: worst fraction of the bound {:.3?}",
            worst.per_order
        );
    }
}

pub(crate) fn gpu_places_t_inside_a_segment_a_million_times_narrower_near_1e4() {
    use splinegpu::EndCondition;
    // Knots near 1e4, the middle segment 1e-6 wide between segments of width 1: in f32 the
    // whole narrow segment lies within one ulp of 1e4 (ulp 0.00098), so the segment and u must
    // come from the host's f64 search.
    let t = vec![
        1.0e4,
        1.0e4 + 1.0,
        1.0e4 + 1.0 + 1e-6,
        1.0e4 + 2.0 + 1e-6,
        1.0e4 + 3.0 + 1e-6,
    ];
    let points = Points::new(2, vec![0.0, 0.0, 1.0, 2.0, 1.5, 2.5, 3.0, 1.0, 4.0, 0.0]).unwrap();
    let inside: Vec<f64> = [0.1, 0.25, 0.5, 0.9]
        .iter()
        .map(|u| t[1] + u * 1e-6)
        .collect();
    for condition in [EndCondition::Natural, EndCondition::NotAKnot] {
        let curve = Curve::new(
            CurveKind::Interpolating {
                condition,
                t: Some(t.clone()),
            },
            points.clone(),
        )
        .unwrap();
        let mut job = EvalJob::new(Derivatives::Second);
        job.push(&curve, &Sampling::At(inside.clone())).unwrap();
        job.push(&curve, &Sampling::PerSegment(50)).unwrap();
        for (i, want_u) in [0.1, 0.25, 0.5, 0.9].into_iter().enumerate() {
            let loc = job.plan(0).loc(i);
            assert_eq!(loc.segment, 1);
            assert!((loc.u - want_u).abs() < 1e-6, "u = {}", loc.u);
        }
        assert_gpu_matches_cpu(&job);
    }
}

pub(crate) fn positions_of_knots_closer_than_f32_reaches_are_evaluated() {
    use splinegpu::EndCondition;
    // Knots 1e-300 apart: 1/Δ is beyond f32, but positions never use it (the cubic is in local
    // u), so a job of positions runs on the GPU; one with derivatives is refused, naming 1/Δ.
    let curve = Curve::new(
        CurveKind::Interpolating {
            condition: EndCondition::Natural,
            t: Some(vec![0.0, 1e-300, 2e-300, 3e-300]),
        },
        Points::new(2, vec![0.0, 0.0, 1.0, 2.0, 1.5, -1.0, 3.0, 1.0]).unwrap(),
    )
    .unwrap();
    let Some(ctx) = gpu() else { return };
    let mut positions = EvalJob::new(Derivatives::None);
    positions.push(&curve, &Sampling::PerSegment(16)).unwrap();
    positions
        .push(&curve, &Sampling::At(vec![0.0, 0.5e-300, 3e-300]))
        .unwrap();
    assert_gpu_matches_cpu(&positions);
    let mut slopes = EvalJob::new(Derivatives::First);
    slopes.push(&curve, &Sampling::PerSegment(16)).unwrap();
    let refused = ctx.evaluate(&slopes).unwrap_err().to_string();
    assert!(refused.contains("1/Δ"), "{refused}");
}

/// Job `i` of the concurrency test: its own families, dimensions, sampling and derivatives.
fn thread_job(i: usize) -> EvalJob {
    use splinegpu::EndCondition;
    let mut rng = Rng(500 + i as u64);
    let derivatives = [Derivatives::None, Derivatives::First, Derivatives::Second][i % 3];
    let mut job = EvalJob::new(derivatives);
    let bases = bases();
    for c in 0..40 + 10 * i {
        let dim = [1, 2, 3, 4, 5, 7, 30, 64][(i + c) % 8];
        let n = 5 + (c + i) % 9;
        let kind = match (c + i) % 4 {
            0 => CurveKind::Bezier,
            1 => CurveKind::Interpolating {
                condition: EndCondition::Natural,
                t: None,
            },
            _ => CurveKind::Uniform {
                basis: bases[(c + i) % bases.len()].clone(),
                ends: [Ends::Control, Ends::Repeat, Ends::Closed][c % 3],
            },
        };
        let n = if kind == CurveKind::Bezier { 7 } else { n };
        let curve = Curve::new(kind, rng.points(n, dim, -1.0, 1.0)).unwrap();
        let sampling = if (c + i).is_multiple_of(3) {
            Sampling::At(explicit_ts(&mut rng, &curve))
        } else {
            Sampling::PerSegment(1 + ((c * 7 + i) % 40) as u32)
        };
        job.push(&curve, &sampling).unwrap();
    }
    job
}

pub(crate) fn eight_threads_on_one_context_each_get_what_they_get_alone() {
    let Some(context) = gpu() else { return };
    let jobs: Vec<EvalJob> = (0..8).map(thread_job).collect();
    let alone: Vec<_> = jobs
        .iter()
        .map(|job| context.evaluate(job).unwrap())
        .collect();
    std::thread::scope(|s| {
        for (job, expected) in jobs.iter().zip(&alone) {
            s.spawn(move || {
                let mut reused = Samples::for_job(&EvalJob::new(Derivatives::None));
                for _ in 0..4 {
                    assert_eq!(&context.evaluate(job).unwrap(), expected);
                    context.evaluate_into(job, reused.planes_for(job)).unwrap();
                    assert_eq!(&reused, expected);
                }
            });
        }
    });
}

pub(crate) fn evaluate_into_reuses_samples_across_jobs_of_other_shapes() {
    let Some(context) = gpu() else { return };
    let jobs = [medium_job(), {
        let mut job = EvalJob::new(Derivatives::None);
        let kind = CurveKind::Uniform {
            basis: Basis::BSpline,
            ends: Ends::Repeat,
        };
        job.push(
            &Curve::new(kind, Rng(9).points(6, 2, 0.0, 1.0)).unwrap(),
            &Sampling::PerSegment(3),
        )
        .unwrap();
        job
    }];
    let mut reused = context.evaluate(&jobs[1]).unwrap();
    for job in jobs.iter().chain(&jobs) {
        context.evaluate_into(job, reused.planes_for(job)).unwrap();
        assert_eq!(reused, context.evaluate(job).unwrap());
    }
}

/// The weighted nurbs circle (four rational quarter arcs) on the GPU: every sample within the
/// position promise of the unit radius, and the GPU within the promise of the f64 reference.
pub(crate) fn a_weighted_nurbs_circle_stays_on_the_circle_on_the_gpu() {
    let Some(context) = gpu() else { return };
    let (_, _, curve) = nurbs_circle();
    let mut job = EvalJob::new(Derivatives::Second);
    job.push(&curve, &Sampling::PerSegment(64)).unwrap();
    let gpu = context.evaluate(&job).unwrap();
    let bound = splinegpu::accuracy::POSITION_TOLERANCE * 2.0 + 4.0 * f64::from(f32::EPSILON);
    let worst = (gpu.curve(0).points.chunks_exact(2))
        .map(|p| (f64::from(p[0]).hypot(f64::from(p[1])) - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(
        worst <= bound,
        "GPU radius off by {worst:e} (promise {bound:e})"
    );
    println!("GPU circle: radius within {worst:.2e} of 1");
    assert_gpu_matches_cpu(&job);
}
