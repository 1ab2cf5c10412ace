//! The curves the geometric-sampling tests run on and an independent arc length (adaptive
//! Simpson quadrature of the speed): shared by path with the GPU harness.
#![allow(
    dead_code,
    reason = "each test binary uses a different subset of these helpers"
)]

use crate::support::Rng;
use splinegpu::{Basis, Curve, CurveKind, EndCondition, Ends, Points, SegmentTable};

pub(crate) const DIMS: [usize; 5] = [1, 2, 3, 30, 64];

/// |dP/dt| at t, from the curve's own segments (located here, not by the code under test).
pub(crate) fn speed(table: &SegmentTable, t: f64) -> f64 {
    let knots = table.knots();
    let i = (knots.partition_point(|&k| k <= t).max(1) - 1).min(table.len() - 1);
    let segment = table.segment(i);
    let u = ((t - knots[i]) / segment.dt()).clamp(0.0, 1.0);
    let mut d = [0.0; splinegpu::MAX_DIM];
    segment.deriv(u, &mut d[..table.dim()]);
    d.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// ∫ f over [a, b] by adaptive Simpson quadrature to `tol`: a method of its own, independent
/// of the code's Gauss–Legendre pieces. A piece's tolerance never drops below `floor` times
/// its width: where f is all but zero (a standstill of the curve) its rounding noise would
/// otherwise pass every halving of the tolerance and split the piece 2^45 ways (a property
/// test met such a curve and ran for minutes).
pub(crate) fn simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64, floor: f64) -> f64 {
    fn rule(fa: f64, fm: f64, fb: f64, h: f64) -> f64 {
        h / 6.0 * (fa + 4.0 * fm + fb)
    }
    #[allow(
        clippy::too_many_arguments,
        reason = "the recursion carries its endpoints' values"
    )]
    fn step(
        f: &dyn Fn(f64) -> f64,
        (a, b): (f64, f64),
        fa: f64,
        fm: f64,
        fb: f64,
        whole: f64,
        (tol, floor): (f64, f64),
        depth: u32,
    ) -> f64 {
        let m = 0.5 * (a + b);
        let (lm, rm) = (f(0.5 * (a + m)), f(0.5 * (m + b)));
        let (left, right) = (rule(fa, lm, fm, m - a), rule(fm, rm, fb, b - m));
        // Below a few ulps of the piece's own value, halving the tolerance only chases rounding.
        let tol = tol
            .max(4.0 * f64::EPSILON * (left + right).abs())
            .max(floor * (b - a));
        if depth > 45 || (left + right - whole).abs() <= 15.0 * tol {
            return left + right + (left + right - whole) / 15.0;
        }
        step(f, (a, m), fa, lm, fm, left, (0.5 * tol, floor), depth + 1)
            + step(f, (m, b), fm, rm, fb, right, (0.5 * tol, floor), depth + 1)
    }
    let (fa, fm, fb) = (f(a), f(0.5 * (a + b)), f(b));
    step(
        f,
        (a, b),
        fa,
        fm,
        fb,
        rule(fa, fm, fb, b - a),
        (tol, floor),
        0,
    )
}

/// The curve's length from t_0 to each of `ts` (sorted), by [`simpson`] between them.
///
/// Every segment is first cut into 256 equal cells and the rule adapts within each: an adaptive
/// rule alone can step over a narrow dip of the speed (where P' nearly vanishes) without seeing
/// it.
pub(crate) fn lengths_at(table: &SegmentTable, ts: &[f64], tol: f64) -> Vec<f64> {
    let f = |t: f64| speed(table, t);
    let knots = table.knots();
    let grid: Vec<f64> = knots
        .windows(2)
        .flat_map(|k| (0..256).map(move |i| k[0] + (k[1] - k[0]) * f64::from(i) / 256.0))
        .collect();
    // The floor: 64 ulps of the mean speed over the grid, per unit of t (an error far below the
    // 1e-10 of the length the tests check).
    let mean_speed = grid.iter().map(|&t| f(t)).sum::<f64>() / grid.len() as f64;
    let floor = 64.0 * f64::EPSILON * mean_speed;
    let mut s = vec![0.0];
    for w in ts.windows(2) {
        let mut cuts = vec![w[0]];
        cuts.extend(grid.iter().copied().filter(|&k| k > w[0] && k < w[1]));
        cuts.push(w[1]);
        // Each cell's share of the tolerance, by its width.
        let span = knots[knots.len() - 1] - knots[0];
        let piece: f64 = cuts
            .windows(2)
            .map(|c| simpson(&f, c[0], c[1], tol * (c[1] - c[0]) / span, floor))
            .sum();
        s.push(s[s.len() - 1] + piece);
    }
    s
}

