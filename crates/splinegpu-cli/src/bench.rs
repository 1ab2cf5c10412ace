//! `splinegpu bench`: the named workloads of the CLI contract, measured in one run so that
//! their figures can be compared as ratios (GPU against CPU against the machine's memset
//! bandwidth into already-touched memory), since the machines they run on are shared and noisy.
//!
//! Each measurement is the median of at least [`REPETITIONS`] runs after one warm-up run; a
//! short path is repeated until its runs add up to [`TIMED_SECONDS`] (at most
//! [`MAX_REPETITIONS`] runs), so that its fastest run, which the ratios use, is drawn from
//! enough runs to miss most of a shared machine's stalls.

use std::hint::black_box;
use std::time::Instant;

use crate::stream;
use splinegpu::GpuError;
use splinegpu::SegmentTable;
use splinegpu::profiling::STORE_CEILING_RUN;
use splinegpu::wgpu;
use splinegpu::{Basis, GpuContext, SamplePlan, Sampling};
use splinegpu::{Curve, CurveKind, Ends, Points};
use splinegpu::{Derivatives, EvalJob};
use splinegpu::{EndCondition, Fitter};
use splinegpu::{Planes, available_threads, evaluate_cpu_into};
use std::sync::Arc;

/// Why a bench run stopped.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A workload name that is not one of [`WORKLOADS`].
    #[error("unknown workload \"{0}\" (expected one of {names})", names = WORKLOADS.join(", "))]
    UnknownWorkload(String),
    /// The GPU failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// cli-w1's document or output failed.
    #[error("cli-w1: {0}")]
    Cli(String),
}

/// w1's plain loop: 32 samples per segment, positions only.
const W1_PLAIN: Option<PlainLoop> = Some(PlainLoop::Grid(32));

/// The fewest timed runs per measurement, after the warm-up.
pub const REPETITIONS: usize = 5;

/// The seconds of timed runs a measurement gathers at least, where [`MAX_REPETITIONS`] allow:
/// 5 runs of cli-w1's outputs (about a second each here) take longer than this, while memset
/// (about 4 ms) gets 100 runs.
pub const TIMED_SECONDS: f64 = 0.5;

/// The most timed runs per measurement.
pub const MAX_REPETITIONS: usize = 100;

/// The workloads, in the order `bench` runs them by default.
pub const WORKLOADS: [&str; 14] = [
    "w1", "w1-nurbs", "w1-b", "w1-d", "w1-arc", "w1-tol", "fit-1m", "eval-at", "small", "frame",
    "cli-w1", "w1-x10", "s1", "teapot",
];

/// One measurement: a contract `--json` line.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// The workload's name.
    pub workload: &'static str,
    /// "gpu-device", "gpu-end-to-end", "gpu-first-call", "cpu-1t", "cpu-all", "memset",
    /// "fit", "plain-loop" (the floor), or w1-tol's "wang".
    pub path: &'static str,
    /// Median seconds.
    pub seconds: f64,
    /// Fastest run.
    pub min_seconds: f64,
    /// Slowest run.
    pub max_seconds: f64,
    /// Samples (or knots, for a fit) per run.
    pub samples: u64,
    /// Useful output bytes per run (D values of 4 bytes for f32 or 8 for f64, no padding).
    pub bytes: u64,
    /// The output's number type, "f32" or "f64" (None for memset); an extension of the
    /// contract's line, which tells the f32 and f64 CPU measurements apart.
    pub float: Option<&'static str>,
}

impl Measurement {
    /// Useful bytes per second, in GB/s.
    #[must_use]
    pub fn gbps(&self) -> f64 {
        self.bytes as f64 / self.seconds / 1e9
    }

    /// The contract's JSON line.
    #[must_use]
    pub fn to_json(&self) -> String {
        let float = self
            .float
            .map(|f| format!(", \"float\": \"{f}\""))
            .unwrap_or_default();
        format!(
            "{{\"workload\": \"{}\", \"path\": \"{}\", \"seconds\": {:e}, \"min_seconds\": {:e}, \
             \"max_seconds\": {:e}, \"samples\": {}, \"bytes\": {}, \"gbps\": {:.4}{float}}}",
            self.workload,
            self.path,
            self.seconds,
            self.min_seconds,
            self.max_seconds,
            self.samples,
            self.bytes,
            self.gbps()
        )
    }
}

/// Times `run` once to warm up, then at least [`REPETITIONS`] times and until the timed runs
/// add up to [`TIMED_SECONDS`] or [`MAX_REPETITIONS`]; returns (median, min, max) seconds.
/// `run` returns its own measured seconds, or `None` to be timed by the wall clock.
pub fn time(mut run: impl FnMut() -> Option<f64>) -> (f64, f64, f64) {
    run();
    let mut times = Vec::new();
    let mut spent = 0.0;
    while times.len() < REPETITIONS || (spent < TIMED_SECONDS && times.len() < MAX_REPETITIONS) {
        let start = Instant::now();
        let own = run();
        let wall = start.elapsed().as_secs_f64();
        times.push(own.unwrap_or(wall));
        spent += wall;
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], times[0], times[times.len() - 1])
}

/// The machine's memset bandwidth into already-touched memory: `bytes` set by all threads.
#[must_use]
pub fn memset(workload: &'static str, bytes: usize) -> Measurement {
    let mut buffer = vec![0u8; bytes];
    let mut stores = StoreBytes::default();
    let (seconds, min_seconds, max_seconds) = time(|| {
        fill_on_every_thread(&mut buffer, stores.next());
        black_box(&buffer);
        None
    });
    Measurement {
        workload,
        path: "memset",
        seconds,
        min_seconds,
        max_seconds,
        samples: 0,
        bytes: bytes as u64,
        float: None,
    }
}

