// Evaluates surface vertices (positions, u/v derivatives, unit normals) from bicubic patches in power form.
// Rust twins of the structs: src/gpu/surface.rs. CPU twin, line by line in f32 (same names,
// loop order and arithmetic): src/gpu/surface_twin.rs.

// Rust twin: gpu::surface::SurfaceParams.
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

// Rust twin: gpu::surface::GpuPatch. Its coefficients start at float coeff_offset: A_ab for
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

// Rust twin: gpu::surface::GpuVertex. Patch `patch_index` at local (u, v), its values written from
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

// Rust twin: gpu::surface::SURFACE_WG_SIZE.
const WG_SIZE: u32 = 64u;

// Below this fraction of |Su| |Sv|, or of the sizes of the sums that make Su and Sv (a
// derivative that vanishes comes out of f32 as rounding noise in an arbitrary direction, which
// the first test alone misses: the contract's 1e-12 and 1e-10 s_u s_v, widened to f32's
// rounding), a cross product is noise: the normal is then the limit from inside the patch,
// taken at points nudged toward its centre. Differences of points that coincide are exactly
// zero in the nets (the host makes them so), so a collapsed edge gives a zero cross product.
const DEGENERATE: f32 = 1e-5;

// The first `planes` (1, 3 or 6) of the local derivatives S, Su, Sv, Suu, Suv, Svv of
// sum_{ab != 00} c_ab u^a v^b, the c_ab read `stride` floats apart from float `first` on
// (coordinate k of a patch: first = offset + k, stride = dim), and with `constant` the term
// ab = 00 from float first too (W's 16 terms); the others stay 0.
fn tensor(first: u32, stride: u32, constant: bool, u: f32, v: f32, planes: u32) -> array<f32, 6> {
    let pu = array<f32, 4>(1.0, u, u * u, u * u * u);
    let dpu = array<f32, 4>(0.0, 1.0, 2.0 * u, 3.0 * u * u);
    let ddpu = array<f32, 4>(0.0, 0.0, 2.0, 6.0 * u);
    let pv = array<f32, 4>(1.0, v, v * v, v * v * v);
    let dpv = array<f32, 4>(0.0, 1.0, 2.0 * v, 3.0 * v * v);
    let ddpv = array<f32, 4>(0.0, 0.0, 2.0, 6.0 * v);
    var d = array<f32, 6>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    var at = first;
    var ab = 1u;
    if constant {
        ab = 0u;
    }
    for (; ab < 16u; ab += 1u) {
        let a = ab / 4u;
        let b = ab % 4u;
        let c = coeffs[at];
        at += stride;
        d[0] += pu[a] * pv[b] * c;
        if planes > 1u {
            d[1] += dpu[a] * pv[b] * c;
            d[2] += pu[a] * dpv[b] * c;
        }
        if planes > 3u {
            d[3] += ddpu[a] * pv[b] * c;
            d[4] += dpu[a] * dpv[b] * c;
            d[5] += pu[a] * ddpv[b] * c;
        }
    }
    return d;
}

// Coordinate k's first `planes` local derivatives at (u, v), S without its origin (o_hi + o_lo
// is added by the caller): the polynomial's, or R = N/W's by the quotient rule.
fn coordinate(p: GpuPatch, k: u32, u: f32, v: f32, planes: u32) -> array<f32, 6> {
    let n = tensor(p.coeff_offset + k, p.dim, false, u, v, planes);
    if p.rational == 0u {
        return n;
    }
    let w = tensor(p.coeff_offset + 17u * p.dim, 1u, true, u, v, planes);
    var r = array<f32, 6>(n[0] / w[0], 0.0, 0.0, 0.0, 0.0, 0.0);
    if planes > 1u {
        r[1] = (n[1] - r[0] * w[1]) / w[0];
        r[2] = (n[2] - r[0] * w[2]) / w[0];
    }
    if planes > 3u {
        r[3] = (n[3] - 2.0 * r[1] * w[1] - r[0] * w[3]) / w[0];
        r[4] = (n[4] - r[1] * w[2] - r[2] * w[1] - r[0] * w[4]) / w[0];
        r[5] = (n[5] - 2.0 * r[2] * w[2] - r[0] * w[5]) / w[0];
    }
    return r;
}

// The cubic Bernstein weights at t, and the quadratic ones (times 3: the derivative's).
fn bernstein3(t: f32) -> array<f32, 4> {
    let s = 1.0 - t;
    return array<f32, 4>(s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t);
}

fn bernstein2(t: f32) -> array<f32, 3> {
    let s = 1.0 - t;
    return array<f32, 3>(3.0 * s * s, 6.0 * s * t, 3.0 * t * t);
}

// Su x Sv at local (u, v) of a 3-D patch, from its normal nets (and, rational, W's power form:
// R_u = (N_u - R W_u) / W), with Su and Sv, and the sizes of the sums that made N_u and N_v
// (the Bernstein weights times the differences' lengths) in x and y of the fourth.
fn cross_at(p: GpuPatch, u: f32, v: f32) -> array<vec3<f32>, 4> {
    let bu = bernstein3(u);
    let bv = bernstein3(v);
    let cu = bernstein2(u);
    let cv = bernstein2(v);
    var n = vec3<f32>(0.0);
    var nu = vec3<f32>(0.0);
    var nv = vec3<f32>(0.0);
    var sizes = vec3<f32>(0.0);
    let base = p.normal_offset;
    for (var i = 0u; i < 4u; i += 1u) {
        for (var j = 0u; j < 4u; j += 1u) {
            let at = base + 3u * (4u * i + j);
            let point = vec3<f32>(coeffs[at], coeffs[at + 1u], coeffs[at + 2u]);
            n += bu[i] * bv[j] * point;
            if i < 3u {
                let d = base + 48u + 3u * (4u * i + j);
                let difference = vec3<f32>(coeffs[d], coeffs[d + 1u], coeffs[d + 2u]);
                nu += cu[i] * bv[j] * difference;
                sizes.x += cu[i] * bv[j] * coeffs[base + 120u + 4u * i + j];
            }
            if j < 3u {
                let d = base + 84u + 3u * (3u * i + j);
                let difference = vec3<f32>(coeffs[d], coeffs[d + 1u], coeffs[d + 2u]);
                nv += bu[i] * cv[j] * difference;
                sizes.y += bu[i] * cv[j] * coeffs[base + 132u + 3u * i + j];
            }
        }
    }
    var su = nu;
    var sv = nv;
    if p.rational == 1u {
        let w = tensor(p.coeff_offset + 17u * p.dim, 1u, true, u, v, 3u);
        let r = n / w[0];
        su = (nu - r * w[1]) / w[0];
        sv = (nv - r * w[2]) / w[0];
    }
    return array<vec3<f32>, 4>(cross(su, sv), su, sv, sizes);
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
        let d = coordinate(p, k, vertex.u, vertex.v, planes);
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
