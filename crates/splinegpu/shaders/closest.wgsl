// Closest points of a set of curves to many query points, one query per invocation, in f32
// (docs/queries.md, "On the GPU"; Rust side: src/gpu/queries/).
//
// The host packs the box tree of a `CurveIndex` (its nodes, the nodes' and items' boxes) and
// each item's piece of a segment as its rational Bezier control points Q_0..Q_3 and weights
// w_0..w_3 (weights 1 on a polynomial segment), all in the index's frame: (x - c) / E, c the
// centre of the curves' box and E their extent, so that every table holds numbers of about 1.
//
// An invocation walks the tree nearer box first and leaves every box whose squared distance is
// at least `cut` = (max(d - eps, 0))^2, d the best distance so far and eps the search's slack:
// nothing in that box can be nearer than d - eps. On a piece left, the same exclusion runs on
// dyadic sub-intervals [a, b] of its parameter: with e_i = w_i (Q_i - q) and the interval's
// control points (de Casteljau), the squared distance is
//
//   g(u) = |sum_i B_i(u) e_i|^2 / (sum_i B_i(u) w_i)^2 = N(u) / W(u),
//
// N and W of degree 6, whose Bernstein coefficients on [a, b] (products of the cubics') give
// g >= min_m N_m / W_m there (every W_m > 0), and g(a) = N_0 / W_0, g(b) = N_6 / W_6 exactly.
// A sub-interval whose bound reaches `cut` is left, the others halved down to MAX_LEVEL; the
// best end seen, polished by Newton steps that lower the distance, is the answer. A child's bound is at least its parent's (its coefficients are
// convex combinations of the parent's), so the stack keeps the parent's bound and leaves a
// child without computing it when the best has moved past it.

const WG_SIZE: u32 = 64u;
// Halvings of a piece's parameter at most: 2^-20 of a piece is far below f32's resolution of
// the distance near a minimum (the distance is flat there to first order).
const MAX_LEVEL: u32 = 20u;
// Entries of the tree walk's stack: a depth-first walk pushing two children holds at most the
// tree's depth plus one (a tree of 2^32 items has depth 31).
const TREE_STACK: u32 = 40u;
// Entries of a piece's stack: MAX_LEVEL + 1 at most, the same way.
const PIECE_STACK: u32 = 24u;
// Newton steps polishing the answer (each kept only where it lowers the distance).
const POLISH_STEPS: u32 = 4u;

struct ClosestParams {
    query_count: u32,
    dim: u32,
    row_width: u32,
    node_count: u32,
    // The search's slack: eps = tolerance + relative * d (in the index's frame).
    tolerance: f32,
    relative: f32,
    _padding: vec2<u32>,
}

// A node: two children, or (leaf = 1) the range [first, second) of slots it holds.
struct GpuNode {
    first: u32,
    second: u32,
    leaf: u32,
    _padding: u32,
}

// Per query: the slot of the piece holding the answer, its local parameter on the piece and
// the squared distance (in the index's frame).
struct ClosestAnswer {
    slot: u32,
    u: f32,
    distance2: f32,
    _padding: u32,
}

@group(0) @binding(0) var<uniform> params: ClosestParams;
@group(0) @binding(1) var<storage, read> nodes: array<GpuNode>;
// Per node, lo then hi (2 D values).
@group(0) @binding(2) var<storage, read> node_boxes: array<f32>;
// Per slot, its piece's box (2 D values).
@group(0) @binding(3) var<storage, read> item_boxes: array<f32>;
// Per slot, w_0..w_3 then Q_0..Q_3 (4 + 4 D values).
@group(0) @binding(4) var<storage, read> controls: array<f32>;
// Per query, D values (in the index's frame).
@group(0) @binding(5) var<storage, read> queries: array<f32>;
@group(0) @binding(6) var<storage, read_write> answers: array<ClosestAnswer>;
// Per query, the closest point (D values, in the index's frame).
@group(0) @binding(7) var<storage, read_write> points: array<f32>;

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + t * (b - a);
}

// The control points of [0, t] of the cubic with control points c.
fn split_left(c: vec4<f32>, t: f32) -> vec4<f32> {
    let p01 = lerp(c.x, c.y, t);
    let p12 = lerp(c.y, c.z, t);
    let p23 = lerp(c.z, c.w, t);
    let p012 = lerp(p01, p12, t);
    let p123 = lerp(p12, p23, t);
    return vec4<f32>(c.x, p01, p012, lerp(p012, p123, t));
}

// The control points of [t, 1] of the cubic with control points c.
fn split_right(c: vec4<f32>, t: f32) -> vec4<f32> {
    let p01 = lerp(c.x, c.y, t);
    let p12 = lerp(c.y, c.z, t);
    let p23 = lerp(c.z, c.w, t);
    let p012 = lerp(p01, p12, t);
    let p123 = lerp(p12, p23, t);
    return vec4<f32>(lerp(p012, p123, t), p123, p23, c.w);
}

