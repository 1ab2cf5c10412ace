//! 2-D strokes: the area a pen of width w(t) sweeps along a curve, with joins at its corners
//! and caps at its ends (the contract's "stroke"), planned on the host in f64 so that the
//! counts are known before any vertex is made.
//!
//! The body: at each cross-section t_j, the vertices C(t_j) ± (w/2) n_j with n = (-T_y, T_x)
//! the unit left normal; consecutive cross-sections of one piece are joined by two triangles.
//! A corner (a joint whose arriving and leaving unit tangents differ by more than 1e-6 rad, a
//! closed curve's closing point, or a cross-section where C' = 0 inside the range) has a
//! cross-section on each side, each with its own side's normal, and a join on the outer side
//! about the corner point: a bevel (the triangle between the corner and the two outer offset
//! points), a miter (the bevel and the triangle out to where the two outer offset lines
//! meet, at h / cos(θ/2) from the corner along the outer normals' bisector, θ the turn,
//! while the miter ratio 1 / sin(φ/2) = 1 / cos(θ/2) is within the limit; the bevel
//! otherwise), or a round join (the fan of ceil(θ/π · sides/2) chords about the corner). A
//! cusp always takes a round join. Caps at an open curve's ends: "butt" nothing, "square"
//! the rectangle reaching w/2 beyond the end, "round" the half disc of sides/2 chords.
//!
//! Every triangle is counter-clockwise in (x, y).

use std::borrow::Cow;

use super::mesh::MeshOut;
use crate::error::InputError;
use crate::job::samples::SampleFloat;
use crate::sampling::SampleLoc;
use crate::segment::{SegmentTable, first_derivative, position};

/// How a stroke ends at an open curve's ends.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Cap {
    /// Nothing beyond the end.
    #[default]
    Butt,
    /// The rectangle of the stroke's width reaching w/2 beyond the end.
    Square,
    /// The half disc of radius w/2 beyond the end.
    Round,
}

/// How a stroke turns a corner.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Join {
    /// The outer offset lines extended until they meet, within the miter limit.
    #[default]
    Miter,
    /// The disc of radius w/2 at the corner.
    Round,
    /// The triangle between the corner and the two outer offset points.
    Bevel,
}

/// A stroke's style (2-D curves).
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    /// The pen's width w.
    pub width: super::Width,
    /// The ends' caps.
    pub cap: Cap,
    /// The corners' joins.
    pub join: Join,
    /// The largest miter ratio 1 / sin(φ/2) drawn as a miter (>= 1; the contract's 4).
    pub miter_limit: f64,
    /// Chords per full turn of round joins and caps (>= 4; the contract's 16).
    pub sides: u32,
    /// A dash pattern: each on interval an open stroke of its own, capped at both ends.
    pub dash: Option<super::Dash>,
}

impl Default for Stroke {
    fn default() -> Self {
        Self {
            width: super::Width::default(),
            cap: Cap::Butt,
            join: Join::Miter,
            miter_limit: 4.0,
            sides: 16,
            dash: None,
        }
    }
}

/// The smallest turn between a joint's tangents that makes it a corner, in radians.
const CORNER: f64 = 1e-6;

/// A cross-section: where the widened table is evaluated, and its unit tangent (its side's,
/// at a corner).
#[derive(Clone, Copy, Debug)]
struct Section {
    segment: usize,
    u: f64,
    t: f64,
    tangent: [f64; 2],
}

/// What joins section `at` (arriving) to the next one (leaving), or to the first (a closed
/// curve's closing point).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Corner {
    Bevel,
    /// The miter point at `reach` half widths from the corner.
    Miter {
        reach: f64,
    },
    Round {
        chords: u32,
    },
}

/// What a stroke's triangles are made from (see [`StrokePlan::topology_key`]): its sections'
/// count, each corner's arriving section and kind (0 bevel, 1 miter, 2 + chords round), its
/// caps.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct StrokeTopology {
    sections: usize,
    corners: Vec<(usize, u32)>,
    cap: Option<Cap>,
    cap_chords: [u32; 2],
}

