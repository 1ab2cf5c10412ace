//! Draws the README's surface picture with the crate itself: the Utah teapot (Newell's 32
//! Bezier patches) as its certified mesh at 1e-3 of its extent, and a rational NURBS torus, each
//! lit by the crate's unit normals, rasterized on the CPU into a PNG.
//!
//! `cargo run -p splinegpu --example surfaces -- docs` (from the repository root) writes
//! `docs/surfaces.png`; its test (`cargo test --example surfaces`) fails when the committed
//! picture is not what the crate draws now.

use std::error::Error;

use splinegpu::Derivatives;
use splinegpu::surface::{Net, Surface, SurfaceJob, SurfaceKind, SurfaceSamples, SurfaceSampling};

#[path = "common/teapot.rs"]
mod teapot;

use teapot::teapot;

/// The picture's size in pixels, and the supersampling per axis.
const WIDTH: usize = 960;
const HEIGHT: usize = 420;
const SUPER: usize = 2;

fn main() -> Result<(), Box<dyn Error>> {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs".to_string());
    std::fs::create_dir_all(&dir)?;
    std::fs::write(format!("{dir}/surfaces.png"), picture()?)?;
    println!("wrote {dir}/surfaces.png");
    Ok(())
}

/// The picture as PNG bytes.
fn picture() -> Result<Vec<u8>, Box<dyn Error>> {
    let mut image = Image::new(WIDTH * SUPER, HEIGHT * SUPER);
    // Left half: the teapot, z up, turned a little toward the viewer.
    let teapot = teapot()?;
    let extent = teapot.net().extent();
    let mesh = tessellate(&teapot, &SurfaceSampling::Tolerance(1e-3 * extent))?;
    let view = View::new(-0.55, 0.35, [0.2, 0.0, 1.55], 0.5 * HEIGHT as f64 / 3.1);
    image.draw(
        &mesh,
        &view,
        [0.25 * WIDTH as f64, 0.52 * HEIGHT as f64],
        [0.80, 0.36, 0.28],
    );
    // Right half: a NURBS torus, exact circles in both directions.
    let torus = torus(2.2, 0.8)?;
    let mesh = tessellate(&torus, &SurfaceSampling::Tolerance(2e-3))?;
    let view = View::new(0.4, 0.9, [0.0; 3], 0.42 * HEIGHT as f64 / 3.0);
    image.draw(
        &mesh,
        &view,
        [0.74 * WIDTH as f64, 0.5 * HEIGHT as f64],
        [0.16, 0.52, 0.58],
    );
    image.png()
}

/// The certified (or per-segment) mesh of a surface, with unit normals.
fn tessellate(
    surface: &Surface,
    sampling: &SurfaceSampling,
) -> Result<SurfaceSamples, Box<dyn Error>> {
    let mut job = SurfaceJob::new(Derivatives::None, true);
    job.push(surface.fit(), sampling.clone())?;
    Ok(job.evaluate_cpu().remove(0))
}

/// A torus of radii `big` and `small` as a rational bicubic: the tensor product of two
/// circles of four rational arcs each (each the exact quadratic quarter arc raised to degree
/// 3), P_ij = ((R + r x_j) X_i, (R + r x_j) Y_i, r y_j), w_ij = w_i w_j.
fn torus(big: f64, small: f64) -> Result<Surface, Box<dyn Error>> {
    let inner = std::f64::consts::SQRT_2 / (1.0 + std::f64::consts::SQRT_2);
    let weight = (1.0 + std::f64::consts::SQRT_2) / 3.0;
    let mut circle = Vec::new();
    for q in 0..4 {
        let (s, c) = (f64::from(q) * std::f64::consts::FRAC_PI_2).sin_cos();
        let (s, c) = (s.round(), c.round());
        circle.push(([c, s], 1.0));
        circle.push(([c - inner * s, s + inner * c], weight));
        circle.push(([-s + inner * c, c + inner * s], weight));
    }
    circle.push(circle[0]);
    let mut knots = vec![0.0; 4];
    for q in 1..4 {
        knots.extend([f64::from(q); 3]);
    }
    knots.extend([4.0; 4]);
    let n = circle.len();
    let (mut coords, mut weights) = (Vec::new(), Vec::new());
    for (a, wa) in &circle {
        for (b, wb) in &circle {
            let radius = big + small * b[0];
            coords.extend([radius * a[0], radius * a[1], small * b[1]]);
            weights.push(wa * wb);
        }
    }
    let kind = SurfaceKind::Nurbs {
        knots_u: knots.clone(),
        knots_v: knots,
        weights: Some(weights),
    };
    Ok(Surface::new(kind, Net::new(3, n, n, coords)?)?)
}

/// An orthographic view: turn about z by `yaw`, tilt toward the viewer by `pitch`, about
/// `center`, `scale` pixels per unit.
struct View {
    rows: [[f64; 3]; 3],
    center: [f64; 3],
    scale: f64,
}

