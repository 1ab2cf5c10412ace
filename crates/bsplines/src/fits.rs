//! The fits a Rust caller reaches for, on one series of data, each checked first (SciPy's
//! rules and words, located by `InputError`) and returning an owned `BSpline`:
//!
//! - `lsq_spline`: least squares on given knots (SciPy's `make_lsq_spline`);
//! - `smoothing_spline`: the cubic smoothing spline, lam given or chosen by GCV
//!   (`make_smoothing_spline`);
//! - `splrep`: FITPACK's smoothing with knots found for a target s, as SciPy's `make_splrep`
//!   (its re-implementation of curfit and percur) places them, `bc_type="periodic"` as
//!   `Splrep::periodic`. SciPy's legacy `splrep` calls the Fortran, whose knots can differ
//!   for small s.
//!
//! `interp::interpolate` makes the interpolating spline of any degree, `grid` the gridded
//! tensor products. The modules below these (`lsq`, `smoothing`, `fitpack`, `periodic`) take
//! batches and borrowed columns for callers that fit thousands of series at once.

use rayon::prelude::*;

use crate::fitpack::{self, Data, Failure, Spline};
use crate::smoothing::{self, Column, Job};
use crate::{BSpline, InputError, lsq, periodic};

/// One series of data: x, y as len(x) rows of `dim` values (row-major), and weights (None:
/// every weight 1).
#[derive(Clone, Copy, Debug)]
pub struct Series<'a> {
    /// The abscissae.
    pub x: &'a [f64],
    /// The values, len(x) rows of `dim`.
    pub y: &'a [f64],
    /// Values per point.
    pub dim: usize,
    /// One weight per x, or None for unit weights.
    pub w: Option<&'a [f64]>,
}

impl<'a> Series<'a> {
    /// Unweighted data of one coordinate.
    pub fn new(x: &'a [f64], y: &'a [f64]) -> Self {
        Self {
            x,
            y,
            dim: 1,
            w: None,
        }
    }

    /// The same data with weights.
    #[must_use]
    pub fn weighted(self, w: &'a [f64]) -> Self {
        Self { w: Some(w), ..self }
    }

    /// y's and w's lengths against x's; the weights (unit ones made here where none).
    fn shaped(&self) -> Result<std::borrow::Cow<'a, [f64]>, InputError> {
        if self.dim == 0 || self.y.len() != self.x.len() * self.dim {
            return Err(InputError::new(
                "y",
                format!(
                    "must hold {} rows of {}, got {} values",
                    self.x.len(),
                    self.dim,
                    self.y.len()
                ),
            ));
        }
        match self.w {
            Some(w) if w.len() != self.x.len() => Err(InputError::new(
                "w",
                format!("{} weights for {} x", w.len(), self.x.len()),
            )),
            Some(w) => Ok(w.into()),
            None => Ok(vec![1.0; self.x.len()].into()),
        }
    }
}

/// A least-squares spline and its weighted residual sum of squares.
#[derive(Clone, Debug)]
pub struct LsqSpline {
    /// The spline.
    pub spline: BSpline,
    /// Σ_i (w_i |y_i − s(x_i)|)^2 over every coordinate.
    pub residual: f64,
}

/// The spline of degree k on knots t closest to the data in weighted least squares.
/// Refused where the data leave a coefficient undetermined (Schoenberg–Whitney).
pub fn lsq_spline(data: &Series<'_>, t: &[f64], k: usize) -> Result<LsqSpline, InputError> {
    let w = data.shaped()?;
    lsq::check(data.x, data.y, &w, t, k)?;
    let fit = lsq::fit(data.x, data.y, data.dim, &w, t, k).ok_or_else(|| {
        InputError::new(
            "t",
            "a least-squares system is singular (the knots and x violate the Schoenberg-Whitney conditions)",
        )
    })?;
    Ok(LsqSpline {
        spline: BSpline::new(t.to_vec(), fit.c, k, data.dim)?,
        residual: fit.residual,
    })
}

/// How a smoothing spline's lam is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lam {
    /// The lam of least generalised cross-validation, searched as SciPy searches it.
    Gcv,
    /// This lam (>= 0).
    Given(f64),
}

/// A cubic smoothing spline and the lam of each coordinate.
#[derive(Clone, Debug)]
pub struct SmoothingSpline {
    /// The spline, on the knots `[x_0] * 3 + x + [x_last] * 3`.
    pub spline: BSpline,
    /// Each coordinate's lam (GCV chooses one per coordinate).
    pub lams: Vec<f64>,
}

