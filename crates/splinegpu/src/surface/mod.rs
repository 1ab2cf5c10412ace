//! Surfaces: the memo's "generalization of splines to surface patches" (contract: "Surfaces").
//!
//! A [`Surface`] is a kind and a net of points, checked once. It is fitted into a
//! [`PatchTable`]: every patch in power form, S(u, v) = Σ_{a,b=0..3} A_ab u^a v^b in the patch's
//! local u, v in [0, 1] (rational patches: a numerator over a denominator). A
//! [`SurfaceSampling`] resolves into a [`SurfacePlan`] (the vertices, each a patch and its local
//! u, v, and the triangles). A [`SurfaceJob`] holds many surfaces' tables and plans, checked
//! as they are pushed, with the layout of their output; it evaluates them in f64 with
//! derivatives and unit normals on the CPU ([`SurfaceJob::evaluate_cpu`]), and
//! [`GpuContext::evaluate_surfaces`](crate::GpuContext::evaluate_surfaces) in f32 on the GPU.
//!
//! - `direction`: each direction's curve rule, and the fit of many net lines by it;
//! - `patch`: the patch table and its evaluation;
//! - `normal`: unit normals, with their limits at collapsed edges and poles;
//! - `mesh`: per-segment grids with shared vertices, patch lists welded along their edges,
//!   explicit (u, v);
//! - `bounds`: proven bounds on a patch's second derivatives (Bernstein hulls);
//! - `tolerance`: certified meshes within a distance, watertight across patches;
//! - `eval`: a plan's vertices evaluated on the CPU;
//! - `kinds`: the kinds by the contract's names, with their fields;
//! - `job`: many surfaces, their plans, checks and output layout ([`SurfaceJob`]);
//! - `chunks`: a job in chunks of bounded size, a large surface cut into pieces, to stream.

pub(crate) mod bounds;
pub(crate) mod chunks;
pub(crate) mod direction;
pub(crate) mod eval;
pub(crate) mod graded;
pub(crate) mod job;
pub(crate) mod kinds;
pub(crate) mod mesh;
pub(crate) mod normal;
pub(crate) mod patch;
pub(crate) mod tolerance;

use crate::basis::Basis;
use crate::curve::Ends;
use crate::error::{InputError, Shown};
use crate::fit::interp::EndCondition;
use crate::points::MAX_DIM;
use direction::Direction;

pub use chunks::{ChunkPart, SurfaceChunk, SurfaceChunks};
pub use eval::{SurfacePlanes, SurfaceSamples};
pub use job::{JobSurface, KEPT_VERTICES, SurfaceJob};
pub use kinds::{
    SURFACE_KINDS, SurfaceFields, not_a_surface_field, not_a_surface_kind, surface_kind_fields,
};
pub use mesh::{SurfacePlan, SurfaceSampling, Vertex};
pub use normal::unit_normal;
pub use patch::{Derivs, Patch, PatchTable};
pub use tolerance::MAX_PATCH_VERTICES;

/// A net of points: `rows` (n_u) rows of `cols` (n_v) points of `dim` coordinates, u along
/// the rows' index and v within a row, stored flat (point (i, j) at `(i * cols + j) * dim`).
/// A patch list's control points are a net of one column.
#[derive(Clone, Debug, PartialEq)]
pub struct Net {
    dim: usize,
    rows: usize,
    cols: usize,
    coords: Vec<f64>,
}

impl Net {
    /// A net from flat coordinates.
    ///
    /// # Errors
    /// `dim` outside 1..=64, no rows or columns, a length that is not rows · cols · dim, or a
    /// coordinate that is not finite (named as `points[i][j][k]`).
    pub fn new(dim: usize, rows: usize, cols: usize, coords: Vec<f64>) -> Result<Self, InputError> {
        if dim == 0 || dim > MAX_DIM {
            return Err(InputError::field(
                "points",
                format!("must have 1 to {MAX_DIM} coordinates per point, got {dim}"),
            ));
        }
        if rows == 0 || cols == 0 || coords.len() != rows * cols * dim {
            return Err(InputError::field(
                "points",
                format!(
                    "must be a net of {rows} x {cols} points of {dim} coordinates ({} values), \
                     got {}",
                    rows * cols * dim,
                    coords.len()
                ),
            ));
        }
        if let Some(i) = coords.iter().position(|v| !v.is_finite()) {
            let (point, k) = (i / dim, i % dim);
            return Err(InputError::field(
                "points",
                format!(
                    "must be finite: points[{}][{}][{k}] = {}",
                    point / cols,
                    point % cols,
                    Shown(coords[i])
                ),
            ));
        }
        Ok(Self {
            dim,
            rows,
            cols,
            coords,
        })
    }

