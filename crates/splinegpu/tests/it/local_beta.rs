//! Beta-splines with local bias and tension (the contract's "Local bias and tension"): the
//! conditions that define them, measured from both sides of every joint; translation
//! invariance; locality in the points and in the joints' values; the memo's B_{b1,b2} and the
//! uniform B-spline as special cases; the convex hull; the input rules.

use crate::support::{Rng, local_beta};
use splinegpu::kinds::KindFields;
use splinegpu::{Basis, Curve, CurveKind, Ends, PerPoint, Points, SegmentTable};

const ENDS: [Ends; 3] = [Ends::Control, Ends::Repeat, Ends::Closed];

fn joints(ends: Ends, n: usize) -> usize {
    if ends == Ends::Control { n - 2 } else { n }
}

fn fit(kind: &CurveKind, points: &Points) -> SegmentTable {
    Curve::new(kind.clone(), points.clone()).unwrap().fit()
}

/// The value, first and second derivative (d/du) of segment s at local u.
fn local(table: &SegmentTable, s: usize, u: f64) -> [Vec<f64>; 3] {
    let seg = table.segment(s);
    let dim = table.dim();
    let mut out = [vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]];
    seg.eval(u, &mut out[0]);
    seg.deriv(u, &mut out[1]);
    seg.deriv2(u, &mut out[2]);
    // The knots are 0, 1, 2, ...: d/dt is d/du.
    assert_eq!(seg.dt(), 1.0);
    out
}

/// Segment s's power coefficients, flat.
fn coefficients(table: &SegmentTable, s: usize) -> Vec<f64> {
    table.segment(s).power().concat()
}

