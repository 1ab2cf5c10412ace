//! Closest points against an independent brute force: every segment sampled densely, each
//! sampled local minimum refined by golden-section search. The certified answer may be no
//! farther than that (plus the contract's ε = 1e-9 (E + |q|∞)), and must be the curve at the
//! reported t, at the reported distance.

use crate::support::{Rng, cpu_at};
use proptest::prelude::*;
use splinegpu::query::CurveIndex;
use splinegpu::{Basis, Curve, CurveKind, EndCondition, Ends, HermiteSlopes, Points, SegmentTable};

/// Samples per segment of the brute force.
const SAMPLES: usize = 400;

/// The squared distance from `q` to `segment` at local u.
fn distance2(segment: &splinegpu::Segment<'_>, q: &[f64], u: f64) -> f64 {
    let mut p = vec![0.0; q.len()];
    segment.eval(u, &mut p);
    p.iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// The least distance from `q` to any of `tables`, by dense sampling and golden-section
/// refinement of every sampled local minimum.
fn brute_force(tables: &[SegmentTable], q: &[f64]) -> f64 {
    let mut best = f64::INFINITY;
    for table in tables {
        for s in 0..table.len() {
            let segment = table.segment(s);
            let d: Vec<f64> = (0..=SAMPLES)
                .map(|i| distance2(&segment, q, i as f64 / SAMPLES as f64))
                .collect();
            for i in 0..=SAMPLES {
                let left = if i == 0 { f64::INFINITY } else { d[i - 1] };
                let right = if i == SAMPLES {
                    f64::INFINITY
                } else {
                    d[i + 1]
                };
                if d[i] > left || d[i] > right {
                    continue;
                }
                best = best.min(d[i]);
                let h = 1.0 / SAMPLES as f64;
                let (mut a, mut b) = ((i as f64 - 1.0) * h, (i as f64 + 1.0) * h);
                (a, b) = (a.max(0.0), b.min(1.0));
                let g = 0.5 * (5f64.sqrt() - 1.0);
                for _ in 0..80 {
                    let (x, y) = (b - g * (b - a), a + g * (b - a));
                    if distance2(&segment, q, x) < distance2(&segment, q, y) {
                        b = y;
                    } else {
                        a = x;
                    }
                }
                best = best.min(distance2(&segment, q, 0.5 * (a + b)));
            }
        }
    }
    best.sqrt()
}

/// The scale of ε: the document's extent E (the largest per-axis range over every curve's
/// points), or where larger the size |A| + |B| + |C| of a segment's power form, which bounds
/// how well f64 can place a point on it (the contract's accuracy section uses the same
/// max(E, |A| + |B| + |C|)).
fn extent(curves: &[Curve], tables: &[SegmentTable]) -> f64 {
    let dim = curves[0].points().dim();
    let points = (0..dim)
        .map(|k| {
            let values = curves
                .iter()
                .flat_map(|c| c.points().coords().iter().skip(k).step_by(dim).copied());
            let lo = values.clone().fold(f64::INFINITY, f64::min);
            let hi = values.fold(f64::NEG_INFINITY, f64::max);
            hi - lo
        })
        .fold(0.0, f64::max);
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let power = tables
        .iter()
        .flat_map(|t| (0..t.len()).map(move |s| t.segment(s)))
        .map(|s| {
            let [a, b, c, _] = s.power();
            norm(a) + norm(b) + norm(c)
        })
        .fold(0.0, f64::max);
    points.max(power)
}

/// Asserts the certified answers for `queries` against brute force, within the contract's ε.
fn check(curves: &[Curve], queries: &[Vec<f64>], what: &str) {
    let tables: Vec<SegmentTable> = curves.iter().map(Curve::fit).collect();
    let index = CurveIndex::new(&tables).unwrap();
    let e = extent(curves, &tables);
    let flat: Vec<f64> = queries.iter().flatten().copied().collect();
    let many = index.closest_many(&flat).unwrap();
    for (i, q) in queries.iter().enumerate() {
        let one = index.closest(q).unwrap();
        let dim = q.len();
        assert_eq!(
            (one.curve, one.t, &one.point[..], one.distance),
            (
                many.curve[i],
                many.t[i],
                &many.points[i * dim..][..dim],
                many.distance[i]
            ),
            "{what}: query {i}: one and many differ"
        );
        let eps = 1e-9 * (e + q.iter().fold(0.0f64, |m, v| m.max(v.abs())));
        // The reported point is the curve at t, at the reported distance from q.
        let at = cpu_at(&curves[one.curve], &[one.t])
            .curve(0)
            .points
            .to_vec();
        for (k, (a, b)) in at.iter().zip(&one.point).enumerate() {
            assert!((a - b).abs() <= eps, "{what}: query {i}: point {k}");
        }
        let d = one
            .point
            .iter()
            .zip(q)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        assert!(
            (d - one.distance).abs() <= eps,
            "{what}: query {i}: distance"
        );
        let brute = brute_force(&tables, q);
        assert!(
            one.distance <= brute + eps,
            "{what}: query {i} at {q:?}: certified {} (curve {}, t {}) but brute force found {brute}",
            one.distance,
            one.curve,
            one.t
        );
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

/// A grid of query points over [lo, hi]².
fn grid(lo: f64, hi: f64, n: usize) -> Vec<Vec<f64>> {
    let step = (hi - lo) / (n - 1) as f64;
    (0..n * n)
        .map(|i| vec![lo + step * (i % n) as f64, lo + step * (i / n) as f64])
        .collect()
}

#[test]
fn loops_and_cusps() {
    // A cubic with a loop, and one with a cusp at u = 1/2 (B'(1/2) = 0).
    let curves = [
        bezier(vec![0.0, 0.0, 4.0, 4.0, -1.0, 4.0, 3.0, 0.0], 2),
        bezier(vec![5.0, 0.0, 6.0, 1.0, 5.0, 1.0, 6.0, 0.0], 2),
    ];
    check(&curves, &grid(-1.0, 7.0, 17), "loop and cusp");
    // Points inside the loop and at the cusp itself.
    check(
        &curves,
        &[
            vec![1.5, 2.0],
            vec![1.5, 1.2],
            vec![5.5, 0.75],
            vec![5.5, 0.5],
        ],
        "inside the loop, at the cusp",
    );
}

#[test]
fn the_nearest_piece_need_not_own_the_nearest_control_point() {
    // Segment 0 reaches toward (0, 10) with its control points but its curve stays below
    // y = 7.5; segment 1, a flat line at y = 8.5 whose control points are all far from
    // (0, 10) in x, is nearer to it.
    let curves = [
        bezier(vec![-1.0, 0.0, -0.2, 10.0, 0.2, 10.0, 1.0, 0.0], 2),
        bezier(vec![-6.0, 8.5, -5.0, 8.5, 5.0, 8.5, 6.0, 8.5], 2),
    ];
    let tables: Vec<SegmentTable> = curves.iter().map(Curve::fit).collect();
    let hit = CurveIndex::new(&tables)
        .unwrap()
        .closest(&[0.0, 10.0])
        .unwrap();
    assert_eq!(hit.curve, 1);
    assert!((hit.distance - 1.5).abs() < 1e-12, "{hit:?}");
    check(
        &curves,
        &[vec![0.0, 10.0], vec![0.3, 9.0]],
        "far control points",
    );
}

#[test]
fn ties_report_one_of_the_nearest() {
    // Two mirror images about x = 0: a query on the mirror is as near to both.
    let curves = [
        bezier(vec![1.0, 0.0, 2.0, 1.0, 2.0, 2.0, 1.0, 3.0], 2),
        bezier(vec![-1.0, 0.0, -2.0, 1.0, -2.0, 2.0, -1.0, 3.0], 2),
    ];
    let queries: Vec<Vec<f64>> = (0..7).map(|i| vec![0.0, 0.5 * i as f64]).collect();
    check(&curves, &queries, "mirrored pair");
}

#[test]
fn points_on_the_curve_are_at_distance_zero() {
    let curve = catmull_rom(Points::new(2, vec![0.0, 0.0, 1.0, 2.0, 3.0, -1.0, 4.0, 0.5]).unwrap());
    let table = curve.fit();
    let index = CurveIndex::new(std::slice::from_ref(&table)).unwrap();
    for t in [0.0, 0.25, 1.0, 1.7, 3.0] {
        let q = cpu_at(&curve, &[t]).curve(0).points.to_vec();
        let hit = index.closest(&q).unwrap();
        assert!(hit.distance <= 1e-9 * 5.0, "t {t}: {hit:?}");
    }
}

#[test]
fn far_from_the_origin_and_on_uneven_knots() {
    let mut rng = Rng(3);
    // Every point moved to 1e6 from the origin: ε grows with |q|, the answers do not degrade.
    let points = rng.points(10, 2, -1.0, 1.0);
    let moved: Vec<f64> = points.coords().iter().map(|v| v + 1e6).collect();
    let curve = catmull_rom(Points::new(2, moved).unwrap());
    let queries: Vec<Vec<f64>> = (0..40)
        .map(|_| vec![1e6 + rng.range(-1.5, 1.5), 1e6 + rng.range(-1.5, 1.5)])
        .collect();
    check(&[curve], &queries, "at 1e6");
    // An interpolating spline whose knot spacings differ by 1e6.
    let t = vec![0.0, 1e-6, 1.0, 2.0, 1e6];
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: Some(t),
    };
    let points = Points::new(2, vec![0.0, 0.0, 0.1, 0.3, 1.0, 1.0, 2.0, 0.0, 3.0, 2.0]).unwrap();
    let curve = Curve::new(kind, points).unwrap();
    check(&[curve], &grid(-1.0, 4.0, 9), "knots uneven by 1e6");
}

#[test]
fn rational_and_three_dimensional_curves() {
    // A weighted NURBS (weights up to 20) and a 3-D PCHIP.
    let kind = CurveKind::Nurbs {
        knots: vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0],
        weights: Some(vec![1.0, 20.0, 0.3, 5.0, 1.0, 2.0]),
    };
    let points = Points::new(
        2,
        vec![0.0, 0.0, 1.0, 3.0, 2.0, -1.0, 3.0, 2.0, 4.0, 0.0, 5.0, 1.0],
    )
    .unwrap();
    let nurbs = Curve::new(kind, points).unwrap();
    check(&[nurbs], &grid(-1.0, 6.0, 11), "weighted nurbs");
    let mut rng = Rng(17);
    let pchip = Curve::new(
        CurveKind::Hermite {
            slopes: HermiteSlopes::Pchip,
            t: None,
        },
        rng.points(8, 3, -2.0, 2.0),
    )
    .unwrap();
    let queries: Vec<Vec<f64>> = (0..60)
        .map(|_| (0..3).map(|_| rng.range(-3.0, 3.0)).collect())
        .collect();
    check(&[pchip], &queries, "3-D pchip");
}

#[test]
fn bad_queries_are_refused_naming_the_query() {
    let curve = catmull_rom(Points::new(2, vec![0.0, 0.0, 1.0, 1.0, 2.0, 0.0]).unwrap());
    let tables = [curve.fit()];
    let index = CurveIndex::new(&tables).unwrap();
    let e = index.closest(&[1.0]).unwrap_err().to_string();
    assert!(e.contains("closest[0]") && e.contains("got 1"), "{e}");
    let e = index
        .closest_many(&[0.0, 0.0, 1.0, f64::NAN])
        .unwrap_err()
        .to_string();
    assert!(e.contains("closest[1]") && e.contains("NaN"), "{e}");
    let three = Curve::new(CurveKind::Bezier, Points::new(3, vec![0.0; 12]).unwrap()).unwrap();
    let mixed = [tables[0].clone(), three.fit()];
    let e = CurveIndex::new(&mixed).unwrap_err().to_string();
    assert!(e.starts_with("curve 1:"), "{e}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Random sets of random kinds against brute force: no nearer point is ever missed.
    #[test]
    fn random_sets_match_brute_force(seed in 0u64..u64::MAX, curves in 1usize..5) {
        let mut rng = Rng(seed | 1);
        let set: Vec<Curve> = (0..curves)
            .map(|i| {
                let points = rng.points(4 + 3 * (i % 3), 2, -2.0, 2.0);
                match i % 4 {
                    0 => catmull_rom(points),
                    1 => Curve::new(CurveKind::Bezier, points).unwrap(),
                    2 => Curve::new(
                        CurveKind::Uniform { basis: Basis::BSpline, ends: Ends::Closed },
                        points,
                    )
                    .unwrap(),
                    _ => Curve::new(
                        CurveKind::Interpolating { condition: EndCondition::Natural, t: None },
                        points,
                    )
                    .unwrap(),
                }
            })
            .collect();
        let queries: Vec<Vec<f64>> =
            (0..12).map(|_| vec![rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)]).collect();
        check(&set, &queries, &format!("seed {seed}"));
    }
}
