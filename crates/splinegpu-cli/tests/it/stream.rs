//! Streaming output: a job cut into chunks gives the same samples as the whole job, and the
//! CLI's NPZ files read back (with a small zip/npy reader here, and with numpy where Python has
//! it) to the library's values.

use std::collections::HashMap;

use std::process::Command;

use crate::support::Rng;
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, EndCondition, Ends, EvalJob, Samples, Sampling,
};

fn job(derivatives: Derivatives) -> EvalJob {
    let mut rng = Rng(4);
    let mut job = EvalJob::new(derivatives);
    let bspline = CurveKind::Uniform {
        basis: Basis::BSpline,
        ends: Ends::Repeat,
    };
    for n in [5, 40, 3] {
        job.push(
            &Curve::new(bspline.clone(), rng.points(n, 3, -2.0, 2.0)).unwrap(),
            &Sampling::PerSegment(9),
        )
        .unwrap();
    }
    let natural = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: None,
    };
    let ts: Vec<f64> = (0..333).map(|_| rng.range(0.0, 29.0)).collect();
    job.push(
        &Curve::new(natural, rng.points(30, 3, -2.0, 2.0)).unwrap(),
        &Sampling::At(ts),
    )
    .unwrap();
    job
}

#[test]
fn chunks_in_order_give_every_sample_once() {
    let job = job(Derivatives::Second);
    let whole = splinegpu::evaluate_reference(&job);
    for max in [1, 7, 50, 100, 10_000] {
        // Per original curve: its samples' t and values, appended chunk by chunk.
        let mut seen: HashMap<usize, (Vec<f64>, [Vec<f64>; 3])> = HashMap::new();
        for chunk in job.chunks(max) {
            let part = splinegpu::evaluate_reference(&chunk.job);
            for (c, piece) in chunk.pieces.iter().enumerate() {
                let s = part.curve(c);
                let entry = seen.entry(piece.curve).or_default();
                assert_eq!(
                    entry.0.len(),
                    piece.first_sample,
                    "pieces of curve {} in order",
                    piece.curve
                );
                entry.0.extend_from_slice(s.t);
                for (plane, values) in entry.1.iter_mut().zip([Some(s.points), s.d1, s.d2]) {
                    plane.extend_from_slice(values.unwrap());
                }
            }
        }
        for c in 0..job.len() {
            let s = whole.curve(c);
            let (t, planes) = &seen[&c];
            assert_eq!(t.as_slice(), s.t, "max {max}, curve {c}: t");
            for (got, want) in planes.iter().zip([s.points, s.d1.unwrap(), s.d2.unwrap()]) {
                assert_eq!(got.as_slice(), want, "max {max}, curve {c}");
            }
        }
    }
}

/// The arrays of an NPZ file: name -> (descr, shape, data bytes), CRCs checked.
pub(crate) fn read_npz(bytes: &[u8]) -> HashMap<String, (String, Vec<usize>, Vec<u8>)> {
    let u16_at = |i: usize| u16::from_le_bytes(bytes[i..i + 2].try_into().unwrap()) as usize;
    let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap());
    let u64_at = |i: usize| u64::from_le_bytes(bytes[i..i + 8].try_into().unwrap()) as usize;
    // End record (no comment), then the zip64 locator before it, then the zip64 end record.
    let end = bytes.len() - 22;
    assert_eq!(u32_at(end), 0x0605_4b50);
    let locator = end - 20;
    assert_eq!(u32_at(locator), 0x0706_4b50);
    let end64 = u64_at(locator + 8);
    assert_eq!(u32_at(end64), 0x0606_4b50);
    let (count, mut at) = (u64_at(end64 + 32), u64_at(end64 + 48));
    let mut arrays = HashMap::new();
    for _ in 0..count {
        assert_eq!(u32_at(at), 0x0201_4b50);
        let crc = u32_at(at + 16);
        let (name_len, extra_len) = (u16_at(at + 28), u16_at(at + 30));
        let name = String::from_utf8(bytes[at + 46..at + 46 + name_len].to_vec()).unwrap();
        let extra = at + 46 + name_len;
        assert_eq!(u16_at(extra), 1, "zip64 field");
        let (size, offset) = (u64_at(extra + 4), u64_at(extra + 20));
        let data_at = offset + 30 + u16_at(offset + 26) + u16_at(offset + 28);
        let data = &bytes[data_at..data_at + size];
        assert_eq!(crc32fast::hash(data), crc, "{name}: CRC");
        assert_eq!(&data[..8], b"\x93NUMPY\x01\x00");
        let header_len = u16::from_le_bytes([data[8], data[9]]) as usize;
        assert_eq!(
            (10 + header_len) % 64,
            0,
            "{name}: data aligned to 64 bytes"
        );
        let header = std::str::from_utf8(&data[10..10 + header_len]).unwrap();
        let descr = header
            .split("'descr': '")
            .nth(1)
            .unwrap()
            .split('\'')
            .next()
            .unwrap()
            .to_string();
        let shape: Vec<usize> = header
            .split("'shape': (")
            .nth(1)
            .unwrap()
            .split(')')
            .next()
            .unwrap()
            .split(',')
            .filter(|s| !s.trim().is_empty())
            .map(|s| s.trim().parse().unwrap())
            .collect();
        arrays.insert(
            name.trim_end_matches(".npy").to_string(),
            (descr, shape, data[10 + header_len..].to_vec()),
        );
        at = extra + extra_len;
    }
    arrays
}

