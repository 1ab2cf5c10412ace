//! A job of many surfaces, as [`EvalJob`](crate::EvalJob) is of many curves: each surface's
//! patches, sampling and plan, checked when it is pushed (normals need 3-D points; a plan
//! that would not fit in memory is refused before it is made), with the layout of the whole
//! output: where each surface's vertices and triangles start when the surfaces are laid end
//! to end, triangles numbered over all vertices. The command line's outputs, the Python
//! arrays and the GPU path all read the layout from here.

use std::borrow::Cow;
use std::sync::OnceLock;

use rayon::prelude::*;

use super::chunks::SurfaceChunk;
use super::eval::{SurfacePlanes, SurfaceSamples, evaluate_surfaces, evaluate_surfaces_into};
use super::mesh::{SurfacePlan, SurfaceSampling, cell_counts};
use super::patch::PatchTable;
use super::tolerance::tolerance_cells;
use crate::error::InputError;
use crate::job::Derivatives;
use crate::{SampleFloat, memory};

/// What pushing a surface made: its plan, or (a plan the job will not keep, whose counts
/// follow from the sampling) its counts alone.
enum Planned {
    Plan(SurfacePlan),
    Counted {
        vertices: usize,
        triangles: Option<usize>,
        /// A tolerance plan's cells, what it is made again from (empty otherwise).
        cells: Vec<[u32; 2]>,
    },
}

/// A tolerance sampling's cells on a surface and the counts of the plan they make.
#[derive(Debug)]
struct CountedCells {
    cells: Vec<[u32; 2]>,
    vertices: usize,
    triangles: usize,
}

impl CountedCells {
    /// The cells and counts where `sampling` is a tolerance, else `None`.
    fn of(table: &PatchTable, sampling: &SurfaceSampling) -> Result<Option<Self>, InputError> {
        let SurfaceSampling::Tolerance(tol) = sampling else {
            return Ok(None);
        };
        let cells = tolerance_cells(table, *tol)?;
        let (vertices, triangles) = cell_counts(table, &cells)?;
        Ok(Some(Self {
            cells,
            vertices,
            triangles,
        }))
    }
}

/// One surface of a [`SurfaceJob`]: its patches, its sampling, its plan's sizes, and the plan
/// when the job keeps it.
#[derive(Debug)]
pub struct JobSurface {
    table: PatchTable,
    sampling: SurfaceSampling,
    vertices: usize,
    triangles: Option<usize>,
    plan: Option<SurfacePlan>,
    /// A plan not kept: its cells per patch, from which it is made again without the
    /// tolerance's bounds (empty where the sampling makes it as cheaply).
    cells: Vec<[u32; 2]>,
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
            None if !self.cells.is_empty() => Cow::Owned(
                SurfacePlan::from_cells(&self.table, &self.cells)
                    .expect("the cells of the plan made when the surface was pushed"),
            ),
            None => Cow::Owned(
                SurfacePlan::new(&self.table, &self.sampling)
                    .expect("the same plan was made when the surface was pushed"),
            ),
        }
    }
}

/// Vertices whose per_segment plans a new job keeps: 2^20 (40 MiB of plans). Holding every
/// plan of a large job costs its memory's first touch (about 3 us a 4 KiB page on this
/// project's machines), more than making a grid's plan again while it is in the cache
/// (docs/benchmarks.md).
pub const KEPT_VERTICES: usize = 1 << 20;

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
    /// Whether the bound holds for every plan (`keeping_plans_up_to`), or only for those
    /// counted without one (per_segment on a net, tolerance; a new job's).
    bound_every_plan: bool,
    /// The memory available, read once (at the first surface that needs it).
    available: OnceLock<Option<u64>>,
    /// Whether the caller evaluates the job chunk by chunk ([`SurfaceJob::streamed`]).
    streamed: bool,
}

impl SurfaceJob {
    /// An empty job forming the planes `derivatives` asks for, and unit normals when
    /// `normals` (every surface must then be 3-D). Past its first [`KEPT_VERTICES`] vertices
    /// it counts per_segment nets without planning them and tolerance samplings from their
    /// cells (the patches' bounds; the plans are made while they are evaluated), and keeps
    /// the other plans, whose counts only the plan gives (explicit (u, v), a per_segment
    /// patch list's welding); [`SurfaceJob::keeping_plans_up_to`] bounds them all.
    #[must_use]
    pub fn new(derivatives: Derivatives, normals: bool) -> Self {
        Self {
            derivatives,
            normals,
            surfaces: Vec::new(),
            vertex_offsets: vec![0],
            triangle_offsets: vec![0],
            keep_vertices: KEPT_VERTICES,
            kept: 0,
            bound_every_plan: false,
            available: OnceLock::new(),
            streamed: false,
        }
    }

