//! `splinegpu._native`: the Rust half of the Python package. The Python half
//! (`python/splinegpu/__init__.py`) turns NumPy-shaped arguments (a (C, n, D) array or a list of
//! (n_i, D) arrays, SciPy's `bc_type`) into the plain per-curve lists taken here, and wraps the
//! results.
//!
//! Errors: a bad argument raises `ValueError` with the crate's located message (curve index,
//! field, value); a GPU failure raises `RuntimeError`. The GIL is released while fitting and
//! evaluating. Results come back without a copy where the crate's buffers allow it: a fresh
//! result's arrays take over the evaluator's vectors (NumPy owns them from then on); with `out=`
//! the CPU backend evaluates straight into the given arrays, while the GPU backend copies its
//! readback into them (the mapped GPU buffer cannot outlive the call).

use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyReadonlyArray3, PyUntypedArrayMethods,
};
use std::sync::Arc;

mod surfaces;

use bsplines::{banded, de_boor, fitpack, grid, lsq, pieces, roots, smoothing};

use pyo3::exceptions::{PyMemoryError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use splinegpu::PerPoint;
use splinegpu::kinds::KindFields;
use splinegpu::{
    Curve, CurveKind, Derivatives, End, EndCondition, Ends, EvalJob, Fitter, GpuContext,
    HermiteSlopes, InputError, Planes, Points, SampleFloat, SamplePlan, Samples, Sampling,
    SegmentTable,
};

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn runtime_error(e: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(e.to_string())
}

/// A batch of (n, D) arrays: one C-contiguous (C, n, D) array, a list of (n_i, D) arrays, or
/// (the rows laid end to end (N, D), offsets (C + 1,)): two borrows for any number of arrays.
#[derive(FromPyObject)]
enum Stack2<'py> {
    Dense(PyReadonlyArray3<'py, f64>),
    Ragged(Vec<PyReadonlyArray2<'py, f64>>),
    Flat(PyReadonlyArray2<'py, f64>, PyReadonlyArray1<'py, i64>),
}

impl Stack2<'_> {
    /// Each array's D and values.
    fn items(&self) -> PyResult<Vec<(usize, &[f64])>> {
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
enum Stack1<'py> {
    Dense(PyReadonlyArray2<'py, f64>),
    Ragged(Vec<PyReadonlyArray1<'py, f64>>),
    Flat(PyReadonlyArray1<'py, f64>, PyReadonlyArray1<'py, i64>),
}

impl Stack1<'_> {
    fn items(&self) -> PyResult<Vec<&[f64]>> {
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
fn rows<'a>(a: &'a PyReadonlyArray2<'_, f64>) -> PyResult<Vec<&'a [f64]>> {
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
enum PerCurve<'py> {
    Dense(PyReadonlyArray2<'py, f64>),
    Ragged(Vec<Option<PyReadonlyArray1<'py, f64>>>),
}

impl PerCurve<'_> {
    fn items(&self) -> PyResult<Vec<Option<&[f64]>>> {
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

/// `make(c)` for every c < n, on the library's pool of threads, in order; the first error in
/// curve order wins. One item is made on the calling thread, touching no pool.
fn on_threads<T: Send>(
    n: usize,
    make: impl Fn(usize) -> Result<T, InputError> + Sync,
) -> Result<Vec<T>, InputError> {
    use rayon::prelude::*;
    if n <= 1 {
        return (0..n).map(make).collect();
    }
    let make = &make;
    let made: Vec<Result<T, InputError>> = (0..n).into_par_iter().map(make).collect();
    made.into_iter().collect()
}

/// A job of `n` curves, each fitted and planned on every thread (`make(c)` gives curve c's
/// table and plan), then pushed in order; errors name their curve.
fn job_on_threads(
    n: usize,
    derivatives: Derivatives,
    make: impl Fn(usize) -> Result<(SegmentTable, SamplePlan), InputError> + Sync,
) -> Result<EvalJob, InputError> {
    let parts = on_threads(n, |c| make(c).map_err(|e| e.in_curve(c)))?;
    let mut job = EvalJob::new(derivatives);
    for (c, (table, plan)) in parts.into_iter().enumerate() {
        job.push_table(table, plan).map_err(|e| e.in_curve(c))?;
    }
    Ok(job)
}

/// A device (or the CPU) made once and reused: `Context(backend="auto" | "gpu" | "cpu")`.
#[pyclass(frozen, module = "splinegpu._native")]
struct Context {
    gpu: Option<GpuContext>,
    info: String,
}

#[pymethods]
impl Context {
    #[new]
    #[pyo3(signature = (backend = "auto"))]
    fn new(py: Python<'_>, backend: &str) -> PyResult<Self> {
        let gpu = match backend {
            "cpu" => None,
            "gpu" => Some(py.detach(GpuContext::new).map_err(runtime_error)?),
            "auto" => py.detach(GpuContext::auto).map_err(runtime_error)?,
            other => {
                return Err(value_error(format!(
                    "backend: must be \"auto\", \"gpu\" or \"cpu\", got \"{other}\""
                )));
            }
        };
        let info = match &gpu {
            Some(gpu) => {
                let info = gpu.adapter_info();
                format!(
                    "gpu: {} ({:?}, {:?}; driver {})",
                    info.name, info.device_type, info.backend, info.driver_info
                )
            }
            None => format!("cpu: f64 on {} threads", splinegpu::available_threads()),
        };
        Ok(Self { gpu, info })
    }

    /// The adapter (or "cpu: ...") this context evaluates on.
    #[getter]
    fn info(&self) -> &str {
        &self.info
    }

    /// "gpu" or "cpu".
    #[getter]
    fn backend(&self) -> &str {
        if self.gpu.is_some() { "gpu" } else { "cpu" }
    }

    /// Tessellates curves given as plain per-curve lists (see `splinegpu.Context.tessellate`).
    /// Returns (t, points, d1, d2, curve_offsets); d1 and d2 are None when not asked for.
    #[pyo3(signature = (points, kind, fields, sampling, derivatives, out))]
    #[allow(
        clippy::too_many_arguments,
        reason = "the Python call's arguments, one each"
    )]
    fn tessellate<'py>(
        &self,
        py: Python<'py>,
        points: Stack2<'py>,
        kind: &str,
        fields: CurveFields<'py>,
        sampling: SamplingArg<'py>,
        derivatives: u64,
        out: Option<Out<'py>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let derivatives = Derivatives::from_order(derivatives).ok_or_else(|| {
            value_error(format!("derivatives: must be 0, 1 or 2, got {derivatives}"))
        })?;
        let points = points.items()?;
        let kinds = KindSource::new(kind, &fields)?;
        let samplings = sampling.per_curve(points.len())?;
        let job = py
            .detach(|| {
                job_on_threads(points.len(), derivatives, |c| {
                    let (dim, coords) = points[c];
                    let curve = Curve::new(kinds.kind(c)?, Points::new(dim, coords.to_vec())?)?;
                    let table = curve.fit();
                    table.check_range(derivatives)?;
                    let plan = SamplePlan::new(&table, &samplings[c])?;
                    Ok((table, plan))
                })
            })
            .map_err(value_error)?;
        let offsets = offsets(&job);
        if let Some(out) = out {
            return out.fill(py, &job, self.gpu.as_ref(), offsets);
        }
        let value_bytes = if self.gpu.is_some() { 4 } else { 8 };
        check_result_fits(&job, value_bytes, &sampling.describe())?;
        let layout = job.layout();
        let dim = layout.max_dim();
        let same_dim = (0..job.len()).all(|c| layout.dim(c) == dim);
        match &self.gpu {
            // NumPy's own arrays, filled in place: its allocator advises large arrays as huge
            // pages, which a Rust Vec handed over does not get (fresh pages: docs/benchmarks.md).
            None if same_dim => Out::zeros::<f64>(py, &job)?.fill(py, &job, None, offsets),
            Some(gpu) if same_dim => {
                Out::zeros::<f32>(py, &job)?.fill(py, &job, Some(gpu), offsets)
            }
            None => {
                let samples = py.detach(|| splinegpu::evaluate_cpu::<f64>(&job, threads()));
                fresh(py, samples, offsets)
            }
            Some(gpu) => {
                let samples = py.detach(|| gpu.evaluate(&job)).map_err(runtime_error)?;
                fresh(py, samples, offsets)
            }
        }
    }
}

/// Per-curve kind fields, as the Python side normalises them (each list has one entry per
/// curve, or is None).
#[derive(FromPyObject)]
struct CurveFields<'py> {
    #[pyo3(item)]
    ends: Option<String>,
    #[pyo3(item)]
    tension: Option<f64>,
    #[pyo3(item)]
    bias: Option<f64>,
    #[pyo3(item)]
    matrix: Option<[[f64; 4]; 4]>,
    #[pyo3(item)]
    t: Option<PerCurve<'py>>,
    #[pyo3(item)]
    start_derivative: Option<PerCurve<'py>>,
    #[pyo3(item)]
    end_derivative: Option<PerCurve<'py>>,
    #[pyo3(item)]
    tangents: Option<PerCurve<'py>>,
    #[pyo3(item)]
    method: Option<String>,
    #[pyo3(item)]
    knots: Option<PerCurve<'py>>,
    #[pyo3(item)]
    weights: Option<PerCurve<'py>>,
    #[pyo3(item)]
    continuity: Option<f64>,
    /// Kochanek–Bartels' tension, continuity and bias given per point (one array per curve).
    #[pyo3(item)]
    tension_each: Option<PerCurve<'py>>,
    #[pyo3(item)]
    continuity_each: Option<PerCurve<'py>>,
    #[pyo3(item)]
    bias_each: Option<PerCurve<'py>>,
}

/// The sampling: its contract name and value; "at" holds one array per curve.
#[derive(FromPyObject)]
enum SamplingArg<'py> {
    At(String, Stack1<'py>),
    Count(String, u64),
    Tolerance(String, f64),
}

impl SamplingArg<'_> {
    /// The sampling as the call gave it: `per_segment=16`, `at=[...]`.
    fn describe(&self) -> String {
        match self {
            SamplingArg::At(name, _) => format!("{name}=[...]"),
            SamplingArg::Count(name, v) => format!("{name}={v}"),
            SamplingArg::Tolerance(name, v) => format!("{name}={v}"),
        }
    }

    fn per_curve(&self, curves: usize) -> PyResult<Vec<Sampling>> {
        let count = |name: &str, v: u64| -> PyResult<u32> {
            u32::try_from(v).map_err(|_| value_error(format!("{name}: {v} is too large")))
        };
        Ok(match self {
            SamplingArg::At(name, at) if name == "at" => {
                let at = at.items()?;
                if at.len() != curves {
                    return Err(value_error(format!(
                        "at: {} arrays for {curves} curves",
                        at.len()
                    )));
                }
                at.iter().map(|a| Sampling::At(a.to_vec())).collect()
            }
            SamplingArg::Count(name, v) if name == "per_segment" => {
                vec![Sampling::PerSegment(count(name, *v)?); curves]
            }
            SamplingArg::Count(name, v) if name == "arc_length" => {
                vec![Sampling::ArcLength(count(name, *v)?); curves]
            }
            SamplingArg::Tolerance(name, v) if name == "tolerance" => {
                vec![Sampling::Tolerance(*v); curves]
            }
            SamplingArg::Count(name, v) if name == "tolerance" => {
                vec![Sampling::Tolerance(*v as f64); curves]
            }
            SamplingArg::At(name, _)
            | SamplingArg::Count(name, _)
            | SamplingArg::Tolerance(name, _) => {
                return Err(value_error(format!(
                    "sampling: \"{name}\" is not one of per_segment, at, arc_length, tolerance"
                )));
            }
        })
    }
}

/// What each curve's kind is made of: the shared fields, and each curve's own t and end
/// derivatives, read from the arrays on the calling thread so that the kinds can be made on
/// every thread.
struct KindSource<'a> {
    name: &'a str,
    ends: Option<Ends>,
    tension: Option<f64>,
    bias: Option<f64>,
    matrix: Option<[[f64; 4]; 4]>,
    t: Vec<Option<&'a [f64]>>,
    start_derivative: Vec<Option<&'a [f64]>>,
    end_derivative: Vec<Option<&'a [f64]>>,
    tangents: Vec<Option<&'a [f64]>>,
    method: Option<&'a str>,
    knots: Vec<Option<&'a [f64]>>,
    weights: Vec<Option<&'a [f64]>>,
    continuity: Option<f64>,
    tension_each: Vec<Option<&'a [f64]>>,
    continuity_each: Vec<Option<&'a [f64]>>,
    bias_each: Vec<Option<&'a [f64]>>,
}

