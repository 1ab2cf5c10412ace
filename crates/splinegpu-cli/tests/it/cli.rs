//! The `splinegpu` binary against the CLI contract: output that parses back to the library's
//! values, the GPU promise through the CLI, and every bad input exiting 2 with one located
//! message and no output file.

use std::path::{Path, PathBuf};

use splinegpu::accuracy::gpu_bound;

struct Run {
    status: i32,
    stdout: String,
    stderr: String,
}

fn splinegpu(args: &[&str], stdin: Option<&str>) -> Run {
    let out = crate::support::run_cli(args, &[], stdin.unwrap_or(""));
    Run {
        status: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

/// Writes MIXED to a file in `dir` and tessellates it with the cpu backend into `dir/name`.
fn tessellate_mixed_to(dir: &Path, name: &str) -> (PathBuf, Run) {
    let input = write_input(dir, MIXED);
    let out = dir.join(name);
    let args = [
        "tessellate",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--backend",
        "cpu",
    ];
    let run = splinegpu(&args, None);
    (out, run)
}

fn write_input(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("input.json");
    std::fs::write(&path, text).unwrap();
    path
}

/// Curves of several kinds and dimensions, derivatives, both sampling modes, values that need
/// all 17 digits, and a curve near 1e6.
const MIXED: &str = r#"{
  "sampling": {"per_segment": 5},
  "derivatives": 2,
  "curves": [
    {"kind": "catmull-rom", "points": [[0.1, 0.2], [1.3, 1.7], [2.9, -0.4], [3.3, 1.1], [4.0, 0.0]]},
    {"kind": "bspline", "ends": "closed", "points": [[0.123456789, 1, 2], [3, 4.5, 6], [7, -8, 9.25]]},
    {"kind": "beta", "bias": 1.3, "tension": 2.5, "ends": "repeat", "points": [[1e6, 2e6, 3e6], [1000000.5, 2000000.25, 3000001], [1000001.5, 1999999.75, 3000000.5]]},
    {"kind": "beta", "bias": [1, 2.5, 0.4, 1.2, 3], "tension": [0, 4, 1, 0, 10], "ends": "closed", "points": [[0, 0], [2, 1], [3, 3], [1, 4], [-1, 2]]},
    {"kind": "beta", "bias": [0.5, 1, 2], "tension": 1.5, "points": [[1e6, 0], [1000001, 2], [1000003, 1], [1000004, 3], [1000005, 0]], "sampling": {"tolerance": 0.01}},
    {"kind": "bezier", "points": [[0], [1], [3], [2]], "sampling": {"at": [0, 0.5, 0.25, 1, 0.5]}},
    {"kind": "matrix", "matrix": [[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 0, 3, 0], [1, 4, 1, 0]], "points": [[1, 1, 1, 1], [2, 0, 1, 3], [0, 5, 1, 2], [3, 3, 3, 3]]},
    {"kind": "natural", "t": [10000, 10000.001, 10002, 10002.5], "points": [[0, 1], [0.002, 1.001], [3, -2], [4, 4]]},
    {"kind": "clamped", "start_derivative": [1, 0, -1], "end_derivative": [0, 2, 0.5], "points": [[0, 0, 0], [1, 1, 1], [2, 0, 3]]},
    {"kind": "periodic", "t": [0, 0.5, 2, 2.25], "points": [[1], [3], [-2], [1]], "sampling": {"at": [0, 2.25, 1.1]}},
    {"kind": "not-a-knot", "points": [[1e6, 0], [1000001, 1], [1000003, -1], [1000004, 0.5], [1000002, 2]]},
    {"kind": "hermite", "t": [0, 0.5, 3], "points": [[0, 1], [2, 2], [1, -1]], "tangents": [[1, 0], [0, -2.5], [3, 3]]},
    {"kind": "pchip", "points": [[0], [0.5], [0.5], [3], [2.75]]},
    {"kind": "nurbs", "knots": [0, 0, 0, 0, 0.5, 2, 2, 2, 5, 5, 5, 5], "points": [[0, 0, 1], [1, 2, 1], [3, 3, 0], [4, 0, 2], [6, -1, 1], [7, 1, 0], [9, 2, 3], [10, 0, 0]]},
    {"kind": "nurbs", "knots": [0, 0, 0, 0, 1, 1, 1, 2.5, 2.5, 2.5, 2.5], "weights": [1, 0.8, 0.8, 1, 3, 0.25, 1], "points": [[1e6, 0], [1000001, 1], [1000000, 2], [999999, 2], [999998, 0], [999999, -2], [1000001, -1]], "sampling": {"arc_length": 9}},
    {"kind": "kochanek-bartels", "ends": "closed", "tension": [0, 0.5, -0.5], "continuity": 0.25, "bias": [1, 0, -1], "t": [0, 1, 1.5, 4], "points": [[0, 0], [2, 1], [1, 3]]},
    {"kind": "akima", "method": "makima", "t": [-2, -1.5, 0, 0.001, 4], "points": [[1, 2, 3], [1, 2, 3], [0, 5, 1], [0.2, 5, 1], [4, 4, 4]], "sampling": {"at": [4, -2, 0.0005, -1.75]}}
  ]
}"#;

/// The rows of a CSV file: (curve, sample, t, values by column, empty fields as None).
fn parse_csv(text: &str) -> (Vec<String>, Vec<Vec<Option<String>>>) {
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|f| (!f.is_empty()).then(|| f.to_string()))
                .collect()
        })
        .collect();
    (header, rows)
}

