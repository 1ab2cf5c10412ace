//! Queries from NumPy: closest points (`Context.closest`: curves of one kind fitted on every
//! thread, the crate's certified [`CurveIndex`] over them, every query point answered on the
//! context's GPU in f32 or on every thread in f64), intersections (`Context.intersections`, f64
//! on every context), closest points on surfaces and rays (on the context's backend), as the
//! arrays the command line's NPZ holds ("curve", "t", "point", "distance"; "i", "j", "t_i",
//! "t_j", "point", "tangent", "overlap"; ...): points, distances and normals float32 from a
//! GPU, parameters float64.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use splinegpu::query::{
    ClosestPoints, CurveIndex, IntersectionColumns, Pairs, QueryError, RayHitColumns, SurfaceIndex,
    SurfacePointColumns, intersections,
};
use splinegpu::{Curve, InputError, Points, SegmentTable};

use crate::args::{Stack2, runtime_error, value_error};
use crate::context::{Context, CurveFields, KindSource, on_threads};
use crate::surfaces::{SurfaceFields, fitted};

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
    context: Option<PyRef<'py, Context>>,
) -> PyResult<Bound<'py, PyDict>> {
    let points = points.items()?;
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
    let tables = py.detach(|| fit(&points, &kinds)).map_err(value_error)?;
    let index = CurveIndex::new(&tables).map_err(value_error)?;
    match context.as_ref().and_then(|c| c.gpu.as_ref()) {
        Some(gpu) => {
            let answers = py
                .detach(|| gpu.closest_points(&index, queries))
                .map_err(query_error)?;
            closest_arrays(py, answers)
        }
        None => {
            let answers = py
                .detach(|| index.closest_many(queries))
                .map_err(value_error)?;
            closest_arrays(py, answers)
        }
    }
}

/// Closest points as the NPZ's arrays: "curve" int64, "t" float64, "point" (Q, D) and
/// "distance" as the answers' numbers (float32 from a GPU).
fn closest_arrays<'py, F: numpy::Element>(
    py: Python<'py>,
    answers: ClosestPoints<F>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let (q, dim) = (answers.len(), answers.dim);
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

/// A query's error as Python raises it: bad input a ValueError, the device a RuntimeError.
fn query_error(e: QueryError) -> PyErr {
    match e {
        QueryError::Input(e) => value_error(e),
        QueryError::Gpu(e) => runtime_error(e),
    }
}

/// `values` as a float32 array from a GPU context, else float64.
fn numbers<'py>(py: Python<'py>, values: Vec<f64>, gpu: bool) -> Bound<'py, PyAny> {
    if gpu {
        let values: Vec<f32> = values.into_iter().map(|x| x as f32).collect();
        PyArray1::from_vec(py, values).into_any()
    } else {
        PyArray1::from_vec(py, values).into_any()
    }
}

/// Every intersection of a batch of 2-D curves of one kind (see
/// `splinegpu.Context.intersections`): `pairs` None for every pair i < j, else the (i, j)
/// pairs in order. A dict of the NPZ's arrays.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts the Python call's arguments by value"
)]
pub(crate) fn intersections_of<'py>(
    py: Python<'py>,
    points: Stack2<'py>,
    kind: &str,
    fields: CurveFields<'py>,
    pairs: Option<Vec<[usize; 2]>>,
) -> PyResult<Bound<'py, PyDict>> {
    let points = points.items()?;
    let kinds = KindSource::new(kind, &fields)?;
    let found = py
        .detach(|| {
            let pairs = pairs.as_deref().map_or(Pairs::All, Pairs::Listed);
            intersections(&fit(&points, &kinds)?, pairs)
        })
        .map_err(value_error)?;
    let n = found.len();
    let c = IntersectionColumns::new(&found);
    let out = PyDict::new(py);
    out.set_item("i", PyArray1::from_vec(py, c.i))?;
    out.set_item("j", PyArray1::from_vec(py, c.j))?;
    out.set_item("t_i", PyArray1::from_vec(py, c.t_i))?;
    out.set_item("t_j", PyArray1::from_vec(py, c.t_j))?;
    out.set_item("point", PyArray1::from_vec(py, c.point).reshape([n, 2])?)?;
    out.set_item("tangent", PyArray1::from_vec(py, c.tangent))?;
    out.set_item("overlap", PyArray1::from_vec(py, c.overlap))?;
    Ok(out)
}

