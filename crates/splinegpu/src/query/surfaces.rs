//! Closest points on surfaces and the first hits of rays, certified (docs/queries.md).
//!
//! Patches sit in a box tree by the boxes of their control points (a patch, rational with
//! positive weights included, lies in their convex hull). A query walks the tree, then
//! searches each patch it cannot exclude by halving rectangles of its parameters, each with
//! its own Bernstein net ([`nets`](super::nets)):
//!
//! - **closest points**: best first by a lower bound of |S − q|² on each rectangle (the least
//!   ratio of the Bernstein coefficients of |N − rW|² and W², W² > 0); the search ends when the
//!   least bound left is within ε of the best distance found (evaluated at the rectangles'
//!   centres and the patch's corners). The coefficients approach the polynomials' values
//!   quadratically as rectangles shrink, so only a few rectangles about each minimum survive
//!   each halving;
//! - **rays**: in a frame (a, b, s) along the unit direction, a rectangle is left where its
//!   control points' a or b range excludes 0 (no point of it on the ray) or its s range lies
//!   beyond the best hit (or before the origin); a rectangle whose three ranges are all within
//!   ε is a hit, polished by Newton's method on (a, b) = 0.

use crate::error::InputError;
use crate::parallel::map_indices;
use crate::query::checks::{check_point, point_count};
use crate::query::nets::{Net, patch_net};
use crate::query::tree::BoxTree;
use crate::surface::{Derivs, PatchTable, unit_normal};

/// The closest point of a set of surfaces to one query point.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The surface's index in the set.
    pub surface: usize,
    /// The patch's index, for a patch list (`None` on a net).
    pub patch: Option<usize>,
    /// The surface's parameters there (a patch list's: the patch's own, in [0, 1]).
    pub u: f64,
    /// See `u`.
    pub v: f64,
    /// The surface at (u, v), D values.
    pub point: Vec<f64>,
    /// |point − q|.
    pub distance: f64,
}

/// Where a ray first meets a set of 3-D surfaces.
#[derive(Clone, Debug, PartialEq)]
pub struct RayHit {
    /// The surface's index in the set.
    pub surface: usize,
    /// The patch's index, for a patch list (`None` on a net).
    pub patch: Option<usize>,
    /// The surface's parameters there (a patch list's: the patch's own).
    pub u: f64,
    /// See `u`.
    pub v: f64,
    /// The distance along the ray from its origin: the point is o + s d / |d|.
    pub s: f64,
    /// The surface at (u, v).
    pub point: [f64; 3],
    /// Su x Sv / |Su x Sv| there (its limit at a degenerate point), not turned to the ray.
    pub normal: [f64; 3],
}

/// A checked ray: its origin, and its frame (two unit vectors across it, then its unit
/// direction).
pub(crate) type CheckedRay = ([f64; 3], [[f64; 3]; 3]);

/// A set of surfaces (fitted, of one dimension) behind a box tree over their patches.
#[derive(Clone, Debug)]
pub struct SurfaceIndex<'a> {
    tables: &'a [PatchTable],
    dim: usize,
    /// Per item of the tree: its (surface, patch), origin and Bernstein net.
    items: Vec<(u32, u32)>,
    nets: Vec<(Vec<f64>, Net)>,
    tree: BoxTree,
    /// The extent E of ε: the largest per-axis range of the patches' control points.
    extent: f64,
}

/// A rectangle of a patch's parameters in the closest-point search, ordered by its lower
/// bound (least first, in Rust's max-heap).
struct Rectangle {
    bound: std::cmp::Reverse<Bound>,
    part: Net,
    u: [f64; 2],
    v: [f64; 2],
    depth: usize,
}

/// A lower bound of the squared distance, ordered as f64's total order.
#[derive(Clone, Copy, PartialEq)]
struct Bound(f64);

impl Eq for Bound {}

