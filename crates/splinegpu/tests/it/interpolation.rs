//! Interpolating splines: the seeds' worked example and problems, SciPy's CubicSpline, closed
//! forms, an independent dense solve, and the cardinal basis functions.

use crate::scipy_fixture::{floats, rows};
use crate::support::{Rng, assert_close, cpu_at};
use splinegpu::accuracy::cpu_bound;
use splinegpu::{
    CardinalBasis, Curve, CurveKind, End, EndCondition, EndKind, Fitter, Points, SegmentTable,
};

fn interpolating(condition: EndCondition, t: Option<Vec<f64>>, points: Points) -> Curve {
    Curve::new(CurveKind::Interpolating { condition, t }, points).unwrap()
}

fn points2(p: &[[f64; 2]]) -> Points {
    Points::new(2, p.iter().flatten().copied().collect()).unwrap()
}

fn conditions(dim: usize) -> Vec<EndCondition> {
    vec![
        EndCondition::Natural,
        EndCondition::Clamped {
            start: (0..dim).map(|k| 0.5 - k as f64).collect(),
            end: (0..dim).map(|k| 1.5 * k as f64 - 2.0).collect(),
        },
        EndCondition::Periodic,
        EndCondition::NotAKnot,
    ]
}

/// `n` points, closed when `condition` is periodic.
/// Ends given one at a time (SciPy's bc_type pairs): second derivatives, a slope and a
/// second derivative, not-a-knot and a second derivative, a slope and not-a-knot.
fn each_conditions(dim: usize) -> Vec<EndCondition> {
    let values = |scale: f64| (0..dim).map(|k| scale * (k as f64 - 0.7)).collect();
    vec![
        EndCondition::Each {
            start: End::SecondDerivative(values(3.0)),
            end: End::SecondDerivative(values(-1.5)),
        },
        EndCondition::Each {
            start: End::FirstDerivative(values(2.0)),
            end: End::SecondDerivative(values(0.5)),
        },
        EndCondition::Each {
            start: End::NotAKnot,
            end: End::SecondDerivative(values(-4.0)),
        },
        EndCondition::Each {
            start: End::FirstDerivative(values(-1.0)),
            end: End::NotAKnot,
        },
    ]
}

fn data(rng: &mut Rng, n: usize, dim: usize, condition: &EndCondition) -> Points {
    let mut coords: Vec<f64> = (0..n * dim).map(|_| rng.range(-5.0, 5.0)).collect();
    if *condition == EndCondition::Periodic {
        let first = coords[..dim].to_vec();
        coords[(n - 1) * dim..].copy_from_slice(&first);
    }
    Points::new(dim, coords).unwrap()
}

/// Knots whose neighbouring spacings differ by up to `ratio` either way, starting at `start`.
fn uneven_knots(n: usize, ratio: f64, start: f64) -> Vec<f64> {
    let pattern = [
        1.0,
        1.0 / ratio,
        0.7,
        ratio.sqrt(),
        2.0,
        0.3 / ratio.sqrt(),
        ratio / 3.0,
    ];
    let mut t = vec![start];
    for i in 0..n - 1 {
        t.push(t[i] + pattern[i % pattern.len()]);
    }
    t
}

#[test]
fn seed_001_worked_example_gives_its_bspline_and_bezier_points() {
    // Seed 001 §5: the relaxed (natural) spline through S0..S4 with uniform t.
    let s = points2(&[[1.0, -1.0], [-1.0, 2.0], [1.0, 4.0], [4.0, 3.0], [7.0, 5.0]]);
    let table = interpolating(EndCondition::Natural, None, s).fit();
    let b = table.bspline_control_points().expect("uniform knots");
    assert_close(
        &b,
        &[1.0, -1.0, -2.0, 2.0, 1.0, 5.0, 4.0, 2.0, 7.0, 5.0],
        1e-12,
        "B-spline control points",
    );
    let expected = [
        [[1.0, -1.0], [0.0, 0.0], [-1.0, 1.0], [-1.0, 2.0]],
        [[-1.0, 2.0], [-1.0, 3.0], [0.0, 4.0], [1.0, 4.0]],
        [[1.0, 4.0], [2.0, 4.0], [3.0, 3.0], [4.0, 3.0]],
        [[4.0, 3.0], [5.0, 3.0], [6.0, 4.0], [7.0, 5.0]],
    ];
    for (i, bezier) in expected.iter().enumerate() {
        let got: Vec<f64> = table.segment(i).bezier_points().unwrap().concat();
        let want: Vec<f64> = bezier.iter().flatten().copied().collect();
        assert_close(&got, &want, 1e-12, &format!("Bezier #{}", i + 1));
    }
}