impl<'a> KindSource<'a> {
    fn new(name: &'a str, fields: &'a CurveFields<'_>) -> PyResult<Self> {
        let ends = match fields.ends.as_deref() {
            None => None,
            Some(name) => Some(Ends::from_name(name).ok_or_else(|| {
                value_error(format!(
                    "\"ends\" must be \"control\", \"repeat\" or \"closed\", got \"{name}\""
                ))
            })?),
        };
        let slices = |list: &'a Option<PerCurve<'_>>| match list {
            None => Ok(Vec::new()),
            Some(list) => list.items(),
        };
        Ok(Self {
            name,
            ends,
            tension: fields.tension,
            bias: fields.bias,
            matrix: fields.matrix,
            t: slices(&fields.t)?,
            start_derivative: slices(&fields.start_derivative)?,
            end_derivative: slices(&fields.end_derivative)?,
            tangents: slices(&fields.tangents)?,
            method: fields.method.as_deref(),
            knots: slices(&fields.knots)?,
            weights: slices(&fields.weights)?,
            continuity: fields.continuity,
            tension_each: slices(&fields.tension_each)?,
            continuity_each: slices(&fields.continuity_each)?,
            bias_each: slices(&fields.bias_each)?,
        })
    }

    /// Curve c's kind.
    fn kind(&self, c: usize) -> Result<CurveKind, InputError> {
        let own = |list: &[Option<&[f64]>]| list.get(c).copied().flatten().map(<[f64]>::to_vec);
        // Curve c's own values where given per point, else the number for every curve.
        let per_point = |each: &[Option<&[f64]>], all: Option<f64>| {
            own(each).map(PerPoint::Each).or(all.map(PerPoint::All))
        };
        CurveKind::named(
            self.name,
            KindFields {
                ends: self.ends,
                tension: per_point(&self.tension_each, self.tension),
                bias: per_point(&self.bias_each, self.bias),
                continuity: per_point(&self.continuity_each, self.continuity),
                matrix: self.matrix,
                t: own(&self.t),
                start_derivative: own(&self.start_derivative),
                end_derivative: own(&self.end_derivative),
                tangents: own(&self.tangents),
                method: self.method.map(str::to_owned),
                knots: own(&self.knots),
                weights: own(&self.weights),
            },
        )
    }
}