/// Every (curve, sample, column, value) of the library's CPU evaluation of `doc`, in CSV order.
fn library_values(doc: &str) -> (splinegpu::EvalJob, splinegpu::Samples<f64>) {
    let job = splinegpu_cli::parse_document(doc).unwrap();
    let samples = splinegpu::evaluate_reference(&job);
    (job, samples)
}

#[test]
fn cpu_csv_parses_back_to_the_library_values() {
    let dir = tempfile::tempdir().unwrap();
    let (out, run) = tessellate_mixed_to(dir.path(), "out.csv");
    assert_eq!(run.status, 0, "{}", run.stderr);
    assert_eq!(run.stderr, "", "the cpu backend has nothing to say");
    let (header, rows) = parse_csv(&std::fs::read_to_string(&out).unwrap());
    let expected_header: Vec<String> = ["curve", "sample", "t"]
        .into_iter()
        .map(str::to_string)
        .chain(
            ["x", "dx", "ddx"]
                .iter()
                .flat_map(|p| (0..4).map(move |k| format!("{p}{k}"))),
        )
        .collect();
    assert_eq!(header, expected_header);
    let (_, samples) = library_values(MIXED);
    let mut row = 0;
    for c in 0..samples.len() {
        let s = samples.curve(c);
        for i in 0..s.t.len() {
            let fields = &rows[row];
            assert_eq!(fields[0].as_deref(), Some(c.to_string().as_str()));
            assert_eq!(fields[1].as_deref(), Some(i.to_string().as_str()));
            let parse = |f: &Option<String>| f.as_ref().map(|v| v.parse::<f64>().unwrap());
            assert_eq!(parse(&fields[2]).unwrap().to_bits(), s.t[i].to_bits());
            for (p, plane) in [Some(s.points), s.d1, s.d2].into_iter().enumerate() {
                let plane = plane.unwrap();
                for k in 0..4 {
                    let field = parse(&fields[3 + 4 * p + k]);
                    if k < s.dim {
                        assert_eq!(
                            field.unwrap().to_bits(),
                            plane[i * s.dim + k].to_bits(),
                            "curve {c} sample {i}"
                        );
                    } else {
                        assert_eq!(
                            field, None,
                            "curve {c} of dimension {} has no column {k}",
                            s.dim
                        );
                    }
                }
            }
            row += 1;
        }
    }
    assert_eq!(row, rows.len());
}

#[test]
fn cpu_json_parses_back_to_the_library_values() {
    let run = splinegpu(
        &["tessellate", "-", "--format", "json", "--backend", "cpu"],
        Some(MIXED),
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    let doc: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let (_, samples) = library_values(MIXED);
    let curves = doc["curves"].as_array().unwrap();
    assert_eq!(curves.len(), samples.len());
    for (c, curve) in curves.iter().enumerate() {
        let s = samples.curve(c);
        let t: Vec<f64> = curve["t"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(t, s.t);
        for (name, plane) in [
            ("points", s.points),
            ("d1", s.d1.unwrap()),
            ("d2", s.d2.unwrap()),
        ] {
            let values: Vec<f64> = curve[name]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|p| p.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()))
                .collect();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&values), bits(plane), "curve {c} {name}");
        }
    }
}

