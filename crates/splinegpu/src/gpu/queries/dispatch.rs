//! Closest points on the GPU: the index packed once and uploaded once, the queries in
//! dispatches whose every binding fits the device's limits, each dispatch's answers read back
//! and turned into the curves' parameters and points on the host.

use crate::error::GpuError;
use crate::gpu::GpuContext;
use crate::gpu::kernel::{Kernel, workgroup_grid};
use crate::gpu::queries::abi::{
    CLOSEST_BINDINGS, CLOSEST_WG_SIZE, CLOSEST_WGSL, ClosestAnswer, ClosestParams,
};
use crate::gpu::queries::pack::PackedIndex;
use crate::gpu::timing::Timestamps;
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
    /// ```no_run
    /// use splinegpu::{Basis, Curve, CurveKind, Ends, GpuContext, Points, query::CurveIndex};
    ///
    /// let points = Points::new(2, vec![0.0, 0.0, 1.0, 1.0, 2.0, 0.0, 3.0, 1.0])?;
    /// let curve = Curve::new(CurveKind::Uniform { basis: Basis::CatmullRom, ends: Ends::Repeat }, points)?;
    /// let tables = [curve.fit()];
    /// let index = CurveIndex::new(&tables)?;
    /// let gpu = GpuContext::new()?;
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
        let method = if self
            .device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
        {
            TimingMethod::Timestamps
        } else {
            TimingMethod::SubmitToCompletion
        };
        Ok((found, DeviceTime { seconds, method }))
    }

    fn closest_on_device(
        &self,
        index: &CurveIndex<'_>,
        queries: &[f64],
        timed: bool,
    ) -> Result<(ClosestPoints<f32>, f64), QueryError> {
        use wgpu::util::DeviceExt;
        let count = index.check_queries(queries)?;
        let packed = PackedIndex::new(index)?;
        let limits = self.device.limits();
        let binding = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let device = &self.device;
        let storage = wgpu::BufferUsages::STORAGE;
        let table = |label: &'static str, bytes: &[u8]| -> Result<wgpu::Buffer, GpuError> {
            if bytes.len() as u64 > binding {
                return Err(GpuError::TooLarge {
                    table: label,
                    bytes: bytes.len() as u64,
                    limit: binding,
                });
            }
            Ok(
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytes,
                    usage: storage,
                }),
            )
        };
        let nodes = table("tree node", bytemuck::cast_slice(&packed.nodes))?;
        let node_boxes = table("tree box", bytemuck::cast_slice(&packed.node_boxes))?;
        let item_boxes = table("piece box", bytemuck::cast_slice(&packed.item_boxes))?;
        let controls = table(
            "piece control point",
            bytemuck::cast_slice(&packed.controls),
        )?;
        let has_timestamps = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut seconds = 0.0;
        let found = closest_with(
            index,
            &packed,
            queries,
            count,
            query_budget(binding, packed.dim),
            &mut |frame, answers, points| {
                let pipeline = self.closest_pipeline();
                let (across, rows) = workgroup_grid(device, answers.len() as u32, CLOSEST_WG_SIZE);
                let params = ClosestParams::new(
                    answers.len(),
                    packed.dim,
                    across * CLOSEST_WG_SIZE,
                    packed.nodes.len(),
                );
                let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("closest params"),
                    contents: bytemuck::bytes_of(&params),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let query_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("closest queries"),
                    contents: bytemuck::cast_slice(frame),
                    usage: storage,
                });
                let answer_bytes = std::mem::size_of_val(answers) as u64;
                let point_bytes = (std::mem::size_of_val(points) as u64).max(4);
                let output = |label, size| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size,
                        usage: storage | wgpu::BufferUsages::COPY_SRC,
                        mapped_at_creation: false,
                    })
                };
                let answer_buffer = output("closest answers", answer_bytes);
                let point_buffer = output("closest points", point_bytes);
                let download = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("closest download"),
                    size: answer_bytes + point_bytes,
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                });
                let stamps = (timed && has_timestamps).then(|| Timestamps::new(device, 1));
                let mut encoder = device.create_command_encoder(&Default::default());
                let resources = [
                    &uniform,
                    &nodes,
                    &node_boxes,
                    &item_boxes,
                    &controls,
                    &query_buffer,
                    &answer_buffer,
                    &point_buffer,
                ]
                .iter()
                .map(|b| b.as_entire_binding())
                .collect();
                pipeline.record(
                    device,
                    &mut encoder,
                    "closest",
                    resources,
                    (across, rows),
                    stamps.as_ref().map(|s| s.writes(0)),
                );
                encoder.copy_buffer_to_buffer(&answer_buffer, 0, &download, 0, answer_bytes);
                encoder.copy_buffer_to_buffer(
                    &point_buffer,
                    0,
                    &download,
                    answer_bytes,
                    point_bytes,
                );
                if let Some(stamps) = &stamps {
                    stamps.resolve(&mut encoder);
                }
                let submitted = std::time::Instant::now();
                self.queue.submit([encoder.finish()]);
                crate::gpu::readback::map_read(device, &download, |bytes| {
                    let (a, p) = bytes.split_at(answer_bytes as usize);
                    answers.copy_from_slice(bytemuck::cast_slice(a));
                    points.copy_from_slice(&bytemuck::cast_slice(p)[..points.len()]);
                })?;
                seconds += match (&stamps, timed) {
                    (Some(stamps), _) => stamps.read(device, self.queue.get_timestamp_period())?,
                    (None, true) => submitted.elapsed().as_secs_f64(),
                    (None, false) => 0.0,
                };
                Ok(())
            },
        )?;
        Ok((found, seconds))
    }
}

/// The most queries of `dim` coordinates one dispatch may hold so that its queries, answers
/// and points each fit a binding of `binding` bytes.
pub(crate) fn query_budget(binding: u64, dim: usize) -> usize {
    let binding = usize::try_from(binding).unwrap_or(usize::MAX);
    let widest = (4 * dim).max(std::mem::size_of::<ClosestAnswer>());
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
    let dim = packed.dim;
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
        packed.frame_queries(chunk, &mut frame);
        answers.clear();
        answers.resize(n, ClosestAnswer::default());
        points.clear();
        points.resize(n * dim, 0.0);
        dispatch(&frame, &mut answers, &mut points)?;
        packed.push_answers(index, (c * budget, chunk), &answers, &points, &mut out)?;
    }
    Ok(out)
}
