//! Writing samples as the contract's CSV and JSON, and output files that appear only whole.
//!
//! Numbers are printed as the shortest text that parses back to the same value of their own
//! type: f32 for GPU samples, f64 for CPU samples and for t (Rust's float formatting has this
//! property; `{:?}` switches to exponent form for very large and very small magnitudes).

use std::fmt::Debug;
use std::fs;
use std::io::{self, Write};
use std::path::Path;

use crate::job::{Derivatives, Piece};
use crate::samples::{CurveSamples, Samples};

/// A sample value: f32 (GPU) or f64 (CPU).
pub trait SampleValue: Copy + Debug {
    /// True unless NaN or infinite.
    fn is_finite_value(self) -> bool;
}

impl SampleValue for f32 {
    fn is_finite_value(self) -> bool {
        self.is_finite()
    }
}

impl SampleValue for f64 {
    fn is_finite_value(self) -> bool {
        self.is_finite()
    }
}

/// Why output could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// A value overflowed its number type (JSON and CSV have no infinities).
    #[error(
        "curve {curve}: sample {sample} is not finite (the curve overflows the output's number type)"
    )]
    NonFinite {
        /// The curve.
        curve: usize,
        /// The sample within the curve.
        sample: usize,
    },
    /// Writing failed.
    #[error("cannot write output: {0}")]
    Io(#[from] io::Error),
    /// The evaluator failed.
    #[error("{0}")]
    Evaluation(String),
}

/// Checks that every value is finite, naming the first sample that is not.
///
/// # Errors
/// [`OutputError::NonFinite`].
pub fn check_finite<F: SampleValue>(samples: &Samples<F>) -> Result<(), OutputError> {
    for c in 0..samples.len() {
        let s = samples.curve(c);
        for plane in [Some(s.points), s.d1, s.d2].into_iter().flatten() {
            if let Some(i) = plane.iter().position(|v| !v.is_finite_value()) {
                return Err(OutputError::NonFinite {
                    curve: c,
                    sample: i / s.dim,
                });
            }
        }
    }
    Ok(())
}

/// Writes CSV: header `curve,sample,t,x0..x{D-1}` (then `dx0..`, `ddx0..` when computed), one
/// row per sample; curves of smaller D leave their missing fields empty.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_csv<F: SampleValue>(samples: &Samples<F>, out: &mut impl Write) -> io::Result<()> {
    let dim = (0..samples.len())
        .map(|c| samples.curve(c).dim)
        .max()
        .unwrap_or(0);
    write_csv_header(dim, samples.derivatives(), out)?;
    let pieces: Vec<Piece> = (0..samples.len())
        .map(|curve| Piece {
            curve,
            first_sample: 0,
        })
        .collect();
    write_csv_rows(samples, &pieces, dim, out)
}

/// The CSV header for curves of at most `dim` coordinates.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_csv_header(
    dim: usize,
    derivatives: Derivatives,
    out: &mut impl Write,
) -> io::Result<()> {
    write!(out, "curve,sample,t")?;
    for (prefix, o) in [("x", 0), ("dx", 1), ("ddx", 2)] {
        if derivatives.order() >= o {
            for k in 0..dim {
                write!(out, ",{prefix}{k}")?;
            }
        }
    }
    writeln!(out)
}

/// CSV rows of `samples`, whose curve i is the piece `pieces[i]` of a larger job (its curve
/// number and first sample number), with `dim` value columns per plane.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_csv_rows<F: SampleValue>(
    samples: &Samples<F>,
    pieces: &[Piece],
    dim: usize,
    out: &mut impl Write,
) -> io::Result<()> {
    for (c, piece) in pieces.iter().enumerate() {
        let s = samples.curve(c);
        for (i, t) in s.t.iter().enumerate() {
            write!(out, "{},{},{t:?}", piece.curve, piece.first_sample + i)?;
            for plane in [Some(s.points), s.d1, s.d2].into_iter().flatten() {
                for v in &plane[i * s.dim..(i + 1) * s.dim] {
                    write!(out, ",{v:?}")?;
                }
                for _ in s.dim..dim {
                    write!(out, ",")?;
                }
            }
            writeln!(out)?;
        }
    }
    Ok(())
}

/// Writes JSON: `{"curves": [{"t": [...], "points": [[...], ...], "d1": [...], "d2": [...]}]}`,
/// "d1"/"d2" only when computed.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_json<F: SampleValue>(samples: &Samples<F>, out: &mut impl Write) -> io::Result<()> {
    write!(out, "{{\"curves\": [")?;
    for c in 0..samples.len() {
        write_json_curve(&samples.curve(c), c == 0, out)?;
    }
    writeln!(out, "]}}")
}

/// One curve's object of the JSON output (preceded by a comma unless it is the `first`).
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_json_curve<F: SampleValue>(
    s: &CurveSamples<'_, F>,
    first: bool,
    out: &mut impl Write,
) -> io::Result<()> {
    if !first {
        write!(out, ",")?;
    }
    write!(out, "\n{{\"t\": [")?;
    for (i, t) in s.t.iter().enumerate() {
        write!(out, "{}{t:?}", if i > 0 { ", " } else { "" })?;
    }
    write!(out, "]")?;
    for (name, plane) in [("points", Some(s.points)), ("d1", s.d1), ("d2", s.d2)] {
        let Some(plane) = plane else { continue };
        write!(out, ", \"{name}\": [")?;
        for (i, point) in plane.chunks_exact(s.dim).enumerate() {
            write!(out, "{}[", if i > 0 { ", " } else { "" })?;
            for (k, v) in point.iter().enumerate() {
                write!(out, "{}{v:?}", if k > 0 { ", " } else { "" })?;
            }
            write!(out, "]")?;
        }
        write!(out, "]")?;
    }
    write!(out, "}}")
}

/// Writes a file that appears only whole: `write` fills a temporary file beside `path`, which
/// is renamed onto `path` only when `write` succeeds. On any failure the temporary file is
/// removed and an existing file at `path` stays as it was.
///
/// # Errors
/// The error of `write`, or an I/O error creating, flushing or renaming the file.
pub fn write_atomically<E: From<io::Error>>(
    path: &Path,
    write: impl FnOnce(&mut io::BufWriter<&fs::File>) -> Result<(), E>,
) -> Result<(), E> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".splinegpu-").suffix(".tmp");
    // tempfile makes private (0600) files; ask for 0666 so that, after the umask, the output
    // gets the same mode as any file the user creates.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let file = builder.tempfile_in(dir)?;
    {
        let mut out = io::BufWriter::new(file.as_file());
        write(&mut out)?;
        out.flush()?;
    }
    file.as_file().sync_all()?;
    file.persist(path).map_err(|e| e.error)?;
    Ok(())
}
