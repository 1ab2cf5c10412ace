//! `pack`: turns an [`EvalJob`] into the segment, coefficient and run tables of the kernel's
//! ABI ([`super::abi`]) split into dispatches, with every size the GPU path needs computed once
//! ([`Packed`]).
//!
//! Where the samples go is the job's [`JobLayout`](crate::JobLayout) (device planes): nothing
//! here recomputes it.

use std::ops::Range;

use super::abi::{
    GpuLoc, GpuSegment, MODE_ARC, MODE_EXPLICIT, MODE_SCALAR, MODE_VECTOR, MODES, Run, TERMS,
    block_vec4s, is_arc, mode_for,
};
use crate::error::GpuError;
use crate::gpu::KernelShape;
use crate::job::{Derivatives, EvalJob};
use crate::parallel::{even_ranges, fan_out, fan_out_map, take_front};
use crate::points::for_dimension;
use crate::sampling::{ArcSamples, Grid, Plan, SampleLoc};

/// One dispatch: a range of runs whose output is the float range `values` of each plane.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Batch {
    /// Indices into [`Packed::runs`].
    pub runs: Range<usize>,
    /// Floats (of each device plane) this dispatch writes.
    pub values: Range<usize>,
    /// `values.start` rounded down to a multiple of 4: the float its runs' `out_offset`s count
    /// from, so that a vector run's vec4 stores stay aligned whichever run a dispatch starts
    /// with. Floats of `base..values.start` belong to the dispatch before.
    pub base: usize,
    /// The runs of each mode (indexed by `MODE_*`), counted from `runs.start`: the batch's
    /// runs are grouped by mode, and each group is dispatched with the pipeline compiled for
    /// its mode alone.
    pub modes: [Range<usize>; MODES],
}

/// How much one dispatch may hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct BatchLimits {
    /// Output floats per plane.
    pub values: usize,
    /// Runs.
    pub runs: usize,
}

impl BatchLimits {
    /// What one dispatch of a job with `planes` output planes may hold on a device with
    /// `limits`, and at most `max_values` output floats per plane.
    #[must_use]
    pub(crate) fn for_device(limits: &wgpu::Limits, planes: usize, max_values: usize) -> Self {
        let binding = max_binding(limits);
        Self {
            values: ((binding / F32 / planes as u64) as usize).min(max_values),
            runs: (binding / size_of::<Run>() as u64) as usize,
        }
    }
}

const F32: u64 = size_of::<f32>() as u64;

/// The largest storage binding (and buffer) the device allows.
fn max_binding(limits: &wgpu::Limits) -> u64 {
    limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size)
}

/// A job as the kernel reads it, and every size its buffers need.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Packed {
    /// Every curve's segments, curve after curve.
    pub segments: Vec<GpuSegment>,
    /// Per segment, its coefficient block of [`block_vec4s`]`(dim, rational)` vec4s.
    pub coeffs: Vec<[f32; 4]>,
    /// Runs; `out_offset` is relative to the start of the run's batch.
    pub runs: Vec<Run>,
    /// The places of explicitly sampled curves' samples, then, from [`Packed::arc_locs`] on,
    /// room for the places the kernel computes for arc-length samples (curve after curve).
    pub locs: Vec<GpuLoc>,
    /// Where the places of arc-length samples start in [`Packed::locs`].
    pub arc_locs: usize,
    /// The arc-length tables of the curves sampled by arc length (`write_arc_table`).
    pub arcs: Vec<[u32; 4]>,
    /// Dispatches, in output order.
    pub batches: Vec<Batch>,
    /// Output planes: 1 + the derivative order.
    pub planes: usize,
    /// Floats per plane of the whole job's device output (the job layout's
    /// [`device_values`](crate::JobLayout::device_values)).
    pub device_values: usize,
    /// Floats per plane of the output one dispatch writes: its largest batch (from its
    /// [`Batch::base`]), a multiple of 4.
    pub plane_stride: usize,
    /// The t of every sample of the curves sampled by tolerance, curve after curve: found
    /// while packing, so that the host need not compute the places again for `Samples::t`.
    pub computed_t: Vec<f64>,
    /// [`pack_into`]'s runs with absolute float offsets, before they are cut into batches:
    /// kept only for their memory.
    all_runs: Vec<(Run, usize, usize)>,
}

impl Packed {
    /// Bytes of the output one dispatch writes (all its planes).
    #[must_use]
    pub(crate) fn dispatch_output_bytes(&self) -> u64 {
        (self.plane_stride * self.planes) as u64 * F32
    }

    /// Bytes of the whole job's output in the device layout (all planes).
    #[must_use]
    pub(crate) fn output_bytes(&self) -> u64 {
        (self.device_values * self.planes) as u64 * F32
    }

