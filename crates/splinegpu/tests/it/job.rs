//! Building a job: `push_many` (fitted and planned on every thread) makes the job that pushing
//! the curves one by one makes, and a bad curve among many is named by its index in the job.

use crate::support::Rng;
use splinegpu::{Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, Sampling};

fn curves(count: usize) -> Vec<(Curve, Sampling)> {
    let mut rng = Rng(5);
    (0..count)
        .map(|i| {
            let kind = CurveKind::Uniform {
                basis: if i % 2 == 0 {
                    Basis::CatmullRom
                } else {
                    Basis::BSpline
                },
                ends: Ends::Control,
            };
            let curve = Curve::new(kind, rng.points(4 + i % 9, 1 + i % 3, -5.0, 5.0)).unwrap();
            let sampling = match i % 3 {
                0 => Sampling::At((0..7).map(|_| rng.range(0.0, 1.0)).collect()),
                _ => Sampling::PerSegment(1 + (i % 17) as u32),
            };
            (curve, sampling)
        })
        .collect()
}

#[test]
fn push_many_makes_the_job_that_pushing_one_by_one_makes() {
    let curves = curves(500);
    let mut one_by_one = EvalJob::new(Derivatives::First);
    let mut many = EvalJob::new(Derivatives::First);
    for (curve, sampling) in &curves[..3] {
        one_by_one.push(curve, sampling).unwrap();
        many.push(curve, sampling).unwrap();
    }
    for (curve, sampling) in &curves[3..] {
        one_by_one.push(curve, sampling).unwrap();
    }
    many.push_many(&curves[3..]).unwrap();
    assert_eq!(many, one_by_one);
}

#[test]
fn a_bad_curve_in_push_many_is_named_by_its_index_in_the_job_which_stays_unchanged() {
    let mut curves = curves(40);
    // Curve 31 of the slice (33 of the job) asks for a t past its end.
    curves[31].1 = Sampling::At(vec![0.5, 1e9]);
    let mut job = EvalJob::new(Derivatives::None);
    job.push(&curves[0].0, &curves[0].1).unwrap();
    job.push(&curves[1].0, &curves[1].1).unwrap();
    let before = job.clone();
    let error = job.push_many(&curves).unwrap_err().to_string();
    assert!(error.starts_with("curve 33:"), "{error}");
    assert!(error.contains("1000000000"), "{error}");
    assert_eq!(job, before);
}