const DOC: &str = r#"{"derivatives": 2, "sampling": {"per_segment": 6}, "curves": [
  {"kind": "catmull-rom", "points": [[0, 0, 0], [1, 2, 0], [2, 0, 1], [3, 1, 1], [4, 0, 0]]},
  {"kind": "natural", "t": [0, 0.5, 3], "points": [[1, 1, 1], [2, 0, 0], [0, 0, 3]], "sampling": {"at": [0, 2.5, 1, 3]}},
  {"kind": "bezier", "points": [[0, 0, 0], [1, 1, 1], [2, 1, 0], [3, 0, 1]]}
]}"#;

fn splinegpu(args: &[&str], envs: &[(&str, &str)]) -> std::process::Output {
    crate::support::run_cli(args, envs, DOC)
}

#[test]
fn cli_npz_reads_back_to_the_library_values() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.npz");
    // Small chunks, so that the stream really is cut.
    let run = splinegpu(
        &[
            "tessellate",
            "-",
            "-o",
            path.to_str().unwrap(),
            "--backend",
            "cpu",
        ],
        &[("SPLINEGPU_CHUNK_SAMPLES", "5")],
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let arrays = read_npz(&std::fs::read(&path).unwrap());
    let job = splinegpu_cli::parse_document(DOC).unwrap();
    let expected = splinegpu::evaluate_reference(&job);
    let n = job.sample_count();
    let f64s = |b: &[u8]| {
        b.chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect::<Vec<_>>()
    };
    let (descr, shape, t) = &arrays["t"];
    assert_eq!((descr.as_str(), shape.as_slice()), ("<f8", &[n][..]));
    let all = |f: &dyn Fn(&splinegpu::CurveSamples<'_, f64>) -> Vec<f64>| {
        (0..job.len())
            .flat_map(|c| f(&expected.curve(c)))
            .collect::<Vec<_>>()
    };
    assert_eq!(f64s(t), all(&|s| s.t.to_vec()));
    for (name, plane) in [("points", 0), ("d1", 1), ("d2", 2)] {
        let (descr, shape, data) = &arrays[name];
        assert_eq!(
            (descr.as_str(), shape.as_slice()),
            ("<f8", &[n, 3][..]),
            "{name}"
        );
        let want = all(&|s| [Some(s.points), s.d1, s.d2][plane].unwrap().to_vec());
        assert_eq!(f64s(data), want, "{name}");
    }
    let (descr, shape, offsets) = &arrays["curve_offsets"];
    assert_eq!((descr.as_str(), shape.as_slice()), ("<i8", &[4][..]));
    let offsets: Vec<i64> = offsets
        .chunks_exact(8)
        .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    // 2 segments x 6 + 1, 4 explicit t, 1 segment x 6 + 1.
    assert_eq!(offsets, [0, 13, 17, 24]);
    // numpy reads it too, where Python has numpy.
    let script = format!(
        "import numpy as np; z = np.load({:?}); print(z['points'].shape, z['d2'].dtype, list(z['curve_offsets']))",
        path.to_str().unwrap()
    );
    if let Ok(out) = Command::new("python3").args(["-c", &script]).output() {
        if out.status.success() {
            assert_eq!(
                String::from_utf8_lossy(&out.stdout).trim(),
                "(24, 3) float64 [np.int64(0), np.int64(13), np.int64(17), np.int64(24)]"
            );
        } else {
            eprintln!(
                "numpy check skipped: {}",
                String::from_utf8_lossy(&out.stderr)
                    .lines()
                    .last()
                    .unwrap_or("")
            );
        }
    }
}

