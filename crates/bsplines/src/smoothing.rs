//! Cubic smoothing splines (SciPy's `make_smoothing_spline`): the f minimising
//!     sum_i w_i (y_i - f(x_i))^2 + lam * integral (f'')^2,
//! a natural cubic spline with a knot at every x, computed in SciPy's formulation (Woltring's,
//! as SciPy re-derived it) so that the same data give the same spline and the same GCV lam:
//!
//! - In a basis of natural splines N_j (N_j = B_{j+1} inside, combinations of B_0..B_2 and
//!   B_{n-1}..B_{n+1} at the ends, on the knots `[x_0] * 3 + x + [x_last] * 3`), the collocation
//!   matrix X (f(x_i) = (X c)_i) and the penalty E (from the divided differences of five
//!   neighbouring x, so that integral f''^2 = c^T X^T E c) are both 5-banded, and the
//!   minimiser solves
//!   `(X + lam W^-1 E) c = y`
//!   (banded LU with partial pivoting, as LAPACK's gbsv that SciPy calls). A solve in
//!   Reinsch's form (second derivatives, R + lam Q^T W^-1 Q) is cheaper but loses digits as
//!   1 / h^3 where x are close: 0.14 of 11 on 2,048 random x against 1e-4 here.
//! - When lam is not given it minimises generalised cross-validation (Wahba):
//!   `GCV(lam) = (|y - X c|^2 / n) / (1 - tr(A) / n)^2`,
//!   y - X c = lam W^-1 E c, and tr(A) = tr(B X^T W X), B = (X^T W X + lam X^T E)^-1, of
//!   which only the central bands are needed: Hutchinson and de Hoog's recurrence on the
//!   Cholesky factor A = U^T D^-1 U (U unit upper, bandwidth 3), from the last row up,
//!   `B_ij = delta_ij D_i - sum_{k=1..3} U_{i,i+k} B_{i+k,j}` (j >= i).
//!   As SciPy's, the trace takes the diagonal and two bands of B (it drops the third).
//! - The minimum is searched on (0, n) by the bounded Brent method of SciPy's
//!   `minimize_scalar(method="bounded")`, step for step.
//!
//! Everything is O(n) a lam; a column's matrices are made once for all its lams, and four
//! columns (of one series or of many) go side by side, one per vector lane (`group`).

mod group;

use crate::InputError;
use crate::bounded_search::{NoMinimum, Search, Step};
use crate::lanes::{Isa, Lanes, Vector, WIDTH};
use group::{Evaluation, Group};

/// Row i of one series' matrices (zero outside the matrix), made once for any lam and any
/// column of y.
#[derive(Clone, Copy, Default)]
pub(crate) struct SeriesRow {
    /// X[i, i - 1 ..= i + 1]: at its own x only three B-splines are not zero.
    design: [f64; 3],
    /// (W^-1 E)[i, i - 2 ..= i + 2] (6 E).
    penalty: [f64; 5],
    /// (X^T W X)[i, i ..= i + 3] and (X^T E)[i, i ..= i + 3]: the upper bands.
    gram: [f64; 4],
    rough: [f64; 4],
}

