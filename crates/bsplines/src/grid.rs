//! Gridded data: tensor-product B-splines (SciPy's `NdBSpline`, and through it
//! `RegularGridInterpolator`'s "linear", "slinear", "cubic" and "quintic") and the gridded
//! PCHIP (`RegularGridInterpolator`'s "pchip"), evaluated at scattered points on every thread.
//!
//! **Tensor product.** With c of shape (n_0, .., n_{d-1}, m) and the knots t_a, degree k_a of
//! each axis,
//!     s(x) = Σ_{i_0 .. i_{d-1}} c[i_0, .., i_{d-1}] Π_a B^(nu_a)_{i_a, k_a}(x_a),
//! where only the k_a + 1 B-splines of x_a's knot span l_a do not vanish (de Boor's recurrence,
//! `de_boor::basis`): the sum runs over the (k_a + 1) products of those, contracted one axis
//! at a time from the first, the last axis' k + 1 coefficients contiguous in memory. Outside
//! [t_k, t_n] of an axis the end span's polynomials continue (`extrapolate`), or the value is
//! NaN; a NaN coordinate gives NaN.
//!
//! **PCHIP on a grid.** SciPy folds one axis at a time, last axis first: PCHIP along the last
//! axis through every grid line, then along the one before through those values, ... . PCHIP is
//! local: its value on [x_i, x_{i+1}] reads the slopes at x_i and x_{i+1}, which read the points
//! i − 1 .. i + 2 (at an end, the three end points). So each point folds only a window of at most
//! 4 nodes per axis (4^d values), with the same slopes as on the whole line.

use rayon::prelude::*;

use crate::tensor_values::{self, Axis};
use crate::{banded, de_boor};

/// Points per task when the work is spread over the pool.
const CHUNK: usize = 2048;

/// A tensor-product B-spline: per axis its knots and degree; the coefficients (n_0, ..,
/// n_{d-1}, m) in C order.
#[derive(Debug)]
pub struct Tensor<'a> {
    /// Each axis' knots.
    pub t: Vec<&'a [f64]>,
    /// Each axis' degree.
    pub k: Vec<usize>,
    /// The coefficients, (n_0, .., n_{d-1}, m) in C order.
    pub c: &'a [f64],
    /// Values per coefficient.
    pub m: usize,
}

impl Tensor<'_> {
    /// Coefficients per axis (n_a = len(t_a) − k_a − 1).
    fn counts(&self) -> Vec<usize> {
        self.t
            .iter()
            .zip(&self.k)
            .map(|(t, k)| t.len() - k - 1)
            .collect()
    }

    /// Derivative `nu` (one order per axis) at each point of `xi` (rows of d coordinates) into
    /// `out` (a row of m per point).
    pub fn evaluate(&self, xi: &[f64], nu: &[usize], extrapolate: bool, out: &mut [f64]) {
        let (d, m) = (self.t.len(), self.m);
        if m == 0 || d == 0 {
            return;
        }
        let counts = self.counts();
        // Strides in values: axis a steps over the coefficients of every later axis.
        let mut strides = vec![m; d];
        for a in (0..d - 1).rev() {
            strides[a] = strides[a + 1] * counts[a + 1];
        }
        let k = self.k[0];
        if d <= 3 && k <= 5 && self.k.iter().all(|&ka| ka == k) && nu.iter().all(|&o| o == 0) {
            let axes: Vec<Axis<'_>> = self.t.iter().map(|t| Axis::new(t, k)).collect();
            let values = |xi: &[f64], out: &mut [f64]| match k {
                0 => tensor_values::evaluate::<1>(&axes, self.c, &strides, m, xi, extrapolate, out),
                1 => tensor_values::evaluate::<2>(&axes, self.c, &strides, m, xi, extrapolate, out),
                2 => tensor_values::evaluate::<3>(&axes, self.c, &strides, m, xi, extrapolate, out),
                3 => tensor_values::evaluate::<4>(&axes, self.c, &strides, m, xi, extrapolate, out),
                4 => tensor_values::evaluate::<5>(&axes, self.c, &strides, m, xi, extrapolate, out),
                _ => tensor_values::evaluate::<6>(&axes, self.c, &strides, m, xi, extrapolate, out),
            };
            return on_pool(xi, d, out, m, values);
        }
        let run = |xi: &[f64], out: &mut [f64]| {
            let mut weights: Vec<Vec<f64>> = self.k.iter().map(|&k| vec![0.0; k + 1]).collect();
            let mut scratch = vec![0.0; self.k.iter().max().map_or(1, |k| k + 1)];
            let mut first = vec![0usize; d];
            for (row, x) in out.chunks_exact_mut(m).zip(xi.chunks_exact(d)) {
                let mut inside = true;
                for a in 0..d {
                    let (t, k) = (self.t[a], self.k[a]);
                    let n = counts[a];
                    let within = (t[k]..=t[n]).contains(&x[a]);
                    if x[a].is_nan() || !(extrapolate || within) {
                        inside = false;
                        break;
                    }
                    let l = de_boor::basis(t, k, x[a], nu[a], &mut weights[a], &mut scratch);
                    first[a] = (l - k) * strides[a];
                }
                if !inside {
                    row.fill(f64::NAN);
                    continue;
                }
                row.fill(0.0);
                let start: usize = first.iter().sum();
                accumulate(self.c, &weights, &strides, start, 1.0, row);
            }
        };
        on_pool(xi, d, out, m, run);
    }
}

