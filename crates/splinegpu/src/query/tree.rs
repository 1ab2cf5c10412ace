//! A bounding-volume tree over axis-aligned boxes in D dimensions, for the queries' exclusion.
//!
//! Each item (a curve's segment, a surface's patch) holds a box that contains all of it (its
//! Bezier control points' box: a Bezier piece, rational with positive weights included, lies in
//! the convex hull of its control points). The tree splits the items at the median of their
//! boxes' centres along the widest axis until a leaf holds at most [`LEAF_ITEMS`], and every
//! node's box contains its children's. A query walks it depth first, nearer child first, and
//! leaves a node whose box is farther than the best answer so far: nothing in that box can be
//! nearer, so the exclusion loses no answer.

/// Items per leaf: a few exact solves are cheaper than another level of boxes.
pub(crate) const LEAF_ITEMS: usize = 4;

/// A node: its box (`lo`, `hi`: D values each, in the tree's box store) and either two
/// children or a range of items.
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Children's node indices, or (for a leaf) the range of `order` it holds.
    first: u32,
    second: u32,
    leaf: bool,
}

/// The tree: nodes, their boxes, and the items in leaf order.
#[derive(Clone, Debug)]
pub(crate) struct BoxTree {
    dim: usize,
    nodes: Vec<Node>,
    /// Per node, `lo` then `hi` (2 D values).
    boxes: Vec<f64>,
    /// Item indices in the order the leaves hold them.
    order: Vec<u32>,
    /// The items' own boxes in that order (2 D values each), checked before an item is
    /// visited.
    item_boxes: Vec<f64>,
}

/// [`BoxTree::flat`]'s tables.
pub(crate) struct FlatTree<'a> {
    /// Per node: (first child, second child, false) or (first slot, end slot, true).
    pub(crate) nodes: Vec<(u32, u32, bool)>,
    /// Per node, `lo` then `hi`.
    pub(crate) node_boxes: &'a [f64],
    /// Per slot, the item it holds.
    pub(crate) order: &'a [u32],
    /// Per slot, its item's box.
    pub(crate) item_boxes: &'a [f64],
}

impl BoxTree {
    /// The tree over `items` boxes given as `lo` then `hi` (2 D values per item).
    pub(crate) fn new(dim: usize, item_boxes: &[f64]) -> Self {
        let count = item_boxes.len() / (2 * dim);
        let mut tree = Self {
            dim,
            nodes: Vec::with_capacity(2 * count / LEAF_ITEMS + 1),
            boxes: Vec::new(),
            order: (0..count as u32).collect(),
            item_boxes: Vec::with_capacity(item_boxes.len()),
        };
        if count > 0 {
            let mut order = std::mem::take(&mut tree.order);
            // Each item's centre (doubled), looked up by the splits.
            let centres: Vec<f64> = item_boxes
                .chunks_exact(2 * dim)
                .flat_map(|b| (0..dim).map(move |k| b[k] + b[dim + k]))
                .collect();
            tree.build(item_boxes, &centres, &mut order, 0);
            for &item in &order {
                let b = &item_boxes[item as usize * 2 * dim..][..2 * dim];
                tree.item_boxes.extend_from_slice(b);
            }
            tree.order = order;
        }
        tree
    }

