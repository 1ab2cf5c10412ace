// Evaluates runs of cubic samples, and their t-derivatives, from power-form coefficients.
// Rust twins of the structs: src/gpu/curves/abi.rs. CPU twin, line by line in f32 (same names, loop
// order and arithmetic): src/gpu/curves/interpret.rs. (src/cpu/ is the f64 reference, not a twin.)

// Rust twin: gpu::curves::abi::Params.
struct Params {
    // Runs in this dispatch.
    run_count: u32,
    // Invocations per row of the 2-D dispatch (workgroups in x times WG_SIZE).
    row_width: u32,
    // Floats per output plane (a multiple of 4): positions at 0, dP/dt at plane_stride,
    // d2P/dt2 at 2*plane_stride.
    plane_stride: u32,
    // 0, 1 or 2.
    derivatives: u32,
    // Float the runs' out_offsets count from in the bound buffer (a multiple of 4): 0 when each
    // dispatch has a buffer of its own, the dispatch's base (gpu::curves::abi::Batch::base) when a job
    // is written whole into a caller's buffer.
    out_base: u32,
    // The dispatch's first run in `runs` (its batch's runs of one mode).
    first_run: u32,
    _padding0: u32,
    _padding1: u32,
}

// Rust twin: gpu::curves::abi::GpuSegment. Its coefficient block starts at vec4 `coeff_offset`:
// the floats a[0..dim], b[0..dim], c[0..dim], d_lo[0..dim], d_hi[0..dim], 1/(t_{i+1} - t_i),
// end to end (gpu::abi::block_vec4s), with P(u) = d_hi + (d_lo + u(c + u(b + u a))) formed
// in f64 on the host, d_hi = f32(D) and d_lo = f32(D - d_hi), so that large coordinates keep
// their low bits. A rational segment (pipelines with RATIONAL) has its denominator's
// a, b, c, d after 1/dt, and P(u) = d_hi + (d_lo + u(c + u(b + u a)) / W(u)) (src/rational.rs).
struct GpuSegment {
    coeff_offset: u32,
    dim: u32,
}

// Rust twin: gpu::curves::abi::Run. `segments` consecutive segments from `segment` on, `count`
// samples of each at u = u0 + j*du, written `dim` floats apart from float out_offset on, one
// segment's block after the other. Modes: MODE_SCALAR writes each float on its own;
// MODE_VECTOR (dim <= 4, out_offset and count*dim multiples of 4, count a multiple of 4)
// writes 4 samples at a time as `dim` whole vec4s; MODE_EXPLICIT writes `count` samples whose
// segment and u are locs[first_loc + j]; MODE_ARC writes samples first..first+count of the
// arc-length sampling of the curve whose `segments` segments start at `segment`, placing each
// from the curve's table at arcs[arc] and writing its place to locs[first_loc + j]. `mode` is
// for the host, which dispatches the runs of each mode with the pipeline whose MODE it is.
struct Run {
    segment: u32,
    segments: u32,
    out_offset: u32,
    count: u32,
    mode: u32,
    u0: f32,
    du: f32,
    first_loc: u32,
    arc: u32,
    first: u32,
}

// Rust twin: gpu::curves::abi::GpuLoc. An explicitly placed sample.
struct GpuLoc {
    segment: u32,
    u: f32,
}

const MODE_VECTOR: u32 = 1u;
const MODE_EXPLICIT: u32 = 2u;
const MODE_ARC: u32 = 3u;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> segments: array<GpuSegment>;
@group(0) @binding(2) var<storage, read> coeffs: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> runs: array<Run>;
@group(0) @binding(4) var<storage, read_write> samples: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> locs: array<GpuLoc>;
// The buffer bound as `coeffs`, float by float: blocks of any dimension.
@group(0) @binding(6) var<storage, read> coeff_floats: array<f32>;
// Arc-length tables, floats as their bits (Rust twin: gpu::curves::pack::write_arc_table): a header
// (m - 1, 1/(m - 1), 0, 0); per segment (start / L, the vec4 of its first piece, pieces, 0);
// per piece of its explicit inverse two vec4s (start / L, u at its start, c1, c2),
// (c3, c4, c5, u at its end): u = u at its start + (u at its end - u at its start) x with
// x = c1 y + ... + c5 y^5, y the length from its start over its length.
@group(0) @binding(7) var<storage, read> arcs: array<vec4<u32>>;

