//! Output that streams: a job evaluated chunk by chunk ([`EvalJob::chunks`]) and written as it
//! goes, so that memory stays bounded however many samples there are.
//!
//! CSV and NPZ are streamed chunk by chunk. NPZ holds each array whole, one after the other:
//! `t` comes from the plans without evaluating, `points` is written while the chunks are
//! evaluated, and the derivatives wait in temporary files for their turn. JSON writes each
//! curve's t before its points, so it holds one curve at a time.

use std::io::{self, Read, Seek, Write};

use bytemuck::Pod;

use crate::job::{EvalJob, Piece};
use crate::npz::{Dtype, NpzWriter};
use crate::output::{self, OutputError, SampleValue};
use crate::samples::Samples;

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
/// [`OutputError::Evaluation`] from `evaluate`, [`OutputError::NonFinite`] naming the first
/// sample that overflowed (its curve and sample numbers in the whole job), or an I/O error.
/// For NPZ, curves of different dimensions are an error.
pub fn write<F: SampleValue + Default + Pod>(
    job: &EvalJob,
    format: Format,
    chunk_samples: usize,
    dtype: Dtype,
    mut evaluate: impl FnMut(&EvalJob, &mut Samples<F>) -> Result<(), String>,
    out: &mut impl Write,
    progress: &mut dyn FnMut(u64),
) -> Result<(), OutputError> {
    let mut samples = Samples::for_job(&EvalJob::new(job.derivatives()));
    let mut run =
        |chunk: &EvalJob, pieces: &[Piece], samples: &mut Samples<F>| -> Result<(), OutputError> {
            evaluate(chunk, samples).map_err(OutputError::Evaluation)?;
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
            let dim = (0..job.len())
                .map(|c| job.table(c).dim())
                .max()
                .unwrap_or(0);
            output::write_csv_header(dim, job.derivatives(), out)?;
            for chunk in job.chunks(chunk_samples) {
                run(&chunk.job, &chunk.pieces, &mut samples)?;
                output::write_csv_rows(&samples, &chunk.pieces, dim, out)?;
            }
        }
        Format::Json => {
            write!(out, "{{\"curves\": [")?;
            for c in 0..job.len() {
                let mut one = EvalJob::new(job.derivatives());
                one.push_table(job.table(c).clone(), job.plan(c).clone());
                run(
                    &one,
                    &[Piece {
                        curve: c,
                        first_sample: 0,
                    }],
                    &mut samples,
                )?;
                output::write_json_curve(&samples.curve(0), c == 0, out)?;
            }
            writeln!(out, "]}}")?;
        }
        Format::Npz => write_npz(job, chunk_samples, dtype, &mut samples, &mut run, out)?,
    }
    Ok(())
}

type Run<'a, F> = dyn FnMut(&EvalJob, &[Piece], &mut Samples<F>) -> Result<(), OutputError> + 'a;

/// The contract's NPZ: "t" (N,) f64, "points" (N, D), "d1" and "d2" (N, D) when asked for, and
/// "curve_offsets" (curves + 1,) i64.
fn write_npz<F: SampleValue + Default + Pod>(
    job: &EvalJob,
    chunk_samples: usize,
    dtype: Dtype,
    samples: &mut Samples<F>,
    run: &mut Run<'_, F>,
    out: &mut impl Write,
) -> Result<(), OutputError> {
    let dim = if job.is_empty() {
        0
    } else {
        job.table(0).dim()
    };
    if let Some(c) = (0..job.len()).find(|&c| job.table(c).dim() != dim) {
        return Err(OutputError::Evaluation(format!(
            "npz needs one dimension for all curves: curve 0 has {dim}, curve {c} has {}",
            job.table(c).dim()
        )));
    }
    let n = job.sample_count() as u64;
    let order = job.derivatives().order();
    let mut npz = NpzWriter::new(out);
    // t, from the plans alone.
    npz.begin("t", Dtype::F64, &[n])?;
    let mut t = Vec::new();
    for chunk in job.chunks(chunk_samples) {
        t.clear();
        for c in 0..chunk.job.len() {
            chunk.job.plan(c).extend_t(&mut t);
        }
        npz.write(bytemuck::cast_slice(&t))?;
    }
    npz.end()?;
    // points, evaluated; the derivatives wait in temporary files.
    let mut later: Vec<io::BufWriter<std::fs::File>> = (0..order)
        .map(|_| tempfile::tempfile().map(io::BufWriter::new))
        .collect::<Result<_, _>>()?;
    npz.begin("points", dtype, &[n, dim as u64])?;
    for chunk in job.chunks(chunk_samples) {
        run(&chunk.job, &chunk.pieces, samples)?;
        let [points, d1, d2] = samples.planes_mut();
        npz.write(bytemuck::cast_slice(points))?;
        for (file, plane) in later.iter_mut().zip([d1, d2]) {
            file.write_all(bytemuck::cast_slice(plane))?;
        }
    }
    npz.end()?;
    for (name, file) in ["d1", "d2"].into_iter().zip(later) {
        let mut file = file.into_inner().map_err(io::IntoInnerError::into_error)?;
        file.rewind()?;
        npz.begin(name, dtype, &[n, dim as u64])?;
        let mut block = vec![0u8; 1 << 20];
        loop {
            let got = file.read(&mut block)?;
            if got == 0 {
                break;
            }
            npz.write(&block[..got])?;
        }
        npz.end()?;
    }
    npz.begin("curve_offsets", Dtype::I64, &[job.len() as u64 + 1])?;
    let mut offset = 0i64;
    let mut offsets = vec![0i64];
    for c in 0..job.len() {
        offset += job.plan(c).len() as i64;
        offsets.push(offset);
    }
    npz.write(bytemuck::cast_slice(&offsets))?;
    npz.end()?;
    npz.finish()?;
    Ok(())
}
