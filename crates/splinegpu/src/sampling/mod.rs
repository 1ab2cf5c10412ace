//! Where a curve is sampled: the contract's sampling rules turned into a `SamplePlan` of
//! (segment, local u, t) triples, all resolved in f64 on the host.

use std::ops::Range;
use std::sync::Arc;

pub(crate) mod arc_length;
pub(crate) mod place;
pub(crate) mod places;
pub(crate) mod runs;
pub(crate) mod tolerance;

use crate::error::{InputError, Shown};
use crate::segment::SegmentTable;
use places::PlaceTables;
use runs::{Runs, first_outside};
use tolerance::{MAX_SAMPLES_PER_SEGMENT, Placement};

/// How to sample a curve (contract: "sampling").
#[derive(Clone, Debug, PartialEq)]
pub enum Sampling {
    /// k >= 1 samples per segment at u = j/k, j = 0..k−1, then the final point (last segment at
    /// u = 1): `segments * k + 1` samples. This is the memo's `(n − 3) * grain + 1`.
    PerSegment(u32),
    /// The given parameter values, in order, repeats allowed; each must lie in the curve's range.
    /// At an interior knot the segment that starts there is used; at the end of the range, the
    /// last segment at u = 1.
    At(Vec<f64>),
    /// m >= 2 points evenly spaced by arc length along the whole curve, the first and the last
    /// at its ends: |s(t_j) − j L/(m − 1)| <= 1e-5 L, L the curve's length (the contract asks
    /// 1e-4 L; each segment's length modelled piece by piece, checked against the speed and
    /// the 8-point rule, and inverted explicitly, one polynomial a sample, at the accuracy
    /// the sampling needs rather than the precise length's). A caller who needs places to
    /// 1e-10 L takes them from [`SegmentTable::inv_arclen`] and samples them with
    /// [`Sampling::At`]. The GPU places the samples itself, in f32 from the same explicit
    /// inverses, within 3e-5 L; its t are formed from them in f64.
    ArcLength(u32),
    /// Per segment, as few samples as this method guarantees such that the polyline through
    /// them stays within `tol` (> 0, in the curve's units and D dimensions) of the curve; never
    /// more than Wang's count. Every segment starts with a sample at u = 0; the curve ends with
    /// its final point.
    Tolerance(f64),
}

impl Default for Sampling {
    /// `PerSegment(16)`, the contract's default.
    fn default() -> Self {
        Sampling::PerSegment(16)
    }
}

/// One sample's place on a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleLoc {
    /// The segment's index.
    pub segment: usize,
    /// The local parameter in [0, 1].
    pub u: f64,
    /// The curve parameter t.
    pub t: f64,
}

/// The samples of one curve (or of a piece of one), resolved against its segment table.
///
/// Per-segment sampling stores nothing per sample: sample i is generated on demand from the
/// grid, so a plan of 10^12 samples costs a few words. Explicit t store one [`SampleLoc`] each.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplePlan(pub(crate) Plan);

/// The two shapes of a plan, for the evaluators and the packer of this crate.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Plan {
    /// Samples `first .. first + len` of the grid of a table's segments: grid sample
    /// g = s·k + j is segment s at u = j/k, and g = segments·k is the final point (the last
    /// segment at u = 1). A whole curve is `first = 0, len = segments·k + 1`; a piece of a
    /// curve cut by [`EvalJob::chunks`](crate::EvalJob::chunks) may start and stop anywhere,
    /// inside a segment too.
    Grid(Grid),
    /// Explicit samples.
    At(Vec<SampleLoc>),
    /// Samples `first .. first + len` of a curve's arc-length sampling.
    Arc(Window<ArcSamples>),
    /// Samples `first .. first + len` of a curve's tolerance sampling.
    Tolerance(Window<ToleranceSamples>),
}

/// Samples `first .. first + len` of a sampling whose samples are computed on demand from
/// per-curve data (shared by every window of the curve).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Window<T> {
    pub data: Arc<T>,
    pub first: usize,
    pub len: usize,
}

