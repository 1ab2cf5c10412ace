//! NumPy arguments as the crate takes them (stacked or ragged curves, per-curve fields), the
//! errors Python sees, the threads a call uses.

use numpy::{
    PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
    PyUntypedArrayMethods,
};

use pyo3::exceptions::{PyMemoryError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

pub(crate) fn runtime_error(e: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(e.to_string())
}

/// A batch of (n, D) arrays: one C-contiguous (C, n, D) array, a list of (n_i, D) arrays, or
/// (the rows laid end to end (N, D), offsets (C + 1,)): two borrows for any number of arrays.
#[derive(FromPyObject)]
pub(crate) enum Stack2<'py> {
    Dense(PyReadonlyArray3<'py, f64>),
    Ragged(Vec<PyReadonlyArray2<'py, f64>>),
    Flat(PyReadonlyArray2<'py, f64>, PyReadonlyArray1<'py, i64>),
}

impl Stack2<'_> {
    /// Each array's D and values.
    pub(crate) fn items(&self) -> PyResult<Vec<(usize, &[f64])>> {
        match self {
            Stack2::Dense(a) => {
                let shape = a.shape();
                let per = shape[1] * shape[2];
                let all = a.as_slice()?;
                Ok((0..shape[0])
                    .map(|c| (shape[2], &all[c * per..(c + 1) * per]))
                    .collect())
            }
            Stack2::Ragged(list) => list
                .iter()
                .map(|a| Ok((a.shape()[1], a.as_slice()?)))
                .collect(),
            Stack2::Flat(values, offsets) => {
                let dim = values.shape()[1];
                Ok(
                    ragged(values.as_slice()?, dim, offsets.as_slice()?, "rows")?
                        .into_iter()
                        .map(|rows| (dim, rows))
                        .collect(),
                )
            }
        }
    }
}

/// A batch of 1-D arrays: one C-contiguous (C, k) array, a list of 1-D arrays, or (the
/// arrays laid end to end, offsets (C + 1,)).
#[derive(FromPyObject)]
pub(crate) enum Stack1<'py> {
    Dense(PyReadonlyArray2<'py, f64>),
    Ragged(Vec<PyReadonlyArray1<'py, f64>>),
    Flat(PyReadonlyArray1<'py, f64>, PyReadonlyArray1<'py, i64>),
}

impl Stack1<'_> {
    pub(crate) fn items(&self) -> PyResult<Vec<&[f64]>> {
        match self {
            Stack1::Dense(a) => rows(a),
            Stack1::Ragged(list) => list.iter().map(|a| Ok(a.as_slice()?)).collect(),
            Stack1::Flat(values, offsets) => {
                ragged(values.as_slice()?, 1, offsets.as_slice()?, "values")
            }
        }
    }
}

/// The rows of a C-contiguous (C, k) array (k may be 0).
pub(crate) fn rows<'a>(a: &'a PyReadonlyArray2<'_, f64>) -> PyResult<Vec<&'a [f64]>> {
    let k = a.shape()[1];
    Ok(a.as_slice()?
        .chunks_exact(k.max(1))
        .take(a.shape()[0])
        .map(|row| &row[..k])
        .collect())
}

/// A per-curve kind field: one C-contiguous (C, k) array, a row per curve (one borrow: the
/// rows of one array handed over as thousands of views made each borrow check the others;
/// docs/benchmarks.md), or a list with an array or None per curve.
#[derive(FromPyObject)]
pub(crate) enum PerCurve<'py> {
    Dense(PyReadonlyArray2<'py, f64>),
    Ragged(Vec<Option<PyReadonlyArray1<'py, f64>>>),
}

impl PerCurve<'_> {
    pub(crate) fn items(&self) -> PyResult<Vec<Option<&[f64]>>> {
        match self {
            PerCurve::Dense(a) => Ok(rows(a)?.into_iter().map(Some).collect()),
            PerCurve::Ragged(list) => list
                .iter()
                .map(|a| a.as_ref().map(|a| a.as_slice()).transpose())
                .collect::<Result<Vec<_>, _>>()
                .map_err(Into::into),
        }
    }
}

/// The threads every CPU evaluation uses.
pub(crate) fn threads() -> usize {
    splinegpu::available_threads()
}

/// A batch's series laid end to end: one array each (ragged lists handed over as thousands
/// of arrays cost a borrow check apiece, which grows with the borrows held), series i at
/// rows offsets[i]..offsets[i + 1].
pub(crate) fn ragged<'a>(
    values: &'a [f64],
    per: usize,
    offsets: &[i64],
    name: &str,
) -> PyResult<Vec<&'a [f64]>> {
    let rows = values.len() / per.max(1);
    let mut out = Vec::with_capacity(offsets.len().saturating_sub(1));
    for (i, pair) in offsets.windows(2).enumerate() {
        let (Ok(start), Ok(end)) = (usize::try_from(pair[0]), usize::try_from(pair[1])) else {
            return Err(value_error(format!("{name}: offset {i} is negative")));
        };
        if start > end || end > rows {
            return Err(value_error(format!(
                "{name}: series {i} spans rows {start}..{end} of {rows}"
            )));
        }
        out.push(&values[start * per..end * per]);
    }
    Ok(out)
}