/// curve_offsets: curve c owns rows offsets[c]..offsets[c + 1].
fn offsets(job: &EvalJob) -> Vec<i64> {
    let layout = job.layout();
    std::iter::once(0)
        .chain((0..job.len()).map(|c| layout.samples_of(c).end as i64))
        .collect()
}

/// A result whose arrays take over `samples`' vectors (no copy).
fn fresh<'py, F: SampleFloat + numpy::Element>(
    py: Python<'py>,
    samples: Samples<F>,
    offsets: Vec<i64>,
) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
    let order = samples.derivatives().order();
    let (layout, t, [points, d1, d2]) = samples.into_parts();
    let dim = if layout.is_empty() {
        0
    } else {
        layout.max_dim()
    };
    let rows = layout.samples();
    let plane = |v: Vec<F>| -> PyResult<Py<PyAny>> {
        Ok(PyArray1::from_vec(py, v)
            .reshape([rows, dim])?
            .into_any()
            .unbind())
    };
    let d1 = if order >= 1 { plane(d1)? } else { py.None() };
    let d2 = if order >= 2 { plane(d2)? } else { py.None() };
    (
        PyArray1::from_vec(py, t),
        plane(points)?,
        d1,
        d2,
        PyArray1::from_vec(py, offsets),
    )
        .into_pyobject(py)
}

/// Refuses, before anything is allocated, a result larger than the memory the process has
/// available (`splinegpu::available_memory`: the machine's, its control group's and its
/// address-space limit's; where none can be read, NumPy's allocation raises MemoryError
/// itself): a MemoryError naming the sampling, the samples and the bytes.
fn check_result_fits(job: &EvalJob, value_bytes: u128, sampling: &str) -> PyResult<()> {
    let layout = job.layout();
    let (rows, values) = (layout.samples() as u128, layout.values() as u128);
    let planes = job.derivatives().order() as u128 + 1;
    let bytes = 8 * rows + value_bytes * values * planes + 8 * (job.len() as u128 + 1);
    match available_memory() {
        Some(available) if bytes > available => Err(PyMemoryError::new_err(format!(
            "tessellate: {sampling} gives {rows} samples, whose arrays need {bytes} bytes; \
             the process has {available} bytes of memory available"
        ))),
        _ => Ok(()),
    }
}

/// The bytes of memory the process may still allocate (`splinegpu::available_memory`).
fn available_memory() -> Option<u128> {
    splinegpu::available_memory().map(u128::from)
}

/// The arrays of an earlier result, reused (`out=`): t, points, d1, d2, curve_offsets.
#[derive(FromPyObject)]
struct Out<'py>(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAny>>,
    Bound<'py, PyArray1<i64>>,
);

impl<'py> Out<'py> {
    /// New NumPy arrays for `job`'s result (curves of one dimension), zeroed by NumPy.
    fn zeros<F: numpy::Element>(py: Python<'py>, job: &EvalJob) -> PyResult<Self> {
        let layout = job.layout();
        let (rows, dim) = (layout.samples(), layout.max_dim());
        let order = job.derivatives().order();
        let plane = || PyArray2::<F>::zeros(py, [rows, dim], false).into_any();
        Ok(Out(
            PyArray1::<f64>::zeros(py, rows, false),
            plane(),
            (order >= 1).then(plane),
            (order >= 2).then(plane),
            PyArray1::<i64>::zeros(py, job.len() + 1, false),
        ))
    }

    /// Evaluates `job` into these arrays and returns them.
    fn fill(
        self,
        py: Python<'py>,
        job: &EvalJob,
        gpu: Option<&GpuContext>,
        offsets: Vec<i64>,
    ) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let layout = job.layout();
        let rows = layout.samples();
        let dim = if job.is_empty() { 0 } else { layout.max_dim() };
        let order = job.derivatives().order();
        if (0..job.len()).any(|c| layout.dim(c) != dim) {
            return Err(value_error(
                "out: curves of different dimensions have no (N, D) arrays to reuse",
            ));
        }
        let Out(t, points, d1, d2, curve_offsets) = self;
        let wrong =
            |what: &str| value_error(format!("out: {what} does not match this call's result"));
        if t.len() != rows || curve_offsets.len() != offsets.len() {
            return Err(wrong("t or curve_offsets"));
        }
        let planes: Vec<Bound<'py, PyAny>> = [Some(points), d1, d2]
            .into_iter()
            .take(order + 1)
            .map(|p| p.ok_or_else(|| wrong("a derivative array")))
            .collect::<PyResult<_>>()?;
        // Every array is checked before any is written.
        let contiguous = |name: &str| value_error(format!("out: {name} must be contiguous"));
        let mut offsets_view = writeable(&curve_offsets, "curve_offsets")?;
        let offsets_slice = offsets_view
            .as_slice_mut()
            .map_err(|_| contiguous("curve_offsets"))?;
        let mut t_view = writeable(&t, "t")?;
        let t_slice = t_view.as_slice_mut().map_err(|_| contiguous("t"))?;
        match gpu {
            None => fill_planes::<f64>(&planes, [rows, dim], "float64 arrays", |p| {
                py.detach(|| splinegpu::evaluate_cpu_into(job, p.with_t(t_slice), threads()));
                Ok(())
            })?,
            Some(gpu) => fill_planes::<f32>(&planes, [rows, dim], "float32 arrays", |p| {
                py.detach(|| gpu.evaluate_into(job, p.with_t(t_slice)))
                    .map_err(runtime_error)
            })?,
        }
        offsets_slice.copy_from_slice(&offsets);
        drop(offsets_view);
        drop(t_view);
        let mut items: Vec<Py<PyAny>> = vec![t.into_any().unbind()];
        for p in 0..3 {
            items.push(
                planes
                    .get(p)
                    .map_or_else(|| py.None(), |a| a.clone().unbind()),
            );
        }
        items.push(curve_offsets.into_any().unbind());
        pyo3::types::PyTuple::new(py, items)
    }
}

