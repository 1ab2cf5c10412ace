//! Kind "nurbs" without weights against SciPy's BSpline(knots, points, 3) (fixtures made by
//! tests/fixtures/make_scipy_bspline_fixtures.py) on the CPU within the contract's f64 scale and
//! on the GPU within the promise; its segments' Bezier export; and its input rules.

use crate::scipy_fixture::{assert_cpu_matches, floats, rows};
use crate::support::assert_gpu_matches_cpu;
use splinegpu::kinds::KindFields;
use splinegpu::{Curve, CurveKind, Derivatives, EvalJob, Points, Sampling};

#[test]
fn nurbs_without_weights_is_scipys_bspline() {
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
    if let Some(gpu) = assert_gpu_matches_cpu(&job) {
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
                    weights: Some(vec![1.0; 4]),
                    ..KindFields::default()
                },
                4,
            ),
            "\"weights\" are not supported yet",
        ),
    ];
    for (result, expected) in cases {
        let message = result.unwrap_err().to_string();
        assert!(message.contains(expected), "{message:?} lacks {expected:?}");
    }
}
