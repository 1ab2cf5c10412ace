//! Properties of the curve families with closed forms: interpolation, continuity, the convex
//! hull, the seeds' worked examples and problems, evaluated by the f64 CPU reference.

use crate::support::{Rng, assert_close, cpu_at};
use splinegpu::{Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, Points, Sampling};

/// One of `Segment::eval`, `deriv`, `deriv2`.
type SegmentFn = fn(&splinegpu::Segment<'_>, f64, &mut [f64]);

fn uniform(basis: Basis, ends: Ends, points: Points) -> Curve {
    Curve::new(CurveKind::Uniform { basis, ends }, points).unwrap()
}

/// Families with their continuity order at the joints (1 = C1, 2 = C2) — the Beta-spline with
/// bias != 1 and the tensioned B-spline are only geometrically continuous, so they are absent.
fn continuous_families() -> Vec<(Basis, usize)> {
    vec![
        (Basis::Cardinal { tension: 0.3 }, 1),
        (Basis::Cardinal { tension: 1.0 }, 1),
        (Basis::CatmullRom, 1),
        (Basis::BSpline, 2),
        (
            Basis::Beta {
                bias: 1.0,
                tension: 0.0,
            },
            2,
        ),
    ]
}

#[test]
fn cardinal_passes_through_its_knots() {
    let mut rng = Rng(7);
    for tension in [0.0, 0.5, 1.0, 2.0] {
        for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
            let points = rng.points(9, 3, -5.0, 5.0);
            let curve = uniform(Basis::Cardinal { tension }, ends, points.clone());
            let n = curve.segment_count();
            let ts: Vec<f64> = (0..=n).map(|i| i as f64).collect();
            let s = cpu_at(&curve, &ts);
            let c = s.curve(0);
            for i in 0..=n {
                // Control ends skip the first point; closed curves come back to P_0 at t = n.
                let knot = match ends {
                    Ends::Control => i + 1,
                    Ends::Repeat => i,
                    Ends::Closed => i % points.len(),
                };
                let what = format!("a = {tension}, {ends:?}, t = {i}");
                assert_close(
                    &c.points[3 * i..3 * i + 3],
                    points.point(knot),
                    1e-12,
                    &what,
                );
            }
        }
    }
}

#[test]
fn families_are_continuous_at_the_joints() {
    let mut rng = Rng(11);
    for (basis, order) in continuous_families() {
        for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
            let curve = uniform(basis.clone(), ends, rng.points(8, 2, -3.0, 3.0));
            let table = curve.fit();
            let (mut left, mut right) = ([0.0; 2], [0.0; 2]);
            for i in 0..table.len() - 1 {
                let (a, b) = (table.segment(i), table.segment(i + 1));
                let checks: [(&str, SegmentFn); 3] = [
                    ("position", |s, u, o| s.eval(u, o)),
                    ("first derivative", |s, u, o| s.deriv(u, o)),
                    ("second derivative", |s, u, o| s.deriv2(u, o)),
                ];
                for (name, f) in &checks[..=order] {
                    f(&a, 1.0, &mut left);
                    f(&b, 0.0, &mut right);
                    assert_close(
                        &left,
                        &right,
                        1e-12,
                        &format!("{basis:?} {ends:?} joint {i}: {name}"),
                    );
                }
            }
        }
    }
}

#[test]
fn cardinal_is_not_c2_in_general() {
    // The check above can fail: a cardinal spline's second derivative jumps at its joints.
    let curve = uniform(
        Basis::CatmullRom,
        Ends::Control,
        Rng(3).points(6, 1, 0.0, 1.0),
    );
    let table = curve.fit();
    let (mut l, mut r) = ([0.0], [0.0]);
    table.segment(0).deriv2(1.0, &mut l);
    table.segment(1).deriv2(0.0, &mut r);
    assert!((l[0] - r[0]).abs() > 1e-6);
}

