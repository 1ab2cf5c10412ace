//! Writing samples as the contract's CSV and JSON, and output files that appear only whole.
//!
//! Numbers are printed as the shortest text that parses back to the same value of their own
//! type: f32 for GPU samples, f64 for CPU samples and for t (Ryu's algorithm, through the `ryu`
//! crate; it writes exponent form, `1e-7`, `3.4028235e38`, outside 1e-5..1e16). CSV rows are
//! formatted on every thread, block by block, and written in order.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use splinegpu::GpuError;
use splinegpu::{Derivatives, Piece};
use splinegpu::{SampleFloat, Samples};

/// Why output could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// A value overflowed its number type (JSON and CSV have no infinities): the input's fault.
    #[error(
        "curve {curve}: sample {sample} is not finite (the curve overflows the output's number type)"
    )]
    NonFinite {
        /// The curve.
        curve: usize,
        /// The sample within the curve.
        sample: usize,
    },
    /// A surface's value overflowed its number type: the input's fault.
    #[error(
        "surface {surface}: vertex {vertex} is not finite (the surface overflows the output's \
         number type)"
    )]
    SurfaceNonFinite {
        /// The surface.
        surface: usize,
        /// The vertex within the surface.
        vertex: usize,
    },
    /// A mesh's value overflowed f64 (a width or radius so large): the input's fault.
    #[error(
        "curve {curve}: mesh vertex {vertex} is not finite (the mesh overflows the output's \
         number type)"
    )]
    MeshNonFinite {
        /// The curve.
        curve: usize,
        /// The vertex within the curve's mesh.
        vertex: usize,
    },
    /// NPZ holds one array of points: every curve needs the first one's dimension.
    #[error(
        "curve {curve}: \"points\" have {dim} coordinates but curve 0's have {first}: npz output \
         needs one dimension for all curves"
    )]
    MixedDimensions {
        /// The first curve whose dimension differs.
        curve: usize,
        /// Its dimension.
        dim: usize,
        /// Curve 0's.
        first: usize,
    },
    /// The samples could not be made from the input (their memory refused): the input's
    /// fault, as a job too large for the machine is.
    #[error(transparent)]
    Input(#[from] splinegpu::InputError),
    /// Writing failed.
    #[error("cannot write output: {0}")]
    Io(#[from] io::Error),
    /// The GPU evaluator failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

/// Checks that every value is finite, naming the first sample that is not.
///
/// # Errors
/// [`OutputError::NonFinite`].
pub fn check_finite<F: SampleFloat>(samples: &Samples<F>) -> Result<(), OutputError> {
    // One branch-free pass over the planes (vectorised); the search for the first value that
    // is not finite runs only when there is one.
    let finite = |plane: &[F]| plane.iter().fold(true, |ok, v| ok & v.finite());
    if samples.planes().into_iter().all(finite) {
        return Ok(());
    }
    for c in 0..samples.len() {
        let s = samples.curve(c);
        for plane in [Some(s.points), s.d1, s.d2].into_iter().flatten() {
            if let Some(i) = plane.iter().position(|v| !v.finite()) {
                return Err(OutputError::NonFinite {
                    curve: c,
                    sample: i / s.dim,
                });
            }
        }
    }
    Ok(())
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
/// number and first sample number), with `dim` value columns per plane. Blocks of up to
/// [`CSV_BLOCK_ROWS`] rows per thread are formatted on all threads while this thread writes
/// the block before, in row order; fewer rows have smaller blocks, at least four of them
/// where each thread still gets [`CSV_MIN_PART_ROWS`], so that every thread formats and the
/// writing overlaps the formatting.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_csv_rows<F: SampleFloat + zmij::Float>(
    samples: &Samples<F>,
    pieces: &[Piece],
    dim: usize,
    out: &mut impl Write,
) -> io::Result<()> {
    let rows = samples.layout().samples();
    let threads = splinegpu::available_threads().max(1);
    let part = (rows.div_ceil(4 * threads)).clamp(CSV_MIN_PART_ROWS, CSV_BLOCK_ROWS);
    let threads = threads.clamp(1, rows.div_ceil(part).max(1));
    let block = threads * part;
    let blocks = (0..rows).step_by(block).map(|start| {
        let end = (start + block).min(rows);
        (0..threads)
            .map(|k| start + (end - start) * k / threads..start + (end - start) * (k + 1) / threads)
            .collect()
    });
    write_in_order(
        blocks,
        |part, text| csv_rows_text(samples, pieces, dim, part, text),
        out,
    )
}

/// Writes the text of `blocks` in order: each block's parts are formatted by `format`, each on
/// a thread of its own, while this thread writes the block before.
fn write_in_order<P: Send>(
    blocks: impl Iterator<Item = Vec<P>>,
    format: impl Fn(P, &mut Text) + Sync,
    out: &mut impl Write,
) -> io::Result<()> {
    // The texts being written, and those being formatted.
    let (mut written, mut formatted): (Vec<Text>, Vec<Text>) = (Vec::new(), Vec::new());
    let format = &format;
    // One pass past the last block writes it.
    for block in blocks.map(Some).chain([None]) {
        let parts = block.unwrap_or_default();
        if formatted.len() < parts.len() {
            formatted.resize_with(parts.len(), Text::default);
        }
        let written_ok = std::thread::scope(|scope| {
            for (part, text) in parts.into_iter().zip(formatted.iter_mut()) {
                scope.spawn(move || format(part, text));
            }
            written
                .iter()
                .try_for_each(|text| out.write_all(text.as_bytes()))
        });
        written_ok?;
        std::mem::swap(&mut written, &mut formatted);
        formatted.iter_mut().for_each(Text::clear);
    }
    Ok(())
}

/// The JSON objects of `samples`' curves (`{"t": [...], "points": [...], ...}`, each after a
/// line break), the first being curve `first_curve` of the document: a curve after the
/// document's first is preceded by a comma. Groups of curves of about [`JSON_PART_SAMPLES`]
/// samples are formatted on all threads while this thread writes the ones before, in order.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_json_curves<F: SampleFloat + zmij::Float>(
    samples: &Samples<F>,
    first_curve: usize,
    out: &mut impl Write,
) -> io::Result<()> {
    let layout = samples.layout();
    // Consecutive curves of at most JSON_PART_SAMPLES samples, or one longer curve.
    let mut parts = Vec::new();
    let (mut from, mut count) = (0, 0);
    for c in 0..samples.len() {
        let n = layout.samples_of(c).len();
        if c > from && count + n > JSON_PART_SAMPLES {
            parts.push(from..c);
            (from, count) = (c, 0);
        }
        count += n;
    }
    if from < samples.len() {
        parts.push(from..samples.len());
    }
    let threads = splinegpu::available_threads().max(1);
    let blocks = parts.chunks(threads).map(<[_]>::to_vec);
    write_in_order(
        blocks,
        |curves, text| {
            for c in curves {
                json_curve_text(samples, c, first_curve + c, text);
            }
        },
        out,
    )
}

/// Curve samples per thread formatted as JSON at once (about 4 MiB of text for 3-D samples).
pub const JSON_PART_SAMPLES: usize = 1 << 16;

/// Appends the JSON object of `samples`' curve `c`, curve `in_document` of the document.
fn json_curve_text<F: SampleFloat + zmij::Float>(
    samples: &Samples<F>,
    c: usize,
    in_document: usize,
    text: &mut Text,
) {
    let s = samples.curve(c);
    let mut number = zmij::Buffer::new();
    text.reserve(16);
    if in_document > 0 {
        text.push(b',');
    }
    text.put(b"\n{\"t\": [");
    for (j, &t) in s.t.iter().enumerate() {
        text.reserve(2 + PIECE_BYTES);
        if j > 0 {
            text.put(b", ");
        }
        text.put(number.format(t).as_bytes());
    }
    text.reserve(1);
    text.push(b']');
    let planes = [
        (&b"points"[..], Some(s.points)),
        (b"d1", s.d1),
        (b"d2", s.d2),
    ];
    for (name, plane) in planes {
        let Some(plane) = plane else { continue };
        text.reserve(16);
        text.put(b", \"");
        text.put(name);
        text.put(b"\": [");
        for (j, point) in plane.chunks_exact(s.dim).enumerate() {
            text.reserve(4 + s.dim * (2 + PIECE_BYTES));
            text.put(if j > 0 { b", [" } else { b"[" });
            for (k, &v) in point.iter().enumerate() {
                if k > 0 {
                    text.put(b", ");
                }
                text.put(number.format(v).as_bytes());
            }
            text.push(b']');
        }
        text.reserve(1);
        text.push(b']');
    }
    text.reserve(1);
    text.push(b'}');
}

/// Rows formatted per thread at once (about 4 MiB of text for 3-D samples).
pub const CSV_BLOCK_ROWS: usize = 1 << 16;

/// Rows a thread formats at least, when a chunk is cut into smaller blocks than
/// [`CSV_BLOCK_ROWS`]: enough to pay for starting the thread.
pub const CSV_MIN_PART_ROWS: usize = 1 << 12;

/// Appends the CSV text of samples `rows` (numbered across `samples`' curves) to `text`.
#[expect(
    clippy::needless_range_loop,
    reason = "curve c indexes the pieces and the samples' layout alike"
)]
fn csv_rows_text<F: SampleFloat + zmij::Float>(
    samples: &Samples<F>,
    pieces: &[Piece],
    dim: usize,
    rows: std::ops::Range<usize>,
    text: &mut Text,
) {
    if rows.is_empty() {
        return;
    }
    let layout = samples.layout();
    let mut ints = itoa::Buffer::new();
    let (mut t_text, mut floats) = (
        zmij::Buffer::new(),
        [zmij::Buffer::new(), zmij::Buffer::new()],
    );
    let planes = samples.derivatives().order() + 1;
    // The longest row: two integers, t, and every value, each with its separator.
    let row_bytes = 2 * 21 + 25 + planes * dim * 26 + 1;
    for c in layout.curve_of_sample(rows.start)..samples.len() {
        let range = layout.samples_of(c);
        if range.start >= rows.end {
            break;
        }
        let (piece, s) = (&pieces[c], samples.curve(c));
        for i in rows.start.max(range.start) - range.start..rows.end.min(range.end) - range.start {
            text.reserve(row_bytes);
            text.put(ints.format(piece.curve).as_bytes());
            text.push(b',');
            text.put(ints.format(piece.first_sample + i).as_bytes());
            text.push(b',');
            let mut t = Some(t_text.format(s.t[i]));
            for plane in [Some(s.points), s.d1, s.d2].into_iter().flatten() {
                put_values(
                    text,
                    &mut floats,
                    t.take(),
                    &plane[i * s.dim..(i + 1) * s.dim],
                );
                for _ in s.dim..dim {
                    text.push(b',');
                }
            }
            text.push(b'\n');
        }
    }
}

