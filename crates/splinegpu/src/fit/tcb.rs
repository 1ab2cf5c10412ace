//! Kochanek–Bartels splines ("kochanek-bartels"): keyframes with tension T, continuity C and
//! bias B at each point (D. Kochanek and R. Bartels, "Interpolating splines with local tension,
//! continuity, and bias control", SIGGRAPH 1984), as the contract defines them.
//!
//! The points are windowed as the uniform kinds window them ([`Ends`]); the segment from P_i to
//! P_{i+1} (neighbours P_{i−1}, P_{i+2}) is the cubic Hermite piece in u ∈ [0, 1] with
//!
//! ```text
//! dP/du(0) = d_i     = (1−T_i)(1+B_i)(1+C_i)/2 (P_i − P_{i−1}) + (1−T_i)(1−B_i)(1−C_i)/2 (P_{i+1} − P_i)
//! dP/du(1) = e_{i+1} = (1−T_{i+1})(1+B_{i+1})(1−C_{i+1})/2 (P_{i+1} − P_i)
//!                    + (1−T_{i+1})(1−B_{i+1})(1+C_{i+1})/2 (P_{i+2} − P_{i+1})
//! A = 2(P_i − P_{i+1}) + d_i + e_{i+1},  B = 3(P_{i+1} − P_i) − 2 d_i − e_{i+1},  C = d_i,  D = P_i
//! ```
//!
//! Without "t" the knots are 0, 1, ..., segments. With "t" (one value per point, n + 1 for
//! closed ends), the segment spans [t_i, t_{i+1}] and, with Δ_j = t_{j+1} − t_j, d_i is scaled by
//! 2Δ_i/(Δ_{i−1} + Δ_i) and e_{i+1} by 2Δ_i/(Δ_i + Δ_{i+1}); a Δ past the given ones is its
//! neighbour's (repeat ends) or wraps around (closed). T = C = B = 0 without t is Catmull-Rom;
//! C = B = 0 is the cardinal spline of tension (1 − T)/2.

use crate::conventions::Ends;
use crate::error::InputError;

pub use crate::conventions::PerPoint;
use crate::segment::SegmentTable;

/// A Kochanek–Bartels curve's parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Tcb {
    /// Tension T (default 0): 1 stops the curve at the point, −1 rounds it out.
    pub tension: PerPoint,
    /// Continuity C (default 0): other than 0 gives the curve a corner at the point.
    pub continuity: PerPoint,
    /// Bias B (default 0): the tangent leans toward the incoming (> 0) or the outgoing chord.
    pub bias: PerPoint,
}

impl Default for Tcb {
    fn default() -> Self {
        Self {
            tension: PerPoint::All(0.0),
            continuity: PerPoint::All(0.0),
            bias: PerPoint::All(0.0),
        }
    }
}

/// Checks a Kochanek–Bartels curve of `n` points: enough points for its ends, T, C and B finite
/// (one per point where arrays), and t, where given, finite, strictly increasing and one value
/// per point (n + 1 for closed ends).
///
/// # Errors
/// The first rule broken, naming its field.
pub(crate) fn check(ends: Ends, tcb: &Tcb, t: Option<&[f64]>, n: usize) -> Result<(), InputError> {
    ends.check_points(n)?;
    tcb.tension.check("tension", n, "point")?;
    tcb.continuity.check("continuity", n, "point")?;
    tcb.bias.check("bias", n, "point")?;
    let Some(t) = t else { return Ok(()) };
    let wanted = if ends == Ends::Closed { n + 1 } else { n };
    if t.len() != wanted {
        let per = if ends == Ends::Closed {
            "one value per point and one more for the return to points[0]"
        } else {
            "one value per point"
        };
        return Err(InputError::field(
            "t",
            format!("must have {per} ({wanted}), got {}", t.len()),
        ));
    }
    crate::checks::check_increasing("t", t, crate::checks::Order::Strictly)?;
    Ok(())
}

/// The curve's segments into `out` (data already [`check`]ed). `window(s)` gives segment s's
/// four point indices (P_{i−1}, P_i, P_{i+1}, P_{i+2}); `first` is the index into t (and the
/// point index) of the first segment's start (1 for control ends, else 0).
#[expect(clippy::too_many_arguments, reason = "the fit's inputs, each its own")]
pub(crate) fn fit_into(
    points: &[f64],
    dim: usize,
    tcb: &Tcb,
    t: Option<&[f64]>,
    ends: Ends,
    segments: usize,
    extent: f64,
    window: impl Fn(usize) -> [usize; 4],
    out: &mut SegmentTable,
) {
    let first = usize::from(ends == Ends::Control);
    let (knots, coeffs) = out.parts_mut(dim, extent);
    knots.clear();
    match t {
        None => knots.extend((0..=segments).map(|i| i as f64)),
        Some(t) => knots.extend_from_slice(&t[first..=first + segments]),
    }
    coeffs.resize(4 * dim * segments, 0.0);
    // Δ_j of the given t, with the ends' rule past them.
    let delta = |t: &[f64], j: isize| -> f64 {
        let last = t.len() as isize - 2;
        let j = match ends {
            Ends::Closed => j.rem_euclid(last + 1),
            _ => j.clamp(0, last),
        } as usize;
        t[j + 1] - t[j]
    };
    for (s, c) in coeffs.chunks_exact_mut(4 * dim).enumerate() {
        let [prev, from, to, next] = window(s);
        let (mut scale_out, mut scale_in) = (1.0, 1.0);
        if let Some(t) = t {
            let i = (first + s) as isize;
            let here = delta(t, i);
            scale_out = 2.0 * here / (delta(t, i - 1) + here);
            scale_in = 2.0 * here / (here + delta(t, i + 1));
        }
        let (tf, cf, bf) = (
            tcb.tension.at(from),
            tcb.continuity.at(from),
            tcb.bias.at(from),
        );
        let (tt, ct, bt) = (tcb.tension.at(to), tcb.continuity.at(to), tcb.bias.at(to));
        let out_in = (1.0 - tf) * (1.0 + bf) * (1.0 + cf) / 2.0;
        let out_out = (1.0 - tf) * (1.0 - bf) * (1.0 - cf) / 2.0;
        let in_in = (1.0 - tt) * (1.0 + bt) * (1.0 - ct) / 2.0;
        let in_out = (1.0 - tt) * (1.0 - bt) * (1.0 + ct) / 2.0;
        let (a, rest) = c.split_at_mut(dim);
        let (b, rest) = rest.split_at_mut(dim);
        let (cc, d) = rest.split_at_mut(dim);
        for k in 0..dim {
            let p = |j: usize| points[j * dim + k];
            let (p0, p1, p2, p3) = (p(prev), p(from), p(to), p(next));
            let leaving = scale_out * (out_in * (p1 - p0) + out_out * (p2 - p1));
            let arriving = scale_in * (in_in * (p2 - p1) + in_out * (p3 - p2));
            a[k] = 2.0 * (p1 - p2) + leaving + arriving;
            b[k] = 3.0 * (p2 - p1) - 2.0 * leaving - arriving;
            cc[k] = leaving;
            d[k] = p1;
        }
    }
}
