//! Recording a packed job's dispatches: its tables on the device ([`Tables`]), where each
//! dispatch writes ([`Target`]), and one compute pass per dispatch, in which the runs of each
//! mode go to that mode's pipeline.

use std::sync::PoisonError;

use wgpu::util::DeviceExt;

use super::abi::{self, Params, WG_SIZE};
use super::pack::{self, BatchLimits, Packed};
use crate::error::GpuError;
use crate::gpu::GpuContext;
use crate::gpu::timing::Timestamps;
use crate::job::EvalJob;

/// Bytes per f32.
pub(super) const F32: u64 = size_of::<f32>() as u64;

impl GpuContext {
    /// Packs `job` for this context's kernel shape, into a packing kept from an earlier call
    /// when there is one, and checks it against the device's limits. Hand it back with
    /// [`GpuContext::keep_packing`].
    pub(super) fn pack(&self, job: &EvalJob) -> Result<Packed, GpuError> {
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
    pub(super) fn keep_packing(&self, packed: Packed) {
        let mut kept = self.packings.lock().unwrap_or_else(PoisonError::into_inner);
        // As many as calls ran at once; a few at most.
        if kept.len() < 8 {
            kept.push(packed);
        }
    }

    /// Records every dispatch of `packed` into `encoder`, batch `b` writing into
    /// `target(batch)`, and calls `after(encoder, b)` after each.
    pub(super) fn encode<'t>(
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
pub(super) struct Target<'a> {
    pub(super) binding: wgpu::BufferBinding<'a>,
    pub(super) out_base: u32,
    pub(super) plane_stride: u32,
}

/// A packed job's tables on the device.
pub(super) struct Tables {
    segments: wgpu::Buffer,
    coeffs: wgpu::Buffer,
    pub(super) locs: wgpu::Buffer,
    arcs: wgpu::Buffer,
    runs: Vec<wgpu::Buffer>,
}

/// What an empty table binds: a binding is never empty, and must hold at least its
/// `min_binding_size` (the largest is a `Run`'s).
const EMPTY_TABLE: [u8; size_of::<abi::Run>()] = [0; size_of::<abi::Run>()];

impl Tables {
    /// Uploads the tables through `upload(role, bytes)`; an empty table uploads
    /// [`EMPTY_TABLE`].
    pub(super) fn upload(
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
