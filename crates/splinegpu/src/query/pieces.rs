//! Segments cut into pieces for the queries' box trees: each piece [u0, u1] of a segment with
//! the box of its own Bezier control points (de Casteljau's, homogeneous for a rational
//! segment, whose weights stay positive), which holds every point of the piece.
//!
//! Segments are cut into pieces no longer (along their control polygon) than E / (k√n), E the
//! extent of all the control points, n the number of segments and k the caller's fineness
//! (measured on the bench's q1 and q2: 8 for closest points, 2 for intersections), at most
//! [`MAX_PIECES`] a segment: a box small beside the spacing of the curves prunes, where a
//! segment that crosses the whole set would hold most query points (or most other segments)
//! in its box.

use crate::segment::SegmentTable;

/// A piece [u0, u1] of a curve's segment: an item of the tree.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Piece {
    pub(crate) curve: u32,
    pub(crate) segment: u32,
    pub(crate) u0: f64,
    pub(crate) u1: f64,
}

/// A segment's (rational) Bezier control points and weights, as `Segment::rational_bezier`
/// gives them.
type RationalBezier = ([Vec<f64>; 4], [f64; 4]);

/// The most pieces a segment is cut into.
const MAX_PIECES: usize = 64;

/// Every segment of `tables` cut into pieces (module docs), and each piece's box, `lo` then
/// `hi`, widened by a few units in the last place of its coordinates for the rounding of the
/// conversion and the subdivision.
pub(crate) fn pieces(tables: &[SegmentTable], dim: usize, fineness: f64) -> (Vec<Piece>, Vec<f64>) {
    let beziers: Vec<Vec<RationalBezier>> = tables
        .iter()
        .map(|t| {
            (0..t.len())
                .map(|s| t.segment(s).rational_bezier())
                .collect()
        })
        .collect();
    let count: usize = beziers.iter().map(Vec::len).sum();
    let (mut lo, mut hi) = (vec![f64::INFINITY; dim], vec![f64::NEG_INFINITY; dim]);
    for (points, _) in beziers.iter().flatten() {
        for p in points {
            for k in 0..dim {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let extent = (0..dim).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let longest = extent / (fineness * (count as f64).sqrt());
    let mut items = Vec::with_capacity(count);
    let mut boxes = Vec::with_capacity(count * 2 * dim);
    let mut scratch = Vec::with_capacity(4 * (dim + 1));
    for (c, segments) in beziers.iter().enumerate() {
        for (s, (points, weights)) in segments.iter().enumerate() {
            let polygon: f64 = points
                .windows(2)
                .map(|w| {
                    (0..dim)
                        .map(|k| (w[1][k] - w[0][k]).powi(2))
                        .sum::<f64>()
                        .sqrt()
                })
                .sum();
            let cuts = if longest > 0.0 && polygon.is_finite() {
                ((polygon / longest).ceil() as usize).clamp(1, MAX_PIECES)
            } else {
                1
            };
            for i in 0..cuts {
                let (u0, u1) = (i as f64 / cuts as f64, (i + 1) as f64 / cuts as f64);
                items.push(Piece {
                    curve: c as u32,
                    segment: s as u32,
                    u0,
                    u1,
                });
                push_piece_box(points, *weights, (u0, u1), &mut scratch, &mut boxes);
            }
        }
    }
    (items, boxes)
}

/// The box of the Bezier control points of the piece [u0, u1] of the (rational) cubic with
/// control points `points` and weights `weights` (see [`piece_homogeneous`]), appended to
/// `boxes`. `h` is scratch space.
fn push_piece_box(
    points: &[Vec<f64>; 4],
    weights: [f64; 4],
    piece: (f64, f64),
    h: &mut Vec<f64>,
    boxes: &mut Vec<f64>,
) {
    let dim = points[0].len();
    piece_homogeneous(points, weights, piece, h);
    let at = boxes.len();
    boxes.resize(at + 2 * dim, 0.0);
    for k in 0..dim {
        let values = (0..4).map(|i| h[i * (dim + 1) + k] / h[i * (dim + 1) + dim]);
        let lo = values.clone().fold(f64::INFINITY, f64::min);
        let hi = values.fold(f64::NEG_INFINITY, f64::max);
        let pad = 64.0 * f64::EPSILON * lo.abs().max(hi.abs()).max(hi - lo);
        boxes[at + k] = lo - pad;
        boxes[at + dim + k] = hi + pad;
    }
}

/// The homogeneous Bezier control points (ω Q, ω) of the piece [u0, u1] of the (rational)
/// cubic with control points `points` and weights `weights`, D + 1 values each (the weight
/// last), into `h`: de Casteljau split at u1 and then at u0 / u1.
pub(crate) fn piece_homogeneous(
    points: &[Vec<f64>; 4],
    weights: [f64; 4],
    (u0, u1): (f64, f64),
    h: &mut Vec<f64>,
) {
    let dim = points[0].len();
    let width = dim + 1;
    h.clear();
    for (p, &w) in points.iter().zip(&weights) {
        h.extend(p.iter().map(|x| x * w));
        h.push(w);
    }
    // In place: keeping the left part [0, at] leaves point i = the i-th left edge of the
    // triangle; keeping the right part [at, 1] the i-th right edge.
    let split = |h: &mut [f64], at: f64, keep_left: bool| {
        for level in 1..4 {
            if keep_left {
                for i in (level..4).rev() {
                    for k in 0..width {
                        let (a, b) = (h[(i - 1) * width + k], h[i * width + k]);
                        h[i * width + k] = a + at * (b - a);
                    }
                }
            } else {
                for i in 0..4 - level {
                    for k in 0..width {
                        let (a, b) = (h[i * width + k], h[(i + 1) * width + k]);
                        h[i * width + k] = a + at * (b - a);
                    }
                }
            }
        }
    };
    if u1 < 1.0 {
        split(h, u1, true);
    }
    if u0 > 0.0 {
        split(h, u0 / u1, false);
    }
}
