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
}
