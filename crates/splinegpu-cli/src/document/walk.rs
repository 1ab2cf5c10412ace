//! The document's JSON walked with serde visitors (see the module docs of `document`): every
//! object's keys one by one (a key given twice is an error), each curve fitted as it is read,
//! located errors reported through a side channel ([`Located`]) because serde's error type
//! carries only text.

use std::cell::RefCell;
use std::fmt;
use std::sync::mpsc;

use serde::Deserialize;
use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::{Map, Value};

use splinegpu::{Derivatives, InputError, Location, MAX_DIM, Points};

use crate::document::curves::{ParsedCurve, ReadCurve, fit_curve, sampling_spec};
use crate::document::queries::{PointListSeed, QueryEntry};
use crate::document::surfaces::ReadSurface;
use crate::document::values::describe;

/// The document's top-level keys.
pub(crate) const DOCUMENT_KEYS: [&str; 7] = [
    "sampling",
    "derivatives",
    "curves",
    "surfaces",
    "normals",
    "geometry",
    "queries",
];

/// The document `de` reads, walked whole (its end checked), or its first located error (a
/// syntax error where none was located).
pub(crate) fn parse<'de, R: serde_json::de::Read<'de>>(
    de: &mut serde_json::Deserializer<R>,
) -> Result<ParsedDocument, InputError> {
    let located = Located::default();
    let parsed = DocumentSeed(&located)
        .deserialize(&mut *de)
        .and_then(|doc| de.end().map(|()| doc));
    match parsed {
        Ok(doc) => Ok(doc),
        Err(e) => Err(located.0.into_inner().unwrap_or_else(|| syntax(&e))),
    }
}

/// A JSON syntax error, with its line and column; or a read error, which is no fault of the
/// JSON's (and has no place when nothing was read).
pub(crate) fn syntax(e: &serde_json::Error) -> InputError {
    let message = e.to_string();
    // serde_json appends " at line L column C"; the message gives those itself.
    let message = message
        .rfind(" at line ")
        .map_or(message.as_str(), |i| &message[..i]);
    let (line, column) = (e.line(), e.column());
    InputError::document(match (e.is_io(), line) {
        (true, 0) => format!("cannot read the input: {message}"),
        (true, _) => format!("cannot read the input after line {line}, column {column}: {message}"),
        (false, _) => format!("invalid JSON at line {line}, column {column}: {message}"),
    })
}

/// The first located error a visitor found; the visitor then aborts the parse with an empty
/// serde error.
#[derive(Default)]
pub(crate) struct Located(RefCell<Option<InputError>>);

impl Located {
    /// Records `error`, placed at `place`, and returns the error that stops the parse.
    fn fail<T, E: de::Error>(&self, place: &Location, error: InputError) -> Result<T, E> {
        let error = match place {
            Location::Curve(i) => error.in_curve(*i),
            Location::Surface(i) => error.in_surface(*i),
            _ => error.in_document(),
        };
        self.0.borrow_mut().get_or_insert(error);
        Err(E::custom("located input error"))
    }

    /// [`Located::fail`] for an error that comes before any recorded so far.
    fn fail_first<T, E: de::Error>(&self, place: &Location, error: InputError) -> Result<T, E> {
        self.0.borrow_mut().take();
        self.fail(place, error)
    }
}

/// What the document's visitor gathers; curves are already fitted.
pub(crate) struct ParsedDocument {
    /// The document's "sampling" entries, read as curves or surfaces take them.
    pub(crate) sampling: Option<Vec<(String, Value)>>,
    pub(crate) derivatives: Derivatives,
    /// Whether the document named "derivatives" (a query document may not).
    pub(crate) derivatives_given: bool,
    pub(crate) curves: Option<Vec<ParsedCurve>>,
    pub(crate) surfaces: Option<Vec<ReadSurface>>,
    pub(crate) normals: Option<bool>,
    /// The document's "geometry", read by the geometry job (a surfaces document refuses it).
    pub(crate) geometry: Option<Value>,
    /// The document's "queries" entries (`splinegpu query`), read by `document::queries`.
    pub(crate) queries: Option<Vec<(String, QueryEntry)>>,
}

