// Draws tessellated curves as line strips: each vertex is a sample of splinegpu's output.
// Rust side: src/gpu/preview.rs (View is its twin).

// Rust twin: gpu::preview::View. Clip position = sample.xy * scale + offset.
struct View {
    scale: vec2<f32>,
    offset: vec2<f32>,
    color: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;

// The first two coordinates of a sample.
@vertex
fn vs_main(@location(0) sample: vec2<f32>) -> @builtin(position) vec4<f32> {
    return vec4(sample * view.scale + view.offset, 0.0, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return view.color;
}
