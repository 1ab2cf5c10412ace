//! A document's "geometry" (contract: "Geometry: strokes, tubes and ribbons"): the object read
//! into the library's [`Geometry`], every field's error naming the field and its value, and
//! the curves' meshes planned into a [`GeometryJob`].

use serde_json::{Map, Value};

use splinegpu::geometry::{Cap, Dash, Geometry, GeometryJob, Join, Ribbon, Stroke, Tube, Width};
use splinegpu::{Curve, Derivatives, InputError, Sampling};

use crate::document::curves::{ParsedCurve, sampling_spec};
use crate::document::values::{describe, number, number_array};

/// The geometry keys and each one's fields.
const STROKE_FIELDS: [&str; 7] = [
    "width",
    "cap",
    "join",
    "miter_limit",
    "sides",
    "dash",
    "dash_offset",
];
const TUBE_FIELDS: [&str; 6] = ["radius", "sides", "up", "caps", "dash", "dash_offset"];
const RIBBON_FIELDS: [&str; 4] = ["width", "up", "dash", "dash_offset"];

/// A "geometry" value: an object with exactly one key, "stroke", "tube" or "ribbon", whose
/// value is an object of that geometry's fields.
///
/// # Errors
/// The rule broken, naming the field ("geometry" or the inner key) and the value.
pub(crate) fn parse_geometry(value: &Value) -> Result<Geometry, InputError> {
    let wrong = |why: String| InputError::field("geometry", why);
    let object = value.as_object().ok_or_else(|| {
        wrong(format!(
            "must be an object with one key (stroke, tube or ribbon), got {}",
            describe(value)
        ))
    })?;
    let mut entries = object.iter();
    let (Some((key, fields)), None) = (entries.next(), entries.next()) else {
        return Err(wrong(format!(
            "must have exactly one key (stroke, tube or ribbon), got {}",
            object.len()
        )));
    };
    let allowed: &[&str] = match key.as_str() {
        "stroke" => &STROKE_FIELDS,
        "tube" => &TUBE_FIELDS,
        "ribbon" => &RIBBON_FIELDS,
        other => {
            return Err(wrong(format!(
                "has an unknown key \"{other}\" (expected stroke, tube or ribbon)"
            )));
        }
    };
    let fields = fields.as_object().ok_or_else(|| {
        InputError::field(
            key.as_str(),
            format!("must be an object of its fields, got {}", describe(fields)),
        )
    })?;
    if let Some(field) = fields.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(InputError::field(
            field.as_str(),
            format!(
                "is not a field of a {key} (allowed: {})",
                allowed.join(", ")
            ),
        ));
    }
    Ok(match key.as_str() {
        "stroke" => Geometry::Stroke(stroke(fields)?),
        "tube" => Geometry::Tube(tube(fields)?),
        _ => Geometry::Ribbon(Ribbon {
            width: width(fields, "width")?,
            up: up(fields)?,
            dash: dash(fields)?,
        }),
    })
}

fn stroke(fields: &Map<String, Value>) -> Result<Stroke, InputError> {
    let mut stroke = Stroke {
        width: width(fields, "width")?,
        dash: dash(fields)?,
        ..Stroke::default()
    };
    if let Some(v) = fields.get("cap") {
        stroke.cap = match v.as_str() {
            Some("butt") => Cap::Butt,
            Some("round") => Cap::Round,
            Some("square") => Cap::Square,
            _ => return Err(one_of("cap", "\"butt\", \"round\" or \"square\"", v)),
        };
    }
    if let Some(v) = fields.get("join") {
        stroke.join = match v.as_str() {
            Some("miter") => Join::Miter,
            Some("round") => Join::Round,
            Some("bevel") => Join::Bevel,
            _ => return Err(one_of("join", "\"miter\", \"round\" or \"bevel\"", v)),
        };
    }
    if let Some(v) = fields.get("miter_limit") {
        stroke.miter_limit = number(v, "miter_limit")?;
    }
    if let Some(v) = fields.get("sides") {
        stroke.sides = sides(v)?;
    }
    Ok(stroke)
}

