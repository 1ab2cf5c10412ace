//! The context's pool of device buffers, and the lease through which an evaluation borrows
//! them: whatever path the evaluation leaves by (an error included), the lease's `Drop` gives
//! every buffer back.

use std::sync::{Mutex, PoisonError};

/// Device buffers by role, kept between evaluations and grown when a job needs more. Fresh
/// memory is expensive on CPU adapters (lavapipe backs buffers with host pages that fault in
/// on first touch, writing them far slower than touched memory; docs/benchmarks.md). An evaluation
/// takes its buffers out and puts them back when done, so concurrent evaluations on one
/// context never share a buffer.
#[derive(Debug, Default)]
pub(super) struct BufferPool {
    buffers: std::collections::HashMap<(&'static str, usize), wgpu::Buffer>,
}

impl BufferPool {
    /// The pooled buffer for `role` (and index, for per-dispatch buffers) if it holds `size`
    /// bytes, else a new one.
    pub(super) fn take(
        &mut self,
        device: &wgpu::Device,
        role: (&'static str, usize),
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let size = size.next_multiple_of(16);
        match self.buffers.remove(&role) {
            Some(buffer) if buffer.size() >= size => buffer,
            _ => device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(role.0),
                size,
                usage,
                mapped_at_creation: false,
            }),
        }
    }

    /// Returns a buffer taken for `role`, keeping the larger of it and any already there.
    pub(super) fn give(&mut self, role: (&'static str, usize), buffer: wgpu::Buffer) {
        match self.buffers.get(&role) {
            Some(kept) if kept.size() >= buffer.size() => {}
            _ => {
                self.buffers.insert(role, buffer);
            }
        }
    }
}

/// The buffers one evaluation has taken out of a pool; dropping the lease gives them back.
pub(super) struct Lease<'a> {
    pool: &'a Mutex<BufferPool>,
    device: &'a wgpu::Device,
    taken: Vec<((&'static str, usize), wgpu::Buffer)>,
}

impl<'a> Lease<'a> {
    /// A lease on `pool`, whose new buffers `device` makes.
    pub(super) fn new(pool: &'a Mutex<BufferPool>, device: &'a wgpu::Device) -> Self {
        Self {
            pool,
            device,
            taken: Vec::new(),
        }
    }

    /// The pooled buffer for `role` if it holds `size` bytes, else a new one with `usage`;
    /// it goes back to the pool with the lease.
    pub(super) fn take(
        &mut self,
        role: (&'static str, usize),
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let buffer = self
            .pool
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take(self.device, role, size, usage);
        self.taken.push((role, buffer.clone()));
        buffer
    }
}

impl Drop for Lease<'_> {
    fn drop(&mut self) {
        let mut pool = self.pool.lock().unwrap_or_else(PoisonError::into_inner);
        for (role, buffer) in self.taken.drain(..) {
            pool.give(role, buffer);
        }
    }
}