#[test]
fn relaxed_spline_through_three_points_at_one_half() {
    // Seed 001, problem DD-4(d): P(1/2) = 13/32 S0 + 22/32 S1 − 3/32 S2.
    let s = points2(&[[0.3, 2.0], [1.7, -1.0], [-0.4, 5.5]]);
    let curve = interpolating(EndCondition::Natural, None, s.clone());
    let samples = cpu_at(&curve, &[0.5]);
    let expected: Vec<f64> = (0..2)
        .map(|k| (13.0 * s.point(0)[k] + 22.0 * s.point(1)[k] - 3.0 * s.point(2)[k]) / 32.0)
        .collect();
    assert_close(samples.curve(0).points, &expected, 1e-14, "P(1/2)");
    // Problem DD-5: the same numbers are the basis functions' values at t = 1/2.
    let basis = CardinalBasis::new(&[0.0, 1.0, 2.0], EndKind::Natural).unwrap();
    assert_close(
        &basis.weights_at(0.5).unwrap(),
        &[13.0 / 32.0, 22.0 / 32.0, -3.0 / 32.0],
        1e-15,
        "f_j(1/2)",
    );
}

#[test]
fn clamped_spline_of_problem_dd13() {
    // Seed 001, problem DD-13: through (0,0), (1,1), (2,2) with P'(0) = P'(2) = (1,0). The
    // clamped "1 4 1" system [2 1 0; 1 4 1; 0 1 2] B = [3S0 + v; 6S1; 3S2 − w] =
    // [(1,0); (6,6); (5,6)], with the inverse the problem gives, 1/12 [7 -2 1; -2 4 -2; 1 -2 7]:
    //   B0 = (7(1,0) − 2(6,6) + (5,6))/12 = (0, −1/2)
    //   B1 = (−2(1,0) + 4(6,6) − 2(5,6))/12 = (1, 1)
    //   B2 = ((1,0) − 2(6,6) + 7(5,6))/12 = (2, 5/2)
    // and Bezier segment i is S_i, 2/3 B_i + 1/3 B_{i+1}, 1/3 B_i + 2/3 B_{i+1}, S_{i+1}.
    let condition = EndCondition::Clamped {
        start: vec![1.0, 0.0],
        end: vec![1.0, 0.0],
    };
    let table = interpolating(
        condition,
        None,
        points2(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]),
    )
    .fit();
    assert_close(
        &table.bspline_control_points().unwrap(),
        &[0.0, -0.5, 1.0, 1.0, 2.0, 2.5],
        1e-14,
        "B",
    );
    let third = 1.0 / 3.0;
    assert_close(
        &table.segment(0).bezier_points().unwrap().concat(),
        &[0.0, 0.0, third, 0.0, 2.0 * third, 0.5, 1.0, 1.0],
        1e-14,
        "Bezier #1",
    );
    assert_close(
        &table.segment(1).bezier_points().unwrap().concat(),
        &[1.0, 1.0, 4.0 * third, 1.5, 5.0 * third, 2.0, 2.0, 2.0],
        1e-14,
        "Bezier #2",
    );
}

