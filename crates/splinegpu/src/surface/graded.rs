//! Graded meshes: every patch its own n_u x n_v cells, an edge shared by patches of other
//! counts meshed once at the larger, and each patch's interior making the transition to its
//! edges without T-junctions (the tolerance mesher's plans, [`super::tolerance`]).
//!
//! # A patch's triangles
//!
//! A patch of N = (N_u, N_v) cells whose four sides are cut into e_s >= N intervals each
//! (sides 0 and 1 at u = 0 and 1, along v; sides 2 and 3 at v = 0 and 1, along u; N the
//! patch's count along the side):
//!
//! - every e_s equal to its N: the N_u x N_v grid, two triangles a cell;
//! - else, N_u, N_v >= 2: the inner grid of the vertices (a/N_u, b/N_v), 0 < a < N_u,
//!   0 < b < N_v, two triangles a cell, and a ring round it: each side's e_s + 1 points zipped
//!   to the inner grid's side facing it (from inner corner to inner corner), by their place
//!   along the side: the zipper steps along whichever row's next point comes first;
//! - else (N_u or N_v is 1): a strip: the two sides that run across the direction of count 1
//!   (at u = 0 and 1 where N_u is 1) zipped by their place, and each of the other two sides
//!   fanned onto the far vertex of the zipper's triangle at its end.
//!
//! # Within tol
//!
//! The certificate (module [`super::tolerance`]) bounds a flat triangle's gap by
//! 1/2 Σ λ_i Q(p_i − x) <= 1/2 (A Σ λ_i du_i² + B Σ λ_i dv_i²) with A = M_uu + M_uv,
//! B = M_vv + M_uv and du_i = u_i − x_u: Σ λ_i du_i² is the variance of u under the weights
//! λ, at most R_u² / 4 for a triangle spanning R_u in u; so a triangle spanning at most 1/N_u
//! in u and 1/N_v in v is within (A / N_u² + B / N_v²) / 8 <= tol, N being the patch's own
//! counts (A / N_u² <= 4 tol). Grid cells span exactly that; a zipper's triangle has two
//! neighbouring points of one row (spacing <= 1/N) and one of the other, which the zipper
//! keeps within the larger of the rows' spacings, and the rows are one inner step apart
//! (1/N_u or 1/N_v); a strip's triangles span at most all of the direction whose count is 1.
//! Tested on random counts (`every_triangle_spans_at_most_a_cell`).
//!
//! # Within the cap
//!
//! A patch makes 2 N_u N_v + Σ_s (e_s − N_s) triangles (the ring: 2 (N_u − 2)(N_v − 2) inside,
//! e_s + N − 2 along each side; the strip: Σ_s e_s − 2). With e_s = max(N_s, N'_s), N' the
//! neighbour's count along the shared side, e_s − N_s is 0 unless N'_s > N_s >= 1, and then at
//! most N'_s − 1: charge it to the neighbour. A patch of counts (n_u, n_v) is charged at most
//! once through each of its four sides (an edge borders at most two patches), at most
//! 2 (n_u − 1) + 2 (n_v − 1) <= 2 n_u n_v in all (the difference is 2 (n_u − 1)(n_v − 1) + 2).
//! So the mesh has at most Σ 4 n_u n_v triangles, twice the sum over patches of 2 n_u n_v:
//! the contract's cap, with each patch's own counts.
//!
//! # Watertight
//!
//! Every point of a side is keyed by where it is on the surface, not by the patch: a net's by
//! its segment and place in each direction (a line between two patches belongs to the one
//! that starts there, a closed direction's last line is its first), a patch list's as the
//! welded grids key it (a corner's control index, an edge's four indices in the smaller order
//! and its place along them). Both patches of an edge count it alike (e_s), so they find the
//! same points: made once, bit-identical, and no point of one side inside a triangle edge of
//! the other.

use std::collections::HashMap;

use crate::error::InputError;
use crate::surface::mesh::{SurfacePlan, Vertex, check_count};
use crate::surface::patch::PatchTable;

/// A point of one patch's mesh: point k of side s (of e_s + 1), or inner grid vertex (a, b).
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
enum Local {
    Side(usize, usize),
    Inner(usize, usize),
}

