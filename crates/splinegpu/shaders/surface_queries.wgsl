// Closest points on surfaces (entry point `closest`) and the first hits of rays (`rays`), one
// query per invocation, in f32 (docs/queries.md, "On the GPU"; Rust side:
// src/gpu/queries/surfaces.rs).
//
// The host packs a `SurfaceIndex`'s box tree and each patch as its rational Bernstein net:
// weights w_ij (divided by the largest) and control points Q_ij, i along u and j along v,
// all in the index's frame (x - c) / E. An invocation walks the tree (nearest box first for
// closest points, first entry along the ray for rays) and searches each patch it cannot
// exclude over dyadic rectangles of its parameters, each with its own net (de Casteljau
// along u, then along v):
//
// - closest: |S - q|^2 = N / W with N = sum_k (sum B_ij w_ij (Q_ijk - q_k))^2 and
//   W = (sum B_ij w_ij)^2, of degree 6 in u and in v; on a rectangle, |S - q|^2 >= the least
//   ratio N_mn / W_mn of their Bernstein coefficients, and the four corners' ratios are the
//   exact values there. A rectangle whose bound reaches the cut (max(d - eps, 0))^2 is left.
// - rays: in the ray's frame (a, b across it, s along it), a rectangle is left where the
//   a or b coordinates of its projected control points all lie beyond the slack on one side
//   (no point of it on the ray), or its s range lies beyond the best hit or behind the
//   origin; a rectangle small within the slack (or at the deepest level) is a hit at its
//   centre.
// Each answer is then polished by Newton steps kept only where they improve it.

const WG_SIZE: u32 = 64u;
// Halvings of a patch's parameters at most: a rectangle code 4^level + (iu 2^level + iv) fits
// a u32 up to level 15.
const MAX_LEVEL: u32 = 15u;
// The tree walk's stack (as the curves' kernel).
const TREE_STACK: u32 = 40u;
// A patch's stack: a depth-first search pushing four children holds at most 3 MAX_LEVEL + 1.
const PATCH_STACK: u32 = 48u;
// Newton steps polishing an answer.
const POLISH_STEPS: u32 = 6u;
// No hit.
const NONE: u32 = 0xffffffffu;

// Products of Bernstein polynomials: B_a B_c = PRODUCT[4 a + c] B_{a + c} (degree 3 by 3 to 6).
const PRODUCT = array<f32, 16>(
    1.0, 0.5, 0.2, 0.05,
    0.5, 0.6, 0.45, 0.2,
    0.2, 0.45, 0.6, 0.5,
    0.05, 0.2, 0.5, 1.0,
);

struct SurfaceQueryParams {
    query_count: u32,
    dim: u32,
    row_width: u32,
    node_count: u32,
    // The search's slack: eps = tolerance + relative * d (closest), the rays' pad is
    // tolerance (1 + |o|inf).
    tolerance: f32,
    relative: f32,
    _padding: vec2<u32>,
}

struct GpuNode {
    first: u32,
    second: u32,
    leaf: u32,
    _padding: u32,
}

// Per query: the slot of the patch holding the answer (NONE: no hit), its local (u, v), and
// the squared distance (closest) or the distance along the ray (rays), in the frame.
struct SurfaceAnswer {
    slot: u32,
    u: f32,
    v: f32,
    value: f32,
}

@group(0) @binding(0) var<uniform> params: SurfaceQueryParams;
@group(0) @binding(1) var<storage, read> nodes: array<GpuNode>;
@group(0) @binding(2) var<storage, read> node_boxes: array<f32>;
@group(0) @binding(3) var<storage, read> item_boxes: array<f32>;
// Per slot: w_00..w_33 (16 values), then Q_ij (D values each), ij = 4 i + j.
@group(0) @binding(4) var<storage, read> nets: array<f32>;
// Closest: D values a query. Rays: o, d, a, b (12 values; d, a, b unit vectors).
@group(0) @binding(5) var<storage, read> queries: array<f32>;
@group(0) @binding(6) var<storage, read_write> answers: array<SurfaceAnswer>;

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + t * (b - a);
}

