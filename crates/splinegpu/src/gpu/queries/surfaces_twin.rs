//! The CPU twin of `shaders/surface_queries.wgsl`: both entry points in f32, line by line (same
//! names, same loop order, same f32 arithmetic in the same order), run over every query of
//! every dispatch that [`GpuContext::closest_on_surfaces`](crate::GpuContext::closest_on_surfaces)
//! and [`GpuContext::ray_hits`](crate::GpuContext::ray_hits) would make, so that the packing and
//! the kernel's searches are tested against the contract's promise without a GPU.

use crate::gpu::queries::abi::{
    ClosestParams, GpuNode, NO_HIT, PATCH_STACK, SURFACE_MAX_LEVEL, SURFACE_POLISH_STEPS,
    SurfaceAnswer, TREE_STACK,
};
use crate::gpu::queries::pack::PackedNets;
use crate::gpu::queries::surfaces::{Entry, RAY_WIDTH, closest_on_surfaces_with, ray_hits_with};
use crate::query::{QueryError, RayHit, SurfaceIndex, SurfacePoint};

/// `GpuContext::closest_on_surfaces` as the kernel computes it, in dispatches of at most
/// `budget` queries.
pub(crate) fn closest_on_surfaces_twin(
    index: &SurfaceIndex<'_>,
    queries: &[f64],
    budget: usize,
) -> Result<Vec<SurfacePoint>, QueryError> {
    index.check_queries(queries)?;
    let packed = PackedNets::new(index)?;
    closest_on_surfaces_with(index, &packed, queries, budget, &mut |frame| {
        Ok(Kernel::new(&packed, frame, Entry::Closest).run(Entry::Closest))
    })
}

/// `GpuContext::ray_hits` as the kernel computes it, in dispatches of at most `budget` rays.
pub(crate) fn ray_hits_twin(
    index: &SurfaceIndex<'_>,
    rays: &[f64],
    budget: usize,
) -> Result<Vec<Option<RayHit>>, QueryError> {
    let checked = index.check_rays(rays)?;
    let packed = PackedNets::new(index)?;
    ray_hits_with(index, &packed, &checked, budget, &mut |frame| {
        Ok(Kernel::new(&packed, frame, Entry::Rays).run(Entry::Rays))
    })
}

const PRODUCT: [f32; 16] = [
    1.0, 0.5, 0.2, 0.05, 0.5, 0.6, 0.45, 0.2, 0.2, 0.45, 0.6, 0.5, 0.05, 0.2, 0.5, 1.0,
];

struct Kernel<'a> {
    params: ClosestParams,
    nodes: &'a [GpuNode],
    node_boxes: &'a [f32],
    item_boxes: &'a [f32],
    nets: &'a [f32],
    queries: &'a [f32],
}

type Vec4 = [f32; 4];
type Net = [f32; 16];

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

fn on_interval(c: Vec4, lo: f32, hi: f32) -> Vec4 {
    let mut d = c;
    if hi < 1.0 {
        let p01 = lerp(d[0], d[1], hi);
        let p12 = lerp(d[1], d[2], hi);
        let p23 = lerp(d[2], d[3], hi);
        let p012 = lerp(p01, p12, hi);
        let p123 = lerp(p12, p23, hi);
        d = [d[0], p01, p012, lerp(p012, p123, hi)];
    }
    if lo > 0.0 {
        let t = lo / hi;
        let p01 = lerp(d[0], d[1], t);
        let p12 = lerp(d[1], d[2], t);
        let p23 = lerp(d[2], d[3], t);
        let p012 = lerp(p01, p12, t);
        let p123 = lerp(p12, p23, t);
        d = [lerp(p012, p123, t), p123, p23, d[3]];
    }
    d
}

