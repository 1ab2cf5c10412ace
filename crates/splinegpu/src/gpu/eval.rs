//! `GpuContext::evaluate`: upload a packed job, dispatch it in batches, read the samples back.

use std::sync::{PoisonError, mpsc};

use wgpu::util::DeviceExt;

use super::GpuContext;
use super::abi::{self, Params, WG_SIZE};
use super::pack::{self, BatchLimits, Packed, check_size};
use crate::error::{GpuError, TargetError};
use crate::job::EvalJob;
use crate::job::layout::JobLayout;
use crate::job::samples::Samples;

const F32: u64 = size_of::<f32>() as u64;

/// How long the evaluation dispatches ran on the device.
#[cfg_attr(
    not(feature = "profiling"),
    expect(unreachable_pub, reason = "public through the profiling feature")
)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviceTime {
    /// Seconds, summed over the job's dispatches.
    pub seconds: f64,
    /// How they were measured.
    pub method: TimingMethod,
}

/// How [`DeviceTime`] was measured.
#[cfg_attr(
    not(feature = "profiling"),
    expect(unreachable_pub, reason = "public through the profiling feature")
)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingMethod {
    /// Timestamp queries at the start and end of every compute pass.
    Timestamps,
    /// Wall clock from each dispatch's submission to its completion (adapters without
    /// timestamp queries); includes submission overhead.
    SubmitToCompletion,
}

impl GpuContext {
    /// Evaluates every curve of `job` on the GPU and reads the f32 samples back.
    ///
    /// The output is cut into as many dispatches as the device's storage-binding limit needs;
    /// all of them go in one submission.
    ///
    /// # Errors
    /// A value outside the f32 range ([`GpuError::OutOfRange`]), a segment table larger than
    /// one binding ([`GpuError::TooLarge`]), or a device failure ([`GpuError::Device`]).
    pub fn evaluate(&self, job: &EvalJob) -> Result<Samples<f32>, GpuError> {
        let mut samples = Samples::for_job(&EvalJob::new(job.derivatives()));
        self.evaluate_into(job, &mut samples)?;
        Ok(samples)
    }

    /// [`GpuContext::evaluate`] into `samples`, which is laid out for `job` first, reusing
    /// its memory: a caller evaluating jobs of similar size again and again allocates nothing
    /// and pays no page faults after the first call.
    ///
    /// # Errors
    /// As [`GpuContext::evaluate`].
    pub fn evaluate_into(&self, job: &EvalJob, samples: &mut Samples<f32>) -> Result<(), GpuError> {
        samples.prepare_planes(job);
        self.run(job, false, samples)?;
        Ok(())
    }

    /// Evaluates `job` into a caller's planes, laid out as the job's
    /// [`JobLayout`](crate::JobLayout) lays out host planes (as
    /// [`evaluate_cpu_values_into`](crate::evaluate_cpu_values_into) does): positions in
    /// `planes[0]` and, when the job asks for them, first and second derivatives in `planes[1]`
    /// and `planes[2]` (pass empty slices otherwise). No t is formed: for a consumer that needs
    /// only the values (t is derivable from the job's plans, [`SamplePlan::loc`](crate::SamplePlan::loc)).
    ///
    /// # Errors
    /// As [`GpuContext::evaluate`].
    ///
    /// # Panics
    /// If a plane the job needs is not exactly as long as the job's values.
    pub fn evaluate_values_into(
        &self,
        job: &EvalJob,
        planes: [&mut [f32]; 3],
    ) -> Result<(), GpuError> {
        let (values, order) = (job.layout().values(), job.derivatives().order());
        for (o, plane) in planes.iter().enumerate() {
            let expected = if order >= o { values } else { 0 };
            assert_eq!(plane.len(), expected, "plane {o}: {} values", plane.len());
        }
        let mut planes = Planes {
            layout: job.layout(),
            planes,
        };
        self.run(job, false, &mut planes)?;
        Ok(())
    }

