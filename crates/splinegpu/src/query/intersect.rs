//! Every point where two 2-D curves meet (and where one meets itself), certified
//! (docs/queries.md).
//!
//! Pairs of pieces whose boxes overlap come from the curves' box trees. On a pair, with A(s)
//! and B(t) the two segments, the search looks at a box X = S × T of their parameters and
//! F(s, t) = A(s) − B(t):
//! - **exclusion by hulls**: the boxes of the two pieces' control points do not meet, or one
//!   piece's control points all lie on one side of the other's fat line (the band about its
//!   chord that holds its control points; Sederberg and Nishita, 1990), so neither do the
//!   pieces;
//! - **the Krawczyk test** on X' (X widened by a twentieth of its size on each side): with
//!   x̃ its centre, Y the inverse of F's Jacobian at x̃ and J(X') an interval enclosure of the
//!   Jacobian [A'(S), −B'(T)] over it ([`planar`](super::planar)),
//!   K = x̃ − Y F(x̃) + (I − Y J(X')) (X' − x̃), widened by |Y| ε/4 (where the curves come within
//!   ε/4 they are taken to meet). Every such point of X' lies in K (the mean value theorem), so
//!   K ∩ X' = ∅ excludes X'; and K inside the interior of X' proves that X' holds exactly one
//!   root (Krawczyk, 1969; Moore, 1977), to which Newton's method from x̃ converges;
//! - otherwise the longer piece is halved and both halves are looked at again, until both
//!   pieces lie in boxes smaller than ε/2 (ε = 1e-9 (E + |q|∞)): such a pair is within ε of
//!   meeting, and its centre is a candidate (a tangency, a singular point, the end of an
//!   overlap), merged with its neighbours into one point.
//!
//! Where two segments coincide along a piece (the ends of each lying on the other, and the
//! points between too), the two ends are reported with `overlap` and nothing between them.
//! Two pieces of one curve that meet at their common joint exclude that joint: where some
//! axis orders both pieces' tangents strictly the same way, the pieces lie on either side of
//! the joint along that axis and share no other point.

use std::collections::HashSet;

use crate::error::InputError;
use crate::query::closest::closest_on_segment;
use crate::query::pieces::{Piece, pieces};
use crate::query::planar::{Interval, PlanarSegment, fat_line_apart, hull_box};
use crate::query::tree::BoxTree;
use crate::segment::SegmentTable;

/// A point where two curves meet (or one meets itself).
#[derive(Clone, Debug, PartialEq)]
pub struct Intersection {
    /// The first curve of the pair, as the query names it.
    pub i: usize,
    /// The second curve (equal to `i` for a self-intersection).
    pub j: usize,
    /// Curve i's parameter at the point.
    pub t_i: f64,
    /// Curve j's parameter there (for a self-intersection, the larger of the two).
    pub t_j: f64,
    /// The point, curve i at t_i.
    pub point: [f64; 2],
    /// The curves touch here with tangents parallel within 1e-6 radians.
    pub tangent: bool,
    /// One end of a piece along which the curves coincide.
    pub overlap: bool,
}

/// Which pairs of curves to intersect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pairs<'a> {
    /// Every pair i < j.
    All,
    /// These pairs, in this order; [i, i] asks for curve i's self-intersections.
    Listed(&'a [[usize; 2]]),
}

