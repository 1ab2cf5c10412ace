//! A job of many surfaces, as [`EvalJob`](crate::EvalJob) is of many curves: each surface's
//! patches, sampling and plan, checked when it is pushed (normals need 3-D points; a plan
//! that would not fit in memory is refused before it is made), with the layout of the whole
//! output: where each surface's vertices and triangles start when the surfaces are laid end
//! to end, triangles numbered over all vertices. The command line's outputs, the Python
//! arrays and the GPU path all read the layout from here.

use std::borrow::Cow;
use std::ops::Range;
use std::sync::OnceLock;

use rayon::prelude::*;

use super::eval::{SurfacePlanes, SurfaceSamples, evaluate_surfaces, evaluate_surfaces_into};
use super::mesh::{SurfacePlan, SurfaceSampling};
use super::patch::PatchTable;
use crate::error::InputError;
use crate::job::Derivatives;
use crate::{SampleFloat, memory};

/// One surface of a [`SurfaceJob`]: its patches, its sampling, its plan's sizes, and the plan
/// when the job keeps it.
#[derive(Debug)]
pub struct JobSurface {
    table: PatchTable,
    sampling: SurfaceSampling,
    vertices: usize,
    triangles: Option<usize>,
    plan: Option<SurfacePlan>,
}

impl JobSurface {
    /// The fitted patches.
    #[must_use]
    pub fn table(&self) -> &PatchTable {
        &self.table
    }

    /// How it is sampled.
    #[must_use]
    pub fn sampling(&self) -> &SurfaceSampling {
        &self.sampling
    }

    /// Its vertices.
    #[must_use]
    pub fn vertices(&self) -> usize {
        self.vertices
    }

    /// Its triangles; `None` for explicit (u, v).
    #[must_use]
    pub fn triangles(&self) -> Option<usize> {
        self.triangles
    }

    /// Its plan: the kept one, or made again (the same plan: planning is deterministic).
    #[must_use]
    pub fn plan(&self) -> Cow<'_, SurfacePlan> {
        match &self.plan {
            Some(plan) => Cow::Borrowed(plan),
            None => Cow::Owned(
                SurfacePlan::new(&self.table, &self.sampling)
                    .expect("the same plan was made when the surface was pushed"),
            ),
        }
    }
}

/// Many surfaces to evaluate together (see the module docs).
///
/// ```
/// use splinegpu::Derivatives;
/// use splinegpu::surface::{Net, Surface, SurfaceKind, SurfaceJob, SurfaceSampling};
///
/// let net = Net::new(3, 4, 4, (0..48).map(|i| f64::from(i % 7)).collect())?;
/// let surface = Surface::new(SurfaceKind::Bezier, net)?;
/// let mut job = SurfaceJob::new(Derivatives::First, true);
/// job.push(surface.fit(), SurfaceSampling::PerSegment([8, 8]))?;
/// assert_eq!(job.vertex_offsets(), &[0, 81]);
/// let samples = job.evaluate_cpu();
/// assert_eq!(samples[0].normals.as_ref().map(Vec::len), Some(3 * 81));
/// # Ok::<(), splinegpu::InputError>(())
/// ```
#[derive(Debug)]
pub struct SurfaceJob {
    derivatives: Derivatives,
    normals: bool,
    surfaces: Vec<JobSurface>,
    vertex_offsets: Vec<u64>,
    triangle_offsets: Vec<u64>,
    /// Vertices whose plans are kept; the plans of the surfaces pushed past it are made again
    /// when they are evaluated.
    keep_vertices: usize,
    kept: usize,
    /// The memory available, read once (at the first surface that needs it).
    available: OnceLock<Option<u64>>,
}

impl SurfaceJob {
    /// An empty job forming the planes `derivatives` asks for, and unit normals when
    /// `normals` (every surface must then be 3-D). It keeps every plan.
    #[must_use]
    pub fn new(derivatives: Derivatives, normals: bool) -> Self {
        Self {
            derivatives,
            normals,
            surfaces: Vec::new(),
            vertex_offsets: vec![0],
            triangle_offsets: vec![0],
            keep_vertices: usize::MAX,
            kept: 0,
            available: OnceLock::new(),
        }
    }

