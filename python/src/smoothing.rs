//! Cubic smoothing splines (SciPy's `make_smoothing_spline`): the f minimising
//!     sum_i w_i (y_i - f(x_i))^2 + lam * integral (f'')^2,
//! a natural cubic spline with a knot at every x, computed in SciPy's formulation (Woltring's,
//! as SciPy re-derived it) so that the same data give the same spline and the same GCV lam:
//!
//! - In a basis of natural splines N_j (N_j = B_{j+1} inside, combinations of B_0..B_2 and
//!   B_{n-1}..B_{n+1} at the ends, on the knots [x_0] * 3 + x + [x_last] * 3), the collocation
//!   matrix X (f(x_i) = (X c)_i) and the penalty E (from the divided differences of five
//!   neighbouring x, so that integral f''^2 = c^T X^T E c) are both 5-banded, and the
//!   minimiser solves
//!   `(X + lam W^-1 E) c = y`
//!   (banded LU with partial pivoting, as LAPACK's gbsv that SciPy calls). A solve in
//!   Reinsch's form (second derivatives, R + lam Q^T W^-1 Q) is cheaper but loses digits as
//!   1 / h^3 where x are close: 0.14 of 11 on 2,048 random x against 1e-4 here.
//! - When lam is not given it minimises generalised cross-validation (Wahba):
//!   `GCV(lam) = (|y - X c|^2 / n) / (1 - tr(A) / n)^2`,
//!   y - X c = lam W^-1 E c, and tr(A) = tr(B X^T W X), B = (X^T W X + lam X^T E)^-1, of
//!   which only the central bands are needed: Hutchinson and de Hoog's recurrence on the
//!   Cholesky factor A = U^T D^-1 U (U unit upper, bandwidth 3), from the last row up,
//!   `B_ij = delta_ij D_i - sum_{k=1..3} U_{i,i+k} B_{i+k,j}` (j >= i).
//!   As SciPy's, the trace takes the diagonal and two bands of B (it drops the third).
//! - The minimum is searched on (0, n) by the bounded Brent method of SciPy's
//!   `minimize_scalar(method="bounded")`, step for step.
//!
//! Everything is O(n) a lam; a series' matrices are made once for every lam and column.

/// LAPACK's banded layout of an n x n matrix with two bands each side: `band[r][j]` =
/// A[j + r - 2, j] (r = 2 the diagonal).
type Bands5 = [Vec<f64>; 5];

/// One series' matrices, made once for any lam and any column of y.
pub(crate) struct System {
    n: usize,
    /// x, for the conversion to B-spline coefficients.
    x: Vec<f64>,
    /// The rows of X and W^-1 E (6 E): `[i][s]` = A[i, i + s - 2], zero outside the matrix.
    design: Vec<[f64; 5]>,
    penalty: Vec<[f64; 5]>,
    /// The upper bands of X^T W X and X^T E by rows: `[i][d]` = (i, i + d), d = 0..=3.
    xtwx: Vec<[f64; 4]>,
    xte: Vec<[f64; 4]>,
}

/// Working vectors reused across lam and series.
#[derive(Default)]
pub(crate) struct Scratch {
    /// The LU's upper rows: row i's columns i + 1 .. i + 4 (the band and the fill of
    /// pivoting), then 1 / U_ii.
    lu: Vec<[f64; 5]>,
    /// The solution, c_i at [i + 2], with two zeros before and four after.
    c: Vec<f64>,
    /// The Cholesky factor's rows divided by their diagonals, the diagonal's place holding
    /// D_i = 1 / U_ii^2.
    unit: Vec<[f64; 4]>,
}

impl Scratch {
    /// Room for a system of n rows.
    pub(crate) fn fit(&mut self, n: usize) {
        if self.lu.len() < n {
            self.lu.resize(n, [0.0; 5]);
            self.c.resize(n + 6, 0.0);
            self.unit.resize(n, [0.0; 4]);
        }
    }
}