/// The bytes memset writes, one per repetition: never zero and never the byte before, so that
/// every store changes memory. Zeros written over zeros are about 3x faster on some machines
/// than any other store (this one: 119 MB in 1.3 ms against 3.9 ms for any other byte; the
/// CPU drops stores that change nothing), and would make memset a bound no evaluator
/// writing real values can approach.
#[derive(Default)]
struct StoreBytes(u8);

impl StoreBytes {
    fn next(&mut self) -> u8 {
        self.0 = self.0 % 255 + 1;
        self.0
    }
}

/// `buffer` set to `byte`, split evenly between all threads.
fn fill_on_every_thread(buffer: &mut [u8], byte: u8) {
    use rayon::prelude::*;
    let chunk = buffer.len().div_ceil(available_threads()).max(1);
    // On the pool the crate's stages run on, so that the floor pays what they pay to start.
    buffer
        .par_chunks_mut(chunk)
        .for_each(|part| part.fill(byte));
}

/// The output number type of a cli-w1 path.
#[derive(Clone, Copy)]
enum Float {
    F32,
    F64,
}

impl Float {
    fn bytes(self) -> u64 {
        match self {
            Float::F32 => 4,
            Float::F64 => 8,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Float::F32 => "f32",
            Float::F64 => "f64",
        }
    }
}

/// A deterministic generator (xorshift64*) for the workloads' data.
struct Rng(u64);

impl Rng {
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        lo + (hi - lo) * (bits as f64 / (1u64 << 53) as f64)
    }
}

/// w1's 10,000 curves: 34 control points in 3-D in ±100, "control" ends.
fn w1_curves(basis: &Basis) -> impl Iterator<Item = Curve> + '_ {
    curves_like_w1(basis, 10_000)
}

/// `count` curves made as w1's are (w1's own first, for any count >= 10,000).
fn curves_like_w1(basis: &Basis, count: usize) -> impl Iterator<Item = Curve> + '_ {
    let mut rng = Rng(1);
    (0..count).map(move |_| {
        let points = Points::new(3, (0..34 * 3).map(|_| rng.range(-100.0, 100.0)).collect())
            .expect("finite points");
        let kind = CurveKind::Uniform {
            basis: basis.clone(),
            ends: Ends::Control,
        };
        Curve::new(kind, points).expect("34 points")
    })
}

/// w1 (`basis` Catmull-Rom), w1-b (B-spline), w1-d (w1 with derivatives): w1's curves, 32
/// samples per segment plus the end point: 10,000 × (31 × 32 + 1) = 9,930,000 samples.
#[must_use]
pub fn w1_job(basis: Basis, derivatives: Derivatives) -> EvalJob {
    w1_job_sampled(&basis, derivatives, |_| Sampling::PerSegment(32))
}

/// w1's Catmull-Rom curves, each sampled as `sampling(curve)` says.
fn w1_job_sampled(
    basis: &Basis,
    derivatives: Derivatives,
    sampling: impl Fn(&Curve) -> Sampling,
) -> EvalJob {
    let mut job = EvalJob::new(derivatives);
    for curve in w1_curves(basis) {
        job.push(&curve, &sampling(&curve)).expect("valid sampling");
    }
    job
}

/// w1-nurbs: w1's points as clamped rational B-splines (34 points, knots 0 four times, 30
/// interior knots with spacings 10^U(-1, 1), the end four times; weights in [0.5, 2]), 32
/// samples per span: w1's 31 segments per curve and its 9,930,000 samples.
#[must_use]
pub fn w1_nurbs_job() -> EvalJob {
    let mut rng = Rng(3);
    let mut job = EvalJob::new(Derivatives::None);
    for curve in w1_curves(&Basis::CatmullRom) {
        let mut knots = vec![0.0; 4];
        let mut at = 0.0;
        for _ in 0..30 {
            at += 10f64.powf(rng.range(-1.0, 1.0));
            knots.push(at);
        }
        at += 10f64.powf(rng.range(-1.0, 1.0));
        knots.extend([at; 4]);
        let kind = CurveKind::Nurbs {
            knots,
            weights: Some((0..34).map(|_| rng.range(0.5, 2.0)).collect()),
        };
        let curve = Curve::new(kind, curve.points().clone()).expect("a valid knot vector");
        job.push(&curve, &Sampling::PerSegment(32))
            .expect("valid sampling");
    }
    job
}

/// w1-x10: 100,000 curves made as w1's (99.3 M samples, 1.19 GB of f32 positions), so that
/// on a GPU the timed region dwarfs launch overhead.
#[must_use]
pub fn w1_x10_job() -> EvalJob {
    let mut job = EvalJob::new(Derivatives::None);
    for curve in curves_like_w1(&Basis::CatmullRom, 100_000) {
        job.push(&curve, &Sampling::PerSegment(32))
            .expect("valid sampling");
    }
    job
}

/// w1-arc: w1's curves at 993 points evenly spaced by arc length (w1's 9,930,000 samples).
#[must_use]
pub fn w1_arc_job() -> EvalJob {
    w1_job_sampled(&Basis::CatmullRom, Derivatives::None, |_| {
        Sampling::ArcLength(993)
    })
}

/// The tolerance of w1-tol's curves: 1e-3 of each one's extent.
fn w1_tolerance(curve: &Curve) -> f64 {
    1e-3 * curve.points().extent()
}

/// w1-tol: w1's curves, each at a tolerance of 1e-3 of its own extent.
#[must_use]
pub fn w1_tol_job() -> EvalJob {
    w1_job_sampled(&Basis::CatmullRom, Derivatives::None, |curve| {
        Sampling::Tolerance(w1_tolerance(curve))
    })
}