    /// Builds the node over `items` (a slice of `order` starting at `offset`), returning its
    /// index.
    fn build(
        &mut self,
        item_boxes: &[f64],
        centres: &[f64],
        items: &mut [u32],
        offset: usize,
    ) -> u32 {
        let dim = self.dim;
        let at = self.nodes.len();
        self.nodes.push(Node {
            first: 0,
            second: 0,
            leaf: true,
        });
        // This node's box: the union of its items'.
        let mut lo = vec![f64::INFINITY; dim];
        let mut hi = vec![f64::NEG_INFINITY; dim];
        for &item in items.iter() {
            let b = &item_boxes[item as usize * 2 * dim..][..2 * dim];
            for k in 0..dim {
                lo[k] = lo[k].min(b[k]);
                hi[k] = hi[k].max(b[dim + k]);
            }
        }
        self.boxes.extend_from_slice(&lo);
        self.boxes.extend_from_slice(&hi);
        if items.len() <= LEAF_ITEMS {
            self.nodes[at] = Node {
                first: offset as u32,
                second: (offset + items.len()) as u32,
                leaf: true,
            };
            return at as u32;
        }
        let centre = |item: u32, axis: usize| centres[item as usize * dim + axis];
        let axis = (0..dim)
            .max_by(|&i, &j| (hi[i] - lo[i]).total_cmp(&(hi[j] - lo[j])))
            .unwrap_or(0);
        let half = items.len() / 2;
        items.select_nth_unstable_by(half, |&a, &b| centre(a, axis).total_cmp(&centre(b, axis)));
        let (left, right) = items.split_at_mut(half);
        let first = self.build(item_boxes, centres, left, offset);
        let second = self.build(item_boxes, centres, right, offset + half);
        self.nodes[at] = Node {
            first,
            second,
            leaf: false,
        };
        at as u32
    }

    /// Every item whose box may hold something within `best` (a squared distance that `visit`
    /// may lower as it goes) of `q`, nearer boxes first; `visit(item, best)` is given the item's
    /// index. The walk leaves every node and item whose box lies at a squared distance
    /// >= `best`.
    pub(crate) fn nearest(&self, q: &[f64], best: &mut f64, mut visit: impl FnMut(u32, &mut f64)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack: Vec<(f64, u32)> = Vec::with_capacity(64);
        stack.push((self.distance2(0, q), 0));
        while let Some((d2, at)) = stack.pop() {
            if d2 >= *best {
                continue;
            }
            let node = self.nodes[at as usize];
            if node.leaf {
                for at in node.first as usize..node.second as usize {
                    let b = &self.item_boxes[at * 2 * self.dim..][..2 * self.dim];
                    let (lo, hi) = b.split_at(self.dim);
                    if box_distance2(lo, hi, q) < *best {
                        visit(self.order[at], best);
                    }
                }
                continue;
            }
            let (a, b) = (
                self.distance2(node.first, q),
                self.distance2(node.second, q),
            );
            // The nearer child is popped first.
            if a <= b {
                stack.push((b, node.second));
                stack.push((a, node.first));
            } else {
                stack.push((a, node.first));
                stack.push((b, node.second));
            }
        }
    }

    /// Every item whose box the ray o + s d (d a unit vector) enters at some s in [0, `best`],
    /// `best` lowered by `visit` as it goes, nearer entries first; the walk leaves every node
    /// the ray enters beyond `best`, or misses.
    pub(crate) fn along_ray(
        &self,
        o: &[f64],
        d: &[f64],
        best: &mut f64,
        mut visit: impl FnMut(u32, &mut f64),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let entry = |b: &[f64]| -> Option<f64> {
            let (mut enter, mut exit) = (0.0f64, f64::INFINITY);
            for k in 0..self.dim {
                let (lo, hi) = (b[k], b[self.dim + k]);
                if d[k] == 0.0 {
                    if o[k] < lo || o[k] > hi {
                        return None;
                    }
                    continue;
                }
                let (a, c) = ((lo - o[k]) / d[k], (hi - o[k]) / d[k]);
                enter = enter.max(a.min(c));
                exit = exit.min(a.max(c));
            }
            (enter <= exit).then_some(enter)
        };
        let mut stack: Vec<(f64, u32)> = Vec::with_capacity(64);
        if let Some(s) = entry(self.node_boxes(0)) {
            stack.push((s, 0));
        }
        while let Some((s, at)) = stack.pop() {
            if s > *best {
                continue;
            }
            let node = self.nodes[at as usize];
            if node.leaf {
                for i in node.first as usize..node.second as usize {
                    let b = &self.item_boxes[i * 2 * self.dim..][..2 * self.dim];
                    if entry(b).is_some_and(|s| s <= *best) {
                        visit(self.order[i], best);
                    }
                }
                continue;
            }
            let children = [node.first, node.second].map(|c| (entry(self.node_boxes(c)), c));
            let mut children: Vec<(f64, u32)> = children
                .into_iter()
                .filter_map(|(s, c)| s.map(|s| (s, c)))
                .collect();
            // The nearer entry is popped first.
            children.sort_by(|x, y| y.0.total_cmp(&x.0));
            stack.extend(children);
        }
    }