#[test]
fn fits_match_scipy_cubic_spline() {
    // tests/fixtures/make_scipy_fixtures.py wrote this file with SciPy's CubicSpline.
    let doc: serde_json::Value =
        serde_json::from_str(include_str!("../fixtures/scipy_cubic_spline.json")).unwrap();
    let cases = doc["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 12);
    for case in cases {
        let dim = case["dim"].as_u64().unwrap() as usize;
        let name = case["condition"].as_str().unwrap();
        let condition = match name {
            "natural" => EndCondition::Natural,
            "periodic" => EndCondition::Periodic,
            "not-a-knot" => EndCondition::NotAKnot,
            _ => EndCondition::Clamped {
                start: floats(&case["start_derivative"]),
                end: floats(&case["end_derivative"]),
            },
        };
        let points = Points::new(dim, rows(&case["points"])).unwrap();
        let curve = interpolating(condition, Some(floats(&case["t"])), points);
        let x = floats(&case["x"]);
        let ours = cpu_at(&curve, &x);
        let table = curve.fit();
        let plan = splinegpu::SamplePlan::new(&table, &splinegpu::Sampling::At(x.clone())).unwrap();
        let c = ours.curve(0);
        for (order, (key, plane)) in [
            ("y", c.points),
            ("d1", c.d1.unwrap()),
            ("d2", c.d2.unwrap()),
        ]
        .into_iter()
        .enumerate()
        {
            let expected = rows(&case[key]);
            for (i, (got, want)) in plane.iter().zip(&expected).enumerate() {
                let segment = table.segment(plan.loc(i / dim).segment);
                let bound =
                    cpu_bound(&segment, table.extent(), order, i % dim) + 1e-13 * want.abs();
                assert!(
                    (got - want).abs() <= bound,
                    "{name} D={dim} {key} at x = {}: {got} vs SciPy {want} (bound {bound})",
                    x[i / dim]
                );
            }
        }
    }
}

#[test]
fn every_end_condition_is_c2_and_meets_its_ends() {
    let mut rng = Rng(41);
    // Every condition at its fewest points, and large fits solved in blocks of 65,536 rows on
    // several threads: the last end's neighbour (a not-a-knot end's own row) first in its
    // block (131,074 points) and the separator before a block of one row (65,537).
    let cases = conditions(3).into_iter().chain(each_conditions(3));
    let cases = cases.flat_map(|c| {
        let fewest = c.min_points();
        [fewest, 15, 65_537, 131_074].map(|n| (c.clone(), n))
    });
    for (condition, n) in cases {
        let t = uneven_knots(n, 1e3, 10.0);
        let points = data(&mut rng, n, 3, &condition);
        let curve = interpolating(condition.clone(), Some(t.clone()), points.clone());
        let table = curve.fit();
        let (mut l, mut r) = ([0.0; 3], [0.0; 3]);
        let close =
            |a: &[f64], b: &[f64], scale: f64, what: &str| assert_close(a, b, 1e-9 * scale, what);
        for i in 0..table.len() - 1 {
            let (a, b) = (table.segment(i), table.segment(i + 1));
            let scale = |o| {
                (0..3)
                    .map(|k| splinegpu::accuracy::promise_scale(&a, table.extent(), o, k))
                    .fold(0.0, f64::max)
            };
            a.eval(1.0, &mut l);
            b.eval(0.0, &mut r);
            close(
                &l,
                &r,
                scale(0),
                &format!("{condition:?} value at knot {}", i + 1),
            );
            close(
                &l,
                points.point(i + 1),
                scale(0),
                "passes through the point",
            );
            a.deriv(1.0, &mut l);
            b.deriv(0.0, &mut r);
            close(
                &l,
                &r,
                scale(1),
                &format!("{condition:?} slope at knot {}", i + 1),
            );
            a.deriv2(1.0, &mut l);
            b.deriv2(0.0, &mut r);
            close(
                &l,
                &r,
                scale(2),
                &format!("{condition:?} curvature at knot {}", i + 1),
            );
        }
        let (first, last) = (table.segment(0), table.segment(table.len() - 1));
        let end_scale = |o| {
            (0..3)
                .map(|k| splinegpu::accuracy::promise_scale(&first, table.extent(), o, k))
                .fold(0.0, f64::max)
        };
        // Not-a-knot between segments x and y: the third derivative 6A/Δ³ is the same on both
        // sides, to 1e-9 of its coefficient scale 6(|A| + |B| + |C|)/Δ³, like the other
        // derivatives.
        let not_a_knot = |x: usize, y: usize| {
            let third =
                |s: &splinegpu::Segment<'_>, k: usize| 6.0 * s.power()[0][k] / s.dt().powi(3);
            let third_scale = |s: &splinegpu::Segment<'_>, k: usize| {
                let [a, b, c, _] = s.power();
                6.0 * (a[k].abs() + b[k].abs() + c[k].abs()) / s.dt().powi(3)
            };
            let (sx, sy) = (table.segment(x), table.segment(y));
            for k in 0..3 {
                let (p, q) = (third(&sx, k), third(&sy, k));
                let tol = 1e-9 * third_scale(&sx, k).max(third_scale(&sy, k));
                assert!(
                    (p - q).abs() <= tol,
                    "not-a-knot at {y}: {p} vs {q} (tolerance {tol})"
                );
            }
        };
        match &condition {
            EndCondition::Natural => {
                first.deriv2(0.0, &mut l);
                last.deriv2(1.0, &mut r);
                close(&l, &[0.0; 3], end_scale(2), "natural start");
                close(&r, &[0.0; 3], end_scale(2).max(1.0), "natural end");
            }
            EndCondition::Clamped { start, end } => {
                first.deriv(0.0, &mut l);
                last.deriv(1.0, &mut r);
                close(&l, start, 1.0, "clamped start");
                close(&r, end, 1.0, "clamped end");
            }
            EndCondition::Periodic => {
                for order in 0..3 {
                    let f: [fn(&splinegpu::Segment<'_>, f64, &mut [f64]); 3] = [
                        |s, u, o| s.eval(u, o),
                        |s, u, o| s.deriv(u, o),
                        |s, u, o| s.deriv2(u, o),
                    ];
                    f[order](&first, 0.0, &mut l);
                    f[order](&last, 1.0, &mut r);
                    close(
                        &l,
                        &r,
                        end_scale(order).max(1.0),
                        &format!("periodic seam, derivative {order}"),
                    );
                }
            }
            EndCondition::NotAKnot => {
                not_a_knot(0, 1);
                not_a_knot(table.len() - 2, table.len() - 1);
            }
            EndCondition::Each { start, end } => {
                let ends = [
                    (start, &first, 0.0, (0, 1)),
                    // (A not-a-knot end has at least two segments; a spline of two points
                    // has one.)
                    (
                        end,
                        &last,
                        1.0,
                        (table.len().saturating_sub(2), table.len() - 1),
                    ),
                ];
                for (condition, segment, u, (x, y)) in ends {
                    match condition {
                        End::FirstDerivative(v) => {
                            segment.deriv(u, &mut l);
                            close(&l, v, end_scale(1).max(1.0), "a given slope");
                        }
                        End::SecondDerivative(v) => {
                            segment.deriv2(u, &mut l);
                            close(&l, v, end_scale(2).max(1.0), "a given second derivative");
                        }
                        End::NotAKnot => not_a_knot(x, y),
                    }
                }
            }
        }
    }
}

#[test]
fn clamped_and_not_a_knot_reproduce_a_cubic() {
    // P(t) = (t³ − 2t² + 0.5t + 3, −t³ + t): both conditions recover any cubic exactly.
    let p = |t: f64| [t * t * t - 2.0 * t * t + 0.5 * t + 3.0, -t * t * t + t];
    let dp = |t: f64| [3.0 * t * t - 4.0 * t + 0.5, -3.0 * t * t + 1.0];
    let t = vec![-1.0, -0.2, 0.1, 1.5, 1.6, 3.0];
    let points = Points::new(2, t.iter().flat_map(|&x| p(x)).collect()).unwrap();
    let clamped = EndCondition::Clamped {
        start: dp(-1.0).to_vec(),
        end: dp(3.0).to_vec(),
    };
    for condition in [clamped, EndCondition::NotAKnot] {
        let curve = interpolating(condition.clone(), Some(t.clone()), points.clone());
        let ts = [-0.9, 0.0, 0.7, 2.2, 2.9];
        let s = cpu_at(&curve, &ts);
        let expected: Vec<f64> = ts.iter().flat_map(|&x| p(x)).collect();
        assert_close(
            s.curve(0).points,
            &expected,
            1e-12,
            &format!("{condition:?}"),
        );
    }
}

#[test]
fn collinear_points_stay_on_their_line() {
    let t = uneven_knots(9, 50.0, 0.0);
    let points = Points::new(2, t.iter().flat_map(|&x| [2.0 * x + 1.0, -x]).collect()).unwrap();
    let curve = interpolating(EndCondition::Natural, Some(t.clone()), points);
    let ts: Vec<f64> = (0..50)
        .map(|i| t[0] + (t[8] - t[0]) * f64::from(i) / 49.0)
        .collect();
    let s = cpu_at(&curve, &ts);
    let expected: Vec<f64> = ts.iter().flat_map(|&x| [2.0 * x + 1.0, -x]).collect();
    assert_close(s.curve(0).points, &expected, 1e-9, "on the line");
}

/// The spline as an independent dense system: 4(n−1) power coefficients per coordinate from
/// interpolation, C1 and C2 at every interior knot and the two end equations, each row scaled to
/// unit maximum, solved by Gaussian elimination with partial pivoting.
#[expect(
    clippy::needless_range_loop,
    reason = "Gaussian elimination, indexed as the textbook writes it"
)]
fn dense_fit(
    t: &[f64],
    values: &[f64],
    dim: usize,
    condition: &EndCondition,
) -> Vec<Vec<[f64; 4]>> {
    let segments = t.len() - 1;
    let unknowns = 4 * segments;
    let dt: Vec<f64> = (0..segments).map(|i| t[i + 1] - t[i]).collect();
    // Rows of (coefficients over [A_i, B_i, C_i, D_i]..., right-hand side per coordinate).
    let mut rows: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    let zero = vec![0.0; dim];
    let point = |i: usize| values[i * dim..(i + 1) * dim].to_vec();
    let row = |entries: &[(usize, f64)]| {
        let mut r = vec![0.0; unknowns];
        for &(j, v) in entries {
            r[j] += v;
        }
        r
    };
    // P'(1)/Δ and P''(1)/Δ² of segment i, P'(0)/Δ and P''(0)/Δ² of segment j, as entries.
    let slope_end = |i: usize| {
        vec![
            (4 * i, 3.0 / dt[i]),
            (4 * i + 1, 2.0 / dt[i]),
            (4 * i + 2, 1.0 / dt[i]),
        ]
    };
    let curve_end = |i: usize| {
        vec![
            (4 * i, 6.0 / dt[i].powi(2)),
            (4 * i + 1, 2.0 / dt[i].powi(2)),
        ]
    };
    let slope_start = |j: usize| vec![(4 * j + 2, 1.0 / dt[j])];
    let curve_start = |j: usize| vec![(4 * j + 1, 2.0 / dt[j].powi(2))];
    let negate = |v: Vec<(usize, f64)>| v.into_iter().map(|(j, x)| (j, -x)).collect::<Vec<_>>();
    for i in 0..segments {
        rows.push((row(&[(4 * i + 3, 1.0)]), point(i)));
        rows.push((
            row(&[
                (4 * i, 1.0),
                (4 * i + 1, 1.0),
                (4 * i + 2, 1.0),
                (4 * i + 3, 1.0),
            ]),
            point(i + 1),
        ));
    }
    let mut joints: Vec<(usize, usize)> = (0..segments - 1).map(|i| (i, i + 1)).collect();
    if *condition == EndCondition::Periodic {
        joints.push((segments - 1, 0));
    }
    for (i, j) in joints {
        rows.push((
            row(&[slope_end(i), negate(slope_start(j))].concat()),
            zero.clone(),
        ));
        rows.push((
            row(&[curve_end(i), negate(curve_start(j))].concat()),
            zero.clone(),
        ));
    }
    let last = segments - 1;
    let natural = End::SecondDerivative(zero.clone());
    let ends = match condition {
        EndCondition::Natural => vec![natural.clone(), natural],
        EndCondition::Clamped { start, end } => vec![
            End::FirstDerivative(start.clone()),
            End::FirstDerivative(end.clone()),
        ],
        EndCondition::NotAKnot => vec![End::NotAKnot, End::NotAKnot],
        EndCondition::Each { start, end } => vec![start.clone(), end.clone()],
        EndCondition::Periodic => Vec::new(),
    };
    // Per end: its slope, second derivative, or the third derivative's jump at its neighbour.
    let sides = [
        (slope_start(0), curve_start(0), (0, 1)),
        (
            slope_end(last),
            curve_end(last),
            (last.saturating_sub(1), last),
        ),
    ];
    for (end, (slope, curve, (i, j))) in ends.iter().zip(sides) {
        rows.push(match end {
            End::FirstDerivative(v) => (row(&slope), v.clone()),
            End::SecondDerivative(v) => (row(&curve), v.clone()),
            End::NotAKnot => (
                row(&[(4 * i, 1.0 / dt[i].powi(3)), (4 * j, -1.0 / dt[j].powi(3))]),
                zero.clone(),
            ),
        });
    }
    assert_eq!(rows.len(), unknowns);
    (0..dim)
        .map(|k| {
            let mut m: Vec<Vec<f64>> = Vec::new();
            let mut b = Vec::new();
            for (r, rhs) in &rows {
                let s = r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                m.push(r.iter().map(|x| x / s).collect());
                b.push(rhs[k] / s);
            }
            for col in 0..unknowns {
                let p = (col..unknowns)
                    .max_by(|&x, &y| m[x][col].abs().total_cmp(&m[y][col].abs()))
                    .unwrap();
                m.swap(col, p);
                b.swap(col, p);
                for r in col + 1..unknowns {
                    let f = m[r][col] / m[col][col];
                    for c in col..unknowns {
                        m[r][c] -= f * m[col][c];
                    }
                    b[r] -= f * b[col];
                }
            }
            let mut x = vec![0.0; unknowns];
            for r in (0..unknowns).rev() {
                let s: f64 = (r + 1..unknowns).map(|c| m[r][c] * x[c]).sum();
                x[r] = (b[r] - s) / m[r][r];
            }
            (0..segments)
                .map(|i| [x[4 * i], x[4 * i + 1], x[4 * i + 2], x[4 * i + 3]])
                .collect()
        })
        .collect()
}

