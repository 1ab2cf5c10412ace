//! The library's integration tests, in one binary: the public API as a caller uses it.
//!
//! The GPU-only tests are the `gpu` binary (tests/gpu/); those here that also look at the GPU
//! (geometric samplings) do their CPU checks everywhere and compare with the GPU where wgpu
//! finds an adapter (lavapipe in CI).

mod at;
mod basis;
mod cpu_fast;
mod geometric_sampling;
mod hermite;
mod interpolation;
mod kochanek_bartels;
mod local_beta;
mod nurbs;
mod properties;
mod scipy_fixture;
mod support;
mod surface;
mod surface_gpu;
mod surface_tolerance;
