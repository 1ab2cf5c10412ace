//! The query workloads, each path the whole call (the curves fitted, the index built, every
//! answer into new arrays):
//! - q1, the closest points of 100,000 points on 100 open Catmull-Rom curves of 16 2-D
//!   points, on the CPU and (given a GPU) gpu-device (the kernel's dispatches) and
//!   gpu-end-to-end (the whole call, fit to f32 answers); beside it the plain loop (the same exact solve on every segment, no index) and
//!   kurbo's `nearest` on every segment, both for the first 1,000 points and scaled to all,
//!   kurbo's misses counted against our certified answers;
//! - q2, every intersection among 1,000 open Catmull-Rom curves of 16 2-D points (random walks
//!   from uniform starts, so that each meets its neighbours); beside it lyon_geom's
//!   cubic-cubic intersections on every pair of segments of two curves whose boxes overlap
//!   (found by a sweep), one thread, the certified intersections it did not report counted.

use std::hint::black_box;

use splinegpu::query::{
    ClosestPoints, CurveIndex, Intersection, Pairs, QueryError, closest_on_segment, intersections,
};
use splinegpu::{Basis, Curve, CurveKind, Ends, GpuContext, Points, SegmentTable};

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

pub(crate) fn q1(
    gpu: Option<&GpuContext>,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), QueryError> {
    let curves = q1_curves();
    let points = q1_points(&curves);
    let count = (points.len() / 2) as u64;
    report(&memset("q1", (count * ANSWER_BYTES) as usize));
    let measurement = |path, times, misses| answers("q1", path, times, count, ANSWER_BYTES, misses);
    whole_call(&measurement, report, || {
        black_box(closest(&curves, &points));
    });
    let certified = closest(&curves, &points);
    if let Some(gpu) = gpu {
        q1_gpu(gpu, &curves, &points, &certified, report)?;
    }
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
    Ok(())
}

/// q1's gpu-device (the dispatches, timed on the device) and gpu-end-to-end (fit, index,
/// pack, upload, answer, read back), the GPU's answers farther than the contract's GPU bound
/// from the certified ones counted as misses.
fn q1_gpu(
    gpu: &GpuContext,
    curves: &[Curve],
    points: &[f64],
    certified: &ClosestPoints,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), QueryError> {
    let count = certified.len() as u64;
    let measurement = |path, times, misses| Measurement {
        float: Some("f32"),
        ..answers("q1", path, times, count, ANSWER_BYTES, misses)
    };
    let tables: Vec<SegmentTable> = curves.iter().map(Curve::fit).collect();
    let index = CurveIndex::new(&tables)?;
    let mut failure = None;
    let device = time(|| match gpu.closest_points_timed(&index, points) {
        Ok((found, device)) => {
            black_box(found);
            Some(device.seconds)
        }
        Err(e) => {
            failure.get_or_insert(e);
            None
        }
    });
    if let Some(e) = failure {
        return Err(e);
    }
    report(&measurement("gpu-device", device, None));
    let whole = || -> Result<ClosestPoints<f32>, QueryError> {
        let tables: Vec<SegmentTable> = curves.iter().map(Curve::fit).collect();
        gpu.closest_points(&CurveIndex::new(&tables)?, points)
    };
    let end_to_end = time(|| {
        if let Err(e) = whole().map(black_box) {
            failure.get_or_insert(e);
        }
        None
    });
    if let Some(e) = failure {
        return Err(e);
    }
    // The contract's bound, with the curves' position bound taken as 1e-6 of the extent
    // (100; the f32 spacing of coordinates below 128 is 2^-17, below 1e-5 of it).
    let extent = 100.0;
    let found = whole()?;
    let misses = found
        .distance
        .iter()
        .zip(&certified.distance)
        .zip(points.chunks_exact(2))
        .filter(|&((&gpu, &ours), q)| {
            let q = q[0].abs().max(q[1].abs());
            (f64::from(gpu) - ours).abs() > 1e-5 * (extent + q) + 1e-6 * extent
        })
        .count() as u64;
    report(&measurement("gpu-end-to-end", end_to_end, Some(misses)));
    Ok(())
}

/// A measurement of `count` answers of `bytes` each (f64 numbers) on `path`.
fn answers(
    workload: &'static str,
    path: &'static str,
    (seconds, min_seconds, max_seconds): (f64, f64, f64),
    count: u64,
    bytes: u64,
    misses: Option<u64>,
) -> Measurement {
    Measurement {
        workload,
        path,
        seconds,
        min_seconds,
        max_seconds,
        samples: count,
        bytes: count * bytes,
        float: Some("f64"),
        misses,
        max_error: None,
    }
}

