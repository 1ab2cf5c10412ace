//! Property tests of the document parser: random JSON, contract-shaped documents with broken
//! parts, byte-level mutations of valid documents, and random valid curves of every family.
//!
//! For every input: the parser never panics; a rejection is an input error placed at the
//! document or at a curve (the CLI exits 2 with it); parsing from memory and from a reader agree; and an accepted document
//! evaluates to finite samples. Documents with "geometry" (strokes, tubes, ribbons with fields
//! right, wrong or random) are read the same way, and an accepted one makes the meshes it
//! announces, finite.
//!
//! Each property runs 10,000 cases; `PROPTEST_CASES=1000000 cargo test --release --test
//! document_properties` is the longer run.

use proptest::prelude::*;
use splinegpu::{EvalJob, InputError, Location};

/// Cases per property: PROPTEST_CASES, or 10,000.
fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000);
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// JSON as text, objects allowed to repeat keys (a `serde_json::Value` cannot).
#[derive(Clone, Debug)]
enum Json {
    Null,
    Bool(bool),
    Number(String),
    Str(String),
    Array(Vec<Json>),
    Object(Vec<(String, Json)>),
}

impl Json {
    fn render(&self, out: &mut String) {
        match self {
            Json::Null => out.push_str("null"),
            Json::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            Json::Number(n) => out.push_str(n),
            Json::Str(s) => out.push_str(&serde_json::Value::from(s.as_str()).to_string()),
            Json::Array(items) => {
                out.push('[');
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    item.render(out);
                }
                out.push(']');
            }
            Json::Object(entries) => {
                out.push('{');
                for (i, (k, v)) in entries.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    out.push_str(&serde_json::Value::from(k.as_str()).to_string());
                    out.push(':');
                    v.render(out);
                }
                out.push('}');
            }
        }
    }

    fn text(&self) -> String {
        let mut out = String::new();
        self.render(&mut out);
        out
    }
}

/// The keys and words of the contract, so that random objects often look like documents.
const WORDS: &[&str] = &[
    "sampling",
    "derivatives",
    "curves",
    "kind",
    "points",
    "ends",
    "tension",
    "bias",
    "matrix",
    "t",
    "start_derivative",
    "end_derivative",
    "tangents",
    "method",
    "continuity",
    "knots",
    "weights",
    "per_segment",
    "at",
    "arc_length",
    "tolerance",
    "cardinal",
    "catmull-rom",
    "bspline",
    "tensioned-bspline",
    "beta",
    "bezier",
    "natural",
    "clamped",
    "periodic",
    "not-a-knot",
    "hermite",
    "pchip",
    "akima",
    "makima",
    "kochanek-bartels",
    "nurbs",
    "control",
    "repeat",
    "closed",
];

fn word() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => proptest::sample::select(WORDS).prop_map(str::to_string),
        1 => "[a-z_]{0,8}",
        1 => any::<String>(),
    ]
}

/// Numbers as JSON text, the awkward ones included.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => (-5i64..40).prop_map(|v| v.to_string()),
        2 => any::<f64>()
            .prop_filter("finite", |v| v.is_finite())
            .prop_map(|v| format!("{v:?}")),
        1 => proptest::sample::select(&[
            "1e308", "-1e308", "1.7976931348623157e308", "-0.0", "0.0", "5e-324", "1e-300",
            "18446744073709551615", "-9223372036854775808", "4000000000", "4294967296",
            "1e400", "123456789012345678901234567890",
        ][..])
        .prop_map(str::to_string),
    ]
}

fn json() -> impl Strategy<Value = Json> {
    let leaf = prop_oneof![
        Just(Json::Null),
        any::<bool>().prop_map(Json::Bool),
        number().prop_map(Json::Number),
        word().prop_map(Json::Str),
    ];
    leaf.prop_recursive(6, 64, 6, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Json::Array),
            prop::collection::vec((word(), inner), 0..6).prop_map(Json::Object),
        ]
    })
}