/// Every intersection of the `pairs` of 2-D `curves`, sorted by the pair's place (for
/// [`Pairs::All`], by i and then j), then t_i, then t_j.
///
/// ```
/// use splinegpu::{Curve, CurveKind, Points, query::{Pairs, intersections}};
///
/// // The diagonals of the unit square, as straight cubic Beziers.
/// let line = |coords: Vec<f64>| Curve::new(CurveKind::Bezier, Points::new(2, coords)?);
/// let a = line(vec![0.0, 0.0, 1.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 1.0, 1.0])?;
/// let b = line(vec![0.0, 1.0, 1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0, 1.0, 0.0])?;
/// let found = intersections(&[a.fit(), b.fit()], Pairs::All)?;
/// assert_eq!(found.len(), 1);
/// assert!((found[0].point[0] - 0.5).abs() < 1e-12 && (found[0].t_i - 0.5).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// No curves; a curve that is not 2-D (named by its index); a listed pair naming a curve
/// that is not there (named as `intersections[k]`).
pub fn intersections(
    curves: &[SegmentTable],
    pairs: Pairs<'_>,
) -> Result<Vec<Intersection>, InputError> {
    if curves.is_empty() {
        return Err(InputError::field("curves", "must not be empty"));
    }
    if let Some(c) = curves.iter().position(|t| t.dim() != 2) {
        return Err(InputError::field(
            "points",
            format!(
                "must have 2 coordinates for intersections, got {}",
                curves[c].dim()
            ),
        )
        .in_curve(c));
    }
    if let Pairs::Listed(listed) = pairs
        && let Some(k) = listed
            .iter()
            .position(|p| p.iter().any(|&c| c >= curves.len()))
    {
        return Err(InputError::field(
            format!("intersections[{k}]"),
            format!(
                "names a curve that is not there ({} curves): {:?}",
                curves.len(),
                listed[k]
            ),
        ));
    }
    let set = CurveSet::new(curves, matches!(pairs, Pairs::Listed(_)));
    // Per pair of curves, the pairs of their pieces whose boxes meet: for "all" from one join
    // of a tree over every piece with itself, for listed pairs from the two curves' trees.
    let groups: Vec<PairOfCurves> = match pairs {
        Pairs::Listed(listed) => listed.iter().map(|&[i, j]| ([i, j], Vec::new())).collect(),
        Pairs::All => set.meeting_pieces(),
    };
    let listed = matches!(pairs, Pairs::Listed(_));
    let found = crate::parallel::fan_out_map(
        crate::parallel::even_ranges(groups.len(), crate::available_threads() * 4).collect(),
        |range: std::ops::Range<usize>| {
            let mut scratch = Scratch::default();
            range
                .flat_map(|k| {
                    let ([i, j], pieces) = &groups[k];
                    if listed {
                        let pieces = set.piece_pairs(*i, *j);
                        set.pair(*i, *j, &pieces, &mut scratch)
                    } else {
                        set.pair(*i, *j, pieces, &mut scratch)
                    }
                })
                .collect::<Vec<_>>()
        },
    );
    Ok(found.into_iter().flatten().collect())
}

/// Two curves (i, j) and the pairs of their pieces whose boxes meet (indices into each
/// curve's pieces; empty where they are still to be found).
type PairOfCurves = ([usize; 2], Vec<(usize, usize)>);

/// Buffers one thread reuses from pair to pair: the search's stack and its candidates.
#[derive(Default)]
struct Scratch {
    stack: Vec<(Interval, Interval)>,
    found: Vec<Candidate>,
}

/// The curves, their segments as polynomials, their pieces in box trees (one a curve).
struct CurveSet<'a> {
    tables: &'a [SegmentTable],
    segments: Vec<Vec<PlanarSegment>>,
    /// Per curve, its pieces in order (segment, then u) and (for listed pairs) their tree.
    pieces: Vec<Vec<Piece>>,
    trees: Vec<BoxTree>,
    /// Per curve, its pieces' boxes (lo x, lo y, hi x, hi y each), in its pieces' order.
    piece_boxes: Vec<Vec<f64>>,
    /// The extent E of ε.
    extent: f64,
}

/// A candidate meeting of two segments: local parameters, and whether Krawczyk's test proved
/// it (false: a pair of pieces within ε of each other).
#[derive(Clone, Copy, Debug)]
struct Candidate {
    s: f64,
    t: f64,
    proven: bool,
}

/// Two segments that coincide between two ends (each end's local parameters on both).
#[derive(Clone, Copy, Debug)]
struct Overlap {
    sa: usize,
    sb: usize,
    ends: [Candidate; 2],
}

/// Where two pieces of one curve meet at their joint: the joint's local parameters on each.
#[derive(Clone, Copy, Debug)]
struct Joint {
    s: f64,
    t: f64,
}

