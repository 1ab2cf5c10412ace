// Store-only kernel for the bench's "gpu-memset" (RUN = 1) and "gpu-store-ceiling" paths
// (src/gpu/ceiling.rs): invocation i writes vec4s i·RUN .. (i+1)·RUN of `out`, with values that
// depend on both indices so that nothing can be folded away.
@group(0) @binding(0) var<storage, read_write> out: array<vec4<f32>>;
override RUN: u32;
override INVOCATIONS: u32;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * 65535u * 64u + id.x;
    if i >= INVOCATIONS { return; }
    let f = f32(i);
    for (var j = 0u; j < RUN; j++) {
        let u = f32(j);
        out[i * RUN + j] = vec4(u, f, u * f, u + f);
    }
}