/// Why a smoothing spline could not be made.
#[derive(Debug, PartialEq, Clone)]
pub(crate) enum Failure {
    /// A matrix was singular or not positive definite.
    IllPosed,
    /// The search for the GCV minimum gave NaN or ran out of evaluations.
    NoMinimum(&'static str),
}

/// The coefficients 1 / prod_{k != i} (x_i - x_k) of the divided difference on `x`.
fn divided_difference(x: &[f64]) -> [f64; 5] {
    let mut out = [0.0; 5];
    for (i, o) in out.iter_mut().enumerate().take(x.len()) {
        let mut product = 1.0;
        for (k, &xk) in x.iter().enumerate() {
            if k != i {
                product *= x[i] - xk;
            }
        }
        *o = 1.0 / product;
    }
    out
}

impl System {
    /// The matrices of x (n >= 5, strictly increasing) and positive weights w;
    /// `basis(x_i)` gives the cubic B-splines of the knots [x_0] * 3 + x + [x_last] * 3 at
    /// x_i as (first index, 4 values).
    pub(crate) fn new(x: &[f64], w: &[f64]) -> Self {
        let n = x.len();
        let t: Vec<f64> = [x[0]; 3]
            .iter()
            .chain(x)
            .chain(&[x[n - 1]; 3])
            .copied()
            .collect();
        // B_j(x_i), read as SciPy's design matrix entries Xb[i, j].
        let mut rows = vec![(0_usize, [0.0_f64; 4]); n];
        let (mut values, mut scratch) = ([0.0; 4], [0.0; 4]);
        for (i, &xi) in x.iter().enumerate() {
            let l = crate::de_boor::basis(&t, 3, xi, 0, &mut values, &mut scratch);
            rows[i] = (l - 3, values);
        }
        let xb = |i: usize, j: usize| {
            let (first, v) = rows[i];
            if j >= first && j < first + 4 {
                v[j - first]
            } else {
                0.0
            }
        };
        let mut design: Bands5 = std::array::from_fn(|_| vec![0.0; n]);
        // A[i, j] into band 2 + i - j of column j.
        let set = |bands: &mut Bands5, i: usize, j: usize, v: f64| bands[2 + i - j][j] = v;
        for j in 2..n - 2 {
            for i in j - 1..=j + 1 {
                set(&mut design, i, j, xb(i, j + 1));
            }
        }
        set(&mut design, 0, 0, (x[2] + x[1] - 2.0 * x[0]) * xb(0, 0));
        set(&mut design, 1, 0, (x[2] - x[0]) * xb(1, 1));
        set(&mut design, 0, 1, xb(0, 0));
        set(&mut design, 1, 1, xb(1, 1) + xb(1, 2));
        set(&mut design, 2, 1, xb(2, 2));
        let last = n - 1;
        set(&mut design, last - 2, last - 1, xb(last - 2, last));
        set(
            &mut design,
            last - 1,
            last,
            (x[last] - x[last - 2]) * xb(last - 1, last + 1),
        );
        set(
            &mut design,
            last - 1,
            last - 1,
            xb(last - 1, last) + xb(last - 1, last + 1),
        );
        set(
            &mut design,
            last,
            last,
            (2.0 * x[last] - x[last - 1] - x[last - 2]) * xb(last, last + 2),
        );
        set(&mut design, last, last - 1, xb(last, last + 2));
        let mut penalty: Bands5 = std::array::from_fn(|_| vec![0.0; n]);
        let mut column = |j: usize, rows: std::ops::Range<usize>, scale: f64| {
            let dd = divided_difference(&x[rows.clone()]);
            for (r, i) in rows.enumerate() {
                set(&mut penalty, i, j, 6.0 * scale * dd[r] / w[i]);
            }
        };
        column(0, 0..3, 1.0);
        column(1, 0..4, 1.0);
        for j in 2..n - 2 {
            column(j, j - 2..j + 3, x[j + 2] - x[j - 2]);
        }
        column(last - 1, n - 4..n, -1.0);
        column(last, n - 3..n, 1.0);
        let xtwx = symmetric_product(&design, w, &design);
        let xte = symmetric_product(&design, w, &penalty);
        let rows = |bands: &Bands5| -> Vec<[f64; 5]> {
            (0..n)
                .map(|i| {
                    std::array::from_fn(|s| match (i + s).checked_sub(2) {
                        Some(j) if j < n => bands[4 - s][j],
                        _ => 0.0,
                    })
                })
                .collect()
        };
        let by_row = |bands: [Vec<f64>; 4]| -> Vec<[f64; 4]> {
            (0..n)
                .map(|i| std::array::from_fn(|d| bands[d][i]))
                .collect()
        };
        Self {
            n,
            x: x.to_vec(),
            design: rows(&design),
            penalty: rows(&penalty),
            xtwx: by_row(xtwx),
            xte: by_row(xte),
        }
    }