/// A stroke's plan: its cross-sections, its corners (after which section, and how), its caps
/// and its counts.
#[derive(Clone, Debug)]
pub(crate) struct StrokePlan {
    sections: Vec<Section>,
    /// (arriving section, join); the leaving one is the next, or the first for the closing
    /// corner of a closed curve.
    corners: Vec<(usize, Corner)>,
    cap: Option<Cap>,
    /// A round cap's chords at the start and at the end.
    cap_chords: [u32; 2],
    pub(crate) vertices: u64,
    pub(crate) triangles: u64,
}

/// v / |v|, `None` where |v| is 0 or not finite. |v| is sqrt(x² + y²) where the sum of the
/// squares is a normal f64 (within an ulp or so of hypot's), and hypot where it would
/// overflow or underflow (hypot costs about as much as the rest of a section's planning).
fn unit2(v: [f64; 2]) -> Option<[f64; 2]> {
    let squares = v[0] * v[0] + v[1] * v[1];
    let length = if squares.is_normal() {
        squares.sqrt()
    } else {
        v[0].hypot(v[1])
    };
    (length > 0.0 && length.is_finite()).then(|| [v[0] / length, v[1] / length])
}

/// The table's position derivatives at (segment, u) (the first two coordinates): C', and C''
/// only where C' gives no direction (zero, or not finite), the one place a tangent reads it
/// ([`tangent_of`]): most places need C' alone.
fn derivatives(table: &SegmentTable, segment: usize, u: f64) -> ([f64; 2], Option<[f64; 2]>) {
    let s = table.segment(segment);
    let mut d = [0.0; 3];
    s.deriv(u, &mut d);
    let d1 = [d[0], d[1]];
    let directionless = d1 == [0.0, 0.0] || !(d1[0].is_finite() && d1[1].is_finite());
    let d2 = directionless.then(|| {
        s.deriv2(u, &mut d);
        [d[0], d[1]]
    });
    (d1, d2)
}

/// The widened table (x, y, w) read at places that come segment by segment: a polynomial
/// segment's coefficients and 1/Δ read once for its places, each value by the same operations
/// as [`Segment::eval`](crate::Segment::eval) and [`Segment::deriv`](crate::Segment::deriv)
/// (so the same bits); a rational segment through them.
struct HeldSegment<'t> {
    table: &'t SegmentTable,
    /// The segment read, and what is held of it.
    held: Option<(usize, Option<WidenedTerms>)>,
}

/// A polynomial segment's (A, B, C, D) for x, y and w, and 1/Δ (`None` for a rational one).
type WidenedTerms = ([[f64; 4]; 3], f64);

impl<'t> HeldSegment<'t> {
    fn new(table: &'t SegmentTable) -> Self {
        Self { table, held: None }
    }

    /// The terms of `segment` (`None` where it is rational, or the table is not x, y, w),
    /// read once for a run of places.
    #[inline]
    fn terms(&mut self, segment: usize) -> Option<&WidenedTerms> {
        if self.held.as_ref().is_none_or(|(s, _)| *s != segment) {
            let s = self.table.segment(segment);
            let polynomial = s.denominator().is_none() && self.table.dim() == 3;
            let held = polynomial.then(|| {
                let [a, b, c, d] = s.power();
                (
                    std::array::from_fn(|k| [a[k], b[k], c[k], d[k]]),
                    1.0 / s.dt(),
                )
            });
            self.held = Some((segment, held));
        }
        self.held.as_ref().and_then(|(_, held)| held.as_ref())
    }

