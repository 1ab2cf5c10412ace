//! Closest points on surfaces and the first hits of rays on the GPU
//! (`shaders/surface_queries.wgsl`): the index packed and uploaded once, the queries in
//! dispatches within the device's limits, each answer's patch and (u, v), found and polished
//! in f32 on the device, finished on the host: the point (and for a ray its distance along it
//! and the unit normal) evaluated in f64 at that (u, v), as [`SurfaceIndex`] finishes its own.

use crate::error::GpuError;
use crate::gpu::GpuContext;
use crate::gpu::kernel::Kernel;
use crate::gpu::queries::abi::{
    ClosestParams, NO_HIT, SURFACE_QUERIES_BINDINGS, SURFACE_QUERIES_WG_SIZE, SURFACE_QUERIES_WGSL,
    SurfaceAnswer,
};
use crate::gpu::queries::device::{DeviceTables, row_width};
use crate::gpu::queries::dispatch::query_budget;
use crate::gpu::queries::pack::PackedNets;
use crate::query::{CheckedRay, QueryError, RayHit, SurfaceIndex, SurfacePoint};
use crate::surface::Derivs;

/// Which entry point of the kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Entry {
    Closest,
    Rays,
}

impl Entry {
    /// The values of one query in the frame.
    pub(crate) fn width(self, dim: usize) -> usize {
        match self {
            Entry::Closest => dim,
            Entry::Rays => RAY_WIDTH,
        }
    }
}

/// A ray in the frame: its origin, then the unit vectors d, a and b (a, b across it).
pub(crate) const RAY_WIDTH: usize = 12;

/// Runs one dispatch over queries in the frame, returning their answers.
pub(crate) type SurfaceDispatch<'a> =
    dyn FnMut(&[f32]) -> Result<Vec<SurfaceAnswer>, GpuError> + 'a;

/// The checked `queries` (D values each) answered by `dispatch` in dispatches of at most
/// `budget`, each answer finished on the host at its patch and (u, v).
pub(crate) fn closest_on_surfaces_with(
    index: &SurfaceIndex<'_>,
    packed: &PackedNets,
    queries: &[f64],
    budget: usize,
    dispatch: &mut SurfaceDispatch<'_>,
) -> Result<Vec<SurfacePoint>, QueryError> {
    let dim = index.dim();
    let mut frame = Vec::new();
    let mut out = Vec::with_capacity(queries.len() / dim);
    let mut derivs = Derivs::default();
    derivs.iter_mut().for_each(|d| d.resize(dim, 0.0));
    for (c, chunk) in queries.chunks(budget * dim).enumerate() {
        packed.tree.frame_points(chunk, &mut frame);
        for (i, answer) in dispatch(&frame)?.iter().enumerate() {
            let item = packed.tree.order[answer.slot as usize] as usize;
            let q = &chunk[i * dim..][..dim];
            let (u, v) = (f64::from(answer.u), f64::from(answer.v));
            let found = index.surface_point(item, u, v, q, &mut derivs);
            if !found.distance.is_finite() {
                return Err(crate::error::InputError::field(
                    format!("closest[{}]", c * budget + i),
                    "lies too far from the surfaces: its squared distance overflows float64",
                )
                .into());
            }
            out.push(found);
        }
    }
    Ok(out)
}

/// The `checked` rays ([`SurfaceIndex::check_rays`]) answered by `dispatch` in dispatches of
/// at most `budget`, each hit finished on the host at its patch and (u, v).
pub(crate) fn ray_hits_with(
    index: &SurfaceIndex<'_>,
    packed: &PackedNets,
    checked: &[CheckedRay],
    budget: usize,
    dispatch: &mut SurfaceDispatch<'_>,
) -> Result<Vec<Option<RayHit>>, QueryError> {
    let mut out = Vec::with_capacity(checked.len());
    let mut derivs = Derivs::default();
    derivs.iter_mut().for_each(|d| d.resize(3, 0.0));
    let (mut frame, mut origin) = (Vec::new(), Vec::new());
    for chunk in checked.chunks(budget) {
        // Each ray as its origin in the frame and its three unit vectors (d, a, b).
        let origins: Vec<f64> = chunk.iter().flat_map(|(o, _)| *o).collect();
        packed.tree.frame_points(&origins, &mut origin);
        frame.clear();
        for (r, (_, [a, b, d])) in chunk.iter().enumerate() {
            frame.extend_from_slice(&origin[3 * r..][..3]);
            for axis in [d, a, b] {
                frame.extend(axis.map(|x| x as f32));
            }
        }
        for (answer, (o, [_, _, d])) in dispatch(&frame)?.iter().zip(chunk) {
            out.push(if answer.slot == NO_HIT {
                None
            } else {
                let item = packed.tree.order[answer.slot as usize] as usize;
                let (u, v) = (f64::from(answer.u), f64::from(answer.v));
                index.ray_hit(item, u, v, o, d, &mut derivs)
            });
        }
    }
    Ok(out)
}