/// The cubic f minimising Σ w_i (y_i − f(x_i))^2 + lam ∫ f''^2, each coordinate on its own.
/// x strictly increasing with at least 5 points, w > 0.
pub fn smoothing_spline(data: &Series<'_>, lam: Lam) -> Result<SmoothingSpline, InputError> {
    let w = data.shaped()?;
    smoothing::check(data.x, data.y, &w)?;
    let lam = match lam {
        Lam::Gcv => None,
        Lam::Given(v) if v >= 0.0 => Some(v),
        Lam::Given(v) => return Err(InputError::new("lam", format!("must be >= 0, got {v}"))),
    };
    let jobs: Vec<Job<'_>> = (0..data.dim)
        .map(|offset| Job {
            x: data.x,
            w: &w,
            y: Column {
                values: data.y,
                stride: data.dim,
                offset,
            },
            lam,
        })
        .collect();
    let n = data.x.len();
    let mut c = vec![0.0; (n + 2) * data.dim];
    let mut lams = Vec::with_capacity(data.dim);
    for (col, fit) in smoothing::fit(&jobs).into_iter().enumerate() {
        let fit = fit.map_err(|e| smoothing_failure(e).at(col))?;
        for (j, v) in fit.c.iter().enumerate() {
            c[j * data.dim + col] = *v;
        }
        lams.push(fit.lam);
    }
    let (first, last) = (data.x[0], data.x[n - 1]);
    let t: Vec<f64> = [first; 3]
        .into_iter()
        .chain(data.x.iter().copied())
        .chain([last; 3])
        .collect();
    Ok(SmoothingSpline {
        spline: BSpline::new(t, c, 3, data.dim)?,
        lams,
    })
}

/// Each series' smoothing spline, one series a task on every thread: the batch form of
/// `smoothing_spline`, the first bad series named by its index. (A series' columns share the
/// vector lanes; packing four series into them, as the Python batches do, is not done here.)
pub fn smoothing_splines(
    batch: &[Series<'_>],
    lam: Lam,
) -> Result<Vec<SmoothingSpline>, InputError> {
    batch
        .par_iter()
        .enumerate()
        .map(|(i, data)| smoothing_spline(data, lam).map_err(|e| e.in_series(i)))
        .collect()
}

/// The error of a smoothing spline that could not be made, in SciPy's words.
fn smoothing_failure(e: smoothing::Failure) -> InputError {
    match e {
        smoothing::Failure::IllPosed => InputError::new("y", "Seems like the problem is ill-posed"),
        smoothing::Failure::NoMinimum(why) => InputError::new(
            "y",
            format!("Unable to find minimum of the GCV function: {why}"),
        ),
    }
}

/// FITPACK's options for `splrep`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Splrep<'a> {
    /// Knots to smooth on, instead of FITPACK's search (curfit's task = -1).
    pub knots: Option<&'a [f64]>,
    /// The most knots the search may place (None: FITPACK's default, `fitpack::default_nest`).
    pub nest: Option<usize>,
    /// A periodic spline of period xe − xb (percur); the last point repeats the first.
    pub periodic: bool,
    /// The interval [xb, xe] (None: [x_0, x_last]).
    pub interval: Option<(f64, f64)>,
}

/// A FITPACK smoothing spline and its root finder's ier (0 converged; 2 or 3 stopped early,
/// where SciPy warns and keeps the spline).
#[derive(Clone, Debug)]
pub struct FitpackSpline {
    /// The spline.
    pub spline: BSpline,
    /// FITPACK's ier.
    pub ier: u8,
}

/// The spline of degree k (1 to 6, as the Python package's `make_splrep` takes) with the fewest knots FITPACK's search finds such that
/// fp = Σ w_i^2 |y_i − s(x_i)|^2 <= s, then the smoothest on those knots with fp = s (s = 0:
/// the interpolant).
pub fn splrep(
    data: &Series<'_>,
    k: usize,
    s: f64,
    options: Splrep<'_>,
) -> Result<FitpackSpline, InputError> {
    if !(1..=6).contains(&k) {
        return Err(InputError::new("k", format!("must be 1 to 6, got {k}")));
    }
    if !(s >= 0.0 && s.is_finite()) {
        return Err(InputError::new(
            "s",
            format!("must be finite and >= 0, got {s}"),
        ));
    }
    let w = data.shaped()?;
    let x = data.x;
    let (xb, xe) = options.interval.unwrap_or_else(|| {
        (
            x.first().copied().unwrap_or(0.0),
            x.last().copied().unwrap_or(0.0),
        )
    });
    let one = Data {
        x,
        y: data.y,
        d: data.dim,
        w: &w,
        xb,
        xe,
    };
    fitpack::check(&one, k, options.periodic)?;
    let nest = options
        .nest
        .unwrap_or_else(|| fitpack::default_nest(x.len(), k, options.periodic));
    let fitted = fitpack_fit(&one, k, s, options.knots, nest, options.periodic).map_err(|_| {
        InputError::new(
            "x",
            "a least-squares system is singular (the knots and x violate the Schoenberg-Whitney conditions)",
        )
    })?;
    Ok(FitpackSpline {
        spline: BSpline::new(fitted.t, fitted.c, k, data.dim)?,
        ier: fitted.ier,
    })
}

/// FITPACK's whole fit, unchecked (`splrep` checks first): knots by the search (or the given
/// t), then the smoothing spline; curfit's (`fitpack`), or percur's where `periodic`
/// (`periodic`).
pub fn fitpack_fit(
    data: &Data<'_>,
    k: usize,
    s: f64,
    t: Option<&[f64]>,
    nest: usize,
    periodic: bool,
) -> Result<Spline, Failure> {
    let t = match t {
        Some(t) => t.to_vec(),
        None if periodic => periodic::knots(data, k, s, nest)?,
        None => fitpack::knots(data, k, s, nest)?,
    };
    if periodic {
        periodic::smooth(data, &t, k, s)
    } else {
        fitpack::smooth(data, &t, k, s)
    }
}
