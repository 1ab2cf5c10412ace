//! The closest point of a set of curves to many query points, certified (docs/queries.md).
//!
//! For a query point q and one segment P(u) = D + R(u), R = N / W (W ≡ 1 on a polynomial
//! segment), written relative to the segment's origin with r = q − D, the squared distance
//! g(u) = |R(u) − r|² has
//!
//! ```text
//! g'(u) / 2 = (R − r)·R' = (N − r W)·(N' W − N W') / W³
//! ```
//!
//! whose numerator h(u) = Σ_k (N_k − r_k W)(N_k' W − N_k W') is a polynomial of degree 5
//! (polynomial segment: Σ (A u³ + B u² + C u − r)(3A u² + 2B u + C)) or at most 8 (rational;
//! W > 0 on [0, 1], so h and g' share their signs). g's minimum over [0, 1] is at 0, at 1, or
//! where g' changes sign from − to +, so among the ends and the sign-changing roots of h, which
//! [`roots::visit_sign_change_roots`] isolates by the signs of h's Bernstein coefficients
//! (Descartes' rule: no change, no root; one change, one simple root between the ends; more,
//! halve and look again), falling back to isolating them between the roots of h', which are
//! then tried too (where a pair of roots too close to tell apart would be).
//!
//! Over the whole set, the box tree (`tree::BoxTree`) gives the pieces of segments
//! (`pieces`, about E / (8√n) long) nearest first and leaves every box farther than the best
//! distance found: a piece [u0, u1] of a segment lies in the box of its own Bezier control
//! points, so no piece left out could be nearer, and on a piece the same solve runs on
//! [u0, u1].

use crate::error::InputError;
use crate::parallel::map_indices;
use crate::query::checks::{check_point, point_count};
use crate::query::pieces::{Piece, pieces};
use crate::query::roots::{Poly, visit_sign_change_roots};
use crate::query::tree::BoxTree;
use crate::segment::{Segment, SegmentTable};

/// The closest point of the set to one query point.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosestPoint {
    /// The curve's index in the set.
    pub curve: usize,
    /// The curve's parameter there.
    pub t: f64,
    /// The curve at `t` (D values).
    pub point: Vec<f64>,
    /// |point − q|.
    pub distance: f64,
}

/// Closest points for many query points, as arrays (query i's answer at row i): points and
/// distances in f64 from the CPU ([`CurveIndex::closest_many`]), in f32 from the GPU
/// ([`GpuContext::closest_points`](crate::GpuContext::closest_points)); parameters always
/// in f64.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ClosestPoints<F = f64> {
    /// The number of coordinates of each point.
    pub dim: usize,
    /// Per query, the curve's index in the set.
    pub curve: Vec<usize>,
    /// Per query, the curve's parameter.
    pub t: Vec<f64>,
    /// Per query, the closest point (D values, flat).
    pub points: Vec<F>,
    /// Per query, the distance.
    pub distance: Vec<F>,
}

impl<F> ClosestPoints<F> {
    /// How many queries were answered.
    #[must_use]
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there were none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}

/// A set of curves (fitted, as [`SegmentTable`]s of one dimension) behind a box tree over
/// their segments, for closest-point queries.
///
/// ```
/// use splinegpu::{Basis, Curve, CurveKind, Ends, Points, query::CurveIndex};
///
/// let points = Points::new(2, vec![0.0, 0.0, 1.0, 1.0, 2.0, 0.0, 3.0, 1.0])?;
/// let curve = Curve::new(CurveKind::Uniform { basis: Basis::CatmullRom, ends: Ends::Repeat }, points)?;
/// let tables = [curve.fit()];
/// let index = CurveIndex::new(&tables)?;
/// let hit = index.closest(&[1.0, 2.0])?;
/// assert_eq!(hit.curve, 0);
/// assert!((hit.distance - 1.0).abs() < 1e-12); // the top of the first bump, (1, 1)
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct CurveIndex<'a> {
    tables: &'a [SegmentTable],
    dim: usize,
    /// Per item of the tree, its piece.
    items: Vec<Piece>,
    tree: BoxTree,
}

impl<'a> CurveIndex<'a> {
    /// The index over every segment of `tables`.
    ///
    /// # Errors
    /// No curves; a curve whose dimension differs from the first's (named by its index).
    pub fn new(tables: &'a [SegmentTable]) -> Result<Self, InputError> {
        let Some(first) = tables.first() else {
            return Err(InputError::field("curves", "must not be empty"));
        };
        let dim = first.dim();
        for (c, table) in tables.iter().enumerate() {
            if table.dim() != dim {
                return Err(InputError::field(
                    "points",
                    format!(
                        "must have {dim} coordinates like curve 0's, got {}",
                        table.dim()
                    ),
                )
                .in_curve(c));
            }
        }
        let (items, boxes) = pieces(tables, dim, 8.0);
        Ok(Self {
            tables,
            dim,
            tree: BoxTree::new(dim, &boxes),
            items,
        })
    }

