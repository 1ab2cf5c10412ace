//! An index packed for the query kernels, in the index's frame: every coordinate x written as
//! (x − c) / E in f32, c the centre of the root box and E its largest side, so that the tables
//! hold numbers of about 1 wherever the curves or surfaces lie (their position relative to one
//! another kept to f32's 2^-24 of E), and the queries the same way. [`PackedTree`] is the box
//! tree; [`PackedIndex`] adds the curves' pieces, [`PackedNets`] the surfaces' patches.

use crate::error::{GpuError, InputError};
use crate::gpu::queries::abi::{ClosestAnswer, GpuNode};
use crate::query::pieces::piece_homogeneous;
use crate::query::tree::FlatTree;
use crate::query::{ClosestPoints, CurveIndex, SurfaceIndex};

/// Query coordinates beyond this (in the frame, 1e15 extents from the curves) are clamped to
/// it: every point of the curves is then within 1e-15 (relative) of the nearest distance, far
/// inside the promise, and the kernel's squared distances stay within f32.
const FARTHEST: f64 = 1e15;

/// The smallest weight a piece may keep after its weights are divided by their largest: below
/// it the rational piece's denominator is not an f32 number.
const LEAST_WEIGHT: f32 = 1e-30;

/// A box tree in its frame.
#[derive(Debug)]
pub(crate) struct PackedTree {
    pub dim: usize,
    /// c, the frame's origin (D values).
    pub origin: Vec<f64>,
    /// E, the frame's unit.
    pub unit: f64,
    pub nodes: Vec<GpuNode>,
    /// Per node, `lo` then `hi` in the frame, rounded outward.
    pub node_boxes: Vec<f32>,
    /// Per slot, its item's box the same way.
    pub item_boxes: Vec<f32>,
    /// Per slot, the index of its item.
    pub order: Vec<u32>,
}

impl PackedTree {
    fn new(flat: &FlatTree<'_>, dim: usize) -> Self {
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
        let mut tree = Self {
            dim,
            origin,
            unit,
            nodes: flat
                .nodes
                .iter()
                .map(|&(first, second, leaf)| GpuNode {
                    first,
                    second,
                    leaf: u32::from(leaf),
                    _padding: 0,
                })
                .collect(),
            node_boxes: Vec::new(),
            item_boxes: Vec::new(),
            order: flat.order.to_vec(),
        };
        tree.node_boxes = tree.outward(flat.node_boxes);
        tree.item_boxes = tree.outward(flat.item_boxes);
        tree
    }

    /// Coordinate k of `x` in the frame.
    pub(crate) fn frame(&self, k: usize, x: f64) -> f64 {
        (x - self.origin[k]) / self.unit
    }

    /// Boxes (`lo` then `hi`, D values each) in the frame, rounded outward to f32.
    fn outward(&self, boxes: &[f64]) -> Vec<f32> {
        let dim = self.dim;
        let mut out = Vec::with_capacity(boxes.len());
        for b in boxes.chunks_exact(2 * dim) {
            out.extend((0..dim).map(|k| round_down(self.frame(k, b[k]))));
            out.extend((0..dim).map(|k| round_up(self.frame(k, b[dim + k]))));
        }
        out
    }

    /// Points (D values each) in the frame, into `out`.
    pub(crate) fn frame_points(&self, points: &[f64], out: &mut Vec<f32>) {
        out.clear();
        out.extend(
            points
                .iter()
                .enumerate()
                .map(|(i, &x)| self.frame(i % self.dim, x).clamp(-FARTHEST, FARTHEST) as f32),
        );
    }

    /// Coordinate k of a point of the frame, back in the index's coordinates.
    pub(crate) fn unframe(&self, k: usize, x: f32) -> f64 {
        self.origin[k] + self.unit * f64::from(x)
    }
}

