//! The library's integration tests, in one binary: the public API as a caller uses it.
//!
//! GPU tests run on whatever adapter wgpu finds (lavapipe in CI) and compare with the f64
//! reference under the accuracy promise ([`splinegpu::accuracy`]).

mod basis;
mod cpu_fast;
mod geometric_sampling;
mod gpu_vs_cpu;
mod interpolation;
mod properties;
mod render;
mod support;