/// A curve's arc-length sampling: m points at lengths j L/(m − 1).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ArcSamples {
    m: usize,
    /// The length where each segment starts, and, last, the curve's length L.
    starts: Vec<f64>,
    tables: PlaceTables,
    knots: Vec<f64>,
}

impl ArcSamples {
    fn new(table: &SegmentTable, m: usize) -> Self {
        let tables = table.place_tables();
        let mut starts = vec![0.0];
        for t in tables.iter() {
            starts.push(starts[starts.len() - 1] + t.length());
        }
        Self {
            m,
            starts,
            tables,
            knots: table.knots().to_vec(),
        }
    }

    /// The number of samples, m.
    pub(crate) fn count(&self) -> usize {
        self.m
    }

    /// The length where each segment starts, and, last, the curve's length.
    pub(crate) fn starts(&self) -> &[f64] {
        &self.starts
    }

    /// Each segment's place table.
    pub(crate) fn tables(&self) -> &PlaceTables {
        &self.tables
    }

    fn loc(&self, j: usize) -> SampleLoc {
        self.loc_from(j, &mut ArcHint::default())
    }

    /// The places of samples `range`, each as [`ArcSamples::loc_from`] places it (the same
    /// segment, the same inverse piece, the same arithmetic), found by walking the segments'
    /// inverse pieces along with the samples instead of searching for each: the samples of a
    /// piece are counted from where its lengths end (a guess, then the exact test) and placed
    /// together, one polynomial each, in a loop the compiler vectorizes.
    #[inline(always)]
    fn runs_into(&self, range: Range<usize>, out: &mut Runs) {
        let segments = self.tables.len();
        let length = self.starts[segments];
        let denominator = (self.m - 1) as f64;
        let target = |j: usize| length * j as f64 / denominator;
        // The curve's end is placed by loc_from, as its start is.
        let interior_end = range.end.min(self.m - 1);
        let mut hint = ArcHint::default();
        let mut j = range.start;
        while j < range.end {
            // The first of a run (or an end), placed as loc_from places it.
            let first = self.loc_from(j, &mut hint);
            out.push(first.segment, first.u);
            let is_end = j == 0 || j + 1 == self.m;
            j += 1;
            // A target at or below this segment's start is placed afresh (only a curve of
            // length 0 has one after its first sample).
            if is_end || j >= interior_end || target(j) - self.starts[first.segment] <= 0.0 {
                continue;
            }
            let segment = first.segment;
            let table = self.tables.get(segment);
            let start = self.starts[segment];
            let at_end = table.length();
            // The next segment's start: a target there belongs to it.
            let next_start = if segment + 1 < segments {
                self.starts[segment + 1]
            } else {
                f64::INFINITY
            };
            while j < interior_end {
                let (piece, piece_end) = table.inverse_piece(hint.piece);
                let inside = |i: usize| {
                    let t = target(i);
                    t < next_start && t - start <= piece_end
                };
                let limit = next_start.min(start + piece_end);
                let guess = (limit / length * denominator).ceil();
                let end = first_outside(j..interior_end, guess, inside);
                if end == j {
                    if target(j) >= next_start {
                        break;
                    }
                    // Past this piece's lengths: the next piece, as `PlaceTable::place`'s
                    // search would find it.
                    hint.piece += 1;
                    continue;
                }
                // A copy the loop knows is not written through `out`.
                let piece = piece.clone();
                for (k, u) in out.extend(segment, end - j).iter_mut().enumerate() {
                    let s = target(j + k) - start;
                    // As `PlaceTable::place`: u = 1 at or beyond the segment's length (both
                    // computed, one kept: a loop without branches).
                    let placed = piece.at(s);
                    *u = if s >= at_end { 1.0 } else { placed };
                }
                j = end;
            }
        }
    }

