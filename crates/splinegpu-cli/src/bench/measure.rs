//! How the bench measures: the median and fastest of repeated runs after a warm-up
//! ([`time`]), each reported as a [`Measurement`] (a contract `--json` line), and the machine's
//! store bandwidth beside them ([`memset`]): the ratios every figure is read against.

use std::hint::black_box;
use std::time::Instant;

use splinegpu::available_threads;

/// The fewest timed runs per measurement, after the warm-up.
pub const REPETITIONS: usize = 5;

/// The seconds of timed runs a measurement gathers at least, where [`MAX_REPETITIONS`] allow:
/// 5 runs of cli-w1's outputs take longer than this, while memset gets 100 runs.
pub const TIMED_SECONDS: f64 = 0.5;

/// The most timed runs per measurement.
pub const MAX_REPETITIONS: usize = 100;

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
    /// For an anchor that answers queries (q1's and q2's), how many of its answers missed
    /// the certified one (the contract's "misses"); None elsewhere.
    pub misses: Option<u64>,
    /// For the strokes, the largest distance of the path's mesh from the exact stroke (the
    /// contract's "max_error"); None elsewhere.
    pub max_error: Option<f64>,
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
        let misses = self
            .misses
            .map(|m| format!(", \"misses\": {m}"))
            .unwrap_or_default();
        let max_error = self
            .max_error
            .map(|e| format!(", \"max_error\": {e:e}"))
            .unwrap_or_default();
        format!(
            "{{\"workload\": \"{}\", \"path\": \"{}\", \"seconds\": {:e}, \"min_seconds\": {:e}, \
             \"max_seconds\": {:e}, \"samples\": {}, \"bytes\": {}, \"gbps\": {:.4}{float}{misses}{max_error}}}",
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
        misses: None,
        max_error: None,
    }
}

/// The bytes memset writes, one per repetition: never zero and never the byte before, so that
/// every store changes memory. Zeros written over zeros are several times faster on some
/// machines than any other store (the CPU drops stores that change nothing;
/// docs/benchmarks.md), and would make memset a bound no evaluator writing real values can
/// approach.
#[derive(Default)]
pub(crate) struct StoreBytes(u8);

impl StoreBytes {
    pub(crate) fn next(&mut self) -> u8 {
        self.0 = self.0 % 255 + 1;
        self.0
    }
}

/// `buffer` set to `byte`, split evenly between all threads.
pub(crate) fn fill_on_every_thread(buffer: &mut [u8], byte: u8) {
    use rayon::prelude::*;
    let chunk = buffer.len().div_ceil(available_threads()).max(1);
    // On the pool the crate's stages run on, so that the floor pays what they pay to start.
    buffer
        .par_chunks_mut(chunk)
        .for_each(|part| part.fill(byte));
}