// The control points of [a, b] of the cubic with control points c.
fn on_interval(c: vec4<f32>, a: f32, b: f32) -> vec4<f32> {
    var d = c;
    if (b < 1.0) {
        d = split_left(d, b);
    }
    if (a > 0.0) {
        d = split_right(d, a / b);
    }
    return d;
}

// The Bernstein coefficients of x^2 (x a cubic's), degree 6: m = 0..3 in `low`, 4..6 in
// `high.xyz`.
struct Sextic {
    low: vec4<f32>,
    high: vec4<f32>,
}

fn square(x: vec4<f32>) -> Sextic {
    return Sextic(
        vec4<f32>(
            x.x * x.x,
            x.x * x.y,
            (2.0 * x.x * x.z + 3.0 * x.y * x.y) / 5.0,
            (x.x * x.w + 9.0 * x.y * x.z) / 10.0,
        ),
        vec4<f32>(
            (2.0 * x.y * x.w + 3.0 * x.z * x.z) / 5.0,
            x.z * x.w,
            x.w * x.w,
            0.0,
        ),
    );
}

// The dyadic interval [k / 2^level, (k + 1) / 2^level] coded as 2^level + k.
fn interval(code: u32) -> vec2<f32> {
    let level = firstLeadingBit(code);
    let scale = 1.0 / f32(1u << level);
    let k = f32(code - (1u << level));
    return vec2<f32>(k * scale, (k + 1.0) * scale);
}

// (lower bound of g on [a, b], g(a), g(b)) for the piece in `slot` and the query at `q`.
fn bounds(slot: u32, q: u32, ab: vec2<f32>) -> vec3<f32> {
    let dim = params.dim;
    let base = slot * (4u + 4u * dim);
    let w = vec4<f32>(controls[base], controls[base + 1u], controls[base + 2u], controls[base + 3u]);
    let den = square(on_interval(w, ab.x, ab.y));
    var num = Sextic(vec4<f32>(0.0), vec4<f32>(0.0));
    for (var k = 0u; k < dim; k++) {
        let at = base + 4u + k;
        let x = queries[q + k];
        let e = vec4<f32>(
            w.x * (controls[at] - x),
            w.y * (controls[at + dim] - x),
            w.z * (controls[at + 2u * dim] - x),
            w.w * (controls[at + 3u * dim] - x),
        );
        let s = square(on_interval(e, ab.x, ab.y));
        num.low += s.low;
        num.high += s.high;
    }
    let low = num.low / den.low;
    let high = num.high / den.high;
    let least = min(min(min(low.x, low.y), min(low.z, low.w)), min(min(high.x, high.y), high.z));
    return vec3<f32>(least, low.x, high.z);
}

// The squared distance from the query at `q` to the box at `base` of `node_boxes` (`node`) or
// `item_boxes`.
fn box_distance2(node: bool, base: u32, q: u32) -> f32 {
    let dim = params.dim;
    var d2 = 0.0;
    for (var k = 0u; k < dim; k++) {
        var lo: f32;
        var hi: f32;
        if (node) {
            lo = node_boxes[base + k];
            hi = node_boxes[base + dim + k];
        } else {
            lo = item_boxes[base + k];
            hi = item_boxes[base + dim + k];
        }
        let x = queries[q + k];
        let gap = max(max(lo - x, x - hi), 0.0);
        d2 += gap * gap;
    }
    return d2;
}

// The best answer so far, and the cut it gives.
struct Best {
    d2: f32,
    slot: u32,
    u: f32,
    cut: f32,
}

fn improve(best: ptr<function, Best>, d2: f32, slot: u32, u: f32) {
    if (d2 < (*best).d2) {
        (*best).d2 = d2;
        (*best).slot = slot;
        (*best).u = u;
        let d = sqrt(d2);
        let near = max(d - (params.tolerance + params.relative * d), 0.0);
        (*best).cut = near * near;
    }
}

// The piece in `slot` searched for anything nearer than the best by more than the slack.
fn search_piece(slot: u32, q: u32, best: ptr<function, Best>) {
    var codes: array<u32, PIECE_STACK>;
    var parents: array<f32, PIECE_STACK>;
    codes[0] = 1u;
    parents[0] = 0.0;
    var top = 1u;
    while (top > 0u) {
        top -= 1u;
        let code = codes[top];
        if (parents[top] >= (*best).cut) {
            continue;
        }
        let ab = interval(code);
        let b = bounds(slot, q, ab);
        improve(best, b.y, slot, ab.x);
        improve(best, b.z, slot, ab.y);
        if (b.x >= (*best).cut || firstLeadingBit(code) >= MAX_LEVEL) {
            continue;
        }
        // The half on the nearer end's side is searched first (pushed last).
        let left = 2u * code;
        if (b.y <= b.z) {
            codes[top] = left + 1u;
            codes[top + 1u] = left;
        } else {
            codes[top] = left;
            codes[top + 1u] = left + 1u;
        }
        parents[top] = b.x;
        parents[top + 1u] = b.x;
        top += 2u;
    }
}

