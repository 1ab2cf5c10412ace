//! Where a surface is sampled (contract: "Samplings of a surface"): a [`SurfaceSampling`]
//! resolved against a [`PatchTable`] into a [`SurfacePlan`], the vertices (each a patch and its
//! local u, v) and the triangles over them.
//!
//! - Per segment on a net: the grid of all patches together, each vertex once,
//!   (segments_u k_u + 1) x (segments_v k_v + 1) row-major (u outer), a closed direction
//!   without its last line (the cells wrap around). Cell (a, b) gives the triangles
//!   (a, b), (a+1, b), (a+1, b+1) and (a, b), (a+1, b+1), (a, b+1): counter-clockwise in (u, v).
//! - Per segment on a patch list: each patch a k x k grid, its vertices welded with other
//!   patches' along shared edges (the same four control indices, either order) and at shared
//!   corners (the same control index): a vertex is keyed by its corner's index, or by its edge's
//!   indices read in the smaller of the two orders and its place along them, so both patches
//!   find the same vertex (bit-identical by construction: it is evaluated once).
//! - At: the given (u, v), located as curves locate t (an interior knot starts the next
//!   segment; the range's end is the last segment at 1), or a patch list's (p, u, v).

use std::collections::HashMap;
use std::ops::Range;

use crate::error::{InputError, Shown};
use crate::surface::graded::{graded_counts, graded_plan, patch_triangles};
use crate::surface::patch::PatchTable;

/// How a surface is sampled.
#[derive(Clone, Debug, PartialEq)]
pub enum SurfaceSampling {
    /// k_u x k_v cells per patch (a patch list: k x k, the same k both ways).
    PerSegment([u32; 2]),
    /// The given (u, v) of a net, in order; no triangles.
    At(Vec<[f64; 2]>),
    /// The given (patch, u, v) of a patch list, in order; no triangles.
    AtPatches(Vec<(usize, [f64; 2])>),
    /// A certified, watertight mesh within this distance of the surface (see
    /// [`SurfacePlan::tolerance`]).
    Tolerance(f64),
}

/// One vertex: the patch it is evaluated on, its local (u, v) in [0, 1]², and its (u, v) in the
/// surface's parameters (a patch list's: the local ones).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// The patch (a net's row-major, u outer; a patch list's index).
    pub patch: u32,
    /// Local (u, v) on the patch.
    pub local: [f64; 2],
    /// (u, v) in the surface's parameters.
    pub uv: [f64; 2],
}

/// A surface's vertices and triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfacePlan {
    /// The vertices, in the output's order.
    pub vertices: Vec<Vertex>,
    /// Three vertex indices per triangle, counter-clockwise in (u, v); `None` for explicit
    /// (u, v).
    pub triangles: Option<Vec<[u32; 3]>>,
    /// Per patch, the cells (k_u, k_v) of its grid. Where neighbouring patches agree on the
    /// count along every shared edge (per_segment's one k), a patch list's patch p owns the
    /// next 2 k_u k_v triangles, cell by cell (u outer), and a net's grid is of all patches
    /// together; otherwise (a tolerance mesh graded patch by patch, [`crate::surface`]'s
    /// `graded`) each patch's triangles follow the patch before's, its grid making the
    /// transition to edges counted at the finer neighbour's
    /// ([`SurfacePlan::patch_triangles`] says which are whose). Empty for explicit (u, v).
    pub cells: Vec<[u32; 2]>,
}

/// The most vertices one surface may have: indices are u32 on every path.
const MAX_VERTICES: u64 = u32::MAX as u64;

