//! Weighted least-squares splines (SciPy's `make_lsq_spline`, FITPACK's fitting core): the
//! coefficients c minimising
//!     sum_i (w_i (y_i - sum_j c_j B_{j,k}(x_i)))^2
//! for given knots, by Givens rotations. Each data row (k + 1 basis values from its span's
//! first column, times w_i) is rotated into an upper triangular band R and the right-hand
//! sides Z = Q^T W y, one row at a time; what the rotations leave of the row's right-hand side
//! is its part of the residual. Back substitution R c = Z then gives c. O(m k^2) for m data
//! points, and no normal equations (whose condition is R's squared).
//!
//! R's diagonal is zero exactly when a coefficient is touched by no data (Schoenberg and
//! Whitney's condition fails): that fit is refused.

use crate::InputError;
use crate::de_boor;

/// An upper triangular band R (`width` entries a row: R[row, row + d] at
/// `r[row * width + d]`) with its right-hand sides Z (m a row), built by rotating rows in.
#[derive(Clone, Debug)]
pub struct Triangle {
    /// Entries a row of R.
    pub width: usize,
    /// Right-hand sides a row.
    pub m: usize,
    /// R, `width` a row.
    pub r: Vec<f64>,
    /// Z, m a row.
    pub z: Vec<f64>,
}

impl Triangle {
    /// R and Z of `rows` rows, zero.
    pub fn new(rows: usize, width: usize, m: usize) -> Self {
        Self {
            width,
            m,
            r: vec![0.0; rows * width],
            z: vec![0.0; rows * m],
        }
    }

    /// The row h (its entries from column `first`; h.len() <= width) with right-hand side
    /// `rhs` rotated in, as FITPACK does it (fpgivs and fprota): the row is a window of
    /// `width` columns sliding right one column a step, so that what a rotation brings in
    /// from R's row beyond the row's own entries is rotated on into the rows below. `rhs` is
    /// left with what the rotations did not take: the row's residual.
    pub fn rotate_in(&mut self, first: usize, h: &[f64], rhs: &mut [f64]) {
        // The window in registers for the widths of degrees 0 to 6 (k + 1 and k + 2).
        match self.width {
            1 => self.rotate_fixed::<1>(first, h, rhs),
            2 => self.rotate_fixed::<2>(first, h, rhs),
            3 => self.rotate_fixed::<3>(first, h, rhs),
            4 => self.rotate_fixed::<4>(first, h, rhs),
            5 => self.rotate_fixed::<5>(first, h, rhs),
            6 => self.rotate_fixed::<6>(first, h, rhs),
            7 => self.rotate_fixed::<7>(first, h, rhs),
            8 => self.rotate_fixed::<8>(first, h, rhs),
            _ => self.rotate_any(first, h, rhs),
        }
    }

    /// `rotate_in` with the window a fixed-size array.
    fn rotate_fixed<const W: usize>(&mut self, first: usize, h: &[f64], rhs: &mut [f64]) {
        let m = self.m;
        let rows = self.r.len() / W;
        let mut window = [0.0; W];
        window[..h.len()].copy_from_slice(h);
        for row in first..rows {
            let pivot = window[0];
            if pivot != 0.0 {
                let band: &mut [f64; W] = (&mut self.r[row * W..(row + 1) * W])
                    .try_into()
                    .expect("a row of the band");
                let (cos, sin) = givens(pivot, band);
                for j in 1..W {
                    let (old, incoming) = (band[j], window[j]);
                    band[j] = cos * old + sin * incoming;
                    window[j] = cos * incoming - sin * old;
                }
                rotate_rows(&mut self.z[row * m..(row + 1) * m], rhs, cos, sin);
            }
            let mut rest = false;
            for j in 1..W {
                window[j - 1] = window[j];
                rest |= window[j] != 0.0;
            }
            window[W - 1] = 0.0;
            if !rest {
                break;
            }
        }
    }

