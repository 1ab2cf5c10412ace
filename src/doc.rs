//! The CLI's input document (contract: "Input document"), parsed and checked into an
//! [`EvalJob`]. Every error names the curve index (or the document key), the field and the
//! value; the whole document is checked before anything is evaluated.

use serde_json::{Map, Value};

use crate::basis::Basis;
use crate::curve::{Curve, CurveKind, Ends, Points};
use crate::error::InputError;
use crate::fit::interp::EndCondition;
use crate::job::{Derivatives, EvalJob};
use crate::sampling::Sampling;

/// Why a document cannot be evaluated.
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
pub enum DocumentError {
    /// The document breaks a rule of the contract (CLI exit status 2).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The document is valid but asks for something this build does not do yet (exit 1).
    #[error("not supported yet: {0}")]
    Unsupported(String),
}

/// Every kind the contract names.
const KINDS: [&str; 11] = [
    "cardinal",
    "catmull-rom",
    "bspline",
    "tensioned-bspline",
    "beta",
    "matrix",
    "bezier",
    "natural",
    "clamped",
    "periodic",
    "not-a-knot",
];

/// A "sampling" object as written: arc-length sampling is checked but not built yet.
#[derive(Clone, Debug, PartialEq)]
enum SamplingSpec {
    Plan(Sampling),
    ArcLength,
}

/// Parses and checks a document, fits its curves and resolves their sampling.
///
/// # Errors
/// [`DocumentError::Input`] for the first rule broken (JSON syntax errors give line and
/// column); [`DocumentError::Unsupported`] when the document is valid but needs a feature
/// not built yet.
pub fn parse_document(text: &str) -> Result<EvalJob, DocumentError> {
    let root: Value = serde_json::from_str(text).map_err(|e| {
        InputError::document(format!(
            "invalid JSON at line {}, column {}: {}",
            e.line(),
            e.column(),
            strip_position(&e.to_string())
        ))
    })?;
    let root = root.as_object().ok_or_else(|| {
        InputError::document(format!("must be a JSON object, got {}", describe(&root)))
    })?;
    check_keys(root, &["sampling", "derivatives", "curves"], "the document")?;
    let mut unsupported = None;
    let sampling = match root.get("sampling") {
        Some(v) => parse_sampling(v)?,
        None => SamplingSpec::Plan(Sampling::default()),
    };
    let derivatives = match root.get("derivatives") {
        None => Derivatives::None,
        Some(v) => v
            .as_u64()
            .and_then(Derivatives::from_order)
            .ok_or_else(|| {
                InputError::field(
                    "derivatives",
                    format!("must be 0, 1 or 2, got {}", describe(v)),
                )
            })?,
    };
    let curves = root
        .get("curves")
        .ok_or_else(|| InputError::field("curves", "is missing"))?
        .as_array()
        .ok_or_else(|| InputError::field("curves", "must be an array of curves"))?;
    if curves.is_empty() {
        return Err(InputError::field("curves", "must not be empty").into());
    }
    let mut job = EvalJob::new(derivatives);
    for (i, value) in curves.iter().enumerate() {
        parse_curve(value, &sampling, &mut job, &mut unsupported).map_err(|e| e.in_curve(i))?;
    }
    match unsupported {
        Some(what) => Err(DocumentError::Unsupported(what)),
        None => Ok(job),
    }
}

