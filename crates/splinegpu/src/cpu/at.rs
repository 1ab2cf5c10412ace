//! Explicit parameters evaluated as a caller makes them: each t located and evaluated in one
//! pass, with no plan in between, straight into the caller's memory.
//!
//! A t is placed as [`SamplePlan`](crate::SamplePlan) places it (the last segment whose first
//! knot is <= t, the range's end on the last segment at u = 1, u = (t − t_i)/(t_{i+1} − t_i)
//! clamped to [0, 1]) and evaluated with the formulas of [`segment`](crate::segment), so the
//! values are bit for bit those of a job with `Sampling::At` through [`evaluate_cpu`] in the
//! same float type. Parameters in increasing order (sorted queries, the common case) walk
//! forward from the previous t's segment; scattered ones go through the table's
//! [`Locator`](crate::locator::Locator) (buckets over the knots), or a binary search where a
//! call has too few of them to repay making it.
//!
//! [`evaluate_cpu`]: crate::evaluate_cpu

use std::borrow::Borrow;

use crate::InputError;
use crate::job::samples::SampleFloat;
use crate::locator::Locator;
use crate::parallel::{even_ranges, fan_out_map, take_front};
use crate::sampling::out_of_range;
use crate::segment::{
    SegmentTable, first_derivative, position, second_derivative, third_derivative,
};

/// The fewest parameters worth a task of the pool: locating and evaluating one takes tens of
/// nanoseconds, a task's hand-over about a microsecond.
const MIN_PART: usize = 4096;

/// Segments walked forward from the previous t's before a binary search takes over.
const WALK: usize = 8;

/// The `nu`-th derivative with respect to t (0: the position; 1, 2, 3: dP/dt, d²P/dt²,
/// d³P/dt³) of `table`'s curve at every parameter of `at`, into `out` (`dim` values per
/// parameter, in `at`'s order), on up to `threads` threads of the process's pool.
///
/// This is the call for values at explicit parameters (a SciPy user's `s(x)`): nothing is
/// allocated, and each t is located and evaluated in one pass. Positions, d1 and d2 equal
/// those of an [`EvalJob`](crate::EvalJob) with [`Sampling::At`](crate::Sampling::At) through
/// [`evaluate_cpu`](crate::evaluate_cpu) bit for bit; the third derivative is 6A/Δ³ on the
/// segment that holds t.
///
/// # Errors
/// `nu` above 3 (the error names `"nu"`); a t that is not finite or lies outside the curve's
/// range (the error names `"at"`, the first such index and its value). On an error `out` holds
/// unspecified values.
///
/// # Panics
/// If `out` does not hold `at.len() * table.dim()` values.
pub fn evaluate_at_into<F: SampleFloat>(
    table: &SegmentTable,
    at: &[f64],
    nu: usize,
    out: &mut [F],
    threads: usize,
) -> Result<(), InputError> {
    let dim = table.dim();
    assert_eq!(
        out.len(),
        at.len() * dim,
        "out holds {} values for {} parameters of {dim} coordinates",
        out.len(),
        at.len()
    );
    if nu > 3 {
        return Err(InputError::field(
            "nu",
            format!("must be 0, 1, 2 or 3, got {nu}"),
        ));
    }
    let parts = threads.clamp(1, at.len().div_ceil(MIN_PART).max(1));
    let mut rest = out;
    let parts: Vec<_> = even_ranges(at.len(), parts)
        .map(|range| {
            let mine = take_front(&mut rest, range.len() * dim);
            (range, mine)
        })
        .collect();
    let failed = fan_out_map(parts, |(range, out)| {
        let first = range.start;
        place_and_evaluate(table, nu, &at[range], out).map_err(|i| first + i)
    });
    match failed.into_iter().find_map(Result::err) {
        Some(i) => Err(out_of_range(table, i, at[i])),
        None => Ok(()),
    }
}