fn net_on(n: Net, r: Vec4) -> Net {
    let mut m = n;
    for j in 0..4 {
        let c = on_interval([m[j], m[4 + j], m[8 + j], m[12 + j]], r[0], r[1]);
        (m[j], m[4 + j], m[8 + j], m[12 + j]) = (c[0], c[1], c[2], c[3]);
    }
    for i in 0..4 {
        let c = on_interval(
            [m[4 * i], m[4 * i + 1], m[4 * i + 2], m[4 * i + 3]],
            r[2],
            r[3],
        );
        m[4 * i..4 * i + 4].copy_from_slice(&c);
    }
    m
}

fn rectangle(code: u32) -> Vec4 {
    let level = (31 - code.leading_zeros()) / 2;
    let rest = code - (1 << (2 * level));
    let scale = 1.0 / (1u32 << level) as f32;
    let iu = (rest >> level) as f32;
    let iv = (rest & ((1 << level) - 1)) as f32;
    [
        iu * scale,
        (iu + 1.0) * scale,
        iv * scale,
        (iv + 1.0) * scale,
    ]
}

fn child(code: u32, cu: u32, cv: u32) -> u32 {
    let level = (31 - code.leading_zeros()) / 2;
    let rest = code - (1 << (2 * level));
    let iu = 2 * (rest >> level) + cu;
    let iv = 2 * (rest & ((1 << level) - 1)) + cv;
    let next = level + 1;
    (1 << (2 * next)) + (iu << next) + iv
}

fn level(code: u32) -> u32 {
    (31 - code.leading_zeros()) / 2
}

fn basis(t: f32) -> [Vec4; 3] {
    let s = 1.0 - t;
    [
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
        [6.0 * s, 6.0 * t - 12.0 * s, 6.0 * s - 12.0 * t, 6.0 * t],
    ]
}

fn dot4(a: Vec4, b: Vec4) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