#[test]
fn gpu_csv_meets_the_promise() {
    if crate::support::gpu().is_none() {
        return;
    }
    let run = splinegpu(&["tessellate", "-", "--backend", "gpu"], Some(MIXED));
    assert_eq!(run.status, 0, "{}", run.stderr);
    assert_eq!(run.stderr, "", "no driver noise on stderr");
    let (_, rows) = parse_csv(&run.stdout);
    let (job, samples) = library_values(MIXED);
    let mut row = 0;
    for c in 0..samples.len() {
        let (s, table, plan) = (samples.curve(c), job.table(c), job.plan(c));
        for i in 0..s.t.len() {
            let segment = table.segment(plan.loc(i).segment);
            for (p, plane) in [Some(s.points), s.d1, s.d2].into_iter().enumerate() {
                for k in 0..s.dim {
                    let exact = plane.unwrap()[i * s.dim + k];
                    // The GPU prints f32 values; the text must parse as one.
                    let gpu: f32 = rows[row][3 + 4 * p + k].as_ref().unwrap().parse().unwrap();
                    let bound = gpu_bound(&segment, table.extent(), p, k, exact);
                    assert!(
                        (f64::from(gpu) - exact).abs() <= bound,
                        "curve {c} sample {i} order {p}: {gpu} vs {exact}"
                    );
                }
            }
            row += 1;
        }
    }
}

#[test]
fn format_follows_the_output_extension() {
    let dir = tempfile::tempdir().unwrap();
    let (out, run) = tessellate_mixed_to(dir.path(), "result.json");
    assert_eq!(run.status, 0, "{}", run.stderr);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(serde_json::from_str::<serde_json::Value>(&text).is_ok());
}

#[cfg(unix)]
#[test]
fn output_files_get_the_mode_of_any_new_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.csv");
    let run = splinegpu(
        &[
            "tessellate",
            "-",
            "-o",
            out.to_str().unwrap(),
            "--backend",
            "cpu",
        ],
        Some(MIXED),
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    let plain = dir.path().join("plain");
    std::fs::File::create(&plain).unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&out), mode(&plain));
}

