//! Reading SciPy's values from the committed fixtures (tests/fixtures/*.json, each with the
//! script that made it) and comparing the CPU reference with them.

use crate::support::cpu_at;
use splinegpu::Curve;
use splinegpu::accuracy::cpu_bound;

/// A JSON array of numbers.
pub(crate) fn floats(v: &serde_json::Value) -> Vec<f64> {
    (v.as_array().unwrap().iter())
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// A JSON array of arrays of numbers, flattened.
pub(crate) fn rows(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().flat_map(floats).collect()
}

/// Asserts that the f64 reference of `curve` at `x` gives SciPy's value, first and second
/// derivative (`expected`) within the contract's scale (1e-9 of the promise's) plus the f64
/// rounding of the coefficients themselves: `ulps` · eps · M / Δ^order, M = |D| + |C| of the
/// segment's coordinate (the size of the values A and B are formed from; a line or a flat run,
/// whose A and B SciPy holds as exactly 0, leaves that rounding as all there is). Returns the
/// worst error as a fraction of its bound.
pub(crate) fn assert_cpu_matches(
    what: &str,
    curve: &Curve,
    x: &[f64],
    expected: &[Vec<f64>; 3],
    ulps: f64,
) -> f64 {
    let table = curve.fit();
    let plan = splinegpu::SamplePlan::new(&table, &splinegpu::Sampling::At(x.to_vec())).unwrap();
    let ours = cpu_at(curve, x);
    let c = ours.curve(0);
    let dim = c.dim;
    let mut worst = 0.0f64;
    for (order, plane) in [c.points, c.d1.unwrap(), c.d2.unwrap()]
        .into_iter()
        .enumerate()
    {
        for (i, (got, want)) in plane.iter().zip(&expected[order]).enumerate() {
            let segment = table.segment(plan.loc(i / dim).segment);
            let [_, _, c1, d0] = segment.power();
            let m = d0[i % dim].abs() + c1[i % dim].abs();
            let rounding = ulps * f64::EPSILON * m / segment.dt().powi(order as i32);
            let bound = cpu_bound(&segment, table.extent(), order, i % dim) + rounding;
            worst = worst.max((got - want).abs() / bound);
            assert!(
                (got - want).abs() <= bound,
                "{what}: order {order} at x = {}: {got} vs SciPy {want} (bound {bound})",
                x[i / dim]
            );
        }
    }
    worst
}