/// [`evaluate_at_into`] for many curves at once: curve c (`tables[c]`) at its own parameters
/// `at[c]`, its values after curve c − 1's in `out` (`at[c].len() * tables[c].dim()` values
/// each), the curves spread over up to `threads` threads of the pool (a single curve's
/// parameters spread instead). This is a batch of splines called at their own points (SciPy's
/// loop of `s(x)` over splines), with no job built.
///
/// # Errors
/// As [`evaluate_at_into`], for the first curve in order that has one, the error naming it.
///
/// # Panics
/// If `tables` and `at` differ in length, or `out` does not hold every curve's values.
pub fn evaluate_curves_at_into<F, T, A>(
    tables: &[T],
    at: &[A],
    nu: usize,
    out: &mut [F],
    threads: usize,
) -> Result<(), InputError>
where
    F: SampleFloat,
    T: Borrow<SegmentTable> + Sync,
    A: AsRef<[f64]> + Sync,
{
    assert_eq!(tables.len(), at.len(), "one array of parameters per curve");
    if let ([table], [at]) = (tables, at) {
        return evaluate_at_into(table.borrow(), at.as_ref(), nu, out, threads)
            .map_err(|e| e.in_curve(0));
    }
    let lengths: Vec<usize> = (tables.iter().zip(at))
        .map(|(table, at)| table.borrow().dim() * at.as_ref().len())
        .collect();
    let needed: usize = lengths.iter().sum();
    assert_eq!(
        out.len(),
        needed,
        "out holds {} of {needed} values",
        out.len()
    );
    let mut rest = out;
    let parts: Vec<_> = even_ranges(tables.len(), threads)
        .map(|curves| {
            let n = lengths[curves.clone()].iter().sum();
            (curves, take_front(&mut rest, n))
        })
        .collect();
    let failed = fan_out_map(parts, |(curves, mut out)| {
        for c in curves {
            let mine = take_front(&mut out, lengths[c]);
            let (table, at) = (tables[c].borrow(), at[c].as_ref());
            evaluate_at_into(table, at, nu, mine, 1).map_err(|e| e.in_curve(c))?;
        }
        Ok(())
    });
    failed.into_iter().collect()
}

/// [`evaluate_at_into`]'s work on one part, with the dimension and the order known at compile
/// time where they are common; `Err(i)` for the first t outside the range.
fn place_and_evaluate<F: SampleFloat>(
    table: &SegmentTable,
    nu: usize,
    at: &[f64],
    out: &mut [F],
) -> Result<(), usize> {
    macro_rules! by_order {
        ($d:literal) => {
            match nu {
                0 => run::<0, $d, F>(table, at, out),
                1 => run::<1, $d, F>(table, at, out),
                2 => run::<2, $d, F>(table, at, out),
                _ => run::<3, $d, F>(table, at, out),
            }
        };
    }
    match table.dim() {
        1 => by_order!(1),
        2 => by_order!(2),
        3 => by_order!(3),
        4 => by_order!(4),
        _ => by_order!(0),
    }
}

/// Every t of `at` placed and its `NU`-th derivative written, `D` coordinates (0: the
/// table's own dimension, read at run time).
#[inline(always)]
fn run<const NU: usize, const D: usize, F: SampleFloat>(
    table: &SegmentTable,
    at: &[f64],
    out: &mut [F],
) -> Result<(), usize> {
    let dim = if D == 0 { table.dim() } else { D };
    let (knots, coeffs) = (table.knots(), table.power_coefficients());
    let mut placer = Placer::new(table, at);
    if table.is_rational() {
        // The quotient rule per sample (`crate::rational`), as the reference evaluates it.
        let mut value = [0.0; crate::points::MAX_DIM];
        for (i, (&t, o)) in at.iter().zip(out.chunks_exact_mut(dim)).enumerate() {
            let (segment, u) = placer.place(t).ok_or(i)?;
            table
                .segment(segment)
                .derivative_into(NU, u, &mut value[..dim]);
            for (o, v) in o.iter_mut().zip(&value) {
                *o = F::from_f64(*v);
            }
        }
        return Ok(());
    }
    // In blocks: every t of a block placed first, then every value written. Two short loops
    // of independent iterations keep more places and Horner chains in flight than one long
    // loop body (eval-at, one thread: 175 ms fused, see the commit for the blocked figure).
    let mut places = [(0usize, 0f64); BLOCK];
    for (b, (at, out)) in at
        .chunks(BLOCK)
        .zip(out.chunks_mut(BLOCK * dim))
        .enumerate()
    {
        for (i, (&t, place)) in at.iter().zip(&mut places).enumerate() {
            *place = placer.place(t).ok_or(b * BLOCK + i)?;
        }
        for (&(segment, u), o) in places.iter().zip(out.chunks_exact_mut(dim)) {
            let c = &coeffs[4 * dim * segment..][..4 * dim];
            let inv_dt = 1.0 / (knots[segment + 1] - knots[segment]);
            for k in 0..dim {
                let (a, b, cc, d) = (c[k], c[dim + k], c[2 * dim + k], c[3 * dim + k]);
                o[k] = F::from_f64(match NU {
                    0 => position(a, b, cc, d, u),
                    1 => first_derivative(a, b, cc, u, inv_dt),
                    2 => second_derivative(a, b, u, inv_dt),
                    _ => third_derivative(a, inv_dt),
                });
            }
        }
    }
    Ok(())
}

/// Places parameters one after the other as [`SamplePlan`](crate::SamplePlan) defines their
/// places (see the module's documentation): sorted ones by walking forward, scattered ones
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

/// Parameters placed before their values are written (see [`run`]).
const BLOCK: usize = 64;

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
