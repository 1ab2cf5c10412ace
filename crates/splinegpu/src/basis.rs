//! The 4x4 basis matrices of the uniform cubic families, in f64.
//!
//! Every matrix here is written by rows, as the memo (A. R. Smith, "Spline Tutorial Notes",
//! Lucasfilm Technical Memo 77) writes it, and is used as
//!
//! ```text
//! P(u) = [u^3 u^2 u 1] · M · [P_i, P_i+1, P_i+2, P_i+3]^T,   u in [0, 1],
//! ```
//!
//! so row 0 of `M · X` is the cubic coefficient A, row 3 the constant D. Functions that return
//! rows are named `*_rows` and return `[[f64; 4]; 4]` in row-major order; [`Basis::to_dmat4`]
//! converts to glam's column-major [`DMat4`] without mixing the two silently.

use glam::DMat4;

use crate::error::{InputError, Shown};

/// Row-major 4x4 matrix, `rows[r][c]`.
pub type Rows = [[f64; 4]; 4];

/// A uniform cubic family defined by a 4x4 basis matrix, on a window of four points that
/// slides by one ([`CurveKind::Uniform`](crate::CurveKind::Uniform)). Bezier curves, whose
/// windows step by three, are [`CurveKind::Bezier`](crate::CurveKind::Bezier).
#[derive(Clone, Debug, PartialEq)]
pub enum Basis {
    /// Cardinal spline C_a (memo, "The Cardinal Splines"): interpolates its knots, C1, tangent at
    /// x_0 equal to a·(x_1 − x_−1). `tension` is a; any finite value.
    Cardinal {
        /// The tension a.
        tension: f64,
    },
    /// Catmull-Rom spline, C_0.5 (memo, "The Classic Interpolating Spline"; the printed matrix's
    /// last row must read [0 2 0 0] before the factor 1/2).
    CatmullRom,
    /// Uniform cubic B-spline B (memo, "The Classic Approximating Spline"): C2, inside the convex
    /// hull of each window of four control points.
    BSpline,
    /// Duff's tensioned B-spline B_a (memo, "Tensioned B-Splines"); B_1 = B. `tension` a > 0.
    TensionedBSpline {
        /// The tension a.
        tension: f64,
    },
    /// Barsky's Beta-spline B_{b1,b2} (memo, "The Beta Splines"), scaled by 1/d with
    /// d = b2 + 2b1^3 + 4b1^2 + 4b1 + 2, which must not be 0. B_{1,0} = B.
    Beta {
        /// The bias b1.
        bias: f64,
        /// The tension b2.
        tension: f64,
    },
    /// A matrix the user gives, row-major.
    Matrix(Rows),
}

impl Basis {
    /// The matrix by rows, after checking the parameters.
    ///
    /// # Errors
    /// A non-finite parameter or matrix entry, a tensioned B-spline with a <= 0, or a
    /// Beta-spline whose d is 0; the error names the field ("tension", "bias" or "matrix").
    pub fn try_rows(&self) -> Result<Rows, InputError> {
        match *self {
            Basis::Cardinal { tension } => {
                check_finite("tension", tension)?;
                Ok(cardinal_rows(tension))
            }
            Basis::CatmullRom => Ok(cardinal_rows(0.5)),
            Basis::BSpline => Ok(bspline_rows()),
            Basis::TensionedBSpline { tension } => {
                check_finite("tension", tension)?;
                if tension <= 0.0 {
                    return Err(InputError::field(
                        "tension",
                        format!(
                            "must be > 0 for a tensioned B-spline, got {}",
                            Shown(tension)
                        ),
                    ));
                }
                Ok(tensioned_bspline_rows(tension))
            }
            Basis::Beta { bias, tension } => {
                check_finite("bias", bias)?;
                check_finite("tension", tension)?;
                beta_rows(bias, tension)
            }
            Basis::Matrix(rows) => {
                for (r, row) in rows.iter().enumerate() {
                    for (c, &v) in row.iter().enumerate() {
                        if !v.is_finite() {
                            return Err(InputError::field(
                                "matrix",
                                format!("entries must be finite: matrix[{r}][{c}] = {}", Shown(v)),
                            ));
                        }
                    }
                }
                Ok(rows)
            }
        }
    }

    /// The matrix as glam's column-major [`DMat4`] (`M.row(r)` is row r of the memo's matrix).
    ///
    /// # Errors
    /// As [`Basis::try_rows`].
    pub fn to_dmat4(&self) -> Result<DMat4, InputError> {
        Ok(DMat4::from_cols_array_2d(&self.try_rows()?).transpose())
    }
}

fn check_finite(field: &str, v: f64) -> Result<(), InputError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(InputError::field(
            field,
            format!("must be finite, got {}", Shown(v)),
        ))
    }
}