    /// This job, to be evaluated chunk by chunk ([`SurfaceJob::chunks`]): a surface pushed is
    /// checked against the memory its pieces need, not its whole samples' (a per_segment
    /// net's none past the vertex cap; another sampling's whole plan, 64 bytes a vertex).
    /// Evaluating it whole is still safe: the samples are allocated fallibly.
    #[must_use]
    pub fn streamed(mut self) -> Self {
        self.streamed = true;
        self
    }

    /// This job, keeping the plans (40 bytes a vertex) of the surfaces first pushed up to
    /// `vertices` in all and making the others again when they are evaluated (each then
    /// dropped as soon as its surface is evaluated): memory stays bounded however many
    /// surfaces are pushed, and a plan is touched while it is still in the cache.
    #[must_use]
    pub fn keeping_plans_up_to(mut self, vertices: usize) -> Self {
        self.keep_vertices = vertices;
        self.bound_every_plan = true;
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
        let planned = self.planned_for(&table, &sampling, self.kept, None)?;
        self.append(table, sampling, planned);
        Ok(())
    }

    /// What the job holds of a surface pushed with `kept` vertices' plans kept before it: its
    /// plan where it will be kept or where only the plan gives its counts, else its counts
    /// alone (the plan is made again when it is evaluated).
    fn planned_for(
        &self,
        table: &PatchTable,
        sampling: &SurfaceSampling,
        kept: usize,
        counted: Option<CountedCells>,
    ) -> Result<Planned, InputError> {
        let counted = match counted {
            Some(counted) => Some(counted),
            None => CountedCells::of(table, sampling)?,
        };
        if let Some(CountedCells {
            cells,
            vertices,
            triangles,
        }) = counted
        {
            // The cells give the counts; the plan is made from them where it is kept.
            if kept.saturating_add(vertices) > self.keep_vertices {
                return Ok(Planned::Counted {
                    vertices,
                    triangles: Some(triangles),
                    cells,
                });
            }
            return SurfacePlan::from_cells(table, &cells).map(Planned::Plan);
        }
        if let Some((vertices, triangles)) = SurfacePlan::counts(table, sampling)?
            && kept.saturating_add(vertices) > self.keep_vertices
        {
            return Ok(Planned::Counted {
                vertices,
                triangles: Some(triangles),
                cells: Vec::new(),
            });
        }
        SurfacePlan::new(table, sampling).map(Planned::Plan)
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
        // An upper estimate of the vertices kept before each surface (as if every counted
        // surface's plan were kept), so that planning on every thread never keeps more than
        // the bound allows; `append` keeps within it exactly.
        for (i, (table, sampling)) in surfaces.iter().enumerate() {
            self.check(table, sampling)
                .map_err(|e| e.in_surface(first + i))?;
        }
        // Tolerance surfaces' cells and counts first, on every thread (their bounds: the
        // plans are made from them only where they are kept).
        let counted: Vec<Result<Option<CountedCells>, InputError>> = surfaces
            .par_iter()
            .map(|(table, sampling)| CountedCells::of(table, sampling))
            .collect();
        let mut cells = Vec::with_capacity(counted.len());
        for (i, c) in counted.into_iter().enumerate() {
            cells.push(c.map_err(|e| e.in_surface(first + i))?);
        }
        let mut kept = Vec::with_capacity(surfaces.len());
        let mut before = self.kept;
        for ((table, sampling), cells) in surfaces.iter().zip(&cells) {
            kept.push(before);
            let counted = match cells {
                Some(cells) => Some(cells.vertices as u64),
                None => SurfacePlan::vertex_count(table, sampling),
            };
            before =
                before.saturating_add(usize::try_from(counted.unwrap_or(0)).unwrap_or(usize::MAX));
        }
        let plans: Vec<Result<Planned, InputError>> = surfaces
            .par_iter()
            .zip(kept)
            .zip(cells)
            .map(|(((table, sampling), kept), cells)| {
                self.planned_for(table, sampling, kept, cells)
            })
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

    /// Appends a planned (or counted) surface and its place in the layout.
    fn append(&mut self, table: PatchTable, sampling: SurfaceSampling, planned: Planned) {
        let (vertices, triangles, plan, counted_cells) = match planned {
            Planned::Plan(plan) => (
                plan.vertices.len(),
                plan.triangles.as_ref().map(Vec::len),
                Some(plan),
                Vec::new(),
            ),
            Planned::Counted {
                vertices,
                triangles,
                cells,
            } => (vertices, triangles, None, cells),
        };
        let within = self.kept.saturating_add(vertices) <= self.keep_vertices;
        let keep = plan.is_some() && (within || !self.bound_every_plan);
        if keep {
            self.kept += vertices;
        }
        // A tolerance plan let go keeps its cells: made again from them, it skips the bounds.
        let cells = match (&plan, &sampling) {
            (Some(plan), SurfaceSampling::Tolerance(_)) if !keep => plan.cells.clone(),
            _ => counted_cells,
        };
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
            plan: plan.filter(|_| keep),
            cells,
        });
    }

    /// Refuses, before its plan is made, a surface whose plan (64 bytes a vertex), samples
    /// and f64 values would not fit in the memory available: a count near the u32 vertex cap
    /// would otherwise end in an allocation failure. A streamed job's surface needs its plan
    /// alone whole (a chunk's samples are a bounded part), and a per_segment net's not even
    /// that (its pieces are made line by line).
    fn check_fits(&self, table: &PatchTable, sampling: &SurfaceSampling) -> Result<(), InputError> {
        let Some(vertices) = SurfacePlan::vertex_count(table, sampling) else {
            return Ok(());
        };
        let grid = matches!(sampling, SurfaceSampling::PerSegment(_)) && table.knots().is_some();
        if self.streamed && grid {
            return Ok(());
        }
        let Some(available) = *self.available.get_or_init(memory::available_memory) else {
            return Ok(());
        };
        let planes = 1 + [0, 2, 5][self.derivatives.order()];
        // The plan's vertex (40 bytes) and two triangles (24), the samples' (u, v), their
        // copy of the triangles and their values.
        let values = 8 * (planes * table.dim() as u128 + 3 * u128::from(self.normals));
        let per_vertex = if self.streamed {
            40 + 24
        } else {
            40 + 24 + 16 + 24 + values
        };
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

    /// Every surface evaluated on the CPU in f64, on every thread.
    ///
    /// # Panics
    /// If the memory for the samples cannot be had
    /// ([`SurfaceJob::try_evaluate_cpu_chunk`] says so instead).
    #[must_use]
    pub fn evaluate_cpu(&self) -> Vec<SurfaceSamples> {
        self.try_evaluate_cpu_chunk(&SurfaceChunk::whole(0..self.len()))
            .unwrap_or_else(|e| panic!("{e}"))
    }

    /// Every surface evaluated on the CPU in f64, the job consumed: each surface's plan is
    /// dropped as soon as it is evaluated, so that the samples reuse its memory (a caller who
    /// wants the samples and not the job waits less than for [`SurfaceJob::evaluate_cpu`]).
    #[must_use]
    pub fn into_samples(self) -> Vec<SurfaceSamples> {
        let (derivatives, normals) = (self.derivatives, self.normals);
        self.surfaces
            .into_par_iter()
            .map(|s| {
                let samples = evaluate_surfaces(&s.table, &s.plan(), derivatives, normals)
                    .unwrap_or_else(|e| panic!("the memory for a surface's samples: {e}"));
                drop(s);
                samples
            })
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
        let chunks: Vec<Vec<usize>> = job
            .chunks(10)
            .map(|c| c.parts().iter().map(|p| p.surface()).collect())
            .collect();
        assert_eq!(chunks, [vec![0], vec![1, 2]]);
        // The second plan was not kept (9 + 8 > 10) and is made again, the same.
        assert!(job.surfaces()[1].plan.is_none());
        let second = job.chunks(10).nth(1).unwrap();
        let again = job.try_evaluate_cpu_chunk(&second).unwrap();
        assert_eq!(again[0].len(), 8);
    }

    /// Plans let go are made again bit for bit: per_segment from the sampling, tolerance from
    /// the cells kept (both kinds of table), explicit (u, v) from the sampling.
    #[test]
    fn plans_not_kept_are_made_again_the_same() {
        let list = {
            let net = Net::new(3, 16, 1, (0..48).map(|i| f64::from(i % 11)).collect()).unwrap();
            let patches = vec![std::array::from_fn(|k| k)];
            Surface::new(SurfaceKind::BezierPatches { patches }, net)
                .unwrap()
                .fit()
        };
        // A 2 x 2 patch net with a sharp corner: rows and columns of different counts.
        let sharp = {
            let coords = (0..49)
                .flat_map(|p| {
                    let (i, j) = (p / 7, p % 7);
                    [f64::from(i), f64::from(j), if p == 0 { 40.0 } else { 0.0 }]
                })
                .collect();
            Surface::new(SurfaceKind::Bezier, Net::new(3, 7, 7, coords).unwrap())
                .unwrap()
                .fit()
        };
        let samplings = [
            (bezier(3), SurfaceSampling::PerSegment([3, 2])),
            (sharp, SurfaceSampling::Tolerance(0.05)),
            (bezier(3), SurfaceSampling::Tolerance(0.01)),
            (list, SurfaceSampling::Tolerance(0.02)),
            (
                bezier(3),
                SurfaceSampling::At(vec![[0.25, 0.5], [1.0, 0.0]]),
            ),
        ];
        for (table, sampling) in samplings {
            let want = SurfacePlan::new(&table, &sampling).unwrap();
            let mut job = SurfaceJob::new(Derivatives::None, false).keeping_plans_up_to(0);
            job.push(table, sampling.clone()).unwrap();
            let surface = &job.surfaces()[0];
            assert!(surface.plan.is_none(), "{sampling:?}");
            assert_eq!(*surface.plan(), want, "{sampling:?}");
            assert_eq!(surface.vertices(), want.vertices.len());
            assert_eq!(surface.triangles(), want.triangles.as_ref().map(Vec::len));
        }
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
