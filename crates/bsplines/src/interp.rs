//! Interpolating B-splines of any degree, as SciPy's `make_interp_spline` makes them with its
//! default ends: the spline s of degree k with s(x_i) = y_i on SciPy's not-a-knot knots
//! (`not_a_knot`; k = 0 steps on [x_i, x_{i+1}), k = 1 the broken line). The collocation
//! matrix A_ij = B_{j,k}(x_i) has k + 1 nonzero entries a row (the B-splines of x_i's span),
//! so c solves one banded system (`banded`), every coordinate of y a right-hand side.

use crate::{BSpline, InputError, banded, de_boor};

/// SciPy's not-a-knot knots of x for degree k: x itself (odd k) or its midpoints (even k),
/// less the first and last (k + 1) / 2 (k / 2) of them, each end k + 1 times. For k = 3
/// the second and last-but-one x are no knots, so the first two and last two pieces are
/// one cubic each. x needs at least k + 1 points.
pub fn not_a_knot(x: &[f64], k: usize) -> Vec<f64> {
    let m = x.len();
    let inner: Vec<f64> = if k % 2 == 1 {
        let cut = k.div_ceil(2);
        x[cut..m - cut].to_vec()
    } else {
        let cut = k / 2;
        (cut..m - 1 - cut)
            .map(|i| (x[i] + x[i + 1]) / 2.0)
            .collect()
    };
    let mut t = vec![x[0]; k + 1];
    t.extend(inner);
    t.extend(std::iter::repeat_n(x[m - 1], k + 1));
    t
}

/// The knots SciPy's `make_interp_spline(x, y, k)` puts under its spline: x with x_last
/// repeated (k = 0), x with both ends doubled (k = 1), else `not_a_knot`.
pub fn interpolation_knots(x: &[f64], k: usize) -> Vec<f64> {
    match k {
        0 => x.iter().copied().chain([x[x.len() - 1]]).collect(),
        1 => [x[0]]
            .into_iter()
            .chain(x.iter().copied())
            .chain([x[x.len() - 1]])
            .collect(),
        _ => not_a_knot(x, k),
    }
}

/// The spline of degree k through (x_i, y_i): x strictly increasing with at least k + 1
/// points, y len(x) rows of `dim` (row-major), all finite.
pub fn interpolate(x: &[f64], y: &[f64], dim: usize, k: usize) -> Result<BSpline, InputError> {
    crate::check_increasing("x", x, true)?;
    if x.len() < k + 1 {
        return Err(InputError::new(
            "x",
            format!(
                "degree {k} needs at least {} points, got {}",
                k + 1,
                x.len()
            ),
        ));
    }
    if dim == 0 || y.len() != x.len() * dim {
        return Err(InputError::new(
            "y",
            format!(
                "must hold {} rows of {dim}, got {} values",
                x.len(),
                y.len()
            ),
        ));
    }
    crate::check_finite("y", y)?;
    let t = interpolation_knots(x, k);
    let width = k + 1;
    let (mut first, mut rows) = (Vec::with_capacity(x.len()), vec![0.0; x.len() * width]);
    let mut scratch = vec![0.0; width];
    for (&at, row) in x.iter().zip(rows.chunks_exact_mut(width)) {
        first.push(de_boor::basis(&t, k, at, 0, row, &mut scratch) - k);
    }
    let mut c = y.to_vec();
    if !banded::solve(&first, &rows, width, &mut c, dim) {
        return Err(InputError::new("x", "the collocation matrix is singular"));
    }
    BSpline::new(t, c, k, dim)
}

#[cfg(test)]
mod tests {
    use super::{interpolate, not_a_knot};

    #[test]
    fn not_a_knot_drops_points_next_to_the_ends() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let cubic = [0.0, 0.0, 0.0, 0.0, 2.0, 3.0, 5.0, 5.0, 5.0, 5.0];
        assert_eq!(not_a_knot(&x, 3), cubic);
        let quadratic = [0.0, 0.0, 0.0, 1.5, 2.5, 3.5, 5.0, 5.0, 5.0];
        assert_eq!(not_a_knot(&x, 2), quadratic);
    }

    #[test]
    fn the_interpolant_of_a_polynomial_of_its_degree_is_that_polynomial() {
        // Not-a-knot ends reproduce every polynomial of degree <= k exactly (up to rounding).
        for k in 1..=5 {
            let x: Vec<f64> = (0..12)
                .map(|i| f64::from(i) * 0.7 + 0.1 * f64::from(i * i % 3))
                .collect();
            let p = |v: f64| (0..=k).fold(0.0, |acc, j| acc * v + 1.0 + f64::from(j as u8) * 0.25);
            let y: Vec<f64> = x.iter().map(|&v| p(v)).collect();
            let s = interpolate(&x, &y, 1, k).unwrap();
            let at: Vec<f64> = (0..50).map(|i| f64::from(i) * 0.16).collect();
            for (&v, got) in at.iter().zip(s.evaluate(&at, 0)) {
                assert!(
                    (got - p(v)).abs() <= 1e-9 * p(v).abs().max(1.0),
                    "k {k} at {v}"
                );
            }
        }
    }

    #[test]
    fn repeated_x_is_refused_where_it_repeats() {
        let e = interpolate(&[0.0, 1.0, 1.0, 2.0], &[0.0; 4], 1, 3).unwrap_err();
        assert_eq!((e.argument, e.position), ("x", Some(2)));
    }
}