    /// [`GpuContext::evaluate_into`], also measuring how long the dispatches ran on the device:
    /// by timestamp queries where the device has `TIMESTAMP_QUERY`, else by submitting each
    /// dispatch alone and waiting for it.
    ///
    /// # Errors
    /// As [`GpuContext::evaluate`].
    #[cfg(feature = "profiling")]
    pub fn evaluate_timed(
        &self,
        job: &EvalJob,
        samples: &mut Samples<f32>,
    ) -> Result<DeviceTime, GpuError> {
        samples.prepare_planes(job);
        let time = self.run(job, true, samples)?;
        // A job without samples dispatches nothing: zero seconds.
        Ok(time.unwrap_or(DeviceTime {
            seconds: 0.0,
            method: TimingMethod::Timestamps,
        }))
    }

    /// Evaluates `job` into `samples` (its planes laid out for it; its t, where it keeps them,
    /// are filled in here, on the host while the device works).
    fn run(
        &self,
        job: &EvalJob,
        timed: bool,
        samples: &mut impl Destination,
    ) -> Result<Option<DeviceTime>, GpuError> {
        if job.layout().values() == 0 {
            samples.fill_t(job, &[], &[]);
            return Ok(None);
        }
        let packed = self.pack(job)?;
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        // Pooled buffers are taken out for this evaluation and given back at its end.
        let mut pool = self.pool.lock().unwrap_or_else(PoisonError::into_inner);
        let mut taken = Vec::new();
        let mut take = |role: (&'static str, usize), size: u64, usage: wgpu::BufferUsages| {
            let buffer = pool.take(&self.device, role, size, usage);
            taken.push((role, buffer.clone()));
            buffer
        };
        let tables = Tables::upload(&packed, |role, contents| {
            // COPY_SRC: the places the kernel computes are read back from `locs`.
            let usage = wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC;
            if self.map_output {
                // Host memory: written in place, with no staging buffer for wgpu to allocate
                // and for the queue to copy from.
                let usage = usage | wgpu::BufferUsages::MAP_WRITE;
                let buffer = take(role, contents.len() as u64, usage);
                map_write(&self.device, &buffer, contents)?;
                Ok(buffer)
            } else {
                let buffer = take(role, contents.len() as u64, usage);
                self.queue.write_buffer(&buffer, 0, contents);
                Ok(buffer)
            }
        })?;
        // One output buffer, reused by every batch: each batch's copy-out is recorded before
        // the next batch's dispatch, and wgpu orders the two. Where the context maps output
        // buffers and one batch holds the whole job, the output buffer is read itself, its
        // planes `plane_stride` apart: no copy into a download buffer.
        let mapped_output = self.map_output && packed.batches.len() == 1;
        let (role, read_by) = if mapped_output {
            ("mapped samples", wgpu::BufferUsages::MAP_READ)
        } else {
            ("samples", wgpu::BufferUsages::COPY_SRC)
        };
        let output = take(
            (role, 0),
            packed.dispatch_output_bytes(),
            wgpu::BufferUsages::STORAGE | read_by,
        );
        let (download, download_stride) = if mapped_output {
            (output.clone(), packed.plane_stride)
        } else {
            let download = take(
                ("download", 0),
                packed.output_bytes(),
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            );
            (download, packed.device_values)
        };
        // The places of arc-length samples, which the host turns into t.
        let arc_locs = &packed.locs[packed.arc_locs..];
        let arc_bytes = size_of_val(arc_locs) as u64;
        let arc_download = (arc_bytes > 0).then(|| {
            take(
                ("arc places", 0),
                arc_bytes,
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            )
        });
        drop(pool);

        let has_timestamps = self
            .device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY);
        let stamps =
            (timed && has_timestamps).then(|| Timestamps::new(&self.device, packed.batches.len()));
        let mut waited = 0.0;
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let target = |_: &pack::Batch| Target {
            binding: output.as_entire_buffer_binding(),
            out_base: 0,
            plane_stride: packed.plane_stride as u32,
        };
        self.encode(
            &mut encoder,
            &packed,
            &tables,
            target,
            stamps.as_ref(),
            |encoder, b| {
                if timed && stamps.is_none() {
                    // No timestamps: this dispatch goes alone, and we wait for it.
                    let start = std::time::Instant::now();
                    let done = std::mem::replace(
                        encoder,
                        self.device.create_command_encoder(&Default::default()),
                    );
                    self.queue.submit([done.finish()]);
                    self.device
                        .poll(wgpu::PollType::wait_indefinitely())
                        .map_err(|e| GpuError::Device(e.to_string()))?;
                    waited += start.elapsed().as_secs_f64();
                }
                if mapped_output {
                    return Ok(());
                }
                // Plane p of this batch (its own floats, from its base on) lands at plane p's
                // place in the download buffer.
                let batch = &packed.batches[b];
                let (values, skip) = (&batch.values, (batch.values.start - batch.base) as u64);
                for p in 0..packed.planes as u64 {
                    encoder.copy_buffer_to_buffer(
                        &output,
                        (p * packed.plane_stride as u64 + skip) * F32,
                        &download,
                        (p * packed.device_values as u64 + values.start as u64) * F32,
                        values.len() as u64 * F32,
                    );
                }
                Ok(())
            },
        )?;
        if let Some(stamps) = &stamps {
            stamps.resolve(&mut encoder);
        }
        if let Some(arc_download) = &arc_download {
            let from = (packed.arc_locs * size_of::<abi::GpuLoc>()) as u64;
            encoder.copy_buffer_to_buffer(&tables.locs, from, arc_download, 0, arc_bytes);
        }
        self.queue.submit([encoder.finish()]);
        // Every t is known on the host: formed while the device works, except when the
        // device is timed. A CPU adapter's device shares the host's cores, so that work would
        // slow the kernel and be counted in its time (lavapipe, w1: 7-9 ms of t).
        let t_known = arc_download.is_none();
        if t_known && !timed {
            samples.fill_t(job, &packed.computed_t, &[]);
        }
        if let Some(e) = pollster::block_on(out_of_memory.pop()) {
            return Err(GpuError::Device(e.to_string()));
        }
        if let Some(e) = pollster::block_on(validation.pop()) {
            return Err(GpuError::Device(e.to_string()));
        }
        map_read(&self.device, &download, |bytes| {
            let (layout, planes) = samples.layout_and_planes();
            unpack_device_planes(bytemuck::cast_slice(bytes), layout, download_stride, planes);
        })?;
        if t_known && timed {
            samples.fill_t(job, &packed.computed_t, &[]);
        }
        if let Some(arc_download) = &arc_download {
            map_read(&self.device, arc_download, |bytes| {
                let places = bytemuck::cast_slice(&bytes[..arc_bytes as usize]);
                samples.fill_t(job, &packed.computed_t, places);
            })?;
        }
        let mut pool = self.pool.lock().unwrap_or_else(PoisonError::into_inner);
        for (role, buffer) in taken {
            pool.give(role, buffer);
        }
        drop(pool);
        self.keep_packing(packed);
        let time = match stamps {
            Some(stamps) => Some(DeviceTime {
                seconds: stamps.read(&self.device, self.queue.get_timestamp_period())?,
                method: TimingMethod::Timestamps,
            }),
            None => timed.then_some(DeviceTime {
                seconds: waited,
                method: TimingMethod::SubmitToCompletion,
            }),
        };
        Ok(time)
    }

    /// Where [`GpuContext::record_into`] puts `job`'s samples, to size the caller's buffer.
    #[must_use]
    pub fn output_layout(&self, job: &EvalJob) -> OutputLayout {
        OutputLayout::new(job)
    }

    /// Records the evaluation of `job` into the caller's `encoder`, writing the f32 samples
    /// into the caller's `buffer` from byte `offset` on, laid out as [`OutputLayout`] says:
    /// nothing is read back, so a renderer can draw them (as vertices, with `buffer` made with
    /// `STORAGE | VERTEX` usage) in the same submission.
    ///
    /// The job's tables go into buffers of their own that the recorded commands keep alive,
    /// so the call may be repeated before the encoder is submitted.
    ///
    /// # Errors
    /// [`GpuError::Target`] when `buffer` lacks `STORAGE` usage, is too small from `offset`, or
    /// `offset` is not a multiple of the device's `min_storage_buffer_offset_alignment`; the
    /// job's output larger than one storage binding ([`GpuError::TooLarge`]); a value outside
    /// the f32 range ([`GpuError::OutOfRange`]).
    pub fn record_into(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        job: &EvalJob,
        buffer: &wgpu::Buffer,
        offset: u64,
    ) -> Result<OutputLayout, GpuError> {
        let layout = OutputLayout::new(job);
        let limits = self.device.limits();
        check_size(
            "output",
            layout.bytes,
            limits.max_storage_buffer_binding_size,
        )?;
        let alignment = u64::from(limits.min_storage_buffer_offset_alignment);
        if !buffer.usage().contains(wgpu::BufferUsages::STORAGE) {
            return Err(TargetError::MissingStorageUsage.into());
        }
        if !offset.is_multiple_of(alignment) {
            return Err(TargetError::MisalignedOffset { offset, alignment }.into());
        }
        if offset.saturating_add(layout.bytes) > buffer.size() {
            return Err(TargetError::TooSmall {
                available: buffer.size().saturating_sub(offset),
                needed: layout.bytes,
            }
            .into());
        }
        if layout.bytes == 0 {
            return Ok(layout);
        }
        let packed = self.pack(job)?;
        let tables = Tables::upload(&packed, |role, contents| {
            Ok(self
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(role.0),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                }))
        })?;
        let target = |b: &pack::Batch| Target {
            binding: wgpu::BufferBinding {
                buffer,
                offset,
                size: std::num::NonZeroU64::new(layout.bytes),
            },
            out_base: b.base as u32,
            plane_stride: packed.device_values as u32,
        };
        self.encode(encoder, &packed, &tables, target, None, |_, _| Ok(()))?;
        self.keep_packing(packed);
        Ok(layout)
    }

    /// Packs `job` for this context's kernel shape, into a packing kept from an earlier call
    /// when there is one, and checks it against the device's limits. Hand it back with
    /// [`GpuContext::keep_packing`].
    fn pack(&self, job: &EvalJob) -> Result<Packed, GpuError> {
        let limits = self.device.limits();
        let planes = job.derivatives().order() + 1;
        let batch_limits = BatchLimits::for_device(&limits, planes, self.max_dispatch_values);
        let kept = self
            .packings
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .pop();
        let mut packed = kept.unwrap_or_default();
        pack::pack_into(job, self.shape, batch_limits, &mut packed)?;
        packed.check(&limits)?;
        Ok(packed)
    }

    /// Keeps `packed`'s memory for a later call.
    fn keep_packing(&self, packed: Packed) {
        let mut kept = self.packings.lock().unwrap_or_else(PoisonError::into_inner);
        // As many as calls ran at once; a few at most.
        if kept.len() < 8 {
            kept.push(packed);
        }
    }

    /// Records every dispatch of `packed` into `encoder`, batch `b` writing into
    /// `target(batch)`, and calls `after(encoder, b)` after each.
    fn encode<'t>(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        packed: &Packed,
        tables: &Tables,
        target: impl Fn(&pack::Batch) -> Target<'t>,
        stamps: Option<&Timestamps>,
        mut after: impl FnMut(&mut wgpu::CommandEncoder, usize) -> Result<(), GpuError>,
    ) -> Result<(), GpuError> {
        for (b, batch) in packed.batches.iter().enumerate() {
            self.dispatch(encoder, packed, tables, b, &target(batch), stamps);
            after(encoder, b)?;
        }
        Ok(())
    }

    /// Records dispatch `b` of `packed`, writing into `target`: one compute pass, in which
    /// the batch's runs of each mode are dispatched with that mode's pipeline.
    fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        packed: &Packed,
        tables: &Tables,
        b: usize,
        target: &Target<'_>,
        stamps: Option<&Timestamps>,
    ) {
        let batch = &packed.batches[b];
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("eval"),
            timestamp_writes: stamps.map(|s| s.writes(b)),
        });
        for (pipeline, runs) in self.pipelines.iter().zip(&batch.modes) {
            if runs.is_empty() {
                continue;
            }
            let invocations = runs.len() as u64 * u64::from(self.shape.lanes);
            let groups = invocations.div_ceil(u64::from(WG_SIZE)) as u32;
            let groups_x = groups.min(self.device.limits().max_compute_workgroups_per_dimension);
            let groups_y = groups.div_ceil(groups_x);
            let params = Params {
                run_count: runs.len() as u32,
                row_width: groups_x * WG_SIZE,
                plane_stride: target.plane_stride,
                derivatives: (packed.planes - 1) as u32,
                out_base: target.out_base,
                first_run: runs.start as u32,
                _padding: [0; 2],
            };
            let params = self
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("params"),
                    contents: bytemuck::bytes_of(&params),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            let resources = [
                params.as_entire_buffer_binding(),
                tables.segments.as_entire_buffer_binding(),
                tables.coeffs.as_entire_buffer_binding(),
                tables.runs[b].as_entire_buffer_binding(),
                target.binding.clone(),
                tables.locs.as_entire_buffer_binding(),
                tables.coeffs.as_entire_buffer_binding(),
                tables.arcs.as_entire_buffer_binding(),
            ];
            let entries: Vec<_> = (resources.into_iter().enumerate())
                .map(|(i, binding)| wgpu::BindGroupEntry {
                    binding: i as u32,
                    resource: wgpu::BindingResource::Buffer(binding),
                })
                .collect();
            let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("eval"),
                layout: &self.bind_group_layout,
                entries: &entries,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(groups_x, groups_y, 1);
        }
    }
}