// The control points of [lo, hi] of the cubic with control points c (de Casteljau).
fn on_interval(c: vec4<f32>, lo: f32, hi: f32) -> vec4<f32> {
    var d = c;
    if (hi < 1.0) {
        let p01 = lerp(d.x, d.y, hi);
        let p12 = lerp(d.y, d.z, hi);
        let p23 = lerp(d.z, d.w, hi);
        let p012 = lerp(p01, p12, hi);
        let p123 = lerp(p12, p23, hi);
        d = vec4<f32>(d.x, p01, p012, lerp(p012, p123, hi));
    }
    if (lo > 0.0) {
        let t = lo / hi;
        let p01 = lerp(d.x, d.y, t);
        let p12 = lerp(d.y, d.z, t);
        let p23 = lerp(d.z, d.w, t);
        let p012 = lerp(p01, p12, t);
        let p123 = lerp(p12, p23, t);
        d = vec4<f32>(lerp(p012, p123, t), p123, p23, d.w);
    }
    return d;
}

// A net (ij = 4 i + j) restricted to the rectangle r = (u0, u1, v0, v1).
fn net_on(n: array<f32, 16>, r: vec4<f32>) -> array<f32, 16> {
    var m = n;
    for (var j = 0u; j < 4u; j++) {
        let c = on_interval(vec4<f32>(m[j], m[4u + j], m[8u + j], m[12u + j]), r.x, r.y);
        m[j] = c.x;
        m[4u + j] = c.y;
        m[8u + j] = c.z;
        m[12u + j] = c.w;
    }
    for (var i = 0u; i < 4u; i++) {
        let c = on_interval(vec4<f32>(m[4u * i], m[4u * i + 1u], m[4u * i + 2u], m[4u * i + 3u]), r.z, r.w);
        m[4u * i] = c.x;
        m[4u * i + 1u] = c.y;
        m[4u * i + 2u] = c.z;
        m[4u * i + 3u] = c.w;
    }
    return m;
}

// The rectangle of the code 4^level + (iu 2^level + iv): (u0, u1, v0, v1).
fn rectangle(code: u32) -> vec4<f32> {
    let level = firstLeadingBit(code) / 2u;
    let rest = code - (1u << (2u * level));
    let scale = 1.0 / f32(1u << level);
    let iu = f32(rest >> level);
    let iv = f32(rest & ((1u << level) - 1u));
    return vec4<f32>(iu * scale, (iu + 1.0) * scale, iv * scale, (iv + 1.0) * scale);
}

// The code of child (cu, cv) of the rectangle `code`.
fn child(code: u32, cu: u32, cv: u32) -> u32 {
    let level = firstLeadingBit(code) / 2u;
    let rest = code - (1u << (2u * level));
    let iu = 2u * (rest >> level) + cu;
    let iv = 2u * (rest & ((1u << level) - 1u)) + cv;
    let next = level + 1u;
    return (1u << (2u * next)) + (iu << next) + iv;
}

fn weights(base: u32) -> array<f32, 16> {
    var w: array<f32, 16>;
    for (var ij = 0u; ij < 16u; ij++) {
        w[ij] = nets[base + ij];
    }
    return w;
}

// (value, d/du, d/dv, d2/du2, d2/dudv, d2/dv2) at (u, v) of the bicubic with net n.
struct Jet {
    value: f32,
    du: f32,
    dv: f32,
    duu: f32,
    duv: f32,
    dvv: f32,
}

// The cubic Bernstein basis at t, its first and second derivatives.
fn basis(t: f32) -> array<vec4<f32>, 3> {
    let s = 1.0 - t;
    return array<vec4<f32>, 3>(
        vec4<f32>(s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t),
        vec4<f32>(-3.0 * s * s, 3.0 * s * s - 6.0 * t * s, 6.0 * t * s - 3.0 * t * t, 3.0 * t * t),
        vec4<f32>(6.0 * s, 6.0 * t - 12.0 * s, 6.0 * s - 12.0 * t, 6.0 * t),
    );
}

