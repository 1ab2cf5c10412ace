//! Tessellates a document and draws the first two coordinates of every curve as an SVG.
//!
//! `cargo run --example svg -- examples/curves.json out/curves.svg`
//!
//! It uses the GPU (lavapipe where there is no GPU) and falls back to the CPU reference when
//! wgpu finds no adapter at all.

use std::error::Error;
use std::fmt::Write as _;

use splinegpu::{GpuContext, Samples};

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, input, output] = args.as_slice() else {
        return Err("usage: svg INPUT.json OUTPUT.svg".into());
    };

    // 1. Parse and check the document, fit every curve, resolve its sampling.
    let job = splinegpu_cli::parse_document(&std::fs::read_to_string(input)?)?;

    // 2. Evaluate: on the GPU when there is one (any adapter), else the f64 reference.
    let curves = match GpuContext::new() {
        Ok(gpu) => polylines(&gpu.evaluate(&job)?),
        Err(e) => {
            eprintln!("no GPU ({e}); using the CPU reference");
            polylines(&splinegpu::evaluate_reference(&job))
        }
    };

    // 3. Fit the drawing to the samples' bounding box and write one polyline per curve.
    let all = curves.iter().flatten();
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in all {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let margin = 0.05 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-9);
    let (w, h) = (hi[0] - lo[0] + 2.0 * margin, hi[1] - lo[1] + 2.0 * margin);
    let colours = [
        "#d1495b", "#00798c", "#edae49", "#30638e", "#66a182", "#8d6a9f",
    ];
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{} {} {w} {h}\" width=\"900\" \
         height=\"{}\">\n<rect x=\"{}\" y=\"{}\" width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n",
        lo[0] - margin,
        lo[1] - margin,
        (900.0 * h / w).round(),
        lo[0] - margin,
        lo[1] - margin,
    );
    for (c, curve) in curves.iter().enumerate() {
        let points: Vec<String> = curve
            .iter()
            .map(|p| format!("{:.4},{:.4}", p[0], p[1]))
            .collect();
        writeln!(
            svg,
            "<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" points=\"{}\"/>",
            colours[c % colours.len()],
            0.004 * w,
            points.join(" ")
        )?;
    }
    svg.push_str("</svg>\n");
    std::fs::write(output, svg)?;
    Ok(())
}

/// Each curve's samples as 2-D points (a 1-D curve is drawn against its sample index).
fn polylines<F: Copy + Into<f64>>(samples: &Samples<F>) -> Vec<Vec<[f64; 2]>> {
    (0..samples.len())
        .map(|c| {
            let s = samples.curve(c);
            s.points
                .chunks_exact(s.dim)
                .enumerate()
                .map(|(i, p)| match p {
                    [x] => [i as f64, (*x).into()],
                    [x, y, ..] => [(*x).into(), (*y).into()],
                    [] => [0.0, 0.0],
                })
                .collect()
        })
        .collect()
}