/// Where a job's samples go: the output binding, the float where a dispatch's output starts
/// in it, and the floats between planes.
struct Target<'a> {
    binding: wgpu::BufferBinding<'a>,
    out_base: u32,
    plane_stride: u32,
}

/// A packed job's tables on the device.
struct Tables {
    segments: wgpu::Buffer,
    coeffs: wgpu::Buffer,
    locs: wgpu::Buffer,
    arcs: wgpu::Buffer,
    runs: Vec<wgpu::Buffer>,
}

/// What an empty table binds: a binding is never empty, and must hold at least its
/// `min_binding_size` (the largest is a `Run`'s).
const EMPTY_TABLE: [u8; size_of::<abi::Run>()] = [0; size_of::<abi::Run>()];

impl Tables {
    /// Uploads the tables through `upload(role, bytes)`; an empty table uploads
    /// [`EMPTY_TABLE`].
    fn upload(
        packed: &Packed,
        mut upload: impl FnMut((&'static str, usize), &[u8]) -> Result<wgpu::Buffer, GpuError>,
    ) -> Result<Self, GpuError> {
        let mut upload = |role, bytes: &[u8]| {
            upload(
                role,
                if bytes.is_empty() {
                    &EMPTY_TABLE
                } else {
                    bytes
                },
            )
        };
        Ok(Self {
            segments: upload(("segments", 0), bytemuck::cast_slice(&packed.segments))?,
            coeffs: upload(("coeffs", 0), bytemuck::cast_slice(&packed.coeffs))?,
            locs: upload(("locs", 0), bytemuck::cast_slice(&packed.locs))?,
            arcs: upload(("arcs", 0), bytemuck::cast_slice(&packed.arcs))?,
            runs: (packed.batches.iter().enumerate())
                .map(|(b, batch)| {
                    upload(
                        ("runs", b),
                        bytemuck::cast_slice(&packed.runs[batch.runs.clone()]),
                    )
                })
                .collect::<Result<_, _>>()?,
        })
    }
}

/// Where [`GpuContext::record_into`] writes a job's samples, in bytes from its `offset`:
/// positions first (curve c's `counts[c]` samples of `dims[c]` f32 values, tightly packed, from
/// `curve_starts[c]` on; each curve starts 16-byte aligned), then, when the job asks for them,
/// the first derivatives at `plane_bytes` further, and the second at twice that.
///
/// To draw curve c as a line strip of vec`dims[c]` vertices: bind the buffer from
/// `offset + curve_starts[c]` with a stride of `4 * dims[c]` bytes and draw `counts[c]`
/// vertices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputLayout {
    /// Byte offset of each curve's first sample, relative to the write's `offset`.
    pub curve_starts: Vec<u64>,
    /// Samples of each curve.
    pub counts: Vec<u64>,
    /// Coordinates per sample of each curve.
    pub dims: Vec<u32>,
    /// Bytes from one plane to the next (positions, dP/dt, d2P/dt2).
    pub plane_bytes: u64,
    /// Bytes written in all, from `offset` on.
    pub bytes: u64,
}

impl OutputLayout {
    /// The device planes of `job`'s layout, in bytes.
    fn new(job: &EvalJob) -> Self {
        let layout = job.layout();
        let plane_bytes = layout.device_values() as u64 * F32;
        Self {
            curve_starts: (0..job.len())
                .map(|c| layout.device_start(c) as u64 * F32)
                .collect(),
            counts: (0..job.len())
                .map(|c| layout.samples_of(c).len() as u64)
                .collect(),
            dims: (0..job.len()).map(|c| layout.dim(c) as u32).collect(),
            plane_bytes,
            bytes: plane_bytes * (job.derivatives().order() as u64 + 1),
        }
    }
}

/// A timestamp at the start and the end of each dispatch's compute pass.
pub(super) struct Timestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    download: wgpu::Buffer,
    count: u32,
}

