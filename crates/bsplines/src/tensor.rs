//! A tensor-product B-spline over a grid, owned: the interpolant of gridded values (SciPy's
//! `RegularGridInterpolator` with method "cubic", "quintic", ... or `make_ndbspl`), each axis
//! on its not-a-knot knots, and its evaluation at scattered points (`grid::Tensor`).

use crate::{InputError, grid, interp};

/// s(x) = Σ c[i_0, .., i_{d-1}] Π_a B_{i_a, k}(x_a), one degree k on every axis, c of shape
/// (n_0, .., n_{d-1}, dim) in C order.
#[derive(Clone, Debug, PartialEq)]
pub struct TensorSpline {
    t: Vec<Vec<f64>>,
    k: usize,
    c: Vec<f64>,
    dim: usize,
}

impl TensorSpline {
    /// The spline of degree k on every axis through `values` at the grid's nodes: `nodes[a]`
    /// strictly increasing with at least k + 1 nodes, `values` of shape (n_0, .., n_{d-1},
    /// dim) in C order, finite.
    pub fn interpolate(
        nodes: &[&[f64]],
        values: &[f64],
        dim: usize,
        k: usize,
    ) -> Result<Self, InputError> {
        if nodes.is_empty() {
            return Err(InputError::new("nodes", "a grid needs at least one axis"));
        }
        for (a, x) in nodes.iter().enumerate() {
            crate::check_increasing("nodes", x, true).map_err(|e| e.in_series(a))?;
            if x.len() < k + 1 {
                return Err(InputError::new(
                    "nodes",
                    format!("degree {k} needs at least {} nodes, got {}", k + 1, x.len()),
                )
                .in_series(a));
            }
        }
        let count: usize = nodes.iter().map(|x| x.len()).product::<usize>() * dim;
        if dim == 0 || values.len() != count {
            return Err(InputError::new(
                "values",
                format!(
                    "must hold {count} values (the grid's nodes times dim), got {}",
                    values.len()
                ),
            ));
        }
        crate::check_finite("values", values)?;
        let t: Vec<Vec<f64>> = nodes
            .iter()
            .map(|x| interp::interpolation_knots(x, k))
            .collect();
        let knots: Vec<&[f64]> = t.iter().map(Vec::as_slice).collect();
        let mut c = values.to_vec();
        grid::fit(nodes, &knots, &vec![k; nodes.len()], &mut c, dim).map_err(|a| {
            InputError::new("nodes", "the collocation matrix is singular").in_series(a)
        })?;
        Ok(Self { t, k, c, dim })
    }

    /// Each axis' knots.
    pub fn knots(&self) -> &[Vec<f64>] {
        &self.t
    }

    /// The coefficients, (n_0, .., n_{d-1}, dim) in C order.
    pub fn coefficients(&self) -> &[f64] {
        &self.c
    }

    /// The values at `points` (rows of d coordinates), rows of `dim`; outside the grid the
    /// end pieces continue, a NaN coordinate gives NaN.
    pub fn evaluate(&self, points: &[f64]) -> Vec<f64> {
        let d = self.t.len();
        let tensor = grid::Tensor {
            t: self.t.iter().map(Vec::as_slice).collect(),
            k: vec![self.k; d],
            c: &self.c,
            m: self.dim,
        };
        let mut out = vec![0.0; points.len() / d * self.dim];
        tensor.evaluate(points, &vec![0; d], true, &mut out);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::TensorSpline;

    #[test]
    fn a_bicubic_interpolant_reproduces_a_bicubic() {
        let x: Vec<f64> = (0..7).map(|i| f64::from(i) * 0.5).collect();
        let y: Vec<f64> = (0..6).map(|i| f64::from(i * i) * 0.2).collect();
        let f = |a: f64, b: f64| a * a * a - 2.0 * a * b * b + b * b * b + 1.0;
        let values: Vec<f64> = x
            .iter()
            .flat_map(|&a| y.iter().map(move |&b| f(a, b)))
            .collect();
        let s = TensorSpline::interpolate(&[&x, &y], &values, 1, 3).unwrap();
        let points = [0.3, 0.7, 2.9, 4.1, 1.25, 2.5];
        for (p, got) in points.chunks(2).zip(s.evaluate(&points)) {
            assert!((got - f(p[0], p[1])).abs() < 1e-10, "{p:?}");
        }
    }
}