/// Methods for the JSON types a visitor does not expect: each reports the value it got.
macro_rules! reject_scalars {
    () => {
        fn visit_bool<E: de::Error>(self, v: bool) -> Result<Self::Value, E> {
            self.wrong(&Value::from(v))
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
            self.wrong(&Value::from(v))
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
            self.wrong(&Value::from(v))
        }
        fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
            self.wrong(&Value::from(v))
        }
        fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
            self.wrong(&Value::from(v))
        }
        fn visit_unit<E: de::Error>(self) -> Result<Self::Value, E> {
            self.wrong(&Value::Null)
        }
    };
}

/// A visitor that expects an object, rejecting arrays with the value it got.
macro_rules! reject_seq {
    () => {
        fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
            let got = Value::deserialize(SeqAccessDeserializer::new(seq))?;
            self.wrong(&got)
        }
    };
}

/// A visitor that expects an array, rejecting objects with the value it got.
macro_rules! reject_map {
    () => {
        fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
            let got = Value::deserialize(MapAccessDeserializer::new(map))?;
            self.wrong(&got)
        }
    };
}

/// Reads an object's next key, refusing one it has seen already.
fn next_key<'de, A: MapAccess<'de>>(
    map: &mut A,
    seen: &mut Vec<String>,
    located: &Located,
    place: &Location,
) -> Result<Option<String>, A::Error> {
    let Some(key) = map.next_key::<String>()? else {
        return Ok(None);
    };
    if seen.contains(&key) {
        let error = InputError::field(key, "appears twice in one object");
        return located.fail(place, error);
    }
    seen.push(key.clone());
    Ok(Some(key))
}

/// The document: an object with "sampling", "derivatives" and "curves".
struct DocumentSeed<'a>(&'a Located);

impl<'de> DeserializeSeed<'de> for DocumentSeed<'_> {
    type Value = ParsedDocument;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<ParsedDocument, D::Error> {
        d.deserialize_any(self)
    }
}

impl DocumentSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<ParsedDocument, E> {
        let error = InputError::document(format!("must be a JSON object, got {}", describe(got)));
        self.0.fail(&Location::Document, error)
    }
}

impl<'de> Visitor<'de> for DocumentSeed<'_> {
    type Value = ParsedDocument;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<ParsedDocument, A::Error> {
        let (located, place) = (self.0, Location::Document);
        let mut doc = ParsedDocument {
            sampling: None,
            derivatives: Derivatives::None,
            curves: None,
            surfaces: None,
            normals: None,
            geometry: None,
            derivatives_given: false,
            queries: None,
        };
        let mut seen = Vec::new();
        while let Some(key) = next_key(&mut map, &mut seen, located, &place)? {
            match key.as_str() {
                "sampling" => {
                    doc.sampling = Some(map.next_value_seed(ObjectSeed(
                        located,
                        place.clone(),
                        "sampling",
                    ))?);
                }
                "derivatives" => {
                    doc.derivatives_given = true;
                    let v: Value = map.next_value()?;
                    doc.derivatives = match v.as_u64().and_then(Derivatives::from_order) {
                        Some(d) => d,
                        None => {
                            let message = format!("must be 0, 1 or 2, got {}", describe(&v));
                            return located.fail(&place, InputError::field("derivatives", message));
                        }
                    };
                }
                "curves" => doc.curves = Some(map.next_value_seed(CurvesSeed(located))?),
                "geometry" => doc.geometry = Some(map.next_value()?),
                "queries" => doc.queries = Some(map.next_value_seed(QueriesSeed(located))?),
                "surfaces" => doc.surfaces = Some(map.next_value_seed(SurfacesSeed(located))?),
                "normals" => {
                    let v: Value = map.next_value()?;
                    doc.normals = match v.as_bool() {
                        Some(b) => Some(b),
                        None => {
                            let message = format!("must be true or false, got {}", describe(&v));
                            return located.fail(&place, InputError::field("normals", message));
                        }
                    };
                }
                other => {
                    let message = format!(
                        "is not a field of the document (allowed: {})",
                        DOCUMENT_KEYS.join(", ")
                    );
                    return located.fail(&place, InputError::field(other, message));
                }
            }
        }
        Ok(doc)
    }

    reject_scalars!();
    reject_seq!();
}

/// "curves": an array of curve objects, each fitted as soon as it is read.
struct CurvesSeed<'a>(&'a Located);

impl<'de> DeserializeSeed<'de> for CurvesSeed<'_> {
    type Value = Vec<ParsedCurve>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Vec<ParsedCurve>, D::Error> {
        d.deserialize_any(self)
    }
}

impl CurvesSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<Vec<ParsedCurve>, E> {
        let message = format!("must be an array of curves, got {}", describe(got));
        self.0
            .fail(&Location::Document, InputError::field("curves", message))
    }
}