/// Appends `before` (if any), then `,v` for each of `values`, in that order, formatting each
/// number before the one ahead of it is copied. Reading digits back right after zmij stored
/// them stalls: the copy's wide loads span several of its narrow stores, which cannot be
/// forwarded, so the load waits for them to reach the cache. Another number's formatting in
/// between hides that wait (docs/benchmarks.md has the figure).
fn put_values<F: zmij::Float + Copy>(
    text: &mut Text,
    [a, b]: &mut [zmij::Buffer; 2],
    before: Option<&str>,
    values: &[F],
) {
    let mut values = values.iter();
    let Some(&first) = values.next() else {
        if let Some(before) = before {
            text.put(before.as_bytes());
        }
        return;
    };
    let mut held = a.format(first);
    if let Some(before) = before {
        text.put(before.as_bytes());
    }
    while let Some(&v) = values.next() {
        let next = b.format(v);
        text.push(b',');
        text.put(held.as_bytes());
        let Some(&v) = values.next() else {
            text.push(b',');
            text.put(next.as_bytes());
            return;
        };
        held = a.format(v);
        text.push(b',');
        text.put(next.as_bytes());
    }
    text.push(b',');
    text.put(held.as_bytes());
}

/// Text formatted into memory that stays allocated and initialized from one block to the
/// next, so that a number's few bytes go in by fixed-size moves rather than a call to
/// `memcpy` each (which took a fifth of the CSV path's time).
#[derive(Default)]
struct Text {
    bytes: Vec<u8>,
    len: usize,
}