/// `run(xi, out)` on the whole call, or in chunks over the pool when it is large.
fn on_pool(
    xi: &[f64],
    d: usize,
    out: &mut [f64],
    m: usize,
    run: impl Fn(&[f64], &mut [f64]) + Sync,
) {
    if xi.len() / d <= CHUNK {
        run(xi, out);
    } else {
        out.par_chunks_mut(CHUNK * m)
            .zip(xi.par_chunks(CHUNK * d))
            .for_each(|(out, xi)| run(xi, out));
    }
}

/// row += weight · Σ over the remaining axes' spans of their weights' product times c, from
/// `offset` (axis 0 of `weights` is the next axis to contract).
fn accumulate(
    c: &[f64],
    weights: &[Vec<f64>],
    strides: &[usize],
    offset: usize,
    weight: f64,
    row: &mut [f64],
) {
    let m = row.len();
    if let [last] = weights {
        for (r, &w) in last.iter().enumerate() {
            let w = w * weight;
            if w == 0.0 {
                continue;
            }
            let at = offset + r * strides[0];
            for (o, &cj) in row.iter_mut().zip(&c[at..at + m]) {
                *o += w * cj;
            }
        }
        return;
    }
    for (r, &w) in weights[0].iter().enumerate() {
        if w != 0.0 {
            let at = offset + r * strides[0];
            accumulate(c, &weights[1..], &strides[1..], at, weight * w, row);
        }
    }
}

/// Gridded data for the PCHIP fold: the axes (strictly increasing) and the values (n_0, ..,
/// n_{d-1}, m) in C order.
#[derive(Debug)]
pub struct Grid<'a> {
    /// Each axis' nodes, strictly increasing.
    pub axes: Vec<&'a [f64]>,
    /// The values, (n_0, .., n_{d-1}, m) in C order.
    pub values: &'a [f64],
    /// Values per node.
    pub m: usize,
}

impl Grid<'_> {
    /// SciPy's gridded PCHIP (last axis first, see the module's documentation) at each point of
    /// `xi` into `out` (a row of m per point). Past an axis' ends its end piece continues.
    pub fn pchip(&self, xi: &[f64], out: &mut [f64]) {
        let (d, m) = (self.axes.len(), self.m);
        if m == 0 || d == 0 {
            return;
        }
        let mut strides = vec![m; d];
        for a in (0..d - 1).rev() {
            strides[a] = strides[a + 1] * self.axes[a + 1].len();
        }
        let run = |xi: &[f64], out: &mut [f64]| {
            let mut fold = Fold::new(d, m);
            for (row, x) in out.chunks_exact_mut(m).zip(xi.chunks_exact(d)) {
                if x.iter().any(|v| v.is_nan()) {
                    row.fill(f64::NAN);
                    continue;
                }
                fold.point(self, &strides, x, row);
            }
        };
        on_pool(xi, d, out, m, run);
    }
}

/// One point's windows and the memory its fold works in (reused from point to point).
struct Fold {
    /// Per axis: the first node of the window and its width (2 to 4 nodes).
    window: Vec<(usize, usize)>,
    /// The window's values, C order, m per node; folded in place, one axis at a time.
    block: Vec<f64>,
    /// One line of the window (up to 4 nodes of m values) and its slopes.
    line: Vec<f64>,
    slopes: Vec<f64>,
    /// Per axis: the interval of x within the window, and a node index while gathering.
    intervals: Vec<usize>,
    index: Vec<usize>,
}

impl Fold {
    fn new(d: usize, m: usize) -> Self {
        Self {
            window: vec![(0, 0); d],
            block: vec![0.0; 4usize.pow(d as u32) * m],
            line: vec![0.0; 4 * m],
            slopes: vec![0.0; 4 * m],
            intervals: vec![0; d],
            index: vec![0; d],
        }
    }