impl<'a> CurveSet<'a> {
    fn new(tables: &'a [SegmentTable], per_curve_trees: bool) -> Self {
        let (items, boxes) = pieces(tables, 2, 2.0);
        let mut per_curve = vec![Vec::new(); tables.len()];
        let mut per_curve_boxes = vec![Vec::new(); tables.len()];
        for (piece, b) in items.iter().zip(boxes.chunks_exact(4)) {
            per_curve[piece.curve as usize].push(*piece);
            per_curve_boxes[piece.curve as usize].extend_from_slice(b);
        }
        let trees = if per_curve_trees {
            per_curve_boxes.iter().map(|b| BoxTree::new(2, b)).collect()
        } else {
            Vec::new()
        };
        // The extent E of ε: the largest range, per axis, of all the pieces' boxes.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for b in boxes.chunks_exact(4) {
            for k in 0..2 {
                lo[k] = lo[k].min(b[k]);
                hi[k] = hi[k].max(b[2 + k]);
            }
        }
        Self {
            tables,
            segments: tables
                .iter()
                .map(|t| {
                    (0..t.len())
                        .map(|s| PlanarSegment::new(&t.segment(s)))
                        .collect()
                })
                .collect(),
            pieces: per_curve,
            trees,
            piece_boxes: per_curve_boxes,
            extent: (hi[0] - lo[0]).max(hi[1] - lo[1]),
        }
    }

    /// Every pair i < j of curves with pieces whose boxes meet, with those pairs of pieces
    /// (their indices in each curve's pieces), from one tree over all the pieces joined with
    /// itself; in the order of i, then j.
    fn meeting_pieces(&self) -> Vec<PairOfCurves> {
        let mut owners = Vec::new();
        let mut boxes = Vec::new();
        for (c, tree_boxes) in self.piece_boxes.iter().enumerate() {
            for (local, b) in tree_boxes.chunks_exact(4).enumerate() {
                owners.push((c, local));
                boxes.extend_from_slice(b);
            }
        }
        let tree = BoxTree::new(2, &boxes);
        let mut meetings = Vec::new();
        tree.overlapping_pairs_within(|a, b| {
            let ((ca, la), (cb, lb)) = (owners[a as usize], owners[b as usize]);
            if ca != cb {
                // Pieces come in curve order, so a < b puts the lower curve first.
                meetings.push((ca, cb, la, lb));
            }
        });
        meetings.sort_unstable();
        let mut groups: Vec<PairOfCurves> = Vec::new();
        for (ca, cb, la, lb) in meetings {
            match groups.last_mut() {
                Some((pair, pieces)) if *pair == [ca, cb] => pieces.push((la, lb)),
                _ => groups.push(([ca, cb], vec![(la, lb)])),
            }
        }
        groups
    }

    /// The pairs of pieces of curves i and j whose boxes meet (i == j: a <= b), sorted.
    fn piece_pairs(&self, i: usize, j: usize) -> Vec<(usize, usize)> {
        let mut pairs = Vec::new();
        self.trees[i].overlapping_pairs(&self.trees[j], |a, b| {
            if i != j || a <= b {
                pairs.push((a as usize, b as usize));
            }
        });
        pairs.sort_unstable();
        pairs
    }

    /// ε at a point: 1e-9 (E + |q|∞).
    fn eps(&self, q: [f64; 2]) -> f64 {
        1e-9 * (self.extent + q[0].abs().max(q[1].abs()))
    }

    /// The intersections of curves i and j (i == j: curve i's own), sorted by t_i, then t_j.
    fn pair(
        &self,
        i: usize,
        j: usize,
        piece_pairs: &[(usize, usize)],
        scratch: &mut Scratch,
    ) -> Vec<Intersection> {
        let mut candidates: Vec<(usize, usize, Candidate)> = Vec::new();
        let mut overlaps: Vec<Overlap> = Vec::new();
        // Segment pairs whose overlap was looked for, and those found to overlap.
        let mut checked: HashSet<(u32, u32)> = HashSet::new();
        let mut coinciding: HashSet<(u32, u32)> = HashSet::new();
        let closed = i == j && self.is_closed(i);
        for &(a, b) in piece_pairs {
            let (pa, pb) = (self.pieces[i][a], self.pieces[j][b]);
            let key = (pa.segment, pb.segment);
            let same_segment = i == j && pa.segment == pb.segment;
            if coinciding.contains(&key) {
                continue;
            }
            let joint = if i != j {
                None
            } else if a == b {
                // One piece against itself: its loop, if any.
                self.self_piece(i, pa, scratch);
                let tag = |c| (pa.segment as usize, pa.segment as usize, c);
                candidates.extend(scratch.found.drain(..).map(tag));
                continue;
            } else {
                self.joint(i, a, b, closed)
            };
            let (sa, sb) = (
                &self.segments[i][pa.segment as usize],
                &self.segments[j][pb.segment as usize],
            );
            let (s, t) = ([pa.u0, pa.u1], [pb.u0, pb.u1]);
            let tag = |c| (pa.segment as usize, pb.segment as usize, c);
            // A few boxes settle a pair of pieces that cross or miss; one that takes more is
            // looked at for an overlap of its segments first (whose search would never end).
            let settled = self.search((sa, s), (sb, t), joint, SEARCH_BUDGET, scratch);
            if !settled
                && !same_segment
                && checked.insert(key)
                && let Some(ends) = self.overlap(i, pa.segment, j, pb.segment)
            {
                overlaps.push(ends);
                coinciding.insert(key);
                continue;
            }
            if !settled {
                self.search((sa, s), (sb, t), joint, usize::MAX, scratch);
            }
            candidates.extend(scratch.found.drain(..).map(tag));
        }
        self.gather(i, j, &candidates, &overlaps)
    }

    /// Whether curve c ends where it starts (within ε), so that its last and first pieces meet
    /// at a joint.
    fn is_closed(&self, c: usize) -> bool {
        let table = &self.tables[c];
        let (mut start, mut end) = ([0.0; 2], [0.0; 2]);
        table.segment(0).eval(0.0, &mut start);
        table.segment(table.len() - 1).eval(1.0, &mut end);
        (start[0] - end[0]).abs().max((start[1] - end[1]).abs()) <= self.eps(start)
    }

    /// The joint two pieces a < b of curve c share, if they are neighbours: a's end and b's
    /// start, or on a closed curve its first piece's start and its last's end.
    fn joint(&self, c: usize, a: usize, b: usize, closed: bool) -> Option<Joint> {
        let pieces = &self.pieces[c];
        if b == a + 1 {
            let (pa, pb) = (pieces[a], pieces[b]);
            // Within one segment the joint is a cut (u1 = next u0); across segments, the knot.
            return Some(Joint {
                s: pa.u1,
                t: if pa.segment == pb.segment { pb.u0 } else { 0.0 },
            });
        }
        (closed && a == 0 && b == pieces.len() - 1).then_some(Joint { s: 0.0, t: 1.0 })
    }

    /// A piece's meetings with itself: none where some axis orders its tangents one way (the
    /// piece is then monotone along it); otherwise its two halves against each other (meeting
    /// at the middle, a joint) and each against itself.
    fn self_piece(&self, c: usize, piece: Piece, scratch: &mut Scratch) {
        let segment = &self.segments[c][piece.segment as usize];
        let mut stack = vec![[piece.u0, piece.u1]];
        while let Some([lo, hi]) = stack.pop() {
            if monotone_axis(&segment.derivative_box(lo, hi)).is_some() || hi - lo < 1e-12 {
                continue;
            }
            let mid = 0.5 * (lo + hi);
            let joint = Some(Joint { s: mid, t: mid });
            let (left, right) = ((segment, [lo, mid]), (segment, [mid, hi]));
            self.search(left, right, joint, usize::MAX, scratch);
            stack.push([lo, mid]);
            stack.push([mid, hi]);
        }
    }

    /// The search of the module docs on the pieces `s` of `a` and `t` of `b` (`joint`, where
    /// they are neighbours on one curve), its candidates added to `scratch.found`. False,
    /// with none added, where it would look at more than `budget` boxes.
    fn search(
        &self,
        (a, s): (&PlanarSegment, Interval),
        (b, t): (&PlanarSegment, Interval),
        joint: Option<Joint>,
        budget: usize,
        scratch: &mut Scratch,
    ) -> bool {
        // B's origin moved into A's frame: F = A_local(s) − (B_local(t) − shift).
        let shift = [a.origin[0] - b.origin[0], a.origin[1] - b.origin[1]];
        let (stack, found) = (&mut scratch.stack, &mut scratch.found);
        let kept = found.len();
        stack.clear();
        stack.push((s, t));
        let mut steps = 0usize;
        let mut found = |c| found.push(c);
        while let Some((s, t)) = stack.pop() {
            steps += 1;
            if steps > budget {
                scratch.found.truncate(kept);
                return false;
            }
            let points_a = a.local_points(s[0], s[1]);
            let points_b = b
                .local_points(t[0], t[1])
                .map(|p| [p[0] - shift[0], p[1] - shift[1]]);
            let (box_a, box_b) = (hull_box(&points_a), hull_box(&points_b));
            let point = [a.origin[0] + box_a[0][0], a.origin[1] + box_a[1][0]];
            let eps = self.eps(point);
            let pad = 0.25 * eps;
            if (0..2).any(|k| box_a[k][0] > box_b[k][1] + pad || box_b[k][0] > box_a[k][1] + pad)
                || fat_line_apart(&points_a, &points_b, pad)
                || fat_line_apart(&points_b, &points_a, pad)
            {
                continue;
            }
            let at_joint =
                joint.is_some_and(|j| (s[0] == j.s || s[1] == j.s) && (t[0] == j.t || t[1] == j.t));
            if at_joint
                && let (Some(x), Some(y)) = (
                    monotone_axis(&a.derivative_box(s[0], s[1])),
                    monotone_axis(&b.derivative_box(t[0], t[1])),
                )
                && x.0 == y.0
                && x.1 == y.1
            {
                // Both pieces run the same way along one axis: they share only the joint.
                continue;
            }
            match krawczyk(a, s, b, t, shift, eps) {
                Verdict::None => continue,
                Verdict::One(root) => {
                    if (0.0..=1.0).contains(&root[0]) && (0.0..=1.0).contains(&root[1]) {
                        found(Candidate {
                            s: root[0],
                            t: root[1],
                            proven: true,
                        });
                    }
                    continue;
                }
                Verdict::Unknown => {}
            }
            let size = |bx: &[Interval; 2]| (bx[0][1] - bx[0][0]).max(bx[1][1] - bx[1][0]);
            let (size_a, size_b) = (size(&box_a), size(&box_b));
            if size_a <= NEAR * eps && size_b <= NEAR * eps {
                // Small pieces the test cannot settle run nearly parallel (a tangency): where
                // they come within ε, their closest approach stands for the box.
                let (sc, tc) = closest_approach((a, s), (b, t), shift);
                let (pa, pb) = (a.local(sc), b.local(tc));
                let gap = (pa[0] - pb[0] + shift[0]).hypot(pa[1] - pb[1] + shift[1]);
                if gap <= eps {
                    found(Candidate {
                        s: sc,
                        t: tc,
                        proven: false,
                    });
                    continue;
                }
            }
            let narrow = s[1] - s[0] < 1e-15 && t[1] - t[0] < 1e-15;
            if (size_a <= 0.5 * eps && size_b <= 0.5 * eps) || narrow || steps > MAX_STEPS {
                found(Candidate {
                    s: 0.5 * (s[0] + s[1]),
                    t: 0.5 * (t[0] + t[1]),
                    proven: false,
                });
                continue;
            }
            if size_a >= size_b {
                let mid = 0.5 * (s[0] + s[1]);
                stack.push(([s[0], mid], t));
                stack.push(([mid, s[1]], t));
            } else {
                let mid = 0.5 * (t[0] + t[1]);
                stack.push((s, [t[0], mid]));
                stack.push((s, [mid, t[1]]));
            }
        }
        true
    }

    /// Whether segment `sa` of curve i and segment `sb` of curve j coincide along a piece:
    /// its two ends (as (segment, local parameters)), where two distinct ends of either
    /// segment lie on the other and seven points between them lie on it too.
    fn overlap(&self, i: usize, sa: u32, j: usize, sb: u32) -> Option<Overlap> {
        let (a, b) = (
            self.tables[i].segment(sa as usize),
            self.tables[j].segment(sb as usize),
        );
        let at = |segment: &crate::Segment<'_>, u: f64| {
            let mut p = [0.0; 2];
            segment.eval(u, &mut p);
            p
        };
        let mut ends: Vec<(f64, f64, [f64; 2])> = Vec::new();
        for u in [0.0, 1.0] {
            let p = at(&a, u);
            let (v, d) = closest_on_segment(&b, &p);
            if d <= self.eps(p) {
                ends.push((u, v, p));
            }
            let p = at(&b, u);
            let (v, d) = closest_on_segment(&a, &p);
            if d <= self.eps(p) {
                ends.push((v, u, p));
            }
        }
        ends.sort_by(|x, y| x.0.total_cmp(&y.0));
        let (first, last) = (ends.first()?, ends.last()?);
        let gap = (first.2[0] - last.2[0])
            .abs()
            .max((first.2[1] - last.2[1]).abs());
        if gap <= 4.0 * self.eps(first.2) {
            return None;
        }
        for k in 1..8 {
            let u = first.0 + (last.0 - first.0) * k as f64 / 8.0;
            let p = at(&a, u);
            if closest_on_segment(&b, &p).1 > self.eps(p) {
                return None;
            }
        }
        let end = |e: &(f64, f64, [f64; 2])| Candidate {
            s: e.0,
            t: e.1,
            proven: true,
        };
        Some(Overlap {
            sa: sa as usize,
            sb: sb as usize,
            ends: [end(first), end(last)],
        })
    }

    /// The candidates and overlaps of curves i and j as intersections: overlaps joined across
    /// joints and reported by their ends, candidates inside them dropped, neighbouring
    /// candidates merged into one (a proven one where there is one), self-intersections at a
    /// single parameter dropped, sorted by t_i, then t_j.
    fn gather(
        &self,
        i: usize,
        j: usize,
        candidates: &[(usize, usize, Candidate)],
        overlaps: &[Overlap],
    ) -> Vec<Intersection> {
        let global = |c: usize, segment: usize, u: f64| {
            let piece = self.tables[c].segment(segment);
            if u >= 1.0 {
                self.tables[c].knots()[segment + 1]
            } else {
                piece.t0() + u * piece.dt()
            }
        };
        let point_of = |c: usize, segment: usize, u: f64| {
            let mut p = [0.0; 2];
            self.tables[c].segment(segment).eval(u, &mut p);
            p
        };
        let make = |sa: usize, sb: usize, c: Candidate, overlap: bool| {
            let (ti, tj) = (global(i, sa, c.s), global(j, sb, c.t));
            let da = self.segments[i][sa].derivative(c.s);
            let db = self.segments[j][sb].derivative(c.t);
            let cross = (da[0] * db[1] - da[1] * db[0]).abs();
            let norms = da[0].hypot(da[1]) * db[0].hypot(db[1]);
            let (t_i, t_j) = if i == j && tj < ti {
                (tj, ti)
            } else {
                (ti, tj)
            };
            Intersection {
                i,
                j,
                t_i,
                t_j,
                point: point_of(i, sa, c.s),
                tangent: !overlap && cross <= 1e-6 * norms,
                overlap,
            }
        };
        // Overlaps: both ends of each, then joined where one's end is the next one's start.
        let mut spans: Vec<(Intersection, Intersection)> = overlaps
            .iter()
            .map(|o| {
                let [x, y] = o.ends;
                (make(o.sa, o.sb, x, true), make(o.sa, o.sb, y, true))
            })
            .map(|(x, y)| if y.t_i < x.t_i { (y, x) } else { (x, y) })
            .collect();
        spans.sort_by(|x, y| x.0.t_i.total_cmp(&y.0.t_i));
        let mut joined: Vec<(Intersection, Intersection)> = Vec::new();
        for span in spans {
            match joined.last_mut() {
                Some(last) if self.same_point(&last.1, &span.0) => last.1 = span.1,
                _ => joined.push(span),
            }
        }
        let mut points: Vec<(Intersection, bool, f64)> = candidates
            .iter()
            .map(|&(sa, sb, c)| {
                let x = make(sa, sb, c, false);
                let pb = point_of(j, sb, c.t);
                let miss = (x.point[0] - pb[0]).hypot(x.point[1] - pb[1]);
                (x, c.proven, miss)
            })
            .filter(|(x, ..)| {
                !joined.iter().any(|(a, b)| {
                    x.t_i >= a.t_i.min(b.t_i) - 1e-12 && x.t_i <= a.t_i.max(b.t_i) + 1e-12
                        || self.same_point(x, a)
                        || self.same_point(x, b)
                })
            })
            .filter(|(x, ..)| i != j || !self.one_place(i, x.t_i, x.t_j))
            .collect();
        points.sort_by(|x, y| {
            x.0.t_i
                .total_cmp(&y.0.t_i)
                .then(x.0.t_j.total_cmp(&y.0.t_j))
        });
        // Candidates of one meeting: neighbours (by t_i) between which the curves stay
        // within 4ε (at the middle of both parameters), as along a tangency's run; two proven
        // roots only where they are one point (found from neighbouring boxes).
        let mut merged: Vec<(Intersection, bool, f64)> = Vec::new();
        for p in points {
            let one = merged.last().is_some_and(|last| {
                if last.1 && p.1 {
                    return self.same_point(&last.0, &p.0);
                }
                let close = (last.0.t_i - p.0.t_i).abs() <= self.t_gap(i)
                    && (last.0.t_j - p.0.t_j).abs() <= self.t_gap(j);
                close && self.together(i, j, &last.0, &p.0)
            });
            match merged.last_mut() {
                Some(last) if one => {
                    let better = (p.1 && !last.1) || (p.1 == last.1 && p.2 < last.2);
                    if better {
                        *last = p;
                    }
                }
                _ => merged.push(p),
            }
        }
        let mut out: Vec<Intersection> = merged.into_iter().map(|(x, ..)| x).collect();
        for (a, b) in joined {
            out.push(a);
            out.push(b);
        }
        out.sort_by(|x, y| x.t_i.total_cmp(&y.t_i).then(x.t_j.total_cmp(&y.t_j)));
        out
    }

    /// Whether two reported points are one: within 4ε of each other.
    fn same_point(&self, a: &Intersection, b: &Intersection) -> bool {
        let gap = (a.point[0] - b.point[0])
            .abs()
            .max((a.point[1] - b.point[1]).abs());
        gap <= 4.0 * self.eps(a.point)
    }

    /// How far apart in curve c's parameter two candidates of one meeting may be: 1e-3 of its
    /// parameter range (a tangency's candidates spread over about √ε of it).
    fn t_gap(&self, c: usize) -> f64 {
        let (t0, t1) = self.tables[c].t_range();
        1e-3 * (t1 - t0)
    }

    /// Whether curves i and j stay within 4ε of each other halfway between two meetings (at
    /// the middle of t_i and of t_j).
    fn together(&self, i: usize, j: usize, x: &Intersection, y: &Intersection) -> bool {
        let (p, q) = (
            self.at(i, 0.5 * (x.t_i + y.t_i)),
            self.at(j, 0.5 * (x.t_j + y.t_j)),
        );
        (p[0] - q[0]).hypot(p[1] - q[1]) <= 4.0 * self.eps(p)
    }

    /// Whether curve c's meeting with itself at t_a < t_b is one place passed once, not a
    /// self-intersection: the curve stays within 4ε of it halfway between (a joint with
    /// itself, or a stretch where it barely moves), where a loop between them goes away.
    fn one_place(&self, c: usize, t_a: f64, t_b: f64) -> bool {
        let (p, m) = (self.at(c, t_a), self.at(c, 0.5 * (t_a + t_b)));
        (p[0] - m[0]).hypot(p[1] - m[1]) <= 4.0 * self.eps(p)
    }

    /// Curve c at parameter t.
    fn at(&self, c: usize, t: f64) -> [f64; 2] {
        let table = &self.tables[c];
        let knots = table.knots();
        let s = knots[1..knots.len() - 1].partition_point(|&k| k <= t);
        let segment = table.segment(s);
        let mut p = [0.0; 2];
        segment.eval(((t - segment.t0()) / segment.dt()).clamp(0.0, 1.0), &mut p);
        p
    }
}

