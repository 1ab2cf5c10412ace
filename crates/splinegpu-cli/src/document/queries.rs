//! A query document (contract: "Queries: closest points, intersections and rays"): curves or
//! surfaces as they are (no "sampling", "derivatives", "normals" or "geometry", a curve's or
//! surface's own included) and "queries" with exactly one key, every query checked against
//! the document's D before anything is answered.

use std::fmt;

use serde::Deserialize;
use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::Value;

use splinegpu::surface::PatchTable;
use splinegpu::{InputError, SegmentTable};

use crate::document::surfaces::build_surface;
use crate::document::values::{abbreviate, describe};
use crate::document::walk::ParsedDocument;

/// The most queries one document may hold (the outputs number them in 32 bits on the GPU).
pub const MAX_QUERIES: usize = u32::MAX as usize;

/// A query document: what is asked, of which curves or surfaces.
#[derive(Debug)]
pub struct QueryDocument {
    /// The fitted curves or surfaces.
    pub target: QueryTarget,
    /// What is asked of them.
    pub queries: Queries,
}

/// The document's curves or surfaces, fitted.
#[derive(Debug)]
pub enum QueryTarget {
    /// Curves of one dimension D.
    Curves(Vec<SegmentTable>),
    /// Surfaces of one dimension D.
    Surfaces(Vec<PatchTable>),
}

/// The one key of "queries", its values checked.
#[derive(Debug, PartialEq)]
pub enum Queries {
    /// Points of D coordinates each, flat.
    Closest(Vec<f64>),
    /// Pairs of curve indices (i, j); `None` for "all" (every i < j).
    Intersections(Option<Vec<[usize; 2]>>),
    /// Rays as (ox, oy, oz, dx, dy, dz), flat.
    Rays(Vec<f64>),
}

impl Queries {
    /// The key's name, for messages.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Queries::Closest(_) => "closest",
            Queries::Intersections(_) => "intersections",
            Queries::Rays(_) => "rays",
        }
    }
}

/// One entry of "queries" as read: a point list ("closest", "rays") or any other value.
#[derive(Debug)]
pub(crate) enum QueryEntry {
    Points(PointList),
    Value(Value),
}

/// A "closest" or "rays" list read without a tree of JSON values (which would take about
/// 100 bytes a number): its numbers in one flat array, each row's length, and what was wrong
/// first, kept for the message once the document's D is known.
#[derive(Debug, Default)]
pub(crate) struct PointList {
    values: Vec<f64>,
    lengths: Vec<u32>,
    /// The first row that is not an array of numbers: its index and its value.
    first_bad: Option<(usize, Value)>,
    /// The whole value, where it is not an array.
    not_a_list: Option<Value>,
    /// Whether its numbers would not fit in memory (or are more than 2^32 - 1 rows).
    too_large: bool,
}

impl PointList {
    /// Room for one more number, or false (and `too_large`) where memory has none.
    fn room(&mut self) -> bool {
        if self.values.len() == self.values.capacity()
            && self.values.try_reserve(self.values.len().max(64)).is_err()
        {
            self.too_large = true;
        }
        !self.too_large
    }
}

/// Reads a point list (see [`PointList`]).
pub(crate) struct PointListSeed;

impl<'de> DeserializeSeed<'de> for PointListSeed {
    type Value = PointList;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<PointList, D::Error> {
        d.deserialize_any(PointListVisitor)
    }
}

struct PointListVisitor;

impl PointListVisitor {
    fn not_a_list<E>(got: Value) -> Result<PointList, E> {
        Ok(PointList {
            not_a_list: Some(got),
            ..PointList::default()
        })
    }
}

