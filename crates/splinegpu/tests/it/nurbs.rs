//! Kind "nurbs" without weights against SciPy's BSpline(knots, points, 3) (fixtures made by
//! tests/fixtures/make_scipy_bspline_fixtures.py) on the CPU within the contract's f64 scale and
//! on the GPU within the promise; with weights, against the rational basis sum evaluated
//! independently (Cox–de Boor on the knots, not the power form), an exact circle, finite
//! differences and the rational Bezier export; and its input rules.

use crate::scipy_fixture::{assert_cpu_matches, floats, rows};
use crate::shapes::nurbs_circle;
use crate::support::{Rng, assert_gpu_matches_cpu, cpu_at};
use splinegpu::kinds::KindFields;
use splinegpu::{Curve, CurveKind, Derivatives, EvalJob, Points, Sampling};

#[test]
fn nurbs_without_weights_is_scipys_bspline() {
    nurbs_cases_checked();
}

/// SciPy's BSpline cases checked on the CPU, as one job.
fn nurbs_cases_checked() -> EvalJob {
    let doc: serde_json::Value =
        serde_json::from_str(include_str!("../fixtures/scipy_bspline.json")).unwrap();
    let cases = doc["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 36);
    let mut job = EvalJob::new(Derivatives::Second);
    let mut worst = 0.0f64;
    for case in cases {
        let dim = case["dim"].as_u64().unwrap() as usize;
        let what = format!("{} knots, D = {dim}", case["shape"].as_str().unwrap());
        let knots = floats(&case["knots"]);
        let kind = CurveKind::Nurbs {
            knots,
            weights: None,
        };
        let curve = Curve::new(kind, Points::new(dim, rows(&case["points"])).unwrap()).unwrap();
        let x = floats(&case["x"]);
        let expected = [rows(&case["y"]), rows(&case["d1"]), rows(&case["d2"])];
        worst = worst.max(assert_cpu_matches(&what, &curve, &x, &expected, 16.0));
        job.push(&curve, &Sampling::At(x)).unwrap();
        job.push(&curve, &Sampling::PerSegment(5)).unwrap();
    }
    println!("worst CPU error against SciPy: {worst:.2e} of the bound");
    job
}

#[allow(
    dead_code,
    reason = "a trial of the GPU harness (tests/gpu/main.rs), which includes this file"
)]
pub(crate) fn scipys_bspline_cases_meet_the_gpu_promise() {
    if let Some(gpu) = assert_gpu_matches_cpu(&nurbs_cases_checked()) {
        println!("worst GPU error: {:.3} of the promise", gpu.ratio);
    }
}

#[test]
fn a_clamped_knot_vector_on_four_points_is_the_bezier_of_its_points() {
    // knots 0,0,0,0,1,1,1,1: one span, whose Bezier control points are the points themselves.
    let p = vec![0.0, 0.0, 1.0, 3.0, 4.0, -1.0, 6.0, 2.0];
    let kind = CurveKind::Nurbs {
        knots: vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        weights: None,
    };
    let table = Curve::new(kind, Points::new(2, p.clone()).unwrap())
        .unwrap()
        .fit();
    assert_eq!(table.len(), 1);
    let bezier = table.segment(0).bezier_points().unwrap().concat();
    for (a, b) in bezier.iter().zip(&p) {
        assert!((a - b).abs() < 1e-14, "{bezier:?} vs {p:?}");
    }
}

