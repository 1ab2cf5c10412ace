//! `evaluate_at_into` (explicit parameters located and evaluated in one pass) against a job
//! with `Sampling::At` through the reference: bit for bit, sorted or not, on any thread count;
//! its third derivative against differences of the reference's second; bad input refused.

use crate::support::Rng;
use splinegpu::{Curve, CurveKind, Derivatives, EndCondition, EvalJob, Sampling};

/// A not-a-knot spline of `n` knots in `dim` coordinates, spacings spread over six decades.
fn spline(rng: &mut Rng, n: usize, dim: usize) -> Curve {
    let mut t = vec![0.0];
    for i in 1..n {
        t.push(t[i - 1] + 10f64.powf(rng.range(-3.0, 3.0)));
    }
    let kind = CurveKind::Interpolating {
        condition: EndCondition::NotAKnot,
        t: Some(t),
    };
    Curve::new(kind, rng.points(n, dim, -1e3, 1e3)).unwrap()
}

/// The reference's plane `nu` (0, 1, 2) of `curve` at `ts`.
fn reference(curve: &Curve, ts: &[f64], nu: usize) -> Vec<f64> {
    let mut job = EvalJob::new(Derivatives::Second);
    job.push(curve, &Sampling::At(ts.to_vec())).unwrap();
    let samples = splinegpu::evaluate_reference(&job);
    let c = samples.curve(0);
    [c.points, c.d1.unwrap(), c.d2.unwrap()][nu].to_vec()
}

#[test]
fn values_at_explicit_t_equal_the_reference_bit_for_bit() {
    let mut rng = Rng(23);
    for dim in [1, 2, 3, 4, 5, 11] {
        let curve = spline(&mut rng, 40, dim);
        let table = curve.fit();
        let (lo, hi) = table.t_range();
        // Random t, the knots themselves, both ends, and a sorted run long enough to be cut
        // into parts.
        let mut ts: Vec<f64> = (0..300).map(|_| rng.range(lo, hi)).collect();
        ts.extend_from_slice(table.knots());
        ts.extend([lo, hi, hi, lo]);
        let mut sorted: Vec<f64> = (0..20_000).map(|_| rng.range(lo, hi)).collect();
        sorted.sort_by(f64::total_cmp);
        ts.extend(sorted);
        for nu in 0..3 {
            let expected = reference(&curve, &ts, nu);
            for threads in [1, 2, 5] {
                let mut out = vec![f64::NAN; ts.len() * dim];
                splinegpu::evaluate_at_into(&table, &ts, nu, &mut out, threads).unwrap();
                let same = out
                    .iter()
                    .zip(&expected)
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "dim {dim}, nu {nu}, {threads} threads");
                let mut narrow = vec![f32::NAN; ts.len() * dim];
                splinegpu::evaluate_at_into(&table, &ts, nu, &mut narrow, threads).unwrap();
                assert!(narrow.iter().zip(&expected).all(|(a, b)| *a == *b as f32));
            }
        }
    }
}

#[test]
fn the_third_derivative_is_the_slope_of_the_second() {
    let mut rng = Rng(5);
    let curve = spline(&mut rng, 12, 2);
    let table = curve.fit();
    for s in 0..table.len() {
        // d2 is linear on a segment: the central difference inside it is exact but for rounding.
        let (t0, t1) = (table.knots()[s], table.knots()[s + 1]);
        let (mid, h) = ((t0 + t1) / 2.0, (t1 - t0) / 4.0);
        let d2 = reference(&curve, &[mid - h, mid + h], 2);
        let mut d3 = vec![0.0; 2];
        splinegpu::evaluate_at_into(&table, &[mid], 3, &mut d3, 1).unwrap();
        for k in 0..2 {
            let slope = (d2[2 + k] - d2[k]) / (2.0 * h);
            let scale = d2[k].abs().max(d2[2 + k].abs()) / (2.0 * h);
            assert!(
                (d3[k] - slope).abs() <= 1e-9 * scale.max(f64::MIN_POSITIVE),
                "segment {s}: {} vs {slope}",
                d3[k]
            );
        }
    }
}

#[test]
fn bad_parameters_and_orders_are_refused_with_their_place() {
    let mut rng = Rng(9);
    let curve = spline(&mut rng, 6, 3);
    let table = curve.fit();
    let (lo, hi) = table.t_range();
    let mut out = vec![0.0; 3 * 3];
    for bad in [f64::NAN, hi + hi * 1e-12, lo - 1.0, f64::INFINITY] {
        // Past a part boundary too: the first bad index is reported.
        let ts = [lo, bad, hi];
        let e = splinegpu::evaluate_at_into(&table, &ts, 0, &mut out, 4).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("at[1]"), "{text}");
    }
    let e = splinegpu::evaluate_at_into(&table, &[lo, lo, lo], 4, &mut out, 1).unwrap_err();
    assert!(e.to_string().contains("nu"), "{e}");
    let many: Vec<f64> = (0..10_000)
        .map(|i| lo + (hi - lo) * f64::from(i) / 1e4)
        .collect();
    let mut ts = many.clone();
    ts[9_000] = f64::NAN;
    ts[9_500] = f64::NAN;
    let mut out = vec![0.0; ts.len() * 3];
    let e = splinegpu::evaluate_at_into(&table, &ts, 0, &mut out, 3).unwrap_err();
    assert!(e.to_string().contains("at[9000]"), "{e}");
}

