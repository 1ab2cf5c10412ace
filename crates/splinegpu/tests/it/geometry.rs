//! Tubes and ribbons against their exact shapes: rings at the radius from the curve, normals
//! of the exact surface (a cone's, derived by hand), triangles facing out, closed tubes
//! watertight and without a twist at the seam, and bad geometry refused by name.

use std::collections::HashMap;

use splinegpu::geometry::{Geometry, GeometryJob, Meshes, Ribbon, Tube, Width};
use splinegpu::{Basis, Curve, CurveKind, EndCondition, Ends, Points, Sampling};

fn natural(points: Vec<f64>) -> Curve {
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: None,
    };
    Curve::new(kind, Points::new(3, points).unwrap()).unwrap()
}

/// The z axis from 0 to 4 through 5 points: a natural spline reproduces the line, C(t) =
/// (0, 0, t).
fn axis() -> Curve {
    natural((0..5).flat_map(|i| [0.0, 0.0, f64::from(i)]).collect())
}

/// A trefoil, the (2, 3) torus knot, as a closed Catmull-Rom curve of 24 points: a loop
/// whose rotation-minimizing frame comes back turned, so that a tube without the closing-up
/// twists at its seam (this test's seam is then 1.2 times as wide as any other ring gap).
fn trefoil() -> Curve {
    let points = (0..24)
        .flat_map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / 24.0;
            let r = 2.0 + (3.0 * a).cos();
            [r * (2.0 * a).cos(), r * (2.0 * a).sin(), (3.0 * a).sin()]
        })
        .collect();
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    };
    Curve::new(kind, Points::new(3, points).unwrap()).unwrap()
}

fn meshes(curve: &Curve, geometry: &Geometry, sampling: &Sampling) -> (GeometryJob, Meshes) {
    let mut job = GeometryJob::new();
    job.push(curve, geometry, sampling).unwrap();
    let meshes = job.evaluate_cpu();
    (job, meshes)
}

fn vertex(m: &Meshes, v: usize) -> [f64; 3] {
    [m.points[3 * v], m.points[3 * v + 1], m.points[3 * v + 2]]
}

