//! `Splines`: fitted piecewise cubics held for SciPy's 1-D classes (fit, fit_hermite,
//! fit_bspline), evaluated through a context, their state for pickling.

use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1};
use std::sync::Arc;

use bsplines::roots;

use crate::args::{Stack1, Stack2, runtime_error, threads, value_error, zeros};
use crate::context::{Context, available_memory, on_threads};
use crate::roots::{PendingRoots, TablePieces};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use splinegpu::{
    Curve, CurveKind, Derivatives, End, EndCondition, EvalJob, Fitter, HermiteSlopes, InputError,
    Points, SamplePlan, Samples, Sampling, SegmentTable,
};

/// One fitted interpolating spline, or many: what `splinegpu.CubicSpline` holds.
#[pyclass(frozen, module = "splinegpu._native")]
pub(crate) struct Splines {
    /// Shared with every evaluation's job: a call copies no knots.
    pub(crate) tables: Vec<Arc<SegmentTable>>,
}

/// One end given on its own, as the Python side spells it: ("first" | "second", values) or
/// ("not-a-knot", None); `None` is a first derivative of zero (SciPy's "clamped").
pub(crate) type EndArg = Option<(String, Option<Vec<f64>>)>;

/// An end's derivative values, zeros where none are given.
pub(crate) fn end_values(end: &EndArg, dim: usize) -> Vec<f64> {
    end.as_ref()
        .and_then(|(_, v)| v.clone())
        .unwrap_or_else(|| vec![0.0; dim])
}

/// An end given on its own ([`End`]).
pub(crate) fn end_of(end: &EndArg, dim: usize) -> PyResult<End> {
    Ok(match end.as_ref().map(|(order, _)| order.as_str()) {
        None | Some("first") => End::FirstDerivative(end_values(end, dim)),
        Some("second") => End::SecondDerivative(end_values(end, dim)),
        Some("not-a-knot") => End::NotAKnot,
        Some(other) => {
            return Err(value_error(format!(
                "bc_type: an end \"{other}\" is not known"
            )));
        }
    })
}

/// The end condition of SciPy's `bc_type`: "not-a-knot", "natural", "periodic", "clamped"
/// (first derivatives, zero unless given at both ends), or "each" (SciPy's pairs, each end on
/// its own).
pub(crate) fn condition(
    bc: &str,
    start: &EndArg,
    end: &EndArg,
    dim: usize,
) -> PyResult<EndCondition> {
    Ok(match bc {
        "not-a-knot" => EndCondition::NotAKnot,
        "natural" => EndCondition::Natural,
        "periodic" => EndCondition::Periodic,
        "clamped" => EndCondition::Clamped {
            start: end_values(start, dim),
            end: end_values(end, dim),
        },
        "each" => EndCondition::Each {
            start: end_of(start, dim)?,
            end: end_of(end, dim)?,
        },
        other => {
            return Err(value_error(format!(
                "bc_type: must be \"not-a-knot\", \"natural\", \"clamped\", \"periodic\", a pair of those but \"periodic\", or ((order, value), (order, value)) with order 1 or 2, got \"{other}\""
            )));
        }
    })
}

/// Fits one spline per (x, y) pair: y an (n, m) array at the n strictly increasing x.
#[pyfunction]
#[pyo3(signature = (xs, ys, bc_type, start = None, end = None))]
pub(crate) fn fit<'py>(
    py: Python<'py>,
    xs: Stack1<'py>,
    ys: Stack2<'py>,
    bc_type: &str,
    start: EndArg,
    end: EndArg,
) -> PyResult<Splines> {
    let (xs, ys) = (xs.items()?, ys.items()?);
    if xs.len() != ys.len() {
        return Err(value_error(format!(
            "{} x arrays for {} y arrays",
            xs.len(),
            ys.len()
        )));
    }
    let dim = ys.first().map_or(1, |y| y.0);
    let condition = condition(bc_type, &start, &end, dim)?;
    let tables = py
        .detach(|| {
            on_threads(xs.len(), |c| {
                let (dim, y) = ys[c];
                let condition = condition
                    .on_few_points_as_scipy(xs[c], y, dim)
                    .map_err(|e| e.in_curve(c))?;
                if dim == 0 || dim > splinegpu::MAX_DIM {
                    return Err(InputError::field(
                        "points",
                        format!(
                            "must have 1 to {} values per x, got {dim}",
                            splinegpu::MAX_DIM
                        ),
                    )
                    .in_curve(c));
                }
                // Fitted from the caller's arrays where they lie (the fit checks them as a
                // curve's construction would): a copy of 1 M knots in 3-D is 32 MB of fresh
                // pages.
                let mut table = SegmentTable::default();
                Fitter::new()
                    .fit_into(xs[c], y, dim, &condition, &mut table)
                    .map_err(|e| e.in_curve(c))?;
                Ok(Arc::new(finite(table).map_err(|e| e.in_curve(c))?))
            })
        })
        .map_err(value_error)?;
    Ok(Splines { tables })
}