    /// [`derivatives`] at (segment, u).
    #[inline]
    fn derivatives(&mut self, segment: usize, u: f64) -> ([f64; 2], Option<[f64; 2]>) {
        let table = self.table;
        let Some((terms, inv_dt)) = self.terms(segment) else {
            return derivatives(table, segment, u);
        };
        let d1 = [0, 1].map(|k| {
            let [a, b, c, _] = terms[k];
            first_derivative(a, b, c, u, *inv_dt)
        });
        if d1 == [0.0, 0.0] || !(d1[0].is_finite() && d1[1].is_finite()) {
            return derivatives(self.table, segment, u);
        }
        (d1, None)
    }

    /// The position and width (x, y, w) at (segment, u).
    #[inline]
    fn centre(&mut self, segment: usize, u: f64) -> [f64; 3] {
        let table = self.table;
        let Some((terms, _)) = self.terms(segment) else {
            let mut p = [0.0; 3];
            table.segment(segment).eval(u, &mut p);
            return p;
        };
        terms.map(|[a, b, c, d]| position(a, b, c, d, u))
    }
}

/// The unit tangent at (segment, u) approached from above (`below` false) or below.
fn tangent(table: &SegmentTable, segment: usize, u: f64, below: bool) -> Option<[f64; 2]> {
    let (d1, d2) = derivatives(table, segment, u);
    tangent_of(d1, d2, below)
}

/// The unit tangent from C' and C'' (C''s direction, reversed from below, where C' = 0; C''
/// is given there, see [`derivatives`]).
fn tangent_of(d1: [f64; 2], d2: Option<[f64; 2]>, below: bool) -> Option<[f64; 2]> {
    unit2(d1).or_else(|| {
        d2.and_then(unit2)
            .map(|t| if below { [-t[0], -t[1]] } else { t })
    })
}

fn turn(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] * b[1] - a[1] * b[0])
        .atan2(a[0] * b[0] + a[1] * b[1])
        .abs()
}

/// `locs` with a place at every joint between their first and their last where the curve
/// turns a corner that they do not already hold (arc-length places seldom fall on one, nor a
/// dash's): every corner gets its join. `locs` themselves where they hold every joint (a
/// tolerance or per-segment sampling's do): no copy.
fn with_corner_joints<'l>(table: &SegmentTable, locs: &'l [SampleLoc]) -> Cow<'l, [SampleLoc]> {
    let (first, last) = (locs[0].t, locs[locs.len() - 1].t);
    // The joints strictly inside the places' range (a place at a joint has u = 0 on the
    // segment that starts there).
    let inside = (1..table.len()).filter(|&s| {
        let t = table.segment(s).t0();
        t > first && t < last
    });
    let held = |s: usize| {
        let t = table.segment(s).t0();
        let at = locs.partition_point(|loc| loc.t < t);
        locs.get(at).is_some_and(|loc| loc.t == t)
    };
    if inside.clone().all(held) {
        return Cow::Borrowed(locs);
    }
    let joints = inside.filter(|&s| {
        let arriving = tangent(table, s - 1, 1.0, true);
        let leaving = tangent(table, s, 0.0, false);
        matches!((arriving, leaving), (Some(a), Some(b)) if turn(a, b) > CORNER)
    });
    let mut merged = Vec::with_capacity(locs.len());
    let mut joints = joints.peekable();
    for loc in locs {
        while let Some(&s) = joints.peek() {
            let t = table.segment(s).t0();
            if t > loc.t {
                break;
            }
            if t < loc.t {
                merged.push(SampleLoc {
                    segment: s,
                    u: 0.0,
                    t,
                });
            }
            joints.next();
        }
        merged.push(*loc);
    }
    Cow::Owned(merged)
}

