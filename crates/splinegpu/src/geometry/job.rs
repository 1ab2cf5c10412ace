//! `GeometryJob`: many curves' meshes, counted when each curve is pushed and made together.

use std::ops::Range;
use std::sync::OnceLock;

use rayon::prelude::*;

use super::frames::{self, Vec3};
use super::mesh::{self, MeshOut, Section, Shape};
use super::plan::{Body, Planned, check_mesh_size, mesh_bytes, plan, section};
use super::stroke::StrokePlan;
use super::{Geometry, Width};
use crate::curve::Curve;
use crate::error::InputError;
use crate::job::samples::SampleFloat;
use crate::memory;
use crate::sampling::{SampleLoc, Sampling};
use crate::segment::SegmentTable;

/// A tube's or ribbon's plan, undashed, as the GPU packer reads it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SweptPlan<'a> {
    /// The widened table (the width its last coordinate).
    pub(crate) table: &'a SegmentTable,
    /// The cross-sections.
    pub(crate) locs: &'a [SampleLoc],
    /// The arc length to each (closed curves).
    pub(crate) lengths: Option<&'a [f64]>,
    pub(crate) shape: Shape,
    pub(crate) n0: Vec3,
    /// A dashed curve's pieces: each the indices of its cross-sections in `locs`.
    pub(crate) dashes: Option<&'a [Vec<usize>]>,
}

/// A curve's plan as the GPU packer reads it.
#[derive(Clone, Copy, Debug)]
pub(crate) enum KernelPlan<'a> {
    /// A tube or ribbon, dashed or not.
    Swept(SweptPlan<'a>),
    /// A stroke: the widened table (x, y, w) and its pieces (one, or one a dash), laid one
    /// after the other.
    Stroke {
        table: &'a SegmentTable,
        pieces: &'a [StrokePlan],
    },
}

impl KernelPlan<'_> {
    /// A stroke's pieces' topologies (what its triangles are made from), none for a tube or
    /// ribbon (whose triangles follow from its counts).
    pub(crate) fn stroke_topology(&self) -> Vec<super::stroke::StrokeTopology> {
        match self {
            Self::Swept(_) => Vec::new(),
            Self::Stroke { pieces, .. } => pieces.iter().map(StrokePlan::topology_key).collect(),
        }
    }

    /// The widened table.
    pub(crate) fn table(&self) -> &SegmentTable {
        match self {
            Self::Swept(plan) => plan.table,
            Self::Stroke { table, .. } => table,
        }
    }
}

/// What is made at one cross-section: its ring's (or ribbon pair's) first vertex, and a cap's
/// vertex with the way it faces (-1: a piece's start, -T; +1: its end, T).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Slot {
    pub(crate) first_vertex: u32,
    pub(crate) cap: Option<(u32, i32)>,
}