impl GpuContext {
    fn surface_query_pipeline(&self, entry: Entry) -> &Kernel {
        let (cell, name) = match entry {
            Entry::Closest => (&self.surface_closest, "closest"),
            Entry::Rays => (&self.rays, "rays"),
        };
        cell.get_or_init(|| {
            Kernel::with_entry(
                &self.device,
                "surface_queries.wgsl",
                SURFACE_QUERIES_WGSL,
                name,
                &SURFACE_QUERIES_BINDINGS,
            )
        })
    }

    /// [`SurfaceIndex::closest_many`] on the GPU: each query's patch and (u, v) found in f32
    /// by one invocation (docs/queries.md, "On the GPU"), the point and distance evaluated
    /// there in f64 on the host. The distance is within the contract's GPU bound of the true
    /// least distance (the patch's position bound plus 1e-5 (E + |q|∞)).
    ///
    /// ```
    /// use splinegpu::GpuContext;
    /// use splinegpu::query::SurfaceIndex;
    /// use splinegpu::surface::{Net, Surface, SurfaceKind};
    ///
    /// // A flat bicubic patch over [0, 3]² at z = 0 (x = 3u, y = 3v).
    /// let coords = (0..16).flat_map(|ij| [f64::from(ij / 4), f64::from(ij % 4), 0.0]).collect();
    /// let tables = [Surface::new(SurfaceKind::Bezier, Net::new(3, 4, 4, coords)?)?.fit()];
    /// let index = SurfaceIndex::new(&tables)?;
    /// let Ok(gpu) = GpuContext::new() else { return Ok(()) };
    /// let found = gpu.closest_on_surfaces(&index, &[1.0, 2.0, 5.0])?;
    /// assert!((found[0].distance - 5.0).abs() < 1e-4);
    /// let hits = gpu.ray_hits(&index, &[1.0, 2.0, 5.0, 0.0, 0.0, -1.0])?;
    /// assert!((hits[0].as_ref().map(|h| h.s).unwrap() - 5.0).abs() < 1e-4);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`QueryError::Input`] for a point as [`SurfaceIndex::closest_many`] refuses it;
    /// [`QueryError::Gpu`] when the device is lost, the index's tables exceed a storage
    /// binding, or a rational surface's weights differ by more than f32's range.
    pub fn closest_on_surfaces(
        &self,
        index: &SurfaceIndex<'_>,
        queries: &[f64],
    ) -> Result<Vec<SurfacePoint>, QueryError> {
        index.check_queries(queries)?;
        let packed = PackedNets::new(index)?;
        let tables = self.upload_nets(&packed)?;
        let budget = query_budget(self.binding_limit(), index.dim());
        closest_on_surfaces_with(index, &packed, queries, budget, &mut |frame| {
            self.run_surface_queries(Entry::Closest, &packed, &tables, frame)
        })
    }

    /// [`SurfaceIndex::rays_many`] on the GPU: each ray's first patch and (u, v) found in f32
    /// by one invocation, its distance along the ray, point and unit normal evaluated there in
    /// f64 on the host. No hit nearer along the ray by more than the contract's GPU bound is
    /// missed.
    ///
    /// # Errors
    /// [`QueryError::Input`] for a ray as [`SurfaceIndex::rays_many`] refuses it;
    /// [`QueryError::Gpu`] as [`GpuContext::closest_on_surfaces`].
    pub fn ray_hits(
        &self,
        index: &SurfaceIndex<'_>,
        rays: &[f64],
    ) -> Result<Vec<Option<RayHit>>, QueryError> {
        let checked = index.check_rays(rays)?;
        let packed = PackedNets::new(index)?;
        let tables = self.upload_nets(&packed)?;
        let budget = query_budget(self.binding_limit(), RAY_WIDTH);
        ray_hits_with(index, &packed, &checked, budget, &mut |frame| {
            self.run_surface_queries(Entry::Rays, &packed, &tables, frame)
        })
    }

    fn upload_nets(&self, packed: &PackedNets) -> Result<DeviceTables, GpuError> {
        self.upload_query_tables(&[
            ("tree node", bytemuck::cast_slice(&packed.tree.nodes)),
            ("tree box", bytemuck::cast_slice(&packed.tree.node_boxes)),
            ("patch box", bytemuck::cast_slice(&packed.tree.item_boxes)),
            ("patch net", bytemuck::cast_slice(&packed.nets)),
        ])
    }

    /// One dispatch of `entry` over `frame` (D values a closest-point query, [`RAY_WIDTH`] a
    /// ray).
    fn run_surface_queries(
        &self,
        entry: Entry,
        packed: &PackedNets,
        tables: &DeviceTables,
        frame: &[f32],
    ) -> Result<Vec<SurfaceAnswer>, GpuError> {
        let count = frame.len() / entry.width(packed.tree.dim);
        let params = ClosestParams::new(
            count,
            packed.tree.dim,
            row_width(self, count, SURFACE_QUERIES_WG_SIZE),
            packed.tree.nodes.len(),
        );
        let mut answers = vec![SurfaceAnswer::default(); count];
        self.dispatch_queries(
            (
                self.surface_query_pipeline(entry),
                SURFACE_QUERIES_WG_SIZE,
                count,
            ),
            bytemuck::bytes_of(&params),
            tables,
            frame,
            &mut [bytemuck::cast_slice_mut(&mut answers)],
            false,
        )?;
        Ok(answers)
    }
}