fn normal(m: &Meshes, v: usize) -> [f64; 3] {
    [m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The triangle's normal (b - a) x (c - a), counter-clockwise seen from where it points.
fn facing(m: &Meshes, [a, b, c]: [u32; 3]) -> [f64; 3] {
    let (a, b, c) = (
        vertex(m, a as usize),
        vertex(m, b as usize),
        vertex(m, c as usize),
    );
    cross(sub(b, a), sub(c, a))
}

/// How many triangles hold each undirected edge.
fn edge_uses(m: &Meshes) -> HashMap<(u32, u32), usize> {
    let mut uses = HashMap::new();
    for &[a, b, c] in &m.triangles {
        for (p, q) in [(a, b), (b, c), (c, a)] {
            *uses.entry((p.min(q), p.max(q))).or_insert(0) += 1;
        }
    }
    uses
}

#[test]
fn a_tube_about_a_line_has_its_rings_at_the_radius_facing_out_and_capped_watertight() {
    let tube = Geometry::Tube(Tube {
        radius: Width::Constant(0.25),
        sides: Some(7),
        caps: true,
        ..Tube::default()
    });
    let (job, m) = meshes(&axis(), &tube, &Sampling::PerSegment(4));
    // 4 segments x 4 + 1 = 17 rings of 7, and the two caps' centres.
    assert_eq!(job.vertex_count(), 17 * 7 + 2);
    assert_eq!(job.triangle_count(), 2 * 16 * 7 + 2 * 7);
    for v in 0..17 * 7 {
        let p = vertex(&m, v);
        assert!(
            ((p[0] * p[0] + p[1] * p[1]).sqrt() - 0.25).abs() < 1e-12,
            "{p:?}"
        );
        assert!((p[2] - m.t[v]).abs() < 1e-12);
        let n = normal(&m, v);
        // The exact normal of a cylinder: radial.
        assert!((n[0] - p[0] / 0.25).abs() < 1e-12 && (n[1] - p[1] / 0.25).abs() < 1e-12);
        assert!(n[2].abs() < 1e-12);
    }
    assert_eq!(normal(&m, 17 * 7), [0.0, 0.0, -1.0]);
    assert_eq!(normal(&m, 17 * 7 + 1), [0.0, 0.0, 1.0]);
    for &triangle in &m.triangles {
        let f = facing(&m, triangle);
        let [a, b, c] = triangle.map(|v| vertex(&m, v as usize));
        let centre = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0, 0.0];
        let outward = if triangle.iter().any(|&v| v >= 17 * 7) {
            // A cap's triangle: outward is along the axis, away from the tube's middle.
            [0.0, 0.0, (a[2] + b[2] + c[2]) / 3.0 - 2.0]
        } else {
            centre
        };
        assert!(dot(f, outward) > 0.0, "{triangle:?} faces in");
    }
    assert!(
        edge_uses(&m).values().all(|&n| n == 2),
        "a capped tube is closed"
    );
}

/// A cone: radius 1 + t/2 per point along the z axis (the natural spline of the radii
/// reproduces the line), so r_s = 1/2 and the exact normal leans back along the axis:
/// n = (e - T/2) / sqrt(1 + 1/4).
#[test]
fn a_tube_of_growing_radius_has_the_cones_exact_normals() {
    let radii = (0..5).map(|i| 1.0 + 0.5 * f64::from(i)).collect();
    let tube = Geometry::Tube(Tube {
        radius: Width::PerPoint(radii),
        sides: Some(5),
        ..Tube::default()
    });
    let (_, m) = meshes(&axis(), &tube, &Sampling::ArcLength(9));
    for v in 0..9 * 5 {
        let p = vertex(&m, v);
        let r = 1.0 + 0.5 * m.t[v];
        assert!(((p[0] * p[0] + p[1] * p[1]).sqrt() - r).abs() < 1e-12);
        let n = normal(&m, v);
        let scale = 1.25f64.sqrt();
        let expected = [p[0] / r / scale, p[1] / r / scale, -0.5 / scale];
        for i in 0..3 {
            assert!(
                (n[i] - expected[i]).abs() < 1e-12,
                "{n:?} against {expected:?}"
            );
        }
    }
    // Arc length places: t evenly spaced on a line.
    for j in 0..9 {
        assert!((m.t[5 * j] - 0.5 * j as f64).abs() < 1e-9, "{}", m.t[5 * j]);
    }
}

/// A tube of constant radius r about a circle of radius 1 (curvature κ = 1): its surface's
/// normal at e (a unit vector across the tangent) is e where the stretch 1 - r κ (e · n̂) is
/// positive (n̂ the circle's principal normal, towards its centre) and -e where it is negative
/// (the surface turned inside out past the centre), as the module `geometry::mesh` derives.
/// A thin tube (r = 0.3) is positive all round; a thick one (r = 1.5) turns on its inner side.
#[test]
fn a_tube_thicker_than_its_curvature_turns_its_inner_normals_inward() {
    let points = (0..64)
        .flat_map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / 64.0;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    };
    let circle = Curve::new(kind, Points::new(3, points).unwrap()).unwrap();
    for (r, inward) in [(0.3, false), (1.5, true)] {
        let tube = Geometry::Tube(Tube {
            radius: Width::Constant(r),
            sides: Some(8),
            ..Tube::default()
        });
        let (job, m) = meshes(&circle, &tube, &Sampling::PerSegment(2));
        let mut turned = 0;
        for ring in 0..job.vertex_count() as usize / 8 {
            // The ring's centre: its 8 directions sum to 0.
            let centre = (0..8).fold([0.0; 3], |c, k| {
                let p = vertex(&m, 8 * ring + k);
                [c[0] + p[0] / 8.0, c[1] + p[1] / 8.0, c[2] + p[2] / 8.0]
            });
            let towards = centre.map(|x| -x / dot(centre, centre).sqrt());
            for v in 8 * ring..8 * ring + 8 {
                let e = sub(vertex(&m, v), centre).map(|x| x / r);
                let stretch = 1.0 - r * dot(e, towards);
                if stretch.abs() < 0.05 {
                    continue; // within the Catmull-Rom circle's curvature error of 0
                }
                let sign = stretch.signum();
                turned += usize::from(sign < 0.0);
                let n = normal(&m, v);
                for i in 0..3 {
                    assert!(
                        (n[i] - sign * e[i]).abs() < 1e-9,
                        "r {r}, vertex {v}: {n:?} against {sign} x {e:?}"
                    );
                }
            }
        }
        assert_eq!(turned > 0, inward, "r {r}: {turned} normals turned inward");
    }
}

#[test]
fn a_closed_tube_wraps_its_rings_without_a_twist_at_the_seam() {
    let tube = Geometry::Tube(Tube {
        radius: Width::Constant(0.1),
        sides: Some(6),
        caps: true, // a closed tube has no ends to cap
        ..Tube::default()
    });
    let (job, m) = meshes(&trefoil(), &tube, &Sampling::PerSegment(8));
    let rings = 24 * 8;
    assert_eq!(job.vertex_count(), rings as u64 * 6);
    assert!(
        edge_uses(&m).values().all(|&n| n == 2),
        "a closed tube is closed"
    );
    // The quads across the seam join vertex k of the last ring to vertex k of the first: as
    // near as those of any other pair of neighbouring rings, which a twist would not be.
    let widest = |a: usize, b: usize| {
        (0..6)
            .map(|k| {
                let d = sub(vertex(&m, a * 6 + k), vertex(&m, b * 6 + k));
                dot(d, d).sqrt()
            })
            .fold(0.0, f64::max)
    };
    let elsewhere = (0..rings - 1).map(|j| widest(j, j + 1)).fold(0.0, f64::max);
    assert!(
        widest(rings - 1, 0) <= 1.01 * elsewhere,
        "{} against {elsewhere}",
        widest(rings - 1, 0)
    );
}