/// Every spline's pieces: coefficients (4, P, m), starts and ends (P,), offsets (S + 1,).
pub(crate) type Pieces<'py> = (
    Bound<'py, PyArray3<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i64>>,
);

/// One table's parts for pickling: its dimension, knots, power coefficients (A, B, C, D per
/// segment) and extent.
pub(crate) type TableState<'py> = (
    usize,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    f64,
);

/// Makes one cubic B-spline per (t, c) pair (the crate's kind "nurbs" without weights, which
/// is SciPy's `BSpline(t, c, 3)` on [t[3], t[n]]): c an (n', m) array whose first
/// n = len(t) − 4 rows are the coefficients (rows past them are ignored, as SciPy's).
/// `None` where the crate's kind does not take a spline SciPy takes (a knot inside the base
/// interval 4 times, where the spline breaks; more than 64 columns; slopes that overflow):
/// the package then makes the pieces itself.
#[pyfunction]
pub(crate) fn fit_bspline<'py>(
    py: Python<'py>,
    ts: Stack1<'py>,
    cs: Stack2<'py>,
) -> PyResult<Option<Splines>> {
    let (ts, cs) = (ts.items()?, cs.items()?);
    if ts.len() != cs.len() {
        return Err(value_error(format!(
            "{} knot arrays for {} coefficient arrays",
            ts.len(),
            cs.len()
        )));
    }
    let tables = py.detach(|| {
        on_threads(ts.len(), |s| {
            let (dim, c) = cs[s];
            let used = (ts[s].len().saturating_sub(4) * dim).min(c.len());
            let kind = CurveKind::Nurbs {
                knots: ts[s].to_vec(),
                weights: None,
            };
            let points = Points::new(dim, c[..used].to_vec())?;
            Ok(Arc::new(finite(Curve::new(kind, points)?.fit())?))
        })
    });
    // Every refusal here is of a spline SciPy's rules (checked by the package) let through.
    Ok(tables.ok().map(|tables| Splines { tables }))
}

/// The fitted table, refused where a coefficient is not finite: finite data whose slopes
/// overflow f64 (a jump of 1e300 over 1e-300), as SciPy refuses them.
///
/// A piece's coefficients in local u are y_0, h m_0 and sums of 3 (y_1 - y_0) and h m's, and
/// the fits' slopes stay within K max|q| <= K E / h_min (E the points' extent, q the chords,
/// K at most the spacing ratio r = (t_n - t_0) / h_min), so every coefficient is below
/// about 6 E r^2: data with E r^2 < 1e300 are finite without reading the coefficients (a
/// read of all of them would cost a tenth of the fit), the rest are read.
pub(crate) fn finite(table: SegmentTable) -> Result<SegmentTable, InputError> {
    let knots = table.knots();
    let spacing = knots
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let ratio = (knots[knots.len() - 1] - knots[0]) / spacing;
    if table.extent() * ratio * ratio < 1e300 || table.is_finite() {
        return Ok(table);
    }
    Err(InputError::field(
        "points",
        "the fitted slopes are not finite (the data's slopes overflow float64)".to_string(),
    ))
}