#[test]
fn auto_says_which_backend_it_used() {
    let run = splinegpu(&["tessellate", "-"], Some(MIXED));
    assert_eq!(run.status, 0, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(run.stderr.contains("backend auto: "), "{}", run.stderr);
}

#[test]
fn info_lists_adapters_and_exits_0() {
    let run = splinegpu(&["info"], None);
    assert_eq!(run.status, 0, "{}", run.stderr);
    assert!(run.stdout.contains("auto: "), "{}", run.stdout);
}

/// (document, what the message must name).
const BAD_INPUTS: &[(&str, &[&str])] = &[
    (
        r#"{"curves": [{"kind": "hermite", "points": [[0], [1], [2]], "tangents": [[0], [1]]}]}"#,
        &["curve 0", "\"tangents\"", "got 2 numbers"],
    ),
    (
        r#"{"curves": [{"kind": "hermite", "points": [[0], [1]], "tangents": [[0], [1, 2]]}]}"#,
        &["curve 0", "tangents[1] has 2 numbers"],
    ),
    (
        r#"{"curves": [{"kind": "hermite", "points": [[0], [1]]}]}"#,
        &["curve 0", "\"tangents\" is missing"],
    ),
    (
        r#"{"curves": [{"kind": "akima", "method": "cubic", "points": [[0], [1], [2]]}]}"#,
        &["curve 0", "\"method\"", "\"cubic\""],
    ),
    (
        r#"{"curves": [{"kind": "pchip", "ends": "closed", "points": [[0], [1], [2]]}]}"#,
        &["curve 0", "\"ends\" is not a field of a \"pchip\" curve"],
    ),
    (
        r#"{"curves": [{"kind": "pchip", "points": [[0]]}]}"#,
        &["curve 0", "at least 2 points"],
    ),
    (
        r#"{"curves": [{"kind": "nurbs", "knots": [0, 1, 2, 3, 4, 5, 6], "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0", "\"knots\"", "got 7"],
    ),
    (
        r#"{"curves": [{"kind": "nurbs", "knots": [0, 1, 2, 3, 4, 5, 6, 7], "weights": [1, -1, 1, 1], "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0", "\"weights\"", "weights[1] = -1"],
    ),
    (
        r#"{"curves": [{"kind": "nurbs", "knots": [0, 1, 2, 3, 4, 5, 6, 7], "weights": [1, 1, 1], "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0", "\"weights\"", "(4), got 3"],
    ),
    (
        r#"{"curves": [{"kind": "kochanek-bartels", "ends": "closed", "t": [0, 1, 2], "points": [[0], [1], [2]]}]}"#,
        &["curve 0", "\"t\"", "(4), got 3"],
    ),
    (
        r#"{"curves": [{"kind": "kochanek-bartels", "bias": [0, 1], "points": [[0], [1], [2], [3]]}]}"#,
        &[
            "curve 0",
            "\"bias\" must have one value per point (4), got 2",
        ],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}, {"kind": "beta", "bias": [1, -2, 1], "points": [[0], [1], [2], [3], [4]]}]}"#,
        &[
            "curve 1",
            "\"bias\" must be > 0 at every joint: bias[1] = -2",
        ],
    ),
    (
        r#"{"curves": [{"kind": "beta", "ends": "repeat", "tension": [1, 1, 1], "points": [[0], [1], [2], [3]]}]}"#,
        &[
            "curve 0",
            "\"tension\" must have one value per joint (4), got 3",
        ],
    ),
    (
        r#"{"curves": [{"kind": "beta", "bias": 0, "tension": [1, 1], "points": [[0], [1], [2], [3]]}]}"#,
        &[
            "curve 0",
            "\"bias\" must be > 0 when bias or tension is given per joint, got 0",
        ],
    ),
    (
        r#"{"curves": [{"kind": "cardinal", "tension": [0.5, 0.5, 0.5, 0.5], "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0", "\"tension\" must be a number"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [NaN]]}]}"#,
        &["document:", "line 1"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [Infinity]]}]}"#,
        &["document:", "line 1"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [1e999]]}]}"#,
        &["document:", "line 1"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}, {"kind": "catmull-rom", "points": [[0], [1], [2]]}]}"#,
        &["curve 1:", "\"points\"", "got 3"],
    ),
    (
        r#"{"curves": [{"kind": "bezier", "points": [[0, 0], [1, 1], [2, 2, 2], [3, 3]]}]}"#,
        &["curve 0:", "\"points\"", "points[2]"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[], [], [], []]}]}"#,
        &["curve 0:", "\"points\"", "has 0"],
    ),
    (
        r#"{"curves": [{"kind": "bezier", "points": [[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]]}]}"#,
        &["curve 0:", "\"points\"", "has 65"],
    ),
    (
        r#"{"sampling": {"per_segment": 0}, "curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}]}"#,
        &["document:", "\"per_segment\""],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}, {"kind": "bspline", "points": [[0], [1], [2], [3]], "sampling": {"per_segment": 0}}]}"#,
        &["curve 1:", "\"per_segment\""],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3], [4]], "sampling": {"at": [0.5, 2.5]}}]}"#,
        &["curve 0:", "\"at\"", "at[1] = 2.5"],
    ),
    (
        r#"{"curves": [{"kind": "beta", "bias": -1, "tension": 0, "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0:", "\"tension\"", "d = "],
    ),
    (
        r#"{"curves": [{"kind": "lagrange", "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0:", "\"kind\"", "lagrange"],
    ),
    (
        r#"{"curves": [{"kind": "cardinal", "tenson": 0.3, "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0:", "\"tenson\""],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "tension": 0.3, "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0:", "\"tension\""],
    ),
    (
        r#"{"curves": [{"kind": "bezier", "ends": "closed", "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0:", "\"ends\""],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": "abc"}]}"#,
        &["curve 0:", "\"points\""],
    ),
    (
        r#"{"curves": [{"kind": "cardinal", "tension": "high", "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0:", "\"tension\""],
    ),
    (
        r#"{"curves": [{"kind": 3, "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0:", "\"kind\""],
    ),
    (
        r#"{"derivatives": 3, "curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}]}"#,
        &["document:", "\"derivatives\""],
    ),
    (r#"{"curves": []}"#, &["document:", "\"curves\"", "empty"]),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}], "sample": {"at": []}}"#,
        &["document:", "\"sample\""],
    ),
    (
        r#"{"sampling": {"per_segment": 2, "at": [0]}, "curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}]}"#,
        &["document:", "\"sampling\""],
    ),
    (
        r#"{"curves": [{"kind": "matrix", "matrix": [[1, 2, 3], [1, 2, 3], [1, 2, 3]], "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 0:", "\"matrix\""],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}, {"kind": "natural", "t": [0, 1, 1], "points": [[0], [1], [2]]}]}"#,
        &["curve 1:", "\"t\"", "t[2] = 1 follows t[1] = 1"],
    ),
    (
        r#"{"curves": [{"kind": "natural", "t": [0, 1], "points": [[0], [1], [2]]}]}"#,
        &["curve 0:", "\"t\""],
    ),
    (
        r#"{"curves": [{"kind": "periodic", "points": [[0, 0], [1, 0], [0, 1], [0.5, 0]]}]}"#,
        &["curve 0:", "\"points\"", "points[3][0]"],
    ),
    (
        r#"{"curves": [{"kind": "clamped", "start_derivative": [1, 0], "points": [[0, 0], [1, 0], [0, 1]]}]}"#,
        &["curve 0:", "\"end_derivative\""],
    ),
    (
        r#"{"curves": [{"kind": "clamped", "start_derivative": [1], "end_derivative": [1, 0], "points": [[0, 0], [1, 0], [0, 1]]}]}"#,
        &["curve 0:", "\"start_derivative\"", "got 1"],
    ),
    (
        r#"{"curves": [{"kind": "not-a-knot", "points": [[0], [1], [2]]}]}"#,
        &["curve 0:", "\"points\"", "got 3"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]], "sampling": {"arc_length": 1}}]}"#,
        &["curve 0:", "\"arc_length\""],
    ),
    // A key given twice is an error at every level, never last-wins.
    (
        r#"{"derivatives": 1, "curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}], "derivatives": 2}"#,
        &["document:", "\"derivatives\"", "twice"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}, {"kind": "bspline", "kind": "bezier", "points": [[0], [1], [2], [3]]}]}"#,
        &["curve 1:", "\"kind\"", "twice"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]], "sampling": {"per_segment": 2, "per_segment": 3}}]}"#,
        &["curve 0:", "\"per_segment\"", "twice"],
    ),
    // Values whose samples overflow float64 are the input's fault.
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}, {"kind": "bspline", "points": [[1e308], [-1e308], [1e308], [-1e308]]}]}"#,
        &["curve 1:", "\"points\"", "float64"],
    ),
    (
        r#"{"derivatives": 2, "curves": [{"kind": "natural", "t": [0, 1e-300, 1], "points": [[0], [1e10], [0]]}]}"#,
        &["curve 0:", "\"points\"", "float64"],
    ),
    (
        r#"{"derivatives": 2, "curves": [{"kind": "natural", "t": [0, 1e-200, 2e-200], "points": [[0], [1], [0]]}]}"#,
        &["curve 0:", "\"points\"", "second derivatives"],
    ),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]], "ends": [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]}]}"#,
        &["document:", "line 1"],
    ),
    (r#"[1, 2]"#, &["document:", "JSON object", "[1,2]"]),
    (
        r#"{"curves": [{"kind": "bspline", "points": [[0], [1], [2], [3]]}]} trailing"#,
        &["document:", "line 1"],
    ),
];