/// A patch's cells and its sides' counts (0 and 1 along v at u = 0 and 1, 2 and 3 along u at
/// v = 0 and 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct PatchCounts {
    cells: [usize; 2],
    sides: [usize; 4],
}

impl PatchCounts {
    /// Whether the patch is a plain grid: every side counted as its cells.
    fn plain(&self) -> bool {
        let [nu, nv] = self.cells;
        self.sides == [nv, nv, nu, nu]
    }

    /// Where `point` is in the patch's local (u, v).
    fn local(&self, point: Local) -> [f64; 2] {
        let place = |k: usize, e: usize| k as f64 / e as f64;
        match point {
            Local::Side(s, k) => {
                let t = place(k, self.sides[s]);
                match s {
                    0 => [0.0, t],
                    1 => [1.0, t],
                    2 => [t, 0.0],
                    _ => [t, 1.0],
                }
            }
            Local::Inner(a, b) => [place(a, self.cells[0]), place(b, self.cells[1])],
        }
    }

    /// `point` as a side's point where it lies on a side (inner grid vertices on the boundary
    /// of a plain grid), so that each boundary point has one name.
    fn canonical(&self, point: Local) -> Local {
        let [nu, nv] = self.cells;
        match point {
            Local::Inner(0, b) => Local::Side(0, b),
            Local::Inner(a, b) if a == nu => Local::Side(1, b),
            Local::Inner(a, 0) => Local::Side(2, a),
            Local::Inner(a, b) if b == nv => Local::Side(3, a),
            // A corner is side 0's or side 1's end.
            Local::Side(2, 0) => Local::Side(0, 0),
            Local::Side(3, 0) => Local::Side(0, self.sides[0]),
            Local::Side(2, k) if k == self.sides[2] => Local::Side(1, 0),
            Local::Side(3, k) if k == self.sides[3] => Local::Side(1, self.sides[1]),
            other => other,
        }
    }

    /// The patch's triangles, counter-clockwise in (u, v), each as its three points.
    fn triangles(&self, emit: &mut impl FnMut([Local; 3])) {
        let [nu, nv] = self.cells;
        // A cell's two triangles, counter-clockwise as made.
        let cell = |emit: &mut dyn FnMut([Local; 3]), a: usize, b: usize| {
            let (p, q, r, s) = (
                Local::Inner(a, b),
                Local::Inner(a + 1, b),
                Local::Inner(a + 1, b + 1),
                Local::Inner(a, b + 1),
            );
            emit([p, q, r]);
            emit([p, r, s]);
        };
        if self.plain() {
            for a in 0..nu {
                for b in 0..nv {
                    cell(emit, a, b);
                }
            }
            return;
        }
        if nu >= 2 && nv >= 2 {
            for a in 1..nu - 1 {
                for b in 1..nv - 1 {
                    cell(emit, a, b);
                }
            }
        }
        // The zippers' and fans' triangles, turned counter-clockwise by their (u, v).
        let mut push = |t: [Local; 3]| {
            let [p, q, r] = t.map(|x| self.local(x));
            let area = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
            emit(if area < 0.0 { [t[0], t[2], t[1]] } else { t });
        };
        let side = |s: usize| -> Vec<(f64, Local)> {
            (0..=self.sides[s])
                .map(|k| {
                    let uv = self.local(Local::Side(s, k));
                    (uv[usize::from(s < 2)], Local::Side(s, k))
                })
                .collect()
        };
        if nu >= 2 && nv >= 2 {
            let inner_u = |b: usize| -> Vec<(f64, Local)> {
                (1..nu)
                    .map(|a| (a as f64 / nu as f64, Local::Inner(a, b)))
                    .collect()
            };
            let inner_v = |a: usize| -> Vec<(f64, Local)> {
                (1..nv)
                    .map(|b| (b as f64 / nv as f64, Local::Inner(a, b)))
                    .collect()
            };
            zip(&side(0), &inner_v(1), &mut push);
            zip(&side(1), &inner_v(nu - 1), &mut push);
            zip(&side(2), &inner_u(1), &mut push);
            zip(&side(3), &inner_u(nv - 1), &mut push);
            return;
        }
        // A strip along the direction whose count may exceed 1: its two long sides zipped,
        // the ends fanned onto the zipper's end triangles.
        let (long, ends) = if nu == 1 {
            ([0, 1], [2, 3])
        } else {
            ([2, 3], [0, 1])
        };
        let (a, b) = (side(long[0]), side(long[1]));
        let mut zipped = Vec::new();
        zip(&a, &b, &mut |t| zipped.push(t));
        let last = zipped.len() - 1;
        for (i, t) in zipped.into_iter().enumerate() {
            let end = match i {
                0 => Some((ends[0], [a[0].1, b[0].1])),
                i if i == last => Some((ends[1], [a[a.len() - 1].1, b[b.len() - 1].1])),
                _ => None,
            };
            match end {
                // The end triangle's far vertex (the one not on the end side) takes the fan.
                Some((s, pair)) => {
                    let far = t.into_iter().find(|x| !pair.contains(x));
                    let far = far.expect("a zipper's end triangle has a vertex off the end");
                    for w in side(s).windows(2) {
                        push([w[0].1, w[1].1, far]);
                    }
                }
                None => push(t),
            }
        }
    }
}

