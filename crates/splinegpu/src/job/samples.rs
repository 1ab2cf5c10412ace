//! `Samples`: the evaluated points (and derivatives) of every curve of a job, laid out flat.

use std::fmt::Debug;

use crate::job::layout::JobLayout;
use crate::job::planes::Planes;
use crate::job::{Derivatives, EvalJob};
use crate::sampling::Filling;

pub(crate) mod sealed {
    use crate::job::EvalJob;

    /// The evaluator of each number type, compiled once in this crate (the impls are the CPU
    /// evaluator's, in `cpu/`): non-generic, so that a caller's build settings (a crate of 16
    /// codegen units, which inlines across units only what is marked) cannot undo the hot
    /// loop's inlining (docs/benchmarks.md has the figures).
    pub trait Sealed: Sized {
        /// Samples `range` of `job` into `t` (unless empty) and the planes.
        fn evaluate_range(
            job: &EvalJob,
            range: std::ops::Range<usize>,
            t: &mut [f64],
            out: [&mut [Self]; 3],
        );
    }
}

/// The number type of evaluated values: f32 (the GPU's, and the fast CPU evaluator's on
/// request) or f64 (the CPU's). Sealed: these two are the only ones.
pub trait SampleFloat:
    sealed::Sealed + Copy + Default + Debug + PartialEq + Send + Sync + bytemuck::Pod + 'static
{
    /// "f32" or "f64", as the bench's JSON lines and the NPZ headers name it.
    const NAME: &'static str;

    /// `v` rounded to this type (to nearest).
    fn from_f64(v: f64) -> Self;

    /// True unless NaN or infinite.
    fn finite(self) -> bool;
}

impl SampleFloat for f32 {
    const NAME: &'static str = "f32";

    #[inline(always)]
    fn from_f64(v: f64) -> Self {
        v as f32
    }

    fn finite(self) -> bool {
        self.is_finite()
    }
}

impl SampleFloat for f64 {
    const NAME: &'static str = "f64";

    #[inline(always)]
    fn from_f64(v: f64) -> Self {
        v
    }

    fn finite(self) -> bool {
        self.is_finite()
    }
}

/// The samples of a job: for curve c, the samples and values its [`JobLayout`] names, `dim(c)`
/// values per sample in `points` (and in `d1`, `d2` when computed). `F` is f64 from the CPU
/// evaluators and f32 from the GPU; `t` is always f64.
#[derive(Clone, Debug, PartialEq)]
pub struct Samples<F> {
    layout: JobLayout,
    derivatives: Derivatives,
    t: Vec<f64>,
    points: Vec<F>,
    d1: Vec<F>,
    d2: Vec<F>,
}

/// One curve's samples, borrowed from [`Samples`].
#[derive(Clone, Copy, Debug)]
pub struct CurveSamples<'a, F> {
    /// Coordinates per point.
    pub dim: usize,
    /// The curve parameter of each sample.
    pub t: &'a [f64],
    /// Positions, `dim` values per sample.
    pub points: &'a [F],
    /// dP/dt, when computed.
    pub d1: Option<&'a [F]>,
    /// d2P/dt2, when computed.
    pub d2: Option<&'a [F]>,
}

impl<F: Copy + Default> Samples<F> {
    /// The layout for `job`, with `t` filled in from the plans and every value zero.
    #[must_use]
    pub fn for_job(job: &EvalJob) -> Self {
        let mut samples = Self {
            layout: JobLayout::default(),
            derivatives: job.derivatives(),
            t: Vec::new(),
            points: Vec::new(),
            d1: Vec::new(),
            d2: Vec::new(),
        };
        samples.prepare(job);
        samples
    }

    /// Lays `self` out for `job` in place, keeping its allocations: `t` is filled in from the
    /// plans, and the value planes are resized (new values are zero, the others keep whatever
    /// they held until they are overwritten).
    pub fn prepare(&mut self, job: &EvalJob) {
        self.prepare_planes(job);
        self.fill_t(job);
    }

    /// Fills in `t` from `job`'s plans (`self` laid out for it already).
    pub(crate) fn fill_t(&mut self, job: &EvalJob) {
        fill_t(job, &[], &[], &mut self.t);
    }

