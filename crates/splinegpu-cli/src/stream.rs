//! Output that streams: a job evaluated chunk by chunk ([`EvalJob::chunks`]) and written as it
//! goes, so that memory stays bounded however many samples there are.
//!
//! CSV is streamed chunk by chunk. NPZ holds each array whole, one after the other: `t` first
//! when the plans give it without evaluating, `points` while the chunks are evaluated, then the
//! derivatives (and an arc-length or tolerance job's `t`, computed with the points), which wait
//! in temporary files for their turn. JSON evaluates runs of whole curves as CSV does chunks,
//! and writes each curve's t, then its points, then each derivative; a curve longer than a
//! chunk is evaluated chunk by chunk once per plane.

use std::io::{self, Write};

use crate::npz::{Dtype, NpzWriter};
use crate::output::{self, OutputError};
use crate::spill::Spill;
use splinegpu::GpuContext;
use splinegpu::GpuError;
use splinegpu::SamplePlan;
use splinegpu::{Chunk, EvalJob, Piece};
use splinegpu::{SampleFloat, Samples};

/// An output format of the CLI contract.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated rows, one per sample.
    Csv,
    /// One JSON document.
    Json,
    /// numpy's zip of `.npy` arrays.
    Npz,
}

/// Samples per chunk when the caller has no reason to choose: 1,048,576 (24 MiB of 3-D f64
/// positions).
pub const CHUNK_SAMPLES: usize = 1 << 20;

/// Evaluates `job` chunk by chunk with `evaluate` (into one reused `Samples`) and writes it to
/// `out` as `format`, calling `progress` with each chunk's sample count.
///
/// # Errors
/// [`OutputError::Gpu`] from `evaluate`, [`OutputError::NonFinite`] naming the first sample
/// that overflowed (its curve and sample numbers in the whole job), or an I/O error. For NPZ,
/// curves of different dimensions are an error ([`OutputError::MixedDimensions`]).
pub fn write<F: SampleFloat + zmij::Float>(
    job: &EvalJob,
    format: Format,
    chunk_samples: usize,
    mut evaluate: impl FnMut(&EvalJob, &mut Samples<F>) -> Result<(), GpuError>,
    out: &mut impl Write,
    progress: &mut dyn FnMut(u64),
) -> Result<(), OutputError> {
    let mut samples = Samples::for_job(&EvalJob::new(job.derivatives()));
    let mut run =
        |chunk: &EvalJob, pieces: &[Piece], samples: &mut Samples<F>| -> Result<(), OutputError> {
            // Errors name the whole job's curve, not the chunk's.
            evaluate(chunk, samples).map_err(|e| match e {
                GpuError::OutOfRange { curve, what } => GpuError::OutOfRange {
                    curve: pieces[curve].curve,
                    what,
                },
                other => other,
            })?;
            output::check_finite(samples).map_err(|e| match e {
                OutputError::NonFinite { curve, sample } => OutputError::NonFinite {
                    curve: pieces[curve].curve,
                    sample: pieces[curve].first_sample + sample,
                },
                other => other,
            })?;
            progress(chunk.sample_count() as u64);
            Ok(())
        };
    match format {
        Format::Csv => {
            let dim = job.layout().max_dim();
            output::write_csv_header(dim, job.derivatives(), out)?;
            for chunk in job.chunks(chunk_samples) {
                run(&chunk.job, &chunk.pieces, &mut samples)?;
                output::write_csv_rows(&samples, &chunk.pieces, dim, out)?;
            }
        }
        Format::Json => write_json(job, chunk_samples, &mut samples, &mut run, out)?,
        Format::Npz => write_npz(job, chunk_samples, &mut samples, &mut run, out)?,
    }
    Ok(())
}

/// [`write()`] with `gpu`'s evaluator (f32 samples) or, without a context, the fast CPU evaluator
/// on every thread (f64, equal to the reference bit for bit): what `splinegpu tessellate` runs.
///
/// # Errors
/// As [`write()`].
pub fn write_on(
    job: &EvalJob,
    format: Format,
    chunk_samples: usize,
    gpu: Option<&GpuContext>,
    out: &mut impl Write,
    progress: &mut dyn FnMut(u64),
) -> Result<(), OutputError> {
    match gpu {
        Some(gpu) => write(
            job,
            format,
            chunk_samples,
            |j, s: &mut Samples<f32>| gpu.evaluate_into(j, s.planes_for(j)),
            out,
            progress,
        ),
        None => {
            let threads = splinegpu::available_threads();
            let cpu = |j: &EvalJob, s: &mut Samples<f64>| -> Result<(), GpuError> {
                splinegpu::evaluate_cpu_into(j, s.planes_for(j), threads);
                Ok(())
            };
            write(job, format, chunk_samples, cpu, out, progress)
        }
    }
}

