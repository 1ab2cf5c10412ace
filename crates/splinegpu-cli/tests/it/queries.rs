//! `splinegpu query` through the binary: closest points and intersections on curves, closest
//! points and rays on surfaces, in every format against hand-derived answers and the
//! library's, every bad query exiting 2 with one message naming the field and the query's
//! index and writing nothing, and the GPU backend's answers in f32 within its bound.

use std::path::Path;

use serde_json::Value;

/// Runs `splinegpu query` on `doc` into `dir/name` (extra `args` after), returning the exit
/// status, standard error and the output's bytes (None when no file was left).
fn query(dir: &Path, doc: &str, name: &str, args: &[&str]) -> (i32, String, Option<Vec<u8>>) {
    let input = dir.join("query.json");
    std::fs::write(&input, doc).unwrap();
    let out = dir.join(name);
    let _ = std::fs::remove_file(&out);
    let mut all = vec![
        "query",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let run = crate::support::run_cli(&all, &[], "");
    (
        run.status.code().unwrap_or(-1),
        String::from_utf8(run.stderr).unwrap(),
        std::fs::read(&out).ok(),
    )
}

/// Two straight Bezier segments, y = 0 and y = 5 for x in [0, 3] (evenly spaced control
/// points, so x = 3t), and three points whose answers follow by hand: (1.5, 2) is 2 above
/// curve 0 at t = 1/2; (1, 4) is 1 below curve 1 at t = 1/3; (-1, -1) is nearest to curve 0's
/// start, at √2.
const LINES: &str = r#"{"curves": [
  {"kind": "bezier", "points": [[0, 0], [1, 0], [2, 0], [3, 0]]},
  {"kind": "bezier", "points": [[0, 5], [1, 5], [2, 5], [3, 5]]}],
 "queries": {"closest": [[1.5, 2], [1, 4], [-1, -1]]}}"#;

/// (curve, t, point, distance) of each of LINES' queries.
fn lines_answers() -> [(i64, f64, [f64; 2], f64); 3] {
    [
        (0, 0.5, [1.5, 0.0], 2.0),
        (1, 1.0 / 3.0, [1.0, 5.0], 1.0),
        (0, 0.0, [0.0, 0.0], 2f64.sqrt()),
    ]
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12
}

#[test]
fn closest_points_in_every_format_are_the_hand_derived_ones() {
    let dir = tempfile::tempdir().unwrap();
    let want = lines_answers();
    // JSON.
    let (status, stderr, out) = query(dir.path(), LINES, "out.json", &["--backend", "cpu"]);
    assert_eq!(status, 0, "{stderr}");
    let json: Value = serde_json::from_slice(&out.unwrap()).unwrap();
    let rows = json["closest"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    for (row, (curve, t, point, distance)) in rows.iter().zip(want) {
        assert_eq!(row["curve"].as_i64(), Some(curve), "{row}");
        assert!(close(row["t"].as_f64().unwrap(), t), "{row}");
        for k in 0..2 {
            assert!(close(row["point"][k].as_f64().unwrap(), point[k]), "{row}");
        }
        assert!(close(row["distance"].as_f64().unwrap(), distance), "{row}");
    }
    // CSV: the contract's header, one row a query, the same numbers.
    let (status, stderr, out) = query(dir.path(), LINES, "out.csv", &[]);
    assert_eq!(status, 0, "{stderr}");
    let text = String::from_utf8(out.unwrap()).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("query,curve,t,x0,x1,distance"));
    for (i, (line, (curve, t, point, distance))) in lines.zip(want).enumerate() {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!((v[0], v[1]), (i as f64, curve as f64), "{line}");
        assert!(
            close(v[2], t) && close(v[3], point[0]) && close(v[4], point[1]),
            "{line}"
        );
        assert!(close(v[5], distance), "{line}");
    }
    // NPZ: the JSON keys as arrays.
    let (status, stderr, out) = query(dir.path(), LINES, "out.npz", &[]);
    assert_eq!(status, 0, "{stderr}");
    let arrays = crate::stream::read_npz(&out.unwrap());
    let f64s = |name: &str| -> Vec<f64> { bytemuck::pod_collect_to_vec(&arrays[name].2) };
    let curves: Vec<i64> = bytemuck::pod_collect_to_vec(&arrays["curve"].2);
    assert_eq!(arrays["point"].1, [3, 2]);
    assert_eq!(arrays["curve"].0, "<i8");
    for (i, (curve, t, point, distance)) in want.into_iter().enumerate() {
        assert_eq!(curves[i], curve);
        assert!(close(f64s("t")[i], t) && close(f64s("distance")[i], distance));
        assert!(close(f64s("point")[2 * i], point[0]) && close(f64s("point")[2 * i + 1], point[1]));
    }
}

