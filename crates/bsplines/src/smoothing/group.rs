//! Four smoothing systems solved side by side, one per lane (`Lanes`): row i of every lane
//! lies together, so each step of the elimination, the factorisation and the recurrences of
//! `super` is one vector operation (`Vector`) for all four series, each with its own lam.
//!
//! Lanes hold series of different lengths. A lane's rows past its own n are padding, the
//! identity block of a block-diagonal system, which leaves its real rows' arithmetic as it
//! would be alone:
//! - the real rows have zeros in every column past n (of X, W^-1 E, X^T W X and X^T E), so
//!   no pivot comes from a padding row, no multiplier reaches one, and the padding's values
//!   enter the real rows' sums only as 0 * value;
//! - padding rows are X = I, W^-1 E = 0, y = 0, X^T W X = 0, X^T E = I: the solve gives
//!   c = 0 there, the factorisation D = 1 / lam (lam > 0), and they add exactly 0 to the
//!   residual and to tr(A).
//!
//! So each lane's GCV and coefficients are bit for bit those of its series alone.

use super::SeriesRow;
use crate::lanes::{Lanes, Vector, WIDTH};

/// Whether each lane's values so far were all positive and finite, NaN passed over (it reaches
/// the results instead), in one accumulator: the smallest min(v, 1/v), which is > 0 exactly
/// where every v is (v = 0 gives 0, v = inf gives 1/v = 0, a negative v less than 0; a
/// subnormal v, whose 1/v overflows, gives v). A check kept out of the rows' loops, where a
/// compare and a branch a row cost more than the check; one register, not two (a minimum and
/// a maximum), in loops that spill.
#[derive(Clone, Copy)]
struct Positive<V> {
    smallest: V,
}

impl<V: Vector> Positive<V> {
    #[inline(always)]
    fn new() -> Self {
        Self {
            smallest: V::splat(f64::INFINITY),
        }
    }

    /// Takes v with its reciprocal 1/v, which the factorisations compute anyway.
    #[inline(always)]
    fn include(&mut self, v: V, reciprocal: V) {
        self.smallest = v.min(reciprocal).min(self.smallest);
    }

    /// Lane by lane: every value positive and finite (NaN aside).
    #[inline(always)]
    fn all(&self) -> [bool; WIDTH] {
        self.smallest.store().0.map(|v| v > 0.0)
    }
}

/// Row i of every lane: what a lam's evaluation reads.
#[derive(Clone, Copy)]
struct Row {
    /// X[i, i - 1 ..= i + 1] (X is tridiagonal: at its own x only three B-splines are not 0).
    design: [Lanes; 3],
    /// (W^-1 E)[i, i - 2 ..= i + 2].
    penalty: [Lanes; 5],
    y: Lanes,
    /// (X^T W X)[i, i ..= i + 3] and (X^T E)[i, i ..= i + 3].
    gram: [Lanes; 4],
    rough: [Lanes; 4],
}

/// A lane's row past its series' end (its y is zero).
const PADDING: SeriesRow = SeriesRow {
    design: [0.0, 1.0, 0.0],
    penalty: [0.0; 5],
    gram: [0.0; 4],
    rough: [1.0, 0.0, 0.0, 0.0],
};

/// Row i of the factors one evaluation makes, read back on its way up.
#[derive(Clone, Copy)]
struct Factors {
    /// The LU's row i: columns i + 1 ..= i + 4 (the band and the fill of pivoting), then
    /// 1 / U_ii.
    lu: [Lanes; 5],
    /// The right-hand side eliminated.
    c: Lanes,
    /// The Cholesky factor's row over its diagonal, [D_i, Ũ_{i,i+1..i+3}] (see `cholesky`).
    unit: [Lanes; 4],
}

/// What one evaluation gives each lane.
pub(crate) struct Evaluation {
    /// |lam W^-1 E c|^2 = |y - X c|^2 (weighted).
    pub residual: [f64; WIDTH],
    /// tr(A) as SciPy takes it (see `inverse_step`).
    pub trace: [f64; WIDTH],
    /// Every pivot of the LU (in magnitude) positive and finite, NaN aside.
    pub solved: [bool; WIDTH],
    /// Every pivot of the Cholesky factorisation (U_ii^2) positive and finite, NaN aside:
    /// X^T W X + lam X^T E positive definite.
    pub factored: [bool; WIDTH],
}

