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
//! part (between zeros of the speed) that holds the length (bisection where the speed
//! vanishes or Newton leaves the bracket), started from the straight guess in the part and
//! stopped by a bound rather than one more quadrature: a Newton
//! step of δ in u from a point whose length error is known leaves an error of at most
//! ½ max|P''| δ², since |d speed/du| = |P'·P''|/|P'| <= |P''|. An arc-length sampling needs
//! neither the precision nor the Newton steps: its places come from
//! [`places`](super::places)' tables, made at the accuracy the contract asks.
//!
//! A rational segment (weighted NURBS, see [`rational`](crate::rational)) goes the same way
//! with its speed |R'(u)| by the quotient rule: the quadrature is unchanged,
//! its critical points are the sign changes of R'·R'' on a grid of 64 intervals (bisected to
//! f64 precision; two within one interval may pass unseen, which costs subdivisions, not
//! accuracy, where the speed does not vanish), and max|P''| in the Newton bound is the proven
//! bound of [`RationalCubic::second_derivative_bound`].

use super::places::{PLACE_ACCURACY, PlaceTables};
use crate::rational::{Denominator, RationalCubic, quotient};
use crate::segment::{Segment, SegmentTable};
use smallvec::{SmallVec, smallvec};

/// A segment's critical points or kinks: a handful (a polynomial segment's are the roots of a
/// cubic and of a quadratic, and 1), kept inline.
pub(crate) type Cuts = SmallVec<[f64; 8]>;

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

/// Gauss–Legendre nodes on [-1, 1] (the positive half) and their weights, 4 points.
const GL4_NODES: [f64; 2] = [0.339_981_043_584_856_3, 0.861_136_311_594_052_6];
const GL4_WEIGHTS: [f64; 2] = [0.652_145_154_862_546_1, 0.347_854_845_137_453_9];

/// The deepest subdivision: pieces no shorter than 2^-40 in u.
pub(crate) const MAX_DEPTH: u32 = 40;

