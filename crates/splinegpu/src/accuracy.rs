//! The accuracy the tool promises (docs/input-format.md, "Accuracy the tool promises"; how it
//! is tested: docs/accuracy.md), as a bound per sample and coordinate: for the f32 GPU path
//! against the exact value, and for the f64 CPU path (1e-9 of the same scales).
//!
//! For a sample on a segment P(u) = A u^3 + B u^2 + C u + D of parameter length Δ, in the
//! curve of extent E, coordinate k, with S_k = |A_k| + |B_k| + |C_k|:
//!
//! ```text
//! position:  1e-5 · max(E, S_k) + 4 ulp(M_k) + ulp(value),   M_k = |D_k| + S_k >= max_u |P_k(u)|
//! dP/dt:     1e-4 · (3|A_k| + 2|B_k| + |C_k|) / Δ   + ulp(value)
//! d2P/dt2:   1e-4 · (6|A_k| + 2|B_k|) / Δ^2         + ulp(value)
//! ```
//!
//! ulp(x) is the f32 spacing at |x|. Coordinates are taken one at a time (|A_k| <= |A| for any
//! norm), so this is never looser than the contract.
//!
//! On a rational segment (a weighted NURBS) the contract takes A, B, C, D of the numerator
//! Σ w_j N_j P_j divided by the segment's smallest weight, and multiplies the position's
//! relative term by ρ, the first derivative's by ρ² and the second's by ρ³ (ρ = the largest
//! over the smallest weight of its four control points). The table holds that numerator
//! relative to the origin O = D (see [`Denominator`](crate::Denominator)), so its absolute
//! coefficients are A + O a, B + O b, C + O c (a, b, c of the denominator); M_k is
//! |O_k| + S_k, which bounds |P_k| since W >= 1. Nothing but the ulp terms grows with the
//! distance from the origin: the host forms the coefficients in f64 and splits D into a f32
//! value and its f32 remainder (the GPU packer).

use crate::segment::Segment;

/// Relative position tolerance of the GPU path, against max(E, |A| + |B| + |C|).
pub const POSITION_TOLERANCE: f64 = 1e-5;

/// Relative derivative tolerance of the GPU path, against the derivative's coefficient scale.
pub const DERIVATIVE_TOLERANCE: f64 = 1e-4;

/// Relative tolerance of the f64 CPU path, against the same scales.
pub const CPU_TOLERANCE: f64 = 1e-9;

/// The f32 spacing at |x|: the distance from |x| (rounded to f32) to the next f32 up.
#[must_use]
pub fn ulp_f32(x: f64) -> f64 {
    let a = (x.abs() as f32).min(f32::MAX);
    f64::from(a.next_up()) - f64::from(a)
}

/// The scale the promise is relative to, for coordinate `k` of derivative `order` (0, 1 or 2)
/// on `segment` of a curve of extent `extent`: max(E, S_k), (3|A_k| + 2|B_k| + |C_k|)/Δ or
/// (6|A_k| + 2|B_k|)/Δ², times ρ, ρ² or ρ³ on a rational segment (see the module docs).
#[must_use]
pub fn promise_scale(segment: &Segment<'_>, extent: f64, order: usize, k: usize) -> f64 {
    let [a, b, c, d] = segment.power();
    let (mut a, mut b, mut c) = (a[k], b[k], c[k]);
    // ρ^(order + 1) on a rational segment, with the numerator's absolute coefficients.
    let mut growth = 1.0;
    if let Some(w) = segment.denominator() {
        let [wa, wb, wc, _] = w.coeffs;
        (a, b, c) = (a + d[k] * wa, b + d[k] * wb, c + d[k] * wc);
        growth = w.rho.powi(order as i32 + 1);
    }
    let (a, b, c) = (a.abs(), b.abs(), c.abs());
    let dt = segment.dt();
    growth
        * match order {
            0 => extent.max(a + b + c),
            1 => (3.0 * a + 2.0 * b + c) / dt,
            _ => (6.0 * a + 2.0 * b) / (dt * dt),
        }
}