impl SweptPlan<'_> {
    /// Whether its frames are closed up (a closed curve's).
    pub(crate) fn closed(&self) -> bool {
        self.lengths.is_some()
    }

    /// Each vertex's t and the triangles of its mesh, as [`make`] writes them (a dashed
    /// curve's pieces one after the other, their triangles indexing the whole mesh).
    pub(crate) fn topology(&self, t: &mut [f64], triangles: &mut [[u32; 3]]) {
        let Some(pieces) = self.dashes else {
            let all: Vec<f64> = self.locs.iter().map(|l| l.t).collect();
            return mesh::topology(self.shape, &all, self.closed(), t, triangles);
        };
        let (mut v0, mut f0) = (0, 0);
        for piece in pieces {
            let (v, f) = mesh::counts(self.shape, piece.len() as u64, false);
            let (v, f) = (v as usize, f as usize);
            let own: Vec<f64> = piece.iter().map(|&k| self.locs[k].t).collect();
            let part = &mut triangles[f0..f0 + f];
            mesh::topology(self.shape, &own, false, &mut t[v0..v0 + v], part);
            for i in part.iter_mut().flatten() {
                *i += v0 as u32;
            }
            (v0, f0) = (v0 + v, f0 + f);
        }
    }

    /// Where each cross-section's vertices go, `None` for a cross-section nothing is made at
    /// (a closed curve's last, whose ring is the first's; a place a dash does not hold). The
    /// vertices are laid out as [`mesh::write`] lays them, a dashed curve's pieces one after
    /// the other.
    pub(crate) fn slots(&self) -> Vec<Option<Slot>> {
        let (per, caps) = match self.shape {
            Shape::Tube { sides, caps } => (sides, caps),
            Shape::Ribbon => (2, false),
        };
        let mut slots = vec![None; self.locs.len()];
        let mut place = |piece: &[usize], closed: bool, base: u32| -> u32 {
            let rings = if closed { piece.len() - 1 } else { piece.len() };
            let caps = caps && !closed;
            for (j, &k) in piece.iter().take(rings).enumerate() {
                slots[k] = Some(Slot {
                    first_vertex: base + j as u32 * per,
                    cap: None,
                });
            }
            let end = base + rings as u32 * per;
            if caps {
                let (first, last) = (piece[0], piece[piece.len() - 1]);
                for (k, cap) in [(first, (end, -1)), (last, (end + 1, 1))] {
                    if let Some(slot) = &mut slots[k] {
                        slot.cap = Some(cap);
                    }
                }
                return end + 2;
            }
            end
        };
        match self.dashes {
            None => {
                let all: Vec<usize> = (0..self.locs.len()).collect();
                place(&all, self.closed(), 0);
            }
            Some(pieces) => {
                let mut base = 0;
                for piece in pieces {
                    base = place(piece, false, base);
                }
            }
        }
        slots
    }
}

/// Many curves' meshes: each curve's geometry and sampling checked and its counts known when
/// it is pushed, the meshes made by [`GeometryJob::evaluate_cpu`]. Mesh c owns vertices
/// `vertex_offsets()[c]..vertex_offsets()[c + 1]` and triangles likewise; its triangles'
/// indices are local to it (a renderer draws mesh c with base vertex `vertex_offsets()[c]`).
#[derive(Debug)]
pub struct GeometryJob {
    curves: Vec<Planned>,
    vertex_offsets: Vec<u64>,
    triangle_offsets: Vec<u64>,
    available: OnceLock<Option<u64>>,
}

/// The meshes of a [`GeometryJob`], every curve's in order: f64 from the CPU, f32 from the
/// GPU ([`GpuContext::evaluate_geometry`](crate::GpuContext::evaluate_geometry)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Meshes<F = f64> {
    /// 3 coordinates a vertex.
    pub points: Vec<F>,
    /// The unit normal at each vertex, 3 coordinates a vertex.
    pub normals: Vec<F>,
    /// The curve parameter each vertex was made at (a cap's centre: its end's).
    pub t: Vec<f64>,
    /// Counter-clockwise triangles, indices local to their mesh.
    pub triangles: Vec<[u32; 3]>,
    /// Mesh c's vertices are `vertex_offsets[c]..vertex_offsets[c + 1]`.
    pub vertex_offsets: Vec<u64>,
    /// Mesh c's triangles are `triangle_offsets[c]..triangle_offsets[c + 1]`.
    pub triangle_offsets: Vec<u64>,
}

impl Default for GeometryJob {
    /// [`GeometryJob::new`]: its offsets start at 0.
    fn default() -> Self {
        Self::new()
    }
}

impl GeometryJob {
    /// An empty job.
    #[must_use]
    pub fn new() -> Self {
        Self {
            curves: Vec::new(),
            vertex_offsets: vec![0],
            triangle_offsets: vec![0],
            available: OnceLock::new(),
        }
    }