#[test]
#[expect(
    clippy::needless_range_loop,
    reason = "the dense reference indexes rows and columns as the equations are written"
)]
fn o_n_fits_agree_with_a_dense_solve_at_spacing_ratios_up_to_1e6() {
    // Seed 002 found the periodic block elimination ill-conditioned; the cyclic slope system
    // with Sherman–Morrison must agree with dense pivoted elimination even at extreme spacings.
    let mut rng = Rng(1e6 as u64);
    for ratio in [1.0, 1e3, 1e6] {
        for condition in conditions(2).into_iter().chain(each_conditions(2)) {
            let n = 14;
            let t = uneven_knots(n, ratio, 1e4);
            let points = data(&mut rng, n, 2, &condition);
            let table = interpolating(condition.clone(), Some(t.clone()), points.clone()).fit();
            let dense = dense_fit(&t, points.coords(), 2, &condition);
            for i in 0..table.len() {
                let segment = table.segment(i);
                for k in 0..2 {
                    for (order, (ours, theirs)) in segment_values(&segment, k)
                        .iter()
                        .zip(dense_values(dense[k][i], segment.dt()))
                        .enumerate()
                    {
                        for (u, (a, b)) in ours.iter().zip(theirs).enumerate() {
                            let bound =
                                cpu_bound(&segment, table.extent(), order, k) + 1e-12 * b.abs();
                            assert!(
                                (a - b).abs() <= bound,
                                "ratio {ratio:e} {condition:?} segment {i} coord {k} order {order} at u[{u}]: {a} vs dense {b}"
                            );
                        }
                    }
                }
            }
        }
    }
}

