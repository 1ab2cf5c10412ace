//! Tolerance cross-sections against the exact shapes, both ways: points spread over every
//! triangle lie within tol of the exact surface (or area), and points of the exact surface
//! lie within tol of a triangle (a stroke's area, away from its boundary by more than tol,
//! inside one). Distances are measured here from the contract's definitions alone (the
//! swept circle at each t, the ribbon's segment along an independently carried
//! rotation-minimizing frame, the pen's segment across the curve), each search giving an
//! upper bound of the true distance, so that a pass is a proof up to the sampling of the
//! triangles and the surface.

use splinegpu::geometry::{Geometry, GeometryJob, Meshes, Ribbon, Stroke, Tube, Width};
use splinegpu::{Curve, CurveKind, EndCondition, Points, Sampling, SegmentTable};

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

fn scale(a: V3, s: f64) -> V3 {
    a.map(|x| x * s)
}

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// The curve with its width as one more coordinate, the contract's definition of w(t):
/// position, unit tangent and width at t.
struct Exact {
    table: SegmentTable,
    dim: usize,
}

impl Exact {
    fn new(kind: &CurveKind, points: &[f64], dim: usize, widths: &[f64]) -> Self {
        let widened: Vec<f64> = points
            .chunks(dim)
            .zip(widths)
            .flat_map(|(p, &w)| p.iter().copied().chain([w]))
            .collect();
        let curve = Curve::new(kind.clone(), Points::new(dim + 1, widened).unwrap()).unwrap();
        Self {
            table: curve.fit(),
            dim,
        }
    }

    fn range(&self) -> (f64, f64) {
        self.table.t_range()
    }

    fn at(&self, t: f64) -> (V3, V3, f64) {
        let knots = self.table.knots();
        let s = knots
            .partition_point(|&k| k <= t)
            .saturating_sub(1)
            .min(self.table.len() - 1);
        let segment = self.table.segment(s);
        let u = ((t - segment.t0()) / segment.dt()).clamp(0.0, 1.0);
        let (mut p, mut d) = ([0.0; 4], [0.0; 4]);
        segment.eval(u, &mut p[..=self.dim]);
        segment.deriv(u, &mut d[..=self.dim]);
        let mut position = [0.0; 3];
        let mut tangent = [0.0; 3];
        position[..self.dim].copy_from_slice(&p[..self.dim]);
        tangent[..self.dim].copy_from_slice(&d[..self.dim]);
        let speed = norm(tangent);
        (position, scale(tangent, 1.0 / speed), p[self.dim].max(0.0))
    }
}