#[test]
fn a_ribbon_spans_its_width_across_the_curve_facing_its_normal() {
    let ribbon = Geometry::Ribbon(Ribbon {
        width: Width::Constant(0.5),
        up: Some([0.0, 0.0, 1.0]),
        dash: None,
    });
    let (job, m) = meshes(&trefoil(), &ribbon, &Sampling::PerSegment(4));
    let pairs = 24 * 4;
    assert_eq!(job.vertex_count(), 2 * pairs as u64);
    assert_eq!(job.triangle_count(), 2 * pairs as u64);
    for j in 0..pairs {
        let (a, b) = (vertex(&m, 2 * j), vertex(&m, 2 * j + 1));
        let across = sub(b, a);
        assert!((dot(across, across).sqrt() - 0.5).abs() < 1e-12);
        assert!(dot(across, normal(&m, 2 * j)).abs() < 1e-12);
        assert_eq!(normal(&m, 2 * j), normal(&m, 2 * j + 1));
    }
    for &triangle in &m.triangles {
        let n = normal(&m, triangle[0] as usize);
        assert!(
            dot(facing(&m, triangle), n) > 0.0,
            "{triangle:?} faces away from N"
        );
    }
}

#[test]
fn bad_geometry_is_refused_by_name() {
    let tube = |radius, sides| {
        Geometry::Tube(Tube {
            radius,
            sides: Some(sides),
            ..Tube::default()
        })
    };
    let flat = Curve::new(
        CurveKind::Uniform {
            basis: Basis::BSpline,
            ends: Ends::Control,
        },
        Points::new(2, vec![0.0, 0.0, 1.0, 0.0, 2.0, 1.0, 3.0, 1.0]).unwrap(),
    )
    .unwrap();
    let per_segment = Sampling::PerSegment(4);
    let cases: Vec<(Curve, Geometry, Sampling, &str)> = vec![
        (
            flat,
            tube(Width::Constant(1.0), 8),
            per_segment.clone(),
            "geometry",
        ),
        (
            axis(),
            tube(Width::Constant(0.0), 8),
            per_segment.clone(),
            "radius",
        ),
        (
            axis(),
            tube(Width::Constant(f64::NAN), 8),
            per_segment.clone(),
            "radius",
        ),
        (
            axis(),
            tube(Width::PerPoint(vec![1.0; 4]), 8),
            per_segment.clone(),
            "radius",
        ),
        (
            axis(),
            tube(Width::Constant(1.0), 2),
            per_segment.clone(),
            "sides",
        ),
        (
            axis(),
            tube(Width::Constant(1.0), 8),
            Sampling::At(vec![0.5]),
            "sampling",
        ),
        (
            axis(),
            Geometry::Ribbon(Ribbon {
                width: Width::Constant(1.0),
                up: Some([0.0, 0.0, -3.0]),
                dash: None,
            }),
            per_segment,
            "up",
        ),
    ];
    for (curve, geometry, sampling, field) in cases {
        let mut job = GeometryJob::new();
        let error = job.push(&curve, &geometry, &sampling).unwrap_err();
        assert_eq!(error.field.as_deref(), Some(field), "{error}");
        assert!(job.is_empty());
    }
}

/// Every kind carries its radius as one more coordinate: a tube of radius 0.5 at every point
/// (so r(t) = 0.5 everywhere, hermite's tangents and clamped ends being 0 in it) has each ring
/// at 0.5 from the curve's own point at the ring's t, in the plane perpendicular to its
/// tangent there (the curve evaluated on its own, by the CPU reference).
#[test]
fn every_kind_carries_a_radius_per_point_as_one_more_coordinate() {
    use crate::support::{Rng, cpu_at, local_beta};
    use splinegpu::HermiteSlopes;
    let mut rng = Rng(45);
    let n = 7;
    let knots: Vec<f64> = [0.0, 0.0, 0.0, 0.0, 1.0, 2.5, 3.0, 5.0, 5.0, 5.0, 5.0].to_vec();
    let kinds = vec![
        CurveKind::Hermite {
            slopes: HermiteSlopes::Given((0..3 * n).map(|_| rng.range(-2.0, 2.0)).collect()),
            t: None,
        },
        CurveKind::Interpolating {
            condition: EndCondition::Clamped {
                start: vec![1.0, -2.0, 0.5],
                end: vec![0.0, 3.0, 1.0],
            },
            t: Some(vec![0.0, 0.5, 2.0, 2.5, 4.0, 4.2, 6.0]),
        },
        CurveKind::Nurbs {
            knots,
            weights: Some((0..n).map(|_| rng.range(0.5, 2.0)).collect()),
        },
        local_beta(&mut rng, Ends::Closed, n),
    ];
    for kind in kinds {
        let curve = Curve::new(kind.clone(), rng.points(n, 3, -3.0, 3.0)).unwrap();
        let tube = Geometry::Tube(Tube {
            radius: Width::PerPoint(vec![0.5; n]),
            sides: Some(4),
            ..Tube::default()
        });
        let (_, m) = meshes(&curve, &tube, &Sampling::PerSegment(5));
        let exact = cpu_at(&curve, &m.t);
        let samples = exact.curve(0);
        let d1 = samples.d1.unwrap();
        for v in 0..m.t.len() {
            let centre = [
                samples.points[3 * v],
                samples.points[3 * v + 1],
                samples.points[3 * v + 2],
            ];
            let out = sub(vertex(&m, v), centre);
            assert!(
                (dot(out, out).sqrt() - 0.5).abs() < 1e-9,
                "{kind:?}: vertex {v}"
            );
            let tangent = [d1[3 * v], d1[3 * v + 1], d1[3 * v + 2]];
            let across = dot(out, tangent) / dot(tangent, tangent).sqrt();
            assert!(
                across.abs() < 1e-9,
                "{kind:?}: vertex {v} is {across} off its plane"
            );
        }
    }
}