// (value, first, second derivative) at u of the cubic with control points c.
fn jet(c: vec4<f32>, u: f32) -> vec3<f32> {
    let v = 1.0 - u;
    let value = v * v * v * c.x + 3.0 * u * v * v * c.y + 3.0 * u * u * v * c.z + u * u * u * c.w;
    let first = 3.0 * (v * v * (c.y - c.x) + 2.0 * u * v * (c.z - c.y) + u * u * (c.w - c.z));
    let second = 6.0 * (v * (c.z - 2.0 * c.y + c.x) + u * (c.w - 2.0 * c.z + c.y));
    return vec3<f32>(value, first, second);
}

// (P_k, P_k', P_k'') at u of the piece in `slot`: with N = sum B_i w_i Q_i and W = sum B_i w_i,
// P = N / W, P' = (N' - P W') / W, P'' = (N'' - 2 P' W' - P W'') / W.
fn piece_jet(slot: u32, u: f32, k: u32) -> vec3<f32> {
    let dim = params.dim;
    let base = slot * (4u + 4u * dim);
    let w = vec4<f32>(controls[base], controls[base + 1u], controls[base + 2u], controls[base + 3u]);
    let at = base + 4u + k;
    let x = vec4<f32>(
        w.x * controls[at],
        w.y * controls[at + dim],
        w.z * controls[at + 2u * dim],
        w.w * controls[at + 3u * dim],
    );
    let n = jet(x, u);
    let d = jet(w, u);
    let p = n.x / d.x;
    let p1 = (n.y - p * d.y) / d.x;
    let p2 = (n.z - 2.0 * p1 * d.y - p * d.z) / d.x;
    return vec3<f32>(p, p1, p2);
}

// The best point polished by Newton on g'(u) / 2 = (P - q) . P' within its piece, each step kept
// only where it lowers g: the dyadic search stops once nothing can be nearer by the slack, which
// leaves the point up to sqrt(slack) along a curve that is flat in distance there.
fn polish(best: ptr<function, Best>, q: u32) {
    let dim = params.dim;
    for (var step = 0u; step < POLISH_STEPS; step++) {
        var slope = 0.0;
        var curvature = 0.0;
        for (var k = 0u; k < dim; k++) {
            let p = piece_jet((*best).slot, (*best).u, k);
            let gap = p.x - queries[q + k];
            slope += gap * p.y;
            curvature += p.y * p.y + gap * p.z;
        }
        if (!(curvature > 0.0)) {
            return;
        }
        let next = clamp((*best).u - slope / curvature, 0.0, 1.0);
        var d2 = 0.0;
        for (var k = 0u; k < dim; k++) {
            let gap = piece_jet((*best).slot, next, k).x - queries[q + k];
            d2 += gap * gap;
        }
        if (!(d2 < (*best).d2)) {
            return;
        }
        (*best).u = next;
        (*best).d2 = d2;
    }
}

@compute @workgroup_size(WG_SIZE)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = id.y * params.row_width + id.x;
    if (index >= params.query_count) {
        return;
    }
    let dim = params.dim;
    let q = index * dim;
    var best = Best(3.0e38, 0u, 0.0, 3.0e38);
    var stack_nodes: array<u32, TREE_STACK>;
    var stack_d2: array<f32, TREE_STACK>;
    stack_nodes[0] = 0u;
    stack_d2[0] = box_distance2(true, 0u, q);
    var top = 1u;
    while (top > 0u) {
        top -= 1u;
        if (stack_d2[top] >= best.cut) {
            continue;
        }
        let node = nodes[stack_nodes[top]];
        if (node.leaf != 0u) {
            for (var slot = node.first; slot < node.second; slot++) {
                if (box_distance2(false, slot * 2u * dim, q) < best.cut) {
                    search_piece(slot, q, &best);
                }
            }
            continue;
        }
        let a = box_distance2(true, node.first * 2u * dim, q);
        let b = box_distance2(true, node.second * 2u * dim, q);
        // The nearer child is popped first.
        if (a <= b) {
            stack_nodes[top] = node.second;
            stack_d2[top] = b;
            stack_nodes[top + 1u] = node.first;
            stack_d2[top + 1u] = a;
        } else {
            stack_nodes[top] = node.first;
            stack_d2[top] = a;
            stack_nodes[top + 1u] = node.second;
            stack_d2[top + 1u] = b;
        }
        top += 2u;
    }
    polish(&best, q);
    answers[index] = ClosestAnswer(best.slot, best.u, best.d2, 0u);
    for (var k = 0u; k < dim; k++) {
        points[index * dim + k] = piece_jet(best.slot, best.u, k).x;
    }
}