/// Hands `write` the t of `plan`'s samples in blocks of at most `block` (numbered from 0),
/// filled into `t`, so that no more than a block is held.
fn for_each_t_block(
    plan: &SamplePlan,
    block: usize,
    t: &mut Vec<f64>,
    mut write: impl FnMut(usize, &[f64]) -> io::Result<()>,
) -> io::Result<()> {
    for (i, start) in (0..plan.len()).step_by(block).enumerate() {
        t.clear();
        plan.extend_t(start..(start + block).min(plan.len()), t);
        write(i, t)?;
    }
    Ok(())
}

type Run<'a, F> = dyn FnMut(&EvalJob, &[Piece], &mut Samples<F>) -> Result<(), OutputError> + 'a;

/// The contract's JSON. Consecutive curves of at most `chunk_samples` samples in all are
/// evaluated together and formatted on every thread; a longer curve is written alone, each of
/// its planes chunk by chunk.
fn write_json<F: SampleFloat + zmij::Float>(
    job: &EvalJob,
    chunk_samples: usize,
    samples: &mut Samples<F>,
    run: &mut Run<'_, F>,
    out: &mut impl Write,
) -> Result<(), OutputError> {
    write!(out, "{{\"curves\": [")?;
    let mut c = 0;
    while c < job.len() {
        if job.plan(c).len() > chunk_samples {
            write_json_long_curve(job, c, chunk_samples, samples, run, out)?;
            c += 1;
            continue;
        }
        let first = c;
        let mut group = EvalJob::new(job.derivatives());
        let mut pieces = Vec::new();
        while c < job.len()
            && (c == first || group.sample_count() + job.plan(c).len() <= chunk_samples)
        {
            group
                .push_curve_of(job, c)
                .expect("curves of a job fit a job");
            pieces.push(Piece {
                curve: c,
                first_sample: 0,
            });
            c += 1;
        }
        run(&group, &pieces, samples)?;
        output::write_json_curves(samples, first, out)?;
    }
    writeln!(out, "]}}")?;
    Ok(())
}

/// Curve `c`'s JSON object when the curve has more than `chunk_samples` samples: its t, then
/// its points, then each derivative, the curve evaluated chunk by chunk once per plane (and
/// once more for t where its places are found while evaluating: t as evaluated, as the other
/// formats write it).
fn write_json_long_curve<F: SampleFloat + zmij::Float>(
    job: &EvalJob,
    c: usize,
    chunk_samples: usize,
    samples: &mut Samples<F>,
    run: &mut Run<'_, F>,
    out: &mut impl Write,
) -> Result<(), OutputError> {
    let plan = job.plan(c);
    let mut one = EvalJob::new(job.derivatives());
    one.push_curve_of(job, c)
        .expect("one curve of a job fits a job");
    // Each chunk of the curve evaluated into `samples`, with its pieces named in the document.
    let mut evaluate = |chunk: &Chunk, samples: &mut Samples<F>| {
        let pieces: Vec<Piece> = (chunk.pieces.iter())
            .map(|p| Piece { curve: c, ..*p })
            .collect();
        run(&chunk.job, &pieces, samples)
    };
    write!(out, "{}\n{{\"t\": [", if c > 0 { "," } else { "" })?;
    if plan.is_computed() {
        for (i, chunk) in one.chunks(chunk_samples).enumerate() {
            evaluate(&chunk, samples)?;
            output::write_json_numbers(samples.curve(0).t, i == 0, out)?;
        }
    } else {
        let mut t = Vec::new();
        for_each_t_block(plan, chunk_samples, &mut t, |i, t| {
            output::write_json_numbers(t, i == 0, out)
        })?;
    }
    write!(out, "]")?;
    let names = ["points", "d1", "d2"];
    for (o, name) in names.iter().enumerate().take(job.derivatives().order() + 1) {
        write!(out, ", \"{name}\": [")?;
        for (i, chunk) in one.chunks(chunk_samples).enumerate() {
            evaluate(&chunk, samples)?;
            let s = samples.curve(0);
            let plane = [Some(s.points), s.d1, s.d2][o].expect("computed plane");
            output::write_json_points(plane, s.dim, i == 0, out)?;
        }
        write!(out, "]")?;
    }
    write!(out, "}}")?;
    Ok(())
}