#[test]
fn closed_curves_join_at_the_seam() {
    let mut rng = Rng(5);
    for (basis, order) in continuous_families() {
        let curve = uniform(basis.clone(), Ends::Closed, rng.points(5, 3, -1.0, 1.0));
        let n = curve.segment_count() as f64;
        let s = cpu_at(&curve, &[0.0, n]);
        let c = s.curve(0);
        let planes = [c.points, c.d1.unwrap(), c.d2.unwrap()];
        for plane in &planes[..=order] {
            assert_close(&plane[..3], &plane[3..], 1e-12, &format!("{basis:?} seam"));
        }
    }
}

#[test]
fn bspline_samples_lie_in_the_hull_of_their_window() {
    let mut rng = Rng(19);
    let points = rng.points(12, 2, -10.0, 10.0);
    let curve = uniform(Basis::BSpline, Ends::Control, points.clone());
    let mut job = EvalJob::new(Derivatives::None);
    job.push(&curve, &Sampling::PerSegment(50)).unwrap();
    let samples = splinegpu::evaluate_reference(&job);
    let c = samples.curve(0);
    for (i, p) in c.points.chunks_exact(2).enumerate() {
        let segment = job.plan(0).loc(i).segment;
        let window: Vec<[f64; 2]> = (segment..segment + 4)
            .map(|j| [points.point(j)[0], points.point(j)[1]])
            .collect();
        assert!(
            inside_hull(&window, [p[0], p[1]]),
            "sample {i} {p:?} outside hull of {window:?}"
        );
    }
}

/// Whether `p` lies in the convex hull of `points` (within 1e-9), by the monotone chain.
fn inside_hull(points: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut pts = points.to_vec();
    pts.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &q in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    (0..hull.len()).all(|i| cross(hull[i], hull[(i + 1) % hull.len()], p) >= -1e-9)
}

#[test]
fn bspline_derivatives_at_knots_follow_the_control_polygon() {
    // Seed 001, problem DD-20: B'(i) is half the vector from B_{i-1} to B_{i+1}, and B''(i)
    // twice the vector from B_i to the midpoint of B_{i-1} B_{i+1}. With the memo's control
    // ends, knot t = j sits at control point B_{j+1}.
    let points = Rng(23).points(9, 3, -4.0, 4.0);
    let curve = uniform(Basis::BSpline, Ends::Control, points.clone());
    let n = curve.segment_count();
    let ts: Vec<f64> = (0..=n).map(|j| j as f64).collect();
    let s = cpu_at(&curve, &ts);
    let c = s.curve(0);
    for j in 0..=n {
        let (prev, mid, next) = (points.point(j), points.point(j + 1), points.point(j + 2));
        let d1: Vec<f64> = (0..3).map(|k| (next[k] - prev[k]) / 2.0).collect();
        let d2: Vec<f64> = (0..3)
            .map(|k| 2.0 * ((prev[k] + next[k]) / 2.0 - mid[k]))
            .collect();
        assert_close(
            &c.d1.unwrap()[3 * j..3 * j + 3],
            &d1,
            1e-12,
            &format!("B'({j})"),
        );
        assert_close(
            &c.d2.unwrap()[3 * j..3 * j + 3],
            &d2,
            1e-12,
            &format!("B''({j})"),
        );
    }
}