impl<'de> Visitor<'de> for CurvesSeed<'_> {
    type Value = Vec<ParsedCurve>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of curves")
    }

    /// Curves are read here and fitted on a second thread, [`FIT_BATCH`] at a time, at most two
    /// batches behind the reader. A curve's fitting error is reported as if the parse had
    /// stopped at it: before any error in the curves read after it, syntax errors included.
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<ParsedCurve>, A::Error> {
        let located = self.0;
        std::thread::scope(|scope| {
            let (to_fitter, read_curves) = mpsc::sync_channel::<Vec<ReadCurve>>(2);
            let fitter = scope.spawn(move || {
                let mut fitted = Vec::new();
                for batch in read_curves {
                    for curve in batch {
                        let i = fitted.len();
                        match fit_curve(&curve.fields, &curve.keys, curve.points) {
                            Ok(fit) => fitted.push(ParsedCurve {
                                curve: fit.curve,
                                table: fit.table,
                                sampling: curve.sampling,
                                geometry: fit.geometry,
                            }),
                            // Dropping the receiver tells the reader to stop.
                            Err(e) => return Err((i, e)),
                        }
                    }
                }
                Ok(fitted)
            });
            let mut read = 0;
            let mut batch = Vec::with_capacity(FIT_BATCH);
            let parsed = loop {
                match seq.next_element_seed(CurveSeed(located, read)) {
                    Ok(Some(curve)) => {
                        batch.push(curve);
                        read += 1;
                        if batch.len() == FIT_BATCH {
                            let full = std::mem::replace(&mut batch, Vec::with_capacity(FIT_BATCH));
                            if to_fitter.send(full).is_err() {
                                break Ok(());
                            }
                        }
                    }
                    Ok(None) => break Ok(()),
                    Err(e) => break Err(e),
                }
            };
            // The curves read whole before the end (or an error) are fitted too: one of them
            // may fail first. A fitter that has stopped already has its error.
            if !batch.is_empty() {
                let _ = to_fitter.send(batch);
            }
            drop(to_fitter);
            let fitted = fitter.join().expect("the fitting thread panicked");
            match fitted {
                // Fitted curves were read whole, before anything the reader failed on.
                Err((i, e)) => located.fail_first(&Location::Curve(i), e),
                Ok(curves) => parsed.map(|()| curves),
            }
        })
    }

    reject_scalars!();
    reject_map!();
}

/// Curves handed to the fitting thread at a time: one message per curve cost w1's document
/// more than the fitting it moved, one per 64 curves saves it (docs/benchmarks.md).
pub(crate) const FIT_BATCH: usize = 64;

/// "surfaces": an array of surface objects, read whole (a surface's net is its size) and
/// checked, fitted and planned once the document is read.
struct SurfacesSeed<'a>(&'a Located);

impl<'de> DeserializeSeed<'de> for SurfacesSeed<'_> {
    type Value = Vec<ReadSurface>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Vec<ReadSurface>, D::Error> {
        d.deserialize_any(self)
    }
}

impl SurfacesSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<Vec<ReadSurface>, E> {
        let message = format!("must be an array of surfaces, got {}", describe(got));
        self.0
            .fail(&Location::Document, InputError::field("surfaces", message))
    }
}

impl<'de> Visitor<'de> for SurfacesSeed<'_> {
    type Value = Vec<ReadSurface>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of surfaces")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<ReadSurface>, A::Error> {
        let mut surfaces = Vec::new();
        while let Some(surface) = seq.next_element_seed(SurfaceSeed(self.0, surfaces.len()))? {
            surfaces.push(surface);
        }
        Ok(surfaces)
    }

    reject_scalars!();
    reject_map!();
}

/// One surface object: its keys checked for duplicates, its "sampling" read as entries.
struct SurfaceSeed<'a>(&'a Located, usize);

impl<'de> DeserializeSeed<'de> for SurfaceSeed<'_> {
    type Value = ReadSurface;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<ReadSurface, D::Error> {
        d.deserialize_any(self)
    }
}

impl SurfaceSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<ReadSurface, E> {
        let error = InputError::document(format!("must be a JSON object, got {}", describe(got)));
        self.0.fail(&Location::Surface(self.1), error)
    }
}