    /// Plans `curve`'s mesh: `geometry` made at the cross-sections `sampling` places.
    ///
    /// # Errors
    /// A curve whose dimension the geometry does not take (field "geometry"); a radius or
    /// width that is not finite and > 0 or not one per point ("radius", "width"); a tube of
    /// fewer than 3 sides, or with tolerance sides whose polygon alone strays more than tol
    /// ("sides"); an `up` not 3 finite numbers or parallel to the first tangent ("up"); a
    /// tolerance not finite and > 0, or one that cannot be certified (the curve's speed
    /// vanishes, or a tube's or ribbon's tangent turns a corner: "tolerance"); "at" sampling,
    /// more than [`MAX_SECTIONS`](super::MAX_SECTIONS) cross-sections, more than 2^32 - 1 vertices in the mesh, or
    /// a mesh larger than the memory the process has ("sampling"). The caller places the
    /// error in its curve
    /// ([`InputError::in_curve`]); the job is then unchanged.
    pub fn push(
        &mut self,
        curve: &Curve,
        geometry: &Geometry,
        sampling: &Sampling,
    ) -> Result<(), InputError> {
        let planned = plan(curve, geometry, sampling)?;
        let (vertices, triangles) = (planned.vertices, planned.triangles);
        check_mesh_size(vertices)?;
        let total_vertices = self.vertex_count() + vertices;
        let total_triangles = self.triangle_count() + triangles;
        self.check_fits(total_vertices, total_triangles)?;
        self.curves.push(planned);
        self.vertex_offsets.push(total_vertices);
        self.triangle_offsets.push(total_triangles);
        Ok(())
    }

    /// [`GeometryJob::push`] for many curves, planned on every thread and added in order.
    ///
    /// # Errors
    /// The first failing curve's error, placed at its index in the job
    /// ([`InputError::in_curve`]); the job is then unchanged.
    pub fn push_many(&mut self, curves: &[(Curve, Geometry, Sampling)]) -> Result<(), InputError> {
        let first = self.len();
        let planned: Vec<Result<Planned, InputError>> = curves
            .par_iter()
            .map(|(curve, geometry, sampling)| plan(curve, geometry, sampling))
            .collect();
        let mut plans = Vec::with_capacity(planned.len());
        for (i, plan) in planned.into_iter().enumerate() {
            plans.push(plan.map_err(|e| e.in_curve(first + i))?);
        }
        let (mut vertices, mut triangles) = (self.vertex_count(), self.triangle_count());
        let (mut vertex_offsets, mut triangle_offsets) = (Vec::new(), Vec::new());
        for (i, plan) in plans.iter().enumerate() {
            check_mesh_size(plan.vertices).map_err(|e| e.in_curve(first + i))?;
            vertices += plan.vertices;
            triangles += plan.triangles;
            vertex_offsets.push(vertices);
            triangle_offsets.push(triangles);
        }
        self.check_fits(vertices, triangles)
            .map_err(|e| e.in_curve(first + curves.len().saturating_sub(1)))?;
        self.curves.extend(plans);
        self.vertex_offsets.extend(vertex_offsets);
        self.triangle_offsets.extend(triangle_offsets);
        Ok(())
    }

    /// Refuses a job whose meshes (7 f64 and a triangle's 12 bytes per vertex and triangle)
    /// would not fit in the memory the process has.
    fn check_fits(&self, vertices: u64, triangles: u64) -> Result<(), InputError> {
        let Some(available) = *self.available.get_or_init(memory::available_memory) else {
            return Ok(());
        };
        let bytes = mesh_bytes(vertices, triangles);
        if bytes > u128::from(available) {
            return Err(InputError::field(
                "sampling",
                format!(
                    "gives the job {vertices} vertices and {triangles} triangles, {bytes} bytes; \
                     the process has {available} bytes of memory available"
                ),
            ));
        }
        Ok(())
    }

