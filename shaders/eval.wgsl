// Evaluates runs of cubic samples, and their t-derivatives, from power-form coefficients.
// Rust twins of the structs: src/gpu/layout.rs. CPU twin of the arithmetic: src/cpu.rs.

// Rust twin: gpu::layout::Params.
struct Params {
    // Runs in this dispatch.
    run_count: u32,
    // Invocations per row of the 2-D dispatch (workgroups in x times WG_SIZE).
    row_width: u32,
    // Values per output plane: positions at 0, dP/dt at plane_stride, d2P/dt2 at 2*plane_stride.
    plane_stride: u32,
    // 0, 1 or 2.
    derivatives: u32,
}

// Rust twin: gpu::layout::GpuSegment. Its coefficients are 5 floats per coordinate,
// [a, b, c, d_lo, d_hi]: P(u) = d_hi + (d_lo + u(c + u(b + u a))), formed in f64 on the host
// with d_hi = f32(D) and d_lo = f32(D - d_hi), so large coordinates keep their low bits.
struct Segment {
    coeff_offset: u32,
    dim: u32,
    // 1 / (t_{i+1} - t_i).
    inv_dt: f32,
}

// Rust twin: gpu::layout::Run. `count` samples of one segment at u = u0 + j*du, written
// `dim` values apart from out_offset on.
struct Run {
    segment: u32,
    out_offset: u32,
    count: u32,
    u0: f32,
    du: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> segments: array<Segment>;
@group(0) @binding(2) var<storage, read> coeffs: array<f32>;
@group(0) @binding(3) var<storage, read> runs: array<Run>;
@group(0) @binding(4) var<storage, read_write> samples: array<f32>;

const WG_SIZE: u32 = 64u;

// Invocations that share one run: 1 loops over the run's samples in one invocation (CPU
// adapters), a larger value gives each invocation every LANES-th sample (GPUs).
override LANES: u32 = 1u;

@compute @workgroup_size(WG_SIZE)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = id.y * params.row_width + id.x;
    let run_index = index / LANES;
    if run_index >= params.run_count {
        return;
    }
    let run = runs[run_index];
    let segment = segments[run.segment];
    let inv_dt = segment.inv_dt;
    let inv_dt2 = inv_dt * inv_dt;
    for (var j = index % LANES; j < run.count; j += LANES) {
        let u = run.u0 + f32(j) * run.du;
        let out = run.out_offset + j * segment.dim;
        for (var k = 0u; k < segment.dim; k++) {
            let at = segment.coeff_offset + 5u * k;
            let a = coeffs[at];
            let b = coeffs[at + 1u];
            let c = coeffs[at + 2u];
            let d_lo = coeffs[at + 3u];
            let d_hi = coeffs[at + 4u];
            samples[out + k] = d_hi + (d_lo + u * (c + u * (b + u * a)));
            if params.derivatives >= 1u {
                samples[params.plane_stride + out + k] = (c + u * (2.0 * b + 3.0 * u * a)) * inv_dt;
            }
            if params.derivatives >= 2u {
                samples[2u * params.plane_stride + out + k] = (2.0 * b + 6.0 * u * a) * inv_dt2;
            }
        }
    }
}
