//! Piecewise polynomials and B-splines evaluated, integrated and differentiated for SciPy's
//! PPoly and BSpline, and B-spline basis rows.

use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyReadonlyArray3, PyUntypedArrayMethods,
};

use bsplines::{de_boor, pieces};

use crate::args::{value_error, zeros};
use pyo3::prelude::*;

/// The piecewise polynomial's shape checked: breakpoints (P + 1) and c (k, P, m), both
/// contiguous; (k, m).
pub(crate) fn piece_shape(
    breaks: &[f64],
    c: &PyReadonlyArray3<'_, f64>,
) -> PyResult<(usize, usize)> {
    let shape = c.shape();
    if breaks.len() < 2 || shape[1] != breaks.len() - 1 {
        return Err(value_error(format!(
            "c: {} pieces for {} breakpoints",
            shape[1],
            breaks.len()
        )));
    }
    Ok((shape[0], shape[2]))
}

/// Derivative `nu` of a piecewise polynomial (breakpoints increasing, c (k, P, m) in SciPy's
/// power form) at x, any x (the end pieces continue), in f64: (len(x), m). See `pieces`.
#[pyfunction]
pub(crate) fn evaluate_pieces<'py>(
    py: Python<'py>,
    breaks: PyReadonlyArray1<'_, f64>,
    c: PyReadonlyArray3<'_, f64>,
    x: PyReadonlyArray1<'_, f64>,
    nu: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let breaks = breaks.as_slice()?;
    let (k, m) = piece_shape(breaks, &c)?;
    let (c, x) = (c.as_slice()?, x.as_slice()?);
    let mut out = zeros(x.len(), m, "x")?;
    pieces::evaluate(breaks, c, k, m, x, nu, &mut out);
    PyArray1::from_vec(py, out).reshape([x.len(), m])
}

/// The integral from a to b of a piecewise polynomial (as `evaluate_pieces` takes it), the
/// end pieces continuing past the breakpoints: (m,).
#[pyfunction]
pub(crate) fn integrate_pieces<'py>(
    py: Python<'py>,
    breaks: PyReadonlyArray1<'_, f64>,
    c: PyReadonlyArray3<'_, f64>,
    a: f64,
    b: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let breaks = breaks.as_slice()?;
    let (k, m) = piece_shape(breaks, &c)?;
    let mut out = vec![0.0; m];
    pieces::integrate(breaks, c.as_slice()?, k, m, a, b, &mut out);
    Ok(PyArray1::from_vec(py, out))
}

/// The antiderivative of a piecewise polynomial (as `evaluate_pieces` takes it; breakpoints
/// may decrease), zero at the first breakpoint and continuous: (k + 1, P, m).
#[pyfunction]
pub(crate) fn antiderivative_pieces<'py>(
    py: Python<'py>,
    breaks: PyReadonlyArray1<'_, f64>,
    c: PyReadonlyArray3<'_, f64>,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let breaks = breaks.as_slice()?;
    let (k, m) = piece_shape(breaks, &c)?;
    let out = pieces::antiderivative(breaks, c.as_slice()?, k, m);
    PyArray1::from_vec(py, out).reshape([k + 1, breaks.len() - 1, m])
}

/// Derivative `nu` of the B-spline (knots t, coefficients c (>= n, m), degree k) at x, as
/// SciPy evaluates it (de Boor's sums over each x's knot span; past the base interval the end
/// polynomials in powers where `ends_in_powers`; see `de_boor`): (len(x), m).
#[pyfunction]
pub(crate) fn evaluate_bspline<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'_, f64>,
    c: PyReadonlyArray2<'_, f64>,
    k: usize,
    x: PyReadonlyArray1<'_, f64>,
    nu: usize,
    ends_in_powers: bool,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let t = t.as_slice()?;
    let (rows, m) = (c.shape()[0], c.shape()[1]);
    if t.len() < 2 * k + 2 || rows < t.len() - k - 1 {
        return Err(value_error(format!(
            "c: {rows} coefficients for {} knots of degree {k}",
            t.len()
        )));
    }
    let (c, x) = (c.as_slice()?, x.as_slice()?);
    let mut out = zeros(x.len(), m, "x")?;
    let evaluate = |out: &mut [f64]| de_boor::evaluate(t, c, m, k, x, nu, ends_in_powers, out);
    if x.len() < 1024 {
        // A small call: releasing the GIL would cost more than the work.
        evaluate(&mut out);
    } else {
        py.detach(|| evaluate(&mut out));
    }
    PyArray1::from_vec(py, out).reshape([x.len(), m])
}

/// The nu-th derivatives of the k + 1 B-splines that do not vanish on each x's knot span (l
/// its `span`, t_l <= x < t_{l+1}), (len(x), k + 1): the workspace's one Cox–de Boor
/// recursion (`bsplines::de_boor::basis_in`), for the package's collocation and design
/// matrices.
#[pyfunction]
pub(crate) fn bspline_basis<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'_, f64>,
    k: usize,
    x: PyReadonlyArray1<'_, f64>,
    span: PyReadonlyArray1<'_, i64>,
    nu: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (t, x, span) = (t.as_slice()?, x.as_slice()?, span.as_slice()?);
    if x.len() != span.len() {
        return Err(value_error(format!(
            "span: one per x ({}), got {}",
            x.len(),
            span.len()
        )));
    }
    let Some(n) = t.len().checked_sub(k + 1).filter(|&n| n > k) else {
        return Err(value_error(format!(
            "t: needs at least 2k + 2 = {} knots, got {}",
            2 * k + 2,
            t.len()
        )));
    };
    if let Some(i) = span
        .iter()
        .position(|&l| !(k as i64..n as i64).contains(&l))
    {
        return Err(value_error(format!(
            "span[{i}] = {} is not a knot span of degree {k} (k to n - 1 = {})",
            span[i],
            n - 1
        )));
    }
    let width = k + 1;
    let mut out = zeros(x.len(), width, "x")?;
    py.detach(|| {
        let mut scratch = vec![0.0; width];
        for ((row, &xi), &l) in out.chunks_exact_mut(width).zip(x).zip(span) {
            bsplines::de_boor::basis_in(t, k, xi, l as usize, nu, row, &mut scratch);
        }
    });
    PyArray1::from_vec(py, out).reshape([x.len(), width])
}