    /// The number of curves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.curves.len()
    }

    /// Whether the job has no curves.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.curves.is_empty()
    }

    /// Every mesh's vertices, together.
    #[must_use]
    pub fn vertex_count(&self) -> u64 {
        *self.vertex_offsets.last().unwrap_or(&0)
    }

    /// Every mesh's triangles, together.
    #[must_use]
    pub fn triangle_count(&self) -> u64 {
        *self.triangle_offsets.last().unwrap_or(&0)
    }

    /// Mesh c's first vertex, for c in 0..=len (the last: the vertex count).
    #[must_use]
    pub fn vertex_offsets(&self) -> &[u64] {
        &self.vertex_offsets
    }

    /// Mesh c's first triangle, for c in 0..=len.
    #[must_use]
    pub fn triangle_offsets(&self) -> &[u64] {
        &self.triangle_offsets
    }

    /// The geometry mesh c is made of.
    ///
    /// # Panics
    /// If c is not a curve of the job.
    #[must_use]
    pub fn geometry(&self, c: usize) -> &Geometry {
        &self.curves[c].geometry
    }

    /// Curve c's plan as the GPU kernel takes it.
    pub(crate) fn kernel_plan(&self, c: usize) -> KernelPlan<'_> {
        let planned = &self.curves[c];
        match (self.swept(c), &planned.body) {
            (Some(plan), _) => KernelPlan::Swept(plan),
            (None, Body::Stroke(pieces)) => KernelPlan::Stroke {
                table: &planned.table,
                pieces,
            },
            (None, Body::Swept { .. }) => unreachable!("a swept body has a swept plan"),
        }
    }

    /// Each vertex's t and the triangles of curve c's mesh, as the CPU makes them: a tube's
    /// or ribbon's from its plan alone, a stroke's pieces' from their f64 positions (its
    /// triangles are turned counter-clockwise by them), one piece after the other.
    pub(crate) fn topology(&self, c: usize, t: &mut [f64], triangles: &mut [[u32; 3]]) {
        let (table, pieces) = match self.kernel_plan(c) {
            KernelPlan::Swept(plan) => return plan.topology(t, triangles),
            KernelPlan::Stroke { table, pieces } => (table, pieces),
        };
        let (mut v0, mut f0) = (0, 0);
        for piece in pieces {
            let (v, f) = (piece.vertices as usize, piece.triangles as usize);
            let part = &mut triangles[f0..f0 + f];
            piece.topology(table, &mut t[v0..v0 + v], part);
            for i in part.iter_mut().flatten() {
                *i += v0 as u32;
            }
            (v0, f0) = (v0 + v, f0 + f);
        }
    }

    /// Curve c's tube or ribbon plan, `None` for a stroke.
    pub(crate) fn swept(&self, c: usize) -> Option<SweptPlan<'_>> {
        let planned = &self.curves[c];
        match &planned.body {
            Body::Swept {
                locs,
                lengths,
                shape,
                n0,
                dashes,
            } => Some(SweptPlan {
                table: &planned.table,
                locs,
                lengths: lengths.as_deref(),
                shape: *shape,
                n0: *n0,
                dashes: dashes.as_deref(),
            }),
            Body::Stroke(_) => None,
        }
    }

    /// The job's curves cut into consecutive ranges of at most `vertices` vertices each (a
    /// curve with more is a range of its own): what a writer evaluates at a time to bound
    /// its memory.
    #[must_use]
    pub fn groups(&self, vertices: u64) -> Vec<Range<usize>> {
        let mut groups = Vec::new();
        let mut start = 0;
        for c in 0..self.len() {
            let held = self.vertex_offsets[c + 1] - self.vertex_offsets[start];
            if c > start && held > vertices {
                groups.push(start..c);
                start = c;
            }
        }
        groups.push(start..self.len());
        groups
    }

    /// Every curve's mesh, in f64 on every thread, into new memory.
    #[must_use]
    pub fn evaluate_cpu(&self) -> Meshes {
        self.evaluate_cpu_group(0..self.len())
    }

    /// The meshes of the curves in `range`, in f64 on every thread, into new memory; the
    /// offsets of the result start at 0 with the range's first curve.
    ///
    /// # Panics
    /// If `range` is not within the job, or the process cannot have the memory (with the
    /// reason; [`GeometryJob::try_evaluate_cpu_group`] returns it instead).
    #[must_use]
    pub fn evaluate_cpu_group(&self, range: Range<usize>) -> Meshes {
        self.try_evaluate_cpu_group(range)
            .unwrap_or_else(|e| panic!("{e}"))
    }

    /// [`GeometryJob::evaluate_cpu_group`], its allocations fallible: where the process
    /// cannot have the meshes' memory (a limit the estimate made at `push` missed), an error
    /// naming "sampling", never an abort.
    ///
    /// # Errors
    /// The meshes' memory refused.
    ///
    /// # Panics
    /// If `range` is not within the job.
    pub fn try_evaluate_cpu_group(&self, range: Range<usize>) -> Result<Meshes, InputError> {
        let first_vertex = self.vertex_offsets[range.start];
        let first_triangle = self.triangle_offsets[range.start];
        let vertex_offsets: Vec<u64> = self.vertex_offsets[range.start..=range.end]
            .iter()
            .map(|o| o - first_vertex)
            .collect();
        let triangle_offsets: Vec<u64> = self.triangle_offsets[range.start..=range.end]
            .iter()
            .map(|o| o - first_triangle)
            .collect();
        let vertices =
            usize::try_from(vertex_offsets[range.len()]).expect("checked against memory");
        let triangles =
            usize::try_from(triangle_offsets[range.len()]).expect("checked against memory");
        let refused = |_| {
            InputError::field(
                "sampling",
                format!(
                    "makes {vertices} vertices and {triangles} triangles for curves {} to {}, \
                     {} bytes, more than the process can have",
                    range.start,
                    range.end.saturating_sub(1),
                    mesh_bytes(vertices as u64, triangles as u64)
                ),
            )
        };
        let mut meshes = Meshes {
            points: memory::try_zeroed(3 * vertices).map_err(refused)?,
            normals: memory::try_zeroed(3 * vertices).map_err(refused)?,
            t: memory::try_zeroed(vertices).map_err(refused)?,
            triangles: memory::try_zeroed(triangles).map_err(refused)?,
            vertex_offsets,
            triangle_offsets,
        };
        let planes = MeshPlanes {
            points: &mut meshes.points,
            normals: &mut meshes.normals,
            t: &mut meshes.t,
            triangles: &mut meshes.triangles,
        };
        let outs = self.split(range.clone(), planes);
        self.curves[range]
            .par_iter()
            .zip(outs)
            .for_each(|(planned, mut out)| make(planned, &mut out));
        Ok(meshes)
    }

    /// Every curve's mesh into the caller's memory (a renderer's, kept from frame to frame),
    /// in f32 or f64 on every thread: nothing is allocated but each stroke's positions.
    ///
    /// # Errors
    /// A plane whose length is not the job's (3 values a vertex for points and normals, one t
    /// a vertex, one entry a triangle); the error names "planes".
    pub fn evaluate_into<F: SampleFloat>(
        &self,
        planes: MeshPlanes<'_, F>,
    ) -> Result<(), InputError> {
        let (v, f) = (self.vertex_count(), self.triangle_count());
        for (name, len, want) in [
            ("points", planes.points.len(), 3 * v),
            ("normals", planes.normals.len(), 3 * v),
            ("t", planes.t.len(), v),
            ("triangles", planes.triangles.len(), f),
        ] {
            if len as u64 != want {
                return Err(InputError::field(
                    "planes",
                    format!("\"{name}\" holds {len} entries, the job's meshes {want}"),
                ));
            }
        }
        let outs = self.split(0..self.len(), planes);
        self.curves
            .par_iter()
            .zip(outs)
            .for_each(|(planned, mut out)| make(planned, &mut out));
        Ok(())
    }

    /// Every curve's vertices alone (positions and normals, 3 values a vertex each, f32 or
    /// f64) into the caller's memory, on every thread: a renderer's frame after
    /// [`GeometryJob::refit`], whose counts and triangles the first
    /// [`GeometryJob::evaluate_into`] wrote and a refit keeps (a stroke's triangles keep the
    /// orientation they were made with). Half the bytes of `evaluate_into` or less: no t, no
    /// triangles.
    ///
    /// # Errors
    /// A plane whose length is not the job's; the error names "planes".
    pub fn evaluate_vertices_into<F: SampleFloat>(
        &self,
        points: &mut [F],
        normals: &mut [F],
    ) -> Result<(), InputError> {
        let want = 3 * self.vertex_count();
        for (name, len) in [("points", points.len()), ("normals", normals.len())] {
            if len as u64 != want {
                return Err(InputError::field(
                    "planes",
                    format!("\"{name}\" holds {len} entries, the job's meshes {want}"),
                ));
            }
        }
        let planes = MeshPlanes {
            points,
            normals,
            t: &mut [],
            triangles: &mut [],
        };
        let outs = split_planes(planes, &self.vertex_offsets, &self.triangle_offsets, false);
        self.curves
            .par_iter()
            .zip(outs)
            .for_each(|(planned, mut out)| make(planned, &mut out));
        Ok(())
    }

    /// Fits curve c again from `curve` (its points moved; its geometry and sampling kept),
    /// keeping its place and its triangles: for a renderer's moving curves, refitted each
    /// frame and evaluated into the same buffers ([`GeometryJob::evaluate_vertices_into`]).
    ///
    /// # Errors
    /// The new curve's own errors (as [`GeometryJob::push`]'s), a mesh of other counts than
    /// curve c's (a stroke that gains or loses a corner, another number of segments), or a
    /// stroke whose joins or caps changed with the same counts (a miter and a bevel trading
    /// corners: other triangles), naming "curve": the job is then unchanged and must be made
    /// again.
    ///
    /// # Panics
    /// If c is not a curve of the job.
    pub fn refit(&mut self, c: usize, curve: &Curve) -> Result<(), InputError> {
        let old = &self.curves[c];
        let planned = plan(curve, &old.geometry, &old.sampling)?;
        if (planned.vertices, planned.triangles) != (old.vertices, old.triangles) {
            return Err(InputError::field(
                "curve",
                format!(
                    "makes {} vertices and {} triangles where the job holds {} and {}",
                    planned.vertices, planned.triangles, old.vertices, old.triangles
                ),
            ));
        }
        let joins = |p: &Planned| match &p.body {
            Body::Stroke(pieces) => pieces.iter().map(StrokePlan::topology_key).collect(),
            Body::Swept { .. } => Vec::new(),
        };
        if joins(&planned) != joins(old) {
            return Err(InputError::field(
                "curve",
                "makes a stroke whose joins or caps are not the job's (the same counts, other \
                 triangles)",
            ));
        }
        self.curves[c] = planned;
        Ok(())
    }

    /// The planes, which hold the curves of `range`, cut into each curve's part.
    fn split<'a, F>(&self, range: Range<usize>, planes: MeshPlanes<'a, F>) -> Vec<MeshOut<'a, F>> {
        split_planes(
            planes,
            &self.vertex_offsets[range.start..=range.end],
            &self.triangle_offsets[range.start..=range.end],
            true,
        )
    }
}

