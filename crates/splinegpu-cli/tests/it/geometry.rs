//! Curves with "geometry" through the binary: every output format holds the library's meshes
//! (JSON, NPZ streamed in groups, CSV, .obj, .glb read back by the gltf crate), a straight
//! stroke's vertices where the hand derivation puts them, every bad geometry exiting 2 with
//! one message naming the curve, the field and the value and writing nothing, and tolerance
//! cross-sections as the library makes them.

use std::path::Path;

use serde_json::Value;
use splinegpu::geometry::{Geometry, GeometryJob, Meshes, Ribbon, Tube, Width};
use splinegpu::{Basis, Curve, CurveKind, Ends, Points, Sampling};

fn tessellate(dir: &Path, doc: &str, name: &str, backend: &str) -> (i32, String) {
    let input = dir.join("geometry.json");
    std::fs::write(&input, doc).unwrap();
    let out = dir.join(name);
    let run = crate::support::run_cli(
        &[
            "tessellate",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--backend",
            backend,
        ],
        &[],
        "",
    );
    (
        run.status.code().unwrap_or(-1),
        String::from_utf8(run.stderr).unwrap(),
    )
}

const TUBE_POINTS: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 1.0],
    [0.0, 0.0, 1.0],
];
const RIBBON_POINTS: [[f64; 3]; 4] = [
    [2.0, 0.0, 0.0],
    [3.0, 0.0, 0.5],
    [3.0, 1.0, 0.0],
    [2.0, 1.0, 0.5],
];

/// A capped Catmull-Rom tube (the document's geometry) and a closed B-spline ribbon whose
/// width varies per point (its own), per_segment 8.
fn document() -> String {
    format!(
        r#"{{"sampling": {{"per_segment": 8}},
 "geometry": {{"tube": {{"radius": 0.1, "sides": 6, "caps": true}}}},
 "curves": [
  {{"kind": "catmull-rom", "points": {}}},
  {{"kind": "bspline", "ends": "closed", "points": {},
    "geometry": {{"ribbon": {{"width": [0.1, 0.2, 0.3, 0.2], "up": [0, 0, 1]}}}}}}
 ]}}"#,
        serde_json::to_string(&TUBE_POINTS).unwrap(),
        serde_json::to_string(&RIBBON_POINTS).unwrap()
    )
}

fn curve(kind: CurveKind, points: &[[f64; 3]]) -> Curve {
    let flat = points.iter().flatten().copied().collect();
    Curve::new(kind, Points::new(3, flat).unwrap()).unwrap()
}

/// The document's meshes made by the library.
fn library_meshes() -> Meshes {
    let tube = curve(
        CurveKind::Uniform {
            basis: Basis::CatmullRom,
            ends: Ends::Control,
        },
        &TUBE_POINTS,
    );
    let ribbon = curve(
        CurveKind::Uniform {
            basis: Basis::BSpline,
            ends: Ends::Closed,
        },
        &RIBBON_POINTS,
    );
    let mut job = GeometryJob::new();
    let sampling = Sampling::PerSegment(8);
    let tube_geometry = Geometry::Tube(Tube {
        radius: Width::Constant(0.1),
        sides: Some(6),
        up: None,
        caps: true,
        dash: None,
    });
    let ribbon_geometry = Geometry::Ribbon(Ribbon {
        width: Width::PerPoint(vec![0.1, 0.2, 0.3, 0.2]),
        up: Some([0.0, 0.0, 1.0]),
        dash: None,
    });
    job.push(&tube, &tube_geometry, &sampling).unwrap();
    job.push(&ribbon, &ribbon_geometry, &sampling).unwrap();
    job.evaluate_cpu()
}

fn numbers(value: &Value) -> Vec<f64> {
    match value {
        Value::Array(items) => items.iter().flat_map(numbers).collect(),
        v => vec![v.as_f64().unwrap()],
    }
}

fn range(offsets: &[u64], c: usize) -> std::ops::Range<usize> {
    offsets[c] as usize..offsets[c + 1] as usize
}