/// Borrows `arrays` (positions, then the derivatives asked for) as writable planes of `F`,
/// each `len` values, and hands them to `fill` as [`Planes`].
fn fill_planes<'py, F: numpy::Element>(
    arrays: &[Bound<'py, PyAny>],
    [rows, dim]: [usize; 2],
    dtype: &str,
    fill: impl FnOnce(Planes<'_, F>) -> PyResult<()>,
) -> PyResult<()> {
    let wrong = |what: &str| value_error(format!("out: {what} does not match this call's result"));
    let arrays: Vec<Bound<'py, PyArray2<F>>> = arrays
        .iter()
        .map(|p| p.cast::<PyArray2<F>>().cloned().map_err(|_| wrong(dtype)))
        .collect::<PyResult<_>>()?;
    let mut views = Vec::with_capacity(arrays.len());
    for (p, array) in arrays.iter().enumerate() {
        let name = ["points", "d1", "d2"][p];
        // The values are written row after row: only a C-ordered (N, D) array holds them so.
        if array.shape() != [rows, dim] || !array.is_c_contiguous() {
            return Err(value_error(format!(
                "out: {name} must be a C-ordered array of shape ({rows}, {dim}), got shape {:?}{}",
                array.shape(),
                if array.is_c_contiguous() {
                    ""
                } else {
                    " not C-ordered"
                }
            )));
        }
        views.push(writeable(array, name)?);
    }
    let mut slices = Vec::with_capacity(views.len());
    for view in &mut views {
        slices.push(view.as_slice_mut()?);
    }
    let mut slices = slices.into_iter();
    let points = slices.next().ok_or_else(|| wrong("points"))?;
    fill(Planes {
        t: None,
        points,
        d1: slices.next(),
        d2: slices.next(),
    })
}

/// `array` borrowed for writing, or a ValueError naming it (`out: d1 ...`): read-only, or
/// sharing its memory with another array of the same call (the same array given twice).
fn writeable<'py, T: numpy::Element, D: numpy::ndarray::Dimension>(
    array: &Bound<'py, numpy::PyArray<T, D>>,
    name: &str,
) -> PyResult<numpy::PyReadwriteArray<'py, T, D>> {
    array.try_readwrite().map_err(|e| {
        value_error(match e {
            numpy::BorrowError::NotWriteable => format!("out: {name} is not writeable"),
            _ => format!("out: {name} shares its memory with another array of out"),
        })
    })
}

/// The threads every CPU evaluation uses.
fn threads() -> usize {
    splinegpu::available_threads()
}

/// One fitted interpolating spline, or many: what `splinegpu.CubicSpline` holds.
#[pyclass(frozen, module = "splinegpu._native")]
struct Splines {
    /// Shared with every evaluation's job: a call copies no knots.
    tables: Vec<Arc<SegmentTable>>,
}

/// One end given on its own, as the Python side spells it: ("first" | "second", values) or
/// ("not-a-knot", None); `None` is a first derivative of zero (SciPy's "clamped").
type EndArg = Option<(String, Option<Vec<f64>>)>;

/// An end's derivative values, zeros where none are given.
fn end_values(end: &EndArg, dim: usize) -> Vec<f64> {
    end.as_ref()
        .and_then(|(_, v)| v.clone())
        .unwrap_or_else(|| vec![0.0; dim])
}