#[test]
fn chunked_csv_is_the_same_file() {
    let whole = splinegpu(&["tessellate", "-", "--backend", "cpu"], &[]);
    let chunked = splinegpu(
        &["tessellate", "-", "--backend", "cpu"],
        &[("SPLINEGPU_CHUNK_SAMPLES", "3")],
    );
    assert!(whole.status.success() && chunked.status.success());
    assert_eq!(whole.stdout, chunked.stdout);
    let gpu_whole = splinegpu(&["tessellate", "-", "--backend", "gpu"], &[]);
    let gpu_chunked = splinegpu(
        &["tessellate", "-", "--backend", "gpu", "--format", "json"],
        &[("SPLINEGPU_CHUNK_SAMPLES", "3")],
    );
    if crate::support::gpu().is_some() {
        assert!(gpu_whole.status.success() && gpu_chunked.status.success());
    }
}

/// JSON is evaluated in runs of whole curves, a curve longer than a chunk alone plane by
/// plane: the document is the same whatever the chunk size.
#[test]
fn chunked_json_is_the_same_document() {
    let args = ["tessellate", "-", "--backend", "cpu", "--format", "json"];
    let whole = splinegpu(&args, &[]);
    assert!(whole.status.success());
    // 3: every curve alone; 20: the first curve (33 samples) alone, then runs; 40: runs.
    for chunk in ["3", "20", "40"] {
        let chunked = splinegpu(&args, &[("SPLINEGPU_CHUNK_SAMPLES", chunk)]);
        assert!(chunked.status.success());
        assert_eq!(whole.stdout, chunked.stdout, "chunks of {chunk}");
    }
}

/// On the GPU an arc-length sample's t is where the kernel placed it: JSON writes that t, as
/// CSV does, so that each point is the curve at its t, curves longer than a chunk too.
#[test]
fn gpu_json_and_csv_give_the_same_t() {
    if crate::support::gpu().is_none() {
        return;
    }
    let doc = r#"{"sampling": {"arc_length": 37}, "curves": [
        {"kind": "catmull-rom", "points": [[0, 0], [1, 3], [2, 0.1], [7, 1], [8, 0], [9, 5]]},
        {"kind": "natural", "t": [0, 0.1, 3], "points": [[1, 1], [2, 0], [0, 3]]}]}"#;
    // Default chunks, and chunks of 10 samples: each curve written alone, plane by plane.
    for chunk in ["1048576", "10"] {
        let run = |format| {
            let out = crate::support::run_cli(
                &["tessellate", "-", "--backend", "gpu", "--format", format],
                &[("SPLINEGPU_CHUNK_SAMPLES", chunk)],
                doc,
            );
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            String::from_utf8(out.stdout).unwrap()
        };
        let csv_t: Vec<f64> = (run("csv").lines().skip(1))
            .map(|row| row.split(',').nth(2).unwrap().parse().unwrap())
            .collect();
        let json: serde_json::Value = serde_json::from_str(&run("json")).unwrap();
        let json_t: Vec<f64> = (json["curves"].as_array().unwrap().iter())
            .flat_map(|c| c["t"].as_array().unwrap().clone())
            .map(|t| t.as_f64().unwrap())
            .collect();
        assert_eq!(csv_t.len(), 2 * 37);
        assert_eq!(json_t, csv_t, "chunks of {chunk}");
    }
}

/// A curve beyond float32's range in a later chunk is named by its number in the document,
/// not in its chunk.
#[test]
fn gpu_range_errors_name_the_documents_curve_whatever_the_chunk() {
    if crate::support::gpu().is_none() {
        return;
    }
    let doc = r#"{"curves": [
        {"kind": "bezier", "points": [[0], [1], [2], [3]]},
        {"kind": "bezier", "points": [[0], [1], [2], [3]]},
        {"kind": "bezier", "points": [[0], [1], [1e39], [3]]}]}"#;
    for chunk in ["3", "1000"] {
        let out = crate::support::run_cli(
            &["tessellate", "-", "--format", "npz", "--backend", "gpu"],
            &[("SPLINEGPU_CHUNK_SAMPLES", chunk)],
            doc,
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains("curve 2:") && stderr.contains("float32"),
            "chunks of {chunk}: {stderr}"
        );
    }
}