/// The least of `f` over [a, b]: a grid, then golden sections about its best point (an upper
/// bound of the true least, which is all the checks need).
fn least(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const GRID: usize = 24;
    let (mut best, mut at) = (f64::INFINITY, a);
    for i in 0..=GRID {
        let t = a + (b - a) * i as f64 / GRID as f64;
        let v = f(t);
        if v < best {
            (best, at) = (v, t);
        }
    }
    let step = (b - a) / GRID as f64;
    let (mut lo, mut hi) = ((at - step).max(a), (at + step).min(b));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..32 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(x1) < f(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    best.min(f(0.5 * (lo + hi)))
}

/// The distance from p to the closest point of triangle abc (Ericson, "Real-Time Collision
/// Detection", 5.1.5).
fn point_triangle(p: V3, a: V3, b: V3, c: V3) -> f64 {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return norm(ap);
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return norm(bp);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return norm(sub(p, add(a, scale(ab, v))));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return norm(cp);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return norm(sub(p, add(a, scale(ac, w))));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return norm(sub(p, add(b, scale(sub(c, b), w))));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    norm(sub(p, add(a, add(scale(ab, v), scale(ac, w)))))
}

/// The distance from p to the segment ab.
fn point_segment(p: V3, a: V3, b: V3) -> f64 {
    let ab = sub(b, a);
    let l = dot(ab, ab);
    let x = if l > 0.0 {
        (dot(sub(p, a), ab) / l).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm(sub(p, add(a, scale(ab, x))))
}

/// A mesh's triangles with their corners and the t of each corner.
struct Tris {
    corners: Vec<[V3; 3]>,
    ts: Vec<[f64; 3]>,
}

impl Tris {
    fn of(m: &Meshes) -> Self {
        let vertex = |v: u32| {
            let v = v as usize;
            [m.points[3 * v], m.points[3 * v + 1], m.points[3 * v + 2]]
        };
        Self {
            corners: m.triangles.iter().map(|t| t.map(vertex)).collect(),
            ts: m
                .triangles
                .iter()
                .map(|t| t.map(|v| m.t[v as usize]))
                .collect(),
        }
    }

    /// The widest gap between the mesh's distinct t.
    fn widest_cell(m: &Meshes) -> f64 {
        let mut ts = m.t.clone();
        ts.sort_by(f64::total_cmp);
        ts.dedup();
        ts.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max)
    }

    /// Points spread over triangle i (its corners, edge midpoints and four inside).
    fn spread(&self, i: usize) -> impl Iterator<Item = V3> + '_ {
        const WEIGHTS: [[f64; 3]; 10] = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.5],
            [0.5, 0.0, 0.5],
            [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
            [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
            [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
            [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
        ];
        let [a, b, c] = self.corners[i];
        WEIGHTS
            .iter()
            .map(move |w| add(add(scale(a, w[0]), scale(b, w[1])), scale(c, w[2])))
    }

    /// The triangles with a corner within `reach` of t: buckets over t, each holding every
    /// triangle with a corner within `reach` of it.
    fn buckets(&self, range: (f64, f64), reach: f64) -> Buckets {
        const COUNT: usize = 256;
        let width = (range.1 - range.0) / COUNT as f64;
        let mut lists = vec![Vec::new(); COUNT];
        let index = |t: f64| (((t - range.0) / width).floor().max(0.0) as usize).min(COUNT - 1);
        for (i, ts) in self.ts.iter().enumerate() {
            let mut hit = vec![];
            for &t in ts {
                hit.extend(index(t - reach)..=index(t + reach));
            }
            hit.sort_unstable();
            hit.dedup();
            for b in hit {
                lists[b].push(i);
            }
        }
        Buckets {
            lists,
            start: range.0,
            width,
        }
    }
}

struct Buckets {
    lists: Vec<Vec<usize>>,
    start: f64,
    width: f64,
}

impl Buckets {
    fn at(&self, t: f64) -> &[usize] {
        let b = ((t - self.start) / self.width).floor().max(0.0) as usize;
        &self.lists[b.min(self.lists.len() - 1)]
    }
}

/// The largest distance from the mesh's triangles to the exact surface, whose distance from
/// a point p at parameter t is `from(p, t)`; searched over t within a cell of each corner.
fn mesh_to_shape(m: &Meshes, range: (f64, f64), from: impl Fn(V3, f64) -> f64) -> f64 {
    let tris = Tris::of(m);
    let cell = Tris::widest_cell(m);
    let mut worst = 0.0f64;
    for i in 0..tris.corners.len() {
        for p in tris.spread(i) {
            let ts = tris.ts[i];
            let (lo, hi) = (
                ts.iter().copied().fold(f64::INFINITY, f64::min),
                ts.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            );
            // A closed mesh's seam joins the last cell to the first: search about each corner.
            let spans: Vec<(f64, f64)> = if hi - lo > 2.0 * cell {
                ts.iter().map(|&t| (t - cell, t + cell)).collect()
            } else {
                vec![(lo - cell, hi + cell)]
            };
            let d = spans
                .into_iter()
                .map(|(a, b)| least(|x| from(p, x), a.max(range.0), b.min(range.1)))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    worst
}

/// The largest distance from the exact surface's points (at `ts`, each with its points) to
/// the mesh.
fn shape_to_mesh(m: &Meshes, range: (f64, f64), points: impl Iterator<Item = (f64, V3)>) -> f64 {
    let tris = Tris::of(m);
    let buckets = tris.buckets(range, Tris::widest_cell(m));
    let mut worst = 0.0f64;
    for (t, q) in points {
        let d = buckets
            .at(t)
            .iter()
            .map(|&i| {
                let [a, b, c] = tris.corners[i];
                point_triangle(q, a, b, c)
            })
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
    }
    worst
}

/// A unit vector perpendicular to the unit `t`.
fn perpendicular(t: V3) -> V3 {
    let axis = if t[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let c = cross(t, axis);
    scale(c, 1.0 / norm(c))
}

/// The distance from p to the circle of radius r about c in the plane perpendicular to the
/// unit t.
fn point_circle(p: V3, c: V3, t: V3, r: f64) -> f64 {
    let d = sub(p, c);
    let along = dot(d, t);
    let across = norm(sub(d, scale(t, along)));
    along.hypot(across - r)
}

/// The 3-D curve's mesh of `geometry` at tolerance `tol`, made on the CPU.
fn tolerance_mesh(kind: &CurveKind, points: &[f64], geometry: &Geometry, tol: f64) -> Meshes {
    let curve = Curve::new(kind.clone(), Points::new(3, points.to_vec()).unwrap()).unwrap();
    let mut job = GeometryJob::new();
    job.push(&curve, geometry, &Sampling::Tolerance(tol))
        .unwrap();
    job.evaluate_cpu()
}

/// Both directions' largest distances within tol, printed as fractions of it.
fn assert_within(what: &str, m: &Meshes, out: f64, back: f64, tol: f64) {
    eprintln!(
        "{what} tol {tol}: {} vertices, mesh to surface {:.3} tol, surface to mesh {:.3} tol",
        m.t.len(),
        out / tol,
        back / tol
    );
    assert!(
        out <= tol,
        "a triangle strays {out} from the {what} (tol {tol})"
    );
    assert!(
        back <= tol,
        "the {what} strays {back} from the mesh (tol {tol})"
    );
}

fn tubes_within(kind: &CurveKind, points: &[f64], radii: &[f64], tol: f64, caps: bool) -> f64 {
    let exact = Exact::new(kind, points, 3, radii);
    let geometry = Geometry::Tube(Tube {
        radius: Width::PerPoint(radii.to_vec()),
        caps,
        ..Tube::default()
    });
    let m = tolerance_mesh(kind, points, &geometry, tol);
    let range = exact.range();
    // With caps, the discs at the ends are part of the shape.
    let disc = |p: V3, t: f64| {
        let (c, tangent, r) = exact.at(t);
        let d = sub(p, c);
        let along = dot(d, tangent);
        along.hypot((norm(sub(d, scale(tangent, along))) - r).max(0.0))
    };
    let out = mesh_to_shape(&m, range, |p, t| {
        let (c, tangent, r) = exact.at(t);
        let on_tube = point_circle(p, c, tangent, r);
        if caps {
            on_tube.min(disc(p, range.0)).min(disc(p, range.1))
        } else {
            on_tube
        }
    });
    let samples = (0..=600).flat_map(|i| {
        let t = range.0 + (range.1 - range.0) * f64::from(i) / 600.0;
        let (c, tangent, r) = exact.at(t);
        let e1 = perpendicular(tangent);
        let e2 = cross(tangent, e1);
        (0..48).map(move |k| {
            let a = std::f64::consts::TAU * f64::from(k) / 48.0;
            (
                t,
                add(c, add(scale(e1, r * a.cos()), scale(e2, r * a.sin()))),
            )
        })
    });
    let back = shape_to_mesh(&m, range, samples);
    assert_within("tube", &m, out, back, tol);
    out.max(back)
}

/// The trefoil of tests/it/geometry.rs (closed Catmull-Rom through 24 points): its kind and
/// points.
fn trefoil() -> (CurveKind, Vec<f64>) {
    let curve = super::trefoil();
    (curve.kind().clone(), curve.points().coords().to_vec())
}

/// A helix of 1.5 turns through 10 points, natural spline.
fn helix() -> (CurveKind, Vec<f64>) {
    let points = (0..10)
        .flat_map(|i| {
            let a = 0.9 * f64::from(i);
            [a.cos(), a.sin(), 0.3 * a]
        })
        .collect();
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: None,
    };
    (kind, points)
}

#[test]
fn tolerance_tubes_are_within_tol_of_the_exact_tube_both_ways() {
    let (kind, points) = trefoil();
    let worst = tubes_within(&kind, &points, &[0.3; 24], 1e-2, false);
    // Not vacuous: the bound is not so loose that the mesh is far within it.
    assert!(worst > 0.1 * 1e-2, "the trefoil's tube is within {worst}");
    // Radii per point, open with caps.
    let (kind, points) = helix();
    let radii: Vec<f64> = (0..10).map(|i| 0.05 + 0.02 * f64::from(i)).collect();
    tubes_within(&kind, &points, &radii, 2e-3, true);
    // A weighted NURBS (a rational curve).
    let kind = CurveKind::Nurbs {
        knots: vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0],
        weights: Some(vec![1.0, 3.0, 0.5, 1.0, 2.0, 1.0]),
    };
    let points = vec![
        0.0, 0.0, 0.0, 1.0, 2.0, 0.0, 2.0, 0.0, 1.0, 3.0, 1.0, 2.0, 4.0, 3.0, 1.0, 5.0, 0.0, 0.0,
    ];
    tubes_within(&kind, &points, &[0.2; 6], 5e-3, true);
}

/// The exact rotation-minimizing frame: double reflections on a grid of 20,000 steps (its
/// error O(h^4), far below the tolerances here), N_0 by the contract's rule without "up",
/// closed up on a closed curve; between grid points the binormal is interpolated.
struct Frame {
    start: f64,
    step: f64,
    binormals: Vec<V3>,
}

impl Frame {
    fn new(exact: &Exact, closed: bool) -> Self {
        const STEPS: usize = 20_000;
        let range = exact.range();
        let step = (range.1 - range.0) / STEPS as f64;
        let at: Vec<(V3, V3)> = (0..=STEPS)
            .map(|i| {
                let (c, t, _) = exact.at(range.0 + step * i as f64);
                (c, t)
            })
            .collect();
        let t0 = at[0].1;
        // The axis least aligned with T_0, made perpendicular to it.
        let k = (0..3)
            .min_by(|&a, &b| t0[a].abs().total_cmp(&t0[b].abs()))
            .unwrap();
        let mut axis = [0.0; 3];
        axis[k] = 1.0;
        let n0 = sub(axis, scale(t0, dot(axis, t0)));
        let mut n = scale(n0, 1.0 / norm(n0));
        let mut normals = vec![n];
        let mut lengths = vec![0.0];
        for w in at.windows(2) {
            let ((x0, t0), (x1, t1)) = (w[0], w[1]);
            let v1 = sub(x1, x0);
            let c1 = dot(v1, v1);
            let r = sub(n, scale(v1, 2.0 / c1 * dot(v1, n)));
            let tl = sub(t0, scale(v1, 2.0 / c1 * dot(v1, t0)));
            let v2 = sub(t1, tl);
            let c2 = dot(v2, v2);
            n = if c2 > 0.0 {
                sub(r, scale(v2, 2.0 / c2 * dot(v2, r)))
            } else {
                r
            };
            normals.push(n);
            lengths.push(lengths[lengths.len() - 1] + norm(v1));
        }
        if closed {
            let last = normals[STEPS];
            let alpha = dot(cross(normals[0], last), t0).atan2(dot(normals[0], last));
            let total = lengths[STEPS];
            for (i, n) in normals.iter_mut().enumerate() {
                let (sin, cos) = (-alpha * lengths[i] / total).sin_cos();
                let t = at[i].1;
                *n = add(scale(*n, cos), scale(cross(t, *n), sin));
            }
        }
        let binormals = normals
            .iter()
            .zip(&at)
            .map(|(&n, &(_, t))| cross(t, n))
            .collect();
        Self {
            start: range.0,
            step,
            binormals,
        }
    }

    fn binormal(&self, t: f64) -> V3 {
        let x = ((t - self.start) / self.step).clamp(0.0, (self.binormals.len() - 1) as f64);
        let i = (x.floor() as usize).min(self.binormals.len() - 2);
        let f = x - i as f64;
        let b = add(
            scale(self.binormals[i], 1.0 - f),
            scale(self.binormals[i + 1], f),
        );
        scale(b, 1.0 / norm(b))
    }
}

fn ribbons_within(kind: &CurveKind, points: &[f64], widths: &[f64], tol: f64, closed: bool) {
    let exact = Exact::new(kind, points, 3, widths);
    let frame = Frame::new(&exact, closed);
    let geometry = Geometry::Ribbon(Ribbon {
        width: Width::PerPoint(widths.to_vec()),
        ..Ribbon::default()
    });
    let m = tolerance_mesh(kind, points, &geometry, tol);
    let range = exact.range();
    let across = |t: f64| {
        let (c, _, w) = exact.at(t);
        let half = scale(frame.binormal(t), 0.5 * w);
        (sub(c, half), add(c, half))
    };
    let out = mesh_to_shape(&m, range, |p, t| {
        let (a, b) = across(t);
        point_segment(p, a, b)
    });
    let samples = (0..=1500).flat_map(|i| {
        let t = range.0 + (range.1 - range.0) * f64::from(i) / 1500.0;
        let (a, b) = across(t);
        (0..=8).map(move |k| (t, add(a, scale(sub(b, a), f64::from(k) / 8.0))))
    });
    let back = shape_to_mesh(&m, range, samples);
    assert_within("ribbon", &m, out, back, tol);
}

#[test]
fn tolerance_ribbons_are_within_tol_of_the_exact_ribbon_both_ways() {
    let (kind, points) = trefoil();
    ribbons_within(&kind, &points, &[0.4; 24], 5e-3, true);
    let (kind, points) = helix();
    let widths: Vec<f64> = (0..10).map(|i| 0.3 - 0.025 * f64::from(i)).collect();
    ribbons_within(&kind, &points, &widths, 2e-3, false);
}

/// A 2-D S-curve through 8 points (natural spline), its pen's width per point.
fn s_curve() -> (CurveKind, Vec<f64>, Vec<f64>) {
    let points = (0..8)
        .flat_map(|i| {
            let x = f64::from(i);
            [x, (0.8 * x).sin()]
        })
        .collect();
    let widths = (0..8).map(|i| 0.2 + 0.05 * f64::from(i % 3)).collect();
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: None,
    };
    (kind, points, widths)
}

#[test]
fn tolerance_strokes_are_within_tol_of_the_pens_area_and_cover_it() {
    let tol = 1e-3;
    let (kind, points, widths) = s_curve();
    let exact = Exact::new(&kind, &points, 2, &widths);
    let curve = Curve::new(kind, Points::new(2, points).unwrap()).unwrap();
    let geometry = Geometry::Stroke(Stroke {
        width: Width::PerPoint(widths),
        ..Stroke::default()
    });
    let mut job = GeometryJob::new();
    job.push(&curve, &geometry, &Sampling::Tolerance(tol))
        .unwrap();
    let m = job.evaluate_cpu();
    let range = exact.range();
    // The pen's segment across the curve at t (butt caps, no corners: the body is the area).
    let across = |t: f64| {
        let (c, tangent, w) = exact.at(t);
        let half = [-tangent[1] * 0.5 * w, tangent[0] * 0.5 * w, 0.0];
        (sub(c, half), add(c, half))
    };
    let out = mesh_to_shape(&m, range, |p, t| {
        let (a, b) = across(t);
        point_segment(p, a, b)
    });
    // The area's boundary, densely: the two offset curves and the ends' segments; a point of
    // the area is farther than tol from it when its distance to the samples, less half their
    // spacing, is.
    let dense: Vec<(V3, V3)> = (0..=20_000)
        .map(|i| across(range.0 + (range.1 - range.0) * f64::from(i) / 20_000.0))
        .collect();
    let spacing = dense
        .windows(2)
        .map(|w| norm(sub(w[1].0, w[0].0)).max(norm(sub(w[1].1, w[0].1))))
        .fold(0.0, f64::max);
    let (first, last) = (dense[0], dense[dense.len() - 1]);
    let from_boundary = |q: V3| {
        let curves = dense
            .iter()
            .map(|&(a, b)| norm(sub(q, a)).min(norm(sub(q, b))))
            .fold(f64::INFINITY, f64::min);
        (curves - 0.5 * spacing)
            .min(point_segment(q, first.0, first.1))
            .min(point_segment(q, last.0, last.1))
    };
    let tris = Tris::of(&m);
    let buckets = tris.buckets(range, Tris::widest_cell(&m));
    let (mut checked, mut uncovered) = (0, 0);
    for i in 0..=300 {
        let t = range.0 + (range.1 - range.0) * f64::from(i) / 300.0;
        let (a, b) = across(t);
        for k in 1..12 {
            let q = add(a, scale(sub(b, a), f64::from(k) / 12.0));
            if from_boundary(q) <= tol {
                continue;
            }
            checked += 1;
            let inside = buckets.at(t).iter().any(|&j| {
                let [a, b, c] = tris.corners[j];
                point_triangle(q, a, b, c) <= 1e-12
            });
            if !inside {
                uncovered += 1;
            }
        }
    }
    eprintln!(
        "stroke tol {tol}: {} vertices, mesh to area {:.3} tol, {checked} inner points checked",
        m.t.len(),
        out / tol
    );
    assert!(
        out <= tol,
        "a triangle strays {out} from the stroke (tol {tol})"
    );
    assert!(
        checked > 1000,
        "only {checked} points of the area were checked"
    );
    assert_eq!(uncovered, 0, "points of the area in no triangle");
}
