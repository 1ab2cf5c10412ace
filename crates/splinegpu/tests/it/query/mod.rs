//! Queries against brute force: closest points on adversarial curve sets.

mod closest;
mod intersections;
