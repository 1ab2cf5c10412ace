//! Host-side fits in f64: interpolating splines ([`interp`]), the tridiagonal solvers behind
//! them ([`tridiag`], and [`blocked`] for the dominant ones, on every thread), and cardinal basis functions for many curves that share their knots
//! ([`cardinal`]).

pub mod blocked;
pub mod cardinal;
pub mod interp;
pub mod tridiag;
