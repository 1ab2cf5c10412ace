//! B-splines of any degree in f64, with SciPy's semantics: evaluation by de Boor's recurrence,
//! interpolation on SciPy's knots, least squares, FITPACK's knot searches for a smoothing
//! target (curfit, percur, parcur), cubic smoothing splines with GCV, gridded tensor-product
//! fits, piecewise polynomials and their roots. Neither GPU nor Python: the numerics under
//! `splinegpu`'s Python package, for Rust callers too.
//!
//! ```
//! use bsplines::{Lam, Series, smoothing_spline};
//!
//! let x: Vec<f64> = (0..50).map(|i| f64::from(i) / 7.0).collect();
//! let y: Vec<f64> = x.iter().map(|v| v.sin()).collect();
//! let fit = smoothing_spline(&Series::new(&x, &y), Lam::Gcv)?;
//! let at = fit.spline.evaluate(&[1.0], 0);
//! assert!((at[0] - 1f64.sin()).abs() < 1e-3);
//! # Ok::<(), bsplines::InputError>(())
//! ```
//!
//! The typed entry points (`interpolate`, `lsq_spline`, `smoothing_spline`, `splrep`,
//! `TensorSpline`) check their input and name what is wrong (`InputError`: the argument, the
//! series, the position). The modules under them work on borrowed slices and batches, for
//! callers that lay out thousands of series themselves (the Python extension does).
//!
//! | module | what it holds |
//! |---|---|
//! | `de_boor` | the B-splines at a point (Cox–de Boor), evaluation of a spline |
//! | `banded` | banded linear systems (collocation) |
//! | `interp` | interpolation of any degree, SciPy's not-a-knot knots |
//! | `lsq` | weighted least squares by Givens rotations, the basis rows of data |
//! | `fitpack`, `periodic` | FITPACK's knot search and smoothing as SciPy's `make_splrep` re-derives it, open and periodic |
//! | `curfit`, `percur`, `regrid` | FITPACK's own curfit, parcur, percur, clocur and regrid, step for step (SciPy's splrep, splprep, UnivariateSpline, RectBivariateSpline) |
//! | `smoothing` | cubic smoothing splines, GCV, four series side by side (`lanes`) |
//! | `bounded_search` | Brent's bounded minimisation, as SciPy runs it |
//! | `grid`, `tensor_values` | tensor-product splines and gridded PCHIP |
//! | `pieces`, `roots` | piecewise polynomials in power form, their integrals and roots |

pub mod banded;
pub mod bounded_search;
pub mod bspline;
pub mod curfit;
pub mod de_boor;
pub mod error;
pub mod fitpack;
pub mod fits;
pub mod grid;
pub mod interp;
pub mod lanes;
pub mod lsq;
pub mod pchip;
pub mod percur;
pub mod periodic;
pub mod pieces;
pub mod regrid;
pub mod roots;
pub mod smoothing;
pub mod tensor;
pub mod tensor_values;

pub use bspline::BSpline;
pub use error::{InputError, check_finite, check_increasing};
pub use fits::{
    FitpackSpline, Lam, LsqSpline, Series, SmoothingSpline, Splrep, lsq_spline, smoothing_spline,
    smoothing_splines, splrep,
};
pub use interp::interpolate;
pub use tensor::TensorSpline;
