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
use crate::parallel::{even_ranges, fan_out_map, take_front};
use crate::sampling::out_of_range;
use crate::sampling::place::Placer;
use crate::segment::{
    SegmentTable, first_derivative, position, second_derivative, third_derivative,
};

/// The fewest parameters worth a task of the pool: locating and evaluating one takes tens of
/// nanoseconds, a task's hand-over about a microsecond.
const MIN_PART: usize = 4096;

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
    // loop body (eval-at, one thread: docs/benchmarks.md).
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

/// Parameters placed before their values are written (see [`run`]).
const BLOCK: usize = 64;