    /// Working vectors for this system's size.
    pub(crate) fn scratch(&self) -> Scratch {
        let mut s = Scratch::default();
        s.fit(self.n);
        s
    }

    /// Row i of X + lam W^-1 E in a 7-slot window (slot q: column i + q - 2) and y_i; zeros
    /// past the last row.
    #[inline(always)]
    fn fresh(&self, lam: f64, y: Column<'_>, i: usize) -> ([f64; 7], f64) {
        if i >= self.n {
            return ([0.0; 7], 0.0);
        }
        let (d, p) = (&self.design[i], &self.penalty[i]);
        let mut row = [0.0; 7];
        for q in 0..5 {
            row[q] = d[q] + lam * p[q];
        }
        (row, y.get(i))
    }

    /// (X + lam W^-1 E) c = y into `s.c` (see `Solve`).
    fn solve(&self, lam: f64, y: Column<'_>, s: &mut Scratch) -> Result<(), Failure> {
        let mut lane = Solve::start(self, lam, y);
        for j in 0..self.n {
            lane.eliminate(self, lam, y, j, s)?;
        }
        let mut back = [0.0; 4];
        for i in (0..self.n).rev() {
            back_substitute(&mut back, i, s);
        }
        Ok(())
    }

    /// The smoothing spline of column y for lam, as its n + 2 B-spline coefficients on the
    /// knots t = [x_0] * 3 + x + [x_last] * 3: the natural basis' c taken back (SciPy's
    /// (2.2.10)): the first two from c_0 and c_1, the last two from c_{n-1} and c_{n-2}.
    pub(crate) fn coefficients(
        &self,
        lam: f64,
        y: Column<'_>,
        s: &mut Scratch,
    ) -> Result<Vec<f64>, Failure> {
        self.solve(lam, y, s)?;
        let (x, n) = (&self.x, self.n);
        let c = &s.c[2..n + 2];
        let mut out = Vec::with_capacity(n + 2);
        out.push(c[0] * (x[2] + x[1] - 2.0 * x[0]) + c[1]);
        out.push(c[0] * (x[2] - x[0]) + c[1]);
        out.extend_from_slice(&c[1..n - 1]);
        out.push(c[n - 1] * (x[n - 1] - x[n - 3]) + c[n - 2]);
        out.push(c[n - 1] * (2.0 * x[n - 1] - x[n - 2] - x[n - 3]) + c[n - 2]);
        if out.iter().all(|v| v.is_finite()) {
            Ok(out)
        } else {
            Err(Failure::IllPosed)
        }
    }
}

/// One column of y: y_i = values[i * stride + offset].
#[derive(Clone, Copy)]
pub(crate) struct Column<'a> {
    pub values: &'a [f64],
    pub stride: usize,
    pub offset: usize,
}

impl Column<'_> {
    #[inline(always)]
    fn get(&self, i: usize) -> f64 {
        self.values[i * self.stride + self.offset]
    }
}

/// The forward elimination of (X + lam W^-1 E) c = y, one column a step: Gaussian elimination
/// with partial pivoting in the band (the largest of the pivot's own row and the two below
/// it, the first on ties, the multipliers by the pivot's reciprocal, as LAPACK's gbtf2; a swap
/// widens a row to four columns right of its diagonal). The three rows in play are kept here
/// (in registers), row r's slot q holding column r + q - 2; each finished row is stored once
/// in the scratch (its columns r + 1 .. r + 4, then 1 / U_rr) with its right-hand side.
struct Solve {
    rows: [[f64; 7]; 3],
    rhs: [f64; 3],
}

impl Solve {
    #[inline(always)]
    fn start(system: &System, lam: f64, y: Column<'_>) -> Self {
        let (a, b, c) = (
            system.fresh(lam, y, 0),
            system.fresh(lam, y, 1),
            system.fresh(lam, y, 2),
        );
        Self {
            rows: [a.0, b.0, c.0],
            rhs: [a.1, b.1, c.1],
        }
    }