fn jet(n: array<f32, 16>, u: f32, v: f32) -> Jet {
    let bu = basis(u);
    let bv = basis(v);
    // Per row i (fixed u index): the row's value and v-derivatives.
    var rows: array<vec3<f32>, 4>;
    for (var i = 0u; i < 4u; i++) {
        let c = vec4<f32>(n[4u * i], n[4u * i + 1u], n[4u * i + 2u], n[4u * i + 3u]);
        rows[i] = vec3<f32>(dot(bv[0], c), dot(bv[1], c), dot(bv[2], c));
    }
    let r0 = vec4<f32>(rows[0].x, rows[1].x, rows[2].x, rows[3].x);
    let r1 = vec4<f32>(rows[0].y, rows[1].y, rows[2].y, rows[3].y);
    let r2 = vec4<f32>(rows[0].z, rows[1].z, rows[2].z, rows[3].z);
    return Jet(dot(bu[0], r0), dot(bu[1], r0), dot(bu[0], r1), dot(bu[2], r0), dot(bu[1], r1), dot(bu[0], r2));
}

// Coordinate k of the patch in `slot` at (u, v), with its derivatives: P = N / W and the
// quotient rule for each derivative.
fn patch_jet(slot: u32, u: f32, v: f32, k: u32) -> Jet {
    let dim = params.dim;
    let base = slot * (16u + 16u * dim);
    let w = weights(base);
    var x: array<f32, 16>;
    for (var ij = 0u; ij < 16u; ij++) {
        x[ij] = w[ij] * nets[base + 16u + ij * dim + k];
    }
    let n = jet(x, u, v);
    let d = jet(w, u, v);
    let p = n.value / d.value;
    let pu = (n.du - p * d.du) / d.value;
    let pv = (n.dv - p * d.dv) / d.value;
    let puu = (n.duu - 2.0 * pu * d.du - p * d.duu) / d.value;
    let pvv = (n.dvv - 2.0 * pv * d.dv - p * d.dvv) / d.value;
    let puv = (n.duv - pu * d.dv - pv * d.du - p * d.duv) / d.value;
    return Jet(p, pu, pv, puu, puv, pvv);
}

// The Bernstein coefficients of x^2 (x a bicubic's net), degree 6 by 6 (7 mu + mv), added to
// `sum`.
fn add_square(x: array<f32, 16>, sum: ptr<function, array<f32, 49>>) {
    for (var a = 0u; a < 4u; a++) {
        for (var b = 0u; b < 4u; b++) {
            let xab = x[4u * a + b];
            for (var c = 0u; c < 4u; c++) {
                for (var d = 0u; d < 4u; d++) {
                    let m = PRODUCT[4u * a + c] * PRODUCT[4u * b + d];
                    let at = 7u * (a + c) + b + d;
                    (*sum)[at] += m * xab * x[4u * c + d];
                }
            }
        }
    }
}

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

struct Best {
    value: f32,
    slot: u32,
    u: f32,
    v: f32,
    cut: f32,
}

fn improve(best: ptr<function, Best>, d2: f32, slot: u32, u: f32, v: f32) {
    if (d2 < (*best).value) {
        (*best).value = d2;
        (*best).slot = slot;
        (*best).u = u;
        (*best).v = v;
        let d = sqrt(d2);
        let near = max(d - (params.tolerance + params.relative * d), 0.0);
        (*best).cut = near * near;
    }
}