const US: [f64; 3] = [0.0, 0.4, 1.0];

/// Value, slope and curvature of coordinate k of `segment` at `US`.
fn segment_values(segment: &splinegpu::Segment<'_>, k: usize) -> [[f64; 3]; 3] {
    let dim = segment.power()[0].len();
    let mut out = [[0.0; 3]; 3];
    let mut v = vec![0.0; dim];
    for (j, &u) in US.iter().enumerate() {
        segment.eval(u, &mut v);
        out[0][j] = v[k];
        segment.deriv(u, &mut v);
        out[1][j] = v[k];
        segment.deriv2(u, &mut v);
        out[2][j] = v[k];
    }
    out
}

fn dense_values([a, b, c, d]: [f64; 4], dt: f64) -> [[f64; 3]; 3] {
    let f = |u: f64| {
        [
            d + u * (c + u * (b + u * a)),
            (c + u * (2.0 * b + 3.0 * u * a)) / dt,
            (2.0 * b + 6.0 * u * a) / (dt * dt),
        ]
    };
    let v = US.map(f);
    [
        [v[0][0], v[1][0], v[2][0]],
        [v[0][1], v[1][1], v[2][1]],
        [v[0][2], v[1][2], v[2][2]],
    ]
}

#[test]
fn cardinal_basis_combinations_equal_direct_fits() {
    let mut rng = Rng(8);
    for condition in conditions(4) {
        let t = uneven_knots(11, 20.0, -2.0);
        let basis = CardinalBasis::new(&t, condition.kind().unwrap()).unwrap();
        for _channel in 0..3 {
            let points = data(&mut rng, 11, 4, &condition);
            let direct = interpolating(condition.clone(), Some(t.clone()), points.clone()).fit();
            let derivatives = match &condition {
                EndCondition::Clamped { start, end } => Some((start.as_slice(), end.as_slice())),
                _ => None,
            };
            let combined = basis.combine(&points, derivatives).unwrap();
            assert_tables_close(&direct, &combined, 1e-12, &format!("{condition:?}"));
            // P(t) = Σ_j f_j(t) S_j at one time, the "linear combination at each time" use.
            let weights = basis.weights_at(3.3).unwrap();
            let s = cpu_at(
                &interpolating(condition.clone(), Some(t.clone()), points.clone()),
                &[3.3],
            );
            let inputs: Vec<&[f64]> = match derivatives {
                Some((a, b)) => (0..11).map(|j| points.point(j)).chain([a, b]).collect(),
                None => (0..basis.inputs()).map(|j| points.point(j)).collect(),
            };
            let combined_point: Vec<f64> = (0..4)
                .map(|k| weights.iter().zip(&inputs).map(|(w, p)| w * p[k]).sum())
                .collect();
            assert_close(&combined_point, s.curve(0).points, 1e-12, "weights at t");
        }
    }
}