    /// `rotate_in` for any width.
    fn rotate_any(&mut self, first: usize, h: &[f64], rhs: &mut [f64]) {
        let (width, m) = (self.width, self.m);
        let rows = self.r.len() / width;
        let mut window = h.to_vec();
        window.resize(width, 0.0);
        for row in first..rows {
            let pivot = window[0];
            if pivot != 0.0 {
                let band = &mut self.r[row * width..(row + 1) * width];
                let (cos, sin) = givens(pivot, band);
                for (target, v) in band[1..].iter_mut().zip(&mut window[1..]) {
                    let (old, incoming) = (*target, *v);
                    *target = cos * old + sin * incoming;
                    *v = cos * incoming - sin * old;
                }
                rotate_rows(&mut self.z[row * m..(row + 1) * m], rhs, cos, sin);
            }
            window.rotate_left(1);
            window[width - 1] = 0.0;
            if window.iter().all(|&v| v == 0.0) {
                break;
            }
        }
    }

    /// Data row i (its basis values and y, y len(w) rows of m, times w_i) rotated in, `h`
    /// (k + 1) and `rhs` (m) the scratch for it; returns its residual squared.
    fn rotate_data_row(
        &mut self,
        rows: &BasisRows,
        i: usize,
        y: &[f64],
        w: &[f64],
        h: &mut [f64],
        rhs: &mut [f64],
    ) -> f64 {
        let m = self.m;
        let (first, values) = rows.row(i);
        for (target, v) in h.iter_mut().zip(values) {
            *target = w[i] * v;
        }
        for (target, &v) in rhs.iter_mut().zip(&y[i * m..(i + 1) * m]) {
            *target = w[i] * v;
        }
        self.rotate_in(first, h, rhs);
        rhs.iter().map(|v| v * v).sum()
    }

    /// A block of p rows that share their first column (`columns`: the block column by
    /// column, p values each, width of them; `rhs`: m columns of p) taken into R and Z by
    /// one Householder reflection a column: for column j (R's row `first` + j), with
    /// alpha = R_jj and sigma the block column's sum of squares, the reflection
    ///     H = I - 2 v v^T / v^T v,   v = (alpha - beta, block column j),
    ///     beta = sqrt(alpha^2 + sigma)   (R_jj stays positive; v_0 by Parlett's form),
    /// maps (R_jj, block column) to (beta, 0), and the block's later columns and right-hand
    /// sides with it. The rows are sorted, so R's rows have nothing past the block's last
    /// column and the reflections fill nothing in. Returns the block's residual: what the
    /// reflections left of its right-hand sides, squared.
    pub fn absorb(&mut self, first: usize, columns: &mut [f64], rhs: &mut [f64], p: usize) -> f64 {
        let (width, m) = (self.width, self.m);
        let rows = self.r.len() / width;
        for j in 0..width.min(rows - first) {
            let (done, rest) = columns.split_at_mut((j + 1) * p);
            let h = &done[j * p..];
            let sigma: f64 = h.iter().map(|v| v * v).sum();
            if sigma == 0.0 {
                continue;
            }
            let row = first + j;
            let alpha = self.r[row * width];
            let beta = (alpha * alpha + sigma).sqrt();
            let v0 = if alpha <= 0.0 {
                alpha - beta
            } else {
                -sigma / (alpha + beta)
            };
            let scale = 2.0 / (v0 * v0 + sigma);
            self.r[row * width] = beta;
            for d in 1..width - j {
                let target = &mut rest[(d - 1) * p..d * p];
                let entry = &mut self.r[row * width + d];
                reflect(v0, h, scale, entry, target);
            }
            for c in 0..m {
                let target = &mut rhs[c * p..(c + 1) * p];
                reflect(v0, h, scale, &mut self.z[row * m + c], target);
            }
        }
        rhs.iter().map(|v| v * v).sum()
    }