/// `planes` cut into each mesh's part, mesh c owning the vertices and triangles between
/// entries c and c + 1 of the offsets (counted from any start); without `topology`, the
/// vertices alone (`t` and `triangles` empty).
pub(crate) fn split_planes<'a, F>(
    planes: MeshPlanes<'a, F>,
    vertex_offsets: &[u64],
    triangle_offsets: &[u64],
    topology: bool,
) -> Vec<MeshOut<'a, F>> {
    let MeshPlanes {
        mut points,
        mut normals,
        mut t,
        mut triangles,
    } = planes;
    let mut outs = Vec::with_capacity(vertex_offsets.len().saturating_sub(1));
    for (v, f) in vertex_offsets.windows(2).zip(triangle_offsets.windows(2)) {
        let (v, f) = ((v[1] - v[0]) as usize, (f[1] - f[0]) as usize);
        let (p, rest_p) = std::mem::take(&mut points).split_at_mut(3 * v);
        let (n, rest_n) = std::mem::take(&mut normals).split_at_mut(3 * v);
        let (tv, tf) = if topology { (v, f) } else { (0, 0) };
        let (tt, rest_t) = std::mem::take(&mut t).split_at_mut(tv);
        let (tri, rest_tri) = std::mem::take(&mut triangles).split_at_mut(tf);
        (points, normals, t, triangles) = (rest_p, rest_n, rest_t, rest_tri);
        outs.push(MeshOut {
            points: p,
            normals: n,
            t: tt,
            triangles: tri,
            topology,
        });
    }
    outs
}