/// The boxes a pair of pieces may look at before its segments are checked for an overlap.
const SEARCH_BUDGET: usize = 64;

/// Pieces smaller than this many ε that the Krawczyk test leaves undecided are settled by
/// their closest approach (a tangency's run of boxes would otherwise go down to ε).
const NEAR: f64 = 1e3;

/// The closest approach of two small pieces (A on `s`, B on `t`): alternate projections, each
/// by Newton's method on the squared distance's slope, kept in the pieces' intervals; then,
/// where the pieces cross at a shallow angle (where the projections crawl, by cos² of it a
/// step), Newton's method on A(s) − B(t) = 0, each step kept only where it brings them nearer
/// (not within 1e-6 radians of a tangency, where the projections' answer stands).
fn closest_approach(
    (a, s): (&PlanarSegment, Interval),
    (b, t): (&PlanarSegment, Interval),
    shift: [f64; 2],
) -> (f64, f64) {
    // The parameter on `segment` (within `range`) nearest to `target` (in its frame).
    let project = |segment: &PlanarSegment, range: Interval, target: [f64; 2], mut u: f64| {
        for _ in 0..6 {
            let (p, d) = (segment.local(u), segment.derivative(u));
            let e = [p[0] - target[0], p[1] - target[1]];
            let slope = e[0] * d[0] + e[1] * d[1];
            let curvature = d[0] * d[0] + d[1] * d[1];
            if curvature == 0.0 {
                break;
            }
            u = (u - slope / curvature).clamp(range[0], range[1]);
        }
        u
    };
    let (mut sc, mut tc) = (0.5 * (s[0] + s[1]), 0.5 * (t[0] + t[1]));
    for _ in 0..4 {
        let pa = a.local(sc);
        tc = project(b, t, [pa[0] + shift[0], pa[1] + shift[1]], tc);
        let pb = b.local(tc);
        sc = project(a, s, [pb[0] - shift[0], pb[1] - shift[1]], sc);
    }
    let gap = |sc: f64, tc: f64| {
        let (pa, pb) = (a.local(sc), b.local(tc));
        [pa[0] - pb[0] + shift[0], pa[1] - pb[1] + shift[1]]
    };
    let mut f = gap(sc, tc);
    for _ in 0..8 {
        let (da, db) = (a.derivative(sc), b.derivative(tc));
        // F' = [A'(s), −B'(t)]; within 1e-6 radians of parallel (a tangency) the projections'
        // answer stands.
        let det = -da[0] * db[1] + da[1] * db[0];
        if det.abs() <= 1e-6 * da[0].hypot(da[1]) * db[0].hypot(db[1]) || !det.is_finite() {
            break;
        }
        let ds = (-f[0] * db[1] + f[1] * db[0]) / det;
        let dt = (da[0] * f[1] - da[1] * f[0]) / det;
        let (ns, nt) = ((sc - ds).clamp(s[0], s[1]), (tc - dt).clamp(t[0], t[1]));
        let g = gap(ns, nt);
        if g[0].hypot(g[1]) >= f[0].hypot(f[1]) {
            break;
        }
        (sc, tc, f) = (ns, nt, g);
    }
    (sc, tc)
}