/// fit-1m's data: 1,000,000 non-uniform knots (spacings within a factor of 100) and 3-D points.
#[must_use]
pub fn fit_1m_data() -> (Vec<f64>, Vec<f64>) {
    let mut rng = Rng(2);
    let mut t = Vec::with_capacity(1_000_000);
    let mut at = 0.0;
    for _ in 0..1_000_000 {
        t.push(at);
        at += 10f64.powf(rng.range(-1.0, 1.0));
    }
    let values = (0..3_000_000).map(|_| rng.range(-10.0, 10.0)).collect();
    (t, values)
}

/// eval-at: 10,000 natural splines of 64 non-uniform knots in 3-D, each at 1,000 random t.
#[must_use]
pub fn eval_at_job() -> EvalJob {
    let mut rng = Rng(3);
    let mut job = EvalJob::new(Derivatives::None);
    for _ in 0..10_000 {
        let mut t = vec![0.0];
        for i in 1..64 {
            t.push(t[i - 1] + rng.range(0.1, 2.0));
        }
        let points = Points::new(3, (0..64 * 3).map(|_| rng.range(-10.0, 10.0)).collect())
            .expect("finite points");
        let ts: Vec<f64> = (0..1_000).map(|_| rng.range(0.0, t[63])).collect();
        let kind = CurveKind::Interpolating {
            condition: EndCondition::Natural,
            t: Some(t),
        };
        let curve = Curve::new(kind, points).expect("valid knots");
        job.push(&curve, &Sampling::At(ts)).expect("t in range");
    }
    job
}

/// Runs the named workloads and hands each measurement to `report` as soon as it is made, each
/// workload's memset first. GPU paths are skipped when `gpu` is `None`. Besides the contract's
/// paths, "gpu-first-call" is a workload's first evaluation on the context (one run).
///
/// # Errors
/// An unknown workload name (before anything runs), or a GPU failure.
pub fn run(
    names: &[String],
    gpu: Option<&GpuContext>,
    mut report: impl FnMut(&Measurement),
) -> Result<(), BenchError> {
    let names: Vec<&'static str> = if names.is_empty() {
        WORKLOADS.to_vec()
    } else {
        names
            .iter()
            .map(|n| {
                WORKLOADS
                    .iter()
                    .find(|w| **w == n.as_str())
                    .copied()
                    .ok_or_else(|| BenchError::UnknownWorkload(n.clone()))
            })
            .collect::<Result<_, _>>()?
    };
    for name in names {
        match name {
            "fit-1m" => fit_1m(&mut report),
            "s1" | "teapot" => crate::surface_bench::run(name, gpu, &mut report)?,
            "cli-w1" => cli_w1(gpu, &mut report)?,
            "w1-x10" => evaluation(name, &w1_x10_job(), W1_PLAIN, gpu, &mut report)?,
            "w1-nurbs" => evaluation(
                name,
                &w1_nurbs_job(),
                Some(PlainLoop::RationalGrid(32)),
                gpu,
                &mut report,
            )?,
            "eval-at" => eval_at(&eval_at_job(), gpu, &mut report)?,
            "small" => small(gpu, &mut report)?,
            "frame" => frame(gpu, &mut report)?,
            "w1-b" => evaluation(
                name,
                &w1_job(Basis::BSpline, Derivatives::None),
                W1_PLAIN,
                gpu,
                &mut report,
            )?,
            "w1-arc" => {
                evaluation(name, &w1_arc_job(), None, gpu, &mut report)?;
                kurbo_arclen(&mut report);
            }
            "w1-tol" => {
                evaluation(name, &w1_tol_job(), None, gpu, &mut report)?;
                wang(&mut report);
                kurbo_flatten(&mut report);
            }
            "w1-d" => evaluation(
                name,
                &w1_job(Basis::CatmullRom, Derivatives::Second),
                None,
                gpu,
                &mut report,
            )?,
            _ => evaluation(
                name,
                &w1_job(Basis::CatmullRom, Derivatives::None),
                W1_PLAIN,
                gpu,
                &mut report,
            )?,
        }
    }
    Ok(())
}

/// The (x, y) projection of w1's first 100 curves: each as our fitted curve and as kurbo's
/// cubic Béziers (the projection of a Catmull-Rom curve is the Catmull-Rom curve of the
/// projected points).
fn projected_w1() -> Vec<(Curve, Vec<kurbo::CubicBez>)> {
    w1_curves(&Basis::CatmullRom)
        .take(100)
        .map(|curve| {
            let xy: Vec<f64> = curve
                .points()
                .coords()
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1]])
                .collect();
            let kind = curve.kind().clone();
            let projected = Curve::new(kind, Points::new(2, xy).expect("finite")).expect("valid");
            let table = projected.fit();
            let beziers = (0..table.len())
                .map(|i| {
                    let [p0, p1, p2, p3] = (table.segment(i).bezier_points())
                        .expect("the bench's arc-length curves are polynomial");
                    let pt = |p: &[f64]| kurbo::Point::new(p[0], p[1]);
                    kurbo::CubicBez::new(pt(&p0), pt(&p1), pt(&p2), pt(&p3))
                })
                .collect();
            (projected, beziers)
        })
        .collect()
}

/// One timed run of `run` (for the anchors, slow by design), returning its samples.
fn once(run: impl FnOnce() -> u64) -> (f64, u64) {
    let start = Instant::now();
    let samples = black_box(run());
    (start.elapsed().as_secs_f64(), samples)
}

/// Ours beside an anchor: the curves sampled as `sampling` says, planned and evaluated in f64
/// on one thread; returns the samples.
fn ours_1t(curves: &[(Curve, Vec<kurbo::CubicBez>)], sampling: impl Fn(&Curve) -> Sampling) -> u64 {
    let mut job = EvalJob::new(Derivatives::None);
    for (curve, _) in curves {
        job.push(curve, &sampling(curve)).expect("valid");
    }
    let mut out = splinegpu::Samples::<f64>::for_job(&job);
    splinegpu::evaluate_cpu_into(&job, out.planes_for(&job), 1);
    job.sample_count() as u64
}