/// The batch's curves fitted on every thread, each error placed at its curve.
fn fit(
    points: &[(usize, &[f64])],
    kinds: &KindSource<'_>,
) -> Result<Vec<SegmentTable>, InputError> {
    on_threads(points.len(), |c| {
        let (dim, coords) = points[c];
        let curve = Points::new(dim, coords.to_vec())
            .and_then(|points| Curve::new(kinds.kind(c)?, points))
            .map_err(|e| e.in_curve(c))?;
        Ok(curve.fit())
    })
}

/// The closest point of a batch of surfaces of one kind to each row of `queries` (see
/// `splinegpu.Context.closest_on_surfaces`): a dict of the NPZ's arrays ("patch" -1 on nets).
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts the Python call's arguments by value"
)]
pub(crate) fn closest_on_surfaces<'py>(
    py: Python<'py>,
    nets: Vec<PyReadonlyArray3<'py, f64>>,
    kind: &str,
    fields: SurfaceFields<'py>,
    queries: PyReadonlyArray2<'py, f64>,
    context: Option<PyRef<'py, Context>>,
) -> PyResult<Bound<'py, PyDict>> {
    let tables = fitted(&nets, kind, &fields)?;
    let dim = queries.shape()[1];
    if let Some(first) = tables.first()
        && first.dim() != dim
    {
        return Err(value_error(format!(
            "points: must have {} columns (the surfaces' D), got {dim}",
            first.dim()
        )));
    }
    let queries = queries.as_slice()?;
    let index = SurfaceIndex::new(&tables).map_err(value_error)?;
    let gpu = context.as_ref().and_then(|c| c.gpu.as_ref());
    let answers = py
        .detach(|| match gpu {
            Some(gpu) => gpu.closest_on_surfaces(&index, queries),
            None => index.closest_many(queries).map_err(QueryError::from),
        })
        .map_err(query_error)?;
    let q = answers.len();
    let c = SurfacePointColumns::new(&answers);
    let out = PyDict::new(py);
    out.set_item("surface", PyArray1::from_vec(py, c.surface))?;
    out.set_item("patch", PyArray1::from_vec(py, c.patch))?;
    out.set_item("u", PyArray1::from_vec(py, c.u))?;
    out.set_item("v", PyArray1::from_vec(py, c.v))?;
    let point = numbers(py, c.point, gpu.is_some());
    out.set_item("point", point.call_method1("reshape", ((q, dim),))?)?;
    out.set_item("distance", numbers(py, c.distance, gpu.is_some()))?;
    Ok(out)
}

/// The first hit of each ray (a row of `rays`: ox, oy, oz, dx, dy, dz) on a batch of 3-D
/// surfaces of one kind (see `splinegpu.Context.rays`): a dict of the NPZ's arrays, "hit"
/// false with NaN and -1 where a ray meets nothing.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts the Python call's arguments by value"
)]
pub(crate) fn ray_hits<'py>(
    py: Python<'py>,
    nets: Vec<PyReadonlyArray3<'py, f64>>,
    kind: &str,
    fields: SurfaceFields<'py>,
    rays: PyReadonlyArray2<'py, f64>,
    context: Option<PyRef<'py, Context>>,
) -> PyResult<Bound<'py, PyDict>> {
    let tables = fitted(&nets, kind, &fields)?;
    let rays = rays.as_slice()?;
    let index = SurfaceIndex::new(&tables).map_err(value_error)?;
    let gpu = context.as_ref().and_then(|c| c.gpu.as_ref());
    let hits = py
        .detach(|| match gpu {
            Some(gpu) => gpu.ray_hits(&index, rays),
            None => index.rays_many(rays).map_err(QueryError::from),
        })
        .map_err(query_error)?;
    let q = hits.len();
    let c = RayHitColumns::new(&hits);
    let out = PyDict::new(py);
    out.set_item("hit", PyArray1::from_vec(py, c.hit))?;
    out.set_item("surface", PyArray1::from_vec(py, c.surface))?;
    out.set_item("patch", PyArray1::from_vec(py, c.patch))?;
    out.set_item("u", PyArray1::from_vec(py, c.u))?;
    out.set_item("v", PyArray1::from_vec(py, c.v))?;
    out.set_item("s", PyArray1::from_vec(py, c.s))?;
    let (point, normal) = (
        numbers(py, c.point, gpu.is_some()),
        numbers(py, c.normal, gpu.is_some()),
    );
    out.set_item("point", point.call_method1("reshape", ((q, 3),))?)?;
    out.set_item("normal", normal.call_method1("reshape", ((q, 3),))?)?;
    Ok(out)
}