/// Curve c's kind and points (`make(c)`: the kind, values per point, coordinates) for every
/// c < n, each made into a curve and fitted on the library's threads; a curve's error names
/// it.
pub(crate) fn fit_curves(
    py: Python<'_>,
    n: usize,
    make: impl Fn(usize) -> Result<(CurveKind, usize, Vec<f64>), InputError> + Sync,
) -> PyResult<Splines> {
    let tables = py
        .detach(|| {
            on_threads(n, |c| {
                let (kind, dim, coords) = make(c)?;
                let points = Points::new(dim, coords).map_err(|e| e.in_curve(c))?;
                let table = Curve::new(kind, points).map_err(|e| e.in_curve(c))?.fit();
                Ok(Arc::new(finite(table).map_err(|e| e.in_curve(c))?))
            })
        })
        .map_err(value_error)?;
    Ok(Splines { tables })
}

/// Fits one cubic Hermite spline per (x, y) pair: y an (n, m) array at the n strictly
/// increasing x, its derivatives at the points given (`method` "given", `dydx` arrays like
/// the ys) or by SciPy's rules for each column ("pchip", "akima", "makima").
#[pyfunction]
#[pyo3(signature = (xs, ys, method, dydx = None))]
pub(crate) fn fit_hermite<'py>(
    py: Python<'py>,
    xs: Stack1<'py>,
    ys: Stack2<'py>,
    method: &str,
    dydx: Option<Stack2<'py>>,
) -> PyResult<Splines> {
    let (xs, ys) = (xs.items()?, ys.items()?);
    let dydx = dydx.as_ref().map(Stack2::items).transpose()?;
    if xs.len() != ys.len() || dydx.as_ref().is_some_and(|d| d.len() != ys.len()) {
        return Err(value_error(format!(
            "{} x arrays for {} y arrays",
            xs.len(),
            ys.len()
        )));
    }
    fit_curves(py, xs.len(), |c| {
        let (dim, y) = ys[c];
        let slopes = match (method, &dydx) {
            ("given", Some(dydx)) => HermiteSlopes::Given(dydx[c].1.to_vec()),
            ("pchip", None) => HermiteSlopes::Pchip,
            ("akima", None) => HermiteSlopes::Akima,
            ("makima", None) => HermiteSlopes::Makima,
            _ => {
                return Err(InputError::field(
                    "method",
                    format!("\"{method}\" is not a way to form the derivatives"),
                ));
            }
        };
        let kind = CurveKind::Hermite {
            slopes,
            t: Some(xs[c].to_vec()),
        };
        Ok((kind, dim, y.to_vec()))
    })
}

#[pymethods]
impl Splines {
    /// Number of splines.
    fn __len__(&self) -> usize {
        self.tables.len()
    }