/// Why a smoothing spline could not be made.
#[derive(Debug, PartialEq, Clone)]
pub enum Failure {
    /// A matrix was singular or not positive definite.
    IllPosed,
    /// The search for the GCV minimum gave NaN or ran out of evaluations.
    NoMinimum(&'static str),
}

/// The coefficients 1 / prod_{k != i} (x_i - x_k) of the divided difference on the N points
/// `x` (N a constant: the loops unroll).
#[inline(always)]
fn divided_difference<const N: usize>(x: [f64; N]) -> [f64; N] {
    std::array::from_fn(|i| {
        let mut product = 1.0;
        for (k, &xk) in x.iter().enumerate() {
            if k != i {
                product *= x[i] - xk;
            }
        }
        1.0 / product
    })
}

/// The rows of the matrices of x (n >= 5, strictly increasing) and positive weights w, into
/// `rows` (resized to n), from the cubic B-splines of the knots [x_0] * 3 + x + [x_last] * 3
/// at each x_i.
fn series_rows(x: &[f64], w: &[f64], rows: &mut Vec<SeriesRow>) {
    let n = x.len();
    rows.clear();
    rows.resize(n, SeriesRow::default());
    let t: Vec<f64> = [x[0]; 3]
        .iter()
        .chain(x)
        .chain(&[x[n - 1]; 3])
        .copied()
        .collect();
    // B_j(x_i), read as SciPy's design matrix entries Xb[i, j]: x_i = t_{i+3} starts span
    // i + 3, and the last x ends span n + 1.
    let (mut values, mut scratch) = ([0.0; 4], [0.0; 4]);
    let splines: Vec<(usize, [f64; 4])> = (0..n)
        .map(|i| {
            if i + 1 < n {
                (i, crate::de_boor::cubic_at_knot(&t, i + 3))
            } else {
                crate::de_boor::basis_in(&t, 3, x[i], n + 1, 0, &mut values, &mut scratch);
                (n - 2, values)
            }
        })
        .collect();
    let xb = |i: usize, j: usize| {
        let (first, v) = splines[i];
        if j >= first && j < first + 4 {
            v[j - first]
        } else {
            0.0
        }
    };
    // X[i, j], |i - j| <= 1: the natural basis is B_{j+1} inside, combinations at the ends.
    let set = |rows: &mut Vec<SeriesRow>, i: usize, j: usize, v: f64| {
        rows[i].design[j + 1 - i] = v;
    };
    for (i, row) in rows.iter_mut().enumerate() {
        for (s, slot) in row.design.iter_mut().enumerate() {
            match (i + s).checked_sub(1) {
                Some(j) if (2..n - 2).contains(&j) => *slot = xb(i, j + 1),
                _ => {}
            }
        }
    }
    set(rows, 0, 0, (x[2] + x[1] - 2.0 * x[0]) * xb(0, 0));
    set(rows, 1, 0, (x[2] - x[0]) * xb(1, 1));
    set(rows, 0, 1, xb(0, 0));
    set(rows, 1, 1, xb(1, 1) + xb(1, 2));
    set(rows, 2, 1, xb(2, 2));
    let last = n - 1;
    set(rows, last - 2, last - 1, xb(last - 2, last));
    set(
        rows,
        last - 1,
        last,
        (x[last] - x[last - 2]) * xb(last - 1, last + 1),
    );
    set(
        rows,
        last - 1,
        last - 1,
        xb(last - 1, last) + xb(last - 1, last + 1),
    );
    set(
        rows,
        last,
        last,
        (2.0 * x[last] - x[last - 1] - x[last - 2]) * xb(last, last + 2),
    );
    set(rows, last, last - 1, xb(last, last + 2));
    // Column j of W^-1 E: 6 scale w_i^-1 times the divided difference's coefficients on rows
    // first.. (the N points from x[first]).
    fn column<const N: usize>(
        rows: &mut [SeriesRow],
        x: &[f64],
        w: &[f64],
        j: usize,
        first: usize,
        scale: f64,
    ) {
        let points: [f64; N] = std::array::from_fn(|r| x[first + r]);
        for (r, dd) in divided_difference(points).into_iter().enumerate() {
            let (i, v) = (first + r, 6.0 * scale * dd);
            // v / 1 is v: unit weights (the usual case) skip a division a term.
            rows[i].penalty[j + 2 - i] = if w[i] == 1.0 { v } else { v / w[i] };
        }
    }
    column::<3>(rows, x, w, 0, 0, 1.0);
    column::<4>(rows, x, w, 1, 0, 1.0);
    for j in 2..n - 2 {
        column::<5>(rows, x, w, j, j - 2, x[j + 2] - x[j - 2]);
    }
    column::<4>(rows, x, w, last - 1, n - 4, -1.0);
    column::<3>(rows, x, w, last, n - 3, 1.0);
    // (X^T W Y)[i, j] = sum over the rows r both columns touch of X[r, i] w_r Y[r, j]
    // (X[r, i] is zero unless |r - i| <= 1, Y[r, j] unless |r - j| <= 1 or 2), r upwards.
    for i in 0..n {
        let (gram, rough) = if i >= 1 && i + 4 <= n {
            inner_bands(rows, w, i)
        } else {
            edge_bands(rows, w, i)
        };
        rows[i].gram = gram;
        rows[i].rough = rough;
    }
}

/// Row i's upper bands of X^T W X and X^T E where every row r = i - 1 ..= i + 1 and column
/// up to i + 3 is in the matrix: `edge_bands`' sums with their terms written out (the same
/// terms in the same order).
#[inline(always)]
fn inner_bands(rows: &[SeriesRow], w: &[f64], i: usize) -> ([f64; 4], [f64; 4]) {
    let (above, row, below) = (&rows[i - 1], &rows[i], &rows[i + 1]);
    // X[r, i] w_r for r = i - 1, i, i + 1.
    let (xa, xr, xb) = (
        above.design[2] * w[i - 1],
        row.design[1] * w[i],
        below.design[0] * w[i + 1],
    );
    let gram = [
        0.0 + xa * above.design[2] + xr * row.design[1] + xb * below.design[0],
        0.0 + xr * row.design[2] + xb * below.design[1],
        0.0 + xb * below.design[2],
        0.0,
    ];
    let rough = [
        0.0 + xa * above.penalty[3] + xr * row.penalty[2] + xb * below.penalty[1],
        0.0 + xa * above.penalty[4] + xr * row.penalty[3] + xb * below.penalty[2],
        0.0 + xr * row.penalty[4] + xb * below.penalty[3],
        0.0 + xb * below.penalty[4],
    ];
    (gram, rough)
}

/// Row i's upper bands of X^T W X and X^T E, (i, i + d) for d = 0..=3, by the sums over the
/// rows r in the matrix.
fn edge_bands(rows: &[SeriesRow], w: &[f64], i: usize) -> ([f64; 4], [f64; 4]) {
    let n = rows.len();
    let mut gram = [0.0; 4];
    let mut rough = [0.0; 4];
    for d in 0..4 {
        let j = i + d;
        if j >= n {
            break;
        }
        let (mut g, mut e) = (0.0, 0.0);
        for r in j.saturating_sub(2).max(i.saturating_sub(1))..(i + 2).min(n) {
            let xw = rows[r].design[i + 1 - r] * w[r];
            if j + 1 >= r && j <= r + 1 {
                g += xw * rows[r].design[j + 1 - r];
            }
            e += xw * rows[r].penalty[j + 2 - r];
        }
        gram[d] = g;
        rough[d] = e;
    }
    (gram, rough)
}

/// One series' data checked as SciPy's `make_smoothing_spline` checks it, in SciPy's words: x
/// strictly increasing, weights finite and > 0, at least 5 points, y finite.
pub fn check(x: &[f64], y: &[f64], w: &[f64]) -> Result<(), InputError> {
    let ascending = x
        .iter()
        .position(|v| !v.is_finite())
        .or_else(|| x.windows(2).position(|p| p[1] <= p[0]).map(|i| i + 1));
    if let Some(i) = ascending {
        return Err(InputError::new("x", "``x`` should be an ascending array").at(i));
    }
    if let Some(i) = w.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(InputError::new("w", "Invalid vector of weights").at(i));
    }
    if x.len() < 5 {
        return Err(InputError::new(
            "x",
            "``x`` and ``y`` length must be at least 5",
        ));
    }
    if let Some(i) = y.iter().position(|v| !v.is_finite()) {
        return Err(InputError::new("y", "must be finite (NaN or infinity found)").at(i));
    }
    Ok(())
}

