// Makes tubes', ribbons' and strokes' vertices and unit normals from curves whose width (or
// radius) is a fourth coordinate of the same spline (src/geometry/widen.rs): `main` one
// invocation per tube or ribbon, `strokes` one per stroke vertex.
// Rust twins of the structs: src/gpu/geometry/abi.rs. CPU twin, line by line in f32 (same
// names, loop order and arithmetic): src/gpu/geometry/twin.rs. The f64 reference this follows:
// src/geometry/frames.rs (the frames) and src/geometry/mesh.rs (rings, strips, normals).
//
// Why one invocation per curve: a curve's frames are a chain (each normal carried from the one
// before by a double reflection, and a closed curve's closing angle known only once the chain
// has gone around), so an invocation walks its curve's cross-sections in order, carrying the
// frame, and writes each ring as it passes it; a closed curve is walked twice, the first time
// for its closing angle alone. Nothing is stored between cross-sections but the last frame.
//
// Why one invocation per stroke vertex: a stroke carries no frame, so each of its vertices is
// C + h v at its own place, h half the width there and v an offset the host planned in f64
// (the side's unit normal, a join's or round cap's direction, a miter's reach along its
// bisector, a square cap's corner: src/geometry/stroke.rs, `build`); neighbouring invocations
// write neighbouring vertices.

// Rust twin: gpu::geometry::abi::GeometryParams.
struct GeometryParams {
    // Curves in this dispatch.
    curve_count: u32,
    // Invocations per row of the 2-D dispatch (workgroups in x times WG_SIZE).
    row_width: u32,
    // The float the curves' `out` count from in the bound output.
    out_base: u32,
    // Stroke vertices in this dispatch, and invocations per row of the `strokes` dispatch.
    stroke_vertex_count: u32,
    stroke_row_width: u32,
    _padding0: u32,
    _padding1: u32,
    _padding2: u32,
}

// Rust twin: gpu::geometry::abi::GpuMeshCurve. Its segments' blocks start at vec4 `first_block`,
// `block_vec4s` each: a, b, c, d (x, y, z and the width; d's x, y, z relative to the curve's
// origin, o_hi + o_lo in f64), then (1/Δ, W's a, b, c) and (W's d, 0, 0, 0) for a rational
// segment: P(u) = d + ((a u + b) u + c) u, or d + ((a u + b) u + c) u / W(u).
struct GpuMeshCurve {
    first_block: u32,
    block_vec4s: u32,
    rational: u32,
    first_section: u32,
    sections: u32,
    // 0: a tube, 1: a ribbon, 2: a stroke (its curve record holds its table and origin; its
    // vertices are GpuStrokeVertex records, `sections` 0).
    shape: u32,
    sides: u32,
    _padding2: u32,
    // 1: a closed curve (its frames closed up).
    closed: u32,
    // Its first vertex, counted from params.out_base in 6 floats (position, normal) a vertex.
    first_vertex: u32,
    _padding0: u32,
    _padding1: u32,
    origin_hi: vec4<f32>,
    origin_lo: vec4<f32>,
    // N_0, made on the host in f64 from `up` or the axis least aligned with T_0.
    n0: vec4<f32>,
    // The tangent a cross-section without one takes before any has one.
    t_first: vec4<f32>,
}

// Rust twin: gpu::geometry::abi::GpuSection. A cross-section: its segment (of its curve), local
// u, (closed curves) its arc length over the curve's, s_j / L, and what is made there: its
// ring's (or pair's) first vertex of the curve's, and a cap's vertex facing -T (cap_sign -1, a
// piece's start) or T (+1, its end). NONE where nothing is: a closed curve's last
// cross-section (its ring is the first's), a place that only carries a dashed curve's frame.
struct GpuSection {
    segment: u32,
    u: f32,
    along: f32,
    first_vertex: u32,
    cap_vertex: u32,
    cap_sign: i32,
    _padding0: u32,
    _padding1: u32,
}

// Rust twin: gpu::geometry::abi::GpuStrokeVertex. Vertex `vertex` of curve `curve`'s mesh is
// C + h v at (segment, u), C relative to the curve's origin, h half the width there.
struct GpuStrokeVertex {
    curve: u32,
    vertex: u32,
    segment: u32,
    u: f32,
    v: vec2<f32>,
}

@group(0) @binding(0) var<uniform> params: GeometryParams;
@group(0) @binding(1) var<storage, read> curves: array<GpuMeshCurve>;
@group(0) @binding(2) var<storage, read> blocks: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> sections: array<GpuSection>;
@group(0) @binding(4) var<storage, read_write> out: array<f32>;
@group(0) @binding(5) var<storage, read> stroke_vertices: array<GpuStrokeVertex>;