fn assert_tables_close(a: &SegmentTable, b: &SegmentTable, tol: f64, what: &str) {
    assert_eq!(a.knots(), b.knots());
    for i in 0..a.len() {
        let (x, y) = (a.segment(i).power().concat(), b.segment(i).power().concat());
        let scale = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        assert_close(&x, &y, tol * scale, &format!("{what} segment {i}"));
    }
}

/// Scaling every knot by s leaves each segment's cubic in its local u as it was (the slopes
/// scale by 1/s, the spacings by s): fits whose spacings are near the ends of f64's range,
/// where the product of two spacings underflows or overflows, give the unscaled fit's
/// coefficients; so does a natural fit of 70,000 knots, solved in blocks. (s is a power of
/// two, so the scaled knots are exact.)
#[test]
fn fits_do_not_depend_on_the_knots_scale() {
    let mut rng = Rng(77);
    let mut fitter = Fitter::new();
    let (mut want, mut got) = (SegmentTable::default(), SegmentTable::default());
    let cases = conditions(3)
        .into_iter()
        .map(|c| (40, c))
        .chain([(70_000, EndCondition::Natural)]);
    for (n, condition) in cases {
        let t = uneven_knots(n, 100.0, 0.0);
        let points = data(&mut rng, n, 3, &condition);
        fitter
            .fit_into(&t, points.coords(), 3, &condition, &mut want)
            .unwrap();
        for s in [-1000, -530, 530, 1000].map(|e| 2f64.powi(e)) {
            let scaled: Vec<f64> = t.iter().map(|x| x * s).collect();
            let condition = match &condition {
                EndCondition::Clamped { start, end } => EndCondition::Clamped {
                    start: start.iter().map(|v| v / s).collect(),
                    end: end.iter().map(|v| v / s).collect(),
                },
                other => other.clone(),
            };
            fitter
                .fit_into(&scaled, points.coords(), 3, &condition, &mut got)
                .unwrap();
            for i in 0..n - 1 {
                let (x, y) = (
                    want.segment(i).power().concat(),
                    got.segment(i).power().concat(),
                );
                let scale = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                let what = format!("{condition:?} n {n} scale {s:e} segment {i}");
                assert_close(&y, &x, 1e-12 * scale, &what);
            }
        }
    }
}

