//! Surface documents through the binary: JSON that parses back to the library's values, CSV's
//! header and rows, meshes (.obj, .glb read back by the gltf crate), and every bad surface
//! exiting 2 with one message naming the surface, the field and the value, writing nothing;
//! the teapot example; the GPU backend's f32 values beside the CPU's.

use std::path::Path;

use serde_json::Value;
use splinegpu::Derivatives;
use splinegpu::surface::{Net, Surface, SurfaceJob, SurfaceKind, SurfaceSampling};

fn run(args: &[&str]) -> (i32, String) {
    let out = crate::support::run_cli(args, &[], "");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn tessellate(dir: &Path, doc: &str, name: &str, backend: &str) -> (i32, String) {
    let input = dir.join("surfaces.json");
    std::fs::write(&input, doc).unwrap();
    let out = dir.join(name);
    run(&[
        "tessellate",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--backend",
        backend,
    ])
}

/// A closed bspline torus-like net, 6 x 5.
fn ring_net() -> Vec<Vec<[f64; 3]>> {
    (0..6)
        .map(|i| {
            (0..5)
                .map(|j| {
                    let (a, b) = (f64::from(i) * 1.047, f64::from(j) * 1.2566);
                    let r = 3.0 + b.cos();
                    [r * a.cos(), r * a.sin(), b.sin()]
                })
                .collect()
        })
        .collect()
}

/// One Bezier patch as a patch list, and its 16 points.
const PATCH_POINTS: &str = "[[0,0,0],[1,0,0],[2,0,0],[3,0,1],[0,1,0],[1,1,1],[2,1,1],[3,1,0],\
[0,2,0],[1,2,1],[2,2,1],[3,2,0],[0,3,1],[1,3,0],[2,3,0],[3,3,0]]";

/// The document's first surface (the closed ring at per_segment [3, 2]) through the library.
fn ring_samples() -> splinegpu::surface::SurfaceSamples {
    let coords: Vec<f64> = ring_net().iter().flatten().flatten().copied().collect();
    let kind = SurfaceKind::Uniform {
        basis: splinegpu::Basis::BSpline,
        ends: [splinegpu::Ends::Closed; 2],
    };
    let table = Surface::new(kind, Net::new(3, 6, 5, coords).unwrap())
        .unwrap()
        .fit();
    let mut job = SurfaceJob::new(Derivatives::Second, true);
    job.push(table, SurfaceSampling::PerSegment([3, 2]))
        .unwrap();
    job.evaluate_cpu().remove(0)
}

fn document() -> String {
    let net = serde_json::to_string(&ring_net()).unwrap();
    format!(
        r#"{{"sampling": {{"per_segment": [3, 2]}}, "derivatives": 2, "normals": true,
  "surfaces": [
    {{"kind": "bspline", "ends": ["closed", "closed"], "points": {net}}},
    {{"kind": "bezier", "points": {PATCH_POINTS}, "patches": [[0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15]],
      "sampling": {{"per_segment": 2}}}},
    {{"kind": "nurbs", "knots_u": [0,0,0,0,1,1,1,1], "knots_v": [0,0,0,0,0.5,2,2,2,2],
      "weights": [[1,2,1,1,1],[1,1,1,0.5,1],[1,1,1,1,1],[3,1,1,1,1]],
      "points": [[[0,0,0],[0,1,0],[0,2,1],[0,3,0],[0,4,0]],[[1,0,1],[1,1,2],[1,2,0],[1,3,1],[1,4,0]],
                 [[2,0,0],[2,1,1],[2,2,1],[2,3,2],[2,4,1]],[[3,0,0],[3,1,0],[3,2,1],[3,3,0],[3,4,1]]],
      "sampling": {{"at": [[0, 0], [0.5, 1.25], [1, 2]]}}}}
  ]}}"#
    )
}

