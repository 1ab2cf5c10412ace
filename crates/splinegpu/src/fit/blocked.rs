//! Strictly diagonally dominant tridiagonal systems solved in blocks, on every thread (the
//! slope systems of natural and clamped ends).
//!
//! The Thomas algorithm is one chain of dependent divisions: on a million rows it waits on
//! latency, not on arithmetic or memory. Here the rows are cut into blocks of `block` rows
//! with one separator row between neighbours, and every block is solved on its own with
//! both its separators moved to the right-hand side:
//!
//! ```text
//! x_i = y_i + left_i · X_{j−1} + right_i · X_j      (row i of block j)
//! ```
//!
//! (y: the block's Thomas solution; left, right: its solutions for the separators' columns,
//! which are zero but in its first and last rows.) Putting that into each separator's own row
//! leaves a tridiagonal system in the separators alone,
//!
//! ```text
//! sub·left_{p−1} X_{j−1} + (diag + sub·right_{p−1} + sup·left_{p+1}) X_j + sup·right_{p+1} X_{j+1}
//!     = r_p − sub·y_{p−1} − sup·y_{p+1}            (separator j at row p)
//! ```
//!
//! solved on one thread (a few dozen rows for a million), after which every block adds its
//! separators' share. That share, left_i and right_i, decays geometrically away from its
//! separator and underflows to exactly zero within a few thousand rows, so only the rows near
//! a block's ends change. The blocks are independent chains, so they run on every thread. The
//! cut depends only on `block`, never on the number of threads, so the answer does not
//! either; a system of at most `block` rows is one block: the Thomas algorithm itself.

use super::tridiag::{Tridiagonal, solve_tridiagonal};

/// Rows of a block for the fits: 65,536, so a million-knot fit is 16 blocks.
pub(crate) const SOLVE_BLOCK: usize = 1 << 16;

/// Memory reused between solves.
#[derive(Clone, Debug, Default)]
pub(crate) struct BlockedScratch {
    /// Thomas' modified superdiagonal, row by row.
    sup_prime: Vec<f64>,
    /// Each row's coefficient of the separator before its block, and of the one after it.
    left: Vec<f64>,
    right: Vec<f64>,
    /// The separators' system and its right-hand sides.
    separators: Tridiagonal,
    separator_rhs: Vec<f64>,
    fill: Vec<f64>,
}

/// A system's rows, built as the solve reaches them (so the data behind them is read once).
pub(crate) trait Rows: Sync {
    /// What a sweep carries from one row to the next ([`Rows::next_row`]).
    type Carry: Default;

    /// Row i's (sub, diag, sup), its right-hand sides written into `rhs`.
    fn row(&self, i: usize, rhs: &mut [f64]) -> (f64, f64, f64);

    /// [`Rows::row`] for a sweep going down the rows: `carry` is what the call for row
    /// i − 1 left (its default before a sweep's first row), so that what neighbouring rows
    /// share is formed once.
    fn next_row(&self, i: usize, carry: &mut Self::Carry, rhs: &mut [f64]) -> (f64, f64, f64);
}