    /// The number of coordinates of the curves (and of every query point).
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The point of the set nearest to `q` (D values).
    ///
    /// # Errors
    /// `q` of another length than D, or with a coordinate that is not finite; a `q` so far
    /// from the curves that its squared distance overflows f64 (beyond about 1e154).
    pub fn closest(&self, q: &[f64]) -> Result<ClosestPoint, InputError> {
        check_point(q, self.dim, 0, "curves")?;
        let (curve, t, d2) = self.nearest(q);
        check_distance(d2, 0)?;
        let mut point = vec![0.0; self.dim];
        self.point_at(curve, t, &mut point);
        Ok(ClosestPoint {
            curve,
            t,
            point,
            distance: d2.sqrt(),
        })
    }

    /// [`CurveIndex::closest`] for every point of `queries` (D values each, flat), on every
    /// thread.
    ///
    /// # Errors
    /// A length that is not a multiple of D; a coordinate that is not finite, or a point too
    /// far for f64 (as [`CurveIndex::closest`]), named by its query's index.
    pub fn closest_many(&self, queries: &[f64]) -> Result<ClosestPoints, InputError> {
        let dim = self.dim;
        let count = self.check_queries(queries)?;
        let answers = map_indices(count, |i| self.nearest(&queries[i * dim..][..dim]));
        let mut out = ClosestPoints {
            dim,
            curve: Vec::with_capacity(count),
            t: Vec::with_capacity(count),
            points: vec![0.0; count * dim],
            distance: Vec::with_capacity(count),
        };
        for (i, (curve, t, d2)) in answers.into_iter().enumerate() {
            check_distance(d2, i)?;
            self.point_at(curve, t, &mut out.points[i * dim..][..dim]);
            out.curve.push(curve);
            out.t.push(t);
            out.distance.push(d2.sqrt());
        }
        Ok(out)
    }

    /// The number of query points in `queries` (D values each, flat), each checked.
    ///
    /// # Errors
    /// As [`CurveIndex::closest_many`], but for the distance's overflow.
    pub(crate) fn check_queries(&self, queries: &[f64]) -> Result<usize, InputError> {
        let dim = self.dim;
        let count = point_count(queries, dim)?;
        for i in 0..count {
            check_point(&queries[i * dim..][..dim], dim, i, "curves")?;
        }
        Ok(count)
    }

    /// The curves.
    pub(crate) fn tables(&self) -> &'a [SegmentTable] {
        self.tables
    }

    /// The tree's items, the pieces of segments.
    pub(crate) fn pieces(&self) -> &[Piece] {
        &self.items
    }

    /// The box tree over the pieces.
    pub(crate) fn tree(&self) -> &BoxTree {
        &self.tree
    }

    /// The curve's parameter at local parameter `u` of segment `s` of curve `c` (the
    /// segment's end knot itself at u >= 1).
    pub(crate) fn parameter(&self, c: usize, s: usize, u: f64) -> f64 {
        let table = &self.tables[c];
        if u >= 1.0 {
            table.knots()[s + 1]
        } else {
            let segment = table.segment(s);
            segment.t0() + u * segment.dt()
        }
    }

    /// The nearest (curve, t, squared distance) to a checked `q`.
    fn nearest(&self, q: &[f64]) -> (usize, f64, f64) {
        let mut best = f64::INFINITY;
        let mut found = (0u32, 0u32, 0.0);
        let mut r = [0.0; crate::MAX_DIM];
        self.tree.nearest(q, &mut best, |item, best| {
            let Piece {
                curve: c,
                segment: s,
                u0,
                u1,
            } = self.items[item as usize];
            let segment = self.tables[c as usize].segment(s as usize);
            let [.., origin] = segment.power();
            for k in 0..self.dim {
                r[k] = q[k] - origin[k];
            }
            let (u, d2) = segment_minimum(&segment, &r[..self.dim], u0, u1);
            if d2 < *best {
                *best = d2;
                found = (c, s, u);
            }
        });
        let (c, s, u) = found;
        (c as usize, self.parameter(c as usize, s as usize, u), best)
    }

    /// Curve `curve` at parameter `t` into `out`.
    pub(crate) fn point_at(&self, curve: usize, t: f64, out: &mut [f64]) {
        let table = &self.tables[curve];
        let knots = table.knots();
        let s = knots[1..knots.len() - 1].partition_point(|&k| k <= t);
        let segment = table.segment(s);
        segment.eval(((t - segment.t0()) / segment.dt()).clamp(0.0, 1.0), out);
    }
}

