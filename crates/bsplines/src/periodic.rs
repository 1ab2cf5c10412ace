//! Periodic smoothing splines (FITPACK's percur and fpperi; SciPy's `make_splrep` and
//! `make_splprep` with bc_type "periodic"): the periodic spline s of degree k with period
//! xe - xb and the fewest knots FITPACK's search finds such that
//!     fp = sum_{i < m-1} w_i^2 |y_i - s(x_i)|^2 <= s_target
//! (the last point repeats the first and is left out), then, on those knots, the smoothest
//! periodic spline with fp = s_target. The steps are `fitpack`'s; what differs is the matrix.
//!
//! On knots t (n of them; t_k = xb, t_{n-k-1} = xe, the k knots past each end the period's
//! shift of those inside it) a periodic spline has n7 = n - 2k - 1 free coefficients, the
//! rest repeating them: c_{n7+j} = c_j. A data row's k + 1 B-splines from column `first` on
//! fall on columns (first + r) mod n7, so the least-squares matrix is a band whose rows near
//! the end wrap to its first columns. Rotated into a triangle (`Bordered`), only the last B
//! columns (B = k) fill: a band of width k + 1 and a dense border. The smoothing step's
//! jump rows (k + 2 wide, wrapping the same way) widen both by one.
//!
//! Every step, tolerance and tie as FITPACK's fpperi as SciPy 1.17's `_fitpack_repro` runs
//! it, so that the same data and s give the same knots and coefficients.

use crate::fitpack::{self, Data, Failure, Spline, TOLERANCE};
use crate::lsq::{self, BasisRows};

/// An upper triangular n x n matrix with its right-hand sides (d a row) whose rows are
/// banded (`width` entries from the diagonal) but for the last `border` columns, which every
/// row may reach: row j < n - border holds its band columns in `band` (clipped at the
/// border) and its border columns in `edge`; the last `border` rows are all border.
#[derive(Clone)]
struct Bordered {
    n: usize,
    width: usize,
    border: usize,
    d: usize,
    band: Vec<f64>,
    edge: Vec<f64>,
    z: Vec<f64>,
}

impl Bordered {
    /// An empty triangle of n unknowns, a band of `width`, a border of `border` columns (all n
    /// where n is fewer).
    fn new(n: usize, width: usize, border: usize, d: usize) -> Self {
        let border = border.min(n);
        Self {
            n,
            width,
            border,
            d,
            band: vec![0.0; (n - border) * width],
            edge: vec![0.0; n * border],
            z: vec![0.0; n * d],
        }
    }

    /// The rows above the border.
    fn band_rows(&self) -> usize {
        self.n - self.border
    }

    /// Entry (row, col), col >= row.
    fn entry(&self, row: usize, col: usize) -> f64 {
        let nb = self.band_rows();
        if col >= nb {
            self.edge[row * self.border + col - nb]
        } else if col - row < self.width {
            self.band[row * self.width + col - row]
        } else {
            0.0
        }
    }

    /// The same matrix and right-hand sides with a band one wider and a border one wider:
    /// the last band column joins the border (fpperi's g from a).
    fn widened(&self) -> Self {
        let mut out = Self::new(self.n, self.width + 1, self.border + 1, self.d);
        let nb = out.band_rows();
        for row in 0..self.n {
            for col in row..self.n {
                let v = self.entry(row, col);
                if col >= nb {
                    out.edge[row * out.border + col - nb] = v;
                } else if col - row < out.width {
                    out.band[row * out.width + col - row] = v;
                }
            }
        }
        out.z.clone_from(&self.z);
        out
    }

    /// The row (`window`: its entries at band columns `first`, `first` + 1, ..., zero at
    /// the border; `edge`: its entries at the border columns) with right-hand side `rhs`
    /// rotated in, as fpperi does it: down the band rows from `first`, the window sliding
    /// right a column a step, the border rotated along; then down the border rows. `rhs` is
    /// left with the row's residual.
    fn rotate_in(&mut self, first: usize, window: &mut [f64], edge: &mut [f64], rhs: &mut [f64]) {
        let (width, border, d) = (self.width, self.border, self.d);
        let nb = self.band_rows();
        for row in first..nb {
            let pivot = window[0];
            if pivot != 0.0 {
                let band = &mut self.band[row * width..(row + 1) * width];
                let (cos, sin) = lsq::givens(pivot, band);
                lsq::rotate_rows(&mut band[1..], &mut window[1..], cos, sin);
                lsq::rotate_rows(
                    &mut self.edge[row * border..(row + 1) * border],
                    edge,
                    cos,
                    sin,
                );
                lsq::rotate_rows(&mut self.z[row * d..(row + 1) * d], rhs, cos, sin);
            }
            window.rotate_left(1);
            window[width - 1] = 0.0;
            if window.iter().all(|&v| v == 0.0) {
                break;
            }
        }
        for j in 0..border {
            let pivot = edge[j];
            if pivot == 0.0 {
                continue;
            }
            let row = nb + j;
            let entries = &mut self.edge[row * border + j..(row + 1) * border];
            let (cos, sin) = lsq::givens(pivot, entries);
            lsq::rotate_rows(&mut entries[1..], &mut edge[j + 1..], cos, sin);
            lsq::rotate_rows(&mut self.z[row * d..(row + 1) * d], rhs, cos, sin);
        }
    }

