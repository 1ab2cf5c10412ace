//! Arc length of cubic segments in any dimension, and its inverse.
//!
//! A segment P(u) = A u³ + B u² + C u + D, u in [0, 1], has speed |P'(u)| = sqrt(Q(u)) with
//! Q(u) = |3A u² + 2B u + C|², a polynomial of degree 4 whatever the dimension (the speed itself
//! is evaluated from P''s components, see [`Speed`]). The length ∫ sqrt(Q) du is integrated by adaptive
//! Gauss–Legendre quadrature: a piece is accepted when the 8-point rule on it and the sum of the
//! rule on its two halves agree within its share of the accuracy, else it is split (as kurbo's
//! `CubicBez::arclen` and Geometric Tools' `ParametricCurve` do, with a different error test).
//! Where the speed vanishes (a cusp, or coincident control points) Q has a double root and the
//! speed a kink, which the subdivision isolates; nothing divides by the speed unguarded.
//!
//! The segment is first cut at the critical points of Q (zeros of the cubic Q'), so that on
//! each part the speed is monotone and a zero of it lies only at a part's end: a kink strictly
//! inside a piece, but outside the rule's nodes, would pass the halving test unseen.
//!
//! The accepted pieces, with their cumulative lengths, make an [`ArcTable`]: the length from
//! u = 0 to any u is the length of the pieces before it plus one 8-point rule inside its piece,
//! and the inverse (the u at a given length) is a safeguarded Newton iteration inside the
//! piece that holds the length (bisection where the speed vanishes or Newton leaves the
//! bracket), started from the quintic Hermite interpolant of u(s) on the piece (its ends' u,
//! du/ds and d²u/ds²) and stopped by a bound rather than one more quadrature: a Newton
//! step of δ in u from a point whose length error is known leaves an error of at most
//! ½ max|P''| δ², since |d speed/du| = |P'·P''|/|P'| <= |P''|.
//!
//! A rational segment (weighted NURBS, see [`rational`](crate::rational)) goes the same way
//! with its speed |R'(u)| by the quotient rule: the quadrature and the models are unchanged,
//! its critical points are the sign changes of R'·R'' on a grid of 64 intervals (bisected to
//! f64 precision; two within one interval may pass unseen, which costs subdivisions, not
//! accuracy, where the speed does not vanish), and max|P''| in the Newton bound is the proven
//! bound of [`RationalCubic::second_derivative_bound`].

use crate::rational::{Denominator, RationalCubic, quotient};
use crate::segment::{Segment, SegmentTable};

/// Accuracy of arc lengths when the caller has no reason to choose: an error of at most 1e-12
/// of the length measured.
pub const DEFAULT_ARCLEN_ACCURACY: f64 = 1e-12;

/// Gauss–Legendre nodes on [-1, 1] (the positive half) and their weights, 8 points.
const GL8_NODES: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GL8_WEIGHTS: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// The deepest subdivision: pieces no shorter than 2^-40 in u.
const MAX_DEPTH: u32 = 40;

/// A segment's speed |P'(u)|, P'(u) = a u² + b u + c with a = 3A, b = 2B, c = C.
///
/// The speed is evaluated from the components of P', not from the expanded quartic
/// Q(u) = |P'(u)|²: where the speed is small against the coefficients (a near-cusp of a long
/// segment), Q's rounding error of ~1e-16 of its coefficients' square would become an error of
/// ~1e-8 of the coefficients in sqrt(Q); the components keep it near 1e-16 of them. Q's
/// coefficients serve only to find its critical points.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Speed {
    /// (a_k, b_k, c_k) for each coordinate k, divided by `scale`; on a rational segment its
    /// numerator's (A_k, B_k, C_k), divided by `scale`.
    terms: Vec<[f64; 3]>,
    /// A power of two near the largest coefficient: the squares of scaled terms neither
    /// overflow nor underflow, whatever the curve's size (points near 1e200 included).
    scale: f64,
    /// W(u) of a rational segment.
    denominator: Option<Denominator>,
}

/// Intervals of the grid on which a rational segment's critical points are looked for.
const RATIONAL_GRID: usize = 64;

impl Speed {
    /// The derivative's coefficients of `segment`.
    pub(crate) fn of(segment: &Segment<'_>) -> Self {
        let [pa, pb, pc, _] = segment.power();
        if let Some(w) = segment.denominator() {
            let largest = (pa.iter().chain(pb).chain(pc)).fold(0.0f64, |m, v| m.max(v.abs()));
            let scale = power_of_two_near(largest);
            return Self {
                terms: (0..pa.len())
                    .map(|k| [pa[k] / scale, pb[k] / scale, pc[k] / scale])
                    .collect(),
                scale,
                denominator: Some(w),
            };
        }
        let largest = (0..pa.len())
            .map(|k| {
                (3.0 * pa[k])
                    .abs()
                    .max((2.0 * pb[k]).abs())
                    .max(pc[k].abs())
            })
            .fold(0.0f64, f64::max);
        let scale = power_of_two_near(largest);
        Self {
            terms: (0..pa.len())
                .map(|k| [3.0 * pa[k] / scale, 2.0 * pb[k] / scale, pc[k] / scale])
                .collect(),
            scale,
            denominator: None,
        }
    }

