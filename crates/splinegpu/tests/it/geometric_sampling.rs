//! Sampling by geometry: arc-length spacing against an independent quadrature, and tolerance
//! sampling against dense f64 sampling of every chord, on every family, end convention and
//! dimension, with uneven knots, far from the origin, at cusps and where the curve stands
//! still (the GPU's own arc-length places are tests/gpu/geometric_sampling.rs's).

use crate::arc_lengths::{DIMS, curves, lengths_at, spacing_error, uniform_kinds};
use crate::support::{Rng, assert_gpu_matches_cpu};
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, EndCondition, Ends, EvalJob, PerPoint, Points, Sampling,
    wang_count,
};

#[test]
fn arc_length_samples_are_evenly_spaced_within_1e_5_of_the_length() {
    let m = 37;
    let mut worst = 0.0f64;
    for dim in DIMS {
        for (c, curve) in curves(dim).iter().enumerate() {
            let mut job = EvalJob::new(Derivatives::First);
            job.push(curve, &Sampling::ArcLength(m)).unwrap();
            let samples = splinegpu::evaluate_reference(&job);
            let ts = samples.curve(0).t;
            assert_eq!(ts.len(), m as usize);
            let table = job.table(0);
            let (t0, t1) = table.t_range();
            assert_eq!(
                (ts[0], ts[ts.len() - 1]),
                (t0, t1),
                "the ends are the curve's"
            );
            assert!(ts.windows(2).all(|w| w[0] <= w[1]), "t in order");
            let (total, error) = spacing_error(table, ts);
            worst = worst.max(error);
            // The explicit inverse: within 1e-5 L (the contract asks 1e-4 L of the CPU).
            assert!(error <= 1e-5, "D {dim}, curve {c}: {error:e} of L");
            // The library's length agrees with the independent one.
            let length = table.arclen(splinegpu::DEFAULT_ARCLEN_ACCURACY);
            assert!(
                (length - total).abs() <= 1e-10 * total,
                "D {dim} curve {c}: {length} vs {total}"
            );
        }
    }
    eprintln!("worst arc-length spacing error: {worst:.2e} of L");
}

#[test]
fn the_parameter_at_a_length_inverts_the_length() {
    let curve = &curves(3)[1];
    let table = curve.fit();
    let total = table.arclen(1e-13);
    for frac in [0.0, 0.01, 0.25, 0.5, 0.999, 1.0] {
        let t = table.inv_arclen(frac * total, 1e-13);
        let s = lengths_at(&table, &[table.t_range().0, t], 1e-15 * total)[1];
        assert!((s - frac * total).abs() <= 1e-10 * total, "{frac}: {s}");
    }
    // Each segment's length, summed, is the curve's.
    let parts: f64 = table.segment_arclens(1e-13).iter().sum();
    assert!((parts - total).abs() <= 1e-12 * total);
}

#[test]
fn the_memos_chord_polygon_converges_to_the_arc_length_from_below() {
    // Smith's memo marks equal lengths off the polygon through many samples per segment: its
    // length never exceeds the curve's, and tends to it as the samples grow denser.
    let curve = &curves(2)[1];
    let table = curve.fit();
    let length = table.arclen(1e-13);
    let mut last_gap = f64::INFINITY;
    for grain in [10u32, 100, 1000, 10_000] {
        let mut job = EvalJob::new(Derivatives::None);
        job.push(curve, &Sampling::PerSegment(grain)).unwrap();
        let samples = splinegpu::evaluate_reference(&job);
        let p = samples.curve(0).points;
        let polygon: f64 = p
            .chunks_exact(2)
            .zip(p.chunks_exact(2).skip(1))
            .map(|(a, b)| ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt())
            .sum();
        let gap = length - polygon;
        assert!(
            gap >= -1e-12 * length,
            "grain {grain}: the polygon is shorter"
        );
        assert!(gap < last_gap, "grain {grain}: closer than before");
        last_gap = gap;
    }
    assert!(last_gap < 1e-7 * length);
}

/// The curve's own size: the largest per-axis range of its samples (64 per segment), which can
/// be far larger than its points' extent (an interpolating curve on very uneven knots
/// overshoots).
fn size(curve: &Curve) -> f64 {
    let mut job = EvalJob::new(Derivatives::None);
    job.push(curve, &Sampling::PerSegment(64)).unwrap();
    let samples = splinegpu::evaluate_reference(&job);
    let s = samples.curve(0);
    (0..s.dim)
        .map(|k| {
            let axis = s.points.iter().skip(k).step_by(s.dim);
            let (lo, hi) = axis.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
            hi - lo
        })
        .fold(1e-3, f64::max)
}

