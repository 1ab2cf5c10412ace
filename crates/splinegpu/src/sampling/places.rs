//! Places by arc length on a cubic segment, made for an arc-length sampling (contract:
//! "arc_length m", spaced within 1e-4 L on the CPU and 1e-3 L on the GPU): the segment's
//! lengths mapped to u by explicit inverse pieces, one polynomial a sample, built in one pass
//! over the segment at the accuracy the sampling needs rather than at the precise length's
//! 1e-12 (the whole of a w1-arc call was its tables' making).
//!
//! The segment is cut where its speed vanishes (a kink of |P'|; see
//! [`arc_length`](super::arc_length)). Each part is covered by model pieces: on [a, b] of width
//! w, the model of the length from a is the quintic Hermite interpolant s(x), x = (u − a)/w, of
//! the piece's length ℓ (the 8-point Gauss–Legendre rule), the speed v and its slope v' at the
//! ends (s' = v w, s'' = v' w²). The piece is kept when
//! - the model's slope s'(x) is within `accuracy` of w v at the rule's eight nodes: where it
//!   is so over the whole piece, the model is within `accuracy` of the length to any point
//!   inside (it meets the rule's length at x = 1, and the rule is exact for the model);
//! - the 4-point rule is within `quadrature_tolerance` w of the 8-point one (an estimate of
//!   the coarser rule's error, which bounds the finer's): the pieces' lengths, summed from the
//!   segment's start, are then within `quadrature_tolerance` times the range of u covered;
//!
//! else it is halved. Each model piece is then mapped back by the explicit inverse: degree-5
//! polynomials of the length, halved until each is within `accuracy` of its model at the
//! points between its interpolation nodes. A place is within the two accuracies and the
//! quadrature's share of the length asked; the bounds are measured at nodes and check points,
//! as the precise tables' halving test is, not proven ([`SegmentTable::place_tables`] says
//! what was measured).

use super::arc_length::{
    GL8_POSITIONS, MAX_DEPTH, Speed, polynomial, polynomial_slope, quintic_hermite,
};
use std::cell::Cell;

use super::arc_length::last_before;
use crate::segment::Segment;

/// The accuracy of a sampling's places relative to the curve's length (the quadrature's share
/// and the models' and inverses', as `SegmentTable::place_tables` shares it): a tenth of the
/// contract's CPU spacing (1e-4 L), room for what the measured bounds may miss; the GPU's f32
/// adds errors near 1e-6 L.
pub(crate) const PLACE_ACCURACY: f64 = 1e-5;

/// A segment's lengths mapped to u by explicit inverse pieces (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PlaceTable {
    length: f64,
    /// In order of the lengths where they start (the last ends at `length`).
    pieces: Box<[InversePiece]>,
}

thread_local! {
    /// A thread's inverse pieces while it makes a table, which keeps them at their exact
    /// number (a growing vector's spare room, kept for every segment of a sampling, was as
    /// large as the pieces).
    static SCRATCH: Cell<Vec<InversePiece>> = const { Cell::new(Vec::new()) };
}

impl PlaceTable {
    /// The table of `segment` (see the module docs): `quadrature_tolerance` per unit of u,
    /// `accuracy` in length.
    pub(crate) fn new(segment: &Segment<'_>, quadrature_tolerance: f64, accuracy: f64) -> Self {
        let speed = Speed::of(segment);
        let mut pieces = SCRATCH.take();
        pieces.clear();
        let mut builder = Builder {
            length: 0.0,
            pieces,
        };
        let tolerances = (quadrature_tolerance, accuracy);
        let mut a = 0.0;
        for (i, b) in speed.kinks().into_iter().enumerate() {
            // Away from a zero of the speed, it grows as |P''| times the distance: the slopes
            // at a kink are the one-sided ones.
            let mut ends = (speed.with_slope(a), speed.with_slope(b));
            if i > 0 {
                ends.0.1 = speed.bend_at(a);
            }
            if b < 1.0 {
                ends.1.1 = -speed.bend_at(b);
            }
            builder.fit(&speed, (a, b), ends, tolerances, 0);
            a = b;
        }
        let table = Self {
            length: builder.length,
            pieces: builder.pieces.as_slice().into(),
        };
        SCRATCH.set(builder.pieces);
        table
    }

    /// The segment's length (the model pieces' together).
    pub(crate) fn length(&self) -> f64 {
        self.length
    }

    /// The u in [0, 1] at which the length from 0 reaches `s` (clamped to [0, length]): one
    /// polynomial a length. `hint` is the inverse piece the last (nondecreasing) length fell
    /// in (0 for the first); the answer does not depend on it.
    #[inline]
    pub(crate) fn place(&self, s: f64, hint: &mut usize) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        if s >= self.length {
            return 1.0;
        }
        let last = self.pieces.len() - 1;
        let k = last_before(&self.pieces, (*hint).min(last), |p| p.s0 < s);
        *hint = k;
        self.pieces[k].at(s)
    }

    /// The inverse piece `k` and the lengths it takes, as [`PlaceTable::place`] chooses
    /// pieces: above its start and up to the next one's (the last: up to the segment's
    /// length; at or beyond it, u = 1).
    pub(crate) fn inverse_piece(&self, k: usize) -> (&InversePiece, f64) {
        let last = self.pieces.get(k + 1).map_or(f64::INFINITY, |p| p.s0);
        (&self.pieces[k], last)
    }

    /// The inverse's pieces as (the length where each starts, its u there, its u at its end,
    /// p's coefficients c1..c5 (c0 is 0: p(0) = 0)), for the GPU's f32 table: the kernel
    /// places a sample as the CPU does, one polynomial a sample.
    pub(crate) fn inverse_pieces(
        &self,
    ) -> impl ExactSizeIterator<Item = (f64, f64, f64, [f64; 5])> {
        self.pieces.iter().map(|p| {
            let c = [p.c[1], p.c[2], p.c[3], p.c[4], p.c[5]];
            (p.s0, p.u0, p.u0 + p.du, c)
        })
    }
}