const WG_SIZE: u32 = 64u;

// The one run mode this pipeline evaluates (MODE_VECTOR, ...; 0 is MODE_SCALAR): a CPU adapter
// runs every branch of `main`, masked, whether a lane takes it or not, so each dispatch holds
// the runs of one mode and its pipeline that mode's code only (lavapipe, w1: 31.8 ms device
// in one kernel of all four modes, 24.9 ms as one dispatch per mode).
override MODE: u32;

// Whether this pipeline's runs are of rational segments (a weighted NURBS): their samples are
// the quotient of the numerator and the denominator W, derivatives by the quotient rule.
override RATIONAL: bool = false;

// Invocations that share one run: 1 loops over the run's samples in one invocation (CPU
// adapters), a larger value gives each invocation every LANES-th sample or group (GPUs).
override LANES: u32 = 1u;

// A cubic in u for 4 coordinates, held in registers: hi + (lo + u(c + u(b + u a))).
struct Cubic {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
    lo: vec4<f32>,
    hi: vec4<f32>,
}

// A segment's cubic in 4 coordinates (zero past its dimension) and its 1/(t_{i+1} - t_i).
struct Piece {
    p: Cubic,
    inv_dt: f32,
}

// Whole blocks of 1, 2, 3 and 4 dimensions, loaded as 2, 3, 4 and 6 vec4s: a CPU adapter
// pays for every float loaded (lavapipe 22.3 loads each through a loop over its SIMD lanes).
fn piece1(at: u32) -> Piece {
    let v0 = coeffs[at];
    let v1 = coeffs[at + 1u];
    let z = vec3(0.0);
    return Piece(Cubic(vec4(v0.x, z), vec4(v0.y, z), vec4(v0.z, z), vec4(v0.w, z), vec4(v1.x, z)), v1.y);
}

fn piece2(at: u32) -> Piece {
    let v0 = coeffs[at];
    let v1 = coeffs[at + 1u];
    let v2 = coeffs[at + 2u];
    let z = vec2(0.0);
    return Piece(Cubic(vec4(v0.xy, z), vec4(v0.zw, z), vec4(v1.xy, z), vec4(v1.zw, z), vec4(v2.xy, z)), v2.z);
}

fn piece3(at: u32) -> Piece {
    let v0 = coeffs[at];
    let v1 = coeffs[at + 1u];
    let v2 = coeffs[at + 2u];
    let v3 = coeffs[at + 3u];
    return Piece(Cubic(vec4(v0.xyz, 0.0), vec4(v0.w, v1.xy, 0.0), vec4(v1.zw, v2.x, 0.0), vec4(v2.yzw, 0.0),
        vec4(v3.xyz, 0.0)), v3.w);
}

fn piece4(at: u32) -> Piece {
    return Piece(Cubic(coeffs[at], coeffs[at + 1u], coeffs[at + 2u], coeffs[at + 3u], coeffs[at + 4u]),
        coeffs[at + 5u].x);
}

// Coordinates 4q..4q+3 of a segment of any dimension, float by float.
fn piece_any(segment: GpuSegment, q: u32) -> Piece {
    let block = 4u * segment.coeff_offset;
    let dim = segment.dim;
    var terms = array<vec4<f32>, 5>();
    for (var k = 4u * q; k < min(dim, 4u * q + 4u); k++) {
        for (var t = 0u; t < 5u; t++) {
            terms[t][k - 4u * q] = coeff_floats[block + t * dim + k];
        }
    }
    return Piece(Cubic(terms[0], terms[1], terms[2], terms[3], terms[4]), coeff_floats[block + 5u * dim]);
}

// A segment of at most 4 coordinates, by whole vec4s: the same floats as piece_any(segment, 0u).
fn piece_small(segment: GpuSegment) -> Piece {
    switch segment.dim {
        case 1u: {
            return piece1(segment.coeff_offset);
        }
        case 2u: {
            return piece2(segment.coeff_offset);
        }
        case 3u: {
            return piece3(segment.coeff_offset);
        }
        default: {
            return piece4(segment.coeff_offset);
        }
    }
}

