//! The query workloads: q1, the closest points of 100,000 points on 100 open Catmull-Rom
//! curves of 16 2-D points, each path the whole call (the curves fitted, the index built, every
//! point answered into new arrays); beside it the plain loop (the same exact solve on every
//! segment, no index) and kurbo's `nearest` on every segment, both for the first 1,000 points
//! and scaled to all, kurbo's misses counted against our certified answers.

use std::hint::black_box;

use splinegpu::query::{ClosestPoints, CurveIndex, closest_on_segment};
use splinegpu::{Basis, Curve, CurveKind, Ends, Points, SegmentTable};

use crate::bench::anchors::once;
use crate::bench::measure::{Measurement, memset, time};
use crate::bench::workloads::Rng;

/// q1's curves: 100 open Catmull-Rom curves of 16 points in [0, 100]².
fn q1_curves() -> Vec<Curve> {
    let mut rng = Rng(46);
    (0..100)
        .map(|_| {
            let coords = (0..16 * 2).map(|_| rng.range(0.0, 100.0)).collect();
            let kind = CurveKind::Uniform {
                basis: Basis::CatmullRom,
                ends: Ends::Repeat,
            };
            Curve::new(kind, Points::new(2, coords).expect("finite")).expect("16 points")
        })
        .collect()
}

/// q1's 100,000 query points, uniform in the curves' points' bounding box.
fn q1_points(curves: &[Curve]) -> Vec<f64> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in curves
        .iter()
        .flat_map(|c| c.points().coords().chunks_exact(2))
    {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let mut rng = Rng(47);
    (0..100_000)
        .flat_map(|_| [rng.range(lo[0], hi[0]), rng.range(lo[1], hi[1])])
        .collect()
}

/// The whole library call: fit, index, answer.
fn closest(curves: &[Curve], points: &[f64]) -> ClosestPoints {
    let tables: Vec<SegmentTable> = curves.iter().map(Curve::fit).collect();
    let index = CurveIndex::new(&tables).expect("one dimension");
    index.closest_many(points).expect("finite points")
}

/// Points the plain loop and kurbo answer (the rest is scaled from them).
const ANCHOR_POINTS: usize = 1_000;

/// Bytes of one answer: curve (int64), t, a 2-D point and the distance.
const ANSWER_BYTES: u64 = 8 + 8 + 16 + 8;

pub(crate) fn q1(report: &mut impl FnMut(&Measurement)) {
    let curves = q1_curves();
    let points = q1_points(&curves);
    let count = (points.len() / 2) as u64;
    report(&memset("q1", (count * ANSWER_BYTES) as usize));
    let measurement = |path, (seconds, min_seconds, max_seconds), misses| Measurement {
        workload: "q1",
        path,
        seconds,
        min_seconds,
        max_seconds,
        samples: count,
        bytes: count * ANSWER_BYTES,
        float: Some("f64"),
        misses,
    };
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread");
    let cpu_1t = time(|| {
        one_thread.install(|| black_box(closest(&curves, &points)));
        None
    });
    report(&measurement("cpu-1t", cpu_1t, None));
    let cpu_all = time(|| {
        black_box(closest(&curves, &points));
        None
    });
    report(&measurement("cpu-all", cpu_all, None));
    let certified = closest(&curves, &points);
    let first = &points[..2 * ANCHOR_POINTS];
    let scale = count as f64 / ANCHOR_POINTS as f64;
    let scaled = |seconds: f64| (seconds * scale, seconds * scale, seconds * scale);

    // The plain loop: every point against every segment with the same exact solve.
    let tables: Vec<SegmentTable> = curves.iter().map(Curve::fit).collect();
    let (seconds, _) = once(|| {
        let mut answered = 0;
        for q in first.chunks_exact(2) {
            let best = tables
                .iter()
                .flat_map(|table| (0..table.len()).map(move |s| table.segment(s)))
                .map(|segment| closest_on_segment(&segment, q).1)
                .fold(f64::INFINITY, f64::min);
            black_box(best);
            answered += 1;
        }
        answered
    });
    report(&measurement("plain-loop", scaled(seconds), None));

    // kurbo: its nearest on every segment as a cubic Bezier, to 1e-9.
    let beziers: Vec<kurbo::CubicBez> = tables
        .iter()
        .flat_map(|table| (0..table.len()).map(move |s| table.segment(s)))
        .map(|segment| {
            let [p0, p1, p2, p3] = segment.bezier_points().expect("polynomial");
            let pt = |p: &[f64]| kurbo::Point::new(p[0], p[1]);
            kurbo::CubicBez::new(pt(&p0), pt(&p1), pt(&p2), pt(&p3))
        })
        .collect();
    let mut kurbo_distances = Vec::with_capacity(ANCHOR_POINTS);
    let (seconds, _) = once(|| {
        use kurbo::ParamCurveNearest;
        for q in first.chunks_exact(2) {
            let p = kurbo::Point::new(q[0], q[1]);
            let best = beziers
                .iter()
                .map(|b| b.nearest(p, 1e-9).distance_sq)
                .fold(f64::INFINITY, f64::min);
            kurbo_distances.push(best.sqrt());
        }
        ANCHOR_POINTS as u64
    });
    let extent = 100.0;
    let misses = kurbo_distances
        .iter()
        .zip(&certified.distance)
        .filter(|(k, ours)| **k > **ours + 1e-9 * extent)
        .count() as u64;
    report(&measurement("kurbo", scaled(seconds), Some(misses)));
}