    /// Sample `j`'s place, for one of a run of increasing `j`: the searches start at `hint`
    /// (the last sample's segment and its inverse's hint; default for the first), which
    /// changes how long they take, not what they find.
    fn loc_from(&self, j: usize, hint: &mut ArcHint) -> SampleLoc {
        let segments = self.tables.len();
        if j == 0 {
            return SampleLoc {
                segment: 0,
                u: 0.0,
                t: self.knots[0],
            };
        }
        if j + 1 == self.m {
            return SampleLoc {
                segment: segments - 1,
                u: 1.0,
                t: self.knots[segments],
            };
        }
        let length = self.starts[segments];
        let target = length * j as f64 / (self.m - 1) as f64;
        // The last segment that starts at or before the target.
        let segment =
            arc_length::last_before(&self.starts[..segments], hint.segment, |&s| s <= target);
        if segment != hint.segment {
            *hint = ArcHint {
                segment,
                ..ArcHint::default()
            };
        }
        let table = self.tables.get(segment);
        let u = table.place(target - self.starts[segment], &mut hint.piece);
        let t = t_at(&self.knots, segment, u);
        SampleLoc { segment, u, t }
    }
}

/// Where [`ArcSamples::loc_from`]'s searches start: the last sample's segment, and the piece
/// of its explicit inverse there.
#[derive(Clone, Copy, Debug, Default)]
struct ArcHint {
    segment: usize,
    piece: usize,
}

/// A curve's tolerance sampling: each segment's placement (its count and the table its u are
/// computed from on demand).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ToleranceSamples {
    knots: Vec<f64>,
    placements: Vec<Placement>,
    /// The index of each segment's first sample, and, last, of the final point.
    offsets: Vec<usize>,
}

impl ToleranceSamples {
    fn new(table: &SegmentTable, tol: f64) -> Result<Self, InputError> {
        let mut placements = Vec::with_capacity(table.len());
        let mut offsets = vec![0];
        for i in 0..table.len() {
            let placement = tolerance::place(&table.segment(i), tol).map_err(|count| {
                InputError::field(
                    "sampling",
                    format!(
                        "tolerance {} needs {} samples on segment {i}, more than \
                         {MAX_SAMPLES_PER_SEGMENT} (2^20)",
                        Shown(tol),
                        Shown(count)
                    ),
                )
            })?;
            offsets.push(offsets[i] + placement.count as usize);
            placements.push(placement);
        }
        Ok(Self {
            knots: table.knots().to_vec(),
            placements,
            offsets,
        })
    }

    fn len(&self) -> usize {
        self.offsets[self.placements.len()] + 1
    }

    fn t(&self, segment: usize, u: f64) -> f64 {
        t_at(&self.knots, segment, u)
    }

    fn loc(&self, g: usize) -> SampleLoc {
        let segments = self.placements.len();
        if g == self.offsets[segments] {
            return SampleLoc {
                segment: segments - 1,
                u: 1.0,
                t: self.t(segments - 1, 1.0),
            };
        }
        let segment = self.offsets.partition_point(|&o| o <= g) - 1;
        let j = (g - self.offsets[segment]) as u32;
        let u = self.placements[segment].u(j);
        SampleLoc {
            segment,
            u,
            t: self.t(segment, u),
        }
    }

    /// The places of samples `range` (of the whole curve), segment by segment.
    fn runs_into(&self, range: Range<usize>, out: &mut Runs) {
        let segments = self.placements.len();
        let mut us = Vec::new();
        let mut g = range.start;
        while g < range.end {
            if g == self.offsets[segments] {
                out.push(segments - 1, 1.0);
                g += 1;
                continue;
            }
            let segment = self.offsets.partition_point(|&o| o <= g) - 1;
            self.placements[segment].us_into(&mut us);
            let first = g - self.offsets[segment];
            let end = us.len().min(first + range.end - g);
            out.extend(segment, end - first)
                .copy_from_slice(&us[first..end]);
            g += end - first;
        }
    }
}

/// A window of the per-segment sample grid (see [`Plan::Grid`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Grid {
    /// Samples per segment.
    pub k: u32,
    /// The table's knots (segments + 1 values).
    pub knots: Vec<f64>,
    /// The grid index of the plan's first sample.
    pub first: usize,
    /// Number of samples.
    pub len: usize,
}

impl Grid {
    /// Number of segments.
    pub(crate) fn segments(&self) -> usize {
        self.knots.len() - 1
    }

    /// The grid index of the final point: `segments · k`.
    pub(crate) fn closing(&self) -> usize {
        self.segments() * self.k as usize
    }