#[test]
fn json_holds_the_library_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr) = tessellate(dir.path(), &document(), "out.json", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let text = std::fs::read_to_string(dir.path().join("out.json")).unwrap();
    let json: Value = serde_json::from_str(&text).unwrap();
    let meshes = json["meshes"].as_array().unwrap();
    let want = library_meshes();
    assert_eq!(meshes.len(), 2);
    for (c, mesh) in meshes.iter().enumerate() {
        let v = range(&want.vertex_offsets, c);
        let f = range(&want.triangle_offsets, c);
        assert_eq!(
            numbers(&mesh["points"]),
            want.points[3 * v.start..3 * v.end]
        );
        assert_eq!(
            numbers(&mesh["normals"]),
            want.normals[3 * v.start..3 * v.end]
        );
        assert_eq!(numbers(&mesh["t"]), want.t[v]);
        let triangles: Vec<f64> = want.triangles[f]
            .iter()
            .flatten()
            .map(|&i| f64::from(i))
            .collect();
        assert_eq!(numbers(&mesh["triangles"]), triangles);
    }
}

/// NPZ in groups of 20 vertices (each mesh a group of its own) is the whole one byte for
/// byte, and its arrays are the library's, triangles indexing the whole vertex array.
#[test]
fn npz_streams_in_groups_with_the_library_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("geometry.json");
    std::fs::write(&input, document()).unwrap();
    let write = |name: &str, envs: &[(&str, &str)]| {
        let out = dir.path().join(name);
        let args = [
            "tessellate",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--backend",
            "cpu",
        ];
        let run = crate::support::run_cli(&args, envs, "");
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        std::fs::read(out).unwrap()
    };
    let whole = write("whole.npz", &[]);
    let grouped = write("grouped.npz", &[("SPLINEGPU_CHUNK_SAMPLES", "20")]);
    assert!(
        whole == grouped,
        "the grouped NPZ differs from the whole one"
    );
    let arrays = crate::stream::read_npz(&grouped);
    let f64s = |name: &str| -> Vec<f64> { bytemuck::pod_collect_to_vec(&arrays[name].2) };
    let i64s = |name: &str| -> Vec<i64> { bytemuck::pod_collect_to_vec(&arrays[name].2) };
    let want = library_meshes();
    let (vertices, triangles) = (want.t.len(), want.triangles.len());
    assert_eq!(arrays["points"].1, [vertices, 3]);
    assert_eq!(arrays["normals"].1, [vertices, 3]);
    assert_eq!(arrays["triangles"].1, [triangles, 3]);
    assert_eq!(f64s("points"), want.points);
    assert_eq!(f64s("normals"), want.normals);
    assert_eq!(f64s("t"), want.t);
    let signed = |o: &[u64]| -> Vec<i64> { o.iter().map(|&x| x as i64).collect() };
    assert_eq!(i64s("curve_offsets"), signed(&want.vertex_offsets));
    assert_eq!(i64s("triangle_offsets"), signed(&want.triangle_offsets));
    let whole_array: Vec<i64> = (0..2)
        .flat_map(|c| {
            let base = want.vertex_offsets[c] as i64;
            want.triangles[range(&want.triangle_offsets, c)]
                .iter()
                .flatten()
                .map(move |&i| i64::from(i) + base)
        })
        .collect();
    assert_eq!(i64s("triangles"), whole_array);
}

