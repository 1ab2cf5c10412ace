//! Real roots of many piecewise cubics at once, as SciPy's `PPoly.solve` finds them (the
//! package's `splinegpu.interpolate` batches and its cubic `PPoly`s call this; the NumPy
//! fallback in `_ppoly.py` keeps the same rules for higher degrees).
//!
//! Piece p of a spline is `c0 v^3 + c1 v^2 + c2 v + c3` with v = x − start_p on
//! [start_p, end_p]. For the value y:
//! - its degree is that of its highest nonzero term (SciPy's rule, for coefficients given as
//!   they are: `Solve::exact`) or, for the package's own fits, of its highest term that is not
//!   negligible: nonzero and, over the piece's width h, larger than 8 eps of all its terms
//!   there (|c_m| h^(3−m)); a fitted spline's coefficients carry the fit's rounding where
//!   SciPy's are exact zeros;
//! - degree 1 and 2 in closed form (the quadratic's without cancellation); degree 3 in closed
//!   form where that decides real against complex as the companion matrix does (see
//!   `Depressed`), otherwise by the companion matrix's eigenvalues, which the caller supplies
//!   (NumPy's LAPACK, as SciPy's) for the pieces [`solve`] leaves undecided
//!   ([`Pending::finish`]);
//! - each real root gets one Newton step where the step is smaller than the root, and is kept
//!   inside its piece (the first piece open to the left and the last to the right when
//!   extrapolating);
//! - per spline in piece order: a breakpoint where the value jumps across y (with
//!   `discontinuity`), then the piece's roots by real part, then, for a piece equal to y
//!   everywhere, its start and NaN; a value equal to the one before it is dropped.

use rayon::prelude::*;

/// One piece: (c0, c1, c2, c3) as SciPy's rows, and the x it spans.
#[derive(Debug, Clone, Copy)]
pub struct Piece {
    /// c0..c3, the highest power first.
    pub c: [f64; 4],
    /// Where the piece starts (v = x - start).
    pub start: f64,
    /// Where it ends.
    pub end: f64,
}

/// Where the pieces come from: spline s owns pieces `first(s)..first(s + 1)`, numbered
/// across all splines (the numbers `undecided` gives and `Solve::decided` takes).
pub trait Source: Sync {
    /// The number of splines.
    fn splines(&self) -> usize;
    /// The number of spline s's first piece (`first(splines())` is the total).
    fn first(&self, s: usize) -> usize;
    /// Piece `j` of spline `s`.
    fn piece(&self, s: usize, j: usize) -> Piece;
}

/// Pieces given as arrays (copied, to outlive the call that gave them): `c` holds the rows
/// c0..c3 (`c[m * P + p]`), spline s owns pieces `offsets[s]..offsets[s + 1]`.
#[derive(Debug)]
pub struct Arrays {
    /// The rows c0..c3 of every piece, `c[m * P + p]`.
    pub c: Vec<f64>,
    /// Each piece's start.
    pub start: Vec<f64>,
    /// Each piece's end.
    pub end: Vec<f64>,
    /// Spline s's pieces are `offsets[s]..offsets[s + 1]`.
    pub offsets: Vec<usize>,
}

impl Source for Arrays {
    fn splines(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    fn first(&self, s: usize) -> usize {
        self.offsets[s]
    }

    fn piece(&self, s: usize, j: usize) -> Piece {
        let (n, p) = (self.start.len(), self.offsets[s] + j);
        Piece {
            c: [
                self.c[p],
                self.c[n + p],
                self.c[2 * n + p],
                self.c[3 * n + p],
            ],
            start: self.start[p],
            end: self.end[p],
        }
    }
}

/// A piece's polynomial minus y, as the root finder sees it.
enum Kind {
    /// Equal to y everywhere (no term left, and y is 0; or only a constant equal to y).
    Everywhere,
    /// A constant other than y: no root.
    Constant,
    /// Degree 1 to 3: the coefficients from the leading one, highest first, y subtracted.
    Degree(usize, [f64; 4]),
}

fn kind(c: [f64; 4], width: f64, y: f64, exact: bool) -> Kind {
    let size: [f64; 4] = std::array::from_fn(|m| c[m].abs() * width.abs().powi(3 - m as i32));
    let total: f64 = size.iter().sum();
    let lead = (0..4).find(|&m| c[m] != 0.0 && (exact || size[m] > 8.0 * f64::EPSILON * total));
    let constant = c[3] - y;
    match lead {
        None if y == 0.0 => Kind::Everywhere,
        None => Kind::Constant,
        Some(3) if constant == 0.0 => Kind::Everywhere,
        Some(3) => Kind::Constant,
        Some(lead) => {
            let mut a = [0.0; 4];
            a[..4 - lead].copy_from_slice(&c[lead..]);
            a[3 - lead] = constant;
            Kind::Degree(3 - lead, a)
        }
    }
}

/// Up to three real roots, ascending.
#[derive(Debug, Clone, Copy, Default)]
struct Real {
    roots: [f64; 3],
    len: usize,
}

impl Real {
    fn of(roots: &[f64]) -> Self {
        let mut out = Self::default();
        out.roots[..roots.len()].copy_from_slice(roots);
        out.len = roots.len();
        out
    }

