//! `splinegpu bench`: the named workloads of the CLI contract, measured in one run so that
//! their figures can be compared as ratios (GPU against CPU against the machine's memset
//! bandwidth into already-touched memory), since the machines they run on are shared and noisy.
//!
//! Each measurement is the median of at least [`REPETITIONS`] runs after one warm-up run; a
//! short path is repeated until its runs add up to [`TIMED_SECONDS`] (at most
//! [`MAX_REPETITIONS`] runs), so that its fastest run, which the ratios use, is drawn from
//! enough runs to miss most of a shared machine's stalls.

mod anchors;
mod geometry;
mod measure;
mod queries;
mod strokes;
mod surfaces;
mod workloads;

use anchors::{kurbo_arclen, kurbo_flatten, wang};
use measure::{StoreBytes, fill_on_every_thread};
use workloads::{Rng, w1_curves};

pub use measure::{MAX_REPETITIONS, Measurement, REPETITIONS, TIMED_SECONDS, memset, time};
pub use workloads::{
    eval_at_job, fit_1m_data, w1_arc_job, w1_document, w1_job, w1_nurbs_job, w1_tol_job, w1_x10_job,
};

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
    /// A query workload's points or curves were refused, or the GPU failed on them.
    #[error(transparent)]
    Query(#[from] splinegpu::query::QueryError),
    /// cli-w1's document or output failed.
    #[error("cli-w1: {0}")]
    Cli(String),
}

/// w1's plain loop: 32 samples per segment, positions only.
const W1_PLAIN: Option<PlainLoop> = Some(PlainLoop::Grid(32));

/// The workloads, in the order `bench` runs them by default.
pub const WORKLOADS: [&str; 18] = [
    "w1", "w1-nurbs", "w1-b", "w1-d", "w1-arc", "w1-tol", "fit-1m", "eval-at", "small", "frame",
    "cli-w1", "w1-x10", "s1", "teapot", "tubes", "strokes", "q1", "q2",
];

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
            "s1" | "teapot" => surfaces::run(name, gpu, &mut report)?,
            "tubes" | "strokes" => geometry::run(name, gpu, &mut report)?,
            "q1" => queries::q1(gpu, &mut report)?,
            "q2" => queries::q2(&mut report),
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
                whole_call(name, |_| Sampling::ArcLength(993), &mut report);
                kurbo_arclen(&mut report);
            }
            "w1-tol" => {
                evaluation(name, &w1_tol_job(), None, gpu, &mut report)?;
                whole_call(
                    name,
                    |curve| Sampling::Tolerance(workloads::w1_tolerance(curve)),
                    &mut report,
                );
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
            _ => {
                evaluation(
                    name,
                    &w1_job(Basis::CatmullRom, Derivatives::None),
                    W1_PLAIN,
                    gpu,
                    &mut report,
                )?;
                whole_call(name, |_| Sampling::PerSegment(32), &mut report);
            }
        }
    }
    Ok(())
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
        misses: None,
        max_error: None,
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
        misses: None,
        max_error: None,
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
        misses: None,
        max_error: None,
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

/// `cpu-whole` of w1 (per_segment 32), w1-arc and w1-tol (their samplings): the library call as
/// a caller with w1's points makes it, each run from the points: the curves fitted and planned
/// on every thread (`EvalJob::push_many`), then evaluated in f64 with t into reused samples.
/// The Python bench compares its `tessellate(out=...)` against w1's figure: the difference is
/// the bindings' own cost.
fn whole_call(
    workload: &'static str,
    sampling: impl Fn(&Curve) -> Sampling,
    report: &mut impl FnMut(&Measurement),
) {
    let curves: Vec<(Curve, Sampling)> = w1_curves(&Basis::CatmullRom)
        .map(|curve| {
            let sampling = sampling(&curve);
            (curve, sampling)
        })
        .collect();
    let build = || {
        let mut job = EvalJob::new(Derivatives::None);
        job.push_many(&curves).expect("w1's curves fit");
        job
    };
    let sized = build();
    let mut samples = splinegpu::Samples::<f64>::for_job(&sized);
    let run = time(|| {
        let job = build();
        evaluate_cpu_into(&job, samples.planes_for(&job), available_threads());
        black_box(&samples);
        None
    });
    report(&measured(workload, &sized, "cpu-whole", run, 8));
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
    fn an_anchors_misses_end_its_json_line_and_others_have_none() {
        let mut m = Measurement {
            workload: "q1",
            path: "kurbo",
            seconds: 2.0,
            min_seconds: 2.0,
            max_seconds: 2.0,
            samples: 10,
            bytes: 400,
            float: Some("f64"),
            misses: Some(3),
            max_error: None,
        };
        let line: serde_json::Value = serde_json::from_str(&m.to_json()).unwrap();
        assert_eq!(line["misses"], 3);
        assert_eq!(line["float"], "f64");
        m.misses = None;
        assert!(!m.to_json().contains("misses"));
        assert!(!m.to_json().contains("max_error"));
        // A strokes path's accuracy.
        m.max_error = Some(1.5e-4);
        let line: serde_json::Value = serde_json::from_str(&m.to_json()).unwrap();
        assert_eq!(line["max_error"], 1.5e-4);
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
