//! Draws the README's figures with the crate itself, as SVG: every family on the same control
//! polygon (as the memo draws them), one curve sampled per segment, by arc length and by
//! tolerance, side by side, each polyline over the curve it stands for, and the kinds people
//! bring (PCHIP and Akima against the natural spline on monotone data, Kochanek–Bartels over
//! Catmull-Rom, knot-vector B-splines, Hermite), and Beta-splines whose bias and tension vary
//! joint by joint over the curve of the same values everywhere.
//!
//! `cargo run -p splinegpu --example figures -- docs` (from the repository root) writes
//! `docs/families.svg`, `docs/samplings.svg`, `docs/kinds.svg` and `docs/local-beta.svg`; its test (`cargo test
//! --example figures`) fails when the committed pictures are not what the crate draws now.

use std::error::Error;
use std::fmt::Write as _;

use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, Ends, EvalJob, HermiteSlopes, PerPoint, Points, Sampling,
    Tcb,
};

/// One panel: a title, the control polygon (if any), the true curve (if it is not the
/// samples themselves) and the samples to draw.
struct Panel {
    title: String,
    polygon: Vec<[f64; 2]>,
    /// The curve, densely sampled, drawn thin under a sampling's polyline.
    curve: Vec<[f64; 2]>,
    samples: Vec<[f64; 2]>,
    /// Draw each sample as a dot.
    dots: bool,
}

/// The control polygon every family is drawn on.
const POLYGON: [[f64; 2]; 7] = [
    [0.0, 0.0],
    [1.0, 2.0],
    [2.5, 2.2],
    [3.0, 0.4],
    [4.5, 0.2],
    [5.0, 2.0],
    [6.2, 1.6],
];

fn main() -> Result<(), Box<dyn Error>> {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs".to_string());
    std::fs::create_dir_all(&dir)?;
    for (name, svg) in figures()? {
        std::fs::write(format!("{dir}/{name}"), svg)?;
    }
    println!(
        "wrote {dir}/families.svg, {dir}/samplings.svg, {dir}/kinds.svg and {dir}/local-beta.svg"
    );
    Ok(())
}

