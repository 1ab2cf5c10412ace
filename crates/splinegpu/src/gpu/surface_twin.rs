//! The CPU twin of `shaders/surface.wgsl`: the kernel in f32, line by line (same names, same
//! loop order, same f32 arithmetic in the same order), run over every invocation of every
//! dispatch that [`GpuContext::evaluate_surfaces`](crate::GpuContext::evaluate_surfaces) would
//! make, so that the packing and the kernel's arithmetic are tested against the contract's
//! promise without a GPU.

use super::surface::{
    GpuPatch, GpuVertex, SURFACE_WG_SIZE, SurfaceParams, evaluate_group_with, plane_count,
};
use crate::error::GpuError;
use crate::job::Derivatives;
use crate::surface::{PatchTable, SurfacePlan, SurfaceSamples};

/// `DEGENERATE` in the kernel.
const DEGENERATE: f32 = 1e-5;

/// Evaluates `surfaces` as the kernel does, in dispatches of at most `budget` floats per plane.
pub(crate) fn evaluate_surfaces_twin(
    surfaces: &[(&PatchTable, &SurfacePlan)],
    derivatives: Derivatives,
    normals: bool,
    budget: usize,
) -> Result<Vec<SurfaceSamples<f32>>, GpuError> {
    let planes = plane_count(derivatives, normals);
    evaluate_group_with(
        surfaces,
        derivatives,
        normals,
        budget,
        |packed, vertices, floats| {
            let params = SurfaceParams {
                vertex_count: vertices.len() as u32,
                row_width: (vertices.len() as u32).div_ceil(SURFACE_WG_SIZE) * SURFACE_WG_SIZE,
                plane_stride: floats as u32,
                derivatives: derivatives.order() as u32,
                normals: u32::from(normals),
                _padding: [0; 3],
            };
            let kernel = Kernel {
                params,
                patches: &packed.patches,
                coeffs: &packed.coeffs,
                vertices,
            };
            let mut out = vec![0.0f32; planes * floats];
            for i in 0..params.row_width {
                kernel.main(i, &mut out);
            }
            Ok(out)
        },
    )
}

/// One dispatch's bindings.
struct Kernel<'a> {
    params: SurfaceParams,
    patches: &'a [GpuPatch],
    coeffs: &'a [f32],
    vertices: &'a [GpuVertex],
}

type Vec3 = [f32; 3];

fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(s: f32, a: Vec3) -> Vec3 {
    [s * a[0], s * a[1], s * a[2]]
}

