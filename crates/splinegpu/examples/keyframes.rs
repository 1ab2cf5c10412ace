//! Key frames in R^30 (seed 001 §6): a stick figure of 15 vertices, each frame one point in
//! R^30, interpolated by one natural (relaxed) cubic spline to 24 frames per time unit.
//!
//! `cargo run --example keyframes -- out/keyframes.csv` writes one row per frame: the frame
//! number, its time and the 30 coordinates (x0, y0, .. x14, y14); key frames are marked.

use std::error::Error;
use std::fmt::Write as _;

use splinegpu::{
    Curve, CurveKind, Derivatives, EndCondition, EvalJob, GpuContext, Points, Sampling,
};

/// The figure's 15 vertices at rest: head, neck, shoulders, elbows, hands, hips, knees, feet...
const REST: [[f64; 2]; 15] = [
    [0.0, 1.8],
    [0.0, 1.55],
    [-0.2, 1.5],
    [0.2, 1.5],
    [-0.3, 1.2],
    [0.3, 1.2],
    [-0.35, 0.95],
    [0.35, 0.95],
    [0.0, 1.0],
    [-0.12, 0.95],
    [0.12, 0.95],
    [-0.15, 0.5],
    [0.15, 0.5],
    [-0.15, 0.0],
    [0.15, 0.0],
];

/// Key frame at time `t`: the figure waves its arms and bends its knees by `phase`.
fn key_frame(phase: f64, shift: f64) -> Vec<f64> {
    let mut frame = Vec::with_capacity(30);
    for (i, [x, y]) in REST.iter().enumerate() {
        let (dx, dy) = match i {
            4 | 6 => (-0.1 * phase, 0.4 * phase), // left elbow and hand rise
            5 | 7 => (0.1 * phase, -0.2 * phase), // right arm swings down
            11 | 12 => (0.1 * phase, -0.05 * phase.abs()), // knees bend
            _ => (0.0, 0.0),
        };
        frame.extend([x + dx + shift, y + dy]);
    }
    frame
}

fn main() -> Result<(), Box<dyn Error>> {
    let output = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "out/keyframes.csv".to_string());

    // 1. Five key frames at uneven times, each a point in R^30; the figure drifts right.
    let times = [0.0, 1.0, 1.5, 3.0, 4.0];
    let phases = [0.0, 1.0, -0.5, 0.8, 0.0];
    let coords: Vec<f64> = times
        .iter()
        .zip(phases)
        .flat_map(|(&t, p)| key_frame(p, 0.3 * t))
        .collect();
    let points = Points::new(30, coords)?;

    // 2. One natural cubic spline through them: C2 motion, relaxed at both ends.
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: Some(times.to_vec()),
    };
    let curve = Curve::new(kind, points)?;

    // 3. Sample 24 frames per time unit: t = j / 24 for j = 0..=96.
    let frames: Vec<f64> = (0..=96).map(|j| f64::from(j) / 24.0).collect();
    let mut job = EvalJob::new(Derivatives::None);
    job.push(&curve, &Sampling::At(frames.clone()))?;
    let values: Vec<f64> = match GpuContext::new() {
        Ok(gpu) => gpu
            .evaluate(&job)?
            .curve(0)
            .points
            .iter()
            .map(|&v| f64::from(v))
            .collect(),
        Err(e) => {
            eprintln!("no GPU ({e}); using the CPU reference");
            splinegpu::evaluate_reference(&job).curve(0).points.to_vec()
        }
    };

    // 4. One row per frame; key frames are the rows whose time is a key time.
    let mut csv = String::from("frame,t,key");
    for v in 0..15 {
        write!(csv, ",x{v},y{v}")?;
    }
    csv.push('\n');
    for (j, (t, frame)) in frames.iter().zip(values.chunks_exact(30)).enumerate() {
        write!(
            csv,
            "{j},{t:.5},{}",
            if times.contains(t) { "*" } else { "" }
        )?;
        for v in frame {
            write!(csv, ",{v:.5}")?;
        }
        csv.push('\n');
    }
    if let Some(dir) = std::path::Path::new(&output).parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(&output, csv)?;
    println!(
        "wrote {} frames of 30 coordinates to {output}",
        frames.len()
    );
    Ok(())
}