    /// Coordinates per point.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// (n_u, n_v): rows and points per row.
    #[must_use]
    pub fn shape(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// The coordinates, point-major, rows outer.
    #[must_use]
    pub fn coords(&self) -> &[f64] {
        &self.coords
    }

    /// The extent E: the largest per-axis (max − min) over the points.
    #[must_use]
    pub fn extent(&self) -> f64 {
        crate::points::extent(&self.coords, self.dim)
    }
}

/// What a surface is: the contract's surface kinds.
#[derive(Clone, Debug, PartialEq)]
pub enum SurfaceKind {
    /// The tensor product of a uniform family (bspline, catmull-rom, cardinal,
    /// tensioned-bspline, beta, matrix): patch (i, j) is U · M · P_window · Mᵀ · Vᵀ on the 4 x 4
    /// window of the net, windowed in each direction by its ends (`ends[0]` along u).
    Uniform {
        /// The basis matrix, the same in both directions.
        basis: Basis,
        /// The end convention along u and along v.
        ends: [Ends; 2],
    },
    /// Bicubic Bezier patches on a (3k + 1) x (3l + 1) net, sharing their edges.
    Bezier,
    /// A list of bicubic Bezier patches, each 16 indices into the control points (a net of
    /// one column), b_ij at index 4i + j, i along u; each patch spans [0, 1]² (the Utah
    /// teapot's form).
    BezierPatches {
        /// 16 control indices per patch.
        patches: Vec<[usize; 16]>,
    },
    /// The bicubic spline through every point of the net: the 1-D fit with `conditions[0]`
    /// along u, then with `conditions[1]` along v (natural, not-a-knot or periodic).
    Interpolating {
        /// The end condition along u and along v.
        conditions: [EndCondition; 2],
        /// One strictly increasing parameter per row; `None`: 0, 1, ..., n_u − 1.
        u: Option<Vec<f64>>,
        /// One strictly increasing parameter per column; `None`: 0, 1, ..., n_v − 1.
        v: Option<Vec<f64>>,
    },
    /// A cubic B-spline surface on knot vectors, rational with weights:
    /// S = Σ w_ij N_i(u) N_j(v) P_ij / Σ w_ij N_i(u) N_j(v).
    Nurbs {
        /// n_u + 4 knots along u.
        knots_u: Vec<f64>,
        /// n_v + 4 knots along v.
        knots_v: Vec<f64>,
        /// One weight > 0 per point, rows outer; `None`: all 1 (a polynomial surface).
        weights: Option<Vec<f64>>,
    },
}

/// A surface ready to fit: its kind and its net, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    kind: SurfaceKind,
    net: Net,
    /// The rule along u and along v (none for a patch list).
    directions: Option<[Direction; 2]>,
}

impl Surface {
    /// A checked surface.
    ///
    /// # Errors
    /// Too few points along a direction for its rule (or, for a Bezier net, counts that are
    /// not 3k + 1), a basis parameter out of its domain, parameters u or v that are not one
    /// strictly increasing finite value per row or column, a periodic direction whose first and
    /// last lines differ, knot vectors or weights that break the curve rules, or patch indices
    /// out of range; each names its field and value.
    pub fn new(kind: SurfaceKind, net: Net) -> Result<Self, InputError> {
        let (rows, cols) = net.shape();
        let directions = match &kind {
            SurfaceKind::Uniform { basis, ends } => Some([
                Direction::windows(basis, ends[0])?,
                Direction::windows(basis, ends[1])?,
            ]),
            SurfaceKind::Bezier => Some([Direction::Bezier, Direction::Bezier]),
            SurfaceKind::BezierPatches { patches } => {
                check_patches(patches, rows * cols)?;
                None
            }
            SurfaceKind::Interpolating { conditions, u, v } => {
                let mut rules = Vec::new();
                for (axis, (condition, t), n) in [
                    ("u", (&conditions[0], u), rows),
                    ("v", (&conditions[1], v), cols),
                ] {
                    direction::check_condition(condition)?;
                    let t = match t {
                        Some(t) => {
                            direction::check_parameters(t, n, axis)?;
                            t.clone()
                        }
                        None => (0..n).map(|i| i as f64).collect(),
                    };
                    rules.push(Direction::Interpolating {
                        condition: condition.clone(),
                        t,
                    });
                }
                let [along_u, along_v]: [Direction; 2] = rules.try_into().expect("two directions");
                Some([along_u, along_v])
            }
            SurfaceKind::Nurbs {
                knots_u,
                knots_v,
                weights,
            } => {
                for (field, knots, n) in [("knots_u", knots_u, rows), ("knots_v", knots_v, cols)] {
                    crate::fit::nurbs::check(knots, None, n).map_err(|mut e| {
                        if e.field.as_deref() == Some("knots") {
                            e.field = Some(field.to_string());
                            e.message = e.message.replace("knots[", &format!("{field}["));
                        }
                        e
                    })?;
                }
                if let Some(w) = weights {
                    check_weights(w, rows, cols)?;
                }
                Some([
                    Direction::Knots {
                        knots: knots_u.clone(),
                    },
                    Direction::Knots {
                        knots: knots_v.clone(),
                    },
                ])
            }
        };
        if let Some([along_u, along_v]) = &directions {
            along_u.check_lines(rows, "u")?;
            along_v.check_lines(cols, "v")?;
            check_periodic(&net, along_u, along_v)?;
        }
        Ok(Self {
            kind,
            net,
            directions,
        })
    }