/// One column of y: y_i = values[i * stride + offset].
#[derive(Clone, Copy, Debug)]
pub struct Column<'a> {
    /// The values of every column.
    pub values: &'a [f64],
    /// Values a row.
    pub stride: usize,
    /// The column's place in a row.
    pub offset: usize,
}

impl Column<'_> {
    fn get(&self, i: usize) -> f64 {
        self.values[i * self.stride + self.offset]
    }
}

/// One smoothing spline to make: a series (x strictly increasing, n >= 5; w positive), one
/// column of its y, and its lam (None: the lam of least GCV).
#[derive(Clone, Copy, Debug)]
pub struct Job<'a> {
    /// The abscissae, strictly increasing.
    pub x: &'a [f64],
    /// One weight per x, > 0.
    pub w: &'a [f64],
    /// The column of y to smooth.
    pub y: Column<'a>,
    /// The lam, or None for GCV's.
    pub lam: Option<f64>,
}

/// A smoothing spline: its n + 2 B-spline coefficients on the knots
/// `t = [x_0] * 3 + x + [x_last] * 3`, and its lam.
#[derive(Debug)]
pub struct Fit {
    /// The n + 2 B-spline coefficients.
    pub c: Vec<f64>,
    /// The lam.
    pub lam: f64,
}