// Derivative `order` (0, 1 or 2) with respect to t of a piece, as a cubic in u. Position: the
// terms as stored (d_hi + (d_lo + u(c + u(b + u a)))). dP/dt = c/dt + u(2b/dt + u 3a/dt);
// d2P/dt2 = 2b/dt^2 + u 6a/dt^2. One Horner loop then serves every plane.
fn derive(piece: Piece, order: u32) -> Cubic {
    let p = piece.p;
    let s = piece.inv_dt;
    let zero = vec4(0.0);
    if order == 0u {
        return p;
    }
    if order == 1u {
        return Cubic(zero, 3.0 * s * p.a, 2.0 * s * p.b, s * p.c, zero);
    }
    return Cubic(zero, zero, 6.0 * s * s * p.a, 2.0 * s * s * p.b, zero);
}

fn horner(p: Cubic, u: f32) -> vec4<f32> {
    return p.hi + (p.lo + u * (p.c + u * (p.b + u * p.a)));
}

// Vec4s in a segment's coefficient block in `dim` dimensions (gpu::abi::block_vec4s): 5 dim
// terms and 1/dt, and a rational segment's denominator.
fn block_vec4s(dim: u32) -> u32 {
    return (5u * dim + 1u + select(0u, 4u, RATIONAL) + 3u) / 4u;
}

// The denominator W(u) = w.x u^3 + w.y u^2 + w.z u + w.w of the rational segment whose block
// starts at vec4 `block`: the 4 floats after its 1/dt.
fn denominator(block: u32, dim: u32) -> vec4<f32> {
    let at = 4u * block + 5u * dim + 1u;
    return vec4(coeff_floats[at], coeff_floats[at + 1u], coeff_floats[at + 2u], coeff_floats[at + 3u]);
}

// Derivative `order` (0, 1 or 2) with respect to t of a rational piece at u, by the quotient
// rule: with N = u(c + u(b + u a)) and R = N/W, the position d_hi + (d_lo + R), dP/dt = R'/dt
// with R' = (N' - R W')/W, d2P/dt2 = R''/dt^2 with R'' = (N'' - 2 R' W' - R W'')/W. Only the
// terms the order needs are formed.
fn rational_value(piece: Piece, w: vec4<f32>, u: f32, order: u32) -> vec4<f32> {
    let p = piece.p;
    let s = piece.inv_dt;
    let inv = 1.0 / (w.w + u * (w.z + u * (w.y + u * w.x)));
    let r = u * (p.c + u * (p.b + u * p.a)) * inv;
    if order == 0u {
        return p.hi + (p.lo + r);
    }
    let w1 = w.z + u * (2.0 * w.y + 3.0 * u * w.x);
    let r1 = ((p.c + u * (2.0 * p.b + 3.0 * u * p.a)) - r * w1) * inv;
    if order == 1u {
        return r1 * s;
    }
    let w2 = 2.0 * w.y + 6.0 * u * w.x;
    let r2 = ((2.0 * p.b + 6.0 * u * p.a) - 2.0 * r1 * w1 - r * w2) * inv;
    return r2 * (s * s);
}

// Derivative `order` of a piece at u: `p` is derive(piece, order), `w` a rational piece's
// denominator (RATIONAL is a constant: the driver keeps one branch).
fn value_at(piece: Piece, p: Cubic, w: vec4<f32>, u: f32, order: u32) -> vec4<f32> {
    if RATIONAL {
        return rational_value(piece, w, u, order);
    }
    return horner(p, u);
}

// Coordinates 4q..4q+3 (those below `dim`) of one sample of a rational piece at u, and its
// derivatives, written from float `out` on, each float on its own.
fn write_rational(piece: Piece, w: vec4<f32>, u: f32, q: u32, dim: u32, out: u32) {
    let last = min(dim, 4u * q + 4u);
    for (var order = 0u; order <= params.derivatives; order++) {
        let v = rational_value(piece, w, u, order);
        let plane = out + order * params.plane_stride;
        for (var k = 4u * q; k < last; k++) {
            samples[(plane + k) / 4u][(plane + k) % 4u] = v[k - 4u * q];
        }
    }
}

// Where segment `s` of a vector run starts, in vec4s, in the plane `order`: its group of 4
// samples `g` follows at `dim * g` vec4s (formed once per segment and plane, not per group:
// lavapipe, w1, 22.0-24.3 to 20.9-22.1 ms on the device).
fn segment_start(run: Run, dim: u32, order: u32, s: u32) -> u32 {
    return (run.out_offset + order * params.plane_stride) / 4u + s * run.count / 4u * dim;
}

