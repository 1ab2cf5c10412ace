//! Cubic Hermite pieces: a segment from its two end points and the derivatives there, and the
//! kinds that are nothing else ("hermite" with given tangents, "pchip", "akima"), whose
//! derivatives at the points come from [`shape`](crate::fit::shape).
//!
//! On [t_i, t_{i+1}] (Δ = t_{i+1} − t_i, u = (t − t_i)/Δ) with values f_0, f_1 and derivatives
//! m_0, m_1 (d/dt) at the ends, the piece in local u is
//!
//! ```text
//! P(u) = A u^3 + B u^2 + C u + D,   A = 2(f_0 − f_1) + Δ(m_0 + m_1),   B = 3(f_1 − f_0) − Δ(2 m_0 + m_1),
//!                                   C = Δ m_0,                        D = f_0
//! ```
//!
//! which is SciPy's `CubicHermiteSpline` written in u.

use crate::error::{InputError, Shown};
use crate::fit::shape;
use crate::points::for_dimension;
use crate::segment::SegmentTable;

/// Where a Hermite kind's derivatives at its points come from.
#[derive(Clone, Debug, PartialEq)]
pub enum HermiteSlopes {
    /// Given: dP/dt at each point, `D` values per point ("hermite"'s "tangents").
    Given(Vec<f64>),
    /// Fritsch–Carlson–Butland slopes, each coordinate as SciPy's `PchipInterpolator`.
    Pchip,
    /// Akima's slopes, each coordinate as SciPy's `Akima1DInterpolator(method="akima")`.
    Akima,
    /// The modified Akima slopes, as `Akima1DInterpolator(method="makima")`.
    Makima,
}

impl HermiteSlopes {
    /// The contract's kind name ("hermite", "pchip", "akima"; makima is "akima" with
    /// "method": "makima").
    #[must_use]
    pub fn kind_name(&self) -> &'static str {
        match self {
            HermiteSlopes::Given(_) => "hermite",
            HermiteSlopes::Pchip => "pchip",
            HermiteSlopes::Akima | HermiteSlopes::Makima => "akima",
        }
    }
}

/// Checks a Hermite kind's data: at least 2 points, t strictly increasing and one finite value
/// per point, the points finite, and given tangents one per point of `dim` finite values.
///
/// # Errors
/// The first rule broken, naming its field ("points", "t" or "tangents") and the value.
pub(crate) fn check(
    t: &[f64],
    values: &[f64],
    dim: usize,
    slopes: &HermiteSlopes,
) -> Result<(), InputError> {
    let n = values.len() / dim;
    if n < 2 {
        return Err(InputError::field(
            "points",
            format!(
                "needs at least 2 points for a {} curve, got {n}",
                slopes.kind_name()
            ),
        ));
    }
    if t.len() != n {
        return Err(InputError::field(
            "t",
            format!("must have one value per point ({n}), got {}", t.len()),
        ));
    }
    crate::checks::check_increasing("t", t, crate::checks::Order::Strictly)?;
    crate::points::check_finite(values, dim)?;
    if let HermiteSlopes::Given(tangents) = slopes {
        if tangents.len() != n * dim {
            return Err(InputError::field(
                "tangents",
                format!(
                    "must have one tangent of {dim} numbers per point ({n} x {dim} = {}), got {} \
                     numbers",
                    n * dim,
                    tangents.len()
                ),
            ));
        }
        if let Some(v) = tangents.iter().position(|v| !v.is_finite()) {
            return Err(InputError::field(
                "tangents",
                format!(
                    "must be finite: tangents[{}][{}] = {}",
                    v / dim,
                    v % dim,
                    Shown(tangents[v])
                ),
            ));
        }
    }
    Ok(())
}

/// The Hermite kind's table, into `out` (data already [`check`]ed).
pub(crate) fn fit_into(
    t: &[f64],
    values: &[f64],
    dim: usize,
    slopes: &HermiteSlopes,
    extent: f64,
    out: &mut SegmentTable,
) {
    let computed;
    let slopes = match slopes {
        HermiteSlopes::Given(tangents) => tangents.as_slice(),
        HermiteSlopes::Pchip => {
            computed = shape::pchip_slopes(t, values, dim);
            &computed
        }
        HermiteSlopes::Akima => {
            computed = shape::akima_slopes(t, values, dim, false);
            &computed
        }
        HermiteSlopes::Makima => {
            computed = shape::akima_slopes(t, values, dim, true);
            &computed
        }
    };
    let segments = t.len() - 1;
    let (knots, coeffs) = out.parts_mut(dim, extent);
    knots.clear();
    knots.extend_from_slice(t);
    coeffs.resize(4 * dim * segments, 0.0);
    hermite_segments_for(dim)(t, values, slopes, dim, 0, coeffs);
}

/// The form of [`hermite_segments`]: times, points, slopes, dimension, first segment, output.
pub(crate) type HermitePass = fn(&[f64], &[f64], &[f64], usize, usize, &mut [f64]);

/// [`hermite_segments`] compiled for `dim` coordinates: one to four have builds of their own,
/// so that a segment's loop is unrolled and vectorised.
pub(crate) fn hermite_segments_for(dim: usize) -> HermitePass {
    for_dimension!(dim, hermite_segments, 0)
}

/// Forms the power coefficients of segments `first..` into `out` (4·dim values per segment)
/// from the points and slopes: the cubic Hermite piece in local u. `D` is the dimension, or
/// 0 for any `dim`.
fn hermite_segments<const D: usize>(
    t: &[f64],
    values: &[f64],
    slopes: &[f64],
    dim: usize,
    first: usize,
    out: &mut [f64],
) {
    let dim = if D == 0 { dim } else { D };
    for (s, c) in out.chunks_exact_mut(4 * dim).enumerate() {
        let i = first + s;
        let dt = t[i + 1] - t[i];
        let (f0, f1) = (
            &values[i * dim..(i + 1) * dim],
            &values[(i + 1) * dim..(i + 2) * dim],
        );
        let (m0, m1) = (
            &slopes[i * dim..(i + 1) * dim],
            &slopes[(i + 1) * dim..(i + 2) * dim],
        );
        let (a, rest) = c.split_at_mut(dim);
        let (b, rest) = rest.split_at_mut(dim);
        let (cc, d) = rest.split_at_mut(dim);
        for k in 0..dim {
            a[k] = 2.0 * (f0[k] - f1[k]) + dt * (m0[k] + m1[k]);
            b[k] = 3.0 * (f1[k] - f0[k]) - dt * (2.0 * m0[k] + m1[k]);
            cc[k] = dt * m0[k];
            d[k] = f0[k];
        }
    }
}