/// The triangles between two rows of points (each by its place along the row, increasing):
/// from both rows' first points, step along the row whose next point comes first, each step
/// a triangle of the two points stepped between and the other row's current point.
fn zip(outer: &[(f64, Local)], inner: &[(f64, Local)], push: &mut impl FnMut([Local; 3])) {
    let (mut i, mut j) = (0, 0);
    while i + 1 < outer.len() || j + 1 < inner.len() {
        let step_outer =
            j + 1 == inner.len() || (i + 1 < outer.len() && outer[i + 1].0 <= inner[j + 1].0);
        if step_outer {
            push([outer[i].1, outer[i + 1].1, inner[j].1]);
            i += 1;
        } else {
            push([inner[j].1, inner[j + 1].1, outer[i].1]);
            j += 1;
        }
    }
}

/// Where a boundary point that is keyed one by one is on the surface, whatever patch names it:
/// a corner, or a point of a patch list's collapsed side (an edge's other points are found by
/// [`Graded::edge`]).
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
enum Key {
    /// A net's point: in each direction (segment, k, e), the place k/e along the segment
    /// (a line between segments named by the segment that starts there, (s, 0, 1)).
    Net([(usize, usize, usize); 2]),
    /// A patch list's corner: its control index.
    Corner(usize),
    /// A point of a patch list's collapsed side (one point: its places weld whatever the
    /// side's count): its control index and the place.
    Collapsed(usize, usize),
}

/// Where a side's inner points are shared (see [`Graded::edge`]).
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
enum EdgeId {
    /// A net's: the direction it runs along, its segment there, the line across it.
    Net(usize, usize, usize),
    /// A patch list's: its four control indices in the smaller order.
    List([usize; 4]),
}

/// The points numbered so far: the next number, corners (and a collapsed side's points) by
/// key, each edge's first inner point.
#[derive(Default)]
struct Seen {
    next: u32,
    keyed: HashMap<Key, u32>,
    edges: HashMap<EdgeId, u32>,
}

impl Seen {
    /// A new point's number, made by `make` where there is `made`.
    fn fresh(
        &mut self,
        made: &mut Option<&mut Vec<Vertex>>,
        make: impl FnOnce(&mut Vec<Vertex>),
    ) -> u32 {
        if let Some(made) = made {
            make(made);
        }
        self.next += 1;
        self.next - 1
    }

    /// The number of the point of `key`, new (and made) the first time.
    fn shared(
        &mut self,
        key: Key,
        made: &mut Option<&mut Vec<Vertex>>,
        make: impl FnOnce(&mut Vec<Vertex>),
    ) -> u32 {
        if let Some(&id) = self.keyed.get(&key) {
            return id;
        }
        let id = self.fresh(made, make);
        self.keyed.insert(key, id);
        id
    }
}

/// A patch's points' vertex numbers (see [`Graded::assign`]).
struct Ids {
    sides: [Vec<u32>; 4],
    inner_first: u32,
    /// Inner points a row: N_v − 1.
    across: usize,
}

/// A surface's patches with their sides counted: each side at the larger of its own patch's
/// count along it and its neighbour's.
struct Graded<'a> {
    table: &'a PatchTable,
    patches: Vec<PatchCounts>,
}