impl SurfacePlan {
    /// The plan of `sampling` on `table`.
    ///
    /// # Errors
    /// A sampling that does not fit the surface (a pair of counts or explicit (u, v) on a patch
    /// list, triples on a net), a count of 0, (u, v) outside the range or a patch out of the
    /// list, or more vertices than u32 indices reach; each names "sampling" and the value.
    pub fn new(table: &PatchTable, sampling: &SurfaceSampling) -> Result<Self, InputError> {
        match (sampling, table.knots()) {
            (SurfaceSampling::Tolerance(tol), _) => SurfacePlan::tolerance(table, *tol),
            (SurfaceSampling::PerSegment(k), Some(knots)) => {
                check_per_segment(*k)?;
                let ku = vec![k[0] as usize; knots[0].len() - 1];
                let kv = vec![k[1] as usize; knots[1].len() - 1];
                grid(knots, table.closed(), [&ku, &kv])
            }
            (SurfaceSampling::PerSegment([k, l]), None) => {
                if k != l {
                    return Err(InputError::field(
                        "sampling",
                        format!("per_segment of a patch list takes one k, got [{k}, {l}]"),
                    ));
                }
                if *k == 0 {
                    return Err(InputError::field(
                        "sampling",
                        "per_segment count must be >= 1, got 0",
                    ));
                }
                let patches = table.patch_indices().expect("a patch list");
                welded(patches, &vec![[*k as usize; 2]; patches.len()])
            }
            (SurfaceSampling::At(at), Some(knots)) => explicit(knots, at),
            (SurfaceSampling::AtPatches(at), None) => on_patches(table.len(), at),
            (SurfaceSampling::At(_), None) => Err(InputError::field(
                "sampling",
                "\"at\" on a patch list takes triples [p, u, v]",
            )),
            (SurfaceSampling::AtPatches(_), Some(_)) => Err(InputError::field(
                "sampling",
                "\"at\" on a net takes pairs [u, v]",
            )),
        }
    }
}

impl SurfacePlan {
    /// The grid plan whose `cells` (per patch, as [`SurfacePlan::cells`] holds them) are
    /// given, made again without the counts' bounds: a net's grid or a patch list's welded
    /// grids, bit for bit the plan those cells came from.
    ///
    /// # Errors
    /// Cells that are not one per patch, or a grid past u32 indices.
    pub fn from_cells(table: &PatchTable, cells: &[[u32; 2]]) -> Result<Self, InputError> {
        Self::check_cells(table, cells)?;
        let cells: Vec<[usize; 2]> = cells.iter().map(|c| c.map(|k| k as usize)).collect();
        if let Some(plan) = graded_plan(table, &cells) {
            return plan;
        }
        match (table.knots(), table.patch_indices()) {
            (Some(knots), _) => {
                let across = knots[1].len() - 1;
                let ku: Vec<usize> = cells.iter().step_by(across).map(|c| c[0]).collect();
                let kv: Vec<usize> = cells[..across].iter().map(|c| c[1]).collect();
                grid(knots, table.closed(), [&ku, &kv])
            }
            (None, Some(patches)) => welded(patches, &cells),
            (None, None) => unreachable!("a table is a net or a patch list"),
        }
    }

    /// A patch list's triangles of this plan, each with its patch and its corners' local
    /// (u, v) there, in the order of [`SurfacePlan::triangles`] (a vertex on an edge keeps
    /// one patch's local (u, v); a texture per patch needs each triangle's own); `None` on a
    /// net (its vertices' (u, v) are the surface's own) or without triangles.
    #[must_use]
    pub fn patch_triangles(&self, table: &PatchTable) -> Option<Vec<(u32, [[f64; 2]; 3])>> {
        if table.knots().is_some() || self.triangles.is_none() {
            return None;
        }
        let cells: Vec<[usize; 2]> = self.cells.iter().map(|c| c.map(|k| k as usize)).collect();
        Some(patch_triangles(table, &cells))
    }

    /// Refuses cells that are not one per patch.
    fn check_cells(table: &PatchTable, cells: &[[u32; 2]]) -> Result<(), InputError> {
        if cells.len() != table.len() {
            return Err(InputError::field(
                "cells",
                format!(
                    "must be one per patch ({}), got {}",
                    table.len(),
                    cells.len()
                ),
            ));
        }
        Ok(())
    }
}