/// A one-run measurement of `samples` 2-D f64 points.
fn anchor(workload: &'static str, path: &'static str, seconds: f64, samples: u64) -> Measurement {
    Measurement {
        workload,
        path,
        seconds,
        min_seconds: seconds,
        max_seconds: seconds,
        samples,
        bytes: samples * 16,
        float: Some("f64"),
    }
}

/// w1-arc's anchor: kurbo's `inv_arclen` placing 993 points by arc length on each of the 100
/// projected curves (to 1e-10 of the length, the contract's CPU target being 1e-4), one
/// thread, one run ("kurbo-arclen"); beside it ours on the same curves ("ours-arclen-1t").
fn kurbo_arclen(report: &mut impl FnMut(&Measurement)) {
    use kurbo::ParamCurveArclen;
    let curves = projected_w1();
    let m = 993;
    let (seconds, samples) = once(|| {
        let mut placed = 0u64;
        for (_, beziers) in &curves {
            let rough: f64 = beziers.iter().map(|b| b.arclen(1e-6)).sum();
            let accuracy = 1e-10 * rough;
            let lengths: Vec<f64> = beziers.iter().map(|b| b.arclen(accuracy)).collect();
            let total: f64 = lengths.iter().sum();
            let (mut segment, mut start) = (0, 0.0);
            for j in 0..m {
                let target = total * j as f64 / (m - 1) as f64;
                while segment + 1 < beziers.len() && start + lengths[segment] < target {
                    start += lengths[segment];
                    segment += 1;
                }
                black_box(beziers[segment].inv_arclen(target - start, accuracy));
                placed += 1;
            }
        }
        placed
    });
    report(&anchor("w1-arc", "kurbo-arclen", seconds, samples));
    let (seconds, samples) = once(|| ours_1t(&curves, |_| Sampling::ArcLength(m as u32)));
    report(&anchor("w1-arc", "ours-arclen-1t", seconds, samples));
}

/// w1-tol's anchor: kurbo's `flatten` of the 100 projected curves, each at 1e-3 of its
/// extent, its points counted ("kurbo-flatten", one run); beside it ours on the same curves
/// and tolerances ("ours-flatten").
fn kurbo_flatten(report: &mut impl FnMut(&Measurement)) {
    let curves = projected_w1();
    let (seconds, samples) = once(|| {
        let mut points = 0u64;
        for (curve, beziers) in &curves {
            let mut path = kurbo::BezPath::new();
            path.move_to(beziers[0].p0);
            for b in beziers {
                path.curve_to(b.p1, b.p2, b.p3);
            }
            kurbo::flatten(path, w1_tolerance(curve), |_| points += 1);
        }
        points
    });
    report(&anchor("w1-tol", "kurbo-flatten", seconds, samples));
    let (seconds, samples) =
        once(|| ours_1t(&curves, |curve| Sampling::Tolerance(w1_tolerance(curve))));
    report(&anchor("w1-tol", "ours-flatten", seconds, samples));
}

/// w1-tol's "wang" path: Wang's count for the same curves and tolerances (its "samples"), and
/// the time to count.
fn wang(report: &mut impl FnMut(&Measurement)) {
    let curves: Vec<(SegmentTable, f64)> = w1_curves(&Basis::CatmullRom)
        .map(|c| (c.fit(), w1_tolerance(&c)))
        .collect();
    let mut samples = 0u64;
    let (seconds, min_seconds, max_seconds) = time(|| {
        // Per curve, Wang's count on every segment, then the final point.
        samples = curves
            .iter()
            .map(|(table, tol)| {
                let segments: u64 = (0..table.len())
                    .map(|s| splinegpu::wang_count(&table.segment(s), *tol) as u64)
                    .sum();
                segments + 1
            })
            .sum();
        black_box(samples);
        None
    });
    report(&Measurement {
        workload: "w1-tol",
        path: "wang",
        seconds,
        min_seconds,
        max_seconds,
        samples,
        bytes: 0,
        float: None,
    });
}

fn fit_1m(report: &mut impl FnMut(&Measurement)) {
    let (t, values) = fit_1m_data();
    let bytes = (t.len() - 1) * 4 * 3 * size_of::<f64>();
    report(&memset("fit-1m", bytes));
    let mut fitter = Fitter::new();
    let mut table = SegmentTable::default();
    let measurement = |path, (seconds, min_seconds, max_seconds)| Measurement {
        workload: "fit-1m",
        path,
        seconds,
        min_seconds,
        max_seconds,
        samples: t.len() as u64,
        bytes: bytes as u64,
        float: Some("f64"),
    };
    let fit = time(|| {
        fitter
            .fit_into(
                black_box(&t),
                black_box(&values),
                3,
                &EndCondition::Natural,
                &mut table,
            )
            .expect("valid data");
        black_box(&table);
        None
    });
    report(&measurement("fit", fit));
    // The floor: the textbook second-derivative system by the Thomas algorithm, then the
    // power coefficients, into reused memory.
    let (mut m, mut scratch) = (Vec::new(), Vec::new());
    let mut out = vec![0.0; bytes / size_of::<f64>()];
    let plain = time(|| {
        crate::plain::natural_fit(
            black_box(&t),
            black_box(&values),
            3,
            &mut m,
            &mut scratch,
            &mut out,
        );
        black_box(&out);
        None
    });
    report(&measurement("plain-loop", plain));
}