/// Weights divided by their largest, in f32.
///
/// # Errors
/// The curve or surface `which` names when a weight falls below [`LEAST_WEIGHT`] so.
fn scaled_weights<const N: usize>(w: [f64; N], which: usize) -> Result<[f32; N], GpuError> {
    let largest = w.iter().copied().fold(0.0, f64::max);
    let scaled = w.map(|w| (w / largest) as f32);
    if scaled.iter().any(|&w| w.is_nan() || w < LEAST_WEIGHT) {
        return Err(GpuError::OutOfRange {
            curve: which,
            what: "the ratio of its weights",
        });
    }
    Ok(scaled)
}

/// A [`CurveIndex`] for `shaders/closest.wgsl`.
#[derive(Debug)]
pub(crate) struct PackedIndex {
    pub tree: PackedTree,
    /// Per slot, its piece's weights w_0..w_3 (divided by the largest) then its control points
    /// Q_0..Q_3 in the frame: 4 + 4 D values.
    pub controls: Vec<f32>,
}

impl PackedIndex {
    /// `index` packed.
    ///
    /// # Errors
    /// [`GpuError::OutOfRange`] for a rational curve whose weights differ by more than f32's
    /// range.
    pub(crate) fn new(index: &CurveIndex<'_>) -> Result<Self, GpuError> {
        let dim = index.dim();
        let tree = PackedTree::new(&index.tree().flat(), dim);
        let pieces = index.pieces();
        let mut controls = Vec::with_capacity(tree.order.len() * (4 + 4 * dim));
        let mut h = Vec::with_capacity(4 * (dim + 1));
        for &item in &tree.order {
            let piece = pieces[item as usize];
            let segment = index.tables()[piece.curve as usize].segment(piece.segment as usize);
            let (points, weights) = segment.rational_bezier();
            piece_homogeneous(&points, weights, (piece.u0, piece.u1), &mut h);
            let w: [f64; 4] = std::array::from_fn(|i| h[i * (dim + 1) + dim]);
            controls.extend_from_slice(&scaled_weights(w, piece.curve as usize)?);
            for (i, wi) in w.iter().enumerate() {
                for k in 0..dim {
                    controls.push(tree.frame(k, h[i * (dim + 1) + k] / wi) as f32);
                }
            }
        }
        Ok(Self { tree, controls })
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
        let dim = self.tree.dim;
        for (i, answer) in answers.iter().enumerate() {
            let piece = index.pieces()[self.tree.order[answer.slot as usize] as usize];
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
                let x = self.tree.unframe(k, points[i * dim + k]) as f32;
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

/// A [`SurfaceIndex`] for `shaders/surface_queries.wgsl`.
#[derive(Debug)]
pub(crate) struct PackedNets {
    pub tree: PackedTree,
    /// Per slot, its patch's weights w_ij (ij = 4 i + j, i along u; divided by the largest)
    /// then its control points Q_ij in the frame: 16 + 16 D values.
    pub nets: Vec<f32>,
}

impl PackedNets {
    /// `index` packed.
    ///
    /// # Errors
    /// [`GpuError::OutOfRange`] for a rational surface whose weights differ by more than f32's
    /// range (named as its index, in the error's "curve").
    pub(crate) fn new(index: &SurfaceIndex<'_>) -> Result<Self, GpuError> {
        let dim = index.dim();
        let tree = PackedTree::new(&index.tree().flat(), dim);
        let mut nets = Vec::with_capacity(tree.order.len() * (16 + 16 * dim));
        for &item in &tree.order {
            let (origin, net) = &index.nets()[item as usize];
            let w: [f64; 16] = std::array::from_fn(|ij| net.values[ij * (dim + 1) + dim]);
            nets.extend_from_slice(&scaled_weights(w, index.surface_of(item as usize))?);
            for (ij, wij) in w.iter().enumerate() {
                for (k, o) in origin.iter().enumerate() {
                    let x = o + net.values[ij * (dim + 1) + k] / wij;
                    nets.push(tree.frame(k, x) as f32);
                }
            }
        }
        Ok(Self { tree, nets })
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
