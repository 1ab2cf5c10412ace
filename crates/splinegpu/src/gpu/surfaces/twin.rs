//! The CPU twin of `shaders/surface.wgsl`: the kernel in f32, line by line (same names, same
//! loop order, same f32 arithmetic in the same order), run over every invocation of every
//! dispatch that [`GpuContext::evaluate_surfaces`](crate::GpuContext::evaluate_surfaces) would
//! make, so that the packing and the kernel's arithmetic are tested against the contract's
//! promise without a GPU.

use crate::error::GpuError;
use crate::gpu::surfaces::abi::{GpuPatch, GpuVertex, SURFACE_WG_SIZE, SurfaceParams};
use crate::gpu::surfaces::dispatch::{DispatchBudget, evaluate_group_with, plane_count};
use crate::job::Derivatives;
use crate::surface::{PatchTable, SurfacePlan, SurfaceSamples};

/// `DEGENERATE` in the kernel.
const DEGENERATE: f32 = 1e-5;

/// Evaluates `surfaces` as the kernel does, in the dispatches that a storage-binding limit of
/// `binding` bytes allows.
pub(crate) fn evaluate_surfaces_twin(
    surfaces: &[(&PatchTable, &SurfacePlan)],
    derivatives: Derivatives,
    normals: bool,
    binding: u64,
) -> Result<Vec<SurfaceSamples<f32>>, GpuError> {
    let planes = plane_count(derivatives, normals);
    let budget = DispatchBudget::for_binding(binding, planes);
    evaluate_group_with(
        surfaces,
        derivatives,
        normals,
        budget,
        &mut |packed, vertices, floats, consume| {
            assert!(
                std::mem::size_of_val(vertices) as u64 <= binding
                    && (floats * planes * 4) as u64 <= binding,
                "a dispatch over the binding limit: {} vertices, {floats} floats a plane",
                vertices.len()
            );
            let row_width = (vertices.len() as u32).div_ceil(SURFACE_WG_SIZE) * SURFACE_WG_SIZE;
            let params = SurfaceParams::new(
                vertices.len(),
                row_width,
                floats,
                derivatives.order(),
                normals,
            );
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
            consume(&out);
            Ok(())
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

fn dot4(a: [f32; 4], b: [f32; 4]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

fn dot3(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Kernel<'_> {
    fn coefficient(&self, first: u32, stride: u32, constant: bool, a: u32, b: u32) -> f32 {
        let ab = 4 * a + b;
        if constant {
            return self.coeffs[(first + ab * stride) as usize];
        }
        if ab == 0 {
            return 0.0;
        }
        self.coeffs[(first + (ab - 1) * stride) as usize]
    }

    fn row(&self, first: u32, stride: u32, constant: bool, a: u32, v: f32) -> Vec3 {
        let c0 = self.coefficient(first, stride, constant, a, 0);
        let c1 = self.coefficient(first, stride, constant, a, 1);
        let c2 = self.coefficient(first, stride, constant, a, 2);
        let c3 = self.coefficient(first, stride, constant, a, 3);
        [
            c0 + v * (c1 + v * (c2 + v * c3)),
            c1 + v * (2.0 * c2 + 3.0 * v * c3),
            2.0 * c2 + 6.0 * v * c3,
        ]
    }

    fn tensor(&self, first: u32, stride: u32, constant: bool, u: f32, v: f32) -> [f32; 6] {
        let r0 = self.row(first, stride, constant, 0, v);
        let r1 = self.row(first, stride, constant, 1, v);
        let r2 = self.row(first, stride, constant, 2, v);
        let r3 = self.row(first, stride, constant, 3, v);
        let value: Vec3 = std::array::from_fn(|k| r0[k] + u * (r1[k] + u * (r2[k] + u * r3[k])));
        let slope: Vec3 = std::array::from_fn(|k| r1[k] + u * (2.0 * r2[k] + 3.0 * u * r3[k]));
        let bend: Vec3 = std::array::from_fn(|k| 2.0 * r2[k] + 6.0 * u * r3[k]);
        [value[0], slope[0], value[1], bend[0], slope[1], value[2]]
    }

    fn coordinate(&self, p: GpuPatch, k: u32, u: f32, v: f32) -> [f32; 6] {
        let n = self.tensor(p.coeff_offset + k, p.dim, false, u, v);
        if p.rational == 0 {
            return n;
        }
        let w = self.tensor(p.coeff_offset + 17 * p.dim, 1, true, u, v);
        let r = n[0] / w[0];
        let ru = (n[1] - r * w[1]) / w[0];
        let rv = (n[2] - r * w[2]) / w[0];
        let ruu = (n[3] - 2.0 * ru * w[1] - r * w[3]) / w[0];
        let ruv = (n[4] - ru * w[2] - rv * w[1] - r * w[4]) / w[0];
        let rvv = (n[5] - 2.0 * rv * w[2] - r * w[5]) / w[0];
        [r, ru, rv, ruu, ruv, rvv]
    }

    fn point3(&self, at: u32) -> Vec3 {
        let at = at as usize;
        [self.coeffs[at], self.coeffs[at + 1], self.coeffs[at + 2]]
    }

    fn weighted4(&self, first: u32, w: [f32; 4]) -> Vec3 {
        let sum = add(
            add(
                scale(w[0], self.point3(first)),
                scale(w[1], self.point3(first + 3)),
            ),
            scale(w[2], self.point3(first + 6)),
        );
        add(sum, scale(w[3], self.point3(first + 9)))
    }

    fn weighted3(&self, first: u32, w: [f32; 3]) -> Vec3 {
        add(
            add(
                scale(w[0], self.point3(first)),
                scale(w[1], self.point3(first + 3)),
            ),
            scale(w[2], self.point3(first + 6)),
        )
    }

    fn lengths4(&self, first: u32) -> [f32; 4] {
        std::array::from_fn(|i| self.coeffs[first as usize + i])
    }

    fn lengths3(&self, first: u32) -> [f32; 3] {
        std::array::from_fn(|i| self.coeffs[first as usize + i])
    }

    fn cross_at(&self, p: GpuPatch, u: f32, v: f32) -> [Vec3; 4] {
        let bu = bernstein3(u);
        let bv = bernstein3(v);
        let cu = bernstein2(u);
        let cv = bernstein2(v);
        let base = p.normal_offset;
        let n = add(
            add(
                add(
                    scale(bu[0], self.weighted4(base, bv)),
                    scale(bu[1], self.weighted4(base + 12, bv)),
                ),
                scale(bu[2], self.weighted4(base + 24, bv)),
            ),
            scale(bu[3], self.weighted4(base + 36, bv)),
        );
        let nu = add(
            add(
                scale(cu[0], self.weighted4(base + 48, bv)),
                scale(cu[1], self.weighted4(base + 60, bv)),
            ),
            scale(cu[2], self.weighted4(base + 72, bv)),
        );
        let nv = add(
            add(
                add(
                    scale(bu[0], self.weighted3(base + 84, cv)),
                    scale(bu[1], self.weighted3(base + 93, cv)),
                ),
                scale(bu[2], self.weighted3(base + 102, cv)),
            ),
            scale(bu[3], self.weighted3(base + 111, cv)),
        );
        let size_u = cu[0] * dot4(bv, self.lengths4(base + 120))
            + cu[1] * dot4(bv, self.lengths4(base + 124))
            + cu[2] * dot4(bv, self.lengths4(base + 128));
        let size_v = bu[0] * dot3(cv, self.lengths3(base + 132))
            + bu[1] * dot3(cv, self.lengths3(base + 135))
            + bu[2] * dot3(cv, self.lengths3(base + 138))
            + bu[3] * dot3(cv, self.lengths3(base + 141));
        let mut su = nu;
        let mut sv = nv;
        if p.rational == 1 {
            let w = self.tensor(p.coeff_offset + 17 * p.dim, 1, true, u, v);
            let r = n.map(|x| x / w[0]);
            su = [0, 1, 2].map(|k| (nu[k] - r[k] * w[1]) / w[0]);
            sv = [0, 1, 2].map(|k| (nv[k] - r[k] * w[2]) / w[0]);
        }
        [cross(su, sv), su, sv, [size_u, size_v, 0.0]]
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
            let d = self.coordinate(p, k, vertex.u, vertex.v);
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
    use crate::surface::eval::evaluate_surfaces;
    use crate::surface::{Net, Surface, SurfaceKind, SurfaceSampling};
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
        let twin = evaluate_surfaces_twin(&jobs, Derivatives::Second, true, 1000 * 4 * 7).unwrap();
        let mut poles = 0;
        for (s, ((table, plan), got)) in jobs.iter().zip(&twin).enumerate() {
            let want = evaluate_surfaces(table, plan, Derivatives::Second, true).unwrap();
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

    /// Positions of 3-D surfaces under a 4 KiB binding limit: a plane's floats would allow 341
    /// vertices a dispatch, whose 16-byte records (5,456 bytes) are over the limit; the split
    /// keeps both bindings within it (the twin asserts so on every dispatch) and changes no
    /// value.
    #[test]
    fn every_binding_of_every_dispatch_fits_the_limit() {
        let surfaces = surfaces();
        let tables: Vec<PatchTable> = surfaces.iter().map(|(s, _)| s.fit()).collect();
        let plans: Vec<SurfacePlan> = tables
            .iter()
            .zip(&surfaces)
            .map(|(t, (_, sampling))| SurfacePlan::new(t, sampling).unwrap())
            .collect();
        let jobs: Vec<_> = tables.iter().zip(&plans).collect();
        let small = evaluate_surfaces_twin(&jobs, Derivatives::None, false, 4096).unwrap();
        let whole = evaluate_surfaces_twin(&jobs, Derivatives::None, false, 1 << 30).unwrap();
        for (s, (a, b)) in small.iter().zip(&whole).enumerate() {
            assert_eq!(a.points, b.points, "surface {s}");
        }
    }
}
