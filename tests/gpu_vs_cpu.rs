//! The f32 GPU evaluator against the f64 CPU reference, under the contract's accuracy promise
//! (`splinegpu::accuracy`). Runs on whatever adapter wgpu finds; in CI that is lavapipe.

mod common;

use common::{Rng, assert_gpu_matches_cpu, compare, gpu};
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, GpuContext, KernelShape, Points, Sampling,
};

const DIMS: [usize; 6] = [1, 2, 3, 4, 6, 30];

fn bases() -> Vec<Basis> {
    vec![
        Basis::Cardinal { tension: 0.3 },
        Basis::CatmullRom,
        Basis::BSpline,
        Basis::TensionedBSpline { tension: 0.6 },
        Basis::Beta {
            bias: 1.7,
            tension: 3.0,
        },
        Basis::Matrix([
            [1.0, -2.0, 0.5, 0.0],
            [0.0, 3.0, -1.0, 0.25],
            [2.0, 0.0, 0.0, 1.0],
            [0.1, 0.2, 0.3, 0.4],
        ]),
    ]
}

/// Every family with every end convention, and Bezier, in every dimension of `DIMS`, with
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

#[test]
fn gpu_matches_cpu_for_every_family_end_and_dimension() {
    check_every_curve(0.0, 10.0);
}

#[test]
fn gpu_matches_cpu_near_one_million() {
    // Points near 1e6 spanning about 1: f32 spacing there is 0.0625, so only coefficients
    // formed in f64 relative to the segment's own origin keep positions and derivatives.
    check_every_curve(1.0e6, 0.5);
    check_every_curve(-3.0e6, 2.0);
}

#[test]
fn gpu_matches_cpu_on_2000_mixed_curves_in_one_call() {
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

#[test]
fn jobs_split_into_many_dispatches_give_the_same_samples() {
    let Some(shared) = gpu() else { return };
    let job = medium_job();
    let whole = shared.evaluate(&job).unwrap();
    let split = GpuContext::new().unwrap().with_max_dispatch_values(1000);
    let pieces = split.evaluate(&job).unwrap();
    // Same runs, same arithmetic: only the dispatch boundaries differ.
    assert_eq!(whole, pieces);
}

#[test]
fn every_kernel_shape_meets_the_promise() {
    if gpu().is_none() {
        return;
    }
    let job = medium_job();
    let cpu = splinegpu::cpu::evaluate(&job);
    let shapes = [
        KernelShape::LOOPING,
        KernelShape::PER_SAMPLE,
        KernelShape {
            lanes: 4,
            run_len: 7,
        },
        KernelShape {
            lanes: 1,
            run_len: 1,
        },
    ];
    for shape in shapes {
        let context = GpuContext::new().unwrap().with_shape(shape);
        let worst = compare(&job, &cpu, &context.evaluate(&job).unwrap());
        assert!(worst.ratio <= 1.0, "{shape:?}: {worst:?}");
    }
}

#[test]
fn empty_sample_lists_give_empty_curves() {
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
