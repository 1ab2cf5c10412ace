//! The places of consecutive samples of a computed plan (arc length, tolerance) grouped by
//! segment, so that the CPU evaluator takes each segment's samples as one block (its
//! coefficients hoisted, the block vectorized) rather than one place at a time.

use std::ops::Range;

/// Places of consecutive samples grouped into runs on one segment each: run i is `len` samples
/// on segment `segment`, their local u the next `len` values of `us`.
#[derive(Clone, Debug, Default)]
pub(crate) struct Runs {
    runs: Vec<(usize, usize)>,
    us: Vec<f64>,
}

impl Runs {
    /// No runs, the memory kept.
    pub(crate) fn clear(&mut self) {
        self.runs.clear();
        self.us.clear();
    }

    /// Appends one sample at local `u` on `segment` (to the last run where it is on its
    /// segment).
    pub(crate) fn push(&mut self, segment: usize, u: f64) {
        self.us.push(u);
        self.grow(segment, 1);
    }

    /// Appends `n` samples on `segment` and returns their u to be written (zeros until
    /// then).
    #[inline(always)]
    pub(crate) fn extend(&mut self, segment: usize, n: usize) -> &mut [f64] {
        let base = self.us.len();
        self.us.resize(base + n, 0.0);
        self.grow(segment, n);
        &mut self.us[base..]
    }

    /// Counts `n` samples just appended to `us` into the runs.
    fn grow(&mut self, segment: usize, n: usize) {
        match self.runs.last_mut() {
            Some((last, len)) if *last == segment => *len += n,
            _ => self.runs.push((segment, n)),
        }
    }

    /// The runs in order: each segment and its samples' u.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (usize, &[f64])> {
        let mut at = 0;
        self.runs.iter().map(move |&(segment, len)| {
            let us = &self.us[at..at + len];
            at += len;
            (segment, us)
        })
    }
}

/// The first index of `range` at which `inside` is false (`range.end` if none), for an
/// `inside` true up to some index and false from there on: searched outward from `guess` (an
/// estimate of the answer; any value, NaN included, is safe), so a close guess costs two or
/// three tests.
#[inline(always)]
pub(crate) fn first_outside(
    range: Range<usize>,
    guess: f64,
    inside: impl Fn(usize) -> bool,
) -> usize {
    let (lo, hi) = (range.start, range.end);
    // `as` saturates (NaN to 0): the guess lands in [lo, hi].
    let guess = (guess as usize).clamp(lo, hi);
    // Bracket the answer in (below, above]: inside(below) holds (or below + 1 = lo), inside
    // fails at above (or above = hi), widening by doubling steps from the guess.
    let (mut below, mut above);
    if guess > lo && !inside(guess - 1) {
        above = guess - 1;
        let mut step = 1;
        loop {
            if above - lo < step {
                below = lo;
                if inside(lo) {
                    break;
                }
                return lo;
            }
            below = above - step;
            if inside(below) {
                break;
            }
            above = below;
            step *= 2;
        }
    } else {
        // inside(guess - 1) holds, or guess = lo.
        if guess == hi {
            return hi;
        }
        if !inside(guess) {
            return guess;
        }
        below = guess;
        let mut step = 1;
        loop {
            above = (below + step).min(hi);
            if above == hi || !inside(above) {
                break;
            }
            below = above;
            step *= 2;
        }
    }
    // inside(below), and above is hi or outside: bisect.
    while above - below > 1 {
        let mid = below + (above - below) / 2;
        if inside(mid) {
            below = mid;
        } else {
            above = mid;
        }
    }
    above
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_outside_is_found_from_any_guess() {
        for end in 3..40 {
            for answer in 3..=end {
                for guess in [-5.0, 0.0, 2.0, 3.0, 7.5, 20.0, 39.0, 1e300, f64::NAN] {
                    let got = first_outside(3..end, guess, |i| {
                        assert!((3..end).contains(&i), "tested {i} outside 3..{end}");
                        i < answer
                    });
                    assert_eq!(got, answer, "3..{end}, answer {answer}, guess {guess}");
                }
            }
        }
    }

    #[test]
    fn samples_on_one_segment_join_its_run_and_a_new_segment_starts_one() {
        let mut runs = Runs::default();
        runs.push(0, 0.0);
        runs.extend(0, 2).copy_from_slice(&[0.25, 0.5]);
        runs.push(1, 0.0);
        runs.extend(3, 1)[0] = 0.75;
        let got: Vec<(usize, Vec<f64>)> = runs.iter().map(|(s, us)| (s, us.to_vec())).collect();
        assert_eq!(
            got,
            [(0, vec![0.0, 0.25, 0.5]), (1, vec![0.0]), (3, vec![0.75])]
        );
        runs.clear();
        assert_eq!(runs.iter().count(), 0);
    }
}