    /// This job, keeping the plans (40 bytes a vertex) of the surfaces first pushed up to
    /// `vertices` in all and making the others again when they are evaluated: memory stays
    /// bounded however many surfaces are pushed.
    #[must_use]
    pub fn keeping_plans_up_to(mut self, vertices: usize) -> Self {
        self.keep_vertices = vertices;
        self
    }

    /// Adds a surface: its patches and its sampling, planned now.
    ///
    /// # Errors
    /// Normals asked of a surface that is not 3-D (field "normals"); a sampling whose plan and
    /// f64 values would not fit in the memory available (field "sampling", refused before the
    /// plan is made); the sampling's own errors ([`SurfacePlan::new`]). The job is unchanged.
    pub fn push(&mut self, table: PatchTable, sampling: SurfaceSampling) -> Result<(), InputError> {
        self.check(&table, &sampling)?;
        let plan = SurfacePlan::new(&table, &sampling)?;
        self.append(table, sampling, plan);
        Ok(())
    }

    /// Adds many surfaces, planned on every thread, in order.
    ///
    /// # Errors
    /// The first surface's error (as [`SurfaceJob::push`]'s), placed at its index in the job
    /// ([`InputError::in_surface`]); the job is then unchanged.
    pub fn push_many(
        &mut self,
        surfaces: Vec<(PatchTable, SurfaceSampling)>,
    ) -> Result<(), InputError> {
        let first = self.len();
        for (i, (table, sampling)) in surfaces.iter().enumerate() {
            self.check(table, sampling)
                .map_err(|e| e.in_surface(first + i))?;
        }
        let plans: Vec<Result<SurfacePlan, InputError>> = surfaces
            .par_iter()
            .map(|(table, sampling)| SurfacePlan::new(table, sampling))
            .collect();
        let mut planned = Vec::with_capacity(plans.len());
        for (i, plan) in plans.into_iter().enumerate() {
            planned.push(plan.map_err(|e| e.in_surface(first + i))?);
        }
        for ((table, sampling), plan) in surfaces.into_iter().zip(planned) {
            self.append(table, sampling, plan);
        }
        Ok(())
    }

    /// What [`SurfaceJob::push`] checks before it plans.
    fn check(&self, table: &PatchTable, sampling: &SurfaceSampling) -> Result<(), InputError> {
        if self.normals && table.dim() != 3 {
            return Err(InputError::field(
                "normals",
                format!("need 3-D points, got {} coordinates per point", table.dim()),
            ));
        }
        self.check_fits(table, sampling)
    }

    /// Appends a planned surface and its place in the layout.
    fn append(&mut self, table: PatchTable, sampling: SurfaceSampling, plan: SurfacePlan) {
        let (vertices, triangles) = (plan.vertices.len(), plan.triangles.as_ref().map(Vec::len));
        let keep = self.kept.saturating_add(vertices) <= self.keep_vertices;
        if keep {
            self.kept += vertices;
        }
        let last = |offsets: &[u64]| *offsets.last().expect("offsets start at 0");
        self.vertex_offsets
            .push(last(&self.vertex_offsets) + vertices as u64);
        self.triangle_offsets
            .push(last(&self.triangle_offsets) + triangles.unwrap_or(0) as u64);
        self.surfaces.push(JobSurface {
            table,
            sampling,
            vertices,
            triangles,
            plan: keep.then_some(plan),
        });
    }

    /// Refuses, before its plan is made, a surface whose plan (40 bytes a vertex) and f64
    /// values would not fit in the memory available: a count near the u32 vertex cap would
    /// otherwise end in an allocation failure.
    fn check_fits(&self, table: &PatchTable, sampling: &SurfaceSampling) -> Result<(), InputError> {
        let Some(vertices) = SurfacePlan::vertex_count(table, sampling) else {
            return Ok(());
        };
        let Some(available) = *self.available.get_or_init(memory::available_memory) else {
            return Ok(());
        };
        let planes = 1 + [0, 2, 5][self.derivatives.order()];
        let per_vertex = 40 + 8 * (2 + planes * table.dim() as u128 + 3 * u128::from(self.normals));
        let bytes = u128::from(vertices) * per_vertex;
        if bytes > u128::from(available) {
            return Err(InputError::field(
                "sampling",
                format!(
                    "gives {vertices} vertices, whose plan and values need {bytes} bytes; the \
                     process has {available} bytes of memory available"
                ),
            ));
        }
        Ok(())
    }

