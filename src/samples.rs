//! `Samples`: the evaluated points (and derivatives) of every curve of a job, laid out flat.

use crate::job::{Derivatives, EvalJob};

/// The samples of a job: for curve c, samples `sample_offsets[c]..sample_offsets[c+1]`, each
/// `dim(c)` values in `points` (and in `d1`, `d2` when computed) starting at
/// `value_offsets[c]`. `F` is f64 from the CPU reference and f32 from the GPU; `t` is always
/// f64.
#[derive(Clone, Debug, PartialEq)]
pub struct Samples<F> {
    dims: Vec<usize>,
    sample_offsets: Vec<usize>,
    value_offsets: Vec<usize>,
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
            dims: Vec::new(),
            sample_offsets: Vec::new(),
            value_offsets: Vec::new(),
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
        self.dims.clear();
        self.sample_offsets.clear();
        self.value_offsets.clear();
        self.t.clear();
        self.t.reserve(job.sample_count());
        self.sample_offsets.push(0);
        self.value_offsets.push(0);
        for c in 0..job.len() {
            let (dim, plan) = (job.table(c).dim(), job.plan(c));
            self.dims.push(dim);
            plan.extend_t(&mut self.t);
            self.sample_offsets.push(self.t.len());
            self.value_offsets
                .push(self.value_offsets[c] + plan.len() * dim);
        }
        self.derivatives = job.derivatives();
        let values = self.value_offsets[job.len()];
        let order = self.derivatives.order();
        for (o, plane) in [&mut self.points, &mut self.d1, &mut self.d2]
            .into_iter()
            .enumerate()
        {
            plane.resize(if order >= o { values } else { 0 }, F::default());
        }
    }
}

impl<F> Samples<F> {
    /// Number of curves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.dims.len()
    }

    /// True when there are no curves.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.dims.is_empty()
    }

    /// The derivatives held.
    #[must_use]
    pub fn derivatives(&self) -> Derivatives {
        self.derivatives
    }

    /// Curve `c`'s samples.
    #[must_use]
    pub fn curve(&self, c: usize) -> CurveSamples<'_, F> {
        let values = self.value_offsets[c]..self.value_offsets[c + 1];
        let order = self.derivatives.order();
        CurveSamples {
            dim: self.dims[c],
            t: &self.t[self.sample_offsets[c]..self.sample_offsets[c + 1]],
            points: &self.points[values.clone()],
            d1: (order >= 1).then(|| &self.d1[values.clone()]),
            d2: (order >= 2).then(|| &self.d2[values]),
        }
    }

    /// The value offset (into each plane) where curve `c` starts; `c = len()` gives the total.
    #[must_use]
    pub fn value_offset(&self, c: usize) -> usize {
        self.value_offsets[c]
    }

    /// Mutable planes: positions, then d1 and d2 (empty when not computed).
    pub fn planes_mut(&mut self) -> [&mut [F]; 3] {
        [&mut self.points, &mut self.d1, &mut self.d2]
    }
}