    /// R' and R'' of a rational segment at u, scaled: Σ R'², Σ R'·R'', Σ R''².
    fn rational_at(&self, w: &Denominator, u: f64) -> (f64, f64, f64) {
        let w = w.at(u);
        let (mut q, mut dot, mut bend) = (0.0, 0.0, 0.0);
        for &[a, b, c] in &self.terms {
            let r = quotient::<2>(a, b, c, u, &w);
            q += r[1] * r[1];
            dot += r[1] * r[2];
            bend += r[2] * r[2];
        }
        (q, dot, bend)
    }

    /// |P'(u)|.
    #[inline]
    pub(crate) fn at(&self, u: f64) -> f64 {
        if let Some(w) = &self.denominator {
            return self.rational_at(w, u).0.sqrt() * self.scale;
        }
        self.terms
            .iter()
            .map(|[a, b, c]| {
                let d = c + u * (b + u * a);
                d * d
            })
            .sum::<f64>()
            .sqrt()
            * self.scale
    }

    /// The speed and its derivative P'·P''/|P'| at u (0 where the speed vanishes).
    #[inline]
    pub(crate) fn with_slope(&self, u: f64) -> (f64, f64) {
        if let Some(w) = &self.denominator {
            let (q, dot, _) = self.rational_at(w, u);
            let v = q.sqrt();
            let slope = if v > 0.0 { dot / v * self.scale } else { 0.0 };
            return (v * self.scale, slope);
        }
        let (mut q, mut dot) = (0.0, 0.0);
        for [a, b, c] in &self.terms {
            let d = c + u * (b + u * a);
            q += d * d;
            dot += d * (b + 2.0 * u * a);
        }
        let v = q.sqrt();
        let slope = if v > 0.0 { dot / v * self.scale } else { 0.0 };
        (v * self.scale, slope)
    }

    /// Q(u) = |P'(u)|² = (a·a) u⁴ + 2(a·b) u³ + (b·b + 2 a·c) u² + 2(b·c) u + c·c, as
    /// [q0, q1, q2, q3, q4].
    fn quartic(&self) -> [f64; 5] {
        let (mut aa, mut ab, mut bb, mut ac, mut bc, mut cc) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for [a, b, c] in &self.terms {
            aa += a * a;
            ab += a * b;
            bb += b * b;
            ac += a * c;
            bc += b * c;
            cc += c * c;
        }
        [cc, 2.0 * bc, bb + 2.0 * ac, 2.0 * ab, aa]
    }

