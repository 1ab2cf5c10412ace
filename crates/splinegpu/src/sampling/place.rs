//! Explicit parameters placed on a curve's segments one after the other, as
//! [`SamplePlan`](crate::SamplePlan) places them: the last segment whose first knot is <= t,
//! the range's end on the last segment at u = 1, u = (t − t_i)/(t_{i+1} − t_i) clamped to
//! [0, 1]. Parameters in increasing order (sorted queries, the common case) walk forward from
//! the previous t's segment; scattered ones go through the table's
//! [`Locator`](crate::locator::Locator) (buckets over the knots), or a binary search where a
//! call has too few of them to repay making it. The CPU's explicit-t evaluator and the plans
//! of `Sampling::At` both place through here.

use crate::locator::Locator;
use crate::segment::SegmentTable;

/// Segments walked forward from the previous t's before a binary search takes over.
const WALK: usize = 8;

/// Places parameters one after the other as [`SamplePlan`](crate::SamplePlan) defines their
/// places (see the module docs): sorted ones by walking forward, scattered ones
/// through the table's locator where the parameters given to [`Placer::new`] repay it.
pub(crate) struct Placer<'a> {
    knots: &'a [f64],
    last: usize,
    locator: Option<&'a Locator>,
    segment: usize,
}

impl<'a> Placer<'a> {
    /// A placer for `table`, chosen for the parameters `at` that will be placed.
    pub(crate) fn new(table: &'a SegmentTable, at: &[f64]) -> Self {
        let knots = table.knots();
        Self {
            knots,
            last: knots.len() - 2,
            locator: scattered_locator(table, at),
            segment: 0,
        }
    }

    /// The segment and local u of `t`; `None` outside the curve's range or for a t that is
    /// not finite.
    #[inline(always)]
    pub(crate) fn place(&mut self, t: f64) -> Option<(usize, f64)> {
        let knots = self.knots;
        if !(t >= knots[0] && t <= knots[self.last + 1]) {
            return None;
        }
        self.segment = match self.locator {
            Some(locator) => located(locator, knots, self.last, t),
            None => segment_of(knots, self.last, self.segment, t),
        };
        let (t0, t1) = (knots[self.segment], knots[self.segment + 1]);
        Some((self.segment, ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)))
    }
}

/// The segment of t through `locator`: at most two candidates (the common case) are told
/// apart by one comparison, without a branch on the data; more by binary search.
#[inline(always)]
fn located(locator: &Locator, knots: &[f64], last: usize, t: f64) -> usize {
    let (first, end) = locator.candidates(t);
    let s = if end - first <= 1 {
        first + usize::from((end > first) & (knots[end] <= t))
    } else {
        first + last_at_or_below(&knots[first..=end], t)
    };
    s.min(last)
}

/// The table's locator, for parameters `at` that are not in increasing order (sorted ones walk
/// forward instead); made here when there are enough of them to repay its O(knots) making
/// (one parameter per 16 segments), and used from then on by every call.
fn scattered_locator<'a>(table: &'a SegmentTable, at: &[f64]) -> Option<&'a Locator> {
    const SEGMENTS_PER_PARAMETER: usize = 16;
    if at.windows(2).all(|w| w[0] <= w[1]) {
        return None;
    }
    match table.built_locator() {
        Some(built) => built,
        None if at.len() * SEGMENTS_PER_PARAMETER >= table.len() => table.locator(),
        None => None,
    }
}

/// The segment of t in `[knots[0], knots[last + 1]]`: the last whose first knot is <= t, capped
/// to `last`, found by walking forward from `from` when t lies at or after its start, and by
/// binary search otherwise.
#[inline(always)]
fn segment_of(knots: &[f64], last: usize, from: usize, t: f64) -> usize {
    if knots[from] <= t {
        let mut s = from;
        for _ in 0..WALK {
            if s == last || knots[s + 1] > t {
                return s;
            }
            s += 1;
        }
        // knots[s] <= t: the last such knot at or above s, by binary search.
        return (s + last_at_or_below(&knots[s..], t)).min(last);
    }
    last_at_or_below(knots, t).min(last)
}

/// The index of the last of the increasing `knots` that is <= t, given `knots[0] <= t`: a
/// binary search without branches on the data (each halving picks its half by a conditional
/// move), so that scattered t cost no mispredicted branches.
#[inline(always)]
fn last_at_or_below(knots: &[f64], t: f64) -> usize {
    let (mut base, mut size) = (0, knots.len());
    while size > 1 {
        let half = size / 2;
        let mid = base + half;
        // Invariant: knots[base] <= t, and the answer lies in base..base + size.
        base = std::hint::select_unpredictable(knots[mid] <= t, mid, base);
        size -= half;
    }
    base
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::locate;

    #[test]
    fn the_walk_finds_the_segment_binary_search_finds() {
        // Uneven knots, t on and between them, at both ends, in every order.
        let knots = [
            0.0,
            0.5,
            0.75,
            2.0,
            2.0 + 1e-9,
            3.0,
            10.0,
            10.5,
            11.0,
            12.0,
            20.0,
        ];
        let last = knots.len() - 2;
        let mut ts: Vec<f64> = knots.to_vec();
        ts.extend(knots.windows(2).map(|w| (w[0] + w[1]) / 2.0));
        ts.extend([1e-300, 19.999_999, 20.0, 0.0]);
        for from in 0..=last {
            for &t in &ts {
                let expected = locate(&knots, t).expect("in range").segment;
                assert_eq!(
                    segment_of(&knots, last, from, t),
                    expected,
                    "t {t} from {from}"
                );
            }
        }
    }
}