impl PartialOrd for Bound {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Bound {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

impl Rectangle {
    fn new(part: Net, u: [f64; 2], v: [f64; 2], depth: usize, r: &[f64]) -> Self {
        let bound = std::cmp::Reverse(Bound(part.lower_bound(r)));
        Self {
            bound,
            part,
            u,
            v,
            depth,
        }
    }
}

impl PartialEq for Rectangle {
    fn eq(&self, other: &Self) -> bool {
        self.bound == other.bound
    }
}

impl Eq for Rectangle {}

impl PartialOrd for Rectangle {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Rectangle {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.bound.cmp(&other.bound)
    }
}

/// A rectangle's four quarters, in its own [0, 1]² parameters.
const HALVES: [([f64; 2], [f64; 2]); 4] = [
    ([0.0, 0.5], [0.0, 0.5]),
    ([0.0, 0.5], [0.5, 1.0]),
    ([0.5, 1.0], [0.0, 0.5]),
    ([0.5, 1.0], [0.5, 1.0]),
];

/// The deepest halving of a patch's rectangles.
const MAX_DEPTH: usize = 52;

/// The most rectangles one patch's search looks at for one query (a bound on the work where
/// the surface touches the query along a curve; each rectangle left is within ε).
const MAX_RECTANGLES: usize = 200_000;

impl<'a> SurfaceIndex<'a> {
    /// The index over every patch of `tables`.
    ///
    /// # Errors
    /// No surfaces; a surface whose dimension differs from the first's (named by its index).
    pub fn new(tables: &'a [PatchTable]) -> Result<Self, InputError> {
        let Some(first) = tables.first() else {
            return Err(InputError::field("surfaces", "must not be empty"));
        };
        let dim = first.dim();
        if let Some(s) = tables.iter().position(|t| t.dim() != dim) {
            return Err(InputError::field(
                "points",
                format!(
                    "must have {dim} coordinates like surface 0's, got {}",
                    tables[s].dim()
                ),
            )
            .in_surface(s));
        }
        let mut items = Vec::new();
        let mut nets = Vec::new();
        let mut boxes = Vec::new();
        let (mut lo, mut hi) = (vec![f64::INFINITY; dim], vec![f64::NEG_INFINITY; dim]);
        for (s, table) in tables.iter().enumerate() {
            for p in 0..table.len() {
                let (origin, net) = patch_net(&table.patch(p));
                let at = boxes.len();
                boxes.resize(at + 2 * dim, 0.0);
                for k in 0..dim {
                    boxes[at + k] = f64::INFINITY;
                    boxes[at + dim + k] = f64::NEG_INFINITY;
                }
                for point in net.projected() {
                    for (k, x) in point.enumerate() {
                        let x = origin[k] + x;
                        boxes[at + k] = boxes[at + k].min(x);
                        boxes[at + dim + k] = boxes[at + dim + k].max(x);
                    }
                }
                for k in 0..dim {
                    lo[k] = lo[k].min(boxes[at + k]);
                    hi[k] = hi[k].max(boxes[at + dim + k]);
                    let pad =
                        64.0 * f64::EPSILON * boxes[at + k].abs().max(boxes[at + dim + k].abs());
                    boxes[at + k] -= pad;
                    boxes[at + dim + k] += pad;
                }
                items.push((s as u32, p as u32));
                nets.push((origin, net));
            }
        }
        Ok(Self {
            tables,
            dim,
            tree: BoxTree::new(dim, &boxes),
            items,
            nets,
            extent: (0..dim).map(|k| hi[k] - lo[k]).fold(0.0, f64::max),
        })
    }

    /// The number of coordinates of the surfaces.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The surface of item `item`.
    pub(crate) fn surface_of(&self, item: usize) -> usize {
        self.items[item].0 as usize
    }

    /// The number of query points in `queries` (D values each, flat), each checked.
    ///
    /// # Errors
    /// As [`SurfaceIndex::closest_many`], but for the distance's overflow.
    pub(crate) fn check_queries(&self, queries: &[f64]) -> Result<usize, InputError> {
        let count = point_count(queries, self.dim)?;
        for i in 0..count {
            check_point(
                &queries[i * self.dim..][..self.dim],
                self.dim,
                i,
                "surfaces",
            )?;
        }
        Ok(count)
    }

    /// Every ray of `rays` (6 values each, flat) checked: its origin and frame.
    ///
    /// # Errors
    /// As [`SurfaceIndex::rays_many`].
    pub(crate) fn check_rays(&self, rays: &[f64]) -> Result<Vec<CheckedRay>, InputError> {
        if !rays.len().is_multiple_of(6) {
            return Err(InputError::field(
                "rays",
                format!("must hold 6 values per ray, got {}", rays.len()),
            ));
        }
        rays.chunks_exact(6)
            .enumerate()
            .map(|(i, ray)| self.check_ray(&std::array::from_fn(|k| ray[k]), i))
            .collect()
    }

    /// The box tree over the patches.
    pub(crate) fn tree(&self) -> &BoxTree {
        &self.tree
    }

