//! `EvalJob`: many fitted curves with their sample plans, evaluated together in one call.

use std::sync::Arc;

use rayon::prelude::*;

use crate::curve::Curve;
use crate::error::InputError;
pub(crate) mod layout;
pub(crate) mod planes;
pub(crate) mod samples;

use crate::sampling::{SamplePlan, Sampling};
use crate::segment::SegmentTable;
use layout::JobLayout;

/// `curve` fitted, its values checked against overflow for `derivatives`, and planned.
fn fitted_and_planned(
    curve: &Curve,
    sampling: &Sampling,
    derivatives: Derivatives,
) -> Result<(SegmentTable, SamplePlan), InputError> {
    let table = curve.fit();
    table.check_range(derivatives)?;
    let plan = SamplePlan::new(&table, sampling)?;
    Ok((table, plan))
}

/// A plan of `samples` samples does not fit in a job that already indexes `before`.
fn too_many_samples(samples: usize, before: usize) -> InputError {
    InputError::field(
        "sampling",
        format!(
            "asks for {samples} samples, more than one job can index after the {before} already in it"
        ),
    )
}

/// Which derivatives (with respect to t) to compute besides positions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub enum Derivatives {
    /// Positions only (the default).
    #[default]
    None,
    /// Positions and dP/dt.
    First,
    /// Positions, dP/dt and d2P/dt2.
    Second,
}

impl Derivatives {
    /// From the contract's number 0, 1 or 2.
    #[must_use]
    pub fn from_order(order: u64) -> Option<Self> {
        match order {
            0 => Some(Derivatives::None),
            1 => Some(Derivatives::First),
            2 => Some(Derivatives::Second),
            _ => None,
        }
    }

    /// The highest derivative order computed: 0, 1 or 2.
    #[must_use]
    pub fn order(self) -> usize {
        self as usize
    }
}

/// Curves to evaluate in one call: each a [`SegmentTable`] and a [`SamplePlan`], and the
/// [`JobLayout`] that says where their samples go.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EvalJob {
    // Shared, so that a chunk of the job ([`EvalJob::chunks`]) holds its whole curves without
    // copying them (w1's tables are 35 MB, an explicit-t job's plans several times that).
    tables: Vec<Arc<SegmentTable>>,
    plans: Vec<Arc<SamplePlan>>,
    derivatives: Derivatives,
    layout: JobLayout,
}

impl EvalJob {
    /// An empty job computing `derivatives`.
    #[must_use]
    pub fn new(derivatives: Derivatives) -> Self {
        Self {
            derivatives,
            ..Self::default()
        }
    }

    /// Fits `curve` and adds it, sampled as `sampling` says.
    ///
    /// # Errors
    /// A sampling that does not fit the curve (see [`SamplePlan::new`]), values whose samples
    /// overflow f64 ([`SegmentTable::check_range`]), or a job whose sample offsets would
    /// overflow; the caller places the error in its curve with
    /// [`InputError::in_curve`].
    pub fn push(&mut self, curve: &Curve, sampling: &Sampling) -> Result<(), InputError> {
        let (table, plan) = fitted_and_planned(curve, sampling, self.derivatives)?;
        self.push_table(table, plan)
    }

    /// Fits and plans many curves on every thread, then adds them in order: what
    /// [`EvalJob::push`] does for each, as a caller with thousands of curves wants it done.
    ///
    /// # Errors
    /// The first failing curve's error (as [`EvalJob::push`]'s), placed at its index in the job
    /// ([`InputError::in_curve`]); the job is then unchanged.
    pub fn push_many(&mut self, curves: &[(Curve, Sampling)]) -> Result<(), InputError> {
        let first = self.len();
        let derivatives = self.derivatives;
        let made: Vec<Result<(SegmentTable, SamplePlan), InputError>> = curves
            .par_iter()
            .map(|(curve, sampling)| fitted_and_planned(curve, sampling, derivatives))
            .collect();
        let mut parts = Vec::with_capacity(made.len());
        for (i, part) in made.into_iter().enumerate() {
            parts.push(part.map_err(|e| e.in_curve(first + i))?);
        }
        let mut layout = self.layout.clone();
        for (i, (table, plan)) in parts.iter().enumerate() {
            let before = layout.samples();
            layout
                .push(table.dim(), plan.len())
                .ok_or_else(|| too_many_samples(plan.len(), before).in_curve(first + i))?;
        }
        self.layout = layout;
        for (table, plan) in parts {
            self.tables.push(Arc::new(table));
            self.plans.push(Arc::new(plan));
        }
        Ok(())
    }

    /// Adds an already fitted curve and its plan. The plan must have been made for this table.
    ///
    /// # Errors
    /// The job's sample or value offsets would overflow (the error names `"sampling"`).
    pub fn push_table(&mut self, table: SegmentTable, plan: SamplePlan) -> Result<(), InputError> {
        self.push_shared(Arc::new(table), Arc::new(plan))
    }

    /// Adds curve `c` of `job`, sharing its table and plan rather than copying them.
    ///
    /// # Errors
    /// As [`EvalJob::push_table`].
    pub fn push_curve_of(&mut self, job: &EvalJob, c: usize) -> Result<(), InputError> {
        self.push_shared(Arc::clone(&job.tables[c]), Arc::clone(&job.plans[c]))
    }

