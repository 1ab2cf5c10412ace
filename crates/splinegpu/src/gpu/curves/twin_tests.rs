//! The packer and every kernel shape, without a GPU: the f32 interpreter of the packed runs
//! (the kernel's CPU twin) against the f64 reference, under the accuracy promise, for every
//! family, dimension, sampling, chunking and dispatch limit; and, where wgpu finds an adapter
//! (lavapipe in CI), the GPU against the interpreter.

use super::evaluate_interpreted;
use crate::gpu::KernelShape;
use crate::gpu::curves::pack::BatchLimits;
#[cfg(feature = "profiling")]
use crate::support::gpu;
use crate::support::{Rng, bases, compare};
#[cfg(feature = "profiling")]
use splinegpu::GpuContext;
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, EndCondition, Ends, EvalJob, Points, Samples, Sampling,
};

const DIMS: [usize; 7] = [1, 2, 3, 4, 5, 30, 64];

/// No limit on a dispatch: the whole job in one.
const UNLIMITED: BatchLimits = BatchLimits {
    values: usize::MAX,
    runs: usize::MAX,
};

fn every_kind(rng: &mut Rng, dim: usize) -> Vec<CurveKind> {
    let mut kinds = Vec::new();
    for basis in bases() {
        for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
            kinds.push(CurveKind::Uniform {
                basis: basis.clone(),
                ends,
            });
        }
    }
    kinds.push(CurveKind::Bezier);
    let uneven: Vec<f64> = [0.0, 0.5, 0.501, 3.0, 3.5, 10.0, 10.25].to_vec();
    for condition in [
        EndCondition::Natural,
        EndCondition::Clamped {
            start: (0..dim).map(|_| rng.range(-2.0, 2.0)).collect(),
            end: (0..dim).map(|_| rng.range(-2.0, 2.0)).collect(),
        },
        EndCondition::NotAKnot,
    ] {
        kinds.push(CurveKind::Interpolating {
            condition,
            t: Some(uneven.clone()),
        });
    }
    // A rational B-spline on clamped, uneven knots with a double knot (7 points).
    kinds.push(CurveKind::Nurbs {
        knots: vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.501, 0.501, 3.0, 3.0, 3.0, 3.0],
        weights: Some((0..7).map(|_| rng.range(0.2, 5.0)).collect()),
    });
    kinds
}

/// Every family in `dim` dimensions, 7 points each, sampled `sampling(curve)`.
fn job_of(dim: usize, derivatives: Derivatives, sampling: impl Fn(&Curve) -> Sampling) -> EvalJob {
    let mut rng = Rng(dim as u64 + 17);
    let mut job = EvalJob::new(derivatives);
    for kind in every_kind(&mut rng, dim) {
        let curve = Curve::new(kind, rng.points(7, dim, -4.0, 4.0)).unwrap();
        job.push(&curve, &sampling(&curve)).unwrap();
    }
    // A periodic curve: its last point equal to its first.
    let mut coords: Vec<f64> = (0..5 * dim).map(|_| rng.range(-4.0, 4.0)).collect();
    let first = coords[..dim].to_vec();
    coords[4 * dim..].copy_from_slice(&first);
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Periodic,
        t: None,
    };
    let curve = Curve::new(kind, Points::new(dim, coords).unwrap()).unwrap();
    job.push(&curve, &sampling(&curve)).unwrap();
    job
}

/// The samplings tested: per segment (1, 4, 7 and 32 samples), explicit t (knots, ends,
/// random values, repeats, out of order) and arc length (placed by the kernel).
type SamplingOf = Box<dyn Fn(&Curve) -> Sampling>;

fn samplings() -> Vec<(&'static str, SamplingOf)> {
    let explicit = |curve: &Curve| {
        let (lo, hi) = curve.t_range();
        let mut rng = Rng(5);
        let mut ts: Vec<f64> = (0..23).map(|_| rng.range(lo, hi)).collect();
        ts.extend([hi, lo, hi, (lo + hi) / 2.0]);
        Sampling::At(ts)
    };
    vec![
        (
            "per_segment 1",
            Box::new(|_: &Curve| Sampling::PerSegment(1)),
        ),
        (
            "per_segment 4",
            Box::new(|_: &Curve| Sampling::PerSegment(4)),
        ),
        (
            "per_segment 7",
            Box::new(|_: &Curve| Sampling::PerSegment(7)),
        ),
        (
            "per_segment 32",
            Box::new(|_: &Curve| Sampling::PerSegment(32)),
        ),
        ("at", Box::new(explicit)),
        (
            "arc_length 29",
            Box::new(|_: &Curve| Sampling::ArcLength(29)),
        ),
    ]
}

fn assert_within_promise(what: &str, job: &EvalJob, f32_samples: &Samples<f32>) {
    let reference = splinegpu::evaluate_reference(job);
    let worst = compare(job, &reference, f32_samples);
    assert!(worst.ratio <= 1.0, "{what}: {worst:?}");
}

