//! Closest points on curves on the GPU: the index packed once and uploaded once, the queries in
//! dispatches whose every binding fits the device's limits, each dispatch's answers read back
//! and turned into the curves' parameters and points on the host.

use crate::error::GpuError;
use crate::gpu::GpuContext;
use crate::gpu::kernel::Kernel;
use crate::gpu::queries::abi::{
    CLOSEST_BINDINGS, CLOSEST_WG_SIZE, CLOSEST_WGSL, ClosestAnswer, ClosestParams,
};
use crate::gpu::queries::device::row_width;
use crate::gpu::queries::pack::PackedIndex;
#[cfg(feature = "profiling")]
use crate::gpu::timing::{DeviceTime, TimingMethod};
use crate::query::{ClosestPoints, CurveIndex, QueryError};

/// Runs one dispatch of the kernel: the queries (D values each, in the frame), their answers
/// and points (D values each) to fill.
pub(crate) type ClosestDispatch<'a> =
    dyn FnMut(&[f32], &mut [ClosestAnswer], &mut [f32]) -> Result<(), GpuError> + 'a;

impl GpuContext {
    fn closest_pipeline(&self) -> &Kernel {
        self.closest.get_or_init(|| {
            Kernel::new(
                &self.device,
                "closest.wgsl",
                CLOSEST_WGSL,
                &CLOSEST_BINDINGS,
            )
        })
    }

    /// [`CurveIndex::closest_many`] on the GPU: for every point of `queries` (D values each,
    /// flat) the nearest point of the index's curves, found in f32 by one invocation a query
    /// (docs/queries.md, "On the GPU"). The distance is within the contract's GPU bound of the
    /// true least distance (the curve's position bound plus 1e-5 (E + |q|∞)); parameters are
    /// f64, points and distances f32 (the distance from the reported point to the query).
    ///
    /// ```
    /// use splinegpu::{Basis, Curve, CurveKind, Ends, GpuContext, Points, query::CurveIndex};
    ///
    /// let points = Points::new(2, vec![0.0, 0.0, 1.0, 1.0, 2.0, 0.0, 3.0, 1.0])?;
    /// let curve = Curve::new(CurveKind::Uniform { basis: Basis::CatmullRom, ends: Ends::Repeat }, points)?;
    /// let tables = [curve.fit()];
    /// let index = CurveIndex::new(&tables)?;
    /// let Ok(gpu) = GpuContext::new() else { return Ok(()) };
    /// let found = gpu.closest_points(&index, &[1.0, 2.0, 3.0, -1.0])?;
    /// assert_eq!(found.len(), 2);
    /// assert!((found.distance[0] - 1.0).abs() < 1e-4);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`QueryError::Input`] for a point as [`CurveIndex::closest_many`] refuses it;
    /// [`QueryError::Gpu`] when the device is lost, the index's tables exceed a storage
    /// binding, or a rational curve's weights differ by more than f32's range.
    pub fn closest_points(
        &self,
        index: &CurveIndex<'_>,
        queries: &[f64],
    ) -> Result<ClosestPoints<f32>, QueryError> {
        Ok(self.closest_on_device(index, queries, false)?.0)
    }

    /// [`GpuContext::closest_points`], also measuring how long the dispatches ran on the
    /// device (timestamps where the device has them, else submission to completion).
    ///
    /// # Errors
    /// As [`GpuContext::closest_points`].
    #[cfg(feature = "profiling")]
    pub fn closest_points_timed(
        &self,
        index: &CurveIndex<'_>,
        queries: &[f64],
    ) -> Result<(ClosestPoints<f32>, DeviceTime), QueryError> {
        let (found, seconds) = self.closest_on_device(index, queries, true)?;
        let method = TimingMethod::of(&self.device);
        Ok((found, DeviceTime { seconds, method }))
    }

    fn closest_on_device(
        &self,
        index: &CurveIndex<'_>,
        queries: &[f64],
        timed: bool,
    ) -> Result<(ClosestPoints<f32>, f64), QueryError> {
        let count = index.check_queries(queries)?;
        let packed = PackedIndex::new(index)?;
        let tables = self.upload_query_tables(&[
            ("tree node", bytemuck::cast_slice(&packed.tree.nodes)),
            ("tree box", bytemuck::cast_slice(&packed.tree.node_boxes)),
            ("piece box", bytemuck::cast_slice(&packed.tree.item_boxes)),
            (
                "piece control point",
                bytemuck::cast_slice(&packed.controls),
            ),
        ])?;
        let mut seconds = 0.0;
        let found = closest_with(
            index,
            &packed,
            queries,
            count,
            query_budget(self.binding_limit(), packed.tree.dim),
            &mut |frame, answers, points| {
                let params = ClosestParams::new(
                    answers.len(),
                    packed.tree.dim,
                    row_width(self, answers.len(), CLOSEST_WG_SIZE),
                    packed.tree.nodes.len(),
                );
                seconds += self.dispatch_queries(
                    (self.closest_pipeline(), CLOSEST_WG_SIZE, answers.len()),
                    bytemuck::bytes_of(&params),
                    &tables,
                    frame,
                    &mut [
                        bytemuck::cast_slice_mut(answers),
                        bytemuck::cast_slice_mut(points),
                    ],
                    timed,
                )?;
                Ok(())
            },
        )?;
        Ok((found, seconds))
    }
}

/// The most queries of `width` values each (and one 16-byte answer) one dispatch may hold so
/// that its queries and its outputs each fit a binding of `binding` bytes.
pub(crate) fn query_budget(binding: u64, width: usize) -> usize {
    let binding = usize::try_from(binding).unwrap_or(usize::MAX);
    let widest = (4 * width).max(std::mem::size_of::<ClosestAnswer>());
    (binding / widest).clamp(1, 1 << 24)
}

/// The `count` checked `queries` answered by `dispatch` in dispatches of at most `budget`
/// queries, in the order given.
pub(crate) fn closest_with(
    index: &CurveIndex<'_>,
    packed: &PackedIndex,
    queries: &[f64],
    count: usize,
    budget: usize,
    dispatch: &mut ClosestDispatch<'_>,
) -> Result<ClosestPoints<f32>, QueryError> {
    let dim = packed.tree.dim;
    let mut out = ClosestPoints {
        dim,
        curve: Vec::with_capacity(count),
        t: Vec::with_capacity(count),
        points: Vec::with_capacity(count * dim),
        distance: Vec::with_capacity(count),
    };
    let mut frame = Vec::new();
    let mut answers = Vec::new();
    let mut points = Vec::new();
    for (c, chunk) in queries.chunks(budget * dim).enumerate() {
        let n = chunk.len() / dim;
        packed.tree.frame_points(chunk, &mut frame);
        answers.clear();
        answers.resize(n, ClosestAnswer::default());
        points.clear();
        points.resize(n * dim, 0.0);
        dispatch(&frame, &mut answers, &mut points)?;
        packed.push_answers(index, (c * budget, chunk), &answers, &points, &mut out)?;
    }
    Ok(out)
}
