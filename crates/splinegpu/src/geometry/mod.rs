//! Geometry: what a renderer draws from a curve, a triangle mesh made at the curve's
//! cross-sections (the contract's "Geometry: strokes, tubes and ribbons").
//!
//! A stage after sampling: the sampling says where the cross-sections lie (per_segment k: the
//! samples' t; arc_length m: m places evenly spaced by the length of the curve's position), the
//! curve's rotation-minimizing frames orient them ([`frames`]), and the meshes are made from
//! the frames ([`mesh`]). A width or radius given per point is one more coordinate of the same
//! spline (the `widen` module), so every curve kind carries it as it carries its points.
//!
//! The counts of a mesh (vertices, triangles) are decided on the host when the curve is pushed
//! into a [`GeometryJob`], before any work: a renderer sizes its buffers from them.
//!
//! Cross-sections per_segment, by arc length, or by a certified tolerance (the
//! `tolerance` module: the mesh within tol of the exact shape); tubes and ribbons are made on
//! the GPU too ([`GpuContext::evaluate_geometry`](crate::GpuContext::evaluate_geometry)).
//!
//! ```
//! use splinegpu::geometry::{Geometry, GeometryJob, Tube, Width};
//! use splinegpu::{Curve, CurveKind, Basis, Ends, Points, Sampling};
//!
//! // A closed Catmull-Rom loop in 3-D as a tube of radius 0.1 and 8 sides.
//! let points = vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.5, -1.0, 0.0, 0.0, 0.0, -1.0, -0.5];
//! let kind = CurveKind::Uniform { basis: Basis::CatmullRom, ends: Ends::Closed };
//! let curve = Curve::new(kind, Points::new(3, points).unwrap()).unwrap();
//! let tube = Geometry::Tube(Tube { radius: Width::Constant(0.1), ..Tube::default() });
//! let mut job = GeometryJob::new();
//! job.push(&curve, &tube, &Sampling::PerSegment(16)).unwrap();
//! // 4 segments of 16 cross-sections each; a closed tube's last ring is its first.
//! assert_eq!(job.vertex_count(), 64 * 8);
//! assert_eq!(job.triangle_count(), 2 * 64 * 8);
//! let meshes = job.evaluate_cpu();
//! assert_eq!(meshes.points.len(), 3 * 64 * 8);
//! ```

mod dash;
pub mod frames;
pub(crate) mod job;
pub mod mesh;
mod plan;
pub(crate) mod stroke;
mod tolerance;
mod widen;

pub use dash::Dash;
pub use job::{GeometryJob, MeshPlanes, Meshes};
pub use plan::MAX_SECTIONS;
pub use stroke::{Cap, Join, Stroke};

/// A width (ribbons, strokes) or radius (tubes): one value for the whole curve, or one per
/// point, interpolated as one more coordinate of the curve's spline (a value below 0 there
/// counts as 0).
#[derive(Clone, Debug, PartialEq)]
pub enum Width {
    /// The same finite value > 0 everywhere.
    Constant(f64),
    /// One finite value > 0 per point of the curve.
    PerPoint(Vec<f64>),
}

impl Default for Width {
    fn default() -> Self {
        Width::Constant(1.0)
    }
}

/// A tube: the surface swept by the circle of radius r(t) about C(t) in the plane
/// perpendicular to the tangent (3-D curves); by default of radius 1, without caps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tube {
    /// The radius r.
    pub radius: Width,
    /// Vertices per ring (>= 3). `None`: the contract's 8 with per_segment or arc_length
    /// cross-sections, the method's choice with tolerance (half the tolerance to the rings'
    /// polygons at the largest radius).
    pub sides: Option<u32>,
    /// The first frame's normal before it is made perpendicular to the first tangent; `None`:
    /// the coordinate axis least aligned with the tangent.
    pub up: Option<[f64; 3]>,
    /// Discs closing an open tube's ends (a vertex at each end and a fan of `sides` triangles).
    pub caps: bool,
    /// A dash pattern: each on interval an open tube of its own (capped with `caps`).
    pub dash: Option<Dash>,
}

/// A ribbon: the strip C(t) + s B(t), |s| <= w(t)/2, facing the rotation-minimizing normal
/// N(t) (3-D curves).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Ribbon {
    /// The width w.
    pub width: Width,
    /// As [`Tube::up`].
    pub up: Option<[f64; 3]>,
    /// A dash pattern: each on interval an open ribbon of its own.
    pub dash: Option<Dash>,
}

/// What to make of a curve.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// A stroke of a 2-D curve (its mesh in the plane z = 0, normals +z).
    Stroke(Stroke),
    /// A tube about the curve.
    Tube(Tube),
    /// A ribbon along the curve.
    Ribbon(Ribbon),
}

impl Geometry {
    /// The contract's key: "tube" or "ribbon".
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Geometry::Stroke(_) => "stroke",
            Geometry::Tube(_) => "tube",
            Geometry::Ribbon(_) => "ribbon",
        }
    }

    /// The width or radius, and the field it is named by.
    pub(crate) fn width(&self) -> (&Width, &'static str) {
        match self {
            Geometry::Stroke(stroke) => (&stroke.width, "width"),
            Geometry::Tube(tube) => (&tube.radius, "radius"),
            Geometry::Ribbon(ribbon) => (&ribbon.width, "width"),
        }
    }

    /// The dash pattern, if any.
    pub(crate) fn dash(&self) -> Option<&Dash> {
        match self {
            Geometry::Stroke(stroke) => stroke.dash.as_ref(),
            Geometry::Tube(tube) => tube.dash.as_ref(),
            Geometry::Ribbon(ribbon) => ribbon.dash.as_ref(),
        }
    }

    /// The first frame's `up`.
    pub(crate) fn up(&self) -> Option<[f64; 3]> {
        match self {
            Geometry::Tube(tube) => tube.up,
            Geometry::Ribbon(ribbon) => ribbon.up,
            Geometry::Stroke(_) => None,
        }
    }
}