/// A caller's memory for a job's meshes: positions and normals (3 values a vertex, f32 or
/// f64), the t of each vertex, and the triangles (indices local to each mesh).
#[derive(Debug)]
pub struct MeshPlanes<'a, F> {
    /// 3 values a vertex.
    pub points: &'a mut [F],
    /// 3 values a vertex.
    pub normals: &'a mut [F],
    /// One a vertex.
    pub t: &'a mut [f64],
    /// One a triangle.
    pub triangles: &'a mut [[u32; 3]],
}

/// Makes one curve's mesh into `out`.
fn make<F: SampleFloat>(planned: &Planned, out: &mut MeshOut<'_, F>) {
    let (locs, lengths, shape, n0, dashes) = match &planned.body {
        Body::Stroke(strokes) => {
            let mut pieces = out.pieces();
            for stroke in strokes {
                let (v, f) = (stroke.vertices as usize, stroke.triangles as usize);
                pieces.next_piece(v, f, |piece| stroke.write(&planned.table, piece));
            }
            return;
        }
        Body::Swept {
            locs,
            lengths,
            shape,
            n0,
            dashes,
        } => (locs, lengths, *shape, *n0, dashes),
    };
    // A constant width is the width itself, not the widened table's value (w within a
    // rounding, w' of 1e-18 where the fit's sums do not cancel exactly).
    let constant = match planned.geometry.width().0 {
        Width::Constant(w) => Some(*w),
        Width::PerPoint(_) => None,
    };
    let mut sections: Vec<Section> = locs
        .iter()
        .map(|&loc| {
            let mut s = section(&planned.table, loc);
            if let Some(w) = constant {
                (s.width, s.width_d1) = (w, 0.0);
            }
            s
        })
        .collect();
    let d1: Vec<Vec3> = sections.iter().map(|s| s.d1).collect();
    let d2: Vec<Vec3> = sections.iter().map(|s| s.d2).collect();
    let tangents = frames::tangents(&d1, &d2);
    let positions: Vec<Vec3> = sections.iter().map(|s| s.position).collect();
    let mut normals = frames::rotation_minimizing(&positions, &tangents, n0);
    if let Some(lengths) = lengths {
        frames::close_up(&tangents, &mut normals, lengths);
    }
    for ((section, tangent), normal) in sections.iter_mut().zip(tangents).zip(normals) {
        section.tangent = tangent;
        section.normal = normal;
    }
    let Some(dashes) = dashes else {
        return mesh::write(shape, &sections, lengths.is_some(), out);
    };
    let mut pieces = out.pieces();
    for dash in dashes {
        let own: Vec<Section> = dash.iter().map(|&k| sections[k]).collect();
        let (v, f) = mesh::counts(shape, own.len() as u64, false);
        pieces.next_piece(v as usize, f as usize, |piece| {
            mesh::write(shape, &own, false, piece);
        });
    }
}