    #[inline(always)]
    fn eliminate(
        &mut self,
        system: &System,
        lam: f64,
        y: Column<'_>,
        j: usize,
        s: &mut Scratch,
    ) -> Result<(), Failure> {
        let [r0, r1, r2] = &mut self.rows;
        let [c0, c1, c2] = &mut self.rhs;
        let (a0, a1, a2) = (r0[2].abs(), r1[1].abs(), r2[0].abs());
        let largest = a0.max(a1).max(a2);
        if !(largest > 0.0 && largest.is_finite()) {
            return Err(Failure::IllPosed);
        }
        if a1 > a0 && a1 >= a2 {
            // Columns j .. j + 4: slot q + 2 of row j, q + 1 of row j + 1.
            for q in 0..5 {
                std::mem::swap(&mut r0[q + 2], &mut r1[q + 1]);
            }
            std::mem::swap(c0, c1);
        } else if a2 > a0 && a2 > a1 {
            for q in 0..5 {
                std::mem::swap(&mut r0[q + 2], &mut r2[q]);
            }
            std::mem::swap(c0, c2);
        }
        let inverse = 1.0 / r0[2];
        let (f1, f2) = (r1[1] * inverse, r2[0] * inverse);
        r1[1] = 0.0;
        r2[0] = 0.0;
        for q in 1..5 {
            r1[1 + q] -= f1 * r0[2 + q];
            r2[q] -= f2 * r0[2 + q];
        }
        *c1 -= f1 * *c0;
        *c2 -= f2 * *c0;
        s.lu[j] = [r0[3], r0[4], r0[5], r0[6], inverse];
        s.c[j + 2] = *c0;
        let (next, value) = system.fresh(lam, y, j + 3);
        self.rows = [self.rows[1], self.rows[2], next];
        self.rhs = [self.rhs[1], self.rhs[2], value];
        Ok(())
    }
}

/// Back substitution's step for row i (from the last up), the four values after it carried.
#[inline(always)]
fn back_substitute(after: &mut [f64; 4], i: usize, s: &mut Scratch) {
    let u = &s.lu[i];
    let v =
        (s.c[i + 2] - u[0] * after[0] - u[1] * after[1] - u[2] * after[2] - u[3] * after[3]) * u[4];
    s.c[i + 2] = v;
    *after = [v, after[0], after[1], after[2]];
}

/// (lam (W^-1 E c)_i)^2: row i of W^-1 E touches c_{i-2} .. c_{i+2}.
#[inline(always)]
fn residual_squared(system: &System, lam: f64, i: usize, s: &Scratch) -> f64 {
    let (p, window) = (&system.penalty[i], &s.c[i..i + 5]);
    let r = lam
        * (p[0] * window[0]
            + p[1] * window[1]
            + p[2] * window[2]
            + p[3] * window[3]
            + p[4] * window[4]);
    r * r
}

/// Row i's step of X^T W X + lam X^T E = U^T U (upper, bandwidth 3), computed as Ũ^T P Ũ
/// with Ũ = U's rows over their diagonals and P_i = U_ii^2 (no square roots, one division a
/// row), the three rows above carried as [P_k, Ũ_{k,k+1..k+3}]; row i stored in the scratch
/// as [1 / P_i, Ũ_{i,i+1..i+3}].
#[inline(always)]
fn cholesky_step(
    system: &System,
    lam: f64,
    above: &mut [[f64; 4]; 3],
    i: usize,
    s: &mut Scratch,
) -> Result<(), Failure> {
    let (g, e) = (&system.xtwx[i], &system.xte[i]);
    let a: [f64; 4] = std::array::from_fn(|d| g[d] + lam * e[d]);
    let [p1, p2, p3] = &*above;
    // U_{k,i} U_{k,l} = P_k Ũ_{k,i} Ũ_{k,l}.
    let (s1, s2, s3) = (p1[0] * p1[1], p2[0] * p2[2], p3[0] * p3[3]);
    let diagonal = a[0] - s1 * p1[1] - s2 * p2[2] - s3 * p3[3];
    if !(diagonal > 0.0 && diagonal.is_finite()) {
        return Err(Failure::IllPosed);
    }
    let inverse = 1.0 / diagonal;
    let row = [
        diagonal,
        (a[1] - s1 * p1[2] - s2 * p2[3]) * inverse,
        (a[2] - s1 * p1[3]) * inverse,
        a[3] * inverse,
    ];
    s.unit[i] = [inverse, row[1], row[2], row[3]];
    *above = [row, above[0], above[1]];
    Ok(())
}

