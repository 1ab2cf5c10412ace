//! A surface's plan evaluated on the CPU in f64: positions, derivatives with respect to the
//! surface's parameters, unit normals, on every thread.

use rayon::prelude::*;

use crate::job::Derivatives;
use crate::surface::mesh::SurfacePlan;
use crate::surface::normal::unit_normal;
use crate::surface::patch::{AlongU, Derivs, PatchTable};

/// One surface's samples (contract: "Output of a surface document"), flat and vertex-major:
/// f64 from the CPU ([`evaluate_surfaces`]), f32 from the GPU
/// ([`GpuContext::evaluate_surfaces`](crate::GpuContext::evaluate_surfaces)); (u, v) always f64.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceSamples<F = f64> {
    /// Coordinates per point.
    pub dim: usize,
    /// (u, v) of every vertex in the surface's parameters (a patch list's: local to its patch).
    pub uv: Vec<[f64; 2]>,
    /// The patch each vertex was evaluated on, for patch lists; `None` for nets.
    pub patch: Option<Vec<u32>>,
    /// Positions, `dim` per vertex.
    pub points: Vec<F>,
    /// d/du and d/dv, `dim` per vertex, when first derivatives are asked for.
    pub du: Option<Vec<F>>,
    /// See [`SurfaceSamples::du`].
    pub dv: Option<Vec<F>>,
    /// Second derivatives d²/du², d²/dudv, d²/dv², when asked for.
    pub duu: Option<Vec<F>>,
    /// See [`SurfaceSamples::duu`].
    pub duv: Option<Vec<F>>,
    /// See [`SurfaceSamples::duu`].
    pub dvv: Option<Vec<F>>,
    /// Unit normals, 3 per vertex, when asked for (3-D surfaces only).
    pub normals: Option<Vec<F>>,
    /// Three vertex indices per triangle; `None` for explicit (u, v).
    pub triangles: Option<Vec<[u32; 3]>>,
}

impl<F> SurfaceSamples<F> {
    /// Number of vertices.
    #[must_use]
    pub fn len(&self) -> usize {
        self.uv.len()
    }

    /// True when there is no vertex.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.uv.is_empty()
    }
}

/// Vertices evaluated per task on the pool.
const CHUNK: usize = 4096;

/// Evaluates `plan` on `table` in f64: positions, the derivatives asked for, and unit normals
/// when `normals` (the table must then be 3-D; callers check it where the input is read).
///
/// # Panics
/// If `normals` is asked of a table whose dimension is not 3.
#[must_use]
pub fn evaluate_surfaces(
    table: &PatchTable,
    plan: &SurfacePlan,
    derivatives: Derivatives,
    normals: bool,
) -> SurfaceSamples {
    assert!(!normals || table.dim() == 3, "normals need 3-D points");
    let dim = table.dim();
    let n = plan.vertices.len();
    let orders = derivatives.order();
    // Planes: position, du, dv, duu, duv, dvv, normals; the ones not asked for stay empty.
    let widths = [
        dim,
        if orders >= 1 { dim } else { 0 },
        if orders >= 1 { dim } else { 0 },
        if orders >= 2 { dim } else { 0 },
        if orders >= 2 { dim } else { 0 },
        if orders >= 2 { dim } else { 0 },
        if normals { 3 } else { 0 },
    ];
    let mut planes: Vec<Vec<f64>> = widths.iter().map(|w| vec![0.0; w * n]).collect();
    {
        let mut views: Vec<_> = planes
            .iter_mut()
            .zip(widths)
            .map(|(plane, w)| {
                plane
                    .chunks_mut((w * CHUNK).max(1))
                    .map(Some)
                    .collect::<Vec<_>>()
            })
            .collect();
        let chunks = n.div_ceil(CHUNK);
        let mut tasks: Vec<(usize, Vec<Option<&mut [f64]>>)> = (0..chunks)
            .map(|c| {
                let parts = views
                    .iter_mut()
                    .zip(widths)
                    .map(|(v, w)| if w == 0 { None } else { v[c].take() })
                    .collect();
                (c, parts)
            })
            .collect();
        // Positions; Su and Sv for first derivatives or normals; the second ones when asked.
        let count = if orders >= 2 {
            6
        } else if orders == 1 || normals {
            3
        } else {
            1
        };
        let u_orders = match count {
            1 => 1,
            3 => 2,
            _ => 3,
        };
        tasks.par_iter_mut().for_each(|(c, parts)| {
            let mut local: Derivs = Default::default();
            let mut along = AlongU::default();
            let mut held: Option<(u32, f64)> = None;
            let first = *c * CHUNK;
            for (i, vertex) in plan.vertices[first..(first + CHUNK).min(n)]
                .iter()
                .enumerate()
            {
                let patch = table.patch(vertex.patch as usize);
                let [u, v] = vertex.local;
                // Vertices of one patch at one u (a grid's rows) share the u-stage.
                if held != Some((vertex.patch, u)) {
                    patch.contract_u(u, u_orders, &mut along);
                    held = Some((vertex.patch, u));
                }
                patch.finish_v(&along, v, count, &mut local);
                let scale = patch.parameter_scales();
                for (m, part) in parts.iter_mut().take(6).enumerate() {
                    if let Some(part) = part {
                        for k in 0..dim {
                            part[i * dim + k] = local[m][k] * scale[m];
                        }
                    }
                }
                if let Some(part) = &mut parts[6] {
                    part[i * 3..i * 3 + 3].copy_from_slice(&unit_normal(&patch, u, v, &local));
                }
            }
        });
    }
    let mut planes = planes.into_iter();
    let mut next = |asked: bool| {
        let plane = planes.next().expect("seven planes");
        asked.then_some(plane)
    };
    let points = next(true).expect("positions");
    let (du, dv) = (next(orders >= 1), next(orders >= 1));
    let (duu, duv, dvv) = (next(orders >= 2), next(orders >= 2), next(orders >= 2));
    let normals = next(normals);
    SurfaceSamples {
        dim,
        uv: plan.vertices.iter().map(|v| v.uv).collect(),
        patch: table
            .patch_indices()
            .map(|_| plan.vertices.iter().map(|v| v.patch).collect()),
        points,
        du,
        dv,
        duu,
        duv,
        dvv,
        normals,
        triangles: plan.triangles.clone(),
    }
}