/// The four pictures, by file name.
fn figures() -> Result<[(&'static str, String); 4], Box<dyn Error>> {
    // 1. Every family on the same polygon ("repeat" ends, so each starts and ends near it).
    let coords: Vec<f64> = POLYGON.iter().flatten().copied().collect();
    let families: Vec<(&str, CurveKind)> = vec![
        (
            "cardinal, tension 0.2",
            uniform(Basis::Cardinal { tension: 0.2 }),
        ),
        ("Catmull-Rom (cardinal 0.5)", uniform(Basis::CatmullRom)),
        ("uniform B-spline", uniform(Basis::BSpline)),
        (
            "tensioned B-spline, a = 0.5",
            uniform(Basis::TensionedBSpline { tension: 0.5 }),
        ),
        (
            "Beta-spline, bias 1, tension 10",
            uniform(Basis::Beta {
                bias: 1.0,
                tension: 10.0,
            }),
        ),
        (
            "Beta-spline, bias 3, tension 0",
            uniform(Basis::Beta {
                bias: 3.0,
                tension: 0.0,
            }),
        ),
        ("Bezier (2 segments)", CurveKind::Bezier),
        (
            "natural interpolating",
            CurveKind::Interpolating {
                condition: splinegpu::EndCondition::Natural,
                t: None,
            },
        ),
        (
            "not-a-knot interpolating",
            CurveKind::Interpolating {
                condition: splinegpu::EndCondition::NotAKnot,
                t: None,
            },
        ),
    ];
    let mut panels = Vec::new();
    for (title, kind) in families {
        let curve = Curve::new(kind, Points::new(2, coords.clone())?)?;
        panels.push(Panel {
            title: title.to_string(),
            polygon: POLYGON.to_vec(),
            curve: Vec::new(),
            samples: sample(&curve, &Sampling::PerSegment(32))?,
            dots: false,
        });
    }
    let families = svg(&panels, 3);

    // 2. One curve, three samplings with about the same number of points.
    let curve = Curve::new(uniform(Basis::CatmullRom), Points::new(2, coords)?)?;
    let per_segment = sample(&curve, &Sampling::PerSegment(4))?;
    let n = per_segment.len() as u32;
    let by_length = sample(&curve, &Sampling::ArcLength(n))?;
    let by_tolerance = sample(&curve, &Sampling::Tolerance(0.03))?;
    let dense = sample(&curve, &Sampling::PerSegment(64))?;
    let panels = [
        ("per segment, 4 each", per_segment),
        ("arc length, same count", by_length),
        ("tolerance 0.03", by_tolerance),
    ]
    .map(|(title, samples)| Panel {
        title: format!("{title}: {} points", samples.len()),
        polygon: Vec::new(),
        curve: dense.clone(),
        samples,
        dots: true,
    });
    Ok([
        ("families.svg", families),
        ("samplings.svg", svg(&panels, 3)),
        ("kinds.svg", kinds()?),
        ("local-beta.svg", local_beta()?),
    ])
}

/// Beta-splines with local bias and tension (the memo's "Future"), in red, each over the
/// Beta-spline of its first joint's values at every joint, in grey, on the same polygon
/// ("repeat" ends: a joint at every point, joint j at point j).
fn local_beta() -> Result<String, Box<dyn Error>> {
    let coords: Vec<f64> = POLYGON.iter().flatten().copied().collect();
    let cases: [(&str, [f64; 7], [f64; 7]); 6] = [
        (
            "tension 25 at joint 3, else 0",
            [1.0; 7],
            [0.0, 0.0, 0.0, 25.0, 0.0, 0.0, 0.0],
        ),
        (
            "tension rising 0 .. 30, joint by joint",
            [1.0; 7],
            [0.0, 1.0, 3.0, 6.0, 12.0, 20.0, 30.0],
        ),
        (
            "tension 40 at joints 1, 5, else 0",
            [1.0; 7],
            [0.0, 40.0, 0.0, 0.0, 0.0, 40.0, 0.0],
        ),
        (
            "bias 4 at joint 2, else 1",
            [1.0, 1.0, 4.0, 1.0, 1.0, 1.0, 1.0],
            [0.0; 7],
        ),
        (
            "bias 0.2 at joint 4, else 1",
            [1.0, 1.0, 1.0, 1.0, 0.2, 1.0, 1.0],
            [0.0; 7],
        ),
        (
            "bias 3 at joint 2, tension 15 at 4",
            [1.0, 1.0, 3.0, 1.0, 1.0, 1.0, 1.0],
            [0.0, 0.0, 0.0, 0.0, 15.0, 0.0, 0.0],
        ),
    ];
    let mut panels = Vec::new();
    for (title, bias, tension) in cases {
        let local = CurveKind::LocalBeta {
            ends: Ends::Repeat,
            bias: PerPoint::Each(bias.to_vec()),
            tension: PerPoint::Each(tension.to_vec()),
        };
        let global = uniform(Basis::Beta {
            bias: bias[0],
            tension: tension[0],
        });
        let points = Points::new(2, coords.clone())?;
        panels.push(Panel {
            title: title.to_string(),
            polygon: POLYGON.to_vec(),
            curve: sample(
                &Curve::new(global, points.clone())?,
                &Sampling::PerSegment(32),
            )?,
            samples: sample(&Curve::new(local, points)?, &Sampling::PerSegment(32))?,
            dots: false,
        });
    }
    Ok(svg(&panels, 3))
}

/// Monotone data that a natural spline overshoots: a flat run, a step, a flat run.
const MONOTONE: [[f64; 2]; 7] = [
    [0.0, 0.0],
    [1.0, 0.1],
    [2.0, 0.2],
    [3.0, 1.9],
    [4.0, 2.0],
    [4.6, 2.1],
    [6.2, 2.2],
];

/// The kinds people bring, each on data that shows what it is for.
fn kinds() -> Result<String, Box<dyn Error>> {
    let mut panels = Vec::new();
    // Row 1: interpolation of monotone data (t = x, so each panel is y as a function of x).
    let monotone: Vec<f64> = MONOTONE.iter().flatten().copied().collect();
    let t = Some(MONOTONE.iter().map(|p| p[0]).collect::<Vec<f64>>());
    let shape = |slopes| CurveKind::Hermite {
        slopes,
        t: t.clone(),
    };
    for (title, kind) in [
        (
            "natural: overshoots monotone data",
            CurveKind::Interpolating {
                condition: splinegpu::EndCondition::Natural,
                t: t.clone(),
            },
        ),
        ("pchip: monotone, no overshoot", shape(HermiteSlopes::Pchip)),
        ("akima, method makima", shape(HermiteSlopes::Makima)),
    ] {
        let curve = Curve::new(kind, Points::new(2, monotone.clone())?)?;
        panels.push(Panel {
            title: title.to_string(),
            polygon: MONOTONE.to_vec(),
            curve: Vec::new(),
            samples: sample(&curve, &Sampling::PerSegment(32))?,
            dots: false,
        });
    }
    // Row 2: Kochanek–Bartels over Catmull-Rom (thick grey), one parameter at a time.
    let coords: Vec<f64> = POLYGON.iter().flatten().copied().collect();
    let catmull = Curve::new(
        CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Repeat,
        },
        Points::new(2, coords.clone())?,
    )?;
    let under = sample(&catmull, &Sampling::PerSegment(32))?;
    for (title, tcb) in [
        (
            "Kochanek-Bartels, tension 0.7",
            Tcb {
                tension: PerPoint::All(0.7),
                ..Tcb::default()
            },
        ),
        (
            "continuity 0.8: corners",
            Tcb {
                continuity: PerPoint::All(0.8),
                ..Tcb::default()
            },
        ),
        (
            "bias 0.8, 0, -0.8 in turn",
            Tcb {
                bias: PerPoint::Each([0.8, 0.0, -0.8].repeat(3)[..7].to_vec()),
                ..Tcb::default()
            },
        ),
    ] {
        let kind = CurveKind::KochanekBartels {
            ends: Ends::Repeat,
            tcb,
            t: None,
        };
        let curve = Curve::new(kind, Points::new(2, coords.clone())?)?;
        panels.push(Panel {
            title: title.to_string(),
            polygon: POLYGON.to_vec(),
            curve: under.clone(),
            samples: sample(&curve, &Sampling::PerSegment(32))?,
            dots: false,
        });
    }
    // Row 3: knot-vector B-splines (seven control points, eleven knots) and Hermite.
    for (title, knots) in [
        (
            "nurbs, clamped knots",
            vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0],
        ),
        (
            "nurbs, a triple knot: a corner",
            vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0],
        ),
    ] {
        let kind = CurveKind::Nurbs {
            knots,
            weights: None,
        };
        let curve = Curve::new(kind, Points::new(2, coords.clone())?)?;
        panels.push(Panel {
            title: title.to_string(),
            polygon: POLYGON.to_vec(),
            curve: Vec::new(),
            samples: sample(&curve, &Sampling::PerSegment(32))?,
            dots: false,
        });
    }
    let tangents: Vec<f64> = [[1.0, 0.0]; 7].iter().flatten().copied().collect();
    let hermite = CurveKind::Hermite {
        slopes: HermiteSlopes::Given(tangents),
        t: None,
    };
    let curve = Curve::new(hermite, Points::new(2, coords.clone())?)?;
    panels.push(Panel {
        title: "hermite, every tangent (1, 0)".to_string(),
        polygon: POLYGON.to_vec(),
        curve: Vec::new(),
        samples: sample(&curve, &Sampling::PerSegment(32))?,
        dots: false,
    });
    // Row 4: weights. An exact circle, then one weight raised and lowered on the clamped knots.
    let (polygon, weights) = circle([3.1, 1.1], 1.5);
    let (a, b) = (weights[0], weights[1]);
    let kind = CurveKind::Nurbs {
        knots: CIRCLE_KNOTS.to_vec(),
        weights: Some(weights),
    };
    let curve = Curve::new(
        kind,
        Points::new(2, polygon.iter().flatten().copied().collect())?,
    )?;
    panels.push(Panel {
        title: format!("nurbs circle, weights {a} and {b:.3}"),
        polygon,
        curve: Vec::new(),
        samples: sample(&curve, &Sampling::PerSegment(16))?,
        dots: false,
    });
    for weight in [4.0, 0.25] {
        let mut weights = vec![1.0; 7];
        weights[2] = weight;
        let kind = CurveKind::Nurbs {
            knots: vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0],
            weights: Some(weights),
        };
        let curve = Curve::new(kind, Points::new(2, coords.clone())?)?;
        panels.push(Panel {
            title: format!("nurbs, weight {weight} on point 2, else 1"),
            polygon: POLYGON.to_vec(),
            curve: Vec::new(),
            samples: sample(&curve, &Sampling::PerSegment(32))?,
            dots: false,
        });
    }
    Ok(svg(&panels, 3))
}

