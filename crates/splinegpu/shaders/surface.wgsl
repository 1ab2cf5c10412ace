// Evaluates surface vertices (positions, u/v derivatives, unit normals) from bicubic patches in power form.
// Rust twins of the structs: src/gpu/surfaces/abi.rs. CPU twin, line by line in f32 (same names,
// loop order and arithmetic): src/gpu/surfaces/twin.rs.

// Rust twin: gpu::surfaces::abi::SurfaceParams.
struct SurfaceParams {
    // Vertices in this dispatch.
    vertex_count: u32,
    // Invocations per row of the 2-D dispatch (workgroups in x times WG_SIZE).
    row_width: u32,
    // Floats per output plane: positions at 0, then d/du, d/dv (derivatives >= 1), d2/du2,
    // d2/dudv, d2/dv2 (derivatives = 2), then unit normals (normals = 1), each plane_stride on.
    plane_stride: u32,
    // 0, 1 or 2.
    derivatives: u32,
    // 1: write unit normals (every patch 3-D).
    normals: u32,
    _padding0: u32,
    _padding1: u32,
    _padding2: u32,
}

// Rust twin: gpu::surfaces::abi::GpuPatch. Its coefficients start at float coeff_offset: A_ab for
// (a, b) != (0, 0) in the order 4a + b, dim floats each (15 dim), then the origin
// A_00 = S(0, 0) as o_hi = f32(A_00) and o_lo = f32(A_00 - o_hi) (dim floats each), so that
// large coordinates keep their low bits: S = o_hi + (o_lo + sum). A rational patch (S = O + N/W,
// src/surface/patch.rs) has W's 16 coefficients after them, and S = o_hi + (o_lo + N/W).
// With normals asked for (3-D patches), a patch then has its normal nets (normal_offset): N's
// Bezier points N_ij (16 x 3, i along u), their differences along u, N_(i+1)j - N_ij (12 x 3),
// and along v (12 x 3), then the differences' lengths (12 along u, 12 along v), formed in f64:
// the normal's derivatives are sums of these with non-negative Bernstein weights, which keeps
// their relative accuracy where power coefficients would cancel (uneven knots).
struct GpuPatch {
    coeff_offset: u32,
    dim: u32,
    rational: u32,
    // Float offset of the normal nets (3-D patches).
    normal_offset: u32,
    // 1/du and 1/dv: local derivatives to the surface's parameters.
    inv_du: f32,
    inv_dv: f32,
    _padding1: u32,
    _padding2: u32,
}

// Rust twin: gpu::surfaces::abi::GpuVertex. Patch `patch_index` at local (u, v), its values written from
// float `out` of each plane on (normals too: 3-D).
struct GpuVertex {
    patch_index: u32,
    out: u32,
    u: f32,
    v: f32,
}

@group(0) @binding(0) var<uniform> params: SurfaceParams;
@group(0) @binding(1) var<storage, read> patches: array<GpuPatch>;
@group(0) @binding(2) var<storage, read> coeffs: array<f32>;
@group(0) @binding(3) var<storage, read> vertices: array<GpuVertex>;
@group(0) @binding(4) var<storage, read_write> out: array<f32>;

// Rust twin: gpu::surfaces::abi::SURFACE_WG_SIZE.
const WG_SIZE: u32 = 64u;

// Below this fraction of |Su| |Sv|, or of the sizes of the sums that make Su and Sv (a
// derivative that vanishes comes out of f32 as rounding noise in an arbitrary direction, which
// the first test alone misses: the contract's 1e-12 and 1e-10 s_u s_v, widened to f32's
// rounding), a cross product is noise: the normal is then the limit from inside the patch,
// taken at points nudged toward its centre. Differences of points that coincide are exactly
// zero in the nets (the host makes them so), so a collapsed edge gives a zero cross product.
const DEGENERATE: f32 = 1e-5;

// Coefficient c_ab of sum_ab c_ab u^a v^b read `stride` floats apart from float `first` on:
// with `constant` every ab from first on (W's 16 terms), else ab = 00 is 0 and the 15 others
// start at first (coordinate k of a patch: first = offset + k, stride = dim).
fn coefficient(first: u32, stride: u32, constant: bool, a: u32, b: u32) -> f32 {
    let ab = 4u * a + b;
    if constant {
        return coeffs[first + ab * stride];
    }
    if ab == 0u {
        return 0.0;
    }
    return coeffs[first + (ab - 1u) * stride];
}