#[test]
fn nurbs_input_rules_are_located() {
    let named = |fields: KindFields, n: usize| {
        let kind = CurveKind::named("nurbs", fields)?;
        let coords = (0..n).map(|i| i as f64).collect();
        Curve::new(kind, Points::new(1, coords).unwrap())
    };
    let knots = |k: Vec<f64>| KindFields {
        knots: Some(k),
        ..KindFields::default()
    };
    let cases: Vec<(Result<Curve, splinegpu::InputError>, &str)> = vec![
        (named(KindFields::default(), 4), "\"knots\" is missing"),
        (
            named(knots(vec![0.0; 7]), 4),
            "n + 4 = 8 values for 4 points, got 7",
        ),
        (
            named(knots(vec![0., 1., 2., 3., 2., 5., 6., 7.]), 4),
            "knots[4] = 2 follows knots[3] = 3",
        ),
        (
            named(knots(vec![0., 1., 2., 3., 3., 5., 6., 7.]), 4),
            "knots[3] < knots[n]",
        ),
        (
            named(
                knots(vec![0., 1., 2., 3., 4., 4., 4., 4., 8., 9., 10., 11.]),
                8,
            ),
            "at most 3 times inside (knots[3], knots[n]): 4 appears 4 times from knots[4]",
        ),
        (
            named(knots(vec![0., 0., 0., 0., 0., 1., 1., 1., 1.]), 5),
            "at most 4 times: 0 appears 5 times",
        ),
        (
            named(knots(vec![0., 1., 2., f64::NAN, 4., 5., 6., 7.]), 4),
            "knots[3] = NaN",
        ),
        (named(knots(vec![0.0; 7]), 3), "at least 4 points"),
        (
            named(
                KindFields {
                    knots: Some((0..8).map(f64::from).collect()),
                    weights: Some(vec![1.0; 3]),
                    ..KindFields::default()
                },
                4,
            ),
            "\"weights\" must have one value per point (4), got 3",
        ),
        (
            named(
                KindFields {
                    knots: Some((0..8).map(f64::from).collect()),
                    weights: Some(vec![1.0, 2.0, 0.0, 1.0]),
                    ..KindFields::default()
                },
                4,
            ),
            "\"weights\" must be finite and > 0: weights[2] = 0",
        ),
        (
            named(
                KindFields {
                    knots: Some((0..8).map(f64::from).collect()),
                    weights: Some(vec![1.0, f64::INFINITY, 1.0, 1.0]),
                    ..KindFields::default()
                },
                4,
            ),
            "weights[1] = inf",
        ),
    ];
    for (result, expected) in cases {
        let message = result.unwrap_err().to_string();
        assert!(message.contains(expected), "{message:?} lacks {expected:?}");
    }
}

/// N_{j,p}^{(d)}(t), the d-th derivative of the B-spline basis function j of degree p, by the
/// Cox–de Boor recursion and its derivative formula (0/0 taken as 0), with the degree-0
/// functions the indicator of `span`: an evaluation independent of the crate's power form.
fn basis(knots: &[f64], span: usize, j: usize, p: usize, d: usize, t: f64) -> f64 {
    if p == 0 {
        return if d == 0 && j == span { 1.0 } else { 0.0 };
    }
    let ratio = |num: f64, den: f64| if den > 0.0 { num / den } else { 0.0 };
    let (left, right) = (knots[j + p] - knots[j], knots[j + p + 1] - knots[j + 1]);
    if d == 0 {
        ratio(t - knots[j], left) * basis(knots, span, j, p - 1, 0, t)
            + ratio(knots[j + p + 1] - t, right) * basis(knots, span, j + 1, p - 1, 0, t)
    } else {
        let p_f = p as f64;
        ratio(p_f, left) * basis(knots, span, j, p - 1, d - 1, t)
            - ratio(p_f, right) * basis(knots, span, j + 1, p - 1, d - 1, t)
    }
}

/// P, dP/dt and d2P/dt2 of the rational B-spline at t: the homogeneous sums
/// c^(d) = Σ w_j N_j^(d) P_j and w^(d) = Σ w_j N_j^(d), then P = c/w, P' = (c' − P w')/w,
/// P'' = (c'' − 2 P' w' − P w'')/w.
fn rational_at(
    knots: &[f64],
    weights: &[f64],
    points: &[f64],
    dim: usize,
    t: f64,
) -> [Vec<f64>; 3] {
    let n = weights.len();
    // The span: the last non-empty [k_i, k_{i+1}) with k_i <= t, 3 <= i < n.
    let span = (3..n)
        .rev()
        .find(|&i| knots[i] < knots[i + 1] && knots[i] <= t)
        .unwrap();
    let mut c = [vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]];
    let mut w = [0.0; 3];
    for j in span - 3..=span {
        for d in 0..3 {
            let b = weights[j] * basis(knots, span, j, 3, d, t);
            w[d] += b;
            for k in 0..dim {
                c[d][k] += b * points[j * dim + k];
            }
        }
    }
    let p: Vec<f64> = (0..dim).map(|k| c[0][k] / w[0]).collect();
    let d1: Vec<f64> = (0..dim).map(|k| (c[1][k] - p[k] * w[1]) / w[0]).collect();
    let d2: Vec<f64> = (0..dim)
        .map(|k| (c[2][k] - 2.0 * d1[k] * w[1] - p[k] * w[2]) / w[0])
        .collect();
    [p, d1, d2]
}

