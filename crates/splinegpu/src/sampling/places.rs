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

/// A curve's place tables: each segment's lengths mapped to u by explicit inverse pieces (see
/// the module docs), every segment's pieces in one allocation (a table a segment was as many
/// allocations, freed with the job and their pages faulted in again by the next).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PlaceTables {
    /// Each segment's length.
    lengths: Box<[f64]>,
    /// Segment i's pieces are `pieces[first[i]..first[i + 1]]`.
    first: Box<[usize]>,
    /// Each segment's in order of the lengths where they start (the last ends at the
    /// segment's length).
    pieces: Box<[InversePiece]>,
}

/// One segment's table: its length and its inverse pieces.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PlaceTable<'a> {
    length: f64,
    pieces: &'a [InversePiece],
}

thread_local! {
    /// A thread's inverse pieces while it makes a curve's tables, which keeps them at their
    /// exact number (a growing vector's spare room, kept for every curve of a sampling, was as
    /// large as the pieces).
    static SCRATCH: Cell<Vec<InversePiece>> = const { Cell::new(Vec::new()) };
}

impl PlaceTables {
    /// The tables of `segments` (see the module docs): `quadrature_tolerance` per unit of u,
    /// `accuracy` in length.
    pub(crate) fn new<'s>(
        segments: impl ExactSizeIterator<Item = Segment<'s>>,
        quadrature_tolerance: f64,
        accuracy: f64,
    ) -> Self {
        let mut lengths = Vec::with_capacity(segments.len());
        let mut first = Vec::with_capacity(segments.len() + 1);
        let mut pieces = SCRATCH.take();
        pieces.clear();
        let mut builder = Builder {
            length: 0.0,
            pieces,
        };
        first.push(0);
        for segment in segments {
            builder.length = 0.0;
            builder.segment(&segment, quadrature_tolerance, accuracy);
            lengths.push(builder.length);
            first.push(builder.pieces.len());
        }
        let tables = Self {
            lengths: lengths.into(),
            first: first.into(),
            pieces: builder.pieces.as_slice().into(),
        };
        SCRATCH.set(builder.pieces);
        tables
    }

    /// The number of segments.
    pub(crate) fn len(&self) -> usize {
        self.lengths.len()
    }

    /// Segment `i`'s table.
    pub(crate) fn get(&self, i: usize) -> PlaceTable<'_> {
        PlaceTable {
            length: self.lengths[i],
            pieces: &self.pieces[self.first[i]..self.first[i + 1]],
        }
    }

    /// Every segment's table, in order.
    pub(crate) fn iter(&self) -> impl ExactSizeIterator<Item = PlaceTable<'_>> {
        (0..self.len()).map(|i| self.get(i))
    }
}

impl<'a> PlaceTable<'a> {
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
        let k = last_before(self.pieces, (*hint).min(last), |p| p.s0 < s);
        *hint = k;
        self.pieces[k].at(s)
    }

    /// The inverse piece `k` and the lengths it takes, as [`PlaceTable::place`] chooses
    /// pieces: above its start and up to the next one's (the last: up to the segment's
    /// length; at or beyond it, u = 1).
    pub(crate) fn inverse_piece(&self, k: usize) -> (&'a InversePiece, f64) {
        let last = self.pieces.get(k + 1).map_or(f64::INFINITY, |p| p.s0);
        (&self.pieces[k], last)
    }

    /// The inverse's pieces as (the length where each starts, its u there, its u at its end,
    /// p's coefficients c1..c5 (c0 is 0: p(0) = 0)), for the GPU's f32 table: the kernel
    /// places a sample as the CPU does, one polynomial a sample.
    pub(crate) fn inverse_pieces(
        &self,
    ) -> impl ExactSizeIterator<Item = (f64, f64, f64, [f64; 5])> + 'a {
        self.pieces.iter().map(|p| {
            let c = [p.c[1], p.c[2], p.c[3], p.c[4], p.c[5]];
            (p.s0, p.u0, p.u0 + p.du, c)
        })
    }
}

/// Tables being made: the length so far of the segment being made, and the inverse pieces.
struct Builder {
    length: f64,
    pieces: Vec<InversePiece>,
}

impl Builder {
    /// Appends `segment`'s pieces (its length from 0 in `self.length`).
    fn segment(&mut self, segment: &Segment<'_>, quadrature_tolerance: f64, accuracy: f64) {
        let speed = Speed::of(segment);
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
            self.fit(&speed, (a, b), ends, tolerances, 0);
            a = b;
        }
    }

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
        // Every node is tested, none skipped (a NaN is not within): straight-line code, no
        // branch a node.
        let within_at_nodes: usize = GL8_POSITIONS
            .iter()
            .zip(at_nodes)
            .map(|(&x, v)| usize::from((polynomial_slope(&c, x) - w * v).abs() <= accuracy))
            .sum();
        let fits = length <= accuracy
            || (within_at_nodes == GL8_POSITIONS.len()
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
            // Every node and check point is computed, none skipped (a NaN is not within):
            // straight-line code, no branch a point.
            let (dx, ds) = (xb - xa, sb - sa);
            let nodes: [f64; 6] = std::array::from_fn(|i| match i {
                0 => 0.0,
                5 => 1.0,
                _ => (model.at(xa + LOBATTO[i] * dx) - sa) / ds,
            });
            let increasing = nodes.windows(2).all(|pair| pair[0] < pair[1]);
            let p = interpolate(&nodes, &LOBATTO);
            let lengths = MIDPOINTS.map(|m| model.at(xa + m * dx));
            let within: usize = lengths
                .iter()
                .map(|&s| {
                    let tau = (s - sa) / ds;
                    let x = xa + dx * evaluate5(&p, tau).clamp(0.0, 1.0);
                    usize::from((model.at(x) - s).abs() <= accuracy)
                })
                .sum();
            let fits = increasing && within == MIDPOINTS.len();
            if increasing {
                piece.c = p;
            }
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
    #[inline]
    fn at(&self, x: f64) -> f64 {
        // Clamped by comparisons, as `InversePiece::at` is (`f64::clamp` checks that its
        // bounds are ordered, a branch at every call).
        let s = polynomial(&self.c, x);
        if x >= 1.0 || s > self.length {
            self.length
        } else if s < 0.0 {
            0.0
        } else {
            s
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
        let u = self.u0 + self.du * evaluate5(&self.c, tau);
        // Clamped to [u0, u0 + du] (du >= 0) by selects: `f64::clamp`'s check of bounds not
        // known to be ordered would keep the callers' loops from vectorizing.
        let end = self.u0 + self.du;
        if u < self.u0 {
            self.u0
        } else if u > end {
            end
        } else {
            u
        }
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
