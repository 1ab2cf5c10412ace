//! The closest-point kernel's twin, and the GPU where wgpu finds an adapter (lavapipe in CI),
//! against the f64 search ([`CurveIndex::closest_many`], itself tested against brute force)
//! under the contract's GPU bound: the distance within the curve's position bound plus
//! 1e-5 (E + |q|∞) of the certified one, the point the curve at the reported t within the
//! position bound, the distance the point's.

use super::closest_points_twin;
use crate::accuracy::gpu_bound;
use crate::support::{Rng, gpu};
use splinegpu::query::{ClosestPoints, CurveIndex, QueryError};
use splinegpu::{
    Basis, Curve, CurveKind, EndCondition, Ends, HermiteSlopes, Points, Segment, SegmentTable,
};

/// The segment of `table` holding `t` and its local parameter there.
fn segment_at(table: &SegmentTable, t: f64) -> (Segment<'_>, f64) {
    let knots = table.knots();
    let s = knots[1..knots.len() - 1].partition_point(|&k| k <= t);
    let segment = table.segment(s);
    let u = ((t - segment.t0()) / segment.dt()).clamp(0.0, 1.0);
    (segment, u)
}

/// The curves' extent as the contract's E is bounded below: the largest per-axis range of
/// their Bezier control points (which lie in the hull of the control and data points).
fn extent(tables: &[SegmentTable]) -> f64 {
    let dim = tables[0].dim();
    (0..dim)
        .map(|k| {
            let values = tables.iter().flat_map(|t| {
                (0..t.len()).flat_map(move |s| t.segment(s).rational_bezier().0.map(|p| p[k]))
            });
            let lo = values.clone().fold(f64::INFINITY, f64::min);
            let hi = values.fold(f64::NEG_INFINITY, f64::max);
            hi - lo
        })
        .fold(0.0, f64::max)
}

/// The f32 position bound of `table` at `t` (the per-coordinate bounds' norm), and the exact
/// point there.
fn position_bound(table: &SegmentTable, t: f64, e: f64) -> (f64, Vec<f64>) {
    let (segment, u) = segment_at(table, t);
    let mut exact = vec![0.0; table.dim()];
    segment.eval(u, &mut exact);
    let bound = (0..table.dim())
        .map(|k| gpu_bound(&segment, e, 0, k, exact[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    (bound, exact)
}

/// The twin (whole, and in dispatches of 7 queries) and the GPU against the f64 search.
fn check(what: &str, curves: &[Curve], queries: &[f64]) {
    let tables: Vec<SegmentTable> = curves.iter().map(Curve::fit).collect();
    let index = CurveIndex::new(&tables).unwrap();
    let dim = index.dim();
    let cpu = index.closest_many(queries).unwrap();
    let twin = closest_points_twin(&index, queries, 1 << 24).unwrap();
    assert_eq!(
        closest_points_twin(&index, queries, 7).unwrap(),
        twin,
        "{what}: dispatches of 7 queries differ from one"
    );
    let mut found: Vec<(&str, ClosestPoints<f32>)> = vec![("twin", twin)];
    if let Some(context) = gpu() {
        found.push(("GPU", context.closest_points(&index, queries).unwrap()));
    }
    let e = extent(&tables);
    for (path, found) in &found {
        assert_eq!(found.len(), cpu.len(), "{what}: {path}");
        for i in 0..cpu.len() {
            let q = &queries[i * dim..][..dim];
            let q_norm = q.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let (ours, exact) = position_bound(&tables[found.curve[i]], found.t[i], e);
            let (theirs, _) = position_bound(&tables[cpu.curve[i]], cpu.t[i], e);
            let bound = ours.max(theirs) + 1e-5 * (e + q_norm);
            let distance = f64::from(found.distance[i]);
            assert!(
                (distance - cpu.distance[i]).abs() <= bound,
                "{what}: {path}: query {i} at {q:?}: distance {distance} (curve {}, t {}), \
                 certified {} (curve {}, t {}), bound {bound:e}",
                found.curve[i],
                found.t[i],
                cpu.distance[i],
                cpu.curve[i],
                cpu.t[i]
            );
            let point = &found.points[i * dim..][..dim];
            let mut d2 = 0.0;
            for k in 0..dim {
                let x = f64::from(point[k]);
                assert!(
                    (x - exact[k]).abs() <= ours,
                    "{what}: {path}: query {i}: point {k} is {x}, the curve at t {}",
                    exact[k]
                );
                d2 += (x - q[k]).powi(2);
            }
            let ulp = f64::from(found.distance[i].next_up() - found.distance[i]);
            assert!(
                (d2.sqrt() - distance).abs() <= ulp,
                "{what}: {path}: query {i}"
            );
        }
    }
}

fn bezier(coords: Vec<f64>, dim: usize) -> Curve {
    Curve::new(CurveKind::Bezier, Points::new(dim, coords).unwrap()).unwrap()
}

fn catmull_rom(points: Points) -> Curve {
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Repeat,
    };
    Curve::new(kind, points).unwrap()
}

/// A grid of n x n query points over [lo, hi]², flat.
fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let step = (hi - lo) / (n - 1) as f64;
    (0..n * n)
        .flat_map(|i| [lo + step * (i % n) as f64, lo + step * (i / n) as f64])
        .collect()
}

#[test]
fn loops_cusps_and_ties() {
    let curves = [
        // A loop, a cusp at u = 1/2, and a mirrored pair (ties on x = 10).
        bezier(vec![0.0, 0.0, 4.0, 4.0, -1.0, 4.0, 3.0, 0.0], 2),
        bezier(vec![5.0, 0.0, 6.0, 1.0, 5.0, 1.0, 6.0, 0.0], 2),
        bezier(vec![11.0, 0.0, 12.0, 1.0, 12.0, 2.0, 11.0, 3.0], 2),
        bezier(vec![9.0, 0.0, 8.0, 1.0, 8.0, 2.0, 9.0, 3.0], 2),
    ];
    let mut queries = grid(-1.0, 13.0, 15);
    queries.extend([
        1.5, 2.0, 1.5, 1.2, 5.5, 0.75, 5.5, 0.5, 10.0, 1.5, 10.0, 0.0,
    ]);
    check("loops, cusps and ties", &curves, &queries);
}

#[test]
fn mixed_kinds_in_one_dispatch() {
    let mut rng = Rng(29);
    let nurbs = Curve::new(
        CurveKind::Nurbs {
            knots: vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0],
            weights: Some(vec![1.0, 20.0, 0.3, 5.0, 1.0, 2.0]),
        },
        Points::new(
            2,
            vec![0.0, 0.0, 1.0, 3.0, 2.0, -1.0, 3.0, 2.0, 4.0, 0.0, 5.0, 1.0],
        )
        .unwrap(),
    )
    .unwrap();
    let mut curves = vec![nurbs];
    for i in 0..12 {
        let points = rng.points(4 + 3 * (i % 3), 2, -3.0, 8.0);
        curves.push(match i % 4 {
            0 => catmull_rom(points),
            1 => Curve::new(CurveKind::Bezier, points).unwrap(),
            2 => Curve::new(
                CurveKind::Uniform {
                    basis: Basis::BSpline,
                    ends: Ends::Closed,
                },
                points,
            )
            .unwrap(),
            _ => Curve::new(
                CurveKind::Interpolating {
                    condition: EndCondition::Natural,
                    t: None,
                },
                points,
            )
            .unwrap(),
        });
    }
    let queries: Vec<f64> = (0..300).map(|_| rng.range(-5.0, 10.0)).collect();
    check("mixed kinds", &curves, &queries);
}

