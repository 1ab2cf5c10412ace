//! The query points' checks, shared by the curves' and the surfaces' indexes: a point's length
//! and finiteness, a flat list's length; each error names the query as `closest[index]`.

use crate::error::InputError;

/// Query `index`'s point `q`: D = `dim` coordinates (`of`: whose D, for the message), each
/// finite.
pub(crate) fn check_point(q: &[f64], dim: usize, index: usize, of: &str) -> Result<(), InputError> {
    if q.len() != dim {
        return Err(InputError::field(
            format!("closest[{index}]"),
            format!("must have {dim} coordinates (the {of}' D), got {}", q.len()),
        ));
    }
    if let Some(k) = q.iter().position(|v| !v.is_finite()) {
        return Err(InputError::field(
            format!("closest[{index}]"),
            format!("coordinate {k} is {}, not a finite number", q[k]),
        ));
    }
    Ok(())
}

/// How many points of `dim` coordinates the flat list `queries` holds.
pub(crate) fn point_count(queries: &[f64], dim: usize) -> Result<usize, InputError> {
    if !queries.len().is_multiple_of(dim) {
        return Err(InputError::field(
            "closest",
            format!(
                "must hold {dim} coordinates per point, got {} values",
                queries.len()
            ),
        ));
    }
    Ok(queries.len() / dim)
}