    /// The zeros of Q'(u) = q1 + 2 q2 u + 3 q3 u² + 4 q4 u³ strictly inside (0, 1), in order.
    /// The zeros of Q'' (a quadratic, in closed form) cut [0, 1] into parts on which Q' is
    /// monotone, so each part holds at most one zero, found by bisection to f64 precision.
    pub(crate) fn critical_points(&self) -> Vec<f64> {
        if let Some(w) = &self.denominator {
            return self.rational_critical_points(w);
        }
        let q = &self.quartic();
        let dq = |u: f64| q[1] + u * (2.0 * q[2] + u * (3.0 * q[3] + u * 4.0 * q[4]));
        // Q'' = 2 q2 + 6 q3 u + 12 q4 u².
        let mut cuts = vec![0.0];
        cuts.extend(
            quadratic_roots(12.0 * q[4], 6.0 * q[3], 2.0 * q[2])
                .into_iter()
                .filter(|&r| r > 0.0 && r < 1.0),
        );
        cuts.push(1.0);
        cuts.sort_by(f64::total_cmp);
        let mut roots = Vec::new();
        for w in cuts.windows(2) {
            let (mut lo, mut hi) = (w[0], w[1]);
            let (flo, fhi) = (dq(lo), dq(hi));
            if flo == 0.0 || fhi == 0.0 || (flo < 0.0) == (fhi < 0.0) {
                // A zero at a cut is a cut already, or lies at 0 or 1; none inside otherwise.
                if fhi == 0.0 && hi < 1.0 {
                    roots.push(hi);
                }
                continue;
            }
            // 64 halvings of an interval within [0, 1] reach f64 resolution.
            for _ in 0..64 {
                let mid = 0.5 * (lo + hi);
                if (dq(mid) < 0.0) == (flo < 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            roots.push(0.5 * (lo + hi));
        }
        // Q's inflections (the cuts) bound the parts too: a kink cannot hide there either.
        roots.extend(cuts[1..cuts.len() - 1].iter().copied());
        roots.sort_by(f64::total_cmp);
        roots.dedup();
        roots
    }

    /// The sign changes of R'·R'' (the speed's extrema) on a rational segment, found on a
    /// grid of [`RATIONAL_GRID`] intervals and bisected to f64 precision, in order.
    fn rational_critical_points(&self, w: &Denominator) -> Vec<f64> {
        let slope = |u: f64| self.rational_at(w, u).1;
        let mut roots = Vec::new();
        let mut lo = 0.0;
        let mut f_lo = slope(0.0);
        for i in 1..=RATIONAL_GRID {
            let hi = i as f64 / RATIONAL_GRID as f64;
            let f_hi = slope(hi);
            if f_hi == 0.0 && hi < 1.0 {
                roots.push(hi);
            } else if f_lo != 0.0 && f_hi != 0.0 && (f_lo < 0.0) != (f_hi < 0.0) {
                let (mut a, mut b) = (lo, hi);
                for _ in 0..64 {
                    let mid = 0.5 * (a + b);
                    if (slope(mid) < 0.0) == (f_lo < 0.0) {
                        a = mid;
                    } else {
                        b = mid;
                    }
                }
                roots.push(0.5 * (a + b));
            }
            (lo, f_lo) = (hi, f_hi);
        }
        roots
    }

    /// |P''(u)|.
    pub(crate) fn bend_at(&self, u: f64) -> f64 {
        if let Some(w) = &self.denominator {
            return self.rational_at(w, u).2.sqrt() * self.scale;
        }
        (self.terms.iter())
            .map(|[a, b, _]| (2.0 * a * u + b).powi(2))
            .sum::<f64>()
            .sqrt()
            * self.scale
    }

    /// max |P''(u)| over [0, 1]: P'' = 2a u + b is linear, and a norm is convex, so the
    /// largest is at an end.
    pub(crate) fn bend(&self) -> f64 {
        if let Some(w) = self.denominator {
            let coefficient = |i: usize| self.terms.iter().map(|t| t[i]).collect::<Vec<_>>();
            let (a, b, c) = (coefficient(0), coefficient(1), coefficient(2));
            let cubic = RationalCubic {
                a: &a,
                b: &b,
                c: &c,
                w,
            };
            return cubic.second_derivative_bound() * self.scale;
        }
        let norm = |f: &dyn Fn(&[f64; 3]) -> f64| {
            self.terms.iter().map(|t| f(t) * f(t)).sum::<f64>().sqrt()
        };
        norm(&|[_, b, _]| *b).max(norm(&|[a, b, _]| 2.0 * a + b)) * self.scale
    }

    /// The 8-point Gauss–Legendre rule for ∫ speed over [a, b]. The eight nodes are evaluated
    /// side by side (coordinate by coordinate, then eight square roots), which the compiler
    /// turns into vector instructions.
    #[inline]
    pub(crate) fn gl8(&self, a: f64, b: f64) -> f64 {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        if self.denominator.is_some() {
            let mut sum = 0.0;
            for i in 0..4 {
                let x = half * GL8_NODES[i];
                sum += GL8_WEIGHTS[i] * (self.at(mid - x) + self.at(mid + x));
            }
            return sum * half;
        }
        let u: [f64; 8] = std::array::from_fn(|i| {
            let x = GL8_NODES[i % 4];
            if i < 4 {
                mid - half * x
            } else {
                mid + half * x
            }
        });
        let mut q = [0.0; 8];
        for [a, b, c] in &self.terms {
            for i in 0..8 {
                let d = c + u[i] * (b + u[i] * a);
                q[i] += d * d;
            }
        }
        let mut sum = 0.0;
        for i in 0..4 {
            sum += GL8_WEIGHTS[i] * (q[i].sqrt() + q[i + 4].sqrt());
        }
        sum * half * self.scale
    }
}

/// 2^e with 2^e <= `x` < 2^(e+1) for a finite positive `x`, else 1: dividing by it is exact.
pub(crate) fn power_of_two_near(x: f64) -> f64 {
    if x.is_finite() && x > 0.0 {
        2f64.powi(x.log2().floor() as i32)
    } else {
        1.0
    }
}

/// The real roots of a x² + b x + c (none, one or two; `a` may be 0), computed without
/// cancellation.
fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    if a == 0.0 {
        return if b == 0.0 { vec![] } else { vec![-c / b] };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return vec![];
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    if q == 0.0 {
        return vec![0.0];
    }
    vec![q / a, c / q]
}

/// A segment's arc length as pieces of u on which the quadrature is accurate: `u[k]..u[k + 1]`
/// has length `s[k + 1] − s[k]`; `u` runs from 0 to 1 and `s` from 0 to the segment's length.
/// Beside them, coarser pieces on each of which a polynomial models the length (a first guess
/// of the inverse solves it).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ArcTable {
    speed: Speed,
    u: Vec<f64>,
    s: Vec<f64>,
    /// The model's pieces: `model_u[k]..model_u[k + 1]` has length `model_s[k + 1] −
    /// model_s[k]` (read off the quadrature's pieces).
    model_u: Vec<f64>,
    model_s: Vec<f64>,
    /// Per model piece, the length from its start as c1 x + … + c5 x⁵ in
    /// x = (u − model_u[k]) / (model_u[k + 1] − model_u[k]), within the table's model accuracy
    /// (see [`ArcTable::new`]).
    model: Vec<[f64; 5]>,
    /// The accuracy of the model, in length.
    model_accuracy: f64,
    /// The explicit inverse (with a model): piece k starts at length `inverse_s[k]` (the
    /// last ends at the segment's length) and maps its lengths to u by a polynomial (see
    /// [`InversePiece`], [`ArcTable::place`]).
    inverse_s: Vec<f64>,
    inverse: Vec<InversePiece>,
    /// [`Speed::bend`]: bounds how fast the speed changes.
    bend: f64,
}

/// The accuracy of the length model, relative to the curve's length, and of its explicit
/// inverse against it: the samples' places (the CPU's in f64, the GPU's in f32, which adds
/// errors of this order) are the inverse's; a precise inverse's Newton steps start from the
/// model's solution.
pub(crate) const MODEL_ACCURACY: f64 = 1e-7;

/// Steps of the safeguarded Newton iteration that solves a model piece: its solution moves
/// less than the model's error after these from the linear guess (quadratic convergence), or
/// within 2^-12 of the piece where the speed vanishes at an end.
pub(crate) const SOLVE_STEPS: u32 = 12;

/// The model's error is measured at these x of each piece (see [`ArcTable::new`]).
const CHECK_POINTS: [f64; 2] = [0.25, 0.75];

impl ArcTable {
    /// The table of `segment`: each piece's length within its share (by its width in u) of
    /// the absolute `accuracy`, and the length model within `model_accuracy` (infinite: one
    /// model piece per part between critical points).
    ///
    /// The model on a piece is the quintic Hermite interpolant of s(u) through the piece's
    /// ends, with ds/du = v and d²s/du² = v' there (v the speed, v' its derivative in u).
    /// Its error is x³(1−x)³ w⁶ s⁽⁶⁾(ξ)/720 on a piece of width w, largest near the middle and
    /// shrinking 64-fold with each halving; s is as smooth as the speed, which has a kink only
    /// where it vanishes (model pieces start as the parts between such points). The
    /// model's length is compared with the quadrature's at x = 1/4 and 3/4 (two points, so
    /// that an error changing sign in the middle is not missed), and the piece is halved while
    /// either is off by more than a quarter of `model_accuracy`. A piece no longer than
    /// `model_accuracy` needs no test: any u in it lies within its length.
    pub(crate) fn new(segment: &Segment<'_>, accuracy: f64, model_accuracy: f64) -> Self {
        let speed = Speed::of(segment);
        let mut table = Self {
            speed: speed.clone(),
            u: vec![0.0],
            s: vec![0.0],
            model_u: vec![0.0],
            model_s: vec![0.0],
            model: Vec::new(),
            model_accuracy,
            inverse_s: Vec::new(),
            inverse: Vec::new(),
            bend: speed.bend(),
        };
        // Between consecutive critical points of Q the speed is monotone, so a zero of the
        // speed (a kink of |P'|) can only be an end of a part: a kink strictly inside a piece
        // but outside the rule's nodes would pass the halving test unseen.
        let mut cuts = speed.critical_points();
        cuts.push(1.0);
        let mut a = 0.0;
        for &b in &cuts {
            let tol = (accuracy * (b - a)).max(f64::MIN_POSITIVE);
            table.subdivide(a, b, speed.gl8(a, b), tol, 0);
            a = b;
        }
        // The model is as smooth as the speed, which has a kink only where it vanishes: model
        // pieces start as the parts between such critical points (or near-zeros, below 1e-9 of
        // the fastest critical point or end).
        let fastest = (cuts.iter().chain(&[0.0]))
            .map(|&c| speed.at(c))
            .fold(0.0, f64::max);
        cuts.retain(|&c| c == 1.0 || speed.at(c) <= 1e-9 * fastest);
        let mut a = 0.0;
        for (i, &b) in cuts.iter().enumerate() {
            // Away from a zero of the speed, it grows as |P''| times the distance: the slopes
            // at a kink are the one-sided ones.
            let mut ends = (speed.with_slope(a), speed.with_slope(b));
            if i > 0 {
                ends.0.1 = speed.bend_at(a);
            }
            if b < 1.0 {
                ends.1.1 = -speed.bend_at(b);
            }
            let length = table.length_to(b) - table.length_to(a);
            table.fit_model(a, b, length.max(0.0), ends, model_accuracy, 0);
            a = b;
        }
        if model_accuracy.is_finite() {
            for k in 0..table.model.len() {
                table.fit_inverse(k, (0.0, 1.0), 0);
            }
        }
        table
    }