pub(crate) struct Group {
    /// Room for the longest series, and three rows more (the elimination reads three ahead).
    rows: Vec<Row>,
    factors: Vec<Factors>,
    /// Evaluations' c, row by row: one for each lane's kept c (`keep`) and one more, which the
    /// next evaluation writes (`latest`). A lane's c is kept without a copy.
    solutions: [Vec<Lanes>; WIDTH + 1],
    /// Where the last evaluation wrote c.
    latest: usize,
    /// Where each lane's kept c is.
    kept: [usize; WIDTH],
    /// Each lane's n (0 for an idle lane).
    n: [usize; WIDTH],
}

impl Group {
    /// Idle lanes with room for series of up to `capacity` points.
    pub(crate) fn new(capacity: usize) -> Self {
        let mut group = Self {
            rows: vec![
                Row {
                    design: [Lanes::ZERO; 3],
                    penalty: [Lanes::ZERO; 5],
                    y: Lanes::ZERO,
                    gram: [Lanes::ZERO; 4],
                    rough: [Lanes::ZERO; 4],
                };
                capacity + 3
            ],
            factors: vec![
                Factors {
                    lu: [Lanes::ZERO; 5],
                    c: Lanes::ZERO,
                    unit: [Lanes::ZERO; 4],
                };
                capacity
            ],
            solutions: std::array::from_fn(|_| vec![Lanes::ZERO; capacity]),
            latest: 0,
            kept: [0; WIDTH],
            n: [capacity; WIDTH],
        };
        for lane in 0..WIDTH {
            group.clear(lane);
        }
        group
    }

    /// Each lane's n.
    pub(crate) fn lengths(&self) -> [usize; WIDTH] {
        self.n
    }

    #[inline(always)]
    fn set(&mut self, lane: usize, i: usize, row: &SeriesRow, y: f64) {
        let r = &mut self.rows[i];
        for (q, v) in row.design.iter().enumerate() {
            r.design[q].0[lane] = *v;
        }
        for (q, v) in row.penalty.iter().enumerate() {
            r.penalty[q].0[lane] = *v;
        }
        r.y.0[lane] = y;
        for d in 0..4 {
            r.gram[d].0[lane] = row.gram[d];
            r.rough[d].0[lane] = row.rough[d];
        }
    }

    /// Lane `lane` takes the system of a series (n <= capacity) and its column y.
    pub(crate) fn load(&mut self, lane: usize, rows: &[SeriesRow], y: impl Fn(usize) -> f64) {
        let previous = self.n[lane];
        let n = rows.len();
        for (i, row) in rows.iter().enumerate() {
            self.set(lane, i, row, y(i));
        }
        for i in n..previous.max(n) {
            self.set(lane, i, &PADDING, 0.0);
        }
        self.n[lane] = n;
    }

    /// Lane `lane` idle: padding throughout.
    pub(crate) fn clear(&mut self, lane: usize) {
        for i in 0..self.n[lane] + 3 {
            self.set(lane, i, &PADDING, 0.0);
        }
        self.n[lane] = 0;
    }

    /// Lane `lane` keeps the last evaluation's c (until it keeps another).
    pub(crate) fn keep(&mut self, lane: usize) {
        self.kept[lane] = self.latest;
    }

    /// Lane `lane`'s kept c (natural basis).
    pub(crate) fn kept(&self, lane: usize) -> Vec<f64> {
        self.solutions[self.kept[lane]][..self.n[lane]]
            .iter()
            .map(|c| c.0[lane])
            .collect()
    }

    /// Row i of X + lam W^-1 E in a 7-slot window (slot q: column i + q - 2) and y_i.
    #[inline(always)]
    fn fresh<V: Vector>(&self, lam: V, i: usize) -> ([V; 7], V) {
        let r = &self.rows[i];
        let zero = V::splat(0.0);
        let (d, p) = (r.design.map(V::load), r.penalty.map(V::load));
        let row = [
            lam * p[0],
            d[0] + lam * p[1],
            d[1] + lam * p[2],
            d[2] + lam * p[3],
            lam * p[4],
            zero,
            zero,
        ];
        (row, V::load(r.y))
    }

