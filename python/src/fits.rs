//! The batched fits over `bsplines`: banded solves, least squares, smoothing (GCV and fixed
//! lam), FITPACK's knot search (splrep, continued), every series on its own thread.

use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};

use bsplines::{banded, curfit, fitpack, lsq, percur, regrid, smoothing};

use crate::args::{Stack1, Stack2, ragged, value_error};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// X with A X = B for a banded A given by rows (row i: `rows[i]`'s values from column
/// `first[i]`) and B (n, m), by elimination with partial pivoting inside the band (see
/// `banded`); None when A is singular. The B-spline fits of any degree solve their collocation
/// systems here.
#[pyfunction]
pub(crate) fn solve_banded<'py>(
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
pub(crate) type Series<'a> = (&'a [f64], &'a [f64], &'a [f64]);

/// Least-squares fits: the stacked coefficients, each series' residual, the first singular
/// series.
pub(crate) type LsqFits<'py> = (Bound<'py, PyArray2<f64>>, Vec<f64>, Option<usize>);

/// FITPACK fits: the knots stacked, their offsets, the coefficients stacked, each ier.
/// Where FITPACK's knot search stopped (`bsplines::curfit::Search`): knots, nrdata, fp0,
/// fpold, nplus, ier.
pub(crate) type CurfitState = (Vec<f64>, Vec<usize>, f64, f64, usize, i32);

/// `fit_curfit`'s answer: knots, coefficients (rows of d), fp, ier and the search's state.
pub(crate) type CurfitAnswer<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    f64,
    i32,
    CurfitState,
);

pub(crate) type FitpackFits<'py> = (
    Bound<'py, PyArray1<f64>>,
    Vec<i64>,
    Bound<'py, PyArray2<f64>>,
    Vec<u8>,
);

/// `fit_regrid`'s answer: knots in x and y, coefficients, fp and ier.
pub(crate) type RegridAnswer<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    f64,
    i32,
);

/// Each series' columns' lams (S, m).
pub(crate) type Lams<'py> = Bound<'py, PyArray2<f64>>;

/// Smoothing splines' knots laid end to end, their coefficients stacked, and their lams.
pub(crate) type SmoothingFits<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Lams<'py>,
);

/// One column's smoothing spline.
pub(crate) type Smoothed = Result<smoothing::Fit, smoothing::Failure>;