    /// Appends [xa, xb] of model piece `k` (x its own parameter, s_k(x) its model of the
    /// length) as pieces of the explicit inverse, halved until each is within the model's
    /// accuracy of the model. On a piece, x is the degree-5 polynomial in the length through
    /// the model at the six Chebyshev–Lobatto points of x, and its error is measured at the
    /// five points of x between them: the model's length at the polynomial's x against the
    /// length asked. Only the model's polynomial is evaluated. A piece no longer than the
    /// accuracy needs no test. Where the speed vanishes at a piece's end, x(s) grows as √s
    /// there and the pieces halve toward it.
    fn fit_inverse(&mut self, k: usize, (xa, xb): (f64, f64), depth: u32) {
        let (c, tol) = (&self.model[k], self.model_accuracy);
        // A piece of length 0 (a segment that stands still) may end a rounding below its
        // start.
        let length = (self.model_s[k + 1] - self.model_s[k]).max(0.0);
        let model = |x: f64| {
            if x >= 1.0 {
                length
            } else {
                polynomial(c, x).clamp(0.0, length)
            }
        };
        let (sa, sb) = (model(xa), model(xb));
        let (mu, w) = (self.model_u[k], self.model_u[k + 1] - self.model_u[k]);
        let mut piece = InversePiece::linear((mu + xa * w, mu + xb * w), (sa, sb));
        if sb - sa > tol && xb > xa {
            let nodes: [f64; 6] = std::array::from_fn(|i| match i {
                0 => 0.0,
                5 => 1.0,
                _ => (model(xa + LOBATTO[i] * (xb - xa)) - sa) / (sb - sa),
            });
            let increasing = nodes.windows(2).all(|pair| pair[0] < pair[1]);
            let fits = increasing && {
                let p = interpolate(&nodes, &LOBATTO);
                let fits = MIDPOINTS.iter().all(|&m| {
                    let s = model(xa + m * (xb - xa));
                    let tau = (s - sa) / (sb - sa);
                    let x = xa + (xb - xa) * evaluate5(&p, tau).clamp(0.0, 1.0);
                    (model(x) - s).abs() <= tol
                });
                piece.c = p;
                fits
            };
            if !fits && depth < MAX_DEPTH {
                let mid = 0.5 * (xa + xb);
                self.fit_inverse(k, (xa, mid), depth + 1);
                self.fit_inverse(k, (mid, xb), depth + 1);
                return;
            }
            if !fits {
                piece.c = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
            }
        }
        // Lengths from the segment's start: the model piece's start plus the model's.
        piece.s0 += self.model_s[k];
        self.inverse_s.push(piece.s0);
        self.inverse.push(piece);
    }