/// Row i's step (from the last up) of B = (U^T U)^-1's bands by Hutchinson and de Hoog's
/// recurrence, carrying [B_{i+1,i+1..i+3}, B_{i+2,i+2..i+3}, B_{i+3,i+3}] (zero past the
/// matrix, as U is); returns row i's part of tr(B X^T W X), which leaves out B's third band
/// as SciPy's does.
#[inline(always)]
fn inverse_step(system: &System, carried: &mut [f64; 6], i: usize, s: &Scratch) -> f64 {
    let (u, g) = (&s.unit[i], &system.xtwx[i]);
    let [b11, b12, b13, b22, b23, b33] = *carried;
    let b03 = -(u[1] * b13 + u[2] * b23 + u[3] * b33);
    let b02 = -(u[1] * b12 + u[2] * b22 + u[3] * b23);
    let b01 = -(u[1] * b11 + u[2] * b12 + u[3] * b13);
    let b00 = u[0] - (u[1] * b01 + u[2] * b02 + u[3] * b03);
    *carried = [b00, b01, b02, b11, b12, b22];
    b00 * g[0] + 2.0 * (b01 * g[1] + b02 * g[2])
}

/// One GCV evaluation in flight: a series' system, its column, the lam and the scratch.
pub(crate) struct Lane<'a> {
    pub system: &'a System,
    pub y: Column<'a>,
    pub lam: f64,
    pub scratch: &'a mut Scratch,
}