// Rust twin: gpu::geometry::abi::GEOMETRY_WG_SIZE.
const WG_SIZE: u32 = 64u;

// Rust twin: gpu::geometry::abi::NONE.
const NONE: u32 = 0xffffffffu;

const TAU: f32 = 6.283185307179586;

// What a cross-section is made from: the position relative to the curve's origin, C' and C''
// (in t), the width (clamped at 0) and its derivative (0 where clamped).
struct Place {
    position: vec3<f32>,
    d1: vec3<f32>,
    d2: vec3<f32>,
    width: f32,
    width_d1: f32,
}

fn place(curve: GpuMeshCurve, segment: u32, u: f32) -> Place {
    let at = curve.first_block + segment * curve.block_vec4s;
    let a = blocks[at];
    let b = blocks[at + 1u];
    let c = blocks[at + 2u];
    let d = blocks[at + 3u];
    let e = blocks[at + 4u];
    let inv = e.x;
    var value = d + ((a * u + b) * u + c) * u;
    var first = ((3.0 * a * u + 2.0 * b) * u + c) * inv;
    var second = (6.0 * a * u + 2.0 * b) * (inv * inv);
    if curve.rational == 1u {
        let wd = blocks[at + 5u].x;
        let w = ((e.y * u + e.z) * u + e.w) * u + wd;
        let w1 = (3.0 * e.y * u + 2.0 * e.z) * u + e.w;
        let w2 = 6.0 * e.y * u + 2.0 * e.z;
        let r = ((a * u + b) * u + c) * u / w;
        let r1 = (((3.0 * a * u + 2.0 * b) * u + c) - r * w1) / w;
        let r2 = ((6.0 * a * u + 2.0 * b) - 2.0 * r1 * w1 - r * w2) / w;
        value = d + r;
        first = r1 * inv;
        second = r2 * (inv * inv);
    }
    let clamped = value.w < 0.0;
    return Place(value.xyz, first.xyz, second.xyz, max(value.w, 0.0), select(first.w, 0.0, clamped));
}

// v / |v|, or 0 where |v| is 0 (or not finite).
fn unit_or_zero(v: vec3<f32>) -> vec3<f32> {
    let length = sqrt(dot(v, v));
    if length > 0.0 && length < 3.4e38 {
        return v / length;
    }
    return vec3<f32>(0.0);
}

fn is_zero(v: vec3<f32>) -> bool {
    return all(v == vec3<f32>(0.0));
}

// The unit tangent from C' and C'' (C''s direction, reversed at the end of the range, where
// C' = 0), or `previous` where both vanish.
fn tangent(p: Place, at_end: bool, previous: vec3<f32>) -> vec3<f32> {
    let t = unit_or_zero(p.d1);
    if !is_zero(t) {
        return t;
    }
    let bend = unit_or_zero(p.d2);
    if !is_zero(bend) {
        return select(bend, -bend, at_end);
    }
    return previous;
}

// The coordinate axis least aligned with `t` (the first of equals) made perpendicular to it.
fn axis_normal(t: vec3<f32>) -> vec3<f32> {
    var e = vec3<f32>(1.0, 0.0, 0.0);
    if abs(t.y) < abs(t.x) && abs(t.y) <= abs(t.z) {
        e = vec3<f32>(0.0, 1.0, 0.0);
    } else if abs(t.z) < abs(t.x) && abs(t.z) < abs(t.y) {
        e = vec3<f32>(0.0, 0.0, 1.0);
    }
    return unit_or_zero(e - dot(e, t) * t);
}

// One double-reflection step from (x0, t0, n0) to (x1, t1), made perpendicular to t1.
fn reflected_twice(x0: vec3<f32>, x1: vec3<f32>, t0: vec3<f32>, t1: vec3<f32>, n0: vec3<f32>) -> vec3<f32> {
    let v1 = x1 - x0;
    let c1 = dot(v1, v1);
    var r = n0;
    var t = t0;
    if c1 > 0.0 {
        r = n0 - (2.0 / c1 * dot(v1, n0)) * v1;
        t = t0 - (2.0 / c1 * dot(v1, t0)) * v1;
    }
    let v2 = t1 - t;
    let c2 = dot(v2, v2);
    var n1 = r;
    if c2 > 0.0 {
        n1 = r - (2.0 / c2 * dot(v2, r)) * v2;
    }
    let kept = unit_or_zero(n1 - dot(n1, t1) * t1);
    if !is_zero(kept) {
        return kept;
    }
    let old = unit_or_zero(n0 - dot(n0, t1) * t1);
    if !is_zero(old) {
        return old;
    }
    return axis_normal(t1);
}

