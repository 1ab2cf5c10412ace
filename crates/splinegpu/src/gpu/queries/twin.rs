//! The CPU twin of `shaders/closest.wgsl`: the kernel in f32, line by line (same names, same
//! loop order, same f32 arithmetic in the same order), run over every query of every dispatch
//! that [`GpuContext::closest_points`](crate::GpuContext::closest_points) would make, so that
//! the packing and the kernel's search are tested against the contract's promise without a
//! GPU.

use crate::gpu::queries::abi::{
    ClosestAnswer, ClosestParams, GpuNode, MAX_LEVEL, PIECE_STACK, POLISH_STEPS, TREE_STACK,
};
use crate::gpu::queries::dispatch::closest_with;
use crate::gpu::queries::pack::PackedIndex;
use crate::query::{ClosestPoints, CurveIndex, QueryError};

/// [`GpuContext::closest_points`](crate::GpuContext::closest_points) as the kernel computes
/// it, in dispatches of at most `budget` queries.
pub(crate) fn closest_points_twin(
    index: &CurveIndex<'_>,
    queries: &[f64],
    budget: usize,
) -> Result<ClosestPoints<f32>, QueryError> {
    let count = index.check_queries(queries)?;
    let packed = PackedIndex::new(index)?;
    closest_with(
        index,
        &packed,
        queries,
        count,
        budget,
        &mut |frame, answers, points| {
            let params =
                ClosestParams::new(answers.len(), packed.tree.dim, 0, packed.tree.nodes.len());
            let kernel = Kernel {
                params,
                nodes: &packed.tree.nodes,
                node_boxes: &packed.tree.node_boxes,
                item_boxes: &packed.tree.item_boxes,
                controls: &packed.controls,
                queries: frame,
            };
            for (i, answer) in answers.iter_mut().enumerate() {
                kernel.main(i as u32, answer, points);
            }
            Ok(())
        },
    )
}

struct Kernel<'a> {
    params: ClosestParams,
    nodes: &'a [GpuNode],
    node_boxes: &'a [f32],
    item_boxes: &'a [f32],
    controls: &'a [f32],
    queries: &'a [f32],
}

type Vec4 = [f32; 4];

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

fn split_left(c: Vec4, t: f32) -> Vec4 {
    let p01 = lerp(c[0], c[1], t);
    let p12 = lerp(c[1], c[2], t);
    let p23 = lerp(c[2], c[3], t);
    let p012 = lerp(p01, p12, t);
    let p123 = lerp(p12, p23, t);
    [c[0], p01, p012, lerp(p012, p123, t)]
}

fn split_right(c: Vec4, t: f32) -> Vec4 {
    let p01 = lerp(c[0], c[1], t);
    let p12 = lerp(c[1], c[2], t);
    let p23 = lerp(c[2], c[3], t);
    let p012 = lerp(p01, p12, t);
    let p123 = lerp(p12, p23, t);
    [lerp(p012, p123, t), p123, p23, c[3]]
}

fn on_interval(c: Vec4, a: f32, b: f32) -> Vec4 {
    let mut d = c;
    if b < 1.0 {
        d = split_left(d, b);
    }
    if a > 0.0 {
        d = split_right(d, a / b);
    }
    d
}

/// The Bernstein coefficients of x², degree 6 (`Sextic` in the kernel, m = 0..6).
fn square(x: Vec4) -> [f32; 7] {
    [
        x[0] * x[0],
        x[0] * x[1],
        (2.0 * x[0] * x[2] + 3.0 * x[1] * x[1]) / 5.0,
        (x[0] * x[3] + 9.0 * x[1] * x[2]) / 10.0,
        (2.0 * x[1] * x[3] + 3.0 * x[2] * x[2]) / 5.0,
        x[2] * x[3],
        x[3] * x[3],
    ]
}

fn jet(c: Vec4, u: f32) -> [f32; 3] {
    let v = 1.0 - u;
    let value =
        v * v * v * c[0] + 3.0 * u * v * v * c[1] + 3.0 * u * u * v * c[2] + u * u * u * c[3];
    let first = 3.0 * (v * v * (c[1] - c[0]) + 2.0 * u * v * (c[2] - c[1]) + u * u * (c[3] - c[2]));
    let second = 6.0 * (v * (c[2] - 2.0 * c[1] + c[0]) + u * (c[3] - 2.0 * c[2] + c[1]));
    [value, first, second]
}

fn interval(code: u32) -> (f32, f32) {
    let level = 31 - code.leading_zeros();
    let scale = 1.0 / (1u32 << level) as f32;
    let k = (code - (1u32 << level)) as f32;
    (k * scale, (k + 1.0) * scale)
}

struct Best {
    d2: f32,
    slot: u32,
    u: f32,
    cut: f32,
}

