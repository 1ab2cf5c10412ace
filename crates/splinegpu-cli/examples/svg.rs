//! Draws a document's curves as an SVG a person can read: one panel per curve, titled with
//! its family and parameters, its control polygon dashed beside the tessellated curve, y up.
//!
//! `cargo run -p splinegpu-cli --example svg -- crates/splinegpu-cli/examples/curves.json out/curves.svg`
//!
//! It tessellates on the GPU (lavapipe where there is no GPU) and falls back to the CPU
//! reference when wgpu finds no adapter at all. Only the first two coordinates are drawn; a
//! 1-D curve is drawn against its parameter t.

use std::error::Error;
use std::fmt::Write as _;

use serde_json::Value;
use splinegpu::{GpuContext, Samples};

/// Panels per row, and each panel's size in pixels.
const COLUMNS: usize = 3;
const PANEL: f64 = 300.0;
/// Room above the panels for the title, and above each panel's plot for its label.
const TITLE: f64 = 56.0;
const LABEL: f64 = 40.0;

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, input, output] = args.as_slice() else {
        return Err("usage: svg INPUT.json OUTPUT.svg".into());
    };
    let text = std::fs::read_to_string(input)?;

    // 1. Parse and check the document, fit every curve, resolve its sampling.
    let job = splinegpu_cli::parse_document(&text)?;
    // The same document as plain JSON, for the labels and the control polygons.
    let document: Value = serde_json::from_str(&text)?;
    let curves = document["curves"].as_array().ok_or("no \"curves\" array")?;

    // 2. Evaluate: on the GPU when there is one (any adapter), else the f64 reference.
    let (polylines, backend) = match GpuContext::new() {
        Ok(gpu) => (
            polylines(&gpu.evaluate(&job)?),
            format!("GPU, {}", gpu.adapter_info().name),
        ),
        Err(e) => {
            eprintln!("svg: no GPU ({e}); drawing the CPU reference");
            (
                polylines(&splinegpu::evaluate_reference(&job)),
                "CPU reference".to_string(),
            )
        }
    };

    // 3. One panel per curve, its drawing fitted to the curve and its control polygon.
    let rows = polylines.len().div_ceil(COLUMNS);
    let (width, height) = (COLUMNS as f64 * PANEL, TITLE + rows as f64 * PANEL);
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {width} {height}\" \
         width=\"{width}\" height=\"{height}\" font-family=\"sans-serif\">\n\
         <rect width=\"{width}\" height=\"{height}\" fill=\"white\"/>\n\
         <text x=\"12\" y=\"26\" font-size=\"18\">{}: {} curves, tessellated by splinegpu</text>\n\
         <text x=\"12\" y=\"46\" font-size=\"12\" fill=\"#555\">{}; dashed: the control \
         points; solid: the curve's samples joined; y up</text>\n",
        escape(input),
        polylines.len(),
        escape(&backend),
    );
    for (c, samples) in polylines.iter().enumerate() {
        let curve = &curves[c];
        let control: Vec<[f64; 2]> = curve["points"]
            .as_array()
            .map(|points| {
                points
                    .iter()
                    .enumerate()
                    .map(|(i, p)| point(p, i))
                    .collect()
            })
            .unwrap_or_default();
        let (x0, y0) = (
            (c % COLUMNS) as f64 * PANEL,
            TITLE + (c / COLUMNS) as f64 * PANEL,
        );
        panel(&mut svg, c, curve, samples, &control, x0, y0)?;
    }
    svg.push_str("</svg>\n");
    std::fs::write(output, svg)?;
    Ok(())
}

/// Draws curve `c` in the panel at (`x0`, `y0`): its label, its control polygon and its
/// samples, fitted into the panel with y up.
fn panel(
    svg: &mut String,
    c: usize,
    curve: &Value,
    samples: &[[f64; 2]],
    control: &[[f64; 2]],
    x0: f64,
    y0: f64,
) -> Result<(), std::fmt::Error> {
    const COLOURS: [&str; 6] = [
        "#d1495b", "#00798c", "#edae49", "#30638e", "#66a182", "#8d6a9f",
    ];
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in samples.iter().chain(control) {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-12);
    let (plot, pad) = (PANEL - LABEL - 24.0, 12.0);
    let scale = plot / span;
    // Centred in the plot; y flipped so that it grows upwards.
    let (cx, cy) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let at = |p: &[f64; 2]| {
        (
            x0 + PANEL / 2.0 + (p[0] - cx) * scale,
            y0 + LABEL + pad + plot / 2.0 - (p[1] - cy) * scale,
        )
    };
    let path = |points: &[[f64; 2]]| {
        (points.iter().map(at))
            .map(|(x, y)| format!("{x:.2},{y:.2}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let colour = COLOURS[c % COLOURS.len()];
    writeln!(
        svg,
        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" \
         stroke=\"#ddd\"/>",
        x0 + 4.0,
        y0 + 4.0,
        PANEL - 8.0,
        PANEL - 8.0
    )?;
    let (family, details) = label(curve);
    writeln!(
        svg,
        "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"14\" fill=\"{colour}\">curve {c}: {}</text>\n\
         <text x=\"{:.1}\" y=\"{:.1}\" font-size=\"11\" fill=\"#555\">{}</text>",
        x0 + 12.0,
        y0 + 22.0,
        escape(&family),
        x0 + 12.0,
        y0 + 37.0,
        escape(&details)
    )?;
    writeln!(
        svg,
        "<polyline fill=\"none\" stroke=\"#999\" stroke-width=\"1\" stroke-dasharray=\"4 3\" \
         points=\"{}\"/>",
        path(control)
    )?;
    for p in control {
        let (x, y) = at(p);
        writeln!(
            svg,
            "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"2.5\" fill=\"#999\"/>"
        )?;
    }
    writeln!(
        svg,
        "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\" points=\"{}\"/>",
        path(samples)
    )
}

/// The curve's family, and the fields that shape it as the document gives them with its
/// point count: (`cardinal`, `ends repeat, tension 1.0; 8 points`).
fn label(curve: &Value) -> (String, String) {
    let kind = curve["kind"].as_str().unwrap_or("?");
    let fields: Vec<String> = (curve.as_object().into_iter().flatten())
        .filter(|(key, _)| !matches!(key.as_str(), "kind" | "points"))
        .map(|(key, value)| match value {
            Value::String(s) => format!("{key} {s}"),
            other => format!("{key} {other}"),
        })
        .collect();
    let points = curve["points"].as_array().map_or(0, Vec::len);
    let details = if fields.is_empty() {
        format!("{points} points")
    } else {
        format!("{}; {points} points", fields.join(", "))
    };
    (kind.to_string(), details)
}

/// A document point's first two coordinates (a 1-D point against its index `i`).
fn point(p: &Value, i: usize) -> [f64; 2] {
    let x = |k: usize| p[k].as_f64().unwrap_or(0.0);
    match p.as_array().map_or(0, Vec::len) {
        1 => [i as f64, x(0)],
        _ => [x(0), x(1)],
    }
}

/// Each curve's samples as 2-D points (a 1-D curve against its t).
fn polylines<F: Copy + Into<f64>>(samples: &Samples<F>) -> Vec<Vec<[f64; 2]>> {
    (0..samples.len())
        .map(|c| {
            let s = samples.curve(c);
            (s.points.chunks_exact(s.dim).zip(s.t))
                .map(|(p, &t)| match p {
                    [x] => [t, (*x).into()],
                    [x, y, ..] => [(*x).into(), (*y).into()],
                    [] => [0.0, 0.0],
                })
                .collect()
        })
        .collect()
}

/// Text safe inside an SVG element.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