    /// Checks every table against the device's binding limit, and the whole output against
    /// its buffer limit.
    ///
    /// # Errors
    /// [`GpuError::TooLarge`] naming the first table that does not fit.
    pub(crate) fn check(&self, limits: &wgpu::Limits) -> Result<(), GpuError> {
        let binding = max_binding(limits);
        check_size(
            "segment",
            size_of_val(self.segments.as_slice()) as u64,
            binding,
        )?;
        check_size(
            "coefficient",
            size_of_val(self.coeffs.as_slice()) as u64,
            binding,
        )?;
        check_size(
            "sample place",
            size_of_val(self.locs.as_slice()) as u64,
            binding,
        )?;
        check_size(
            "arc-length",
            size_of_val(self.arcs.as_slice()) as u64,
            binding,
        )?;
        check_size("output", self.output_bytes(), limits.max_buffer_size)
    }
}

/// `Err(TooLarge)` when `bytes` exceed `limit`.
pub(crate) fn check_size(table: &'static str, bytes: u64, limit: u64) -> Result<(), GpuError> {
    if bytes > limit {
        Err(GpuError::TooLarge {
            table,
            bytes,
            limit,
        })
    } else {
        Ok(())
    }
}

/// Packs `job` into runs of at most `shape.run_len` samples, and cuts them into dispatches that
/// stay within `limits` (a run holds at most `run_len` · 64 floats per plane).
///
/// The power coefficients are rounded to f32 only here, after M·X was formed in f64; D is
/// split as d_hi = f32(D), d_lo = f32(D − d_hi), so a curve far from the origin keeps its
/// shape to f32 precision of its size, not of its distance from the origin.
///
/// # Errors
/// A coefficient, or 1/Δ where derivatives are asked for, outside the f32 range
/// ([`GpuError::OutOfRange`]).
#[cfg(test)]
pub(crate) fn pack(
    job: &EvalJob,
    shape: KernelShape,
    limits: BatchLimits,
) -> Result<Packed, GpuError> {
    let mut packed = Packed::default();
    pack_into(job, shape, limits, &mut packed)?;
    Ok(packed)
}

/// [`pack`] into `packed`, reusing its memory: a caller packing jobs of similar size again and
/// again allocates nothing and pays no page faults after the first call.
///
/// # Errors
/// As [`pack`].
pub(crate) fn pack_into(
    job: &EvalJob,
    shape: KernelShape,
    limits: BatchLimits,
    packed: &mut Packed,
) -> Result<(), GpuError> {
    let layout = job.layout();
    packed.planes = job.derivatives().order() + 1;
    packed.device_values = layout.device_values();
    let mut all_runs = std::mem::take(&mut packed.all_runs);
    all_runs.clear();
    // `segments` and `coeffs` are resized by `fill_coefficients`, which writes every entry.
    packed.runs.clear();
    packed.locs.clear();
    packed.batches.clear();
    packed.computed_t.clear();
    let mut arc_samples = 0;
    let mut places = Vec::new();
    fill_coefficients(job, &mut packed.segments, &mut packed.coeffs)?;
    let arc_tables = fill_arc_tables(job, &mut packed.arcs);
    let mut first_segment = 0;
    for c in 0..job.len() {
        if c % PLACE_BLOCK == 0 {
            places = computed_places(job, c..(c + PLACE_BLOCK).min(job.len()));
        }
        let (table, plan) = (job.table(c), job.plan(c));
        let dim = table.dim();
        let runs = CurveRuns {
            runs: &mut all_runs,
            first_segment,
            segments: table.len() as u32,
            value_base: layout.device_start(c),
            dim,
            rational: table.is_rational(),
            shape,
        };
        match &plan.0 {
            Plan::Grid(grid) => runs.grid(grid),
            Plan::At(places) => runs.explicit(places, &mut packed.locs),
            // Arc length: the kernel finds each sample's place from the curve's table.
            Plan::Arc(window) => {
                runs.arc(
                    window.first..window.first + window.len,
                    arc_tables[c],
                    arc_samples,
                );
                arc_samples += window.len;
            }
            // Every other plan is placed on the host (tolerance): places decided in f64 (on
            // every thread, a block of curves at a time, so that both backends give the same
            // t), sampled as explicit t are.
            _ => {
                debug_assert!(plan.is_placed_on_host());
                let places = &places[c % PLACE_BLOCK];
                packed.computed_t.extend(places.iter().map(|l| l.t));
                runs.explicit(places, &mut packed.locs);
            }
        }
        first_segment += table.len() as u32;
    }
    // The places of arc-length samples follow the explicit ones.
    packed.arc_locs = packed.locs.len();
    for (run, _, _) in &mut all_runs {
        if is_arc(run.mode) {
            run.first_loc += packed.arc_locs as u32;
        }
    }
    packed
        .locs
        .resize(packed.arc_locs + arc_samples, GpuLoc::default());
    cut_batches(packed, &all_runs, limits);
    packed.all_runs = all_runs;
    packed.plane_stride = (packed.batches.iter())
        .map(|b| (b.values.end - b.base).next_multiple_of(4))
        .max()
        .unwrap_or(0);
    Ok(())
}

