//! Gridded tensor-product splines: evaluation (one and many), the interpolating grid fit,
//! column ranges and the gridded PCHIP.

use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};

use bsplines::grid;

use crate::args::{value_error, zeros};
use pyo3::prelude::*;

/// The knots of each axis, checked against the degrees: at least 2 k + 2 each.
pub(crate) fn tensor_axes<'a>(
    ts: &'a [PyReadonlyArray1<'_, f64>],
    k: &[usize],
) -> PyResult<Vec<&'a [f64]>> {
    if ts.len() != k.len() || ts.is_empty() {
        return Err(value_error(format!(
            "t: {} knot vectors for {} degrees",
            ts.len(),
            k.len()
        )));
    }
    ts.iter()
        .zip(k)
        .enumerate()
        .map(|(a, (t, &k))| {
            let t = t.as_slice()?;
            if t.len() < 2 * k + 2 {
                return Err(value_error(format!(
                    "t[{a}]: {} knots for degree {k}, need at least {}",
                    t.len(),
                    2 * k + 2
                )));
            }
            Ok(t)
        })
        .collect()
}

/// The points (N, d) checked against d axes.
pub(crate) fn points_of<'a>(xi: &'a PyReadonlyArray2<'_, f64>, d: usize) -> PyResult<&'a [f64]> {
    if xi.shape()[1] != d {
        return Err(value_error(format!(
            "xi: points of {} coordinates for {d} axes",
            xi.shape()[1]
        )));
    }
    Ok(xi.as_slice()?)
}

/// Derivative `nu` (one order per axis) of the tensor-product B-spline (knots `ts`, degrees
/// `k`, coefficients c (n_0 · .. · n_{d-1}, m)) at the points xi (N, d), as SciPy's
/// `NdBSpline` evaluates it (see `grid`): (N, m).
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts a list of arrays as a Vec"
)]
pub(crate) fn evaluate_tensor<'py>(
    py: Python<'py>,
    ts: Vec<PyReadonlyArray1<'_, f64>>,
    k: Vec<usize>,
    c: PyReadonlyArray2<'_, f64>,
    xi: PyReadonlyArray2<'_, f64>,
    nu: Vec<usize>,
    extrapolate: bool,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let t = tensor_axes(&ts, &k)?;
    let needed: usize = t.iter().zip(&k).map(|(t, k)| t.len() - k - 1).product();
    if c.shape()[0] != needed || nu.len() != t.len() {
        return Err(value_error(format!(
            "c: {} rows of coefficients for {needed} knot products, nu of {} orders for {} axes",
            c.shape()[0],
            nu.len(),
            t.len()
        )));
    }
    let m = c.shape()[1];
    let xi = points_of(&xi, t.len())?;
    let tensor = grid::Tensor {
        t,
        k,
        c: c.as_slice()?,
        m,
    };
    let rows = xi.len() / tensor.t.len();
    let mut out = zeros(rows, m, "xi")?;
    if rows < 1024 {
        tensor.evaluate(xi, &nu, extrapolate, &mut out);
    } else {
        py.detach(|| tensor.evaluate(xi, &nu, extrapolate, &mut out));
    }
    PyArray1::from_vec(py, out).reshape([rows, m])
}

/// One spline of a tensor batch as Python hands it: knots per axis, degrees, coefficients.
pub(crate) type TensorArgs<'py> = (
    Vec<PyReadonlyArray1<'py, f64>>,
    Vec<usize>,
    PyReadonlyArray2<'py, f64>,
);

/// A batch's values (N, m) and each member's first row (S + 1).
pub(crate) type Batched<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<i64>>);

/// Many tensor-product B-splines (each its own axes, knots and degrees; every one m values a
/// point), spline i at its own points xis[i] (N_i, d_i): (values (sum N_i, m), offsets
/// (S + 1,)), spline i's rows offsets[i]..offsets[i + 1]; derivative orders nu[i] (one per
/// axis). Splines are spread over the pool.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts lists of arrays as Vecs"
)]
pub(crate) fn evaluate_tensors<'py>(
    py: Python<'py>,
    splines: Vec<TensorArgs<'_>>,
    xis: Vec<PyReadonlyArray2<'_, f64>>,
    nu: Vec<Vec<usize>>,
    extrapolate: bool,
) -> PyResult<Batched<'py>> {
    if splines.len() != xis.len() || splines.len() != nu.len() {
        return Err(value_error(format!(
            "xis: {} arrays of points and {} derivative orders for {} splines",
            xis.len(),
            nu.len(),
            splines.len()
        )));
    }
    let m = splines.first().map_or(0, |s| s.2.shape()[1]);
    let mut tensors = Vec::with_capacity(splines.len());
    let mut points = Vec::with_capacity(splines.len());
    for (i, (((ts, k, c), xi), nu)) in splines.iter().zip(&xis).zip(&nu).enumerate() {
        let named = |e: PyErr| value_error(format!("spline {i}: {e}"));
        let t = tensor_axes(ts, k).map_err(named)?;
        let needed: usize = t.iter().zip(k).map(|(t, k)| t.len() - k - 1).product();
        if c.shape()[0] != needed || c.shape()[1] != m || nu.len() != t.len() {
            return Err(value_error(format!(
                "spline {i}: c of {:?} for {needed} knot products and {m} values a point, \
                 nu of {} orders for {} axes",
                c.shape(),
                nu.len(),
                t.len()
            )));
        }
        points.push(points_of(xi, t.len()).map_err(named)?);
        tensors.push(grid::Tensor {
            t,
            k: k.clone(),
            c: c.as_slice()?,
            m,
        });
    }
    let mut offsets = vec![0i64; tensors.len() + 1];
    for (i, (x, tensor)) in points.iter().zip(&tensors).enumerate() {
        offsets[i + 1] = offsets[i] + (x.len() / tensor.t.len()) as i64;
    }
    let rows = usize::try_from(offsets[tensors.len()]).unwrap_or(0);
    let mut out = zeros(rows, m, "xi")?;
    py.detach(|| {
        use rayon::prelude::*;
        let mut parts = Vec::with_capacity(tensors.len());
        let mut rest = out.as_mut_slice();
        for (x, tensor) in points.iter().zip(&tensors) {
            let (part, tail) = rest.split_at_mut(x.len() / tensor.t.len() * m);
            parts.push(part);
            rest = tail;
        }
        parts
            .into_par_iter()
            .zip(points.par_iter().zip(tensors.par_iter()).zip(nu.par_iter()))
            .for_each(|(part, ((x, tensor), nu))| tensor.evaluate(x, nu, extrapolate, part));
    });
    Ok((
        PyArray1::from_vec(py, out).reshape([rows, m])?,
        PyArray1::from_vec(py, offsets),
    ))
}

