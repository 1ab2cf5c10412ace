//! A 2-D segment as polynomials relative to its origin, and proven enclosures of a piece
//! [lo, hi] of it: the box of its points and the box of its derivative, for the intersection
//! search ([`super::intersect`]).
//!
//! With P(u) = D + N(u) / W(u) (W ≡ 1 on a polynomial segment, W > 0 on [0, 1]):
//! - the piece's points lie in the convex hull of its rational Bezier control points, whose
//!   coordinates are the ratios b_i(N_k) / b_i(W) of N_k's and W's Bernstein coefficients on
//!   [lo, hi] (the homogeneous control points (b_i(N), b_i(W)), with b_i(W) > 0);
//! - P'(u) = T(u) / W(u)², T = N'W − NW': T_k lies between the least and largest of its
//!   Bernstein coefficients on [lo, hi] and W² between the squares of W's, so P'_k lies in
//!   their interval quotient (W² > 0).

use crate::query::roots::{Poly, bernstein, cubic_bernstein};
use crate::segment::Segment;

/// A closed interval [lo, hi].
pub(crate) type Interval = [f64; 2];

/// One 2-D segment's polynomials: N_x, N_y and W, T_x and T_y, and its origin D.
#[derive(Clone, Debug)]
pub(crate) struct PlanarSegment {
    n: [Poly; 2],
    w: Poly,
    t: [Poly; 2],
    pub(crate) origin: [f64; 2],
    /// Whether W ≡ 1.
    polynomial: bool,
}

impl PlanarSegment {
    pub(crate) fn new(segment: &Segment<'_>) -> Self {
        let [a, b, c, d] = segment.power();
        let n: [Poly; 2] = std::array::from_fn(|k| Poly::new(&[0.0, c[k], b[k], a[k]]));
        let (w, polynomial) = match segment.denominator() {
            None => (Poly::new(&[1.0]), true),
            Some(w) => {
                let [wa, wb, wc, wd] = w.coeffs;
                (Poly::new(&[wd, wc, wb, wa]), false)
            }
        };
        let dw = w.derivative();
        let t = std::array::from_fn(|k| n[k].derivative().times(&w).minus(&n[k].times(&dw)));
        Self {
            n,
            w,
            t,
            origin: [d[0], d[1]],
            polynomial,
        }
    }

    /// The point at u relative to the origin, N(u) / W(u).
    pub(crate) fn local(&self, u: f64) -> [f64; 2] {
        let w = self.w.at(u);
        [self.n[0].at(u) / w, self.n[1].at(u) / w]
    }

    /// dP/du at u.
    pub(crate) fn derivative(&self, u: f64) -> [f64; 2] {
        let w = self.w.at(u);
        [self.t[0].at(u) / (w * w), self.t[1].at(u) / (w * w)]
    }

    /// The (projected) Bezier control points of the piece [lo, hi] relative to the origin:
    /// the ratios of the homogeneous control points (N's and W's Bernstein coefficients, both
    /// written in degree 3). The piece lies in their convex hull.
    pub(crate) fn local_points(&self, lo: f64, hi: f64) -> [[f64; 2]; 4] {
        let w = if self.polynomial {
            [1.0; 4]
        } else {
            cubic_bernstein(&self.w, lo, hi)
        };
        let (x, y) = (
            cubic_bernstein(&self.n[0], lo, hi),
            cubic_bernstein(&self.n[1], lo, hi),
        );
        std::array::from_fn(|i| [x[i] / w[i], y[i] / w[i]])
    }

    /// A box holding dP/du over [lo, hi], per axis.
    pub(crate) fn derivative_box(&self, lo: f64, hi: f64) -> [Interval; 2] {
        let (w_lo, w_hi) = if self.polynomial {
            (1.0, 1.0)
        } else {
            let w = bernstein(&self.w, lo, hi);
            let w = &w[..=self.w.degree];
            let least = w.iter().copied().fold(f64::INFINITY, f64::min);
            let most = w.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (least * least, most * most)
        };
        std::array::from_fn(|k| {
            let t = bernstein(&self.t[k], lo, hi);
            let t = &t[..=self.t[k].degree];
            let least = t.iter().copied().fold(f64::INFINITY, f64::min);
            let most = t.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            [
                least / if least >= 0.0 { w_hi } else { w_lo },
                most / if most >= 0.0 { w_lo } else { w_hi },
            ]
        })
    }
}

/// The box of control points, per axis.
pub(crate) fn hull_box(points: &[[f64; 2]; 4]) -> [Interval; 2] {
    std::array::from_fn(|k| {
        points
            .iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |r, p| {
                [r[0].min(p[k]), r[1].max(p[k])]
            })
    })
}

/// Whether the hulls of two sets of control points are apart by Sederberg's fat line: all of
/// `b`'s points lie on one side of the band, about the chord of `a`, that holds `a`'s (wider
/// by `pad`). A piece lies in its points' hull, so then the pieces do not meet.
pub(crate) fn fat_line_apart(a: &[[f64; 2]; 4], b: &[[f64; 2]; 4], pad: f64) -> bool {
    let (d, e) = (a[0], a[3]);
    let n = [d[1] - e[1], e[0] - d[0]];
    let length = (n[0] * n[0] + n[1] * n[1]).sqrt();
    if length == 0.0 || !length.is_finite() {
        return false;
    }
    let side = |p: &[f64; 2]| ((p[0] - d[0]) * n[0] + (p[1] - d[1]) * n[1]) / length;
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for p in &a[1..3] {
        let s = side(p);
        lo = lo.min(s);
        hi = hi.max(s);
    }
    let (lo, hi) = (lo - pad, hi + pad);
    let sides = b.map(|p| side(&p));
    sides.iter().all(|&s| s < lo) || sides.iter().all(|&s| s > hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Curve, CurveKind, Points};

    /// The enclosures hold every sampled point and derivative of pieces of a weighted NURBS.
    #[test]
    fn enclosures_hold_the_piece() {
        let kind = CurveKind::Nurbs {
            knots: vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 2.0],
            weights: Some(vec![1.0, 7.0, 0.4, 2.0, 1.0]),
        };
        let points =
            Points::new(2, vec![0.0, 0.0, 1.0, 3.0, 2.0, -1.0, 3.0, 2.0, 4.0, 0.0]).unwrap();
        let table = Curve::new(kind, points).unwrap().fit();
        for s in 0..table.len() {
            let segment = PlanarSegment::new(&table.segment(s));
            for (lo, hi) in [(0.0, 1.0), (0.2, 0.45), (0.9, 1.0)] {
                let (b, d) = (
                    hull_box(&segment.local_points(lo, hi)),
                    segment.derivative_box(lo, hi),
                );
                for i in 0..=50 {
                    let u = lo + (hi - lo) * i as f64 / 50.0;
                    let (p, dp) = (segment.local(u), segment.derivative(u));
                    let mut want = [0.0; 2];
                    table.segment(s).eval(u, &mut want);
                    for k in 0..2 {
                        let slack = 1e-12 * (1.0 + p[k].abs());
                        assert!((p[k] + segment.origin[k] - want[k]).abs() < 1e-9);
                        assert!(b[k][0] - slack <= p[k] && p[k] <= b[k][1] + slack);
                        let slack = 1e-12 * (1.0 + dp[k].abs());
                        assert!(d[k][0] - slack <= dp[k] && dp[k] <= d[k][1] + slack);
                    }
                }
            }
        }
    }
}