/// Every curve's segments and coefficient blocks, curve after curve, filled on every thread
/// (a contiguous range of curves each) into `segments` and `coeffs`, resized for them; the
/// rounding to f32 is [`pack`]'s.
///
/// # Errors
/// [`GpuError::OutOfRange`] for the first curve (by index) with a value outside f32.
fn fill_coefficients(
    job: &EvalJob,
    segments: &mut Vec<GpuSegment>,
    coeffs: &mut Vec<[f32; 4]>,
) -> Result<(), GpuError> {
    let tables: Vec<_> = (0..job.len()).map(|c| job.table(c)).collect();
    let total_segments = tables.iter().map(|t| t.len()).sum();
    let total_vec4s = tables.iter().map(|t| blocks_of(t)).sum();
    let with_inv_dt = job.derivatives() != Derivatives::None;
    // Resized, not cleared: every entry is written below (a refill of the same size writes
    // no zeros first).
    segments.resize(total_segments, GpuSegment::default());
    coeffs.resize(total_vec4s, [0.0; 4]);
    // One contiguous range of curves per thread, with its part of both tables.
    let (mut segments, mut coeffs) = (segments.as_mut_slice(), coeffs.as_mut_slice());
    let mut coeff_base = 0;
    let parts: Vec<_> = even_ranges(tables.len(), crate::available_threads())
        .map(|curves| {
            let part = &tables[curves.clone()];
            let n_segments = part.iter().map(|t| t.len()).sum();
            let n_vec4s = part.iter().map(|t| blocks_of(t)).sum();
            let my_segments = take_front(&mut segments, n_segments);
            let my_coeffs = take_front(&mut coeffs, n_vec4s);
            let base = coeff_base;
            coeff_base += n_vec4s;
            (curves, part, base, my_segments, my_coeffs)
        })
        .collect();
    // The first error by curve index: the parts are in curve order.
    fan_out_map(parts, |(curves, part, base, segments, coeffs)| {
        fill_part(part, curves, base, with_inv_dt, segments, coeffs)
    })
    .into_iter()
    .collect()
}

/// The vec4s of a table's coefficient blocks.
fn blocks_of(table: &crate::SegmentTable) -> usize {
    table.len() * block_vec4s(table.dim(), table.is_rational())
}

/// [`fill_coefficients`] for the curves `curves` (whose tables are `tables`), their segments
/// and blocks going to `segments` and `coeffs`, which start at vec4 `coeff_base` of the whole
/// table; 1/Δ is written `with_inv_dt`, else 0.
fn fill_part(
    tables: &[&crate::SegmentTable],
    curves: Range<usize>,
    coeff_base: usize,
    with_inv_dt: bool,
    segments: &mut [GpuSegment],
    coeffs: &mut [[f32; 4]],
) -> Result<(), GpuError> {
    let (mut s_at, mut at) = (0, 0);
    for (c, table) in curves.zip(tables) {
        let dim = table.dim();
        let block_len = block_vec4s(dim, table.is_rational());
        let curve_blocks = at..at + table.len() * block_len;
        for (s, segment) in segments[s_at..s_at + table.len()].iter_mut().enumerate() {
            *segment = GpuSegment {
                coeff_offset: (coeff_base + at + s * block_len) as u32,
                dim: dim as u32,
            };
        }
        s_at += table.len();
        let blocks: &mut [f32] = bytemuck::cast_slice_mut(&mut coeffs[curve_blocks.clone()]);
        write_blocks(table, with_inv_dt, blocks);
        at = curve_blocks.end;
        // One branch-free pass over the curve's blocks; the search for what overflowed runs
        // only when something did.
        let blocks: &[f32] = bytemuck::cast_slice(&coeffs[curve_blocks]);
        if !blocks.iter().fold(true, |ok, v| ok & v.is_finite()) {
            // The first block with a value out of range, and whether its 1/Δ is.
            let bad = blocks
                .chunks_exact(4 * block_len)
                .find(|block| !block.iter().all(|v| v.is_finite()));
            let what = match bad {
                Some(block) if !block[TERMS * dim].is_finite() => "1/Δ of a segment",
                _ => "a coordinate or power coefficient",
            };
            return Err(GpuError::OutOfRange { curve: c, what });
        }
    }
    Ok(())
}

/// A curve's coefficient blocks (see [`block_vec4s`]): the coordinate k of term t is float
/// t·dim + k of a block; 1/Δ (`with_inv_dt`, else 0) follows the terms, then a rational
/// segment's denominator (a, b, c, d), then zeros to the block's end.
/// d_hi = f32(D), d_lo = f32(D − d_hi). One to four coordinates are compiled for their count
/// ([`write_blocks_of`]), so that a block's stores are unrolled.
fn write_blocks(table: &crate::SegmentTable, with_inv_dt: bool, blocks: &mut [f32]) {
    for_dimension!(table.dim(), write_blocks_of, 0)(table, with_inv_dt, blocks);
}