/// Cardinal matrix C_a by rows:
///
/// ```text
/// [ -a   2-a   a-2    a ]
/// [ 2a   a-3   3-2a  -a ]
/// [ -a   0     a      0 ]
/// [  0   1     0      0 ]
/// ```
///
/// It is M_1^-1 M_2 for P(0) = x_0, P(1) = x_1, P'(0) = a(x_1 − x_−1), P'(1) = a(x_2 − x_0).
#[must_use]
pub fn cardinal_rows(a: f64) -> Rows {
    [
        [-a, 2.0 - a, a - 2.0, a],
        [2.0 * a, a - 3.0, 3.0 - 2.0 * a, -a],
        [-a, 0.0, a, 0.0],
        [0.0, 1.0, 0.0, 0.0],
    ]
}

/// Uniform cubic B-spline matrix B = 1/6 [[-1 3 -3 1] [3 -6 3 0] [-3 0 3 0] [1 4 1 0]].
#[must_use]
pub fn bspline_rows() -> Rows {
    scale(
        [
            [-1.0, 3.0, -3.0, 1.0],
            [3.0, -6.0, 3.0, 0.0],
            [-3.0, 0.0, 3.0, 0.0],
            [1.0, 4.0, 1.0, 0.0],
        ],
        1.0 / 6.0,
    )
}

/// Duff's tensioned B-spline B_a by rows:
///
/// ```text
/// 1/6 [ -a    12-9a    9a-12   a ]
///     [ 3a    12a-18   18-15a  0 ]
///     [ -3a   0        3a      0 ]
///     [ a     6-2a     a       0 ]
/// ```
#[must_use]
pub fn tensioned_bspline_rows(a: f64) -> Rows {
    scale(
        [
            [-a, 12.0 - 9.0 * a, 9.0 * a - 12.0, a],
            [3.0 * a, 12.0 * a - 18.0, 18.0 - 15.0 * a, 0.0],
            [-3.0 * a, 0.0, 3.0 * a, 0.0],
            [a, 6.0 - 2.0 * a, a, 0.0],
        ],
        1.0 / 6.0,
    )
}

/// Barsky's Beta-spline B_{b1,b2} by rows, scaled by 1/d, d = b2 + 2b1^3 + 4b1^2 + 4b1 + 2:
///
/// ```text
/// [ -2b1^3   2(b2+b1^3+b1^2+b1)    -2(b2+b1^2+b1+1)   2 ]
/// [  6b1^3  -3(b2+2b1^3+2b1^2)      3(b2+2b1^2)       0 ]
/// [ -6b1^3   6(b1^3-b1)             6b1               0 ]
/// [  2b1^3   b2+4(b1^2+b1)          2                 0 ]
/// ```
///
/// # Errors
/// d = 0 (the memo's appendix tests bias == 0 && tension == 0 instead; d is what matters).
pub fn beta_rows(b1: f64, b2: f64) -> Result<Rows, InputError> {
    let (s, c) = (b1 * b1, b1 * b1 * b1);
    let d = b2 + 2.0 * c + 4.0 * s + 4.0 * b1 + 2.0;
    // An overflow is the parameter's that overflows: bias enters d cubed, tension once.
    if !c.is_finite() {
        return Err(InputError::field(
            "bias",
            format!(
                "is too large for a Beta-spline: bias^3 overflows float64 (bias {})",
                Shown(b1)
            ),
        ));
    }
    if !d.is_finite() {
        return Err(InputError::field(
            "tension",
            format!(
                "is too large for a Beta-spline: d = b2 + 2b1^3 + 4b1^2 + 4b1 + 2 overflows \
                 float64 (bias {}, tension {})",
                Shown(b1),
                Shown(b2)
            ),
        ));
    }
    if d == 0.0 {
        return Err(InputError::field(
            "tension",
            format!(
                "makes the Beta-spline degenerate: d = b2 + 2b1^3 + 4b1^2 + 4b1 + 2 = {} \
                 for bias {}, tension {}",
                Shown(d),
                Shown(b1),
                Shown(b2)
            ),
        ));
    }
    Ok(scale(
        [
            [
                -2.0 * c,
                2.0 * (b2 + c + s + b1),
                -2.0 * (b2 + s + b1 + 1.0),
                2.0,
            ],
            [
                6.0 * c,
                -3.0 * (b2 + 2.0 * c + 2.0 * s),
                3.0 * (b2 + 2.0 * s),
                0.0,
            ],
            [-6.0 * c, 6.0 * (c - b1), 6.0 * b1, 0.0],
            [2.0 * c, b2 + 4.0 * (s + b1), 2.0, 0.0],
        ],
        1.0 / d,
    ))
}

/// Cubic Bezier in power form: the Bernstein polynomials (1-u)^3, 3u(1-u)^2, 3u^2(1-u), u^3
/// expanded in [u^3 u^2 u 1] give the columns of
/// `[[-1 3 -3 1] [3 -6 3 0] [-3 3 0 0] [1 0 0 0]]`.
#[must_use]
pub fn bezier_rows() -> Rows {
    [
        [-1.0, 3.0, -3.0, 1.0],
        [3.0, -6.0, 3.0, 0.0],
        [-3.0, 3.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
    ]
}

fn scale(mut rows: Rows, s: f64) -> Rows {
    for row in &mut rows {
        for v in row {
            *v *= s;
        }
    }
    rows
}