mod tolerance;

mod strokes {
    //! Strokes against their exact areas: straight Bezier pieces, so that the exact area is
    //! rectangles, the join's region and the caps' (round: every point within w/2 of the
    //! path). Each mesh is checked both ways: points spread over every triangle lie in the
    //! area, and points of the area (away from its boundary by more than a chord's sagitta)
    //! lie in some triangle.

    use super::*;
    use splinegpu::geometry::{Cap, Join, Stroke};

    mod dashes;

    /// The polyline through `corners` as cubic Bezier pieces with their control points a third
    /// and two thirds along each side (straight, at constant speed).
    fn polyline(corners: &[[f64; 2]]) -> Curve {
        let mut points = vec![corners[0][0], corners[0][1]];
        for pair in corners.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            for k in 1..=3 {
                let s = f64::from(k) / 3.0;
                points.extend([a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]);
            }
        }
        Curve::new(CurveKind::Bezier, Points::new(2, points).unwrap()).unwrap()
    }

    fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let s = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
        (p[0] - a[0] - s * dx).hypot(p[1] - a[1] - s * dy)
    }

    fn distance(p: [f64; 2], corners: &[[f64; 2]]) -> f64 {
        corners
            .windows(2)
            .map(|w| distance_to_segment(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min)
    }

    fn xy(m: &Meshes, v: u32) -> [f64; 2] {
        [m.points[3 * v as usize], m.points[3 * v as usize + 1]]
    }

    fn inside_triangle(p: [f64; 2], [a, b, c]: [[f64; 2]; 3]) -> bool {
        let side = |a: [f64; 2], b: [f64; 2]| {
            (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
        };
        let eps = -1e-12;
        side(a, b) >= eps && side(b, c) >= eps && side(c, a) >= eps
    }

    /// Checks `m` against the area `in_area` (with `margin`: how far inside the area a point
    /// must be to be owed a triangle, `deep(p)`), over the box `[lo, hi]`.
    fn check(
        m: &Meshes,
        in_area: impl Fn([f64; 2]) -> bool,
        deep: impl Fn([f64; 2]) -> bool,
        lo: [f64; 2],
        hi: [f64; 2],
    ) {
        let triangles: Vec<[[f64; 2]; 3]> =
            m.triangles.iter().map(|t| t.map(|v| xy(m, v))).collect();
        for (i, &[a, b, c]) in triangles.iter().enumerate() {
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            assert!(area >= 0.0, "triangle {i} is clockwise");
            for (wa, wb) in [
                (1.0, 0.0),
                (0.0, 1.0),
                (0.0, 0.0),
                (0.3, 0.3),
                (0.5, 0.5),
                (0.1, 0.8),
            ] {
                let wc = 1.0 - wa - wb;
                let p = [
                    wa * a[0] + wb * b[0] + wc * c[0],
                    wa * a[1] + wb * b[1] + wc * c[1],
                ];
                assert!(in_area(p), "triangle {i}: {p:?} is outside the stroke");
            }
        }
        let steps = 160;
        for i in 0..=steps {
            for j in 0..=steps {
                let p = [
                    lo[0] + (hi[0] - lo[0]) * f64::from(i) / f64::from(steps),
                    lo[1] + (hi[1] - lo[1]) * f64::from(j) / f64::from(steps),
                ];
                if deep(p) {
                    assert!(
                        triangles.iter().any(|&t| inside_triangle(p, t)),
                        "{p:?} is not covered"
                    );
                }
            }
        }
    }

    fn stroke(cap: Cap, join: Join, miter_limit: f64) -> Geometry {
        Geometry::Stroke(Stroke {
            width: Width::Constant(0.5),
            cap,
            join,
            miter_limit,
            sides: 16,
            dash: None,
        })
    }

    const ZIGZAG: [[f64; 2]; 4] = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [3.5, 0.5]];

    /// Round joins and caps: the exact area is every point within w/2 of the path (a round
    /// fan's chords fall short of its arc by h (1 - cos(π/8)) at most, with 16 sides).
    #[test]
    fn round_joins_and_caps_cover_the_points_within_half_the_width() {
        let (job, m) = meshes(
            &polyline(&ZIGZAG),
            &stroke(Cap::Round, Join::Round, 4.0),
            &Sampling::PerSegment(4),
        );
        assert_eq!(job.vertex_count() as usize, m.t.len());
        let h = 0.25;
        let sagitta = h * (1.0 - (std::f64::consts::PI / 8.0).cos());
        check(
            &m,
            |p| distance(p, &ZIGZAG) <= h + 1e-12,
            |p| distance(p, &ZIGZAG) < h - sagitta - 1e-9,
            [-0.5, -0.5],
            [4.0, 2.5],
        );
    }

    /// A right-angle corner is a miter (ratio √2 <= 4): the outer corner squared off; with a
    /// limit of 1.2 it is a bevel, the triangle between the corner and the outer offsets.
    /// Butt and square caps: nothing, or w/2 more of the rectangle, beyond each end.
    #[test]
    fn miters_bevels_and_square_caps_make_their_exact_regions() {
        let l = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]];
        let h = 0.25;
        let rect = |p: [f64; 2], x0: f64, x1: f64, y0: f64, y1: f64, e: f64| {
            p[0] >= x0 - e && p[0] <= x1 + e && p[1] >= y0 - e && p[1] <= y1 + e
        };
        for (cap, join, limit, extra_vertices) in [
            (Cap::Butt, Join::Miter, 4.0, 2),
            (Cap::Square, Join::Miter, 4.0, 2 + 4),
            (Cap::Butt, Join::Bevel, 4.0, 1),
            (Cap::Butt, Join::Miter, 1.2, 1),
        ] {
            let (job, m) = meshes(
                &polyline(&l),
                &stroke(cap, join, limit),
                &Sampling::PerSegment(3),
            );
            // 7 cross-sections, the corner's twice, two vertices each.
            assert_eq!(
                job.vertex_count(),
                2 * 8 + extra_vertices,
                "{cap:?} {join:?} {limit}"
            );
            let reach = if cap == Cap::Square { h } else { 0.0 };
            let mitered = join == Join::Miter && limit >= 2f64.sqrt();
            let area = |p: [f64; 2], e: f64| {
                rect(p, -reach, 2.0, -h, h, e)
                    || rect(p, 2.0 - h, 2.0 + h, 0.0, 2.0 + reach, e)
                    // The corner's outer quarter: all of it for a miter, the bevel's half.
                    || (rect(p, 2.0, 2.0 + h, -h, 0.0, e)
                        && (mitered || (p[0] - 2.0) - (p[1] + h) <= e))
            };
            check(
                &m,
                |p| area(p, 1e-12),
                |p| area(p, -1e-9),
                [-0.5, -0.5],
                [2.5, 2.5],
            );
        }
    }

    /// A closed curve has no caps, and its closing point is a joint: a closed square path
    /// (four straight pieces) with miters has a square frame as its exact area.
    #[test]
    fn a_closed_path_joins_its_closing_point() {
        // Closed uniform kinds are smooth; a closed square is the Bezier path back to its
        // start, whose ends the stroke caps, so the closing here is a periodic interpolating
        // circle: no caps, no corner, its band covered all round.
        let n = 24;
        let points: Vec<f64> = (0..=n)
            .flat_map(|i| {
                let a = std::f64::consts::TAU * f64::from(i % n) / f64::from(n);
                [2.0 * a.cos(), 2.0 * a.sin()]
            })
            .collect();
        let kind = CurveKind::Interpolating {
            condition: EndCondition::Periodic,
            t: None,
        };
        let curve = Curve::new(kind, Points::new(2, points).unwrap()).unwrap();
        let (job, m) = meshes(
            &curve,
            &stroke(Cap::Round, Join::Miter, 4.0),
            &Sampling::PerSegment(8),
        );
        // 24 x 8 + 1 cross-sections, no caps, no corner.
        assert_eq!(job.vertex_count(), 2 * (24 * 8 + 1));
        // The exact curve: the spline through the circle's points, densely sampled.
        let dense = crate::support::cpu_at(
            &curve,
            &(0..=24_000)
                .map(|i| f64::from(i) / 1000.0)
                .collect::<Vec<_>>(),
        );
        let path: Vec<[f64; 2]> = dense
            .curve(0)
            .points
            .chunks(2)
            .map(|p| [p[0], p[1]])
            .collect();
        let h = 0.25;
        check(
            &m,
            |p| distance(p, &path) <= h + 1e-3,
            |p| distance(p, &path) < h - 1e-3,
            [-2.5, -2.5],
            [2.5, 2.5],
        );
    }
}