/// The interpolating tensor B-spline through `values` (n_0 · .. · n_{d-1}, m) at the grid of
/// `nodes` (one strictly increasing array per axis), on the knots and degrees given (n_a =
/// len(t_a) − k_a − 1 = len(nodes_a)): its coefficients, the same shape (see `grid::fit`);
/// None where an axis' collocation system is singular.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts lists of arrays as Vecs"
)]
pub(crate) fn fit_tensor<'py>(
    py: Python<'py>,
    nodes: Vec<PyReadonlyArray1<'_, f64>>,
    ts: Vec<PyReadonlyArray1<'_, f64>>,
    k: Vec<usize>,
    values: PyReadonlyArray2<'_, f64>,
) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
    let t = tensor_axes(&ts, &k)?;
    let nodes: Vec<&[f64]> = nodes
        .iter()
        .map(|a| a.as_slice())
        .collect::<Result<_, _>>()?;
    let shape_ok = nodes.len() == t.len()
        && nodes
            .iter()
            .zip(t.iter().zip(&k))
            .all(|(x, (t, k))| x.len() == t.len() - k - 1);
    let needed: usize = nodes.iter().map(|x| x.len()).product();
    if !shape_ok || values.shape()[0] != needed {
        return Err(value_error(format!(
            "fit_tensor: nodes of {:?} points for {} knot vectors, values of {} rows",
            nodes.iter().map(|x| x.len()).collect::<Vec<_>>(),
            t.len(),
            values.shape()[0]
        )));
    }
    let m = values.shape()[1];
    let mut c = values.as_slice()?.to_vec();
    let solved = py.detach(|| grid::fit(&nodes, &t, &k, &mut c, m));
    if solved.is_err() {
        return Ok(None);
    }
    Ok(Some(PyArray1::from_vec(py, c).reshape([needed, m])?))
}

/// The smallest and largest value of each column of xi (N, d), NaN for a column that holds a
/// NaN: one pass over the points (NumPy's min and max along axis 0 of a C-ordered array
/// stride through it column by column, several times slower).
#[pyfunction]
pub(crate) fn column_ranges(xi: PyReadonlyArray2<'_, f64>) -> PyResult<(Vec<f64>, Vec<f64>)> {
    let d = xi.shape()[1];
    let (mut lo, mut hi) = (vec![f64::INFINITY; d], vec![f64::NEG_INFINITY; d]);
    let mut nan = vec![false; d];
    for row in xi.as_slice()?.chunks_exact(d.max(1)) {
        for (a, &v) in row.iter().enumerate() {
            lo[a] = lo[a].min(v);
            hi[a] = hi[a].max(v);
            nan[a] |= v.is_nan();
        }
    }
    for a in (0..d).filter(|&a| nan[a]) {
        (lo[a], hi[a]) = (f64::NAN, f64::NAN);
    }
    Ok((lo, hi))
}

/// SciPy's gridded PCHIP (`RegularGridInterpolator`'s "pchip": the last axis first) of the
/// values (n_0 · .. · n_{d-1}, m) on the strictly increasing axes at the points xi (N, d):
/// (N, m).
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts a list of arrays as a Vec"
)]
pub(crate) fn pchip_grid<'py>(
    py: Python<'py>,
    axes: Vec<PyReadonlyArray1<'_, f64>>,
    values: PyReadonlyArray2<'_, f64>,
    xi: PyReadonlyArray2<'_, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let axes: Vec<&[f64]> = axes
        .iter()
        .map(|a| a.as_slice())
        .collect::<Result<_, _>>()?;
    let needed: usize = axes.iter().map(|a| a.len()).product();
    if axes.is_empty() || axes.iter().any(|a| a.len() < 2) || values.shape()[0] != needed {
        return Err(value_error(format!(
            "values: {} rows for axes of {:?} points (each at least 2)",
            values.shape()[0],
            axes.iter().map(|a| a.len()).collect::<Vec<_>>()
        )));
    }
    let m = values.shape()[1];
    let xi = points_of(&xi, axes.len())?;
    let grid = grid::Grid {
        axes,
        values: values.as_slice()?,
        m,
    };
    let rows = xi.len() / grid.axes.len();
    let mut out = zeros(rows, m, "xi")?;
    if rows < 256 {
        grid.pchip(xi, &mut out);
    } else {
        py.detach(|| grid.pchip(xi, &mut out));
    }
    PyArray1::from_vec(py, out).reshape([rows, m])
}
