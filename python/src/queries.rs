//! Closest points from NumPy (`Context.closest`): curves of one kind fitted on every thread,
//! the crate's certified [`CurveIndex`] over them, every query point answered on every thread
//! in f64, as the arrays the command line's NPZ holds ("curve", "t", "point", "distance").

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use splinegpu::query::CurveIndex;
use splinegpu::{Curve, InputError, Points, SegmentTable};

use crate::args::{Stack2, value_error};
use crate::context::{CurveFields, KindSource, on_threads};

/// The closest point of a batch of curves of one kind to each row of `queries` (see
/// `splinegpu.Context.closest`): a dict of the NPZ's arrays.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts the Python call's arguments by value"
)]
pub(crate) fn closest_points<'py>(
    py: Python<'py>,
    points: Stack2<'py>,
    kind: &str,
    fields: CurveFields<'py>,
    queries: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let points = points.items()?;
    let n = points.len();
    let kinds = KindSource::new(kind, &fields)?;
    let dim = queries.shape()[1];
    if let Some(&(curves_dim, _)) = points.first()
        && curves_dim != dim
    {
        return Err(value_error(format!(
            "points: must have {curves_dim} columns (the curves' D), got {dim}"
        )));
    }
    let queries = queries.as_slice()?;
    let answers = py
        .detach(|| {
            let tables = on_threads(n, |c| -> Result<SegmentTable, InputError> {
                let (dim, coords) = points[c];
                let curve = Points::new(dim, coords.to_vec())
                    .and_then(|points| Curve::new(kinds.kind(c)?, points))
                    .map_err(|e| e.in_curve(c))?;
                Ok(curve.fit())
            })?;
            CurveIndex::new(&tables)?.closest_many(queries)
        })
        .map_err(value_error)?;
    let out = PyDict::new(py);
    let q = answers.len();
    let curves: Vec<i64> = answers.curve.iter().map(|&c| c as i64).collect();
    out.set_item("curve", PyArray1::from_vec(py, curves))?;
    out.set_item("t", PyArray1::from_vec(py, answers.t))?;
    out.set_item(
        "point",
        PyArray1::from_vec(py, answers.points).reshape([q, dim])?,
    )?;
    out.set_item("distance", PyArray1::from_vec(py, answers.distance))?;
    Ok(out)
}