    /// The sparse row (`columns[r]`: its entry `values[r]`, columns in [0, n)) rotated in:
    /// its band entries placed from `first` (the lowest band column it touches, or 0 where
    /// it wraps), its border entries summed.
    fn rotate_row(&mut self, first: usize, columns: &[(usize, f64)], rhs: &mut [f64]) {
        let nb = self.band_rows();
        // On the stack: a band of k + 2 <= 8 entries and a border of k + 1 <= 7 (k <= 6).
        let (mut window, mut edge) = ([0.0; 8], [0.0; 8]);
        for &(col, v) in columns {
            if col >= nb {
                edge[col - nb] += v;
            } else {
                window[col - first] = v;
            }
        }
        let (width, border) = (self.width, self.border);
        self.rotate_in(first, &mut window[..width], &mut edge[..border], rhs);
    }

    /// The diagonal's sum (FITPACK's start for p: n over it), border rows up, then the band.
    fn diagonal_sum(&self) -> f64 {
        let nb = self.band_rows();
        let border: f64 = (nb..self.n).rev().map(|j| self.entry(j, j)).sum();
        (0..nb).fold(border, |sum, j| sum + self.entry(j, j))
    }

    /// R c = Z solved as fpbacp does (the border rows up, then each band row less its border
    /// part, then its band part), or None where the diagonal has a zero or c is not finite.
    fn back_substitute(&self) -> Option<Vec<f64>> {
        let (n, width, border, d) = (self.n, self.width, self.border, self.d);
        let nb = self.band_rows();
        let mut c = vec![0.0; n * d];
        for row in (nb..n).rev() {
            let j = row - nb;
            let entries = &self.edge[row * border..(row + 1) * border];
            if entries[j] == 0.0 {
                return None;
            }
            for col in 0..d {
                let mut v = self.z[row * d + col];
                for l in j + 1..border {
                    v -= c[(nb + l) * d + col] * entries[l];
                }
                c[row * d + col] = v / entries[j];
            }
        }
        for row in (0..nb).rev() {
            let diagonal = self.band[row * width];
            if diagonal == 0.0 {
                return None;
            }
            for col in 0..d {
                let mut v = self.z[row * d + col];
                for l in 0..border {
                    v -= c[(nb + l) * d + col] * self.edge[row * border + l];
                }
                for off in 1..width.min(nb - row) {
                    v -= c[(row + off) * d + col] * self.band[row * width + off];
                }
                c[row * d + col] = v / diagonal;
            }
        }
        c.iter().all(|v| v.is_finite()).then_some(c)
    }
}

/// The n7 free coefficients (rows of d) extended by the k that repeat the first.
fn repeated(free: Vec<f64>, k: usize, d: usize) -> Vec<f64> {
    let n7 = free.len() / d;
    let mut c = free;
    for j in 0..k {
        let at = (j % n7) * d;
        c.extend_from_within(at..at + d);
    }
    c
}

/// The data rows of the first m - 1 points rotated into the periodic triangle on t (as
/// given: its ends are not reset here), and fp, what the rotations left over.
fn data_triangle(data: &Data<'_>, rows: &BasisRows, t: &[f64], k: usize) -> (Bordered, f64) {
    let d = data.d;
    let n7 = t.len() - 2 * k - 1;
    let mut tri = Bordered::new(n7, k + 1, k, d);
    let nb = tri.band_rows();
    let mut columns = Vec::with_capacity(k + 1);
    let mut rhs = vec![0.0; d];
    let mut fp = 0.0;
    for i in 0..data.x.len() - 1 {
        let (first, values) = rows.row(i);
        let wi = data.w[i];
        columns.clear();
        columns.extend(
            values
                .iter()
                .enumerate()
                .map(|(r, v)| ((first + r) % n7, v * wi)),
        );
        for (target, &v) in rhs.iter_mut().zip(&data.y[i * d..(i + 1) * d]) {
            *target = wi * v;
        }
        // A row whose B-splines all lie left of the border does not wrap; one that reaches
        // past it wraps to the first columns, and its band part starts at column 0.
        let start = if first < nb { first } else { 0 };
        tri.rotate_row(start, &columns, &mut rhs);
        fp += rhs.iter().map(|v| v * v).sum::<f64>();
    }
    (tri, fp)
}