#[test]
fn a_reused_fitter_gives_the_same_table() {
    let mut rng = Rng(12);
    let mut fitter = Fitter::new();
    let mut table = SegmentTable::default();
    for (n, condition) in [
        (30, EndCondition::NotAKnot),
        (5, EndCondition::Natural),
        (12, EndCondition::Periodic),
    ] {
        let t = uneven_knots(n, 10.0, 0.0);
        let points = data(&mut rng, n, 3, &condition);
        fitter
            .fit_into(&t, points.coords(), 3, &condition, &mut table)
            .unwrap();
        let direct = interpolating(condition, Some(t), points).fit();
        assert_eq!(table, direct);
    }
}

#[test]
fn bad_interpolation_data_are_typed_errors() {
    let p = |n: usize| Points::new(2, (0..2 * n).map(|i| i as f64).collect()).unwrap();
    let err = |condition: EndCondition, t: Option<Vec<f64>>, points: Points| {
        Curve::new(CurveKind::Interpolating { condition, t }, points).unwrap_err()
    };
    let cases = [
        (
            err(EndCondition::Natural, Some(vec![0.0, 1.0, 1.0]), p(3)),
            "t",
            "t[2] = 1 follows t[1] = 1",
        ),
        (
            err(EndCondition::Natural, Some(vec![0.0, 2.0, 1.0]), p(3)),
            "t",
            "t[2] = 1 follows t[1] = 2",
        ),
        (
            err(EndCondition::Natural, Some(vec![0.0, 1.0]), p(3)),
            "t",
            "got 2",
        ),
        (
            err(EndCondition::Natural, Some(vec![0.0, f64::NAN, 2.0]), p(3)),
            "t",
            "t[1] = NaN",
        ),
        (
            err(EndCondition::Natural, None, p(1)),
            "points",
            "at least 2",
        ),
        (
            err(EndCondition::Periodic, None, p(2)),
            "points",
            "at least 3",
        ),
        (
            err(EndCondition::NotAKnot, None, p(3)),
            "points",
            "at least 4",
        ),
        (
            err(EndCondition::Periodic, None, p(4)),
            "points",
            "points[3][0]",
        ),
        (
            err(
                EndCondition::Clamped {
                    start: vec![1.0],
                    end: vec![0.0, 0.0],
                },
                None,
                p(3),
            ),
            "start_derivative",
            "got 1",
        ),
        (
            err(
                EndCondition::Clamped {
                    start: vec![1.0, 0.0],
                    end: vec![0.0, f64::INFINITY],
                },
                None,
                p(3),
            ),
            "end_derivative",
            "inf",
        ),
    ];
    for (e, field, text) in cases {
        assert_eq!(e.field.as_deref(), Some(field), "{e}");
        assert!(e.to_string().contains(text), "{e} lacks {text}");
    }
}

#[test]
fn large_fits_formed_on_several_threads_interpolate_and_join_smoothly() {
    // 300,000 knots: the coefficients are formed in chunks on several threads; every segment
    // must still start and end at its points and join its neighbours with matching slopes.
    let n = 300_000;
    let t = uneven_knots(n, 100.0, 0.0);
    let mut rng = Rng(300);
    let points = data(&mut rng, n, 2, &EndCondition::Natural);
    let mut table = SegmentTable::default();
    let mut fitter = Fitter::new();
    fitter
        .fit_into(&t, points.coords(), 2, &EndCondition::Natural, &mut table)
        .unwrap();
    // The knots are copied on several threads too; the extent is the points'.
    assert_eq!(table.knots(), &t[..]);
    let axis = |k: usize| points.coords().iter().skip(k).step_by(2).copied();
    let span = |k: usize| axis(k).fold(f64::MIN, f64::max) - axis(k).fold(f64::MAX, f64::min);
    assert_eq!(table.extent(), span(0).max(span(1)));
    // Bad data in a large fit are named as in a small one.
    let mut bad = points.coords().to_vec();
    bad[2 * 250_000 + 1] = f64::NAN;
    let e = fitter
        .fit_into(&t, &bad, 2, &EndCondition::Natural, &mut table)
        .unwrap_err();
    assert!(e.to_string().contains("points[250000][1]"), "{e}");
    let mut unordered = t.clone();
    unordered[200_000] = unordered[199_999];
    let e = fitter
        .fit_into(
            &unordered,
            points.coords(),
            2,
            &EndCondition::Natural,
            &mut table,
        )
        .unwrap_err();
    assert!(e.to_string().contains("t[200000]"), "{e}");
    let (mut end, mut start) = ([0.0; 2], [0.0; 2]);
    for i in 0..n - 1 {
        let segment = table.segment(i);
        segment.eval(0.0, &mut start);
        assert_eq!(start, points.point(i), "segment {i} starts at its point");
        segment.eval(1.0, &mut end);
        assert_close(
            &end,
            points.point(i + 1),
            1e-9 * table.extent(),
            &format!("segment {i} ends at its point"),
        );
        if i + 1 < n - 1 {
            let next = table.segment(i + 1);
            segment.deriv(1.0, &mut end);
            next.deriv(0.0, &mut start);
            let scale = (0..2)
                .map(|k| splinegpu::accuracy::promise_scale(&segment, table.extent(), 1, k))
                .fold(0.0, f64::max);
            assert_close(
                &end,
                &start,
                1e-9 * scale,
                &format!("slope at knot {}", i + 1),
            );
        }
    }
}