    /// Every spline's table as parts (`from_state` restores them bit for bit): what pickling
    /// a spline saves, so that it reaches a Dask worker or a process pool without a refit.
    fn state<'py>(&self, py: Python<'py>) -> Vec<TableState<'py>> {
        self.tables
            .iter()
            .map(|table| {
                let coeffs: Vec<f64> = (0..table.len())
                    .flat_map(|i| table.segment(i).power().concat())
                    .collect();
                (
                    table.dim(),
                    PyArray1::from_slice(py, table.knots()),
                    PyArray1::from_vec(py, coeffs),
                    table.extent(),
                )
            })
            .collect()
    }

    /// The splines `state` saved; a part that breaks a rule is a ValueError naming it.
    #[staticmethod]
    fn from_state(
        state: Vec<(
            usize,
            PyReadonlyArray1<'_, f64>,
            PyReadonlyArray1<'_, f64>,
            f64,
        )>,
    ) -> PyResult<Self> {
        let tables = state
            .iter()
            .enumerate()
            .map(|(c, (dim, knots, coeffs, extent))| {
                SegmentTable::from_power(
                    *dim,
                    knots.as_slice()?.to_vec(),
                    coeffs.as_slice()?.to_vec(),
                    *extent,
                )
                .map(Arc::new)
                .map_err(|e| value_error(e.in_curve(c)))
            })
            .collect::<PyResult<Vec<_>>>()?;
        Ok(Self { tables })
    }

    /// Splines from their pieces laid end to end: spline s's knots are
    /// `knots[knot_offsets[s]..knot_offsets[s + 1]]`, its pieces' power coefficients (A, B, C,
    /// D per piece, `dim` values each, u = (x - x_j) / h) follow the previous splines' in
    /// `coeffs`, and `extents[s]` is its extent; a part that breaks a rule is a ValueError
    /// naming the spline.
    #[staticmethod]
    fn from_pieces(
        py: Python<'_>,
        dim: usize,
        knots: PyReadonlyArray1<'_, f64>,
        knot_offsets: PyReadonlyArray1<'_, i64>,
        coeffs: PyReadonlyArray1<'_, f64>,
        extents: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        let (knots, offsets) = (knots.as_slice()?, knot_offsets.as_slice()?);
        let (coeffs, extents) = (coeffs.as_slice()?, extents.as_slice()?);
        if offsets.len() != extents.len() + 1 {
            return Err(value_error(format!(
                "knot_offsets: {} for {} extents (wants one more)",
                offsets.len(),
                extents.len()
            )));
        }
        let mut parts = Vec::with_capacity(extents.len());
        let mut at = 0;
        for (s, pair) in offsets.windows(2).enumerate() {
            let (lo, hi) = (pair[0] as usize, pair[1] as usize);
            if pair[0] < 0 || lo > hi || hi > knots.len() || hi - lo < 2 {
                return Err(value_error(format!(
                    "knot_offsets[{s}..{}]: must span at least 2 of the {} knots, got {}..{}",
                    s + 1,
                    knots.len(),
                    pair[0],
                    pair[1]
                )));
            }
            let length = 4 * dim * (hi - lo - 1);
            let end = at + length;
            if end > coeffs.len() {
                return Err(value_error(format!(
                    "coeffs: {} values, spline {s} needs them to {end}",
                    coeffs.len()
                )));
            }
            parts.push((lo..hi, at..end, extents[s]));
            at = end;
        }
        let tables = py
            .detach(|| {
                on_threads(parts.len(), |s| {
                    let (k, c, extent) = parts[s].clone();
                    SegmentTable::from_power(dim, knots[k].to_vec(), coeffs[c].to_vec(), extent)
                        .map(Arc::new)
                        .map_err(|e| e.in_curve(s))
                })
            })
            .map_err(value_error)?;
        Ok(Self { tables })
    }

    /// Spline `i`'s coefficients as SciPy's PPoly holds them: c[k, j, :] multiplies
    /// (x − x_j)^(3−k) on interval j, shape (4, n − 1, m).
    fn coefficients<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let table = self
            .tables
            .get(i)
            .ok_or_else(|| value_error(format!("spline {i} of {}", self.tables.len())))?;
        let (n, m) = (table.len(), table.dim());
        let mut c = zeros(4 * n, m, "the pieces")?;
        scipy_coefficients(table, &mut c, n, 0);
        PyArray1::from_vec(py, c).reshape([4, n, m])
    }

    /// Every spline's pieces at once: (c (4, P, m) as `coefficients` gives them, piece after
    /// piece of spline after spline; each piece's start and end x (P,); offsets (S + 1,):
    /// spline s owns pieces offsets[s]..offsets[s + 1]).
    fn pieces<'py>(&self, py: Python<'py>) -> PyResult<Pieces<'py>> {
        let total: usize = self.tables.iter().map(|t| t.len()).sum();
        let m = self.tables.first().map_or(1, |t| t.dim());
        if let Some(s) = self.tables.iter().position(|t| t.dim() != m) {
            return Err(value_error(format!(
                "spline {s} has {} values per x where spline 0 has {m}",
                self.tables[s].dim()
            )));
        }
        let mut c = zeros(4 * total, m, "the pieces")?;
        let (mut start, mut end) = (Vec::with_capacity(total), Vec::with_capacity(total));
        let mut offsets = vec![0i64];
        let mut at = 0;
        for table in &self.tables {
            scipy_coefficients(table, &mut c, total, at);
            let knots = table.knots();
            start.extend_from_slice(&knots[..knots.len() - 1]);
            end.extend_from_slice(&knots[1..]);
            at += table.len();
            offsets.push(at as i64);
        }
        Ok((
            PyArray1::from_vec(py, c).reshape([4, total, m])?,
            PyArray1::from_vec(py, start),
            PyArray1::from_vec(py, end),
            PyArray1::from_vec(py, offsets),
        ))
    }

    /// `solve_pieces` of the splines' pieces (one value per x), read from the tables without
    /// forming the arrays.
    fn solve(
        &self,
        py: Python<'_>,
        y: f64,
        discontinuity: bool,
        extrapolate: bool,
    ) -> PyResult<PendingRoots> {
        let source = Box::new(TablePieces::new(&self.tables)?);
        let how = roots::Solve {
            y,
            discontinuity,
            extrapolate,
            exact: false,
        };
        Ok(PendingRoots::new(py, source, how))
    }

    /// Spline 0 at `x` (a contiguous 1-D float64 array), derivative `nu` (0, 1 or 2) with
    /// respect to x, on `context`: shape (len(x), m), float64 from the CPU, float32 from the
    /// GPU; `None` where an x is not finite or lies outside the knots (the caller's general
    /// route takes those). On the CPU each x is located and evaluated in one pass straight into
    /// the new array ([`splinegpu::evaluate_at_into`]); on the GPU through a job.
    fn evaluate_one<'py>(
        &self,
        py: Python<'py>,
        context: &Context,
        x: PyReadonlyArray1<'py, f64>,
        nu: usize,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        let table = self
            .tables
            .first()
            .ok_or_else(|| value_error("no spline to evaluate"))?;
        let x = x.as_slice()?;
        let derivatives = derivatives_of(nu)?;
        if let Some(gpu) = &context.gpu {
            let (lo, hi) = table.t_range();
            if !x.iter().all(|&v| v >= lo && v <= hi) {
                return Ok(None);
            }
            let job = one_spline_job(table, x, derivatives)?;
            let samples = py.detach(|| gpu.evaluate(&job)).map_err(runtime_error)?;
            return gpu_plane(py, samples, nu, table.dim()).map(Some);
        }
        let out = values_array(py, x.len(), table.dim())?;
        {
            let mut o = out.readwrite();
            let o = o.as_slice_mut()?;
            match py.detach(|| splinegpu::evaluate_at_into(table, x, nu, o, threads())) {
                Ok(()) => {}
                // An x outside the knots or not finite: the one refusal that is not an error.
                Err(e) if e.field.as_deref() == Some("at") => return Ok(None),
                Err(e) => return Err(value_error(e)),
            }
        }
        Ok(Some(out.into_any()))
    }

    /// Spline i at `at[i]` for every i, derivative `nu` (0, 1 or 2) with respect to x, on
    /// `context`: (values (N, m), offsets (S + 1,)), spline i's values in rows
    /// offsets[i]:offsets[i+1]. On the CPU the splines are spread over the pool, each x
    /// located and evaluated in one pass into the one result array.
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        context: &Context,
        at: Stack1<'py>,
        nu: usize,
    ) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let at = at.items()?;
        let derivatives = derivatives_of(nu)?;
        let tables = &self.tables;
        if at.len() != tables.len() {
            return Err(value_error(format!(
                "{} arrays of x for {} splines",
                at.len(),
                tables.len()
            )));
        }
        let dim = tables.first().map_or(1, |t| t.dim());
        if let Some(c) = tables.iter().position(|t| t.dim() != dim) {
            return Err(value_error(format!(
                "spline {c} has {} values per x where spline 0 has {dim}",
                tables[c].dim()
            )));
        }
        let offsets: Vec<i64> = std::iter::once(0)
            .chain(at.iter().scan(0usize, |rows, a| {
                *rows += a.len();
                Some(*rows as i64)
            }))
            .collect();
        let rows = at.iter().map(|a| a.len()).sum();
        let offsets = PyArray1::from_vec(py, offsets);
        match &context.gpu {
            Some(gpu) => {
                let job = py
                    .detach(|| {
                        let plans = on_threads(tables.len(), |c| {
                            SamplePlan::new(&tables[c], &Sampling::At(at[c].to_vec()))
                                .map_err(|e| e.in_curve(c))
                        })?;
                        let mut job = EvalJob::new(derivatives);
                        for (c, plan) in plans.into_iter().enumerate() {
                            job.push_shared(Arc::clone(&tables[c]), Arc::new(plan))
                                .map_err(|e| e.in_curve(c))?;
                        }
                        Ok::<_, InputError>(job)
                    })
                    .map_err(value_error)?;
                let samples = py.detach(|| gpu.evaluate(&job)).map_err(runtime_error)?;
                (gpu_plane(py, samples, nu, dim)?, offsets).into_pyobject(py)
            }
            _ => {
                let out = values_array(py, rows, dim)?;
                {
                    let mut o = out.readwrite();
                    let o = o.as_slice_mut()?;
                    py.detach(|| splinegpu::evaluate_curves_at_into(tables, &at, nu, o, threads()))
                        .map_err(value_error)?;
                }
                (out, offsets).into_pyobject(py)
            }
        }
    }
}

