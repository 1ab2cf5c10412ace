//! The meshes made from a curve's cross-sections and frames: their counts (known before any
//! work) and their vertices, normals and triangles.
//!
//! - Tube: cross-section j is a ring of s vertices x_j + r_j (cos θ_k N_j + sin θ_k B_j),
//!   θ_k = 2πk/s; rings j and j+1 are joined by the quads (j, k), (j, k+1), (j+1, k+1),
//!   (j+1, k), two triangles each; a closed curve's last ring is its first. Caps: a vertex
//!   at each open end (normal -T_0, T_n) and a fan of s triangles onto the end ring.
//! - Ribbon: cross-section j gives x_j - (w_j/2) B_j and x_j + (w_j/2) B_j (normals N_j),
//!   joined to the next pair by two triangles; a closed curve's wraps as its tube does.
//!
//! Every triangle is counter-clockwise seen from its normal's side (a tube's from outside).
//!
//! A tube's vertex normal is the exact surface's. With e = cos θ N + sin θ B, the surface
//! X(s, θ) = C(s) + r(s) e(s, θ) (s the arc length) has, the frame being rotation-minimizing
//! (e_s = -(T_s · e) T),
//!
//! ```text
//! X_s = (1 - r T_s·e) T + r_s e,   X_θ = r (-sin θ N + cos θ B),
//! X_s × X_θ / r = r_s T - (1 - r T_s·e) e   ⇒   n = ((1 - r T_s·e) e - r_s T) / |...|
//! ```
//!
//! with T_s = (C'' - (C''·T) T) / |C'|² and r_s = r' / |C'| (derivatives in t). Where C' = 0
//! the normal is e.

use bsplines::lanes::Isa;

use super::frames::{Vec3, cross, dot, unit};
use crate::job::samples::SampleFloat;

/// What a mesh is made from at one cross-section: the curve parameter, the position and its
/// first two derivatives in t, the width (or radius, clamped at 0) and its derivative, and
/// the frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    /// The curve parameter t_j.
    pub t: f64,
    /// C(t_j).
    pub position: Vec3,
    /// C'(t_j).
    pub d1: Vec3,
    /// C''(t_j).
    pub d2: Vec3,
    /// w(t_j) or r(t_j), at least 0.
    pub width: f64,
    /// Its derivative in t (0 where the width is clamped).
    pub width_d1: f64,
    /// The unit tangent T_j.
    pub tangent: Vec3,
    /// The unit normal N_j.
    pub normal: Vec3,
}

/// A mesh's shape, all that its counts depend on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// A tube of `sides` vertices per ring, with or without end caps.
    Tube {
        /// Vertices per ring.
        sides: u32,
        /// End discs (an open curve's).
        caps: bool,
    },
    /// A ribbon.
    Ribbon,
}

/// The vertex and triangle counts of a mesh of `sections` cross-sections (at least 2), closed
/// (the last cross-section the first's) or open.
#[must_use]
pub fn counts(shape: Shape, sections: u64, closed: bool) -> (u64, u64) {
    let distinct = if closed { sections - 1 } else { sections };
    let joins = sections - 1;
    match shape {
        Shape::Tube { sides, caps } => {
            let s = u64::from(sides);
            let capped = caps && !closed;
            (
                distinct * s + if capped { 2 } else { 0 },
                2 * joins * s + if capped { 2 * s } else { 0 },
            )
        }
        Shape::Ribbon => (2 * distinct, 2 * joins),
    }
}

/// Where one mesh goes, in the caller's float type: 3 coordinates a vertex of points and
/// normals, one t a vertex, and triangles of indices local to the mesh; without `topology`,
/// the vertices alone (t and triangles empty: a renderer's refit keeps them).
pub(crate) struct MeshOut<'a, F> {
    pub(crate) points: &'a mut [F],
    pub(crate) normals: &'a mut [F],
    pub(crate) t: &'a mut [f64],
    pub(crate) triangles: &'a mut [[u32; 3]],
    pub(crate) topology: bool,
}

impl<F: SampleFloat> MeshOut<'_, F> {
    pub(crate) fn vertex(&mut self, v: usize, position: Vec3, normal: Vec3, t: f64) {
        for i in 0..3 {
            self.points[3 * v + i] = F::from_f64(position[i]);
            self.normals[3 * v + i] = F::from_f64(normal[i]);
        }
        if self.topology {
            self.t[v] = t;
        }
    }
}

impl<F> MeshOut<'_, F> {
    /// This output written piece after piece (a dashed curve's dashes), each piece's
    /// triangles indexing the whole mesh's vertices.
    pub(crate) fn pieces(&mut self) -> Pieces<'_, F> {
        Pieces {
            rest: MeshOut {
                points: &mut *self.points,
                normals: &mut *self.normals,
                t: &mut *self.t,
                triangles: &mut *self.triangles,
                topology: self.topology,
            },
            base: 0,
        }
    }
}