impl Timestamps {
    pub(super) fn new(device: &wgpu::Device, dispatches: usize) -> Self {
        let count = 2 * dispatches as u32;
        let bytes = u64::from(count) * size_of::<u64>() as u64;
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("dispatch times"),
                ty: wgpu::QueryType::Timestamp,
                count,
            }),
            resolve: buffer(
                "timestamps",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            download: buffer(
                "timestamps download",
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            ),
            count,
        }
    }

    /// The pass timestamps of dispatch `b`.
    pub(super) fn writes(&self, b: usize) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(2 * b as u32),
            end_of_pass_write_index: Some(2 * b as u32 + 1),
        }
    }

    pub(super) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..self.count, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.download, 0, self.resolve.size());
    }

    /// Seconds between each pass's two timestamps, summed; `period` is nanoseconds per tick.
    pub(super) fn read(&self, device: &wgpu::Device, period: f32) -> Result<f64, GpuError> {
        let ticks: Vec<u64> = map_read(device, &self.download, |bytes| {
            bytemuck::cast_slice(bytes).to_vec()
        })?;
        let total: u64 = ticks
            .chunks_exact(2)
            .map(|t| t[1].saturating_sub(t[0]))
            .sum();
        Ok(total as f64 * f64::from(period) * 1e-9)
    }
}