// A vector run: `count` samples of each of its segments, 4 at a time as `dim` whole vec4s.
// Lavapipe runs every loop in a branch no lane takes at least once, masked, so the dimension
// is decided once per run, outside the loops, at the price of one loop nest per dimension.
// The run's segments are consecutive segments of one curve, so their blocks follow the first
// one's, and a segment costs only its block's loads.
fn vector_run(run: Run, lane: u32) {
    let groups = run.count / 4u;
    let du = run.du;
    let first = segments[run.segment];
    let at = first.coeff_offset;
    var den = vec4(0.0);
    switch first.dim {
        case 1u: {
            for (var s = 0u; s < run.segments; s++) {
                let block = at + s * block_vec4s(1u);
                let piece = piece1(block);
                if RATIONAL {
                    den = denominator(block, 1u);
                }
                for (var order = 0u; order <= params.derivatives; order++) {
                    let p = derive(piece, order);
                    let w0 = segment_start(run, 1u, order, s);
                    for (var g = lane; g < groups; g += LANES) {
                        let u = run.u0 + f32(4u * g) * du;
                        samples[w0 + g] = vec4(value_at(piece, p, den, u, order).x,
                            value_at(piece, p, den, u + du, order).x,
                            value_at(piece, p, den, u + 2.0 * du, order).x,
                            value_at(piece, p, den, u + 3.0 * du, order).x);
                    }
                }
            }
        }
        case 2u: {
            for (var s = 0u; s < run.segments; s++) {
                let block = at + s * block_vec4s(2u);
                let piece = piece2(block);
                if RATIONAL {
                    den = denominator(block, 2u);
                }
                for (var order = 0u; order <= params.derivatives; order++) {
                    let p = derive(piece, order);
                    let w0 = segment_start(run, 2u, order, s);
                    for (var g = lane; g < groups; g += LANES) {
                        let u = run.u0 + f32(4u * g) * du;
                        let o = w0 + 2u * g;
                        samples[o] = vec4(value_at(piece, p, den, u, order).xy,
                            value_at(piece, p, den, u + du, order).xy);
                        samples[o + 1u] = vec4(value_at(piece, p, den, u + 2.0 * du, order).xy,
                            value_at(piece, p, den, u + 3.0 * du, order).xy);
                    }
                }
            }
        }
        case 3u: {
            for (var s = 0u; s < run.segments; s++) {
                let block = at + s * block_vec4s(3u);
                let piece = piece3(block);
                if RATIONAL {
                    den = denominator(block, 3u);
                }
                for (var order = 0u; order <= params.derivatives; order++) {
                    let p = derive(piece, order);
                    let w0 = segment_start(run, 3u, order, s);
                    for (var g = lane; g < groups; g += LANES) {
                        let u = run.u0 + f32(4u * g) * du;
                        let s0 = value_at(piece, p, den, u, order);
                        let s1 = value_at(piece, p, den, u + du, order);
                        let s2 = value_at(piece, p, den, u + 2.0 * du, order);
                        let s3 = value_at(piece, p, den, u + 3.0 * du, order);
                        let o = w0 + 3u * g;
                        samples[o] = vec4(s0.xyz, s1.x);
                        samples[o + 1u] = vec4(s1.yz, s2.xy);
                        samples[o + 2u] = vec4(s2.z, s3.xyz);
                    }
                }
            }
        }
        default: {
            for (var s = 0u; s < run.segments; s++) {
                let block = at + s * block_vec4s(4u);
                let piece = piece4(block);
                if RATIONAL {
                    den = denominator(block, 4u);
                }
                for (var order = 0u; order <= params.derivatives; order++) {
                    let p = derive(piece, order);
                    let w0 = segment_start(run, 4u, order, s);
                    for (var g = lane; g < groups; g += LANES) {
                        let u = run.u0 + f32(4u * g) * du;
                        let o = w0 + 4u * g;
                        samples[o] = value_at(piece, p, den, u, order);
                        samples[o + 1u] = value_at(piece, p, den, u + du, order);
                        samples[o + 2u] = value_at(piece, p, den, u + 2.0 * du, order);
                        samples[o + 3u] = value_at(piece, p, den, u + 3.0 * du, order);
                    }
                }
            }
        }
    }
}