    /// Every pair of items (a from this tree, b from `other`) whose own boxes overlap, each
    /// once, handed to `visit(a, b)`.
    pub(crate) fn overlapping_pairs(&self, other: &Self, mut visit: impl FnMut(u32, u32)) {
        if self.nodes.is_empty() || other.nodes.is_empty() {
            return;
        }
        let dim = self.dim;
        let meet =
            |a: &[f64], b: &[f64]| (0..dim).all(|k| a[k] <= b[dim + k] && b[k] <= a[dim + k]);
        let mut stack = vec![(0u32, 0u32)];
        while let Some((a, b)) = stack.pop() {
            let (na, nb) = (self.nodes[a as usize], other.nodes[b as usize]);
            if !meet(self.node_boxes(a), other.node_boxes(b)) {
                continue;
            }
            match (na.leaf, nb.leaf) {
                (true, true) => {
                    for x in na.first as usize..na.second as usize {
                        for y in nb.first as usize..nb.second as usize {
                            let bx = &self.item_boxes[x * 2 * dim..][..2 * dim];
                            let by = &other.item_boxes[y * 2 * dim..][..2 * dim];
                            if meet(bx, by) {
                                visit(self.order[x], other.order[y]);
                            }
                        }
                    }
                }
                (false, true) => stack.extend([(na.first, b), (na.second, b)]),
                (true, false) => stack.extend([(a, nb.first), (a, nb.second)]),
                (false, false) => stack.extend([
                    (na.first, nb.first),
                    (na.first, nb.second),
                    (na.second, nb.first),
                    (na.second, nb.second),
                ]),
            }
        }
    }

    /// Every pair of distinct items of this tree whose boxes overlap, each once (the smaller
    /// item first): [`BoxTree::overlapping_pairs`] of the tree with itself, without the
    /// mirrored half.
    pub(crate) fn overlapping_pairs_within(&self, mut visit: impl FnMut(u32, u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let dim = self.dim;
        let meet =
            |a: &[f64], b: &[f64]| (0..dim).all(|k| a[k] <= b[dim + k] && b[k] <= a[dim + k]);
        let item = |x: usize| &self.item_boxes[x * 2 * dim..][..2 * dim];
        let emit = |x: usize, y: usize, visit: &mut dyn FnMut(u32, u32)| {
            if meet(item(x), item(y)) {
                let (a, b) = (self.order[x], self.order[y]);
                visit(a.min(b), a.max(b));
            }
        };
        // (a, b) with a == b: a node against itself; a != b: two nodes (each pair once).
        let mut stack = vec![(0u32, 0u32)];
        while let Some((a, b)) = stack.pop() {
            let (na, nb) = (self.nodes[a as usize], self.nodes[b as usize]);
            if a == b {
                if na.leaf {
                    for x in na.first as usize..na.second as usize {
                        for y in x + 1..na.second as usize {
                            emit(x, y, &mut visit);
                        }
                    }
                } else {
                    stack.extend([
                        (na.first, na.first),
                        (na.second, na.second),
                        (na.first, na.second),
                    ]);
                }
                continue;
            }
            if !meet(self.node_boxes(a), self.node_boxes(b)) {
                continue;
            }
            match (na.leaf, nb.leaf) {
                (true, true) => {
                    for x in na.first as usize..na.second as usize {
                        for y in nb.first as usize..nb.second as usize {
                            emit(x, y, &mut visit);
                        }
                    }
                }
                (false, true) => stack.extend([(na.first, b), (na.second, b)]),
                (true, false) => stack.extend([(a, nb.first), (a, nb.second)]),
                (false, false) => stack.extend([
                    (na.first, nb.first),
                    (na.first, nb.second),
                    (na.second, nb.first),
                    (na.second, nb.second),
                ]),
            }
        }
    }

    /// Node `at`'s box, `lo` then `hi`.
    /// The tree as flat tables, for a kernel that walks it (`gpu::queries`): per node its
    /// two children or its leaf's range of slots and whether it is a leaf, the nodes' boxes,
    /// the items in slot order and their boxes (2 D values a box, `lo` then `hi`).
    pub(crate) fn flat(&self) -> FlatTree<'_> {
        FlatTree {
            nodes: self
                .nodes
                .iter()
                .map(|n| (n.first, n.second, n.leaf))
                .collect(),
            node_boxes: &self.boxes,
            order: &self.order,
            item_boxes: &self.item_boxes,
        }
    }