impl StrokePlan {
    /// Plans the stroke of `style` on the widened `table` (x, y, w) at `locs`, closed or open.
    ///
    /// # Errors
    /// A miter limit below 1 or not finite ("miter_limit"), fewer than 4 sides ("sides").
    pub(crate) fn new(
        table: &SegmentTable,
        locs: &[SampleLoc],
        style: &Stroke,
        closed: bool,
        tolerance: Option<f64>,
    ) -> Result<Self, InputError> {
        if !(style.miter_limit.is_finite() && style.miter_limit >= 1.0) {
            return Err(InputError::field(
                "miter_limit",
                format!("must be a finite number >= 1, got {}", style.miter_limit),
            ));
        }
        if style.sides < 4 {
            return Err(InputError::field(
                "sides",
                format!("a stroke needs at least 4 sides, got {}", style.sides),
            ));
        }
        let half_turn = u64::from(style.sides.div_ceil(2));
        // A round join's or cap's chords for a turn θ at `loc`: sides/2 a half turn, or with
        // tolerance the fewest whose sagitta is within it at the half width there.
        let chords = |theta: f64, loc: &SampleLoc| match tolerance {
            None => {
                let c = (theta / std::f64::consts::PI * half_turn as f64).ceil();
                c.clamp(1.0, half_turn as f64) as u32
            }
            Some(tol) => {
                let mut p = [0.0; 3];
                table.segment(loc.segment).eval(loc.u, &mut p);
                super::tolerance::round_chords(theta, 0.5 * p[2].max(0.0), tol)
            }
        };
        let join = |arriving: [f64; 2], leaving: [f64; 2], cusp: bool, at: &SampleLoc| {
            let theta = turn(arriving, leaving);
            if cusp || style.join == Join::Round {
                return Corner::Round {
                    chords: chords(theta, at),
                };
            }
            let reach = 1.0 / (0.5 * theta).cos();
            match style.join {
                Join::Miter if reach <= style.miter_limit => Corner::Miter { reach },
                _ => Corner::Bevel,
            }
        };
        let locs = with_corner_joints(table, locs);
        let last = locs.len() - 1;
        let mut sections: Vec<Section> = Vec::with_capacity(locs.len());
        let mut corners = Vec::new();
        let mut previous = [1.0, 0.0];
        let mut held = HeldSegment::new(table);
        for (j, loc) in locs.iter().enumerate() {
            let loc = *loc;
            let at_end = j == last;
            let (d1, d2) = held.derivatives(loc.segment, loc.u);
            let here = tangent_of(d1, d2, at_end && j > 0);
            let leaving = here.unwrap_or(previous);
            let section = |tangent| Section {
                segment: loc.segment,
                u: loc.u,
                t: loc.t,
                tangent,
            };
            let interior = j > 0 && !at_end;
            if interior && loc.u == 0.0 && loc.segment > 0 {
                // A joint: the arriving side is the segment before at u = 1.
                let arriving = tangent(table, loc.segment - 1, 1.0, true).unwrap_or(previous);
                if turn(arriving, leaving) > CORNER {
                    sections.push(Section {
                        segment: loc.segment - 1,
                        u: 1.0,
                        t: loc.t,
                        tangent: arriving,
                    });
                    corners.push((sections.len() - 1, join(arriving, leaving, false, &loc)));
                }
            } else if interior && d1 == [0.0, 0.0] && here.is_some() {
                // A cusp inside a segment: arriving from below, leaving from above.
                let arriving = tangent_of(d1, d2, true).unwrap_or(previous);
                sections.push(section(arriving));
                corners.push((sections.len() - 1, join(arriving, leaving, true, &loc)));
            }
            sections.push(section(leaving));
            previous = leaving;
        }
        if closed {
            let (arriving, leaving) = (sections[sections.len() - 1].tangent, sections[0].tangent);
            if turn(arriving, leaving) > CORNER {
                corners.push((sections.len() - 1, join(arriving, leaving, false, &locs[0])));
            }
        }
        let cap = (!closed).then_some(style.cap);
        let pi = std::f64::consts::PI;
        let mut plan = Self {
            sections,
            corners,
            cap,
            cap_chords: [chords(pi, &locs[0]), chords(pi, &locs[last])],
            vertices: 0,
            triangles: 0,
        };
        (plan.vertices, plan.triangles) = plan.counts();
        Ok(plan)
    }

