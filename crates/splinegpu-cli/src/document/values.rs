//! The JSON values of a document's fields read as numbers, arrays, matrices and end
//! conventions, each error naming the field and the value it got: shared by curves and surfaces.

use serde_json::Value;

use splinegpu::{Ends, InputError};

pub(crate) fn parse_ends(v: &Value) -> Result<Ends, InputError> {
    match v.as_str().and_then(Ends::from_name) {
        Some(ends) => Ok(ends),
        None => Err(InputError::field(
            "ends",
            format!(
                "must be \"control\", \"repeat\" or \"closed\", got {}",
                describe(v)
            ),
        )),
    }
}

pub(crate) fn parse_matrix(value: &Value) -> Result<[[f64; 4]; 4], InputError> {
    let wrong = || {
        InputError::field(
            "matrix",
            format!("must be 4 rows of 4 numbers, got {}", describe(value)),
        )
    };
    let rows = value
        .as_array()
        .filter(|r| r.len() == 4)
        .ok_or_else(wrong)?;
    let mut m = [[0.0; 4]; 4];
    for (r, row) in rows.iter().enumerate() {
        let row = row.as_array().filter(|c| c.len() == 4).ok_or_else(wrong)?;
        for (c, v) in row.iter().enumerate() {
            m[r][c] = v.as_f64().ok_or_else(wrong)?;
        }
    }
    Ok(m)
}

pub(crate) fn number(value: &Value, field: &str) -> Result<f64, InputError> {
    value.as_f64().ok_or_else(|| {
        InputError::field(field, format!("must be a number, got {}", describe(value)))
    })
}

pub(crate) fn number_array(value: &Value, field: &str) -> Result<Vec<f64>, InputError> {
    let items = value.as_array().ok_or_else(|| {
        InputError::field(
            field,
            format!("must be an array of numbers, got {}", describe(value)),
        )
    })?;
    items
        .iter()
        .enumerate()
        .map(|(i, v)| {
            v.as_f64().ok_or_else(|| {
                InputError::field(
                    field,
                    format!("must hold numbers: {field}[{i}] = {}", describe(v)),
                )
            })
        })
        .collect()
}

/// A JSON value in a message: its text, shortened.
pub(crate) fn describe(value: &Value) -> String {
    abbreviate(value.to_string())
}

/// `text` as a message quotes a value: cut to 37 characters and "..." beyond 40.
pub(crate) fn abbreviate(text: String) -> String {
    if text.chars().count() > 40 {
        format!("{}...", text.chars().take(37).collect::<String>())
    } else {
        text
    }
}
