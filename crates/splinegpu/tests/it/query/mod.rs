//! Queries against brute force and closed forms: closest points and intersections of curves,
//! closest points and rays on surfaces.

mod closest;
mod intersections;
mod surfaces;