/// A table being made: the length so far and the inverse pieces.
struct Builder {
    length: f64,
    pieces: Vec<InversePiece>,
}

impl Builder {
    /// Appends [a, b] (the speed and its slope at its ends in `ends`) as model pieces, each
    /// mapped back by its inverse pieces, halved while the model or the rule is off.
    fn fit(
        &mut self,
        speed: &Speed,
        (a, b): (f64, f64),
        ends: ((f64, f64), (f64, f64)),
        (quadrature_tolerance, accuracy): (f64, f64),
        depth: u32,
    ) {
        let w = b - a;
        let (length, at_nodes) = speed.gl8_nodes(a, b);
        let ((v0, dv0), (v1, dv1)) = ends;
        let c = quintic_hermite(length, v0 * w, v1 * w, dv0 * w * w, dv1 * w * w);
        // The model's slope at the nodes, and the rules' difference (see the module docs).
        let fits = length <= accuracy
            || (GL8_POSITIONS
                .iter()
                .zip(at_nodes)
                .all(|(&x, v)| (polynomial_slope(&c, x) - w * v).abs() <= accuracy)
                && (speed.gl4(a, b) - length).abs() <= w * quadrature_tolerance);
        if !fits && depth < MAX_DEPTH {
            let mid = 0.5 * (a + b);
            let at_mid = speed.with_slope(mid);
            let tolerances = (quadrature_tolerance, accuracy);
            self.fit(speed, (a, mid), (ends.0, at_mid), tolerances, depth + 1);
            self.fit(speed, (mid, b), (at_mid, ends.1), tolerances, depth + 1);
            return;
        }
        let model = Model {
            c,
            length: length.max(0.0),
            start: self.length,
            u: (a, w),
        };
        self.invert(&model, (0.0, 1.0), accuracy, 0);
        self.length += model.length;
    }

    /// Appends [xa, xb] of `model` (x its own parameter) as pieces of the explicit inverse,
    /// halved until each is within `accuracy` of the model. On a piece, x is the degree-5
    /// polynomial in the length through the model at the six Chebyshev–Lobatto points of x,
    /// and its error is measured at the five points of x between them: the model's length at
    /// the polynomial's x against the length asked. A piece no longer than the accuracy needs
    /// no test. Where the speed vanishes at a piece's end, x(s) grows as √s there and the
    /// pieces halve toward it.
    fn invert(&mut self, model: &Model, (xa, xb): (f64, f64), accuracy: f64, depth: u32) {
        let (sa, sb) = (model.at(xa), model.at(xb));
        let (ua, w) = model.u;
        let mut piece = InversePiece::linear((ua + xa * w, ua + xb * w), (sa, sb));
        if sb - sa > accuracy && xb > xa {
            let nodes: [f64; 6] = std::array::from_fn(|i| match i {
                0 => 0.0,
                5 => 1.0,
                _ => (model.at(xa + LOBATTO[i] * (xb - xa)) - sa) / (sb - sa),
            });
            let increasing = nodes.windows(2).all(|pair| pair[0] < pair[1]);
            let fits = increasing && {
                let p = interpolate(&nodes, &LOBATTO);
                let fits = MIDPOINTS.iter().all(|&m| {
                    let s = model.at(xa + m * (xb - xa));
                    let tau = (s - sa) / (sb - sa);
                    let x = xa + (xb - xa) * evaluate5(&p, tau).clamp(0.0, 1.0);
                    (model.at(x) - s).abs() <= accuracy
                });
                piece.c = p;
                fits
            };
            if !fits && depth < MAX_DEPTH {
                let mid = 0.5 * (xa + xb);
                self.invert(model, (xa, mid), accuracy, depth + 1);
                self.invert(model, (mid, xb), accuracy, depth + 1);
                return;
            }
            if !fits {
                piece.c = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
            }
        }
        // Lengths from the segment's start: the model piece's start plus the model's.
        piece.s0 += model.start;
        self.pieces.push(piece);
    }
}

/// A model piece: the length from `start` (at u = `u.0`, over a width `u.1` of u) as
/// c1 x + … + c5 x⁵, x in [0, 1], reaching `length` at x = 1.
struct Model {
    c: [f64; 5],
    length: f64,
    start: f64,
    u: (f64, f64),
}

impl Model {
    /// The length from the piece's start at x, within [0, length] (a piece of length 0, a
    /// segment that stands still, may end a rounding below its start).
    fn at(&self, x: f64) -> f64 {
        if x >= 1.0 {
            self.length
        } else {
            polynomial(&self.c, x).clamp(0.0, self.length)
        }
    }
}

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