#[test]
fn the_command_line_gives_the_librarys_answers() {
    use splinegpu::query::CurveIndex;
    let doc = r#"{"curves": [
      {"kind": "catmull-rom", "points": [[0, 0], [1, 2], [2, -1], [3, 1], [4, 0]]},
      {"kind": "natural", "t": [0, 0.5, 3, 3.1], "points": [[0, 1], [2, 2], [1, -1], [4, 3]]}],
     "queries": {"closest": [[0.5, 0.5], [2, 2], [3.5, -2], [10, 10], [1.2, 0.3]]}}"#;
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr, out) = query(dir.path(), doc, "out.json", &[]);
    assert_eq!(status, 0, "{stderr}");
    let json: Value = serde_json::from_slice(&out.unwrap()).unwrap();
    let Ok(splinegpu_cli::Document::Query(document)) = splinegpu_cli::parse_input(doc) else {
        panic!("not a query document");
    };
    let (
        splinegpu_cli::document::queries::QueryTarget::Curves(tables),
        splinegpu_cli::document::queries::Queries::Closest(points),
    ) = (&document.target, &document.queries)
    else {
        panic!("not closest points on curves");
    };
    let want = CurveIndex::new(tables)
        .unwrap()
        .closest_many(points)
        .unwrap();
    for (i, row) in json["closest"].as_array().unwrap().iter().enumerate() {
        assert_eq!(row["curve"].as_u64(), Some(want.curve[i] as u64));
        // Printed to round-trip: the same f64s.
        assert_eq!(row["t"].as_f64(), Some(want.t[i]));
        assert_eq!(row["distance"].as_f64(), Some(want.distance[i]));
        assert_eq!(row["point"][0].as_f64(), Some(want.points[2 * i]));
    }
}

const CURVE: &str = r#"{"kind": "bezier", "points": [[0, 0], [1, 1], [2, 0], [3, 1]]}"#;
const CURVE_3D: &str =
    r#"{"kind": "bezier", "points": [[0, 0, 0], [1, 1, 0], [2, 0, 1], [3, 1, 1]]}"#;
const PATCH: &str = r#"{"kind": "bezier", "points": [
  [[0,0,0],[1,0,0],[2,0,0],[3,0,0]], [[0,1,0],[1,1,1],[2,1,1],[3,1,0]],
  [[0,2,0],[1,2,1],[2,2,1],[3,2,0]], [[0,3,0],[1,3,0],[2,3,0],[3,3,0]]]}"#;