/// The places of the 8-point rule's nodes in an interval, as fractions of it: the lower four
/// (1 − node)/2, then the upper four (1 + node)/2, as [`Speed::gl8`] pairs them.
pub(crate) const GL8_POSITIONS: [f64; 8] = [
    0.5 * (1.0 - GL8_NODES[0]),
    0.5 * (1.0 - GL8_NODES[1]),
    0.5 * (1.0 - GL8_NODES[2]),
    0.5 * (1.0 - GL8_NODES[3]),
    0.5 * (1.0 + GL8_NODES[0]),
    0.5 * (1.0 + GL8_NODES[1]),
    0.5 * (1.0 + GL8_NODES[2]),
    0.5 * (1.0 + GL8_NODES[3]),
];

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
    /// monotone, so each part holds at most one zero, found by Newton steps kept in
    /// its bracket to f64 precision.
    pub(crate) fn critical_points(&self) -> Cuts {
        if let Some(w) = &self.denominator {
            return self.rational_critical_points(w);
        }
        let q = &self.quartic();
        let dq = |u: f64| q[1] + u * (2.0 * q[2] + u * (3.0 * q[3] + u * 4.0 * q[4]));
        // Q'' = 2 q2 + 6 q3 u + 12 q4 u².
        let mut cuts: Cuts = smallvec![0.0];
        cuts.extend(
            quadratic_roots(12.0 * q[4], 6.0 * q[3], 2.0 * q[2])
                .into_iter()
                .filter(|&r| r > 0.0 && r < 1.0),
        );
        cuts.push(1.0);
        cuts.sort_by(f64::total_cmp);
        let mut roots = Cuts::new();
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
            // Newton's steps on Q' (its slope Q'' is monotone on the part, so they converge
            // fast), kept inside the bracket, bisecting where a step would leave it: within
            // 64 steps the bracket or the step reaches f64 resolution.
            let ddq = |u: f64| 2.0 * q[2] + u * (6.0 * q[3] + u * 12.0 * q[4]);
            let mut x = 0.5 * (lo + hi);
            for _ in 0..64 {
                let f = dq(x);
                if f == 0.0 {
                    break;
                }
                if (f < 0.0) == (flo < 0.0) {
                    lo = x;
                } else {
                    hi = x;
                }
                let next = x - f / ddq(x);
                let next = if next > lo && next < hi {
                    next
                } else {
                    0.5 * (lo + hi)
                };
                if (next - x).abs() <= f64::EPSILON * x.abs() || hi - lo <= f64::EPSILON * hi {
                    x = next;
                    break;
                }
                x = next;
            }
            roots.push(x);
        }
        // Q's inflections (the cuts) bound the parts too: a kink cannot hide there either.
        roots.extend(cuts[1..cuts.len() - 1].iter().copied());
        roots.sort_by(f64::total_cmp);
        roots.dedup();
        roots
    }

    /// The sign changes of R'·R'' (the speed's extrema) on a rational segment, found on a
    /// grid of [`RATIONAL_GRID`] intervals and bisected to f64 precision, in order.
    fn rational_critical_points(&self, w: &Denominator) -> Cuts {
        let slope = |u: f64| self.rational_at(w, u).1;
        let mut roots = Cuts::new();
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

    /// The speed at each of `u`: on a polynomial segment side by side (coordinate by
    /// coordinate, then the square roots), which the compiler turns into vector instructions;
    /// the same operations as [`Speed::at`] at each, so the same bits.
    #[inline]
    fn speeds<const N: usize>(&self, u: [f64; N]) -> [f64; N] {
        if self.denominator.is_some() {
            return u.map(|u| self.at(u));
        }
        let mut q = [0.0; N];
        for [a, b, c] in &self.terms {
            for i in 0..N {
                let d = c + u[i] * (b + u[i] * a);
                q[i] += d * d;
            }
        }
        q.map(|q| q.sqrt() * self.scale)
    }

    /// The 4-point Gauss–Legendre rule for ∫ speed over [a, b], its nodes side by side
    /// ([`Speed::speeds`]).
    #[inline]
    pub(crate) fn gl4(&self, a: f64, b: f64) -> f64 {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let x = [half * GL4_NODES[0], half * GL4_NODES[1]];
        let v = self.speeds([mid - x[0], mid + x[0], mid - x[1], mid + x[1]]);
        let mut sum = 0.0;
        for i in 0..2 {
            sum += GL4_WEIGHTS[i] * (v[2 * i] + v[2 * i + 1]);
        }
        sum * half
    }

    /// [`Speed::gl8`] and the speed at the rule's nodes, in the order of
    /// [`GL8_POSITIONS`] (their places in [a, b] as fractions of it).
    #[inline]
    pub(crate) fn gl8_nodes(&self, a: f64, b: f64) -> (f64, [f64; 8]) {
        let w = b - a;
        let v = self.speeds(std::array::from_fn(|i| a + w * GL8_POSITIONS[i]));
        let mut sum = 0.0;
        for i in 0..4 {
            sum += GL8_WEIGHTS[i] * (v[i] + v[i + 4]);
        }
        (sum * 0.5 * w, v)
    }

    /// Where the speed vanishes inside (0, 1) (its critical points at or below 1e-9 of the
    /// fastest critical point or end: a kink of |P'|), then 1: the ends of the parts on which
    /// the length is as smooth as the speed.
    pub(crate) fn kinks(&self) -> Cuts {
        if self.denominator.is_none() {
            // Q's Bernstein coefficients on [0, 1] bound it: where the least is above 1e-16
            // of the largest (1e-9 in the speed is 1e-18 in Q: a margin of 100) and above
            // their rounding (8 ulps of the power coefficients' sizes), Q is above 1e-18
            // times its largest value everywhere, so no critical point can be a kink and
            // none is looked for.
            let [q0, q1, q2, q3, q4] = self.quartic();
            let bernstein = [
                q0,
                q0 + q1 / 4.0,
                q0 + q1 / 2.0 + q2 / 6.0,
                q0 + 0.75 * q1 + 0.5 * q2 + q3 / 4.0,
                q0 + q1 + q2 + q3 + q4,
            ];
            let least = bernstein.iter().copied().fold(f64::INFINITY, f64::min);
            let largest = bernstein.iter().copied().fold(0.0, f64::max);
            let rounding =
                8.0 * f64::EPSILON * (q0.abs() + q1.abs() + q2.abs() + q3.abs() + q4.abs());
            if least > 1e-16 * largest + rounding {
                return smallvec![1.0];
            }
        }
        let mut cuts = self.critical_points();
        cuts.push(1.0);
        self.kinks_among(cuts)
    }

    /// [`Speed::kinks`] found among `cuts`, the critical points followed by 1.
    fn kinks_among(&self, mut cuts: Cuts) -> Cuts {
        let fastest = (cuts.iter().chain(&[0.0]))
            .map(|&c| self.at(c))
            .fold(0.0, f64::max);
        cuts.retain(|c| *c == 1.0 || self.at(*c) <= 1e-9 * fastest);
        cuts
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
fn quadratic_roots(a: f64, b: f64, c: f64) -> SmallVec<[f64; 2]> {
    if a == 0.0 {
        return if b == 0.0 {
            smallvec![]
        } else {
            smallvec![-c / b]
        };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return smallvec![];
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    if q == 0.0 {
        return smallvec![0.0];
    }
    smallvec![q / a, c / q]
}

/// A segment's arc length as pieces of u on which the quadrature is accurate: `u[k]..u[k + 1]`
/// has length `s[k + 1] − s[k]`; `u` runs from 0 to 1 and `s` from 0 to the segment's length.
/// Beside them, the parts between the zeros of the speed, where the inverse's Newton steps
/// start from the straight guess.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ArcTable {
    speed: Speed,
    u: Vec<f64>,
    s: Vec<f64>,
    /// The parts: `part_u[k]..part_u[k + 1]` has length `part_s[k + 1] − part_s[k]` (read
    /// off the quadrature's pieces).
    part_u: Vec<f64>,
    part_s: Vec<f64>,
    /// [`Speed::bend`]: bounds how fast the speed changes.
    bend: f64,
}

impl ArcTable {
    /// The table of `segment`: each piece's length within its share (by its width in u) of
    /// the absolute `accuracy`.
    pub(crate) fn new(segment: &Segment<'_>, accuracy: f64) -> Self {
        let speed = Speed::of(segment);
        let bend = speed.bend();
        let mut table = Self {
            speed,
            u: vec![0.0],
            s: vec![0.0],
            part_u: vec![0.0],
            part_s: vec![0.0],
            bend,
        };
        // Between consecutive critical points of Q the speed is monotone, so a zero of the
        // speed (a kink of |P'|) can only be an end of a part: a kink strictly inside a piece
        // but outside the rule's nodes would pass the halving test unseen.
        let mut cuts = table.speed.critical_points();
        cuts.push(1.0);
        let mut a = 0.0;
        for &b in &cuts {
            let tol = (accuracy * (b - a)).max(f64::MIN_POSITIVE);
            let whole = table.speed.gl8(a, b);
            table.subdivide(a, b, whole, tol, 0);
            a = b;
        }
        // The parts' ends are among the quadrature's cuts, found once.
        let mut a = 0.0;
        for b in table.speed.kinks_among(cuts) {
            let length = (table.length_to(b) - table.length_to(a)).max(0.0);
            let s = table.part_s[table.part_s.len() - 1];
            table.part_u.push(b);
            // The last part ends at the segment's length exactly.
            table
                .part_s
                .push(if b == 1.0 { table.length() } else { s + length });
            a = b;
        }
        table
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
        let k = last_before(&self.u[..self.u.len() - 1], from, |&x| x <= u);
        self.s[k] + self.speed.gl8(self.u[k], u)
    }

    /// The part that holds length `s` in (0, length), searched from `hint.part` on, and the
    /// straight guess of its u there.
    #[inline]
    fn guess(&self, s: f64, hint: &mut InverseHint) -> (usize, f64) {
        let (ps, pu) = (&self.part_s, &self.part_u);
        // The first part whose end reaches s: ps[k] < s <= ps[k + 1], so it is not empty.
        let k = last_before(&ps[..ps.len() - 1], hint.part, |&x| x < s);
        if k != hint.part {
            hint.part = k;
            hint.quadrature = last_before(&self.u[..self.u.len() - 1], hint.quadrature, |&x| {
                x <= pu[k]
            });
        }
        let length = ps[k + 1] - ps[k];
        let x = if length <= 0.0 {
            0.0
        } else {
            ((s - ps[k]) / length).clamp(0.0, 1.0)
        };
        (k, pu[k] + x * (pu[k + 1] - pu[k]))
    }

    /// The u in [0, 1] at which the length from 0 reaches `s` (clamped to [0, length]),
    /// within `accuracy` in length: Newton's method on the length inside the part that holds
    /// `s`, from the straight guess, falling back to bisection of the piece when the
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
        let (mut lo, mut hi) = (self.part_u[k], self.part_u[k + 1]);
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
}

/// Where [`ArcTable::inverse_from`]'s searches start: the part of the last length, and the
/// quadrature piece that holds that part's start.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct InverseHint {
    part: usize,
    quadrature: usize,
}

/// The last index, from `from` on, whose value satisfies `before`, which holds on a prefix of
/// `values` that reaches `from`: steps doubling from `from`, then halving, so a search that
/// starts near its answer is short.
#[inline]
pub(crate) fn last_before<T>(values: &[T], from: usize, before: impl Fn(&T) -> bool) -> usize {
    let (mut lo, mut step) = (from, 1);
    let mut hi = lo + step;
    while hi < values.len() && before(&values[hi]) {
        lo = hi;
        step *= 2;
        hi = lo + step;
    }
    let hi = hi.min(values.len());
    lo + values[lo + 1..hi].partition_point(before)
}

/// c1 x + c2 x² + … + c5 x⁵.
#[inline]
pub(crate) fn polynomial(c: &[f64; 5], x: f64) -> f64 {
    x * (c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * c[4]))))
}

