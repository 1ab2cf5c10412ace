//! 1,000 curves tessellated straight into a renderer's vertex buffer and drawn as line strips
//! into an offscreen image, in one submission with no readback of the samples; the image is
//! saved as a PNG.
//!
//! `cargo run --release --example render -- out/render.png` (lavapipe works).

use std::error::Error;

use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, GpuContext, Points, Sampling,
};

mod preview;

use preview::{LinePreview, LineView};

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

/// The preview draws what `record_into` wrote (`cargo test --example render`): a ring's pixels
/// are lit where the f64 reference puts the curve and nowhere far from it, and the preview's
/// uniform matches its WGSL twin.
#[cfg(test)]
mod tests {
    use super::*;

    /// A closed Catmull-Rom curve through 6 points on the circle of radius 0.6.
    fn ring() -> EvalJob {
        let points: Vec<f64> = (0..6)
            .flat_map(|i| {
                let a = f64::from(i) * std::f64::consts::PI / 3.0;
                [0.6 * a.cos(), 0.6 * a.sin(), 0.25]
            })
            .collect();
        let kind = CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Closed,
        };
        let mut job = EvalJob::new(Derivatives::None);
        job.push(
            &Curve::new(kind, Points::new(3, points).unwrap()).unwrap(),
            &Sampling::PerSegment(64),
        )
        .unwrap();
        job
    }

    #[test]
    fn the_view_uniform_matches_its_wgsl_twin() {
        let module = naga::front::wgsl::parse_str(include_str!("lines.wgsl")).unwrap();
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("View"))
            .expect("struct View in lines.wgsl");
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("View is not a struct");
        };
        let offsets: Vec<(Option<&str>, u32)> = members
            .iter()
            .map(|m| (m.name.as_deref(), m.offset))
            .collect();
        assert_eq!(*span as usize, size_of::<LineView>());
        assert_eq!(
            offsets,
            [
                (Some("scale"), std::mem::offset_of!(LineView, scale) as u32),
                (
                    Some("offset"),
                    std::mem::offset_of!(LineView, offset) as u32
                ),
                (Some("color"), std::mem::offset_of!(LineView, color) as u32),
            ]
        );
    }

    #[test]
    fn a_drawn_curve_lights_its_pixels_and_none_far_from_it() {
        let Ok(context) = GpuContext::new() else {
            eprintln!("no GPU adapter: skipped");
            return;
        };
        let (device, queue) = (context.device(), context.queue());
        let job = ring();
        let layout = context.output_layout(&job);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("vertices"),
            size: layout.bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
            mapped_at_creation: false,
        });
        const SIZE: u32 = 64;
        let mut preview = LinePreview::new(device, SIZE, SIZE);
        let mut encoder = device.create_command_encoder(&Default::default());
        context.record_into(&mut encoder, &job, &buffer, 0).unwrap();
        preview.draw(
            device,
            &mut encoder,
            &buffer,
            0,
            &layout,
            LineView::fit(-1.0, -1.0, 1.0, 1.0, [1.0; 4]),
        );
        queue.submit([encoder.finish()]);
        let rgba = preview.read_rgba(device, queue).unwrap();
        let lit = |x: i64, y: i64| {
            (0..SIZE as i64).contains(&x)
                && (0..SIZE as i64).contains(&y)
                && rgba[(4 * (y * SIZE as i64 + x)) as usize] > 128
        };
        // The curve's samples, from the CPU reference, in pixels (y down).
        let reference = splinegpu::evaluate_reference(&job);
        let to_pixel = |p: &[f64]| {
            (
                (p[0] + 1.0) / 2.0 * f64::from(SIZE),
                (1.0 - p[1]) / 2.0 * f64::from(SIZE),
            )
        };
        let polyline: Vec<(f64, f64)> = reference
            .curve(0)
            .points
            .chunks_exact(3)
            .map(to_pixel)
            .collect();
        for &(x, y) in &polyline {
            let near_lit = (-1..=1).any(|dx| (-1..=1).any(|dy| lit(x as i64 + dx, y as i64 + dy)));
            assert!(near_lit, "no lit pixel near the curve at ({x:.1}, {y:.1})");
        }
        let distance = |px: f64, py: f64| {
            polyline.windows(2).fold(f64::INFINITY, |d, w| {
                let ((ax, ay), (bx, by)) = (w[0], w[1]);
                let (vx, vy) = (bx - ax, by - ay);
                let t = (((px - ax) * vx + (py - ay) * vy) / (vx * vx + vy * vy).max(1e-12))
                    .clamp(0.0, 1.0);
                d.min(((px - ax - t * vx).powi(2) + (py - ay - t * vy).powi(2)).sqrt())
            })
        };
        let mut lit_far = Vec::new();
        for y in 0..SIZE as i64 {
            for x in 0..SIZE as i64 {
                if lit(x, y) && distance(x as f64 + 0.5, y as f64 + 0.5) > 4.0 {
                    lit_far.push((x, y));
                }
            }
        }
        assert!(
            lit_far.is_empty(),
            "pixels lit far from the curve: {lit_far:?}"
        );
        let lit_count = (0..SIZE as i64 * SIZE as i64)
            .filter(|i| lit(i % SIZE as i64, i / SIZE as i64))
            .count();
        assert!(lit_count > 100, "only {lit_count} pixels lit");
    }
}
