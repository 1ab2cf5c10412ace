//! The small value types the curve kinds share, in a leaf module: how a sliding-window family
//! treats the ends of its points ([`Ends`]), and a parameter given once or per point
//! ([`PerPoint`]).

use crate::error::{InputError, Shown};

/// How a sliding-window family treats the ends of its point list (contract: "ends").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Ends {
    /// The memo's convention: n >= 4 points give n − 3 segments, the first and the last point
    /// only steer the ends; t in [0, n − 3].
    #[default]
    Control,
    /// The first and the last point are doubled before windowing (the memo's "double the first
    /// and last knots"): n >= 2 points give n − 1 segments; t in [0, n − 1].
    Repeat,
    /// Cyclic, windowing P_{n−1}, P_0, ..., P_{n−1}, P_0, P_1 (the memo's cyclic spline):
    /// n >= 3 points give n segments; t in [0, n].
    Closed,
}

impl Ends {
    /// Every convention, as the input format names them.
    pub const NAMES: [&'static str; 3] = ["control", "repeat", "closed"];

    /// The input format's name of this convention: "control", "repeat" or "closed".
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Ends::Control => "control",
            Ends::Repeat => "repeat",
            Ends::Closed => "closed",
        }
    }

    /// The convention the input format calls `name`, if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        [Ends::Control, Ends::Repeat, Ends::Closed]
            .into_iter()
            .find(|ends| ends.name() == name)
    }

    /// The fewest points this convention accepts.
    #[must_use]
    pub fn min_points(self) -> usize {
        match self {
            Ends::Control => 4,
            Ends::Repeat => 2,
            Ends::Closed => 3,
        }
    }

    /// Refuses fewer than [`Ends::min_points`] points, naming "points".
    ///
    /// # Errors
    /// `n` is below the convention's minimum.
    pub(crate) fn check_points(self, n: usize) -> Result<(), InputError> {
        if n < self.min_points() {
            return Err(InputError::field(
                "points",
                format!(
                    "needs at least {} points with ends \"{}\", got {n}",
                    self.min_points(),
                    self.name()
                ),
            ));
        }
        Ok(())
    }

    /// Number of segments for `n` points (n >= `min_points`).
    #[must_use]
    pub fn segments(self, n: usize) -> usize {
        match self {
            Ends::Control => n - 3,
            Ends::Repeat => n - 1,
            Ends::Closed => n,
        }
    }

    /// Indices into the n points of segment i's window of four.
    pub(crate) fn window(self, n: usize, i: usize) -> [usize; 4] {
        // Position j of the extended sequence, mapped back to a point index.
        let at = |j: usize| -> usize {
            match self {
                Ends::Control => j,
                // [P0, P0, P1, ..., P_{n-1}, P_{n-1}]
                Ends::Repeat => j.saturating_sub(1).min(n - 1),
                // [P_{n-1}, P0, ..., P_{n-1}, P0, P1]: (j + n − 1) mod n, where j + n − 1 <
                // 3n (j <= n + 2 and n >= 3), without a division.
                Ends::Closed => {
                    let m = j + n - 1;
                    if m >= 2 * n {
                        m - 2 * n
                    } else if m >= n {
                        m - n
                    } else {
                        m
                    }
                }
            }
        };
        [at(i), at(i + 1), at(i + 2), at(i + 3)]
    }
}

/// A parameter given once for the whole curve, or one value per point (Kochanek–Bartels) or per
/// joint (a Beta-spline with local bias and tension).
#[derive(Clone, Debug, PartialEq)]
pub enum PerPoint {
    /// The same value at every point.
    All(f64),
    /// One value per point (or per joint).
    Each(Vec<f64>),
}

impl PerPoint {
    /// The value at point (or joint) `i`.
    pub(crate) fn at(&self, i: usize) -> f64 {
        match self {
            PerPoint::All(v) => *v,
            PerPoint::Each(values) => values[i],
        }
    }

    /// Checks the values: finite, and one per `per` ("point", "joint") of `n` when given so.
    pub(crate) fn check(&self, field: &str, n: usize, per: &str) -> Result<(), InputError> {
        let values = match self {
            PerPoint::All(v) => std::slice::from_ref(v),
            PerPoint::Each(values) => {
                if values.len() != n {
                    return Err(InputError::field(
                        field,
                        format!("must have one value per {per} ({n}), got {}", values.len()),
                    ));
                }
                values
            }
        };
        match values.iter().position(|v| !v.is_finite()) {
            Some(i) if matches!(self, PerPoint::Each(_)) => Err(InputError::field(
                field,
                format!("must be finite: {field}[{i}] = {}", Shown(values[i])),
            )),
            Some(i) => Err(InputError::field(
                field,
                format!("must be a finite number, got {}", Shown(values[i])),
            )),
            None => Ok(()),
        }
    }
}
