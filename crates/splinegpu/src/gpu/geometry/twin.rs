//! The geometry kernel's f32 twin on the CPU: `shaders/geometry.wgsl` line by line (same
//! names, loop order and arithmetic), run on the packed tables, so that the packer and the
//! kernel's arithmetic are held to the contract's promise without a GPU.

use crate::gpu::geometry::abi::{GpuMeshCurve, NONE, SHAPE_STROKE, VERTEX_FLOATS};
use crate::gpu::geometry::pack::PackedGeometry;

type V3 = [f32; 3];

const TAU: f32 = std::f32::consts::TAU;

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(s: f32, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}
fn div(a: V3, s: f32) -> V3 {
    [a[0] / s, a[1] / s, a[2] / s]
}
fn dot(a: V3, b: V3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn xyz(v: [f32; 4]) -> V3 {
    [v[0], v[1], v[2]]
}

struct Place {
    position: V3,
    d1: V3,
    d2: V3,
    width: f32,
    width_d1: f32,
}

fn place(blocks: &[[f32; 4]], curve: &GpuMeshCurve, segment: u32, u: f32) -> Place {
    let at = (curve.first_block + segment * curve.block_vec4s) as usize;
    let (a, b, c, d, e) = (
        blocks[at],
        blocks[at + 1],
        blocks[at + 2],
        blocks[at + 3],
        blocks[at + 4],
    );
    let inv = e[0];
    let mut value = [0.0f32; 4];
    let mut first = [0.0f32; 4];
    let mut second = [0.0f32; 4];
    for k in 0..4 {
        value[k] = d[k] + ((a[k] * u + b[k]) * u + c[k]) * u;
        first[k] = ((3.0 * a[k] * u + 2.0 * b[k]) * u + c[k]) * inv;
        second[k] = (6.0 * a[k] * u + 2.0 * b[k]) * (inv * inv);
    }
    if curve.rational == 1 {
        let wd = blocks[at + 5][0];
        let w = ((e[1] * u + e[2]) * u + e[3]) * u + wd;
        let w1 = (3.0 * e[1] * u + 2.0 * e[2]) * u + e[3];
        let w2 = 6.0 * e[1] * u + 2.0 * e[2];
        for k in 0..4 {
            let r = ((a[k] * u + b[k]) * u + c[k]) * u / w;
            let r1 = (((3.0 * a[k] * u + 2.0 * b[k]) * u + c[k]) - r * w1) / w;
            let r2 = ((6.0 * a[k] * u + 2.0 * b[k]) - 2.0 * r1 * w1 - r * w2) / w;
            value[k] = d[k] + r;
            first[k] = r1 * inv;
            second[k] = r2 * (inv * inv);
        }
    }
    let clamped = value[3] < 0.0;
    Place {
        position: xyz(value),
        d1: xyz(first),
        d2: xyz(second),
        width: value[3].max(0.0),
        width_d1: if clamped { 0.0 } else { first[3] },
    }
}

fn unit_or_zero(v: V3) -> V3 {
    let length = dot(v, v).sqrt();
    if length > 0.0 && length < 3.4e38 {
        return div(v, length);
    }
    [0.0; 3]
}

fn is_zero(v: V3) -> bool {
    v == [0.0; 3]
}

fn tangent(p: &Place, at_end: bool, previous: V3) -> V3 {
    let t = unit_or_zero(p.d1);
    if !is_zero(t) {
        return t;
    }
    let bend = unit_or_zero(p.d2);
    if !is_zero(bend) {
        return if at_end { scale(-1.0, bend) } else { bend };
    }
    previous
}

fn axis_normal(t: V3) -> V3 {
    let mut e = [1.0, 0.0, 0.0];
    if t[1].abs() < t[0].abs() && t[1].abs() <= t[2].abs() {
        e = [0.0, 1.0, 0.0];
    } else if t[2].abs() < t[0].abs() && t[2].abs() < t[1].abs() {
        e = [0.0, 0.0, 1.0];
    }
    unit_or_zero(sub(e, scale(dot(e, t), t)))
}

fn reflected_twice(x0: V3, x1: V3, t0: V3, t1: V3, n0: V3) -> V3 {
    let v1 = sub(x1, x0);
    let c1 = dot(v1, v1);
    let mut r = n0;
    let mut t = t0;
    if c1 > 0.0 {
        r = sub(n0, scale(2.0 / c1 * dot(v1, n0), v1));
        t = sub(t0, scale(2.0 / c1 * dot(v1, t0), v1));
    }
    let v2 = sub(t1, t);
    let c2 = dot(v2, v2);
    let mut n1 = r;
    if c2 > 0.0 {
        n1 = sub(r, scale(2.0 / c2 * dot(v2, r), v2));
    }
    let kept = unit_or_zero(sub(n1, scale(dot(n1, t1), t1)));
    if !is_zero(kept) {
        return kept;
    }
    let old = unit_or_zero(sub(n0, scale(dot(n0, t1), t1)));
    if !is_zero(old) {
        return old;
    }
    axis_normal(t1)
}

fn turned(v: V3, axis: V3, angle: f32) -> V3 {
    add(scale(angle.cos(), v), scale(angle.sin(), cross(axis, v)))
}

struct Kernel<'a> {
    packed: &'a PackedGeometry,
    out: &'a mut [f32],
}