/// Parses one curve and adds it to `job`; errors are placed in the curve by the caller.
fn parse_curve(
    value: &Value,
    default_sampling: &SamplingSpec,
    job: &mut EvalJob,
    unsupported: &mut Option<String>,
) -> Result<(), InputError> {
    let curve = value.as_object().ok_or_else(|| {
        InputError::document(format!("must be a JSON object, got {}", describe(value)))
    })?;
    let kind = curve
        .get("kind")
        .ok_or_else(|| InputError::field("kind", "is missing"))?;
    let kind = kind.as_str().ok_or_else(|| {
        InputError::field("kind", format!("must be a string, got {}", describe(kind)))
    })?;
    if !KINDS.contains(&kind) {
        return Err(InputError::field(
            "kind",
            format!(
                "is unknown: \"{kind}\" (expected one of {})",
                KINDS.join(", ")
            ),
        ));
    }
    let owner = format!("a \"{kind}\" curve");
    let points = parse_points(
        curve
            .get("points")
            .ok_or_else(|| InputError::field("points", "is missing"))?,
    )?;
    let sampling = match curve.get("sampling") {
        Some(v) => parse_sampling(v)?,
        None => default_sampling.clone(),
    };
    let uniform = |basis: Basis, extra: &[&str]| -> Result<CurveKind, InputError> {
        let mut allowed = vec!["kind", "points", "sampling", "ends"];
        allowed.extend_from_slice(extra);
        check_keys(curve, &allowed, &owner)?;
        Ok(CurveKind::Uniform {
            basis,
            ends: parse_ends(curve.get("ends"))?,
        })
    };
    let number_or = |field: &str, default: f64| match curve.get(field) {
        None => Ok(default),
        Some(v) => number(v, field),
    };
    let kind = match kind {
        "cardinal" => uniform(
            Basis::Cardinal {
                tension: number_or("tension", 0.5)?,
            },
            &["tension"],
        )?,
        "catmull-rom" => uniform(Basis::CatmullRom, &[])?,
        "bspline" => uniform(Basis::BSpline, &[])?,
        "tensioned-bspline" => uniform(
            Basis::TensionedBSpline {
                tension: number_or("tension", 1.0)?,
            },
            &["tension"],
        )?,
        "beta" => uniform(
            Basis::Beta {
                bias: number_or("bias", 1.0)?,
                tension: number_or("tension", 0.0)?,
            },
            &["bias", "tension"],
        )?,
        "matrix" => {
            let m = curve
                .get("matrix")
                .ok_or_else(|| InputError::field("matrix", "is missing"))?;
            uniform(Basis::Matrix(parse_matrix(m)?), &["matrix"])?
        }
        "bezier" => {
            check_keys(curve, &["kind", "points", "sampling"], &owner)?;
            CurveKind::Bezier
        }
        interpolating => interpolating_kind(curve, interpolating, &owner)?,
    };
    let curve = Curve::new(kind, points)?;
    match sampling {
        SamplingSpec::Plan(sampling) => job.push(&curve, &sampling),
        SamplingSpec::ArcLength => {
            unsupported.get_or_insert_with(|| "\"arc_length\" sampling".to_string());
            Ok(())
        }
    }
}

/// An interpolating curve's kind from its fields ("t", and for clamped ends the two
/// derivatives); the data themselves are checked by `Curve::new`.
fn interpolating_kind(
    curve: &Map<String, Value>,
    kind: &str,
    owner: &str,
) -> Result<CurveKind, InputError> {
    let mut allowed = vec!["kind", "points", "sampling", "t"];
    if kind == "clamped" {
        allowed.extend(["start_derivative", "end_derivative"]);
    }
    check_keys(curve, &allowed, owner)?;
    let derivative = |field: &str| -> Result<Vec<f64>, InputError> {
        let v = curve.get(field).ok_or_else(|| {
            InputError::field(
                field,
                "is missing (a clamped spline needs both end derivatives)",
            )
        })?;
        number_array(v, field)
    };
    let condition = match kind {
        "natural" => EndCondition::Natural,
        "periodic" => EndCondition::Periodic,
        "not-a-knot" => EndCondition::NotAKnot,
        _ => EndCondition::Clamped {
            start: derivative("start_derivative")?,
            end: derivative("end_derivative")?,
        },
    };
    let t = curve.get("t").map(|v| number_array(v, "t")).transpose()?;
    Ok(CurveKind::Interpolating { condition, t })
}