#[test]
fn csv_has_the_contracts_header_and_one_row_per_vertex() {
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr) = tessellate(dir.path(), &document(), "out.csv", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let text = std::fs::read_to_string(dir.path().join("out.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "curve,vertex,t,x0,x1,x2,nx,ny,nz");
    let rows: Vec<&str> = lines.collect();
    let want = library_meshes();
    assert_eq!(rows.len(), want.t.len());
    let first_ribbon = want.vertex_offsets[1] as usize;
    assert!(rows[first_ribbon].starts_with("1,0,"));
    let fields: Vec<f64> = rows[first_ribbon]
        .split(',')
        .skip(2)
        .map(|x| x.parse().unwrap())
        .collect();
    let p = 3 * first_ribbon;
    assert_eq!(fields[0], want.t[first_ribbon]);
    assert_eq!(fields[1..4], want.points[p..p + 3]);
    assert_eq!(fields[4..7], want.normals[p..p + 3]);
}

#[test]
fn meshes_open_as_they_are() {
    let dir = tempfile::tempdir().unwrap();
    let want = library_meshes();
    let counts = |c: usize| {
        (
            range(&want.vertex_offsets, c).len(),
            range(&want.triangle_offsets, c).len(),
        )
    };
    let (status, stderr) = tessellate(dir.path(), &document(), "out.glb", "auto");
    assert_eq!(status, 0, "{stderr}");
    let bytes = std::fs::read(dir.path().join("out.glb")).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let names: Vec<_> = gltf
        .meshes()
        .map(|m| m.name().unwrap().to_string())
        .collect();
    assert_eq!(names, ["curve-0", "curve-1"]);
    for (c, mesh) in gltf.meshes().enumerate() {
        let primitive = mesh.primitives().next().unwrap();
        let (v, f) = counts(c);
        assert_eq!(
            primitive.get(&gltf::Semantic::Positions).unwrap().count(),
            v
        );
        assert_eq!(primitive.get(&gltf::Semantic::Normals).unwrap().count(), v);
        assert_eq!(primitive.indices().unwrap().count(), 3 * f);
    }
    let (status, stderr) = tessellate(dir.path(), &document(), "out.obj", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let obj = std::fs::read_to_string(dir.path().join("out.obj")).unwrap();
    let lines = |tag: &str| obj.lines().filter(|l| l.starts_with(tag)).count();
    assert_eq!(lines("v "), want.t.len());
    assert_eq!(lines("vn "), want.t.len());
    assert_eq!(lines("f "), want.triangles.len());
    // Faces index the whole file's vertices from 1: the ribbon's start after the tube's.
    let first = want.vertex_offsets[1] + 1;
    assert!(obj.contains("o curve-1") && obj.contains(&format!("f {first}//{first} ")));
}

/// A straight stroke from (0, 0) to (3, 0) of width 0.5 with butt caps, one cross-section a
/// segment: each cross-section's two vertices lie at C(t) ± (w/2) n, n = (-T_y, T_x) = (0, 1),
/// written with 2 coordinates and no normals.
#[test]
fn a_straight_stroke_has_its_vertices_at_half_the_width_across_the_line() {
    let doc = r#"{"sampling": {"per_segment": 1}, "curves": [
        {"kind": "bezier", "points": [[0, 0], [1, 0], [2, 0], [3, 0]],
         "geometry": {"stroke": {"width": 0.5}}}]}"#;
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr) = tessellate(dir.path(), doc, "out.json", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let text = std::fs::read_to_string(dir.path().join("out.json")).unwrap();
    let json: Value = serde_json::from_str(&text).unwrap();
    let mesh = &json["meshes"][0];
    assert!(mesh.get("normals").is_none(), "a stroke has no normals");
    let mut points: Vec<(f64, f64)> = mesh["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let p = p.as_array().unwrap();
            assert_eq!(p.len(), 2, "a stroke's points are 2-D");
            (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())
        })
        .collect();
    points.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let close =
        |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12;
    let want = [(0.0, -0.25), (0.0, 0.25), (3.0, -0.25), (3.0, 0.25)];
    assert_eq!(points.len(), 4, "{points:?}");
    for (got, want) in points.iter().zip(want) {
        assert!(close(*got, want), "{points:?}");
    }
    assert_eq!(numbers(&mesh["t"]), [0.0, 0.0, 1.0, 1.0]);
    assert_eq!(mesh["triangles"].as_array().unwrap().len(), 2);
    // The NPZ's points are 2-D too, and it holds no normals.
    let (status, stderr) = tessellate(dir.path(), doc, "out.npz", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let arrays = crate::stream::read_npz(&std::fs::read(dir.path().join("out.npz")).unwrap());
    assert_eq!(arrays["points"].1, [4, 2]);
    assert!(!arrays.contains_key("normals"));
}

const LINE3: &str = r#""kind": "catmull-rom", "points": [[0,0,0],[1,0,0],[1,1,0],[0,1,1]]"#;
const LINE2: &str = r#""kind": "catmull-rom", "points": [[0,0],[1,0],[1,1],[0,1]]"#;

/// A document whose top-level keys start with `top` and whose curves are a good tube and then
/// a curve of `fields`.
fn doc(top: &str, fields: &str) -> String {
    format!(
        r#"{{{top} "curves": [{{{LINE3}, "geometry": {{"tube": {{"radius": 0.1}}}}}}, {{{fields}}}]}}"#
    )
}

/// Curve 1 as a 3-D (`LINE3`) or 2-D curve with `geometry`.
fn curve_1(line: &str, geometry: &str) -> String {
    doc("", &format!(r#"{line}, "geometry": {geometry}"#))
}

#[test]
fn bad_geometry_exits_2_naming_the_curve_the_field_and_the_value() {
    let stroke =
        |fields: &str| curve_1(LINE2, &format!(r#"{{"stroke": {{"width": 0.1{fields}}}}}"#));
    let tube = |fields: &str| curve_1(LINE3, &format!(r#"{{"tube": {{"radius": 0.1{fields}}}}}"#));
    let cases: Vec<(String, &str)> = vec![
        (
            curve_1(LINE3, r#"{"tube": {"radius": 1}, "ribbon": {"width": 1}}"#),
            "curve 1: \"geometry\" must have exactly one key (stroke, tube or ribbon), got 2",
        ),
        (
            curve_1(LINE3, "{}"),
            "curve 1: \"geometry\" must have exactly one key (stroke, tube or ribbon), got 0",
        ),
        (
            curve_1(LINE3, r#"{"pipe": {"radius": 1}}"#),
            "curve 1: \"geometry\" has an unknown key \"pipe\"",
        ),
        (
            curve_1(LINE3, "[1]"),
            "curve 1: \"geometry\" must be an object",
        ),
        (
            curve_1(LINE3, r#"{"tube": 0.1}"#),
            "curve 1: \"tube\" must be an object of its fields, got 0.1",
        ),
        (
            curve_1(LINE3, r#"{"stroke": {"width": 0.1}}"#),
            "curve 1: \"geometry\" a stroke needs 2-D points, got 3 coordinates per point",
        ),
        (
            curve_1(LINE2, r#"{"ribbon": {"width": 0.1}}"#),
            "curve 1: \"geometry\" a ribbon needs 3-D points, got 2",
        ),
        (
            curve_1(LINE3, r#"{"tube": {"radius": 0}}"#),
            "curve 1: \"radius\" must be a finite number > 0, got radius = 0",
        ),
        (
            curve_1(LINE3, r#"{"tube": {"radius": [1, 1, -2, 1]}}"#),
            "curve 1: \"radius\" must be a finite number > 0, got radius[2] = -2",
        ),
        (
            curve_1(LINE3, r#"{"tube": {"radius": [1, 1, 1]}}"#),
            "curve 1: \"radius\" 3 values for 4 points",
        ),
        (
            curve_1(LINE3, r#"{"tube": {"radius": "thin"}}"#),
            "curve 1: \"radius\" must be a number, got \"thin\"",
        ),
        (
            curve_1(LINE3, r#"{"tube": {}}"#),
            "curve 1: \"radius\" is missing",
        ),
        (
            curve_1(LINE3, r#"{"ribbon": {"radius": 1}}"#),
            "curve 1: \"radius\" is not a field of a ribbon (allowed: width, up, dash, dash_offset)",
        ),
        (
            stroke(r#", "cap": "flat""#),
            "curve 1: \"cap\" must be \"butt\", \"round\" or \"square\", got \"flat\"",
        ),
        (
            stroke(r#", "join": "sharp""#),
            "curve 1: \"join\" must be \"miter\", \"round\" or \"bevel\", got \"sharp\"",
        ),
        (
            stroke(r#", "miter_limit": 0.5"#),
            "curve 1: \"miter_limit\" must be a finite number >= 1, got 0.5",
        ),
        (
            stroke(r#", "sides": 3"#),
            "curve 1: \"sides\" a stroke needs at least 4 sides, got 3",
        ),
        (
            tube(r#", "sides": 2"#),
            "curve 1: \"sides\" a tube needs at least 3 sides, got 2",
        ),
        (
            tube(r#", "sides": 2.5"#),
            "curve 1: \"sides\" must be an integer from 0 to 2^32 - 1, got 2.5",
        ),
        (
            tube(r#", "caps": "yes""#),
            "curve 1: \"caps\" must be true or false, got \"yes\"",
        ),
        (
            tube(r#", "up": [0, 1]"#),
            "curve 1: \"up\" must be an array of 3 finite numbers, got [0,1]",
        ),
        // The tangent at the start of the Catmull-Rom window is (P2 - P0) / 2 = (0.5, 0.5, 0).
        (
            tube(r#", "up": [2, 2, 0]"#),
            "curve 1: \"up\" [2.0, 2.0, 0.0] is parallel",
        ),
        (
            tube(r#", "dash": [1, 2, 3]"#),
            "curve 1: \"dash\" must hold an even number of lengths (on, off, ...), got 3",
        ),
        (
            tube(r#", "dash": [1, -1]"#),
            "curve 1: \"dash\" lengths must be finite and >= 0: dash[1] = -1",
        ),
        (
            tube(r#", "dash": [0, 0]"#),
            "curve 1: \"dash\" lengths must have a finite sum > 0, got 0",
        ),
        (
            tube(r#", "dash_offset": 1"#),
            "curve 1: \"dash_offset\" needs a \"dash\" pattern beside it",
        ),
        (
            doc(
                "",
                &format!(
                    r#"{LINE3}, "sampling": {{"at": [0.5]}}, "geometry": {{"tube": {{"radius": 1}}}}"#
                ),
            ),
            "curve 1: \"sampling\" \"at\" places no cross-sections",
        ),
        (doc("", LINE3), "curve 1: \"geometry\" is missing"),
        (
            doc(r#""derivatives": 1,"#, LINE3),
            "document: \"derivatives\" must be 0 with geometry",
        ),
        (
            doc(r#""geometry": {"tube": {"radius": -1}},"#, LINE3),
            "curve 1: \"radius\" must be a finite number > 0, got radius = -1",
        ),
        (
            doc(r#""geometry": {"tube": 1},"#, LINE3),
            "document: \"tube\" must be an object of its fields, got 1",
        ),
        (
            r#"{"geometry": {"tube": {"radius": 1}}, "surfaces": [{"kind": "bezier",
                "points": [[[0,0,0],[1,0,0],[2,0,0],[3,0,0]],[[0,1,0],[1,1,0],[2,1,0],[3,1,0]],
                [[0,2,0],[1,2,0],[2,2,0],[3,2,0]],[[0,3,0],[1,3,0],[2,3,0],[3,3,0]]]}]}"#
                .to_string(),
            "document: \"geometry\" is a field of curves documents",
        ),
        (
            r#"{"geometry": {"tube": {"radius": 1}}}"#.to_string(),
            "document: \"curves\" is missing",
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (doc, want) in &cases {
        for (name, backend) in [("out.csv", "cpu"), ("out.glb", "gpu"), ("out.npz", "auto")] {
            let (status, stderr) = tessellate(dir.path(), doc, name, backend);
            assert_eq!(status, 2, "{doc}: {stderr}");
            assert_eq!(stderr.lines().count(), 1, "{doc}: {stderr}");
            assert!(
                stderr.starts_with(&format!("splinegpu: {want}")),
                "{doc}: {stderr}"
            );
            assert!(!dir.path().join(name).exists(), "{doc}: {name} was written");
        }
    }
}

/// NPZ holds one array of points: a stroke (2-D) and a tube (3-D) cannot share it; the other
/// formats take them together.
#[test]
fn strokes_and_tubes_share_every_format_but_npz() {
    let doc = doc(
        "",
        &format!(r#"{LINE2}, "geometry": {{"stroke": {{"width": 0.1}}}}"#),
    );
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr) = tessellate(dir.path(), &doc, "out.npz", "cpu");
    assert_eq!(status, 2, "{stderr}");
    assert!(
        stderr.contains(
            "curve 1: \"geometry\" a stroke makes 2-D points but curve 0's tube makes 3-D"
        ),
        "{stderr}"
    );
    assert!(!dir.path().join("out.npz").exists());
    let (status, stderr) = tessellate(dir.path(), &doc, "out.csv", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let text = std::fs::read_to_string(dir.path().join("out.csv")).unwrap();
    assert!(text.starts_with("curve,vertex,t,x0,x1,x2,nx,ny,nz\n"));
    // The stroke's rows leave z and the normals empty.
    let stroke_row = text.lines().find(|l| l.starts_with("1,0,")).unwrap();
    assert!(stroke_row.ends_with(",,,,"), "{stroke_row}");
    assert_eq!(stroke_row.split(',').count(), 9);
    for name in ["out.json", "out.obj", "out.glb"] {
        let (status, stderr) = tessellate(dir.path(), &doc, name, "cpu");
        assert_eq!(status, 0, "{name}: {stderr}");
    }
}

/// A mesh whose vertices overflow f64 (rings of radius 1e308 about a line at x = 1e308, whose
/// fit is exact) is refused in every format, naming the curve and the vertex, with nothing
/// written.
#[test]
fn a_mesh_that_overflows_is_refused_in_every_format() {
    let doc = r#"{"sampling": {"per_segment": 2}, "geometry": {"tube": {"radius": 1e308}},
        "curves": [{"kind": "natural", "points": [[0,0,0],[1,0,0],[1,1,0],[0,1,1]]},
                   {"kind": "natural", "points": [[1e308,0,0],[1e308,1,0],[1e308,2,0],[1e308,3,0]]}]}"#;
    let dir = tempfile::tempdir().unwrap();
    for name in ["out.npz", "out.obj", "out.glb", "out.csv", "out.json"] {
        let (status, stderr) = tessellate(dir.path(), doc, name, "cpu");
        assert_eq!(status, 2, "{name}: {stderr}");
        assert!(
            stderr.contains("curve 1: mesh vertex 0 is not finite"),
            "{name}: {stderr}"
        );
        assert!(!dir.path().join(name).exists(), "{name} was written");
    }
}

/// `--backend gpu`: the same triangles, t and offsets, float32 points and normals near the
/// CPU's (the promise itself is the library's GPU tests'), and a document of strokes.
#[test]
fn the_gpu_backend_writes_float32_meshes_beside_the_cpus() {
    if !crate::shared::gpu_tests_run() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut arrays = Vec::new();
    for (name, backend) in [("cpu.npz", "cpu"), ("gpu.npz", "gpu")] {
        let (status, stderr) = tessellate(dir.path(), &document(), name, backend);
        assert_eq!(status, 0, "{backend}: {stderr}");
        arrays.push(crate::stream::read_npz(
            &std::fs::read(dir.path().join(name)).unwrap(),
        ));
    }
    let (cpu, gpu) = (&arrays[0], &arrays[1]);
    for name in ["t", "triangles", "curve_offsets", "triangle_offsets"] {
        assert_eq!(cpu[name], gpu[name], "{name}");
    }
    for name in ["points", "normals"] {
        assert_eq!(gpu[name].0, "<f4", "{name}");
        let want: Vec<f64> = bytemuck::pod_collect_to_vec(&cpu[name].2);
        let got: Vec<f32> = bytemuck::pod_collect_to_vec(&gpu[name].2);
        for (w, g) in want.iter().zip(&got) {
            assert!((w - f64::from(*g)).abs() < 1e-4, "{name}: {w} against {g}");
        }
    }
    let doc = doc(
        "",
        &format!(r#"{LINE2}, "geometry": {{"stroke": {{"width": 0.1}}}}"#),
    );
    let (status, stderr) = tessellate(dir.path(), &doc, "mixed.json", "gpu");
    assert_eq!(status, 0, "{stderr}");
}

/// Tolerance cross-sections through the command line: the library's meshes (a tube whose
/// sides the method chooses and a ribbon), and what the tolerance cannot be certified for
/// refused by name with nothing written.
#[test]
fn tolerance_geometry_is_the_librarys_and_its_limits_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        r#"{{"sampling": {{"tolerance": 0.002}}, "curves": [
 {{{LINE3}, "geometry": {{"tube": {{"radius": 0.1}}}}}},
 {{{LINE3}, "geometry": {{"ribbon": {{"width": 0.2}}}}}}]}}"#
    );
    let (status, stderr) = tessellate(dir.path(), &text, "out.json", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out.json")).unwrap())
            .unwrap();
    let line = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 1.0],
    ];
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Control,
    };
    let mut job = GeometryJob::new();
    let sampling = Sampling::Tolerance(0.002);
    for geometry in [
        Geometry::Tube(Tube {
            radius: Width::Constant(0.1),
            ..Tube::default()
        }),
        Geometry::Ribbon(Ribbon {
            width: Width::Constant(0.2),
            ..Ribbon::default()
        }),
    ] {
        job.push(&curve(kind.clone(), &line), &geometry, &sampling)
            .unwrap();
    }
    let want = job.evaluate_cpu();
    for (c, mesh) in json["meshes"].as_array().unwrap().iter().enumerate() {
        let v = range(&want.vertex_offsets, c);
        assert_eq!(
            numbers(&mesh["points"]),
            want.points[3 * v.start..3 * v.end]
        );
        assert_eq!(numbers(&mesh["t"]), want.t[v]);
    }
    // The sides chosen leave the rings room: more than the default 8 at this tolerance.
    let rings = |c: usize| {
        let v = range(&want.vertex_offsets, c);
        let mut t = want.t[v].to_vec();
        t.dedup();
        t.len()
    };
    let tube_vertices = (want.vertex_offsets[1] - want.vertex_offsets[0]) as usize;
    assert!(
        tube_vertices / rings(0) > 8,
        "{tube_vertices} vertices in {} rings",
        rings(0)
    );
    let cases = [
        (
            r#"{"tube": {"radius": 0.1, "sides": 4}}"#,
            "curve 1: \"sides\" 4 sides stray",
        ),
        (
            r#"{"tube": {"radius": 0.1, "up": [1, 2]}}"#,
            "curve 1: \"up\"",
        ),
    ];
    for (geometry, want) in cases {
        let text = doc(
            r#""sampling": {"tolerance": 0.002},"#,
            &format!(r#"{LINE3}, "geometry": {geometry}"#),
        );
        let (status, stderr) = tessellate(dir.path(), &text, "bad.json", "cpu");
        assert_eq!(status, 2, "{text}: {stderr}");
        assert!(stderr.contains(want), "{text}: {stderr}");
        assert!(!dir.path().join("bad.json").exists());
    }
    // A tolerance no polygon of at most 2^20 sides meets.
    let fine = doc(
        r#""sampling": {"tolerance": 1e-300},"#,
        &format!(r#"{LINE3}, "geometry": {{"tube": {{"radius": 0.1}}}}"#),
    );
    let (status, stderr) = tessellate(dir.path(), &fine, "bad.json", "cpu");
    assert_eq!(status, 2, "{stderr}");
    assert!(
        stderr.contains("curve 0: \"tolerance\" 1e-300 asks more than 2^20 sides"),
        "{stderr}"
    );
    // A Bezier chain that turns a corner: one ring cannot stand for both sides' circles.
    let corner = r#"{"curves": [{"kind": "bezier", "sampling": {"tolerance": 0.01},
 "points": [[0,0,0],[1,0,0],[2,0,0],[3,0,0],[3,1,0],[3,2,0],[3,3,0]],
 "geometry": {"tube": {"radius": 0.1}}}]}"#;
    let (status, stderr) = tessellate(dir.path(), corner, "bad.json", "cpu");
    assert_eq!(status, 2, "{stderr}");
    assert!(
        stderr.contains("curve 0: \"tolerance\" cannot be certified across the corner at t = 1"),
        "{stderr}"
    );
}

/// A dashed tube through the command line is the library's dashed mesh (its pattern and
/// offset read from "dash" and "dash_offset").
#[test]
fn dashes_are_read_into_the_library_pattern() {
    let text = format!(
        r#"{{"sampling": {{"arc_length": 33}}, "curves": [{{"kind": "catmull-rom",
            "points": {}, "geometry": {{"tube": {{"radius": 0.1, "caps": true,
            "dash": [0.5, 0.25], "dash_offset": 0.1}}}}}}]}}"#,
        serde_json::to_string(&TUBE_POINTS).unwrap()
    );
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr) = tessellate(dir.path(), &text, "out.json", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out.json")).unwrap())
            .unwrap();
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Control,
    };
    let tube = Geometry::Tube(Tube {
        radius: Width::Constant(0.1),
        caps: true,
        dash: Some(splinegpu::geometry::Dash {
            lengths: vec![0.5, 0.25],
            offset: 0.1,
        }),
        ..Tube::default()
    });
    let mut job = GeometryJob::new();
    job.push(&curve(kind, &TUBE_POINTS), &tube, &Sampling::ArcLength(33))
        .unwrap();
    let want = job.evaluate_cpu();
    let mesh = &json["meshes"][0];
    assert_eq!(numbers(&mesh["points"]), want.points);
    assert_eq!(numbers(&mesh["t"]), want.t);
    assert!(want.triangles.len() > 100);
}

/// One tube mesh of 3.2 M vertices near a 512 MiB address-space limit (`ulimit -v`) ends with
/// exit 0 and a whole file, or exit 2 naming "sampling" and no file: the meshes' allocations
/// are fallible, JSON writes a mesh's text as it goes and NPZ its indices in runs (the JSON
/// text of the whole mesh and the NPZ's shifted indices aborted with exit 134, "memory
/// allocation of ... bytes failed", before).
#[test]
fn geometry_near_the_process_memory_limit_never_aborts() {
    let dir = tempfile::tempdir().unwrap();
    let doc = r#"{"sampling": {"per_segment": 20000}, "curves": [{"kind": "catmull-rom",
        "points": [[0,0,0],[1,0,0],[1,1,0],[0,1,1],[0,2,2]],
        "geometry": {"tube": {"radius": 0.1, "sides": 80}}}]}"#;
    let input = dir.path().join("near.json");
    std::fs::write(&input, doc).unwrap();
    for format in ["json", "npz"] {
        let output = dir.path().join(format!("near-out.{format}"));
        let out = crate::support::tessellate_under_limit(524288, &input, &output);
        let stderr = String::from_utf8_lossy(&out.stderr);
        match out.status.code() {
            Some(0) => assert!(output.exists(), "{format}"),
            Some(2) => {
                assert!(stderr.contains("\"sampling\""), "{format}: {stderr}");
                assert!(!output.exists(), "{format}");
            }
            other => panic!("{format}: exit {other:?}: {stderr}"),
        }
        let _ = std::fs::remove_file(&output);
    }
}