#[test]
fn bad_input_exits_2_names_the_place_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for (doc, names) in BAD_INPUTS {
        let input = write_input(dir.path(), doc);
        let existing = dir.path().join("existing.csv");
        std::fs::write(&existing, "KEEP").unwrap();
        let fresh = dir.path().join("fresh.csv");
        for (out, backend) in [(&existing, "cpu"), (&fresh, "gpu"), (&fresh, "auto")] {
            let run = splinegpu(
                &[
                    "tessellate",
                    input.to_str().unwrap(),
                    "-o",
                    out.to_str().unwrap(),
                    "--backend",
                    backend,
                ],
                None,
            );
            assert_eq!(run.status, 2, "{doc}: {}", run.stderr);
            assert_eq!(
                run.stderr.lines().count(),
                1,
                "one message for {doc}: {}",
                run.stderr
            );
            for name in *names {
                assert!(
                    run.stderr.contains(name),
                    "{doc}: message lacks {name}: {}",
                    run.stderr
                );
            }
        }
        assert_eq!(std::fs::read_to_string(&existing).unwrap(), "KEEP");
        assert!(!fresh.exists(), "{doc} left an output file");
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left.len(), 2, "temporary files left behind: {left:?}");
    }
}

#[test]
fn missing_input_and_unknown_flags_exit_2() {
    let run = splinegpu(&["tessellate", "/nonexistent/input.json"], None);
    assert_eq!(run.status, 2);
    assert!(
        run.stderr.contains("/nonexistent/input.json"),
        "{}",
        run.stderr
    );
    let run = splinegpu(&["tessellate", "-", "--colour"], Some(MIXED));
    assert_eq!(run.status, 2);
    // A folder opens but cannot be read: named as such, not as invalid JSON.
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().to_str().unwrap();
    let run = splinegpu(&["tessellate", path], None);
    assert_eq!(run.status, 2, "{}", run.stderr);
    let want = format!("document: cannot read input \"{path}\": it is a directory");
    assert!(run.stderr.contains(&want), "{}", run.stderr);
}