/// Where [`GpuContext::run`] puts a job's samples: a [`Samples`] (t formed on the host too),
/// or a caller's planes (values only).
trait Destination {
    /// Forms the t of `job`'s samples, if this destination keeps them (see
    /// `Samples::fill_t_from`).
    fn fill_t(&mut self, job: &EvalJob, tolerance: &[f64], arc_places: &[abi::GpuLoc]);
    /// The host layout and the planes the values go into.
    fn layout_and_planes(&mut self) -> (&JobLayout, [&mut [f32]; 3]);
}

impl Destination for Samples<f32> {
    fn fill_t(&mut self, job: &EvalJob, tolerance: &[f64], arc_places: &[abi::GpuLoc]) {
        self.fill_t_from(job, tolerance, arc_places);
    }

    fn layout_and_planes(&mut self) -> (&JobLayout, [&mut [f32]; 3]) {
        self.layout_and_planes_mut()
    }
}

/// A caller's planes, laid out as `layout` says.
struct Planes<'a> {
    layout: &'a JobLayout,
    planes: [&'a mut [f32]; 3],
}

impl Destination for Planes<'_> {
    fn fill_t(&mut self, _: &EvalJob, _: &[f64], _: &[abi::GpuLoc]) {}

    fn layout_and_planes(&mut self) -> (&JobLayout, [&mut [f32]; 3]) {
        let [p, d1, d2] = &mut self.planes;
        (self.layout, [&mut **p, &mut **d1, &mut **d2])
    }
}

