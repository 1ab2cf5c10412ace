//! `EvalJob`: many fitted curves with their sample plans, evaluated together in one call.

use crate::curve::Curve;
use crate::error::InputError;
use crate::sampling::{SamplePlan, Sampling};
use crate::segment::SegmentTable;

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

/// Curves to evaluate in one call: each a [`SegmentTable`] and a [`SamplePlan`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EvalJob {
    tables: Vec<SegmentTable>,
    plans: Vec<SamplePlan>,
    derivatives: Derivatives,
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
    /// A sampling that does not fit the curve (see [`SamplePlan::new`]); the caller places the
    /// error in its curve with [`InputError::in_curve`].
    pub fn push(&mut self, curve: &Curve, sampling: &Sampling) -> Result<(), InputError> {
        let table = curve.fit();
        let plan = SamplePlan::new(&table, sampling)?;
        self.push_table(table, plan);
        Ok(())
    }

    /// Adds an already fitted curve and its plan. The plan must have been made for this table.
    pub fn push_table(&mut self, table: SegmentTable, plan: SamplePlan) {
        self.tables.push(table);
        self.plans.push(plan);
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
        self.plans.iter().map(SamplePlan::len).sum()
    }

    /// The job as a sequence of smaller jobs of about `max_samples` samples each, made one at a
    /// time, for output that streams with bounded memory. Whole curves go together while they
    /// fit; a longer curve is cut at segment boundaries (per-segment sampling: at least one
    /// segment per piece, so a piece can hold more than `max_samples` when one segment does)
    /// or between samples (explicit t). Evaluating the chunks in order gives every curve's
    /// samples in order, each once.
    pub fn chunks(&self, max_samples: usize) -> impl Iterator<Item = Chunk> + '_ {
        let max_samples = max_samples.max(1);
        let mut pieces = (0..self.len())
            .flat_map(move |c| self.pieces(c, max_samples))
            .peekable();
        std::iter::from_fn(move || {
            let mut chunk = Chunk {
                job: EvalJob::new(self.derivatives),
                pieces: Vec::new(),
            };
            let mut samples = 0;
            while let Some(piece) =
                pieces.next_if(|p| samples == 0 || samples + p.2.len() <= max_samples)
            {
                let (place, table, plan) = piece;
                samples += plan.len();
                chunk.job.push_table(table, plan);
                chunk.pieces.push(place);
            }
            (!chunk.pieces.is_empty()).then_some(chunk)
        })
    }

    /// Curve `c` cut into pieces of about `max_samples` samples.
    fn pieces(&self, c: usize, max_samples: usize) -> Vec<(Piece, SegmentTable, SamplePlan)> {
        let (table, plan) = (&self.tables[c], &self.plans[c]);
        if plan.len() <= max_samples {
            return vec![(
                Piece {
                    curve: c,
                    first_sample: 0,
                },
                table.clone(),
                plan.clone(),
            )];
        }
        match plan {
            SamplePlan::PerSegment { k, closing, .. } => {
                let per_piece = (max_samples / *k as usize).max(1);
                (0..table.len())
                    .step_by(per_piece)
                    .map(|s0| {
                        let s1 = (s0 + per_piece).min(table.len());
                        let part = table.slice(s0..s1);
                        let plan = SamplePlan::PerSegment {
                            k: *k,
                            knots: part.knots().to_vec(),
                            closing: *closing && s1 == table.len(),
                        };
                        let place = Piece {
                            curve: c,
                            first_sample: s0 * *k as usize,
                        };
                        (place, part, plan)
                    })
                    .collect()
            }
            SamplePlan::At(locs) => locs
                .chunks(max_samples)
                .enumerate()
                .map(|(i, part)| {
                    let place = Piece {
                        curve: c,
                        first_sample: i * max_samples,
                    };
                    (place, table.clone(), SamplePlan::At(part.to_vec()))
                })
                .collect(),
        }
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
