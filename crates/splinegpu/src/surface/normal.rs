//! Unit normals of a patch, finite everywhere: the unit vector along S_u × S_v, and where that
//! vanishes (a collapsed edge, a pole: the teapot's lid top and bottom) its limit as (u, v)
//! approaches the point from inside the patch.
//!
//! The limit: along the ray (u, v) = (u0, v0) + t (du, dv) toward the patch's centre,
//! S_u × S_v is a polynomial in t, c(t) = Σ_k c_k t^k, and as t → 0+ its direction tends to
//! that of its first coefficient that is not zero. For a rational patch S = O + Ñ/W,
//! S_u = P / W² and S_v = Q / W² with P = Ñ_u W − Ñ W_u and Q = Ñ_v W − Ñ W_v, so S_u × S_v
//! points along P × Q, again a polynomial along the ray. The coefficients are formed exactly
//! (binomial expansions of the power form), so the limit is the true one, not a nudge inside.

use crate::surface::patch::{Derivs, Patch};

/// Below this fraction of |S_u| |S_v| (or of s_u s_v, the patch's derivative sizes) a cross
/// product is rounding noise in an arbitrary direction: the point is degenerate (contract).
const DEGENERATE_ANGLE: f64 = 1e-12;
/// See [`DEGENERATE_ANGLE`]: the bound against the patch's derivative sizes.
const DEGENERATE_SIZE: f64 = 1e-10;
/// Along the ray, a coefficient of S_u x S_v below this fraction of its factors' sizes is
/// rounding noise (f64's, with a margin); above it, it sets the limit's direction. Lower than
/// [`DEGENERATE_SIZE`]: a point the contract's test calls degenerate only because its patch's
/// power form is large (uneven knots) still has its own cross product as its limit.
const NOISE: f64 = 1e-13;

/// The unit normal of a 3-D patch at local (u, v), whose local derivatives (as
/// [`Patch::local_derivatives`] gives them) are `local`.
#[must_use]
pub fn unit_normal(patch: &Patch<'_>, u: f64, v: f64, local: &Derivs) -> [f64; 3] {
    let (su, sv) = (&local[1], &local[2]);
    let n = cross([su[0], su[1], su[2]], [sv[0], sv[1], sv[2]]);
    let length = norm(n);
    let [size_u, size_v] = patch.derivative_sizes();
    if length > DEGENERATE_ANGLE * norm([su[0], su[1], su[2]]) * norm([sv[0], sv[1], sv[2]])
        && length > DEGENERATE_SIZE * size_u * size_v
    {
        return n.map(|x| x / length);
    }
    limit_normal(patch, u, v)
}

/// The limit of the unit normal at local (u, v) from inside the patch, along the ray toward its
/// centre; (0, 0, 1) where the whole ray is degenerate (a patch collapsed to a curve or a
/// point has no normal).
fn limit_normal(patch: &Patch<'_>, u: f64, v: f64) -> [f64; 3] {
    let (mut du, mut dv) = (0.5 - u, 0.5 - v);
    if du == 0.0 && dv == 0.0 {
        du = 1.0;
        dv = 0.0;
    }
    // Numerator, its u and v derivatives, per coordinate; W and its derivatives.
    let scalar = |value: &dyn Fn(usize, usize) -> f64, order_u: usize, order_v: usize| {
        along_ray(value, order_u, order_v, [u, v], [du, dv])
    };
    let one = |a: usize, b: usize| if a + b == 0 { 1.0 } else { 0.0 };
    let w_of = |a: usize, b: usize| patch.denominator().map_or(one(a, b), |w| w[4 * a + b]);
    let rational = patch.denominator().is_some();
    let w = scalar(&w_of, 0, 0);
    let w_u = scalar(&w_of, 1, 0);
    let w_v = scalar(&w_of, 0, 1);
    let mut p: [Vec<f64>; 3] = Default::default();
    let mut q: [Vec<f64>; 3] = Default::default();
    for k in 0..3 {
        // Ñ: a rational patch's A_00 slot holds its origin, whose numerator term is zero.
        let n_of = |a: usize, b: usize| {
            if rational && a + b == 0 {
                0.0
            } else {
                patch.coefficient(a, b)[k]
            }
        };
        let (n, n_u, n_v) = (
            scalar(&n_of, 0, 0),
            scalar(&n_of, 1, 0),
            scalar(&n_of, 0, 1),
        );
        p[k] = subtract(&multiply(&n_u, &w), &multiply(&n, &w_u));
        q[k] = subtract(&multiply(&n_v, &w), &multiply(&n, &w_v));
    }
    let size =
        |f: &[Vec<f64>; 3]| norm([0, 1, 2].map(|k| f[k].iter().map(|c| c.abs()).sum::<f64>()));
    let threshold = NOISE * size(&p) * size(&q);
    // c = P × Q, coefficient by coefficient.
    let terms = p[0].len() + q[0].len() - 1;
    for order in 0..terms {
        let coefficient =
            |f: &[Vec<f64>; 3], k: usize, i: usize| f[k].get(i).copied().unwrap_or(0.0);
        let mut c = [0.0; 3];
        for i in 0..=order {
            let a = [0, 1, 2].map(|k| coefficient(&p, k, i));
            let b = [0, 1, 2].map(|k| coefficient(&q, k, order - i));
            let x = cross(a, b);
            for k in 0..3 {
                c[k] += x[k];
            }
        }
        let length = norm(c);
        if length > threshold {
            return c.map(|x| x / length);
        }
    }
    [0.0, 0.0, 1.0]
}

/// The polynomial in t of ∂^(order_u + order_v) f / ∂u^order_u ∂v^order_v along
/// (u, v) = origin + t · direction, where f = Σ value(a, b) u^a v^b (a, b in 0..4); coefficients
/// of t^0, t^1, ... (7 of them).
fn along_ray(
    value: &dyn Fn(usize, usize) -> f64,
    order_u: usize,
    order_v: usize,
    origin: [f64; 2],
    direction: [f64; 2],
) -> Vec<f64> {
    let mut out = vec![0.0; 7];
    for a in order_u..4 {
        for b in order_v..4 {
            let c = value(a, b);
            if c == 0.0 {
                continue;
            }
            let factor = falling(a, order_u) * falling(b, order_v);
            let pu = binomial_power(origin[0], direction[0], a - order_u);
            let pv = binomial_power(origin[1], direction[1], b - order_v);
            for (i, x) in pu.iter().enumerate() {
                for (j, y) in pv.iter().enumerate() {
                    out[i + j] += c * factor * x * y;
                }
            }
        }
    }
    out
}

/// a (a − 1) ... (a − m + 1).
fn falling(a: usize, m: usize) -> f64 {
    (0..m).map(|i| (a - i) as f64).product()
}

/// The coefficients of (x0 + t dx)^m in powers of t.
fn binomial_power(x0: f64, dx: f64, m: usize) -> Vec<f64> {
    let mut out = vec![1.0];
    for _ in 0..m {
        let mut next = vec![0.0; out.len() + 1];
        for (i, c) in out.iter().enumerate() {
            next[i] += c * x0;
            next[i + 1] += c * dx;
        }
        out = next;
    }
    out
}

fn multiply(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

fn subtract(a: &[f64], b: &[f64]) -> Vec<f64> {
    (0..a.len().max(b.len()))
        .map(|i| a.get(i).copied().unwrap_or(0.0) - b.get(i).copied().unwrap_or(0.0))
        .collect()
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