/// What is left of a [`MeshOut`] after the pieces written so far, and where the next piece's
/// vertices start.
pub(crate) struct Pieces<'a, F> {
    rest: MeshOut<'a, F>,
    base: u32,
}

impl<F> Pieces<'_, F> {
    /// The next `vertices` and `triangles` of the output, written by `write` as a mesh of its
    /// own (indices from 0) and then moved to their place in the whole.
    pub(crate) fn next_piece(
        &mut self,
        vertices: usize,
        triangles: usize,
        write: impl FnOnce(&mut MeshOut<'_, F>),
    ) {
        let (points, rest_points) =
            std::mem::take(&mut self.rest.points).split_at_mut(3 * vertices);
        let (normals, rest_normals) =
            std::mem::take(&mut self.rest.normals).split_at_mut(3 * vertices);
        let topology = self.rest.topology;
        let (tv, tf) = if topology {
            (vertices, triangles)
        } else {
            (0, 0)
        };
        let (t, rest_t) = std::mem::take(&mut self.rest.t).split_at_mut(tv);
        let (tri, rest_tri) = std::mem::take(&mut self.rest.triangles).split_at_mut(tf);
        let mut piece = MeshOut {
            points,
            normals,
            t,
            triangles: tri,
            topology,
        };
        write(&mut piece);
        for triangle in piece.triangles.iter_mut() {
            for i in triangle {
                *i += self.base;
            }
        }
        self.rest = MeshOut {
            points: rest_points,
            normals: rest_normals,
            t: rest_t,
            triangles: rest_tri,
            topology,
        };
        self.base += index(vertices as u64);
    }
}

fn index(v: u64) -> u32 {
    u32::try_from(v).expect("a mesh's vertices were counted within u32 when it was pushed")
}

/// Writes the mesh of `sections` (with their frames) into `out`, sized by [`counts`],
/// compiled for the widest vectors this CPU has (a tube's ring is a run of lanes).
pub(crate) fn write<F: SampleFloat>(
    shape: Shape,
    sections: &[Section],
    closed: bool,
    out: &mut MeshOut<'_, F>,
) {
    // One of the crate's five unsafe blocks (the others are the CPU evaluator's and the
    // frames' closing-up, the same dispatch, and memory/'s madvise and getrlimit): a function
    // compiled for an instruction set may only be called where the CPU has it.
    #[allow(
        unsafe_code,
        reason = "a function compiled for an instruction set is called only where the CPU has it"
    )]
    match Isa::widest() {
        Isa::Baseline => write_any(shape, sections, closed, out),
        // SAFETY: `Isa::widest` names AVX2 only where the CPU has it.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { write_avx2(shape, sections, closed, out) },
        // SAFETY: as for AVX2, with AVX-512F (and VL).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { write_avx512(shape, sections, closed, out) },
    }
}

/// [`write_any`] with AVX2 enabled (all it calls a vertex is inlined into it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn write_avx2<F: SampleFloat>(
    shape: Shape,
    sections: &[Section],
    closed: bool,
    out: &mut MeshOut<'_, F>,
) {
    write_any(shape, sections, closed, out);
}

/// [`write_any`] with AVX-512F enabled, as [`write_avx2`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f")]
fn write_avx512<F: SampleFloat>(
    shape: Shape,
    sections: &[Section],
    closed: bool,
    out: &mut MeshOut<'_, F>,
) {
    write_any(shape, sections, closed, out);
}

/// [`write`] as the instruction set of its caller compiles it.
#[inline(always)]
fn write_any<F: SampleFloat>(
    shape: Shape,
    sections: &[Section],
    closed: bool,
    out: &mut MeshOut<'_, F>,
) {
    match shape {
        Shape::Tube { sides, caps } => tube(sections, sides, caps && !closed, closed, out),
        Shape::Ribbon => ribbon(sections, closed, out),
    }
}