/// A point array: usually D numbers, sometimes the wrong length or a wrong type.
fn points() -> impl Strategy<Value = Json> {
    let point = |dim: usize| {
        prop::collection::vec(number().prop_map(Json::Number), dim..=dim).prop_map(Json::Array)
    };
    let regular = (
        prop_oneof![Just(1usize), Just(2), Just(3), Just(64), 0usize..70],
        0usize..12,
    )
        .prop_flat_map(move |(dim, n)| prop::collection::vec(point(dim), n..=n));
    prop_oneof![
        6 => regular.prop_map(Json::Array),
        1 => prop::collection::vec(json(), 0..5).prop_map(Json::Array),
        1 => json(),
    ]
}

/// A curve object of a random kind with mostly sensible fields, and sometimes extra or
/// repeated ones.
fn curve() -> impl Strategy<Value = Json> {
    let kind = proptest::sample::select(WORDS).prop_map(|w| Json::Str(w.to_string()));
    let field = (word(), json());
    (kind, points(), prop::collection::vec(field, 0..4)).prop_map(|(kind, points, extra)| {
        let mut entries = vec![("kind".to_string(), kind), ("points".to_string(), points)];
        entries.extend(extra);
        Json::Object(entries)
    })
}

/// A sampling object: per_segment, at, arc_length or tolerance with small values, or junk.
fn sampling() -> impl Strategy<Value = Json> {
    let one = |key: &'static str, value: Json| Json::Object(vec![(key.to_string(), value)]);
    prop_oneof![
        (0u32..9).prop_map(move |k| one("per_segment", Json::Number(k.to_string()))),
        prop::collection::vec(number().prop_map(Json::Number), 0..6)
            .prop_map(move |t| one("at", Json::Array(t))),
        (0u32..5).prop_map(move |m| one("arc_length", Json::Number(m.to_string()))),
        json(),
    ]
}

fn document() -> impl Strategy<Value = Json> {
    (
        prop::option::of(sampling()),
        prop::option::of(prop_oneof![
            (0u32..4).prop_map(|d| Json::Number(d.to_string())),
            json()
        ]),
        prop::collection::vec(curve(), 0..4),
        prop::collection::vec((word(), json()), 0..2),
    )
        .prop_map(|(sampling, derivatives, curves, extra)| {
            let mut entries = Vec::new();
            if let Some(s) = sampling {
                entries.push(("sampling".to_string(), s));
            }
            if let Some(d) = derivatives {
                entries.push(("derivatives".to_string(), d));
            }
            entries.push(("curves".to_string(), Json::Array(curves)));
            entries.extend(extra);
            Json::Object(entries)
        })
}

/// A "geometry" value: one of the three keys (sometimes two, none or another) whose object
/// holds fields of the contract with sensible, awkward or random values.
fn geometry() -> impl Strategy<Value = Json> {
    const FIELDS: &[&str] = &[
        "width",
        "radius",
        "cap",
        "join",
        "miter_limit",
        "sides",
        "up",
        "caps",
        "dash",
        "dash_offset",
    ];
    let value = prop_oneof![
        3 => (1u32..40).prop_map(|v| Json::Number(format!("0.0{v}"))),
        2 => (0u32..20).prop_map(|v| Json::Number(v.to_string())),
        2 => prop::collection::vec((1u32..9).prop_map(|v| Json::Number(format!("0.{v}"))), 0..8)
            .prop_map(Json::Array),
        1 => proptest::sample::select(&["butt", "round", "square", "miter", "bevel", "x"][..])
            .prop_map(|w| Json::Str(w.to_string())),
        1 => any::<bool>().prop_map(Json::Bool),
        1 => json(),
    ];
    let fields =
        prop::collection::vec((proptest::sample::select(FIELDS), value), 0..5).prop_map(|fields| {
            Json::Object(
                fields
                    .into_iter()
                    .map(|(k, v)| (k.to_string(), v))
                    .collect(),
            )
        });
    let key = prop_oneof![
        4 => proptest::sample::select(&["stroke", "tube", "ribbon"][..]).prop_map(str::to_string),
        1 => word(),
    ];
    prop_oneof![
        8 => (key, fields).prop_map(|(k, f)| Json::Object(vec![(k, f)])),
        1 => prop::collection::vec((word(), json()), 0..3).prop_map(Json::Object),
        1 => json(),
    ]
}