#[test]
fn bad_strokes_are_refused_by_name() {
    use splinegpu::geometry::Stroke;
    let flat = Curve::new(
        CurveKind::Bezier,
        Points::new(2, vec![0.0, 0.0, 1.0, 0.0, 2.0, 1.0, 3.0, 1.0]).unwrap(),
    )
    .unwrap();
    let cases = [
        (axis(), Stroke::default(), "geometry"),
        (
            flat.clone(),
            Stroke {
                sides: 3,
                ..Stroke::default()
            },
            "sides",
        ),
        (
            flat.clone(),
            Stroke {
                miter_limit: 0.5,
                ..Stroke::default()
            },
            "miter_limit",
        ),
        (
            flat,
            Stroke {
                width: Width::Constant(-1.0),
                ..Stroke::default()
            },
            "width",
        ),
    ];
    for (curve, stroke, field) in cases {
        let mut job = GeometryJob::new();
        let error = job
            .push(&curve, &Geometry::Stroke(stroke), &Sampling::PerSegment(4))
            .unwrap_err();
        assert_eq!(error.field.as_deref(), Some(field), "{error}");
    }
}

/// Tolerances that cannot be met are refused with their reason: a tube whose first rings and
/// sides alone make more than 2^32 - 1 vertices, before its cells are measured (quad by quad,
/// a check that would run for hours), a tolerance below what cells as narrow as f64 cuts
/// them can reach, and a cusp, where the speed vanishes.
#[test]
fn unreachable_tolerances_are_refused_with_their_reason() {
    use splinegpu::geometry::Stroke;
    let bent = natural(vec![
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 1.0, 0.0, 3.0, 0.0, 1.0,
    ]);
    let tube = Geometry::Tube(Tube {
        radius: Width::Constant(1.0),
        ..Tube::default()
    });
    let plane =
        |points: Vec<f64>| Curve::new(CurveKind::Bezier, Points::new(2, points).unwrap()).unwrap();
    let stroke = Geometry::Stroke(Stroke::default());
    let cases = [
        (bent, tube, 1e-10, "sampling", "at least"),
        (
            plane(vec![0.0, 0.0, 1.0, 0.0, 2.0, 1.0, 3.0, 0.0]),
            stroke.clone(),
            1e-300,
            "tolerance",
            "use a larger tolerance",
        ),
        (
            plane(vec![0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0]),
            stroke,
            1e-3,
            "tolerance",
            "speed vanishes",
        ),
    ];
    for (curve, geometry, tol, field, why) in cases {
        let mut job = GeometryJob::new();
        let error = job
            .push(&curve, &geometry, &Sampling::Tolerance(tol))
            .unwrap_err();
        assert_eq!(error.field.as_deref(), Some(field), "{error}");
        assert!(error.to_string().contains(why), "{error}");
        assert!(job.is_empty());
    }
}

