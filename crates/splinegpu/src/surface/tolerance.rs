//! Tolerance sampling of a surface: a certified, watertight triangle mesh (contract:
//! "tolerance tol").
//!
//! # The certificate
//!
//! On a triangle of parameter space with vertices p_i, the flat triangle's point at x is
//! Σ λ_i S(p_i), and by Taylor's theorem about x (Σ λ_i (p_i − x) = 0)
//!
//! ```text
//! |S(x) − Σ λ_i S(p_i)| <= 1/2 Σ λ_i Q(p_i − x),   Q(du, dv) = M_uu du² + 2 M_uv |du dv| + M_vv dv²,
//! ```
//!
//! M_uu, M_uv, M_vv bounds on |S_uu|, |S_uv|, |S_vv| over the patch. On the two triangles of a
//! cell of h_u x h_v the right side is at most Q(h_u, h_v) / 8 (its largest value is at the
//! midpoint of the diagonal), and with 2|du dv| <= du² + dv² that is within tol when
//! h_u² (M_uu + M_uv) <= 4 tol and h_v² (M_vv + M_uv) <= 4 tol: a patch gets
//! n_u = max(1, ceil(sqrt((M_uu + M_uv) / (4 tol)))) cells along u and n_v likewise, the
//! contract's counts (the surface analogue of Wang's formula).
//!
//! # The bounds
//!
//! A polynomial patch's second derivatives are polynomials of bidegree (1, 3), (2, 2) and
//! (3, 1); written in the Bernstein basis their values lie in the convex hull of their
//! coefficients, so the largest coefficient norm bounds the maximum (and is close to it on the
//! smooth patches of a net). A rational patch S = O + Ñ/W bounds R = Ñ/W by its rational Bezier
//! points (Ñ's Bernstein coefficients over W's), W from below by its smallest Bernstein
//! coefficient, and its derivatives through the quotient rule:
//! R_u = (Ñ_u − R W_u) / W, R_uu = (Ñ_uu − 2 R_u W_u − R W_uu) / W, R_uv = (Ñ_uv − R_u W_v −
//! R_v W_u − R W_uv) / W, each term bounded by its Bernstein coefficients.
//!
//! # Graded and watertight
//!
//! Every patch keeps its own counts; an edge shared by patches of different counts along it
//! is meshed once at the larger, and the coarser patch's grid makes the transition to it in a
//! ring of triangles round its inner grid, each spanning at most one of its own cells, so
//! still within tol (module `graded`: the mesh, the proof that it is within the contract's
//! cap of twice Σ 2 n_u n_v, and why it has no T-junctions). Where neighbours agree along
//! every edge the mesh is the welded grid ([`welded`]) or, on a net, one grid.

use crate::error::{InputError, Shown};
use crate::surface::mesh::SurfacePlan;
use crate::surface::patch::{Patch, PatchTable};

/// The most vertices one patch's grid may have (contract: a patch whose (n_u + 1)(n_v + 1)
/// exceeds 2^20 is bad input).
pub const MAX_PATCH_VERTICES: u64 = 1 << 20;

impl SurfacePlan {
    /// The certified mesh of `table` within `tol` (see the module docs).
    ///
    /// # Errors
    /// tol not finite and > 0, or a patch whose own grid would exceed
    /// [`MAX_PATCH_VERTICES`] (naming "sampling", the patch and the count).
    pub fn tolerance(table: &PatchTable, tol: f64) -> Result<Self, InputError> {
        SurfacePlan::from_cells(table, &tolerance_cells(table, tol)?)
    }
}

/// The cells (n_u, n_v) of every patch of the certified mesh of `table` within `tol`, what
/// its plan is made from ([`SurfacePlan::from_cells`]) and its counts are read off
/// ([`cell_counts`](crate::surface::mesh::cell_counts)) without making it.
///
/// # Errors
/// As [`SurfacePlan::tolerance`].
pub(crate) fn tolerance_cells(table: &PatchTable, tol: f64) -> Result<Vec<[u32; 2]>, InputError> {
    if !(tol.is_finite() && tol > 0.0) {
        return Err(InputError::field(
            "tolerance",
            format!("must be a finite number > 0, got {tol}"),
        ));
    }
    (0..table.len())
        .map(|p| {
            let counts = patch_counts(&table.patch(p), tol).map_err(|e| at_patch(e, p))?;
            Ok(counts.map(|k| k as u32))
        })
        .collect()
}

/// The error of patch p's counts.
fn at_patch(mut e: InputError, p: usize) -> InputError {
    e.message = format!("{} (patch {p})", e.message);
    e
}

/// A patch's own counts (n_u, n_v) for `tol`.
///
/// # Errors
/// A grid of more than [`MAX_PATCH_VERTICES`], or bounds that are not finite.
pub(crate) fn patch_counts(patch: &Patch<'_>, tol: f64) -> Result<[usize; 2], InputError> {
    let [m_uu, m_uv, m_vv] = patch.second_derivative_bounds();
    let count = |m: f64| ((m / (4.0 * tol)).sqrt().ceil()).max(1.0);
    let (nu, nv) = (count(m_uu + m_uv), count(m_vv + m_uv));
    let vertices = (nu + 1.0) * (nv + 1.0);
    if vertices.is_nan() || vertices > MAX_PATCH_VERTICES as f64 {
        return Err(InputError::field(
            "sampling",
            format!(
                "needs {} vertices on one patch at this tolerance, more than 2^20 ({} x {} \
                 cells)",
                Shown(vertices),
                Shown(nu),
                Shown(nv)
            ),
        ));
    }
    Ok([nu as usize, nv as usize])
}