fn dot3(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// (value, d/du, d/dv, d2/du2, d2/dudv, d2/dv2).
type Jet = [f32; 6];

fn jet(n: &Net, u: f32, v: f32) -> Jet {
    let bu = basis(u);
    let bv = basis(v);
    let mut rows = [[0.0f32; 3]; 4];
    for (i, row) in rows.iter_mut().enumerate() {
        let c = [n[4 * i], n[4 * i + 1], n[4 * i + 2], n[4 * i + 3]];
        *row = [dot4(bv[0], c), dot4(bv[1], c), dot4(bv[2], c)];
    }
    let column = |k: usize| [rows[0][k], rows[1][k], rows[2][k], rows[3][k]];
    let (r0, r1, r2) = (column(0), column(1), column(2));
    [
        dot4(bu[0], r0),
        dot4(bu[1], r0),
        dot4(bu[0], r1),
        dot4(bu[2], r0),
        dot4(bu[1], r1),
        dot4(bu[0], r2),
    ]
}

fn add_square(x: &Net, sum: &mut [f32; 49]) {
    for a in 0..4 {
        for b in 0..4 {
            let xab = x[4 * a + b];
            for c in 0..4 {
                for d in 0..4 {
                    let m = PRODUCT[4 * a + c] * PRODUCT[4 * b + d];
                    sum[7 * (a + c) + b + d] += m * xab * x[4 * c + d];
                }
            }
        }
    }
}

struct Best {
    value: f32,
    slot: u32,
    u: f32,
    v: f32,
    cut: f32,
}

/// A ray in the frame.
struct Ray {
    o: [f32; 3],
    d: [f32; 3],
    a: [f32; 3],
    b: [f32; 3],
    pad: f32,
}

impl<'a> Kernel<'a> {
    fn new(packed: &'a PackedNets, queries: &'a [f32], entry: Entry) -> Self {
        let dim = packed.tree.dim;
        Self {
            params: ClosestParams::new(
                queries.len() / entry.width(dim),
                dim,
                0,
                packed.tree.nodes.len(),
            ),
            nodes: &packed.tree.nodes,
            node_boxes: &packed.tree.node_boxes,
            item_boxes: &packed.tree.item_boxes,
            nets: &packed.nets,
            queries,
        }
    }

    fn run(&self, entry: Entry) -> Vec<SurfaceAnswer> {
        (0..self.params.query_count)
            .map(|i| match entry {
                Entry::Closest => self.closest(i),
                Entry::Rays => self.rays(i),
            })
            .collect()
    }

    fn weights(&self, base: usize) -> Net {
        std::array::from_fn(|ij| self.nets[base + ij])
    }

    fn patch_jet(&self, slot: u32, u: f32, v: f32, k: usize) -> Jet {
        let dim = self.params.dim as usize;
        let base = slot as usize * (16 + 16 * dim);
        let w = self.weights(base);
        let x: Net = std::array::from_fn(|ij| w[ij] * self.nets[base + 16 + ij * dim + k]);
        let n = jet(&x, u, v);
        let d = jet(&w, u, v);
        let p = n[0] / d[0];
        let pu = (n[1] - p * d[1]) / d[0];
        let pv = (n[2] - p * d[2]) / d[0];
        let puu = (n[3] - 2.0 * pu * d[1] - p * d[3]) / d[0];
        let pvv = (n[5] - 2.0 * pv * d[2] - p * d[5]) / d[0];
        let puv = (n[4] - pu * d[2] - pv * d[1] - p * d[4]) / d[0];
        [p, pu, pv, puu, puv, pvv]
    }

    fn box_distance2(&self, node: bool, base: usize, q: usize) -> f32 {
        let dim = self.params.dim as usize;
        let boxes = if node {
            self.node_boxes
        } else {
            self.item_boxes
        };
        let mut d2 = 0.0f32;
        for k in 0..dim {
            let (lo, hi) = (boxes[base + k], boxes[base + dim + k]);
            let x = self.queries[q + k];
            let gap = (lo - x).max(x - hi).max(0.0);
            d2 += gap * gap;
        }
        d2
    }

    fn improve(&self, best: &mut Best, d2: f32, slot: u32, (u, v): (f32, f32)) {
        if d2 < best.value {
            (best.value, best.slot, best.u, best.v) = (d2, slot, u, v);
            let d = d2.sqrt();
            let near = (d - (self.params.tolerance + self.params.relative * d)).max(0.0);
            best.cut = near * near;
        }
    }

    fn closest_on_patch(&self, slot: u32, q: usize, best: &mut Best) {
        let dim = self.params.dim as usize;
        let base = slot as usize * (16 + 16 * dim);
        let w = self.weights(base);
        let mut codes = [0u32; PATCH_STACK];
        let mut parents = [0.0f32; PATCH_STACK];
        codes[0] = 1;
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let code = codes[top];
            if parents[top] >= best.cut {
                continue;
            }
            let r = rectangle(code);
            let (mut num, mut den) = ([0.0f32; 49], [0.0f32; 49]);
            add_square(&net_on(w, r), &mut den);
            for k in 0..dim {
                let x = self.queries[q + k];
                let e: Net =
                    std::array::from_fn(|ij| w[ij] * (self.nets[base + 16 + ij * dim + k] - x));
                add_square(&net_on(e, r), &mut num);
            }
            let mut least = num[0] / den[0];
            for m in 1..49 {
                least = least.min(num[m] / den[m]);
            }
            let corners = [
                num[0] / den[0],
                num[6] / den[6],
                num[42] / den[42],
                num[48] / den[48],
            ];
            self.improve(best, corners[0], slot, (r[0], r[2]));
            self.improve(best, corners[1], slot, (r[0], r[3]));
            self.improve(best, corners[2], slot, (r[1], r[2]));
            self.improve(best, corners[3], slot, (r[1], r[3]));
            if least >= best.cut || level(code) >= SURFACE_MAX_LEVEL {
                continue;
            }
            let mut nearest = 0;
            for c in 1..4 {
                if corners[c] < corners[nearest] {
                    nearest = c;
                }
            }
            for c in 0..4 {
                let which = ((nearest + 1 + c) % 4) as u32;
                codes[top] = child(code, which / 2, which % 2);
                parents[top] = least;
                top += 1;
            }
        }
    }

    fn polish_closest(&self, best: &mut Best, q: usize) {
        let dim = self.params.dim as usize;
        for _ in 0..SURFACE_POLISH_STEPS {
            let (mut g, mut h) = ([0.0f32; 2], [0.0f32; 3]);
            for k in 0..dim {
                let p = self.patch_jet(best.slot, best.u, best.v, k);
                let e = p[0] - self.queries[q + k];
                g = [g[0] + e * p[1], g[1] + e * p[2]];
                h = [
                    h[0] + (p[1] * p[1] + e * p[3]),
                    h[1] + (p[1] * p[2] + e * p[4]),
                    h[2] + (p[2] * p[2] + e * p[5]),
                ];
            }
            let det = h[0] * h[2] - h[1] * h[1];
            if det.is_nan() || det <= 0.0 || h[0].is_nan() || h[0] <= 0.0 {
                return;
            }
            let u = best.u - (h[2] * g[0] - h[1] * g[1]) / det;
            let v = best.v - (h[0] * g[1] - h[1] * g[0]) / det;
            if !((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)) {
                return;
            }
            let mut d2 = 0.0f32;
            for k in 0..dim {
                let e = self.patch_jet(best.slot, u, v, k)[0] - self.queries[q + k];
                d2 += e * e;
            }
            if d2.is_nan() || d2 >= best.value {
                return;
            }
            (best.u, best.v, best.value) = (u, v, d2);
        }
    }

    fn closest(&self, index: u32) -> SurfaceAnswer {
        let dim = self.params.dim as usize;
        let q = index as usize * dim;
        let mut best = Best {
            value: 3.0e38,
            slot: 0,
            u: 0.0,
            v: 0.0,
            cut: 3.0e38,
        };
        let mut stack_nodes = [0u32; TREE_STACK];
        let mut stack_d2 = [0.0f32; TREE_STACK];
        stack_d2[0] = self.box_distance2(true, 0, q);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            if stack_d2[top] >= best.cut {
                continue;
            }
            let node = self.nodes[stack_nodes[top] as usize];
            if node.leaf != 0 {
                for slot in node.first..node.second {
                    if self.box_distance2(false, slot as usize * 2 * dim, q) < best.cut {
                        self.closest_on_patch(slot, q, &mut best);
                    }
                }
                continue;
            }
            let a = self.box_distance2(true, node.first as usize * 2 * dim, q);
            let b = self.box_distance2(true, node.second as usize * 2 * dim, q);
            if a <= b {
                (stack_nodes[top], stack_d2[top]) = (node.second, b);
                (stack_nodes[top + 1], stack_d2[top + 1]) = (node.first, a);
            } else {
                (stack_nodes[top], stack_d2[top]) = (node.first, a);
                (stack_nodes[top + 1], stack_d2[top + 1]) = (node.second, b);
            }
            top += 2;
        }
        self.polish_closest(&mut best, q);
        SurfaceAnswer {
            slot: best.slot,
            u: best.u,
            v: best.v,
            value: best.value,
        }
    }

    fn entry(&self, node: bool, base: usize, ray: &Ray) -> f32 {
        let (mut enter, mut leave) = (0.0f32, 3.0e38f32);
        let boxes = if node {
            self.node_boxes
        } else {
            self.item_boxes
        };
        for k in 0..3 {
            let (lo, hi) = (boxes[base + k], boxes[base + 3 + k]);
            if ray.d[k] == 0.0 {
                if ray.o[k] < lo || ray.o[k] > hi {
                    return -1.0;
                }
                continue;
            }
            let x = (lo - ray.o[k]) / ray.d[k];
            let y = (hi - ray.o[k]) / ray.d[k];
            enter = enter.max(x.min(y));
            leave = leave.min(x.max(y));
        }
        if enter <= leave { enter } else { -1.0 }
    }

    fn hit_on_patch(&self, slot: u32, ray: &Ray, best: &mut Best) {
        let base = slot as usize * 64;
        let w = self.weights(base);
        let (mut ea, mut eb, mut es) = ([0.0f32; 16], [0.0f32; 16], [0.0f32; 16]);
        for ij in 0..16 {
            let at = base + 16 + 3 * ij;
            let x = [
                self.nets[at] - ray.o[0],
                self.nets[at + 1] - ray.o[1],
                self.nets[at + 2] - ray.o[2],
            ];
            ea[ij] = w[ij] * dot3(ray.a, x);
            eb[ij] = w[ij] * dot3(ray.b, x);
            es[ij] = w[ij] * dot3(ray.d, x);
        }
        let mut codes = [0u32; PATCH_STACK];
        codes[0] = 1;
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let code = codes[top];
            let r = rectangle(code);
            let (wr, ar, br, sr) = (net_on(w, r), net_on(ea, r), net_on(eb, r), net_on(es, r));
            let (mut alo, mut ahi) = (3.0e38f32, -3.0e38f32);
            let (mut blo, mut bhi) = (3.0e38f32, -3.0e38f32);
            let (mut slo, mut shi) = (3.0e38f32, -3.0e38f32);
            for ij in 0..16 {
                let (a, b, s) = (ar[ij] / wr[ij], br[ij] / wr[ij], sr[ij] / wr[ij]);
                (alo, ahi) = (alo.min(a), ahi.max(a));
                (blo, bhi) = (blo.min(b), bhi.max(b));
                (slo, shi) = (slo.min(s), shi.max(s));
            }
            let pad = ray.pad;
            if alo > pad || ahi < -pad || blo > pad || bhi < -pad || slo > best.value || shi < -pad
            {
                continue;
            }
            let small = ahi - alo <= 0.5 * pad && bhi - blo <= 0.5 * pad && shi - slo <= 0.5 * pad;
            if small || level(code) >= SURFACE_MAX_LEVEL {
                let hit = (0.5 * (slo + shi)).max(0.0);
                if hit < best.value {
                    (best.value, best.slot) = (hit, slot);
                    (best.u, best.v) = (0.5 * (r[0] + r[1]), 0.5 * (r[2] + r[3]));
                }
                continue;
            }
            let corners = [
                sr[0] / wr[0],
                sr[3] / wr[3],
                sr[12] / wr[12],
                sr[15] / wr[15],
            ];
            let mut nearest = 0;
            for c in 1..4 {
                if corners[c] < corners[nearest] {
                    nearest = c;
                }
            }
            for c in 0..4 {
                let which = ((nearest + 1 + c) % 4) as u32;
                codes[top] = child(code, which / 2, which % 2);
                top += 1;
            }
        }
    }

    fn point(&self, slot: u32, u: f32, v: f32) -> [Jet; 3] {
        [0, 1, 2].map(|k| self.patch_jet(slot, u, v, k))
    }

    fn polish_hit(&self, best: &mut Best, ray: &Ray) {
        let (mut u, mut v) = (best.u, best.v);
        let mut xyz = self.point(best.slot, u, v);
        let minus_o = |j: &[Jet; 3]| [j[0][0] - ray.o[0], j[1][0] - ray.o[1], j[2][0] - ray.o[2]];
        let mut p = minus_o(&xyz);
        let mut f = [dot3(ray.a, p), dot3(ray.b, p)];
        for _ in 0..SURFACE_POLISH_STEPS {
            let su = [xyz[0][1], xyz[1][1], xyz[2][1]];
            let sv = [xyz[0][2], xyz[1][2], xyz[2][2]];
            let j = [
                dot3(ray.a, su),
                dot3(ray.a, sv),
                dot3(ray.b, su),
                dot3(ray.b, sv),
            ];
            let det = j[0] * j[3] - j[1] * j[2];
            if det.is_nan() || det == 0.0 {
                break;
            }
            let nu = u - (j[3] * f[0] - j[1] * f[1]) / det;
            let nv = v - (j[0] * f[1] - j[2] * f[0]) / det;
            if !((0.0..=1.0).contains(&nu) && (0.0..=1.0).contains(&nv)) {
                break;
            }
            let next = self.point(best.slot, nu, nv);
            let np = minus_o(&next);
            let g = [dot3(ray.a, np), dot3(ray.b, np)];
            let length = |x: [f32; 2]| (x[0] * x[0] + x[1] * x[1]).sqrt();
            if length(g).is_nan() || length(g) >= length(f) {
                break;
            }
            (u, v, xyz, p, f) = (nu, nv, next, np, g);
        }
        (best.u, best.v) = (u, v);
        best.value = dot3(ray.d, p).max(0.0);
    }

    fn rays(&self, index: u32) -> SurfaceAnswer {
        let at = RAY_WIDTH * index as usize;
        let q = |k: usize| self.queries[at + k];
        let o = [q(0), q(1), q(2)];
        let far = o[0].abs().max(o[1].abs()).max(o[2].abs());
        let ray = Ray {
            o,
            d: [q(3), q(4), q(5)],
            a: [q(6), q(7), q(8)],
            b: [q(9), q(10), q(11)],
            pad: self.params.tolerance * (1.0 + far),
        };
        let mut best = Best {
            value: 1.0e6 * (1.0 + far),
            slot: NO_HIT,
            u: 0.0,
            v: 0.0,
            cut: 0.0,
        };
        let mut stack_nodes = [0u32; TREE_STACK];
        let mut stack_s = [0.0f32; TREE_STACK];
        let root = self.entry(true, 0, &ray);
        let mut top = 0;
        if root >= 0.0 {
            (stack_nodes[0], stack_s[0]) = (0, root);
            top = 1;
        }
        while top > 0 {
            top -= 1;
            if stack_s[top] > best.value {
                continue;
            }
            let node = self.nodes[stack_nodes[top] as usize];
            if node.leaf != 0 {
                for slot in node.first..node.second {
                    let s = self.entry(false, slot as usize * 6, &ray);
                    if s >= 0.0 && s <= best.value {
                        self.hit_on_patch(slot, &ray, &mut best);
                    }
                }
                continue;
            }
            let a = self.entry(true, node.first as usize * 6, &ray);
            let b = self.entry(true, node.second as usize * 6, &ray);
            if b >= 0.0 && (a < 0.0 || b >= a) {
                (stack_nodes[top], stack_s[top]) = (node.second, b);
                top += 1;
            }
            if a >= 0.0 {
                (stack_nodes[top], stack_s[top]) = (node.first, a);
                top += 1;
            }
            if b >= 0.0 && a >= 0.0 && b < a {
                (stack_nodes[top], stack_s[top]) = (node.second, b);
                top += 1;
            }
        }
        if best.slot != NO_HIT {
            self.polish_hit(&mut best, &ray);
        }
        SurfaceAnswer {
            slot: best.slot,
            u: best.u,
            v: best.v,
            value: best.value,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The twin against the certified answers (tests/it/query/surface_checks.rs), and
    /// dispatches of 7 queries giving what one gives.
    #[test]
    fn the_twin_gives_the_certified_answers_within_the_bound() {
        crate::surface_checks::check_against_the_certified_answers(
            &|index, queries| closest_on_surfaces_twin(index, queries, 1 << 24).unwrap(),
            &|index, rays| ray_hits_twin(index, rays, 1 << 24).unwrap(),
        );
        let tables = [crate::shapes::teapot().fit()];
        let index = SurfaceIndex::new(&tables).unwrap();
        let queries: Vec<f64> = (0..30).map(|i| f64::from(i % 7) - 2.0).collect();
        assert_eq!(
            closest_on_surfaces_twin(&index, &queries, 7).unwrap(),
            closest_on_surfaces_twin(&index, &queries, 1 << 24).unwrap()
        );
        let rays: Vec<f64> = (0..60)
            .map(|i| {
                if i % 6 == 5 {
                    -1.0
                } else {
                    f64::from(i % 4) * 0.5
                }
            })
            .collect();
        assert_eq!(
            ray_hits_twin(&index, &rays, 7).unwrap(),
            ray_hits_twin(&index, &rays, 1 << 24).unwrap()
        );
    }
}