#[test]
fn push_many_makes_the_meshes_that_pushing_one_by_one_makes() {
    let tube = Geometry::Tube(Tube {
        radius: Width::Constant(0.1),
        caps: true,
        ..Tube::default()
    });
    let ribbon = Geometry::Ribbon(Ribbon {
        width: Width::Constant(0.2),
        up: None,
        dash: None,
    });
    let curves = vec![
        (axis(), tube.clone(), Sampling::PerSegment(3)),
        (trefoil(), ribbon, Sampling::ArcLength(50)),
        (trefoil(), tube, Sampling::PerSegment(2)),
    ];
    let mut one_by_one = GeometryJob::new();
    for (curve, geometry, sampling) in &curves {
        one_by_one.push(curve, geometry, sampling).unwrap();
    }
    // A default job is an empty one, its offsets starting at 0.
    let mut many = GeometryJob::default();
    many.push(&curves[0].0, &curves[0].1, &curves[0].2).unwrap();
    many.push_many(&curves[1..]).unwrap();
    assert_eq!(many.vertex_offsets(), one_by_one.vertex_offsets());
    assert_eq!(many.evaluate_cpu(), one_by_one.evaluate_cpu());
    // A bad curve among many is named by its index in the job.
    let mut bad = curves.clone();
    bad[1].2 = Sampling::At(vec![0.5]);
    let error = many.push_many(&bad).unwrap_err().to_string();
    assert!(error.starts_with("curve 4:"), "{error}");
    assert_eq!(many.len(), 3);
}

/// Groups of curves bounded by their vertices cover the job in order, each curve once (a
/// curve larger than the bound a group of its own), and their meshes, made group by group,
/// are the whole job's.
#[test]
fn meshes_made_group_by_group_are_the_whole_jobs() {
    let tube = Geometry::Tube(Tube {
        radius: Width::Constant(0.1),
        caps: true,
        ..Tube::default()
    });
    let stroke = Geometry::Stroke(splinegpu::geometry::Stroke {
        width: Width::Constant(0.05),
        ..Default::default()
    });
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: None,
    };
    let flat_points = Points::new(2, vec![0.0, 0.0, 1.0, 0.5, 2.0, -0.5, 3.0, 0.0]).unwrap();
    let flat = Curve::new(kind, flat_points).unwrap();
    let mut job = GeometryJob::new();
    for (curve, geometry, k) in [
        (axis(), &tube, 3),
        (trefoil(), &tube, 2),
        (flat, &stroke, 5),
        (axis(), &tube, 1),
    ] {
        job.push(&curve, geometry, &Sampling::PerSegment(k))
            .unwrap();
    }
    let whole = job.evaluate_cpu();
    for bound in [1, 40, 100, 10_000] {
        let groups = job.groups(bound);
        assert_eq!(groups.first().unwrap().start, 0);
        assert_eq!(groups.last().unwrap().end, job.len());
        let (mut points, mut t, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
        for pair in groups.windows(2) {
            assert_eq!(pair[0].end, pair[1].start);
        }
        for group in groups {
            let first = group.start;
            let held = job.vertex_offsets()[group.end] - job.vertex_offsets()[first];
            assert!(group.len() == 1 || held <= bound, "{group:?} holds {held}");
            let part = job.evaluate_cpu_group(group.clone());
            for (c, curve) in group.enumerate() {
                let base = job.vertex_offsets()[first];
                assert_eq!(part.vertex_offsets[c] + base, job.vertex_offsets()[curve]);
            }
            points.extend(part.points);
            t.extend(part.t);
            triangles.extend(part.triangles);
        }
        assert_eq!(points, whole.points, "bound {bound}");
        assert_eq!(t, whole.t);
        assert_eq!(triangles, whole.triangles);
    }
    assert!(matches!(job.geometry(2), Geometry::Stroke(_)));
}

/// A renderer's buffers for a job's meshes.
struct Buffers {
    points: Vec<f32>,
    normals: Vec<f32>,
    t: Vec<f64>,
    triangles: Vec<[u32; 3]>,
}