/// Solves the `n`-row system `rows` with `cols` right-hand sides into `x` (row-major, `cols`
/// per row), in blocks of `block` rows on `threads` threads. The matrix must be strictly
/// diagonally dominant by rows (row 0's sub and row n − 1's sup are ignored).
pub(crate) fn solve_blocked<R: Rows>(
    n: usize,
    cols: usize,
    block: usize,
    rows: &R,
    x: &mut Vec<f64>,
    scratch: &mut BlockedScratch,
    threads: usize,
) {
    debug_assert!(n >= 1 && block >= 2);
    // Not cleared: every value read is written first (a separator's own entries in the
    // scratch rows are never read), and new memory is first touched by the blocks' sweeps,
    // on every thread.
    crate::memory::resize_for_overwrite(x, n * cols);
    for v in [
        &mut scratch.sup_prime,
        &mut scratch.left,
        &mut scratch.right,
    ] {
        crate::memory::resize_for_overwrite(v, n);
    }
    // Block j: rows starts[j] .. starts[j + 1] − 1; the last row of each but the last block is
    // its separator.
    let starts: Vec<usize> = (0..n).step_by(block).chain([n]).collect();
    let blocks = starts.len() - 1;
    let parts = blocks_of(&starts, cols, x, scratch);
    on_threads(parts, threads, |part| {
        let end = if part.rows.end == n {
            n
        } else {
            part.rows.end - 1
        };
        let (x, cp, left, right) = (part.x, part.cp, part.left, part.right);
        sweep(rows, part.rows.start..end, cols, x, cp, left, right);
    });
    if blocks == 1 {
        return;
    }
    // The separators' system.
    let seps = blocks - 1;
    let s = &mut scratch.separators;
    s.reset(seps);
    // Held apart from the scratch while the blocks borrow it again below.
    let mut separators = std::mem::take(&mut scratch.separator_rhs);
    separators.clear();
    separators.resize(seps * cols, 0.0);
    let mut rhs = vec![0.0; cols];
    for j in 0..seps {
        let p = starts[j + 1] - 1;
        let (sub, diag, sup) = rows.row(p, &mut rhs);
        let (l, r) = (&scratch.left, &scratch.right);
        s.sub[j] = sub * l[p - 1];
        s.diag[j] = diag + sub * r[p - 1] + sup * l[p + 1];
        s.sup[j] = sup * r[p + 1];
        for k in 0..cols {
            separators[j * cols + k] =
                rhs[k] - sub * x[(p - 1) * cols + k] - sup * x[(p + 1) * cols + k];
        }
    }
    let solved = solve_tridiagonal(s, &mut separators, cols, &mut scratch.fill);
    if solved.is_err() {
        // Not dominant after all (pivots lost to underflow): the whole system as one block.
        let (cp, left, right) = (
            &mut scratch.sup_prime,
            &mut scratch.left,
            &mut scratch.right,
        );
        sweep(rows, 0..n, cols, x, cp, left, right);
    } else {
        // Each block adds its separators' share; a separator row gets its value.
        let parts = blocks_of(&starts, cols, x, scratch);
        on_threads(parts, threads, |part| {
            let j = part.index;
            let before = (j > 0).then(|| &separators[(j - 1) * cols..j * cols]);
            let after = (j < seps).then(|| &separators[j * cols..(j + 1) * cols]);
            let inner = if after.is_some() {
                part.rows.len() - 1
            } else {
                part.rows.len()
            };
            // A row whose left and right are both zero keeps its value: the separators' shares
            // decay geometrically away from them and underflow to exactly zero within a few
            // thousand rows, so only the rows near the block's ends change. Left is zero
            // after its last nonzero row (a zero carries forward in both sweeps), right before
            // its first.
            let (left, right) = (&part.left[..inner], &part.right[..inner]);
            let left_end = match before {
                Some(_) => left.iter().rposition(|&l| l != 0.0).map_or(0, |i| i + 1),
                None => 0,
            };
            let right_start = match after {
                Some(_) => right.iter().position(|&r| r != 0.0).unwrap_or(inner),
                None => inner,
            };
            let changed = if left_end < right_start {
                [0..left_end, right_start..inner]
            } else {
                [0..inner, inner..inner]
            };
            for i in changed.into_iter().flatten() {
                let (l, r) = (left[i], right[i]);
                let values = &mut part.x[i * cols..(i + 1) * cols];
                for k in 0..cols {
                    let mut v = values[k];
                    if let Some(b) = before {
                        v += l * b[k];
                    }
                    if let Some(a) = after {
                        v += r * a[k];
                    }
                    values[k] = v;
                }
            }
            if let Some(a) = after {
                part.x[inner * cols..].copy_from_slice(a);
            }
        });
    }
    scratch.separator_rhs = separators;
}

/// One block's rows and its slices of the solution and the scratch rows.
struct Part<'a> {
    /// The block's number.
    index: usize,
    rows: std::ops::Range<usize>,
    x: &'a mut [f64],
    cp: &'a mut [f64],
    left: &'a mut [f64],
    right: &'a mut [f64],
}

/// The blocks that `starts` cut, each with its own slices.
fn blocks_of<'a>(
    starts: &[usize],
    cols: usize,
    x: &'a mut [f64],
    scratch: &'a mut BlockedScratch,
) -> Vec<Part<'a>> {
    let (mut x, mut cp) = (x, &mut scratch.sup_prime[..]);
    let (mut left, mut right) = (&mut scratch.left[..], &mut scratch.right[..]);
    let mut parts = Vec::with_capacity(starts.len());
    for (index, w) in starts.windows(2).enumerate() {
        let len = w[1] - w[0];
        let (xh, xt) = std::mem::take(&mut x).split_at_mut(len * cols);
        let (ch, ct) = std::mem::take(&mut cp).split_at_mut(len);
        let (lh, lt) = std::mem::take(&mut left).split_at_mut(len);
        let (rh, rt) = std::mem::take(&mut right).split_at_mut(len);
        (x, cp, left, right) = (xt, ct, lt, rt);
        parts.push(Part {
            index,
            rows: w[0]..w[1],
            x: xh,
            cp: ch,
            left: lh,
            right: rh,
        });
    }
    parts
}

/// Runs `work` on every item, the items split into contiguous groups, one per thread (the last
/// group on this one; a single item needs no other thread).
fn on_threads<T: Send>(items: Vec<T>, threads: usize, work: impl Fn(T) + Sync) {
    let n = items.len();
    let mut items = items.into_iter();
    let groups: Vec<Vec<T>> = crate::parallel::even_ranges(n, threads)
        .map(|range| items.by_ref().take(range.len()).collect())
        .collect();
    crate::parallel::fan_out(groups, |group| group.into_iter().for_each(&work));
}