    /// The u in [0, 1] at which the length from 0 reaches `s` (clamped to [0, length]) by
    /// the explicit inverse: within twice the model's accuracy in length (the model's own
    /// error and the inverse's against it, each measured as [`ArcTable::new`] says), one
    /// polynomial a length. `hint` is the inverse piece the last (nondecreasing) length
    /// fell in (0 for the first); the answer does not depend on it.
    #[inline]
    pub(crate) fn place(&self, s: f64, hint: &mut usize) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        if s >= self.length() {
            return 1.0;
        }
        let pieces = self.inverse.len();
        let k = last_before(&self.inverse_s, (*hint).min(pieces - 1), |x| x < s);
        *hint = k;
        self.inverse[k].at(s)
    }

    /// The inverse piece `k` and the lengths it takes, as [`ArcTable::place`] chooses pieces:
    /// above its start and up to the next one's (the last: up to the segment's length; at or
    /// beyond it, u = 1).
    pub(crate) fn inverse_piece(&self, k: usize) -> (&InversePiece, f64) {
        let last = self.inverse_s.get(k + 1).copied().unwrap_or(f64::INFINITY);
        (&self.inverse[k], last)
    }

    /// Appends [a, b] (whose 8-point estimate is `whole`) as quadrature pieces, split until
    /// the quadrature is within `tol`.
    fn subdivide(&mut self, a: f64, b: f64, whole: f64, tol: f64, depth: u32) {
        let speed = &self.speed;
        let mid = 0.5 * (a + b);
        let (left, right) = (speed.gl8(a, mid), speed.gl8(mid, b));
        // A tolerance below a few ulps of the piece's own length only chases rounding: it
        // would split without end, and the sum of the many pieces would gather the rounding.
        let tol = tol.max(4.0 * f64::EPSILON * (left + right));
        // A non-finite estimate cannot improve by splitting: stop rather than split 2^40 ways.
        let settled = !(left + right).is_finite() || (left + right - whole).abs() <= tol;
        if depth >= MAX_DEPTH || settled {
            // Both halves are kept: their sum is the better estimate.
            let s = self.s[self.s.len() - 1];
            self.u.extend([mid, b]);
            self.s.extend([s + left, s + left + right]);
            return;
        }
        self.subdivide(a, mid, left, 0.5 * tol, depth + 1);
        self.subdivide(mid, b, right, 0.5 * tol, depth + 1);
    }

    /// Appends [a, b] of `length` (the speed and its slope at its ends in `ends`) as model
    /// pieces, halved until each model is within `accuracy`.
    fn fit_model(
        &mut self,
        a: f64,
        b: f64,
        length: f64,
        ends: ((f64, f64), (f64, f64)),
        accuracy: f64,
        depth: u32,
    ) {
        let w = b - a;
        let ((v0, dv0), (v1, dv1)) = ends;
        let c = quintic_hermite(length, v0 * w, v1 * w, dv0 * w * w, dv1 * w * w);
        let start = self.length_to(a);
        if depth < MAX_DEPTH && length > accuracy && !self.model_fits(a, b, start, &c, accuracy) {
            let mid = 0.5 * (a + b);
            let at_mid = self.speed.with_slope(mid);
            let left = (self.length_to(mid) - start).clamp(0.0, length);
            self.fit_model(a, mid, left, (ends.0, at_mid), accuracy, depth + 1);
            self.fit_model(mid, b, length - left, (at_mid, ends.1), accuracy, depth + 1);
            return;
        }
        let s = self.model_s[self.model_s.len() - 1];
        self.model_u.push(b);
        // The last piece ends at the segment's length exactly.
        self.model_s
            .push(if b == 1.0 { self.length() } else { s + length });
        self.model.push(c);
    }

    /// Whether the model `c` of piece [a, b] (whose start is at length `start`) is within a
    /// quarter of `accuracy` of the quadrature's length at the check points.
    fn model_fits(&self, a: f64, b: f64, start: f64, c: &[f64; 5], accuracy: f64) -> bool {
        CHECK_POINTS.iter().all(|&x| {
            let s = self.length_to(a + x * (b - a)) - start;
            (polynomial(c, x) - s).abs() <= 0.25 * accuracy
        })
    }

    /// The segment's length.
    pub(crate) fn length(&self) -> f64 {
        self.s[self.s.len() - 1]
    }

    /// The length from u = 0 to `u` in [0, 1]: the quadrature pieces before it, and the
    /// 8-point rule inside its own.
    #[inline]
    pub(crate) fn length_to(&self, u: f64) -> f64 {
        self.length_to_from(u, 0)
    }