impl<'a> Graded<'a> {
    fn new(table: &'a PatchTable, cells: &[[usize; 2]]) -> Self {
        let mut patches: Vec<PatchCounts> = cells
            .iter()
            .map(|&[nu, nv]| PatchCounts {
                cells: [nu, nv],
                sides: [nv, nv, nu, nu],
            })
            .collect();
        match (table.knots(), table.patch_indices()) {
            (Some(knots), _) => {
                let (rows, across) = (knots[0].len() - 1, knots[1].len() - 1);
                let closed = table.closed();
                // The neighbour across a line of direction d, if any (a closed direction wraps).
                let step = |i: usize, n: usize, d: usize, forward: bool| -> Option<usize> {
                    match (forward, i) {
                        (true, i) if i + 1 < n => Some(i + 1),
                        (true, _) => closed[d].then_some(0),
                        (false, 0) => closed[d].then_some(n - 1),
                        (false, i) => Some(i - 1),
                    }
                };
                for iu in 0..rows {
                    for iv in 0..across {
                        let p = iu * across + iv;
                        let [nu, nv] = cells[p];
                        let mut sides = [nv, nv, nu, nu];
                        for (s, forward) in [(0, false), (1, true)] {
                            if let Some(q) = step(iu, rows, 0, forward) {
                                sides[s] = sides[s].max(cells[q * across + iv][1]);
                            }
                        }
                        for (s, forward) in [(2, false), (3, true)] {
                            if let Some(q) = step(iv, across, 1, forward) {
                                sides[s] = sides[s].max(cells[iu * across + q][0]);
                            }
                        }
                        patches[p].sides = sides;
                    }
                }
            }
            (None, Some(lists)) => {
                let mut largest: HashMap<[usize; 4], usize> = HashMap::new();
                for (controls, counts) in lists.iter().zip(&patches) {
                    for s in 0..4 {
                        if let Some(edge) = shared_edge(controls, s) {
                            let e = largest.entry(edge).or_insert(0);
                            *e = (*e).max(counts.sides[s]);
                        }
                    }
                }
                for (controls, counts) in lists.iter().zip(&mut patches) {
                    for s in 0..4 {
                        if let Some(edge) = shared_edge(controls, s) {
                            counts.sides[s] = largest[&edge];
                        }
                    }
                }
            }
            (None, None) => unreachable!("a table is a net or a patch list"),
        }
        Self { table, patches }
    }

    /// Whether every patch is a plain grid (the mesh is the welded or net grid of the cells).
    fn plain(&self) -> bool {
        self.patches.iter().all(PatchCounts::plain)
    }

    /// The key of patch p's boundary `point` (a canonical side point): any on a net; on a
    /// patch list a corner or a collapsed side's point (the points it is asked for there).
    fn key(&self, p: usize, point: Local) -> Key {
        let counts = &self.patches[p];
        let Local::Side(s, k) = point else {
            unreachable!("inner points have no key")
        };
        let e = counts.sides[s];
        match (self.table.knots(), self.table.patch_indices()) {
            (Some(knots), _) => {
                let across = knots[1].len() - 1;
                let segment = [p / across, p % across];
                let closed = self.table.closed();
                let part = |d: usize, k: usize, e: usize| -> (usize, usize, usize) {
                    let segments = knots[d].len() - 1;
                    match (k, segment[d]) {
                        (0, s) => (s, 0, 1),
                        (k, s) if k < e => (s, k, e),
                        (_, s) if s + 1 < segments => (s + 1, 0, 1),
                        (_, _) if closed[d] => (0, 0, 1),
                        (_, s) => (s, 1, 1),
                    }
                };
                Key::Net(match s {
                    0 => [part(0, 0, 1), part(1, k, e)],
                    1 => [part(0, 1, 1), part(1, k, e)],
                    2 => [part(0, k, e), part(1, 0, 1)],
                    _ => [part(0, k, e), part(1, 1, 1)],
                })
            }
            (None, Some(lists)) => {
                let controls = &lists[p];
                let corner = |i: usize, j: usize| Key::Corner(controls[4 * i + j]);
                match (s, k) {
                    (0, 0) => corner(0, 0),
                    (0, k) if k == e => corner(0, 3),
                    (1, 0) => corner(3, 0),
                    (1, k) if k == e => corner(3, 3),
                    _ => {
                        debug_assert!(shared_edge(controls, s).is_none(), "a collapsed side");
                        Key::Collapsed(side_indices(controls, s)[0], k)
                    }
                }
            }
            (None, None) => unreachable!("a table is a net or a patch list"),
        }
    }

