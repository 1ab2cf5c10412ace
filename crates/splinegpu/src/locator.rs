//! `Locator`: the segment of a parameter t in O(1) for evenly spread knots, exactly as a binary
//! search over all the knots finds it.
//!
//! The range [t_0, t_n] is cut into B equal buckets, bucket(t) = ⌊(t − t_0)·B/(t_n − t_0)⌋
//! (capped to B − 1). bucket() never decreases as t grows (a subtraction and a multiplication
//! by a positive constant are monotone in IEEE arithmetic), so for t in bucket b every knot in
//! an earlier bucket lies below t and every knot in a later one above it: the last knot <= t
//! is among the knots from `last[b − 1]` (the last knot of buckets before b; knot 0 for b = 0)
//! to `last[b]`, where `last[b]` is the last knot whose bucket is at most b. With B equal to the
//! number of segments, evenly spread knots leave one or two candidates per bucket; uneven
//! ones leave more, found by a binary search among them, never worse than one over all knots.
//! B is [`BUCKETS_PER_SEGMENT`] times the number of segments, so that knots spaced unevenly
//! within a factor of a few still leave at most two candidates: then the choice between them
//! is one comparison and no branch.

/// Buckets per segment: 4 u32 (16 bytes) per segment, beside its 32 bytes per coordinate of
/// coefficients. On eval-at's knots (spacings within a factor of 20) one per segment left
/// more than two candidates often enough that the search's branches cost most of the time.
const BUCKETS_PER_SEGMENT: usize = 4;

/// The buckets of one table's knots (see the module's documentation).
#[derive(Clone, Debug)]
pub(crate) struct Locator {
    /// t_0.
    start: f64,
    /// B / (t_n − t_0).
    scale: f64,
    /// B − 1.
    last_bucket: usize,
    /// Per bucket b, the index of the last knot whose bucket is <= b.
    last: Vec<u32>,
}

impl Locator {
    /// The buckets of `knots` (strictly increasing, at least two); `None`
    /// where they cannot be formed (a range too narrow for B/(t_n − t_0) to be finite, or more
    /// knots than a u32 counts).
    pub(crate) fn new(knots: &[f64]) -> Option<Self> {
        let segments = knots.len() - 1;
        let buckets = segments * BUCKETS_PER_SEGMENT;
        let (start, end) = (knots[0], knots[segments]);
        let scale = buckets as f64 / (end - start);
        if !scale.is_finite() || u32::try_from(knots.len()).is_err() {
            return None;
        }
        let mut locator = Self {
            start,
            scale,
            last_bucket: buckets - 1,
            last: Vec::with_capacity(buckets),
        };
        // Knots in order, their buckets never decreasing: bucket b's entry is the last knot
        // seen before the first knot of a later bucket.
        let mut knot = 0;
        for b in 0..buckets {
            while knot + 1 < knots.len() && locator.bucket(knots[knot + 1]) <= b {
                knot += 1;
            }
            locator.last.push(knot as u32);
        }
        Some(locator)
    }

    /// The bucket of t (t in the knots' range).
    #[inline(always)]
    fn bucket(&self, t: f64) -> usize {
        (((t - self.start) * self.scale) as usize).min(self.last_bucket)
    }

    /// The candidates for t's last knot <= t: indices `lo..=hi` into the knots, with
    /// knots[lo] <= t (t in the knots' range).
    #[inline(always)]
    pub(crate) fn candidates(&self, t: f64) -> (usize, usize) {
        let b = self.bucket(t);
        let lo = if b == 0 { 0 } else { self.last[b - 1] as usize };
        (lo, self.last[b] as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// For t on every knot, between them, and at the ends: the last knot <= t is a candidate,
    /// and the first candidate is <= t.
    #[test]
    fn the_candidates_hold_the_last_knot_at_or_below_t() {
        let even: Vec<f64> = (0..50).map(f64::from).collect();
        // Spacings over twelve decades, and a cluster the buckets cannot separate.
        let mut uneven = vec![0.0];
        for i in 1..60usize {
            let gap = 10f64.powi((i as i32 * 7) % 13 - 6);
            uneven.push(uneven[i - 1] + gap);
        }
        let clustered = [-3.0, 1e-12, 2e-12, 3e-12, 4e-12, 1.0, 1e6];
        for knots in [even.as_slice(), &uneven, &clustered, &[0.0, 1.0]] {
            let locator = Locator::new(knots).unwrap();
            let mut ts: Vec<f64> = knots.to_vec();
            ts.extend(knots.windows(2).map(|w| w[0] + (w[1] - w[0]) * 0.37));
            ts.extend(knots.windows(2).map(|w| w[1].next_down().max(w[0])));
            for t in ts {
                let want = knots.partition_point(|&k| k <= t) - 1;
                let (lo, hi) = locator.candidates(t);
                assert!(lo <= want && want <= hi, "t {t}: {want} not in {lo}..={hi}");
                assert!(knots[lo] <= t);
            }
        }
    }

    #[test]
    fn a_range_too_narrow_to_scale_has_no_locator() {
        assert!(Locator::new(&[0.0, 1e-320]).is_none());
    }
}
