//! Weighted least-squares splines (SciPy's `make_lsq_spline`, FITPACK's fitting core): the
//! coefficients c minimising
//!     sum_i (w_i (y_i - sum_j c_j B_{j,k}(x_i)))^2
//! for given knots, by Givens rotations. Each data row (k + 1 basis values from its span's
//! first column, times w_i) is rotated into an upper triangular band R (k + 1 entries a row)
//! and the right-hand sides Z = Q^T W y, one row at a time; what the rotations leave of the
//! row's right-hand side is its part of the residual. Back substitution R c = Z then gives c.
//! O(m k^2) for m data points, and no normal equations (whose condition is R's squared).
//!
//! R's diagonal is zero exactly when a coefficient is touched by no data (Schoenberg and
//! Whitney's condition fails): that fit is refused.

use crate::de_boor;

/// A least-squares fit: coefficients (len(t) - k - 1 rows of m) and the weighted residual
/// sum of squares (all columns together).
pub(crate) struct Fit {
    pub c: Vec<f64>,
    pub residual: f64,
}

/// The fit of y (len(x) rows of m, row-major) with weights w on knots t of degree k, or None
/// when R is singular (some coefficient has no data: Schoenberg-Whitney). x must lie in
/// [t_k, t_n].
pub(crate) fn fit(x: &[f64], y: &[f64], m: usize, w: &[f64], t: &[f64], k: usize) -> Option<Fit> {
    let nc = t.len() - k - 1;
    let k1 = k + 1;
    // r[row * k1 + d] = R[row, row + d].
    let mut r = vec![0.0; nc * k1];
    let mut z = vec![0.0; nc * m];
    let (mut h, mut scratch) = (vec![0.0; k1], vec![0.0; k1]);
    let mut rhs = vec![0.0; m];
    let mut residual = 0.0;
    for (i, (&xi, &wi)) in x.iter().zip(w).enumerate() {
        let l = de_boor::basis(t, k, xi, 0, &mut h, &mut scratch);
        for v in &mut h {
            *v *= wi;
        }
        for (target, &v) in rhs.iter_mut().zip(&y[i * m..(i + 1) * m]) {
            *target = wi * v;
        }
        for first in 0..k1 {
            let pivot = h[first];
            if pivot == 0.0 {
                continue;
            }
            let row = l - k + first;
            let band = &mut r[row * k1..(row + 1) * k1];
            let hypot = pivot.hypot(band[0]);
            let (cos, sin) = (band[0] / hypot, pivot / hypot);
            band[0] = hypot;
            for (target, v) in band[1..].iter_mut().zip(&mut h[first + 1..]) {
                let (old, incoming) = (*target, *v);
                *target = cos * old + sin * incoming;
                *v = cos * incoming - sin * old;
            }
            for (target, v) in z[row * m..(row + 1) * m].iter_mut().zip(&mut rhs) {
                let (old, incoming) = (*target, *v);
                *target = cos * old + sin * incoming;
                *v = cos * incoming - sin * old;
            }
        }
        residual += rhs.iter().map(|v| v * v).sum::<f64>();
    }
    for row in (0..nc).rev() {
        let diagonal = r[row * k1];
        if diagonal == 0.0 {
            return None;
        }
        for col in 0..m {
            let mut v = z[row * m + col];
            for d in 1..k1.min(nc - row) {
                v -= r[row * k1 + d] * z[(row + d) * m + col];
            }
            z[row * m + col] = v / diagonal;
        }
    }
    z.iter().all(|v| v.is_finite()).then_some(Fit { c: z, residual })
}

#[cfg(test)]
mod tests {
    use super::fit;

    /// A cubic is in the cubic spline space: least squares reproduces it exactly (its
    /// B-spline coefficients on [0]*4 + [1]*4 are its Bernstein coefficients).
    #[test]
    fn reproduces_a_cubic() {
        let x: Vec<f64> = (0..20).map(|i| f64::from(i) / 19.0).collect();
        // p(x) = x^3: Bernstein coefficients 0, 0, 0, 1.
        let y: Vec<f64> = x.iter().map(|v| v * v * v).collect();
        let w: Vec<f64> = (0..20).map(|i| 1.0 + f64::from(i % 3)).collect();
        let t = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let f = fit(&x, &y, 1, &w, &t, 3).unwrap();
        for (c, expected) in f.c.iter().zip([0.0, 0.0, 0.0, 1.0]) {
            assert!((c - expected).abs() < 1e-13, "{c}");
        }
        assert!(f.residual < 1e-26);
    }

    /// The weighted mean is the degree-0 least-squares fit, and the residual its weighted
    /// sum of squares.
    #[test]
    fn degree_zero_is_the_weighted_mean() {
        let x = [0.1, 0.2, 0.7];
        let y = [1.0, 2.0, 4.0];
        let w = [1.0, 2.0, 1.0];
        let f = fit(&x, &y, 1, &w, &[0.0, 1.0], 0).unwrap();
        // Minimise sum (w_i (y_i - c))^2: c = sum w_i^2 y_i / sum w_i^2 = (1 + 8 + 4) / 6.
        let c = 13.0 / 6.0;
        assert!((f.c[0] - c).abs() < 1e-14);
        let expected: f64 = (0..3).map(|i| (w[i] * (y[i] - c)).powi(2)).sum();
        assert!((f.residual - expected).abs() < 1e-13);
    }

    /// A coefficient no data touches is refused.
    #[test]
    fn schoenberg_whitney_is_checked() {
        let x = [0.0, 0.1, 0.2, 0.3, 0.35];
        let y = [1.0; 5];
        let w = [1.0; 5];
        let t = [0.0, 0.0, 0.5, 0.6, 1.0, 1.0];
        assert!(fit(&x, &y, 1, &w, &t, 1).is_none());
    }
}