impl Kernel<'_> {
    fn write_vertex(&mut self, curve: &GpuMeshCurve, v: u32, position: V3, normal: V3) {
        let at = VERTEX_FLOATS * (curve.first_vertex + v) as usize;
        let p = add(xyz(curve.origin_hi), add(xyz(curve.origin_lo), position));
        self.out[at..at + 3].copy_from_slice(&p);
        self.out[at + 3..at + 6].copy_from_slice(&normal);
    }

    fn write_section(&mut self, curve: &GpuMeshCurve, first: u32, p: &Place, t: V3, n: V3) {
        let b = cross(t, n);
        if curve.shape == 1 {
            let half = 0.5 * p.width;
            self.write_vertex(curve, first, sub(p.position, scale(half, b)), n);
            self.write_vertex(curve, first + 1, add(p.position, scale(half, b)), n);
            return;
        }
        let speed = dot(p.d1, p.d1).sqrt();
        let mut bend = [0.0; 3];
        let mut slope = 0.0;
        if speed > 0.0 {
            let along = dot(p.d2, t);
            bend = div(sub(p.d2, scale(along, t)), speed * speed);
            slope = p.width_d1 / speed;
        }
        for k in 0..curve.sides {
            let angle = TAU * k as f32 / curve.sides as f32;
            let e = add(scale(angle.cos(), n), scale(angle.sin(), b));
            let stretch = 1.0 - p.width * dot(bend, e);
            let mut normal = unit_or_zero(sub(scale(stretch, e), scale(slope, t)));
            if is_zero(normal) {
                normal = e;
            }
            let position = add(p.position, scale(p.width, e));
            self.write_vertex(curve, first + k, position, normal);
        }
    }

    fn walk(&mut self, curve: &GpuMeshCurve, alpha: f32, write: bool) -> V3 {
        let last = curve.sections - 1;
        let mut previous_t = xyz(curve.t_first);
        let mut previous_x = [0.0; 3];
        let mut n = xyz(curve.n0);
        for j in 0..curve.sections {
            let s = self.packed.sections[(curve.first_section + j) as usize];
            let p = place(&self.packed.blocks, curve, s.segment, s.u);
            let t = tangent(&p, j == last && j > 0, previous_t);
            if j > 0 {
                n = reflected_twice(previous_x, p.position, previous_t, t, n);
            }
            if write && s.first_vertex != NONE {
                self.write_section(curve, s.first_vertex, &p, t, turned(n, t, -alpha * s.along));
            }
            if write && s.cap_sign != 0 {
                self.write_vertex(curve, s.cap_vertex, p.position, scale(s.cap_sign as f32, t));
            }
            previous_t = t;
            previous_x = p.position;
        }
        n
    }

    fn main(&mut self, index: usize) {
        let curve = self.packed.curves[index];
        if curve.shape == SHAPE_STROKE {
            return;
        }
        let mut alpha = 0.0;
        if curve.closed == 1 {
            let carried = self.walk(&curve, 0.0, false);
            let head = self.packed.sections[curve.first_section as usize];
            let first = place(&self.packed.blocks, &curve, head.segment, head.u);
            let t0 = tangent(&first, false, xyz(curve.t_first));
            let n0 = xyz(curve.n0);
            alpha = dot(cross(n0, carried), t0).atan2(dot(n0, carried));
        }
        self.walk(&curve, alpha, true);
    }

    fn strokes(&mut self, index: usize) {
        let r = self.packed.stroke_vertices[index];
        let curve = self.packed.curves[r.curve as usize];
        let p = place(&self.packed.blocks, &curve, r.segment, r.u);
        let h = 0.5 * p.width;
        let offset = add(p.position, scale(h, [r.v[0], r.v[1], 0.0]));
        self.write_vertex(&curve, r.vertex, offset, [0.0, 0.0, 1.0]);
    }
}

