//! A document's curves (contract: "Input document"): each curve object's fields checked and
//! fitted as soon as it is read ([`fit_curve`]), its sampling resolved ([`sampling_spec`]), and
//! the fitted curves planned on every thread into the job ([`curve_job`]).

use serde_json::{Map, Value};

use splinegpu::kinds::{KindFields, kind_fields, not_a_field};
use splinegpu::{Curve, CurveKind, Derivatives, EvalJob, InputError, PerPoint, Points};
use splinegpu::{SamplePlan, Sampling, SegmentTable};

use crate::document::geometry::parse_geometry;
use crate::document::values::{describe, number, number_array, parse_ends, parse_matrix};
use splinegpu::geometry::Geometry;

/// A curve object as read: its fields (keys in order), its points and its sampling, checked
/// and fitted by [`fit_curve`].
pub(crate) struct ReadCurve {
    pub(crate) fields: Map<String, Value>,
    pub(crate) keys: Vec<String>,
    pub(crate) points: Option<Points>,
    pub(crate) sampling: Option<Sampling>,
}

/// One fitted curve, with its own sampling and geometry if it has them. The curve itself is
/// kept beside its table: a mesh's width is fitted as one more coordinate of it, and whether
/// the document asks for meshes is known only once it is read whole.
pub(crate) struct ParsedCurve {
    pub(crate) curve: Curve,
    pub(crate) table: SegmentTable,
    pub(crate) sampling: Option<Sampling>,
    pub(crate) geometry: Option<Geometry>,
}

/// A curve object's fields made into its curve, fitted, and its "geometry" read.
pub(crate) struct FittedCurve {
    pub(crate) curve: Curve,
    pub(crate) table: SegmentTable,
    pub(crate) geometry: Option<Geometry>,
}

/// A curve document's job: each curve's plan from its own sampling or the document's
/// (`sampling`), made on every thread, pushed in order, the first error by curve index.
///
/// # Errors
/// No curves, a document sampling or a plan that breaks its rules (placed at the document or
/// the curve).
pub(crate) fn curve_job(
    sampling: Option<&[(String, Value)]>,
    curves: Option<Vec<ParsedCurve>>,
    derivatives: Derivatives,
) -> Result<EvalJob, InputError> {
    let sampling = sampling
        .map(sampling_spec)
        .transpose()
        .map_err(InputError::in_document)?;
    let curves = curves.ok_or_else(|| InputError::field("curves", "is missing").in_document())?;
    if curves.is_empty() {
        return Err(InputError::field("curves", "must not be empty").in_document());
    }
    let default = sampling.unwrap_or_default();
    // Plans on every thread (an arc-length or tolerance plan measures its curve: most of the
    // time of such documents).
    let plans = plan_on_every_thread(&curves, |curve| {
        curve.table.check_range(derivatives)?;
        SamplePlan::new(&curve.table, curve.sampling.as_ref().unwrap_or(&default))
    });
    let mut job = EvalJob::new(derivatives);
    for (i, (curve, plan)) in curves.into_iter().zip(plans).enumerate() {
        let place = |e: InputError| e.in_curve(i);
        job.push_table(curve.table, plan.map_err(place)?)
            .map_err(place)?;
    }
    Ok(job)
}

/// `plan(curve)` for every curve, in order, the curves split into one contiguous range per
/// thread.
pub(crate) fn plan_on_every_thread(
    curves: &[ParsedCurve],
    plan: impl Fn(&ParsedCurve) -> Result<SamplePlan, InputError> + Sync,
) -> Vec<Result<SamplePlan, InputError>> {
    let threads = splinegpu::available_threads().clamp(1, curves.len().max(1));
    let plan = &plan;
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|k| {
                let part = &curves[curves.len() * k / threads..curves.len() * (k + 1) / threads];
                scope.spawn(move || part.iter().map(plan).collect::<Vec<_>>())
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a planning thread panicked"))
            .collect()
    })
}

/// The samplings, as a "sampling" object names them.
pub(crate) const SAMPLINGS: &str = "per_segment, at, arc_length or tolerance";