    /// [`ArcTable::length_to`], searching the quadrature's pieces from piece `from` on (which
    /// starts at or before `u`).
    #[inline]
    fn length_to_from(&self, u: f64, from: usize) -> f64 {
        let k = last_before(&self.u[..self.u.len() - 1], from, |x| x <= u);
        self.s[k] + self.speed.gl8(self.u[k], u)
    }

    /// The model piece that holds length `s` in (0, length), searched from `hint.model` on,
    /// and the u where its model reaches `s`.
    #[inline]
    fn guess(&self, s: f64, hint: &mut InverseHint) -> (usize, f64) {
        let (ms, mu) = (&self.model_s, &self.model_u);
        // The first piece whose end reaches s: ms[k] < s <= ms[k + 1], so it is not empty.
        let k = last_before(&ms[..self.model.len()], hint.model, |x| x < s);
        if k != hint.model {
            hint.model = k;
            hint.quadrature =
                last_before(&self.u[..self.u.len() - 1], hint.quadrature, |x| x <= mu[k]);
        }
        // Solved to the model's own error, which Newton's step on the length then removes.
        let within = self.model_accuracy;
        let x = solve_model(&self.model[k], s - ms[k], ms[k + 1] - ms[k], within);
        (k, mu[k] + x * (mu[k + 1] - mu[k]))
    }

    /// The u in [0, 1] at which the length from 0 reaches `s` (clamped to [0, length]),
    /// within `accuracy` in length: Newton's method on the length inside the model piece that
    /// holds `s`, from the model's solution, falling back to bisection of the piece when the
    /// speed vanishes or a step leaves the bracket. A step is the last when its remainder
    /// bound says so: a step of δ in u from a point whose length error is known leaves an
    /// error of at most ½ max|P''| δ², since |d speed/du| = |P'·P''|/|P'| <= |P''|. The answer
    /// depends on `s` alone (not on earlier calls), so every chunking of a sampling gives the
    /// same t.
    pub(crate) fn inverse(&self, s: f64, accuracy: f64) -> f64 {
        self.inverse_from(s, accuracy, &mut InverseHint::default())
    }

    /// [`ArcTable::inverse`] for one of a run of nondecreasing lengths: the searches start
    /// where the last one's ended (`hint`, updated; [`InverseHint::default`] for the first),
    /// which changes how long they take, not what they find.
    pub(crate) fn inverse_from(&self, s: f64, accuracy: f64, hint: &mut InverseHint) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        if s >= self.length() {
            return 1.0;
        }
        let (k, mut u) = self.guess(s, hint);
        let (mut lo, mut hi) = (self.model_u[k], self.model_u[k + 1]);
        for _ in 0..100 {
            let f = self.length_to_from(u, hint.quadrature) - s;
            if f.abs() <= accuracy {
                return u;
            }
            if f < 0.0 {
                lo = u;
            } else {
                hi = u;
            }
            let v = self.speed.at(u);
            let step = f / v;
            let newton = u - step;
            if v > 0.0 && newton > lo && newton < hi {
                // The length at `newton` is off by at most f's quadrature error (as an
                // accepted f is) plus the Newton remainder.
                if 0.5 * self.bend * step * step <= accuracy {
                    return newton;
                }
                u = newton;
            } else {
                u = 0.5 * (lo + hi);
            }
            if hi - lo <= f64::EPSILON * hi.max(1e-300) {
                return u;
            }
        }
        u
    }

    /// The explicit inverse's pieces as (the length where each starts, its u there, its u at
    /// its end, p's coefficients c1..c5 (c0 is 0: p(0) = 0)), for the GPU's f32 table: the
    /// kernel places a sample as the CPU does, one polynomial a sample.
    pub(crate) fn inverse_pieces(
        &self,
    ) -> impl ExactSizeIterator<Item = (f64, f64, f64, [f64; 5])> {
        self.inverse.iter().map(|p| {
            let c = [p.c[1], p.c[2], p.c[3], p.c[4], p.c[5]];
            (p.s0, p.u0, p.u0 + p.du, c)
        })
    }
}

/// Where [`ArcTable::inverse_from`]'s searches start: the model piece of the last length, and
/// the quadrature piece that holds that model piece's start.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct InverseHint {
    model: usize,
    quadrature: usize,
}

/// The last index, from `from` on, whose value satisfies `before`, which holds on a prefix of
/// `values` that reaches `from`: steps doubling from `from`, then halving, so a search that
/// starts near its answer is short.
#[inline]
pub(crate) fn last_before(values: &[f64], from: usize, before: impl Fn(f64) -> bool) -> usize {
    let (mut lo, mut step) = (from, 1);
    let mut hi = lo + step;
    while hi < values.len() && before(values[hi]) {
        lo = hi;
        step *= 2;
        hi = lo + step;
    }
    let hi = hi.min(values.len());
    lo + values[lo + 1..hi].partition_point(|&v| before(v))
}

/// The Chebyshev–Lobatto points of [0, 1] for degree 5: (1 − cos(iπ/5)) / 2.
const LOBATTO: [f64; 6] = [
    0.0,
    0.095_491_502_812_526_27,
    0.345_491_502_812_526_3,
    0.654_508_497_187_473_7,
    0.904_508_497_187_473_7,
    1.0,
];

/// The points between consecutive [`LOBATTO`] points, where an inverse piece's error is
/// measured.
const MIDPOINTS: [f64; 5] = [
    0.047_745_751_406_263_14,
    0.220_491_502_812_526_3,
    0.5,
    0.779_508_497_187_473_7,
    0.952_254_248_593_736_9,
];