/// The kernel's output for `packed` (every curve's vertices, 6 floats each), made on the CPU:
/// both entry points.
pub(crate) fn run(packed: &PackedGeometry) -> Vec<f32> {
    let mut out = vec![0.0; VERTEX_FLOATS * packed.vertices];
    let mut kernel = Kernel {
        packed,
        out: &mut out,
    };
    for index in 0..packed.curves.len() {
        kernel.main(index);
    }
    for index in 0..packed.stroke_vertices.len() {
        kernel.strokes(index);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accuracy::gpu_bound;
    use crate::geometry::{Geometry, GeometryJob, Ribbon, Tube, Width};
    use crate::{Basis, Curve, CurveKind, EndCondition, Ends, Points, Sampling};

    /// A wobbly loop of `n` points about `center` (deterministic).
    fn wobbly(n: usize, center: f64, seed: f64) -> Vec<f64> {
        (0..n)
            .flat_map(|j| {
                let a = std::f64::consts::TAU * j as f64 / n as f64;
                let r = 1.0 + 0.3 * (3.0 * a + seed).sin();
                [
                    center + r * a.cos(),
                    center + r * a.sin(),
                    center + 0.4 * (2.0 * a + seed).cos(),
                ]
            })
            .collect()
    }

    /// A natural spline of 6 points on knots 1e-3 to 38.5 apart.
    fn uneven_natural() -> CurveKind {
        CurveKind::Interpolating {
            condition: EndCondition::Natural,
            t: Some(vec![0.0, 1e-3, 1.0, 1.5, 40.0, 41.0]),
        }
    }

    /// A cubic NURBS of 6 weighted points.
    fn weighted_nurbs() -> CurveKind {
        CurveKind::Nurbs {
            knots: vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.5, 1.0, 1.0, 1.0, 1.0],
            weights: Some(vec![1.0, 2.0, 0.5, 1.5, 1.0, 3.0]),
        }
    }

    /// The twin's meshes against the f64 reference under the contract's promise: positions
    /// within the curve's GPU position bound plus 1e-5 r, normals within 1e-3 rad; closed
    /// loops near the origin and at 1e6, caps, uneven knots with per-point radii, a rational
    /// ribbon, a dashed closed tube with caps on every dash.
    #[test]
    fn the_twin_keeps_the_promise() {
        let closed = CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Closed,
        };
        let (natural, nurbs) = (uneven_natural(), weighted_nurbs());
        let tube = |radius, caps| {
            Geometry::Tube(Tube {
                radius,
                caps,
                ..Tube::default()
            })
        };
        let ribbon = Geometry::Ribbon(Ribbon {
            width: Width::Constant(0.2),
            ..Ribbon::default()
        });
        let cases = [
            (
                closed.clone(),
                wobbly(12, 0.0, 0.1),
                tube(Width::Constant(0.05), false),
                0.05,
            ),
            (
                closed,
                wobbly(12, 1e6, 0.7),
                tube(Width::Constant(0.05), false),
                0.05,
            ),
            (
                natural,
                wobbly(6, 3.0, 1.3),
                tube(
                    Width::PerPoint(vec![0.02, 0.05, 0.1, 0.05, 0.02, 0.08]),
                    true,
                ),
                0.1,
            ),
            (nurbs, wobbly(6, 5.0, 2.1), ribbon, 0.2),
            (
                CurveKind::Uniform {
                    basis: Basis::BSpline,
                    ends: Ends::Closed,
                },
                wobbly(9, -2.0, 0.4),
                Geometry::Tube(Tube {
                    radius: Width::Constant(0.05),
                    caps: true,
                    dash: Some(crate::geometry::Dash {
                        lengths: vec![0.8, 0.3],
                        offset: 0.1,
                    }),
                    ..Tube::default()
                }),
                0.05,
            ),
        ];
        let cases: Vec<_> = cases
            .into_iter()
            .map(|(kind, coords, geometry, width)| (kind, 3, coords, geometry, width))
            .collect();
        assert_twin_keeps_the_promise(&cases);
    }

    /// Every curve of `cases` (kind, dimension, coordinates, geometry, largest width or
    /// radius) made by the twin against the f64 reference: positions within the curve's GPU
    /// position bound plus 1e-5 of the width, normals within 1e-3 rad.
    fn assert_twin_keeps_the_promise(cases: &[(CurveKind, usize, Vec<f64>, Geometry, f64)]) {
        let mut job = GeometryJob::new();
        let mut tables = Vec::new();
        for (kind, dim, coords, geometry, _) in cases {
            let points = Points::new(*dim, coords.clone()).unwrap();
            let curve = Curve::new(kind.clone(), points).unwrap();
            job.push(&curve, geometry, &Sampling::PerSegment(12))
                .unwrap();
            tables.push(curve.fit());
        }
        let want = job.evaluate_cpu();
        let plans: Vec<_> = (0..job.len()).map(|c| (c, job.kernel_plan(c))).collect();
        let packed = PackedGeometry::new(&plans).unwrap();
        let got = run(&packed);
        for (c, (_, dim, coords, _, radius)) in cases.iter().enumerate() {
            let axis = |k: usize| coords.iter().skip(k).step_by(*dim).copied();
            let extent = (0..*dim)
                .map(|k| axis(k).fold(f64::MIN, f64::max) - axis(k).fold(f64::MAX, f64::min))
                .fold(0.0, f64::max);
            let table = &tables[c];
            let vertices = want.vertex_offsets[c] as usize..want.vertex_offsets[c + 1] as usize;
            for v in vertices {
                for k in 0..3 {
                    let exact = want.points[3 * v + k];
                    let bound = if k < *dim {
                        (0..table.len())
                            .map(|s| gpu_bound(&table.segment(s), extent, 0, k, exact))
                            .fold(0.0, f64::max)
                    } else {
                        0.0
                    } + 1e-5 * radius;
                    let error = (f64::from(got[6 * v + k]) - exact).abs();
                    assert!(error <= bound, "curve {c} vertex {v}: {error} > {bound}");
                }
                let dot: f64 = (0..3)
                    .map(|k| want.normals[3 * v + k] * f64::from(got[6 * v + 3 + k]))
                    .sum();
                assert!(
                    dot.clamp(-1.0, 1.0).acos() <= 1e-3,
                    "curve {c} vertex {v}: {dot}"
                );
            }
        }
    }

    /// Strokes through the twin's `strokes` entry: every join (miter, round, bevel, a miter
    /// past its limit), square and round caps, a cusp, a width per point on uneven knots, a
    /// weighted NURBS, a dashed closed curve, and a polyline at 1e6; mixed with a tube in the
    /// same packing.
    #[test]
    fn the_twin_strokes_keep_the_promise() {
        use crate::geometry::{Cap, Join, Stroke};
        let stroke = |join, cap, width: Width| {
            Geometry::Stroke(Stroke {
                width,
                join,
                cap,
                ..Stroke::default()
            })
        };
        // Straight Bezier segments through `corners` (x, y pairs), thirds as inner points.
        let polyline = |corners: &[f64]| -> Vec<f64> {
            let mut out = corners[..2].to_vec();
            for pair in corners.chunks(2).collect::<Vec<_>>().windows(2) {
                let (a, b) = (pair[0], pair[1]);
                for k in 1..=3 {
                    let f = f64::from(k) / 3.0;
                    out.extend([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]);
                }
            }
            out
        };
        let zigzag = |at: f64| -> Vec<f64> {
            let corners: Vec<f64> = (0..7)
                .flat_map(|j| {
                    let up = if j % 2 == 0 {
                        0.0
                    } else {
                        0.4 + 0.1 * j as f64
                    };
                    [at + j as f64, at + up]
                })
                .collect();
            polyline(&corners)
        };
        let linear = CurveKind::Bezier;
        let (natural, nurbs) = (uneven_natural(), weighted_nurbs());
        let flat = |coords: Vec<f64>| -> Vec<f64> {
            coords.chunks(3).flat_map(|p| [p[0], p[1]]).collect()
        };
        let cases = vec![
            (
                linear.clone(),
                2,
                zigzag(0.0),
                stroke(Join::Miter, Cap::Square, Width::Constant(0.1)),
                0.1,
            ),
            (
                linear.clone(),
                2,
                zigzag(1e6),
                stroke(Join::Round, Cap::Round, Width::Constant(0.1)),
                0.1,
            ),
            (
                linear,
                2,
                polyline(&[0.0, 0.0, 1.0, 0.0, 0.0, 0.05, 1.0, 0.1]),
                stroke(Join::Miter, Cap::Butt, Width::Constant(0.05)),
                0.05,
            ),
            (
                CurveKind::Bezier,
                2,
                vec![0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0],
                stroke(Join::Bevel, Cap::Round, Width::Constant(0.05)),
                0.05,
            ),
            (
                natural,
                2,
                flat(wobbly(6, 3.0, 1.3)),
                stroke(
                    Join::Round,
                    Cap::Square,
                    Width::PerPoint(vec![0.02, 0.05, 0.1, 0.05, 0.02, 0.08]),
                ),
                0.1,
            ),
            (
                nurbs,
                2,
                flat(wobbly(6, 5.0, 2.1)),
                stroke(Join::Miter, Cap::Round, Width::Constant(0.2)),
                0.2,
            ),
            (
                CurveKind::Uniform {
                    basis: Basis::BSpline,
                    ends: Ends::Closed,
                },
                2,
                flat(wobbly(9, -2.0, 0.4)),
                Geometry::Stroke(Stroke {
                    width: Width::Constant(0.05),
                    cap: Cap::Round,
                    dash: Some(crate::geometry::Dash {
                        lengths: vec![0.8, 0.3],
                        offset: 0.1,
                    }),
                    ..Stroke::default()
                }),
                0.05,
            ),
            (
                CurveKind::Uniform {
                    basis: Basis::CatmullRom,
                    ends: Ends::Closed,
                },
                3,
                wobbly(12, 0.0, 0.1),
                Geometry::Tube(Tube {
                    radius: Width::Constant(0.05),
                    ..Tube::default()
                }),
                0.05,
            ),
        ];
        assert_twin_keeps_the_promise(&cases);
    }
}
