//! The Hermite kinds ("hermite", "pchip", "akima" and makima) against SciPy's
//! CubicHermiteSpline, PchipInterpolator and Akima1DInterpolator (fixtures made by
//! tests/fixtures/make_scipy_shape_fixtures.py), on the CPU within the contract's f64 scale and
//! on the GPU within the promise; PCHIP's shape; and their input rules.

use crate::scipy_fixture::{assert_cpu_matches, floats, rows};
use crate::support::{assert_gpu_matches_cpu, cpu_at};
use splinegpu::kinds::KindFields;
use splinegpu::{Curve, CurveKind, Derivatives, EvalJob, HermiteSlopes, Points, Sampling};

/// A fixture case: its description, the curve, x, and SciPy's y, d1 and d2 there.
struct Case {
    what: String,
    curve: Curve,
    x: Vec<f64>,
    expected: [Vec<f64>; 3],
}

/// Every fixture case.
fn cases() -> Vec<Case> {
    let doc: serde_json::Value =
        serde_json::from_str(include_str!("../fixtures/scipy_hermite.json")).unwrap();
    let cases = doc["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 112);
    (cases.iter())
        .map(|case| {
            let dim = case["dim"].as_u64().unwrap() as usize;
            let kind = case["kind"].as_str().unwrap();
            let slopes = match kind {
                "hermite" => HermiteSlopes::Given(rows(&case["tangents"])),
                "pchip" => HermiteSlopes::Pchip,
                "akima" => HermiteSlopes::Akima,
                _ => HermiteSlopes::Makima,
            };
            let what = format!(
                "{kind} on {} knots, {} data, D = {dim}",
                case["shape"].as_str().unwrap(),
                case["data"].as_str().unwrap()
            );
            let t = Some(floats(&case["t"]));
            let points = Points::new(dim, rows(&case["points"])).unwrap();
            let curve = Curve::new(CurveKind::Hermite { slopes, t }, points).unwrap();
            let expected = [rows(&case["y"]), rows(&case["d1"]), rows(&case["d2"])];
            Case {
                what,
                curve,
                x: floats(&case["x"]),
                expected,
            }
        })
        .collect()
}

/// The SciPy cases checked on the CPU, as one job sampled at their x.
fn hermite_cases_checked() -> EvalJob {
    let mut worst = 0.0f64;
    let mut job = EvalJob::new(Derivatives::Second);
    for Case {
        what,
        curve,
        x,
        expected,
    } in cases()
    {
        worst = worst.max(assert_cpu_matches(&what, &curve, &x, &expected, 8.0));
        job.push(&curve, &Sampling::At(x)).unwrap();
    }
    println!("worst CPU error against SciPy: {worst:.2e} of the bound");
    job
}

#[test]
fn the_hermite_kinds_match_scipy_on_the_cpu() {
    hermite_cases_checked();
}

#[allow(
    dead_code,
    reason = "a trial of the GPU harness (tests/gpu/main.rs), which includes this file"
)]
pub(crate) fn the_hermite_kinds_meet_the_gpu_promise() {
    if let Some(gpu) = assert_gpu_matches_cpu(&hermite_cases_checked()) {
        println!("worst GPU error: {:.3} of the promise", gpu.ratio);
    }
}

#[test]
fn pchip_does_not_overshoot_monotone_data_where_natural_does() {
    let t = vec![0.0, 1.0, 1.2, 4.0, 4.1, 9.0];
    let y = vec![0.0, 0.1, 3.0, 3.1, 7.0, 7.2];
    let pchip = Curve::new(
        CurveKind::Hermite {
            slopes: HermiteSlopes::Pchip,
            t: Some(t.clone()),
        },
        Points::new(1, y.clone()).unwrap(),
    )
    .unwrap();
    let natural = Curve::new(
        CurveKind::Interpolating {
            condition: splinegpu::EndCondition::Natural,
            t: Some(t),
        },
        Points::new(1, y).unwrap(),
    )
    .unwrap();
    let x: Vec<f64> = (0..=9000).map(|i| f64::from(i) / 1000.0).collect();
    let increasing = |curve: &Curve| {
        let s = cpu_at(curve, &x);
        s.curve(0).points.windows(2).all(|w| w[1] >= w[0])
    };
    assert!(increasing(&pchip));
    assert!(
        !increasing(&natural),
        "the data should make the natural spline overshoot"
    );
}

#[test]
fn hermite_input_rules_are_located() {
    // n points in 2-D, x increasing so that the default t are fine.
    let named = |name: &str, fields: KindFields, n: usize| {
        let kind = CurveKind::named(name, fields)?;
        let coords = (0..2 * n).map(|v| f64::from(v as u32 % 5)).collect();
        Curve::new(kind, Points::new(2, coords).unwrap())
    };
    let tangents = |v: Vec<f64>| KindFields {
        tangents: Some(v),
        ..KindFields::default()
    };
    let cases: Vec<(Result<Curve, splinegpu::InputError>, &str)> = vec![
        (
            named("hermite", KindFields::default(), 3),
            "\"tangents\" is missing",
        ),
        (
            named("hermite", tangents(vec![0.0; 5]), 3),
            "3 x 2 = 6), got 5",
        ),
        (
            named(
                "hermite",
                tangents(vec![0.0, 1.0, f64::NAN, 0.0, 0.0, 0.0]),
                3,
            ),
            "tangents[1][0] = NaN",
        ),
        (
            named("pchip", KindFields::default(), 1),
            "at least 2 points for a pchip curve",
        ),
        (
            named(
                "akima",
                KindFields {
                    t: Some(vec![0.0, 2.0, 1.0]),
                    ..KindFields::default()
                },
                3,
            ),
            "t[2] = 1 follows t[1] = 2",
        ),
        (
            named(
                "akima",
                KindFields {
                    method: Some("spline".into()),
                    ..KindFields::default()
                },
                3,
            ),
            "\"method\" must be \"akima\" or \"makima\", got \"spline\"",
        ),
        (
            named(
                "pchip",
                KindFields {
                    method: Some("makima".into()),
                    ..KindFields::default()
                },
                3,
            ),
            "\"method\" is not a field of a \"pchip\" curve",
        ),
    ];
    for (result, expected) in cases {
        let message = result.unwrap_err().to_string();
        assert!(message.contains(expected), "{message:?} lacks {expected:?}");
    }
}