/// cpu-1t and cpu-all: the whole call `run` timed on a pool of one thread, then on all.
fn whole_call(
    measurement: &impl Fn(&'static str, (f64, f64, f64), Option<u64>) -> Measurement,
    report: &mut impl FnMut(&Measurement),
    run: impl Fn() + Sync,
) {
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread");
    let cpu_1t = time(|| {
        one_thread.install(&run);
        None
    });
    report(&measurement("cpu-1t", cpu_1t, None));
    let cpu_all = time(|| {
        run();
        None
    });
    report(&measurement("cpu-all", cpu_all, None));
}

/// q2's curves: 1,000 open Catmull-Rom curves of 16 points, each a random walk from a uniform
/// start in [0, 100]² with steps uniform in [-5, 5] on each axis.
fn q2_curves() -> Vec<Curve> {
    let mut rng = Rng(48);
    (0..1000)
        .map(|_| {
            let mut p = [rng.range(0.0, 100.0), rng.range(0.0, 100.0)];
            let mut coords = Vec::with_capacity(32);
            for _ in 0..16 {
                coords.extend_from_slice(&p);
                p = [p[0] + rng.range(-5.0, 5.0), p[1] + rng.range(-5.0, 5.0)];
            }
            let kind = CurveKind::Uniform {
                basis: Basis::CatmullRom,
                ends: Ends::Repeat,
            };
            Curve::new(kind, Points::new(2, coords).expect("finite")).expect("16 points")
        })
        .collect()
}

/// Bytes of one intersection: i, j (int64), t_i, t_j, a 2-D point, two booleans.
const CROSSING_BYTES: u64 = 8 + 8 + 8 + 8 + 16 + 1 + 1;

/// The whole library call: fit, index, every pair.
fn crossings(curves: &[Curve]) -> Vec<Intersection> {
    let tables: Vec<SegmentTable> = curves.iter().map(Curve::fit).collect();
    intersections(&tables, Pairs::All).expect("2-D curves")
}

pub(crate) fn q2(report: &mut impl FnMut(&Measurement)) {
    let curves = q2_curves();
    let certified = crossings(&curves);
    let count = certified.len() as u64;
    report(&memset("q2", (count * CROSSING_BYTES) as usize));
    let measurement =
        |path, times, misses| answers("q2", path, times, count, CROSSING_BYTES, misses);
    whole_call(&measurement, report, || {
        black_box(crossings(&curves));
    });

    // lyon_geom: every segment as a cubic Bezier with its curve's index.
    use lyon_geom::{CubicBezierSegment, point};
    let segments: Vec<(usize, CubicBezierSegment<f64>)> = curves
        .iter()
        .enumerate()
        .flat_map(|(c, curve)| {
            let table = curve.fit();
            (0..table.len())
                .map(|s| {
                    let [p0, p1, p2, p3] = table.segment(s).bezier_points().expect("polynomial");
                    let pt = |p: &[f64]| point(p[0], p[1]);
                    let bezier = CubicBezierSegment {
                        from: pt(&p0),
                        ctrl1: pt(&p1),
                        ctrl2: pt(&p2),
                        to: pt(&p3),
                    };
                    (c, bezier)
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let mut lyon_points: Vec<[f64; 2]> = Vec::new();
    let (seconds, _) = once(|| {
        lyon_points.clear();
        // A sweep along x over the segments' boxes.
        let boxes: Vec<_> = segments
            .iter()
            .map(|(_, b)| b.fast_bounding_box())
            .collect();
        let mut order: Vec<usize> = (0..segments.len()).collect();
        order.sort_by(|&a, &b| boxes[a].min.x.total_cmp(&boxes[b].min.x));
        let mut active: Vec<usize> = Vec::new();
        for &a in &order {
            active.retain(|&b| boxes[b].max.x >= boxes[a].min.x);
            for &b in &active {
                let (ca, cb) = (segments[a].0, segments[b].0);
                if ca == cb || !boxes[a].intersects(&boxes[b]) && !touching(&boxes[a], &boxes[b]) {
                    continue;
                }
                for (t, _) in segments[a].1.cubic_intersections_t(&segments[b].1) {
                    let p = segments[a].1.sample(t);
                    lyon_points.push([p.x, p.y]);
                }
            }
            active.push(a);
        }
        lyon_points.len() as u64
    });
    // Ours missed by lyon: no lyon point within 1e-6 of the extent (100) of it.
    let tolerance = 1e-4;
    let cell = |p: [f64; 2]| {
        (
            (p[0] / tolerance).floor() as i64,
            (p[1] / tolerance).floor() as i64,
        )
    };
    let mut grid: std::collections::HashMap<(i64, i64), Vec<[f64; 2]>> = Default::default();
    for &p in &lyon_points {
        grid.entry(cell(p)).or_default().push(p);
    }
    let misses = certified
        .iter()
        .filter(|x| !x.overlap)
        .filter(|x| {
            let (cx, cy) = cell(x.point);
            let near = (cx - 1..=cx + 1).any(|i| {
                (cy - 1..=cy + 1).any(|j| {
                    grid.get(&(i, j)).is_some_and(|ps| {
                        ps.iter()
                            .any(|p| (p[0] - x.point[0]).hypot(p[1] - x.point[1]) <= tolerance)
                    })
                })
            });
            !near
        })
        .count() as u64;
    report(&measurement(
        "lyon",
        (seconds, seconds, seconds),
        Some(misses),
    ));
}

/// Whether two boxes touch (share an edge or a corner), which lyon's `intersects` (strict)
/// leaves out.
fn touching(
    a: &lyon_geom::euclid::default::Box2D<f64>,
    b: &lyon_geom::euclid::default::Box2D<f64>,
) -> bool {
    a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y
}