/// Refuses a per_segment count of 0 on a net.
fn check_per_segment(k: [u32; 2]) -> Result<(), InputError> {
    if k.contains(&0) {
        return Err(InputError::field(
            "sampling",
            format!("per_segment counts must be >= 1, got [{}, {}]", k[0], k[1]),
        ));
    }
    Ok(())
}

impl SurfacePlan {
    /// The vertices and triangles of the plan [`SurfacePlan::new`] would make, with its
    /// checks, where they follow from the sampling alone (per_segment on a net: a grid of
    /// (Σ k_u + open) x (Σ k_v + open) vertices and 2 · Σ k_u · Σ k_v triangles); `None` where
    /// only the plan says (a welded patch list, explicit (u, v), a tolerance).
    ///
    /// # Errors
    /// As [`SurfacePlan::new`] for the samplings it counts.
    pub fn counts(
        table: &PatchTable,
        sampling: &SurfaceSampling,
    ) -> Result<Option<(usize, usize)>, InputError> {
        let (SurfaceSampling::PerSegment(k), Some(knots)) = (sampling, table.knots()) else {
            return Ok(None);
        };
        check_per_segment(*k)?;
        let closed = table.closed();
        let cells = [0, 1].map(|d| (knots[d].len() - 1) as u64 * u64::from(k[d]));
        let lines = [0, 1].map(|d| cells[d] + u64::from(!closed[d]));
        check_count(lines[0].saturating_mul(lines[1]))?;
        Ok(Some((
            (lines[0] * lines[1]) as usize,
            (2 * cells[0] * cells[1]) as usize,
        )))
    }

    /// The vertices `sampling` gives on `table`, counted without making the plan (a patch
    /// list's welded grids: their bound, each patch's grid whole); None for a tolerance
    /// sampling, whose counts come from the patches' bounds as the plan is made. What a
    /// caller checks against the memory it has before asking for a plan of billions.
    #[must_use]
    pub fn vertex_count(table: &PatchTable, sampling: &SurfaceSampling) -> Option<u64> {
        match (sampling, table.knots()) {
            (SurfaceSampling::PerSegment([ku, kv]), Some([u, v])) => Some(
                ((u.len() as u64 - 1) * u64::from(*ku) + 1)
                    .saturating_mul((v.len() as u64 - 1) * u64::from(*kv) + 1),
            ),
            (SurfaceSampling::PerSegment([k, _]), None) => {
                Some((table.len() as u64).saturating_mul((u64::from(*k) + 1).saturating_pow(2)))
            }
            (SurfaceSampling::At(at), _) => Some(at.len() as u64),
            (SurfaceSampling::AtPatches(at), _) => Some(at.len() as u64),
            (SurfaceSampling::Tolerance(_), _) => None,
        }
    }
}

/// One direction's lines of a grid with `ks[i]` cells on segment i: (segment, local, parameter)
/// for each line, a closed direction without its last line.
fn lines(knots: &[f64], closed: bool, ks: &[usize]) -> Vec<(usize, f64, f64)> {
    let segments = knots.len() - 1;
    let mut out = Vec::with_capacity(ks.iter().sum::<usize>() + 1);
    for (i, &k) in ks.iter().enumerate() {
        for j in 0..k {
            let local = j as f64 / k as f64;
            out.push((i, local, knots[i] + local * (knots[i + 1] - knots[i])));
        }
    }
    if !closed {
        out.push((segments - 1, 1.0, knots[segments]));
    }
    out
}

/// Refuses a mesh of more vertices than u32 indices reach.
pub(crate) fn check_count(vertices: u64) -> Result<(), InputError> {
    if vertices > MAX_VERTICES {
        return Err(InputError::field(
            "sampling",
            format!("gives {vertices} vertices, more than the {MAX_VERTICES} one surface may have"),
        ));
    }
    Ok(())
}