// Coordinates 4q..4q+3 (those below `dim`) of one sample of `piece` at u, and its derivatives,
// written from float `out` on, each float on its own.
fn write_group(piece: Piece, u: f32, q: u32, dim: u32, out: u32) {
    let last = min(dim, 4u * q + 4u);
    for (var order = 0u; order <= params.derivatives; order++) {
        let v = horner(derive(piece, order), u);
        let plane = out + order * params.plane_stride;
        for (var k = 4u * q; k < last; k++) {
            samples[(plane + k) / 4u][(plane + k) % 4u] = v[k - 4u * q];
        }
    }
}

const NO_SEGMENT: u32 = 0xffffffffu;

// The segment whose coefficients a run of samples placed one by one holds: consecutive samples
// on one segment of at most 4 coordinates load its block once (a CPU adapter pays for every
// float loaded).
// `w` is a rational segment's denominator.
struct Loaded {
    segment: u32,
    piece: Piece,
    w: vec4<f32>,
}

fn nothing_loaded() -> Loaded {
    let z = vec4(0.0);
    return Loaded(NO_SEGMENT, Piece(Cubic(z, z, z, z, z), 0.0), z);
}

// Sample j of a run, at its own segment and u, written from float out_offset + j * dim on.
fn place_sample(loc: GpuLoc, out_offset: u32, j: u32, loaded: ptr<function, Loaded>) {
    let segment = segments[loc.segment];
    let out = out_offset + j * segment.dim;
    if segment.dim <= 4u {
        if (*loaded).segment != loc.segment {
            (*loaded).piece = piece_small(segment);
            if RATIONAL {
                (*loaded).w = denominator(segment.coeff_offset, segment.dim);
            }
            (*loaded).segment = loc.segment;
        }
        if RATIONAL {
            write_rational((*loaded).piece, (*loaded).w, loc.u, 0u, segment.dim, out);
        } else {
            write_group((*loaded).piece, loc.u, 0u, segment.dim, out);
        }
    } else {
        for (var q = 0u; 4u * q < segment.dim; q++) {
            if RATIONAL {
                write_rational(piece_any(segment, q), denominator(segment.coeff_offset, segment.dim), loc.u, q, segment.dim, out);
            } else {
                write_group(piece_any(segment, q), loc.u, q, segment.dim, out);
            }
        }
    }
}

// An explicit run: each sample at its own segment and u.
fn explicit_run(run: Run, lane: u32) {
    var loaded = nothing_loaded();
    for (var j = lane; j < run.count; j += LANES) {
        place_sample(locs[run.first_loc + j], run.out_offset, j, &loaded);
    }
}

// c1 y + c2 y^2 + ... + c5 y^5.
fn model_at(c: vec4<f32>, c5: f32, y: f32) -> f32 {
    return y * (c.x + y * (c.y + y * (c.z + y * (c.w + y * c5))));
}