#[test]
fn bad_queries_exit_2_naming_the_field_and_the_query() {
    let curves =
        |queries: &str| format!(r#"{{"curves": [{CURVE}, {CURVE}], "queries": {queries}}}"#);
    let surfaces = |queries: &str| format!(r#"{{"surfaces": [{PATCH}], "queries": {queries}}}"#);
    let cases: Vec<(String, &str)> = vec![
        (curves(r#"{}"#), r#""queries" must have exactly one key"#),
        (
            curves(r#"{"closest": [[0, 0]], "rays": []}"#),
            r#""queries" must have exactly one key"#,
        ),
        (curves(r#"{"nearest": []}"#), r#""nearest" is not a query"#),
        (curves(r#"[1]"#), r#""queries" must be an object"#),
        (
            curves(r#"{"closest": [[0, 0], [1, 2, 3]]}"#),
            r#""closest[1]" must be 2 numbers"#,
        ),
        (
            curves(r#"{"closest": [[0, "a"]]}"#),
            r#""closest[0]" must be 2 numbers"#,
        ),
        (curves(r#"{"closest": 3}"#), r#""closest" must be an array"#),
        (
            curves(r#"{"intersections": [[0, 2]]}"#),
            r#""intersections[0]" names curve 2"#,
        ),
        (
            curves(r#"{"intersections": [[0]]}"#),
            r#""intersections[0]" must be a pair"#,
        ),
        (
            curves(r#"{"intersections": "some"}"#),
            r#""intersections" must be "all""#,
        ),
        (
            format!(r#"{{"curves": [{CURVE_3D}], "queries": {{"intersections": "all"}}}}"#),
            r#""intersections" are found between 2-D curves"#,
        ),
        (
            curves(r#"{"rays": [[0, 0, 0, 1, 0, 0]]}"#),
            r#""rays" meet surfaces"#,
        ),
        (
            surfaces(r#"{"rays": [[0, 0, 0, 1, 0]]}"#),
            r#""rays[0]" must be 6 numbers"#,
        ),
        (
            surfaces(r#"{"rays": [[0, 0, 0, 1, 0, 0], [1, 1, 1, 0, 0, 0]]}"#),
            r#""rays[1]" has a zero direction"#,
        ),
        (
            surfaces(r#"{"intersections": "all"}"#),
            r#""intersections" are found between curves"#,
        ),
        (
            surfaces(r#"{"closest": [[0, 0]]}"#),
            r#""closest[0]" must be 3 numbers"#,
        ),
        (
            format!(
                r#"{{"curves": [{CURVE}], "sampling": {{"per_segment": 4}}, "queries": {{"closest": []}}}}"#
            ),
            r#"document: "sampling" is not a field of a query document"#,
        ),
        (
            format!(r#"{{"curves": [{CURVE}], "derivatives": 1, "queries": {{"closest": []}}}}"#),
            r#"document: "derivatives" is not a field"#,
        ),
        (
            format!(
                r#"{{"curves": [{CURVE}, {{"kind": "bezier", "points": [[0, 0], [1, 1], [2, 0], [3, 1]], "sampling": {{"per_segment": 2}}}}], "queries": {{"closest": []}}}}"#
            ),
            r#"curve 1: "sampling" is not a field of a query document"#,
        ),
        (
            format!(r#"{{"curves": [{CURVE}, {CURVE_3D}], "queries": {{"closest": []}}}}"#),
            r#"curve 1: "points" must have 2 coordinates"#,
        ),
        (
            format!(r#"{{"curves": [{CURVE}], "queries": {{"closest": [[1e200, 0]]}}}}"#),
            r#""closest[0]" lies too far from the curves"#,
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (doc, want) in &cases {
        for name in ["out.json", "out.csv", "out.npz"] {
            let (status, stderr, out) = query(dir.path(), doc, name, &[]);
            assert_eq!(status, 2, "{doc}: {stderr}");
            assert!(stderr.contains(want), "{doc}:\n  {stderr}  wanted {want}");
            // One message, after the auto backend's note where a closest-point query chose one.
            let lines = stderr
                .lines()
                .filter(|l| !l.starts_with("splinegpu: backend auto:"));
            assert_eq!(lines.count(), 1, "{stderr}");
            assert!(out.is_none(), "{doc}: {name} was left");
        }
    }
}

#[test]
fn documents_in_the_wrong_command_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("doc.json");
    std::fs::write(&input, LINES).unwrap();
    let run = crate::support::run_cli(&["tessellate", input.to_str().unwrap()], &[], "");
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("`splinegpu query`"));
    let plain = format!(r#"{{"curves": [{CURVE}]}}"#);
    let (status, stderr, _) = query(dir.path(), &plain, "out.csv", &[]);
    assert_eq!(status, 2, "{stderr}");
    assert!(stderr.contains(r#""queries" is missing"#), "{stderr}");
    let (status, stderr, _) = query(dir.path(), LINES, "out.glb", &[]);
    assert_eq!(status, 2, "{stderr}");
}

/// The GPU's closest points (f32 points and distances, f64 parameters) within the contract's
/// GPU bound of the hand-derived ones: 1e-5 (E + |q|∞) plus the lines' position bound (their
/// coordinates are exact in f32, so a few units in the last place of 5).
#[test]
fn closest_points_on_the_gpu_are_f32_within_the_bound() {
    if crate::support::gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let bound = |q: f64| 1e-5 * (5.0 + q) + 1e-5;
    let want = lines_answers();
    let queries: [[f64; 2]; 3] = [[1.5, 2.0], [1.0, 4.0], [-1.0, -1.0]];
    let (status, stderr, out) = query(dir.path(), LINES, "out.npz", &["--backend", "gpu"]);
    assert_eq!(status, 0, "{stderr}");
    let arrays = crate::stream::read_npz(&out.unwrap());
    assert_eq!(arrays["point"].0, "<f4");
    assert_eq!(arrays["distance"].0, "<f4");
    assert_eq!(arrays["t"].0, "<f8");
    let f32s = |name: &str| -> Vec<f32> { bytemuck::pod_collect_to_vec(&arrays[name].2) };
    let t: Vec<f64> = bytemuck::pod_collect_to_vec(&arrays["t"].2);
    let curves: Vec<i64> = bytemuck::pod_collect_to_vec(&arrays["curve"].2);
    for (i, (curve, t_want, point, distance)) in want.into_iter().enumerate() {
        let b = bound(queries[i][0].abs().max(queries[i][1].abs()));
        assert_eq!(curves[i], curve);
        assert!((t[i] - t_want).abs() <= b, "query {i}: t {}", t[i]);
        for (k, want) in point.iter().enumerate() {
            assert!((f64::from(f32s("point")[2 * i + k]) - want).abs() <= b);
        }
        assert!((f64::from(f32s("distance")[i]) - distance).abs() <= b);
    }
    // JSON holds the same f32 numbers, each the shortest text of its f32.
    let (status, stderr, out) = query(dir.path(), LINES, "out.json", &["--backend", "gpu"]);
    assert_eq!(status, 0, "{stderr}");
    let json: Value = serde_json::from_slice(&out.unwrap()).unwrap();
    for (i, row) in json["closest"].as_array().unwrap().iter().enumerate() {
        let text = row["distance"].to_string();
        assert_eq!(text.parse::<f32>().unwrap(), f32s("distance")[i], "{row}");
        assert!(text.len() <= 10, "{row}: not the shortest text of an f32");
    }
    // Intersections are refined in f64 on the host on either backend.
    let doc = CROSSINGS.replace("QUERY", "\"all\"");
    let (status, stderr, _) = query(dir.path(), &doc, "out.csv", &["--backend", "gpu"]);
    assert_eq!(status, 0, "{stderr}");
}

/// The diagonals of the square [0, 3]² (straight Beziers, x = 3t) cross at (1.5, 1.5), t = 1/2
/// on both; the line y = 0.5 from x = 0 to 3 crosses the first at x = 0.5 (t = 1/6) and the
/// second at x = 2.5 (t = 5/6); and x ∈ [2, 3.5] on y = 0.5 (x = 2 + 1.5t) crosses the second
/// there too (t = 1/3) and overlaps the line from x = 2 to 3.
const CROSSINGS: &str = r#"{"curves": [
  {"kind": "bezier", "points": [[0, 0], [1, 1], [2, 2], [3, 3]]},
  {"kind": "bezier", "points": [[0, 3], [1, 2], [2, 1], [3, 0]]},
  {"kind": "bezier", "points": [[0, 0.5], [1, 0.5], [2, 0.5], [3, 0.5]]},
  {"kind": "bezier", "points": [[2, 0.5], [2.5, 0.5], [3, 0.5], [3.5, 0.5]]}],
 "queries": {"intersections": QUERY}}"#;

/// One intersection as the outputs hold it: (i, j, t_i, t_j, x, y, tangent, overlap).
type Crossing = (i64, i64, f64, f64, f64, f64, bool, bool);

/// CROSSINGS' intersections with "all", in the contract's order.
fn crossings() -> Vec<Crossing> {
    vec![
        (0, 1, 0.5, 0.5, 1.5, 1.5, false, false),
        (0, 2, 1.0 / 6.0, 1.0 / 6.0, 0.5, 0.5, false, false),
        (1, 2, 5.0 / 6.0, 5.0 / 6.0, 2.5, 0.5, false, false),
        (1, 3, 5.0 / 6.0, 1.0 / 3.0, 2.5, 0.5, false, false),
        (2, 3, 2.0 / 3.0, 0.0, 2.0, 0.5, false, true),
        (2, 3, 1.0, 2.0 / 3.0, 3.0, 0.5, false, true),
    ]
}

#[test]
fn intersections_in_every_format_are_the_hand_derived_ones() {
    let dir = tempfile::tempdir().unwrap();
    let doc = CROSSINGS.replace("QUERY", r#""all""#);
    let want = crossings();
    let (status, stderr, out) = query(dir.path(), &doc, "out.json", &[]);
    assert_eq!(status, 0, "{stderr}");
    let json: Value = serde_json::from_slice(&out.unwrap()).unwrap();
    let rows = json["intersections"].as_array().unwrap();
    assert_eq!(rows.len(), want.len(), "{json}");
    for (row, w) in rows.iter().zip(&want) {
        assert_eq!(
            (row["i"].as_i64(), row["j"].as_i64()),
            (Some(w.0), Some(w.1)),
            "{row}"
        );
        assert!(close(row["t_i"].as_f64().unwrap(), w.2), "{row}");
        assert!(close(row["t_j"].as_f64().unwrap(), w.3), "{row}");
        assert!(close(row["point"][0].as_f64().unwrap(), w.4), "{row}");
        assert!(close(row["point"][1].as_f64().unwrap(), w.5), "{row}");
        assert_eq!(row["tangent"].as_bool(), Some(w.6), "{row}");
        assert_eq!(row["overlap"].as_bool(), Some(w.7), "{row}");
    }
    let (status, stderr, out) = query(dir.path(), &doc, "out.csv", &[]);
    assert_eq!(status, 0, "{stderr}");
    let text = String::from_utf8(out.unwrap()).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("i,j,t_i,t_j,x0,x1,tangent,overlap"));
    for (line, w) in lines.zip(&want) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!((v[0], v[1]), (w.0 as f64, w.1 as f64), "{line}");
        assert!(close(v[2], w.2) && close(v[3], w.3) && close(v[4], w.4) && close(v[5], w.5));
        assert_eq!(
            (v[6], v[7]),
            (f64::from(u8::from(w.6)), f64::from(u8::from(w.7)))
        );
    }
    let (status, stderr, out) = query(dir.path(), &doc, "out.npz", &[]);
    assert_eq!(status, 0, "{stderr}");
    let arrays = crate::stream::read_npz(&out.unwrap());
    assert_eq!(arrays["point"].1, [want.len(), 2]);
    assert_eq!(arrays["overlap"].0, "|b1");
    let overlap = &arrays["overlap"].2;
    assert_eq!(
        overlap,
        &want.iter().map(|w| u8::from(w.7)).collect::<Vec<_>>()
    );
    let j: Vec<i64> = bytemuck::pod_collect_to_vec(&arrays["j"].2);
    assert_eq!(j, want.iter().map(|w| w.1).collect::<Vec<_>>());
}

#[test]
fn listed_pairs_come_as_written_and_in_their_order() {
    let dir = tempfile::tempdir().unwrap();
    let doc = CROSSINGS.replace("QUERY", "[[2, 1], [1, 0], [3, 3]]");
    let (status, stderr, out) = query(dir.path(), &doc, "out.json", &[]);
    assert_eq!(status, 0, "{stderr}");
    let json: Value = serde_json::from_slice(&out.unwrap()).unwrap();
    let pairs: Vec<(i64, i64)> = json["intersections"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["i"].as_i64().unwrap(), r["j"].as_i64().unwrap()))
        .collect();
    // A straight line does not meet itself.
    assert_eq!(pairs, [(2, 1), (1, 0)], "{json}");
    let first = &json["intersections"][0];
    assert!(close(first["t_i"].as_f64().unwrap(), 5.0 / 6.0), "{first}");
}

/// A flat bicubic Bezier patch over [0, 3]² at z = 0 (x = 3u, y = 3v), as a net and as a
/// patch list: (1, 2, 5) is 5 above (1, 2, 0), at (u, v) = (1/3, 2/3); a ray down from it hits
/// there at s = 5 with normal ±z; a ray upward meets nothing.
const FLAT: &str = r#"[[[0,0,0],[0,1,0],[0,2,0],[0,3,0]],[[1,0,0],[1,1,0],[1,2,0],[1,3,0]],
  [[2,0,0],[2,1,0],[2,2,0],[2,3,0]],[[3,0,0],[3,1,0],[3,2,0],[3,3,0]]]"#;

#[test]
fn closest_points_and_rays_on_surfaces_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let net =
        format!(r#"{{"surfaces": [{{"kind": "bezier", "points": {FLAT}}}], "queries": QUERY}}"#);
    let closest = net.replace("QUERY", r#"{"closest": [[1, 2, 5]]}"#);
    let (status, stderr, out) = query(dir.path(), &closest, "out.json", &[]);
    assert_eq!(status, 0, "{stderr}");
    let json: Value = serde_json::from_slice(&out.unwrap()).unwrap();
    let row = &json["closest"][0];
    assert_eq!(row["surface"].as_u64(), Some(0));
    assert!(row.get("patch").is_none(), "a net has no patch: {row}");
    assert!(
        close(row["u"].as_f64().unwrap(), 1.0 / 3.0)
            && close(row["v"].as_f64().unwrap(), 2.0 / 3.0)
    );
    assert!(close(row["distance"].as_f64().unwrap(), 5.0), "{row}");
    let (status, stderr, out) = query(dir.path(), &closest, "out.csv", &[]);
    assert_eq!(status, 0, "{stderr}");
    let text = String::from_utf8(out.unwrap()).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("query,surface,patch,u,v,x0,x1,x2,distance")
    );
    assert!(lines.next().unwrap().starts_with("0,0,,"), "{text}");
    let rays = net.replace(
        "QUERY",
        r#"{"rays": [[1, 2, 5, 0, 0, -2], [1, 2, 5, 0, 0, 1]]}"#,
    );
    let (status, stderr, out) = query(dir.path(), &rays, "out.json", &[]);
    assert_eq!(status, 0, "{stderr}");
    let json: Value = serde_json::from_slice(&out.unwrap()).unwrap();
    let hit = &json["rays"][0];
    assert!(close(hit["s"].as_f64().unwrap(), 5.0), "{hit}");
    assert!(
        close(hit["normal"][2].as_f64().unwrap().abs(), 1.0),
        "{hit}"
    );
    assert!(
        close(hit["point"][0].as_f64().unwrap(), 1.0)
            && close(hit["point"][1].as_f64().unwrap(), 2.0)
    );
    assert!(json["rays"][1].is_null(), "{json}");
    let (status, stderr, out) = query(dir.path(), &rays, "out.csv", &[]);
    assert_eq!(status, 0, "{stderr}");
    let text = String::from_utf8(out.unwrap()).unwrap();
    assert_eq!(
        text.lines().next(),
        Some("query,hit,surface,patch,u,v,s,x,y,z,nx,ny,nz")
    );
    assert_eq!(text.lines().nth(2), Some("1,0,,,,,,,,,,,"));
    let (status, stderr, out) = query(dir.path(), &rays, "out.npz", &[]);
    assert_eq!(status, 0, "{stderr}");
    let arrays = crate::stream::read_npz(&out.unwrap());
    assert_eq!(arrays["hit"].2, [1, 0]);
    let surface: Vec<i64> = bytemuck::pod_collect_to_vec(&arrays["surface"].2);
    let patch: Vec<i64> = bytemuck::pod_collect_to_vec(&arrays["patch"].2);
    let s: Vec<f64> = bytemuck::pod_collect_to_vec(&arrays["s"].2);
    assert_eq!((surface, patch), (vec![0, -1], vec![-1, -1]));
    assert!(close(s[0], 5.0) && s[1].is_nan());
    // As a patch list the patch is named.
    let list = format!(
        r#"{{"surfaces": [{{"kind": "bezier", "points": {}, "patches": [[0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15]]}}],
          "queries": {{"rays": [[1, 2, 5, 0, 0, -1]]}}}}"#,
        serde_json::to_string(
            &serde_json::from_str::<Value>(FLAT)
                .unwrap()
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|row| row.as_array().unwrap().clone())
                .collect::<Vec<_>>()
        )
        .unwrap()
    );
    let (status, stderr, out) = query(dir.path(), &list, "out.json", &[]);
    assert_eq!(status, 0, "{stderr}");
    let json: Value = serde_json::from_slice(&out.unwrap()).unwrap();
    assert_eq!(json["rays"][0]["patch"].as_u64(), Some(0), "{json}");
}

/// FLAT's closest point and ray on the GPU: f32 points, distances and normals, f64 (u, v) and s,
/// within the contract's GPU bound of the hand-derived answers.
#[test]
fn closest_points_and_rays_on_surfaces_on_the_gpu() {
    if crate::support::gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let net =
        format!(r#"{{"surfaces": [{{"kind": "bezier", "points": {FLAT}}}], "queries": QUERY}}"#);
    let bound = 1e-5 * (3.0 + 5.0) + 1e-5 * 3.0;
    let closest = net.replace("QUERY", r#"{"closest": [[1, 2, 5]]}"#);
    let (status, stderr, out) = query(dir.path(), &closest, "out.npz", &["--backend", "gpu"]);
    assert_eq!(status, 0, "{stderr}");
    let arrays = crate::stream::read_npz(&out.unwrap());
    assert_eq!(
        ["point", "distance", "u", "v"].map(|n| arrays[n].0.as_str()),
        ["<f4", "<f4", "<f8", "<f8"]
    );
    let distance: Vec<f32> = bytemuck::pod_collect_to_vec(&arrays["distance"].2);
    let u: Vec<f64> = bytemuck::pod_collect_to_vec(&arrays["u"].2);
    let v: Vec<f64> = bytemuck::pod_collect_to_vec(&arrays["v"].2);
    assert!(
        (f64::from(distance[0]) - 5.0).abs() <= bound,
        "{distance:?}"
    );
    assert!((u[0] - 1.0 / 3.0).abs() <= bound && (v[0] - 2.0 / 3.0).abs() <= bound);
    let rays = net.replace(
        "QUERY",
        r#"{"rays": [[1, 2, 5, 0, 0, -3], [1, 2, 5, 0, 0, 1]]}"#,
    );
    let (status, stderr, out) = query(dir.path(), &rays, "out.npz", &["--backend", "gpu"]);
    assert_eq!(status, 0, "{stderr}");
    let arrays = crate::stream::read_npz(&out.unwrap());
    assert_eq!(
        ["point", "normal", "s", "hit"].map(|n| arrays[n].0.as_str()),
        ["<f4", "<f4", "<f8", "|b1"]
    );
    let s: Vec<f64> = bytemuck::pod_collect_to_vec(&arrays["s"].2);
    let normal: Vec<f32> = bytemuck::pod_collect_to_vec(&arrays["normal"].2);
    assert_eq!(arrays["hit"].2, [1, 0]);
    assert!((s[0] - 5.0).abs() <= bound && s[1].is_nan(), "{s:?}");
    assert!((normal[2].abs() - 1.0).abs() <= 1e-6, "{normal:?}");
}