// The patch in `slot` searched for anything nearer than the best by more than the slack.
fn closest_on_patch(slot: u32, q: u32, best: ptr<function, Best>) {
    let dim = params.dim;
    let base = slot * (16u + 16u * dim);
    let w = weights(base);
    var codes: array<u32, PATCH_STACK>;
    var parents: array<f32, PATCH_STACK>;
    codes[0] = 1u;
    parents[0] = 0.0;
    var top = 1u;
    while (top > 0u) {
        top -= 1u;
        let code = codes[top];
        if (parents[top] >= (*best).cut) {
            continue;
        }
        let r = rectangle(code);
        var num: array<f32, 49>;
        var den: array<f32, 49>;
        add_square(net_on(w, r), &den);
        for (var k = 0u; k < dim; k++) {
            let x = queries[q + k];
            var e: array<f32, 16>;
            for (var ij = 0u; ij < 16u; ij++) {
                e[ij] = w[ij] * (nets[base + 16u + ij * dim + k] - x);
            }
            add_square(net_on(e, r), &num);
        }
        var least = num[0] / den[0];
        for (var m = 1u; m < 49u; m++) {
            least = min(least, num[m] / den[m]);
        }
        // The corners' exact values: (u0, v0), (u0, v1), (u1, v0), (u1, v1).
        let corners = vec4<f32>(num[0] / den[0], num[6] / den[6], num[42] / den[42], num[48] / den[48]);
        improve(best, corners.x, slot, r.x, r.z);
        improve(best, corners.y, slot, r.x, r.w);
        improve(best, corners.z, slot, r.y, r.z);
        improve(best, corners.w, slot, r.y, r.w);
        if (least >= (*best).cut || firstLeadingBit(code) / 2u >= MAX_LEVEL) {
            continue;
        }
        // The quarter holding the nearest corner is searched first (pushed last).
        var nearest = 0u;
        for (var c = 1u; c < 4u; c++) {
            if (corners[c] < corners[nearest]) {
                nearest = c;
            }
        }
        for (var c = 0u; c < 4u; c++) {
            let which = (nearest + 1u + c) % 4u;
            codes[top] = child(code, which / 2u, which % 2u);
            parents[top] = least;
            top += 1u;
        }
    }
}

// The best point polished by Newton on the gradient of |S - q|^2 / 2, ((S - q).S_u,
// (S - q).S_v), each step kept only where it stays on the patch and lowers the distance.
fn polish_closest(best: ptr<function, Best>, q: u32) {
    let dim = params.dim;
    for (var step = 0u; step < POLISH_STEPS; step++) {
        var g = vec2<f32>(0.0);
        var h = vec3<f32>(0.0);
        for (var k = 0u; k < dim; k++) {
            let p = patch_jet((*best).slot, (*best).u, (*best).v, k);
            let e = p.value - queries[q + k];
            g += vec2<f32>(e * p.du, e * p.dv);
            h += vec3<f32>(p.du * p.du + e * p.duu, p.du * p.dv + e * p.duv, p.dv * p.dv + e * p.dvv);
        }
        let det = h.x * h.z - h.y * h.y;
        if (!(det > 0.0) || !(h.x > 0.0)) {
            return;
        }
        let u = (*best).u - (h.z * g.x - h.y * g.y) / det;
        let v = (*best).v - (h.x * g.y - h.y * g.x) / det;
        if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0)) {
            return;
        }
        var d2 = 0.0;
        for (var k = 0u; k < dim; k++) {
            let e = patch_jet((*best).slot, u, v, k).value - queries[q + k];
            d2 += e * e;
        }
        if (!(d2 < (*best).value)) {
            return;
        }
        (*best).u = u;
        (*best).v = v;
        (*best).value = d2;
    }
}

@compute @workgroup_size(WG_SIZE)
fn closest(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = id.y * params.row_width + id.x;
    if (index >= params.query_count) {
        return;
    }
    let dim = params.dim;
    let q = index * dim;
    var best = Best(3.0e38, 0u, 0.0, 0.0, 3.0e38);
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
                    closest_on_patch(slot, q, &best);
                }
            }
            continue;
        }
        let a = box_distance2(true, node.first * 2u * dim, q);
        let b = box_distance2(true, node.second * 2u * dim, q);
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
    polish_closest(&best, q);
    answers[index] = SurfaceAnswer(best.slot, best.u, best.v, best.value);
}

// A ray: its origin, direction and the two unit vectors across it, in the frame.
struct Ray {
    o: vec3<f32>,
    d: vec3<f32>,
    a: vec3<f32>,
    b: vec3<f32>,
    pad: f32,
}