/// The longest piece [`Text::put`] takes: a u64's 20 digits, an f64's 24 characters.
const PIECE_BYTES: usize = 32;

impl Text {
    /// Makes room for `more` bytes (and a piece's slack) past the text.
    fn reserve(&mut self, more: usize) {
        let needed = self.len + more + PIECE_BYTES;
        if self.bytes.len() < needed {
            self.bytes.resize(needed.max(2 * self.bytes.len()), 0);
        }
    }

    fn push(&mut self, byte: u8) {
        self.bytes[self.len] = byte;
        self.len += 1;
    }

    /// Appends `piece` (at most [`PIECE_BYTES`] long) by two overlapping fixed-size moves.
    #[inline(always)]
    fn put(&mut self, piece: &[u8]) {
        let n = piece.len();
        debug_assert!(n <= PIECE_BYTES);
        let to = &mut self.bytes[self.len..self.len + PIECE_BYTES];
        if n >= 16 {
            to[..16].copy_from_slice(&piece[..16]);
            to[n - 16..n].copy_from_slice(&piece[n - 16..]);
        } else if n >= 8 {
            to[..8].copy_from_slice(&piece[..8]);
            to[n - 8..n].copy_from_slice(&piece[n - 8..]);
        } else if n >= 4 {
            to[..4].copy_from_slice(&piece[..4]);
            to[n - 4..n].copy_from_slice(&piece[n - 4..]);
        } else if n > 0 {
            to[0] = piece[0];
            to[n / 2] = piece[n / 2];
            to[n - 1] = piece[n - 1];
        }
        self.len += n;
    }