#[test]
fn interpreter_meets_the_promise_for_every_shape_family_dimension_and_sampling() {
    for dim in DIMS {
        for (name, sampling) in samplings() {
            let job = job_of(dim, Derivatives::Second, sampling);
            for shape in KernelShape::TESTED {
                let f32_samples = evaluate_interpreted(&job, shape, UNLIMITED).unwrap();
                assert_within_promise(&format!("D {dim}, {name}, {shape:?}"), &job, &f32_samples);
            }
        }
    }
}

#[test]
fn small_dispatch_limits_change_nothing() {
    for dim in [1, 3, 5] {
        for (name, sampling) in samplings() {
            let job = job_of(dim, Derivatives::First, sampling);
            for shape in KernelShape::TESTED {
                let whole = evaluate_interpreted(&job, shape, UNLIMITED).unwrap();
                for limits in [
                    BatchLimits {
                        values: 64,
                        runs: usize::MAX,
                    },
                    BatchLimits {
                        values: usize::MAX,
                        runs: 3,
                    },
                    BatchLimits { values: 8, runs: 1 },
                ] {
                    let cut = evaluate_interpreted(&job, shape, limits).unwrap();
                    // Same runs, same arithmetic: only the dispatch boundaries differ.
                    assert_eq!(cut, whole, "D {dim}, {name}, {shape:?}, {limits:?}");
                }
            }
        }
    }
}

#[test]
fn chunks_split_anywhere_meet_the_promise_and_keep_every_sample() {
    for dim in [1, 3, 30] {
        for (name, sampling) in samplings() {
            let job = job_of(dim, Derivatives::Second, sampling);
            // The kernel's t (the reference's, but where the kernel places arc-length samples).
            let whole = evaluate_interpreted(&job, KernelShape::LOOPING, UNLIMITED).unwrap();
            for max in [1, 5, 33, 1000] {
                let mut seen = vec![0usize; job.len()];
                for chunk in job.chunks(max) {
                    assert!(chunk.job.sample_count() <= max);
                    let part =
                        evaluate_interpreted(&chunk.job, KernelShape::LOOPING, UNLIMITED).unwrap();
                    assert_within_promise(
                        &format!("D {dim}, {name}, max {max}"),
                        &chunk.job,
                        &part,
                    );
                    for (c, piece) in chunk.pieces.iter().enumerate() {
                        assert_eq!(seen[piece.curve], piece.first_sample);
                        let t = part.curve(c).t;
                        let all = whole.curve(piece.curve).t;
                        assert_eq!(t, &all[piece.first_sample..piece.first_sample + t.len()]);
                        seen[piece.curve] += t.len();
                    }
                }
                for (c, seen) in seen.iter().enumerate() {
                    assert_eq!(*seen, job.plan(c).len(), "curve {c} complete");
                }
            }
        }
    }
}

#[test]
fn a_segment_of_a_billion_samples_is_chunked_without_holding_it() {
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Repeat,
    };
    let curve = Curve::new(
        kind,
        Points::new(2, vec![0.0, 0.0, 1.0, 2.0, 3.0, 1.0]).unwrap(),
    )
    .unwrap();
    let mut job = EvalJob::new(Derivatives::First);
    job.push(&curve, &Sampling::PerSegment(1_000_000_000))
        .unwrap();
    assert_eq!(job.sample_count(), 2_000_000_001);
    // The first, a middle and the last chunk of 1,000 samples, as the stream meets them.
    let mut chunks = job.chunks(1000);
    let first = chunks.next().unwrap();
    let middle = chunks.nth(999_999).unwrap();
    let last = job.chunks(1000).last().unwrap();
    for chunk in [first, middle, last] {
        let part = evaluate_interpreted(&chunk.job, KernelShape::LOOPING, UNLIMITED).unwrap();
        assert_within_promise("a billion per segment", &chunk.job, &part);
    }
}

/// The interpreter's limits for a context: what its device lets one dispatch hold.
#[cfg(feature = "profiling")]
fn limits_of(context: &GpuContext, job: &EvalJob) -> BatchLimits {
    BatchLimits::for_device(
        &context.device().limits(),
        job.derivatives().order() + 1,
        usize::MAX,
    )
}

#[cfg(feature = "profiling")]
#[test]
fn gpu_equals_the_interpreter_bit_for_bit_for_every_shape() {
    if gpu().is_none() {
        return;
    }
    for shape in KernelShape::TESTED {
        let context = GpuContext::new().unwrap().with_shape(shape);
        for dim in [1, 2, 3, 4, 5, 64] {
            for (name, sampling) in samplings() {
                let job = job_of(dim, Derivatives::Second, sampling);
                let on_gpu = context.evaluate(&job).unwrap();
                let twin = evaluate_interpreted(&job, shape, limits_of(&context, &job)).unwrap();
                // Same f32 operations in the same order: lavapipe contracts nothing into FMAs
                // (measured: 7.2 M values equal), so there the two are equal value by value. A
                // GPU driver may fuse multiply-adds; there the promise is what holds.
                if context.adapter_info().device_type == wgpu::DeviceType::Cpu {
                    assert!(
                        on_gpu == twin,
                        "GPU and interpreter differ: D {dim}, {name}, {shape:?}"
                    );
                }
                assert_within_promise(&format!("GPU, D {dim}, {name}, {shape:?}"), &job, &on_gpu);
            }
        }
    }
}