/// Weighted curves: clamped or open knot vectors with spacings whose ratios reach 1e6, a double
/// knot, weights in [0.1, 10], points within ±5 of `offset`; 1 to 3 dimensions.
fn weighted_curves(rng: &mut Rng, offset: f64) -> Vec<(Vec<f64>, Vec<f64>, Curve)> {
    let mut out = Vec::new();
    let knot_vectors = [
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0],
        vec![0.0, 0.0, 0.0, 0.0, 1e-6, 1e-6, 1.0, 2.0, 2.0, 2.0, 2.0],
        vec![
            -3.0,
            -2.0,
            -1.0,
            0.0,
            0.5,
            1e3,
            1e3 + 1e-3,
            2e3,
            2e3,
            2e3,
            2e3,
        ],
        vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0],
    ];
    for (i, knots) in knot_vectors.iter().enumerate() {
        let n = knots.len() - 4;
        let dim = 1 + i % 3;
        let weights: Vec<f64> = (0..n).map(|_| 10f64.powf(rng.range(-1.0, 1.0))).collect();
        let points = rng.points(n, dim, offset - 5.0, offset + 5.0);
        let kind = CurveKind::Nurbs {
            knots: knots.clone(),
            weights: Some(weights.clone()),
        };
        out.push((knots.clone(), weights, Curve::new(kind, points).unwrap()));
    }
    out
}

/// Parameters inside each non-empty span of `knots` (a few per span, the span's start, and the
/// range's end).
fn ts_of(rng: &mut Rng, knots: &[f64], n: usize) -> Vec<f64> {
    let mut ts = Vec::new();
    for i in 3..n {
        if knots[i] < knots[i + 1] {
            ts.push(knots[i]);
            ts.extend((0..5).map(|_| rng.range(knots[i], knots[i + 1])));
        }
    }
    ts.push(knots[n]);
    ts
}

/// The curve (its knots and the weights of its rational basis sum, ones where it has none)
/// against that sum at a few parameters a span, on the CPU within its bound (`cpu_bound`); the
/// parameters go into `job` for the GPU. Returns the worst error's share of its bound.
fn assert_basis_sum(
    rng: &mut Rng,
    (knots, weights, curve): &(Vec<f64>, Vec<f64>, Curve),
    job: &mut EvalJob,
) -> f64 {
    let n = weights.len();
    let dim = curve.points().dim();
    let ts = ts_of(rng, knots, n);
    let samples = cpu_at(curve, &ts);
    let got = samples.curve(0);
    let table = curve.fit();
    let mut worst = 0.0f64;
    for (i, &t) in ts.iter().enumerate() {
        let want = rational_at(knots, weights, curve.points().coords(), dim, t);
        let s = (table.knots().partition_point(|&k| k <= t).max(1) - 1).min(table.len() - 1);
        let segment = table.segment(s);
        let planes = [got.points, got.d1.unwrap(), got.d2.unwrap()];
        for (order, plane) in planes.iter().enumerate() {
            for k in 0..dim {
                let bound = splinegpu::accuracy::cpu_bound(&segment, table.extent(), order, k);
                let error = (plane[i * dim + k] - want[order][k]).abs();
                assert!(
                    error <= bound,
                    "knots {knots:?}, t {t}, order {order}: {} vs {} ({error:e} > {bound:e})",
                    plane[i * dim + k],
                    want[order][k]
                );
                worst = worst.max(error / bound);
            }
        }
    }
    job.push(curve, &Sampling::At(ts)).unwrap();
    job.push(curve, &Sampling::PerSegment(9)).unwrap();
    worst
}

/// The weighted test curves (`weighted_curves`, points near 0 and near 1e6), with their
/// weights or without them (against the basis sum with unit weights), each against the basis
/// sum on the CPU; returns them as one job.
fn basis_sums_checked(seed: u64, weighted: bool) -> EvalJob {
    let mut rng = Rng(seed);
    let mut job = EvalJob::new(Derivatives::Second);
    let mut worst = 0.0f64;
    for offset in [0.0, 1e6] {
        for (knots, weights, curve) in weighted_curves(&mut rng, offset) {
            let case = if weighted {
                (knots, weights, curve)
            } else {
                let kind = CurveKind::Nurbs {
                    knots: knots.clone(),
                    weights: None,
                };
                let plain = Curve::new(kind, curve.points().clone()).unwrap();
                (knots, vec![1.0; weights.len()], plain)
            };
            worst = worst.max(assert_basis_sum(&mut rng, &case, &mut job));
        }
    }
    println!(
        "worst CPU error against the basis sum (weighted: {weighted}): {worst:.2e} of the bound"
    );
    job
}

#[allow(
    dead_code,
    reason = "a trial of the GPU harness (tests/gpu/main.rs), which includes this file"
)]
pub(crate) fn basis_sums_meet_the_gpu_promise() {
    for (seed, weighted) in [(41, true), (43, false)] {
        if let Some(gpu) = assert_gpu_matches_cpu(&basis_sums_checked(seed, weighted)) {
            println!(
                "worst GPU error (weighted: {weighted}): {:.3} of the promise ({:?})",
                gpu.ratio, gpu.per_order
            );
        }
    }
}