#[test]
fn many_curves_at_their_own_t_equal_one_job_and_errors_name_the_curve() {
    let mut rng = Rng(41);
    let curves: Vec<Curve> = (0..30)
        .map(|c| spline(&mut rng, 4 + c % 9, 1 + c % 4))
        .collect();
    let tables: Vec<_> = curves.iter().map(Curve::fit).collect();
    let at: Vec<Vec<f64>> = (tables.iter().enumerate())
        .map(|(c, table)| {
            let (lo, hi) = table.t_range();
            (0..(c * 7) % 50).map(|_| rng.range(lo, hi)).collect()
        })
        .collect();
    let mut job = EvalJob::new(Derivatives::First);
    for (curve, at) in curves.iter().zip(&at) {
        job.push(curve, &Sampling::At(at.clone())).unwrap();
    }
    let reference = splinegpu::evaluate_reference(&job);
    let [_, d1, _] = reference.planes();
    for threads in [1, 2, 7] {
        let mut out = vec![f64::NAN; d1.len()];
        splinegpu::evaluate_curves_at_into(&tables, &at, 1, &mut out, threads).unwrap();
        assert!(out.iter().zip(d1).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
    let mut bad = at.clone();
    bad[17][0] = f64::NAN;
    bad[23][0] = f64::NAN;
    let mut out = vec![0.0; d1.len()];
    let e = splinegpu::evaluate_curves_at_into(&tables, &bad, 1, &mut out, 3).unwrap_err();
    assert!(e.to_string().contains("curve 17"), "{e}");
}

#[test]
fn a_table_refitted_in_place_is_located_on_its_new_knots() {
    use splinegpu::{Fitter, SegmentTable};
    let mut rng = Rng(3);
    let mut table = SegmentTable::default();
    let mut fitter = Fitter::new();
    for scale in [1.0, 1e3, 1e-2] {
        let curve = spline(&mut rng, 200, 2);
        let CurveKind::Interpolating { t: Some(t), .. } = curve.kind() else {
            unreachable!()
        };
        let t: Vec<f64> = t.iter().map(|v| v * scale).collect();
        let values = curve.points().coords();
        fitter
            .fit_into(&t, values, 2, &EndCondition::Natural, &mut table)
            .unwrap();
        let (lo, hi) = table.t_range();
        // Scattered and many: the locator is made (on the first table) and must follow the refit.
        let ts: Vec<f64> = (0..500).map(|_| rng.range(lo, hi)).collect();
        let mut out = vec![0f64; ts.len() * 2];
        splinegpu::evaluate_at_into(&table, &ts, 0, &mut out, 1).unwrap();
        let mut job = EvalJob::new(Derivatives::None);
        job.push_table(
            table.clone(),
            splinegpu::SamplePlan::new(&table, &Sampling::At(ts)).unwrap(),
        )
        .unwrap();
        let want = splinegpu::evaluate_reference(&job);
        assert!(
            out.iter()
                .zip(want.planes()[0])
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
    }
}

/// The places of explicit t, by the definition written out here (the last knot <= t, capped to
/// the last segment; u = (t − t_i)/Δ_i clamped to [0, 1]): the plan's and therefore both
/// evaluators', for scattered t (through the locator) and sorted ones (walking).
#[test]
fn explicit_t_are_placed_as_the_definition_says() {
    let mut rng = Rng(77);
    for n in [2, 5, 300] {
        let curve = spline(&mut rng, n.max(4), 1);
        let table = curve.fit();
        let knots = table.knots();
        let (lo, hi) = table.t_range();
        let mut scattered: Vec<f64> = (0..2000).map(|_| rng.range(lo, hi)).collect();
        scattered.extend_from_slice(knots);
        scattered.extend([hi, lo]);
        let mut sorted = scattered.clone();
        sorted.sort_by(f64::total_cmp);
        for ts in [scattered, sorted] {
            let plan = splinegpu::SamplePlan::new(&table, &Sampling::At(ts.clone())).unwrap();
            for (i, &t) in ts.iter().enumerate() {
                let last = knots.len() - 2;
                let segment = (knots.iter().filter(|&&k| k <= t).count() - 1).min(last);
                let u =
                    ((t - knots[segment]) / (knots[segment + 1] - knots[segment])).clamp(0.0, 1.0);
                let loc = plan.loc(i);
                assert_eq!(
                    (loc.segment, loc.u.to_bits()),
                    (segment, u.to_bits()),
                    "t = {t}"
                );
            }
        }
    }
}
