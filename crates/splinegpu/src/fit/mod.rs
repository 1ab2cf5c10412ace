//! The fit stage, on the host in f64: a [`Curve`](crate::Curve) becomes a
//! [`SegmentTable`](crate::SegmentTable) of cubic segments in power form.
//!
//! - [`uniform`]: the memo's 4x4-matrix families and Bezier curves, M·X per window of four points;
//! - [`interp`]: interpolating splines (natural, clamped, periodic, not-a-knot) on any knots;
//! - [`hermite`] and [`shape`]: cubic Hermite pieces from derivatives at the points, given
//!   ("hermite") or computed (PCHIP, Akima);
//! - [`nurbs`]: cubic B-splines on their own knot vectors, span by span;
//! - [`local_beta`]: Beta-splines with bias and tension per joint, a basis matrix per segment;
//! - [`tcb`]: Kochanek–Bartels splines (tension, continuity, bias), Hermite pieces on windows;
//! - [`cardinal`]: cardinal basis functions, for many curves that share their knots;
//! - [`tridiag`] and [`blocked`]: the O(n) solvers behind them (blocked for the diagonally
//!   dominant systems, on every thread).

pub(crate) mod blocked;
pub(crate) mod cardinal;
pub(crate) mod hermite;
pub(crate) mod interp;
pub(crate) mod local_beta;
pub(crate) mod nurbs;
pub(crate) mod shape;
pub(crate) mod tcb;
pub(crate) mod tridiag;
pub(crate) mod uniform;