impl View {
    fn new(yaw: f64, pitch: f64, center: [f64; 3], scale: f64) -> Self {
        let (sy, cy) = yaw.sin_cos();
        let (sp, cp) = pitch.sin_cos();
        // Screen x, screen y (up), depth (toward the viewer): x, y and x × y.
        let rows = [
            [cy, -sy, 0.0],
            [sp * sy, sp * cy, cp],
            [-cp * sy, -cp * cy, sp],
        ];
        Self {
            rows,
            center,
            scale,
        }
    }

    fn apply(&self, p: &[f64]) -> [f64; 3] {
        let d = [
            p[0] - self.center[0],
            p[1] - self.center[1],
            p[2] - self.center[2],
        ];
        self.rows.map(|r| r[0] * d[0] + r[1] * d[1] + r[2] * d[2])
    }
}

/// An RGB image with a depth buffer, drawn at `SUPER` times the output's resolution.
struct Image {
    width: usize,
    height: usize,
    color: Vec<[f64; 3]>,
    depth: Vec<f64>,
}

impl Image {
    fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            color: vec![[1.0; 3]; width * height],
            depth: vec![f64::NEG_INFINITY; width * height],
        }
    }

    /// Rasterizes `mesh` seen through `view`, centred at `at` (output pixels), in `base`
    /// colour lit by a key light and an ambient term through the interpolated normals (both
    /// sides lit: the teapot's patches do not all face out).
    fn draw(&mut self, mesh: &SurfaceSamples, view: &View, at: [f64; 2], base: [f64; 3]) {
        let s = SUPER as f64;
        let screen: Vec<[f64; 3]> = mesh
            .points
            .chunks_exact(3)
            .map(|p| {
                let q = view.apply(p);
                [
                    s * (at[0] + view.scale * q[0]),
                    s * (at[1] - view.scale * q[1]),
                    q[2],
                ]
            })
            .collect();
        let normals: Vec<[f64; 3]> = mesh
            .normals
            .as_deref()
            .unwrap_or_default()
            .chunks_exact(3)
            .map(|n| {
                view.apply(&[
                    n[0] + view.center[0],
                    n[1] + view.center[1],
                    n[2] + view.center[2],
                ])
            })
            .collect();
        let light = normalize([-0.4, 0.6, 0.7]);
        for t in mesh.triangles.as_deref().unwrap_or_default() {
            let [a, b, c] = t.map(|i| screen[i as usize]);
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if area.abs() < 1e-12 {
                continue;
            }
            let x0 = a[0].min(b[0]).min(c[0]).floor().max(0.0) as usize;
            let x1 = (a[0].max(b[0]).max(c[0]).ceil() as usize).min(self.width - 1);
            let y0 = a[1].min(b[1]).min(c[1]).floor().max(0.0) as usize;
            let y1 = (a[1].max(b[1]).max(c[1]).ceil() as usize).min(self.height - 1);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                    let wa = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
                    let wb = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
                    let wc = 1.0 - wa - wb;
                    if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                        continue;
                    }
                    let z = wa * a[2] + wb * b[2] + wc * c[2];
                    let i = y * self.width + x;
                    if z <= self.depth[i] {
                        continue;
                    }
                    self.depth[i] = z;
                    let [na, nb, nc] = t.map(|v| normals[v as usize]);
                    let n = normalize([0, 1, 2].map(|k| wa * na[k] + wb * nb[k] + wc * nc[k]));
                    let lit = (n[0] * light[0] + n[1] * light[1] + n[2] * light[2]).abs();
                    let shade = 0.25 + 0.75 * lit;
                    let rim = 0.35 * lit.powi(24);
                    self.color[i] = base.map(|c| (c * shade + rim).min(1.0));
                }
            }
        }
    }

    /// The image averaged down by `SUPER` and encoded as an 8-bit RGB PNG.
    fn png(&self) -> Result<Vec<u8>, Box<dyn Error>> {
        let (w, h) = (self.width / SUPER, self.height / SUPER);
        let mut pixels = Vec::with_capacity(w * h * 3);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0.0; 3];
                for dy in 0..SUPER {
                    for dx in 0..SUPER {
                        let c = self.color[(y * SUPER + dy) * self.width + x * SUPER + dx];
                        for k in 0..3 {
                            sum[k] += c[k];
                        }
                    }
                }
                let n = (SUPER * SUPER) as f64;
                pixels.extend(sum.map(|v| (v / n * 255.0).round() as u8));
            }
        }
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, w as u32, h as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&pixels)?;
        writer.finish()?;
        Ok(out)
    }
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-300);
    v.map(|x| x / n)
}

/// The committed picture is what the crate draws now.
#[cfg(test)]
mod tests {
    #[test]
    fn the_committed_picture_is_not_stale() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/surfaces.png");
        let committed = std::fs::read(path).unwrap_or_else(|e| panic!("docs/surfaces.png: {e}"));
        assert!(
            committed == super::picture().unwrap(),
            "docs/surfaces.png is stale: run `cargo run -p splinegpu --example surfaces -- docs` \
             from the repository root and commit the result"
        );
    }
}