#[test]
fn npz_of_curves_with_different_dimensions_is_bad_input() {
    let doc = r#"{"curves": [{"kind": "bezier", "points": [[0], [1], [2], [3]]}, {"kind": "bezier", "points": [[0, 0], [1, 1], [2, 0], [3, 1]]}]}"#;
    let out = crate::support::run_cli(
        &["tessellate", "-", "--format", "npz", "--backend", "cpu"],
        &[],
        doc,
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("curve 1:") && stderr.contains("\"points\""),
        "{stderr}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn samples_reused_across_chunks_do_not_leak_between_them() {
    // A later, smaller chunk must not show values of an earlier, larger one.
    let job = job(Derivatives::None);
    let mut samples = Samples::<f64>::for_job(&job);
    splinegpu::evaluate_cpu_into(&job, samples.planes_for(&job), 2);
    let small = job.chunks(3).last().unwrap();
    splinegpu::evaluate_cpu_into(&small.job, samples.planes_for(&small.job), 2);
    assert_eq!(samples, splinegpu::evaluate_reference(&small.job));
}

/// Values of every class a float type has: zeros of both signs, subnormals (the smallest
/// included), the smallest normal, integers, values with exponent-form text, the largest.
fn value_classes<F: Copy>(
    max: F,
    min_positive: F,
    smallest: F,
    more: &[F],
    neg: impl Fn(F) -> F,
) -> Vec<F> {
    let mut values = vec![
        max,
        neg(max),
        min_positive,
        neg(min_positive),
        smallest,
        neg(smallest),
    ];
    values.extend_from_slice(more);
    values.extend(more.iter().map(|&v| neg(v)));
    values
}

/// Writes `values` (cycled) as the points of a job whose curves have 3 and 2 coordinates and
/// enough rows for several blocks on every thread, and checks that every field of every row
/// parses back to the value it came from, bit for bit, with the rows in order.
fn csv_round_trip<F>(values: &[F])
where
    F: splinegpu::SampleFloat + std::str::FromStr + zmij::Float,
    <F as std::str::FromStr>::Err: std::fmt::Debug,
{
    let mut job = EvalJob::new(Derivatives::First);
    let mut rng = Rng(9);
    let bezier = CurveKind::Bezier;
    for (dim, k) in [(3, 100_000), (2, 70_001)] {
        job.push(
            &Curve::new(bezier.clone(), rng.points(4, dim, -1.0, 1.0)).unwrap(),
            &Sampling::PerSegment(k),
        )
        .unwrap();
    }
    let mut samples = Samples::<F>::for_job(&job);
    let planes = samples.planes_for(&job);
    for plane in [Some(planes.points), planes.d1, planes.d2]
        .into_iter()
        .flatten()
    {
        for (i, v) in plane.iter_mut().enumerate() {
            *v = values[i % values.len()];
        }
    }
    let pieces: Vec<splinegpu::Piece> = (0..job.len())
        .map(|curve| splinegpu::Piece {
            curve,
            first_sample: 0,
        })
        .collect();
    let mut text = Vec::new();
    splinegpu_cli::output::write_csv_rows(&samples, &pieces, 3, &mut text).unwrap();
    let text = String::from_utf8(text).unwrap();
    let mut lines = text.lines();
    for c in 0..job.len() {
        let s = samples.curve(c);
        for i in 0..s.t.len() {
            let line = lines.next().expect("a row per sample");
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), 3 + 2 * 3, "{line}");
            assert_eq!((fields[0], fields[1]), (&*c.to_string(), &*i.to_string()));
            assert_eq!(
                fields[2].parse::<f64>().unwrap().to_bits(),
                s.t[i].to_bits()
            );
            for (p, plane) in [s.points, s.d1.unwrap()].iter().enumerate() {
                for k in 0..3 {
                    let field = fields[3 + 3 * p + k];
                    if k >= s.dim {
                        assert_eq!(field, "", "padding of a {}-D curve", s.dim);
                        continue;
                    }
                    let v = plane[i * s.dim + k];
                    let back: F = field.parse().unwrap();
                    assert_eq!(
                        bytemuck::bytes_of(&back),
                        bytemuck::bytes_of(&v),
                        "{field} for {v:?}"
                    );
                    // As short as Rust's own shortest round-trip text (exponent aside).
                    let debug = format!("{v:?}");
                    assert!(field.len() <= debug.len() + 2, "{field} vs {debug}");
                }
            }
        }
    }
    assert_eq!(lines.next(), None);
}

#[test]
fn csv_text_round_trips_every_f64_value_class() {
    csv_round_trip(&value_classes(
        f64::MAX,
        f64::MIN_POSITIVE,
        f64::from_bits(1),
        &[
            0.0,
            1e-300,
            2.2e-310,
            1.0,
            3.0,
            9_007_199_254_740_992.0,
            1e16,
            0.1,
            3.4e38,
            1e-7,
            123.456,
        ],
        |v: f64| -v,
    ));
}

#[test]
fn csv_text_round_trips_every_f32_value_class() {
    csv_round_trip(&value_classes(
        f32::MAX,
        f32::MIN_POSITIVE,
        f32::from_bits(1),
        &[
            0.0,
            1e-40,
            1.0,
            7.0,
            16_777_216.0,
            3.4e38,
            0.1,
            1e-7,
            1e10,
            123.456,
        ],
        |v: f32| -v,
    ));
}