/// `rows * width` zeros, allocated fallibly: a result too large for the memory the process may
/// take (under a limit an estimate missed) is a MemoryError naming `what`, never an abort.
pub(crate) fn zeros(rows: usize, width: usize, what: &str) -> PyResult<Vec<f64>> {
    let refuse = || {
        PyMemoryError::new_err(format!(
            "{what}: {rows} x {width} values do not fit in the memory the process may take"
        ))
    };
    let len = rows.checked_mul(width).ok_or_else(refuse)?;
    filled(len, what)
}

/// A new NumPy array of zeros of `shape`, made by `numpy.zeros`: where the process cannot
/// have the memory NumPy raises MemoryError, which this returns (numpy's Rust constructors
/// panic on NumPy's refusal: "PyObject pointer is null").
pub(crate) fn new_zeros<'py, F: numpy::Element, D: numpy::ndarray::Dimension>(
    py: Python<'py>,
    shape: &[usize],
) -> PyResult<Bound<'py, numpy::PyArray<F, D>>> {
    let zeros = py
        .import("numpy")?
        .call_method1("zeros", (shape.to_vec(), numpy::dtype::<F>(py)))?;
    Ok(zeros.cast_into::<numpy::PyArray<F, D>>()?)
}

/// `n` zeros, allocated fallibly and zeroed by the allocator (as `vec![0; n]`, nothing
/// written): a MemoryError naming `what` where the process cannot have them, never an abort.
pub(crate) fn filled<T: bytemuck::Zeroable>(n: usize, what: &str) -> PyResult<Vec<T>> {
    bytemuck::allocation::try_zeroed_slice_box(n)
        .map(Vec::from)
        .map_err(|()| {
            PyMemoryError::new_err(format!(
                "{what}: {n} values do not fit in the memory the process may take"
            ))
        })
}

/// The array `name` of shape `shape`: `out`'s (checked: dtype, shape, C order, writeable),
/// or a new one of zeros.
pub(crate) fn array<'py, F: numpy::Element>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyDict>>,
    name: &str,
    shape: [usize; 2],
) -> PyResult<Bound<'py, PyArray2<F>>> {
    let Some(given) = out.map(|o| o.get_item(name)).transpose()?.flatten() else {
        return new_zeros(py, &shape);
    };
    let wrong = |what: String| value_error(format!("out: \"{name}\" {what}"));
    let Ok(given) = given.cast_into::<PyArray2<F>>() else {
        return Err(wrong(format!(
            "must be a 2-D {} array",
            numpy::dtype::<F>(py)
        )));
    };
    if given.shape() != shape {
        return Err(wrong(format!(
            "has shape {:?}, this result {shape:?}",
            given.shape()
        )));
    }
    if !given.is_c_contiguous() {
        return Err(wrong("must be C-contiguous".into()));
    }
    if given.try_readwrite().is_err() {
        return Err(wrong(
            "must be writeable (and not borrowed elsewhere)".into(),
        ));
    }
    Ok(given)
}