    fn as_slice(&self) -> &[f64] {
        &self.roots[..self.len]
    }
}

/// A cubic a0 u^3 + a1 u^2 + a2 u + a3 as t^3 + p t + q with u = t − b/3 (b, c, d the
/// coefficients over a0), where its discriminant 4p^3 + 27q^2 decides real against complex
/// as the companion matrix does: not within 1e-6 of its terms (a nearly double root, which
/// rounding may make real or complex), and a3 != 0 (a root at the piece's start).
#[derive(Debug)]
struct Depressed {
    p: f64,
    q: f64,
    shift: f64,
    disc: f64,
}

impl Depressed {
    fn of(a: &[f64; 4]) -> Option<Self> {
        let (b, c, d) = (a[1] / a[0], a[2] / a[0], a[3] / a[0]);
        let shift = b / 3.0;
        let p = c - b * shift;
        let q = d - shift * (c - 2.0 * shift * shift);
        let disc = 4.0 * p.powi(3) + 27.0 * q * q;
        let scale = 4.0 * p.abs().powi(3) + 27.0 * q * q;
        (disc.is_finite() && disc.abs() > 1e-6 * scale && a[3] != 0.0).then_some(Self {
            p,
            q,
            shift,
            disc,
        })
    }

    /// The real roots in u, ascending: three by the trigonometric form for a negative
    /// discriminant, else one by Cardano's (its two terms formed without cancellation).
    fn roots(&self) -> Real {
        let Self { p, q, shift, disc } = *self;
        if disc < 0.0 {
            let r = 2.0 * (-p / 3.0).sqrt();
            let angle = (3.0 * q / (p * r)).clamp(-1.0, 1.0).acos() / 3.0;
            // r cos(angle - 2 pi j / 3) for j = 0, 1, 2, from one sine and cosine.
            let (sin, cos) = angle.sin_cos();
            let half = 0.75f64.sqrt() * sin;
            let mut roots = [
                r * cos - shift,
                r * (-0.5 * cos + half) - shift,
                r * (-0.5 * cos - half) - shift,
            ];
            roots.sort_by(f64::total_cmp);
            return Real { roots, len: 3 };
        }
        let root = (q * q / 4.0 + p.powi(3) / 27.0).sqrt();
        // −sign(q) with sign(0) = 0, as NumPy's.
        let sign = if q > 0.0 {
            1.0
        } else if q < 0.0 {
            -1.0
        } else {
            0.0
        };
        let mut big = -sign * (q.abs() / 2.0 + root).cbrt();
        if big == 0.0 {
            big = (-q).cbrt();
        }
        let small = if big != 0.0 { -p / (3.0 * big) } else { 0.0 };
        Real::of(&[big + small - shift])
    }
}

/// The real roots of a0 u^2 + a1 u + a2: none for a negative discriminant, else the larger in
/// size by the formula and the other from the product (no cancellation), in that order.
fn quadratic(a: &[f64; 4]) -> Real {
    let (a0, a1, a2) = (a[0], a[1], a[2]);
    let d = a1 * a1 - 4.0 * a0 * a2;
    if d < 0.0 {
        return Real::default();
    }
    if d == 0.0 {
        let r = -a1 / (2.0 * a0);
        return Real::of(&[r, r]);
    }
    let root = d.sqrt();
    if a1 < 0.0 {
        Real::of(&[(2.0 * a2) / (-a1 + root), (-a1 + root) / (2.0 * a0)])
    } else {
        Real::of(&[(-a1 - root) / (2.0 * a0), (2.0 * a2) / (-a1 - root)])
    }
}

/// Derivative `d` (0 or 1) of a piece's full cubic at local v.
fn value(c: &[f64; 4], v: f64, d: usize) -> f64 {
    if d == 0 {
        ((c[0] * v + c[1]) * v + c[2]) * v + c[3]
    } else {
        (3.0 * c[0] * v + 2.0 * c[1]) * v + c[2]
    }
}

/// The options of one solve.
#[derive(Debug)]
pub struct Solve {
    /// The value whose x are wanted.
    pub y: f64,
    /// Whether a jump through y between pieces counts as a root (SciPy's `discontinuity`).
    pub discontinuity: bool,
    /// Whether the end pieces continue past the breakpoints.
    pub extrapolate: bool,
    /// Whether a piece's degree is that of its highest nonzero term (SciPy's rule, for
    /// coefficients given as they are), rather than of its highest term that is not
    /// negligible over the piece (for the package's fits, which carry rounding there).
    pub exact: bool,
}

/// A piece the closed forms leave to the companion matrix's eigenvalues: its number and
/// coefficients.
pub type Undecided = (usize, [f64; 4]);

/// Every spline's roots but those of the splines with [`Undecided`] pieces, which wait for
/// the pieces' eigenvalues ([`Pending::finish`]).
#[derive(Debug)]
pub struct Pending {
    per_spline: Vec<Vec<f64>>,
    /// The undecided pieces, ascending.
    pub undecided: Vec<Undecided>,
    waiting: Vec<usize>,
}

/// Every spline's roots (see the module's rules), in one pass over the pieces; a cubic the
/// closed form does not decide is left undecided, with its spline.
pub fn solve<S: Source + ?Sized>(source: &S, how: &Solve) -> Pending {
    let found: Vec<(Vec<f64>, Vec<Undecided>)> = (0..source.splines())
        .into_par_iter()
        .with_min_len(64)
        .map(|s| spline_roots(source, s, how, None))
        .collect();
    let mut pending = Pending {
        per_spline: Vec::with_capacity(found.len()),
        undecided: Vec::new(),
        waiting: Vec::new(),
    };
    for (s, (roots, undecided)) in found.into_iter().enumerate() {
        if !undecided.is_empty() {
            pending.waiting.push(s);
            pending.undecided.extend(undecided);
        }
        pending.per_spline.push(roots);
    }
    pending
}

impl Pending {
    /// The roots of every spline, the waiting ones found again with `decided`: the real
    /// parts of the undecided pieces' eigenvalues, (piece, root) sorted by piece, each
    /// piece's ascending. Returns (roots, offsets (S + 1)).
    pub fn finish<S: Source + ?Sized>(
        mut self,
        source: &S,
        how: &Solve,
        decided: &[(usize, f64)],
    ) -> (Vec<f64>, Vec<i64>) {
        let again: Vec<Vec<f64>> = self
            .waiting
            .par_iter()
            .map(|&s| spline_roots(source, s, how, Some(decided)).0)
            .collect();
        for (&s, roots) in self.waiting.iter().zip(again) {
            self.per_spline[s] = roots;
        }
        let mut offsets = Vec::with_capacity(self.per_spline.len() + 1);
        offsets.push(0i64);
        let mut roots = Vec::with_capacity(self.per_spline.iter().map(Vec::len).sum());
        for one in &self.per_spline {
            roots.extend_from_slice(one);
            offsets.push(roots.len() as i64);
        }
        (roots, offsets)
    }
}

/// Spline s's roots, and its undecided pieces: without `decided` they give no roots; with
/// it, theirs.
fn spline_roots<S: Source + ?Sized>(
    source: &S,
    s: usize,
    how: &Solve,
    decided: Option<&[(usize, f64)]>,
) -> (Vec<f64>, Vec<Undecided>) {
    let mut out: Vec<f64> = Vec::new();
    let mut undecided = Vec::new();
    // The last event's value (kept or not): a value equal to it is dropped.
    let mut last: Option<f64> = None;
    let mut push = |v: f64, always: bool, out: &mut Vec<f64>| {
        if always || last != Some(v) {
            out.push(v);
        }
        last = Some(v);
    };
    let (first, count) = (source.first(s), source.first(s + 1) - source.first(s));
    let y = how.y;
    let decided = decided.unwrap_or(&[]);
    let mut decided = decided[decided.partition_point(|&(p, _)| p < first)..]
        .iter()
        .peekable();
    let mut previous: Option<Piece> = None;
    for j in 0..count {
        let piece = source.piece(s, j);
        let Piece { c, start, end } = piece;
        if let (true, Some(before)) = (how.discontinuity, previous) {
            let before = value(&before.c, before.end - before.start, 0) - y;
            let after = c[3] - y;
            if (before < 0.0 && after > 0.0) || (before > 0.0 && after < 0.0) {
                push(start, false, &mut out);
            }
        }
        previous = Some(piece);
        let candidates = match kind(c, end - start, y, how.exact) {
            Kind::Everywhere => {
                push(start, true, &mut out);
                push(f64::NAN, true, &mut out);
                continue;
            }
            Kind::Constant => continue,
            Kind::Degree(1, a) => Real::of(&[-a[1] / a[0]]),
            Kind::Degree(2, a) => quadratic(&a),
            Kind::Degree(_, a) => match Depressed::of(&a) {
                Some(cubic) => cubic.roots(),
                None => {
                    undecided.push((first + j, c));
                    let mut roots = Real::default();
                    while let Some(&&(q, r)) = decided.peek() {
                        if q > first + j {
                            break;
                        }
                        if q == first + j && roots.len < 3 {
                            roots.roots[roots.len] = r;
                            roots.len += 1;
                        }
                        decided.next();
                    }
                    roots
                }
            },
        };
        let (open_left, open_right) =
            (how.extrapolate && j == 0, how.extrapolate && j + 1 == count);
        for &real in candidates.as_slice() {
            let f = value(&c, real, 0) - y;
            let df = value(&c, real, 1);
            let step = if df != 0.0 { f / df } else { 0.0 };
            let real = if df != 0.0 && step.abs() < real.abs() {
                real - step
            } else {
                real
            };
            let root = real + start;
            // Not past a closed end (a NaN only where both ends are open).
            let inside = (root <= end || open_right) && (start <= root || open_left);
            if inside {
                push(root, false, &mut out);
            }
        }
    }
    (out, undecided)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arrays(c: [f64; 4], start: f64, end: f64) -> Arrays {
        Arrays {
            c: c.to_vec(),
            start: vec![start],
            end: vec![end],
            offsets: vec![0, 1],
        }
    }

    fn one(c: [f64; 4], start: f64, end: f64, y: f64, extrapolate: bool) -> Vec<f64> {
        let pieces = arrays(c, start, end);
        let how = Solve {
            y,
            discontinuity: true,
            extrapolate,
            exact: false,
        };
        let pending = solve(&pieces, &how);
        assert!(pending.undecided.is_empty());
        pending.finish(&pieces, &how, &[]).0
    }

    #[test]
    fn a_cubic_with_three_known_roots() {
        // (v - 1)(v - 2)(v - 3) = v^3 - 6 v^2 + 11 v - 6 on [10, 14]: roots at 11, 12, 13.
        let roots = one([1.0, -6.0, 11.0, -6.0], 10.0, 14.0, 0.0, false);
        assert_eq!(roots.len(), 3);
        for (got, want) in roots.iter().zip([11.0, 12.0, 13.0]) {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
    }

    #[test]
    fn one_real_root_and_the_ends() {
        // v^3 + v - 2 has the one real root v = 1; outside [0, 0.5] unless extrapolating.
        assert!(one([1.0, 0.0, 1.0, -2.0], 0.0, 0.5, 0.0, false).is_empty());
        let roots = one([1.0, 0.0, 1.0, -2.0], 0.0, 0.5, 0.0, true);
        assert_eq!(roots.len(), 1);
        assert!((roots[0] - 1.0).abs() < 1e-15);
        // Solving for y = 3 on 2 v: v = 1.5.
        assert_eq!(one([0.0, 0.0, 2.0, 0.0], 0.0, 2.0, 3.0, false), vec![1.5]);
    }

    #[test]
    fn a_piece_equal_to_y_gives_its_start_and_nan() {
        let roots = one([0.0, 0.0, 0.0, 4.0], 1.0, 2.0, 4.0, false);
        assert_eq!(roots[0], 1.0);
        assert!(roots[1].is_nan());
    }

    #[test]
    fn a_double_root_waits_for_the_eigenvalues() {
        // (v - 1)^2 (v - 3): its discriminant is zero, so the closed form does not decide.
        let a = [1.0, -5.0, 7.0, -3.0];
        let pieces = arrays(a, 0.0, 4.0);
        let how = Solve {
            y: 0.0,
            discontinuity: true,
            extrapolate: false,
            exact: false,
        };
        let pending = solve(&pieces, &how);
        assert_eq!(pending.undecided, vec![(0, a)]);
        // The eigenvalues 1, 1, 3 as the caller would hand them over: 1 once, then 3.
        let (roots, offsets) = pending.finish(&pieces, &how, &[(0, 1.0), (0, 1.0), (0, 3.0)]);
        assert_eq!(offsets, vec![0, 2]);
        assert_eq!(roots, vec![1.0, 3.0]);
    }
}
