//! `GpuContext::evaluate` and its kin: pack a job, upload its tables, dispatch it in batches,
//! read the samples back. [`GpuContext::run`] does it in named steps, each a function below;
//! the buffers come from the context's pool through a [`Lease`] that gives them back on every
//! path out, an error included.

use super::dispatch::{F32, Tables, Target};
use super::pack::{self, Packed};
use crate::error::GpuError;
use crate::gpu::GpuContext;
use crate::gpu::pool::Lease;
use crate::gpu::readback::{map_read, map_write, unpack_device_planes};
use crate::gpu::timing::{DeviceTime, Timestamps, TimingMethod};
use crate::job::EvalJob;
use crate::job::planes::Planes;
use crate::job::samples::{Samples, fill_t};

impl GpuContext {
    /// Evaluates every curve of `job` on the GPU and reads the f32 samples back (t in f64).
    ///
    /// The output is cut into as many dispatches as the device's storage-binding limit needs;
    /// all of them go in one submission.
    ///
    /// # Errors
    /// A value outside the f32 range ([`GpuError::OutOfRange`]), a segment table larger than
    /// one binding ([`GpuError::TooLarge`]), or a device failure ([`GpuError::Device`]).
    pub fn evaluate(&self, job: &EvalJob) -> Result<Samples<f32>, GpuError> {
        let mut samples = Samples::for_job(&EvalJob::new(job.derivatives()));
        self.evaluate_into(job, samples.planes_for(job))?;
        Ok(samples)
    }

    /// [`GpuContext::evaluate`] into a caller's [`Planes`]: t (formed on the host, in f64,
    /// while the device works) when they hold it, the positions and the derivatives the job
    /// asks for. Through [`Samples::planes_for`] a caller evaluating jobs of similar size again
    /// and again allocates nothing and pays no page faults after the first call.
    ///
    /// # Errors
    /// As [`GpuContext::evaluate`].
    ///
    /// # Panics
    /// If a plane's presence or length does not match the job (see [`Planes`]).
    pub fn evaluate_into(&self, job: &EvalJob, planes: Planes<'_, f32>) -> Result<(), GpuError> {
        self.run(job, false, planes)?;
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
        planes: Planes<'_, f32>,
    ) -> Result<DeviceTime, GpuError> {
        let time = self.run(job, true, planes)?;
        // A job without samples dispatches nothing: zero seconds.
        Ok(time.unwrap_or(DeviceTime {
            seconds: 0.0,
            method: TimingMethod::Timestamps,
        }))
    }

    /// Evaluates `job` into `samples` (its planes laid out for it; its t, where it keeps them,
    /// are filled in here, on the host while the device works).
    ///
    /// The steps: pack the job; upload its tables and take its output buffers (from the pool,
    /// through a lease); record and submit its dispatches with their copy-outs; form the t the
    /// host knows while the device works; check the device's error scopes; read the samples
    /// back; form the t of arc-length samples from the places the kernel found.
    fn run(
        &self,
        job: &EvalJob,
        timed: bool,
        planes: Planes<'_, f32>,
    ) -> Result<Option<DeviceTime>, GpuError> {
        let (t, planes) = planes.checked(job);
        if job.layout().values() == 0 {
            fill_t(job, &[], &[], t);
            return Ok(None);
        }
        let packed = self.pack(job)?;
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let mut lease = Lease::new(&self.pool, &self.device);
        let tables = self.upload_tables(&packed, &mut lease)?;
        let outputs = self.output_buffers(&packed, &mut lease);
        let submitted = self.submit(&packed, &tables, &outputs, timed)?;
        // Every t is known on the host unless the kernel places arc-length samples: formed
        // while the device works, except when the device is timed. A CPU adapter's device
        // shares the host's cores, so that work would slow the kernel and be counted in its
        // time (lavapipe: docs/benchmarks.md).
        let t_known = outputs.arc_places.is_none();
        if t_known && !timed {
            fill_t(job, &packed.computed_t, &[], t);
        }
        if let Some(e) = pollster::block_on(out_of_memory.pop()) {
            return Err(GpuError::device(e));
        }
        if let Some(e) = pollster::block_on(validation.pop()) {
            return Err(GpuError::device(e));
        }
        map_read(&self.device, &outputs.download, |bytes| {
            let values = bytemuck::cast_slice(bytes);
            unpack_device_planes(values, job.layout(), outputs.download_stride, planes);
        })?;
        if t_known && timed {
            fill_t(job, &packed.computed_t, &[], t);
        }
        if let Some((arc_places, arc_bytes)) = &outputs.arc_places {
            map_read(&self.device, arc_places, |bytes| {
                let places = bytemuck::cast_slice(&bytes[..*arc_bytes as usize]);
                fill_t(job, &packed.computed_t, places, t);
            })?;
        }
        drop(lease);
        self.keep_packing(packed);
        submitted.device_time(&self.device, &self.queue)
    }