    /// Every lane's residual and trace at its lam (and c, for `keep`): the elimination and
    /// the factorisation down the rows together, then the back substitution, the residual and
    /// the inverse's recurrence up them together.
    #[inline(always)]
    pub(crate) fn evaluate<V: Vector>(&mut self, lam: Lanes) -> Evaluation {
        let lam = V::load(lam);
        let zero = V::splat(0.0);
        let longest = self.n.iter().copied().max().unwrap_or(0);
        // c goes where no lane's kept c is (of WIDTH + 1, one is free).
        self.latest = (0..=WIDTH)
            .find(|s| !self.kept.contains(s))
            .unwrap_or_default();
        let (a, b, c) = (self.fresh(lam, 0), self.fresh(lam, 1), self.fresh(lam, 2));
        let mut window = Window {
            rows: [a.0, b.0, c.0],
            rhs: [a.1, b.1, c.1],
        };
        let mut above = [[zero; 4]; 3];
        let (mut pivots, mut diagonals) = (Positive::new(), Positive::new());
        for j in 0..longest {
            let (lu, c) = window.eliminate(&mut pivots);
            let unit = cholesky(&self.rows[j], lam, &mut above, &mut diagonals);
            // Row j + 3 made last: its vectors live only from here (registers are short).
            window.push(self.fresh(lam, j + 3));
            self.factors[j] = Factors {
                lu: lu.map(V::store),
                c: c.store(),
                unit: unit.map(V::store),
            };
        }
        // c_i .. c_{i+4} as the rows are solved upwards (zero past the matrix).
        let mut after = [zero; 5];
        let mut carried = [zero; 6];
        let (mut residual, mut trace) = (zero, zero);
        let solution = &mut self.solutions[self.latest][..longest];
        for (i, (f, out)) in self.factors.iter().zip(solution).enumerate().rev() {
            let u = f.lu.map(V::load);
            let v = (V::load(f.c)
                - u[0] * after[0]
                - u[1] * after[1]
                - u[2] * after[2]
                - u[3] * after[3])
                * u[4];
            *out = v.store();
            after = [v, after[0], after[1], after[2], after[3]];
            if i + 2 < longest {
                residual = residual + residual_squared(&self.rows[i + 2], lam, &after);
            }
            trace = trace + inverse_step(f.unit.map(V::load), &self.rows[i].gram, &mut carried);
        }
        // Rows 1 and 0 reach c_{-1} and c_{-2}: zero.
        for i in (0..longest.min(2)).rev() {
            after = [zero, after[0], after[1], after[2], after[3]];
            residual = residual + residual_squared(&self.rows[i], lam, &after);
        }
        Evaluation {
            residual: residual.store().0,
            trace: trace.store().0,
            solved: pivots.all(),
            factored: diagonals.all(),
        }
    }
}

/// The three rows of the elimination in play, row r's slot q holding column r + q - 2, and
/// their right-hand sides.
struct Window<V> {
    rows: [[V; 7]; 3],
    rhs: [V; 3],
}

impl<V: Vector> Window<V> {
    /// Column j's step of Gaussian elimination with partial pivoting in the band, as LAPACK's
    /// gbtf2: the pivot the largest of the top row's own entry and the two below it (the
    /// first on ties), multipliers by the pivot's reciprocal; a swap widens a row to four
    /// columns right of its diagonal. Returns the finished row (its columns j + 1 ..= j + 4,
    /// then 1 / U_jj) and its right-hand side, and takes row j + 3 in. The pivot's magnitude
    /// goes into `pivots`.
    #[inline(always)]
    fn eliminate(&mut self, pivots: &mut Positive<V>) -> ([V; 5], V) {
        let [r0, r1, r2] = &mut self.rows;
        let [c0, c1, c2] = &mut self.rhs;
        let (a0, a1, a2) = (r0[2].abs(), r1[1].abs(), r2[0].abs());
        let largest = a0.max(a1).max(a2);
        let second = V::and(a1.gt(a0), a1.ge(a2));
        let third = V::and_not(second, V::and(a2.gt(a0), a2.gt(a1)));
        for q in 0..5 {
            let (top, mid, low) = (r0[q + 2], r1[q + 1], r2[q]);
            r0[q + 2] = V::select(second, mid, V::select(third, low, top));
            r1[q + 1] = V::select(second, top, mid);
            r2[q] = V::select(third, top, low);
        }
        let (top, mid, low) = (*c0, *c1, *c2);
        *c0 = V::select(second, mid, V::select(third, low, top));
        *c1 = V::select(second, top, mid);
        *c2 = V::select(third, top, low);
        let zero = V::splat(0.0);
        let inverse = V::splat(1.0) / r0[2];
        // The pivot's magnitude is the largest.
        pivots.include(largest, inverse.abs());
        let (f1, f2) = (r1[1] * inverse, r2[0] * inverse);
        r1[1] = zero;
        r2[0] = zero;
        for q in 1..5 {
            r1[1 + q] = r1[1 + q] - f1 * r0[2 + q];
            r2[q] = r2[q] - f2 * r0[2 + q];
        }
        *c1 = *c1 - f1 * *c0;
        *c2 = *c2 - f2 * *c0;
        ([r0[3], r0[4], r0[5], r0[6], inverse], *c0)
    }

