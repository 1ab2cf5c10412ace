//! The strokes workload's anchor and accuracy: lyon's stroke tessellator on the same curves
//! (each one's cubic Bezier segments, from its own fitted table), and the largest distance of
//! a mesh from the exact stroke, measured the same way for lyon's mesh and ours.
//!
//! The exact stroke of these curves (C1 Catmull-Rom: no corners) is the body, the union of
//! the pen's segments C(t) ± (w/2) n(t), and the round caps' half discs. A mesh point's
//! distance from it is searched: the nearest of a dense polyline's samples, then golden
//! sections over t about it for the nearest pen segment, and the caps; every search gives an
//! upper bound of the true distance, so the figure never flatters a mesh.

use lyon_tessellation::math::{Point, point};
use lyon_tessellation::path::Path;
use lyon_tessellation::{
    BuffersBuilder, LineCap, LineJoin, StrokeOptions, StrokeTessellator, StrokeVertex,
    VertexBuffers,
};
use splinegpu::Curve;
use splinegpu::geometry::Meshes;

/// A curve's cubic Bezier segments in the plane.
pub(crate) type Beziers = Vec<[[f64; 2]; 4]>;

/// `curve`'s segments as Bezier control points (its fitted table's).
pub(crate) fn beziers(curve: &Curve) -> Beziers {
    let table = curve.fit();
    (0..table.len())
        .map(|s| {
            let points = table
                .segment(s)
                .bezier_points()
                .expect("a polynomial curve");
            std::array::from_fn(|i| [points[i][0], points[i][1]])
        })
        .collect()
}

/// lyon's options for a stroke of `width` with round joins and caps at `tol`.
fn options(width: f64, tol: f64) -> StrokeOptions {
    StrokeOptions::tolerance(tol as f32)
        .with_line_width(width as f32)
        .with_line_join(LineJoin::Round)
        .with_line_cap(LineCap::Round)
}

fn path(curve: &Beziers) -> Path {
    let p = |q: [f64; 2]| point(q[0] as f32, q[1] as f32);
    let mut builder = Path::builder();
    builder.begin(p(curve[0][0]));
    for b in curve {
        builder.cubic_bezier_to(p(b[1]), p(b[2]), p(b[3]));
    }
    builder.end(false);
    builder.build()
}

/// Every curve's stroke appended to `out` by lyon (the timed path: the paths built from the
/// control points, then tessellated).
pub(crate) fn lyon_strokes(
    curves: &[Beziers],
    width: f64,
    tol: f64,
    out: &mut VertexBuffers<Point, u32>,
) {
    let options = options(width, tol);
    let mut tessellator = StrokeTessellator::new();
    for curve in curves {
        let path = path(curve);
        let mut builder = BuffersBuilder::new(out, |v: StrokeVertex| v.position());
        tessellator
            .tessellate_path(&path, &options, &mut builder)
            .expect("lyon strokes the curve");
    }
}

/// One curve's stroke by lyon: positions and triangles.
fn lyon_mesh(curve: &Beziers, width: f64, tol: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut out = VertexBuffers::new();
    lyon_strokes(std::slice::from_ref(curve), width, tol, &mut out);
    let points = out
        .vertices
        .iter()
        .map(|v| [f64::from(v.x), f64::from(v.y)])
        .collect();
    let triangles = out.indices.chunks(3).map(|t| [t[0], t[1], t[2]]).collect();
    (points, triangles)
}

/// The exact stroke of one curve of Bezier segments (parameter t = segment + u).
struct Exact<'a> {
    curve: &'a Beziers,
    half: f64,
    /// (t, C(t)) on a dense grid.
    dense: Vec<(f64, [f64; 2])>,
}

fn bezier(b: &[[f64; 2]; 4], u: f64) -> ([f64; 2], [f64; 2]) {
    let v = 1.0 - u;
    let (b0, b1, b2, b3) = (v * v * v, 3.0 * u * v * v, 3.0 * u * u * v, u * u * u);
    let (d0, d1, d2) = (3.0 * v * v, 6.0 * u * v, 3.0 * u * u);
    let p = std::array::from_fn(|k| b0 * b[0][k] + b1 * b[1][k] + b2 * b[2][k] + b3 * b[3][k]);
    let d = std::array::from_fn(|k| {
        d0 * (b[1][k] - b[0][k]) + d1 * (b[2][k] - b[1][k]) + d2 * (b[3][k] - b[2][k])
    });
    (p, d)
}

fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ab, ap) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let l = ab[0] * ab[0] + ab[1] * ab[1];
    let x = if l > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) / l).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (ap[0] - x * ab[0]).hypot(ap[1] - x * ab[1])
}