/// A piece of a segment's explicit inverse: lengths s from `s0` on map to
/// u = u0 + du p(τ), τ = (s − s0) / ℓ (clamped to [0, 1]; `inv_length` = 1 / ℓ), p(τ) = Σ c_i τ^i
/// with p(0) = 0 and p(1) = 1, u clamped to the piece's [u0, u0 + du].
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct InversePiece {
    s0: f64,
    inv_length: f64,
    u0: f64,
    du: f64,
    c: [f64; 6],
}

impl InversePiece {
    /// The straight map of [sa, sb] onto [a, b].
    fn linear((a, b): (f64, f64), (sa, sb): (f64, f64)) -> Self {
        Self {
            s0: sa,
            inv_length: if sb > sa { 1.0 / (sb - sa) } else { 0.0 },
            u0: a,
            du: b - a,
            c: [0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
        }
    }

    /// The u of length `s`.
    #[inline]
    pub(crate) fn at(&self, s: f64) -> f64 {
        let tau = ((s - self.s0) * self.inv_length).clamp(0.0, 1.0);
        (self.u0 + self.du * evaluate5(&self.c, tau)).clamp(self.u0, self.u0 + self.du)
    }
}

/// c0 + c1 τ + … + c5 τ⁵.
#[inline]
fn evaluate5(c: &[f64; 6], tau: f64) -> f64 {
    c[0] + tau * (c[1] + tau * (c[2] + tau * (c[3] + tau * (c[4] + tau * c[5]))))
}

/// The coefficients (c0 + c1 τ + … + c5 τ⁵) of the polynomial through (t[i], y[i]) (t
/// increasing): Newton's divided differences, expanded.
fn interpolate(t: &[f64; 6], y: &[f64; 6]) -> [f64; 6] {
    let mut d = *y;
    for level in 1..6 {
        for i in (level..6).rev() {
            d[i] = (d[i] - d[i - 1]) / (t[i] - t[i - level]);
        }
    }
    // Horner on the Newton form: p = d0 + (τ − t0)(d1 + (τ − t1)(d2 + …)).
    let mut c = [0.0; 6];
    c[0] = d[5];
    for i in (0..5).rev() {
        // c ← c · (τ − t_i) + d_i
        let mut next = [0.0; 6];
        for j in 0..5 {
            next[j + 1] += c[j];
            next[j] -= c[j] * t[i];
        }
        next[0] += d[i];
        c = next;
    }
    c
}

/// c1 x + c2 x² + … + c5 x⁵.
#[inline]
fn polynomial(c: &[f64; 5], x: f64) -> f64 {
    x * (c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * c[4]))))
}

/// Its derivative, c1 + 2 c2 x + … + 5 c5 x⁴.
#[inline]
fn polynomial_slope(c: &[f64; 5], x: f64) -> f64 {
    c[0] + x * (2.0 * c[1] + x * (3.0 * c[2] + x * (4.0 * c[3] + x * 5.0 * c[4])))
}

/// The x in [0, 1] where the model `c` of a piece of `length` reaches `s` (in [0, length]):
/// up to [`SOLVE_STEPS`] steps of Newton's method from the linear guess s/length, each kept
/// inside the bracket the signs so far leave (bisecting it when a step would leave it or the
/// slope is not positive), stopping once the model is within `within` of `s` or a step no
/// longer moves x.
pub(crate) fn solve_model(c: &[f64; 5], s: f64, length: f64, within: f64) -> f64 {
    if length <= 0.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut x = (s / length).clamp(0.0, 1.0);
    for _ in 0..SOLVE_STEPS {
        let f = polynomial(c, x) - s;
        if f.abs() <= within {
            return x;
        }
        if f < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let slope = polynomial_slope(c, x);
        let next = x - f / slope;
        // A step below the float's resolution: converged (a bisection would undo it).
        if next == x {
            return x;
        }
        x = if slope > 0.0 && next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
    }
    x
}

/// The coefficients c1..c5 of the quintic p with p(0) = 0, p(1) = `dy`, slopes `m0`, `m1` and
/// second derivatives `a0`, `a1` at 0 and 1 (Hermite's basis, expanded to powers of x). Where
/// one is not finite, the line p = dy·x.
fn quintic_hermite(dy: f64, m0: f64, m1: f64, a0: f64, a1: f64) -> [f64; 5] {
    let c = [
        m0,
        0.5 * a0,
        10.0 * dy - 6.0 * m0 - 4.0 * m1 - 1.5 * a0 + 0.5 * a1,
        -15.0 * dy + 8.0 * m0 + 7.0 * m1 + 1.5 * a0 - a1,
        6.0 * dy - 3.0 * m0 - 3.0 * m1 - 0.5 * a0 + 0.5 * a1,
    ];
    if c.iter().all(|v| v.is_finite()) {
        c
    } else {
        [dy, 0.0, 0.0, 0.0, 0.0]
    }
}