/// Every job's spline, on this thread, the jobs evaluated side by side (`Group`: four lanes,
/// compiled for the widest vectors this CPU has). GCV's lam is searched on (0, n) by the
/// bounded Brent method of SciPy's `minimize_scalar(bounds=(0, n), method="bounded")`, each
/// job's search on its own; a finished job's lane goes to the next. The jobs are taken
/// shortest first, so that lanes side by side have about one length.
pub fn fit(jobs: &[Job<'_>]) -> Vec<Result<Fit, Failure>> {
    // The unsafe calls of the extension: a function compiled for an instruction set may only
    // be called where the CPU has it.
    #[allow(
        unsafe_code,
        reason = "a function compiled for an instruction set is called only where the CPU has it"
    )]
    match Isa::widest() {
        Isa::Baseline => fit_side_by_side::<Lanes>(jobs),
        // SAFETY: `Isa::widest` names AVX2 only where the CPU has it.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { fit_avx2(jobs) },
        // SAFETY: and AVX-512 (F and VL) only where it has those.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { fit_avx512(jobs) },
    }
}

/// `fit` with AVX2 enabled; the evaluation is inlined into it, so all of it is compiled with
/// the wider vectors.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn fit_avx2(jobs: &[Job<'_>]) -> Vec<Result<Fit, Failure>> {
    fit_side_by_side::<crate::lanes::Avx2>(jobs)
}

