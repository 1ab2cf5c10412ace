//! The CLI's input document (contract: "Input document"), parsed and checked into an
//! [`EvalJob`]. Every error names the curve index (or the document key), the field and the
//! value; the whole document is checked before anything is evaluated.
//!
//! The parser walks the JSON with serde visitors instead of building a `serde_json::Value`
//! tree: each curve is fitted as soon as it is read and its points are dropped, so a large
//! document costs about its fitted segment tables (plus, from a file, nothing for its text),
//! and every object's keys are seen one by one, so a key given twice is an error rather than
//! last-wins. Visitors report located errors through a side channel (`Located`) because
//! serde's error type carries only text.

use std::cell::RefCell;
use std::fmt;
use std::io::{self, Read as _};
use std::sync::mpsc;

use serde::Deserialize;
use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::{Map, Value};

use splinegpu::PerPoint;
use splinegpu::SegmentTable;
use splinegpu::kinds::{KindFields, kind_fields, not_a_field};
use splinegpu::{Curve, CurveKind, Ends, MAX_DIM, Points};
use splinegpu::{Derivatives, EvalJob};
use splinegpu::{InputError, Location};
use splinegpu::{SamplePlan, Sampling};

use crate::surfaces::{ReadSurface, surface_job};
use splinegpu::surface::SurfaceJob;

/// The document's top-level keys.
const DOCUMENT_KEYS: [&str; 5] = ["sampling", "derivatives", "curves", "surfaces", "normals"];

/// A parsed document: curves or surfaces (contract: a document holds one or the other).
#[derive(Debug)]
pub enum Document {
    /// A curve document's job.
    Curves(EvalJob),
    /// A surface document's job.
    Surfaces(SurfaceJob),
}

/// Parses and checks a document held in memory, fits its curves and resolves their sampling.
///
/// # Errors
/// The first rule broken, placed at the document (JSON syntax errors give line and column) or
/// at a curve.
pub fn parse_document(text: &str) -> Result<EvalJob, InputError> {
    curves_only(parse_input(text)?)
}

/// [`parse_document`] for a document of curves or of surfaces.
///
/// # Errors
/// As [`parse_document`], surfaces' errors placed at their surface.
pub fn parse_input(text: &str) -> Result<Document, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    parse(&mut serde_json::Deserializer::from_str(text))
}

/// A curve document's job; a surface document is refused, naming "surfaces".
fn curves_only(document: Document) -> Result<EvalJob, InputError> {
    match document {
        Document::Curves(job) => Ok(job),
        Document::Surfaces(_) => Err(InputError::field(
            "surfaces",
            "are not curves (read the document with parse_input)",
        )
        .in_document()),
    }
}

/// [`parse_document`] reading from `reader` as it goes: the document's text is never held
/// whole, so memory stays near the size of its fitted curves. It is read 64 KiB at a time
/// (a file need not come in a `BufReader`), and a leading byte order mark is skipped.
///
/// # Errors
/// As [`parse_document`]; a read error is reported as a document error.
pub fn parse_document_from_reader(reader: impl io::Read) -> Result<EvalJob, InputError> {
    curves_only(parse_input_from_reader(reader)?)
}

/// [`parse_document_from_reader`] for a document of curves or of surfaces.
///
/// # Errors
/// As [`parse_input`]; a read error is reported as a document error.
pub fn parse_input_from_reader(mut reader: impl io::Read) -> Result<Document, InputError> {
    let start = read_past_bom(&mut reader).map_err(|e| syntax(&serde_json::Error::io(e)))?;
    // serde_json takes a reader's bytes one at a time, which only a `BufReader` serves from
    // its buffer: through the bare chain w1's document parsed in 169-173 ms, not 95-99.
    let reader = io::BufReader::with_capacity(1 << 16, start.chain(reader));
    parse(&mut serde_json::Deserializer::from_reader(reader))
}

/// The UTF-8 byte order mark, which editors on Windows put at the start of a file.
const BOM: &[u8] = "\u{feff}".as_bytes();