impl Kernel<'_> {
    fn bounds(&self, slot: u32, q: usize, (a, b): (f32, f32)) -> [f32; 3] {
        let dim = self.params.dim as usize;
        let base = slot as usize * (4 + 4 * dim);
        let c = self.controls;
        let w = [c[base], c[base + 1], c[base + 2], c[base + 3]];
        let den = square(on_interval(w, a, b));
        let mut num = [0.0f32; 7];
        for k in 0..dim {
            let at = base + 4 + k;
            let x = self.queries[q + k];
            let e = [
                w[0] * (c[at] - x),
                w[1] * (c[at + dim] - x),
                w[2] * (c[at + 2 * dim] - x),
                w[3] * (c[at + 3 * dim] - x),
            ];
            let s = square(on_interval(e, a, b));
            for m in 0..7 {
                num[m] += s[m];
            }
        }
        let ratio: [f32; 7] = std::array::from_fn(|m| num[m] / den[m]);
        let least = ratio.iter().copied().fold(f32::INFINITY, f32::min);
        [least, ratio[0], ratio[6]]
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

    fn improve(&self, best: &mut Best, d2: f32, slot: u32, u: f32) {
        if d2 < best.d2 {
            best.d2 = d2;
            best.slot = slot;
            best.u = u;
            let d = d2.sqrt();
            let near = (d - (self.params.tolerance + self.params.relative * d)).max(0.0);
            best.cut = near * near;
        }
    }

    fn search_piece(&self, slot: u32, q: usize, best: &mut Best) {
        let mut codes = [0u32; PIECE_STACK];
        let mut parents = [0.0f32; PIECE_STACK];
        codes[0] = 1;
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let code = codes[top];
            if parents[top] >= best.cut {
                continue;
            }
            let ab = interval(code);
            let b = self.bounds(slot, q, ab);
            self.improve(best, b[1], slot, ab.0);
            self.improve(best, b[2], slot, ab.1);
            if b[0] >= best.cut || 31 - code.leading_zeros() >= MAX_LEVEL {
                continue;
            }
            let left = 2 * code;
            if b[1] <= b[2] {
                codes[top] = left + 1;
                codes[top + 1] = left;
            } else {
                codes[top] = left;
                codes[top + 1] = left + 1;
            }
            parents[top] = b[0];
            parents[top + 1] = b[0];
            top += 2;
        }
    }

    fn piece_jet(&self, slot: u32, u: f32, k: usize) -> [f32; 3] {
        let dim = self.params.dim as usize;
        let base = slot as usize * (4 + 4 * dim);
        let c = self.controls;
        let w = [c[base], c[base + 1], c[base + 2], c[base + 3]];
        let at = base + 4 + k;
        let x = [
            w[0] * c[at],
            w[1] * c[at + dim],
            w[2] * c[at + 2 * dim],
            w[3] * c[at + 3 * dim],
        ];
        let n = jet(x, u);
        let d = jet(w, u);
        let p = n[0] / d[0];
        let p1 = (n[1] - p * d[1]) / d[0];
        let p2 = (n[2] - 2.0 * p1 * d[1] - p * d[2]) / d[0];
        [p, p1, p2]
    }

    fn polish(&self, best: &mut Best, q: usize) {
        let dim = self.params.dim as usize;
        for _ in 0..POLISH_STEPS {
            let (mut slope, mut curvature) = (0.0f32, 0.0f32);
            for k in 0..dim {
                let p = self.piece_jet(best.slot, best.u, k);
                let gap = p[0] - self.queries[q + k];
                slope += gap * p[1];
                curvature += p[1] * p[1] + gap * p[2];
            }
            if curvature.is_nan() || curvature <= 0.0 {
                return;
            }
            let next = (best.u - slope / curvature).clamp(0.0, 1.0);
            let mut d2 = 0.0f32;
            for k in 0..dim {
                let gap = self.piece_jet(best.slot, next, k)[0] - self.queries[q + k];
                d2 += gap * gap;
            }
            if d2.is_nan() || d2 >= best.d2 {
                return;
            }
            best.u = next;
            best.d2 = d2;
        }
    }

    fn main(&self, index: u32, answer: &mut ClosestAnswer, points: &mut [f32]) {
        let dim = self.params.dim as usize;
        let q = index as usize * dim;
        let mut best = Best {
            d2: 3.0e38,
            slot: 0,
            u: 0.0,
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
                        self.search_piece(slot, q, &mut best);
                    }
                }
                continue;
            }
            let a = self.box_distance2(true, node.first as usize * 2 * dim, q);
            let b = self.box_distance2(true, node.second as usize * 2 * dim, q);
            if a <= b {
                stack_nodes[top] = node.second;
                stack_d2[top] = b;
                stack_nodes[top + 1] = node.first;
                stack_d2[top + 1] = a;
            } else {
                stack_nodes[top] = node.first;
                stack_d2[top] = a;
                stack_nodes[top + 1] = node.second;
                stack_d2[top + 1] = b;
            }
            top += 2;
        }
        self.polish(&mut best, q);
        *answer = ClosestAnswer {
            slot: best.slot,
            u: best.u,
            distance2: best.d2,
            _padding: 0,
        };
        for k in 0..dim {
            points[index as usize * dim + k] = self.piece_jet(best.slot, best.u, k)[0];
        }
    }
}

#[cfg(test)]
#[path = "twin_tests.rs"]
mod tests;
