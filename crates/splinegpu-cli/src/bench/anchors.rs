//! The anchors: other libraries on the same work in the same run (kurbo's arc length and
//! flattening, Wang's count), so that our figures sit beside theirs. Bench-only dependencies,
//! reached from here and nowhere in the library.

use std::hint::black_box;
use std::time::Instant;

use splinegpu::{Basis, Sampling, SegmentTable};
use splinegpu::{Curve, Points};
use splinegpu::{Derivatives, EvalJob};

use crate::bench::measure::{Measurement, time};
use crate::bench::workloads::{w1_curves, w1_tolerance};

/// The (x, y) projection of w1's first 100 curves: each as our fitted curve and as kurbo's
/// cubic Béziers (the projection of a Catmull-Rom curve is the Catmull-Rom curve of the
/// projected points).
pub(crate) fn projected_w1() -> Vec<(Curve, Vec<kurbo::CubicBez>)> {
    w1_curves(&Basis::CatmullRom)
        .take(100)
        .map(|curve| {
            let xy: Vec<f64> = curve
                .points()
                .coords()
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1]])
                .collect();
            let kind = curve.kind().clone();
            let projected = Curve::new(kind, Points::new(2, xy).expect("finite")).expect("valid");
            let table = projected.fit();
            let beziers = (0..table.len())
                .map(|i| {
                    let [p0, p1, p2, p3] = (table.segment(i).bezier_points())
                        .expect("the bench's arc-length curves are polynomial");
                    let pt = |p: &[f64]| kurbo::Point::new(p[0], p[1]);
                    kurbo::CubicBez::new(pt(&p0), pt(&p1), pt(&p2), pt(&p3))
                })
                .collect();
            (projected, beziers)
        })
        .collect()
}

/// One timed run of `run` (for the anchors, slow by design), returning its samples.
pub(crate) fn once(run: impl FnOnce() -> u64) -> (f64, u64) {
    let start = Instant::now();
    let samples = black_box(run());
    (start.elapsed().as_secs_f64(), samples)
}

/// Ours beside an anchor: the curves sampled as `sampling` says, planned and evaluated in f64
/// on one thread; returns the samples.
pub(crate) fn ours_1t(
    curves: &[(Curve, Vec<kurbo::CubicBez>)],
    sampling: impl Fn(&Curve) -> Sampling,
) -> u64 {
    let mut job = EvalJob::new(Derivatives::None);
    for (curve, _) in curves {
        job.push(curve, &sampling(curve)).expect("valid");
    }
    let mut out = splinegpu::Samples::<f64>::for_job(&job);
    splinegpu::evaluate_cpu_into(&job, out.planes_for(&job), 1);
    job.sample_count() as u64
}

/// A one-run measurement of `samples` 2-D f64 points.
pub(crate) fn anchor(
    workload: &'static str,
    path: &'static str,
    seconds: f64,
    samples: u64,
) -> Measurement {
    Measurement {
        workload,
        path,
        seconds,
        min_seconds: seconds,
        max_seconds: seconds,
        samples,
        bytes: samples * 16,
        float: Some("f64"),
        misses: None,
        max_error: None,
    }
}

/// w1-arc's anchor: kurbo's `inv_arclen` placing 993 points by arc length on each of the 100
/// projected curves (to 1e-10 of the length, the contract's CPU target being 1e-4), one
/// thread, one run ("kurbo-arclen"); beside it ours on the same curves ("ours-arclen-1t").
pub(crate) fn kurbo_arclen(report: &mut impl FnMut(&Measurement)) {
    use kurbo::ParamCurveArclen;
    let curves = projected_w1();
    let m = 993;
    let (seconds, samples) = once(|| {
        let mut placed = 0u64;
        for (_, beziers) in &curves {
            let rough: f64 = beziers.iter().map(|b| b.arclen(1e-6)).sum();
            let accuracy = 1e-10 * rough;
            let lengths: Vec<f64> = beziers.iter().map(|b| b.arclen(accuracy)).collect();
            let total: f64 = lengths.iter().sum();
            let (mut segment, mut start) = (0, 0.0);
            for j in 0..m {
                let target = total * j as f64 / (m - 1) as f64;
                while segment + 1 < beziers.len() && start + lengths[segment] < target {
                    start += lengths[segment];
                    segment += 1;
                }
                black_box(beziers[segment].inv_arclen(target - start, accuracy));
                placed += 1;
            }
        }
        placed
    });
    report(&anchor("w1-arc", "kurbo-arclen", seconds, samples));
    let (seconds, samples) = once(|| ours_1t(&curves, |_| Sampling::ArcLength(m as u32)));
    report(&anchor("w1-arc", "ours-arclen-1t", seconds, samples));
}

/// w1-tol's anchor: kurbo's `flatten` of the 100 projected curves, each at 1e-3 of its
/// extent, its points counted ("kurbo-flatten", one run); beside it ours on the same curves
/// and tolerances ("ours-flatten").
pub(crate) fn kurbo_flatten(report: &mut impl FnMut(&Measurement)) {
    let curves = projected_w1();
    let (seconds, samples) = once(|| {
        let mut points = 0u64;
        for (curve, beziers) in &curves {
            let mut path = kurbo::BezPath::new();
            path.move_to(beziers[0].p0);
            for b in beziers {
                path.curve_to(b.p1, b.p2, b.p3);
            }
            kurbo::flatten(path, w1_tolerance(curve), |_| points += 1);
        }
        points
    });
    report(&anchor("w1-tol", "kurbo-flatten", seconds, samples));
    let (seconds, samples) =
        once(|| ours_1t(&curves, |curve| Sampling::Tolerance(w1_tolerance(curve))));
    report(&anchor("w1-tol", "ours-flatten", seconds, samples));
}

/// w1-tol's "wang" path: Wang's count for the same curves and tolerances (its "samples"), and
/// the time to count.
pub(crate) fn wang(report: &mut impl FnMut(&Measurement)) {
    let curves: Vec<(SegmentTable, f64)> = w1_curves(&Basis::CatmullRom)
        .map(|c| (c.fit(), w1_tolerance(&c)))
        .collect();
    let mut samples = 0u64;
    let (seconds, min_seconds, max_seconds) = time(|| {
        // Per curve, Wang's count on every segment, then the final point.
        samples = curves
            .iter()
            .map(|(table, tol)| {
                let segments: u64 = (0..table.len())
                    .map(|s| splinegpu::wang_count(&table.segment(s), *tol) as u64)
                    .sum();
                segments + 1
            })
            .sum();
        black_box(samples);
        None
    });
    report(&Measurement {
        workload: "w1-tol",
        path: "wang",
        seconds,
        min_seconds,
        max_seconds,
        samples,
        bytes: 0,
        float: None,
        misses: None,
        max_error: None,
    });
}