#[test]
fn every_joint_is_g2_with_its_own_bias_and_tension() {
    let mut rng = Rng(30);
    for ends in ENDS {
        for n in [4, 5, 9] {
            let kind = local_beta(&mut rng, ends, n);
            let CurveKind::LocalBeta { bias, tension, .. } = &kind else {
                unreachable!()
            };
            let (PerPoint::Each(b1), PerPoint::Each(b2)) = (bias, tension) else {
                unreachable!()
            };
            let table = fit(&kind, &rng.points(n, 3, -5.0, 5.0));
            let segments = table.len();
            // Interior joints; a closed curve's joint 0 too, between its last and first segment.
            let inner: Vec<usize> = if ends == Ends::Closed {
                (0..segments).collect()
            } else {
                (1..segments).collect()
            };
            for j in inner {
                let left = local(&table, (j + segments - 1) % segments, 1.0);
                let right = local(&table, j, 0.0);
                for k in 0..3 {
                    let expect = [
                        left[0][k],
                        b1[j] * left[1][k],
                        b1[j] * b1[j] * left[2][k] + b2[j] * left[1][k],
                    ];
                    for order in 0..3 {
                        let scale = 1.0 + expect[order].abs() + left[order][k].abs();
                        assert!(
                            (right[order][k] - expect[order]).abs() < 1e-12 * scale,
                            "{ends:?} n {n} joint {j} order {order} coordinate {k}: {} vs {}",
                            right[order][k],
                            expect[order]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn translating_the_points_translates_the_curve() {
    let mut rng = Rng(31);
    for ends in ENDS {
        let kind = local_beta(&mut rng, ends, 8);
        let points = rng.points(8, 2, -3.0, 3.0);
        let shift = [1234.5, -0.25];
        let moved: Vec<f64> = points
            .coords()
            .chunks(2)
            .flat_map(|p| [p[0] + shift[0], p[1] + shift[1]])
            .collect();
        let (a, b) = (
            fit(&kind, &points),
            fit(&kind, &Points::new(2, moved).unwrap()),
        );
        for s in 0..a.len() {
            for u in [0.0, 0.3, 0.71, 1.0] {
                let (p, q) = (local(&a, s, u), local(&b, s, u));
                for k in 0..2 {
                    assert!(
                        (q[0][k] - p[0][k] - shift[k]).abs() < 1e-9,
                        "{ends:?} {s} {u}"
                    );
                    assert!((q[1][k] - p[1][k]).abs() < 1e-9);
                    assert!((q[2][k] - p[2][k]).abs() < 1e-9);
                }
            }
        }
    }
}

/// The segments whose coefficients differ between two fits of the same size.
fn changed(a: &SegmentTable, b: &SegmentTable) -> Vec<usize> {
    (0..a.len())
        .filter(|&s| coefficients(a, s) != coefficients(b, s))
        .collect()
}

#[test]
fn one_point_moves_at_most_four_segments_and_one_joint_only_j_minus_2_to_j_plus_1() {
    let mut rng = Rng(32);
    let n = 11;
    for ends in ENDS {
        let kind = local_beta(&mut rng, ends, n);
        let points = rng.points(n, 2, -3.0, 3.0);
        let base = fit(&kind, &points);
        let segments = base.len() as isize;
        for p in 0..n {
            let mut coords = points.coords().to_vec();
            coords[2 * p] += 0.5;
            let moved = fit(&kind, &Points::new(2, coords).unwrap());
            let touched = changed(&base, &moved);
            assert!(
                !touched.is_empty() && touched.len() <= 4,
                "{ends:?} point {p}: {touched:?}"
            );
        }
        let CurveKind::LocalBeta { bias, tension, .. } = &kind else {
            unreachable!()
        };
        for j in 0..joints(ends, n) as isize {
            let PerPoint::Each(mut b1) = bias.clone() else {
                unreachable!()
            };
            b1[j as usize] *= 1.5;
            let other = CurveKind::LocalBeta {
                ends,
                bias: PerPoint::Each(b1),
                tension: tension.clone(),
            };
            let touched = changed(&base, &fit(&other, &points));
            let allowed: Vec<usize> = (j - 2..=j + 1)
                .filter_map(|s| match ends {
                    Ends::Closed => Some(s.rem_euclid(segments) as usize),
                    _ => (0..segments).contains(&s).then_some(s as usize),
                })
                .collect();
            assert!(
                touched.iter().all(|s| allowed.contains(s)),
                "{ends:?} joint {j}: changed {touched:?}, allowed {allowed:?}"
            );
            assert!(!touched.is_empty(), "{ends:?} joint {j} changed nothing");
        }
    }
}

#[test]
fn equal_joints_are_the_memos_beta_spline_and_unit_bias_zero_tension_the_bspline() {
    let mut rng = Rng(33);
    for ends in ENDS {
        let n = 7;
        let points = rng.points(n, 3, -4.0, 4.0);
        for (b1, b2, memo) in [
            (
                1.7,
                3.0,
                Basis::Beta {
                    bias: 1.7,
                    tension: 3.0,
                },
            ),
            (
                0.4,
                0.0,
                Basis::Beta {
                    bias: 0.4,
                    tension: 0.0,
                },
            ),
            (1.0, 0.0, Basis::BSpline),
        ] {
            let local = CurveKind::LocalBeta {
                ends,
                bias: PerPoint::Each(vec![b1; joints(ends, n)]),
                tension: PerPoint::Each(vec![b2; joints(ends, n)]),
            };
            let (a, b) = (
                fit(&local, &points),
                fit(&CurveKind::Uniform { basis: memo, ends }, &points),
            );
            for s in 0..a.len() {
                for (x, y) in coefficients(&a, s).iter().zip(coefficients(&b, s)) {
                    assert!(
                        (x - y).abs() < 1e-12 * (1.0 + y.abs()),
                        "{ends:?} {b1} {b2}"
                    );
                }
            }
        }
    }
}

#[test]
fn positive_bias_and_tension_keep_every_point_a_convex_combination_of_its_window() {
    // With the n unit vectors as points, a sample's coordinates are the basis functions'
    // values there: none negative, and they sum to 1.
    let mut rng = Rng(34);
    for ends in ENDS {
        for extreme in [false, true] {
            let n = 9;
            let mut kind = local_beta(&mut rng, ends, n);
            if extreme {
                let count = joints(ends, n);
                kind = CurveKind::LocalBeta {
                    ends,
                    bias: PerPoint::Each((0..count).map(|j| [1e-3, 1e3, 1.0][j % 3]).collect()),
                    tension: PerPoint::Each((0..count).map(|j| [0.0, 1e3, 1e-3][j % 3]).collect()),
                };
            }
            let mut unit = vec![0.0; n * n];
            for i in 0..n {
                unit[i * n + i] = 1.0;
            }
            let table = fit(&kind, &Points::new(n, unit).unwrap());
            for s in 0..table.len() {
                for step in 0..=40 {
                    let p = &local(&table, s, f64::from(step) / 40.0)[0];
                    let sum: f64 = p.iter().sum();
                    assert!(
                        (sum - 1.0).abs() < 1e-9,
                        "{ends:?} {extreme} {s}: sum {sum}"
                    );
                    let low = p.iter().copied().fold(f64::INFINITY, f64::min);
                    assert!(low > -1e-12, "{ends:?} {extreme} segment {s}: weight {low}");
                }
            }
        }
    }
}

fn named(fields: KindFields, n: usize, ends: Ends) -> Result<Curve, splinegpu::InputError> {
    let kind = CurveKind::named(
        "beta",
        KindFields {
            ends: Some(ends),
            ..fields
        },
    )?;
    Curve::new(
        kind,
        Points::new(1, (0..n).map(|i| i as f64).collect()).unwrap(),
    )
}

#[test]
fn arrays_make_a_local_beta_spline_and_bad_joints_are_named() {
    let each = |v: &[f64]| Some(PerPoint::Each(v.to_vec()));
    // A number beside an array applies to every joint.
    let curve = named(
        KindFields {
            bias: each(&[1.0, 2.0, 0.5]),
            tension: Some(PerPoint::All(2.0)),
            ..KindFields::default()
        },
        5,
        Ends::Control,
    )
    .unwrap();
    assert!(matches!(curve.kind(), CurveKind::LocalBeta { .. }));
    // Numbers alone keep the memo's matrix and its rule (d != 0; a negative bias is allowed).
    let curve = named(
        KindFields {
            bias: Some(PerPoint::All(-0.5)),
            ..KindFields::default()
        },
        5,
        Ends::Control,
    )
    .unwrap();
    assert!(matches!(curve.kind(), CurveKind::Uniform { .. }));
    let cases = [
        (
            each(&[1.0, 0.0, 1.0]),
            None,
            "\"bias\" must be > 0 at every joint: bias[1] = 0",
        ),
        (
            None,
            each(&[0.0, 0.0, -1.0]),
            "\"tension\" must be >= 0 at every joint: tension[2] = -1",
        ),
        (
            each(&[1.0, 1.0]),
            None,
            "\"bias\" must have one value per joint (3), got 2",
        ),
        (
            Some(PerPoint::All(-1.0)),
            each(&[0.0; 3]),
            "\"bias\" must be > 0 when bias or tension",
        ),
        (
            each(&[1.0, f64::NAN, 1.0]),
            None,
            "\"bias\" must be finite: bias[1] = NaN",
        ),
        (
            Some(PerPoint::All(-1.0)),
            Some(PerPoint::All(0.0)),
            "d = b2 + 2b1^3 + 4b1^2 + 4b1 + 2 = 0",
        ),
    ];
    for (bias, tension, message) in cases {
        let err = named(
            KindFields {
                bias,
                tension,
                ..KindFields::default()
            },
            5,
            Ends::Control,
        )
        .unwrap_err()
        .in_curve(4)
        .to_string();
        assert!(err.starts_with("curve 4: "), "{err}");
        assert!(err.contains(message), "{err} lacks {message}");
    }
    // Repeat and closed ends have one joint per point.
    for ends in [Ends::Repeat, Ends::Closed] {
        let err = named(
            KindFields {
                bias: each(&[1.0; 4]),
                ..KindFields::default()
            },
            5,
            ends,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("one value per joint (5), got 4"), "{err}");
    }
}

#[allow(
    dead_code,
    reason = "a trial of the GPU harness (tests/gpu/main.rs), which includes this file"
)]
pub(crate) fn the_gpu_keeps_the_promise_on_local_bias_and_tension_near_the_origin_and_at_1e6() {
    use splinegpu::{Derivatives, EvalJob, Sampling};
    let mut rng = Rng(35);
    let mut job = EvalJob::new(Derivatives::Second);
    for center in [0.0, 1e6] {
        for ends in ENDS {
            for dim in [1, 3, 8] {
                let kind = local_beta(&mut rng, ends, 12);
                let points = rng.points(12, dim, center - 5.0, center + 5.0);
                let curve = Curve::new(kind, points).unwrap();
                job.push(&curve, &Sampling::PerSegment(13)).unwrap();
                job.push(&curve, &Sampling::Tolerance(1e-3)).unwrap();
                job.push(&curve, &Sampling::ArcLength(40)).unwrap();
            }
        }
    }
    if let Some(worst) = crate::support::assert_gpu_matches_cpu(&job) {
        eprintln!(
            "local bias and tension: worst fraction of the GPU bound {:.3?} (positions, d1, d2)",
            worst.per_order
        );
    }
}