#[test]
fn unwritable_output_exits_1() {
    let run = splinegpu(
        &[
            "tessellate",
            "-",
            "-o",
            "/nonexistent/dir/out.csv",
            "--backend",
            "cpu",
        ],
        Some(MIXED),
    );
    assert_eq!(run.status, 1, "{}", run.stderr);
    let want = "cannot write output \"/nonexistent/dir/out.csv\": ";
    assert!(run.stderr.contains(want), "{}", run.stderr);
}

/// The t column and the rows of the CSV `text`.
fn t_column(text: &str) -> Vec<u64> {
    let (_, rows) = parse_csv(text);
    rows.iter()
        .map(|r| r[2].as_deref().unwrap().parse::<f64>().unwrap().to_bits())
        .collect()
}

/// Tolerance sampling's places are decided on the host: bit-identical t on both backends. The
/// GPU places arc-length samples itself, in f32 (within 1e-5 of the length): the same count and
/// ends, and t within a few 1e-7 of the range of the CPU's.
#[test]
fn tolerance_sampling_gives_the_same_t_on_both_backends_and_arc_length_nearly() {
    let docs = [
        r#"{"sampling": {"arc_length": 50}, "derivatives": 1, "curves": [
            {"kind": "catmull-rom", "ends": "closed", "points": [[0, 0], [4, 0], [4, 3], [0, 3]]},
            {"kind": "natural", "t": [0, 0.001, 3], "points": [[0, 0, 0], [1, 2, 0], [3, 1, 1]]}]}"#,
        r#"{"sampling": {"tolerance": 0.01}, "curves": [
            {"kind": "bspline", "ends": "repeat", "points": [[0, 0], [4, 0], [4, 3], [0, 3]]},
            {"kind": "bezier", "points": [[0, 0, 0], [1, 2, 0], [3, 2, 1], [4, 0, 1]]}]}"#,
    ];
    for doc in docs {
        let cpu = splinegpu(&["tessellate", "-", "--backend", "cpu"], Some(doc));
        assert_eq!(cpu.status, 0, "{}", cpu.stderr);
        let gpu = splinegpu(&["tessellate", "-", "--backend", "gpu"], Some(doc));
        if gpu.status != 0 && !std::env::var("CI").is_ok_and(|v| v == "true") {
            eprintln!("skipping the GPU half: {}", gpu.stderr);
            continue;
        }
        assert_eq!(gpu.status, 0, "{}", gpu.stderr);
        let (cpu_t, gpu_t) = (t_column(&cpu.stdout), t_column(&gpu.stdout));
        if doc.contains("arc_length") {
            assert_eq!(cpu_t.len(), 100);
            assert_eq!(gpu_t.len(), 100);
            for (curve, range) in [(0..50, 4.0), (50..100, 3.0)] {
                let (c, g) = (&cpu_t[curve.clone()], &gpu_t[curve]);
                assert_eq!((c[0], c[49]), (g[0], g[49]), "the ends are the curve's");
                for (c, g) in c.iter().zip(g) {
                    let (c, g) = (f64::from_bits(*c), f64::from_bits(*g));
                    assert!(
                        (c - g).abs() <= 1e-6 * range,
                        "t {c} on the CPU, {g} on the GPU"
                    );
                }
            }
        } else {
            assert_eq!(cpu_t, gpu_t, "{doc}");
        }
    }
}