impl Buffers {
    fn planes(&mut self) -> splinegpu::geometry::MeshPlanes<'_, f32> {
        splinegpu::geometry::MeshPlanes {
            points: &mut self.points,
            normals: &mut self.normals,
            t: &mut self.t,
            triangles: &mut self.triangles,
        }
    }
}

/// The renderer's path: meshes into the caller's f32 buffers are the f64 meshes rounded once;
/// a moving curve refitted in place gives the meshes a new job of it gives; a refit that
/// would change the counts, or buffers of the wrong size, are refused by name.
#[test]
fn meshes_go_into_the_callers_buffers_and_moving_curves_are_refitted_in_place() {
    use splinegpu::geometry::{MeshPlanes, Stroke};
    let tube = Geometry::Tube(Tube {
        radius: Width::Constant(0.1),
        ..Tube::default()
    });
    let mut job = GeometryJob::new();
    job.push(&trefoil(), &tube, &Sampling::PerSegment(4))
        .unwrap();
    job.push(&axis(), &tube, &Sampling::ArcLength(7)).unwrap();
    let (v, f) = (job.vertex_count() as usize, job.triangle_count() as usize);
    let mut b = Buffers {
        points: vec![0f32; 3 * v],
        normals: vec![0f32; 3 * v],
        t: vec![0.0; v],
        triangles: vec![[0u32; 3]; f],
    };
    job.evaluate_into(b.planes()).unwrap();
    let exact = job.evaluate_cpu();
    let rounded: Vec<f32> = exact.points.iter().map(|&x| x as f32).collect();
    assert_eq!(b.points, rounded);
    assert_eq!(b.triangles, exact.triangles);
    // The trefoil moves; refitted in place, its mesh is a fresh job's.
    let moved = {
        let p = trefoil()
            .points()
            .coords()
            .iter()
            .map(|x| 1.1 * x + 0.5)
            .collect();
        Curve::new(trefoil().kind().clone(), Points::new(3, p).unwrap()).unwrap()
    };
    job.refit(0, &moved).unwrap();
    // A renderer's frame: the vertices alone, the first frame's t and triangles kept.
    let (kept_t, kept_triangles) = (b.t.clone(), b.triangles.clone());
    job.evaluate_vertices_into(&mut b.points, &mut b.normals)
        .unwrap();
    let (vertices_only, normals_only) = (b.points.clone(), b.normals.clone());
    job.evaluate_into(b.planes()).unwrap();
    assert_eq!(
        (vertices_only, normals_only),
        (b.points.clone(), b.normals.clone())
    );
    assert_eq!((&kept_t, &kept_triangles), (&b.t, &b.triangles));
    let mut fresh = GeometryJob::new();
    fresh.push(&moved, &tube, &Sampling::PerSegment(4)).unwrap();
    fresh.push(&axis(), &tube, &Sampling::ArcLength(7)).unwrap();
    let rounded: Vec<f32> = fresh
        .evaluate_cpu()
        .points
        .iter()
        .map(|&x| x as f32)
        .collect();
    assert_eq!(b.points, rounded);
    let error = job
        .evaluate_vertices_into(&mut b.points[3..], &mut b.normals)
        .unwrap_err();
    assert!(error.message.contains("\"points\""), "{error}");
    // A buffer of the wrong length.
    let error = job
        .evaluate_into(MeshPlanes {
            points: &mut vec![0f32; 3 * v - 3][..],
            normals: &mut b.normals[..],
            t: &mut b.t[..],
            triangles: &mut b.triangles[..],
        })
        .unwrap_err();
    assert!(error.message.contains("\"points\""), "{error}");
    // A stroke that gains a corner when its points move changes its counts: refused.
    let straight = |y: f64| {
        Curve::new(
            CurveKind::Bezier,
            Points::new(
                2,
                vec![
                    0.0, 0.0, 1.0, 0.0, 2.0, 0.0, 3.0, 0.0, 4.0, y, 5.0, 0.0, 6.0, 0.0,
                ],
            )
            .unwrap(),
        )
        .unwrap()
    };
    let mut strokes = GeometryJob::new();
    let stroke = Geometry::Stroke(Stroke::default());
    strokes
        .push(&straight(0.0), &stroke, &Sampling::PerSegment(4))
        .unwrap();
    let before = strokes.vertex_offsets().to_vec();
    let error = strokes.refit(0, &straight(2.0)).unwrap_err();
    assert!(error.message.contains("vertices"), "{error}");
    assert_eq!(strokes.vertex_offsets(), &before[..]);
    // A miter and a bevel trading corners: the same counts, other triangles: refused too.
    let zigzag = |corners: &[[f64; 2]]| {
        let mut p = corners[0].to_vec();
        for w in corners.windows(2) {
            for k in 1..=3 {
                let f = f64::from(k) / 3.0;
                p.extend([
                    w[0][0] + f * (w[1][0] - w[0][0]),
                    w[0][1] + f * (w[1][1] - w[0][1]),
                ]);
            }
        }
        Curve::new(CurveKind::Bezier, Points::new(2, p).unwrap()).unwrap()
    };
    let mut mitered = GeometryJob::new();
    let first = zigzag(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.1], [1.0, 0.2]]);
    mitered
        .push(&first, &stroke, &Sampling::PerSegment(4))
        .unwrap();
    let swapped = zigzag(&[[0.0, 0.0], [1.0, 0.0], [0.0, 0.1], [-1.0, 0.25]]);
    let error = mitered.refit(0, &swapped).unwrap_err();
    assert!(error.message.contains("joins or caps"), "{error}");
}