#[test]
fn seed_001_worked_example_bspline_equals_its_bezier_segments() {
    // Seed 001 section 5: the relaxed spline through S0..S4 has B-spline control points
    // (1,-1), (-2,2), (1,5), (4,2), (7,5) and the four Bezier segments listed below. Relaxed
    // ends are the uniform B-spline with phantom points 2B_0 - B_1 and 2B_4 - B_3 (then
    // S_0 = B_0 and P''(0) = 0), so the bspline and bezier kinds must draw the same curve.
    let b = [
        [4.0, -4.0],
        [1.0, -1.0],
        [-2.0, 2.0],
        [1.0, 5.0],
        [4.0, 2.0],
        [7.0, 5.0],
        [10.0, 8.0],
    ];
    let bezier = [
        [1.0, -1.0],
        [0.0, 0.0],
        [-1.0, 1.0],
        [-1.0, 2.0],
        [-1.0, 3.0],
        [0.0, 4.0],
        [1.0, 4.0],
        [2.0, 4.0],
        [3.0, 3.0],
        [4.0, 3.0],
        [5.0, 3.0],
        [6.0, 4.0],
        [7.0, 5.0],
    ];
    let flat = |p: &[[f64; 2]]| Points::new(2, p.iter().flatten().copied().collect()).unwrap();
    let bspline = uniform(Basis::BSpline, Ends::Control, flat(&b));
    let bezier = Curve::new(CurveKind::Bezier, flat(&bezier)).unwrap();
    let ts: Vec<f64> = (0..=40).map(|i| f64::from(i) / 10.0).collect();
    let (sb, sz) = (cpu_at(&bspline, &ts), cpu_at(&bezier, &ts));
    let (cb, cz) = (sb.curve(0), sz.curve(0));
    assert_close(cb.points, cz.points, 1e-12, "positions");
    assert_close(cb.d1.unwrap(), cz.d1.unwrap(), 1e-12, "first derivatives");
    assert_close(cb.d2.unwrap(), cz.d2.unwrap(), 1e-12, "second derivatives");
    // It interpolates the data S_0..S_4 at t = 0..4 and is relaxed at both ends.
    let data = [1.0, -1.0, -1.0, 2.0, 1.0, 4.0, 4.0, 3.0, 7.0, 5.0];
    let at_knots: Vec<f64> = (0..5)
        .flat_map(|i| cb.points[20 * i..20 * i + 2].to_vec())
        .collect();
    assert_close(&at_knots, &data, 1e-12, "through S_i");
    assert_close(&cb.d2.unwrap()[..2], &[0.0, 0.0], 1e-12, "relaxed start");
    assert_close(&cb.d2.unwrap()[80..], &[0.0, 0.0], 1e-12, "relaxed end");
}

#[test]
fn derivatives_match_finite_differences() {
    let mut rng = Rng(31);
    let bases = [
        Basis::Cardinal { tension: 0.8 },
        Basis::BSpline,
        Basis::TensionedBSpline { tension: 0.4 },
        Basis::Beta {
            bias: 1.5,
            tension: 2.0,
        },
        Basis::Matrix([
            [1.0, -2.0, 0.5, 0.0],
            [0.0, 3.0, -1.0, 0.25],
            [2.0, 0.0, 0.0, 1.0],
            [0.1, 0.2, 0.3, 0.4],
        ]),
    ];
    for basis in bases {
        let curve = uniform(basis.clone(), Ends::Repeat, rng.points(7, 2, -2.0, 2.0));
        let h = 1e-5;
        let ts = [0.3, 1.7, 4.45];
        let shifted: Vec<f64> = ts.iter().flat_map(|&t| [t - h, t, t + h]).collect();
        let s = cpu_at(&curve, &shifted);
        let c = s.curve(0);
        for i in 0..ts.len() {
            let p = |j: usize| &c.points[2 * (3 * i + j)..2 * (3 * i + j) + 2];
            let d = |plane: &[f64], j: usize| plane[2 * (3 * i + j)..2 * (3 * i + j) + 2].to_vec();
            let central: Vec<f64> = (0..2).map(|k| (p(2)[k] - p(0)[k]) / (2.0 * h)).collect();
            let second: Vec<f64> = (0..2)
                .map(|k| (p(2)[k] - 2.0 * p(1)[k] + p(0)[k]) / (h * h))
                .collect();
            assert_close(
                &d(c.d1.unwrap(), 1),
                &central,
                1e-6,
                &format!("{basis:?} d1 at {}", ts[i]),
            );
            assert_close(
                &d(c.d2.unwrap(), 1),
                &second,
                1e-3,
                &format!("{basis:?} d2 at {}", ts[i]),
            );
        }
    }
}