#[test]
fn json_output_parses_back_to_the_library_values() {
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr) = tessellate(dir.path(), &document(), "out.json", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let out: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out.json")).unwrap())
            .unwrap();
    let surfaces = out["surfaces"].as_array().unwrap();
    assert_eq!(surfaces.len(), 3);
    // The closed torus: 18 x 10 vertices, two triangles per cell, no "patch".
    let want = ring_samples();
    let got = &surfaces[0];
    let flat = |key: &str| -> Vec<f64> {
        got[key]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
            .collect()
    };
    assert_eq!(flat("points"), want.points);
    assert_eq!(flat("duv"), *want.duv.as_ref().unwrap());
    assert_eq!(flat("normals"), *want.normals.as_ref().unwrap());
    assert_eq!(got["triangles"].as_array().unwrap().len(), 2 * 18 * 10);
    assert!(got.get("patch").is_none());
    // The patch list carries "patch"; "at" makes no triangles.
    assert_eq!(surfaces[1]["patch"].as_array().unwrap().len(), 9);
    assert!(surfaces[2].get("triangles").is_none());
    assert_eq!(surfaces[2]["uv"][1], serde_json::json!([0.5, 1.25]));
}

/// Every format is written chunk by chunk, a surface larger than a chunk in pieces (issue 47,
/// item 9): with chunks of 7 and 25 vertices (a closed net a line at a time, an open net, a
/// tolerance mesh and welded patch lists cut out of their plans, explicit (u, v)) the file is
/// byte for byte the one written in one chunk, in every format, on both backends.
#[test]
fn every_format_is_the_same_written_in_pieces() {
    let dir = tempfile::tempdir().unwrap();
    let net = serde_json::to_string(&ring_net()).unwrap();
    let meshes = format!(
        r#"{{"sampling": {{"per_segment": [3, 2]}}, "derivatives": 1, "normals": true,
  "surfaces": [
    {{"kind": "bspline", "ends": ["closed", "closed"], "points": {net}}},
    {{"kind": "bezier", "points": {PATCH_POINTS}, "patches": [[0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15]],
      "sampling": {{"per_segment": 5}}}},
    {{"kind": "catmull-rom", "points": {net}, "sampling": {{"per_segment": [2, 5]}}}},
    {{"kind": "bspline", "points": {net}, "sampling": {{"tolerance": 0.01}}}}
  ]}}"#
    );
    let documents = [
        (meshes.as_str(), &["csv", "json", "npz", "obj", "glb"][..]),
        (&document(), &["csv", "json", "npz"][..]),
    ];
    for (doc, formats) in documents {
        let input = dir.path().join("in.json");
        std::fs::write(&input, doc).unwrap();
        for backend in ["cpu", "gpu"] {
            for format in formats {
                let write = |chunk: &str| -> Vec<u8> {
                    let out = dir.path().join(format!("out-{chunk}.{format}"));
                    let args = [
                        "tessellate",
                        input.to_str().unwrap(),
                        "-o",
                        out.to_str().unwrap(),
                        "--backend",
                        backend,
                    ];
                    let envs = [("SPLINEGPU_CHUNK_SAMPLES", chunk)];
                    let run = crate::support::run_cli(&args, &envs, "");
                    let stderr = String::from_utf8_lossy(&run.stderr);
                    assert!(run.status.success(), "{backend} {format} {chunk}: {stderr}");
                    std::fs::read(out).unwrap()
                };
                let whole = write("1000000");
                for chunk in ["7", "25"] {
                    assert!(
                        write(chunk) == whole,
                        "{backend} {format}: chunks of {chunk} differ from one chunk"
                    );
                }
            }
        }
    }
}