/// Copies every curve's values from planes in the device layout (`values`, plane p from
/// `p · stride` on, each the job layout's `device_values()` long) into `planes`, packed as
/// `layout` says.
pub(crate) fn unpack_device_planes(
    values: &[f32],
    layout: &JobLayout,
    stride: usize,
    planes: [&mut [f32]; 3],
) {
    let device_values = layout.device_values();
    for (p, plane) in planes.into_iter().enumerate() {
        if plane.is_empty() {
            continue;
        }
        let device_plane = &values[p * stride..p * stride + device_values];
        // Curves split evenly between the threads, each copying its own.
        layout.per_thread_curves(plane, crate::available_threads(), |curves, part| {
            let Some(first) = curves.clone().next() else {
                return;
            };
            let host_start = layout.values_of(first).start;
            for c in curves {
                let host = layout.values_of(c);
                let at = layout.device_start(c);
                part[host.start - host_start..host.end - host_start]
                    .copy_from_slice(&device_plane[at..at + host.len()]);
            }
        });
    }
}

/// The readback sequence, written once: map the whole buffer for reading, hand the mapped
/// bytes to `read`, drop the view, unmap.
pub(super) fn map_read<T>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    read: impl FnOnce(&[u8]) -> T,
) -> Result<T, GpuError> {
    map_whole(device, buffer, wgpu::MapMode::Read)?;
    let result = {
        let view = buffer
            .get_mapped_range(..)
            .map_err(|e| GpuError::Device(e.to_string()))?;
        read(&view)
    };
    buffer.unmap();
    Ok(result)
}