    /// |Z - R c|^2 over every row and column: with the rotated-out residual of the rows
    /// that made R, the weighted residual sum of squares of any coefficients c on these
    /// knots (|W (y - B c)|^2 = |Q^T W y - R c|^2, Q orthogonal), in O(rows k m).
    pub fn misfit(&self, c: &[f64]) -> f64 {
        let (width, m) = (self.width, self.m);
        let rows = self.r.len() / width;
        let mut total = 0.0;
        for row in 0..rows {
            for col in 0..m {
                let mut v = self.z[row * m + col];
                for d in 0..width.min(rows - row) {
                    v -= self.r[row * width + d] * c[(row + d) * m + col];
                }
                total += v * v;
            }
        }
        total
    }

    /// R c = Z solved (rows x m), or None where R's diagonal has a zero or c is not finite.
    pub fn back_substitute(&self) -> Option<Vec<f64>> {
        let (width, m) = (self.width, self.m);
        let rows = self.r.len() / width;
        let mut c = self.z.clone();
        for row in (0..rows).rev() {
            let diagonal = self.r[row * width];
            if diagonal == 0.0 {
                return None;
            }
            for col in 0..m {
                let mut v = c[row * m + col];
                for d in 1..width.min(rows - row) {
                    v -= self.r[row * width + d] * c[(row + d) * m + col];
                }
                c[row * m + col] = v / diagonal;
            }
        }
        c.iter().all(|v| v.is_finite()).then_some(c)
    }
}

/// FITPACK's fpgivs: the rotation (cos, sin) that zeroes `pivot` against the band row's
/// diagonal, which becomes their root sum of squares: unscaled where the squares' sum is a
/// normal number (the rows are weights times B-splines; one division), scaled by the larger
/// where it under- or overflows (a leftover of 1e-163 meeting an untouched row's zero).
#[inline(always)]
pub fn givens(pivot: f64, band: &mut [f64]) -> (f64, f64) {
    let sum = pivot * pivot + band[0] * band[0];
    let root = if (f64::MIN_POSITIVE..=f64::MAX).contains(&sum) {
        sum.sqrt()
    } else {
        let scale = pivot.abs().max(band[0].abs());
        let (p, q) = (pivot / scale, band[0] / scale);
        scale * (p * p + q * q).sqrt()
    };
    let inverse = 1.0 / root;
    let rotation = (band[0] * inverse, pivot * inverse);
    band[0] = root;
    rotation
}

/// The reflection I - scale v v^T (v = (v0, h)) applied to the column (entry, target).
#[inline(always)]
fn reflect(v0: f64, h: &[f64], scale: f64, entry: &mut f64, target: &mut [f64]) {
    let dot: f64 = h.iter().zip(target.iter()).map(|(a, b)| a * b).sum();
    let f = (v0 * *entry + dot) * scale;
    *entry -= f * v0;
    for (t, &hv) in target.iter_mut().zip(h) {
        *t -= f * hv;
    }
}

/// FITPACK's fprota on two rows (a triangle's and the incoming row's, or their right-hand
/// sides), entry by entry.
#[inline(always)]
pub fn rotate_rows(z: &mut [f64], rhs: &mut [f64], cos: f64, sin: f64) {
    for (target, v) in z.iter_mut().zip(rhs.iter_mut()) {
        let (old, incoming) = (*target, *v);
        *target = cos * old + sin * incoming;
        *v = cos * incoming - sin * old;
    }
}

/// The k + 1 B-splines of degree k that do not vanish at each x (FITPACK's fpbspl, de Boor's
/// BSPLVB recurrence): `rows[i] = B_{first_i .. first_i + k}(x_i)`, first_i = l - k for x's
/// knot span l = clamp(#{t_j <= x} - 1, k, n - 1).
#[derive(Debug)]
pub struct BasisRows {
    /// The degree.
    pub k: usize,
    /// Each row's first column.
    pub first: Vec<usize>,
    /// The rows' k + 1 values each.
    pub values: Vec<f64>,
}

impl BasisRows {
    /// The rows of the points x on knots t.
    pub fn new(x: &[f64], t: &[f64], k: usize) -> Self {
        // The common degrees with k a constant in `build` (its loops unrolled; the same
        // arithmetic, bit for bit).
        match k {
            1 => Self::build(x, t, 1),
            2 => Self::build(x, t, 2),
            3 => Self::build(x, t, 3),
            _ => Self::build(x, t, k),
        }
    }