    /// The derivatives formed.
    #[must_use]
    pub fn derivatives(&self) -> Derivatives {
        self.derivatives
    }

    /// Whether unit normals are formed (every surface is then 3-D).
    #[must_use]
    pub fn normals(&self) -> bool {
        self.normals
    }

    /// The surfaces, in the order pushed.
    #[must_use]
    pub fn surfaces(&self) -> &[JobSurface] {
        &self.surfaces
    }

    /// Surfaces pushed.
    #[must_use]
    pub fn len(&self) -> usize {
        self.surfaces.len()
    }

    /// Whether no surface has been pushed.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.surfaces.is_empty()
    }

    /// Where each surface's vertices start when all are laid end to end, and the total at the
    /// end (`len() + 1` values).
    #[must_use]
    pub fn vertex_offsets(&self) -> &[u64] {
        &self.vertex_offsets
    }

    /// Where each surface's triangles start, and the total at the end (explicit (u, v) have
    /// none).
    #[must_use]
    pub fn triangle_offsets(&self) -> &[u64] {
        &self.triangle_offsets
    }

    /// Every surface's vertices.
    #[must_use]
    pub fn vertex_count(&self) -> u64 {
        *self.vertex_offsets.last().expect("offsets start at 0")
    }

    /// Every surface's triangles.
    #[must_use]
    pub fn triangle_count(&self) -> u64 {
        *self.triangle_offsets.last().expect("offsets start at 0")
    }

    /// Whether any surface is a patch list (its vertices then carry their patch's index).
    #[must_use]
    pub fn has_patch_lists(&self) -> bool {
        self.surfaces
            .iter()
            .any(|s| s.table.patch_indices().is_some())
    }

    /// Consecutive surfaces of at most `vertices` vertices together (a larger surface alone),
    /// in order, covering the job: units to evaluate and write one at a time.
    #[must_use]
    pub fn groups(&self, vertices: usize) -> Vec<Range<usize>> {
        let mut groups = Vec::new();
        let (mut start, mut held) = (0, 0);
        for (i, surface) in self.surfaces.iter().enumerate() {
            if i > start && held + surface.vertices > vertices {
                groups.push(start..i);
                (start, held) = (i, 0);
            }
            held += surface.vertices;
        }
        groups.push(start..self.surfaces.len());
        groups
    }

    /// Every surface evaluated on the CPU in f64, on every thread.
    #[must_use]
    pub fn evaluate_cpu(&self) -> Vec<SurfaceSamples> {
        self.evaluate_cpu_group(0..self.len())
    }

    /// The surfaces of `range` evaluated on the CPU in f64.
    ///
    /// # Panics
    /// If `range` is not within the job.
    #[must_use]
    pub fn evaluate_cpu_group(&self, range: Range<usize>) -> Vec<SurfaceSamples> {
        self.surfaces[range]
            .iter()
            .map(|s| evaluate_surfaces(&s.table, &s.plan(), self.derivatives, self.normals))
            .collect()
    }

    /// Surface `s` evaluated into a caller's planes (each value formed in f64, rounded to `F`
    /// as it is stored): the planes present are formed, nothing is allocated per vertex.
    ///
    /// # Errors
    /// A plane present that is not the surface's vertex count times `dim` values (normals: 3),
    /// or normals asked of a job that does not form them (field "planes").
    ///
    /// # Panics
    /// If `s` is not a surface of the job.
    pub fn evaluate_into<F: SampleFloat>(
        &self,
        s: usize,
        planes: SurfacePlanes<'_, F>,
    ) -> Result<(), InputError> {
        let surface = &self.surfaces[s];
        let (dim, n) = (surface.table.dim(), surface.vertices);
        if planes.normals.is_some() && !self.normals {
            return Err(InputError::field(
                "planes",
                "hold normals, which this job does not form",
            ));
        }
        for (name, plane, width) in [
            ("points", Some(&planes.points), dim),
            ("du", planes.du.as_ref(), dim),
            ("dv", planes.dv.as_ref(), dim),
            ("duu", planes.duu.as_ref(), dim),
            ("duv", planes.duv.as_ref(), dim),
            ("dvv", planes.dvv.as_ref(), dim),
            ("normals", planes.normals.as_ref(), 3),
        ] {
            if let Some(plane) = plane
                && plane.len() != width * n
            {
                return Err(InputError::field(
                    "planes",
                    format!(
                        "\"{name}\" holds {} values, surface {s}'s {n} vertices {}",
                        plane.len(),
                        width * n
                    ),
                ));
            }
        }
        evaluate_surfaces_into(&surface.table, &surface.plan(), planes);
        Ok(())
    }

    /// The surfaces of `range` with their plans, for the GPU path.
    pub(crate) fn planned(&self, range: Range<usize>) -> Vec<(&PatchTable, Cow<'_, SurfacePlan>)> {
        self.surfaces[range]
            .iter()
            .map(|s| (&s.table, s.plan()))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Net, Surface, SurfaceKind};

    fn bezier(dim: usize) -> PatchTable {
        let net = Net::new(dim, 4, 4, (0..16 * dim).map(|i| i as f64).collect()).unwrap();
        Surface::new(SurfaceKind::Bezier, net).unwrap().fit()
    }

    #[test]
    fn normals_of_a_net_that_is_not_3d_are_refused_when_pushed() {
        let mut job = SurfaceJob::new(Derivatives::None, true);
        let e = job
            .push(bezier(2), SurfaceSampling::PerSegment([2, 2]))
            .unwrap_err();
        assert_eq!(e.field.as_deref(), Some("normals"));
        assert!(e.message.contains("got 2 coordinates"), "{e}");
        assert!(job.is_empty());
        job.push(bezier(3), SurfaceSampling::PerSegment([2, 2]))
            .unwrap();
        assert_eq!(job.len(), 1);
    }

    #[test]
    fn the_layout_lays_the_surfaces_end_to_end() {
        let mut job = SurfaceJob::new(Derivatives::None, false).keeping_plans_up_to(10);
        job.push(bezier(3), SurfaceSampling::PerSegment([2, 2]))
            .unwrap();
        job.push(bezier(3), SurfaceSampling::PerSegment([1, 3]))
            .unwrap();
        job.push(bezier(3), SurfaceSampling::At(vec![[0.5, 0.5]]))
            .unwrap();
        // (k_u + 1)(k_v + 1) vertices and 2 k_u k_v triangles a patch; explicit (u, v) none.
        assert_eq!(job.vertex_offsets(), &[0, 9, 17, 18]);
        assert_eq!(job.triangle_offsets(), &[0, 8, 14, 14]);
        assert_eq!(job.groups(10), vec![0..1, 1..3]);
        // The second plan was not kept (9 + 8 > 10) and is made again, the same.
        assert!(job.surfaces()[1].plan.is_none());
        let again = job.evaluate_cpu_group(1..2);
        assert_eq!(again[0].len(), 8);
    }

    #[test]
    fn planes_of_the_wrong_length_are_refused() {
        let mut job = SurfaceJob::new(Derivatives::None, false);
        job.push(bezier(3), SurfaceSampling::PerSegment([2, 2]))
            .unwrap();
        let mut points = vec![0.0f64; 26];
        let planes = SurfacePlanes {
            points: &mut points,
            du: None,
            dv: None,
            duu: None,
            duv: None,
            dvv: None,
            normals: None,
        };
        let e = job.evaluate_into(0, planes).unwrap_err();
        assert!(e.message.contains("holds 26 values"), "{e}");
    }
}
