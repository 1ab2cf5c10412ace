//! Banded linear systems, for the B-spline fits of any degree (`make_interp_spline`'s
//! collocation systems, whose rows hold the k + 1 basis functions that do not vanish at a
//! point): Gaussian elimination with partial pivoting inside the band, as LAPACK's gbsv.
//!
//! Row i of A holds `width` values from column `first[i]`; with `kl = max(i - first[i])` and
//! `ku = max(first[i] + width - 1 - i)`, a row swap can move an entry at most kl columns right
//! of the diagonal, so each row is kept in a window of columns [i - kl, i + kl + ku]. The cost
//! is O(n kl (kl + ku)) for the matrix and O(n (2 kl + ku) m) for m right-hand sides.

/// A X = B solved in place: `rhs` holds B (n x m, row-major) on entry and X on return; false
/// when a pivot column is zero (A singular), `rhs` then untouched.
pub fn solve(first: &[usize], values: &[f64], width: usize, rhs: &mut [f64], m: usize) -> bool {
    match Factored::new(first, values, width) {
        Some(factored) => {
            factored.solve(rhs, m);
            true
        }
        None => false,
    }
}

/// A banded matrix factored once (P A = L U, the elimination's multipliers kept where it
/// zeroed the entries), to solve for any number of right-hand sides after: the elimination's
/// row swaps and steps replayed on them, then back substitution.
#[derive(Debug)]
pub struct Factored {
    n: usize,
    kl: usize,
    ku: usize,
    /// Row i's window of columns [i − kl, i + kl + ku]: a[i · span + (col + kl − i)].
    a: Vec<f64>,
    /// The row swapped into place at each step.
    pivots: Vec<usize>,
}

impl Factored {
    /// The factored matrix, or None where a pivot column is zero or not finite (A singular).
    pub fn new(first: &[usize], values: &[f64], width: usize) -> Option<Self> {
        let n = first.len();
        debug_assert_eq!(values.len(), n * width);
        let kl = (0..n)
            .map(|i| i.saturating_sub(first[i]))
            .max()
            .unwrap_or(0);
        let ku = (0..n)
            .map(|i| (first[i] + width).saturating_sub(i + 1))
            .max()
            .unwrap_or(0);
        let span = 2 * kl + ku + 1;
        let mut a = vec![0.0; n * span];
        for i in 0..n {
            for (w, &v) in values[i * width..(i + 1) * width].iter().enumerate() {
                a[i * span + first[i] + w + kl - i] = v;
            }
        }
        let at = |i: usize, col: usize| i * span + col + kl - i;
        let mut pivots = Vec::with_capacity(n);
        for j in 0..n {
            let last_row = (j + kl).min(n - 1);
            let last_col = (j + kl + ku).min(n - 1);
            let pivot = (j..=last_row)
                .max_by(|&r, &s| a[at(r, j)].abs().total_cmp(&a[at(s, j)].abs()))
                .unwrap_or(j);
            if a[at(pivot, j)] == 0.0 || !a[at(pivot, j)].is_finite() {
                return None;
            }
            if pivot != j {
                for col in j..=last_col {
                    a.swap(at(j, col), at(pivot, col));
                }
            }
            pivots.push(pivot);
            let diagonal = a[at(j, j)];
            for r in j + 1..=last_row {
                let f = a[at(r, j)] / diagonal;
                // The multiplier takes the place of the entry it zeroes.
                a[at(r, j)] = f;
                if f == 0.0 {
                    continue;
                }
                for col in j + 1..=last_col {
                    a[at(r, col)] -= f * a[at(j, col)];
                }
            }
        }
        Some(Self {
            n,
            kl,
            ku,
            a,
            pivots,
        })
    }

    /// A X = B in place for `rhs` (n x m, row-major), row by row (each step a row of m
    /// values less a multiple of another: contiguous, and vectorised where m is large).
    pub fn solve(&self, rhs: &mut [f64], m: usize) {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        debug_assert_eq!(rhs.len(), n * m);
        let span = 2 * kl + ku + 1;
        let a = &self.a;
        let at = |i: usize, col: usize| i * span + col + kl - i;
        for (j, &pivot) in self.pivots.iter().enumerate() {
            if pivot != j {
                let (top, bottom) = rhs.split_at_mut(pivot * m);
                top[j * m..(j + 1) * m].swap_with_slice(&mut bottom[..m]);
            }
            for r in j + 1..=(j + kl).min(n - 1) {
                let f = a[at(r, j)];
                if f != 0.0 {
                    let (top, bottom) = rhs.split_at_mut(r * m);
                    let source = &top[j * m..(j + 1) * m];
                    for (target, &v) in bottom[..m].iter_mut().zip(source) {
                        *target -= f * v;
                    }
                }
            }
        }
        for i in (0..n).rev() {
            let last_col = (i + kl + ku).min(n - 1);
            let (top, below) = rhs.split_at_mut((i + 1) * m);
            let row = &mut top[i * m..];
            for col in i + 1..=last_col {
                let coefficient = a[at(i, col)];
                let source = &below[(col - i - 1) * m..(col - i) * m];
                for (target, &v) in row.iter_mut().zip(source) {
                    *target -= coefficient * v;
                }
            }
            let diagonal = a[at(i, i)];
            for target in row.iter_mut() {
                *target /= diagonal;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::solve;

    /// A tridiagonal system whose first row needs a pivot (a zero diagonal), against the
    /// solution it was made from.
    #[test]
    fn solves_a_system_that_needs_pivoting() {
        // A = [[0, 1, 0], [2, 1, 1], [0, 3, 4]], x = [1, 2, 3] (two columns: x and 2x).
        let first = [0, 0, 0];
        let values = [0.0, 1.0, 0.0, 2.0, 1.0, 1.0, 0.0, 3.0, 4.0];
        let mut rows = vec![0.0; 6];
        let x = [1.0, 2.0, 3.0];
        let dense = [[0.0, 1.0, 0.0], [2.0, 1.0, 1.0], [0.0, 3.0, 4.0]];
        for i in 0..3 {
            let b: f64 = (0..3).map(|j| dense[i][j] * x[j]).sum();
            rows[i * 2] = b;
            rows[i * 2 + 1] = 2.0 * b;
        }
        assert!(solve(&first, &values, 3, &mut rows, 2));
        for i in 0..3 {
            assert!((rows[i * 2] - x[i]).abs() < 1e-14);
            assert!((rows[i * 2 + 1] - 2.0 * x[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn a_singular_matrix_is_reported() {
        let first = [0, 0];
        let values = [1.0, 2.0, 2.0, 4.0];
        let mut rhs = vec![1.0, 2.0];
        assert!(!solve(&first, &values, 2, &mut rhs, 1));
    }
}