    /// Uploads `packed`'s tables into buffers taken through `lease`: on a CPU adapter written
    /// through their mappings (host memory: no staging buffer for wgpu to allocate and for the
    /// queue to copy from), else by `queue.write_buffer`.
    fn upload_tables(&self, packed: &Packed, lease: &mut Lease<'_>) -> Result<Tables, GpuError> {
        Tables::upload(packed, |role, contents| {
            // COPY_SRC: the places the kernel computes are read back from `locs`.
            let usage = wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC;
            if self.map_output {
                let usage = usage | wgpu::BufferUsages::MAP_WRITE;
                let buffer = lease.take(role, contents.len() as u64, usage);
                map_write(&self.device, &buffer, contents)?;
                Ok(buffer)
            } else {
                let buffer = lease.take(role, contents.len() as u64, usage);
                self.queue.write_buffer(&buffer, 0, contents);
                Ok(buffer)
            }
        })
    }

    /// The buffers the samples go through, taken through `lease`. One output buffer serves
    /// every batch: each batch's copy-out is recorded before the next batch's dispatch, and
    /// wgpu orders the two. Where the context maps output buffers and one batch holds the whole
    /// job, the output buffer is read itself, its planes `plane_stride` apart: no copy into a
    /// download buffer.
    fn output_buffers(&self, packed: &Packed, lease: &mut Lease<'_>) -> Outputs {
        let mapped = self.map_output && packed.batches.len() == 1;
        let (role, read_by) = if mapped {
            ("mapped samples", wgpu::BufferUsages::MAP_READ)
        } else {
            ("samples", wgpu::BufferUsages::COPY_SRC)
        };
        let output = lease.take(
            (role, 0),
            packed.dispatch_output_bytes(),
            wgpu::BufferUsages::STORAGE | read_by,
        );
        let (download, download_stride) = if mapped {
            (output.clone(), packed.plane_stride)
        } else {
            let download = lease.take(
                ("download", 0),
                packed.output_bytes(),
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            );
            (download, packed.device_values)
        };
        // The places of arc-length samples, which the host turns into t.
        let arc_bytes = size_of_val(&packed.locs[packed.arc_locs..]) as u64;
        let arc_places = (arc_bytes > 0).then(|| {
            let buffer = lease.take(
                ("arc places", 0),
                arc_bytes,
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            );
            (buffer, arc_bytes)
        });
        Outputs {
            output,
            mapped,
            download,
            download_stride,
            arc_places,
        }
    }