/// The Thomas algorithm on rows `rows` alone, into the front of `x`, `cp`, `left` and
/// `right`: x gets the solution with the rows outside set to zero, `left` the solution for
/// the column before the block (its first row's sub moved to the right-hand side), `right`
/// the one for the column after it. The columns are swept at most four at a time
/// ([`sweep_columns`]).
fn sweep<R: Rows>(
    system: &R,
    rows: std::ops::Range<usize>,
    cols: usize,
    x: &mut [f64],
    cp: &mut [f64],
    left: &mut [f64],
    right: &mut [f64],
) {
    let mut rhs = vec![0.0; cols];
    let mut lane = Lane { x, cp, left, right };
    for first in (0..cols).step_by(4) {
        let sweep = match cols - first {
            1 => sweep_columns::<R, 1>,
            2 => sweep_columns::<R, 2>,
            3 => sweep_columns::<R, 3>,
            _ => sweep_columns::<R, 4>,
        };
        sweep(system, rows.clone(), (cols, first), &mut rhs, &mut lane);
    }
}

/// The slices a sweep fills, from its first row on.
struct Lane<'a> {
    x: &'a mut [f64],
    cp: &'a mut [f64],
    left: &'a mut [f64],
    right: &'a mut [f64],
}

/// [`sweep`] for columns `first..first + C` of x (whose rows hold `cols` values), with `rhs`
/// room for a row's `cols` right-hand sides. (Each group of columns computes the same `cp`,
/// `left` and `right`.)
///
/// Elimination is a chain of dependent divisions, the pivots p_j = diag_j − sub_j·cp_{j−1}
/// with cp_j = sup_j/p_j, and back substitution a chain of dependent multiply-adds; their
/// latency sets much of the pace. So the latest row's values are carried in registers from
/// one link to the next instead of read back from the row just stored (fit-1m: 17.3 to 15.5
/// ms with [`super::interp`]'s coefficients compiled per dimension). The pivot keeps that
/// form, whose product sub·cp is about one spacing: a chain one multiplication shorter,
/// diag − (sub_j·sup_{j−1})/p_{j−1}, multiplies two spacings, which underflows for knots
/// 1e-160 apart and overflows for knots 1e160 apart.
fn sweep_columns<R: Rows, const C: usize>(
    system: &R,
    rows: std::ops::Range<usize>,
    (cols, first): (usize, usize),
    rhs: &mut [f64],
    lane: &mut Lane<'_>,
) {
    let len = rows.len();
    // Forward elimination. Before the first row, as if a row above had x = 0, left = 1 and
    // cp = 0: the first row's sub then multiplies the separator before the block, the
    // right-hand side of that column's solve.
    let (mut above, mut left_above, mut cp_above) = ([0.0; C], 1.0, 0.0);
    let mut carry = R::Carry::default();
    for (j, i) in rows.enumerate() {
        let (sub, diag, sup) = system.next_row(i, &mut carry, rhs);
        let inv_pivot = 1.0 / (diag - sub * cp_above);
        let here = &mut lane.x[j * cols + first..][..C];
        for k in 0..C {
            above[k] = (rhs[first + k] - sub * above[k]) * inv_pivot;
            here[k] = above[k];
        }
        left_above = -sub * left_above * inv_pivot;
        lane.left[j] = left_above;
        cp_above = sup * inv_pivot;
        lane.cp[j] = cp_above;
    }
    // Back substitution.
    let last = len - 1;
    let (mut below, mut left_below, mut right_below) = (above, left_above, -cp_above);
    lane.right[last] = right_below;
    for j in (0..last).rev() {
        let c = lane.cp[j];
        let values = &mut lane.x[j * cols + first..][..C];
        for k in 0..C {
            below[k] = values[k] - c * below[k];
            values[k] = below[k];
        }
        left_below = lane.left[j] - c * left_below;
        lane.left[j] = left_below;
        right_below *= -c;
        lane.right[j] = right_below;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strictly dominant system of `n` rows (diag above |sub| + |sup| by at least 1e-3 of
    /// itself, so some rows are barely dominant) with `cols` right-hand sides.
    fn system(n: usize, cols: usize) -> (Tridiagonal, Vec<f64>) {
        let v = |i: usize, s: f64| ((i as f64 + 1.0) * s).sin();
        let sub: Vec<f64> = (0..n).map(|i| v(i, 1.3) * 3.0).collect();
        let sup: Vec<f64> = (0..n).map(|i| v(i, 2.1) * 3.0).collect();
        let diag = (0..n)
            .map(|i| {
                let off = sub[i].abs() + sup[i].abs();
                let sign = if v(i, 0.37) < 0.0 { -1.0 } else { 1.0 };
                sign * (off * (1.001 + v(i, 0.7).abs()) + 1e-3)
            })
            .collect();
        let rhs = (0..n * cols).map(|i| v(i, 0.9) * 10.0).collect();
        (Tridiagonal { sub, diag, sup }, rhs)
    }

    /// A system held whole.
    struct Held<'a>(&'a Tridiagonal, &'a [f64], usize);

    impl Rows for Held<'_> {
        type Carry = ();

        fn row(&self, i: usize, rhs: &mut [f64]) -> (f64, f64, f64) {
            let Held(a, values, cols) = *self;
            rhs.copy_from_slice(&values[i * cols..(i + 1) * cols]);
            (a.sub[i], a.diag[i], a.sup[i])
        }

        fn next_row(&self, i: usize, (): &mut (), rhs: &mut [f64]) -> (f64, f64, f64) {
            self.row(i, rhs)
        }
    }

    fn blocked(
        a: &Tridiagonal,
        rhs: &[f64],
        cols: usize,
        block: usize,
        threads: usize,
    ) -> Vec<f64> {
        let mut x = Vec::new();
        let mut scratch = BlockedScratch::default();
        let held = Held(a, rhs, cols);
        solve_blocked(a.len(), cols, block, &held, &mut x, &mut scratch, threads);
        x
    }

    /// Every cut of every size agrees with elimination with partial pivoting over the whole
    /// system (`solve_tridiagonal`, itself checked against dense elimination).
    #[test]
    fn blocks_give_the_whole_systems_solution() {
        for n in [1, 2, 3, 4, 5, 8, 9, 17, 50, 64, 65, 131] {
            for cols in 1..=6 {
                let (a, rhs) = system(n, cols);
                let mut want = rhs.clone();
                let mut whole = a.clone();
                // The first sub and last sup are not part of the system.
                whole.sub[0] = 0.0;
                whole.sup[n - 1] = 0.0;
                solve_tridiagonal(&mut whole, &mut want, cols, &mut Vec::new()).unwrap();
                let scale = want.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for block in [2, 3, 7, 16, 1000] {
                    for threads in [1, 3] {
                        let got = blocked(&a, &rhs, cols, block, threads);
                        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                            assert!(
                                (g - w).abs() <= 1e-13 * scale,
                                "n {n} cols {cols} block {block}: x[{i}] = {g}, want {w}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// Long blocks of a spline's slope system: the separators' shares underflow to zero
    /// inside each block, and the rows left as they are still give the whole system's
    /// solution.
    #[test]
    fn long_blocks_agree_where_the_separators_shares_vanish() {
        let n = 30_000;
        let v = |i: usize, s: f64| ((i as f64 + 1.0) * s).sin();
        let spacing: Vec<f64> = (0..n).map(|i| 1.0 + 99.0 * v(i, 0.37).abs()).collect();
        let sub: Vec<f64> = (0..n).map(|i| spacing[i]).collect();
        let sup: Vec<f64> = (0..n).map(|i| spacing[(i + 1) % n]).collect();
        let diag = (0..n).map(|i| 2.0 * (sub[i] + sup[i])).collect();
        let a = Tridiagonal { sub, diag, sup };
        for cols in 1..=3 {
            let rhs: Vec<f64> = (0..n * cols).map(|i| v(i, 0.9) * 10.0).collect();
            let mut want = rhs.clone();
            let mut whole = a.clone();
            (whole.sub[0], whole.sup[n - 1]) = (0.0, 0.0);
            solve_tridiagonal(&mut whole, &mut want, cols, &mut Vec::new()).unwrap();
            let (mut x, mut scratch) = (Vec::new(), BlockedScratch::default());
            solve_blocked(
                n,
                cols,
                10_000,
                &Held(&a, &rhs, cols),
                &mut x,
                &mut scratch,
                2,
            );
            // Mid-block, both shares have underflowed: those rows were left as they were.
            assert_eq!((scratch.left[15_000], scratch.right[15_000]), (0.0, 0.0));
            let scale = want.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            for (i, (g, w)) in x.iter().zip(&want).enumerate() {
                assert!(
                    (g - w).abs() <= 1e-13 * scale,
                    "cols {cols}: x[{i}] = {g}, want {w}"
                );
            }
        }
    }

    /// The cut depends on the block size alone: any number of threads gives the same bits.
    #[test]
    fn the_answer_does_not_depend_on_the_threads() {
        let (a, rhs) = system(1000, 2);
        let one = blocked(&a, &rhs, 2, 37, 1);
        for threads in [2, 5, 64] {
            assert_eq!(one, blocked(&a, &rhs, 2, 37, threads), "{threads} threads");
        }
    }
}