    /// (vertices, triangles) of the mesh [`StrokePlan::write`] makes.
    fn counts(&self) -> (u64, u64) {
        let n = self.sections.len() as u64;
        let inner_corners = self
            .corners
            .iter()
            .filter(|(at, _)| *at + 1 < self.sections.len())
            .count() as u64;
        let (mut vertices, mut triangles) = (2 * n, 2 * (n - 1 - inner_corners));
        for (_, corner) in &self.corners {
            let (v, f) = match corner {
                Corner::Bevel => (1, 1),
                Corner::Miter { .. } => (2, 2),
                Corner::Round { chords } => (u64::from(*chords), u64::from(*chords)),
            };
            vertices += v;
            triangles += f;
        }
        let (v, f) = match self.cap {
            None | Some(Cap::Butt) => (0, 0),
            Some(Cap::Square) => (4, 4),
            Some(Cap::Round) => {
                let c = u64::from(self.cap_chords[0]) + u64::from(self.cap_chords[1]);
                (c, c)
            }
        };
        (vertices + v, triangles + f)
    }

    /// Writes the stroke's mesh into `out` (points with z = 0, normals +z).
    pub(crate) fn write<F: SampleFloat>(&self, table: &SegmentTable, out: &mut MeshOut<'_, F>) {
        let planes = Some((&mut *out.points, &mut *out.normals));
        let topology = out.topology.then_some((&mut *out.t, &mut *out.triangles));
        self.write_parts(table, planes, topology);
    }

    /// Each vertex's t and the triangles of the mesh [`StrokePlan::write`] makes (its
    /// positions made in f64 to turn the triangles, and dropped).
    pub(crate) fn topology(&self, table: &SegmentTable, t: &mut [f64], triangles: &mut [[u32; 3]]) {
        self.write_parts::<f64>(table, None, Some((t, triangles)));
    }

    /// Writes what there are planes for: the points and normals, and each vertex's t and the
    /// triangles.
    fn write_parts<F: SampleFloat>(
        &self,
        table: &SegmentTable,
        planes: Option<(&mut [F], &mut [F])>,
        topology: Option<(&mut [f64], &mut [[u32; 3]])>,
    ) {
        let mut held = HeldSegment::new(table);
        let centres = self
            .sections
            .iter()
            .map(|s| {
                let p = held.centre(s.segment, s.u);
                ([p[0], p[1]], 0.5 * p[2].max(0.0), s.t)
            })
            .collect();
        let mut mesh = Writer {
            planes,
            topology,
            centres,
            positions: Vec::with_capacity(self.vertices as usize),
            triangle: 0,
        };
        self.build(&mut mesh);
        debug_assert_eq!(mesh.positions.len() as u64, self.vertices);
        debug_assert!(mesh.topology.is_none() || mesh.triangle as u64 == self.triangles);
    }