/// Distance from `p` to the segment from `a` to `b`.
fn distance_to_chord(p: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let ab: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let ap: Vec<f64> = a.iter().zip(p).map(|(x, y)| y - x).collect();
    let len2: f64 = ab.iter().map(|v| v * v).sum();
    let s = if len2 > 0.0 {
        (ap.iter().zip(&ab).map(|(x, y)| x * y).sum::<f64>() / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ap.iter()
        .zip(&ab)
        .map(|(x, y)| (x - s * y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Checks every chord of a tolerance-sampled curve by dense f64 sampling, and the count of
/// every segment against Wang's; returns (count, Wang's count).
fn check_tolerance(curve: &Curve, tol: f64) -> (usize, usize) {
    let mut job = EvalJob::new(Derivatives::None);
    job.push(curve, &Sampling::Tolerance(tol)).unwrap();
    let plan = job.plan(0);
    let table = job.table(0);
    let dim = table.dim();
    let locs: Vec<_> = (0..plan.len()).map(|i| plan.loc(i)).collect();
    assert_eq!(locs[0].u, 0.0);
    let last = locs[locs.len() - 1];
    assert_eq!(
        (last.segment, last.u),
        (table.len() - 1, 1.0),
        "ends with the final point"
    );
    let (mut count, mut wang) = (0, 0);
    for s in 0..table.len() {
        let segment = table.segment(s);
        let mut us: Vec<f64> = locs
            .iter()
            .filter(|l| l.segment == s && l.u < 1.0)
            .map(|l| l.u)
            .collect();
        assert_eq!(us[0], 0.0, "segment {s} starts at u = 0");
        let n = us.len();
        count += n;
        let w = wang_count(&segment, tol) as usize;
        wang += w;
        assert!(n <= w, "segment {s}: {n} samples, Wang {w}");
        us.push(1.0);
        let point = |u: f64| {
            let mut p = vec![0.0; dim];
            segment.eval(u, &mut p);
            p
        };
        for pair in us.windows(2) {
            assert!(pair[0] < pair[1], "increasing u");
            let (a, b) = (point(pair[0]), point(pair[1]));
            for i in 1..200 {
                let u = pair[0] + (pair[1] - pair[0]) * f64::from(i) / 200.0;
                let d = distance_to_chord(&point(u), &a, &b);
                assert!(d <= tol * (1.0 + 1e-9), "segment {s}, u {u}: {d} > {tol}");
            }
        }
    }
    (count, wang)
}

#[test]
fn tolerance_samples_keep_every_chord_within_tol_and_never_exceed_wang() {
    let (mut count, mut wang) = (0, 0);
    for dim in DIMS {
        for (c, curve) in curves(dim).iter().enumerate() {
            let size = size(curve);
            for rel in [1e-1, 1e-2, 1e-3] {
                let tol = rel * size;
                let (n, w) = check_tolerance(curve, tol);
                assert!(n <= w, "D {dim}, curve {c}");
                count += n;
                wang += w;
            }
        }
    }
    eprintln!(
        "tolerance sampling: {count} samples, Wang {wang} ({:.3}x)",
        count as f64 / wang as f64
    );
}

#[test]
fn tolerance_sampling_needs_fewer_samples_than_wang_on_w1_like_curves() {
    // 200 of w1's kind of curve (Catmull-Rom, 34 points in ±100, 3-D), each at 1e-3 of its
    // own extent: the count against Wang's, with every chord checked.
    let mut rng = Rng(1);
    let (mut count, mut wang) = (0, 0);
    for _ in 0..200 {
        let kind = CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Control,
        };
        let curve = Curve::new(kind, rng.points(34, 3, -100.0, 100.0)).unwrap();
        let tol = 1e-3 * curve.points().extent();
        let (n, w) = check_tolerance(&curve, tol);
        count += n;
        wang += w;
    }
    let ratio = count as f64 / wang as f64;
    eprintln!("w1-like curves at 1e-3 of their extent: {count} samples, Wang {wang} ({ratio:.3}x)");
    assert!(ratio < 1.0);
}

/// Arc-length and tolerance samplings of every kind, cut into chunks anywhere: every sample
/// once with the whole job's t, and the fast evaluator equal to the reference; the job.
fn geometric_samplings_chunked() -> EvalJob {
    let mut job = EvalJob::new(Derivatives::Second);
    for dim in [1, 3, 30] {
        for curve in curves(dim) {
            job.push(&curve, &Sampling::ArcLength(29)).unwrap();
            job.push(&curve, &Sampling::Tolerance(1e-2 * size(&curve)))
                .unwrap();
        }
    }
    // Chunks cut anywhere give every sample once, with the whole job's t.
    let whole = splinegpu::evaluate_reference(&job);
    let mut seen = vec![Vec::new(); job.len()];
    for chunk in job.chunks(17) {
        let part = splinegpu::evaluate_reference(&chunk.job);
        for (c, piece) in chunk.pieces.iter().enumerate() {
            assert_eq!(seen[piece.curve].len(), piece.first_sample);
            seen[piece.curve].extend_from_slice(part.curve(c).t);
        }
    }
    for (c, seen) in seen.iter().enumerate() {
        assert_eq!(seen.as_slice(), whole.curve(c).t);
    }
    // The fast evaluator equals the reference; the GPU keeps the promise at the same places.
    let mut fast = splinegpu::Samples::<f64>::for_job(&job);
    splinegpu::evaluate_cpu_into(&job, fast.planes_for(&job), 2);
    assert_eq!(fast, whole);
    job
}

#[test]
fn geometric_samplings_chunk_and_evaluate_alike() {
    geometric_samplings_chunked();
}

#[allow(
    dead_code,
    reason = "a trial of the GPU harness (tests/gpu/main.rs), which includes this file"
)]
pub(crate) fn geometric_samplings_evaluate_on_the_gpu_within_the_promise() {
    assert_gpu_matches_cpu(&geometric_samplings_chunked());
}

mod random_curves {
    //! Random curves of every family: spacing within 1e-10 of the length against the
    //! independent quadrature (1e-5 where the GPU places the samples); every tolerance chord within tol; no segment above Wang's count.
    //! 16 arc-length cases (each integrates its curve densely for the reference: about 2 s a
    //! case) and 64 tolerance cases here; PROPTEST_CASES sets both for a longer run.

    use super::*;
    use proptest::prelude::*;

    fn config(default_cases: u32) -> ProptestConfig {
        let cases = std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default_cases);
        ProptestConfig {
            cases,
            failure_persistence: None,
            ..ProptestConfig::default()
        }
    }

    /// A random curve: a family (every uniform kind, local bias and tension, Bezier, and the
    /// interpolating ends),
    /// D in {1, 2, 3, 5}, 4 to 9 points in ±10 (shifted to near 1e5 one time in four).
    fn curve() -> impl Strategy<Value = Curve> {
        (
            0usize..27,
            0usize..4,
            4usize..10,
            any::<bool>(),
            prop::collection::vec(-10.0f64..10.0, 64 * 5),
        )
            .prop_map(|(family, d, n, far, pool)| {
                let dim = [1, 2, 3, 5][d];
                let shift = if far && family % 4 == 0 { 1e5 } else { 0.0 };
                let coords = |n: usize| -> Vec<f64> {
                    (0..n * dim).map(|i| pool[i % pool.len()] + shift).collect()
                };
                let kinds = uniform_kinds();
                if let Some(e) = family.checked_sub(kinds.len()).filter(|&e| e < 3) {
                    // Local bias and tension: b1 in [0.1, 10], b2 in [0, 10] at each joint.
                    let ends = [Ends::Control, Ends::Repeat, Ends::Closed][e];
                    let joints = if ends == Ends::Control { n - 2 } else { n };
                    let kind = CurveKind::LocalBeta {
                        ends,
                        bias: PerPoint::Each(
                            (0..joints).map(|j| 10f64.powf(pool[j] / 10.0)).collect(),
                        ),
                        tension: PerPoint::Each((0..joints).map(|j| pool[n + j].abs()).collect()),
                    };
                    return Curve::new(kind, Points::new(dim, coords(n)).unwrap()).unwrap();
                }
                if family < kinds.len() {
                    let kind = kinds[family].clone();
                    let n = if kind == CurveKind::Bezier {
                        3 * (n / 3) + 1
                    } else {
                        n
                    };
                    return Curve::new(kind, Points::new(dim, coords(n)).unwrap()).unwrap();
                }
                let mut knots = vec![0.0];
                for i in 1..n {
                    knots.push(knots[i - 1] + 10f64.powf(pool[i] / 4.0));
                }
                let condition = match family % 3 {
                    0 => EndCondition::Natural,
                    1 => EndCondition::NotAKnot,
                    _ => EndCondition::Clamped {
                        start: coords(1),
                        end: coords(1),
                    },
                };
                let kind = CurveKind::Interpolating {
                    condition,
                    t: Some(knots),
                };
                Curve::new(kind, Points::new(dim, coords(n)).unwrap()).unwrap()
            })
    }

    proptest! {
        #![proptest_config(config(16))]

        #[test]
        fn arc_length_spacing_meets_1e_5_of_the_length(curve in curve(), m in 2u32..60) {
            super::assert_arc_spacing(&curve, m);
        }
    }

    proptest! {
        #![proptest_config(config(64))]

        #[test]
        fn tolerance_chords_meet_tol_and_counts_never_exceed_wang(
            curve in curve(),
            relative in 1e-3f64..1e-1,
        ) {
            let (n, w) = check_tolerance(&curve, relative * size(&curve));
            prop_assert!(n <= w);
        }
    }
}

/// A segment that stands still (three equal points windowed by the Bezier matrix) has a
/// length model whose ends differ by a rounding below 0: its inverse took that as the
/// length to clamp to, and panicked (the property test above met it once in ~2,000 runs).
#[test]
fn a_segment_of_length_zero_is_placed_without_a_panic() {
    let bezier = Basis::Matrix([
        [-1.0, 3.0, -3.0, 1.0],
        [3.0, -6.0, 3.0, 0.0],
        [-3.0, 3.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
    ]);
    let kind = CurveKind::Uniform {
        basis: bezier,
        ends: Ends::Repeat,
    };
    let points = vec![
        0.0,
        0.0,
        0.0,
        -1.0995758933572848,
        1.5728417360929017,
        -2.35949201790612,
    ];
    let curve = Curve::new(kind, Points::new(1, points).unwrap()).unwrap();
    for m in [2, 3, 17] {
        assert_arc_spacing(&curve, m);
    }
}

/// `curve`'s m arc-length samples lie within 1e-5 L of j L / (m - 1), against the independent
/// quadrature.
fn assert_arc_spacing(curve: &Curve, m: u32) {
    let mut job = EvalJob::new(Derivatives::None);
    job.push(curve, &Sampling::ArcLength(m)).unwrap();
    let table = job.table(0);
    let ts: Vec<f64> = (0..m as usize).map(|j| job.plan(0).loc(j).t).collect();
    let (t0, t1) = table.t_range();
    let total = lengths_at(table, &[t0, t1], 1e-15)[1];
    let s = lengths_at(table, &ts, 1e-15 * total.max(1e-300));
    for (j, s_j) in s.iter().enumerate() {
        let want = total * j as f64 / f64::from(m - 1);
        assert!(
            (s_j - want).abs() <= 1e-5 * total,
            "sample {j}: {s_j} vs {want}"
        );
    }
}

#[test]
fn curves_whose_squares_overflow_are_measured_and_flattened() {
    // Points near 1e200: |P'|² overflows f64 unless the segment is scaled first (a property
    // test met this and the quadrature split itself out of memory).
    let coords: Vec<f64> = [0.0, 0.0, 1.0, 2.0, 3.0, 1.0, 4.0, 3.0]
        .iter()
        .map(|v| v * 1e200)
        .collect();
    let small: Vec<f64> = coords.iter().map(|v| v * 1e-200).collect();
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Repeat,
    };
    let big = Curve::new(kind.clone(), Points::new(2, coords).unwrap()).unwrap();
    let unit = Curve::new(kind, Points::new(2, small).unwrap()).unwrap();
    let (lb, lu) = (big.fit().arclen(1e-12), unit.fit().arclen(1e-12));
    assert!((lb / 1e200 - lu).abs() <= 1e-12 * lu, "{lb} vs {lu}");
    let ts = |curve: &Curve, sampling: Sampling| {
        let mut job = EvalJob::new(Derivatives::None);
        job.push(curve, &sampling).unwrap();
        (0..job.plan(0).len())
            .map(|i| job.plan(0).loc(i).t)
            .collect::<Vec<f64>>()
    };
    let (tb, tu) = (
        ts(&big, Sampling::ArcLength(9)),
        ts(&unit, Sampling::ArcLength(9)),
    );
    for (b, u) in tb.iter().zip(&tu) {
        assert!((b - u).abs() < 1e-9, "{b} vs {u}");
    }
    // The same places at every scale (the unit curve's chords are checked densely; the big
    // one's squares would overflow in this test's own distances).
    let (tb, tu) = (
        ts(&big, Sampling::Tolerance(1e198)),
        ts(&unit, Sampling::Tolerance(1e-2)),
    );
    // (×1e200 is not exact in binary, so the coefficients round differently: the same count,
    // t equal to rounding.)
    assert_eq!(tb.len(), tu.len());
    for (b, u) in tb.iter().zip(&tu) {
        assert!((b - u).abs() < 1e-9, "{b} vs {u}");
    }
    check_tolerance(&unit, 1e-2);
}