/// GCV(lam) of every lane,
///     GCV(lam) = (|lam W^-1 E c|^2 / n) / (1 - tr(A) / n)^2,
/// with the lanes' steps interleaved row by row: each lane's elimination, factorisation and
/// recurrence is one chain of dependent divisions, and independent chains in one loop let the
/// processor overlap them (while the lanes' rows stay in cache).
pub(crate) fn gcv<const L: usize>(lanes: &mut [Lane<'_>; L]) -> [Result<f64, Failure>; L] {
    let n: [usize; L] = std::array::from_fn(|l| lanes[l].system.n);
    for lane in lanes.iter_mut() {
        lane.scratch.fit(lane.system.n);
    }
    let longest = n.iter().copied().max().unwrap_or(0);
    let mut failed: [Option<Failure>; L] = std::array::from_fn(|_| None);
    let mut solve: [Solve; L] =
        std::array::from_fn(|l| Solve::start(lanes[l].system, lanes[l].lam, lanes[l].y));
    for j in 0..longest {
        for l in 0..L {
            let lane = &mut lanes[l];
            if j < n[l]
                && failed[l].is_none()
                && let Err(e) = solve[l].eliminate(lane.system, lane.lam, lane.y, j, lane.scratch)
            {
                failed[l] = Some(e);
            }
        }
    }
    let mut back = [[0.0; 4]; L];
    for step in 0..longest {
        for l in 0..L {
            if step < n[l] && failed[l].is_none() {
                back_substitute(&mut back[l], n[l] - 1 - step, lanes[l].scratch);
            }
        }
    }
    let mut numerator = [0.0; L];
    let mut above = [[[0.0; 4]; 3]; L];
    for i in 0..longest {
        for l in 0..L {
            let lane = &mut lanes[l];
            if i < n[l] && failed[l].is_none() {
                numerator[l] += residual_squared(lane.system, lane.lam, i, lane.scratch);
                if let Err(e) = cholesky_step(lane.system, lane.lam, &mut above[l], i, lane.scratch)
                {
                    failed[l] = Some(e);
                }
            }
        }
    }
    let mut carried = [[0.0; 6]; L];
    let mut trace = [0.0; L];
    for step in 0..longest {
        for l in 0..L {
            if step < n[l] && failed[l].is_none() {
                let lane = &lanes[l];
                trace[l] +=
                    inverse_step(lane.system, &mut carried[l], n[l] - 1 - step, lane.scratch);
            }
        }
    }
    std::array::from_fn(|l| match failed[l].take() {
        Some(e) => Err(e),
        None => {
            let size = n[l] as f64;
            let denominator = 1.0 - trace[l] / size;
            Ok(numerator[l] / size / (denominator * denominator))
        }
    })
}

/// Each column's lam of least GCV on (0, n), as SciPy's `minimize_scalar(bounds=(0, n),
/// method="bounded")` finds it, L searches at a time (`gcv`'s lanes): each search steps on
/// its own and a finished one gives its lane to the next column.
pub(crate) fn gcv_lambdas<const L: usize>(
    columns: &[(&System, Column<'_>)],
    scratch: &mut [Scratch; L],
) -> Vec<Result<f64, Failure>> {
    use crate::bounded_search::{Search, Step};
    let mut results: Vec<Option<Result<f64, Failure>>> = columns.iter().map(|_| None).collect();
    // Each lane: (column index, its search, the lam to evaluate next).
    let mut slots: [Option<(usize, Search, f64)>; L] = std::array::from_fn(|_| None);
    let mut next = 0;
    loop {
        for slot in &mut slots {
            if slot.is_none() && next < columns.len() {
                let (search, x) = Search::new(0.0, columns[next].0.n as f64);
                *slot = Some((next, search, x));
                next += 1;
            }
        }
        if slots.iter().all(Option::is_none) {
            break;
        }
        // Idle lanes evaluate the first busy lane's column again (their result unread).
        let busy = slots.iter().flatten().next().map_or(0, |s| s.0);
        let mut lanes: [Lane<'_>; L] = {
            let mut it = scratch.iter_mut();
            std::array::from_fn(|l| {
                let (column, lam) = slots[l].as_ref().map_or((busy, 1.0), |s| (s.0, s.2));
                Lane {
                    system: columns[column].0,
                    y: columns[column].1,
                    lam,
                    scratch: it.next().expect("a scratch a lane"),
                }
            })
        };
        let values = gcv(&mut lanes);
        for (slot, value) in slots.iter_mut().zip(values) {
            let Some((column, search, x)) = slot else {
                continue;
            };
            let step = match value {
                Ok(fx) => search.tell(fx),
                Err(e) => Step::Done(Err(e)),
            };
            match step {
                Step::Evaluate(lam) => *x = lam,
                Step::Done(result) => {
                    results[*column] = Some(result);
                    *slot = None;
                }
            }
        }
    }
    results
        .into_iter()
        .map(|r| r.expect("every column searched"))
        .collect()
}

/// The upper bands (i, i + d), d = 0..=3, of X^T W Y for 5-banded X and Y (symmetric by
/// construction): sum over the rows r both columns touch of X_ri w_r Y_r,i+d.
fn symmetric_product(a: &Bands5, w: &[f64], b: &Bands5) -> [Vec<f64>; 4] {
    let n = w.len();
    let entry = |m: &Bands5, r: usize, j: usize| {
        if r + 2 >= j && r <= j + 2 {
            m[2 + r - j][j]
        } else {
            0.0
        }
    };
    std::array::from_fn(|d| {
        (0..n)
            .map(|i| {
                let j = i + d;
                if j >= n {
                    return 0.0;
                }
                (j.saturating_sub(2)..(i + 3).min(n))
                    .map(|r| entry(a, r, i) * w[r] * entry(b, r, j))
                    .sum()
            })
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::{Column, System};

    fn column(values: &[f64]) -> Column<'_> {
        Column {
            values,
            stride: 1,
            offset: 0,
        }
    }

    /// B-spline coefficients of a line are its values at the Greville abscissae (knot
    /// averages); a line has no f'', so any lam keeps it.
    #[test]
    fn a_line_is_kept_for_any_lam() {
        let x = [0.0, 1.0, 1.5, 3.0, 4.0, 7.0];
        let y: Vec<f64> = x.iter().map(|v| 2.0 * v - 1.0).collect();
        let w = [1.0, 2.0, 0.5, 1.0, 3.0, 1.0];
        let system = System::new(&x, &w);
        let mut s = system.scratch();
        let t: Vec<f64> = [0.0; 3]
            .iter()
            .chain(&x)
            .chain(&[7.0; 3])
            .copied()
            .collect();
        for lam in [0.0, 0.1, 1e3] {
            let c = system.coefficients(lam, column(&y), &mut s).unwrap();
            for (j, cj) in c.iter().enumerate() {
                let greville = (t[j + 1] + t[j + 2] + t[j + 3]) / 3.0;
                assert!(
                    (cj - (2.0 * greville - 1.0)).abs() < 1e-11,
                    "{lam} {j}: {cj}"
                );
            }
        }
    }

    /// With lam = 0 the spline interpolates: its end coefficients are the end values.
    #[test]
    fn lam_zero_interpolates() {
        let x = [0.0, 0.5, 1.5, 2.0, 3.5, 4.0];
        let y: Vec<f64> = x.iter().map(|v: &f64| v.sin()).collect();
        let system = System::new(&x, &[1.0; 6]);
        let c = system
            .coefficients(0.0, column(&y), &mut system.scratch())
            .unwrap();
        assert!((c[0] - y[0]).abs() < 1e-14 && (c[7] - y[5]).abs() < 1e-14);
    }
}