/// An end given on its own ([`End`]).
fn end_of(end: &EndArg, dim: usize) -> PyResult<End> {
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
fn condition(bc: &str, start: &EndArg, end: &EndArg, dim: usize) -> PyResult<EndCondition> {
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

/// SciPy's periodic spline on 2 points: equal points give the constant (the one periodic
/// cubic through them), which is the spline clamped to slopes zero; elsewhere the condition
/// itself (the fit checks it).
fn scipy_periodic(x: &[f64], y: &[f64], dim: usize) -> Result<EndCondition, InputError> {
    if x.len() != 2 || y.len() != 2 * dim {
        return Ok(EndCondition::Periodic);
    }
    if y[..dim] != y[dim..] {
        return Err(InputError::field(
            "points",
            "of a periodic spline must end where they start (2 points: equal)",
        ));
    }
    Ok(EndCondition::Clamped {
        start: vec![0.0; dim],
        end: vec![0.0; dim],
    })
}

/// SciPy's not-a-knot condition at `x` for `y` (`dim` values a point). On 2 or 3 points SciPy
/// gives the line or the parabola through them; each is the clamped spline with that
/// polynomial's slopes at its ends (the one cubic spline that meets them). With divided
/// differences d_i = (y_{i+1} − y_i)/h_i, the line's slope is d_0; the parabola's is d_0 at the
/// middle of the first interval and changes by (d_1 − d_0)/((h_0 + h_1)/2) per unit of x, so
/// at its ends it is d_0 − (d_1 − d_0)·h_0/(h_0 + h_1) and d_1 + (d_1 − d_0)·h_1/(h_0 + h_1).
/// On 4 or more points, or where x and y disagree in length (the fit names that), the
/// condition itself.
fn scipy_not_a_knot(x: &[f64], y: &[f64], dim: usize) -> EndCondition {
    if !matches!(x.len(), 2 | 3) || y.len() != x.len() * dim {
        return EndCondition::NotAKnot;
    }
    let slope = |i: usize, k: usize| (y[(i + 1) * dim + k] - y[i * dim + k]) / (x[i + 1] - x[i]);
    let (start, end) = if x.len() == 2 {
        let line: Vec<f64> = (0..dim).map(|k| slope(0, k)).collect();
        (line.clone(), line)
    } else {
        let (h0, h1) = (x[1] - x[0], x[2] - x[1]);
        let bend = |k: usize| slope(1, k) - slope(0, k);
        (
            (0..dim)
                .map(|k| slope(0, k) - bend(k) * h0 / (h0 + h1))
                .collect(),
            (0..dim)
                .map(|k| slope(1, k) + bend(k) * h1 / (h0 + h1))
                .collect(),
        )
    };
    EndCondition::Clamped { start, end }
}

/// Fits one spline per (x, y) pair: y an (n, m) array at the n strictly increasing x.
#[pyfunction]
#[pyo3(signature = (xs, ys, bc_type, start = None, end = None))]
fn fit<'py>(
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
                let condition = match condition {
                    EndCondition::NotAKnot => scipy_not_a_knot(xs[c], y, dim),
                    EndCondition::Periodic => {
                        scipy_periodic(xs[c], y, dim).map_err(|e| e.in_curve(c))?
                    }
                    ref other => other.clone(),
                };
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
type Pieces<'py> = (
    Bound<'py, PyArray3<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i64>>,
);

/// One table's parts for pickling: its dimension, knots, power coefficients (A, B, C, D per
/// segment) and extent.
type TableState<'py> = (
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
fn fit_bspline<'py>(
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
fn finite(table: SegmentTable) -> Result<SegmentTable, InputError> {
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
fn fit_curves(
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
fn fit_hermite<'py>(
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
        let mut c = vec![0.0; 4 * n * m];
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
        let mut c = vec![0.0; 4 * total * m];
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
fn scipy_coefficients(table: &SegmentTable, c: &mut [f64], pieces: usize, first: usize) {
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
fn derivatives_of(nu: usize) -> PyResult<Derivatives> {
    Derivatives::from_order(nu as u64)
        .ok_or_else(|| value_error(format!("nu: must be 0, 1 or 2, got {nu}")))
}

/// Plane `nu` of a GPU result as a (samples, dim) float32 array, taking over its vector.
fn gpu_plane(
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
fn one_spline_job(
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
fn values_array(py: Python<'_>, rows: usize, dim: usize) -> PyResult<Bound<'_, PyArray2<f64>>> {
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
    Ok(PyArray2::<f64>::zeros(py, [rows, dim], false))
}

/// A ragged result: the values, and offsets (S + 1) splitting them per spline.
type Ragged<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<i64>>);

/// The pieces the closed forms leave to the eigenvalues: their numbers and coefficients (h, 4).
type Undecided<'py> = (Bound<'py, PyArray1<i64>>, Bound<'py, PyArray2<f64>>);

/// The splines' fitted tables as the root finder's pieces, in SciPy's coefficients (formed as
/// `scipy_coefficients` forms them): one value per x only.
#[derive(Debug)]
struct TablePieces {
    tables: Vec<Arc<SegmentTable>>,
    first: Vec<usize>,
}

impl TablePieces {
    fn new(tables: &[Arc<SegmentTable>]) -> PyResult<Self> {
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
fn arrays(
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
struct PendingRoots {
    source: Box<dyn roots::Source + Send>,
    how: roots::Solve,
    pending: Option<roots::Pending>,
}

impl PendingRoots {
    fn new(py: Python<'_>, source: Box<dyn roots::Source + Send>, how: roots::Solve) -> Self {
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
fn solve_pieces(
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

/// X with A X = B for a banded A given by rows (row i: `rows[i]`'s values from column
/// `first[i]`) and B (n, m), by elimination with partial pivoting inside the band (see
/// `banded`); None when A is singular. The B-spline fits of any degree solve their collocation
/// systems here.
#[pyfunction]
fn solve_banded<'py>(
    py: Python<'py>,
    first: PyReadonlyArray1<'_, i64>,
    rows: PyReadonlyArray2<'_, f64>,
    rhs: PyReadonlyArray2<'_, f64>,
) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
    let first = first.as_slice()?;
    let (n, width) = (rows.shape()[0], rows.shape()[1]);
    let m = rhs.shape()[1];
    if first.len() != n || rhs.shape()[0] != n {
        return Err(PyValueError::new_err(format!(
            "solve_banded: {} first columns and {} right-hand rows for {n} rows",
            first.len(),
            rhs.shape()[0]
        )));
    }
    let first: Vec<usize> = first
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            usize::try_from(f)
                .ok()
                .filter(|&f| f + width <= n)
                .ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "solve_banded: row {i} starts at column {f}, outside the {n} columns"
                    ))
                })
        })
        .collect::<PyResult<_>>()?;
    let values = rows.as_slice()?.to_vec();
    let mut x = rhs.as_slice()?.to_vec();
    let solved = py.detach(|| banded::solve(&first, &values, width, &mut x, m));
    if !solved {
        return Ok(None);
    }
    Ok(Some(PyArray1::from_vec(py, x).reshape([n, m])?))
}

/// One series of a fit: x, y (rows of m values) and w.
type Series<'a> = (&'a [f64], &'a [f64], &'a [f64]);

/// Least-squares fits: the stacked coefficients, each series' residual, the first singular
/// series.
type LsqFits<'py> = (Bound<'py, PyArray2<f64>>, Vec<f64>, Option<usize>);

/// FITPACK fits: the knots stacked, their offsets, the coefficients stacked, each ier.
/// `fit_splrep_from`'s answer: knots, coefficients, ier and where the search stopped.
type SearchedFit<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    u8,
    (Vec<f64>, f64, usize),
);

type FitpackFits<'py> = (
    Bound<'py, PyArray1<f64>>,
    Vec<i64>,
    Bound<'py, PyArray2<f64>>,
    Vec<u8>,
);

/// Each series' columns' lams (S, m).
type Lams<'py> = Bound<'py, PyArray2<f64>>;

/// Smoothing splines' knots laid end to end, their coefficients stacked, and their lams.
type SmoothingFits<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Lams<'py>,
);

/// One column's smoothing spline.
type Smoothed = Result<smoothing::Fit, smoothing::Failure>;

/// A batch's series laid end to end: one array each (ragged lists handed over as thousands
/// of arrays cost a borrow check apiece, which grows with the borrows held), series i at
/// rows offsets[i]..offsets[i + 1].
fn ragged<'a>(
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

/// Each series' (x, y, w) of a batch: x and y as the batch types hold them (y's rows of m
/// values, one m for all), w likewise or None for unit weights, which are then slices of
/// `ones` (one run of ones as long as the longest series, not a second array of N ones).
fn series<'a>(
    xs: &'a Stack1<'_>,
    ys: &'a Stack2<'_>,
    ws: Option<&'a Stack1<'_>>,
    ones: &'a mut Vec<f64>,
) -> PyResult<(Vec<Series<'a>>, usize)> {
    let (xs, ys) = (xs.items()?, ys.items()?);
    let ws = ws.map(Stack1::items).transpose()?;
    if ys.len() != xs.len() || ws.as_ref().is_some_and(|w| w.len() != xs.len()) {
        return Err(value_error(format!(
            "{} x arrays, {} y arrays and {} w arrays",
            xs.len(),
            ys.len(),
            ws.as_ref().map_or(xs.len(), Vec::len)
        )));
    }
    let m = ys.first().map_or(0, |&(m, _)| m);
    for (i, (x, &(mi, y))) in xs.iter().zip(&ys).enumerate() {
        if mi != m || y.len() != x.len() * m {
            return Err(value_error(format!(
                "ys[{i}]: {} values in rows of {mi} for {} x (rows of {m})",
                y.len(),
                x.len()
            )));
        }
        if let Some(w) = ws.as_ref().map(|w| w[i]).filter(|w| w.len() != x.len()) {
            return Err(value_error(format!(
                "ws[{i}]: {} weights for {} x",
                w.len(),
                x.len()
            )));
        }
    }
    if ws.is_none() {
        ones.resize(xs.iter().map(|x| x.len()).max().unwrap_or(0), 1.0);
    }
    let ones: &'a [f64] = ones;
    let data = xs
        .into_iter()
        .zip(ys)
        .enumerate()
        .map(|(i, (x, (_, y)))| {
            let w = match &ws {
                Some(ws) => ws[i],
                None => &ones[..x.len()],
            };
            (x, y, w)
        })
        .collect();
    Ok((data, m))
}

/// A bad series of a batch as the batch doors name it: "xs[3]: <SciPy's words> (at index 17)"
/// for the per-series arrays, `InputError`'s own words for the rest.
fn series_error(e: &bsplines::InputError) -> String {
    let at = e
        .position
        .map(|p| format!(" (at index {p})"))
        .unwrap_or_default();
    match e.series {
        Some(i) if matches!(e.argument, "x" | "y" | "w" | "t") => {
            format!("{}s[{i}]: {}{at}", e.argument, e.message)
        }
        _ => e.to_string(),
    }
}