// Where the ray enters the box at `base` (s >= 0), or -1 where it misses it.
fn entry(node: bool, base: u32, ray: Ray) -> f32 {
    var enter = 0.0;
    var leave = 3.0e38;
    for (var k = 0u; k < 3u; k++) {
        var lo: f32;
        var hi: f32;
        if (node) {
            lo = node_boxes[base + k];
            hi = node_boxes[base + 3u + k];
        } else {
            lo = item_boxes[base + k];
            hi = item_boxes[base + 3u + k];
        }
        if (ray.d[k] == 0.0) {
            if (ray.o[k] < lo || ray.o[k] > hi) {
                return -1.0;
            }
            continue;
        }
        let x = (lo - ray.o[k]) / ray.d[k];
        let y = (hi - ray.o[k]) / ray.d[k];
        enter = max(enter, min(x, y));
        leave = min(leave, max(x, y));
    }
    if (enter <= leave) {
        return enter;
    }
    return -1.0;
}

// The patch in `slot` searched for a hit nearer along the ray than the best.
fn hit_on_patch(slot: u32, ray: Ray, best: ptr<function, Best>) {
    let base = slot * 64u;
    let w = weights(base);
    var ea: array<f32, 16>;
    var eb: array<f32, 16>;
    var es: array<f32, 16>;
    for (var ij = 0u; ij < 16u; ij++) {
        let at = base + 16u + 3u * ij;
        let x = vec3<f32>(nets[at], nets[at + 1u], nets[at + 2u]) - ray.o;
        ea[ij] = w[ij] * dot(ray.a, x);
        eb[ij] = w[ij] * dot(ray.b, x);
        es[ij] = w[ij] * dot(ray.d, x);
    }
    var codes: array<u32, PATCH_STACK>;
    codes[0] = 1u;
    var top = 1u;
    while (top > 0u) {
        top -= 1u;
        let code = codes[top];
        let r = rectangle(code);
        let wr = net_on(w, r);
        let ar = net_on(ea, r);
        let br = net_on(eb, r);
        let sr = net_on(es, r);
        var alo = 3.0e38;
        var ahi = -3.0e38;
        var blo = 3.0e38;
        var bhi = -3.0e38;
        var slo = 3.0e38;
        var shi = -3.0e38;
        for (var ij = 0u; ij < 16u; ij++) {
            let a = ar[ij] / wr[ij];
            let b = br[ij] / wr[ij];
            let s = sr[ij] / wr[ij];
            alo = min(alo, a);
            ahi = max(ahi, a);
            blo = min(blo, b);
            bhi = max(bhi, b);
            slo = min(slo, s);
            shi = max(shi, s);
        }
        let pad = ray.pad;
        if (alo > pad || ahi < -pad || blo > pad || bhi < -pad || slo > (*best).value || shi < -pad) {
            continue;
        }
        let small = ahi - alo <= 0.5 * pad && bhi - blo <= 0.5 * pad && shi - slo <= 0.5 * pad;
        if (small || firstLeadingBit(code) / 2u >= MAX_LEVEL) {
            let hit = max(0.5 * (slo + shi), 0.0);
            if (hit < (*best).value) {
                (*best).value = hit;
                (*best).slot = slot;
                (*best).u = 0.5 * (r.x + r.y);
                (*best).v = 0.5 * (r.z + r.w);
            }
            continue;
        }
        // The quarter holding the corner nearest along the ray is searched first.
        let corners = vec4<f32>(sr[0] / wr[0], sr[3] / wr[3], sr[12] / wr[12], sr[15] / wr[15]);
        var nearest = 0u;
        for (var c = 1u; c < 4u; c++) {
            if (corners[c] < corners[nearest]) {
                nearest = c;
            }
        }
        for (var c = 0u; c < 4u; c++) {
            let which = (nearest + 1u + c) % 4u;
            codes[top] = child(code, which / 2u, which % 2u);
            top += 1u;
        }
    }
}