/// `table`'s pieces in SciPy's PPoly form into `c` (4 rows of `pieces` pieces of `dim`
/// values), from piece `first` on: c[k][j] multiplies (x − x_j)^(3−k). With
/// P(u) = A u³ + B u² + C u + D and u = (x − x_j)/Δ, the rows are A/Δ³, B/Δ², C/Δ, D.
pub(crate) fn scipy_coefficients(table: &SegmentTable, c: &mut [f64], pieces: usize, first: usize) {
    let m = table.dim();
    for j in 0..table.len() {
        let segment = table.segment(j);
        let dt = segment.dt();
        let [a, b, cc, d] = segment.power();
        let at = (first + j) * m;
        for k in 0..m {
            c[at + k] = a[k] / (dt * dt * dt);
            c[pieces * m + at + k] = b[k] / (dt * dt);
            c[2 * pieces * m + at + k] = cc[k] / dt;
            c[3 * pieces * m + at + k] = d[k];
        }
    }
}

/// The job's derivatives for an order the package offers, 0, 1 or 2 (the library's third
/// derivative is not offered yet: its agreement with SciPy on very uneven x is not
/// established).
pub(crate) fn derivatives_of(nu: usize) -> PyResult<Derivatives> {
    Derivatives::from_order(nu as u64)
        .ok_or_else(|| value_error(format!("nu: must be 0, 1 or 2, got {nu}")))
}