/// The sampling a "sampling" object's entries ask for.
pub(crate) fn sampling_spec(entries: &[(String, Value)]) -> Result<Sampling, InputError> {
    let [(key, v)] = entries else {
        return Err(InputError::field(
            "sampling",
            format!(
                "must have exactly one key ({SAMPLINGS}), got {}",
                entries.len()
            ),
        ));
    };
    match key.as_str() {
        "per_segment" => match v.as_u64() {
            Some(k) if k >= 1 && k <= u64::from(u32::MAX) => Ok(Sampling::PerSegment(k as u32)),
            _ => Err(InputError::field(
                "per_segment",
                format!("must be an integer from 1 to 2^32 - 1, got {}", describe(v)),
            )),
        },
        "at" => Ok(Sampling::At(number_array(v, "at")?)),
        "arc_length" => match v.as_u64() {
            Some(m) if m >= 2 && m <= u64::from(u32::MAX) => Ok(Sampling::ArcLength(m as u32)),
            _ => Err(InputError::field(
                "arc_length",
                format!("must be an integer from 2 to 2^32 - 1, got {}", describe(v)),
            )),
        },
        "tolerance" => match v.as_f64() {
            Some(tol) if tol > 0.0 => Ok(Sampling::Tolerance(tol)),
            _ => Err(InputError::field(
                "tolerance",
                format!("must be a number > 0, got {}", describe(v)),
            )),
        },
        other => Err(InputError::field(
            "sampling",
            format!("has an unknown key \"{other}\" (expected {SAMPLINGS})"),
        )),
    }
}

/// Checks a curve's fields (`keys` in the order given), builds the curve and fits it.
pub(crate) fn fit_curve(
    fields: &Map<String, Value>,
    keys: &[String],
    points: Option<Points>,
) -> Result<FittedCurve, InputError> {
    let kind = fields
        .get("kind")
        .ok_or_else(|| InputError::field("kind", "is missing"))?;
    let kind = kind.as_str().ok_or_else(|| {
        InputError::field("kind", format!("must be a string, got {}", describe(kind)))
    })?;
    let Some(allowed) = kind_fields(kind) else {
        // CurveKind::named words the unknown name's error.
        return Err(CurveKind::named(kind, KindFields::default()).expect_err("unknown kind"));
    };
    let key_ok = |key: &str| {
        ["kind", "points", "sampling", "geometry"].contains(&key) || allowed.contains(&key)
    };
    if let Some(key) = keys.iter().find(|k| !key_ok(k)) {
        return Err(not_a_field(kind, key));
    }
    let array_field = |field: &str| {
        fields
            .get(field)
            .map(|v| number_array(v, field))
            .transpose()
    };
    // A number, or (Kochanek–Bartels) an array of one number per point.
    let per_point_field = |field: &str| {
        fields
            .get(field)
            .map(|v| match v {
                Value::Array(_) => number_array(v, field).map(PerPoint::Each),
                _ => number(v, field).map(PerPoint::All),
            })
            .transpose()
    };
    let kind_fields = KindFields {
        ends: fields.get("ends").map(parse_ends).transpose()?,
        tension: per_point_field("tension")?,
        bias: per_point_field("bias")?,
        continuity: per_point_field("continuity")?,
        matrix: fields.get("matrix").map(parse_matrix).transpose()?,
        t: array_field("t")?,
        start_derivative: array_field("start_derivative")?,
        end_derivative: array_field("end_derivative")?,
        tangents: fields.get("tangents").map(parse_tangents).transpose()?,
        method: fields.get("method").map(parse_method).transpose()?,
        knots: array_field("knots")?,
        weights: array_field("weights")?,
    };
    let kind = CurveKind::named(kind, kind_fields)?;
    let points = points.ok_or_else(|| InputError::field("points", "is missing"))?;
    let geometry = fields.get("geometry").map(parse_geometry).transpose()?;
    let curve = Curve::new(kind, points)?;
    Ok(FittedCurve {
        table: curve.fit(),
        curve,
        geometry,
    })
}

/// "tangents": an array of arrays of numbers, all of one length, flattened (their count and
/// length against the points are the curve's to check).
fn parse_tangents(value: &Value) -> Result<Vec<f64>, InputError> {
    let rows = value.as_array().ok_or_else(|| {
        InputError::field(
            "tangents",
            format!(
                "must be an array of tangents (arrays of numbers), got {}",
                describe(value)
            ),
        )
    })?;
    let mut flat = Vec::new();
    let mut width = None;
    for (i, row) in rows.iter().enumerate() {
        let row = number_array(row, "tangents").map_err(|_| {
            InputError::field(
                "tangents",
                format!(
                    "tangents[{i}] must be an array of numbers, got {}",
                    describe(row)
                ),
            )
        })?;
        match width {
            Some(w) if w != row.len() => {
                return Err(InputError::field(
                    "tangents",
                    format!(
                        "tangents[{i}] has {} numbers where tangents[0] has {w}",
                        row.len()
                    ),
                ));
            }
            _ => width = Some(row.len()),
        }
        flat.extend(row);
    }
    Ok(flat)
}

fn parse_method(value: &Value) -> Result<String, InputError> {
    value.as_str().map(str::to_owned).ok_or_else(|| {
        InputError::field(
            "method",
            format!("must be \"akima\" or \"makima\", got {}", describe(value)),
        )
    })
}
