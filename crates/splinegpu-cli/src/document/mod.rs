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

mod curves;
pub mod geometry;
pub mod queries;
pub mod surfaces;
mod values;
mod walk;

use std::io::{self, Read as _};

use splinegpu::EvalJob;
use splinegpu::InputError;
use splinegpu::surface::SurfaceJob;

use crate::document::curves::curve_job;
use crate::document::geometry::geometry_job;
use crate::document::queries::{QueryDocument, query_document};
use crate::document::surfaces::surface_job;
use crate::document::walk::{ParsedDocument, parse, syntax};

/// A parsed document: curves or surfaces (contract: a document holds one or the other).
#[derive(Debug)]
pub enum Document {
    /// A curve document's job.
    Curves(EvalJob),
    /// A surface document's job.
    Surfaces(SurfaceJob),
    /// A curve document with "geometry": its meshes' job.
    Geometry(splinegpu::geometry::GeometryJob),
    /// A document with "queries": closest points, intersections or rays (`splinegpu query`).
    Query(QueryDocument),
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
    into_document(parse(&mut serde_json::Deserializer::from_str(text))?)
}

/// A curve document's job; a surface document, or one of meshes, is refused, naming
/// "surfaces" or "geometry".
fn curves_only(document: Document) -> Result<EvalJob, InputError> {
    match document {
        Document::Curves(job) => Ok(job),
        Document::Surfaces(_) => Err(InputError::field(
            "surfaces",
            "are not curves (read the document with parse_input)",
        )
        .in_document()),
        Document::Geometry(_) => Err(InputError::field(
            "geometry",
            "makes meshes, not samples (read the document with parse_input)",
        )
        .in_document()),
        Document::Query(_) => Err(InputError::field(
            "queries",
            "are answered by `splinegpu query`, not tessellated (read the document with parse_input)",
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
    // its buffer (the bare chain took w1's document nearly twice as long: docs/benchmarks.md).
    let reader = io::BufReader::with_capacity(1 << 16, start.chain(reader));
    into_document(parse(&mut serde_json::Deserializer::from_reader(reader))?)
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

/// The document's job: its curves' or its surfaces'.
fn into_document(mut parsed: ParsedDocument) -> Result<Document, InputError> {
    if let Some(entries) = parsed.queries.take() {
        return query_document(parsed, &entries).map(Document::Query);
    }
    match (parsed.curves, parsed.surfaces) {
        (Some(_), Some(_)) => Err(InputError::field(
            "surfaces",
            "cannot stand beside \"curves\": a document holds curves or surfaces",
        )
        .in_document()),
        (None, Some(_)) if parsed.geometry.is_some() => Err(InputError::field(
            "geometry",
            "is a field of curves documents: surfaces make their own meshes",
        )
        .in_document()),
        (None, Some(surfaces)) => surface_job(
            surfaces,
            parsed.sampling.as_deref(),
            parsed.derivatives,
            parsed.normals.unwrap_or(false),
        )
        .map(Document::Surfaces),
        (curves, None) => {
            if parsed.normals.is_some() {
                return Err(InputError::field(
                    "normals",
                    "is a field of surface documents (\"surfaces\"), not of curves",
                )
                .in_document());
            }
            let meshes = parsed.geometry.is_some()
                || curves
                    .as_ref()
                    .is_some_and(|c| c.iter().any(|c| c.geometry.is_some()));
            if meshes {
                let curves = curves
                    .ok_or_else(|| InputError::field("curves", "is missing").in_document())?;
                if curves.is_empty() {
                    return Err(InputError::field("curves", "must not be empty").in_document());
                }
                return geometry_job(
                    parsed.sampling.as_deref(),
                    parsed.geometry.as_ref(),
                    curves,
                    parsed.derivatives,
                )
                .map(Document::Geometry);
            }
            curve_job(parsed.sampling.as_deref(), curves, parsed.derivatives).map(Document::Curves)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::walk::FIT_BATCH;

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