    fn as_bytes(&self) -> &[u8] {
        &self.bytes[..self.len]
    }

    fn clear(&mut self) {
        self.len = 0;
    }
}

/// Numbers of a JSON array, `, `-separated, preceded by a separator unless they are the
/// `first` of their array.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_json_numbers(values: &[f64], first: bool, out: &mut impl Write) -> io::Result<()> {
    let mut text = zmij::Buffer::new();
    for (i, &v) in values.iter().enumerate() {
        if i > 0 || !first {
            out.write_all(b", ")?;
        }
        out.write_all(text.format(v).as_bytes())?;
    }
    Ok(())
}

/// Points of a JSON array of arrays (`dim` values each), preceded by a separator unless they
/// are the `first` of their array.
///
/// # Errors
/// Any I/O error of `out`.
pub fn write_json_points<F: SampleFloat + zmij::Float>(
    plane: &[F],
    dim: usize,
    first: bool,
    out: &mut impl Write,
) -> io::Result<()> {
    let mut text = zmij::Buffer::new();
    for (i, point) in plane.chunks_exact(dim).enumerate() {
        out.write_all(if i > 0 || !first { b", [" } else { b"[" })?;
        for (k, &v) in point.iter().enumerate() {
            if k > 0 {
                out.write_all(b", ")?;
            }
            out.write_all(text.format(v).as_bytes())?;
        }
        out.write_all(b"]")?;
    }
    Ok(())
}

/// The buffer between the writers and an output file: each write to a file costs a system call
/// and, as the file grows, the file system's bookkeeping (8 KiB writes of NPZ's per-curve `t`
/// blocks took 0.7 s of system time for w1's 317 MB on ext4, 1 MiB writes a tenth of it).
const WRITE_BUFFER: usize = 1 << 20;

/// Writes the output at `path` as the contract says:
/// - a regular file, or a new path, appears only whole: `write` fills a temporary file beside
///   it, which is renamed onto `path` only when `write` succeeds; on any failure the temporary
///   file is removed and an existing file stays as it was. An existing file the user may not
///   write is refused before anything is written (`PermissionDenied`), and the new file keeps
///   an existing one's mode;
/// - a device, FIFO or socket is written directly, never replaced;
/// - a symbolic link is followed to the file it names (which is then treated as above).
///
/// While a temporary file exists its path is listed for [`remove_pending_outputs`], which a
/// signal handler calls before the process ends.
///
/// # Errors
/// The error of `write`, or an I/O error opening, creating, flushing or renaming the file.
pub fn write_output<E: From<io::Error>>(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<(), E>,
) -> Result<(), E> {
    // What the path opens to, links followed: a device, a FIFO or a socket is written in
    // place through the path itself, as a shell's `>` would (so `/dev/stdout`, a link to a
    // link to a pipe that has no path of its own, works too).
    match fs::metadata(path) {
        Ok(meta) if !meta.is_file() && !meta.is_dir() => {
            let file = fs::OpenOptions::new().write(true).open(path)?;
            let mut out = io::BufWriter::with_capacity(WRITE_BUFFER, &file);
            write(&mut out)?;
            out.flush()?;
            Ok(())
        }
        _ => write_atomically(&follow_links(path)?, write),
    }
}

/// `path` with every symbolic link on its last component followed (at most 40, as the
/// kernel's own limit); a dangling link gives the path it names.
fn follow_links(path: &Path) -> io::Result<PathBuf> {
    let mut path = path.to_path_buf();
    for _ in 0..40 {
        match fs::symlink_metadata(&path) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = fs::read_link(&path)?;
                path = match path.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            _ => return Ok(path),
        }
    }
    Err(io::Error::other(format!(
        "too many levels of symbolic links at {}",
        path.display()
    )))
}

/// Temporary output files that exist now, for [`remove_pending_outputs`].
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes every temporary output file that [`write_output`] has not yet renamed or removed:
/// for a signal handler, just before the process exits.
pub fn remove_pending_outputs() {
    let pending = PENDING.lock().unwrap_or_else(PoisonError::into_inner);
    for path in pending.iter() {
        // Already renamed or removed is fine: nothing is left either way.
        let _ = fs::remove_file(path);
    }
}

