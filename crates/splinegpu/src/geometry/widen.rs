//! A curve with its width as one more coordinate: the same kind, ends, knots, weights and fit,
//! so that w(t) is interpolated exactly as the points are (the contract's "one more coordinate
//! of the same spline"). Hermite's given tangents and clamped ends' derivatives are 0 in it.

use super::Width;
use crate::curve::{Curve, CurveKind};
use crate::error::InputError;
use crate::fit::hermite::HermiteSlopes;
use crate::fit::interp::EndCondition;
use crate::points::Points;

/// `curve` with `width` (named `field`) appended to every point as coordinate D.
///
/// # Errors
/// A width that is not finite or not > 0, or a per-point width whose length is not the number
/// of points (the error names `field`, the index and the value).
pub(crate) fn widened(curve: &Curve, width: &Width, field: &str) -> Result<Curve, InputError> {
    let points = curve.points();
    let n = points.len();
    let values: Vec<f64> = match width {
        Width::Constant(w) => {
            check_width(*w, field, None)?;
            vec![*w; n]
        }
        Width::PerPoint(ws) => {
            if ws.len() != n {
                return Err(InputError::field(
                    field,
                    format!("{} values for {n} points (one per point)", ws.len()),
                ));
            }
            for (i, &w) in ws.iter().enumerate() {
                check_width(w, field, Some(i))?;
            }
            ws.clone()
        }
    };
    let dim = points.dim();
    let mut coords = Vec::with_capacity(n * (dim + 1));
    for (i, w) in values.iter().enumerate() {
        coords.extend_from_slice(points.point(i));
        coords.push(*w);
    }
    Curve::new(
        widened_kind(curve.kind(), dim),
        Points::new(dim + 1, coords)?,
    )
}

fn check_width(w: f64, field: &str, index: Option<usize>) -> Result<(), InputError> {
    if w.is_finite() && w > 0.0 {
        return Ok(());
    }
    let at = index.map_or(String::new(), |i| format!("[{i}]"));
    Err(InputError::field(
        field,
        format!("must be a finite number > 0, got {field}{at} = {w}"),
    ))
}

/// The kind's per-coordinate fields with a 0 appended in the new coordinate.
fn widened_kind(kind: &CurveKind, dim: usize) -> CurveKind {
    let zero_after = |values: &[f64]| -> Vec<f64> {
        values
            .chunks(dim)
            .flat_map(|point| point.iter().copied().chain([0.0]))
            .collect()
    };
    match kind {
        CurveKind::Hermite {
            slopes: HermiteSlopes::Given(tangents),
            t,
        } => CurveKind::Hermite {
            slopes: HermiteSlopes::Given(zero_after(tangents)),
            t: t.clone(),
        },
        CurveKind::Interpolating {
            condition: EndCondition::Clamped { start, end },
            t,
        } => CurveKind::Interpolating {
            condition: EndCondition::Clamped {
                start: zero_after(start),
                end: zero_after(end),
            },
            t: t.clone(),
        },
        other => other.clone(),
    }
}