/// A net's grid: `ks[0][i]` cells along u on every patch of row i, `ks[1][j]` along v on every
/// patch of column j; the patches' cells are (ks[0][i], ks[1][j]).
pub(crate) fn grid(
    knots: [&[f64]; 2],
    closed: [bool; 2],
    ks: [&[usize]; 2],
) -> Result<SurfacePlan, InputError> {
    let count = |d: usize| (ks[d].iter().sum::<usize>() + usize::from(!closed[d])) as u64;
    check_count(count(0).saturating_mul(count(1)))?;
    let rows = count(0) as usize;
    let cells_u = ks[0].iter().sum();
    let mut plan = grid_part(knots, closed, ks, 0..rows, 0..cells_u);
    plan.cells = ks[0]
        .iter()
        .flat_map(|&ku| ks[1].iter().map(move |&kv| [ku as u32, kv as u32]))
        .collect();
    Ok(plan)
}

/// Part of a net's grid ([`grid`]'s, whose counts the caller has checked): the vertices of the
/// lines along u in `lines` and the triangles of the rows of cells in `cell_rows`, numbered
/// over the whole grid (a line holds the grid's (Σ k_v + open) vertices; a row of cells its
/// 2 Σ k_v triangles); no cells.
pub(crate) fn grid_part(
    knots: [&[f64]; 2],
    closed: [bool; 2],
    ks: [&[usize]; 2],
    lines_u: Range<usize>,
    cell_rows: Range<usize>,
) -> SurfacePlan {
    let along_u = lines(knots[0], closed[0], ks[0]);
    let along_v = lines(knots[1], closed[1], ks[1]);
    let across = knots[1].len() - 1;
    let (rows, cols) = (along_u.len(), along_v.len());
    let mut vertices = Vec::with_capacity(lines_u.len() * cols);
    for &(iu, lu, u) in &along_u[lines_u] {
        for &(iv, lv, v) in &along_v {
            vertices.push(Vertex {
                patch: (iu * across + iv) as u32,
                local: [lu, lv],
                uv: [u, v],
            });
        }
    }
    let cells_v: usize = ks[1].iter().sum();
    let index = |a: usize, b: usize| ((a % rows) * cols + (b % cols)) as u32;
    let mut triangles = Vec::with_capacity(2 * cell_rows.len() * cells_v);
    for a in cell_rows {
        for b in 0..cells_v {
            push_cell(&mut triangles, a, b, index);
        }
    }
    SurfacePlan {
        vertices,
        triangles: Some(triangles),
        cells: Vec::new(),
    }
}

/// Cell (a, b)'s two triangles, counter-clockwise in (u, v): (a, b), (a+1, b), (a+1, b+1) and
/// (a, b), (a+1, b+1), (a, b+1), `index` giving each corner's vertex.
fn push_cell(
    triangles: &mut Vec<[u32; 3]>,
    a: usize,
    b: usize,
    index: impl Fn(usize, usize) -> u32,
) {
    let (p, q, r, s) = (
        index(a, b),
        index(a + 1, b),
        index(a + 1, b + 1),
        index(a, b + 1),
    );
    triangles.push([p, q, r]);
    triangles.push([p, r, s]);
}

/// Where a patch-list vertex is shared: a corner's control index, or an edge's four indices
/// (in the smaller order) and the place along them.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
enum Weld {
    Corner(usize),
    Edge([usize; 4], usize),
}