/// The most boxes one pair of pieces may look at before its remaining boxes are reported as
/// candidates (a bound on the work at a tangency; each such box is within ε of meeting).
const MAX_STEPS: usize = 200_000;

/// An axis along which every vector of `d` points strictly one way: (axis, positive).
fn monotone_axis(d: &[Interval; 2]) -> Option<(usize, bool)> {
    (0..2).find_map(|k| {
        if d[k][0] > 0.0 {
            Some((k, true))
        } else if d[k][1] < 0.0 {
            Some((k, false))
        } else {
            None
        }
    })
}

/// What the Krawczyk test proved about a box.
enum Verdict {
    /// No root in it.
    None,
    /// Exactly one, here (polished by Newton's method).
    One([f64; 2]),
    /// Neither.
    Unknown,
}

/// The Krawczyk test of the module docs on S × T (widened by a twentieth each side). A root
/// is taken as proven only where Newton's method brought |F| within ε/4 and the tangents
/// there are more than 1e-6 radians apart: a near-tangency (where rounding can fake the test,
/// and Newton's method crawls) is left to the subdivision.
fn krawczyk(
    a: &PlanarSegment,
    s: Interval,
    b: &PlanarSegment,
    t: Interval,
    shift: [f64; 2],
    eps: f64,
) -> Verdict {
    let widen = |x: Interval| {
        let pad = 0.05 * (x[1] - x[0]);
        [x[0] - pad, x[1] + pad]
    };
    let (s, t) = (widen(s), widen(t));
    let centre = [0.5 * (s[0] + s[1]), 0.5 * (t[0] + t[1])];
    let half = [0.5 * (s[1] - s[0]), 0.5 * (t[1] - t[0])];
    let f = |x: [f64; 2]| {
        let (pa, pb) = (a.local(x[0]), b.local(x[1]));
        [pa[0] - pb[0] + shift[0], pa[1] - pb[1] + shift[1]]
    };
    let jacobian = |x: [f64; 2]| {
        let (da, db) = (a.derivative(x[0]), b.derivative(x[1]));
        [[da[0], -db[0]], [da[1], -db[1]]]
    };
    let j = jacobian(centre);
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let scale = (j[0][0].abs() + j[1][0].abs()) * (j[0][1].abs() + j[1][1].abs());
    if !det.is_finite() || det.abs() <= 1e-12 * scale {
        return Verdict::Unknown;
    }
    let y = [
        [j[1][1] / det, -j[0][1] / det],
        [-j[1][0] / det, j[0][0] / det],
    ];
    let fc = f(centre);
    let c = [
        centre[0] - (y[0][0] * fc[0] + y[0][1] * fc[1]),
        centre[1] - (y[1][0] * fc[0] + y[1][1] * fc[1]),
    ];
    // J over the box: columns A'(S) and −B'(T).
    let (da, db) = (a.derivative_box(s[0], s[1]), b.derivative_box(t[0], t[1]));
    let jx: [[Interval; 2]; 2] = [
        [da[0], [-db[0][1], -db[0][0]]],
        [da[1], [-db[1][1], -db[1][0]]],
    ];
    let mut radius = [0.0; 2];
    for (index, (r, row)) in radius.iter_mut().zip(&y).enumerate() {
        for col in 0..2 {
            // (I − Y J)[r][col] = δ − Σ_k Y[r][k] J[k][col], as an interval.
            let mut lo = 0.0;
            let mut hi = 0.0;
            for k in 0..2 {
                let (p, q) = (row[k] * jx[k][col][0], row[k] * jx[k][col][1]);
                lo += p.min(q);
                hi += p.max(q);
            }
            let delta = if index == col { 1.0 } else { 0.0 };
            let magnitude = (delta - lo).abs().max((delta - hi).abs());
            *r += magnitude * half[col];
        }
    }
    // The curves are taken to meet where they come within ε/4 (the hulls' pad): F may be off
    // by that much at every point, which Y carries into K. Without it a touching point that
    // rounding leaves 1e-17 apart would be excluded as no root.
    for (r, row) in radius.iter_mut().zip(&y) {
        *r += (row[0].abs() + row[1].abs()) * 0.25 * eps;
    }
    let bounds = [s, t];
    let inside = (0..2).all(|k| c[k] - radius[k] > bounds[k][0] && c[k] + radius[k] < bounds[k][1]);
    let apart = (0..2).any(|k| c[k] + radius[k] < bounds[k][0] || c[k] - radius[k] > bounds[k][1]);
    if apart {
        return Verdict::None;
    }
    if !inside {
        return Verdict::Unknown;
    }
    // One root in the box: Newton's method from c, kept in the box.
    let mut x = c;
    for _ in 0..8 {
        let (fx, jx) = (f(x), jacobian(x));
        let det = jx[0][0] * jx[1][1] - jx[0][1] * jx[1][0];
        if det == 0.0 {
            break;
        }
        let step = [
            (jx[1][1] * fx[0] - jx[0][1] * fx[1]) / det,
            (-jx[1][0] * fx[0] + jx[0][0] * fx[1]) / det,
        ];
        let next = [
            (x[0] - step[0]).clamp(bounds[0][0], bounds[0][1]),
            (x[1] - step[1]).clamp(bounds[1][0], bounds[1][1]),
        ];
        if next == x {
            break;
        }
        x = next;
    }
    let (fx, jx) = (f(x), jacobian(x));
    let det = jx[0][0] * jx[1][1] - jx[0][1] * jx[1][0];
    let norms = jx[0][0].hypot(jx[1][0]) * jx[0][1].hypot(jx[1][1]);
    if fx[0].hypot(fx[1]) > 0.25 * eps || det.abs() <= 1e-6 * norms {
        return Verdict::Unknown;
    }
    // Within rounding of a segment's end counts as on it.
    Verdict::One(x.map(|u| {
        if (-1e-12..0.0).contains(&u) {
            0.0
        } else if (1.0..=1.0 + 1e-12).contains(&u) {
            1.0
        } else {
            u
        }
    }))
}