// The hit's (u, v) polished by Newton on (a, b) = 0 (the point's offsets across the ray), each
// step kept only where it stays on the patch and brings the point nearer the ray; its distance
// along the ray then taken at the polished point.
fn polish_hit(best: ptr<function, Best>, ray: Ray) {
    var u = (*best).u;
    var v = (*best).v;
    var x = patch_jet((*best).slot, u, v, 0u);
    var y = patch_jet((*best).slot, u, v, 1u);
    var z = patch_jet((*best).slot, u, v, 2u);
    var p = vec3<f32>(x.value, y.value, z.value) - ray.o;
    var f = vec2<f32>(dot(ray.a, p), dot(ray.b, p));
    for (var step = 0u; step < POLISH_STEPS; step++) {
        let su = vec3<f32>(x.du, y.du, z.du);
        let sv = vec3<f32>(x.dv, y.dv, z.dv);
        let j = vec4<f32>(dot(ray.a, su), dot(ray.a, sv), dot(ray.b, su), dot(ray.b, sv));
        let det = j.x * j.w - j.y * j.z;
        if (!(det != 0.0)) {
            break;
        }
        let nu = u - (j.w * f.x - j.y * f.y) / det;
        let nv = v - (j.x * f.y - j.z * f.x) / det;
        if (!(nu >= 0.0 && nu <= 1.0 && nv >= 0.0 && nv <= 1.0)) {
            break;
        }
        let nx = patch_jet((*best).slot, nu, nv, 0u);
        let ny = patch_jet((*best).slot, nu, nv, 1u);
        let nz = patch_jet((*best).slot, nu, nv, 2u);
        let np = vec3<f32>(nx.value, ny.value, nz.value) - ray.o;
        let g = vec2<f32>(dot(ray.a, np), dot(ray.b, np));
        if (!(length(g) < length(f))) {
            break;
        }
        u = nu;
        v = nv;
        x = nx;
        y = ny;
        z = nz;
        p = np;
        f = g;
    }
    (*best).u = u;
    (*best).v = v;
    (*best).value = max(dot(ray.d, p), 0.0);
}

@compute @workgroup_size(WG_SIZE)
fn rays(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = id.y * params.row_width + id.x;
    if (index >= params.query_count) {
        return;
    }
    let at = 12u * index;
    let o = vec3<f32>(queries[at], queries[at + 1u], queries[at + 2u]);
    let far = max(max(abs(o.x), abs(o.y)), abs(o.z));
    let ray = Ray(
        o,
        vec3<f32>(queries[at + 3u], queries[at + 4u], queries[at + 5u]),
        vec3<f32>(queries[at + 6u], queries[at + 7u], queries[at + 8u]),
        vec3<f32>(queries[at + 9u], queries[at + 10u], queries[at + 11u]),
        params.tolerance * (1.0 + far),
    );
    // Nothing beyond s = 1e6 (E + |o|inf) is a hit.
    var best = Best(1.0e6 * (1.0 + far), NONE, 0.0, 0.0, 0.0);
    var stack_nodes: array<u32, TREE_STACK>;
    var stack_s: array<f32, TREE_STACK>;
    let root = entry(true, 0u, ray);
    var top = 0u;
    if (root >= 0.0) {
        stack_nodes[0] = 0u;
        stack_s[0] = root;
        top = 1u;
    }
    while (top > 0u) {
        top -= 1u;
        if (stack_s[top] > best.value) {
            continue;
        }
        let node = nodes[stack_nodes[top]];
        if (node.leaf != 0u) {
            for (var slot = node.first; slot < node.second; slot++) {
                let s = entry(false, slot * 6u, ray);
                if (s >= 0.0 && s <= best.value) {
                    hit_on_patch(slot, ray, &best);
                }
            }
            continue;
        }
        let a = entry(true, node.first * 6u, ray);
        let b = entry(true, node.second * 6u, ray);
        // The child the ray enters first is popped first; a missed child is not pushed.
        if (b >= 0.0 && (a < 0.0 || b >= a)) {
            stack_nodes[top] = node.second;
            stack_s[top] = b;
            top += 1u;
        }
        if (a >= 0.0) {
            stack_nodes[top] = node.first;
            stack_s[top] = a;
            top += 1u;
        }
        if (b >= 0.0 && a >= 0.0 && b < a) {
            stack_nodes[top] = node.second;
            stack_s[top] = b;
            top += 1u;
        }
    }
    if (best.slot != NONE) {
        polish_hit(&best, ray);
    }
    answers[index] = SurfaceAnswer(best.slot, best.u, best.v, best.value);
}