/// Per-series row blocks stacked into one (rows, m) array.
fn stacked(py: Python<'_>, blocks: Vec<Vec<f64>>, m: usize) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let flat: Vec<f64> = blocks.concat();
    let rows = flat.len() / m.max(1);
    PyArray1::from_vec(py, flat).reshape([rows, m])
}

/// Least-squares splines of degree k, one per series, on every thread (`lsq::fit`): xs, ys
/// (rows of m) and ws (None: unit weights) as the batch types take them, the knots laid end
/// to end with their offsets. The coefficients stacked ((sum of len(t_i) - k - 1), m), each
/// series' weighted residual sum of squares, and the series whose knots no data supports
/// (Schoenberg-Whitney), if any.
#[pyfunction]
fn fit_lsq<'py>(
    py: Python<'py>,
    xs: Stack1<'py>,
    ys: Stack2<'py>,
    ws: Option<Stack1<'py>>,
    t: PyReadonlyArray1<'py, f64>,
    t_offsets: PyReadonlyArray1<'py, i64>,
    k: usize,
) -> PyResult<LsqFits<'py>> {
    use rayon::prelude::*;
    let mut ones = Vec::new();
    let (data, m) = series(&xs, &ys, ws.as_ref(), &mut ones)?;
    let ts = ragged(t.as_slice()?, 1, t_offsets.as_slice()?, "ts")?;
    if ts.len() != data.len() || ts.iter().any(|t| t.len() < 2 * k + 2) {
        return Err(value_error(format!(
            "fit_lsq: {} knot vectors for {} series, each at least {} knots",
            ts.len(),
            data.len(),
            2 * k + 2
        )));
    }
    let fits: Vec<Result<Option<lsq::Fit>, String>> = py.detach(|| {
        data.par_iter()
            .zip(&ts)
            .enumerate()
            .map(|(i, (&(x, y, w), t))| {
                lsq::check(x, y, w, t, k).map_err(|e| series_error(&e.in_series(i)))?;
                Ok(lsq::fit(x, y, m, w, t, k))
            })
            .collect()
    });
    let fits = fits
        .into_iter()
        .collect::<Result<Vec<_>, String>>()
        .map_err(value_error)?;
    let singular = fits.iter().position(Option::is_none);
    let (blocks, residuals): (Vec<Vec<f64>>, Vec<f64>) = fits
        .into_iter()
        .zip(&ts)
        .map(|(f, t)| match f {
            Some(f) => (f.c, f.residual),
            None => (vec![f64::NAN; (t.len() - k - 1) * m], f64::NAN),
        })
        .unzip();
    Ok((stacked(py, blocks, m)?, residuals, singular))
}

/// The smoothing splines of every (series, column), each one job of `smoothing::fit`, the
/// jobs in chunks on every thread; in job order (series by series, their columns in turn).
fn smoothing_fits(data: &[Series<'_>], m: usize, given: &[f64]) -> Vec<Smoothed> {
    use rayon::prelude::*;
    use smoothing::{Column, Job};
    let jobs: Vec<Job<'_>> = data
        .iter()
        .enumerate()
        .flat_map(|(i, &(x, y, w))| {
            (0..m).map(move |col| Job {
                x,
                w,
                y: Column {
                    values: y,
                    stride: m,
                    offset: col,
                },
                lam: Some(given[i * m + col]).filter(|lam| !lam.is_nan()),
            })
        })
        .collect();
    // Chunks small enough to keep every thread busy, large enough to keep the lanes full.
    let chunk = jobs
        .len()
        .div_ceil(splinegpu::available_threads() * 8)
        .max(8);
    jobs.par_chunks(chunk)
        .flat_map_iter(smoothing::fit)
        .collect()
}

/// `parts` laid end to end on every thread: one output, part i at its offset (each part's
/// pages first touched by the thread that writes it).
fn laid_end_to_end(
    lengths: impl Iterator<Item = usize>,
    fill: impl Fn(usize, &mut [f64]) + Sync,
) -> Vec<f64> {
    use rayon::prelude::*;
    let lengths: Vec<usize> = lengths.collect();
    let mut out = vec![0.0; lengths.iter().sum()];
    let mut parts = Vec::with_capacity(lengths.len());
    let mut rest = out.as_mut_slice();
    for &length in &lengths {
        let (part, tail) = rest.split_at_mut(length);
        parts.push(part);
        rest = tail;
    }
    parts
        .into_par_iter()
        .enumerate()
        .for_each(|(i, part)| fill(i, part));
    out
}

/// Cubic smoothing splines, one per series, on every thread (`smoothing`): xs, ys (rows of m)
/// and ws (None: unit weights) as the batch types take them; lams (S, m) holds
/// each column's lam, NaN where GCV chooses it. Each series' knots [x_0] * 3 + x + [x_last] * 3
/// laid end to end (sum of n_i + 6), the B-spline coefficients on them stacked
/// ((sum of n_i + 2), m), and the lams used.
#[pyfunction]
fn fit_smoothing<'py>(
    py: Python<'py>,
    xs: Stack1<'py>,
    ys: Stack2<'py>,
    ws: Option<Stack1<'py>>,
    lams: PyReadonlyArray2<'py, f64>,
) -> PyResult<SmoothingFits<'py>> {
    use rayon::prelude::*;
    let mut ones = Vec::new();
    let (data, m) = series(&xs, &ys, ws.as_ref(), &mut ones)?;
    let given = lams.as_slice()?;
    if lams.shape() != [data.len(), m] {
        return Err(value_error(format!(
            "fit_smoothing: lams of shape {:?} for {} series of {m} columns",
            lams.shape(),
            data.len()
        )));
    }
    let checked: Result<(), bsplines::InputError> = py.detach(|| {
        data.par_iter()
            .enumerate()
            .try_for_each(|(i, &(x, y, w))| smoothing::check(x, y, w).map_err(|e| e.in_series(i)))
    });
    checked.map_err(|e| value_error(series_error(&e)))?;
    let fitted = py.detach(|| smoothing_fits(&data, m, given));
    if let Some((job, e)) = fitted
        .iter()
        .enumerate()
        .find_map(|(job, f)| f.as_ref().err().map(|e| (job, e)))
    {
        let i = job / m;
        return Err(value_error(match e {
            smoothing::Failure::IllPosed => {
                format!("series {i}: Seems like the problem is ill-posed")
            }
            smoothing::Failure::NoMinimum(why) => {
                format!("series {i}: Unable to find minimum of the GCV function: {why}")
            }
        }));
    }
    let fits: Vec<&smoothing::Fit> = fitted.iter().flatten().collect();
    let (knots, c) = py.detach(|| {
        let knots = laid_end_to_end(data.iter().map(|d| d.0.len() + 6), |i, part| {
            let x = data[i].0;
            let n = x.len();
            part[..3].fill(x[0]);
            part[3..n + 3].copy_from_slice(x);
            part[n + 3..].fill(x[n - 1]);
        });
        let c = laid_end_to_end(data.iter().map(|d| (d.0.len() + 2) * m), |i, part| {
            for col in 0..m {
                for (j, v) in fits[i * m + col].c.iter().enumerate() {
                    part[j * m + col] = *v;
                }
            }
        });
        (knots, c)
    });
    let used: Vec<f64> = fits.iter().map(|f| f.lam).collect();
    let lams = PyArray1::from_vec(py, used).reshape([data.len(), m])?;
    let rows = c.len() / m.max(1);
    Ok((
        PyArray1::from_vec(py, knots),
        PyArray1::from_vec(py, c).reshape([rows, m])?,
        lams,
    ))
}

