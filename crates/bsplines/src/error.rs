//! The one error type of the crate: a bad input, located. Every check names the argument it
//! is about ("x", "w", "t", "k", ...), the series of a batch it is in (where the call takes
//! many) and the position inside that argument (where one element is to blame), so that a
//! caller can point at the value: `series 3, x[17]: x must be strictly increasing (0.5 after 0.5)`.

use std::borrow::Cow;
use std::fmt;

/// A bad input: what is wrong with which argument, where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InputError {
    /// The argument, by its name in this crate's API ("x", "y", "w", "t", "k", "s", "lam", ...).
    pub argument: &'static str,
    /// The series of a batch the input belongs to; None for a call on one series.
    pub series: Option<usize>,
    /// The element of the argument to blame (an index into x, t, ...), where one is.
    pub position: Option<usize>,
    /// What is wrong, in words (SciPy's own words where SciPy refuses the same input).
    pub message: Cow<'static, str>,
}

impl InputError {
    /// An error about `argument` as a whole.
    pub fn new(argument: &'static str, message: impl Into<Cow<'static, str>>) -> Self {
        Self {
            argument,
            series: None,
            position: None,
            message: message.into(),
        }
    }

    /// The same error, blamed on element `position` of the argument.
    #[must_use]
    pub fn at(self, position: usize) -> Self {
        Self {
            position: Some(position),
            ..self
        }
    }

    /// The same error, in series `series` of a batch.
    #[must_use]
    pub fn in_series(self, series: usize) -> Self {
        Self {
            series: Some(series),
            ..self
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(series) = self.series {
            write!(f, "series {series}, ")?;
        }
        f.write_str(self.argument)?;
        if let Some(position) = self.position {
            write!(f, "[{position}]")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for InputError {}

/// The first value that is NaN or infinite, as an error about `argument` at its position.
pub fn check_finite(argument: &'static str, values: &[f64]) -> Result<(), InputError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => {
            Err(InputError::new(argument, format!("must be finite, got {}", values[i])).at(i))
        }
        None => Ok(()),
    }
}

/// The first place where `values` is not finite, or fails to increase (strictly, or allowing
/// ties), as an error about `argument` naming the position and the values: the one ordering
/// check of the crate.
pub fn check_increasing(
    argument: &'static str,
    values: &[f64],
    strictly: bool,
) -> Result<(), InputError> {
    check_finite(argument, values)?;
    let wrong = |p: &[f64]| if strictly { p[1] <= p[0] } else { p[1] < p[0] };
    if let Some(i) = values.windows(2).position(wrong) {
        let order = if strictly {
            "strictly increasing"
        } else {
            "non-decreasing"
        };
        return Err(InputError::new(
            argument,
            format!("must be {order} ({} after {})", values[i + 1], values[i]),
        )
        .at(i + 1));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{InputError, check_increasing};

    #[test]
    fn an_error_names_the_series_the_argument_and_the_position() {
        let e = InputError::new("x", "must be finite").at(17).in_series(3);
        assert_eq!(e.to_string(), "series 3, x[17]: must be finite");
        assert_eq!(
            InputError::new("k", "must be 1 to 5").to_string(),
            "k: must be 1 to 5"
        );
    }

    #[test]
    fn the_ordering_check_names_the_first_offending_position() {
        assert_eq!(check_increasing("x", &[0.0, 1.0, 1.0], false), Ok(()));
        let tie = check_increasing("x", &[0.0, 1.0, 1.0], true).unwrap_err();
        assert_eq!(tie.position, Some(2));
        assert_eq!(tie.message, "must be strictly increasing (1 after 1)");
        let back = check_increasing("t", &[0.0, 2.0, 1.0], false).unwrap_err();
        assert_eq!(back.to_string(), "t[2]: must be non-decreasing (1 after 2)");
        let nan = check_increasing("x", &[0.0, f64::NAN], true).unwrap_err();
        assert_eq!(nan.to_string(), "x[1]: must be finite, got NaN");
    }
}