fn length(a: Vec3) -> f32 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn bernstein3(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

fn bernstein2(t: f32) -> [f32; 3] {
    let s = 1.0 - t;
    [3.0 * s * s, 6.0 * s * t, 3.0 * t * t]
}

impl Kernel<'_> {
    fn tensor(
        &self,
        first: u32,
        stride: u32,
        constant: bool,
        u: f32,
        v: f32,
        planes: u32,
    ) -> [f32; 6] {
        let pu = [1.0, u, u * u, u * u * u];
        let dpu = [0.0, 1.0, 2.0 * u, 3.0 * u * u];
        let ddpu = [0.0, 0.0, 2.0, 6.0 * u];
        let pv = [1.0, v, v * v, v * v * v];
        let dpv = [0.0, 1.0, 2.0 * v, 3.0 * v * v];
        let ddpv = [0.0, 0.0, 2.0, 6.0 * v];
        let mut d = [0.0f32; 6];
        let mut at = first;
        let start = if constant { 0 } else { 1 };
        for ab in start..16usize {
            let (a, b) = (ab / 4, ab % 4);
            let c = self.coeffs[at as usize];
            at += stride;
            d[0] += pu[a] * pv[b] * c;
            if planes > 1 {
                d[1] += dpu[a] * pv[b] * c;
                d[2] += pu[a] * dpv[b] * c;
            }
            if planes > 3 {
                d[3] += ddpu[a] * pv[b] * c;
                d[4] += dpu[a] * dpv[b] * c;
                d[5] += pu[a] * ddpv[b] * c;
            }
        }
        d
    }

    fn coordinate(&self, p: GpuPatch, k: u32, u: f32, v: f32, planes: u32) -> [f32; 6] {
        let n = self.tensor(p.coeff_offset + k, p.dim, false, u, v, planes);
        if p.rational == 0 {
            return n;
        }
        let w = self.tensor(p.coeff_offset + 17 * p.dim, 1, true, u, v, planes);
        let mut r = [n[0] / w[0], 0.0, 0.0, 0.0, 0.0, 0.0];
        if planes > 1 {
            r[1] = (n[1] - r[0] * w[1]) / w[0];
            r[2] = (n[2] - r[0] * w[2]) / w[0];
        }
        if planes > 3 {
            r[3] = (n[3] - 2.0 * r[1] * w[1] - r[0] * w[3]) / w[0];
            r[4] = (n[4] - r[1] * w[2] - r[2] * w[1] - r[0] * w[4]) / w[0];
            r[5] = (n[5] - 2.0 * r[2] * w[2] - r[0] * w[5]) / w[0];
        }
        r
    }

    fn point(&self, at: u32) -> Vec3 {
        let at = at as usize;
        [self.coeffs[at], self.coeffs[at + 1], self.coeffs[at + 2]]
    }

    fn cross_at(&self, p: GpuPatch, u: f32, v: f32) -> [Vec3; 4] {
        let bu = bernstein3(u);
        let bv = bernstein3(v);
        let cu = bernstein2(u);
        let cv = bernstein2(v);
        let mut n = [0.0f32; 3];
        let mut nu = [0.0f32; 3];
        let mut nv = [0.0f32; 3];
        let mut sizes = [0.0f32; 3];
        let base = p.normal_offset;
        for i in 0..4u32 {
            for j in 0..4u32 {
                let (iu, ju) = (i as usize, j as usize);
                let at = base + 3 * (4 * i + j);
                n = add(n, scale(bu[iu] * bv[ju], self.point(at)));
                if i < 3 {
                    let d = base + 48 + 3 * (4 * i + j);
                    nu = add(nu, scale(cu[iu] * bv[ju], self.point(d)));
                    sizes[0] += cu[iu] * bv[ju] * self.coeffs[(base + 120 + 4 * i + j) as usize];
                }
                if j < 3 {
                    let d = base + 84 + 3 * (3 * i + j);
                    nv = add(nv, scale(bu[iu] * cv[ju], self.point(d)));
                    sizes[1] += bu[iu] * cv[ju] * self.coeffs[(base + 132 + 3 * i + j) as usize];
                }
            }
        }
        let mut su = nu;
        let mut sv = nv;
        if p.rational == 1 {
            let w = self.tensor(p.coeff_offset + 17 * p.dim, 1, true, u, v, 3);
            let r = n.map(|x| x / w[0]);
            su = [0, 1, 2].map(|k| (nu[k] - r[k] * w[1]) / w[0]);
            sv = [0, 1, 2].map(|k| (nv[k] - r[k] * w[2]) / w[0]);
        }
        [cross(su, sv), su, sv, sizes]
    }

    fn unit_normal(&self, p: GpuPatch, u: f32, v: f32) -> Vec3 {
        let mut uu = u;
        let mut vv = v;
        for step in 0..4 {
            let c = self.cross_at(p, uu, vv);
            let size = length(c[0]);
            if size > DEGENERATE * length(c[1]) * length(c[2])
                && size > DEGENERATE * c[3][0] * c[3][1]
                && size > 0.0
            {
                return c[0].map(|x| x / size);
            }
            let toward = [1e-3f32, 1e-2, 1e-1];
            if step < 3 {
                uu = u + (0.5 - u) * toward[step];
                vv = v + (0.5 - v) * toward[step];
            }
        }
        [0.0, 0.0, 1.0]
    }

    fn main(&self, i: u32, out: &mut [f32]) {
        let params = self.params;
        if i >= params.vertex_count {
            return;
        }
        let vertex = self.vertices[i as usize];
        let p = self.patches[vertex.patch_index as usize];
        let scale = [
            1.0,
            p.inv_du,
            p.inv_dv,
            p.inv_du * p.inv_du,
            p.inv_du * p.inv_dv,
            p.inv_dv * p.inv_dv,
        ];
        let mut planes = 1;
        if params.derivatives >= 1 {
            planes = 3;
        }
        if params.derivatives == 2 {
            planes = 6;
        }
        for k in 0..p.dim {
            let d = self.coordinate(p, k, vertex.u, vertex.v, planes);
            let origin = (p.coeff_offset + 15 * p.dim + k) as usize;
            out[(vertex.out + k) as usize] =
                self.coeffs[origin] + (self.coeffs[origin + p.dim as usize] + d[0]);
            for m in 1..planes {
                out[(m * params.plane_stride + vertex.out + k) as usize] =
                    d[m as usize] * scale[m as usize];
            }
        }
        if params.normals == 1 {
            let n = self.unit_normal(p, vertex.u, vertex.v);
            let at = (planes * params.plane_stride + vertex.out) as usize;
            out[at..at + 3].copy_from_slice(&n);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accuracy::surface_gpu_bound;
    use crate::fit::interp::EndCondition;
    use crate::surface::{Net, Surface, SurfaceKind, SurfaceSampling, evaluate_surfaces};
    use crate::{Basis, Ends};

    /// A seeded net of `rows` x `cols` 3-D points within 2 of `center`.
    fn net(seed: u64, rows: usize, cols: usize, center: f64) -> Net {
        let mut state = seed;
        let coords = (0..rows * cols * 3)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1);
                center + 4.0 * ((state >> 11) as f64 / (1u64 << 53) as f64) - 2.0
            })
            .collect();
        Net::new(3, rows, cols, coords).unwrap()
    }

    /// Every kind: nets near 1e5, knot spacings 1e3 apart, rational patches, a collapsed edge.
    fn surfaces() -> Vec<(Surface, SurfaceSampling)> {
        let uniform = |basis, ends, center, seed| {
            let kind = SurfaceKind::Uniform { basis, ends };
            let surface = Surface::new(kind, net(seed, 6, 5, center)).unwrap();
            (surface, SurfaceSampling::PerSegment([5, 4]))
        };
        let beta = Basis::Beta {
            bias: 1.5,
            tension: 2.0,
        };
        let interpolating = SurfaceKind::Interpolating {
            conditions: [EndCondition::NotAKnot, EndCondition::Natural],
            u: Some(vec![0.0, 1e-3, 1.0, 1.001, 2.0, 3.0]),
            v: Some(vec![0.0, 1.0, 1e3, 1e3 + 1.0, 2e3]),
        };
        let nurbs = SurfaceKind::Nurbs {
            knots_u: vec![0.0, 0.0, 0.0, 0.0, 1e-3, 1.0, 1.0, 1.0, 1.0],
            knots_v: vec![5.0, 5.0, 5.0, 5.0, 6.0, 6.0, 6.0, 6.0],
            weights: Some((0..20).map(|i| 0.5 + f64::from(i % 7) * 0.25).collect()),
        };
        // A Bezier net whose first row is one point: a pole along u = 0.
        let mut pole = net(9, 4, 4, 0.0).coords().to_vec();
        for j in 1..4 {
            pole.copy_within(0..3, 3 * j);
        }
        vec![
            uniform(Basis::BSpline, [Ends::Closed, Ends::Closed], 0.0, 1),
            uniform(Basis::CatmullRom, [Ends::Control, Ends::Repeat], 1e5, 2),
            uniform(beta, [Ends::Repeat, Ends::Closed], -3e4, 3),
            (
                Surface::new(SurfaceKind::Bezier, net(4, 7, 4, 1e5)).unwrap(),
                SurfaceSampling::Tolerance(0.05),
            ),
            (
                Surface::new(interpolating, net(5, 6, 5, 0.0)).unwrap(),
                SurfaceSampling::PerSegment([6, 6]),
            ),
            (
                Surface::new(nurbs, net(6, 5, 4, 1e5)).unwrap(),
                SurfaceSampling::PerSegment([7, 3]),
            ),
            (
                Surface::new(SurfaceKind::Bezier, Net::new(3, 4, 4, pole).unwrap()).unwrap(),
                SurfaceSampling::PerSegment([6, 6]),
            ),
        ]
    }

    /// The twin keeps the contract's surface promise against the f64 evaluator on every kind
    /// (values and derivatives under `surface_gpu_bound`, normals within 1e-3 rad where the
    /// cross product is well formed and 0.05 rad at the pole), in dispatches cut small.
    #[test]
    fn the_kernels_twin_keeps_the_surface_promise_on_every_kind() {
        let surfaces = surfaces();
        let tables: Vec<PatchTable> = surfaces.iter().map(|(s, _)| s.fit()).collect();
        let plans: Vec<SurfacePlan> = tables
            .iter()
            .zip(&surfaces)
            .map(|(t, (_, sampling))| SurfacePlan::new(t, sampling).unwrap())
            .collect();
        let jobs: Vec<_> = tables.iter().zip(&plans).collect();
        let twin = evaluate_surfaces_twin(&jobs, Derivatives::Second, true, 1000).unwrap();
        let mut poles = 0;
        for (s, ((table, plan), got)) in jobs.iter().zip(&twin).enumerate() {
            let want = evaluate_surfaces(table, plan, Derivatives::Second, true);
            let pairs = [
                (&want.points, &got.points),
                (want.du.as_ref().unwrap(), got.du.as_ref().unwrap()),
                (want.dv.as_ref().unwrap(), got.dv.as_ref().unwrap()),
                (want.duu.as_ref().unwrap(), got.duu.as_ref().unwrap()),
                (want.duv.as_ref().unwrap(), got.duv.as_ref().unwrap()),
                (want.dvv.as_ref().unwrap(), got.dvv.as_ref().unwrap()),
            ];
            for (i, vertex) in plan.vertices.iter().enumerate() {
                let patch = table.patch(vertex.patch as usize);
                for (m, (w, g)) in pairs.iter().enumerate() {
                    for k in 0..3 {
                        let (w, g) = (w[3 * i + k], f64::from(g[3 * i + k]));
                        let bound = surface_gpu_bound(&patch, table.extent(), m, k, w);
                        assert!(
                            (g - w).abs() <= bound,
                            "surface {s} vertex {i} plane {m} coordinate {k}: {g} vs {w} \
                             (bound {bound})"
                        );
                    }
                }
                let at = |p: &[f64]| [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
                let (du, dv) = (at(pairs[1].0), at(pairs[2].0));
                let norm = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                let cross = [
                    du[1] * dv[2] - du[2] * dv[1],
                    du[2] * dv[0] - du[0] * dv[2],
                    du[0] * dv[1] - du[1] * dv[0],
                ];
                let (w, g) = (
                    at(want.normals.as_ref().unwrap()),
                    at(&got
                        .normals
                        .as_ref()
                        .unwrap()
                        .iter()
                        .map(|&x| f64::from(x))
                        .collect::<Vec<_>>()),
                );
                let angle = (w[0] * g[0] + w[1] * g[1] + w[2] * g[2])
                    .clamp(-1.0, 1.0)
                    .acos();
                let [su, sv] = patch.derivative_sizes();
                let [lu, lv] = patch.length();
                if norm(cross) * lu * lv <= 1e-10 * su * sv {
                    poles += 1;
                    assert!(
                        angle < 0.05,
                        "surface {s} vertex {i}: pole normal {angle} rad off"
                    );
                } else if norm(cross) >= 1e-2 * norm(du) * norm(dv) {
                    assert!(
                        angle <= 1e-3,
                        "surface {s} vertex {i}: normal {angle} rad off"
                    );
                }
            }
        }
        assert!(poles >= 7, "the pole's vertices were tested: {poles}");
    }
}