    /// Lays `self` out for `job` (keeping its allocations, as [`Samples::prepare`] does, but
    /// leaving t for the evaluator to write) and views it as the [`Planes`] the evaluators'
    /// `*_into` calls write: t, the positions and the derivatives the job asks for.
    pub fn planes_for(&mut self, job: &EvalJob) -> Planes<'_, F> {
        self.prepare_planes(job);
        let order = self.derivatives.order();
        Planes {
            t: Some(&mut self.t),
            points: &mut self.points,
            d1: (order >= 1).then_some(&mut self.d1[..]),
            d2: (order >= 2).then_some(&mut self.d2[..]),
        }
    }

    /// [`Samples::prepare`] for a writer that fills in `t` itself: `t` is resized to the job's
    /// samples, not computed (computing the places of arc-length and tolerance samples is most
    /// of their work: an evaluator that computes them anyway writes their t as it goes).
    pub(crate) fn prepare_planes(&mut self, job: &EvalJob) {
        self.layout.clone_from(job.layout());
        self.derivatives = job.derivatives();
        crate::memory::reserve_on_huge_pages(&mut self.t, self.layout.samples());
        self.t.resize(self.layout.samples(), 0.0);
        let values = self.layout.values();
        let order = self.derivatives.order();
        for (o, plane) in [&mut self.points, &mut self.d1, &mut self.d2]
            .into_iter()
            .enumerate()
        {
            let len = if order >= o { values } else { 0 };
            crate::memory::reserve_on_huge_pages(plane, len);
            plane.resize(len, F::default());
        }
    }
}

impl<F> Samples<F> {
    /// Number of curves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.layout.len()
    }

    /// True when there are no curves.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.layout.is_empty()
    }

    /// The derivatives held.
    #[must_use]
    pub fn derivatives(&self) -> Derivatives {
        self.derivatives
    }

    /// Where each curve's samples and values lie (the job's layout).
    #[must_use]
    pub fn layout(&self) -> &JobLayout {
        &self.layout
    }

    /// Curve `c`'s samples.
    #[must_use]
    pub fn curve(&self, c: usize) -> CurveSamples<'_, F> {
        let values = self.layout.values_of(c);
        let order = self.derivatives.order();
        CurveSamples {
            dim: self.layout.dim(c),
            t: &self.t[self.layout.samples_of(c)],
            points: &self.points[values.clone()],
            d1: (order >= 1).then(|| &self.d1[values.clone()]),
            d2: (order >= 2).then(|| &self.d2[values]),
        }
    }

    /// The memory itself: every sample's t, then the planes (positions, d1, d2; empty when not
    /// computed), laid out as [`Samples::layout`] says; for handing the values on without a copy.
    #[must_use]
    pub fn into_parts(self) -> (JobLayout, Vec<f64>, [Vec<F>; 3]) {
        (self.layout, self.t, [self.points, self.d1, self.d2])
    }

    /// The planes: positions, then d1 and d2 (empty when not computed).
    #[must_use]
    pub fn planes(&self) -> [&[F]; 3] {
        [&self.points, &self.d1, &self.d2]
    }

    /// Every sample's t, curve after curve.
    #[must_use]
    pub fn t(&self) -> &[f64] {
        &self.t
    }

    /// Mutable planes: positions, then d1 and d2 (empty when not computed).
    pub(crate) fn planes_mut(&mut self) -> [&mut [F]; 3] {
        [&mut self.points, &mut self.d1, &mut self.d2]
    }
}

/// Writes the t of `job`'s samples into `t` (the job's samples long), taking those of the
/// curves placed on the host (tolerance) from `host_placed` (theirs, curve after curve) and those of the
/// curves sampled by arc length from the places the GPU found, `arc_places` (curve after
/// curve), where they hold them, rather than computing the places again. A place's segment
/// counts from the job's first segment; t = t_i + u·Δ_i is formed in f64, t_{i+1} at u = 1.
/// An empty `t` (a caller who wants none) is left alone.
pub(crate) fn fill_t(
    job: &EvalJob,
    host_placed: &[f64],
    arc_places: &[crate::gpu::curves::abi::GpuLoc],
    t: &mut [f64],
) {
    if t.is_empty() {
        return;
    }
    let (mut host_placed, mut arc_places) = (host_placed, arc_places);
    let mut out = Filling::new(t);
    let mut first_segment = 0;
    for c in 0..job.len() {
        let (table, plan) = (job.table(c), job.plan(c));
        let n = plan.len();
        if plan.is_arc_length() && arc_places.len() >= n {
            let (own, after) = arc_places.split_at(n);
            let knots = table.knots();
            out.extend(own.iter().map(|place| {
                let segment = place.segment as usize - first_segment;
                crate::sampling::t_at(knots, segment, f64::from(place.u))
            }));
            arc_places = after;
        } else if plan.is_placed_on_host() && host_placed.len() >= n {
            let (own, after) = host_placed.split_at(n);
            out.extend(own.iter().copied());
            host_placed = after;
        } else {
            plan.extend_t(0..n, &mut out);
        }
        first_segment += table.len();
    }
    debug_assert_eq!(out.filled(), job.layout().samples());
}