/// A squared distance that f64 could hold (a query within about 1e154 of the curves).
fn check_distance(d2: f64, index: usize) -> Result<(), InputError> {
    if d2.is_finite() {
        return Ok(());
    }
    Err(InputError::field(
        format!("closest[{index}]"),
        "lies too far from the curves: its squared distance overflows float64",
    ))
}

/// The point of one segment nearest to `q` (D values): its local parameter u in [0, 1] and
/// its distance, by the exact solve of the module docs (the one every index query finishes
/// with).
#[must_use]
pub fn closest_on_segment(segment: &Segment<'_>, q: &[f64]) -> (f64, f64) {
    let [.., origin] = segment.power();
    let mut r = [0.0; crate::MAX_DIM];
    for (k, (q, o)) in q.iter().zip(origin).enumerate() {
        r[k] = q - o;
    }
    let (u, d2) = segment_minimum(segment, &r[..q.len()], 0.0, 1.0);
    (u, d2.sqrt())
}

/// The local parameter u in [u0, u1] of the point of `segment` nearest to its origin plus
/// `r`, and the squared distance there (see the module docs).
pub(crate) fn segment_minimum(segment: &Segment<'_>, r: &[f64], u0: f64, u1: f64) -> (f64, f64) {
    let h = distance_slope(segment, r);
    let mut best = (u0, local_distance2(segment, r, u0));
    let mut try_u = |u: f64| {
        let d2 = local_distance2(segment, r, u);
        if d2 < best.1 {
            best = (u, d2);
        }
    };
    try_u(u1);
    visit_sign_change_roots(&h, u0, u1, &mut try_u);
    best
}

/// h(u), the numerator of g'(u)/2 (module docs), as a polynomial.
fn distance_slope(segment: &Segment<'_>, r: &[f64]) -> Poly {
    let [a, b, c, _] = segment.power();
    let mut h = [0.0; 9];
    match segment.denominator() {
        None => {
            for k in 0..r.len() {
                let (a, b, c, r) = (a[k], b[k], c[k], r[k]);
                h[5] += 3.0 * a * a;
                h[4] += 5.0 * a * b;
                h[3] += 4.0 * a * c + 2.0 * b * b;
                h[2] += 3.0 * (b * c - a * r);
                h[1] += c * c - 2.0 * b * r;
                h[0] -= c * r;
            }
            Poly::new(&h[..6])
        }
        Some(w) => {
            let [wa, wb, wc, wd] = w.coeffs;
            let w = [wd, wc, wb, wa];
            let dw = [wc, 2.0 * wb, 3.0 * wa];
            for k in 0..r.len() {
                let n = [0.0, c[k], b[k], a[k]];
                let dn = [c[k], 2.0 * b[k], 3.0 * a[k]];
                let e: [f64; 4] = std::array::from_fn(|i| n[i] - r[k] * w[i]);
                // F = N'W − NW', degree 5 at most (its u⁵ terms cancel).
                let mut f = [0.0; 6];
                for (i, &x) in dn.iter().enumerate() {
                    for (j, &y) in w.iter().enumerate() {
                        f[i + j] += x * y;
                    }
                }
                for (i, &x) in n.iter().enumerate() {
                    for (j, &y) in dw.iter().enumerate() {
                        f[i + j] -= x * y;
                    }
                }
                for (i, &x) in e.iter().enumerate() {
                    for (j, &y) in f.iter().enumerate() {
                        h[i + j] += x * y;
                    }
                }
            }
            Poly::new(&h)
        }
    }
}

/// |R(u) − r|², the squared distance from the origin plus r to the segment at u.
#[inline]
fn local_distance2(segment: &Segment<'_>, r: &[f64], u: f64) -> f64 {
    let [a, b, c, _] = segment.power();
    let inv_w = segment.denominator().map_or(1.0, |w| {
        let [wa, wb, wc, wd] = w.coeffs;
        1.0 / (wd + u * (wc + u * (wb + u * wa)))
    });
    let mut d2 = 0.0;
    for k in 0..r.len() {
        let gap = u * (c[k] + u * (b[k] + u * a[k])) * inv_w - r[k];
        d2 += gap * gap;
    }
    d2
}