/// w1 as the contract's document: the same curves (their coordinates as the shortest text
/// that round-trips them), "control" ends by default, 32 samples per segment.
#[must_use]
pub fn w1_document() -> Vec<u8> {
    let mut rng = Rng(1);
    let mut text = zmij::Buffer::new();
    let mut doc = br#"{"sampling": {"per_segment": 32}, "curves": ["#.to_vec();
    for c in 0..10_000 {
        doc.extend_from_slice(if c > 0 { b",\n" } else { b"\n" });
        doc.extend_from_slice(br#"{"kind": "catmull-rom", "points": ["#);
        for p in 0..34 {
            doc.extend_from_slice(if p > 0 { b", [" } else { b"[" });
            for k in 0..3 {
                if k > 0 {
                    doc.extend_from_slice(b", ");
                }
                doc.extend_from_slice(text.format(rng.range(-100.0, 100.0)).as_bytes());
            }
            doc.push(b']');
        }
        doc.extend_from_slice(b"]}");
    }
    doc.extend_from_slice(b"\n]}\n");
    doc
}

/// `splinegpu tessellate`'s work on `document` into the file `target`: parse, fit, evaluate
/// on `gpu` or the CPU backend, write as `format` (a temporary file renamed onto `target`).
fn tessellate_document(
    document: &[u8],
    target: &std::path::Path,
    format: stream::Format,
    gpu: Option<&GpuContext>,
) -> Result<(), BenchError> {
    let job = crate::document::parse_document_from_reader(document)
        .map_err(|e| BenchError::Cli(e.to_string()))?;
    crate::output::write_output(target, |out| {
        let mut out = out;
        stream::write_on(
            &job,
            format,
            stream::CHUNK_SAMPLES,
            gpu,
            &mut out,
            &mut |_| {},
        )
    })
    .map_err(|e| BenchError::Cli(e.to_string()))
}

/// cli-w1: w1's document through the tessellate path into a file in a temporary folder, as
/// CSV and NPZ from each backend; and "floor-cpu", the least any output path can cost: the
/// document parsed, fitted and evaluated by the CPU backend into reused memory, plus a memset
/// of the NPZ file's size; and the write floors, the same work plus a finished file's bytes
/// written again. Each repetition does the whole work (nothing is cached).
fn cli_w1(
    gpu: Option<&GpuContext>,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), BenchError> {
    let document = w1_document();
    let folder = tempfile::tempdir().map_err(|e| BenchError::Cli(e.to_string()))?;
    let samples = 9_930_000u64;
    let values = samples * 3;
    let npz_bytes = {
        let target = folder.path().join("size.npz");
        tessellate_document(&document, &target, stream::Format::Npz, None)?;
        std::fs::metadata(&target)
            .map_err(|e| BenchError::Cli(e.to_string()))?
            .len()
    };
    report(&memset("cli-w1", npz_bytes as usize));
    // A cli-w1 path's figures: w1's values at 4 or 8 bytes each.
    let measurement = |path, (seconds, min_seconds, max_seconds), float: Float| Measurement {
        workload: "cli-w1",
        path,
        seconds,
        min_seconds,
        max_seconds,
        samples,
        bytes: values * float.bytes(),
        float: Some(float.name()),
    };
    let paths = [
        ("csv-cpu", stream::Format::Csv, "csv", false),
        ("csv-gpu", stream::Format::Csv, "csv", true),
        ("npz-cpu", stream::Format::Npz, "npz", false),
        ("npz-gpu", stream::Format::Npz, "npz", true),
    ];
    for (path, format, extension, on_gpu) in paths {
        let context = if on_gpu {
            match gpu {
                Some(gpu) => Some(gpu),
                None => continue,
            }
        } else {
            None
        };
        let target = folder.path().join(format!("w1.{extension}"));
        let mut failure = None;
        let (seconds, min_seconds, max_seconds) = time(|| {
            if let Err(e) = tessellate_document(&document, &target, format, context) {
                failure = Some(e);
            }
            None
        });
        if let Some(e) = failure {
            return Err(e);
        }
        let float = if on_gpu { Float::F32 } else { Float::F64 };
        report(&measurement(
            path,
            (seconds, min_seconds, max_seconds),
            float,
        ));
    }
    // The floors: the document parsed, fitted and evaluated by the CPU backend into reused
    // memory, then the NPZ file's bytes stored in memory ("floor-cpu"), or a CSV or NPZ file
    // the paths above wrote, written again whole through the same temporary-file-and-rename
    // path into the same target ("csv-write-floor", "npz-write-floor": what putting those
    // bytes in that file costs on this machine, whatever the program).
    let mut samples_f64 = splinegpu::Samples::<f64>::for_job(&EvalJob::new(Derivatives::None));
    let mut floor = |path: &'static str, write: &mut dyn FnMut() -> Result<(), BenchError>| {
        let mut failure = None;
        let (seconds, min_seconds, max_seconds) = time(|| {
            match crate::document::parse_document_from_reader(&document[..]) {
                Ok(job) => splinegpu::evaluate_cpu_into(
                    &job,
                    samples_f64.planes_for(&job),
                    available_threads(),
                ),
                Err(e) => failure = Some(BenchError::Cli(e.to_string())),
            }
            if let Err(e) = write() {
                failure = Some(e);
            }
            black_box(&samples_f64);
            None
        });
        match failure {
            Some(e) => Err(e),
            None => Ok(measurement(
                path,
                (seconds, min_seconds, max_seconds),
                Float::F64,
            )),
        }
    };
    let mut file = vec![0u8; npz_bytes as usize];
    let mut stores = StoreBytes::default();
    report(&floor("floor-cpu", &mut || {
        fill_on_every_thread(&mut file, stores.next());
        black_box(&file);
        Ok(())
    })?);
    drop(file);
    for (path, extension) in [("csv-write-floor", "csv"), ("npz-write-floor", "npz")] {
        let target = folder.path().join(format!("w1.{extension}"));
        let bytes = std::fs::read(&target).map_err(|e| BenchError::Cli(e.to_string()))?;
        report(&floor(path, &mut || {
            crate::output::write_output(&target, |out| out.write_all(&bytes))
                .map_err(|e: std::io::Error| BenchError::Cli(e.to_string()))
        })?);
    }
    Ok(())
}