/// The first bytes of `reader`, up to [`BOM`]'s length, with a byte order mark dropped (RFC
/// 8259 lets a parser ignore one; serde_json reads it as a syntax error).
fn read_past_bom(reader: &mut impl io::Read) -> io::Result<io::Cursor<Vec<u8>>> {
    let mut start = Vec::with_capacity(BOM.len());
    io::Read::take(&mut *reader, BOM.len() as u64).read_to_end(&mut start)?;
    if start == BOM {
        start.clear();
    }
    Ok(io::Cursor::new(start))
}

fn parse<'de, R: serde_json::de::Read<'de>>(
    de: &mut serde_json::Deserializer<R>,
) -> Result<Document, InputError> {
    let located = Located::default();
    let parsed = DocumentSeed(&located)
        .deserialize(&mut *de)
        .and_then(|doc| de.end().map(|()| doc));
    match parsed {
        Ok(doc) => doc.into_document(),
        Err(e) => Err(located.0.into_inner().unwrap_or_else(|| syntax(&e))),
    }
}

/// A JSON syntax error, with its line and column; or a read error, which is no fault of the
/// JSON's (and has no place when nothing was read).
fn syntax(e: &serde_json::Error) -> InputError {
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
struct Located(RefCell<Option<InputError>>);

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
struct ParsedDocument {
    /// The document's "sampling" entries, read as curves or surfaces take them.
    sampling: Option<Vec<(String, Value)>>,
    derivatives: Derivatives,
    curves: Option<Vec<ParsedCurve>>,
    surfaces: Option<Vec<ReadSurface>>,
    normals: Option<bool>,
}

/// One fitted curve, with its own sampling if it has one.
struct ParsedCurve {
    table: SegmentTable,
    sampling: Option<Sampling>,
}

impl ParsedDocument {
    /// The document's job: its curves' or its surfaces'.
    fn into_document(self) -> Result<Document, InputError> {
        match (self.curves.is_some(), self.surfaces.is_some()) {
            (true, true) => Err(InputError::field(
                "surfaces",
                "cannot stand beside \"curves\": a document holds curves or surfaces",
            )
            .in_document()),
            (false, true) => {
                let surfaces = self.surfaces.expect("surfaces");
                surface_job(
                    surfaces,
                    self.sampling.as_deref(),
                    self.derivatives,
                    self.normals.unwrap_or(false),
                )
                .map(Document::Surfaces)
            }
            _ => {
                if self.normals.is_some() {
                    return Err(InputError::field(
                        "normals",
                        "is a field of surface documents (\"surfaces\"), not of curves",
                    )
                    .in_document());
                }
                self.into_job().map(Document::Curves)
            }
        }
    }

    /// The job: each curve's plan from its sampling or the document's.
    fn into_job(self) -> Result<EvalJob, InputError> {
        let sampling = self
            .sampling
            .as_deref()
            .map(sampling_spec)
            .transpose()
            .map_err(InputError::in_document)?;
        let curves = self
            .curves
            .ok_or_else(|| InputError::field("curves", "is missing").in_document())?;
        if curves.is_empty() {
            return Err(InputError::field("curves", "must not be empty").in_document());
        }
        let default = sampling.unwrap_or_default();
        let derivatives = self.derivatives;
        // Plans on every thread (an arc-length or tolerance plan measures its curve: most of
        // the time of such documents), then pushed in order, the first error by curve index.
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
}

/// `plan(curve)` for every curve, in order, the curves split into one contiguous range per
/// thread.
fn plan_on_every_thread(
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
        };
        let mut seen = Vec::new();
        while let Some(key) = next_key(&mut map, &mut seen, located, &place)? {
            match key.as_str() {
                "sampling" => {
                    doc.sampling = Some(map.next_value_seed(SamplingSeed(located, place.clone()))?);
                }
                "derivatives" => {
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
                            Ok(table) => fitted.push(ParsedCurve {
                                table,
                                sampling: curve.sampling,
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
/// more than the fitting it moved (10,000 Catmull-Rom curves: 129-130 to 137-141 ms), one per
/// 64 curves saves it (116-120 ms).
const FIT_BATCH: usize = 64;

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
                sampling = Some(map.next_value_seed(SamplingSeed(located, place.clone()))?);
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

/// A curve object as read: its fields (keys in order), its points and its sampling, checked
/// and fitted by [`fit_curve`].
struct ReadCurve {
    fields: Map<String, Value>,
    keys: Vec<String>,
    points: Option<Points>,
    sampling: Option<Sampling>,
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
                    let entries = map.next_value_seed(SamplingSeed(located, place.clone()))?;
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

/// A "sampling" object's entries, keys checked for duplicates; their meaning is checked by
/// [`sampling_spec`].
struct SamplingSeed<'a>(&'a Located, Location);

impl<'de> DeserializeSeed<'de> for SamplingSeed<'_> {
    type Value = Vec<(String, Value)>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl SamplingSeed<'_> {
    fn wrong<E: de::Error>(self, got: &Value) -> Result<Vec<(String, Value)>, E> {
        let message = format!("must be an object, got {}", describe(got));
        self.0.fail(&self.1, InputError::field("sampling", message))
    }
}

impl<'de> Visitor<'de> for SamplingSeed<'_> {
    type Value = Vec<(String, Value)>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a sampling object")
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

/// The samplings, as a "sampling" object names them.
const SAMPLINGS: &str = "per_segment, at, arc_length or tolerance";

/// The sampling a "sampling" object's entries ask for.
fn sampling_spec(entries: &[(String, Value)]) -> Result<Sampling, InputError> {
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
fn fit_curve(
    fields: &Map<String, Value>,
    keys: &[String],
    points: Option<Points>,
) -> Result<SegmentTable, InputError> {
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
    let key_ok =
        |key: &str| ["kind", "points", "sampling"].contains(&key) || allowed.contains(&key);
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
    Ok(Curve::new(kind, points)?.fit())
}

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
    let text = value.to_string();
    if text.chars().count() > 40 {
        format!("{}...", text.chars().take(37).collect::<String>())
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reader that fails once `text` is read.
    struct FailsAfter(&'static [u8]);

    impl io::Read for FailsAfter {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            if self.0.is_empty() {
                return Err(io::Error::other("the disk went away"));
            }
            let n = buf.len().min(self.0.len());
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    /// A reader that gives one byte a read.
    struct Trickle(&'static [u8]);

    impl io::Read for Trickle {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let Some((first, rest)) = self.0.split_first() else {
                return Ok(0);
            };
            buf[0] = *first;
            self.0 = rest;
            Ok(1)
        }
    }

    #[test]
    fn a_byte_order_mark_is_read_past() {
        let text =
            "\u{feff}{\"curves\": [{\"kind\": \"bspline\", \"points\": [[0], [1], [2], [3]]}]}";
        for job in [
            parse_document(text),
            parse_document_from_reader(text.as_bytes()),
            // One byte a read: the mark is found across short reads.
            parse_document_from_reader(Trickle(text.as_bytes())),
        ] {
            assert_eq!(job.unwrap().sample_count(), 17);
        }
        // Documents shorter than the mark, and a mark alone.
        let error = |text: &str| parse_document_from_reader(text.as_bytes()).unwrap_err();
        assert!(
            error("")
                .to_string()
                .contains("invalid JSON at line 1, column 0")
        );
        assert!(error("{}").to_string().contains("\"curves\" is missing"));
        assert!(
            error("\u{feff}")
                .to_string()
                .contains("invalid JSON at line 1, column 0")
        );
    }

    #[test]
    fn a_read_error_is_named_as_one_not_as_invalid_json() {
        let message = |text| parse_document_from_reader(FailsAfter(text)).unwrap_err();
        assert_eq!(
            message(b"").to_string(),
            "document: cannot read the input: the disk went away"
        );
        // Line 2 is read up to its 14th character when the read fails.
        let text = b"{\"curves\": [\n  {\"kind\": \"bs";
        assert_eq!(
            message(text).to_string(),
            "document: cannot read the input after line 2, column 14: the disk went away"
        );
    }

    /// The message for a document whose one B-spline curve has `points`.
    fn points_error(points: &str) -> String {
        let text = format!(r#"{{"curves": [{{"kind": "bspline", "points": {points}}}]}}"#);
        match parse_document(&text) {
            Ok(_) => panic!("{points} was accepted"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn points_are_read_number_by_number_and_each_fault_named() {
        let cases = [
            (
                "[[0, 1], 5, [2, 3], [4, 5]]",
                "curve 0: \"points\" must be arrays of numbers: points[1] = 5",
            ),
            (
                r#"[[0, 1], {"x": 1}, [2, 3], [4, 5]]"#,
                "curve 0: \"points\" must be arrays of numbers: points[1] = {\"x\":1}",
            ),
            (
                r#"[[0, 1], [2, "3"], [2, 3], [4, 5]]"#,
                "curve 0: \"points\" must be numbers: points[1][1] = \"3\"",
            ),
            (
                "[[0, 1], [2, 3], [null, [4]], [4, 5]]",
                "curve 0: \"points\" must be numbers: points[2][0] = null",
            ),
            (
                "[[0, 1], [2, 3], [true, [4]], [4, 5]]",
                "curve 0: \"points\" must be numbers: points[2][0] = true",
            ),
            (
                "[[0, 1], [2, 3], [1, [4]], [4, 5]]",
                "curve 0: \"points\" must be numbers: points[2][1] = [4]",
            ),
            // The dimension is checked before the numbers.
            (
                r#"[[0, 1], [2, 3], ["a", 2, 3], [4, 5]]"#,
                "curve 0: \"points\" must all have the same dimension: points[2] has 3 \
                 coordinates, points[0] has 2",
            ),
            (
                "[[], [], [], []]",
                "curve 0: \"points\" must have 1 to 64 coordinates per point: points[0] has 0",
            ),
            ("[]", "curve 0: \"points\" must not be empty"),
        ];
        for (points, want) in cases {
            assert_eq!(points_error(points), want, "{points}");
        }
    }

    /// The message for a document of `curves`.
    fn curves_error(curves: &[&str], after: &str) -> String {
        let text = format!(r#"{{"curves": [{}]{after}"#, curves.join(", "));
        match parse_document(&text) {
            Ok(_) => panic!("{text} was accepted"),
            Err(e) => e.to_string(),
        }
    }

    /// Curves are fitted while later ones are read, yet the error reported is the first a
    /// reader that fits each curve before reading on would meet.
    #[test]
    fn the_first_error_in_document_order_is_reported() {
        let good = r#"{"kind": "bspline", "points": [[0], [1], [2], [3]]}"#;
        let unfittable = r#"{"kind": "bspline", "points": [[0], [1]]}"#;
        let bad_sampling = r#"{"kind": "bspline", "points": [[0], [1], [2], [3]],
            "sampling": {"per_segment": 0}}"#;
        let many: Vec<&str> = std::iter::repeat_n(good, 3 * FIT_BATCH).collect();
        let unfittable_1 = "curve 1: \"points\"";
        let unfittable_far = format!("curve {}: \"points\"", many.len());
        let cases: Vec<(Vec<&str>, &str, &str)> = vec![
            // A fitting error, then a syntax error after the curves.
            (vec![good, unfittable, good], "] oops", unfittable_1),
            // A fitting error, then a reading error in a later curve.
            (vec![good, unfittable, bad_sampling], "]}", unfittable_1),
            // A reading error before a curve that cannot be fitted.
            (
                vec![bad_sampling, unfittable],
                "]}",
                "curve 0: \"per_segment\"",
            ),
            // A syntax error, with every curve before it fitted.
            (
                [many.as_slice(), &[good]].concat(),
                "] oops",
                "document: invalid JSON",
            ),
            // A fitting error far behind the reader.
            (
                [many.as_slice(), &[unfittable], &many].concat(),
                "]}",
                &unfittable_far,
            ),
        ];
        for (curves, after, want) in cases {
            let got = curves_error(&curves, after);
            assert!(got.starts_with(want), "{got:?} should start with {want:?}");
        }
    }

    #[test]
    fn integers_and_floats_are_read_as_their_f64() {
        let text = r#"{"curves": [{"kind": "bspline",
            "points": [[0], [-3], [18446744073709551615], [2.5e-300]]}]}"#;
        let job = parse_document(text).expect("a valid document");
        // A uniform B-spline through 4 control points: one segment, whose value at u = 0 is
        // (P0 + 4 P1 + P2) / 6.
        let table = job.table(0);
        let mut at = [0.0];
        table.segment(0).eval(0.0, &mut at);
        let want = (0.0 + 4.0 * -3.0 + 18_446_744_073_709_551_615.0) / 6.0;
        assert_eq!(at[0], want);
    }
}