#[test]
fn a_table_rebuilt_from_its_power_form_is_the_same_table() {
    let mut rng = Rng(41);
    for condition in conditions(3) {
        let points = data(&mut rng, 9, 3, &condition);
        let t = Some(uneven_knots(9, 1e4, -3.0));
        let table = interpolating(condition, t, points).fit();
        let coeffs: Vec<f64> = (0..table.len())
            .flat_map(|i| table.segment(i).power().concat())
            .collect();
        let again =
            SegmentTable::from_power(3, table.knots().to_vec(), coeffs, table.extent()).unwrap();
        assert_eq!(again, table);
    }
}

#[test]
fn a_power_form_that_breaks_a_rule_is_refused_by_name() {
    let refused = |dim, knots: Vec<f64>, coeffs: Vec<f64>, extent: f64, wanted: &str| {
        let e = SegmentTable::from_power(dim, knots, coeffs, extent).unwrap_err();
        assert!(
            e.to_string().contains(wanted),
            "{e} should contain {wanted}"
        );
    };
    let c = vec![1.0; 4];
    refused(0, vec![0.0, 1.0], c.clone(), 1.0, "\"points\"");
    refused(1, vec![0.0], Vec::new(), 1.0, "at least 2 values, got 1");
    refused(1, vec![0.0, f64::NAN], c.clone(), 1.0, "knots[1]");
    refused(
        1,
        vec![1.0, 1.0],
        c.clone(),
        1.0,
        "strictly increasing: knots[1] = 1",
    );
    refused(1, vec![0.0, 1.0], vec![1.0; 5], 1.0, "(4), got 5");
    refused(
        1,
        vec![0.0, 1.0],
        vec![1.0, 1.0, f64::INFINITY, 1.0],
        1.0,
        "coefficients[2]",
    );
    refused(1, vec![0.0, 1.0], c, -1.0, "\"extent\"");
}

/// SciPy's CubicSpline on too few points for its condition: not-a-knot on 3 points is the
/// parabola through them, on 2 the line; periodic on 2 equal points the constant, on 2 that
/// differ refused by name.
#[test]
fn few_points_resolve_as_scipys_cubic_spline() {
    use splinegpu::{Curve, CurveKind, EndCondition, Points};
    let x = [0.0, 1.0, 3.0];
    let y: Vec<f64> = x.iter().map(|&t| 2.0 * t * t - t + 1.0).collect();
    let condition = EndCondition::NotAKnot
        .on_few_points_as_scipy(&x, &y, 1)
        .unwrap();
    let kind = CurveKind::Interpolating {
        condition,
        t: Some(x.to_vec()),
    };
    let curve = Curve::new(kind, Points::new(1, y).unwrap()).unwrap();
    let at: Vec<f64> = (0..=30).map(|i| f64::from(i) / 10.0).collect();
    let samples = crate::support::cpu_at(&curve, &at);
    for (i, &t) in at.iter().enumerate() {
        let want = 2.0 * t * t - t + 1.0;
        assert!((samples.curve(0).points[i] - want).abs() < 1e-12, "t = {t}");
    }
    let line = EndCondition::NotAKnot
        .on_few_points_as_scipy(&[0.0, 2.0], &[1.0, 5.0], 1)
        .unwrap();
    assert_eq!(
        line,
        EndCondition::Clamped {
            start: vec![2.0],
            end: vec![2.0]
        }
    );
    let constant = EndCondition::Periodic.on_few_points_as_scipy(&[0.0, 1.0], &[3.0, 3.0], 1);
    assert_eq!(
        constant.unwrap(),
        EndCondition::Clamped {
            start: vec![0.0],
            end: vec![0.0]
        }
    );
    let error = EndCondition::Periodic.on_few_points_as_scipy(&[0.0, 1.0], &[3.0, 4.0], 1);
    assert_eq!(error.unwrap_err().field.as_deref(), Some("points"));
    assert_eq!(
        EndCondition::Natural
            .on_few_points_as_scipy(&x, &[0.0; 3], 1)
            .unwrap(),
        EndCondition::Natural
    );
}