    /// Grid sample `g`'s segment, local u and t. u = j/k is divided exactly this way by every
    /// evaluator; the final point's t is exactly the last knot.
    pub(crate) fn loc(&self, g: usize) -> SampleLoc {
        let k = self.k as usize;
        let (segment, u) = if g == self.closing() {
            (self.segments() - 1, 1.0)
        } else {
            (g / k, (g % k) as f64 / k as f64)
        };
        let t = t_at(&self.knots, segment, u);
        SampleLoc { segment, u, t }
    }
}

impl Grid {
    /// Appends the t of grid samples `range` to `out`, equal to [`Grid::loc`]'s: segment by
    /// segment, with u = j/k divided once per call for ordinary k rather than once per sample
    /// (with the two integer divisions that find a sample's segment, that was most of the cost).
    fn extend_t(&self, range: Range<usize>, out: &mut impl Extend<f64>) {
        let k = self.k as usize;
        let closing = self.closing();
        let grid_end = range.end.min(closing);
        let us: Vec<f64> = if k <= 1 << 16 {
            (0..k).map(|j| j as f64 / k as f64).collect()
        } else {
            Vec::new()
        };
        let mut g = range.start;
        while g < grid_end {
            let (segment, j) = (g / k, g % k);
            let n = (k - j).min(grid_end - g);
            let (t0, t1) = (self.knots[segment], self.knots[segment + 1]);
            let dt = t1 - t0;
            if us.is_empty() {
                out.extend((j..j + n).map(|j| t0 + (j as f64 / k as f64) * dt));
            } else {
                out.extend(us[j..j + n].iter().map(|&u| t0 + u * dt));
            }
            g += n;
        }
        if range.end > closing {
            out.extend([self.knots[self.segments()]]);
        }
    }

    /// The segment holding grid sample `g` (the final point lies on the last segment).
    fn segment_of(&self, g: usize) -> usize {
        (g / self.k as usize).min(self.segments() - 1)
    }

    /// Samples `range` of this window: the segments they lie on, and the window over just those
    /// segments (for `table.slice(segments)`).
    pub(crate) fn slice(&self, range: std::ops::Range<usize>) -> (std::ops::Range<usize>, Grid) {
        debug_assert!(!range.is_empty() && range.end <= self.len);
        let (g0, g1) = (self.first + range.start, self.first + range.end);
        let (s0, s1) = (self.segment_of(g0), self.segment_of(g1 - 1) + 1);
        let part = Grid {
            k: self.k,
            knots: self.knots[s0..=s1].to_vec(),
            first: g0 - s0 * self.k as usize,
            len: range.len(),
        };
        (s0..s1, part)
    }
}

impl SamplePlan {
    /// Resolves `sampling` against `table`.
    ///
    /// # Errors
    /// k = 0, or more samples than the machine can index (the error names `"per_segment"`); a
    /// t that is not finite or lies outside the curve's range (the error names `"at"`, the
    /// index and the value).
    pub fn new(table: &SegmentTable, sampling: &Sampling) -> Result<Self, InputError> {
        match sampling {
            Sampling::PerSegment(0) => Err(InputError::field("per_segment", "must be >= 1, got 0")),
            &Sampling::PerSegment(k) => {
                let len = table
                    .len()
                    .checked_mul(k as usize)
                    .and_then(|n| n.checked_add(1))
                    .ok_or_else(|| {
                        InputError::field(
                            "per_segment",
                            format!(
                                "asks for {k} samples on each of {} segments: more than this \
                                 machine can index",
                                table.len()
                            ),
                        )
                    })?;
                Ok(SamplePlan(Plan::Grid(Grid {
                    k,
                    knots: table.knots().to_vec(),
                    first: 0,
                    len,
                })))
            }
            Sampling::At(ts) => {
                // 24 bytes a parameter: a large plan's fresh pages are asked for huge.
                let mut locs = Vec::new();
                crate::memory::reserve_on_huge_pages(&mut locs, ts.len());
                // Placed as the one-pass evaluator places them (the same places as `locate`,
                // found faster: sorted t walk, scattered ones use the table's locator).
                let mut placer = place::Placer::new(table, ts);
                for (i, &t) in ts.iter().enumerate() {
                    let (segment, u) = placer.place(t).ok_or_else(|| out_of_range(table, i, t))?;
                    locs.push(SampleLoc { segment, u, t });
                }
                Ok(SamplePlan(Plan::At(locs)))
            }
            &Sampling::ArcLength(m) => {
                if m < 2 {
                    return Err(InputError::field(
                        "arc_length",
                        format!("must be an integer >= 2, got {m}"),
                    ));
                }
                let data = ArcSamples::new(table, m as usize);
                Ok(SamplePlan(Plan::Arc(Window {
                    data: Arc::new(data),
                    first: 0,
                    len: m as usize,
                })))
            }
            &Sampling::Tolerance(tol) => {
                if !(tol.is_finite() && tol > 0.0) {
                    return Err(InputError::field(
                        "tolerance",
                        format!("must be a finite number > 0, got {}", Shown(tol)),
                    ));
                }
                let data = ToleranceSamples::new(table, tol)?;
                let len = data.len();
                Ok(SamplePlan(Plan::Tolerance(Window {
                    data: Arc::new(data),
                    first: 0,
                    len,
                })))
            }
        }
    }

