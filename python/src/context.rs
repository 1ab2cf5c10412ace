//! `Context` and its `tessellate`: curves fitted and planned on every thread, evaluated on the
//! GPU or the CPU into fresh arrays or the caller's (`out=`).

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};

use crate::args::{PerCurve, Stack1, Stack2, new_zeros, runtime_error, threads, value_error};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use splinegpu::PerPoint;
use splinegpu::kinds::KindFields;
use splinegpu::{
    Curve, CurveKind, Derivatives, Ends, EvalJob, GpuContext, InputError, Planes, Points,
    SampleFloat, SamplePlan, Samples, Sampling, SegmentTable,
};

/// `make(c)` for every c < n, on the library's pool of threads, in order; the first error in
/// curve order wins. One item is made on the calling thread, touching no pool.
pub(crate) fn on_threads<T: Send>(
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
pub(crate) fn job_on_threads(
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
pub(crate) struct Context {
    pub(crate) gpu: Option<GpuContext>,
    pub(crate) info: String,
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
pub(crate) struct CurveFields<'py> {
    #[pyo3(item)]
    pub(crate) ends: Option<String>,
    #[pyo3(item)]
    pub(crate) tension: Option<f64>,
    #[pyo3(item)]
    pub(crate) bias: Option<f64>,
    #[pyo3(item)]
    pub(crate) matrix: Option<[[f64; 4]; 4]>,
    #[pyo3(item)]
    pub(crate) t: Option<PerCurve<'py>>,
    #[pyo3(item)]
    pub(crate) start_derivative: Option<PerCurve<'py>>,
    #[pyo3(item)]
    pub(crate) end_derivative: Option<PerCurve<'py>>,
    #[pyo3(item)]
    pub(crate) tangents: Option<PerCurve<'py>>,
    #[pyo3(item)]
    pub(crate) method: Option<String>,
    #[pyo3(item)]
    pub(crate) knots: Option<PerCurve<'py>>,
    #[pyo3(item)]
    pub(crate) weights: Option<PerCurve<'py>>,
    #[pyo3(item)]
    pub(crate) continuity: Option<f64>,
    /// Kochanek–Bartels' tension, continuity and bias given per point (one array per curve).
    #[pyo3(item)]
    pub(crate) tension_each: Option<PerCurve<'py>>,
    #[pyo3(item)]
    pub(crate) continuity_each: Option<PerCurve<'py>>,
    #[pyo3(item)]
    pub(crate) bias_each: Option<PerCurve<'py>>,
}

/// The sampling: its contract name and value; "at" holds one array per curve.
#[derive(FromPyObject)]
pub(crate) enum SamplingArg<'py> {
    At(String, Stack1<'py>),
    Count(String, u64),
    Tolerance(String, f64),
}

impl SamplingArg<'_> {
    /// The sampling as the call gave it: `per_segment=16`, `at=[...]`.
    pub(crate) fn describe(&self) -> String {
        match self {
            SamplingArg::At(name, _) => format!("{name}=[...]"),
            SamplingArg::Count(name, v) => format!("{name}={v}"),
            SamplingArg::Tolerance(name, v) => format!("{name}={v}"),
        }
    }

    pub(crate) fn per_curve(&self, curves: usize) -> PyResult<Vec<Sampling>> {
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
pub(crate) struct KindSource<'a> {
    pub(crate) name: &'a str,
    pub(crate) ends: Option<Ends>,
    pub(crate) tension: Option<f64>,
    pub(crate) bias: Option<f64>,
    pub(crate) matrix: Option<[[f64; 4]; 4]>,
    pub(crate) t: Vec<Option<&'a [f64]>>,
    pub(crate) start_derivative: Vec<Option<&'a [f64]>>,
    pub(crate) end_derivative: Vec<Option<&'a [f64]>>,
    pub(crate) tangents: Vec<Option<&'a [f64]>>,
    pub(crate) method: Option<&'a str>,
    pub(crate) knots: Vec<Option<&'a [f64]>>,
    pub(crate) weights: Vec<Option<&'a [f64]>>,
    pub(crate) continuity: Option<f64>,
    pub(crate) tension_each: Vec<Option<&'a [f64]>>,
    pub(crate) continuity_each: Vec<Option<&'a [f64]>>,
    pub(crate) bias_each: Vec<Option<&'a [f64]>>,
}

impl<'a> KindSource<'a> {
    pub(crate) fn new(name: &'a str, fields: &'a CurveFields<'_>) -> PyResult<Self> {
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
    pub(crate) fn kind(&self, c: usize) -> Result<CurveKind, InputError> {
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
pub(crate) fn offsets(job: &EvalJob) -> Vec<i64> {
    let layout = job.layout();
    std::iter::once(0)
        .chain((0..job.len()).map(|c| layout.samples_of(c).end as i64))
        .collect()
}

/// A result whose arrays take over `samples`' vectors (no copy).
pub(crate) fn fresh<'py, F: SampleFloat + numpy::Element>(
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
pub(crate) fn check_result_fits(job: &EvalJob, value_bytes: u128, sampling: &str) -> PyResult<()> {
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
pub(crate) fn available_memory() -> Option<u128> {
    splinegpu::available_memory().map(u128::from)
}

/// The arrays of an earlier result, reused (`out=`): t, points, d1, d2, curve_offsets.
#[derive(FromPyObject)]
pub(crate) struct Out<'py>(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAny>>,
    Bound<'py, PyArray1<i64>>,
);

impl<'py> Out<'py> {
    /// New NumPy arrays for `job`'s result (curves of one dimension), zeroed by NumPy.
    pub(crate) fn zeros<F: numpy::Element>(py: Python<'py>, job: &EvalJob) -> PyResult<Self> {
        let layout = job.layout();
        let (rows, dim) = (layout.samples(), layout.max_dim());
        let order = job.derivatives().order();
        let plane = || -> PyResult<Bound<'py, PyAny>> {
            Ok(new_zeros::<F, numpy::Ix2>(py, &[rows, dim])?.into_any())
        };
        Ok(Out(
            new_zeros(py, &[rows])?,
            plane()?,
            (order >= 1).then(plane).transpose()?,
            (order >= 2).then(plane).transpose()?,
            new_zeros(py, &[job.len() + 1])?,
        ))
    }

    /// Evaluates `job` into these arrays and returns them.
    pub(crate) fn fill(
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
pub(crate) fn fill_planes<'py, F: numpy::Element>(
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
pub(crate) fn writeable<'py, T: numpy::Element, D: numpy::ndarray::Dimension>(
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
