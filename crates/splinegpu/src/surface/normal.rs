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

use crate::surface::patch::Patch;

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

/// The unit normal of a 3-D patch at local (u, v), whose local first derivatives (as
/// [`Patch::local_derivatives`] gives them) are `su` and `sv`.
#[must_use]
pub fn unit_normal(patch: &Patch<'_>, u: f64, v: f64, su: [f64; 3], sv: [f64; 3]) -> [f64; 3] {
    let n = cross(su, sv);
    let length = norm(n);
    let [size_u, size_v] = patch.derivative_sizes();
    if length > DEGENERATE_ANGLE * norm(su) * norm(sv) && length > DEGENERATE_SIZE * size_u * size_v
    {
        return n.map(|x| x / length);
    }
    limit_normal(patch, u, v)
}

/// Vertices whose normals [`block_normals`] forms together.
pub(crate) const BLOCK: usize = 64;

/// The local S_u and S_v of up to [`BLOCK`] vertices, each coordinate in its own array, and
/// s_u s_v of each vertex's patch: what their normals are formed from.
pub(crate) struct NormalBlock {
    pub(crate) su: [[f64; BLOCK]; 3],
    pub(crate) sv: [[f64; BLOCK]; 3],
    pub(crate) sizes: [f64; BLOCK],
}

impl Default for NormalBlock {
    fn default() -> Self {
        NormalBlock {
            su: [[0.0; BLOCK]; 3],
            sv: [[0.0; BLOCK]; 3],
            sizes: [0.0; BLOCK],
        }
    }
}

impl NormalBlock {
    /// Vertex `j`'s local S_u and S_v (3-D: nothing is kept of other dimensions, which have no
    /// normals) and its patch's sizes.
    #[inline]
    pub(crate) fn put(&mut self, j: usize, su: &[f64], sv: &[f64], patch: &Patch<'_>) {
        if let ([ux, uy, uz], [vx, vy, vz]) = (su, sv) {
            let ([bx, by, bz], [cx, cy, cz]) = (&mut self.su, &mut self.sv);
            (bx[j], by[j], bz[j]) = (*ux, *uy, *uz);
            (cx[j], cy[j], cz[j]) = (*vx, *vy, *vz);
            let [size_u, size_v] = patch.derivative_sizes();
            self.sizes[j] = size_u * size_v;
        }
    }

    /// The unit normals of the first `len` vertices as [`unit_normal`] gives them, in lanes:
    /// n = S_u × S_v, and where |n|² is above both noise floors (squared) and within
    /// [1e-250, 1e250], n / |n| with one square root and one division. Returns which vertices
    /// passed; the others (degenerate or far out of range) are left for [`unit_normal`].
    pub(crate) fn normals(&self, len: usize, out: &mut [[f64; BLOCK]; 3]) -> [bool; BLOCK] {
        let mut regular = [false; BLOCK];
        let ([ux, uy, uz], [vx, vy, vz]) = (&self.su, &self.sv);
        for j in 0..len.min(BLOCK) {
            let n = [
                uy[j] * vz[j] - uz[j] * vy[j],
                uz[j] * vx[j] - ux[j] * vz[j],
                ux[j] * vy[j] - uy[j] * vx[j],
            ];
            let n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            let su2 = ux[j] * ux[j] + uy[j] * uy[j] + uz[j] * uz[j];
            let sv2 = vx[j] * vx[j] + vy[j] * vy[j] + vz[j] * vz[j];
            let size = DEGENERATE_SIZE * self.sizes[j];
            // `&`, not `&&`: no branch in the lanes.
            let ok = (n2 > DEGENERATE_ANGLE * DEGENERATE_ANGLE * su2 * sv2)
                & (n2 > size * size)
                & (1e-250..=1e250).contains(&n2);
            let inverse = 1.0 / n2.sqrt();
            for k in 0..3 {
                out[k][j] = n[k] * inverse;
            }
            regular[j] = ok;
        }
        regular
    }
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
    let mut p = [[0.0; PRODUCT]; 3];
    let mut q = [[0.0; PRODUCT]; 3];
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
    let size = |f: &[[f64; PRODUCT]; 3]| {
        norm([0, 1, 2].map(|k| f[k].iter().map(|c| c.abs()).sum::<f64>()))
    };
    let threshold = NOISE * size(&p) * size(&q);
    // c = P × Q, coefficient by coefficient.
    let terms = 2 * PRODUCT - 1;
    for order in 0..terms {
        let coefficient =
            |f: &[[f64; PRODUCT]; 3], k: usize, i: usize| f[k].get(i).copied().unwrap_or(0.0);
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

/// Coefficients of a bicubic's value or derivative along a ray: powers of t up to 6.
const RAY: usize = 7;
/// Coefficients of a product of two of them: powers up to 12.
const PRODUCT: usize = 2 * RAY - 1;

/// The polynomial in t of ∂^(order_u + order_v) f / ∂u^order_u ∂v^order_v along
/// (u, v) = origin + t · direction, where f = Σ value(a, b) u^a v^b (a, b in 0..4); coefficients
/// of t^0, t^1, ... (7 of them).
fn along_ray(
    value: &dyn Fn(usize, usize) -> f64,
    order_u: usize,
    order_v: usize,
    origin: [f64; 2],
    direction: [f64; 2],
) -> [f64; RAY] {
    let mut out = [0.0; RAY];
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

/// The coefficients of (x0 + t dx)^m in powers of t (m <= 3: the first m + 1 of 4).
fn binomial_power(x0: f64, dx: f64, m: usize) -> [f64; 4] {
    let mut out = [1.0, 0.0, 0.0, 0.0];
    for n in 0..m {
        for i in (0..=n + 1).rev() {
            out[i] = out[i] * x0 + if i > 0 { out[i - 1] * dx } else { 0.0 };
        }
    }
    out
}

fn multiply(a: &[f64; RAY], b: &[f64; RAY]) -> [f64; PRODUCT] {
    let mut out = [0.0; PRODUCT];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

fn subtract(a: &[f64; PRODUCT], b: &[f64; PRODUCT]) -> [f64; PRODUCT] {
    std::array::from_fn(|i| a[i] - b[i])
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