/// [`write_blocks`] for `D` coordinates, or any where `D` is 0.
fn write_blocks_of<const D: usize>(
    table: &crate::SegmentTable,
    with_inv_dt: bool,
    blocks: &mut [f32],
) {
    let dim = if D == 0 { table.dim() } else { D };
    let block_floats = 4 * block_vec4s(dim, table.is_rational());
    let (knots, power) = (table.knots(), table.power_coefficients());
    let segments = blocks.chunks_exact_mut(block_floats);
    for (s, ((block, coeffs), span)) in segments
        .zip(power.chunks_exact(4 * dim))
        .zip(knots.windows(2))
        .enumerate()
    {
        let (terms, tail) = block.split_at_mut(TERMS * dim);
        let (a, rest) = terms.split_at_mut(dim);
        let (b, rest) = rest.split_at_mut(dim);
        let (c, rest) = rest.split_at_mut(dim);
        let (d_lo, d_hi) = rest.split_at_mut(dim);
        for k in 0..dim {
            a[k] = coeffs[k] as f32;
            b[k] = coeffs[dim + k] as f32;
            c[k] = coeffs[2 * dim + k] as f32;
            let d = coeffs[3 * dim + k];
            d_hi[k] = d as f32;
            d_lo[k] = (d - f64::from(d_hi[k])) as f32;
        }
        let (inv_dt, mut padding) = tail.split_first_mut().expect("1/Δ follows the terms");
        *inv_dt = if with_inv_dt {
            (1.0 / (span[1] - span[0])) as f32
        } else {
            0.0
        };
        if let Some(w) = table
            .is_rational()
            .then(|| table.segment(s).denominator())
            .flatten()
        {
            let (denominator, rest) = padding.split_at_mut(4);
            for (f, v) in denominator.iter_mut().zip(w.coeffs) {
                *f = v as f32;
            }
            padding = rest;
        }
        padding.fill(0.0);
    }
}

/// Curves whose places computed on the host (tolerance) are held at once while packing.
const PLACE_BLOCK: usize = 256;

/// The places of the samples of `curves` placed on the host (tolerance; empty for the others),
/// computed on every thread: most of the packing time of such jobs.
fn computed_places(job: &EvalJob, curves: Range<usize>) -> Vec<Vec<SampleLoc>> {
    let computed: Vec<usize> = curves
        .clone()
        .filter(|&c| job.plan(c).is_placed_on_host())
        .collect();
    let mut places = vec![Vec::new(); curves.len()];
    if computed.is_empty() {
        return places;
    }
    let threads = crate::available_threads().clamp(1, computed.len());
    // Curve k of the block goes to thread k mod threads: neighbours differ least in size.
    let computed = &computed;
    let parts = fan_out_map(
        (0..threads).collect(),
        |k| -> Vec<(usize, Vec<SampleLoc>)> {
            (computed.iter().skip(k).step_by(threads))
                .map(|&c| {
                    let plan = job.plan(c);
                    let mut locs = Vec::with_capacity(plan.len());
                    plan.locs_into(0..plan.len(), &mut locs);
                    (c, locs)
                })
                .collect()
        },
    );
    for (c, locs) in parts.into_iter().flatten() {
        places[c - curves.start] = locs;
    }
    places
}