    /// Number of samples.
    #[must_use]
    pub fn len(&self) -> usize {
        match &self.0 {
            Plan::Grid(grid) => grid.len,
            Plan::At(locs) => locs.len(),
            Plan::Arc(w) => w.len,
            Plan::Tolerance(w) => w.len,
        }
    }

    /// True when the plan has no samples (an empty "at" list).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// True for the plans whose places are computed sample by sample (arc length, tolerance),
    /// false for those that read them off (a grid, explicit t).
    #[must_use]
    pub fn is_computed(&self) -> bool {
        matches!(self.0, Plan::Arc(_) | Plan::Tolerance(_))
    }

    /// True for an arc-length plan: the GPU places its samples itself (in f32, within 1e-5 of
    /// the length), so their t differ from the CPU's in the low bits.
    #[must_use]
    pub fn is_arc_length(&self) -> bool {
        matches!(self.0, Plan::Arc(_))
    }

    /// True for the computed plans whose places the host decides for both backends (tolerance:
    /// the GPU packer hands the kernel their places as explicit ones, so that both backends give
    /// the same t); false for the plans the kernel reads off (a grid, explicit t) or computes
    /// itself (arc length). A new sampling whose places the host computes is one of these
    /// wherever it is evaluated.
    pub(crate) fn is_placed_on_host(&self) -> bool {
        self.is_computed() && !self.is_arc_length()
    }

    /// Samples `range` of this plan on `table`, as a table and a plan of their own (a grid's
    /// piece keeps only the segments it lies on); the whole plan is shared as it is.
    pub(crate) fn slice(
        self: &Arc<Self>,
        table: &Arc<SegmentTable>,
        range: Range<usize>,
    ) -> (Arc<SegmentTable>, Arc<SamplePlan>) {
        if range.len() == self.len() {
            return (Arc::clone(table), Arc::clone(self));
        }
        let (table, plan) = match &self.0 {
            Plan::Grid(grid) => {
                let (segments, part) = grid.slice(range);
                (Arc::new(table.slice(segments)), Plan::Grid(part))
            }
            Plan::At(locs) => (Arc::clone(table), Plan::At(locs[range].to_vec())),
            Plan::Arc(w) => (Arc::clone(table), Plan::Arc(w.slice(range))),
            Plan::Tolerance(w) => (Arc::clone(table), Plan::Tolerance(w.slice(range))),
        };
        (table, Arc::new(SamplePlan(plan)))
    }

    /// Appends the t of samples `range` to `out` (a `Vec<f64>`, say), as [`SamplePlan::loc`]
    /// gives them.
    ///
    /// # Panics
    /// If the range reaches past the plan's end.
    pub fn extend_t(&self, range: std::ops::Range<usize>, out: &mut impl Extend<f64>) {
        assert!(
            range.end <= self.len(),
            "samples {range:?} past the plan's end"
        );
        match &self.0 {
            Plan::Grid(grid) => {
                grid.extend_t(grid.first + range.start..grid.first + range.end, out)
            }
            Plan::At(locs) => out.extend(locs[range].iter().map(|l| l.t)),
            _ => {
                let mut locs = Vec::new();
                for start in (range.start..range.end).step_by(LOC_BLOCK) {
                    locs.clear();
                    self.locs_into(start..(start + LOC_BLOCK).min(range.end), &mut locs);
                    out.extend(locs.iter().map(|l| l.t));
                }
            }
        }
    }