impl<'de> Visitor<'de> for SurfaceSeed<'_> {
    type Value = ReadSurface;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a surface object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<ReadSurface, A::Error> {
        let (located, place) = (self.0, Location::Surface(self.1));
        let mut fields = Map::new();
        let mut sampling = None;
        let mut seen = Vec::new();
        while let Some(key) = next_key(&mut map, &mut seen, located, &place)? {
            if key == "sampling" {
                sampling =
                    Some(map.next_value_seed(ObjectSeed(located, place.clone(), "sampling"))?);
            } else {
                fields.insert(key, map.next_value()?);
            }
        }
        Ok(ReadSurface {
            fields,
            keys: seen,
            sampling,
        })
    }

    reject_scalars!();
    reject_seq!();
}

/// One curve object: its fields are gathered for [`fit_curve`].
struct CurveSeed<'a>(&'a Located, usize);

impl<'de> DeserializeSeed<'de> for CurveSeed<'_> {
    type Value = ReadCurve;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<ReadCurve, D::Error> {
        d.deserialize_any(self)
    }
}

impl CurveSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<ReadCurve, E> {
        let error = InputError::document(format!("must be a JSON object, got {}", describe(got)));
        self.0.fail(&Location::Curve(self.1), error)
    }
}

impl<'de> Visitor<'de> for CurveSeed<'_> {
    type Value = ReadCurve;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a curve object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<ReadCurve, A::Error> {
        let (located, place) = (self.0, Location::Curve(self.1));
        let mut fields = Map::new();
        let (mut points, mut sampling) = (None, None);
        let mut seen = Vec::new();
        while let Some(key) = next_key(&mut map, &mut seen, located, &place)? {
            match key.as_str() {
                "points" => points = Some(map.next_value_seed(PointsSeed(located, self.1))?),
                "sampling" => {
                    let entries =
                        map.next_value_seed(ObjectSeed(located, place.clone(), "sampling"))?;
                    sampling = Some(sampling_spec(&entries).or_else(|e| located.fail(&place, e))?);
                }
                _ => {
                    fields.insert(key, map.next_value()?);
                }
            }
        }
        Ok(ReadCurve {
            fields,
            keys: seen,
            points,
            sampling,
        })
    }

    reject_scalars!();
    reject_seq!();
}

/// "points": an array of arrays of D numbers, read straight into flat coordinates.
struct PointsSeed<'a>(&'a Located, usize);

impl<'de> DeserializeSeed<'de> for PointsSeed<'_> {
    type Value = Points;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Points, D::Error> {
        d.deserialize_any(self)
    }
}

impl PointsSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<Points, E> {
        let message = format!("must be an array of points, got {}", describe(got));
        self.fail(message)
    }

    fn fail<T, E: de::Error>(&self, message: String) -> Result<T, E> {
        self.0.fail(
            &Location::Curve(self.1),
            InputError::field("points", message),
        )
    }
}

impl<'de> Visitor<'de> for PointsSeed<'_> {
    type Value = Points;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of points")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Points, A::Error> {
        let (mut coords, mut dim) = (Vec::new(), 0);
        let mut i = 0;
        while let Some(point) = seq.next_element_seed(PointSeed(&mut coords))? {
            let (len, not_number) = match point {
                PointRead::Array { len, not_number } => (len, not_number),
                PointRead::Other(got) => {
                    return self.fail(format!(
                        "must be arrays of numbers: points[{i}] = {}",
                        describe(&got)
                    ));
                }
            };
            if i == 0 {
                dim = len;
                if dim == 0 || dim > MAX_DIM {
                    return self.fail(format!(
                        "must have 1 to {MAX_DIM} coordinates per point: points[0] has {dim}"
                    ));
                }
            } else if len != dim {
                return self.fail(format!(
                    "must all have the same dimension: points[{i}] has {len} coordinates, \
                     points[0] has {dim}"
                ));
            }
            if let Some((k, v)) = not_number {
                return self.fail(format!(
                    "must be numbers: points[{i}][{k}] = {}",
                    describe(&v)
                ));
            }
            i += 1;
        }
        if i == 0 {
            return self.fail("must not be empty".to_string());
        }
        Points::new(dim, coords).or_else(|e| self.0.fail(&Location::Curve(self.1), e))
    }

    reject_scalars!();
    reject_map!();
}

/// One point of "points", its numbers appended to the curve's coordinates as they are read:
/// no value is built per point (which cost w1's document a tenth of its parsing).
struct PointSeed<'c>(&'c mut Vec<f64>);

