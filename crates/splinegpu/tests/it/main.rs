//! The library's integration tests, in one binary: the public API as a caller uses it.
//!
//! The GPU tests are the `gpu` binary (tests/gpu/), under a harness that reports them ignored
//! without an adapter; a few tests here (hermite, kochanek-bartels, local beta, nurbs fixtures)
//! do their CPU checks everywhere and add a GPU comparison where wgpu finds an adapter
//! (always under CI=true, where a missing adapter fails them).

mod arc_lengths;
mod at;
mod basis;
mod cpu_fast;
mod geometric_sampling;
mod geometry;
mod hermite;
mod interpolation;
mod job;
mod kochanek_bartels;
mod local_beta;
mod nurbs;
mod properties;
mod query;
mod scipy_fixture;
mod shapes;
mod support;
mod surface;
mod surface_tolerance;