    #[inline(always)]
    fn build(x: &[f64], t: &[f64], k: usize) -> Self {
        let n = t.len() - k - 1;
        let (mut left, mut right) = (vec![0.0; k + 1], vec![0.0; k + 1]);
        let mut first = Vec::with_capacity(x.len());
        let mut values = vec![0.0; x.len() * (k + 1)];
        let mut l = k;
        for (i, &xi) in x.iter().enumerate() {
            // x is sorted for every fit: walk the span forward, search only when it falls back.
            if xi < t[l] {
                l = k;
            }
            while l + 1 < n && t[l + 1] <= xi {
                l += 1;
            }
            let row = &mut values[i * (k + 1)..(i + 1) * (k + 1)];
            if t[l + 1] > t[l] {
                row[0] = 1.0;
                for j in 0..k {
                    left[j] = xi - t[l - j];
                    right[j] = t[l + 1 + j] - xi;
                    let mut saved = 0.0;
                    for r in 0..=j {
                        // A division, as FITPACK's fpbspl: where weights span many
                        // decades the knot search's residuals at the heavy points are this
                        // recurrence's rounding, and SciPy's knots follow it.
                        let term = row[r] / (right[r] + left[j - r]);
                        row[r] = saved + right[r] * term;
                        saved = left[j - r] * term;
                    }
                    row[j + 1] = saved;
                }
            } else {
                // An empty span (repeated end knots): the general recurrence's zeros.
                let mut scratch = vec![0.0; k + 1];
                de_boor::basis(t, k, xi, 0, row, &mut scratch);
            }
            first.push(l - k);
        }
        Self { k, first, values }
    }

    /// Row i: its first column and k + 1 values.
    pub fn row(&self, i: usize) -> (usize, &[f64]) {
        let k1 = self.k + 1;
        (self.first[i], &self.values[i * k1..(i + 1) * k1])
    }
}

/// The data rows (basis rows times w_i, right-hand sides w_i y_i, y len(x) rows of m) rotated
/// into a triangle of `width` >= k + 1 entries a row, for `columns` coefficients; and the
/// weighted residual sum of squares of the least-squares fit.
pub fn triangle(
    rows: &BasisRows,
    y: &[f64],
    m: usize,
    w: &[f64],
    columns: usize,
    width: usize,
) -> (Triangle, f64) {
    let mut tri = Triangle::new(columns, width, m);
    let (mut h, mut rhs) = (vec![0.0; rows.k + 1], vec![0.0; m]);
    let residual = (0..w.len())
        .map(|i| tri.rotate_data_row(rows, i, y, w, &mut h, &mut rhs))
        .sum();
    (tri, residual)
}

