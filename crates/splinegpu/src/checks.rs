//! The library's one ordering check: parameters, knots and surface directions are finite and
//! increase (strictly, or allowing ties), and the first value that does not is named with its
//! index and the value before it. A leaf module: every fit and table calls it, it calls none.

use crate::error::{InputError, Shown};

/// How a sequence must increase.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Order {
    /// Each value greater than the one before (parameters t, a table's knots).
    Strictly,
    /// Each value at least the one before (a B-spline's knot vector).
    NonDecreasing,
}

/// Checks that every value of `values` is finite and that they increase as `order` says.
/// Branch-free passes first (vectorized); the searches for the first bad value run only when
/// there is one.
///
/// # Errors
/// The first value that is not finite (`must be finite: t[3] = NaN`), else the first that does
/// not increase (`must be strictly increasing: t[2] = 1 follows t[1] = 1`), about field `field`.
pub(crate) fn check_increasing(
    field: &str,
    values: &[f64],
    order: Order,
) -> Result<(), InputError> {
    if !crate::points::all_finite(values)
        && let Some(i) = values.iter().position(|v| !v.is_finite())
    {
        return Err(InputError::field(
            field,
            format!("must be finite: {field}[{i}] = {}", Shown(values[i])),
        ));
    }
    let wrong = |a: f64, b: f64| match order {
        Order::Strictly => b <= a,
        Order::NonDecreasing => b < a,
    };
    let increasing = values
        .windows(2)
        .fold(true, |ok, w| ok & !wrong(w[0], w[1]));
    if !increasing && let Some(i) = (1..values.len()).find(|&i| wrong(values[i - 1], values[i])) {
        let name = match order {
            Order::Strictly => "strictly increasing",
            Order::NonDecreasing => "non-decreasing",
        };
        return Err(InputError::field(
            field,
            format!(
                "must be {name}: {field}[{i}] = {} follows {field}[{}] = {}",
                Shown(values[i]),
                i - 1,
                Shown(values[i - 1])
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_bad_value_is_named_with_its_index() {
        assert!(check_increasing("t", &[0.0, 1.0, 2.0], Order::Strictly).is_ok());
        assert!(check_increasing("knots", &[0.0, 0.0, 1.0], Order::NonDecreasing).is_ok());
        let e = check_increasing("t", &[0.0, 1.0, 1.0], Order::Strictly).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("t"));
        assert_eq!(
            e.message,
            "must be strictly increasing: t[2] = 1 follows t[1] = 1"
        );
        let e = check_increasing("u", &[0.0, f64::NAN, 1.0], Order::Strictly).unwrap_err();
        assert_eq!(e.message, "must be finite: u[1] = NaN");
        let e = check_increasing("knots", &[0.0, 2.0, 1.0], Order::NonDecreasing).unwrap_err();
        assert_eq!(
            e.message,
            "must be non-decreasing: knots[2] = 1 follows knots[1] = 2"
        );
    }
}