fn parse_sampling(value: &Value) -> Result<SamplingSpec, InputError> {
    let map = value.as_object().ok_or_else(|| {
        InputError::field(
            "sampling",
            format!("must be an object, got {}", describe(value)),
        )
    })?;
    if map.len() != 1 {
        return Err(InputError::field(
            "sampling",
            format!(
                "must have exactly one key (per_segment, at or arc_length), got {}",
                map.len()
            ),
        ));
    }
    let (key, v) = map.iter().next().expect("one key");
    match key.as_str() {
        "per_segment" => match v.as_u64() {
            Some(k) if k >= 1 && k <= u64::from(u32::MAX) => {
                Ok(SamplingSpec::Plan(Sampling::PerSegment(k as u32)))
            }
            _ => Err(InputError::field(
                "per_segment",
                format!("must be an integer >= 1, got {}", describe(v)),
            )),
        },
        "at" => Ok(SamplingSpec::Plan(Sampling::At(number_array(v, "at")?))),
        "arc_length" => match v.as_u64() {
            Some(m) if m >= 2 && m <= u64::from(u32::MAX) => Ok(SamplingSpec::ArcLength),
            _ => Err(InputError::field(
                "arc_length",
                format!("must be an integer >= 2, got {}", describe(v)),
            )),
        },
        other => Err(InputError::field(
            "sampling",
            format!("has an unknown key \"{other}\" (expected per_segment, at or arc_length)"),
        )),
    }
}

fn parse_ends(value: Option<&Value>) -> Result<Ends, InputError> {
    match value {
        None => Ok(Ends::default()),
        Some(v) => match v.as_str() {
            Some("control") => Ok(Ends::Control),
            Some("repeat") => Ok(Ends::Repeat),
            Some("closed") => Ok(Ends::Closed),
            _ => Err(InputError::field(
                "ends",
                format!(
                    "must be \"control\", \"repeat\" or \"closed\", got {}",
                    describe(v)
                ),
            )),
        },
    }
}

fn parse_points(value: &Value) -> Result<Points, InputError> {
    let rows = value.as_array().ok_or_else(|| {
        InputError::field(
            "points",
            format!("must be an array of points, got {}", describe(value)),
        )
    })?;
    if rows.is_empty() {
        return Err(InputError::field("points", "must not be empty"));
    }
    let mut dim = 0;
    let mut coords = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        let point = row.as_array().ok_or_else(|| {
            InputError::field(
                "points",
                format!("must be arrays of numbers: points[{i}] = {}", describe(row)),
            )
        })?;
        if i == 0 {
            dim = point.len();
            if dim == 0 || dim > crate::MAX_DIM {
                return Err(InputError::field(
                    "points",
                    format!(
                        "must have 1 to {} coordinates per point: points[0] has {dim}",
                        crate::MAX_DIM
                    ),
                ));
            }
        } else if point.len() != dim {
            return Err(InputError::field(
                "points",
                format!(
                    "must all have the same dimension: points[{i}] has {} coordinates, points[0] has {dim}",
                    point.len()
                ),
            ));
        }
        for (k, v) in point.iter().enumerate() {
            coords.push(v.as_f64().ok_or_else(|| {
                InputError::field(
                    "points",
                    format!("must be numbers: points[{i}][{k}] = {}", describe(v)),
                )
            })?);
        }
    }
    Points::new(dim, coords)
}

fn parse_matrix(value: &Value) -> Result<[[f64; 4]; 4], InputError> {
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

fn number(value: &Value, field: &str) -> Result<f64, InputError> {
    value.as_f64().ok_or_else(|| {
        InputError::field(field, format!("must be a number, got {}", describe(value)))
    })
}

fn number_array(value: &Value, field: &str) -> Result<Vec<f64>, InputError> {
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

/// Unknown keys are errors: they are usually typos, or fields of another kind.
fn check_keys(map: &Map<String, Value>, allowed: &[&str], owner: &str) -> Result<(), InputError> {
    match map.keys().find(|k| !allowed.contains(&k.as_str())) {
        None => Ok(()),
        Some(key) => Err(InputError::field(
            key.clone(),
            format!(
                "is not a field of {owner} (allowed: {})",
                allowed.join(", ")
            ),
        )),
    }
}

/// A JSON value in a message: its text, shortened.
fn describe(value: &Value) -> String {
    let text = value.to_string();
    if text.chars().count() > 40 {
        format!("{}...", text.chars().take(37).collect::<String>())
    } else {
        text
    }
}

/// serde_json appends " at line L column C"; the message gives those itself.
fn strip_position(message: &str) -> &str {
    message
        .rfind(" at line ")
        .map_or(message, |i| &message[..i])
}