/// Every this many bytes written, the disk's writing of them is started.
const WRITEBACK_BYTES: u64 = 8 << 20;

/// A file written front to back that has the kernel start writing each [`WRITEBACK_BYTES`]
/// to the disk as soon as they are written (`posix_fadvise(POSIX_FADV_DONTNEED)` on Linux,
/// which starts the writeback of a range's dirty pages and returns), so that the `sync_all`
/// before the rename waits only for the last of them. Without it the disk receives the file
/// only in that sync, after every byte is made; a second thread calling `sync_data` at
/// intervals instead paid a journal commit and a disk flush each time (docs/benchmarks.md). The advice is only a hint: a failure changes nothing, and the final
/// `sync_all` reports any error in the writing.
struct WritebackStarter<'a> {
    file: &'a fs::File,
    written: u64,
    started: u64,
}

impl<'a> WritebackStarter<'a> {
    fn new(file: &'a fs::File) -> Self {
        Self {
            file,
            written: 0,
            started: 0,
        }
    }
}

impl Write for WritebackStarter<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.file.write(buf)?;
        self.written += n as u64;
        if self.written - self.started >= WRITEBACK_BYTES {
            #[cfg(target_os = "linux")]
            {
                let len = std::num::NonZeroU64::new(self.written - self.started);
                let advice = rustix::fs::Advice::DontNeed;
                let _ = rustix::fs::fadvise(self.file, self.started, len, advice);
            }
            self.started = self.written;
        }
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

/// A regular file (or a new path) that appears only whole; see [`write_output`].
fn write_atomically<E: From<io::Error>>(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<(), E>,
) -> Result<(), E> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // A file already there is replaced only where the user may write it (as `cp` and
    // `sort -o` refuse), and the replacement keeps its mode.
    let existing = match fs::metadata(path) {
        Ok(meta) if meta.is_file() => {
            fs::OpenOptions::new().write(true).open(path)?;
            Some(meta.permissions())
        }
        _ => None,
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".splinegpu-").suffix(".tmp");
    // tempfile makes private (0600) files; ask for 0666 so that, after the umask, the output
    // gets the same mode as any file the user creates.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let file = builder.tempfile_in(dir)?;
    let temp = file.path().to_path_buf();
    PENDING
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .push(temp.clone());
    let result = (|| {
        let mut out =
            io::BufWriter::with_capacity(WRITE_BUFFER, WritebackStarter::new(file.as_file()));
        write(&mut out)?;
        out.flush()?;
        drop(out);
        if let Some(permissions) = existing {
            file.as_file().set_permissions(permissions)?;
        }
        file.as_file().sync_all()?;
        file.persist(path).map_err(|e| e.error)?;
        Ok(())
    })();
    PENDING
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .retain(|p| *p != temp);
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pieces of every length `put` takes, one after another, read back as `extend_from_slice`
    /// would have written them.
    #[test]
    fn text_puts_pieces_of_every_length_whole() {
        let mut text = Text::default();
        let mut want = Vec::new();
        for round in 0..3u8 {
            for n in 0..=PIECE_BYTES {
                let piece: Vec<u8> = (0..n).map(|i| b'a' + ((i + n) % 26) as u8).collect();
                text.reserve(n);
                text.put(&piece);
                text.push(b'0' + round);
                want.extend_from_slice(&piece);
                want.push(b'0' + round);
            }
        }
        assert_eq!(text.as_bytes(), &want[..]);
        text.clear();
        text.reserve(3);
        text.put(b"xyz");
        assert_eq!(text.as_bytes(), b"xyz");
    }

    /// Every count of values, with and without a number before them: the text of formatting
    /// them one at a time, in the order given.
    #[test]
    fn put_values_writes_each_number_in_order() {
        let values = [0.1f32, -2.5e-38, 3.4e38, 7.0, -0.0, 1e-45];
        let mut buffers = [zmij::Buffer::new(), zmij::Buffer::new()];
        for n in 0..=values.len() {
            for before in [None, Some("0.03125")] {
                let mut text = Text::default();
                text.reserve(PIECE_BYTES * (n + 1));
                put_values(&mut text, &mut buffers, before, &values[..n]);
                let mut want = before.unwrap_or("").to_string();
                for &v in &values[..n] {
                    want += &format!(",{}", zmij::Buffer::new().format(v));
                }
                assert_eq!(std::str::from_utf8(text.as_bytes()).unwrap(), want);
            }
        }
    }
}