/// FITPACK smoothing splines (`fits::fitpack_fit`), one per series, on every thread: series i's
/// x, y (rows of d), w (None: unit weights; each as the batch types take them), [xb_i, xe_i]
/// and s_i, degree k, knots found (or given in `ts`), at most `nest` of them (None: FITPACK's
/// default). The knots stacked with their offsets, the
/// coefficients stacked ((sum of len(t_i) - k - 1), d), and each root finder's ier.
#[pyfunction]
#[pyo3(signature = (xs, ys, ws, xb, xe, k, s, t = None, nest = None, periodic = false))]
#[expect(
    clippy::too_many_arguments,
    clippy::needless_pass_by_value,
    reason = "FITPACK's arguments, one each; PyO3 extracts lists as Vecs"
)]
fn fit_splrep<'py>(
    py: Python<'py>,
    xs: Stack1<'py>,
    ys: Stack2<'py>,
    ws: Option<Stack1<'py>>,
    xb: Vec<f64>,
    xe: Vec<f64>,
    k: usize,
    s: Vec<f64>,
    t: Option<(PyReadonlyArray1<'py, f64>, PyReadonlyArray1<'py, i64>)>,
    nest: Option<usize>,
    periodic: bool,
) -> PyResult<FitpackFits<'py>> {
    use rayon::prelude::*;
    let mut ones = Vec::new();
    let (data, d) = series(&xs, &ys, ws.as_ref(), &mut ones)?;
    let given = match &t {
        Some((t, t_offsets)) => Some(ragged(t.as_slice()?, 1, t_offsets.as_slice()?, "t")?),
        None => None,
    };
    if xb.len() != data.len() || xe.len() != data.len() || s.len() != data.len() {
        return Err(value_error("fit_splrep: one xb, xe and s per series"));
    }
    if !(1..=6).contains(&k) {
        return Err(value_error(format!("k: must be 1 to 6, got {k}")));
    }
    let fitted: Vec<Result<fitpack::Spline, String>> = py.detach(|| {
        data.par_iter()
            .enumerate()
            .map(|(i, &(x, y, w))| {
                let one = fitpack::Data {
                    x,
                    y,
                    d,
                    w,
                    xb: xb[i],
                    xe: xe[i],
                };
                let named = |e: &str| e.replace("{i}", &i.to_string());
                fitpack::check(&one, k, periodic).map_err(|e| series_error(&e.in_series(i)))?;
                let t = given.as_ref().map(|g| g[i]);
                let most = nest.unwrap_or(fitpack::default_nest(x.len(), k, periodic));
                bsplines::fits::fitpack_fit(&one, k, s[i], t, most, periodic).map_err(|_| {
                    named("series {i}: a least-squares system is singular (the knots and x violate the Schoenberg-Whitney conditions)")
                })
            })
            .collect()
    });
    let fitted = fitted
        .into_iter()
        .collect::<Result<Vec<_>, String>>()
        .map_err(value_error)?;
    let mut offsets = vec![0_i64];
    let (mut knots, mut blocks, mut iers) = (Vec::new(), Vec::new(), Vec::new());
    for spline in fitted {
        knots.extend_from_slice(&spline.t);
        offsets.push(i64::try_from(knots.len()).unwrap_or(i64::MAX));
        blocks.push(spline.c);
        iers.push(spline.ier);
    }
    Ok((
        PyArray1::from_vec(py, knots),
        offsets,
        stacked(py, blocks, d)?,
        iers,
    ))
}

/// UnivariateSpline's fit, one series, with where its knot search stopped: from the
/// polynomial, or (`from` = (t, fpold, nplus) of an earlier fit of these data)
/// on from there, as curfit's iopt = 1 (`fitpack::knots_from`). Returns (t, c (rows, d),
/// ier, (t, fpold, nplus)).
#[pyfunction]
#[pyo3(signature = (x, y, w, xb, xe, k, s, from = None))]
#[expect(
    clippy::too_many_arguments,
    clippy::needless_pass_by_value,
    reason = "curfit's arguments, one each; PyO3 extracts the state's knots as a Vec"
)]
fn fit_splrep_from<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    y: PyReadonlyArray1<'py, f64>,
    w: PyReadonlyArray1<'py, f64>,
    xb: f64,
    xe: f64,
    k: usize,
    s: f64,
    from: Option<(Vec<f64>, f64, usize)>,
) -> PyResult<SearchedFit<'py>> {
    let (x, y, w) = (x.as_slice()?, y.as_slice()?, w.as_slice()?);
    if y.len() != x.len() || w.len() != x.len() {
        return Err(value_error(
            "fit_splrep_from: x, y and w must have one length",
        ));
    }
    if !((1..=6).contains(&k) && s > 0.0 && s.is_finite()) {
        return Err(value_error(format!(
            "fit_splrep_from: k 1 to 6 and s > 0, got k = {k}, s = {s}"
        )));
    }
    let data = fitpack::Data {
        x,
        y,
        d: 1,
        w,
        xb,
        xe,
    };
    fitpack::check(&data, k, false).map_err(|e| value_error(series_error(&e.in_series(0))))?;
    let from = from.map(|(t, fpold, nplus)| fitpack::Search { t, fpold, nplus });
    let nest = fitpack::default_nest(x.len(), k, false);
    let fitted = py.detach(|| {
        let search = fitpack::knots_from(&data, k, s, nest, from.as_ref())?;
        fitpack::smooth(&data, &search.t, k, s).map(|spline| (spline, search))
    });
    let (spline, search) = fitted.map_err(|_| {
        value_error("x: a least-squares system is singular (the knots and x violate the Schoenberg-Whitney conditions)")
    })?;
    Ok((
        PyArray1::from_vec(py, spline.t),
        PyArray1::from_vec(py, spline.c),
        spline.ier,
        (search.t, search.fpold, search.nplus),
    ))
}

