//! A [`CurveIndex`] packed for `shaders/closest.wgsl`, in the index's frame: every coordinate
//! x written as (x − c) / E in f32, c the centre of the root box and E its largest side, so
//! that the tables hold numbers of about 1 wherever the curves lie (their position relative to
//! one another kept to f32's 2^-24 of E), and the queries the same way.

use crate::error::{GpuError, InputError};
use crate::gpu::queries::abi::{ClosestAnswer, GpuNode};
use crate::query::pieces::piece_homogeneous;
use crate::query::{ClosestPoints, CurveIndex};

/// Query coordinates beyond this (in the frame, 1e15 extents from the curves) are clamped to
/// it: every point of the curves is then within 1e-15 (relative) of the nearest distance, far
/// inside the promise, and the kernel's squared distances stay within f32.
const FARTHEST: f64 = 1e15;

/// The smallest weight a piece may keep after its weights are divided by their largest: below
/// it the rational piece's denominator is not an f32 number.
const LEAST_WEIGHT: f32 = 1e-30;

/// The index's tables for the kernel.
#[derive(Debug)]
pub(crate) struct PackedIndex {
    pub dim: usize,
    /// c, the frame's origin (D values).
    pub origin: Vec<f64>,
    /// E, the frame's unit.
    pub unit: f64,
    pub nodes: Vec<GpuNode>,
    /// Per node, `lo` then `hi` in the frame, rounded outward.
    pub node_boxes: Vec<f32>,
    /// Per slot, its piece's box the same way.
    pub item_boxes: Vec<f32>,
    /// Per slot, its piece's weights w_0..w_3 (divided by the largest) then its control points
    /// Q_0..Q_3 in the frame: 4 + 4 D values.
    pub controls: Vec<f32>,
    /// Per slot, the index of its piece.
    pub order: Vec<u32>,
}

impl PackedIndex {
    /// `index` packed.
    ///
    /// # Errors
    /// [`GpuError::OutOfRange`] for a rational curve whose weights differ by more than f32's
    /// range.
    pub(crate) fn new(index: &CurveIndex<'_>) -> Result<Self, GpuError> {
        let dim = index.dim();
        let flat = index.tree().flat();
        let root = &flat.node_boxes[..2 * dim];
        let origin: Vec<f64> = (0..dim).map(|k| 0.5 * (root[k] + root[dim + k])).collect();
        let side = (0..dim)
            .map(|k| root[dim + k] - root[k])
            .fold(0.0, f64::max);
        let unit = if side > 0.0 && side.is_finite() {
            side
        } else {
            1.0
        };
        let frame = |k: usize, x: f64| (x - origin[k]) / unit;
        let outward = |boxes: &[f64]| -> Vec<f32> {
            boxes
                .chunks_exact(2 * dim)
                .flat_map(|b| {
                    let lo = (0..dim).map(move |k| round_down(frame(k, b[k])));
                    let hi = (0..dim).map(move |k| round_up(frame(k, b[dim + k])));
                    lo.chain(hi).collect::<Vec<_>>()
                })
                .collect()
        };
        let nodes = flat
            .nodes
            .iter()
            .map(|&(first, second, leaf)| GpuNode {
                first,
                second,
                leaf: u32::from(leaf),
                _padding: 0,
            })
            .collect();
        let (node_boxes, item_boxes) = (outward(flat.node_boxes), outward(flat.item_boxes));
        let pieces = index.pieces();
        let mut controls = Vec::with_capacity(flat.order.len() * (4 + 4 * dim));
        let mut h = Vec::with_capacity(4 * (dim + 1));
        for &item in flat.order {
            let piece = pieces[item as usize];
            let segment = index.tables()[piece.curve as usize].segment(piece.segment as usize);
            let (points, weights) = segment.rational_bezier();
            piece_homogeneous(&points, weights, (piece.u0, piece.u1), &mut h);
            let w: [f64; 4] = std::array::from_fn(|i| h[i * (dim + 1) + dim]);
            let largest = w.iter().copied().fold(0.0, f64::max);
            let scaled = w.map(|w| (w / largest) as f32);
            if scaled.iter().any(|&w| w.is_nan() || w < LEAST_WEIGHT) {
                return Err(GpuError::OutOfRange {
                    curve: piece.curve as usize,
                    what: "the ratio of its weights",
                });
            }
            controls.extend_from_slice(&scaled);
            for (i, wi) in w.iter().enumerate() {
                for k in 0..dim {
                    controls.push(frame(k, h[i * (dim + 1) + k] / wi) as f32);
                }
            }
        }
        Ok(Self {
            dim,
            origin,
            unit,
            nodes,
            node_boxes,
            item_boxes,
            controls,
            order: flat.order.to_vec(),
        })
    }

    /// `queries` (checked points, D values each) in the frame, into `out`.
    pub(crate) fn frame_queries(&self, queries: &[f64], out: &mut Vec<f32>) {
        out.clear();
        out.extend(queries.iter().enumerate().map(|(i, &x)| {
            let k = i % self.dim;
            ((x - self.origin[k]) / self.unit).clamp(-FARTHEST, FARTHEST) as f32
        }));
    }

    /// The kernel's answers for `queries` (D values each, the first of them query `first`)
    /// pushed onto `out`: the curve and its parameter (in f64) from the slot and u, the point
    /// out of the frame, the distance from it to the query.
    ///
    /// # Errors
    /// A distance beyond f32's range (a query about 1e38 from the curves), named by its
    /// query's index.
    pub(crate) fn push_answers(
        &self,
        index: &CurveIndex<'_>,
        (first, queries): (usize, &[f64]),
        answers: &[ClosestAnswer],
        points: &[f32],
        out: &mut ClosestPoints<f32>,
    ) -> Result<(), InputError> {
        let dim = self.dim;
        for (i, answer) in answers.iter().enumerate() {
            let piece = index.pieces()[self.order[answer.slot as usize] as usize];
            let u = f64::from(answer.u);
            let local = if u >= 1.0 {
                piece.u1
            } else {
                piece.u0 + (piece.u1 - piece.u0) * u
            };
            let (curve, segment) = (piece.curve as usize, piece.segment as usize);
            out.curve.push(curve);
            out.t.push(index.parameter(curve, segment, local));
            let mut d2 = 0.0;
            for k in 0..dim {
                let x = (self.origin[k] + self.unit * f64::from(points[i * dim + k])) as f32;
                d2 += (f64::from(x) - queries[i * dim + k]).powi(2);
                out.points.push(x);
            }
            let distance = d2.sqrt() as f32;
            if !distance.is_finite() {
                return Err(InputError::field(
                    format!("closest[{}]", first + i),
                    "lies too far from the curves: its distance overflows float32, the GPU \
                     backend's numbers (use the cpu backend)",
                ));
            }
            out.distance.push(distance);
        }
        Ok(())
    }
}

/// The f32 at or below `x`.
fn round_down(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) > x { r.next_down() } else { r }
}

/// The f32 at or above `x`.
fn round_up(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) < x { r.next_up() } else { r }
}