#[test]
fn weighted_nurbs_is_the_rational_basis_sum_on_both_backends() {
    basis_sums_checked(41, true);
}

/// The same knot vectors without weights (the polynomial spans' own construction, from the
/// derivatives at each span's start).
#[test]
fn unweighted_nurbs_is_the_basis_sum_on_both_backends() {
    basis_sums_checked(43, false);
}

#[test]
fn weighted_derivatives_match_finite_differences() {
    let mut rng = Rng(7);
    for (knots, weights, curve) in weighted_curves(&mut rng, 0.0) {
        let n = weights.len();
        let dim = curve.points().dim();
        let table = curve.fit();
        for s in 0..table.len() {
            let segment = table.segment(s);
            let t = segment.t0() + 0.37 * segment.dt();
            // The steps as the parameters are held (t near 1e3 rounds t ± h).
            let (before, after) = (t - 1e-4 * segment.dt(), t + 1e-4 * segment.dt());
            let h = 0.5 * (after - before);
            let at = cpu_at(&curve, &[before, t, after]);
            let c = at.curve(0);
            let (p, d1, d2) = (c.points, c.d1.unwrap(), c.d2.unwrap());
            for k in 0..dim {
                let central = (p[2 * dim + k] - p[k]) / (2.0 * h);
                let second = (d1[2 * dim + k] - d1[k]) / (2.0 * h);
                let scale1 = d1.iter().fold(1e-12f64, |m, v| m.max(v.abs()));
                let scale2 = d2.iter().fold(1e-12f64, |m, v| m.max(v.abs()));
                assert!(
                    (central - d1[dim + k]).abs() <= 1e-5 * scale1,
                    "knots {knots:?} ({n} points), segment {s}: d1 {} vs {central}",
                    d1[dim + k]
                );
                assert!(
                    (second - d2[dim + k]).abs() <= 1e-5 * scale2,
                    "knots {knots:?}, segment {s}: d2 {} vs {second}",
                    d2[dim + k]
                );
            }
        }
    }
}

#[test]
fn a_weighted_nurbs_circle_is_exact() {
    let (_, weights, curve) = nurbs_circle();
    let mut job = EvalJob::new(Derivatives::Second);
    job.push(&curve, &Sampling::PerSegment(64)).unwrap();
    let cpu = splinegpu::evaluate_reference(&job);
    let c = cpu.curve(0);
    for (i, p) in c.points.chunks_exact(2).enumerate() {
        let r = p[0].hypot(p[1]);
        assert!((r - 1.0).abs() < 1e-14, "sample {i}: radius {r}");
        // The velocity is tangent: P·P' = 0.
        let v = &c.d1.unwrap()[2 * i..2 * i + 2];
        assert!(
            (p[0] * v[0] + p[1] * v[1]).abs() < 1e-13,
            "sample {i}: P·P' != 0"
        );
    }
    // The rational Bezier export gives back each quarter's points and weights.
    let table = curve.fit();
    assert!(table.is_rational() && table.segment(0).bezier_points().is_none());
    for s in 0..4 {
        let (q, omega) = table.segment(s).rational_bezier();
        let want = &curve.points().coords()[6 * s..6 * s + 8];
        for i in 0..4 {
            let ratio = omega[i] / omega[0];
            assert!((ratio - weights[3 * s + i] / weights[3 * s]).abs() < 1e-14);
            for k in 0..2 {
                assert!(
                    (q[i][k] - want[2 * i + k]).abs() < 1e-14,
                    "arc {s}, point {i}"
                );
            }
        }
    }
}

#[test]
fn tolerance_on_a_weighted_segment_stays_within_twice_the_count_of_the_true_bound() {
    let mut rng = Rng(3);
    for (_, _, curve) in weighted_curves(&mut rng, 0.0) {
        let table = curve.fit();
        for s in 0..table.len() {
            let segment = table.segment(s);
            let dim = table.dim();
            // max |d2P/du2| by dense sampling: no more than the true maximum.
            let dense = (0..=4000)
                .map(|i| {
                    let mut d2 = vec![0.0; dim];
                    segment.deriv2(f64::from(i) / 4000.0, &mut d2);
                    d2.iter().map(|v| v * v).sum::<f64>().sqrt() * segment.dt().powi(2)
                })
                .fold(0.0, f64::max);
            for tol in [1e-2, 1e-4] {
                let with_dense = (dense / (8.0 * tol)).sqrt().ceil().max(1.0);
                let count = splinegpu::wang_count(&segment, tol);
                assert!(
                    count <= 2.0 * with_dense,
                    "segment {s}: {count} samples, {with_dense} with the true bound"
                );
            }
        }
    }
}