/// Each series' (x, y, w) of a batch: x and y as the batch types hold them (y's rows of m
/// values, one m for all), w likewise or None for unit weights, which are then slices of
/// `ones` (one run of ones as long as the longest series, not a second array of N ones).
pub(crate) fn series<'a>(
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
pub(crate) fn series_error(e: &bsplines::InputError) -> String {
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
pub(crate) fn stacked(
    py: Python<'_>,
    blocks: Vec<Vec<f64>>,
    m: usize,
) -> PyResult<Bound<'_, PyArray2<f64>>> {
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
pub(crate) fn fit_lsq<'py>(
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
pub(crate) fn smoothing_fits(data: &[Series<'_>], m: usize, given: &[f64]) -> Vec<Smoothed> {
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
pub(crate) fn laid_end_to_end(
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
pub(crate) fn fit_smoothing<'py>(
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
pub(crate) fn fit_splrep<'py>(
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
                fitpack::check(&one, k, periodic).map_err(|e| series_error(&e.in_series(i)))?;
                let t = given.as_ref().map(|g| g[i]);
                let most = nest.unwrap_or(fitpack::default_nest(x.len(), k, periodic));
                bsplines::fits::fitpack_fit(&one, k, s[i], t, most, periodic).map_err(|_| {
                    format!(
                        "series {i}: a least-squares system is singular (the knots and x \
                         violate the Schoenberg-Whitney conditions)"
                    )
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

/// FITPACK's own smoothing fit (`bsplines::curfit::smoothing_fit`) of one series, for the
/// legacy doors (splrep, splprep, UnivariateSpline): x (m,), y (m, d), w (m,), [xb, xe],
/// degree k, s > 0, at most `nest` knots, parcur's sums where `parametric`, periodic
/// (percur, clocur: period x[-1] - x[0], the last point not fitted) where `periodic`, from
/// the polynomial or on from an earlier search's state (`from`, as this returns it: curfit's
/// iopt = 1). Returns (t, c (len(t) - k - 1, d), fp, ier, state).
#[pyfunction]
#[pyo3(signature = (x, y, w, xb, xe, k, s, nest, parametric = false, periodic = false, from = None))]
#[expect(
    clippy::too_many_arguments,
    clippy::needless_pass_by_value,
    reason = "curfit's arguments, one each; PyO3 extracts the state's vectors as Vecs"
)]
pub(crate) fn fit_curfit<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    y: PyReadonlyArray2<'py, f64>,
    w: PyReadonlyArray1<'py, f64>,
    xb: f64,
    xe: f64,
    k: usize,
    s: f64,
    nest: usize,
    parametric: bool,
    periodic: bool,
    from: Option<CurfitState>,
) -> PyResult<CurfitAnswer<'py>> {
    let d = y.shape()[1];
    let (x, y, w) = (x.as_slice()?, y.as_slice()?, w.as_slice()?);
    if y.len() != x.len() * d || w.len() != x.len() {
        return Err(value_error(format!(
            "fit_curfit: {} x, {} rows of y and {} w",
            x.len(),
            y.len() / d.max(1),
            w.len()
        )));
    }
    if !((1..=5).contains(&k) && (1..=10).contains(&d) && s > 0.0 && s.is_finite()) {
        return Err(value_error(format!(
            "fit_curfit: k 1 to 5, 1 to 10 coordinates and s > 0, got k = {k}, d = {d}, s = {s}"
        )));
    }
    let least = 2 * k + 2 + usize::from(periodic);
    if nest < least {
        return Err(value_error(format!(
            "nest: at least {least} knots for k = {k}, got {nest}"
        )));
    }
    let data = fitpack::Data { x, y, d, w, xb, xe };
    fitpack::check(&data, k, periodic).map_err(|e| value_error(series_error(&e.in_series(0))))?;
    if periodic && let Some(i) = x.windows(2).position(|p| p[0] >= p[1]) {
        return Err(value_error(format!(
            "x: a periodic fit needs x strictly increasing, x[{i}] = {} >= x[{}] = {}",
            x[i],
            i + 1,
            x[i + 1]
        )));
    }
    if periodic && let Some(i) = w[..w.len() - 1].iter().position(|&v| v <= 0.0) {
        return Err(value_error(format!(
            "w: a periodic fit needs positive weights, w[{i}] = {}",
            w[i]
        )));
    }
    let from = from.map(|(t, nrdata, fp0, fpold, nplus, ier)| curfit::Search {
        t,
        nrdata,
        fp0,
        fpold,
        nplus,
        ier,
    });
    let door = match (parametric, periodic) {
        (false, false) => curfit::Door::Curfit,
        (true, false) => curfit::Door::Parcur,
        (false, true) => curfit::Door::Percur,
        (true, true) => curfit::Door::Clocur,
    };
    let fit = py.detach(|| {
        if periodic {
            percur::smoothing_fit(&data, k, s, nest, from.as_ref(), door)
        } else {
            curfit::smoothing_fit(&data, k, s, nest, from.as_ref(), door)
        }
    });
    if fit.c.iter().any(|v| !v.is_finite()) {
        return Err(value_error(
            "x: a least-squares system is singular (the knots and x violate the \
             Schoenberg-Whitney conditions)",
        ));
    }
    let curfit::Search {
        t,
        nrdata,
        fp0,
        fpold,
        nplus,
        ier,
    } = fit.search;
    Ok((
        PyArray1::from_vec(py, fit.t),
        stacked(py, vec![fit.c], d)?,
        fit.fp,
        fit.ier,
        (t, nrdata, fp0, fpold, nplus, ier),
    ))
}

/// FITPACK's regrid with s > 0 (`bsplines::regrid::smoothing_fit`), RectBivariateSpline's
/// smoothing: x (mx,) and y (my,) strictly increasing inside bounds (xb, xe, yb, ye), z (mx,
/// my), degrees kx, ky, room for mx + kx + 1 and my + ky + 1 knots (SciPy's), at most maxit
/// iterations for p. Returns (tx, ty, c ((nx - kx - 1) (ny - ky - 1),), fp, ier).
#[pyfunction]
#[expect(clippy::too_many_arguments, reason = "regrid's arguments, one each")]
pub(crate) fn fit_regrid<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    y: PyReadonlyArray1<'py, f64>,
    z: PyReadonlyArray2<'py, f64>,
    bounds: [f64; 4],
    kx: usize,
    ky: usize,
    s: f64,
    maxit: usize,
) -> PyResult<RegridAnswer<'py>> {
    let (x, y) = (x.as_slice()?, y.as_slice()?);
    if z.shape() != [x.len(), y.len()] {
        return Err(value_error(format!(
            "z: shape {:?} for {} x and {} y",
            z.shape(),
            x.len(),
            y.len()
        )));
    }
    let z = z.as_slice()?;
    for (name, k, v) in [("kx", kx, x), ("ky", ky, y)] {
        if !(1..=5).contains(&k) || v.len() <= k {
            return Err(value_error(format!(
                "{name}: degree 1 to 5 below the {} points, got {k}",
                v.len()
            )));
        }
        if let Some(i) = v.windows(2).position(|p| p[0] >= p[1] || p[1].is_nan()) {
            return Err(value_error(format!(
                "{}: must be strictly increasing, [{i}] = {} and [{}] = {}",
                &name[1..],
                v[i],
                i + 1,
                v[i + 1]
            )));
        }
    }
    let [xb, xe, yb, ye] = bounds;
    if !(xb <= x[0] && x[x.len() - 1] <= xe && yb <= y[0] && y[y.len() - 1] <= ye) {
        return Err(value_error(format!(
            "bbox: [{xb}, {xe}] x [{yb}, {ye}] must hold the data"
        )));
    }
    if let Some(i) = z.iter().position(|v| !v.is_finite()) {
        return Err(value_error(format!(
            "z: must be finite, z[{}, {}] = {}",
            i / y.len(),
            i % y.len(),
            z[i]
        )));
    }
    if !(s > 0.0 && s.is_finite() && maxit > 0) {
        return Err(value_error(format!(
            "fit_regrid: s > 0 and maxit >= 1, got s = {s}, maxit = {maxit}"
        )));
    }
    let grid = regrid::Grid { x, y, z, bounds };
    let rooms = (x.len() + kx + 1, y.len() + ky + 1);
    let fit = py.detach(|| regrid::smoothing_fit(&grid, (kx, ky), s, rooms, maxit));
    Ok((
        PyArray1::from_vec(py, fit.tx),
        PyArray1::from_vec(py, fit.ty),
        PyArray1::from_vec(py, fit.c),
        fit.fp,
        fit.ier,
    ))
}

/// GCV(lam) of one series (x, y, w) at each lam: the criterion `fit_smoothing` minimises,
/// for the tests to hold against SciPy's.
#[pyfunction]
pub(crate) fn smoothing_gcv(
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