impl Segment<'_> {
    /// The segment's arc length ∫ |P'(u)| du over u in [0, 1], within `accuracy` (absolute,
    /// in the curve's units). Adaptive Gauss–Legendre quadrature; see the `arclen` module docs.
    #[must_use]
    pub fn arclen(&self, accuracy: f64) -> f64 {
        ArcTable::new(self, accuracy, f64::INFINITY).length()
    }

    /// The local u in [0, 1] at which the arc length from u = 0 reaches `s` (clamped to the
    /// segment's length), within `accuracy` in length.
    #[must_use]
    pub fn inv_arclen(&self, s: f64, accuracy: f64) -> f64 {
        ArcTable::new(self, accuracy, f64::INFINITY).inverse(s, accuracy)
    }
}

impl SegmentTable {
    /// The curve's arc length, within `accuracy` times the length (relative:
    /// [`DEFAULT_ARCLEN_ACCURACY`] when the caller has no reason to choose).
    #[must_use]
    pub fn arclen(&self, accuracy: f64) -> f64 {
        self.segment_arclens(accuracy).iter().sum()
    }

    /// Each segment's arc length, together within `accuracy` times the curve's length.
    #[must_use]
    pub fn segment_arclens(&self, accuracy: f64) -> Vec<f64> {
        self.arc_tables(accuracy, false)
            .iter()
            .map(ArcTable::length)
            .collect()
    }

    /// Each segment's [`ArcTable`], together within `accuracy` times the curve's length; with
    /// `with_model`, each table's length model within [`MODEL_ACCURACY`] times the length,
    /// else none refined (the tables then serve for lengths only).
    pub(crate) fn arc_tables(&self, accuracy: f64, with_model: bool) -> Vec<ArcTable> {
        // A first estimate of the length scales the absolute accuracy.
        let rough: f64 = (0..self.len())
            .map(|i| Speed::of(&self.segment(i)).gl8(0.0, 1.0))
            .sum();
        let per_segment = accuracy * rough / self.len() as f64;
        let model = if with_model {
            MODEL_ACCURACY * rough
        } else {
            f64::INFINITY
        };
        (0..self.len())
            .map(|i| ArcTable::new(&self.segment(i), per_segment, model))
            .collect()
    }

    /// The curve parameter t at which the arc length from the curve's start reaches `s`
    /// (clamped to [0, length]), within `accuracy` times the length.
    #[must_use]
    pub fn inv_arclen(&self, s: f64, accuracy: f64) -> f64 {
        let lengths = self.segment_arclens(accuracy);
        let total: f64 = lengths.iter().sum();
        let (mut start, knots) = (0.0, self.knots());
        for (i, length) in lengths.iter().enumerate() {
            if s < start + length || i + 1 == lengths.len() {
                let per_segment = accuracy * total / self.len() as f64;
                let table = ArcTable::new(&self.segment(i), per_segment, f64::INFINITY);
                let u = table.inverse(s - start, accuracy * total);
                return knots[i] + u * (knots[i + 1] - knots[i]);
            }
            start += length;
        }
        knots[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Basis, Curve, CurveKind, Ends, Points};

    fn table_of(coords: Vec<f64>, dim: usize) -> crate::SegmentTable {
        let kind = CurveKind::Uniform {
            basis: Basis::Matrix(crate::basis::bezier_rows()),
            ends: Ends::Control,
        };
        Curve::new(kind, Points::new(dim, coords).unwrap())
            .unwrap()
            .fit()
    }

    #[test]
    fn a_straight_segment_has_its_chord_length_everywhere() {
        // Bezier points evenly spaced on a line: P(u) = (3u, 4u), speed 5.
        let table = table_of(vec![0.0, 0.0, 1.0, 4.0 / 3.0, 2.0, 8.0 / 3.0, 3.0, 4.0], 2);
        let arc = ArcTable::new(&table.segment(0), 1e-14, f64::INFINITY);
        assert!((arc.length() - 5.0).abs() < 1e-13);
        for u in [0.0, 0.1, 0.5, 0.77, 1.0] {
            assert!((arc.length_to(u) - 5.0 * u).abs() < 1e-13);
            assert!((arc.inverse(5.0 * u, 1e-14) - u).abs() < 1e-13);
        }
    }

    #[test]
    fn a_cusp_and_a_standstill_are_measured_without_dividing_by_zero() {
        // A cusp: Bezier (0,0), (1,1), (0,1), (1,0) has P' = 0 inside the segment.
        let cusp = table_of(vec![0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0], 2);
        // All four points equal: zero speed everywhere, zero length.
        let still = table_of(vec![2.0; 4], 1);
        let arc = ArcTable::new(&still.segment(0), 1e-14, f64::INFINITY);
        assert_eq!(arc.length(), 0.0);
        assert_eq!(arc.inverse(0.0, 1e-14), 0.0);
        let arc = ArcTable::new(&cusp.segment(0), 1e-14, f64::INFINITY);
        // Against a fine midpoint rule on chords.
        let n = 2_000_000;
        let mut chords = 0.0;
        let mut prev = [0.0, 0.0];
        for i in 1..=n {
            let mut p = [0.0; 2];
            cusp.segment(0).eval(i as f64 / n as f64, &mut p);
            chords += ((p[0] - prev[0]).powi(2) + (p[1] - prev[1]).powi(2)).sqrt();
            prev = p;
        }
        assert!(
            (arc.length() - chords).abs() < 1e-9,
            "{} vs {chords}",
            arc.length()
        );
        for frac in [0.1, 0.3, 0.5, 0.9] {
            let s = frac * arc.length();
            let u = arc.inverse(s, 1e-14);
            assert!((arc.length_to(u) - s).abs() < 1e-12);
        }
    }
}
