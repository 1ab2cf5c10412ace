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
        let mut dims = Vec::with_capacity(job.len());
        let mut sample_offsets = vec![0];
        let mut value_offsets = vec![0];
        let mut t = Vec::with_capacity(job.sample_count());
        for c in 0..job.len() {
            let (dim, plan) = (job.table(c).dim(), job.plan(c));
            dims.push(dim);
            t.extend((0..plan.len()).map(|i| plan.loc(i).t));
            sample_offsets.push(t.len());
            value_offsets.push(value_offsets[c] + plan.len() * dim);
        }
        let values = value_offsets[job.len()];
        let plane = |order| {
            if job.derivatives().order() >= order {
                vec![F::default(); values]
            } else {
                Vec::new()
            }
        };
        Self {
            dims,
            sample_offsets,
            value_offsets,
            derivatives: job.derivatives(),
            t,
            points: plane(0),
            d1: plane(1),
            d2: plane(2),
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