// Row a in v by Horner: sum_b c_ab v^b, its first and its second derivative in v.
fn row(first: u32, stride: u32, constant: bool, a: u32, v: f32) -> vec3<f32> {
    let c0 = coefficient(first, stride, constant, a, 0u);
    let c1 = coefficient(first, stride, constant, a, 1u);
    let c2 = coefficient(first, stride, constant, a, 2u);
    let c3 = coefficient(first, stride, constant, a, 3u);
    return vec3<f32>(
        c0 + v * (c1 + v * (c2 + v * c3)),
        c1 + v * (2.0 * c2 + 3.0 * v * c3),
        2.0 * c2 + 6.0 * v * c3,
    );
}

// The local derivatives S, Su, Sv, Suu, Suv, Svv of sum_ab c_ab u^a v^b (see `coefficient`):
// the rows in v, then Horner in u over the rows (x: the value, y: d/dv, z: d2/dv2).
fn tensor(first: u32, stride: u32, constant: bool, u: f32, v: f32) -> array<f32, 6> {
    let r0 = row(first, stride, constant, 0u, v);
    let r1 = row(first, stride, constant, 1u, v);
    let r2 = row(first, stride, constant, 2u, v);
    let r3 = row(first, stride, constant, 3u, v);
    let value = r0 + u * (r1 + u * (r2 + u * r3));
    let slope = r1 + u * (2.0 * r2 + 3.0 * u * r3);
    let bend = 2.0 * r2 + 6.0 * u * r3;
    return array<f32, 6>(value.x, slope.x, value.y, bend.x, slope.y, value.z);
}

// Coordinate k's local derivatives at (u, v), S without its origin (o_hi + o_lo is added by the
// caller): the polynomial's, or R = N/W's by the quotient rule.
fn coordinate(p: GpuPatch, k: u32, u: f32, v: f32) -> array<f32, 6> {
    let n = tensor(p.coeff_offset + k, p.dim, false, u, v);
    if p.rational == 0u {
        return n;
    }
    let w = tensor(p.coeff_offset + 17u * p.dim, 1u, true, u, v);
    let r = n[0] / w[0];
    let ru = (n[1] - r * w[1]) / w[0];
    let rv = (n[2] - r * w[2]) / w[0];
    let ruu = (n[3] - 2.0 * ru * w[1] - r * w[3]) / w[0];
    let ruv = (n[4] - ru * w[2] - rv * w[1] - r * w[4]) / w[0];
    let rvv = (n[5] - 2.0 * rv * w[2] - r * w[5]) / w[0];
    return array<f32, 6>(r, ru, rv, ruu, ruv, rvv);
}

// The cubic Bernstein weights at t, and the quadratic ones (times 3: the derivative's).
fn bernstein3(t: f32) -> vec4<f32> {
    let s = 1.0 - t;
    return vec4<f32>(s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t);
}

fn bernstein2(t: f32) -> vec3<f32> {
    let s = 1.0 - t;
    return vec3<f32>(3.0 * s * s, 6.0 * s * t, 3.0 * t * t);
}

// The 3-D point at float `at`.
fn point3(at: u32) -> vec3<f32> {
    return vec3<f32>(coeffs[at], coeffs[at + 1u], coeffs[at + 2u]);
}

// A row of 4 (or 3) 3-D points from float `first` on, weighted by `w`.
fn weighted4(first: u32, w: vec4<f32>) -> vec3<f32> {
    return w.x * point3(first) + w.y * point3(first + 3u) + w.z * point3(first + 6u)
        + w.w * point3(first + 9u);
}

fn weighted3(first: u32, w: vec3<f32>) -> vec3<f32> {
    return w.x * point3(first) + w.y * point3(first + 3u) + w.z * point3(first + 6u);
}

// 4 (or 3) lengths from float `first` on.
fn lengths4(first: u32) -> vec4<f32> {
    return vec4<f32>(coeffs[first], coeffs[first + 1u], coeffs[first + 2u], coeffs[first + 3u]);
}

fn lengths3(first: u32) -> vec3<f32> {
    return vec3<f32>(coeffs[first], coeffs[first + 1u], coeffs[first + 2u]);
}