/// GCV(lam) of one series (x, y, w) at each lam: the criterion `fit_smoothing` minimises,
/// for the tests to hold against SciPy's.
#[pyfunction]
fn smoothing_gcv(
    x: PyReadonlyArray1<'_, f64>,
    y: PyReadonlyArray1<'_, f64>,
    w: PyReadonlyArray1<'_, f64>,
    lams: Vec<f64>,
) -> PyResult<Vec<f64>> {
    let (x, y, w) = (x.as_slice()?, y.as_slice()?, w.as_slice()?);
    smoothing::check(x, y, w).map_err(|e| value_error(series_error(&e.in_series(0))))?;
    if y.len() != x.len() || w.len() != x.len() {
        return Err(value_error(
            "smoothing_gcv: x, y and w must have one length",
        ));
    }
    let column = smoothing::Column {
        values: y,
        stride: 1,
        offset: 0,
    };
    smoothing::criterion(x, w, column, &lams)
        .into_iter()
        .map(|value| value.map_err(|e| value_error(format!("{e:?}"))))
        .collect()
}

/// The piecewise polynomial's shape checked: breakpoints (P + 1) and c (k, P, m), both
/// contiguous; (k, m).
fn piece_shape(breaks: &[f64], c: &PyReadonlyArray3<'_, f64>) -> PyResult<(usize, usize)> {
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
fn evaluate_pieces<'py>(
    py: Python<'py>,
    breaks: PyReadonlyArray1<'_, f64>,
    c: PyReadonlyArray3<'_, f64>,
    x: PyReadonlyArray1<'_, f64>,
    nu: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let breaks = breaks.as_slice()?;
    let (k, m) = piece_shape(breaks, &c)?;
    let (c, x) = (c.as_slice()?, x.as_slice()?);
    let mut out = vec![0.0; x.len() * m];
    pieces::evaluate(breaks, c, k, m, x, nu, &mut out);
    PyArray1::from_vec(py, out).reshape([x.len(), m])
}

/// The integral from a to b of a piecewise polynomial (as `evaluate_pieces` takes it), the
/// end pieces continuing past the breakpoints: (m,).
#[pyfunction]
fn integrate_pieces<'py>(
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
fn antiderivative_pieces<'py>(
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
fn evaluate_bspline<'py>(
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
    let mut out = vec![0.0; x.len() * m];
    let evaluate = |out: &mut [f64]| de_boor::evaluate(t, c, m, k, x, nu, ends_in_powers, out);
    if x.len() < 1024 {
        // A small call: releasing the GIL would cost more than the work.
        evaluate(&mut out);
    } else {
        py.detach(|| evaluate(&mut out));
    }
    PyArray1::from_vec(py, out).reshape([x.len(), m])
}

/// The knots of each axis, checked against the degrees: at least 2 k + 2 each.
fn tensor_axes<'a>(ts: &'a [PyReadonlyArray1<'_, f64>], k: &[usize]) -> PyResult<Vec<&'a [f64]>> {
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
fn points_of<'a>(xi: &'a PyReadonlyArray2<'_, f64>, d: usize) -> PyResult<&'a [f64]> {
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
fn evaluate_tensor<'py>(
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
    let mut out = vec![0.0; rows * m];
    if rows < 1024 {
        tensor.evaluate(xi, &nu, extrapolate, &mut out);
    } else {
        py.detach(|| tensor.evaluate(xi, &nu, extrapolate, &mut out));
    }
    PyArray1::from_vec(py, out).reshape([rows, m])
}

/// One spline of a tensor batch as Python hands it: knots per axis, degrees, coefficients.
type TensorArgs<'py> = (
    Vec<PyReadonlyArray1<'py, f64>>,
    Vec<usize>,
    PyReadonlyArray2<'py, f64>,
);

/// A batch's values (N, m) and each member's first row (S + 1).
type Batched<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<i64>>);

/// Many tensor-product B-splines (each its own axes, knots and degrees; every one m values a
/// point), spline i at its own points xis[i] (N_i, d_i): (values (sum N_i, m), offsets
/// (S + 1,)), spline i's rows offsets[i]..offsets[i + 1]; derivative orders nu[i] (one per
/// axis). Splines are spread over the pool.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "PyO3 extracts lists of arrays as Vecs"
)]
fn evaluate_tensors<'py>(
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
    let mut out = vec![0.0; rows * m];
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
fn fit_tensor<'py>(
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

/// The nu-th derivatives of the k + 1 B-splines that do not vanish on each x's knot span (l
/// its `span`, t_l <= x < t_{l+1}), (len(x), k + 1): the workspace's one Cox–de Boor
/// recursion (`bsplines::de_boor::basis_in`), for the package's collocation and design
/// matrices.
#[pyfunction]
fn bspline_basis<'py>(
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
    let mut out = vec![0.0; x.len() * width];
    py.detach(|| {
        let mut scratch = vec![0.0; width];
        for ((row, &xi), &l) in out.chunks_exact_mut(width).zip(x).zip(span) {
            bsplines::de_boor::basis_in(t, k, xi, l as usize, nu, row, &mut scratch);
        }
    });
    PyArray1::from_vec(py, out).reshape([x.len(), width])
}

/// The smallest and largest value of each column of xi (N, d), NaN for a column that holds a
/// NaN: one pass over the points (NumPy's min and max along axis 0 of a C-ordered array
/// stride through it column by column, several times slower).
#[pyfunction]
fn column_ranges(xi: PyReadonlyArray2<'_, f64>) -> PyResult<(Vec<f64>, Vec<f64>)> {
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
fn pchip_grid<'py>(
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
    let mut out = vec![0.0; rows * m];
    if rows < 256 {
        grid.pchip(xi, &mut out);
    } else {
        py.detach(|| grid.pchip(xi, &mut out));
    }
    PyArray1::from_vec(py, out).reshape([rows, m])
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Context>()?;
    m.add_class::<Splines>()?;
    m.add_class::<PendingRoots>()?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(fit_hermite, m)?)?;
    m.add_function(wrap_pyfunction!(fit_bspline, m)?)?;
    m.add_function(wrap_pyfunction!(solve_pieces, m)?)?;
    m.add_function(wrap_pyfunction!(solve_banded, m)?)?;
    m.add_function(wrap_pyfunction!(fit_lsq, m)?)?;
    m.add_function(wrap_pyfunction!(fit_smoothing, m)?)?;
    m.add_function(wrap_pyfunction!(fit_splrep, m)?)?;
    m.add_function(wrap_pyfunction!(fit_splrep_from, m)?)?;
    m.add_function(wrap_pyfunction!(smoothing_gcv, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate_pieces, m)?)?;
    m.add_function(wrap_pyfunction!(integrate_pieces, m)?)?;
    m.add_function(wrap_pyfunction!(antiderivative_pieces, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate_bspline, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate_tensor, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate_tensors, m)?)?;
    m.add_function(wrap_pyfunction!(pchip_grid, m)?)?;
    m.add_function(wrap_pyfunction!(fit_tensor, m)?)?;
    m.add_function(wrap_pyfunction!(column_ranges, m)?)?;
    m.add_function(wrap_pyfunction!(bspline_basis, m)?)?;
    m.add_function(wrap_pyfunction!(surfaces::tessellate_surfaces, m)?)?;
    m.add("KIND_NAMES", splinegpu::kinds::KIND_NAMES.to_vec())?;
    Ok(())
}