    fn node_boxes(&self, at: u32) -> &[f64] {
        &self.boxes[at as usize * 2 * self.dim..][..2 * self.dim]
    }

    fn node_box(&self, at: u32) -> (&[f64], &[f64]) {
        let b = &self.boxes[at as usize * 2 * self.dim..][..2 * self.dim];
        b.split_at(self.dim)
    }

    /// The squared distance from `q` to node `at`'s box (0 inside it).
    fn distance2(&self, at: u32, q: &[f64]) -> f64 {
        let (lo, hi) = self.node_box(at);
        box_distance2(lo, hi, q)
    }
}

/// The squared distance from `q` to the box [lo, hi] (0 inside it).
#[inline]
pub(crate) fn box_distance2(lo: &[f64], hi: &[f64], q: &[f64]) -> f64 {
    let mut d2 = 0.0;
    for k in 0..q.len() {
        let gap = (lo[k] - q[k]).max(q[k] - hi[k]).max(0.0);
        d2 += gap * gap;
    }
    d2
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Unit boxes at 0, 1, ..., n-1 along x in 2-D.
    fn row(n: usize) -> Vec<f64> {
        (0..n)
            .flat_map(|i| {
                let x = i as f64;
                [x, 0.0, x + 0.5, 0.5]
            })
            .collect()
    }

    #[test]
    fn overlapping_pairs_are_those_of_brute_force() {
        let a = row(37);
        let b: Vec<f64> = (0..23)
            .flat_map(|i| {
                let x = i as f64 * 1.7;
                [x, 0.2, x + 0.2, 0.3]
            })
            .collect();
        let (ta, tb) = (BoxTree::new(2, &a), BoxTree::new(2, &b));
        let mut got = Vec::new();
        ta.overlapping_pairs(&tb, |i, j| got.push((i, j)));
        got.sort_unstable();
        let mut want = Vec::new();
        for i in 0..37u32 {
            for j in 0..23u32 {
                let (x, y) = (&a[i as usize * 4..][..4], &b[j as usize * 4..][..4]);
                if x[0] <= y[2] && y[0] <= x[2] && x[1] <= y[3] && y[1] <= x[3] {
                    want.push((i, j));
                }
            }
        }
        assert_eq!(got, want);
    }

    #[test]
    fn pairs_within_are_the_join_with_itself_once() {
        let boxes: Vec<f64> = (0..41)
            .flat_map(|i| {
                let x = (i * 7 % 41) as f64 * 0.37;
                [x, 0.0, x + 0.8, 1.0]
            })
            .collect();
        let tree = BoxTree::new(2, &boxes);
        let mut within = Vec::new();
        tree.overlapping_pairs_within(|a, b| within.push((a, b)));
        within.sort_unstable();
        let mut joined = Vec::new();
        tree.overlapping_pairs(&tree, |a, b| {
            if a < b {
                joined.push((a, b));
            }
        });
        joined.sort_unstable();
        assert_eq!(within, joined);
        assert!(!within.is_empty());
    }

    #[test]
    fn nearest_visits_the_box_holding_the_answer_and_prunes_far_ones() {
        let tree = BoxTree::new(2, &row(100));
        let mut visited = Vec::new();
        let mut best = f64::INFINITY;
        tree.nearest(&[41.2, 0.2], &mut best, |item, best| {
            visited.push(item);
            let lo = item as f64;
            let d = (41.2f64 - (lo + 0.25)).abs();
            *best = best.min(d * d);
        });
        assert!(visited.contains(&41));
        assert!(visited.len() <= 3 * LEAF_ITEMS, "{visited:?}");
    }
}