/// Writes the f32 arc-length table of a curve sampled by arc length into `out`, exactly
/// [`arc_table_len`] vec4s, which start at vec4 `at` of the whole table. Lengths are
/// fractions of the curve's length L, so that f32 keeps 2^-24 of L whatever the curve's size;
/// floats are stored as their bits.
/// - A header: (m − 1, 1/(m − 1), 0, 0).
/// - Per segment: (its start / L, the vec4 of its first piece, its number of pieces, 0).
/// - Per piece of the segments' explicit inverses ([`PlaceTable`](crate::sampling::places::PlaceTable)),
///   segment after segment, two vec4s: (its start / L, u at its start, c1, c2), (c3, c4, c5, u
///   at its end): u = u at its start + (u at its end − u at its start) x, x = c1 y + … + c5 y⁵
///   in y = (s − its start) / its length, the length model's inverse within 1e-7 L. Its end / L
///   is the next piece's start, and after the last piece comes one whose start is 1.
///
/// Where a piece's ends round to the same f32 (a piece of zero length, or shorter than 2^-24
/// L), the kernel places its samples at its start, within its length. On a curve of zero
/// length every piece is so: every sample but the last lies at u = 0 of the last segment, as
/// the CPU places them.
pub(crate) fn write_arc_table(data: &ArcSamples, out: &mut [[u32; 4]], at: u32) {
    let bits = f32::to_bits;
    let last = data.count() - 1;
    out[0] = [last as u32, bits((1.0 / last as f64) as f32), 0, 0];
    let (starts, tables) = (data.starts(), data.tables());
    let length = starts[tables.len()];
    let fraction = |s: f64| {
        if length > 0.0 {
            (s / length) as f32
        } else {
            0.0
        }
    };
    let records = 1;
    let mut w = records + tables.len();
    for (i, table) in tables.iter().enumerate() {
        let first_piece = w;
        for (s, u, end, c) in table.inverse_pieces() {
            // x = c1 y + ... + c5 y^5 in the piece's y (its lengths from 0 to 1); straight where
            // f32 cannot hold it.
            let mut model = [1.0f32, 0.0, 0.0, 0.0, 0.0];
            let inverse = c.map(|v| v as f32);
            if inverse.iter().all(|v| v.is_finite()) {
                model = inverse;
            }
            // On a curve of zero length, every piece holds u = 0 only.
            let (u, end) = if length > 0.0 { (u, end) } else { (0.0, 0.0) };
            let start = fraction(starts[i] + s);
            out[w] = [start, u as f32, model[0], model[1]].map(bits);
            out[w + 1] = [model[2], model[3], model[4], end as f32].map(bits);
            w += ARC_PIECE_VEC4S;
        }
        let pieces = (w - first_piece) / ARC_PIECE_VEC4S;
        out[records + i] = [
            bits(fraction(starts[i])),
            at + first_piece as u32,
            pieces as u32,
            0,
        ];
    }
    // The end of the last piece.
    let end = if length > 0.0 { 1.0 } else { 0.0 };
    out[w] = [bits(end), 0, 0, 0];
    out[w + 1] = [0; 4];
    debug_assert_eq!(w + 2, out.len());
}

/// Vec4s of a curve's table in [`write_arc_table`]'s layout.
fn arc_table_len(data: &ArcSamples) -> usize {
    let pieces: usize = data.tables().iter().map(|t| t.inverse_pieces().len()).sum();
    1 + data.tables().len() + ARC_PIECE_VEC4S * pieces + 2
}

/// The arc-length tables of the job's curves sampled by arc length, filled on every thread (a
/// contiguous range of curves each) into `arcs`, resized for them: the vec4 where each curve's
/// table starts, by curve (0 for curves sampled otherwise, which have none).
fn fill_arc_tables(job: &EvalJob, arcs: &mut Vec<[u32; 4]>) -> Vec<u32> {
    let data: Vec<Option<&ArcSamples>> = (0..job.len())
        .map(|c| match &job.plan(c).0 {
            Plan::Arc(window) => Some(&*window.data),
            _ => None,
        })
        .collect();
    let lengths: Vec<usize> = data.iter().map(|d| d.map_or(0, arc_table_len)).collect();
    let mut starts = Vec::with_capacity(data.len());
    let mut total = 0;
    for &n in &lengths {
        starts.push(total as u32);
        total += n;
    }
    arcs.clear();
    if total == 0 {
        return starts;
    }
    arcs.resize(total, [0; 4]);
    // One contiguous range of curves per thread, with its part of the table.
    let mut rest = arcs.as_mut_slice();
    let parts: Vec<_> = even_ranges(data.len(), crate::available_threads())
        .map(|curves| {
            let len = lengths[curves.clone()].iter().sum();
            (curves, take_front(&mut rest, len))
        })
        .collect();
    fan_out(parts, |(curves, mine)| {
        let mut at = 0;
        for c in curves {
            if let Some(d) = data[c] {
                write_arc_table(d, &mut mine[at..at + lengths[c]], starts[c]);
                at += lengths[c];
            }
        }
    });
    starts
}

/// Vec4s per piece of a segment's explicit inverse in the arc-length table.
const ARC_PIECE_VEC4S: usize = 2;

/// Cuts the runs (with absolute float offsets) into dispatches within `limits`, and makes
/// `out_offset` relative to each dispatch's [`Batch::base`]. A dispatch may start at any run;
/// only a single run larger than `limits.values` exceeds them.
fn cut_batches(packed: &mut Packed, all_runs: &[(Run, usize, usize)], limits: BatchLimits) {
    let mut start = 0;
    while start < all_runs.len() {
        let first_value = all_runs[start].1;
        let base = first_value / 4 * 4;
        let mut end = start + 1;
        while end < all_runs.len()
            && end - start < limits.runs
            && all_runs[end].2 - base <= limits.values
        {
            end += 1;
        }
        // The batch's runs, grouped by mode (in order within a mode).
        let modes = std::array::from_fn(|mode| {
            let first = packed.runs.len() - start;
            let of_mode = all_runs[start..end]
                .iter()
                .filter(|r| r.0.mode == mode as u32);
            for (run, begin, _) in of_mode {
                packed.runs.push(Run {
                    out_offset: (begin - base) as u32,
                    ..*run
                });
            }
            first..packed.runs.len() - start
        });
        packed.batches.push(Batch {
            runs: start..end,
            values: first_value..all_runs[end - 1].2,
            base,
            modes,
        });
        start = end;
    }
}