#[inline(always)]
fn tube<F: SampleFloat>(
    sections: &[Section],
    sides: u32,
    caps: bool,
    closed: bool,
    out: &mut MeshOut<'_, F>,
) {
    let s = sides as usize;
    let rings = if closed {
        sections.len() - 1
    } else {
        sections.len()
    };
    // The ring's directions, the same on every ring.
    let turns: Vec<(f64, f64)> = (0..s)
        .map(|k| (std::f64::consts::TAU * k as f64 / s as f64).sin_cos())
        .collect();
    for (j, section) in sections[..rings].iter().enumerate() {
        let (tangent, normal, r) = (section.tangent, section.normal, section.width);
        let b = cross(tangent, normal);
        let ring = j * s..(j + 1) * s;
        let points = &mut out.points[3 * ring.start..3 * ring.end];
        let normals = &mut out.normals[3 * ring.start..3 * ring.end];
        if out.topology {
            out.t[ring].fill(section.t);
        }
        // |T_s · e| <= |T_s| <= |C''| / |C'|²: where r |C''| <= |C'|² / 2 every stretch is at
        // least 1/2 (rounding can not take it to 0), and with a constant radius (r' = 0, so
        // r_s = 0) every vertex normal is e itself. Squared: no root, no division.
        let (d1, d2) = (dot(section.d1, section.d1), dot(section.d2, section.d2));
        if section.width_d1 == 0.0 && 4.0 * r * r * d2 <= d1 * d1 {
            radial_ring(&turns, section.position, r, normal, b, points, normals);
            continue;
        }
        let speed = d1.sqrt();
        // T_s and r_s of the module's docs.
        let (bend, slope) = if speed > 0.0 {
            let along = dot(section.d2, tangent);
            let bend = std::array::from_fn::<f64, 3, _>(|i| {
                (section.d2[i] - along * tangent[i]) / (speed * speed)
            });
            (bend, section.width_d1 / speed)
        } else {
            ([0.0; 3], 0.0)
        };
        // T_s · e = cos θ (T_s · N) + sin θ (T_s · B): two dots a ring, not one a vertex.
        let (bend_n, bend_b) = (dot(bend, normal), dot(bend, b));
        let points = points.chunks_exact_mut(3);
        let normals = normals.chunks_exact_mut(3);
        for ((&(sin, cos), point), vertex_normal) in turns.iter().zip(points).zip(normals) {
            let e: Vec3 = std::array::from_fn(|i| cos * normal[i] + sin * b[i]);
            let stretch = 1.0 - r * (cos * bend_n + sin * bend_b);
            // e is a unit vector across T, so |stretch e − r_s T|² = stretch² + r_s²: where
            // the radius is constant (r_s = 0), n is ±e.
            let n: Vec3 = if slope == 0.0 && stretch > 0.0 {
                e
            } else if slope == 0.0 && stretch < 0.0 {
                e.map(|x| -x)
            } else {
                let size = (stretch * stretch + slope * slope).sqrt();
                if size >= f64::MIN_POSITIVE && size.is_finite() {
                    let inverse = 1.0 / size;
                    std::array::from_fn(|i| (stretch * e[i] - slope * tangent[i]) * inverse)
                } else {
                    let n = std::array::from_fn(|i| stretch * e[i] - slope * tangent[i]);
                    unit(n).unwrap_or(e)
                }
            };
            for i in 0..3 {
                point[i] = F::from_f64(section.position[i] + r * e[i]);
                vertex_normal[i] = F::from_f64(n[i]);
            }
        }
    }
    if caps {
        let (first, last) = (&sections[0], &sections[sections.len() - 1]);
        let start = rings * s;
        out.vertex(start, first.position, first.tangent.map(|x| -x), first.t);
        out.vertex(start + 1, last.position, last.tangent, last.t);
    }
    if out.topology {
        tube_triangles(sections.len(), sides, caps, closed, out.triangles);
    }
}

/// A ring whose vertex normals are its directions e_k = cos θ_k N + sin θ_k B (a constant
/// radius, the stretch positive all round): point x + r e_k, normal e_k, each rounded once to
/// the output's type. Branch-free, so that the sides are evaluated in vector lanes.
#[inline(always)]
fn radial_ring<F: SampleFloat>(
    turns: &[(f64, f64)],
    position: Vec3,
    r: f64,
    normal: Vec3,
    b: Vec3,
    points: &mut [F],
    normals: &mut [F],
) {
    let points = points.chunks_exact_mut(3);
    let normals = normals.chunks_exact_mut(3);
    for ((&(sin, cos), point), vertex_normal) in turns.iter().zip(points).zip(normals) {
        for i in 0..3 {
            let e = cos * normal[i] + sin * b[i];
            point[i] = F::from_f64(position[i] + r * e);
            vertex_normal[i] = F::from_f64(e);
        }
    }
}