/// A measurement of `job`'s evaluation: its samples, and its values (every plane) at
/// `bytes_per_value` each (4 for f32, 8 for f64).
fn measured(
    workload: &'static str,
    job: &EvalJob,
    path: &'static str,
    (seconds, min_seconds, max_seconds): (f64, f64, f64),
    bytes_per_value: u64,
) -> Measurement {
    let values = job.layout().values() as u64 * (job.derivatives().order() as u64 + 1);
    Measurement {
        workload,
        path,
        seconds,
        min_seconds,
        max_seconds,
        samples: job.sample_count() as u64,
        bytes: values * bytes_per_value,
        float: Some(if bytes_per_value == 4 { "f32" } else { "f64" }),
    }
}

/// The GPU paths of an evaluation workload. A job larger than the device binds at once (w1-x10's
/// coefficient table on lavapipe) skips them with a note on stderr rather than ending the run.
fn gpu_paths(
    workload: &'static str,
    job: &EvalJob,
    gpu: &GpuContext,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), GpuError> {
    let values = job.layout().values() as u64 * (job.derivatives().order() as u64 + 1);
    let measurement =
        |path, times, bytes_per_value| measured(workload, job, path, times, bytes_per_value);
    // Host memory is reused between runs, as a caller tessellating every frame would.
    let mut samples = splinegpu::Samples::for_job(job);
    // The first call on a context pays what later calls do not (pipeline compilation on
    // lavapipe, buffer allocation): measured once, on its own.
    let start = Instant::now();
    match gpu.evaluate_into(job, samples.planes_for(job)) {
        Err(e @ GpuError::TooLarge { .. }) => {
            eprintln!("splinegpu: {workload}: GPU paths skipped: {e}");
            return Ok(());
        }
        other => other?,
    }
    let first = start.elapsed().as_secs_f64();
    report(&measurement("gpu-first-call", (first, first, first), 4));
    let mut failure = None;
    let device = time(|| match gpu.evaluate_timed(job, samples.planes_for(job)) {
        Ok(time) => Some(time.seconds),
        Err(e) => {
            failure = Some(e);
            Some(0.0)
        }
    });
    if let Some(e) = failure {
        return Err(e);
    }
    report(&measurement("gpu-device", device, 4));
    // Values into the caller's planes, as the CPU paths write them (t is derivable from the
    // plans; `evaluate_into` forms it too).
    let end_to_end = time(|| {
        let values_only = Planes {
            t: None,
            ..samples.planes_for(job)
        };
        black_box(gpu.evaluate_into(job, values_only).ok());
        None
    });
    report(&measurement("gpu-end-to-end", end_to_end, 4));
    if matches!(workload, "w1" | "w1-x10") {
        // What any kernel writing these bytes can reach on this device: one vec4 per
        // invocation, and the looping shape's runs of vec4s.
        let bytes = values * 4;
        for (path, run) in [("gpu-memset", 1), ("gpu-store-ceiling", STORE_CEILING_RUN)] {
            let kernel = gpu.store_kernel(bytes, run)?;
            let mut failure = None;
            let seconds = time(|| match kernel.time(gpu) {
                Ok(s) => Some(s),
                Err(e) => {
                    failure = Some(e);
                    Some(0.0)
                }
            });
            if let Some(e) = failure {
                return Err(e);
            }
            report(&measurement(path, seconds, 4));
        }
    }
    Ok(())
}

/// The plain loop that does an evaluation workload's work (see [`crate::plain`]).
enum PlainLoop {
    /// k samples per segment and the final point, positions only.
    Grid(u32),
    /// The same on rational segments.
    RationalGrid(u32),
}

/// The job of uniform Catmull-Rom curves through `points` (3-D), `k` samples per segment.
fn catmull_rom_job(points: &[Vec<f64>], ends: Ends, k: u32) -> EvalJob {
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends,
    };
    let mut job = EvalJob::new(Derivatives::None);
    for p in points {
        let curve = Curve::new(kind.clone(), Points::new(3, p.clone()).expect("finite"));
        job.push(&curve.expect("enough points"), &Sampling::PerSegment(k))
            .expect("valid sampling");
    }
    job
}

/// small: one Catmull-Rom curve of 16 points in 3-D (control ends), 32 samples per segment
/// (417 samples), the whole call timed as a caller makes it: the curve made from its points,
/// fitted, planned and evaluated. `cpu-call` returns new f32 samples, `cpu-reused` writes into
/// reused ones, `gpu-call` is the GPU's `evaluate` (upload, dispatch, readback); `plain-loop`
/// forms each segment's coefficients from its four points and evaluates them.
fn small(gpu: Option<&GpuContext>, report: &mut impl FnMut(&Measurement)) -> Result<(), GpuError> {
    let workload = "small";
    let mut rng = Rng(16);
    let points = vec![
        (0..16 * 3)
            .map(|_| rng.range(-100.0, 100.0))
            .collect::<Vec<f64>>(),
    ];
    let job = catmull_rom_job(&points, Ends::Control, 32);
    let measurement = |path, times| measured(workload, &job, path, times, 4);
    report(&memset(workload, job.layout().values() * 4));
    if let Some(gpu) = gpu {
        let run = time(|| {
            let job = catmull_rom_job(&points, Ends::Control, 32);
            black_box(gpu.evaluate(&job).ok());
            None
        });
        report(&measurement("gpu-call", run));
    }
    let run = time(|| {
        let job = catmull_rom_job(&points, Ends::Control, 32);
        black_box(splinegpu::evaluate_cpu::<f32>(&job, available_threads()));
        None
    });
    report(&measurement("cpu-call", run));
    let mut reused = splinegpu::Samples::<f32>::for_job(&job);
    let run = time(|| {
        let job = catmull_rom_job(&points, Ends::Control, 32);
        let values_only = Planes {
            t: None,
            ..reused.planes_for(&job)
        };
        evaluate_cpu_into(&job, values_only, available_threads());
        black_box(&reused);
        None
    });
    report(&measurement("cpu-reused", run));
    let mut out = vec![0f32; job.layout().values()];
    let run = time(|| {
        crate::plain::catmull_rom(&points[0], 3, false, 32, &mut out);
        black_box(&out);
        None
    });
    report(&measurement("plain-loop", run));
    Ok(())
}