/// Writes `contents` to the start of `buffer` (with `MAP_WRITE` usage) through a mapping:
/// map the whole buffer for writing, copy, unmap. A large table (w1's 30 MB of coefficients)
/// is split between the threads, each copying its part through a view of its own.
fn map_write(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    contents: &[u8],
) -> Result<(), GpuError> {
    map_whole(device, buffer, wgpu::MapMode::Write)?;
    let threads = if contents.len() < PARALLEL_COPY_BYTES {
        1
    } else {
        crate::available_threads()
    };
    // Parts start on multiples of wgpu::MAP_ALIGNMENT.
    let part = contents
        .len()
        .div_ceil(threads)
        .next_multiple_of(wgpu::MAP_ALIGNMENT as usize);
    let copy = |at: usize, from: &[u8]| -> Result<(), GpuError> {
        let range = at as u64..(at + from.len()) as u64;
        let mut view = buffer
            .get_mapped_range_mut(range)
            .map_err(|e| GpuError::Device(e.to_string()))?;
        view.copy_from_slice(from);
        Ok(())
    };
    let copied = std::thread::scope(|scope| {
        let parts: Vec<_> = (contents.chunks(part).enumerate().skip(1))
            .map(|(i, from)| scope.spawn(move || copy(i * part, from)))
            .collect();
        let first = copy(0, &contents[..part.min(contents.len())]);
        parts
            .into_iter()
            .map(|p| {
                p.join()
                    .unwrap_or_else(|_| Err(GpuError::Device("a copy thread panicked".into())))
            })
            .fold(first, Result::and)
    });
    buffer.unmap();
    copied
}

/// Below this many bytes a table is copied into its mapped buffer on one thread.
const PARALLEL_COPY_BYTES: usize = 1 << 20;

/// map_async on the whole buffer, then polls the device until the callback has run.
fn map_whole(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    mode: wgpu::MapMode,
) -> Result<(), GpuError> {
    let (tx, rx) = mpsc::channel();
    buffer.map_async(mode, .., move |result| {
        // The receiver outlives the poll below; a failed send cannot happen.
        let _ = tx.send(result);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Device(e.to_string()))?;
    rx.recv()
        .map_err(|e| GpuError::Device(e.to_string()))?
        .map_err(|e| GpuError::Device(e.to_string()))
}
