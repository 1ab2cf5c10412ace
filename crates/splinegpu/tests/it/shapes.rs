//! Shapes more than one test binary uses: a weighted nurbs circle, a rational torus, the Utah
//! teapot and a net of constant patches. Shared by path (`#[path = "../it/shapes.rs"]`) with the GPU harness.
#![allow(
    dead_code,
    reason = "each test binary uses a different subset of these shapes"
)]

use splinegpu::surface::{Net, Surface, SurfaceKind};
use splinegpu::{Curve, CurveKind, Points};

/// The 13 control points (x, y) and weights of a unit circle as four rational cubic arcs (each
/// the exact quadratic quarter arc raised to degree 3), and its knots.
fn circle() -> (Vec<[f64; 2]>, Vec<f64>, Vec<f64>) {
    let inner = std::f64::consts::SQRT_2 / (1.0 + std::f64::consts::SQRT_2);
    let weight = (1.0 + std::f64::consts::SQRT_2) / 3.0;
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for q in 0..4 {
        let (s, c) = (f64::from(q) * std::f64::consts::FRAC_PI_2).sin_cos();
        let (s, c) = (s.round(), c.round());
        points.push([c, s]);
        points.push([c - inner * s, s + inner * c]);
        points.push([-s + inner * c, c + inner * s]);
        weights.extend([1.0, weight, weight]);
    }
    points.push(points[0]);
    weights.push(1.0);
    let mut knots = vec![0.0; 4];
    for q in 1..4 {
        knots.extend([f64::from(q); 3]);
    }
    knots.extend([4.0; 4]);
    (points, weights, knots)
}

/// A torus of radii `big` and `small` about `center`, as a rational nurbs surface: the tensor
/// product of two circles, P_ij = ((R + r x_j) X_i, (R + r x_j) Y_i, r y_j), w_ij = w_i w_j.
pub(crate) fn torus_surface(big: f64, small: f64, center: [f64; 3]) -> Surface {
    let (c, w, knots) = circle();
    let n = c.len();
    let mut coords = Vec::new();
    let mut weights = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let radius = big + small * c[j][0];
            coords.extend([
                center[0] + radius * c[i][0],
                center[1] + radius * c[i][1],
                center[2] + small * c[j][1],
            ]);
            weights.push(w[i] * w[j]);
        }
    }
    let kind = SurfaceKind::Nurbs {
        knots_u: knots.clone(),
        knots_v: knots,
        weights: Some(weights),
    };
    Surface::new(kind, Net::new(3, n, n, coords).unwrap()).unwrap()
}

/// The Utah teapot (Newell's 32 Bezier patches on 306 points), as the command line's example
/// document holds it.
pub(crate) fn teapot() -> Surface {
    let text = include_str!("../../../splinegpu-cli/examples/teapot.json");
    let doc: serde_json::Value = serde_json::from_str(text).unwrap();
    let surface = &doc["surfaces"][0];
    let coords: Vec<f64> = surface["points"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect();
    let patches = surface["patches"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| std::array::from_fn(|k| p[k].as_u64().unwrap() as usize))
        .collect();
    let net = Net::new(3, coords.len() / 3, 1, coords).unwrap();
    Surface::new(SurfaceKind::BezierPatches { patches }, net).unwrap()
}

/// A unit circle as four cubic rational Bezier quarter arcs (the quadratic quarter arc with
/// weight sqrt(2)/2 in the middle, degree-elevated): 13 points, triple interior knots.
pub(crate) fn nurbs_circle() -> (Vec<f64>, Vec<f64>, Curve) {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let (w1, q) = ((1.0 + 2.0 * w) / 3.0, 2.0 * w / (1.0 + 2.0 * w));
    // The first quarter from (1, 0) to (0, 1); the others turned by 90 degrees each.
    let quarter = [[1.0, 0.0], [1.0, q], [q, 1.0]];
    let (mut points, mut weights) = (Vec::new(), Vec::new());
    for turn in 0..4 {
        for (i, [x, y]) in quarter.iter().enumerate() {
            let (x, y) = match turn {
                0 => (*x, *y),
                1 => (-y, *x),
                2 => (-x, -y),
                _ => (*y, -x),
            };
            points.extend([x, y]);
            weights.push(if i == 0 { 1.0 } else { w1 });
        }
    }
    points.extend([1.0, 0.0]);
    weights.push(1.0);
    let knots = vec![
        0., 0., 0., 0., 1., 1., 1., 2., 2., 2., 3., 3., 3., 4., 4., 4., 4.,
    ];
    let kind = CurveKind::Nurbs {
        knots: knots.clone(),
        weights: Some(weights.clone()),
    };
    let curve = Curve::new(kind, Points::new(2, points).unwrap()).unwrap();
    (knots, weights, curve)
}

/// 2 x 2 patches whose basis holds each window's first point (U·M = [1 0 0 0] for every u),
/// so that each patch is the constant corner point of its window, discontinuous at every
/// joint: patch (i, j) has z = 10 i + j. A vertex's value names the patch that evaluated it.
pub(crate) fn constant_patches() -> splinegpu::surface::PatchTable {
    let mut rows = [[0.0; 4]; 4];
    rows[3][0] = 1.0;
    let coords: Vec<f64> = (0..25)
        .flat_map(|p| {
            [
                f64::from(p / 5),
                f64::from(p % 5),
                f64::from(10 * (p / 5) + p % 5),
            ]
        })
        .collect();
    let kind = SurfaceKind::Uniform {
        basis: splinegpu::Basis::Matrix(rows),
        ends: [splinegpu::Ends::Control; 2],
    };
    Surface::new(kind, Net::new(3, 5, 5, coords).unwrap())
        .unwrap()
        .fit()
}

/// The patch row (and column) that owns each of the 5 lines of [`constant_patches`] at
/// per_segment 2: lines 0 and 1 on patch 0; 2 (the joint), 3 and 4 (the end, at 1) on patch 1.
pub(crate) const CONSTANT_PATCH_OWNERS: [f64; 5] = [0.0, 0.0, 1.0, 1.0, 1.0];