    /// [`EvalJob::push_table`] for a table and plan that other jobs may hold too: a fitted
    /// spline evaluated again and again shares its table with each job instead of copying it
    /// (a copy costs as much as the knots, whatever the number of samples).
    ///
    /// # Errors
    /// As [`EvalJob::push_table`].
    pub fn push_shared(
        &mut self,
        table: Arc<SegmentTable>,
        plan: Arc<SamplePlan>,
    ) -> Result<(), InputError> {
        let before = self.layout.samples();
        (self.layout)
            .push(table.dim(), plan.len())
            .ok_or_else(|| too_many_samples(plan.len(), before))?;
        self.tables.push(table);
        self.plans.push(plan);
        Ok(())
    }

    /// Refits curve `c` from `curve`, keeping its plan and its place in the layout: for curves
    /// whose points move every frame (a renderer's), so that nothing else is recomputed. The
    /// new table replaces the old one as a fresh pair of small buffers (allocated and freed
    /// one curve at a time, which the allocator recycles; making a whole new job freed and
    /// re-faulted the job's pages every frame).
    ///
    /// # Errors
    /// `curve`'s dimension or knots differ from curve c's (its plan was made for them: the
    /// error names `"points"`; a uniform family keeps its knots as long as its point count),
    /// or its values' samples would overflow f64 ([`SegmentTable::check_range`]); curve c is
    /// then left as it was.
    ///
    /// # Panics
    /// If `c` is not a curve of the job.
    pub fn refit(&mut self, c: usize, curve: &Curve) -> Result<(), InputError> {
        let mut table = SegmentTable::default();
        curve.fit_into(&mut table);
        let old = &self.tables[c];
        if table.dim() != old.dim() || table.knots() != old.knots() {
            return Err(InputError::field(
                "points",
                format!(
                    "a refit must keep the curve's knots and dimension ({} segments of {} \
                     coordinates), got {} segments of {}",
                    old.len(),
                    old.dim(),
                    table.len(),
                    table.dim()
                ),
            ));
        }
        table.check_range(self.derivatives)?;
        self.tables[c] = Arc::new(table);
        Ok(())
    }

    /// Where every curve's samples go.
    #[must_use]
    pub fn layout(&self) -> &JobLayout {
        &self.layout
    }

    /// The derivatives computed.
    #[must_use]
    pub fn derivatives(&self) -> Derivatives {
        self.derivatives
    }

    /// Number of curves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.tables.len()
    }

    /// True when the job has no curves.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tables.is_empty()
    }

    /// Curve `i`'s segments.
    #[must_use]
    pub fn table(&self, i: usize) -> &SegmentTable {
        &self.tables[i]
    }

    /// Curve `i`'s samples.
    #[must_use]
    pub fn plan(&self, i: usize) -> &SamplePlan {
        &self.plans[i]
    }

    /// Total number of samples over all curves.
    #[must_use]
    pub fn sample_count(&self) -> usize {
        self.layout.samples()
    }

    /// The job as a sequence of smaller jobs of at most `max_samples` samples each, made one at
    /// a time, for output that streams with bounded memory. Whole curves go together while they
    /// fit; a longer curve is cut into pieces of `max_samples` samples, anywhere (inside a
    /// segment too), so no chunk holds more than `max_samples` samples however large one
    /// segment's sampling is. Evaluating the chunks in order gives every curve's samples in
    /// order, each once.
    pub fn chunks(&self, max_samples: usize) -> impl Iterator<Item = Chunk> + '_ {
        let max_samples = max_samples.max(1);
        let mut pieces = (0..self.len())
            .flat_map(move |c| {
                let n = self.plans[c].len();
                (0..n.div_ceil(max_samples).max(1)).map(move |p| {
                    let start = p * max_samples;
                    (c, start..(start + max_samples).min(n))
                })
            })
            .peekable();
        std::iter::from_fn(move || {
            let mut chunk = Chunk {
                job: EvalJob::new(self.derivatives),
                pieces: Vec::new(),
            };
            while let Some((c, range)) = pieces.next_if(|(_, r)| {
                chunk.job.sample_count() == 0 || chunk.job.sample_count() + r.len() <= max_samples
            }) {
                let (table, plan) = self.piece(c, range.clone());
                // A piece of a job that fits its layout fits the chunk's.
                chunk
                    .job
                    .push_shared(table, plan)
                    .expect("a chunk indexes fewer samples than its job");
                chunk.pieces.push(Piece {
                    curve: c,
                    first_sample: range.start,
                });
            }
            (!chunk.pieces.is_empty()).then_some(chunk)
        })
    }

    /// Samples `range` of curve `c`, with the segments they lie on: the curve's own table and
    /// plan when the range is all of it.
    fn piece(
        &self,
        c: usize,
        range: std::ops::Range<usize>,
    ) -> (Arc<SegmentTable>, Arc<SamplePlan>) {
        self.plans[c].slice(&self.tables[c], range)
    }
}

/// Where a curve of a [`Chunk`] comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Piece {
    /// The curve's index in the whole job.
    pub curve: usize,
    /// The index, in that curve, of the piece's first sample.
    pub first_sample: usize,
}

/// A part of a job ([`EvalJob::chunks`]): a job of its own, and where each of its curves
/// comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct Chunk {
    /// The part to evaluate.
    pub job: EvalJob,
    /// For each of its curves, the original curve and first sample.
    pub pieces: Vec<Piece>,
}
