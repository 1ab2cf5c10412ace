//! Host-side fits in f64: interpolating splines ([`interp`]), the tridiagonal solvers behind
//! them ([`tridiag`]), and cardinal basis functions for many curves that share their knots
//! ([`cardinal`]).

pub mod cardinal;
pub mod interp;
pub mod tridiag;