#[test]
fn per_segment_sampling_follows_the_memo_count_and_t() {
    // Memo appendix: (n - 3) * grain + 1 points; t = i + j/k; the last sample is the end point.
    let points = Rng(2).points(10, 2, 0.0, 1.0);
    let curve = uniform(Basis::CatmullRom, Ends::Control, points.clone());
    let mut job = EvalJob::new(Derivatives::None);
    job.push(&curve, &Sampling::PerSegment(6)).unwrap();
    let s = splinegpu::evaluate_reference(&job);
    let c = s.curve(0);
    assert_eq!(c.t.len(), (10 - 3) * 6 + 1);
    for (i, t) in c.t.iter().enumerate() {
        assert_eq!(*t, (i / 6) as f64 + (i % 6) as f64 / 6.0);
    }
    assert_close(
        &c.points[c.points.len() - 2..],
        points.point(8),
        1e-12,
        "final point",
    );
}

#[test]
fn at_sampling_uses_the_segment_that_starts_at_a_knot() {
    let curve = uniform(Basis::BSpline, Ends::Repeat, Rng(4).points(5, 1, 0.0, 1.0));
    let table = curve.fit();
    let plan =
        splinegpu::SamplePlan::new(&table, &Sampling::At(vec![0.0, 2.0, 2.5, 4.0, 2.0])).unwrap();
    let locs: Vec<(usize, f64)> = (0..plan.len())
        .map(|i| (plan.loc(i).segment, plan.loc(i).u))
        .collect();
    assert_eq!(locs, [(0, 0.0), (2, 0.0), (2, 0.5), (3, 1.0), (2, 0.0)]);
    let e = splinegpu::SamplePlan::new(&table, &Sampling::At(vec![1.0, 4.000001])).unwrap_err();
    assert!(e.to_string().contains("at[1] = 4.000001"), "{e}");
}

#[test]
fn end_conventions_window_as_the_contract_says() {
    // repeat: [P0, P0, P1, .., Pn-1, Pn-1]; closed: [Pn-1, P0, .., Pn-1, P0, P1].
    let points = Points::new(1, vec![1.0, 10.0, 100.0, 1000.0]).unwrap();
    let m = splinegpu::basis::bspline_rows();
    let window_value = |w: [f64; 4], u: f64| {
        let uu = [u * u * u, u * u, u, 1.0];
        (0..4)
            .map(|r| uu[r] * (0..4).map(|j| m[r][j] * w[j]).sum::<f64>())
            .sum::<f64>()
    };
    let cases = [
        (
            Ends::Repeat,
            3,
            vec![
                [1.0, 1.0, 10.0, 100.0],
                [1.0, 10.0, 100.0, 1000.0],
                [10.0, 100.0, 1000.0, 1000.0],
            ],
        ),
        (
            Ends::Closed,
            4,
            vec![
                [1000.0, 1.0, 10.0, 100.0],
                [1.0, 10.0, 100.0, 1000.0],
                [10.0, 100.0, 1000.0, 1.0],
                [100.0, 1000.0, 1.0, 10.0],
            ],
        ),
    ];
    for (ends, segments, windows) in cases {
        let curve = uniform(Basis::BSpline, ends, points.clone());
        assert_eq!(curve.segment_count(), segments);
        let ts: Vec<f64> = (0..segments).map(|i| i as f64 + 0.25).collect();
        let s = cpu_at(&curve, &ts);
        let expected: Vec<f64> = windows.iter().map(|w| window_value(*w, 0.25)).collect();
        assert_close(s.curve(0).points, &expected, 1e-9, &format!("{ends:?}"));
    }
}

#[test]
fn too_few_points_are_errors() {
    let cases = [
        (
            CurveKind::Uniform {
                basis: Basis::BSpline,
                ends: Ends::Control,
            },
            3,
        ),
        (
            CurveKind::Uniform {
                basis: Basis::BSpline,
                ends: Ends::Repeat,
            },
            1,
        ),
        (
            CurveKind::Uniform {
                basis: Basis::BSpline,
                ends: Ends::Closed,
            },
            2,
        ),
        (CurveKind::Bezier, 3),
        (CurveKind::Bezier, 5),
    ];
    for (kind, n) in cases {
        let e = Curve::new(kind.clone(), Points::new(2, vec![0.0; 2 * n]).unwrap()).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("points"), "{kind:?} with {n}");
    }
}