/// `fit_avx2` with AVX-512's 32 vector registers (the same four-lane vectors): an
/// evaluation's row holds about 30 vectors at once, which 16 registers spill to the stack
/// (the time it saves: docs/benchmarks.md).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f,avx512vl")]
fn fit_avx512(jobs: &[Job<'_>]) -> Vec<Result<Fit, Failure>> {
    fit_side_by_side::<crate::lanes::Avx2>(jobs)
}

/// Where a job in a lane stands.
enum Phase {
    /// GCV's search, which asks for this lam next.
    Search(Search, f64),
    /// The coefficients at a lam given.
    Solve(f64),
}

#[inline(always)]
fn fit_side_by_side<V: Vector>(jobs: &[Job<'_>]) -> Vec<Result<Fit, Failure>> {
    let capacity = jobs.iter().map(|j| j.x.len()).max().unwrap_or(0);
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&i| jobs[i].x.len());
    let mut queue = order.into_iter();
    let mut results: Vec<Option<Result<Fit, Failure>>> = jobs.iter().map(|_| None).collect();
    let mut group = Group::new(capacity);
    let mut rows = Vec::with_capacity(capacity);
    let mut lanes: [Option<(usize, Phase)>; WIDTH] = std::array::from_fn(|_| None);
    loop {
        for (l, lane) in lanes.iter_mut().enumerate() {
            if lane.is_some() {
                continue;
            }
            if let Some(i) = queue.next() {
                let job = jobs[i];
                series_rows(job.x, job.w, &mut rows);
                group.load(l, &rows, |r| job.y.get(r));
                let phase = match job.lam {
                    Some(lam) => Phase::Solve(lam),
                    None => {
                        let (search, lam) = Search::new(0.0, job.x.len() as f64);
                        Phase::Search(search, lam)
                    }
                };
                *lane = Some((i, phase));
            } else if group.lengths()[l] > 0 {
                group.clear(l);
            }
        }
        if lanes.iter().all(Option::is_none) {
            break;
        }
        let lam = Lanes(std::array::from_fn(|l| match &lanes[l] {
            Some((_, Phase::Search(_, lam) | Phase::Solve(lam))) => *lam,
            None => 1.0,
        }));
        let evaluation = group.evaluate::<V>(lam);
        for (l, lane) in lanes.iter_mut().enumerate() {
            let Some((i, phase)) = lane else {
                continue;
            };
            let x = jobs[*i].x;
            let done = match phase {
                Phase::Search(search, lam) => match gcv(&evaluation, l, group.lengths()[l]) {
                    Err(e) => Some(Err(e)),
                    Ok(value) => {
                        let step = search.tell(value);
                        // Each search keeps the c of its best lam so far: where it ends, its
                        // spline without another evaluation.
                        if search.best().to_bits() == lam.to_bits() {
                            group.keep(l);
                        }
                        match step {
                            Step::Evaluate(next) => {
                                *lam = next;
                                None
                            }
                            Step::Done(Ok(chosen)) => Some(
                                bspline_coefficients(x, &group.kept(l))
                                    .map(|c| Fit { c, lam: chosen }),
                            ),
                            Step::Done(Err(NoMinimum(why))) => Some(Err(Failure::NoMinimum(why))),
                        }
                    }
                },
                Phase::Solve(lam) => Some(if evaluation.solved[l] {
                    group.keep(l);
                    bspline_coefficients(x, &group.kept(l)).map(|c| Fit { c, lam: *lam })
                } else {
                    Err(Failure::IllPosed)
                }),
            };
            if let Some(result) = done {
                results[*i] = Some(result);
                *lane = None;
            }
        }
    }
    results
        .into_iter()
        .map(|r| r.expect("every job fitted"))
        .collect()
}

/// Lane l's GCV(lam) = (|lam W^-1 E c|^2 / n) / (1 - tr(A) / n)^2.
fn gcv(e: &Evaluation, l: usize, n: usize) -> Result<f64, Failure> {
    if !(e.solved[l] && e.factored[l]) || e.residual[l].is_nan() || e.trace[l].is_nan() {
        // A NaN pivot passes the pivots' check and reaches the sums.
        return Err(Failure::IllPosed);
    }
    let size = n as f64;
    let denominator = 1.0 - e.trace[l] / size;
    Ok(e.residual[l] / size / (denominator * denominator))
}

/// GCV(lam) of one series at each lam: the criterion `fit` minimises (each lane the series at
/// its own lam).
pub fn criterion(x: &[f64], w: &[f64], y: Column<'_>, lams: &[f64]) -> Vec<Result<f64, Failure>> {
    let mut group = Group::new(x.len());
    let mut rows = Vec::new();
    series_rows(x, w, &mut rows);
    for l in 0..WIDTH {
        group.load(l, &rows, |r| y.get(r));
    }
    lams.chunks(WIDTH)
        .flat_map(|chunk| {
            let lam = Lanes(std::array::from_fn(|l| {
                chunk.get(l).copied().unwrap_or(1.0)
            }));
            let evaluation = group.evaluate::<Lanes>(lam);
            (0..chunk.len())
                .map(|l| gcv(&evaluation, l, x.len()))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The natural basis' c as the spline's n + 2 B-spline coefficients on the knots
/// t = [x_0] * 3 + x + [x_last] * 3 (SciPy's (2.2.10)): the first two from c_0 and c_1, the
/// last two from c_{n-1} and c_{n-2}.
fn bspline_coefficients(x: &[f64], c: &[f64]) -> Result<Vec<f64>, Failure> {
    let n = x.len();
    let mut out = Vec::with_capacity(n + 2);
    out.push(c[0] * (x[2] + x[1] - 2.0 * x[0]) + c[1]);
    out.push(c[0] * (x[2] - x[0]) + c[1]);
    out.extend_from_slice(&c[1..n - 1]);
    out.push(c[n - 1] * (x[n - 1] - x[n - 3]) + c[n - 2]);
    out.push(c[n - 1] * (2.0 * x[n - 1] - x[n - 2] - x[n - 3]) + c[n - 2]);
    if out.iter().all(|v| v.is_finite()) {
        Ok(out)
    } else {
        Err(Failure::IllPosed)
    }
}

#[cfg(test)]
mod tests {
    use super::{Column, Fit, Job, fit, fit_side_by_side};
    use crate::lanes::Lanes;

    fn job<'a>(x: &'a [f64], w: &'a [f64], y: &'a [f64], lam: f64) -> Job<'a> {
        Job {
            x,
            w,
            y: Column {
                values: y,
                stride: 1,
                offset: 0,
            },
            lam: Some(lam),
        }
    }

    /// B-spline coefficients of a line are its values at the Greville abscissae (knot
    /// averages); a line has no f'', so any lam keeps it.
    #[test]
    fn a_line_is_kept_for_any_lam() {
        let x = [0.0, 1.0, 1.5, 3.0, 4.0, 7.0];
        let y: Vec<f64> = x.iter().map(|v| 2.0 * v - 1.0).collect();
        let w = [1.0, 2.0, 0.5, 1.0, 3.0, 1.0];
        let t: Vec<f64> = [0.0; 3]
            .iter()
            .chain(&x)
            .chain(&[7.0; 3])
            .copied()
            .collect();
        let jobs: Vec<Job<'_>> = [0.0, 0.1, 1e3].map(|lam| job(&x, &w, &y, lam)).to_vec();
        for (fitted, lam) in fit(&jobs).into_iter().zip([0.0, 0.1, 1e3]) {
            for (j, cj) in fitted.unwrap().c.iter().enumerate() {
                let greville = (t[j + 1] + t[j + 2] + t[j + 3]) / 3.0;
                assert!(
                    (cj - (2.0 * greville - 1.0)).abs() < 1e-11,
                    "{lam} {j}: {cj}"
                );
            }
        }
    }

    fn same(a: &Result<Fit, super::Failure>, b: &Result<Fit, super::Failure>) {
        let (a, b) = (a.as_ref().unwrap(), b.as_ref().unwrap());
        assert_eq!(a.lam.to_bits(), b.lam.to_bits());
        assert_eq!(a.c, b.c);
    }

    /// GCV searches side by side: the portable lanes and the AVX ones give the same lams and
    /// coefficients bit for bit, and a series searched beside others of other lengths gives
    /// what it gives alone.
    #[test]
    fn lanes_agree_with_each_other_and_with_a_series_alone() {
        let series: Vec<(Vec<f64>, Vec<f64>)> = (0..6)
            .map(|s| {
                let n = 20 + 7 * s;
                let x: Vec<f64> = (0..n)
                    .map(|i| i as f64 + 0.3 * ((i * 7 + s) as f64).sin())
                    .collect();
                let y = x.iter().map(|v| v.sin() + 0.2 * (v * 13.0).cos()).collect();
                (x, y)
            })
            .collect();
        let w = [1.0; 60];
        let jobs: Vec<Job<'_>> = series
            .iter()
            .map(|(x, y)| Job {
                x,
                w: &w[..x.len()],
                y: Column {
                    values: y,
                    stride: 1,
                    offset: 0,
                },
                lam: None,
            })
            .collect();
        let portable = fit_side_by_side::<Lanes>(&jobs);
        same(&portable[3], &fit_side_by_side::<Lanes>(&jobs[3..4])[0]);
        #[cfg(target_arch = "x86_64")]
        if crate::lanes::Isa::widest() != crate::lanes::Isa::Baseline {
            let vectors = fit_side_by_side::<crate::lanes::Avx2>(&jobs);
            for (a, b) in portable.iter().zip(&vectors) {
                same(a, b);
            }
        }
    }

    /// The bands' written-out sums are the general sums bit for bit, on uneven x and weights.
    #[test]
    fn inner_bands_are_the_sums() {
        let x: Vec<f64> = (0..30)
            .map(|i| i as f64 + 0.45 * (i as f64 * 2.7).sin())
            .collect();
        let w: Vec<f64> = (0..30).map(|i| 1.0 + 0.5 * (i as f64).cos()).collect();
        let mut rows = Vec::new();
        super::series_rows(&x, &w, &mut rows);
        for i in 1..x.len() - 3 {
            let (a, b) = (
                super::inner_bands(&rows, &w, i),
                super::edge_bands(&rows, &w, i),
            );
            assert_eq!(a.0.map(f64::to_bits), b.0.map(f64::to_bits), "gram {i}");
            assert_eq!(a.1.map(f64::to_bits), b.1.map(f64::to_bits), "rough {i}");
        }
    }

    /// With lam = 0 the spline interpolates: its end coefficients are the end values. A
    /// shorter series beside it in the lanes (its rows padded) gives what it gives alone.
    #[test]
    fn lam_zero_interpolates() {
        let x = [0.0, 0.5, 1.5, 2.0, 3.5, 4.0, 4.5, 6.0];
        let y: Vec<f64> = x.iter().map(|v: &f64| v.sin()).collect();
        let w = [1.0; 8];
        let fitted = fit(&[job(&x, &w, &y, 0.0)]);
        let c = &fitted[0].as_ref().unwrap().c;
        assert!((c[0] - y[0]).abs() < 1e-14 && (c[9] - y[7]).abs() < 1e-14);
        let together = fit(&[job(&x, &w, &y, 0.0), job(&x[..6], &w[..6], &y[..6], 0.3)]);
        let alone = fit(&[job(&x[..6], &w[..6], &y[..6], 0.3)]);
        assert_eq!(together[0].as_ref().unwrap().c, *c);
        assert_eq!(
            together[1].as_ref().unwrap().c,
            alone[0].as_ref().unwrap().c
        );
    }
}