/// Appends one curve's runs as (run, first float, end float) with absolute float offsets.
struct CurveRuns<'a> {
    runs: &'a mut Vec<(Run, usize, usize)>,
    first_segment: u32,
    /// The curve's number of segments.
    segments: u32,
    /// The float where the curve's first sample goes in each device plane.
    value_base: usize,
    dim: usize,
    /// Whether the curve is rational: its runs take the rational modes.
    rational: bool,
    shape: KernelShape,
}

impl CurveRuns<'_> {
    /// Samples at places of their own: runs of up to run_len samples, each with its own
    /// segment and u.
    fn explicit(self, places: &[SampleLoc], locs: &mut Vec<GpuLoc>) {
        let run_len = self.shape.run_len as usize;
        for (c, chunk) in places.chunks(run_len).enumerate() {
            let begin = self.value_base + c * run_len * self.dim;
            let run = Run {
                segment: 0,
                segments: 1,
                out_offset: 0,
                count: chunk.len() as u32,
                mode: mode_for(MODE_EXPLICIT, self.rational),
                u0: 0.0,
                du: 0.0,
                first_loc: locs.len() as u32,
                arc: 0,
                first: 0,
            };
            locs.extend(chunk.iter().map(|l| GpuLoc {
                segment: self.first_segment + l.segment as u32,
                u: l.u as f32,
            }));
            self.runs.push((run, begin, begin + chunk.len() * self.dim));
        }
    }

    /// Samples `samples` of an arc-length sampling whose table is at `arc` in `arcs`, in runs
    /// of up to run_len samples, their places going to the arc places from `first_place` on.
    fn arc(self, samples: Range<usize>, arc: u32, first_place: usize) {
        let run_len = self.shape.run_len as usize;
        for (c, first) in samples.clone().step_by(run_len).enumerate() {
            let count = run_len.min(samples.end - first);
            let begin = self.value_base + c * run_len * self.dim;
            let run = Run {
                segment: self.first_segment,
                segments: self.segments,
                out_offset: 0,
                count: count as u32,
                mode: mode_for(MODE_ARC, self.rational),
                u0: 0.0,
                du: 0.0,
                first_loc: (first_place + c * run_len) as u32,
                arc,
                first: first as u32,
            };
            self.runs.push((run, begin, begin + count * self.dim));
        }
    }

    /// A window of the per-segment grid: a partial first segment, whole segments, a partial
    /// last segment, and the final point, in output order.
    fn grid(mut self, grid: &Grid) {
        let k = grid.k as usize;
        let closing = grid.closing();
        let (g0, g1) = (grid.first, grid.first + grid.len);
        let grid_end = g1.min(closing);
        // Whole segments s_a..s_b lie inside the window.
        let (s_a, s_b) = (g0.div_ceil(k), grid_end / k);
        if s_a > s_b {
            // The window lies inside one segment.
            let s = g0 / k;
            if g0 < grid_end {
                self.segment_part(s, g0 - s * k..grid_end - s * k, g0, k);
            }
        } else {
            if g0 < s_a * k {
                self.segment_part(s_a - 1, g0 % k..k, g0, k);
            }
            self.whole_segments(s_a..s_b, g0, k);
            if s_b * k < grid_end {
                self.segment_part(s_b, 0..grid_end - s_b * k, g0, k);
            }
        }
        if g1 > closing {
            // The final point, u = 1 on the last segment, on its own.
            self.push_scalar(grid.segments() - 1, closing - g0, 1, 1.0, 0.0);
        }
    }

    /// Whole segments `segments`, the window starting at grid sample `g0`.
    ///
    /// Short segments whose blocks all stay vec4-aligned share runs, several segments each,
    /// so that one looping invocation writes up to `run_len` samples.
    fn whole_segments(&mut self, segments: Range<usize>, g0: usize, k: usize) {
        let per_run = self.shape.run_len as usize / k;
        let begin = self.value_base + (segments.start * k - g0) * self.dim;
        if self.shape.lanes == 1
            && self.dim <= 4
            && k.is_multiple_of(4)
            && per_run >= 2
            && begin.is_multiple_of(4)
        {
            let mut s = segments.start;
            while s < segments.end {
                let n = per_run.min(segments.end - s);
                let begin = self.value_base + (s * k - g0) * self.dim;
                let run = Run {
                    segment: self.first_segment + s as u32,
                    segments: n as u32,
                    out_offset: 0,
                    count: k as u32,
                    mode: mode_for(MODE_VECTOR, self.rational),
                    u0: 0.0,
                    du: (1.0 / k as f64) as f32,
                    first_loc: 0,
                    arc: 0,
                    first: 0,
                };
                self.runs.push((run, begin, begin + n * k * self.dim));
                s += n;
            }
        } else {
            for s in segments {
                self.segment_part(s, 0..k, g0, k);
            }
        }
    }

    /// Grid samples `j` of segment `s` (local indices, u = j/k), in runs of at most `run_len`.
    fn segment_part(&mut self, s: usize, j: Range<usize>, g0: usize, k: usize) {
        let run_len = self.shape.run_len as usize;
        for j0 in j.clone().step_by(run_len) {
            let count = run_len.min(j.end - j0);
            let (kf, j0f) = (k as f64, j0 as f64);
            self.push_scalar(s, s * k + j0 - g0, count as u32, j0f / kf, 1.0 / kf);
        }
    }

    /// `count` samples of segment `segment` at u = u0 + j·du, written from the curve's sample
    /// `sample` on: a head of fewer than 4 samples, after which the floats start at a multiple
    /// of 4, then (for dim <= 4) a body of whole groups of 4 samples written as vec4s, then a
    /// tail.
    fn push_scalar(&mut self, segment: usize, sample: usize, count: u32, u0: f64, du: f64) {
        let dim = self.dim;
        let begin = self.value_base + sample * dim;
        let head = (0..4u32.min(count + 1))
            .find(|&j| (begin + j as usize * dim).is_multiple_of(4))
            .unwrap_or(count);
        let body = if dim <= 4 { (count - head) / 4 * 4 } else { 0 };
        let pieces = [
            (0, head, MODE_SCALAR),
            (head, body, MODE_VECTOR),
            (head + body, count - head - body, MODE_SCALAR),
        ];
        for (j0, n, mode) in pieces {
            if n == 0 {
                continue;
            }
            let first = begin + j0 as usize * dim;
            let run = Run {
                segment: self.first_segment + segment as u32,
                segments: 1,
                out_offset: 0,
                count: n,
                mode: mode_for(mode, self.rational),
                u0: (u0 + f64::from(j0) * du) as f32,
                du: du as f32,
                first_loc: 0,
                arc: 0,
                first: 0,
            };
            self.runs.push((run, first, first + n as usize * dim));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Basis, Curve, CurveKind, Derivatives, EndCondition, Ends, Points, Sampling};

    /// Curves of 1 to 6 dimensions, polynomial and rational, per-segment (k from 1 to 9),
    /// explicit, arc-length and tolerance samplings.
    fn mixed_job() -> EvalJob {
        let mut job = EvalJob::new(Derivatives::First);
        for i in 0..24usize {
            let dim = 1 + i % 6;
            let n = 4 + i % 5;
            let coords = (0..n * dim).map(|v| ((v * 7 + i) % 11) as f64).collect();
            let kind = if i % 5 == 4 {
                // A rational B-spline: clamped knots, interior ones 0.5 apart.
                let interior = (1..n - 3).map(|j| j as f64 * 0.5);
                let last = (n - 3) as f64 * 0.5;
                let knots = [0.0; 4].into_iter().chain(interior).chain([last; 4]);
                CurveKind::Nurbs {
                    knots: knots.collect(),
                    weights: Some((0..n).map(|j| 1.0 + (j % 3) as f64).collect()),
                }
            } else {
                CurveKind::Uniform {
                    basis: Basis::CatmullRom,
                    ends: Ends::Repeat,
                }
            };
            let curve = Curve::new(kind, Points::new(dim, coords).unwrap()).unwrap();
            let sampling = if i % 4 == 3 {
                Sampling::At(vec![0.5, 1.0, 0.0, 2.25])
            } else if i % 6 == 1 {
                Sampling::ArcLength(3 + i as u32)
            } else if i % 6 == 2 {
                Sampling::Tolerance(0.01)
            } else {
                Sampling::PerSegment(1 + (i % 9) as u32)
            };
            job.push(&curve, &sampling).unwrap();
        }
        job
    }

    /// Floats a run writes, from its out_offset on.
    fn run_floats(packed: &Packed, run: &Run) -> usize {
        let dim = packed.segments[run.segment as usize].dim as usize;
        let dim = if crate::gpu::curves::abi::kernel_mode(run.mode).0 == MODE_EXPLICIT {
            packed.segments[packed.locs[run.first_loc as usize].segment as usize].dim as usize
        } else {
            dim
        };
        if is_arc(run.mode) {
            // One sample after the other, whichever segments they fall on.
            return run.count as usize * dim;
        }
        run.segments as usize * run.count as usize * dim
    }

    /// Checks that the runs write every float of every curve's device range exactly once, and
    /// nothing else, in dispatches that start aligned and stay within `limits`.
    fn assert_covers_exactly(job: &EvalJob, shape: KernelShape, limits: BatchLimits) {
        let packed = pack(job, shape, limits).unwrap();
        let layout = job.layout();
        let mut writes = vec![0u8; layout.device_values()];
        for batch in &packed.batches {
            assert_eq!(batch.base % 4, 0, "{shape:?}: dispatch based aligned");
            assert!(batch.runs.len() <= limits.runs);
            // The modes' groups follow one another, cover the batch, and hold their mode only.
            let runs = &packed.runs[batch.runs.clone()];
            let mut next = 0;
            for (mode, group) in batch.modes.iter().enumerate() {
                assert_eq!(group.start, next, "{shape:?}: groups in order");
                assert!(runs[group.clone()].iter().all(|r| r.mode == mode as u32));
                next = group.end;
            }
            assert_eq!(next, runs.len(), "{shape:?}: every run in a group");
            for run in runs {
                let start = batch.base + run.out_offset as usize;
                let end = start + run_floats(&packed, run);
                assert!(
                    start >= batch.values.start && end <= batch.values.end,
                    "{shape:?}: run inside its dispatch"
                );
                if crate::gpu::curves::abi::kernel_mode(run.mode).0 == MODE_VECTOR {
                    assert_eq!(start % 4, 0, "{shape:?}: vector runs aligned");
                }
                for w in &mut writes[start..end] {
                    *w += 1;
                }
            }
            // Within limits, unless one run alone is larger (a run is never split).
            assert!(
                batch.values.end - batch.base <= limits.values || batch.runs.len() == 1,
                "{shape:?}: within limits: {batch:?}"
            );
        }
        for c in 0..job.len() {
            let start = layout.device_start(c);
            let end = start + layout.values_of(c).len();
            assert!(
                writes[start..end].iter().all(|&w| w == 1),
                "{shape:?}: curve {c}"
            );
            let next = if c + 1 < job.len() {
                layout.device_start(c + 1)
            } else {
                layout.device_values()
            };
            assert!(
                writes[end..next].iter().all(|&w| w == 0),
                "{shape:?}: padding"
            );
        }
        assert_eq!(packed.plane_stride % 4, 0);
        assert_eq!(packed.device_values, layout.device_values());
    }

    #[test]
    fn runs_write_every_float_of_every_curve_once() {
        let job = mixed_job();
        for shape in KernelShape::TESTED {
            for limits in [
                BatchLimits {
                    values: usize::MAX,
                    runs: usize::MAX,
                },
                BatchLimits {
                    values: 40,
                    runs: 5,
                },
            ] {
                assert_covers_exactly(&job, shape, limits);
            }
        }
    }

    #[test]
    fn chunks_cut_inside_segments_are_covered_too() {
        let job = mixed_job();
        for max in [1, 3, 10, 17] {
            for chunk in job.chunks(max) {
                for shape in KernelShape::TESTED {
                    let limits = BatchLimits {
                        values: 64,
                        runs: 4,
                    };
                    assert_covers_exactly(&chunk.job, shape, limits);
                }
            }
        }
    }

    #[test]
    fn coefficients_outside_f32_are_refused_with_the_curve() {
        let mut job = EvalJob::new(Derivatives::None);
        for scale in [1.0, 1e300] {
            let coords = vec![0.0, scale, 2.0 * scale, 3.0 * scale];
            let kind = CurveKind::Uniform {
                basis: Basis::BSpline,
                ends: Ends::Control,
            };
            let curve = Curve::new(kind, Points::new(1, coords).unwrap()).unwrap();
            job.push(&curve, &Sampling::PerSegment(2)).unwrap();
        }
        let limits = BatchLimits {
            values: usize::MAX,
            runs: usize::MAX,
        };
        let mut packed = Packed::default();
        match pack_into(&job, KernelShape::LOOPING, limits, &mut packed) {
            Err(GpuError::OutOfRange {
                curve: 1,
                what: "a coordinate or power coefficient",
            }) => {}
            other => panic!("expected curve 1 out of range, got {other:?}"),
        }
        // Knots 1e-300 apart: every coefficient fits f32, 1/Δ does not. Positions do not use
        // it, so only a job with derivatives is refused.
        let kind = CurveKind::Interpolating {
            condition: EndCondition::Natural,
            t: Some(vec![0.0, 1e-300, 2e-300]),
        };
        let curve = Curve::new(kind, Points::new(1, vec![0.0, 1.0, 0.5]).unwrap()).unwrap();
        let mut positions = EvalJob::new(Derivatives::None);
        positions.push(&curve, &Sampling::PerSegment(2)).unwrap();
        pack_into(&positions, KernelShape::LOOPING, limits, &mut packed).unwrap();
        let mut job = EvalJob::new(Derivatives::First);
        job.push(&curve, &Sampling::PerSegment(2)).unwrap();
        match pack_into(&job, KernelShape::LOOPING, limits, &mut packed) {
            Err(GpuError::OutOfRange {
                curve: 0,
                what: "1/Δ of a segment",
            }) => {}
            other => panic!("expected curve 0's 1/Δ out of range, got {other:?}"),
        }
        // A refused packing leaves nothing behind that fails the next one.
        pack_into(&mixed_job(), KernelShape::LOOPING, limits, &mut packed).unwrap();
    }
}