/// The periodic least-squares fit on t: its coefficients (all n - k - 1 rows), each point's
/// residual and fp. The residuals are all m points', the last's too (it repeats the first),
/// as SciPy 1.17 splits them for a new knot; FITPACK's fpperi, and SciPy's later sources,
/// leave the last out, which moves a knot now and then.
fn least_squares(
    data: &Data<'_>,
    t: &[f64],
    k: usize,
) -> Result<(Vec<f64>, Vec<f64>, f64), Failure> {
    let rows = BasisRows::new(data.x, t, k);
    let (tri, fp) = data_triangle(data, &rows, t, k);
    let c = repeated(tri.back_substitute().ok_or(Failure::Singular)?, k, data.d);
    let each = fitpack::residuals(data, &rows, &c).0;
    if fp.is_nan() || each.iter().any(|v| v.is_nan()) {
        return Err(Failure::Singular);
    }
    Ok((c, each, fp))
}

/// The knots of the constant periodic spline: x_0 and x_{m-1}, each k + 1 times shifted by
/// whole periods outward.
fn constant_knots(data: &Data<'_>, k: usize) -> Vec<f64> {
    let per = data.xe - data.xb;
    let last = data.x[data.x.len() - 1];
    let mut t: Vec<f64> = (0..=k).map(|i| data.x[0] - (k - i) as f64 * per).collect();
    t.extend((0..=k).map(|i| last + i as f64 * per));
    t
}

/// SciPy's periodic interpolation knots of x (x itself, for even k each inner x moved back
/// half the step before it; k knots past each end repeating the other end's steps).
fn interpolation_knots(x: &[f64], k: usize) -> Vec<f64> {
    let m = x.len();
    let mut xc = x.to_vec();
    if k.is_multiple_of(2) {
        for i in 1..m - 1 {
            xc[i] = x[i] - (x[i] - x[i - 1]) / 2.0;
        }
    }
    let dx: Vec<f64> = xc.windows(2).map(|p| p[1] - p[0]).collect();
    let mut t = vec![0.0; m + 2 * k];
    t[k..m + k].copy_from_slice(&xc);
    for i in 0..k {
        t[k - i - 1] = t[k - i] - dx[dx.len() - 1 - i % (m - 1)];
        t[m + k + i] = t[m + k + i - 1] + dx[i % (m - 1)];
    }
    t
}

/// The knots of FITPACK's periodic search for fp <= s (fpperi's part 1).
pub fn knots(data: &Data<'_>, k: usize, s: f64, nest: usize) -> Result<Vec<f64>, Failure> {
    let acc = s * TOLERANCE;
    let m = data.x.len();
    let (nmin, nmax) = (2 * (k + 1), m + 2 * k);
    let per = data.xe - data.xb;
    let constant = constant_knots(data, k);
    let fp = least_squares(data, &constant, k)?.2;
    if fp - s < acc || nmax == nmin {
        return Ok(constant);
    }
    // One inner knot, at the middle data point.
    let mut t = vec![0.0; 2 * k + 3];
    t[k + 1] = data.x[m.div_ceil(2) - 1];
    let rules = fitpack::Rules {
        s,
        nest,
        nmax,
        least_squares: &|t| least_squares(data, t, k).map(|(_, each, fp)| (each, fp)),
        // [xb, xe] and the period's shift of the knots inside it past each end.
        ends: &|t| {
            let n = t.len();
            t[k] = data.xb;
            t[n - k - 1] = data.xe;
            for j in 1..=k {
                t[k - j] = t[n - k - j - 1] - per;
                t[n - k + j - 1] = t[k + j] + per;
            }
        },
        interpolation: &|| interpolation_knots(data.x, k),
    };
    let start = fitpack::Search {
        t,
        fpold: fp,
        nplus: 1,
    };
    Ok(fitpack::search(data.x, k, &rules, start)?.t)
}