impl<'de> Visitor<'de> for PointListVisitor {
    type Value = PointList;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of points")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<PointList, A::Error> {
        let mut list = PointList::default();
        loop {
            if list.too_large || list.lengths.len() >= MAX_QUERIES {
                list.too_large = true;
                while seq.next_element::<IgnoredAny>()?.is_some() {}
                return Ok(list);
            }
            let index = list.lengths.len();
            let Some(row) = seq.next_element_seed(RowSeed(&mut list))? else {
                return Ok(list);
            };
            match row {
                Ok(count) => list.lengths.push(count),
                Err(bad) => {
                    list.first_bad.get_or_insert((index, bad));
                    list.lengths.push(u32::MAX);
                }
            }
        }
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<PointList, A::Error> {
        Self::not_a_list(Value::deserialize(de::value::MapAccessDeserializer::new(
            map,
        ))?)
    }
    fn visit_bool<E: de::Error>(self, v: bool) -> Result<PointList, E> {
        Self::not_a_list(Value::from(v))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<PointList, E> {
        Self::not_a_list(Value::from(v))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<PointList, E> {
        Self::not_a_list(Value::from(v))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<PointList, E> {
        Self::not_a_list(Value::from(v))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<PointList, E> {
        Self::not_a_list(Value::from(v))
    }
    fn visit_unit<E: de::Error>(self) -> Result<PointList, E> {
        Self::not_a_list(Value::Null)
    }
}

/// One row of a point list: its numbers pushed onto the list, their count; or the row as a
/// value where it is not an array of numbers (the numbers it pushed taken back).
struct RowSeed<'a>(&'a mut PointList);

impl<'de> DeserializeSeed<'de> for RowSeed<'_> {
    type Value = Result<u32, Value>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        let start = self.0.values.len();
        let row = Value::deserialize(d)?;
        let numbers = row.as_array().and_then(|items| {
            items
                .iter()
                .map(Value::as_f64)
                .collect::<Option<Vec<f64>>>()
        });
        match numbers {
            Some(numbers) if numbers.len() < u32::MAX as usize => {
                for x in &numbers {
                    if !self.0.room() {
                        self.0.values.truncate(start);
                        return Ok(Ok(0));
                    }
                    self.0.values.push(*x);
                }
                Ok(Ok(numbers.len() as u32))
            }
            _ => Ok(Err(row)),
        }
    }
}

/// The query document of a parsed document with "queries".
pub(crate) fn query_document(
    parsed: ParsedDocument,
    entries: &[(String, QueryEntry)],
) -> Result<QueryDocument, InputError> {
    let document = |e: InputError| e.in_document();
    let forbidden = [
        ("sampling", parsed.sampling.is_some()),
        ("derivatives", parsed.derivatives_given),
        ("normals", parsed.normals.is_some()),
        ("geometry", parsed.geometry.is_some()),
    ];
    if let Some((key, _)) = forbidden.iter().find(|(_, given)| *given) {
        return Err(not_in_queries(key).in_document());
    }
    let target = match (parsed.curves, parsed.surfaces) {
        (Some(_), Some(_)) => {
            return Err(InputError::field(
                "surfaces",
                "cannot stand beside \"curves\": a document holds curves or surfaces",
            )
            .in_document());
        }
        (None, None) => {
            return Err(InputError::field("curves", "is missing (or \"surfaces\")").in_document());
        }
        (Some(curves), None) => {
            let mut tables = Vec::with_capacity(curves.len());
            for (i, curve) in curves.into_iter().enumerate() {
                let own = [
                    ("sampling", curve.sampling.is_some()),
                    ("geometry", curve.geometry.is_some()),
                ];
                if let Some((key, _)) = own.iter().find(|(_, given)| *given) {
                    return Err(not_in_queries(key).in_curve(i));
                }
                tables.push(curve.table);
            }
            QueryTarget::Curves(tables)
        }
        (None, Some(surfaces)) => {
            let mut tables = Vec::with_capacity(surfaces.len());
            for (i, read) in surfaces.into_iter().enumerate() {
                if read.sampling.is_some() {
                    return Err(not_in_queries("sampling").in_surface(i));
                }
                let surface =
                    build_surface(&read.fields, &read.keys).map_err(|e| e.in_surface(i))?;
                tables.push(surface.fit());
            }
            QueryTarget::Surfaces(tables)
        }
    };
    let dim = check_dimensions(&target)?;
    let [(key, value)] = entries else {
        return Err(document(InputError::field(
            "queries",
            format!(
                "must have exactly one key (closest, intersections or rays), got {}",
                entries.len()
            ),
        )));
    };
    let queries = match key.as_str() {
        "closest" => Queries::Closest(point_list(
            points_of(value),
            "closest",
            dim,
            "the document's D",
        )?),
        "intersections" => {
            let curves = match &target {
                QueryTarget::Curves(tables) if dim == 2 => tables.len(),
                QueryTarget::Curves(_) => {
                    return Err(document(InputError::field(
                        "intersections",
                        format!("are found between 2-D curves, and these have D = {dim}"),
                    )));
                }
                QueryTarget::Surfaces(_) => {
                    return Err(document(InputError::field(
                        "intersections",
                        "are found between curves, and this document holds surfaces",
                    )));
                }
            };
            let QueryEntry::Value(value) = value else {
                unreachable!("only closest and rays are read as point lists")
            };
            Queries::Intersections(pairs(value, curves)?)
        }
        "rays" => {
            match &target {
                QueryTarget::Surfaces(_) if dim == 3 => {}
                QueryTarget::Surfaces(_) => {
                    return Err(document(InputError::field(
                        "rays",
                        format!("meet 3-D surfaces, and these have D = {dim}"),
                    )));
                }
                QueryTarget::Curves(_) => {
                    return Err(document(InputError::field(
                        "rays",
                        "meet surfaces, and this document holds curves",
                    )));
                }
            }
            let rays = point_list(points_of(value), "rays", 6, "ox, oy, oz, dx, dy, dz")?;
            for (i, ray) in rays.chunks_exact(6).enumerate() {
                if ray[3..].iter().all(|&d| d == 0.0) {
                    return Err(document(InputError::field(
                        format!("rays[{i}]"),
                        "has a zero direction (dx, dy, dz)",
                    )));
                }
            }
            Queries::Rays(rays)
        }
        other => {
            return Err(document(InputError::field(
                other,
                "is not a query (allowed: closest, intersections, rays)",
            )));
        }
    };
    Ok(QueryDocument { target, queries })
}

/// The error for a tessellation key in a query document.
fn not_in_queries(key: &str) -> InputError {
    InputError::field(
        key,
        "is not a field of a query document (queries take the curves and surfaces as they are)",
    )
}

/// The dimension D every curve (surface) shares, or the first that differs.
fn check_dimensions(target: &QueryTarget) -> Result<usize, InputError> {
    let dims: Vec<usize> = match target {
        QueryTarget::Curves(tables) => tables.iter().map(SegmentTable::dim).collect(),
        QueryTarget::Surfaces(tables) => tables.iter().map(PatchTable::dim).collect(),
    };
    let Some(&dim) = dims.first() else {
        let key = match target {
            QueryTarget::Curves(_) => "curves",
            QueryTarget::Surfaces(_) => "surfaces",
        };
        return Err(InputError::field(key, "must not be empty").in_document());
    };
    match dims.iter().position(|&d| d != dim) {
        None => Ok(dim),
        Some(i) => {
            let e = InputError::field(
                "points",
                format!(
                    "must have {dim} coordinates like the first's (queries need one D), got {}",
                    dims[i]
                ),
            );
            Err(match target {
                QueryTarget::Curves(_) => e.in_curve(i),
                QueryTarget::Surfaces(_) => e.in_surface(i),
            })
        }
    }
}

/// The point list of "closest" or "rays", which are read as such.
fn points_of(entry: &QueryEntry) -> &PointList {
    match entry {
        QueryEntry::Points(list) => list,
        QueryEntry::Value(_) => unreachable!("closest and rays are read as point lists"),
    }
}

/// A point list's numbers, each row `width` of them (`what` says what they are), or the first
/// thing wrong with it, named by its key and row.
fn point_list(
    list: &PointList,
    key: &str,
    width: usize,
    what: &str,
) -> Result<Vec<f64>, InputError> {
    if let Some(value) = &list.not_a_list {
        return Err(InputError::field(
            key,
            format!(
                "must be an array of arrays of numbers, got {}",
                describe(value)
            ),
        )
        .in_document());
    }
    if list.too_large {
        return Err(InputError::field(
            key,
            format!(
                "holds more queries than this process can hold (or more than 2^32 - 1): {} read",
                list.lengths.len()
            ),
        )
        .in_document());
    }
    let wrong = |i: usize, got: String| {
        InputError::field(
            format!("{key}[{i}]"),
            format!("must be {width} numbers ({what}), got {got}"),
        )
        .in_document()
    };
    let first_length = list.lengths.iter().position(|&n| n as usize != width);
    match (first_length, &list.first_bad) {
        (Some(i), Some((bad, value))) if *bad <= i => Err(wrong(*bad, describe(value))),
        (Some(i), _) => {
            // The row's numbers, written as JSON would (1 for 1.0).
            let start: usize = list.lengths[..i].iter().map(|&n| n as usize).sum();
            let row: Vec<String> = list.values[start..start + list.lengths[i] as usize]
                .iter()
                .map(f64::to_string)
                .collect();
            Err(wrong(i, abbreviate(format!("[{}]", row.join(",")))))
        }
        _ => Ok(list.values.clone()),
    }
}

/// "all", or an array of [i, j] pairs of curve indices below `curves`.
fn pairs(value: &Value, curves: usize) -> Result<Option<Vec<[usize; 2]>>, InputError> {
    if value.as_str() == Some("all") {
        return Ok(None);
    }
    let items = value.as_array().ok_or_else(|| {
        InputError::field(
            "intersections",
            format!(
                "must be \"all\" or an array of [i, j] pairs, got {}",
                describe(value)
            ),
        )
        .in_document()
    })?;
    if items.len() > MAX_QUERIES {
        return Err(InputError::field(
            "intersections",
            format!("holds {} pairs, more than 2^32 - 1", items.len()),
        )
        .in_document());
    }
    let mut out = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let field = format!("intersections[{i}]");
        let pair = item
            .as_array()
            .filter(|p| p.len() == 2)
            .and_then(|p| Some([p[0].as_u64()?, p[1].as_u64()?]))
            .ok_or_else(|| {
                InputError::field(
                    &field,
                    format!(
                        "must be a pair of curve indices [i, j], got {}",
                        describe(item)
                    ),
                )
                .in_document()
            })?;
        if let Some(&bad) = pair.iter().find(|&&c| c >= curves as u64) {
            return Err(InputError::field(
                &field,
                format!("names curve {bad}, and the document has {curves} curves"),
            )
            .in_document());
        }
        out.push([pair[0] as usize, pair[1] as usize]);
    }
    Ok(Some(out))
}