    /// Records every dispatch of `packed` with its copy-outs (and timestamps, when `timed`
    /// and the device has them) and submits them. Timed without timestamps, each dispatch is
    /// submitted alone and waited for.
    fn submit(
        &self,
        packed: &Packed,
        tables: &Tables,
        outputs: &Outputs,
        timed: bool,
    ) -> Result<Submitted, GpuError> {
        let has_timestamps = (self.device.features()).contains(wgpu::Features::TIMESTAMP_QUERY);
        let stamps =
            (timed && has_timestamps).then(|| Timestamps::new(&self.device, packed.batches.len()));
        let mut waited = 0.0;
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let target = |_: &pack::Batch| Target {
            binding: outputs.output.as_entire_buffer_binding(),
            out_base: 0,
            plane_stride: packed.plane_stride as u32,
        };
        self.encode(
            &mut encoder,
            packed,
            tables,
            target,
            stamps.as_ref(),
            |encoder, b| {
                if timed && stamps.is_none() {
                    waited += self.submit_and_wait(encoder)?;
                }
                if !outputs.mapped {
                    outputs.copy_out(encoder, packed, b);
                }
                Ok(())
            },
        )?;
        if let Some(stamps) = &stamps {
            stamps.resolve(&mut encoder);
        }
        if let Some((arc_places, arc_bytes)) = &outputs.arc_places {
            let from = (packed.arc_locs * size_of::<super::abi::GpuLoc>()) as u64;
            encoder.copy_buffer_to_buffer(&tables.locs, from, arc_places, 0, *arc_bytes);
        }
        self.queue.submit([encoder.finish()]);
        Ok(Submitted {
            timed,
            stamps,
            waited,
        })
    }

    /// Submits what `encoder` holds, replacing it with a new one, and waits for the device:
    /// the seconds from submission to completion.
    fn submit_and_wait(&self, encoder: &mut wgpu::CommandEncoder) -> Result<f64, GpuError> {
        let start = std::time::Instant::now();
        let done = std::mem::replace(
            encoder,
            self.device.create_command_encoder(&Default::default()),
        );
        self.queue.submit([done.finish()]);
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(GpuError::device)?;
        Ok(start.elapsed().as_secs_f64())
    }
}

/// The buffers one evaluation's samples go through (all taken through its lease).
struct Outputs {
    /// What the kernel writes, every batch in turn.
    output: wgpu::Buffer,
    /// Whether `output` is mapped and read itself (then `download` is `output`).
    mapped: bool,
    /// What the host maps and reads: the samples, plane after plane.
    download: wgpu::Buffer,
    /// Floats from one plane to the next in `download`.
    download_stride: usize,
    /// The places the kernel found for arc-length samples, and their bytes.
    arc_places: Option<(wgpu::Buffer, u64)>,
}

impl Outputs {
    /// Records the copy of batch `b`'s planes (its own floats, from its base on) to their
    /// places in the download buffer.
    fn copy_out(&self, encoder: &mut wgpu::CommandEncoder, packed: &Packed, b: usize) {
        let batch = &packed.batches[b];
        let (values, skip) = (&batch.values, (batch.values.start - batch.base) as u64);
        for p in 0..packed.planes as u64 {
            encoder.copy_buffer_to_buffer(
                &self.output,
                (p * packed.plane_stride as u64 + skip) * F32,
                &self.download,
                (p * packed.device_values as u64 + values.start as u64) * F32,
                values.len() as u64 * F32,
            );
        }
    }
}

/// What a submission measured of itself.
struct Submitted {
    timed: bool,
    stamps: Option<Timestamps>,
    /// Seconds waited for dispatches submitted alone (timed, without timestamps).
    waited: f64,
}

impl Submitted {
    /// The device's time, once the submission is done: from the timestamps where there are
    /// some, else the seconds waited; `None` when the evaluation was not timed.
    fn device_time(
        self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<DeviceTime>, GpuError> {
        Ok(match self.stamps {
            Some(stamps) => Some(DeviceTime {
                seconds: stamps.read(device, queue.get_timestamp_period())?,
                method: TimingMethod::Timestamps,
            }),
            None => self.timed.then_some(DeviceTime {
                seconds: self.waited,
                method: TimingMethod::SubmitToCompletion,
            }),
        })
    }
}
