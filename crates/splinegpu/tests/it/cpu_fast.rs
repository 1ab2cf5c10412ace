//! The fast CPU evaluator against the f64 reference: bit for bit in f64, and the reference
//! rounded once in f32, whatever the number of threads and wherever their ranges cut curves.

use crate::support::Rng;
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, EndCondition, Ends, EvalJob, Planes, Samples, Sampling,
};

fn mixed_job(derivatives: Derivatives) -> EvalJob {
    let mut rng = Rng(77);
    let mut job = EvalJob::new(derivatives);
    for i in 0..40usize {
        let dim = [1, 2, 3, 5, 30][i % 5];
        let kind = match i % 3 {
            0 => CurveKind::Uniform {
                basis: Basis::CatmullRom,
                ends: Ends::Closed,
            },
            1 => CurveKind::Interpolating {
                condition: EndCondition::NotAKnot,
                t: None,
            },
            _ => CurveKind::Uniform {
                basis: Basis::Beta {
                    bias: 1.2,
                    tension: 0.5,
                },
                ends: Ends::Repeat,
            },
        };
        let curve = Curve::new(kind, rng.points(5 + i % 7, dim, -3.0, 3.0)).unwrap();
        let sampling = match i % 4 {
            0 => Sampling::At(vec![]),
            1 => Sampling::At((0..9).map(|_| rng.range(0.0, 4.0)).collect()),
            _ => Sampling::PerSegment(1 + (i % 9) as u32),
        };
        job.push(&curve, &sampling).unwrap();
    }
    // One long curve, so that thread ranges fall inside it: over a million samples, so that
    // even 64 threads get a part each (a part is at least 16,384 samples).
    let long = Curve::new(
        CurveKind::Uniform {
            basis: Basis::BSpline,
            ends: Ends::Control,
        },
        rng.points(300, 3, -1.0, 1.0),
    )
    .unwrap();
    job.push(&long, &Sampling::PerSegment(3600)).unwrap();
    job
}

#[test]
fn fast_f64_equals_the_reference_bit_for_bit_on_any_thread_count() {
    for derivatives in [Derivatives::None, Derivatives::Second] {
        let job = mixed_job(derivatives);
        let reference = splinegpu::evaluate_reference(&job);
        let mut fast = Samples::<f64>::for_job(&job);
        for threads in [1, 2, 3, 7, 64] {
            splinegpu::evaluate_cpu_into(&job, fast.planes_for(&job), threads);
            assert_eq!(fast, reference, "{threads} threads, {derivatives:?}");
        }
    }
}

#[test]
fn fast_f32_is_the_reference_rounded_once() {
    let job = mixed_job(Derivatives::First);
    let reference = splinegpu::evaluate_reference(&job);
    let mut fast = Samples::<f32>::for_job(&job);
    splinegpu::evaluate_cpu_into(&job, fast.planes_for(&job), 4);
    for c in 0..job.len() {
        let (r, f) = (reference.curve(c), fast.curve(c));
        assert_eq!(r.t, f.t);
        let round = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<_>>();
        assert_eq!(round(r.points), f.points, "curve {c}");
        assert_eq!(round(r.d1.unwrap()), f.d1.unwrap(), "curve {c}");
    }
}

#[test]
#[should_panic(expected = "points holds 3 of")]
fn planes_of_the_wrong_length_are_refused() {
    let job = mixed_job(Derivatives::None);
    let mut points = vec![0.0f32; 3];
    splinegpu::evaluate_cpu_into(&job, Planes::new(&mut points), 2);
}

#[test]
#[should_panic(expected = "the job computes d1, but no plane was given for it")]
fn a_derivative_plane_the_job_needs_is_not_left_out_silently() {
    let job = mixed_job(Derivatives::First);
    let mut points = vec![0.0f64; job.layout().values()];
    splinegpu::evaluate_cpu_into(&job, Planes::new(&mut points), 2);
}

/// A job refitted with moved points (a renderer's frame) equals a job made from them; a refit
/// that would change the knots or the dimension is refused and leaves the curve as it was.
#[test]
fn a_refitted_job_equals_a_new_one_and_a_bad_refit_changes_nothing() {
    let mut rng = Rng(8);
    let closed = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    };
    let curves = |rng: &mut Rng| -> Vec<Curve> {
        (0..5)
            .map(|_| Curve::new(closed.clone(), rng.points(9, 3, -1.0, 1.0)).unwrap())
            .collect()
    };
    let job_of = |curves: &[Curve]| {
        let mut job = EvalJob::new(Derivatives::Second);
        for curve in curves {
            job.push(curve, &Sampling::PerSegment(7)).unwrap();
        }
        job
    };
    let mut job = job_of(&curves(&mut rng));
    let moved = curves(&mut rng);
    for (c, curve) in moved.iter().enumerate() {
        job.refit(c, curve).unwrap();
    }
    assert_eq!(job, job_of(&moved));
    let before = job.clone();
    let fewer = Curve::new(closed.clone(), rng.points(8, 3, -1.0, 1.0)).unwrap();
    let flat = Curve::new(closed, rng.points(9, 2, -1.0, 1.0)).unwrap();
    let uneven = Curve::new(
        CurveKind::Interpolating {
            condition: EndCondition::Periodic,
            t: Some((0..10).map(|i| f64::from(i) * 1.5).collect()),
        },
        {
            let mut p = rng.points(10, 3, -1.0, 1.0).coords().to_vec();
            let first = p[..3].to_vec();
            p[27..].copy_from_slice(&first);
            splinegpu::Points::new(3, p).unwrap()
        },
    )
    .unwrap();
    for bad in [fewer, flat, uneven] {
        let e = job.refit(1, &bad).unwrap_err();
        assert!(e.to_string().contains("points"), "{e}");
        assert_eq!(job, before);
    }
}
