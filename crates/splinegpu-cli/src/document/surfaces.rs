//! A document's surfaces (contract: "Surfaces"): each surface object's fields read into the
//! library's [`SurfaceFields`] and [`Surface`], its sampling into a [`SurfaceSampling`], and
//! the whole into a [`SurfaceJob`].
//! The JSON walk (duplicate keys, the document's keys) is `walk`'s; this is what the
//! surface objects' values mean.

use serde_json::{Map, Value};

use splinegpu::surface::{
    Net, Surface, SurfaceFields, SurfaceJob, SurfaceKind, SurfaceSampling, not_a_surface_field,
    not_a_surface_kind, surface_kind_fields,
};
use splinegpu::{Derivatives, EndCondition, Ends, InputError, MAX_DIM};

use crate::document::values::{describe, number, number_array, parse_ends, parse_matrix};

/// Vertices a written document evaluates at a time (whole surfaces, at least one): 1,048,576
/// as curves' chunks, or `SPLINEGPU_CHUNK_SAMPLES` as for curves. The job keeps the plans of
/// up to 4 groups' vertices in all (about 256 MiB of plans); the others are made again when
/// their group is evaluated, so that memory stays bounded however many surfaces a document
/// holds.
pub fn group_vertices() -> usize {
    std::env::var("SPLINEGPU_CHUNK_SAMPLES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1 << 20)
}

/// A surface object as read: its fields (keys in order) and its own sampling's entries.
#[derive(Debug)]
pub(crate) struct ReadSurface {
    pub(crate) fields: Map<String, Value>,
    pub(crate) keys: Vec<String>,
    pub(crate) sampling: Option<Vec<(String, Value)>>,
}

/// The job of a surface document: each surface checked, fitted and planned, the first error
/// placed at its surface.
///
/// # Errors
/// The first rule broken, at its surface (or at the document for "normals").
pub(crate) fn surface_job(
    surfaces: Vec<ReadSurface>,
    default: Option<&[(String, Value)]>,
    derivatives: Derivatives,
    normals: bool,
) -> Result<SurfaceJob, InputError> {
    if surfaces.is_empty() {
        return Err(InputError::field("surfaces", "must not be empty").in_document());
    }
    let mut job = SurfaceJob::new(derivatives, normals)
        .keeping_plans_up_to(group_vertices().saturating_mul(4))
        .streamed();
    for (i, read) in surfaces.into_iter().enumerate() {
        let place = |e: InputError| e.in_surface(i);
        let surface = build_surface(&read.fields, &read.keys).map_err(place)?;
        let patch_list = matches!(surface.kind(), SurfaceKind::BezierPatches { .. });
        let sampling = match read.sampling.as_deref().or(default) {
            None => SurfaceSampling::PerSegment([16, 16]),
            Some(entries) => surface_sampling(entries, patch_list).map_err(place)?,
        };
        // The document's values go before the fit: its table is the largest thing made.
        drop(read);
        job.push(surface.fit(), sampling).map_err(place)?;
    }
    Ok(job)
}

/// A surface's "sampling" entries: per_segment k or [k_u, k_v]; at pairs (triples on a patch
/// list); tolerance; arc_length is refused.
fn surface_sampling(
    entries: &[(String, Value)],
    patch_list: bool,
) -> Result<SurfaceSampling, InputError> {
    let [(key, v)] = entries else {
        return Err(InputError::field(
            "sampling",
            format!(
                "must have exactly one key (per_segment, at or tolerance), got {}",
                entries.len()
            ),
        ));
    };
    let count = |v: &Value| v.as_u64().filter(|k| (1..=1 << 20).contains(k));
    match key.as_str() {
        "per_segment" => {
            let k = match v {
                Value::Array(pair) if pair.len() == 2 && !patch_list => {
                    match (count(&pair[0]), count(&pair[1])) {
                        (Some(a), Some(b)) => Some([a as u32, b as u32]),
                        _ => None,
                    }
                }
                Value::Array(_) if patch_list => {
                    return Err(InputError::field(
                        "per_segment",
                        format!("of a patch list takes one k, got {}", describe(v)),
                    ));
                }
                _ => count(v).map(|k| [k as u32; 2]),
            };
            k.map(SurfaceSampling::PerSegment).ok_or_else(|| {
                InputError::field(
                    "per_segment",
                    format!(
                        "must be an integer from 1 to 2^20 or a pair of them, got {}",
                        describe(v)
                    ),
                )
            })
        }
        "at" => {
            let items = v.as_array().ok_or_else(|| {
                InputError::field("at", format!("must be an array, got {}", describe(v)))
            })?;
            let width = if patch_list { 3 } else { 2 };
            let mut pairs = Vec::with_capacity(items.len());
            let mut triples = Vec::new();
            for (i, item) in items.iter().enumerate() {
                let values = number_array(item, "at")
                    .ok()
                    .filter(|x| x.len() == width)
                    .ok_or_else(|| {
                        let what = if patch_list { "[p, u, v]" } else { "[u, v]" };
                        InputError::field(
                            "at",
                            format!("must hold {what} entries: at[{i}] = {}", describe(item)),
                        )
                    })?;
                if patch_list {
                    let p = values[0];
                    if !(p >= 0.0 && p.fract() == 0.0 && p < 1e15) {
                        return Err(InputError::field(
                            "at",
                            format!("patch numbers must be integers >= 0: at[{i}][0] = {p}"),
                        ));
                    }
                    triples.push((p as usize, [values[1], values[2]]));
                } else {
                    pairs.push([values[0], values[1]]);
                }
            }
            Ok(if patch_list {
                SurfaceSampling::AtPatches(triples)
            } else {
                SurfaceSampling::At(pairs)
            })
        }
        "tolerance" => match v.as_f64() {
            Some(tol) if tol > 0.0 => Ok(SurfaceSampling::Tolerance(tol)),
            _ => Err(InputError::field(
                "tolerance",
                format!("must be a number > 0, got {}", describe(v)),
            )),
        },
        "arc_length" => Err(InputError::field(
            "sampling",
            "\"arc_length\" is not a surface sampling (per_segment, at or tolerance)",
        )),
        other => Err(InputError::field(
            "sampling",
            format!("has an unknown key \"{other}\" (expected per_segment, at or tolerance)"),
        )),
    }
}

/// A surface object's fields into a checked [`Surface`].
pub(crate) fn build_surface(
    fields: &Map<String, Value>,
    keys: &[String],
) -> Result<Surface, InputError> {
    let kind = fields
        .get("kind")
        .ok_or_else(|| InputError::field("kind", "is missing"))?;
    let name = kind.as_str().ok_or_else(|| {
        InputError::field("kind", format!("must be a string, got {}", describe(kind)))
    })?;
    let Some(allowed) = surface_kind_fields(name) else {
        return Err(not_a_surface_kind(name));
    };
    if let Some(key) = keys.iter().find(|k| {
        !["kind", "points", "sampling"].contains(&k.as_str()) && !allowed.contains(&k.as_str())
    }) {
        return Err(not_a_surface_field(name, key));
    }
    let points = fields
        .get("points")
        .ok_or_else(|| InputError::field("points", "is missing"))?;
    let array = |field: &str| {
        fields
            .get(field)
            .map(|v| number_array(v, field))
            .transpose()
    };
    // The uniform families take one value per field, for both directions.
    let single = |field: &str| {
        fields
            .get(field)
            .map(|v| match v {
                Value::Array(_) => Err(InputError::field(
                    field,
                    format!(
                        "must be a number for a surface (one value for both directions), got {}",
                        describe(v)
                    ),
                )),
                _ => number(v, field),
            })
            .transpose()
    };
    let patches = fields.get("patches").map(parse_patches).transpose()?;
    // A patch list's points are a list; every other kind's a net.
    let net = if patches.is_some() {
        parse_list(points)?
    } else {
        parse_net(points)?
    };
    let surface_fields = SurfaceFields {
        ends: fields.get("ends").map(parse_surface_ends).transpose()?,
        tension: single("tension")?,
        bias: single("bias")?,
        matrix: fields.get("matrix").map(parse_matrix).transpose()?,
        patches,
        conditions: fields.get("conditions").map(parse_conditions).transpose()?,
        u: array("u")?,
        v: array("v")?,
        knots_u: array("knots_u")?,
        knots_v: array("knots_v")?,
        weights: fields
            .get("weights")
            .map(|w| parse_weights(w, net.shape()))
            .transpose()?,
    };
    Surface::new(SurfaceKind::named(name, surface_fields)?, net)
}

/// "ends": one name for both directions, or [ends_u, ends_v].
fn parse_surface_ends(v: &Value) -> Result<[Ends; 2], InputError> {
    match v {
        Value::Array(pair) if pair.len() == 2 => Ok([parse_ends(&pair[0])?, parse_ends(&pair[1])?]),
        Value::Array(_) => Err(InputError::field(
            "ends",
            format!("must be one name or [ends_u, ends_v], got {}", describe(v)),
        )),
        _ => parse_ends(v).map(|e| [e; 2]),
    }
}

/// "conditions": [c_u, c_v], each "natural", "not-a-knot" or "periodic".
fn parse_conditions(v: &Value) -> Result<[EndCondition; 2], InputError> {
    let wrong = || {
        InputError::field(
            "conditions",
            format!(
                "must be [c_u, c_v], each \"natural\", \"not-a-knot\" or \"periodic\", got {}",
                describe(v)
            ),
        )
    };
    let pair = v.as_array().filter(|p| p.len() == 2).ok_or_else(wrong)?;
    let one = |c: &Value| match c.as_str() {
        Some("natural") => Ok(EndCondition::Natural),
        Some("not-a-knot") => Ok(EndCondition::NotAKnot),
        Some("periodic") => Ok(EndCondition::Periodic),
        _ => Err(wrong()),
    };
    Ok([one(&pair[0])?, one(&pair[1])?])
}

/// "patches": arrays of 16 non-negative integer indices.
fn parse_patches(v: &Value) -> Result<Vec<[usize; 16]>, InputError> {
    let items = v.as_array().ok_or_else(|| {
        InputError::field(
            "patches",
            format!("must be an array of patches, got {}", describe(v)),
        )
    })?;
    items
        .iter()
        .enumerate()
        .map(|(p, item)| {
            let wrong = || {
                InputError::field(
                    "patches",
                    format!(
                        "must hold 16 integer indices each: patches[{p}] = {}",
                        describe(item)
                    ),
                )
            };
            let indices = item
                .as_array()
                .filter(|a| a.len() == 16)
                .ok_or_else(wrong)?;
            let mut out = [0; 16];
            for (k, index) in indices.iter().enumerate() {
                out[k] = index
                    .as_u64()
                    .and_then(|i| usize::try_from(i).ok())
                    .ok_or_else(wrong)?;
            }
            Ok(out)
        })
        .collect()
}

/// One point: an array of numbers, `at` naming it in messages.
fn parse_point(v: &Value, at: &str, coords: &mut Vec<f64>) -> Result<usize, InputError> {
    let items = v.as_array().ok_or_else(|| {
        InputError::field(
            "points",
            format!(
                "must hold points (arrays of numbers): points{at} = {}",
                describe(v)
            ),
        )
    })?;
    for (k, x) in items.iter().enumerate() {
        coords.push(x.as_f64().ok_or_else(|| {
            InputError::field(
                "points",
                format!("must be numbers: points{at}[{k}] = {}", describe(x)),
            )
        })?);
    }
    Ok(items.len())
}

/// Checks a point's dimension against the first's.
fn check_dim(len: usize, first: usize, at: &str) -> Result<(), InputError> {
    if len == 0 || len > MAX_DIM {
        return Err(InputError::field(
            "points",
            format!("must have 1 to {MAX_DIM} coordinates per point: points{at} has {len}"),
        ));
    }
    if len != first {
        return Err(InputError::field(
            "points",
            format!(
                "must all have the same dimension: points{at} has {len} coordinates, the first \
                 point has {first}"
            ),
        ));
    }
    Ok(())
}

/// "points" as a net: n_u rows of n_v points each.
fn parse_net(v: &Value) -> Result<Net, InputError> {
    let rows = v.as_array().filter(|r| !r.is_empty()).ok_or_else(|| {
        InputError::field(
            "points",
            format!(
                "must be a net: a non-empty array of rows of points, got {}",
                describe(v)
            ),
        )
    })?;
    let mut coords = Vec::new();
    let (mut dim, mut cols) = (0, 0);
    for (i, row) in rows.iter().enumerate() {
        let points = row.as_array().filter(|r| !r.is_empty()).ok_or_else(|| {
            InputError::field(
                "points",
                format!(
                    "must be a net: points[{i}] is not a non-empty row of points: {}",
                    describe(row)
                ),
            )
        })?;
        if i == 0 {
            cols = points.len();
        } else if points.len() != cols {
            return Err(InputError::field(
                "points",
                format!(
                    "must be a net (rows of equal length): points[{i}] has {} points, points[0] has {cols}",
                    points.len()
                ),
            ));
        }
        for (j, p) in points.iter().enumerate() {
            let at = format!("[{i}][{j}]");
            let len = parse_point(p, &at, &mut coords)?;
            if i == 0 && j == 0 {
                dim = len;
            }
            check_dim(len, dim, &at)?;
        }
    }
    Net::new(dim, rows.len(), cols, coords)
}

/// "points" of a patch list: a flat array of points, as a net of one column.
fn parse_list(v: &Value) -> Result<Net, InputError> {
    let points = v.as_array().filter(|r| !r.is_empty()).ok_or_else(|| {
        InputError::field(
            "points",
            format!(
                "must be a non-empty array of control points for \"patches\", got {}",
                describe(v)
            ),
        )
    })?;
    let mut coords = Vec::new();
    let mut dim = 0;
    for (i, p) in points.iter().enumerate() {
        let at = format!("[{i}]");
        let len = parse_point(p, &at, &mut coords)?;
        if i == 0 {
            dim = len;
        }
        check_dim(len, dim, &at)?;
    }
    Net::new(dim, points.len(), 1, coords)
}

/// "weights": a net of numbers of the points' `shape` (n_u rows of n_v), flattened; their values
/// are the surface's to check.
fn parse_weights(v: &Value, shape: (usize, usize)) -> Result<Vec<f64>, InputError> {
    let rows = v.as_array().ok_or_else(|| {
        InputError::field(
            "weights",
            format!("must be a net of numbers, got {}", describe(v)),
        )
    })?;
    let mut out = Vec::new();
    let mut cols = None;
    for (i, row) in rows.iter().enumerate() {
        let row = number_array(row, "weights").map_err(|_| {
            InputError::field(
                "weights",
                format!("must be a net of numbers: weights[{i}] = {}", describe(row)),
            )
        })?;
        match cols {
            Some(c) if c != row.len() => {
                return Err(InputError::field(
                    "weights",
                    format!(
                        "must be a net (rows of equal length): weights[{i}] has {} numbers, weights[0] has {c}",
                        row.len()
                    ),
                ));
            }
            _ => cols = Some(row.len()),
        }
        out.extend(row);
    }
    if (rows.len(), cols.unwrap_or(0)) != shape {
        return Err(InputError::field(
            "weights",
            format!(
                "must be a net of the points' shape, {} x {}, got {} x {}",
                shape.0,
                shape.1,
                rows.len(),
                cols.unwrap_or(0)
            ),
        ));
    }
    Ok(out)
}
