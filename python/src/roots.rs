//! Real roots of many splines' pieces at once (`solve_pieces`, `PendingRoots`): the closed forms
//! in the crate, the pieces they leave handed to NumPy's eigenvalues.

use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use std::sync::Arc;

use bsplines::roots;

use crate::args::value_error;
use pyo3::prelude::*;
use splinegpu::SegmentTable;

/// A ragged result: the values, and offsets (S + 1) splitting them per spline.
pub(crate) type Ragged<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<i64>>);

/// The pieces the closed forms leave to the eigenvalues: their numbers and coefficients (h, 4).
pub(crate) type Undecided<'py> = (Bound<'py, PyArray1<i64>>, Bound<'py, PyArray2<f64>>);

/// The splines' fitted tables as the root finder's pieces, in SciPy's coefficients (formed as
/// `scipy_coefficients` forms them): one value per x only.
#[derive(Debug)]
pub(crate) struct TablePieces {
    pub(crate) tables: Vec<Arc<SegmentTable>>,
    pub(crate) first: Vec<usize>,
}

impl TablePieces {
    pub(crate) fn new(tables: &[Arc<SegmentTable>]) -> PyResult<Self> {
        if let Some(s) = tables.iter().position(|t| t.dim() != 1) {
            return Err(value_error(format!(
                "solve: spline {s} has {} values per x; roots are found for splines of one",
                tables[s].dim()
            )));
        }
        let mut first = vec![0];
        for table in tables {
            first.push(first.last().copied().unwrap_or(0) + table.len());
        }
        Ok(Self {
            tables: tables.to_vec(),
            first,
        })
    }
}

impl roots::Source for TablePieces {
    fn splines(&self) -> usize {
        self.tables.len()
    }

    fn first(&self, s: usize) -> usize {
        self.first[s]
    }

    fn piece(&self, s: usize, j: usize) -> roots::Piece {
        let table = &self.tables[s];
        let segment = table.segment(j);
        let dt = segment.dt();
        let [a, b, c, d] = segment.power();
        let knots = table.knots();
        roots::Piece {
            c: [a[0] / (dt * dt * dt), b[0] / (dt * dt), c[0] / dt, d[0]],
            start: knots[j],
            end: knots[j + 1],
        }
    }
}

/// Piecewise cubics given as arrays, copied: c (4, P) as SciPy's rows, each piece's start and
/// end, and offsets (S + 1) splitting the pieces into splines; a shape or an offset out of
/// place is a ValueError naming it.
pub(crate) fn arrays(
    c: &PyReadonlyArray2<'_, f64>,
    start: &PyReadonlyArray1<'_, f64>,
    end: &PyReadonlyArray1<'_, f64>,
    offsets: &PyReadonlyArray1<'_, i64>,
) -> PyResult<roots::Arrays> {
    let (start, end) = (start.as_slice()?, end.as_slice()?);
    let pieces = start.len();
    if c.shape() != [4, pieces] || end.len() != pieces {
        return Err(value_error(format!(
            "c: must have shape (4, {pieces}) for {pieces} pieces' starts, got {:?} with {} ends",
            c.shape(),
            end.len()
        )));
    }
    let mut at: Vec<usize> = Vec::with_capacity(offsets.len());
    for (s, &o) in offsets.as_slice()?.iter().enumerate() {
        match usize::try_from(o) {
            Ok(o) if o >= at.last().copied().unwrap_or(0) && o <= pieces => at.push(o),
            _ => {
                return Err(value_error(format!(
                    "offsets[{s}]: must rise from 0 to the {pieces} pieces, got {o}"
                )));
            }
        }
    }
    if at.first() != Some(&0) || at.last() != Some(&pieces) {
        return Err(value_error(format!(
            "offsets: must run from 0 to the {pieces} pieces"
        )));
    }
    Ok(roots::Arrays {
        c: c.as_slice()?.to_vec(),
        start: start.to_vec(),
        end: end.to_vec(),
        offsets: at,
    })
}

/// A solve in two steps: every spline's roots but those waiting for the eigenvalues of the
/// pieces the closed forms leave undecided (`undecided()`), which the caller finds (NumPy's
/// LAPACK, as SciPy) and hands to `finish`.
#[pyclass(module = "splinegpu._native")]
pub(crate) struct PendingRoots {
    pub(crate) source: Box<dyn roots::Source + Send>,
    pub(crate) how: roots::Solve,
    pub(crate) pending: Option<roots::Pending>,
}

impl PendingRoots {
    pub(crate) fn new(
        py: Python<'_>,
        source: Box<dyn roots::Source + Send>,
        how: roots::Solve,
    ) -> Self {
        let pending = py.detach(|| roots::solve(source.as_ref(), &how));
        Self {
            source,
            how,
            pending: Some(pending),
        }
    }
}

#[pymethods]
impl PendingRoots {
    /// The undecided pieces: their numbers (ascending) and coefficients (h, 4) as SciPy's rows.
    fn undecided<'py>(&self, py: Python<'py>) -> PyResult<Undecided<'py>> {
        let found = self.pending.as_ref().map_or(&[][..], |p| &p.undecided);
        let which = PyArray1::from_iter(py, found.iter().map(|&(p, _)| p as i64));
        let c = PyArray1::from_iter(py, found.iter().flat_map(|&(_, c)| c));
        Ok((which, c.reshape([found.len(), 4])?))
    }

    /// Every spline's roots: (roots, offsets (S + 1)). `decided_pieces` and `decided_roots`:
    /// the real eigenvalues of the undecided pieces (each piece's ascending).
    fn finish<'py>(
        &mut self,
        py: Python<'py>,
        decided_pieces: PyReadonlyArray1<'py, i64>,
        decided_roots: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Ragged<'py>> {
        let (which, real) = (decided_pieces.as_slice()?, decided_roots.as_slice()?);
        if which.len() != real.len() {
            return Err(value_error(
                "decided_pieces and decided_roots: must have one length",
            ));
        }
        let decided: Vec<(usize, f64)> = which
            .iter()
            .zip(real)
            .map(|(&p, &r)| (p as usize, r))
            .collect();
        let pending = self
            .pending
            .take()
            .ok_or_else(|| value_error("finish: this solve is finished already"))?;
        let (source, how) = (self.source.as_ref(), &self.how);
        let (found, offsets) = py.detach(|| pending.finish(source, how, &decided));
        Ok((
            PyArray1::from_vec(py, found),
            PyArray1::from_vec(py, offsets),
        ))
    }
}

/// Every spline's real roots minus `y`, as SciPy's `PPoly.solve` finds them (the rules in
/// `roots`; `exact`: SciPy's degree rule), of piecewise cubics given as arrays (c (4, P),
/// start, end, offsets (S + 1)).
#[pyfunction]
#[expect(
    clippy::too_many_arguments,
    reason = "the arrays and options of one SciPy call"
)]
pub(crate) fn solve_pieces(
    py: Python<'_>,
    c: PyReadonlyArray2<'_, f64>,
    start: PyReadonlyArray1<'_, f64>,
    end: PyReadonlyArray1<'_, f64>,
    offsets: PyReadonlyArray1<'_, i64>,
    y: f64,
    discontinuity: bool,
    extrapolate: bool,
    exact: bool,
) -> PyResult<PendingRoots> {
    let source = Box::new(arrays(&c, &start, &end, &offsets)?);
    let how = roots::Solve {
        y,
        discontinuity,
        extrapolate,
        exact,
    };
    Ok(PendingRoots::new(py, source, how))
}