    /// Every vertex as the GPU makes it, in the mesh's order: (segment, u, v), the vertex
    /// being C + h v with C the position and h half the width there (`shaders/geometry.wgsl`'s
    /// `strokes`).
    pub(crate) fn gpu_vertices(&self, mut vertex: impl FnMut(usize, f64, [f64; 2])) {
        struct Recipes<'a, V> {
            plan: &'a StrokePlan,
            vertex: V,
            count: usize,
        }
        impl<V: FnMut(usize, f64, [f64; 2])> Build for Recipes<'_, V> {
            fn vertex(&mut self, section: usize, v: [f64; 2]) -> usize {
                let s = &self.plan.sections[section];
                (self.vertex)(s.segment, s.u, v);
                self.count += 1;
                self.count - 1
            }
            fn triangle(&mut self, _: [usize; 3]) {}
        }
        self.build(&mut Recipes {
            plan: self,
            vertex: &mut vertex,
            count: 0,
        });
    }

    /// What the mesh's joins and caps are (its sections' count, each corner's place and
    /// kind, the caps): two plans of the same key make the same triangles from the same
    /// vertex recipes, up to each triangle's orientation.
    pub(crate) fn topology_key(&self) -> StrokeTopology {
        let corners = self
            .corners
            .iter()
            .map(|&(at, corner)| {
                let kind = match corner {
                    Corner::Bevel => 0,
                    Corner::Miter { .. } => 1,
                    Corner::Round { chords } => 2 + chords,
                };
                (at, kind)
            })
            .collect();
        StrokeTopology {
            sections: self.sections.len(),
            corners,
            cap: self.cap,
            cap_chords: self.cap_chords,
        }
    }

    /// Makes the mesh through `mesh`: each vertex from its section and its offset v (the
    /// vertex is C + h v there), each triangle from the vertices made so far.
    fn build(&self, mesh: &mut impl Build) {
        // Each section's left and right vertices, 2j and 2j + 1.
        for (j, s) in self.sections.iter().enumerate() {
            let n = [-s.tangent[1], s.tangent[0]];
            mesh.vertex(j, n);
            mesh.vertex(j, [-n[0], -n[1]]);
        }
        // The corners are in their arriving sections' order: walked along with the sections.
        debug_assert!(self.corners.windows(2).all(|w| w[0].0 < w[1].0));
        let mut corner_after = self.corners.iter().map(|(at, _)| *at).peekable();
        for j in 0..self.sections.len() - 1 {
            if corner_after.next_if_eq(&j).is_some() {
                continue;
            }
            let (l0, r0, l1, r1) = (2 * j, 2 * j + 1, 2 * j + 2, 2 * j + 3);
            mesh.triangle([r0, r1, l1]);
            mesh.triangle([r0, l1, l0]);
        }
        for &(at, corner) in &self.corners {
            let next = (at + 1) % self.sections.len();
            let (a, b) = (self.sections[at].tangent, self.sections[next].tangent);
            // Turning left, the outer side is the right one.
            let left_turn = a[0] * b[1] - a[1] * b[0] > 0.0;
            let (outer_a, outer_b) = if left_turn {
                (2 * at + 1, 2 * next + 1)
            } else {
                (2 * at, 2 * next)
            };
            let sign = if left_turn { -1.0 } else { 1.0 };
            let normal = |t: [f64; 2]| [-sign * t[1], sign * t[0]];
            let c = mesh.vertex(at, [0.0, 0.0]);
            match corner {
                Corner::Bevel => mesh.triangle([c, outer_a, outer_b]),
                Corner::Miter { reach } => {
                    let (na, nb) = (normal(a), normal(b));
                    let bisector = unit2([na[0] + nb[0], na[1] + nb[1]]).unwrap_or(na);
                    let m = mesh.vertex(at, [reach * bisector[0], reach * bisector[1]]);
                    mesh.triangle([c, outer_a, m]);
                    mesh.triangle([c, m, outer_b]);
                }
                Corner::Round { chords } => {
                    let (na, nb) = (normal(a), normal(b));
                    let start = na[1].atan2(na[0]);
                    let (cross, dot) =
                        (na[0] * nb[1] - na[1] * nb[0], na[0] * nb[0] + na[1] * nb[1]);
                    // The short way round; a cusp's reversal the half turn ahead of it.
                    let sweep = if cross == 0.0 && dot < 0.0 {
                        -sign * std::f64::consts::PI
                    } else {
                        cross.atan2(dot)
                    };
                    fan(mesh, at, start, sweep, chords, [c, outer_a, outer_b]);
                }
            }
        }
        if let Some(cap) = self.cap {
            let last = self.sections.len() - 1;
            for (end, (j, forward)) in [(0, -1.0), (last, 1.0)].into_iter().enumerate() {
                let t = self.sections[j].tangent;
                let along = [forward * t[0], forward * t[1]];
                let n = [-t[1], t[0]];
                let (l, r) = (2 * j, 2 * j + 1);
                match cap {
                    Cap::Butt => {}
                    Cap::Square => {
                        let l2 = mesh.vertex(j, [n[0] + along[0], n[1] + along[1]]);
                        let r2 = mesh.vertex(j, [along[0] - n[0], along[1] - n[1]]);
                        mesh.triangle([l, r, r2]);
                        mesh.triangle([l, r2, l2]);
                    }
                    Cap::Round => {
                        let start = n[1].atan2(n[0]);
                        // From the left vertex round the end to the right one.
                        let sweep = std::f64::consts::PI * -forward;
                        let c = mesh.vertex(j, [0.0, 0.0]);
                        fan(mesh, j, start, sweep, self.cap_chords[end], [c, l, r]);
                    }
                }
            }
        }
    }
}