/// The weld key of vertex (a, b) of a k_u x k_v patch with `controls`, if it lies on the
/// boundary.
fn weld_key(controls: &[usize; 16], [ku, kv]: [usize; 2], a: usize, b: usize) -> Option<Weld> {
    let (on_u, on_v) = (a == 0 || a == ku, b == 0 || b == kv);
    let (i, j) = (if a == 0 { 0 } else { 3 }, if b == 0 { 0 } else { 3 });
    match (on_u, on_v) {
        (true, true) => Some(Weld::Corner(controls[4 * i + j])),
        (true, false) => Some(edge([0, 1, 2, 3].map(|j| controls[4 * i + j]), b, kv)),
        (false, true) => Some(edge([0, 1, 2, 3].map(|i| controls[4 * i + j]), a, ku)),
        (false, false) => None,
    }
}

/// An edge's key: its indices read in the smaller of the two orders, the place along them
/// counted the same way.
fn edge(indices: [usize; 4], place: usize, k: usize) -> Weld {
    let mut reversed = indices;
    reversed.reverse();
    if reversed < indices {
        Weld::Edge(reversed, k - place)
    } else {
        Weld::Edge(indices, place)
    }
}

/// The vertex and triangle counts of the plan [`SurfacePlan::from_cells`] makes of `cells`,
/// read off them: a graded mesh's as it counts them; a net's grid's (Σ k_u + open) x
/// (Σ k_v + open) vertices, a patch list's interior vertices (k_u - 1)(k_v - 1) a patch and
/// one for each distinct boundary place (its weld key, as [`welded`] shares them); 2 k_u k_v
/// triangles a patch.
///
/// # Errors
/// More vertices than one surface may have.
pub(crate) fn cell_counts(
    table: &PatchTable,
    cells: &[[u32; 2]],
) -> Result<(usize, usize), InputError> {
    let cells: Vec<[usize; 2]> = cells.iter().map(|c| c.map(|k| k as usize)).collect();
    if let Some((vertices, triangles)) = graded_counts(table, &cells) {
        check_count(vertices)?;
        return Ok((vertices as usize, triangles as usize));
    }
    let triangles = cells.iter().map(|[ku, kv]| 2 * ku * kv).sum();
    let vertices = match (table.knots(), table.patch_indices()) {
        (Some(knots), _) => {
            let across = knots[1].len() - 1;
            let closed = table.closed();
            let ku: usize = cells.iter().step_by(across).map(|c| c[0]).sum();
            let kv: usize = cells[..across].iter().map(|c| c[1]).sum();
            ((ku + usize::from(!closed[0])) as u64)
                .saturating_mul((kv + usize::from(!closed[1])) as u64)
        }
        (None, Some(patches)) => {
            let mut boundary = std::collections::HashSet::new();
            let mut interior = 0u64;
            for (controls, &[ku, kv]) in patches.iter().zip(&cells) {
                interior += (ku.saturating_sub(1) * kv.saturating_sub(1)) as u64;
                for a in 0..=ku {
                    let step = if a == 0 || a == ku { 1 } else { kv.max(1) };
                    for b in (0..=kv).step_by(step) {
                        if let Some(key) = weld_key(controls, [ku, kv], a, b) {
                            boundary.insert(key);
                        }
                    }
                }
            }
            interior + boundary.len() as u64
        }
        (None, None) => unreachable!("a table is a net or a patch list"),
    };
    check_count(vertices)?;
    Ok((vertices as usize, triangles))
}