/// The periodic smoothing spline on the knots t with fp = s (fpperi's part 2).
pub fn smooth(data: &Data<'_>, t: &[f64], k: usize, s: f64) -> Result<Spline, Failure> {
    let d = data.d;
    if t.len() == 2 * (k + 1) {
        let c = least_squares(data, t, k)?.0;
        return Ok(Spline {
            t: t.to_vec(),
            c,
            ier: 0,
        });
    }
    let n7 = t.len() - 2 * k - 1;
    let rows = BasisRows::new(data.x, t, k);
    let (base, fpinf) = data_triangle(data, &rows, t, k);
    let p0 = n7 as f64 / base.diagonal_sum();
    let fp0 = least_squares(data, &constant_knots(data, k), k)?.2;
    let wide = base.widened();
    let nb = wide.band_rows();
    let jumps = fitpack::discontinuity(t, k);
    let fit_points = Data {
        x: &data.x[..data.x.len() - 1],
        y: &data.y[..(data.x.len() - 1) * d],
        d,
        w: &data.w[..data.x.len() - 1],
        xb: data.xb,
        xe: data.xe,
    };
    let mut last: Option<Vec<f64>> = None;
    let mut columns = Vec::with_capacity(k + 2);
    let mut rhs = vec![0.0; d];
    let mut f = |p: f64| -> Result<f64, Failure> {
        let mut tri = wide.clone();
        for (row, jump) in jumps.iter().enumerate() {
            columns.clear();
            columns.extend((0..k + 2).map(|r| ((row + r) % n7, jump[r] / p)));
            rhs.fill(0.0);
            let start = if row < nb { row } else { 0 };
            tri.rotate_row(start, &columns, &mut rhs);
        }
        let c = repeated(tri.back_substitute().ok_or(Failure::Singular)?, k, d);
        let fp = fitpack::residuals(&fit_points, &rows, &c).1;
        last = Some(c);
        Ok(fp - s)
    };
    let ier = fitpack::root_rati(
        &mut f,
        p0,
        (0.0, fp0 - s),
        (f64::INFINITY, fpinf - s),
        s * TOLERANCE,
    )?;
    let c = last.ok_or(Failure::Singular)?;
    Ok(Spline {
        t: t.to_vec(),
        c,
        ier,
    })
}

#[cfg(test)]
mod tests {
    use super::{Bordered, Data, knots, smooth};

    /// Rows rotated into the bordered triangle keep the normal matrix: R^T R = A^T A (and
    /// R^T z = A^T y), for rows that do not wrap and rows that do, and the solve gives the
    /// least-squares solution (A^T A c = A^T y).
    #[test]
    fn rotations_keep_the_normal_equations() {
        let n = 9;
        let (width, border) = (3, 2);
        let mut tri = Bordered::new(n, width, border, 1);
        let mut dense: Vec<Vec<f64>> = Vec::new();
        let mut rhs_all = Vec::new();
        let mut seed = 7_u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 + 0.1
        };
        for i in 0..40 {
            // Three entries from column `first`, wrapping past n.
            let first = i % n;
            let columns: Vec<(usize, f64)> = (0..3).map(|r| ((first + r) % n, next())).collect();
            let mut row = vec![0.0; n];
            for &(c, v) in &columns {
                row[c] += v;
            }
            let y = next();
            dense.push(row);
            rhs_all.push(y);
            let start = if first < n - border { first } else { 0 };
            let mut rhs = [y];
            tri.rotate_row(start, &columns, &mut rhs);
        }
        let r = |i: usize, j: usize| if j >= i { tri.entry(i, j) } else { 0.0 };
        for a in 0..n {
            for b in 0..n {
                let normal: f64 = dense.iter().map(|row| row[a] * row[b]).sum();
                let from_r: f64 = (0..n).map(|i| r(i, a) * r(i, b)).sum();
                assert!(
                    (normal - from_r).abs() < 1e-10 * normal.abs().max(1.0),
                    "{a} {b}"
                );
            }
        }
        let c = tri.back_substitute().unwrap();
        for a in 0..n {
            let lhs: f64 = dense
                .iter()
                .map(|row| row[a] * (0..n).map(|j| row[j] * c[j]).sum::<f64>())
                .sum();
            let rhs: f64 = dense.iter().zip(&rhs_all).map(|(row, y)| row[a] * y).sum();
            assert!(
                (lhs - rhs).abs() < 1e-9 * rhs.abs().max(1.0),
                "{a}: {lhs} {rhs}"
            );
        }
    }

    /// Constant data is fitted by the constant at once (fp = 0 < s): 2k + 2 knots, every
    /// coefficient the constant.
    #[test]
    fn a_constant_needs_no_knots() {
        let x: Vec<f64> = (0..12).map(f64::from).collect();
        let y = vec![2.5; 12];
        let w = vec![1.0; 12];
        let data = Data {
            x: &x,
            y: &y,
            d: 1,
            w: &w,
            xb: 0.0,
            xe: 11.0,
        };
        let spline = smooth(&data, &knots(&data, 3, 0.1, 18).unwrap(), 3, 0.1).unwrap();
        assert_eq!(spline.t.len(), 8);
        for c in &spline.c {
            assert!((c - 2.5).abs() < 1e-12, "{c}");
        }
    }
}
