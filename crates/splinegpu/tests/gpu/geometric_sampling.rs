//! Arc-length places found by the GPU (each sample's segment and u from the host's tables,
//! in f32) against an independent quadrature, within 3e-5 of the length, and the values at
//! them within the accuracy promise.

use crate::arc_lengths::{DIMS, curves, spacing_error};
use splinegpu::{Derivatives, EvalJob, Sampling};

pub(crate) fn arc_length_samples_placed_by_the_gpu_are_evenly_spaced_within_3e_5_of_the_length() {
    // The kernel finds each sample's segment and u from the host's tables in f32; the host
    // forms t from them in f64. Same curves as the CPU's 1e-10 test.
    let Some(context) = crate::support::gpu() else {
        return;
    };
    let m = 37;
    let mut worst = 0.0f64;
    for dim in DIMS {
        let mut job = EvalJob::new(Derivatives::Second);
        for curve in curves(dim) {
            job.push(&curve, &Sampling::ArcLength(m)).unwrap();
        }
        let gpu = context.evaluate(&job).unwrap();
        for c in 0..job.len() {
            let ts = gpu.curve(c).t;
            let table = job.table(c);
            let (t0, t1) = table.t_range();
            assert_eq!(
                (ts[0], ts[ts.len() - 1]),
                (t0, t1),
                "D {dim} curve {c}: ends"
            );
            assert!(
                ts.windows(2).all(|w| w[0] <= w[1]),
                "D {dim} curve {c}: order"
            );
            let (_, error) = spacing_error(table, ts);
            worst = worst.max(error);
            assert!(error <= 3e-5, "D {dim}, curve {c}: {error:e} of L");
        }
        // The points and derivatives are those at the GPU's t, within the promise.
        let reference = splinegpu::evaluate_reference(&job);
        let within = crate::support::compare(&job, &reference, &gpu);
        assert!(within.ratio <= 1.0, "D {dim}: {within:?}");
    }
    // Counts from 2 up, on every curve of one dimension.
    for m in [2, 3, 17, 59] {
        let mut job = EvalJob::new(Derivatives::None);
        for curve in curves(2) {
            job.push(&curve, &Sampling::ArcLength(m)).unwrap();
        }
        let gpu = context.evaluate(&job).unwrap();
        for c in 0..job.len() {
            let (_, error) = spacing_error(job.table(c), gpu.curve(c).t);
            worst = worst.max(error);
            assert!(error <= 3e-5, "m {m}, curve {c}: {error:e} of L");
        }
    }
    eprintln!("worst GPU arc-length spacing error: {worst:.2e} of L");
}
