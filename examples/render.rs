//! 1,000 curves tessellated straight into a renderer's vertex buffer and drawn as line strips
//! into an offscreen image, in one submission with no readback of the samples; the image is
//! saved as a PNG.
//!
//! `cargo run --release --example render -- out/render.png` (lavapipe works).

use std::error::Error;

use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, GpuContext, Points, Sampling,
};
use splinegpu::{LinePreview, LineView};

const SIZE: u32 = 1024;

fn main() -> Result<(), Box<dyn Error>> {
    let output = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "out/render.png".to_string());

    // 1. The renderer's device. `GpuContext::from_device` would wrap one it already has.
    let context = GpuContext::new()?;
    let (device, queue) = (context.device(), context.queue());

    // 2. 1,000 closed curves on a 40 x 25 grid: each a Catmull-Rom loop through 9 points
    //    whose radii wobble, B-splines on every third cell.
    let mut job = EvalJob::new(Derivatives::None);
    for i in 0..1000u32 {
        let (cx, cy) = (f64::from(i % 40) + 0.5, f64::from(i / 40) * 1.6 + 0.8);
        let lobes = f64::from(2 + i % 5);
        let points: Vec<f64> = (0..9)
            .flat_map(|j| {
                let a = f64::from(j) * std::f64::consts::TAU / 9.0;
                let r = 0.3 + 0.15 * (lobes * a + f64::from(i) * 0.7).sin();
                [cx + r * a.cos(), cy + r * a.sin()]
            })
            .collect();
        let basis = if i % 3 == 0 {
            Basis::BSpline
        } else {
            Basis::CatmullRom
        };
        let kind = CurveKind::Uniform {
            basis,
            ends: Ends::Closed,
        };
        job.push(
            &Curve::new(kind, Points::new(2, points)?)?,
            &Sampling::PerSegment(16),
        )?;
    }

    // 3. The vertex buffer: STORAGE for the kernel to write, VERTEX for the render pass.
    let layout = context.output_layout(&job);
    let vertices = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("curve vertices"),
        size: layout.bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
        mapped_at_creation: false,
    });

    // 4. One encoder: the tessellation, then the line strips that read its output.
    let mut encoder = device.create_command_encoder(&Default::default());
    context.record_into(&mut encoder, &job, &vertices, 0)?;
    let mut preview = LinePreview::new(device, SIZE, SIZE);
    let view = LineView::fit(0.0, 0.0, 40.0, 40.0, [0.95, 0.75, 0.3, 1.0]);
    preview.draw(device, &mut encoder, &vertices, 0, &layout, view);
    queue.submit([encoder.finish()]);

    // 5. Read the image back and save it.
    let rgba = preview.read_rgba(device, queue)?;
    if let Some(dir) = std::path::Path::new(&output).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut encoder = png::Encoder::new(
        std::io::BufWriter::new(std::fs::File::create(&output)?),
        SIZE,
        SIZE,
    );
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header()?.write_image_data(&rgba)?;
    println!(
        "drew {} curves ({} samples) into {output}",
        job.len(),
        job.sample_count()
    );
    Ok(())
}