    /// The vertex a point of patch p is made as: on a net, a boundary point on the patch that
    /// starts there (the last line on the last patch at 1); on a patch list, where patch p
    /// names it.
    fn vertex(&self, p: usize, point: Local) -> Vertex {
        let local = self.patches[p].local(point);
        let Some(knots) = self.table.knots() else {
            return Vertex {
                patch: p as u32,
                local,
                uv: local,
            };
        };
        // Parameter at place l of segment s, as a net's grid makes it.
        let at = |d: usize, s: usize, l: f64| {
            if l == 1.0 {
                knots[d][s + 1]
            } else {
                knots[d][s] + l * (knots[d][s + 1] - knots[d][s])
            }
        };
        let across = knots[1].len() - 1;
        // Each direction's (segment, local): a boundary point's as its key places it.
        let places: [(usize, f64); 2] = match point {
            Local::Side(..) => {
                let Key::Net(parts) = self.key(p, point) else {
                    unreachable!("a net's points have net keys")
                };
                parts.map(|(s, k, e)| (s, k as f64 / e as f64))
            }
            Local::Inner(..) => [(p / across, local[0]), (p % across, local[1])],
        };
        let [(su, lu), (sv, lv)] = places;
        Vertex {
            patch: (su * across + sv) as u32,
            local: [lu, lv],
            uv: [at(0, su, lu), at(1, sv, lv)],
        }
    }

    /// Where side s of patch p shares its inner points, and whether the patch runs along it
    /// against the shared order: a net's segment of a line (its direction, segment and line,
    /// a closed direction's last line its first), a patch list's edge (its indices in the
    /// smaller order); `None` for a collapsed side (its points keyed one by one).
    fn edge(&self, p: usize, s: usize) -> Option<(EdgeId, bool)> {
        match (self.table.knots(), self.table.patch_indices()) {
            (Some(knots), _) => {
                let (rows, across) = (knots[0].len() - 1, knots[1].len() - 1);
                let closed = self.table.closed();
                let (iu, iv) = (p / across, p % across);
                let line = |i: usize, n: usize, d: usize| if i == n && closed[d] { 0 } else { i };
                Some(match s {
                    0 => (EdgeId::Net(1, iv, line(iu, rows, 0)), false),
                    1 => (EdgeId::Net(1, iv, line(iu + 1, rows, 0)), false),
                    2 => (EdgeId::Net(0, iu, line(iv, across, 1)), false),
                    _ => (EdgeId::Net(0, iu, line(iv + 1, across, 1)), false),
                })
            }
            (None, Some(lists)) => {
                let edge = shared_edge(&lists[p], s)?;
                Some((EdgeId::List(edge), edge != side_indices(&lists[p], s)))
            }
            (None, None) => unreachable!("a table is a net or a patch list"),
        }
    }

