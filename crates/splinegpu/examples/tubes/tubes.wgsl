// Draws the meshes a GeometryRecording wrote: each vertex a position and the exact surface's
// unit normal (24 bytes), lit by one directional light, coloured by where it is.
// Rust side: examples/tubes/main.rs (Camera is its twin).

// Rust twin: Camera in main.rs.
struct Camera {
    view_proj: mat4x4<f32>,
    // The direction toward the light (unit), w unused.
    light: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;

struct Lit {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) world: vec3<f32>,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> Lit {
    return Lit(camera.view_proj * vec4<f32>(position, 1.0), normal, position);
}

// Lit from both sides, for a surface whose patches do not all face out (the teapot's), in
// porcelain white.
@fragment
fn fs_two_sided(in: Lit) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let diffuse = abs(dot(n, camera.light.xyz));
    return vec4<f32>(vec3<f32>(0.92, 0.9, 0.85) * (0.15 + 0.85 * diffuse), 1.0);
}

@fragment
fn fs_main(in: Lit) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let diffuse = max(dot(n, camera.light.xyz), 0.0);
    let base = vec3<f32>(0.55, 0.45, 0.35) + 0.35 * cos(vec3<f32>(0.0, 2.1, 4.2) + 0.35 * in.world.x + 0.2 * in.world.y);
    return vec4<f32>(base * (0.18 + 0.82 * diffuse), 1.0);
}
