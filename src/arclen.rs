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
    /// (a_k, b_k, c_k) for each coordinate k, divided by `scale`.
    terms: Vec<[f64; 3]>,
    /// A power of two near the largest coefficient: the squares of scaled terms neither
    /// overflow nor underflow, whatever the curve's size (points near 1e200 included).
    scale: f64,
}

impl Speed {
    /// The derivative's coefficients of `segment`.
    pub fn of(segment: &Segment<'_>) -> Self {
        let [pa, pb, pc, _] = segment.power();
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
        }
    }

    /// |P'(u)|.
    #[inline]
    pub fn at(&self, u: f64) -> f64 {
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
    pub fn with_slope(&self, u: f64) -> (f64, f64) {
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
    pub fn critical_points(&self) -> Vec<f64> {
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

    /// max |P''(u)| over [0, 1]: P'' = 2a u + b is linear, and a norm is convex, so the
    /// largest is at an end.
    pub fn bend(&self) -> f64 {
        let norm = |f: &dyn Fn(&[f64; 3]) -> f64| {
            self.terms.iter().map(|t| f(t) * f(t)).sum::<f64>().sqrt()
        };
        norm(&|[_, b, _]| *b).max(norm(&|[a, b, _]| 2.0 * a + b)) * self.scale
    }

    /// The 8-point Gauss–Legendre rule for ∫ speed over [a, b].
    #[inline]
    pub fn gl8(&self, a: f64, b: f64) -> f64 {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let mut sum = 0.0;
        for (x, w) in GL8_NODES.iter().zip(GL8_WEIGHTS) {
            sum += w * (self.at(mid - half * x) + self.at(mid + half * x));
        }
        sum * half
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
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ArcTable {
    speed: Speed,
    u: Vec<f64>,
    s: Vec<f64>,
    /// The speed at each `u`, and its derivative.
    v: Vec<(f64, f64)>,
    /// [`Speed::bend`]: bounds how fast the speed changes.
    bend: f64,
}

impl ArcTable {
    /// The table of `segment`, each piece's length within its share (by its width in u) of the
    /// absolute `accuracy`.
    pub fn new(segment: &Segment<'_>, accuracy: f64) -> Self {
        let speed = Speed::of(segment);
        let mut table = Self {
            speed: speed.clone(),
            u: vec![0.0],
            s: vec![0.0],
            v: vec![speed.with_slope(0.0)],
            bend: speed.bend(),
        };
        // Between consecutive critical points of Q the speed is monotone, so a zero of the
        // speed (a kink of |P'|) can only be an end of a part: a kink strictly inside a piece
        // but outside the rule's nodes would pass the halving test unseen.
        let mut cuts = speed.critical_points();
        cuts.push(1.0);
        let mut a = 0.0;
        for b in cuts {
            let tol = (accuracy * (b - a)).max(f64::MIN_POSITIVE);
            table.subdivide(&speed, a, b, speed.gl8(a, b), tol, 0);
            a = b;
        }
        table
    }

    /// Appends [a, b] (whose 8-point estimate is `whole`) as accepted pieces, in order.
    fn subdivide(&mut self, speed: &Speed, a: f64, b: f64, whole: f64, tol: f64, depth: u32) {
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
            self.v.extend([speed.with_slope(mid), speed.with_slope(b)]);
            return;
        }
        self.subdivide(speed, a, mid, left, 0.5 * tol, depth + 1);
        self.subdivide(speed, mid, b, right, 0.5 * tol, depth + 1);
    }

    /// The segment's length.
    pub fn length(&self) -> f64 {
        self.s[self.s.len() - 1]
    }

    /// The length from u = 0 to `u` in [0, 1].
    #[cfg(test)]
    pub fn length_to(&self, u: f64) -> f64 {
        let k = self.piece_of_u(u);
        self.s[k] + self.speed.gl8(self.u[k], u)
    }

    #[cfg(test)]
    fn piece_of_u(&self, u: f64) -> usize {
        (self.u.partition_point(|&x| x <= u).max(1) - 1).min(self.u.len() - 2)
    }

    /// The u in [0, 1] at which the length from 0 reaches `s` (clamped to [0, length]),
    /// within `accuracy` in length: Newton's method on the length inside the piece that holds
    /// `s`, from the piece's quintic Hermite interpolant of u(s), falling back to bisection of
    /// the piece when the speed vanishes or a step leaves the bracket. The answer depends on
    /// `s` alone (not on earlier calls), so every chunking of a sampling gives the same t.
    pub fn inverse(&self, s: f64, accuracy: f64) -> f64 {
        let length = self.length();
        if s <= 0.0 {
            return 0.0;
        }
        if s >= length {
            return 1.0;
        }
        // The first piece whose end reaches s.
        let k = (self.s.partition_point(|&x| x < s).max(1) - 1).min(self.u.len() - 2);
        let (mut lo, mut hi) = (self.u[k], self.u[k + 1]);
        let (from, target) = (lo, s - self.s[k]);
        let speed = &self.speed;
        let mut u = self.first_guess(k, target);
        for _ in 0..100 {
            let f = speed.gl8(from, u) - target;
            if f.abs() <= accuracy {
                return u;
            }
            if f < 0.0 {
                lo = u;
            } else {
                hi = u;
            }
            let v = speed.at(u);
            let step = f / v;
            let newton = u - step;
            if v > 0.0 && newton > lo && newton < hi {
                // The length at `newton` is off by at most f's quadrature error (as an
                // accepted f is) plus the Newton remainder, ½ max|speed'| step².
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

    /// A first u for length `target` past the start of piece `k`, strictly inside the piece:
    /// the quintic Hermite interpolant of u(s) through the piece's ends, with du/ds = 1/v and
    /// d²u/ds² = −v'/v³ there (v the speed, v' its derivative in u), or, where the speed
    /// vanishes at an end, the linear one.
    fn first_guess(&self, k: usize, target: f64) -> f64 {
        let (u0, u1) = (self.u[k], self.u[k + 1]);
        let ((v0, w0), (v1, w1)) = (self.v[k], self.v[k + 1]);
        let h = self.s[k + 1] - self.s[k];
        let x = (target / h.max(f64::MIN_POSITIVE)).min(1.0);
        let linear = u0 + (u1 - u0) * x;
        if !(v0 > 0.0 && v1 > 0.0) {
            return linear;
        }
        // Slopes and curvatures in x = (s − s_k)/h.
        let (m0, m1) = (h / v0, h / v1);
        let (a0, a1) = (-h * h * w0 / (v0 * v0 * v0), -h * h * w1 / (v1 * v1 * v1));
        let (x2, x3) = (x * x, x * x * x);
        let (x4, x5) = (x3 * x, x3 * x2);
        let end = 10.0 * x3 - 15.0 * x4 + 6.0 * x5;
        let quintic = u0 * (1.0 - end)
            + u1 * end
            + m0 * (x - 6.0 * x3 + 8.0 * x4 - 3.0 * x5)
            + m1 * (-4.0 * x3 + 7.0 * x4 - 3.0 * x5)
            + a0 * 0.5 * (x2 - 3.0 * x3 + 3.0 * x4 - x5)
            + a1 * 0.5 * (x3 - 2.0 * x4 + x5);
        if quintic > u0 && quintic < u1 {
            quintic
        } else {
            linear
        }
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
        // A first estimate of the length scales the absolute accuracy.
        let rough: f64 = (0..self.len())
            .map(|i| Speed::of(&self.segment(i)).gl8(0.0, 1.0))
            .sum();
        let per_segment = accuracy * rough / self.len() as f64;
        (0..self.len())
            .map(|i| ArcTable::new(&self.segment(i), per_segment))
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
            basis: Basis::Matrix(crate::bezier_rows()),
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