    /// Patch p's points' vertex indices: each side's, then its inner grid's from
    /// `inner_first`, (a, b) at (a − 1)(N_v − 1) + b − 1. A point seen before (a corner, an
    /// edge another patch made) takes its vertex; a new one is numbered from `made`'s length
    /// and made there, or (`made` None) counted alone. An edge's inner points are numbered
    /// together in the edge's shared order, so the other patch finds them by arithmetic.
    fn assign(&self, p: usize, made: &mut Option<&mut Vec<Vertex>>, seen: &mut Seen) -> Ids {
        let counts = &self.patches[p];
        let mut sides: [Vec<u32>; 4] = Default::default();
        for (s, ids) in sides.iter_mut().enumerate() {
            let e = counts.sides[s];
            ids.resize(e + 1, 0);
            for k in [0, e] {
                let corner = counts.canonical(Local::Side(s, k));
                let key = self.key(p, corner);
                ids[k] = seen.shared(key, made, |made| made.push(self.vertex(p, corner)));
            }
            match self.edge(p, s) {
                Some((edge, reversed)) => {
                    // Place c of the shared order is this side's point k.
                    let point = |c: usize| if reversed { e - c } else { c };
                    let first = match seen.edges.get(&edge) {
                        Some(&first) => first,
                        None => {
                            let first = seen.next;
                            for c in 1..e {
                                let side = Local::Side(s, point(c));
                                seen.fresh(made, |made| {
                                    made.push(self.vertex(p, side));
                                });
                            }
                            seen.edges.insert(edge, first);
                            first
                        }
                    };
                    for c in 1..e {
                        ids[point(c)] = first + (c - 1) as u32;
                    }
                }
                None => {
                    for (k, id) in ids.iter_mut().enumerate().take(e).skip(1) {
                        let side = Local::Side(s, k);
                        let key = self.key(p, side);
                        *id = seen.shared(key, made, |made| made.push(self.vertex(p, side)));
                    }
                }
            }
        }
        let [nu, nv] = counts.cells;
        let inner_first = seen.next;
        for a in 1..nu {
            for b in 1..nv {
                seen.fresh(made, |made| made.push(self.vertex(p, Local::Inner(a, b))));
            }
        }
        Ids {
            sides,
            inner_first,
            across: nv.saturating_sub(1),
        }
    }

    /// (vertices, triangles) of the mesh, counted without making it.
    fn counts(&self) -> (u64, u64) {
        let mut seen = Seen::default();
        let mut triangles = 0u64;
        for (p, counts) in self.patches.iter().enumerate() {
            let [nu, nv] = counts.cells;
            let extra: usize = (0..4).map(|s| counts.sides[s] - [nv, nv, nu, nu][s]).sum();
            triangles += (2 * nu * nv + extra) as u64;
            self.assign(p, &mut None, &mut seen);
        }
        (u64::from(seen.next), triangles)
    }

    /// The mesh: each patch's points numbered (and made) as [`Graded::assign`] says, then its
    /// triangles.
    fn plan(&self) -> Result<SurfacePlan, InputError> {
        // At most every patch's own points: counted exactly only where that bound is large.
        let most: u64 = self
            .patches
            .iter()
            .map(|c| {
                let [nu, nv] = c.cells;
                ((nu - 1) * (nv - 1) + c.sides.iter().map(|e| e + 1).sum::<usize>()) as u64
            })
            .sum();
        if most > u64::from(u32::MAX) {
            check_count(self.counts().0)?;
        }
        // Room for the usual mesh at once (the bound counts each shared point twice).
        let mut vertices = Vec::with_capacity(most.min(1 << 24) as usize);
        let mut triangles = Vec::with_capacity(
            self.patches
                .iter()
                .map(|c| {
                    let [nu, nv] = c.cells;
                    2 * nu * nv + c.sides.iter().sum::<usize>() - 2 * (nu + nv)
                })
                .sum(),
        );
        let mut seen = Seen::default();
        for (p, counts) in self.patches.iter().enumerate() {
            let ids = self.assign(p, &mut Some(&mut vertices), &mut seen);
            counts.triangles(&mut |t| {
                triangles.push(t.map(|point| match counts.canonical(point) {
                    Local::Side(s, k) => ids.sides[s][k],
                    Local::Inner(a, b) => ids.inner_first + ((a - 1) * ids.across + (b - 1)) as u32,
                }));
            });
        }
        Ok(SurfacePlan {
            vertices,
            triangles: Some(triangles),
            cells: self
                .patches
                .iter()
                .map(|c| c.cells.map(|k| k as u32))
                .collect(),
        })
    }

    /// Each triangle's patch and its corners' local (u, v), in the plan's order.
    fn patch_triangles(&self) -> Vec<(u32, [[f64; 2]; 3])> {
        let mut out = Vec::new();
        for (p, counts) in self.patches.iter().enumerate() {
            counts.triangles(&mut |t| out.push((p as u32, t.map(|x| counts.local(x)))));
        }
        out
    }
}