/// frame: 1,000 closed Catmull-Rom curves of 9 points in 3-D whose points change every frame
/// (two sets, alternated), 16 samples per segment (145,000 samples). Each path's timed region is
/// one frame's host work from the new points, the renderer keeping its job from frame to frame:
/// `gpu-frame-host` refits every curve ([`EvalJob::refit`]) and records the job with
/// `record_into` into a renderer's `STORAGE | VERTEX` buffer, then submits (the GPU's own time
/// is waited for outside the timed region, as a renderer's frame would overlap it);
/// `cpu-frame` refits and evaluates into reused f32 samples on every thread; `gpu-frame-new-job`
/// and `cpu-frame-new-job` make a new job each frame instead; `plain-loop` evaluates each curve
/// from its points on every thread.
fn frame(gpu: Option<&GpuContext>, report: &mut impl FnMut(&Measurement)) -> Result<(), GpuError> {
    let workload = "frame";
    let mut rng = Rng(60);
    let mut frame_points = || -> Vec<Vec<f64>> {
        (0..1_000)
            .map(|_| (0..9 * 3).map(|_| rng.range(-1.0, 1.0)).collect())
            .collect()
    };
    let frames = [frame_points(), frame_points()];
    let job = catmull_rom_job(&frames[0], Ends::Closed, 16);
    let measurement = |path, times| measured(workload, &job, path, times, 4);
    report(&memset(workload, job.layout().values() * 4));
    let mut next = 0;
    let mut points = || {
        next = 1 - next;
        &frames[next]
    };
    let kind = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Closed,
    };
    let mut kept = job.clone();
    // The renderer's frame: its curves moved, its job refitted.
    let refit = |job: &mut EvalJob, points: &[Vec<f64>]| {
        for (c, p) in points.iter().enumerate() {
            let moved = Points::new(3, p.clone()).expect("finite");
            let curve = Curve::new(kind.clone(), moved).expect("9 points");
            job.refit(c, &curve).expect("same knots");
        }
    };
    if let Some(gpu) = gpu {
        let (device, queue) = (gpu.device(), gpu.queue());
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("renderer vertices"),
            size: gpu.output_layout(&job).bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
            mapped_at_creation: false,
        });
        for (path, new_job) in [("gpu-frame-host", false), ("gpu-frame-new-job", true)] {
            let mut failure = None;
            let run = time(|| {
                let start = Instant::now();
                let fresh;
                let job = if new_job {
                    fresh = catmull_rom_job(points(), Ends::Closed, 16);
                    &fresh
                } else {
                    refit(&mut kept, points());
                    &kept
                };
                let mut encoder = device.create_command_encoder(&Default::default());
                if let Err(e) = gpu.record_into(&mut encoder, job, &buffer, 0) {
                    failure = Some(e);
                }
                queue.submit([encoder.finish()]);
                let host = start.elapsed().as_secs_f64();
                // The frame's GPU work, done before the next frame starts: not host time.
                let _ = device.poll(wgpu::PollType::wait_indefinitely());
                Some(host)
            });
            if let Some(e) = failure {
                return Err(e);
            }
            report(&measurement(path, run));
        }
    }
    let mut reused = splinegpu::Samples::<f32>::for_job(&job);
    for (path, new_job) in [("cpu-frame", false), ("cpu-frame-new-job", true)] {
        let run = time(|| {
            let fresh;
            let job = if new_job {
                fresh = catmull_rom_job(points(), Ends::Closed, 16);
                &fresh
            } else {
                refit(&mut kept, points());
                &kept
            };
            let values_only = Planes {
                t: None,
                ..reused.planes_for(job)
            };
            evaluate_cpu_into(job, values_only, available_threads());
            black_box(&reused);
            None
        });
        report(&measurement(path, run));
    }
    let mut out = vec![0f32; job.layout().values()];
    let per_curve = out.len() / 1_000;
    let run = time(|| {
        use rayon::prelude::*;
        (out.par_chunks_mut(per_curve).zip(points()))
            .with_min_len(1_000 / available_threads())
            .for_each(|(out, p)| {
                crate::plain::catmull_rom(p, 3, true, 16, out);
            });
        black_box(&out);
        None
    });
    report(&measurement("plain-loop", run));
    Ok(())
}