/// The curve's length L by [`lengths_at`], and the largest |s(t_j) − j L/(m − 1)| over the m
/// samples `ts`, as a fraction of L.
pub(crate) fn spacing_error(table: &SegmentTable, ts: &[f64]) -> (f64, f64) {
    let (t0, t1) = table.t_range();
    let total = lengths_at(table, &[t0, t1], 1e-15)[1];
    let s = lengths_at(table, ts, 1e-15 * total.max(1e-300));
    let last = (ts.len() - 1) as f64;
    let error = (s.iter().enumerate())
        .map(|(j, s_j)| (s_j - total * j as f64 / last).abs() / total.max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max);
    (total, error)
}

pub(crate) fn uniform_kinds() -> Vec<CurveKind> {
    let mut bases = crate::support::bases();
    // A Bezier matrix on sliding windows: segments that do not join.
    bases.push(Basis::Matrix(splinegpu::basis::bezier_rows()));
    let mut kinds = Vec::new();
    for basis in bases {
        for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
            kinds.push(CurveKind::Uniform {
                basis: basis.clone(),
                ends,
            });
        }
    }
    kinds.push(CurveKind::Bezier);
    kinds
}

/// Curves of every family in `dim` dimensions (local bias and tension too), with the awkward ones: interpolating knots
/// spaced up to 1e6 apart, a curve near 1e6, a cusp, and coincident control points.
pub(crate) fn curves(dim: usize) -> Vec<Curve> {
    let mut rng = Rng(dim as u64 * 31 + 7);
    let mut out: Vec<Curve> = uniform_kinds()
        .into_iter()
        .map(|kind| Curve::new(kind, rng.points(7, dim, -3.0, 3.0)).unwrap())
        .collect();
    for ends in [Ends::Control, Ends::Repeat, Ends::Closed] {
        let kind = crate::support::local_beta(&mut rng, ends, 7);
        out.push(Curve::new(kind, rng.points(7, dim, -3.0, 3.0)).unwrap());
    }
    let t = vec![0.0, 1e-6, 1.0, 1.0 + 1e-6, 1e3];
    for condition in [
        EndCondition::Natural,
        EndCondition::NotAKnot,
        EndCondition::Clamped {
            start: vec![1.0; dim],
            end: vec![-1.0; dim],
        },
    ] {
        let kind = CurveKind::Interpolating {
            condition,
            t: Some(t.clone()),
        };
        out.push(Curve::new(kind, rng.points(5, dim, -3.0, 3.0)).unwrap());
    }
    // Near 1e6.
    let far = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Repeat,
    };
    out.push(Curve::new(far, rng.points(6, dim, 1e6 - 2.0, 1e6 + 2.0)).unwrap());
    // A cusp (Bezier (0,0), (1,1), (0,1), (1,0) in the first two coordinates), and a standstill:
    // four equal B-spline points make a stretch where P' vanishes.
    let mut cusp = vec![0.0; 4 * dim];
    for (i, p) in [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0]]
        .iter()
        .enumerate()
    {
        for k in 0..dim.min(2) {
            cusp[i * dim + k] = p[k];
        }
    }
    out.push(Curve::new(CurveKind::Bezier, Points::new(dim, cusp).unwrap()).unwrap());
    let mut still = rng.points(3, dim, -1.0, 1.0).coords().to_vec();
    let repeated = still[dim..2 * dim].to_vec();
    for _ in 0..4 {
        still.extend_from_slice(&repeated);
    }
    still.extend(rng.points(2, dim, -1.0, 1.0).coords());
    let bspline = CurveKind::Uniform {
        basis: Basis::BSpline,
        ends: Ends::Control,
    };
    out.push(Curve::new(bspline, Points::new(dim, still).unwrap()).unwrap());
    // Rational B-splines: weights in [0.1, 10] on uneven knots, and one near 1e6.
    for (knots, offset) in [
        (vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 3.0, 3.0, 3.0, 3.0], 0.0),
        (vec![0.0, 0.0, 0.0, 0.0, 1e-3, 1.0, 3.0, 3.0, 3.0, 3.0], 1e6),
    ] {
        let weights = (0..6).map(|_| 10f64.powf(rng.range(-1.0, 1.0))).collect();
        let kind = CurveKind::Nurbs {
            knots,
            weights: Some(weights),
        };
        let points = rng.points(6, dim, offset - 3.0, offset + 3.0);
        out.push(Curve::new(kind, points).unwrap());
    }
    out
}