/// The control indices along side s of a patch (0 and 1: the rows i = 0 and 3, along v; 2 and
/// 3: the columns j = 0 and 3, along u), in the side's direction.
fn side_indices(controls: &[usize; 16], s: usize) -> [usize; 4] {
    match s {
        0 => [0, 1, 2, 3].map(|j| controls[j]),
        1 => [0, 1, 2, 3].map(|j| controls[12 + j]),
        2 => [0, 1, 2, 3].map(|i| controls[4 * i]),
        _ => [0, 1, 2, 3].map(|i| controls[4 * i + 3]),
    }
}

/// Side s's edge in the smaller order, `None` for a collapsed side (one point: it joins
/// nothing).
fn shared_edge(controls: &[usize; 16], s: usize) -> Option<[usize; 4]> {
    let indices = side_indices(controls, s);
    if indices.iter().all(|&i| i == indices[0]) {
        return None;
    }
    let mut reversed = indices;
    reversed.reverse();
    Some(if reversed < indices {
        reversed
    } else {
        indices
    })
}

/// The graded plan of `cells` on `table`, or `None` where every patch is a plain grid of
/// them (the welded or net grid is that plan).
///
/// # Errors
/// More vertices than one surface may have.
pub(crate) fn graded_plan(
    table: &PatchTable,
    cells: &[[usize; 2]],
) -> Option<Result<SurfacePlan, InputError>> {
    let graded = Graded::new(table, cells);
    (!graded.plain()).then(|| graded.plan())
}

/// The counts of [`graded_plan`]'s plan, `None` where it is a plain grid.
pub(crate) fn graded_counts(table: &PatchTable, cells: &[[usize; 2]]) -> Option<(u64, u64)> {
    let graded = Graded::new(table, cells);
    (!graded.plain()).then(|| graded.counts())
}

/// Each triangle's patch and corners' local (u, v) of the plan of `cells` on a patch list, in
/// the plan's order.
pub(crate) fn patch_triangles(
    table: &PatchTable,
    cells: &[[usize; 2]],
) -> Vec<(u32, [[f64; 2]; 3])> {
    Graded::new(table, cells).patch_triangles()
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;

    use super::*;

    /// Random cells and sides (each side at least its cells' count).
    fn cases() -> Vec<PatchCounts> {
        let mut state = 7u64;
        let mut next = |n: usize| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 33) as usize) % n
        };
        (0..3000)
            .map(|_| {
                let (nu, nv) = (1 + next(6), 1 + next(6));
                let mut sides = [nv, nv, nu, nu];
                for s in &mut sides {
                    if next(2) == 0 {
                        *s += next(9);
                    }
                }
                PatchCounts {
                    cells: [nu, nv],
                    sides,
                }
            })
            .collect()
    }

    /// The certificate's condition: every triangle spans at most 1/N_u in u and 1/N_v in v,
    /// is counter-clockwise, and the triangles tile the unit square (their areas sum to 1,
    /// every boundary point is a corner of some triangle); the count is 2 N_u N_v +
    /// Σ (e_s − N_s).
    #[test]
    fn every_triangle_spans_at_most_a_cell() {
        for counts in cases() {
            let [nu, nv] = counts.cells;
            let mut area = 0.0;
            let mut triangles = 0;
            let mut corners = HashSet::new();
            counts.triangles(&mut |t| {
                let [p, q, r] = t.map(|x| counts.local(x));
                for d in 0..2 {
                    let (lo, hi) = (p[d].min(q[d]).min(r[d]), p[d].max(q[d]).max(r[d]));
                    let cell = 1.0 / [nu, nv][d] as f64;
                    assert!(hi - lo <= cell * (1.0 + 1e-12), "{counts:?}: {t:?}");
                }
                let twice = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
                assert!(twice > 0.0, "{counts:?}: {t:?} not counter-clockwise");
                area += 0.5 * twice;
                triangles += 1;
                for x in t {
                    corners.insert(counts.canonical(x));
                }
            });
            assert!((area - 1.0).abs() < 1e-12, "{counts:?}: area {area}");
            let extra: usize = (0..4).map(|s| counts.sides[s] - [nv, nv, nu, nu][s]).sum();
            assert_eq!(triangles, 2 * nu * nv + extra, "{counts:?}");
            for s in 0..4 {
                for k in 0..=counts.sides[s] {
                    let point = counts.canonical(Local::Side(s, k));
                    assert!(corners.contains(&point), "{counts:?}: {point:?} unused");
                }
            }
        }
    }
}