/// The largest error the GPU path may make in coordinate `k` of derivative `order` (0, 1 or 2)
/// of a sample on `segment`, whose curve has extent `extent`, when the exact value is `value`.
#[must_use]
pub fn gpu_bound(segment: &Segment<'_>, extent: f64, order: usize, k: usize, value: f64) -> f64 {
    let relative = if order == 0 {
        POSITION_TOLERANCE
    } else {
        DERIVATIVE_TOLERANCE
    };
    let mut bound = relative * promise_scale(segment, extent, order, k) + ulp_f32(value);
    if order == 0 {
        let [a, b, c, d] = segment.power();
        bound += 4.0 * ulp_f32(d[k].abs() + a[k].abs() + b[k].abs() + c[k].abs());
    }
    bound
}

/// The largest error the f64 CPU path may make in the same sample: 1e-9 of [`promise_scale`].
#[must_use]
pub fn cpu_bound(segment: &Segment<'_>, extent: f64, order: usize, k: usize) -> f64 {
    CPU_TOLERANCE * promise_scale(segment, extent, order, k)
}

/// The surface promise's scale (contract: "GPU accuracy on a patch") of coordinate `k` of
/// derivative `which` (0: S, 1: S_u, 2: S_v, 3: S_uu, 4: S_uv, 5: S_vv) on `patch`, whose
/// surface has extent `extent`: max(E, Σ_{(a,b) != (0,0)} |A_ab|) for positions, and
/// Σ a |A_ab| / Δu, Σ b |A_ab| / Δv, Σ a(a−1) |A_ab| / Δu², Σ a b |A_ab| / (Δu Δv),
/// Σ b(b−1) |A_ab| / Δv² for the derivatives; a rational patch's (A its numerator relative
/// to its origin over its smallest weight) times ρ^(order + 1).
#[must_use]
pub fn surface_promise_scale(
    patch: &crate::surface::Patch<'_>,
    extent: f64,
    which: usize,
    k: usize,
) -> f64 {
    let [lu, lv] = patch.length();
    let (weight, length): (fn(f64, f64) -> f64, f64) = match which {
        0 => (|_, _| 1.0, 1.0),
        1 => (|a, _| a, lu),
        2 => (|_, b| b, lv),
        3 => (|a, _| a * (a - 1.0), lu * lu),
        4 => (|a, b| a * b, lu * lv),
        _ => (|_, b| b * (b - 1.0), lv * lv),
    };
    let mut sum = 0.0;
    for a in 0..4 {
        for b in 0..4 {
            if a + b > 0 {
                sum += weight(a as f64, b as f64) * patch.coefficient(a, b)[k].abs();
            }
        }
    }
    let order = [0, 1, 1, 2, 2, 2][which.min(5)];
    let rho = patch.rho().powi(order + 1);
    let scale = if which == 0 {
        sum.max(extent)
    } else {
        sum / length
    };
    scale * rho
}

/// The largest error the GPU path may make in coordinate `k` of derivative `which` (as
/// [`surface_promise_scale`]) of a vertex on `patch` when the exact value is `value`: the
/// position's 1e-5 of its scale plus 4 ulp of the patch's largest coordinate plus an ulp of the
/// value, a derivative's 1e-4 of its scale plus an ulp.
#[must_use]
pub fn surface_gpu_bound(
    patch: &crate::surface::Patch<'_>,
    extent: f64,
    which: usize,
    k: usize,
    value: f64,
) -> f64 {
    let relative = if which == 0 {
        POSITION_TOLERANCE
    } else {
        DERIVATIVE_TOLERANCE
    };
    let mut bound = relative * surface_promise_scale(patch, extent, which, k) + ulp_f32(value);
    if which == 0 {
        let largest: f64 = (0..16)
            .map(|ab| patch.coefficient(ab / 4, ab % 4)[k].abs())
            .sum::<f64>();
        bound += 4.0 * ulp_f32(largest);
    }
    bound
}