/// Its derivative, c1 + 2 c2 x + … + 5 c5 x⁴.
#[inline]
pub(crate) fn polynomial_slope(c: &[f64; 5], x: f64) -> f64 {
    c[0] + x * (2.0 * c[1] + x * (3.0 * c[2] + x * (4.0 * c[3] + x * 5.0 * c[4])))
}

/// The coefficients c1..c5 of the quintic p with p(0) = 0, p(1) = `dy`, slopes `m0`, `m1` and
/// second derivatives `a0`, `a1` at 0 and 1 (Hermite's basis, expanded to powers of x). Where
/// one is not finite, the line p = dy·x.
pub(crate) fn quintic_hermite(dy: f64, m0: f64, m1: f64, a0: f64, a1: f64) -> [f64; 5] {
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
        ArcTable::new(self, accuracy).length()
    }

    /// The local u in [0, 1] at which the arc length from u = 0 reaches `s` (clamped to the
    /// segment's length), within `accuracy` in length.
    #[must_use]
    pub fn inv_arclen(&self, s: f64, accuracy: f64) -> f64 {
        ArcTable::new(self, accuracy).inverse(s, accuracy)
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
        self.arc_tables(accuracy)
            .iter()
            .map(ArcTable::length)
            .collect()
    }

    /// Each segment's [`ArcTable`], together within `accuracy` times the curve's length.
    pub(crate) fn arc_tables(&self, accuracy: f64) -> Vec<ArcTable> {
        let per_segment = accuracy * self.rough_length() / self.len() as f64;
        (0..self.len())
            .map(|i| ArcTable::new(&self.segment(i), per_segment))
            .collect()
    }

    /// Each segment's place table ([`PlaceTables`]) for an arc-length sampling, within
    /// [`PLACE_ACCURACY`] times the curve's length (see [`places`](super::places)): the
    /// quadrature's share a sixth of it per unit of u over the whole parameter range, the
    /// models and their inverses 0.4 of it each (the worst sample of 3,000 random curves of
    /// every kind: 0.47 of it, where the inverse's share dominates).
    pub(crate) fn place_tables(&self) -> PlaceTables {
        let rough = self.rough_length();
        let quadrature_tolerance = PLACE_ACCURACY * rough / (6.0 * self.len() as f64);
        let accuracy = 0.4 * PLACE_ACCURACY * rough;
        let segments = (0..self.len()).map(|i| self.segment(i));
        PlaceTables::new(segments, quadrature_tolerance, accuracy)
    }

    /// A first estimate of the length (each segment's 8-point rule), which scales the
    /// absolute accuracies.
    fn rough_length(&self) -> f64 {
        (0..self.len())
            .map(|i| Speed::of(&self.segment(i)).gl8(0.0, 1.0))
            .sum()
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
                let table = ArcTable::new(&self.segment(i), per_segment);
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

    /// The kinks skipped by Q's Bernstein bound are none that the search finds: on random
    /// segments, and on segments through a cusp and near one (P' vanishing, or nearly, at a
    /// random u), the two agree.
    #[test]
    fn kinks_skipped_by_the_bound_are_none_the_search_finds() {
        let mut rng = crate::support::Rng(7);
        let mut next = || rng.range(-1.0, 1.0);
        let (mut skipped, mut kinked) = (0, 0);
        for i in 0..4000 {
            // P'(u) = a u² + b u + c per coordinate; a cusp at u0 where P'(u0) = 0.
            let u0 = 0.5 * (next() + 1.0);
            let near = [0.0, 1e-12, 1e-7, 1e-3][i % 4];
            let coords: Vec<f64> = (0..3)
                .flat_map(|_| {
                    let (a, b) = (next(), next());
                    let c = -(a * u0 * u0 + b * u0) + near * next();
                    // Power coefficients A, B, C of P with P' = 3A u² + 2B u + C.
                    [a / 3.0, b / 2.0, c, next()]
                })
                .collect();
            let speed = Speed {
                terms: coords
                    .chunks_exact(4)
                    .map(|p| [3.0 * p[0], 2.0 * p[1], p[2]])
                    .collect(),
                scale: 1.0,
                denominator: None,
            };
            let kinks = speed.kinks();
            let mut cuts = speed.critical_points();
            cuts.push(1.0);
            assert_eq!(kinks, speed.kinks_among(cuts), "segment {i}");
            if kinks.len() > 1 {
                kinked += 1;
            } else {
                skipped += 1;
            }
        }
        assert!(
            kinked > 500 && skipped > 500,
            "{kinked} kinked, {skipped} not"
        );
    }

    #[test]
    fn a_straight_segment_has_its_chord_length_everywhere() {
        // Bezier points evenly spaced on a line: P(u) = (3u, 4u), speed 5.
        let table = table_of(vec![0.0, 0.0, 1.0, 4.0 / 3.0, 2.0, 8.0 / 3.0, 3.0, 4.0], 2);
        let arc = ArcTable::new(&table.segment(0), 1e-14);
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
        let arc = ArcTable::new(&still.segment(0), 1e-14);
        assert_eq!(arc.length(), 0.0);
        assert_eq!(arc.inverse(0.0, 1e-14), 0.0);
        let arc = ArcTable::new(&cusp.segment(0), 1e-14);
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