/// A curves document with "geometry" at the top, on its curves, or both, and small samplings.
fn geometry_document() -> impl Strategy<Value = Json> {
    let sampling = prop_oneof![
        (1u32..5).prop_map(|k| Json::Object(vec![(
            "per_segment".to_string(),
            Json::Number(k.to_string())
        )])),
        (2u32..12).prop_map(|m| Json::Object(vec![(
            "arc_length".to_string(),
            Json::Number(m.to_string())
        )])),
        sampling(),
    ];
    let curve = (curve(), prop::option::of(geometry())).prop_map(|(curve, geometry)| {
        let Json::Object(mut entries) = curve else {
            unreachable!("curve() makes objects")
        };
        entries.extend(geometry.map(|g| ("geometry".to_string(), g)));
        Json::Object(entries)
    });
    (
        prop::option::of(sampling),
        prop::option::of(geometry()),
        prop::collection::vec(curve, 0..4),
    )
        .prop_map(|(sampling, geometry, curves)| {
            let mut entries = Vec::new();
            entries.extend(sampling.map(|s| ("sampling".to_string(), s)));
            entries.extend(geometry.map(|g| ("geometry".to_string(), g)));
            entries.push(("curves".to_string(), Json::Array(curves)));
            Json::Object(entries)
        })
}