#[test]
fn three_dimensional_and_one_dimensional_curves() {
    let mut rng = Rng(31);
    let pchip = Curve::new(
        CurveKind::Hermite {
            slopes: HermiteSlopes::Pchip,
            t: None,
        },
        rng.points(9, 3, -2.0, 2.0),
    )
    .unwrap();
    let queries: Vec<f64> = (0..120).map(|_| rng.range(-3.0, 3.0)).collect();
    check("3-D pchip", &[pchip], &queries);
    let line = catmull_rom(rng.points(6, 1, -1.0, 1.0));
    check("1-D", &[line], &[-2.0, -0.5, 0.0, 0.3, 2.0]);
}

#[test]
fn far_from_the_origin_and_on_uneven_knots() {
    let mut rng = Rng(37);
    // Curves at 1e6, queried near them and from the origin, 1e6 away.
    let points = rng.points(10, 2, -1.0, 1.0);
    let moved: Vec<f64> = points.coords().iter().map(|v| v + 1e6).collect();
    let curve = catmull_rom(Points::new(2, moved).unwrap());
    let mut queries: Vec<f64> = (0..80).map(|_| 1e6 + rng.range(-1.5, 1.5)).collect();
    queries.extend([0.0, 0.0, 1e6, 0.0, -3e6, 2e6]);
    check("at 1e6", &[curve], &queries);
    // An interpolating spline whose knot spacings differ by 1e6.
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: Some(vec![0.0, 1e-6, 1.0, 2.0, 1e6]),
    };
    let points = Points::new(2, vec![0.0, 0.0, 0.1, 0.3, 1.0, 1.0, 2.0, 0.0, 3.0, 2.0]).unwrap();
    let curve = Curve::new(kind, points).unwrap();
    check("knots uneven by 1e6", &[curve], &grid(-1.0, 4.0, 9));
}

#[test]
fn queries_far_beyond_the_curves_and_points_on_them() {
    let curve = catmull_rom(Points::new(2, vec![0.0, 0.0, 1.0, 2.0, 3.0, -1.0, 4.0, 0.5]).unwrap());
    // 1e20 and 1e30 away: every point of the curve is as near, within the bound.
    check(
        "far",
        std::slice::from_ref(&curve),
        &[1e20, 0.0, -1e30, 1e30, 2.0, 1e25],
    );
    // On the curve: at distance 0 within the bound.
    let table = curve.fit();
    let on: Vec<f64> = [0.0, 0.25, 1.0, 1.7, 3.0]
        .iter()
        .flat_map(|&t| {
            let (segment, u) = segment_at(&table, t);
            let mut p = vec![0.0; 2];
            segment.eval(u, &mut p);
            p
        })
        .collect();
    check("on the curve", std::slice::from_ref(&curve), &on);
    // Beyond f32 from the curves: refused, naming the query.
    let index_tables = [table];
    let index = CurveIndex::new(&index_tables).unwrap();
    let e = closest_points_twin(&index, &[0.0, 0.0, 1e200, 0.0], 1 << 24).unwrap_err();
    assert!(matches!(e, QueryError::Input(_)), "{e}");
    assert!(e.to_string().contains("closest[1]"), "{e}");
}
