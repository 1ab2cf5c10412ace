//! Where a curve is sampled: the contract's sampling rules turned into a `SamplePlan` of
//! (segment, local u, t) triples, all resolved in f64 on the host.

use crate::error::InputError;
use crate::segment::SegmentTable;

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

/// The samples of one curve, resolved against its segment table.
#[derive(Clone, Debug, PartialEq)]
pub enum SamplePlan {
    /// `segments * k` samples, then the final point when `closing`, generated on demand
    /// (nothing per sample is stored).
    PerSegment {
        /// Samples per segment.
        k: u32,
        /// The curve's knots (segments + 1 values).
        knots: Vec<f64>,
        /// Whether the final point (the last segment at u = 1) is a sample: always for a whole
        /// curve, only for the last piece of a curve cut into pieces (see
        /// [`EvalJob::chunks`](crate::EvalJob::chunks)).
        closing: bool,
    },
    /// Explicit samples.
    At(Vec<SampleLoc>),
}

impl SamplePlan {
    /// Resolves `sampling` against `table`.
    ///
    /// # Errors
    /// k = 0; a t that is not finite or lies outside the curve's range (the error names `"at"`,
    /// the index and the value).
    pub fn new(table: &SegmentTable, sampling: &Sampling) -> Result<Self, InputError> {
        match sampling {
            Sampling::PerSegment(0) => Err(InputError::field("per_segment", "must be >= 1, got 0")),
            &Sampling::PerSegment(k) => Ok(SamplePlan::PerSegment {
                k,
                knots: table.knots().to_vec(),
                closing: true,
            }),
            Sampling::At(ts) => {
                let locs = ts
                    .iter()
                    .enumerate()
                    .map(|(i, &t)| {
                        locate(table.knots(), t).ok_or_else(|| out_of_range(table, i, t))
                    })
                    .collect::<Result<_, _>>()?;
                Ok(SamplePlan::At(locs))
            }
        }
    }

    /// Number of samples.
    #[must_use]
    pub fn len(&self) -> usize {
        match self {
            SamplePlan::PerSegment { k, knots, closing } => {
                (knots.len() - 1) * *k as usize + usize::from(*closing)
            }
            SamplePlan::At(locs) => locs.len(),
        }
    }

    /// True when the plan has no samples (an empty "at" list).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Appends every sample's t to `out`, as [`SamplePlan::loc`] gives them, in one pass.
    pub fn extend_t(&self, out: &mut Vec<f64>) {
        match self {
            SamplePlan::PerSegment { k, knots, closing } => {
                let k = *k as usize;
                for w in knots.windows(2) {
                    let (t0, t1) = (w[0], w[1]);
                    out.extend((0..k).map(|j| {
                        let u = j as f64 / k as f64;
                        t0 + u * (t1 - t0)
                    }));
                }
                if *closing {
                    out.push(knots[knots.len() - 1]);
                }
            }
            SamplePlan::At(locs) => out.extend(locs.iter().map(|l| l.t)),
        }
    }

    /// Sample `i`: segment i / k at u = (i mod k)/k, or the final point.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    #[must_use]
    pub fn loc(&self, i: usize) -> SampleLoc {
        match self {
            SamplePlan::PerSegment { k, knots, .. } => {
                let k = *k as usize;
                let segments = knots.len() - 1;
                assert!(i < self.len(), "sample {i} past the plan's end");
                let (segment, u) = if i == segments * k {
                    (segments - 1, 1.0)
                } else {
                    (i / k, (i % k) as f64 / k as f64)
                };
                let (t0, t1) = (knots[segment], knots[segment + 1]);
                // The final point is exactly the last knot; elsewhere t_i + u (t_{i+1} − t_i).
                let t = if u == 1.0 { t1 } else { t0 + u * (t1 - t0) };
                SampleLoc { segment, u, t }
            }
            SamplePlan::At(locs) => locs[i],
        }
    }
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

fn out_of_range(table: &SegmentTable, i: usize, t: f64) -> InputError {
    let (lo, hi) = table.t_range();
    InputError::field(
        "at",
        format!("values must lie in the curve's range [{lo}, {hi}]: at[{i}] = {t}"),
    )
}