/// A tube's triangles: rings j and j + 1 joined by quads of two triangles (a closed curve's
/// last ring its first), and with `caps` a fan onto each end's centre.
///
/// Rings j and j + 1 with j + 1 a ring of its own (all but a closed curve's last quads) are
/// the quads of rings 0 and 1 with j·sides added to every index: that pattern is made once
/// and copied ring by ring, offset, in a loop without divisions or checks (the indices were
/// counted within u32 when the curve was pushed; the largest is checked once here).
fn tube_triangles(sections: usize, sides: u32, caps: bool, closed: bool, out: &mut [[u32; 3]]) {
    let s = u64::from(sides);
    let rings = if closed { sections - 1 } else { sections } as u64;
    let ring = |j: u64| (j % rings) * s;
    let quads = |a: u64, b: u64, out: &mut [[u32; 3]]| {
        for (k, pair) in (0..s).zip(out.chunks_exact_mut(2)) {
            let k1 = if k + 1 == s { 0 } else { k + 1 };
            pair[0] = [index(a + k), index(a + k1), index(b + k1)];
            pair[1] = [index(a + k), index(b + k1), index(b + k)];
        }
    };
    let per_ring = 2 * sides as usize;
    let joined = sections - 1;
    // The rings whose next ring follows them in the vertices: all of an open tube's, all but
    // the last of a closed one's.
    let offset_rings = if closed {
        joined.saturating_sub(1)
    } else {
        joined
    };
    let mut pattern = vec![[0u32; 3]; per_ring];
    quads(0, s, &mut pattern);
    // The largest index the copies write: ring offset_rings's last vertex.
    index(offset_rings as u64 * s + s - 1);
    for (j, ring_out) in out[..offset_rings * per_ring]
        .chunks_exact_mut(per_ring)
        .enumerate()
    {
        let a = (j as u64 * s) as u32;
        for (t, p) in ring_out.iter_mut().zip(&pattern) {
            *t = p.map(|v| v + a);
        }
    }
    let mut triangle = offset_rings * per_ring;
    for j in offset_rings as u64..joined as u64 {
        quads(
            ring(j),
            ring(j + 1),
            &mut out[triangle..triangle + per_ring],
        );
        triangle += per_ring;
    }
    if caps {
        let (start, end) = (rings * s, rings * s + 1);
        let end_ring = ring(rings - 1);
        for k in 0..s {
            let k1 = (k + 1) % s;
            out[triangle] = [index(start), index(k1), index(k)];
            out[triangle + 1] = [index(end), index(end_ring + k), index(end_ring + k1)];
            triangle += 2;
        }
    }
}

fn ribbon(sections: &[Section], closed: bool, out: &mut MeshOut<'_, impl SampleFloat>) {
    let pairs = if closed {
        sections.len() - 1
    } else {
        sections.len()
    };
    for (j, section) in sections[..pairs].iter().enumerate() {
        let b = cross(section.tangent, section.normal);
        let half = 0.5 * section.width;
        let left = std::array::from_fn(|i| section.position[i] - half * b[i]);
        let right = std::array::from_fn(|i| section.position[i] + half * b[i]);
        out.vertex(2 * j, left, section.normal, section.t);
        out.vertex(2 * j + 1, right, section.normal, section.t);
    }
    if out.topology {
        ribbon_triangles(sections.len(), closed, out.triangles);
    }
}

/// A ribbon's triangles: pair j and pair j + 1 joined by two (a closed curve's last pair its
/// first).
fn ribbon_triangles(sections: usize, closed: bool, out: &mut [[u32; 3]]) {
    let pairs = if closed { sections - 1 } else { sections };
    let pair = |j: usize| 2 * (j % pairs) as u64;
    for j in 0..sections - 1 {
        let (a, b) = (pair(j), pair(j + 1));
        out[2 * j] = [index(a), index(a + 1), index(b)];
        out[2 * j + 1] = [index(a + 1), index(b + 1), index(b)];
    }
}

/// What a mesh of `shape` at cross-sections of parameters `ts` has whatever its positions:
/// each vertex's t (a cap's its end's) and the triangles, as [`write`] makes them.
pub(crate) fn topology(
    shape: Shape,
    ts: &[f64],
    closed: bool,
    t: &mut [f64],
    triangles: &mut [[u32; 3]],
) {
    let kept = if closed { ts.len() - 1 } else { ts.len() };
    match shape {
        Shape::Tube { sides, caps } => {
            let s = sides as usize;
            for (j, &tj) in ts[..kept].iter().enumerate() {
                t[j * s..(j + 1) * s].fill(tj);
            }
            let caps = caps && !closed;
            if caps {
                t[kept * s] = ts[0];
                t[kept * s + 1] = ts[ts.len() - 1];
            }
            tube_triangles(ts.len(), sides, caps, closed, triangles);
        }
        Shape::Ribbon => {
            for (j, &tj) in ts[..kept].iter().enumerate() {
                t[2 * j..2 * j + 2].fill(tj);
            }
            ribbon_triangles(ts.len(), closed, triangles);
        }
    }
}