    /// The next row in, the finished one out.
    #[inline(always)]
    fn push(&mut self, (row, rhs): ([V; 7], V)) {
        self.rows = [self.rows[1], self.rows[2], row];
        self.rhs = [self.rhs[1], self.rhs[2], rhs];
    }
}

/// Row i's step of X^T W X + lam X^T E = U^T U (upper, bandwidth 3), computed as Ũ^T P Ũ
/// with Ũ = U's rows over their diagonals and P_i = U_ii^2 (no square roots, one division a
/// row), the three rows above carried as [P_k, Ũ_{k,k+1..k+3}]; returns row i as
/// [1 / P_i, Ũ_{i,i+1..i+3}]; P_i goes into `diagonals`.
#[inline(always)]
fn cholesky<V: Vector>(
    row: &Row,
    lam: V,
    above: &mut [[V; 4]; 3],
    diagonals: &mut Positive<V>,
) -> [V; 4] {
    let a: [V; 4] = std::array::from_fn(|d| V::load(row.gram[d]) + lam * V::load(row.rough[d]));
    let [p1, p2, p3] = &*above;
    // U_{k,i} U_{k,l} = P_k Ũ_{k,i} Ũ_{k,l}.
    let (s1, s2, s3) = (p1[0] * p1[1], p2[0] * p2[2], p3[0] * p3[3]);
    let diagonal = a[0] - s1 * p1[1] - s2 * p2[2] - s3 * p3[3];
    let inverse = V::splat(1.0) / diagonal;
    diagonals.include(diagonal, inverse);
    let new = [
        diagonal,
        (a[1] - s1 * p1[2] - s2 * p2[3]) * inverse,
        (a[2] - s1 * p1[3]) * inverse,
        a[3] * inverse,
    ];
    *above = [new, above[0], above[1]];
    [inverse, new[1], new[2], new[3]]
}

/// (lam (W^-1 E c)_i)^2 for the row i whose c_{i-2} .. c_{i+2} are `c`.
#[inline(always)]
fn residual_squared<V: Vector>(row: &Row, lam: V, c: &[V; 5]) -> V {
    let p = row.penalty.map(V::load);
    let r = lam * (p[0] * c[0] + p[1] * c[1] + p[2] * c[2] + p[3] * c[3] + p[4] * c[4]);
    r * r
}

/// Row i's step (from the last up) of B = (U^T U)^-1's bands by Hutchinson and de Hoog's
/// recurrence, carrying [B_{i+1,i+1..i+3}, B_{i+2,i+2..i+3}, B_{i+3,i+3}] (zero past the
/// matrix, as U is); returns row i's part of tr(B X^T W X), which leaves out B's third band
/// as SciPy's does.
#[inline(always)]
fn inverse_step<V: Vector>(u: [V; 4], gram: &[Lanes; 4], carried: &mut [V; 6]) -> V {
    let [b11, b12, b13, b22, b23, b33] = *carried;
    let zero = V::splat(0.0);
    let b03 = zero - (u[1] * b13 + u[2] * b23 + u[3] * b33);
    let b02 = zero - (u[1] * b12 + u[2] * b22 + u[3] * b23);
    let b01 = zero - (u[1] * b11 + u[2] * b12 + u[3] * b13);
    let b00 = u[0] - (u[1] * b01 + u[2] * b02 + u[3] * b03);
    *carried = [b00, b01, b02, b11, b12, b22];
    let g = gram.map(V::load);
    b00 * g[0] + V::splat(2.0) * (b01 * g[1] + b02 * g[2])
}