/// The circle's knots: four cubic Bezier arcs, each interior knot triple.
const CIRCLE_KNOTS: [f64; 17] = [
    0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0, 4.0, 4.0, 4.0, 4.0,
];

/// The 13 control points and weights of a circle about `center` of radius `r` as four rational
/// cubic arcs: each is the exact quadratic quarter arc (weights 1, sqrt(2)/2, 1 on the corner
/// of its square) raised to degree 3, whose inner points lie on the square's sides, at
/// (P0 + sqrt(2) P1)/(1 + sqrt(2)) and its mirror, with weight (1 + sqrt(2))/3.
fn circle(center: [f64; 2], r: f64) -> (Vec<[f64; 2]>, Vec<f64>) {
    let inner = std::f64::consts::SQRT_2 / (1.0 + std::f64::consts::SQRT_2);
    let weight = (1.0 + std::f64::consts::SQRT_2) / 3.0;
    let at = |x: f64, y: f64| [center[0] + r * x, center[1] + r * y];
    let mut points = Vec::new();
    let mut weights = Vec::new();
    // Quarter q goes from angle q pi/2 to (q + 1) pi/2 through the corner (c, s) + (-s, c).
    for q in 0..4 {
        let (s, c) = (f64::from(q) * std::f64::consts::FRAC_PI_2).sin_cos();
        let (s, c) = (s.round(), c.round());
        points.push(at(c, s));
        points.push(at(c - inner * s, s + inner * c));
        points.push(at(-s + inner * c, c + inner * s));
        weights.extend([1.0, weight, weight]);
    }
    points.push(points[0]);
    weights.push(1.0);
    (points, weights)
}