    /// Per item of the tree, its patch's origin and Bernstein net (relative to the origin).
    pub(crate) fn nets(&self) -> &[(Vec<f64>, Net)] {
        &self.nets
    }

    /// ε at a point: 1e-9 (E + |q|∞).
    fn eps(&self, q: &[f64]) -> f64 {
        1e-9 * (self.extent + q.iter().fold(0.0f64, |m, x| m.max(x.abs())))
    }

    /// The point of the set nearest to `q` (D values), within ε of the least distance.
    ///
    /// # Errors
    /// `q` of another length than D, a coordinate that is not finite, or a `q` so far that
    /// its squared distance overflows f64; each named as `closest[index]`.
    pub fn closest(&self, q: &[f64], index: usize) -> Result<SurfacePoint, InputError> {
        check_point(q, self.dim, index, "surfaces")?;
        let eps = self.eps(q);
        let mut best = f64::INFINITY;
        let mut found = (0usize, 0.0, 0.0);
        let mut derivs = Derivs::default();
        derivs.iter_mut().for_each(|d| d.resize(self.dim, 0.0));
        self.tree.nearest(q, &mut best, |item, best| {
            self.closest_on_patch(item as usize, q, eps, best, &mut found, &mut derivs);
        });
        if !best.is_finite() {
            return Err(InputError::field(
                format!("closest[{index}]"),
                "lies too far from the surfaces: its squared distance overflows float64",
            ));
        }
        let (item, u, v) = found;
        let (u, v) = self.polish_closest(item, u, v, q, &mut derivs);
        Ok(self.surface_point(item, u, v, q, &mut derivs))
    }

    /// The answer at local (u, v) of item `item` for the query point `q`: its surface,
    /// patch and parameters, the point there and its distance to `q`.
    pub(crate) fn surface_point(
        &self,
        item: usize,
        u: f64,
        v: f64,
        q: &[f64],
        derivs: &mut Derivs,
    ) -> SurfacePoint {
        let point = self.local_point(item, u, v, derivs).to_vec();
        let distance = point
            .iter()
            .zip(q)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        let (surface, patch, [u, v]) = self.place(item, u, v);
        SurfacePoint {
            surface,
            patch,
            u,
            v,
            point,
            distance,
        }
    }

    /// [`SurfaceIndex::closest`] for every point of `queries` (D values each, flat), on every
    /// thread.
    ///
    /// # Errors
    /// As [`SurfaceIndex::closest`], for the first query at fault.
    pub fn closest_many(&self, queries: &[f64]) -> Result<Vec<SurfacePoint>, InputError> {
        let dim = self.dim;
        map_indices(point_count(queries, dim)?, |i| {
            self.closest(&queries[i * dim..][..dim], i)
        })
        .into_iter()
        .collect()
    }

    /// The first hit of the ray o + s d, s >= 0, within s <= 1e6 (E + |o|∞); `None` where it
    /// meets nothing there.
    ///
    /// # Errors
    /// Surfaces that are not 3-D; a ray with a coordinate that is not finite or a zero
    /// direction; each named as `rays[index]`.
    pub fn first_hit(&self, ray: &[f64; 6], index: usize) -> Result<Option<RayHit>, InputError> {
        let (o, frame) = self.check_ray(ray, index)?;
        let d = frame[2];
        let eps = self.eps(&o);
        let mut best = self.ray_limit(&o);
        let mut found = None;
        self.tree.along_ray(&o, &d, &mut best, |item, best| {
            self.hit_on_patch(item as usize, &o, &frame, eps, best, &mut found);
        });
        let Some((item, u, v)) = found else {
            return Ok(None);
        };
        let mut derivs = Derivs::default();
        derivs.iter_mut().for_each(|x| x.resize(3, 0.0));
        let (u, v) = self.polish_hit(item, u, v, &o, &frame, &mut derivs);
        Ok(self.ray_hit(item, u, v, &o, &d, &mut derivs))
    }

    /// How far along a ray from `o` a hit may lie: 1e6 (E + |o|∞).
    pub(crate) fn ray_limit(&self, o: &[f64; 3]) -> f64 {
        1e6 * (self.extent + o.iter().fold(0.0f64, |m, x| m.max(x.abs())))
    }