/// The least-squares coefficients by the normal equations B^T W^2 B c = B^T W^2 y (banded,
/// k + 1 bands, Cholesky): no square root or division a data row, where Givens rotations
/// take both for each of the row's k + 1 entries. Their condition is the basis' squared
/// (B-splines are well conditioned: about 1e-13 relative here, against the rotations'
/// 1e-15); for the fits whose coefficients are only read for their residuals (FITPACK's knot
/// search). None where the matrix is not positive definite or not well conditioned.
pub fn normal_fit(
    rows: &BasisRows,
    y: &[f64],
    m: usize,
    w: &[f64],
    columns: usize,
) -> Option<Vec<f64>> {
    let width = rows.k + 1;
    // a[row * width + d] = N[row, row + d].
    let mut a = vec![0.0; columns * width];
    let mut b = vec![0.0; columns * m];
    match width {
        2 => accumulate::<2>(rows, y, m, w, &mut a, &mut b),
        3 => accumulate::<3>(rows, y, m, w, &mut a, &mut b),
        4 => accumulate::<4>(rows, y, m, w, &mut a, &mut b),
        5 => accumulate::<5>(rows, y, m, w, &mut a, &mut b),
        6 => accumulate::<6>(rows, y, m, w, &mut a, &mut b),
        _ => {
            for (i, &wi) in w.iter().enumerate() {
                let (first, values) = rows.row(i);
                let w2 = wi * wi;
                for (r, &vr) in values.iter().enumerate() {
                    let scaled = w2 * vr;
                    let row = first + r;
                    for (d, &vd) in values[r..].iter().enumerate() {
                        a[row * width + d] += scaled * vd;
                    }
                    let target = &mut b[row * m..(row + 1) * m];
                    for (t, &yv) in target.iter_mut().zip(&y[i * m..(i + 1) * m]) {
                        *t += scaled * yv;
                    }
                }
            }
        }
    }
    // N = U^T U, U upper with `width` bands, in place.
    for row in 0..columns {
        for d in 0..width.min(columns - row) {
            let mut v = a[row * width + d];
            // Rows above sharing columns row and row + d.
            for above in row.saturating_sub(width - 1 - d)..row {
                let (i, j) = (row - above, row + d - above);
                if j < width {
                    v -= a[above * width + i] * a[above * width + j];
                }
            }
            if d == 0 {
                if v.is_nan() || v <= 0.0 {
                    return None;
                }
                a[row * width] = v.sqrt();
            } else {
                a[row * width + d] = v / a[row * width];
            }
        }
    }
    // Only where N is well conditioned: cond(N) >= (max U_ii / min U_ii)^2, which far-apart
    // weights or knots with little data drive up; beyond 1e6 (1e-10 in the residuals) the
    // caller rotates instead.
    let (mut low, mut high) = (f64::INFINITY, 0.0_f64);
    for row in 0..columns {
        low = low.min(a[row * width]);
        high = high.max(a[row * width]);
    }
    if high > 1e3 * low {
        return None;
    }
    // U^T z = b, then U c = z.
    for row in 0..columns {
        for above in row.saturating_sub(width - 1)..row {
            let u = a[above * width + row - above];
            for col in 0..m {
                b[row * m + col] -= u * b[above * m + col];
            }
        }
        for col in 0..m {
            b[row * m + col] /= a[row * width];
        }
    }
    for row in (0..columns).rev() {
        for d in 1..width.min(columns - row) {
            let u = a[row * width + d];
            for col in 0..m {
                b[row * m + col] -= u * b[(row + d) * m + col];
            }
        }
        for col in 0..m {
            b[row * m + col] /= a[row * width];
        }
    }
    b.iter().all(|v| v.is_finite()).then_some(b)
}

/// The normal equations' sums (`normal_fit`) for basis rows of W values, the row's block of
/// N in registers.
fn accumulate<const W: usize>(
    rows: &BasisRows,
    y: &[f64],
    m: usize,
    w: &[f64],
    a: &mut [f64],
    b: &mut [f64],
) {
    for (i, &wi) in w.iter().enumerate() {
        let (first, values) = rows.row(i);
        let values: &[f64; W] = values.try_into().expect("k + 1 basis values");
        let w2 = wi * wi;
        for r in 0..W {
            let scaled = w2 * values[r];
            let row = first + r;
            let band = &mut a[row * W..row * W + W - r];
            for (d, target) in band.iter_mut().enumerate() {
                *target += scaled * values[r + d];
            }
            for (target, &yv) in b[row * m..(row + 1) * m]
                .iter_mut()
                .zip(&y[i * m..(i + 1) * m])
            {
                *target += scaled * yv;
            }
        }
    }
}