fn uniform(basis: Basis) -> CurveKind {
    CurveKind::Uniform {
        basis,
        ends: Ends::Repeat,
    }
}

/// The curve's samples as 2-D points (the f64 reference).
fn sample(curve: &Curve, sampling: &Sampling) -> Result<Vec<[f64; 2]>, Box<dyn Error>> {
    let mut job = EvalJob::new(Derivatives::None);
    job.push(curve, sampling)?;
    let samples = splinegpu::evaluate_reference(&job);
    Ok(samples
        .curve(0)
        .points
        .chunks_exact(2)
        .map(|p| [p[0], p[1]])
        .collect())
}

/// The panels in a grid of `columns`, each fitted to the same box, y up.
fn svg(panels: &[Panel], columns: usize) -> String {
    let (w, h, pad): (f64, f64, f64) = (300.0, 170.0, 22.0);
    let rows = panels.len().div_ceil(columns);
    let (lo, hi): ([f64; 2], [f64; 2]) = ([-0.3, -0.6], [6.5, 2.8]);
    let scale = ((w - 2.0 * pad) / (hi[0] - lo[0])).min((h - 2.0 * pad) / (hi[1] - lo[1]));
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" \
         font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" \
         fill=\"white\"/>\n",
        w * columns as f64,
        h * rows as f64
    );
    for (i, panel) in panels.iter().enumerate() {
        let (x0, y0) = ((i % columns) as f64 * w, (i / columns) as f64 * h);
        let at = |p: &[f64; 2]| {
            (
                x0 + pad + (p[0] - lo[0]) * scale,
                y0 + h - pad - (p[1] - lo[1]) * scale,
            )
        };
        let path = |points: &[[f64; 2]]| {
            points
                .iter()
                .map(|p| {
                    let (x, y) = at(p);
                    format!("{x:.2},{y:.2}")
                })
                .collect::<Vec<_>>()
                .join(" ")
        };
        let _ = writeln!(
            out,
            "<text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
            x0 + 8.0,
            y0 + 16.0,
            panel.title
        );
        if !panel.polygon.is_empty() {
            let _ = writeln!(
                out,
                "<polyline fill=\"none\" stroke=\"#999\" stroke-dasharray=\"4 3\" points=\"{}\"/>",
                path(&panel.polygon)
            );
            for p in &panel.polygon {
                let (x, y) = at(p);
                let _ = writeln!(
                    out,
                    "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"2.5\" fill=\"#999\"/>"
                );
            }
        }
        if !panel.curve.is_empty() {
            let _ = writeln!(
                out,
                "<polyline fill=\"none\" stroke=\"#bbb\" stroke-width=\"4\" points=\"{}\"/>",
                path(&panel.curve)
            );
        }
        let _ = writeln!(
            out,
            "<polyline fill=\"none\" stroke=\"#d1495b\" stroke-width=\"1.6\" points=\"{}\"/>",
            path(&panel.samples)
        );
        if panel.dots {
            for p in &panel.samples {
                let (x, y) = at(p);
                let _ = writeln!(
                    out,
                    "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"2.2\" fill=\"#00798c\"/>"
                );
            }
        }
    }
    out.push_str("</svg>\n");
    out
}

/// The committed pictures are what the crate draws now.
#[cfg(test)]
mod tests {
    #[test]
    fn the_committed_pictures_are_not_stale() {
        let docs = concat!(env!("CARGO_MANIFEST_DIR"), "/docs");
        for (name, svg) in super::figures().unwrap() {
            let committed = std::fs::read_to_string(format!("{docs}/{name}"))
                .unwrap_or_else(|e| panic!("docs/{name}: {e}"));
            assert!(
                committed == svg,
                "docs/{name} is stale: run `cargo run -p splinegpu --example figures -- docs` \
                 from the repository root and commit the result"
            );
        }
    }
}