/// A patch list's mesh, patch p a `cells[p]` = (k_u, k_v) grid, welded. Patches that share an
/// edge must have the same count along it (per_segment's one k; the tolerance mesher's counts
/// are made so).
pub(crate) fn welded(
    patches: &[[usize; 16]],
    cells: &[[usize; 2]],
) -> Result<SurfacePlan, InputError> {
    check_count(
        cells
            .iter()
            .map(|[ku, kv]| ((ku + 1) * (kv + 1)) as u64)
            .fold(0u64, u64::saturating_add),
    )?;
    let mut vertices = Vec::new();
    let mut shared: HashMap<Weld, u32> = HashMap::new();
    let mut triangles = Vec::with_capacity(cells.iter().map(|[ku, kv]| 2 * ku * kv).sum());
    let mut local = Vec::new();
    for (p, (controls, &[ku, kv])) in patches.iter().zip(cells).enumerate() {
        local.clear();
        for a in 0..=ku {
            for b in 0..=kv {
                let uv = [a as f64 / ku as f64, b as f64 / kv as f64];
                let mut fresh = || {
                    vertices.push(Vertex {
                        patch: p as u32,
                        local: uv,
                        uv,
                    });
                    (vertices.len() - 1) as u32
                };
                local.push(match weld_key(controls, [ku, kv], a, b) {
                    Some(key) => *shared.entry(key).or_insert_with(fresh),
                    None => fresh(),
                });
            }
        }
        let index = |a: usize, b: usize| local[a * (kv + 1) + b];
        for a in 0..ku {
            for b in 0..kv {
                push_cell(&mut triangles, a, b, index);
            }
        }
    }
    Ok(SurfacePlan {
        vertices,
        triangles: Some(triangles),
        cells: cells
            .iter()
            .map(|&[ku, kv]| [ku as u32, kv as u32])
            .collect(),
    })
}

/// One direction's (segment, local) of parameter t: the segment that starts at an interior
/// knot, the last segment at 1 at the range's end; `None` outside the range.
fn locate(knots: &[f64], t: f64) -> Option<(usize, f64)> {
    let segments = knots.len() - 1;
    if !(knots[0] <= t && t <= knots[segments]) {
        return None;
    }
    let i = knots
        .partition_point(|&k| k <= t)
        .saturating_sub(1)
        .min(segments - 1);
    let local = if t == knots[segments] {
        1.0
    } else {
        (t - knots[i]) / (knots[i + 1] - knots[i])
    };
    Some((i, local))
}

/// Explicit (u, v) on a net.
fn explicit(knots: [&[f64]; 2], at: &[[f64; 2]]) -> Result<SurfacePlan, InputError> {
    let across = knots[1].len() - 1;
    let mut vertices = Vec::with_capacity(at.len());
    for (i, &[u, v]) in at.iter().enumerate() {
        match (locate(knots[0], u), locate(knots[1], v)) {
            (Some((iu, lu)), Some((iv, lv))) => vertices.push(Vertex {
                patch: (iu * across + iv) as u32,
                local: [lu, lv],
                uv: [u, v],
            }),
            _ => {
                return Err(InputError::field(
                    "sampling",
                    format!(
                        "\"at\" values must lie in the surface's range [{}, {}] x [{}, {}]: \
                         at[{i}] = [{}, {}]",
                        Shown(knots[0][0]),
                        Shown(knots[0][knots[0].len() - 1]),
                        Shown(knots[1][0]),
                        Shown(knots[1][across]),
                        Shown(u),
                        Shown(v)
                    ),
                ));
            }
        }
    }
    Ok(SurfacePlan {
        vertices,
        triangles: None,
        cells: Vec::new(),
    })
}

/// Explicit (p, u, v) on a patch list.
fn on_patches(patches: usize, at: &[(usize, [f64; 2])]) -> Result<SurfacePlan, InputError> {
    let mut vertices = Vec::with_capacity(at.len());
    for (i, &(p, [u, v])) in at.iter().enumerate() {
        let inside = |x: f64| (0.0..=1.0).contains(&x);
        if p >= patches || !inside(u) || !inside(v) {
            return Err(InputError::field(
                "sampling",
                format!(
                    "\"at\" triples must name one of the {patches} patches and lie in [0, 1]^2: \
                     at[{i}] = [{p}, {}, {}]",
                    Shown(u),
                    Shown(v)
                ),
            ));
        }
        vertices.push(Vertex {
            patch: p as u32,
            local: [u, v],
            uv: [u, v],
        });
    }
    Ok(SurfacePlan {
        vertices,
        triangles: None,
        cells: Vec::new(),
    })
}
