//! Tridiagonal solves in O(n), for many right-hand sides at once.
//!
//! [`solve_tridiagonal`] is Gaussian elimination with partial pivoting restricted to the band
//! (the scheme of LAPACK's `dgtsv`): stable for any nonsingular tridiagonal matrix, not only
//! diagonally dominant ones, at the cost of one extra superdiagonal of fill-in.

/// A tridiagonal system's three bands: row i reads
/// `sub[i] x[i-1] + diag[i] x[i] + sup[i] x[i+1]` (`sub[0]` and `sup[n-1]` are ignored).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Tridiagonal {
    /// Entries left of the diagonal.
    pub sub: Vec<f64>,
    /// The diagonal.
    pub diag: Vec<f64>,
    /// Entries right of the diagonal.
    pub sup: Vec<f64>,
}

impl Tridiagonal {
    /// Clears the bands and sets them to `n` zero rows, keeping their allocations.
    pub(crate) fn reset(&mut self, n: usize) {
        for band in [&mut self.sub, &mut self.diag, &mut self.sup] {
            band.clear();
            band.resize(n, 0.0);
        }
    }

    /// Number of rows.
    #[must_use]
    pub(crate) fn len(&self) -> usize {
        self.diag.len()
    }
}

/// Solves `A X = B` in place for `cols` right-hand sides: `rhs` holds B row-major (row i is
/// `rhs[i*cols..(i+1)*cols]`) and receives X. `fill` is scratch (one fill-in entry per row).
/// The bands of `a` are overwritten by the factorization.
///
/// # Errors
/// The row at which a zero pivot shows the matrix to be singular.
pub(crate) fn solve_tridiagonal(
    a: &mut Tridiagonal,
    rhs: &mut [f64],
    cols: usize,
    fill: &mut Vec<f64>,
) -> Result<(), usize> {
    let n = a.len();
    debug_assert_eq!(rhs.len(), n * cols);
    fill.clear();
    fill.resize(n, 0.0);
    let (sub, diag, sup) = (&mut a.sub, &mut a.diag, &mut a.sup);
    // Forward elimination. After step i, row i holds diag[i], sup[i] and fill[i] (the entry
    // two right of the diagonal, non-zero only after an interchange).
    for i in 0..n.saturating_sub(1) {
        let below = sub[i + 1];
        if diag[i].abs() >= below.abs() {
            if diag[i] == 0.0 {
                return Err(i);
            }
            let f = below / diag[i];
            diag[i + 1] -= f * sup[i];
            for k in 0..cols {
                rhs[(i + 1) * cols + k] -= f * rhs[i * cols + k];
            }
        } else {
            // Interchange rows i and i+1: the old row i+1 becomes the pivot row.
            let f = diag[i] / below;
            let (old_diag_next, old_sup_next) =
                (diag[i + 1], if i + 1 < n - 1 { sup[i + 1] } else { 0.0 });
            diag[i] = below;
            diag[i + 1] = sup[i] - f * old_diag_next;
            sup[i] = old_diag_next;
            fill[i] = old_sup_next;
            if i + 1 < n - 1 {
                sup[i + 1] = -f * old_sup_next;
            }
            for k in 0..cols {
                let (r0, r1) = (rhs[i * cols + k], rhs[(i + 1) * cols + k]);
                rhs[i * cols + k] = r1;
                rhs[(i + 1) * cols + k] = r0 - f * r1;
            }
        }
    }
    if diag[n - 1] == 0.0 {
        return Err(n - 1);
    }
    // Back substitution with the upper factor (diagonal, sup, fill).
    for i in (0..n).rev() {
        for k in 0..cols {
            let mut v = rhs[i * cols + k];
            if i + 1 < n {
                v -= sup[i] * rhs[(i + 1) * cols + k];
            }
            if i + 2 < n {
                v -= fill[i] * rhs[(i + 2) * cols + k];
            }
            rhs[i * cols + k] = v / diag[i];
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense Gaussian elimination with partial pivoting, the independent reference.
    #[expect(
        clippy::needless_range_loop,
        reason = "Gaussian elimination, indexed as the textbook writes it"
    )]
    fn dense_solve(mut m: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
        let n = b.len();
        for col in 0..n {
            let p = (col..n)
                .max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))
                .unwrap();
            m.swap(col, p);
            b.swap(col, p);
            for r in col + 1..n {
                let f = m[r][col] / m[col][col];
                for c in col..n {
                    m[r][c] -= f * m[col][c];
                }
                b[r] -= f * b[col];
            }
        }
        let mut x = vec![0.0; n];
        for r in (0..n).rev() {
            let s: f64 = (r + 1..n).map(|c| m[r][c] * x[c]).sum();
            x[r] = (b[r] - s) / m[r][r];
        }
        x
    }

    fn dense(a: &Tridiagonal) -> Vec<Vec<f64>> {
        let n = a.len();
        let mut m = vec![vec![0.0; n]; n];
        for i in 0..n {
            m[i][i] = a.diag[i];
            if i > 0 {
                m[i][i - 1] = a.sub[i];
            }
            if i + 1 < n {
                m[i][i + 1] = a.sup[i];
            }
        }
        m
    }

    fn sample_system(n: usize, dominant: bool) -> Tridiagonal {
        let v = |i: usize, s: f64| ((i as f64 + 1.0) * s).sin() * 3.0;
        Tridiagonal {
            sub: (0..n).map(|i| v(i, 1.3)).collect(),
            diag: (0..n)
                .map(|i| {
                    if dominant {
                        7.0 + v(i, 0.7).abs()
                    } else {
                        v(i, 0.7) * 0.1
                    }
                })
                .collect(),
            sup: (0..n).map(|i| v(i, 2.1)).collect(),
        }
    }

    #[test]
    fn tridiagonal_solve_matches_dense_elimination_even_without_dominance() {
        for (n, dominant) in [
            (1, true),
            (2, false),
            (3, false),
            (9, false),
            (40, true),
            (40, false),
        ] {
            let a = sample_system(n, dominant);
            let b: Vec<f64> = (0..2 * n).map(|i| (i as f64 * 0.37).cos()).collect();
            let mut x = b.clone();
            solve_tridiagonal(&mut a.clone(), &mut x, 2, &mut Vec::new()).unwrap();
            for k in 0..2 {
                let col: Vec<f64> = (0..n).map(|i| b[i * 2 + k]).collect();
                let expected = dense_solve(dense(&a), col);
                for i in 0..n {
                    assert!(
                        (x[i * 2 + k] - expected[i]).abs() < 1e-9 * (1.0 + expected[i].abs()),
                        "n={n} i={i}"
                    );
                }
            }
        }
    }

    #[test]
    fn singular_systems_are_reported() {
        let mut a = Tridiagonal {
            sub: vec![0.0, 0.0],
            diag: vec![0.0, 1.0],
            sup: vec![0.0, 0.0],
        };
        assert_eq!(
            solve_tridiagonal(&mut a, &mut [1.0, 1.0], 1, &mut Vec::new()),
            Err(0)
        );
    }
}