/// A point as [`PointSeed`] read it.
enum PointRead {
    /// An array of `len` elements, with its first element that is not a number, if any (its
    /// index and value, for the message).
    Array {
        len: usize,
        not_number: Option<(usize, Value)>,
    },
    /// Not an array.
    Other(Value),
}

impl<'de> DeserializeSeed<'de> for PointSeed<'_> {
    type Value = PointRead;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<PointRead, D::Error> {
        d.deserialize_any(self)
    }
}

impl PointSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<PointRead, E> {
        Ok(PointRead::Other(got.clone()))
    }
}

impl<'de> Visitor<'de> for PointSeed<'_> {
    type Value = PointRead;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of numbers")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<PointRead, A::Error> {
        let (mut len, mut not_number) = (0, None);
        while let Some(element) = seq.next_element::<Coordinate>()? {
            match element {
                Coordinate::Number(x) => self.0.push(x),
                Coordinate::Other(v) => {
                    not_number.get_or_insert((len, v));
                }
            }
            len += 1;
        }
        Ok(PointRead::Array { len, not_number })
    }

    reject_scalars!();
    reject_map!();
}

/// An element of a point: a number, or what stood there instead.
enum Coordinate {
    Number(f64),
    Other(Value),
}

impl<'de> Deserialize<'de> for Coordinate {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(CoordinateVisitor)
    }
}

struct CoordinateVisitor;

impl CoordinateVisitor {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<Coordinate, E> {
        Ok(Coordinate::Other(got.clone()))
    }
}

impl<'de> Visitor<'de> for CoordinateVisitor {
    type Value = Coordinate;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a number")
    }

    // Numbers as serde_json's Value::as_f64 gives them.
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Coordinate, E> {
        Ok(Coordinate::Number(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Coordinate, E> {
        Ok(Coordinate::Number(v as f64))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Coordinate, E> {
        Ok(Coordinate::Number(v))
    }
    fn visit_bool<E: de::Error>(self, v: bool) -> Result<Coordinate, E> {
        self.wrong(&Value::from(v))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Coordinate, E> {
        self.wrong(&Value::from(v))
    }
    fn visit_unit<E: de::Error>(self) -> Result<Coordinate, E> {
        self.wrong(&Value::Null)
    }

    reject_seq!();
    reject_map!();
}

/// "queries": its entries, keys checked for duplicates; the point lists of "closest" and "rays"
/// read as numbers into one flat array ([`PointListSeed`]), not as a tree of JSON values.
struct QueriesSeed<'a>(&'a Located);

impl<'de> DeserializeSeed<'de> for QueriesSeed<'_> {
    type Value = Vec<(String, QueryEntry)>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl QueriesSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<Vec<(String, QueryEntry)>, E> {
        let message = format!("must be an object, got {}", describe(got));
        self.0
            .fail(&Location::Document, InputError::field("queries", message))
    }
}

impl<'de> Visitor<'de> for QueriesSeed<'_> {
    type Value = Vec<(String, QueryEntry)>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a queries object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut entries = Vec::new();
        let mut seen = Vec::new();
        while let Some(key) = next_key(&mut map, &mut seen, self.0, &Location::Document)? {
            let entry = if key == "closest" || key == "rays" {
                QueryEntry::Points(map.next_value_seed(PointListSeed)?)
            } else {
                QueryEntry::Value(map.next_value()?)
            };
            entries.push((key, entry));
        }
        Ok(entries)
    }

    reject_scalars!();
    reject_seq!();
}

/// An object's entries, keys checked for duplicates ("sampling", whose meaning
/// [`sampling_spec`] checks); the third field is its key, for errors.
struct ObjectSeed<'a>(&'a Located, Location, &'static str);

impl<'de> DeserializeSeed<'de> for ObjectSeed<'_> {
    type Value = Vec<(String, Value)>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl ObjectSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<Vec<(String, Value)>, E> {
        let message = format!("must be an object, got {}", describe(got));
        self.0.fail(&self.1, InputError::field(self.2, message))
    }
}

impl<'de> Visitor<'de> for ObjectSeed<'_> {
    type Value = Vec<(String, Value)>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a {} object", self.2)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut entries = Vec::new();
        let mut seen = Vec::new();
        while let Some(key) = next_key(&mut map, &mut seen, self.0, &self.1)? {
            entries.push((key, map.next_value()?));
        }
        Ok(entries)
    }

    reject_scalars!();
    reject_seq!();
}