/// Plane `nu` of a GPU result as a (samples, dim) float32 array, taking over its vector.
pub(crate) fn gpu_plane(
    py: Python<'_>,
    samples: Samples<f32>,
    nu: usize,
    dim: usize,
) -> PyResult<Bound<'_, PyAny>> {
    let rows = samples.layout().samples();
    let (_, _, mut planes) = samples.into_parts();
    let plane = std::mem::take(&mut planes[nu]);
    Ok(PyArray1::from_vec(py, plane)
        .reshape([rows, dim])?
        .into_any())
}

/// One spline at explicit x as a job, for the GPU.
pub(crate) fn one_spline_job(
    table: &Arc<SegmentTable>,
    x: &[f64],
    derivatives: Derivatives,
) -> PyResult<EvalJob> {
    let plan = SamplePlan::new(table, &Sampling::At(x.to_vec())).map_err(value_error)?;
    let mut job = EvalJob::new(derivatives);
    job.push_shared(Arc::clone(table), Arc::new(plan))
        .map_err(value_error)?;
    Ok(job)
}

/// A new (rows, dim) float64 array for values at explicit x (zeroed by NumPy, which maps
/// fresh pages for a large one). One larger than the memory available is refused first, a
/// MemoryError naming its size (the check reads /proc/meminfo, so small arrays skip it).
pub(crate) fn values_array(
    py: Python<'_>,
    rows: usize,
    dim: usize,
) -> PyResult<Bound<'_, PyArray2<f64>>> {
    const CHECKED_BYTES: u128 = 1 << 26;
    let bytes = 8 * rows as u128 * dim as u128;
    if bytes >= CHECKED_BYTES
        && let Some(available) = available_memory().filter(|&a| bytes > a)
    {
        return Err(PyMemoryError::new_err(format!(
            "x: {rows} values of {dim} coordinates need {bytes} bytes; the process has \
             {available} bytes of memory available"
        )));
    }
    crate::args::new_zeros(py, &[rows, dim])
}