    /// The surface's kind.
    #[must_use]
    pub fn kind(&self) -> &SurfaceKind {
        &self.kind
    }

    /// The surface's net.
    #[must_use]
    pub fn net(&self) -> &Net {
        &self.net
    }

    /// The surface's patches in power form, formed in f64 (see [`PatchTable`]).
    #[must_use]
    pub fn fit(&self) -> PatchTable {
        match (&self.kind, &self.directions) {
            (SurfaceKind::BezierPatches { patches }, _) => {
                PatchTable::from_patch_list(&self.net, patches)
            }
            (SurfaceKind::Nurbs { weights, .. }, Some(directions)) => {
                PatchTable::from_directions(&self.net, directions, weights.as_deref())
            }
            (_, Some(directions)) => PatchTable::from_directions(&self.net, directions, None),
            (_, None) => unreachable!("every net kind has its directions"),
        }
    }
}

/// Checks a patch list: 16 indices per patch, each below `points`.
fn check_patches(patches: &[[usize; 16]], points: usize) -> Result<(), InputError> {
    if patches.is_empty() {
        return Err(InputError::field("patches", "must not be empty"));
    }
    for (p, patch) in patches.iter().enumerate() {
        if let Some(k) = patch.iter().position(|&i| i >= points) {
            return Err(InputError::field(
                "patches",
                format!(
                    "must index the {points} points: patches[{p}][{k}] = {}",
                    patch[k]
                ),
            ));
        }
    }
    Ok(())
}

/// Checks a weights net: rows x cols finite values > 0.
fn check_weights(weights: &[f64], rows: usize, cols: usize) -> Result<(), InputError> {
    if weights.len() != rows * cols {
        return Err(InputError::field(
            "weights",
            format!(
                "must be a net of {rows} x {cols} numbers, one per point, got {} values",
                weights.len()
            ),
        ));
    }
    if let Some(i) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(InputError::field(
            "weights",
            format!(
                "must be finite and > 0: weights[{}][{}] = {}",
                i / cols,
                i % cols,
                Shown(weights[i])
            ),
        ));
    }
    Ok(())
}

/// Checks that a periodic direction's first and last lines are equal within 1e-12 of the
/// net's extent.
fn check_periodic(net: &Net, along_u: &Direction, along_v: &Direction) -> Result<(), InputError> {
    let periodic = |d: &Direction| {
        matches!(
            d,
            Direction::Interpolating {
                condition: EndCondition::Periodic,
                ..
            }
        )
    };
    let (rows, cols) = net.shape();
    let dim = net.dim();
    let limit = 1e-12 * net.extent();
    let at = |i: usize, j: usize, k: usize| net.coords[(i * cols + j) * dim + k];
    let mut pairs: Vec<(&str, usize, usize, usize, usize)> = Vec::new();
    if periodic(along_u) {
        pairs.extend((0..cols).map(|j| ("u", 0, j, rows - 1, j)));
    }
    if periodic(along_v) {
        pairs.extend((0..rows).map(|i| ("v", i, 0, i, cols - 1)));
    }
    for (axis, i0, j0, i1, j1) in pairs {
        for k in 0..dim {
            let (a, b) = (at(i0, j0, k), at(i1, j1, k));
            if (a - b).abs() > limit {
                return Err(InputError::field(
                    "points",
                    format!(
                        "must close up along {axis} for a periodic condition: \
                         points[{i1}][{j1}][{k}] = {} differs from points[{i0}][{j0}][{k}] = {}",
                        Shown(b),
                        Shown(a)
                    ),
                ));
            }
        }
    }
    Ok(())
}