/// Random curves of the uniform kinds, closed and open, each as a capped tube, a ribbon and
/// (in 2-D) a stroke of every join and cap: the counts announced are the counts made, every
/// value finite, normals of unit length, tube vertices at the radius from the curve in the
/// plane across its tangent, capped and closed tubes watertight, ribbons their width across
/// their normals, strokes counter-clockwise.
#[test]
fn random_curves_make_the_meshes_they_announce() {
    use crate::support::{Rng, bases};
    use splinegpu::geometry::{Cap, Join, Stroke};
    let mut rng = Rng(4545);
    let mut checked = 0;
    for round in 0..40 {
        // The continuous families: a joint's t is located again below, and a matrix that
        // jumps there would be compared on the other side of the jump.
        for basis in bases()
            .into_iter()
            .filter(|b| !matches!(b, Basis::Matrix(_)))
        {
            let ends = [Ends::Control, Ends::Repeat, Ends::Closed][round % 3];
            let kind = CurveKind::Uniform {
                basis: basis.clone(),
                ends,
            };
            let n = 5 + round % 6;
            let sampling = if round % 2 == 0 {
                Sampling::PerSegment(1 + (round % 5) as u32)
            } else {
                Sampling::ArcLength(3 + round as u32)
            };
            let Ok(curve3) = Curve::new(kind.clone(), rng.points(n, 3, -2.0, 2.0)) else {
                continue;
            };
            let radius = 0.01 + 0.05 * rng.range(0.0, 1.0);
            let tube = Geometry::Tube(Tube {
                radius: Width::Constant(radius),
                sides: Some(3 + (round % 6) as u32),
                caps: true,
                ..Tube::default()
            });
            let ribbon = Geometry::Ribbon(Ribbon {
                width: Width::Constant(0.1),
                up: None,
                dash: None,
            });
            for geometry in [tube, ribbon] {
                let mut job = GeometryJob::new();
                if job.push(&curve3, &geometry, &sampling).is_err() {
                    continue; // a degenerate draw (a curve of no length): refused by name
                }
                let m = job.evaluate_cpu();
                assert_eq!(m.t.len() as u64, job.vertex_count());
                assert_eq!(m.triangles.len() as u64, job.triangle_count());
                assert!(m.points.iter().chain(&m.normals).all(|v| v.is_finite()));
                for v in 0..m.t.len() {
                    let n = normal(&m, v);
                    assert!((dot(n, n) - 1.0).abs() < 1e-9, "{kind:?}: normal {v}");
                }
                if let Geometry::Tube(_) = geometry {
                    assert!(
                        edge_uses(&m).values().all(|&u| u == 2),
                        "{kind:?}: not closed"
                    );
                    let exact = crate::support::cpu_at(&curve3, &m.t);
                    let c = exact.curve(0);
                    let d1 = c.d1.unwrap();
                    let rings = m.t.len() - if ends == Ends::Closed { 0 } else { 2 };
                    for v in 0..rings {
                        let p = [c.points[3 * v], c.points[3 * v + 1], c.points[3 * v + 2]];
                        let t = [d1[3 * v], d1[3 * v + 1], d1[3 * v + 2]];
                        let out = sub(vertex(&m, v), p);
                        let r = dot(out, out).sqrt();
                        assert!(
                            (r - radius).abs() < 1e-9 * (1.0 + radius),
                            "{kind:?} {sampling:?} {v}: {r} against {radius}"
                        );
                        if dot(t, t) > 1e-12 {
                            assert!(dot(out, t).abs() < 1e-9 * dot(t, t).sqrt());
                        }
                    }
                } else {
                    // Each pair spans the width across N (a triangle's facing is N's only where
                    // the sampling resolves the frame's turn: the exact-shape test checks it).
                    for j in 0..m.t.len() / 2 {
                        let across = sub(vertex(&m, 2 * j + 1), vertex(&m, 2 * j));
                        assert!((dot(across, across).sqrt() - 0.1).abs() < 1e-12);
                        assert!(dot(across, normal(&m, 2 * j)).abs() < 1e-12);
                    }
                }
                checked += 1;
            }
            let Ok(curve2) = Curve::new(kind, rng.points(n, 2, -2.0, 2.0)) else {
                continue;
            };
            let stroke = Geometry::Stroke(Stroke {
                width: Width::Constant(0.05),
                cap: [Cap::Butt, Cap::Square, Cap::Round][round % 3],
                join: [Join::Miter, Join::Round, Join::Bevel][(round / 3) % 3],
                ..Stroke::default()
            });
            let mut job = GeometryJob::new();
            if job.push(&curve2, &stroke, &sampling).is_ok() {
                let m = job.evaluate_cpu();
                assert_eq!(m.t.len() as u64, job.vertex_count());
                assert_eq!(m.triangles.len() as u64, job.triangle_count());
                assert!(m.points.iter().all(|v| v.is_finite()));
                for &tri in &m.triangles {
                    assert!(facing(&m, tri)[2] >= 0.0, "a clockwise triangle");
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 500, "only {checked} meshes checked");
}