    fn point(&mut self, grid: &Grid<'_>, strides: &[usize], x: &[f64], row: &mut [f64]) {
        let (d, m) = (grid.axes.len(), grid.m);
        for (a, axis) in grid.axes.iter().enumerate() {
            let n = axis.len();
            // The interval holding x (the end ones past the ends), and its window.
            let i = axis
                .partition_point(|&v| v <= x[a])
                .saturating_sub(1)
                .min(n - 2);
            let lo = i.saturating_sub(1);
            let hi = (i + 2).min(n - 1);
            self.window[a] = (lo, hi - lo + 1);
            self.intervals[a] = i - lo;
        }
        // Gather the window: node (j_0, .., j_{d-1}) of the window at its C-order place.
        let size: usize = self.window.iter().map(|w| w.1).product();
        for cell in 0..size {
            let mut rest = cell;
            for a in (0..d).rev() {
                self.index[a] = rest % self.window[a].1;
                rest /= self.window[a].1;
            }
            let at: usize = (0..d)
                .map(|a| (self.window[a].0 + self.index[a]) * strides[a])
                .sum();
            self.block[cell * m..(cell + 1) * m].copy_from_slice(&grid.values[at..at + m]);
        }
        // Fold the last axis, then the one before, ...: each line of the window along axis a
        // becomes its PCHIP value at x_a, written in place at the line's index.
        let mut lines = size;
        for a in (0..d).rev() {
            let (lo, width) = self.window[a];
            lines /= width;
            let nodes = &grid.axes[a][lo..lo + width];
            for line in 0..lines {
                let values = &self.block[line * width * m..(line + 1) * width * m];
                self.line[..width * m].copy_from_slice(values);
                crate::pchip::pchip_slopes_into(
                    nodes,
                    &self.line[..width * m],
                    m,
                    &mut self.slopes[..width * m],
                );
                let i = self.intervals[a];
                let (h, s) = (nodes[i + 1] - nodes[i], x[a] - nodes[i]);
                for j in 0..m {
                    let (y0, y1) = (self.line[i * m + j], self.line[(i + 1) * m + j]);
                    let (d0, d1) = (self.slopes[i * m + j], self.slopes[(i + 1) * m + j]);
                    let secant = (y1 - y0) / h;
                    // The piece in powers of s = x − x_i, as SciPy's PPoly holds it.
                    let c3 = (d0 + d1 - 2.0 * secant) / (h * h);
                    let c2 = (3.0 * secant - 2.0 * d0 - d1) / h;
                    self.block[line * m + j] = ((c3 * s + c2) * s + d0) * s + y0;
                }
            }
        }
        row.copy_from_slice(&self.block[..m]);
    }
}

