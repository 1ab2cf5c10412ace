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

use crate::query::roots::{Poly, bernstein, bernstein_of_degree};
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

    /// A box holding the piece [lo, hi] of the segment relative to its origin, per axis.
    pub(crate) fn local_box(&self, lo: f64, hi: f64) -> [Interval; 2] {
        // Both written in degree 3 (N is a cubic, W at most one): the ratios of the
        // homogeneous control points.
        let w = bernstein_of_degree(&self.w, 3, lo, hi);
        std::array::from_fn(|k| {
            let x = bernstein_of_degree(&self.n[k], 3, lo, hi);
            let mut range = [f64::INFINITY, f64::NEG_INFINITY];
            for i in 0..=3 {
                let v = if self.polynomial { x[i] } else { x[i] / w[i] };
                range = [range[0].min(v), range[1].max(v)];
            }
            range
        })
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
                let (b, d) = (segment.local_box(lo, hi), segment.derivative_box(lo, hi));
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