    /// Appends the places of samples `range` to `out` (any plan; per-segment plans too).
    ///
    /// # Panics
    /// If the range reaches past the plan's end.
    pub(crate) fn locs_into(&self, range: Range<usize>, out: &mut Vec<SampleLoc>) {
        assert!(
            range.end <= self.len(),
            "samples {range:?} past the plan's end"
        );
        match &self.0 {
            Plan::Grid(grid) => out.extend(range.map(|i| grid.loc(grid.first + i))),
            Plan::At(locs) => out.extend_from_slice(&locs[range]),
            Plan::Arc(_) | Plan::Tolerance(_) => {
                let mut runs = Runs::default();
                let knots = self.runs_into(range, &mut runs);
                out.extend(runs.iter().flat_map(|(segment, us)| {
                    us.iter().map(move |&u| SampleLoc {
                        segment,
                        u,
                        t: t_at(knots, segment, u),
                    })
                }));
            }
        }
    }

    /// Appends the places of samples `range` of a computed plan (arc length, tolerance) to
    /// `out` as runs on one segment each, the same places [`SamplePlan::loc`] gives, and
    /// returns the knots their t are formed from ([`t_at`]).
    ///
    /// # Panics
    /// If the plan is not computed ([`SamplePlan::is_computed`]).
    #[inline(always)]
    pub(crate) fn runs_into(&self, range: Range<usize>, out: &mut Runs) -> &[f64] {
        match &self.0 {
            Plan::Arc(w) => {
                w.data
                    .runs_into(w.first + range.start..w.first + range.end, out);
                &w.data.knots
            }
            Plan::Tolerance(w) => {
                w.data
                    .runs_into(w.first + range.start..w.first + range.end, out);
                &w.data.knots
            }
            Plan::Grid(_) | Plan::At(_) => unreachable!("runs are made of computed plans"),
        }
    }

    /// Sample `i`'s segment, local u and t.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    #[must_use]
    pub fn loc(&self, i: usize) -> SampleLoc {
        assert!(i < self.len(), "sample {i} past the plan's end");
        match &self.0 {
            Plan::Grid(grid) => grid.loc(grid.first + i),
            Plan::At(locs) => locs[i],
            Plan::Arc(w) => w.data.loc(w.first + i),
            Plan::Tolerance(w) => w.data.loc(w.first + i),
        }
    }
}

/// Sample places computed at once by the writers and evaluators of computed plans (arc length,
/// tolerance), so that their memory stays bounded.
pub(crate) const LOC_BLOCK: usize = 8192;

impl<T> Window<T> {
    /// Samples `range` of this window, as a window of its own.
    pub(crate) fn slice(&self, range: Range<usize>) -> Self {
        Self {
            data: Arc::clone(&self.data),
            first: self.first + range.start,
            len: range.len(),
        }
    }
}

/// The t of local `u` on `segment`: t_i + u·(t_{i+1} − t_i), and t_{i+1} itself at u = 1 (the
/// sum may round off it).
#[inline]
pub(crate) fn t_at(knots: &[f64], segment: usize, u: f64) -> f64 {
    let (t0, t1) = (knots[segment], knots[segment + 1]);
    if u == 1.0 { t1 } else { t0 + u * (t1 - t0) }
}

/// The segment and local u of parameter `t`: the last segment whose start is <= t, so an
/// interior knot belongs to the segment that starts there and the range's end to the last
/// segment at u = 1. `None` outside [t_0, t_n] or for a non-finite t.
pub(crate) fn locate(knots: &[f64], t: f64) -> Option<SampleLoc> {
    let segments = knots.len() - 1;
    if !(t >= knots[0] && t <= knots[segments]) {
        return None;
    }
    // Number of knots <= t, minus one, capped to the last segment.
    let segment = (knots.partition_point(|&k| k <= t) - 1).min(segments - 1);
    let (t0, t1) = (knots[segment], knots[segment + 1]);
    let u = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    Some(SampleLoc { segment, u, t })
}