// The last of `count` nondecreasing starts (the first float of arcs[first + stride * n]) that
// is <= x, searched from `start_at` on (whose start is <= x): steps doubling from it, then halving.
fn last_start_at_or_before(first: u32, stride: u32, start_at: u32, count: u32, x: f32) -> u32 {
    var lo = start_at;
    var step = 1u;
    var hi = lo + step;
    while hi < count && bitcast<f32>(arcs[first + stride * hi].x) <= x {
        lo = hi;
        step *= 2u;
        hi = lo + step;
    }
    hi = min(hi, count);
    while hi - lo > 1u {
        let mid = (lo + hi) / 2u;
        if bitcast<f32>(arcs[first + stride * mid].x) <= x {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// Where the last sample of an arc-length run was found (its segment, and its piece there):
// the run's samples come in increasing length, so the next search starts there.
struct ArcHint {
    segment: u32,
    piece: u32,
}

// Sample i of an arc-length run's curve: the first at u = 0 of the first segment, the last
// at u = 1 of the last; between them, at length i/(m - 1) of L, the segment that starts last
// at or before it, the piece of its explicit inverse that does, and the inverse's u there (the
// host's twin: sampling::arc_length::InversePiece::at).
fn arc_place(run: Run, i: u32, hint: ptr<function, ArcHint>) -> GpuLoc {
    let header = arcs[run.arc];
    if i == 0u {
        return GpuLoc(run.segment, 0.0);
    }
    if i >= header.x {
        return GpuLoc(run.segment + run.segments - 1u, 1.0);
    }
    let at_length = f32(i) * bitcast<f32>(header.y);
    let lo = last_start_at_or_before(run.arc + 1u, 1u, (*hint).segment, run.segments, at_length);
    if lo != (*hint).segment {
        (*hint).segment = lo;
        (*hint).piece = 0u;
    }
    let record = arcs[run.arc + 1u + lo];
    let k = last_start_at_or_before(record.y, 2u, (*hint).piece, record.z, at_length);
    (*hint).piece = k;
    let piece = bitcast<vec4<f32>>(arcs[record.y + 2u * k]);
    let c = bitcast<vec4<f32>>(arcs[record.y + 2u * k + 1u]);
    let end = bitcast<f32>(arcs[record.y + 2u * k + 2u].x);
    // The inverse's coefficients c1..c5.
    let c14 = vec4(piece.z, piece.w, c.x, c.y);
    let c5 = c.z;
    let span = end - piece.x;
    var y = 0.0;
    if span > 0.0 {
        y = clamp((at_length - piece.x) / span, 0.0, 1.0);
    }
    let x = clamp(model_at(c14, c5, y), 0.0, 1.0);
    return GpuLoc(run.segment + lo, clamp(piece.y + x * (c.w - piece.y), 0.0, 1.0));
}

// An arc-length run: each sample placed by the curve's table, its place written for the host
// (which forms t in f64), then evaluated there.
fn arc_run(run: Run, lane: u32) {
    var hint = ArcHint(0u, 0u);
    var loaded = nothing_loaded();
    for (var j = lane; j < run.count; j += LANES) {
        let loc = arc_place(run, run.first + j, &hint);
        locs[run.first_loc + j] = loc;
        place_sample(loc, run.out_offset, j, &loaded);
    }
}

// The run's `count` samples of one segment whose block starts at float `out`, each float on
// its own: any dimension and alignment.
fn scalar_block(segment: GpuSegment, out: u32, run: Run, lane: u32) {
    for (var q = 0u; 4u * q < segment.dim; q++) {
        let piece = piece_any(segment, q);
        let last = min(segment.dim, 4u * q + 4u);
        for (var order = 0u; order <= params.derivatives; order++) {
            let p = derive(piece, order);
            let plane = out + order * params.plane_stride;
            for (var j = lane; j < run.count; j += LANES) {
                let v = horner(p, run.u0 + f32(j) * run.du);
                for (var k = 4u * q; k < last; k++) {
                    let f = plane + j * segment.dim + k;
                    samples[f / 4u][f % 4u] = v[k - 4u * q];
                }
            }
        }
    }
}

// The run's `count` samples of one rational segment whose block starts at float `out`, each
// float on its own.
fn rational_block(segment: GpuSegment, out: u32, run: Run, lane: u32) {
    let w = denominator(segment.coeff_offset, segment.dim);
    for (var q = 0u; 4u * q < segment.dim; q++) {
        let piece = piece_any(segment, q);
        for (var j = lane; j < run.count; j += LANES) {
            write_rational(piece, w, run.u0 + f32(j) * run.du, q, segment.dim, out + j * segment.dim);
        }
    }
}

@compute @workgroup_size(WG_SIZE)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = id.y * params.row_width + id.x;
    let run_index = index / LANES;
    if run_index >= params.run_count {
        return;
    }
    var run = runs[params.first_run + run_index];
    run.out_offset += params.out_base;
    let lane = index % LANES;
    // MODE is a constant: the driver keeps one branch.
    if MODE == MODE_VECTOR {
        vector_run(run, lane);
    } else if MODE == MODE_EXPLICIT {
        explicit_run(run, lane);
    } else if MODE == MODE_ARC {
        arc_run(run, lane);
    } else {
        var out = run.out_offset;
        for (var s = 0u; s < run.segments; s++) {
            let segment = segments[run.segment + s];
            if RATIONAL {
                rational_block(segment, out, run, lane);
            } else {
                scalar_block(segment, out, run, lane);
            }
            out += run.count * segment.dim;
        }
    }
}