/// Documents of valid curves (catmull-rom, bspline, natural, bezier; 2-D with strokes, 3-D
/// with tubes and ribbons) whose geometry fields are mostly valid: meshes to make.
fn valid_geometry_document() -> impl Strategy<Value = String> {
    let curve = (
        0usize..4,
        any::<bool>(),
        4usize..9,
        prop::collection::vec(-10.0f64..10.0, 3 * 9),
        0usize..3,
        0.001f64..0.5,
        any::<bool>(),
        0usize..3,
        prop::option::of((0.0f64..2.0, 0.0f64..1.0, -3.0f64..3.0)),
    )
        .prop_map(
            |(kind, flat, n, pool, shape, width, per_point, style, dash)| {
                let kind = ["catmull-rom", "bspline", "natural", "bezier"][kind];
                let n = if kind == "bezier" { 3 * (n / 3) + 1 } else { n };
                let dim = if flat { 2 } else { 3 };
                let points: Vec<String> = (0..n)
                    .map(|i| {
                        let p: Vec<String> =
                            (0..dim).map(|k| format!("{:?}", pool[3 * i + k])).collect();
                        format!("[{}]", p.join(","))
                    })
                    .collect();
                let width = if per_point {
                    let w: Vec<String> = (0..n)
                        .map(|i| format!("{:?}", width * (1.0 + 0.1 * i as f64)))
                        .collect();
                    format!("[{}]", w.join(","))
                } else {
                    format!("{width:?}")
                };
                let dash = dash.map_or(String::new(), |(on, off, offset)| {
                    format!(r#", "dash": [{on:?}, {off:?}], "dash_offset": {offset:?}"#)
                });
                let geometry = if flat {
                    let cap = ["butt", "round", "square"][style];
                    let join = ["miter", "round", "bevel"][shape];
                    format!(
                        r#"{{"stroke": {{"width": {width}, "cap": "{cap}", "join": "{join}"{dash}}}}}"#
                    )
                } else if shape == 0 {
                    format!(r#"{{"ribbon": {{"width": {width}{dash}}}}}"#)
                } else {
                    let caps = style == 1;
                    format!(
                        r#"{{"tube": {{"radius": {width}, "sides": {}, "caps": {caps}{dash}}}}}"#,
                        3 + style * 4
                    )
                };
                format!(
                    r#"{{"kind": "{kind}", "points": [{}], "geometry": {geometry}}}"#,
                    points.join(",")
                )
            },
        );
    let sampling = prop_oneof![
        (1u32..5).prop_map(|k| format!(r#"{{"per_segment": {k}}}"#)),
        (2u32..24).prop_map(|m| format!(r#"{{"arc_length": {m}}}"#)),
        // Certified cross-sections: refused where they cannot be had (a cusp, a corner of a
        // tube, sides too few), located.
        (0.01f64..0.5).prop_map(|tol| format!(r#"{{"tolerance": {tol:?}}}"#)),
    ];
    (sampling, prop::collection::vec(curve, 1..4)).prop_map(|(sampling, curves)| {
        format!(
            r#"{{"sampling": {sampling}, "curves": [{}]}}"#,
            curves.join(",")
        )
    })
}

/// The properties of a document that may hold geometry: parsed or refused with a located
/// error the same way from memory and from a reader; an accepted geometry document's meshes
/// are what it announced, finite (small jobs). Returns whether it made meshes.
fn check_input(text: &str) -> bool {
    use splinegpu_cli::Document;
    let from_memory = splinegpu_cli::parse_input(text);
    let from_reader = splinegpu_cli::parse_input_from_reader(text.as_bytes());
    let meshes = |d: &Document| match d {
        Document::Geometry(job) => Some((job.vertex_count(), job.triangle_count())),
        _ => None,
    };
    match (&from_memory, &from_reader) {
        (Ok(a), Ok(b)) => assert_eq!(meshes(a), meshes(b), "the two entry points agree"),
        (Err(a), Err(b)) if is_syntax(a) => assert!(is_syntax(b), "{a} / {b}"),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "the two agree"),
        _ => panic!("one entry point accepted, the other refused: {text}"),
    }
    match from_memory {
        Ok(Document::Geometry(job)) => {
            if job.vertex_count() > 200_000 {
                return true;
            }
            let m = job.evaluate_cpu();
            assert_eq!(m.t.len() as u64, job.vertex_count());
            assert_eq!(m.triangles.len() as u64, job.triangle_count());
            assert!(m.points.iter().chain(&m.normals).all(|v| v.is_finite()));
            for c in 0..job.len() {
                let vertices = (m.vertex_offsets[c + 1] - m.vertex_offsets[c]) as u32;
                let triangles = m.triangle_offsets[c] as usize..m.triangle_offsets[c + 1] as usize;
                assert!(
                    m.triangles[triangles]
                        .iter()
                        .flatten()
                        .all(|&i| i < vertices)
                );
            }
            true
        }
        Ok(_) => false,
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.starts_with("document: ") || message.starts_with("curve "),
                "{message}"
            );
            false
        }
    }
}

/// Random curves of every family that satisfy the contract.
fn valid_document() -> impl Strategy<Value = String> {
    let coordinate = -1.0e6f64..1.0e6;
    let curve = (0usize..16, 1usize..6, 0usize..6, prop::collection::vec(coordinate, 64 * 16))
        .prop_map(|(family, dim, extra, pool)| {
            let dim = [1, 2, 3, 5, 64][dim - 1];
            let point = |i: usize| {
                let p: Vec<String> = (0..dim).map(|k| format!("{:?}", pool[(i * dim + k) % pool.len()])).collect();
                format!("[{}]", p.join(","))
            };
            let list = |n: usize| (0..n).map(point).collect::<Vec<_>>().join(",");
            let ends = ["control", "repeat", "closed"][extra % 3];
            let uniform = |kind: &str, fields: &str| {
                format!(r#"{{"kind":"{kind}","ends":"{ends}"{fields},"points":[{}]}}"#, list(4 + extra))
            };
            // Uneven knots: spacings 1, 11 and 21 in turn.
            let knots = (0..4 + extra)
                .scan(0.0, |t, i| {
                    let at = *t;
                    *t += 1.0 + (i % 3) as f64 * 10.0;
                    Some(format!("{at}"))
                })
                .collect::<Vec<_>>()
                .join(",");
            let derivative = format!("[{}]", vec!["0.5"; dim].join(","));
            match family {
                0 => uniform("cardinal", r#","tension":0.3"#),
                1 => uniform("catmull-rom", ""),
                2 => uniform("bspline", ""),
                3 => uniform("tensioned-bspline", r#","tension":2"#),
                4 => uniform("beta", r#","bias":1.5,"tension":3"#),
                5 => uniform("matrix", r#","matrix":[[1,2,3,4],[0,1,0,1],[2,2,0,0],[1,0,0,0]]"#),
                6 => format!(r#"{{"kind":"bezier","points":[{}]}}"#, list(3 * (1 + extra % 3) + 1)),
                7 => format!(r#"{{"kind":"natural","t":[{knots}],"points":[{}]}}"#, list(4 + extra)),
                8 => format!(
                    r#"{{"kind":"clamped","t":[{knots}],"start_derivative":{derivative},"end_derivative":{derivative},"points":[{}]}}"#,
                    list(4 + extra)
                ),
                9 => format!(r#"{{"kind":"not-a-knot","points":[{}]}}"#, list(4 + extra)),
                10 => {
                    let tangents = vec![derivative.clone(); 4 + extra].join(",");
                    format!(
                        r#"{{"kind":"hermite","t":[{knots}],"tangents":[{tangents}],"points":[{}]}}"#,
                        list(4 + extra)
                    )
                }
                11 => format!(r#"{{"kind":"pchip","t":[{knots}],"points":[{}]}}"#, list(4 + extra)),
                14 => {
                    // Clamped ends, a double interior knot, spacings 1, 11 and 21 in turn.
                    let n = 4 + extra;
                    let mut knots = vec![0.0; 4];
                    let mut at = 0.0;
                    for i in 0..n - 4 {
                        at += if i == 1 { 0.0 } else { 1.0 + (i % 3) as f64 * 10.0 };
                        knots.push(at);
                    }
                    knots.extend([at + 1.0; 4]);
                    let knots: Vec<String> = knots.iter().map(|k| format!("{k}")).collect();
                    // Every other curve rational, its weights from 0.25 to 4.
                    let weights = if extra % 2 == 1 {
                        let w: Vec<String> =
                            (0..n).map(|i| format!("{}", [0.25, 1.0, 4.0][i % 3])).collect();
                        format!(r#","weights":[{}]"#, w.join(","))
                    } else {
                        String::new()
                    };
                    format!(
                        r#"{{"kind":"nurbs","knots":[{}]{weights},"points":[{}]}}"#,
                        knots.join(","),
                        list(n)
                    )
                }
                13 => {
                    // Per-point tension, global continuity and bias, keys for closed ends.
                    let n = 4 + extra;
                    let tension = vec!["0.25"; n].join(",");
                    let keys = (0..=n).map(|i| format!("{}", i * i + i)).collect::<Vec<_>>().join(",");
                    format!(
                        r#"{{"kind":"kochanek-bartels","ends":"closed","tension":[{tension}],"continuity":-0.5,"bias":0.5,"t":[{keys}],"points":[{}]}}"#,
                        list(n)
                    )
                }
                12 => {
                    let method = ["akima", "makima"][extra % 2];
                    format!(r#"{{"kind":"akima","method":"{method}","points":[{}]}}"#, list(4 + extra))
                }
                _ => {
                    let n = 4 + extra;
                    let pts: Vec<String> = (0..n).map(|i| point(i % (n - 1))).collect();
                    format!(r#"{{"kind":"periodic","points":[{}]}}"#, pts.join(","))
                }
            }
        });
    (prop::collection::vec(curve, 1..6), 1u32..9, 0u32..3).prop_map(|(curves, k, d)| {
        format!(
            r#"{{"sampling":{{"per_segment":{k}}},"derivatives":{d},"curves":[{}]}}"#,
            curves.join(",")
        )
    })
}

/// A few random edits (delete, insert, replace) of a text's bytes, kept valid UTF-8.
fn mutated(text: String, edits: Vec<(usize, u8, u8)>) -> String {
    const ALPHABET: &[u8] = br#"[]{},:"-.0123456789eE tf"#;
    let mut bytes = text.into_bytes();
    for (at, what, with) in edits {
        if bytes.is_empty() {
            break;
        }
        let at = at % bytes.len();
        let with = ALPHABET[with as usize % ALPHABET.len()];
        match what % 3 {
            0 => {
                bytes.remove(at);
            }
            1 => bytes.insert(at, with),
            _ => bytes[at] = with,
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// A JSON syntax error (the document's text, not its meaning).
fn is_syntax(e: &InputError) -> bool {
    e.to_string().starts_with("document: invalid JSON at line ")
}

/// The properties every input must have; returns the job when the document is accepted.
fn check(text: &str) -> Option<EvalJob> {
    let from_memory = splinegpu_cli::parse_document(text);
    let from_reader = splinegpu_cli::parse_document_from_reader(text.as_bytes());
    match (&from_memory, &from_reader) {
        (Ok(a), Ok(b)) => assert_eq!(a, b, "the two entry points agree"),
        // serde_json reads one byte further from a reader before some syntax errors, so the
        // two may name columns one apart; the error is the same.
        (Err(a), Err(b)) if is_syntax(a) => assert!(is_syntax(b), "{a} / {b}"),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "the two agree"),
        _ => panic!("one entry point accepted, the other refused: {text}"),
    }
    match from_memory {
        Ok(job) => Some(job),
        Err(e) => {
            assert!(
                matches!(e.location, Location::Document | Location::Curve(_)),
                "a document's error names the document or a curve: {e}"
            );
            let message = e.to_string();
            assert!(
                message.starts_with("document: ") || message.starts_with("curve "),
                "{message}"
            );
            None
        }
    }
}

/// An accepted document evaluates to finite samples (small jobs; large ones are the streaming
/// tests' business).
fn evaluates_finite(job: &EvalJob) {
    if job.sample_count() > 200_000 {
        return;
    }
    let samples = splinegpu::evaluate_reference(job);
    for c in 0..job.len() {
        let s = samples.curve(c);
        for plane in [Some(s.points), s.d1, s.d2].into_iter().flatten() {
            assert!(plane.iter().all(|v| v.is_finite()), "curve {c}: not finite");
        }
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn random_json_is_parsed_or_refused_with_a_located_error(value in json()) {
        if let Some(job) = check(&value.text()) {
            evaluates_finite(&job);
        }
    }

    #[test]
    fn contract_shaped_documents_are_parsed_or_refused_with_a_located_error(doc in document()) {
        if let Some(job) = check(&doc.text()) {
            evaluates_finite(&job);
        }
    }

    #[test]
    fn mutated_valid_documents_are_parsed_or_refused_with_a_located_error(
        doc in valid_document(),
        edits in prop::collection::vec((any::<usize>(), any::<u8>(), any::<u8>()), 1..6),
    ) {
        if let Some(job) = check(&mutated(doc, edits)) {
            evaluates_finite(&job);
        }
    }

    #[test]
    fn geometry_documents_are_parsed_or_refused_with_a_located_error(doc in geometry_document()) {
        check_input(&doc.text());
    }

    #[test]
    fn valid_geometry_documents_make_the_meshes_they_announce(doc in valid_geometry_document()) {
        // Refusals stay possible (a curve whose points coincide has no tangent for its
        // frame: "up" is then parallel to nothing), but are located.
        check_input(&doc);
    }

    #[test]
    fn valid_curves_of_every_family_are_accepted_and_evaluate_finite(doc in valid_document()) {
        let job = check(&doc).unwrap_or_else(|| panic!("refused: {doc}"));
        evaluates_finite(&job);
    }
}

#[test]
fn deep_nesting_is_refused_without_overflowing_the_stack() {
    for depth in [200, 100_000] {
        let doc = format!(
            r#"{{"curves": [{{"kind": "bspline", "points": {}{}}}]}}"#,
            "[".repeat(depth),
            "]".repeat(depth)
        );
        assert!(check(&doc).is_none());
    }
}

#[test]
fn duplicate_keys_are_refused_at_every_level() {
    for (doc, key) in [
        (r#"{"curves": [], "curves": []}"#, "\"curves\""),
        (
            r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]], "points": [[0]]}]}"#,
            "\"points\"",
        ),
        (
            r#"{"sampling": {"at": [0], "at": [1]}, "curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}]}"#,
            "\"at\"",
        ),
    ] {
        match splinegpu_cli::parse_document(doc) {
            Err(e) => {
                let message = e.to_string();
                assert!(
                    message.contains(key) && message.contains("twice"),
                    "{message}"
                );
            }
            other => panic!("{doc}: {other:?}"),
        }
    }
}