/// The error of parameter `at[i] = t` outside `table`'s range (or not finite).
pub(crate) fn out_of_range(table: &SegmentTable, i: usize, t: f64) -> InputError {
    let (lo, hi) = table.t_range();
    InputError::field(
        "at",
        format!(
            "values must lie in the curve's range [{}, {}]: at[{i}] = {}",
            Shown(lo),
            Shown(hi),
            Shown(t)
        ),
    )
}

/// A slice filled front to back through [`Extend`], so that [`SamplePlan::extend_t`] writes
/// straight into a caller's memory.
pub(crate) struct Filling<'a> {
    out: &'a mut [f64],
    filled: usize,
}

impl<'a> Filling<'a> {
    /// An empty start on `out`.
    pub(crate) fn new(out: &'a mut [f64]) -> Self {
        Self { out, filled: 0 }
    }

    /// How many values have been written.
    pub(crate) fn filled(&self) -> usize {
        self.filled
    }
}

impl Extend<f64> for Filling<'_> {
    /// Writes the values after those already written.
    ///
    /// # Panics
    /// If they would run past the slice's end.
    fn extend<I: IntoIterator<Item = f64>>(&mut self, values: I) {
        let mut values = values.into_iter();
        let mut written = 0;
        for (slot, v) in self.out[self.filled..].iter_mut().zip(&mut values) {
            *slot = v;
            written += 1;
        }
        self.filled += written;
        assert!(values.next().is_none(), "more t than samples");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_length_places_found_from_the_last_ones_equal_those_found_afresh() {
        use crate::{Basis, Curve, CurveKind, Ends, Points};
        // 40 segments, with a cusp (a doubled point) and a standstill (four equal points).
        let mut coords: Vec<f64> = (0..40)
            .flat_map(|i| [f64::from(i).sin() * 3.0, f64::from(i % 7)])
            .collect();
        coords.splice(20..20, [5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 5.0]);
        coords.splice(50..50, [coords[48], coords[49]]);
        let kind = CurveKind::Uniform {
            basis: Basis::BSpline,
            ends: Ends::Repeat,
        };
        let table = Curve::new(kind, Points::new(2, coords).unwrap())
            .unwrap()
            .fit();
        let arc = ArcSamples::new(&table, 997);
        let fresh: Vec<SampleLoc> = (0..997).map(|j| arc.loc(j)).collect();
        let plan = SamplePlan(Plan::Arc(Window {
            data: Arc::new(arc),
            first: 0,
            len: 997,
        }));
        for start in [0, 1, 13, 500, 996] {
            for end in [start + 1, start + 2, start + 40, 997].map(|end| end.min(997)) {
                let mut run = Vec::new();
                plan.locs_into(start..end, &mut run);
                assert_eq!(run, fresh[start..end], "samples {start}..{end}");
            }
        }
    }

    fn grid(segments: usize, k: u32) -> Grid {
        Grid {
            k,
            knots: (0..=segments).map(|i| i as f64 * 0.5).collect(),
            first: 0,
            len: segments * k as usize + 1,
        }
    }

    #[test]
    fn grid_slices_name_the_segments_they_lie_on() {
        let g = grid(4, 3); // 13 samples, the last the final point
        let whole: Vec<SampleLoc> = (0..13).map(|i| g.loc(i)).collect();
        for start in 0..13 {
            for end in start + 1..=13 {
                let (segments, part) = g.slice(start..end);
                for i in 0..end - start {
                    let got = part.loc(part.first + i);
                    let want = whole[start + i];
                    assert_eq!(got.segment + segments.start, want.segment, "{start}..{end}");
                    assert_eq!((got.u, got.t), (want.u, want.t), "{start}..{end}");
                }
                assert!(segments.end <= 4 && part.knots.len() == segments.len() + 1);
            }
        }
    }
}