impl<'a> Exact<'a> {
    const DENSE: usize = 64;

    fn new(curve: &'a Beziers, width: f64) -> Self {
        let n = curve.len() * Self::DENSE;
        let dense = (0..=n)
            .map(|i| {
                let t = i as f64 / Self::DENSE as f64;
                (t, self_at(curve, t).0)
            })
            .collect();
        Self {
            curve,
            half: 0.5 * width,
            dense,
        }
    }

    /// The distance from p to the pen's segment at t.
    fn to_pen(&self, p: [f64; 2], t: f64) -> f64 {
        let (c, d) = self_at(self.curve, t);
        let speed = d[0].hypot(d[1]);
        let n = [-d[1] / speed * self.half, d[0] / speed * self.half];
        distance_to_segment(p, [c[0] - n[0], c[1] - n[1]], [c[0] + n[0], c[1] + n[1]])
    }

    /// The distance from p to the round cap's half disc at the end t (facing `sign` along
    /// the tangent).
    fn to_cap(&self, p: [f64; 2], t: f64, sign: f64) -> f64 {
        let (c, d) = self_at(self.curve, t);
        let speed = d[0].hypot(d[1]);
        let out = [sign * d[0] / speed, sign * d[1] / speed];
        let q = [p[0] - c[0], p[1] - c[1]];
        if q[0] * out[0] + q[1] * out[1] >= 0.0 {
            (q[0].hypot(q[1]) - self.half).max(0.0)
        } else {
            let n = [-out[1] * self.half, out[0] * self.half];
            distance_to_segment(p, [c[0] - n[0], c[1] - n[1]], [c[0] + n[0], c[1] + n[1]])
        }
    }

    fn distance(&self, p: [f64; 2]) -> f64 {
        let nearest = (0..self.dense.len())
            .min_by(|&a, &b| {
                let d = |i: usize| {
                    let c = self.dense[i].1;
                    (p[0] - c[0]).hypot(p[1] - c[1])
                };
                d(a).total_cmp(&d(b))
            })
            .expect("a dense grid");
        let end = self.dense[self.dense.len() - 1].0;
        let step = 1.0 / Self::DENSE as f64;
        let t = self.dense[nearest].0;
        let (mut lo, mut hi) = ((t - step).max(0.0), (t + step).min(end));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let mut best = self.to_pen(p, t);
        for _ in 0..40 {
            let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            let (f1, f2) = (self.to_pen(p, x1), self.to_pen(p, x2));
            best = best.min(f1).min(f2);
            if f1 < f2 {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        best.min(self.to_cap(p, 0.0, -1.0))
            .min(self.to_cap(p, end, 1.0))
    }
}

/// Position and derivative at t = segment + u (the last segment at u = 1 for t = its end).
fn self_at(curve: &Beziers, t: f64) -> ([f64; 2], [f64; 2]) {
    let s = (t.floor() as usize).min(curve.len() - 1);
    bezier(&curve[s], t - s as f64)
}

/// The largest distance from the exact stroke of points spread over every triangle (its
/// corners, edge midpoints, centroid and three more inside).
fn mesh_error(exact: &Exact<'_>, points: &[[f64; 2]], triangles: &[[u32; 3]]) -> f64 {
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
    let mut worst = 0.0f64;
    for t in triangles {
        let [a, b, c] = t.map(|v| points[v as usize]);
        for w in WEIGHTS {
            let p = std::array::from_fn(|k| w[0] * a[k] + w[1] * b[k] + w[2] * c[k]);
            worst = worst.max(exact.distance(p));
        }
    }
    worst
}

/// The largest error of our meshes (`meshes`, made for `curves` in order) and of lyon's on
/// the same curves.
pub(crate) fn max_errors(curves: &[Beziers], meshes: &Meshes, width: f64, tol: f64) -> (f64, f64) {
    let (mut ours, mut lyon) = (0.0f64, 0.0f64);
    for (c, curve) in curves.iter().enumerate() {
        let exact = Exact::new(curve, width);
        let (v0, v1) = (
            meshes.vertex_offsets[c] as usize,
            meshes.vertex_offsets[c + 1] as usize,
        );
        let (f0, f1) = (
            meshes.triangle_offsets[c] as usize,
            meshes.triangle_offsets[c + 1] as usize,
        );
        let points: Vec<[f64; 2]> = (v0..v1)
            .map(|v| [meshes.points[3 * v], meshes.points[3 * v + 1]])
            .collect();
        ours = ours.max(mesh_error(&exact, &points, &meshes.triangles[f0..f1]));
        let (points, triangles) = lyon_mesh(curve, width, tol);
        lyon = lyon.max(mesh_error(&exact, &points, &triangles));
    }
    (ours, lyon)
}