    /// The hit at local (u, v) of item `item` of the ray from `o` along the unit `d`: its
    /// surface, patch and parameters, its distance along the ray (0 for a point behind the
    /// origin, which is within ε of it), the point and the unit normal there; `None` beyond
    /// [`SurfaceIndex::ray_limit`].
    pub(crate) fn ray_hit(
        &self,
        item: usize,
        u: f64,
        v: f64,
        o: &[f64; 3],
        d: &[f64; 3],
        derivs: &mut Derivs,
    ) -> Option<RayHit> {
        let p = self.local_point(item, u, v, derivs);
        let point = [p[0], p[1], p[2]];
        let s = dot(*d, sub(point, *o)).max(0.0);
        if s > self.ray_limit(o) {
            return None;
        }
        let (su, sv) = (
            [derivs[1][0], derivs[1][1], derivs[1][2]],
            [derivs[2][0], derivs[2][1], derivs[2][2]],
        );
        let (surface, patch_index) = self.items[item];
        let patch = self.tables[surface as usize].patch(patch_index as usize);
        let normal = unit_normal(&patch, u, v, su, sv);
        let (surface, patch, [u, v]) = self.place(item, u, v);
        Some(RayHit {
            surface,
            patch,
            u,
            v,
            s,
            point,
            normal,
        })
    }

    /// A ray checked (3-D surfaces, finite values, a direction that is not zero): its origin
    /// and its frame, two unit vectors across it and the unit direction.
    ///
    /// # Errors
    /// As [`SurfaceIndex::first_hit`].
    pub(crate) fn check_ray(&self, ray: &[f64; 6], index: usize) -> Result<CheckedRay, InputError> {
        let field = || format!("rays[{index}]");
        if self.dim != 3 {
            return Err(InputError::field(
                "rays",
                format!("meet 3-D surfaces, and these have D = {}", self.dim),
            ));
        }
        if let Some(k) = ray.iter().position(|v| !v.is_finite()) {
            return Err(InputError::field(
                field(),
                format!("value {k} is {}, not a finite number", ray[k]),
            ));
        }
        let o = [ray[0], ray[1], ray[2]];
        let length = (ray[3] * ray[3] + ray[4] * ray[4] + ray[5] * ray[5]).sqrt();
        if length <= 0.0 || !length.is_finite() {
            return Err(InputError::field(
                field(),
                "has a zero direction (dx, dy, dz)",
            ));
        }
        let d = [ray[3] / length, ray[4] / length, ray[5] / length];
        // Two unit vectors across the ray.
        let helper = if d[0].abs() < 0.6 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let e1 = normalize(cross(d, helper));
        let e2 = cross(d, e1);
        Ok((o, [e1, e2, d]))
    }

    /// [`SurfaceIndex::first_hit`] for every ray of `rays` (6 values each, flat), on every
    /// thread.
    ///
    /// # Errors
    /// As [`SurfaceIndex::first_hit`], for the first ray at fault.
    pub fn rays_many(&self, rays: &[f64]) -> Result<Vec<Option<RayHit>>, InputError> {
        if !rays.len().is_multiple_of(6) {
            return Err(InputError::field(
                "rays",
                format!("must hold 6 values per ray, got {}", rays.len()),
            ));
        }
        map_indices(rays.len() / 6, |i| {
            let ray: [f64; 6] = std::array::from_fn(|k| rays[6 * i + k]);
            self.first_hit(&ray, i)
        })
        .into_iter()
        .collect()
    }

    /// Item `item`'s surface, patch (for a patch list) and the surface's parameters at local
    /// (u, v).
    fn place(&self, item: usize, u: f64, v: f64) -> (usize, Option<usize>, [f64; 2]) {
        let (s, p) = self.items[item];
        let table = &self.tables[s as usize];
        let patch = table.patch(p as usize);
        let listed = table.patch_indices().is_some();
        let (start, length) = (patch.start(), patch.length());
        let at = |k: usize, x: f64| {
            if x >= 1.0 && !listed {
                start[k] + length[k]
            } else {
                start[k] + x * length[k]
            }
        };
        (
            s as usize,
            listed.then_some(p as usize),
            [at(0, u), at(1, v)],
        )
    }

    /// The surface point of item `item` at local (u, v), with its local derivatives in
    /// `derivs`.
    fn local_point<'d>(&self, item: usize, u: f64, v: f64, derivs: &'d mut Derivs) -> &'d [f64] {
        let (s, p) = self.items[item];
        self.tables[s as usize]
            .patch(p as usize)
            .local_derivatives(u, v, derivs);
        &derivs[0]
    }