/// NPZ is written group by group (SPLINEGPU_CHUNK_SAMPLES=20: the torus alone, its plan made
/// again; then the other two), byte for byte as in one group, with the library's values, the
/// triangles indexing the whole vertex array, the offsets and the patch column.
#[test]
fn npz_streams_in_groups_with_the_library_values() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("surfaces.json");
    std::fs::write(&input, document()).unwrap();
    let write = |name: &str, envs: &[(&str, &str)]| {
        let out = dir.path().join(name);
        let args = [
            "tessellate",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        let run = crate::support::run_cli(&[&args[..], &["--backend", "cpu"]].concat(), envs, "");
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
    assert_eq!(arrays["uv"].1, [192, 2]);
    assert_eq!(arrays["points"].0, "<f8");
    assert_eq!(arrays["normals"].1, [192, 3]);
    assert_eq!(i64s("surface_offsets"), [0, 180, 189, 192]);
    assert_eq!(i64s("triangle_offsets"), [0, 360, 368, 368]);
    let want = ring_samples();
    assert_eq!(f64s("points")[..540], want.points);
    assert_eq!(f64s("dvv")[..540], *want.dvv.as_ref().unwrap());
    let triangles = i64s("triangles");
    assert_eq!(triangles.len(), 368 * 3);
    let first: Vec<i64> = want
        .triangles
        .unwrap()
        .iter()
        .flatten()
        .map(|&i| i64::from(i))
        .collect();
    assert_eq!(triangles[..1080], first);
    assert!(triangles[1080..].iter().all(|&i| (180..189).contains(&i)));
    let patch = i64s("patch");
    assert!(patch[..180].iter().chain(&patch[189..]).all(|&p| p == -1));
    assert!(patch[180..189].iter().all(|&p| p == 0));
}

#[test]
fn csv_has_the_contracts_header_and_one_row_per_vertex() {
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr) = tessellate(dir.path(), &document(), "out.csv", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let text = std::fs::read_to_string(dir.path().join("out.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "surface,sample,u,v,x0,x1,x2,dux0,dux1,dux2,dvx0,dvx1,dvx2,duux0,duux1,duux2,\
         duvx0,duvx1,duvx2,dvvx0,dvvx1,dvvx2,nx,ny,nz,patch"
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 180 + 9 + 3);
    assert!(rows[0].starts_with("0,0,0.0,0.0,") && rows[0].ends_with(','));
    assert!(rows[180].starts_with("1,0,0.0,0.0,0.0,0.0,0.0,") && rows[180].ends_with(",0"));
}

#[test]
fn meshes_open_as_they_are() {
    let dir = tempfile::tempdir().unwrap();
    // Meshes need triangles: the "at" surface is left out.
    let doc = document();
    let meshes = doc[..doc.find(",\n    {\"kind\": \"nurbs\"").unwrap()].to_string() + "\n  ]}";
    let (status, stderr) = tessellate(dir.path(), &meshes, "out.glb", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let bytes = std::fs::read(dir.path().join("out.glb")).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let names: Vec<_> = gltf
        .meshes()
        .map(|m| m.name().unwrap().to_string())
        .collect();
    assert_eq!(names, ["surface-0", "surface-1"]);
    let primitive = gltf.meshes().next().unwrap().primitives().next().unwrap();
    assert_eq!(
        primitive.get(&gltf::Semantic::Positions).unwrap().count(),
        180
    );
    assert_eq!(
        primitive.get(&gltf::Semantic::Normals).unwrap().count(),
        180
    );
    assert_eq!(primitive.indices().unwrap().count(), 3 * 360);
    // The binary chunk, streamed after the JSON, holds what its views say: positions within
    // the accessor's bounds, unit normals, indices within each mesh's vertices.
    let blob = gltf.blob.as_deref().unwrap();
    // An accessor's values as 4-byte little-endian words.
    let words = |a: gltf::Accessor<'_>, width: usize| -> Vec<[u8; 4]> {
        let at = a.view().unwrap().offset() + a.offset();
        blob[at..at + 4 * width * a.count()]
            .chunks_exact(4)
            .map(|w| [w[0], w[1], w[2], w[3]])
            .collect()
    };
    for mesh in gltf.meshes() {
        let primitive = mesh.primitives().next().unwrap();
        let bounds = primitive.bounding_box();
        let positions: Vec<f32> = words(primitive.get(&gltf::Semantic::Positions).unwrap(), 3)
            .into_iter()
            .map(f32::from_le_bytes)
            .collect();
        for p in positions.chunks_exact(3) {
            assert!((0..3).all(|k| p[k] >= bounds.min[k] && p[k] <= bounds.max[k]));
        }
        let normals: Vec<f32> = words(primitive.get(&gltf::Semantic::Normals).unwrap(), 3)
            .into_iter()
            .map(f32::from_le_bytes)
            .collect();
        for n in normals.chunks_exact(3) {
            assert!((n[0].hypot(n[1]).hypot(n[2]) - 1.0).abs() < 1e-5, "{n:?}");
        }
        let indices = words(primitive.indices().unwrap(), 1);
        assert!(
            indices
                .into_iter()
                .all(|i| (u32::from_le_bytes(i) as usize) < positions.len() / 3)
        );
    }
    let (status, stderr) = tessellate(dir.path(), &meshes, "out.obj", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let obj = std::fs::read_to_string(dir.path().join("out.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 189);
    assert_eq!(obj.lines().filter(|l| l.starts_with("vn ")).count(), 189);
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 360 + 8);
    // Faces index the whole file's vertices from 1: the patch's start after the torus's 180.
    assert!(obj.contains("o surface-1") && obj.contains("f 181//181 "));
}

#[test]
fn bad_surfaces_exit_2_naming_the_surface_the_field_and_the_value() {
    let cases: [(&str, &[&str]); 12] = [
        (
            r#"{"surfaces": [{"kind": "bspline", "points": [[[0,0,0],[1,0,0],[2,0,0],[3,0,0]],[[0,1,0],[1,1,0],[2,1,0]]]}]}"#,
            &["surface 0", "\"points\"", "points[1] has 3 points, points[0] has 4"],
        ),
        (
            &r#"{"surfaces": [{"kind": "bspline", "points": [[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]]]}, {"kind": "bezier", "points": PTS, "patches": [[0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,16]]}]}"#
                .replace("PTS", PATCH_POINTS),
            &["surface 1", "\"patches\"", "patches[0][15] = 16"],
        ),
        (
            r#"{"surfaces": [{"kind": "nurbs", "knots_u": [0,0,0,0,1,1,1], "knots_v": [0,0,0,0,1,1,1,1], "points": [[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]]]}]}"#,
            &["surface 0", "\"knots_u\"", "got 7"],
        ),
        (
            r#"{"surfaces": [{"kind": "nurbs", "knots_u": [0,0,0,0,1,1,1,1], "knots_v": [0,0,0,0,1,1,1,1], "weights": [[1,1],[1,1],[1,1],[1,1],[1,1],[1,1],[1,1],[1,1]], "points": [[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]]]}]}"#,
            &["surface 0", "\"weights\"", "4 x 4, got 8 x 2"],
        ),
        (
            r#"{"sampling": {"arc_length": 10}, "surfaces": [{"kind": "bspline", "points": [[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]]]}]}"#,
            &["surface 0", "\"sampling\"", "arc_length"],
        ),
        (
            r#"{"normals": true, "surfaces": [{"kind": "bspline", "points": [[[0,0],[1,0],[2,0],[3,0]],[[0,1],[1,1],[2,1],[3,1]],[[0,2],[1,2],[2,2],[3,2]],[[0,3],[1,3],[2,3],[3,3]]]}]}"#,
            &["surface 0", "\"normals\"", "got 2 coordinates"],
        ),
        (
            r#"{"curves": [{"kind": "bspline", "points": [[0],[1],[2],[3]]}], "surfaces": [{"kind": "bspline", "points": [[[0]]]}]}"#,
            &["document:", "\"surfaces\"", "\"curves\""],
        ),
        (
            r#"{"surfaces": [{"kind": "bspline", "ends": "closed", "points": [[[0],[1],[2]],[[0],[1],[2]],[[0],[1],[2]]], "sampling": {"at": [[0, 0], [3.5, 1]]}}]}"#,
            &["surface 0", "\"sampling\"", "at[1] = [3.5, 1]"],
        ),
        (
            r#"{"surfaces": [{"kind": "interpolating", "conditions": ["natural", "periodic"], "points": [[[0],[1],[2]],[[0],[1],[2]]]}]}"#,
            &["surface 0", "\"points\"", "must close up along v"],
        ),
        (
            r#"{"surfaces": [{"kind": "beta", "bias": [1, 2, 1, 1], "points": [[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]]]}]}"#,
            &["surface 0", "\"bias\"", "must be a number for a surface"],
        ),
        (
            // 3.6e9 vertices of a patch list (under the u32 cap), whose plan alone would take
            // 230 GB: refused before it is made. (A net's grid streams line by line instead.)
            &format!(r#"{{"sampling": {{"per_segment": 60000}}, "surfaces": [{{"kind": "bezier", "points": {PATCH_POINTS}, "patches": [[0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15]]}}]}}"#),
            &["surface 0", "\"sampling\"", "3600120001 vertices", "bytes of memory available"],
        ),
        (
            r#"{"surfaces": [{"kind": "catmull-rom", "tension": 0.5, "points": [[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]],[[0],[1],[2],[3]]]}]}"#,
            &["surface 0", "\"tension\"", "is not a field of a \"catmull-rom\" surface"],
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (doc, names) in &cases {
        for (name, backend) in [("out.csv", "cpu"), ("out.glb", "gpu"), ("out.npz", "auto")] {
            let (status, stderr) = tessellate(dir.path(), doc, name, backend);
            assert_eq!(status, 2, "{doc}: {stderr}");
            assert_eq!(stderr.lines().count(), 1, "{stderr}");
            for n in *names {
                assert!(stderr.contains(n), "{doc}: {stderr} lacks {n}");
            }
            assert!(!dir.path().join(name).exists());
        }
    }
    // Meshes need 3-D triangles: "at" makes none.
    let at = r#"{"surfaces": [{"kind": "bspline", "points": [[[0,0,0],[1,0,0],[2,0,0],[3,0,0]],[[0,1,0],[1,1,0],[2,1,0],[3,1,0]],[[0,2,0],[1,2,0],[2,2,0],[3,2,0]],[[0,3,0],[1,3,0],[2,3,0],[3,3,0]]], "sampling": {"at": [[0.5, 0.5]]}}]}"#;
    let (status, stderr) = tessellate(dir.path(), at, "out.obj", "cpu");
    assert_eq!(status, 2);
    assert!(
        stderr.contains("surface 0: \"sampling\"") && stderr.contains(".obj"),
        "{stderr}"
    );
}

#[test]
fn the_teapot_example_meshes_within_its_tolerance_on_both_backends() {
    let dir = tempfile::tempdir().unwrap();
    let teapot = include_str!("../../examples/teapot.json");
    let (status, stderr) = tessellate(dir.path(), teapot, "teapot.glb", "cpu");
    assert_eq!(status, 0, "{stderr}");
    let bytes = std::fs::read(dir.path().join("teapot.glb")).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let primitive = gltf.meshes().next().unwrap().primitives().next().unwrap();
    assert!(primitive.get(&gltf::Semantic::Normals).is_some());
    assert!(primitive.indices().unwrap().count() > 3 * 1000);
    // The GPU backend: the same vertices and triangles, f32 values near the CPU's.
    if !crate::shared::gpu_tests_run() {
        return;
    }
    let mut values = Vec::new();
    for (name, backend) in [("cpu.json", "cpu"), ("gpu.json", "gpu")] {
        let (status, stderr) = tessellate(dir.path(), &document(), name, backend);
        assert_eq!(status, 0, "{stderr}");
        let text = std::fs::read_to_string(dir.path().join(name)).unwrap();
        values.push(serde_json::from_str::<Value>(&text).unwrap());
    }
    let (cpus, gpus) = (&values[0]["surfaces"], &values[1]["surfaces"]);
    for (s, (cpu, gpu)) in cpus
        .as_array()
        .unwrap()
        .iter()
        .zip(gpus.as_array().unwrap())
        .enumerate()
    {
        assert_eq!(cpu["uv"], gpu["uv"]);
        assert_eq!(cpu["triangles"], gpu["triangles"]);
        let flat = |v: &Value| -> Vec<f64> {
            v["points"]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
                .collect()
        };
        for (c, g) in flat(cpu).iter().zip(flat(gpu)) {
            assert!(
                (c - g).abs() < 1e-4 * (1.0 + c.abs()),
                "surface {s}: {c} vs {g}"
            );
        }
    }
}

/// Under an address-space limit (`ulimit -v`, 512 MiB), a surface whose plan must be whole (a
/// patch list at per_segment 4096: 16.8 M vertices, 1.07 GB of plan) exits 2 naming its
/// sampling, before it allocates, and writes nothing: the guard read the machine's memory
/// alone, and the process aborted (exit 134) mid-allocation.
#[test]
fn a_surface_over_the_process_memory_limit_exits_2_before_it_allocates() {
    let dir = tempfile::tempdir().unwrap();
    let doc = format!(
        r#"{{"surfaces": [{{"kind": "bezier", "points": {PATCH_POINTS}, "patches": [[0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15]], "sampling": {{"per_segment": 4096}}}}]}}"#
    );
    let input = dir.path().join("big.json");
    std::fs::write(&input, doc).unwrap();
    let output = dir.path().join("big.npz");
    let out = crate::support::tessellate_under_limit(524288, &input, &output);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("surface 0") && stderr.contains("sampling") && stderr.contains("bytes"),
        "{stderr}"
    );
    assert!(!output.exists());
}

/// Under the same limit, a per_segment net whose samples would not fit whole streams within
/// one surface, line by line (issue 47, item 9): a 1-D net at [3000, 3000] (9.0 M vertices,
/// about 1 GB of plan and samples whole) as CSV, and a 3-D one at [2500, 2500] with normals
/// (6.25 M vertices) as .glb, each through a pipe, exit 0 and whole (every row; the .glb's
/// length in its header). Both were refused (exit 2) or aborted before.
#[test]
fn a_surface_larger_than_memory_streams_within_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let net = |dim: usize| -> String {
        let net: Vec<Vec<Vec<f64>>> = (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| [f64::from(i * j % 3), f64::from(i), f64::from(j)][..dim].to_vec())
                    .collect()
            })
            .collect();
        serde_json::to_string(&net).unwrap()
    };
    let input = dir.path().join("flat.json");
    std::fs::write(
        &input,
        format!(
            r#"{{"surfaces": [{{"kind": "bspline", "points": {}, "sampling": {{"per_segment": [3000, 3000]}}}}]}}"#,
            net(1)
        ),
    )
    .unwrap();
    let (status, _, lines, _, stderr) =
        crate::support::tessellate_to_pipe_under_limit(524288, &input, "csv");
    assert_eq!(status, Some(0), "{stderr}");
    assert_eq!(lines, 1 + 3001 * 3001);
    let input = dir.path().join("solid.json");
    std::fs::write(
        &input,
        format!(
            r#"{{"normals": true, "surfaces": [{{"kind": "bspline", "points": {}, "sampling": {{"per_segment": [2500, 2500]}}}}]}}"#,
            net(3)
        ),
    )
    .unwrap();
    let (status, bytes, _, _, stderr) =
        crate::support::tessellate_to_pipe_under_limit(524288, &input, "glb");
    assert_eq!(status, Some(0), "{stderr}");
    // Positions and normals (12 bytes each a vertex) and three u32 a triangle, after the JSON.
    let (vertices, triangles) = (2501u64 * 2501, 2 * 2500u64 * 2500);
    assert!(bytes > 24 * vertices + 12 * triangles, "{bytes} bytes");
}

/// A surface whose values overflow f64 (a cardinal net of tension 1e308) is refused in every
/// format, exit 2 naming the surface and the vertex, and no output file appears (NPZ, .obj and
/// .glb wrote its NaN vertices with exit 0 before).
#[test]
fn a_surface_that_overflows_is_refused_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let doc = format!(
        r#"{{"sampling": {{"per_segment": 2}}, "surfaces": [
  {{"kind": "bezier", "points": {PATCH_POINTS}, "patches": [[0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15]]}},
  {{"kind": "cardinal", "tension": 1e308, "points": [[[0,0,0],[0,1,0],[0,2,1],[0,3,0]],
    [[1,0,1],[1,1,2],[1,2,0],[1,3,1]],[[2,0,0],[2,1,1],[2,2,1],[2,3,2]],[[3,0,0],[3,1,0],[3,2,1],[3,3,0]]]}}
]}}"#
    );
    for name in ["out.npz", "out.obj", "out.glb", "out.csv", "out.json"] {
        let (code, stderr) = tessellate(dir.path(), &doc, name, "cpu");
        assert_eq!(code, 2, "{name}: {stderr}");
        assert!(
            stderr.contains("surface 1: vertex") && stderr.contains("not finite"),
            "{name}: {stderr}"
        );
        assert!(!dir.path().join(name).exists(), "{name} was written");
    }
}