/// Samples per chunk at most for NPZ: 262,144 (6 MiB of 3-D f64 positions), chosen by w1 into
/// a file (docs/benchmarks.md). (CSV formats a chunk's rows in blocks on every thread, and
/// wants its chunks large.)
const NPZ_CHUNK_SAMPLES: usize = 1 << 18;

/// The contract's NPZ: "t" (N,) f64, "points" (N, D), "d1" and "d2" (N, D) when asked for, and
/// "curve_offsets" (curves + 1,) i64.
fn write_npz<F: SampleFloat>(
    job: &EvalJob,
    chunk_samples: usize,
    samples: &mut Samples<F>,
    run: &mut Run<'_, F>,
    out: &mut impl Write,
) -> Result<(), OutputError> {
    let layout = job.layout();
    let dim = if job.is_empty() { 0 } else { layout.dim(0) };
    if let Some(c) = (0..job.len()).find(|&c| layout.dim(c) != dim) {
        return Err(OutputError::MixedDimensions {
            curve: c,
            dim: layout.dim(c),
            first: dim,
        });
    }
    // Smaller chunks than CSV's: each chunk's samples are evaluated, checked, hashed and
    // copied into the file while they are still in cache.
    let chunk_samples = chunk_samples.min(NPZ_CHUNK_SAMPLES);
    let dtype = Dtype::of::<F>();
    let n = layout.samples() as u64;
    let order = job.derivatives().order();
    let mut npz = NpzWriter::new(out);
    // t first, from the plans, when they give it for nothing (a grid, explicit t); where
    // computing the places is most of the work (arc length, tolerance), t is computed with
    // the points and waits in a temporary file, as the derivatives do.
    let t_later = (0..job.len()).any(|c| job.plan(c).is_computed());
    if !t_later {
        npz.begin("t", Dtype::F64, &[n])?;
        let mut t = Vec::new();
        for c in 0..job.len() {
            for_each_t_block(job.plan(c), chunk_samples, &mut t, |_, t| {
                npz.write(bytemuck::cast_slice(t))
            })?;
        }
        npz.end()?;
    }
    let arrays = [
        ("t", Dtype::F64, vec![n]),
        ("d1", dtype, vec![n, dim as u64]),
        ("d2", dtype, vec![n, dim as u64]),
    ];
    let later_arrays: Vec<_> = arrays
        .into_iter()
        .enumerate()
        .filter(|&(i, _)| (i == 0 && t_later) || (i > 0 && i <= order))
        .map(|(_, array)| array)
        .collect();
    let mut later: Vec<Spill> = (0..later_arrays.len()).map(|_| Spill::new()).collect();
    npz.begin("points", dtype, &[n, dim as u64])?;
    for chunk in job.chunks(chunk_samples) {
        run(&chunk.job, &chunk.pieces, samples)?;
        let (t, [points, d1, d2]) = (samples.t(), samples.planes());
        npz.write(bytemuck::cast_slice(points))?;
        let waiting: [&[u8]; 3] = [
            bytemuck::cast_slice(t),
            bytemuck::cast_slice(d1),
            bytemuck::cast_slice(d2),
        ];
        let waiting = waiting.into_iter().skip(usize::from(!t_later));
        for (file, bytes) in later.iter_mut().zip(waiting) {
            file.write_all(bytes)?;
        }
    }
    npz.end()?;
    for ((name, dtype, shape), waiting) in later_arrays.into_iter().zip(&mut later) {
        npz.array_from(name, dtype, &shape, waiting)?;
    }
    npz.begin("curve_offsets", Dtype::I64, &[job.len() as u64 + 1])?;
    let offsets: Vec<i64> = std::iter::once(0)
        .chain((0..job.len()).map(|c| layout.samples_of(c).end as i64))
        .collect();
    npz.write(bytemuck::cast_slice(&offsets))?;
    npz.end()?;
    npz.finish()?;
    Ok(())
}