/// One series' data checked as SciPy's `make_lsq_spline` checks it, in SciPy's words: t
/// non-decreasing, at least k + 1 points, x non-decreasing inside the base interval
/// [t_k, t_n], weights finite and >= 0, y finite.
pub fn check(x: &[f64], y: &[f64], w: &[f64], t: &[f64], k: usize) -> Result<(), InputError> {
    if t.len() < 2 * k + 2 {
        return Err(InputError::new(
            "t",
            format!(
                "needs at least 2k + 2 = {} knots, got {}",
                2 * k + 2,
                t.len()
            ),
        ));
    }
    if let Some(i) = first_unordered(t) {
        return Err(
            InputError::new("t", "Expect t to be a 1D strictly increasing sequence.").at(i),
        );
    }
    if x.len() < k + 1 {
        return Err(InputError::new("x", "Need more x points."));
    }
    if let Some(i) = first_unordered(x) {
        return Err(InputError::new("x", "Expect x to be a 1D non-decreasing sequence.").at(i));
    }
    let n = t.len() - k - 1;
    let (lo, hi) = if k == 0 {
        (t[0], t[t.len() - 1])
    } else {
        (t[k], t[n])
    };
    if let Some(i) = x.iter().position(|&v| v < lo || v > hi) {
        return Err(InputError::new(
            "x",
            "Out of bounds: x outside the base interval [t[k], t[-k-1]]",
        )
        .at(i));
    }
    if let Some(i) = w.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(InputError::new("w", "weights must be finite and >= 0").at(i));
    }
    if let Some(i) = y.iter().position(|v| !v.is_finite()) {
        return Err(InputError::new("y", "must be finite (NaN or infinity found)").at(i));
    }
    Ok(())
}

/// The first position where `values` is NaN, infinite or below its predecessor.
pub(crate) fn first_unordered(values: &[f64]) -> Option<usize> {
    values
        .iter()
        .position(|v| !v.is_finite())
        .or_else(|| values.windows(2).position(|p| p[1] < p[0]).map(|i| i + 1))
}

/// A least-squares fit: coefficients (len(t) - k - 1 rows of m) and the weighted residual
/// sum of squares (all columns together).
#[derive(Debug)]
pub struct Fit {
    /// The coefficients, len(t) - k - 1 rows of m.
    pub c: Vec<f64>,
    /// The weighted residual sum of squares.
    pub residual: f64,
}

/// The fit of y (len(x) rows of m, row-major) with weights w on knots t of degree k, or None
/// when R is singular (some coefficient has no data: Schoenberg-Whitney). x must lie in
/// [t_k, t_n], sorted. A knot span's rows (they share their first column) go in together
/// by Householder reflections where there are at least `BLOCK` of them
/// (`Triangle::absorb`: a square root and a division a column of the block, where
/// rotations take both for every entry of every row; the same R up to rounding), one by
/// one by FITPACK's rotations where fewer (whose rounding SciPy's tests of tiny fits expect
/// to the last bit).
pub fn fit(x: &[f64], y: &[f64], m: usize, w: &[f64], t: &[f64], k: usize) -> Option<Fit> {
    const BLOCK: usize = 8;
    let rows = BasisRows::new(x, t, k);
    let width = k + 1;
    let mut tri = Triangle::new(t.len() - k - 1, width, m);
    let (mut columns, mut rhs) = (Vec::new(), Vec::new());
    let (mut h, mut row_rhs) = (vec![0.0; width], vec![0.0; m]);
    let mut residual = 0.0;
    let mut start = 0;
    while start < x.len() {
        let first = rows.first[start];
        let end = start + rows.first[start..].partition_point(|&f| f == first);
        let p = end - start;
        if p < BLOCK {
            for i in start..end {
                residual += tri.rotate_data_row(&rows, i, y, w, &mut h, &mut row_rhs);
            }
            start = end;
            continue;
        }
        // The block column by column: its weighted basis values, then its weighted y.
        columns.clear();
        columns.resize(width * p, 0.0);
        rhs.clear();
        rhs.resize(m * p, 0.0);
        for (q, i) in (start..end).enumerate() {
            let values = rows.row(i).1;
            for (c, v) in values.iter().enumerate() {
                columns[c * p + q] = w[i] * v;
            }
            for c in 0..m {
                rhs[c * p + q] = w[i] * y[i * m + c];
            }
        }
        residual += tri.absorb(first, &mut columns, &mut rhs, p);
        start = end;
    }
    tri.back_substitute().map(|c| Fit { c, residual })
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