/// What a stroke's mesh is made through: [`Writer`] on the CPU, the GPU's recipes.
trait Build {
    /// Makes the vertex C + h v of `section` (C its position, h half its width); its index.
    fn vertex(&mut self, section: usize, v: [f64; 2]) -> usize;
    /// Makes a triangle of vertices made before.
    fn triangle(&mut self, vertices: [usize; 3]);
}

/// The fan of `chords` triangles about vertex `c` (the centre of `section`) from vertex
/// `from` round the arc of radius h (angles `start` to `start + sweep`) to vertex `to`.
fn fan(
    mesh: &mut impl Build,
    section: usize,
    start: f64,
    sweep: f64,
    chords: u32,
    [c, from, to]: [usize; 3],
) {
    let mut previous = from;
    for k in 1..chords {
        let angle = start + sweep * f64::from(k) / f64::from(chords);
        let v = mesh.vertex(section, [angle.cos(), angle.sin()]);
        mesh.triangle([c, previous, v]);
        previous = v;
    }
    mesh.triangle([c, previous, to]);
}

/// Writes a stroke's vertices (their points and normals where there are planes for them, and
/// t) and triangles in order, each triangle turned counter-clockwise (by its f64 positions,
/// kept as they are made).
struct Writer<'a, F> {
    planes: Option<(&'a mut [F], &'a mut [F])>,
    topology: Option<(&'a mut [f64], &'a mut [[u32; 3]])>,
    /// Each section's position, half width and t.
    centres: Vec<([f64; 2], f64, f64)>,
    positions: Vec<[f64; 2]>,
    triangle: usize,
}

impl<F: SampleFloat> Build for Writer<'_, F> {
    fn vertex(&mut self, section: usize, v: [f64; 2]) -> usize {
        let (c, h, t) = self.centres[section];
        let p = [c[0] + h * v[0], c[1] + h * v[1]];
        let index = self.positions.len();
        if let Some((points, normals)) = &mut self.planes {
            let at = 3 * index;
            for (k, (x, n)) in [(p[0], 0.0), (p[1], 0.0), (0.0, 1.0)]
                .into_iter()
                .enumerate()
            {
                points[at + k] = F::from_f64(x);
                normals[at + k] = F::from_f64(n);
            }
        }
        if let Some((ts, _)) = &mut self.topology {
            ts[index] = t;
        }
        self.positions.push(p);
        index
    }

    fn triangle(&mut self, [a, b, c]: [usize; 3]) {
        let Some((_, triangles)) = &mut self.topology else {
            return;
        };
        let (pa, pb, pc) = (self.positions[a], self.positions[b], self.positions[c]);
        let area = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]);
        let [a, b, c] = [a, b, c].map(|v| u32::try_from(v).expect("counted within u32"));
        triangles[self.triangle] = if area < 0.0 { [a, c, b] } else { [a, b, c] };
        self.triangle += 1;
    }
}