#[test]
fn bad_arc_length_and_tolerance_values_exit_2_naming_them() {
    for (sampling, names) in [
        (r#"{"arc_length": 1}"#, &["\"arc_length\"", "got 1"][..]),
        (r#"{"arc_length": 2.5}"#, &["\"arc_length\""][..]),
        (r#"{"tolerance": 0}"#, &["\"tolerance\"", "got 0"][..]),
        (r#"{"tolerance": -1}"#, &["\"tolerance\""][..]),
        (r#"{"tolerance": "fine"}"#, &["\"tolerance\"", "fine"][..]),
        (
            r#"{"tolerance": 1e-300}"#,
            &["\"sampling\"", "samples on segment 0"][..],
        ),
    ] {
        let doc = format!(
            r#"{{"curves": [{{"kind": "bspline", "points": [[0], [1], [2], [3]]}},
            {{"kind": "bspline", "points": [[0, 0], [1, 5], [2, -3], [3, 0]], "sampling": {sampling}}}]}}"#
        );
        let run = splinegpu(&["tessellate", "-", "--backend", "cpu"], Some(&doc));
        assert_eq!(run.status, 2, "{sampling}: {}", run.stderr);
        assert!(run.stderr.contains("curve 1:"), "{}", run.stderr);
        for name in names {
            assert!(run.stderr.contains(name), "{sampling}: {}", run.stderr);
        }
    }
}

#[test]
fn numbers_in_messages_are_short_and_a_huge_count_is_not_cut() {
    // Segment 0 of this B-spline has |P''| at most 13 (its second differences are (0, -13) and
    // (0, 11)), so Wang's count at 1e-300 is ceil(sqrt(13 / 8e-300)) = 1.27e150: far past
    // 2^64, and the message must show such a count, not 2^64 - 1. Numbers are shown as short
    // as they read back: "1e-300", not 300 zeros.
    let doc = r#"{"sampling": {"tolerance": 1e-300},
        "curves": [{"kind": "bspline", "points": [[0, 0], [1, 5], [2, -3], [3, 0]]}]}"#;
    let run = splinegpu(&["tessellate", "-", "--backend", "cpu"], Some(doc));
    assert_eq!(run.status, 2, "{}", run.stderr);
    assert!(!run.stderr.contains("0000000"), "{}", run.stderr);
    let count = run
        .stderr
        .split_once("tolerance 1e-300 needs ")
        .and_then(|(_, rest)| rest.split_once(" samples on segment 0"))
        .map(|(count, _)| count.parse::<f64>().unwrap())
        .unwrap_or_else(|| panic!("{}", run.stderr));
    let wang = (13.0_f64 / 8e-300).sqrt().ceil();
    assert!(count > 2f64.powi(64) && count <= wang, "{count} of {wang}");
    // A value outside the range is shown short too.
    let doc = r#"{"sampling": {"at": [1e-300, -2.5e-200]},
        "curves": [{"kind": "natural", "points": [[0], [1]], "t": [0, 1e200]}]}"#;
    let run = splinegpu(&["tessellate", "-", "--backend", "cpu"], Some(doc));
    assert_eq!(run.status, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains("[0, 1e200]: at[1] = -2.5e-200"),
        "{}",
        run.stderr
    );
}

#[test]
fn bench_json_lines_carry_the_float_field() {
    let run = splinegpu(&["bench", "--workload", "fit-1m", "--json"], None);
    assert_eq!(run.status, 0, "{}", run.stderr);
    let lines: Vec<serde_json::Value> = run
        .stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert!(lines.len() >= 2, "{}", run.stdout);
    for line in &lines {
        let path = line["path"].as_str().unwrap();
        match path {
            "memset" => assert!(line.get("float").is_none(), "{line}"),
            _ => assert!(
                matches!(line["float"].as_str(), Some("f32" | "f64")),
                "{path}: {line}"
            ),
        }
        for key in [
            "workload",
            "seconds",
            "min_seconds",
            "max_seconds",
            "samples",
            "bytes",
            "gbps",
        ] {
            assert!(line.get(key).is_some(), "{key} in {line}");
        }
    }
}

#[test]
fn derivatives_not_asked_for_may_exceed_float64() {
    // Knots 1e-200 apart: positions and dP/dt are finite, d2P/dt2 is not.
    let doc = r#"{"derivatives": 1, "curves": [{"kind": "natural", "t": [0, 1e-200, 2e-200], "points": [[0], [1], [0]]}]}"#;
    let run = splinegpu(&["tessellate", "-", "--backend", "cpu"], Some(doc));
    assert_eq!(run.status, 0, "{}", run.stderr);
}