// Su x Sv at local (u, v) of a 3-D patch, from its normal nets (and, rational, W's power form:
// R_u = (N_u - R W_u) / W), with Su and Sv, and the sizes of the sums that made N_u and N_v
// (the Bernstein weights times the differences' lengths) in x and y of the fourth. Each net is
// contracted row by row in v, then the rows in u.
fn cross_at(p: GpuPatch, u: f32, v: f32) -> array<vec3<f32>, 4> {
    let bu = bernstein3(u);
    let bv = bernstein3(v);
    let cu = bernstein2(u);
    let cv = bernstein2(v);
    let base = p.normal_offset;
    let n = bu.x * weighted4(base, bv) + bu.y * weighted4(base + 12u, bv)
        + bu.z * weighted4(base + 24u, bv) + bu.w * weighted4(base + 36u, bv);
    let nu = cu.x * weighted4(base + 48u, bv) + cu.y * weighted4(base + 60u, bv)
        + cu.z * weighted4(base + 72u, bv);
    let nv = bu.x * weighted3(base + 84u, cv) + bu.y * weighted3(base + 93u, cv)
        + bu.z * weighted3(base + 102u, cv) + bu.w * weighted3(base + 111u, cv);
    let size_u = cu.x * dot(bv, lengths4(base + 120u)) + cu.y * dot(bv, lengths4(base + 124u))
        + cu.z * dot(bv, lengths4(base + 128u));
    let size_v = bu.x * dot(cv, lengths3(base + 132u)) + bu.y * dot(cv, lengths3(base + 135u))
        + bu.z * dot(cv, lengths3(base + 138u)) + bu.w * dot(cv, lengths3(base + 141u));
    var su = nu;
    var sv = nv;
    if p.rational == 1u {
        let w = tensor(p.coeff_offset + 17u * p.dim, 1u, true, u, v);
        let r = n / w[0];
        su = (nu - r * w[1]) / w[0];
        sv = (nv - r * w[2]) / w[0];
    }
    return array<vec3<f32>, 4>(cross(su, sv), su, sv, vec3<f32>(size_u, size_v, 0.0));
}

// The unit normal: along Su x Sv, or where that vanishes its limit from inside the patch,
// approached along the ray toward the centre at steps of 1e-3, 1e-2 and 1e-1 of the way.
fn unit_normal(p: GpuPatch, u: f32, v: f32) -> vec3<f32> {
    var uu = u;
    var vv = v;
    for (var step = 0u; step < 4u; step += 1u) {
        let c = cross_at(p, uu, vv);
        let size = length(c[0]);
        if size > DEGENERATE * length(c[1]) * length(c[2])
            && size > DEGENERATE * c[3].x * c[3].y && size > 0.0 {
            return c[0] / size;
        }
        let toward = array<f32, 3>(1e-3, 1e-2, 1e-1);
        if step < 3u {
            uu = u + (0.5 - u) * toward[step];
            vv = v + (0.5 - v) * toward[step];
        }
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}

@compute @workgroup_size(WG_SIZE)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * params.row_width + id.x;
    if i >= params.vertex_count {
        return;
    }
    let vertex = vertices[i];
    let p = patches[vertex.patch_index];
    let scale = array<f32, 6>(1.0, p.inv_du, p.inv_dv, p.inv_du * p.inv_du, p.inv_du * p.inv_dv, p.inv_dv * p.inv_dv);
    var planes = 1u;
    if params.derivatives >= 1u {
        planes = 3u;
    }
    if params.derivatives == 2u {
        planes = 6u;
    }
    for (var k = 0u; k < p.dim; k += 1u) {
        let d = coordinate(p, k, vertex.u, vertex.v);
        let origin = p.coeff_offset + 15u * p.dim + k;
        out[vertex.out + k] = coeffs[origin] + (coeffs[origin + p.dim] + d[0]);
        for (var m = 1u; m < planes; m += 1u) {
            out[m * params.plane_stride + vertex.out + k] = d[m] * scale[m];
        }
    }
    if params.normals == 1u {
        let n = unit_normal(p, vertex.u, vertex.v);
        let at = planes * params.plane_stride + vertex.out;
        out[at] = n.x;
        out[at + 1u] = n.y;
        out[at + 2u] = n.z;
    }
}