fn tube(fields: &Map<String, Value>) -> Result<Tube, InputError> {
    let mut tube = Tube {
        radius: width(fields, "radius")?,
        up: up(fields)?,
        dash: dash(fields)?,
        ..Tube::default()
    };
    if let Some(v) = fields.get("sides") {
        tube.sides = Some(sides(v)?);
    }
    if let Some(v) = fields.get("caps") {
        tube.caps = v
            .as_bool()
            .ok_or_else(|| one_of("caps", "true or false", v))?;
    }
    Ok(tube)
}

fn one_of(field: &str, allowed: &str, got: &Value) -> InputError {
    InputError::field(field, format!("must be {allowed}, got {}", describe(got)))
}

/// "width" or "radius" (required): a number, or an array of one number per point (its
/// values and length are checked against the curve when it is planned).
fn width(fields: &Map<String, Value>, field: &str) -> Result<Width, InputError> {
    match fields.get(field) {
        None => Err(InputError::field(field, "is missing")),
        Some(v @ Value::Array(_)) => Ok(Width::PerPoint(number_array(v, field)?)),
        Some(v) => Ok(Width::Constant(number(v, field)?)),
    }
}

/// "sides": an integer (its least value is the geometry's to check).
fn sides(v: &Value) -> Result<u32, InputError> {
    v.as_u64()
        .and_then(|s| u32::try_from(s).ok())
        .ok_or_else(|| one_of("sides", "an integer from 0 to 2^32 - 1", v))
}

/// "up": 3 finite numbers (its angle with the first tangent is checked when planned).
fn up(fields: &Map<String, Value>) -> Result<Option<[f64; 3]>, InputError> {
    let Some(v) = fields.get("up") else {
        return Ok(None);
    };
    let values = number_array(v, "up")?;
    match <[f64; 3]>::try_from(values) {
        Ok(up) => Ok(Some(up)),
        Err(_) => Err(one_of("up", "an array of 3 finite numbers", v)),
    }
}

/// "dash" and "dash_offset": an array of numbers and a number (the pattern's rules are the
/// library's to check); an offset without a pattern is refused.
fn dash(fields: &Map<String, Value>) -> Result<Option<Dash>, InputError> {
    let offset = fields
        .get("dash_offset")
        .map(|v| number(v, "dash_offset"))
        .transpose()?;
    match (fields.get("dash"), offset) {
        (None, None) => Ok(None),
        (None, Some(_)) => Err(InputError::field(
            "dash_offset",
            "needs a \"dash\" pattern beside it",
        )),
        (Some(v), offset) => Ok(Some(Dash {
            lengths: number_array(v, "dash")?,
            offset: offset.unwrap_or(0.0),
        })),
    }
}

/// A curves document whose curves carry geometry (their own, or `document`'s): every curve's
/// mesh planned, in order, the first error by curve index.
///
/// # Errors
/// Derivatives asked for, a curve without geometry, or a curve's geometry, sampling or mesh
/// that breaks its rules (placed at the document or the curve).
pub(crate) fn geometry_job(
    sampling: Option<&[(String, Value)]>,
    document: Option<&Value>,
    curves: Vec<ParsedCurve>,
    derivatives: Derivatives,
) -> Result<GeometryJob, InputError> {
    if derivatives != Derivatives::None {
        return Err(InputError::field(
            "derivatives",
            format!(
                "must be 0 with geometry (a mesh has no derivatives), got {}",
                derivatives.order()
            ),
        )
        .in_document());
    }
    let sampling = sampling
        .map(sampling_spec)
        .transpose()
        .map_err(InputError::in_document)?
        .unwrap_or_default();
    let document = document
        .map(parse_geometry)
        .transpose()
        .map_err(InputError::in_document)?;
    let mut meshes: Vec<(Curve, Geometry, Sampling)> = Vec::with_capacity(curves.len());
    for (i, curve) in curves.into_iter().enumerate() {
        let geometry = curve.geometry.or_else(|| document.clone()).ok_or_else(|| {
            InputError::field(
                "geometry",
                "is missing: when the document or any curve has geometry, every curve needs one",
            )
            .in_curve(i)
        })?;
        let sampling = curve.sampling.unwrap_or_else(|| sampling.clone());
        meshes.push((curve.curve, geometry, sampling));
    }
    let mut job = GeometryJob::new();
    // Errors are placed at the curve's index in the job, which is the document's.
    job.push_many(&meshes)?;
    Ok(job)
}
