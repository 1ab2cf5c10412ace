//! A B-spline curve of any degree k in d coordinates, owned: knots t (non-decreasing, at
//! least 2k + 2 of them), n = len(t) − k − 1 coefficients of d values each, and its
//! evaluation (`de_boor::evaluate`, SciPy's `BSpline.__call__` with `extrapolate=True`).
//! What the fits of this crate return.

use crate::InputError;
use crate::de_boor;

/// s(x) = Σ_j c_j B_{j,k}(x) on knots t, each c_j a point of `dim` coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline {
    t: Vec<f64>,
    c: Vec<f64>,
    k: usize,
    dim: usize,
}

impl BSpline {
    /// The spline of degree `k` on knots `t` with coefficients `c` (rows of `dim`, row-major).
    /// Refused unless t is finite and non-decreasing with at least 2k + 2 knots, c holds
    /// len(t) − k − 1 finite rows and dim >= 1.
    pub fn new(t: Vec<f64>, c: Vec<f64>, k: usize, dim: usize) -> Result<Self, InputError> {
        if dim == 0 {
            return Err(InputError::new("dim", "must be at least 1"));
        }
        if t.len() < 2 * k + 2 {
            return Err(InputError::new(
                "t",
                format!(
                    "degree {k} needs at least {} knots, got {}",
                    2 * k + 2,
                    t.len()
                ),
            ));
        }
        crate::check_increasing("t", &t, false)?;
        let n = t.len() - k - 1;
        if c.len() != n * dim {
            return Err(InputError::new(
                "c",
                format!(
                    "must hold {n} rows of {dim} (len(t) - k - 1), got {} values",
                    c.len()
                ),
            ));
        }
        crate::check_finite("c", &c)?;
        Ok(Self { t, c, k, dim })
    }

    /// The knots.
    pub fn knots(&self) -> &[f64] {
        &self.t
    }

    /// The coefficients, rows of `dim()`.
    pub fn coefficients(&self) -> &[f64] {
        &self.c
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.k
    }

    /// Coordinates per point.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The base interval [t_k, t_n] the data of a fit lie in.
    pub fn domain(&self) -> (f64, f64) {
        (self.t[self.k], self.t[self.t.len() - self.k - 1])
    }

    /// The `nu`-th derivative at each x, rows of `dim()`; past the base interval the end
    /// pieces continue (SciPy's `extrapolate=True`), a NaN x gives NaN. Spread over the pool
    /// for large calls.
    pub fn evaluate(&self, x: &[f64], nu: usize) -> Vec<f64> {
        let mut out = vec![0.0; x.len() * self.dim];
        self.evaluate_into(x, nu, &mut out);
        out
    }

    /// `evaluate` into `out` (len(x) · dim values), for callers that keep their buffers.
    /// Panics if `out` has another length.
    pub fn evaluate_into(&self, x: &[f64], nu: usize, out: &mut [f64]) {
        assert_eq!(out.len(), x.len() * self.dim, "out: len(x) * dim values");
        de_boor::evaluate(&self.t, &self.c, self.dim, self.k, x, nu, true, out);
    }
}

#[cfg(test)]
mod tests {
    use super::BSpline;

    #[test]
    fn a_spline_with_bad_parts_is_refused_by_name() {
        let t = vec![0.0, 0.0, 1.0, 1.0];
        assert!(BSpline::new(t.clone(), vec![1.0, 2.0], 1, 1).is_ok());
        let e = BSpline::new(t.clone(), vec![1.0], 1, 1).unwrap_err();
        assert_eq!(e.argument, "c");
        let e = BSpline::new(vec![0.0, 1.0, 0.5, 1.0], vec![1.0, 2.0], 1, 1).unwrap_err();
        assert_eq!((e.argument, e.position), ("t", Some(2)));
        let e = BSpline::new(t, vec![1.0, f64::NAN], 1, 1).unwrap_err();
        assert_eq!((e.argument, e.position), ("c", Some(1)));
    }

    #[test]
    fn a_linear_spline_is_its_chords() {
        // Degree 1 on knots [0, 0, 1, 2, 2]: the broken line through (0, 1), (1, 3), (2, 2).
        let s = BSpline::new(vec![0.0, 0.0, 1.0, 2.0, 2.0], vec![1.0, 3.0, 2.0], 1, 1).unwrap();
        assert_eq!(
            s.evaluate(&[0.0, 0.5, 1.0, 1.5, 2.0], 0),
            [1.0, 2.0, 3.0, 2.5, 2.0]
        );
        assert_eq!(s.evaluate(&[0.5, 1.5], 1), [2.0, -1.0]);
        assert_eq!(s.domain(), (0.0, 2.0));
    }
}