// `v` (perpendicular to the unit `axis`) turned by `angle` about it.
fn turned(v: vec3<f32>, axis: vec3<f32>, angle: f32) -> vec3<f32> {
    return v * cos(angle) + cross(axis, v) * sin(angle);
}

fn write_vertex(curve: GpuMeshCurve, v: u32, position: vec3<f32>, normal: vec3<f32>) {
    let at = params.out_base + 6u * (curve.first_vertex + v);
    let p = curve.origin_hi.xyz + (curve.origin_lo.xyz + position);
    out[at] = p.x;
    out[at + 1u] = p.y;
    out[at + 2u] = p.z;
    out[at + 3u] = normal.x;
    out[at + 4u] = normal.y;
    out[at + 5u] = normal.z;
}

// A cross-section's ring (tube) or pair (ribbon) from vertex `first` on, with the frame (t, n).
fn write_section(curve: GpuMeshCurve, first: u32, p: Place, t: vec3<f32>, n: vec3<f32>) {
    let b = cross(t, n);
    if curve.shape == 1u {
        let half = 0.5 * p.width;
        write_vertex(curve, first, p.position - half * b, n);
        write_vertex(curve, first + 1u, p.position + half * b, n);
        return;
    }
    let speed = sqrt(dot(p.d1, p.d1));
    var bend = vec3<f32>(0.0);
    var slope = 0.0;
    if speed > 0.0 {
        let along = dot(p.d2, t);
        bend = (p.d2 - along * t) / (speed * speed);
        slope = p.width_d1 / speed;
    }
    for (var k = 0u; k < curve.sides; k++) {
        let angle = TAU * f32(k) / f32(curve.sides);
        let e = cos(angle) * n + sin(angle) * b;
        let stretch = 1.0 - p.width * dot(bend, e);
        var normal = unit_or_zero(stretch * e - slope * t);
        if is_zero(normal) {
            normal = e;
        }
        write_vertex(curve, first + k, p.position + p.width * e, normal);
    }
}

// Walks the curve's cross-sections carrying the frame; with `write`, writes what each holds
// (the closed-up normal: turned by -alpha s_j / L), else only carries. Returns the last normal.
fn walk(curve: GpuMeshCurve, alpha: f32, write: bool) -> vec3<f32> {
    let last = curve.sections - 1u;
    var previous_t = curve.t_first.xyz;
    var previous_x = vec3<f32>(0.0);
    var n = curve.n0.xyz;
    for (var j = 0u; j < curve.sections; j++) {
        let s = sections[curve.first_section + j];
        let p = place(curve, s.segment, s.u);
        let t = tangent(p, j == last && j > 0u, previous_t);
        if j > 0u {
            n = reflected_twice(previous_x, p.position, previous_t, t, n);
        }
        if write && s.first_vertex != NONE {
            write_section(curve, s.first_vertex, p, t, turned(n, t, -alpha * s.along));
        }
        if write && s.cap_sign != 0 {
            write_vertex(curve, s.cap_vertex, p.position, f32(s.cap_sign) * t);
        }
        previous_t = t;
        previous_x = p.position;
    }
    return n;
}

@compute @workgroup_size(WG_SIZE)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = id.y * params.row_width + id.x;
    if index >= params.curve_count {
        return;
    }
    let curve = curves[index];
    if curve.shape == 2u {
        return;
    }
    var alpha = 0.0;
    if curve.closed == 1u {
        // The angle about T_0 from N_0 to the normal carried once around.
        let carried = walk(curve, 0.0, false);
        let head = sections[curve.first_section];
        let first = place(curve, head.segment, head.u);
        let t0 = tangent(first, false, curve.t_first.xyz);
        let n0 = curve.n0.xyz;
        alpha = atan2(dot(cross(n0, carried), t0), dot(n0, carried));
    }
    walk(curve, alpha, true);
}

@compute @workgroup_size(WG_SIZE)
fn strokes(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = id.y * params.stroke_row_width + id.x;
    if index >= params.stroke_vertex_count {
        return;
    }
    let r = stroke_vertices[index];
    let curve = curves[r.curve];
    let p = place(curve, r.segment, r.u);
    let h = 0.5 * p.width;
    write_vertex(curve, r.vertex, p.position + h * vec3<f32>(r.v, 0.0), vec3<f32>(0.0, 0.0, 1.0));
}