/// The interpolating tensor B-spline's coefficients from its values at the grid's nodes, in
/// place: `values` (n_0, .., n_{d-1}, m) in C order becomes c. The grid's collocation matrix is
/// the Kronecker product of the axes' (row j of axis a: the k_a + 1 B-splines of knots t_a
/// that do not vanish at node j), so c is one banded solve per axis: along axis a the values
/// are (pre, n_a, post) blocks, each n_a x post right-hand sides of that axis' system, solved
/// together as one (n_a, pre · post) system (factored once). Err(a) where axis a's system is
/// singular.
pub fn fit(
    nodes: &[&[f64]],
    knots: &[&[f64]],
    k: &[usize],
    values: &mut [f64],
    m: usize,
) -> Result<(), usize> {
    let d = nodes.len();
    let counts: Vec<usize> = nodes.iter().map(|x| x.len()).collect();
    for a in 0..d {
        let (t, ka, n) = (knots[a], k[a], counts[a]);
        let mut first = Vec::with_capacity(n);
        let mut rows = vec![0.0; n * (ka + 1)];
        let mut scratch = vec![0.0; ka + 1];
        for (j, &x) in nodes[a].iter().enumerate() {
            let row = &mut rows[j * (ka + 1)..(j + 1) * (ka + 1)];
            first.push(de_boor::basis(t, ka, x, 0, row, &mut scratch) - ka);
        }
        let post: usize = counts[a + 1..].iter().product::<usize>() * m;
        if post == 0 || n == 0 {
            continue;
        }
        let factored = banded::Factored::new(&first, &rows, ka + 1).ok_or(a)?;
        let pre = values.len() / (n * post);
        if pre == 1 {
            factored.solve(values, post);
            continue;
        }
        // The (pre, n, post) blocks gathered into one (n, pre · post) system, so that the
        // elimination runs along rows of many right-hand sides (a last axis would otherwise
        // be `pre` solves of one column each), and scattered back.
        let width = pre * post;
        let mut wide = vec![0.0; values.len()];
        for (p, block) in values.chunks_exact(n * post).enumerate() {
            for (j, line) in block.chunks_exact(post).enumerate() {
                wide[j * width + p * post..j * width + (p + 1) * post].copy_from_slice(line);
            }
        }
        factored.solve(&mut wide, width);
        for (p, block) in values.chunks_exact_mut(n * post).enumerate() {
            for (j, line) in block.chunks_exact_mut(post).enumerate() {
                line.copy_from_slice(&wide[j * width + p * post..j * width + (p + 1) * post]);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{Grid, Tensor, fit};

    /// The separable fit interpolates: the fitted bicubic (not-a-knot knots on uneven axes)
    /// gives back every node's two values.
    #[test]
    fn the_fit_interpolates_the_nodes() {
        let x: [f64; 6] = [0.0, 0.1, 1.0, 1.5, 4.0, 4.2];
        let y: [f64; 5] = [-1.0, 0.0, 3.0, 3.5, 9.0];
        // Not-a-knot: the ends four times, the nodes but the second and the next to last.
        let tx = [0.0, 0.0, 0.0, 0.0, 1.0, 1.5, 4.2, 4.2, 4.2, 4.2];
        let ty = [-1.0, -1.0, -1.0, -1.0, 3.0, 9.0, 9.0, 9.0, 9.0];
        let values: Vec<f64> = x
            .iter()
            .flat_map(|&a| y.iter().flat_map(move |&b| [(a * b).sin(), a - 2.0 * b]))
            .collect();
        let mut c = values.clone();
        fit(&[&x, &y], &[&tx, &ty], &[3, 3], &mut c, 2).expect("not singular");
        let tensor = Tensor {
            t: vec![&tx, &ty],
            k: vec![3, 3],
            c: &c,
            m: 2,
        };
        let nodes: Vec<f64> = x
            .iter()
            .flat_map(|&a| y.iter().flat_map(move |&b| [a, b]))
            .collect();
        let mut out = vec![0.0; values.len()];
        tensor.evaluate(&nodes, &[0, 0], true, &mut out);
        for (o, v) in out.iter().zip(&values) {
            assert!((o - v).abs() < 1e-12, "{o} against {v}");
        }
    }

    /// The bilinear B-spline on knots (0 0 1 2 2) x (0 0 1 1) with coefficients a + 10 b at
    /// the nodes is x + 10 y: values, a mixed derivative, NaN outside without extrapolation.
    #[test]
    fn a_plane_in_the_bilinear_basis() {
        let (tx, ty) = ([0.0, 0.0, 1.0, 2.0, 2.0], [0.0, 0.0, 1.0, 1.0]);
        let c: Vec<f64> = (0..3)
            .flat_map(|a| (0..2).map(move |b| f64::from(a) + 10.0 * f64::from(b)))
            .collect();
        let tensor = Tensor {
            t: vec![&tx, &ty],
            k: vec![1, 1],
            c: &c,
            m: 1,
        };
        let xi = [0.5, 0.25, 1.5, 1.0, 3.0, 0.5];
        let mut out = [0.0; 3];
        tensor.evaluate(&xi, &[0, 0], true, &mut out);
        assert_eq!(out, [3.0, 11.5, 8.0]);
        tensor.evaluate(&xi, &[0, 0], false, &mut out);
        assert_eq!(&out[..2], &[3.0, 11.5]);
        assert!(out[2].is_nan());
        tensor.evaluate(&xi, &[1, 0], true, &mut out);
        assert_eq!(out, [1.0, 1.0, 1.0]);
        tensor.evaluate(&xi, &[0, 1], true, &mut out);
        assert_eq!(out, [10.0, 10.0, 10.0]);
        tensor.evaluate(&xi, &[1, 1], true, &mut out);
        assert_eq!(out, [0.0, 0.0, 0.0]);
    }

    /// A monotone cubic along each axis is reproduced where PCHIP's slopes are exact: on data
    /// linear in each axis, the fold gives the plane everywhere (inside and past the ends).
    #[test]
    fn the_pchip_fold_keeps_a_plane() {
        let (ax, ay) = ([0.0, 1.0, 3.0, 4.0, 7.0], [0.0, 0.5, 1.0, 2.0]);
        let values: Vec<f64> = ax
            .iter()
            .flat_map(|&x| ay.iter().map(move |&y| 2.0 * x + 3.0 * y))
            .collect();
        let grid = Grid {
            axes: vec![&ax, &ay],
            values: &values,
            m: 1,
        };
        let xi = [0.0, 0.0, 2.5, 0.7, 6.9, 1.9, 8.0, -1.0];
        let mut out = [0.0; 4];
        grid.pchip(&xi, &mut out);
        for (o, p) in out.iter().zip(xi.chunks(2)) {
            assert!(
                (o - (2.0 * p[0] + 3.0 * p[1])).abs() < 1e-12,
                "{o} at {p:?}"
            );
        }
    }
}