/// eval-at as a caller pays it: every path starts from the fitted curves and their parameters,
/// so locating the parameters is inside each timed region. `cpu-1t` and `cpu-all` (f32, and
/// f64 on all threads) are `evaluate_curves_at_into`, which locates and evaluates each t in one
/// pass; `cpu-job` and `gpu-located` build the job (each curve's parameters located into a
/// plan) and evaluate it on the CPU or the GPU; `plain-loop` binary-searches and evaluates.
/// The GPU's other paths (`gpu-device`, `gpu-end-to-end`) take the job already built, as
/// a renderer reusing its plans would.
fn eval_at(
    job: &EvalJob,
    gpu: Option<&GpuContext>,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), GpuError> {
    let workload = "eval-at";
    let measurement =
        |path, times, bytes_per_value| measured(workload, job, path, times, bytes_per_value);
    report(&memset(workload, job.layout().values() * 4));
    let tables: Vec<Arc<SegmentTable>> = (0..job.len())
        .map(|c| Arc::new(job.table(c).clone()))
        .collect();
    let ts: Vec<Vec<f64>> = (0..job.len())
        .map(|c| {
            let plan = job.plan(c);
            (0..plan.len()).map(|i| plan.loc(i).t).collect()
        })
        .collect();
    // What a caller with fitted curves and fresh parameters does to get a job.
    let located = || {
        let mut job = EvalJob::new(Derivatives::None);
        for (table, ts) in tables.iter().zip(&ts) {
            let plan = SamplePlan::new(table, &Sampling::At(ts.clone())).expect("t in range");
            job.push_shared(Arc::clone(table), Arc::new(plan))
                .expect("one dimension");
        }
        job
    };
    let mut f32_out = vec![0f32; job.layout().values()];
    if let Some(gpu) = gpu {
        gpu_paths(workload, job, gpu, report)?;
        let run = time(|| {
            let job = located();
            black_box(gpu.evaluate_into(&job, Planes::new(&mut f32_out)).ok());
            None
        });
        report(&measurement("gpu-located", run, 4));
    }
    for (path, threads) in [("cpu-1t", 1), ("cpu-all", available_threads())] {
        let run = time(|| {
            splinegpu::evaluate_curves_at_into(&tables, &ts, 0, &mut f32_out, threads)
                .expect("t in range");
            black_box(&f32_out);
            None
        });
        report(&measurement(path, run, 4));
    }
    let run = time(|| {
        let job = located();
        evaluate_cpu_into(&job, Planes::new(&mut f32_out), available_threads());
        black_box(&f32_out);
        None
    });
    report(&measurement("cpu-job", run, 4));
    let run = time(|| {
        crate::plain::at(job, &ts, &mut f32_out, available_threads());
        black_box(&f32_out);
        None
    });
    report(&measurement("plain-loop", run, 4));
    let mut f64_out = vec![0f64; job.layout().values()];
    let run = time(|| {
        splinegpu::evaluate_curves_at_into(&tables, &ts, 0, &mut f64_out, available_threads())
            .expect("t in range");
        black_box(&f64_out);
        None
    });
    report(&measurement("cpu-all", run, 8));
    Ok(())
}

fn evaluation(
    workload: &'static str,
    job: &EvalJob,
    plain: Option<PlainLoop>,
    gpu: Option<&GpuContext>,
    report: &mut impl FnMut(&Measurement),
) -> Result<(), GpuError> {
    let values = job.layout().values() as u64 * (job.derivatives().order() as u64 + 1);
    let measurement =
        |path, times, bytes_per_value| measured(workload, job, path, times, bytes_per_value);
    report(&memset(workload, (values * 4) as usize));
    if let Some(gpu) = gpu {
        gpu_paths(workload, job, gpu, report)?;
    }
    // The fast CPU evaluator into already-touched memory, as `--backend auto` uses it without
    // a GPU: f32 on one thread and on all, then f64 on all.
    let mut f32_samples = splinegpu::Samples::<f32>::for_job(job);
    for (path, threads) in [("cpu-1t", 1), ("cpu-all", available_threads())] {
        let run = time(|| {
            let values_only = Planes {
                t: None,
                ..f32_samples.planes_for(job)
            };
            evaluate_cpu_into(job, values_only, threads);
            black_box(&f32_samples);
            None
        });
        report(&measurement(path, run, 4));
    }
    // The floor: a plain two-line loop over the same work, f32 on all threads.
    if let Some(plain) = plain {
        let p = f32_samples.planes_for(job).points;
        let threads = available_threads();
        let run = time(|| {
            match plain {
                PlainLoop::Grid(k) => crate::plain::grid(job, k, p, threads),
                PlainLoop::RationalGrid(k) => crate::plain::rational_grid(job, k, p, threads),
            }
            black_box(&p);
            None
        });
        report(&measurement("plain-loop", run, 4));
    }
    drop(f32_samples);
    let mut f64_samples = splinegpu::Samples::<f64>::for_job(job);
    let run = time(|| {
        let values_only = Planes {
            t: None,
            ..f64_samples.planes_for(job)
        };
        evaluate_cpu_into(job, values_only, available_threads());
        black_box(&f64_samples);
        None
    });
    report(&measurement("cpu-all", run, 8));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_runs_are_repeated_up_to_the_cap_and_their_own_times_reported() {
        let mut calls = 0;
        // Own times 1 ms, 2 ms, ... after the warm-up's; the wall clock barely moves.
        let (median, min, max) = time(|| {
            calls += 1;
            Some(calls as f64 * 1e-3)
        });
        assert_eq!(calls, 1 + MAX_REPETITIONS);
        assert_eq!(min, 2e-3);
        assert_eq!(max, (1 + MAX_REPETITIONS) as f64 * 1e-3);
        assert_eq!(median, (2 + MAX_REPETITIONS / 2) as f64 * 1e-3);
    }

    #[test]
    fn long_runs_are_repeated_the_fewest_times() {
        let mut calls = 0;
        let step = std::time::Duration::from_secs_f64(TIMED_SECONDS / REPETITIONS as f64);
        time(|| {
            calls += 1;
            std::thread::sleep(step);
            None
        });
        assert_eq!(calls, 1 + REPETITIONS);
    }
}
