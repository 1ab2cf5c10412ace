//! The accuracy the f32 GPU path promises against the f64 reference (CLI contract,
//! "Accuracy the tool promises"), as a bound per sample and coordinate.
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
//! norm), so this is never looser than the contract. Nothing but the ulp terms grows with the
//! distance from the origin: the host forms the coefficients in f64 and splits D into a f32
//! value and its f32 remainder (see [`gpu::layout::pack`](crate::gpu::layout::pack)).

use crate::segment::Segment;

/// Relative position tolerance of the GPU path, against max(E, |A| + |B| + |C|).
pub const POSITION_TOLERANCE: f64 = 1e-5;

/// Relative derivative tolerance of the GPU path, against the derivative's coefficient scale.
pub const DERIVATIVE_TOLERANCE: f64 = 1e-4;

/// The f32 spacing at |x|: the distance from |x| (rounded to f32) to the next f32 up.
#[must_use]
pub fn ulp_f32(x: f64) -> f64 {
    let a = (x.abs() as f32).min(f32::MAX);
    f64::from(a.next_up()) - f64::from(a)
}

/// The largest error the GPU path may make in coordinate `k` of derivative `order` (0, 1 or 2)
/// of a sample on `segment`, whose curve has extent `extent`, when the exact value is `value`.
#[must_use]
pub fn gpu_bound(segment: &Segment<'_>, extent: f64, order: usize, k: usize, value: f64) -> f64 {
    let [a, b, c, d] = segment.power();
    let (a, b, c, d) = (a[k].abs(), b[k].abs(), c[k].abs(), d[k].abs());
    let dt = segment.dt();
    let scale = match order {
        0 => {
            let s = a + b + c;
            return POSITION_TOLERANCE * extent.max(s) + 4.0 * ulp_f32(d + s) + ulp_f32(value);
        }
        1 => (3.0 * a + 2.0 * b + c) / dt,
        _ => (6.0 * a + 2.0 * b) / (dt * dt),
    };
    DERIVATIVE_TOLERANCE * scale + ulp_f32(value)
}