    /// The search of the module docs for the closest point on one patch, lowering `best`
    /// (a squared distance) and setting `found` (item, local u, v) where it finds nearer.
    fn closest_on_patch(
        &self,
        item: usize,
        q: &[f64],
        eps: f64,
        best: &mut f64,
        found: &mut (usize, f64, f64),
        derivs: &mut Derivs,
    ) {
        let (origin, net) = &self.nets[item];
        let r: Vec<f64> = q.iter().zip(origin).map(|(q, o)| q - o).collect();
        let mut try_at = |u: f64, v: f64, best: &mut f64, derivs: &mut Derivs| {
            let p = self.local_point(item, u, v, derivs);
            let g: f64 = p.iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum();
            if g < *best {
                *best = g;
                *found = (item, u, v);
            }
        };
        for (u, v) in [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)] {
            try_at(u, v, best, derivs);
        }
        // Best first: the rectangle of least bound is split next, and the search ends when
        // that bound is within ε of the best distance (no rectangle left can hold nearer).
        let mut heap = std::collections::BinaryHeap::new();
        heap.push(Rectangle::new(net.clone(), [0.0, 1.0], [0.0, 1.0], 0, &r));
        let mut looked = 0;
        while let Some(Rectangle {
            bound,
            part,
            u,
            v,
            depth,
        }) = heap.pop()
        {
            looked += 1;
            // Within ε of the best distance d: (d − ε)² = d² − (2 d ε − ε²).
            let tolerance = (2.0 * best.sqrt() * eps - eps * eps).max(0.0);
            if bound.0.0 >= *best - tolerance {
                break;
            }
            try_at(0.5 * (u[0] + u[1]), 0.5 * (v[0] + v[1]), best, derivs);
            if depth >= MAX_DEPTH || looked >= MAX_RECTANGLES {
                continue;
            }
            for (du, dv) in HALVES {
                let lerp = |r: [f64; 2], t: f64| r[0] + t * (r[1] - r[0]);
                let (cu, cv) = (
                    [lerp(u, du[0]), lerp(u, du[1])],
                    [lerp(v, dv[0]), lerp(v, dv[1])],
                );
                heap.push(Rectangle::new(part.part(du, dv), cu, cv, depth + 1, &r));
            }
        }
    }

    /// The search of the module docs for the first hit on one patch, lowering `best` (the
    /// distance along the ray) and setting `found` (item, local u, v).
    fn hit_on_patch(
        &self,
        item: usize,
        o: &[f64; 3],
        frame: &[[f64; 3]; 3],
        eps: f64,
        best: &mut f64,
        found: &mut Option<(usize, f64, f64)>,
    ) {
        let (origin, net) = &self.nets[item];
        let shift = sub([origin[0], origin[1], origin[2]], *o);
        // The control points' ranges in the ray's frame (a, b, s).
        let ranges = |part: &Net| {
            let mut r = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
            for p in part.projected() {
                let mut x = shift;
                for (x, p) in x.iter_mut().zip(p) {
                    *x += p;
                }
                for (axis, range) in frame.iter().zip(r.iter_mut()) {
                    let c = dot(*axis, x);
                    *range = [range[0].min(c), range[1].max(c)];
                }
            }
            r
        };
        let pad = eps;
        let mut stack = vec![(net.clone(), [0.0, 1.0], [0.0, 1.0], 0usize)];
        let mut looked = 0;
        while let Some((part, u, v, depth)) = stack.pop() {
            looked += 1;
            let [a, b, s] = ranges(&part);
            let misses = a[0] > pad || a[1] < -pad || b[0] > pad || b[1] < -pad;
            if misses || s[0] > *best || s[1] < -pad {
                continue;
            }
            let small = [a, b, s].iter().all(|r| r[1] - r[0] <= 0.5 * eps);
            if small || depth >= MAX_DEPTH || looked >= MAX_RECTANGLES {
                let hit = (0.5 * (s[0] + s[1])).max(0.0);
                if hit < *best {
                    *best = hit;
                    *found = Some((item, 0.5 * (u[0] + u[1]), 0.5 * (v[0] + v[1])));
                }
                continue;
            }
            let mut children: Vec<_> = [
                ([0.0, 0.5], [0.0, 0.5]),
                ([0.0, 0.5], [0.5, 1.0]),
                ([0.5, 1.0], [0.0, 0.5]),
                ([0.5, 1.0], [0.5, 1.0]),
            ]
            .into_iter()
            .map(|(du, dv)| {
                let child = part.part(du, dv);
                let lerp = |r: [f64; 2], t: f64| r[0] + t * (r[1] - r[0]);
                let near = ranges(&child)[2][0];
                (
                    near,
                    child,
                    [lerp(u, du[0]), lerp(u, du[1])],
                    [lerp(v, dv[0]), lerp(v, dv[1])],
                )
            })
            .collect();
            // The nearest along the ray is looked at first.
            children.sort_by(|x, y| y.0.total_cmp(&x.0));
            for (_, child, cu, cv) in children {
                stack.push((child, cu, cv, depth + 1));
            }
        }
    }

    /// A closest point's (u, v) polished by Newton's method on the squared distance's gradient
    /// (S − q)·S_u = (S − q)·S_v = 0, each step kept only where it lowers the distance and
    /// stays on the patch: the search's answer is within ε already, this takes it to the
    /// rounding of f64 at an interior minimum.
    fn polish_closest(
        &self,
        item: usize,
        mut u: f64,
        mut v: f64,
        q: &[f64],
        derivs: &mut Derivs,
    ) -> (f64, f64) {
        let distance2 = |derivs: &Derivs| -> f64 {
            derivs[0]
                .iter()
                .zip(q)
                .map(|(a, b)| (a - b) * (a - b))
                .sum()
        };
        self.local_point(item, u, v, derivs);
        let mut g = distance2(derivs);
        for _ in 0..8 {
            let dot = |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| x * y).sum() };
            let e: Vec<f64> = derivs[0].iter().zip(q).map(|(a, b)| a - b).collect();
            let (su, sv) = (&derivs[1], &derivs[2]);
            let grad = [dot(&e, su), dot(&e, sv)];
            let h = [
                [
                    dot(su, su) + dot(&e, &derivs[3]),
                    dot(su, sv) + dot(&e, &derivs[4]),
                ],
                [
                    dot(su, sv) + dot(&e, &derivs[4]),
                    dot(sv, sv) + dot(&e, &derivs[5]),
                ],
            ];
            let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
            if det <= 0.0 || !det.is_finite() {
                break;
            }
            let nu = u - (h[1][1] * grad[0] - h[0][1] * grad[1]) / det;
            let nv = v - (-h[1][0] * grad[0] + h[0][0] * grad[1]) / det;
            if !(0.0..=1.0).contains(&nu) || !(0.0..=1.0).contains(&nv) {
                break;
            }
            self.local_point(item, nu, nv, derivs);
            let next = distance2(derivs);
            if next >= g {
                break;
            }
            (u, v, g) = (nu, nv, next);
        }
        self.local_point(item, u, v, derivs);
        (u, v)
    }

    /// A hit's (u, v) polished by Newton's method on (a, b) = 0 (the point's offsets across the
    /// ray), kept where it brings the point nearer the ray and stays on the patch.
    fn polish_hit(
        &self,
        item: usize,
        mut u: f64,
        mut v: f64,
        o: &[f64; 3],
        frame: &[[f64; 3]; 3],
        derivs: &mut Derivs,
    ) -> (f64, f64) {
        let across = |derivs: &Derivs| {
            let p = [derivs[0][0], derivs[0][1], derivs[0][2]];
            let x = sub(p, *o);
            [dot(frame[0], x), dot(frame[1], x)]
        };
        self.local_point(item, u, v, derivs);
        let mut f = across(derivs);
        for _ in 0..8 {
            let su = [derivs[1][0], derivs[1][1], derivs[1][2]];
            let sv = [derivs[2][0], derivs[2][1], derivs[2][2]];
            let j = [
                [dot(frame[0], su), dot(frame[0], sv)],
                [dot(frame[1], su), dot(frame[1], sv)],
            ];
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            if det == 0.0 || !det.is_finite() {
                break;
            }
            let nu = u - (j[1][1] * f[0] - j[0][1] * f[1]) / det;
            let nv = v - (-j[1][0] * f[0] + j[0][0] * f[1]) / det;
            if !(0.0..=1.0).contains(&nu) || !(0.0..=1.0).contains(&nv) {
                break;
            }
            self.local_point(item, nu, nv, derivs);
            let g = across(derivs);
            if g[0].hypot(g[1]) >= f[0].hypot(f[1]) {
                break;
            }
            (u, v, f) = (nu, nv, g);
        }
        self.local_point(item, u, v, derivs);
        (u, v)
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}
