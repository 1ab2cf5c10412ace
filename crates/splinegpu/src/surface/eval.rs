//! A surface's plan evaluated on the CPU: positions, derivatives with respect to the surface's
//! parameters and unit normals, on every thread, in f64 and stored as f32 or f64.
//!
//! A vertex is evaluated in two stages from its patch's power form S = Σ A_ab u^a v^b: at its u,
//! C_b = Σ_a u^a A_ab (and the u-derivatives' weights), then at its v, Horner in v over C_b. A
//! grid's row shares its first stage between the k_v vertices of one patch, so a vertex costs
//! four terms per plane. Polynomial patches of up to 4 coordinates take a path with the
//! dimension known at compile time; rational patches and wider points take the general one
//! ([`Patch::contract_u`], [`Patch::finish_v`] and the quotient rule). Both compute every step in
//! f64 and round only when they store.

use rayon::prelude::*;

use crate::job::Derivatives;
use crate::job::samples::SampleFloat;
use crate::surface::mesh::SurfacePlan;
use crate::surface::mesh::Vertex;
use crate::surface::normal::{BLOCK, NormalBlock, unit_normal};
use crate::surface::patch::{AlongU, Derivs, Patch, PatchTable};

/// One surface's samples (contract: "Output of a surface document"), flat and vertex-major:
/// f64 from [`SurfaceJob::evaluate_cpu`](super::SurfaceJob::evaluate_cpu), f32 from the GPU
/// ([`GpuContext::evaluate_surfaces`](crate::GpuContext::evaluate_surfaces)), or any of the
/// two into [`SurfaceSamples::for_plan`]'s memory through
/// [`SurfaceJob::evaluate_into`](super::SurfaceJob::evaluate_into); (u, v) always f64.
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

impl<F: SampleFloat> SurfaceSamples<F> {
    /// Samples of `plan` on `table` with the planes `derivatives` and `normals` ask for, every
    /// value zero, (u, v), patches and triangles from the plan: the memory
    /// [`SurfaceJob::evaluate_into`](super::SurfaceJob::evaluate_into) fills through
    /// [`SurfaceSamples::planes_mut`], again and
    /// again for a surface whose plan does not change.
    ///
    /// # Panics
    /// When the memory for them cannot be had ([`SurfaceSamples::try_for_plan`] says so
    /// instead).
    #[must_use]
    pub fn for_plan(
        table: &PatchTable,
        plan: &SurfacePlan,
        derivatives: Derivatives,
        normals: bool,
    ) -> Self {
        Self::try_for_plan(table, plan, derivatives, normals)
            .unwrap_or_else(|e| panic!("the memory for a surface's samples: {e}"))
    }

    /// [`SurfaceSamples::for_plan`], every allocation fallible: an error where the process
    /// cannot have the memory (an address-space or control-group limit that an estimate
    /// missed), never an abort.
    ///
    /// # Errors
    /// The first allocation refused.
    pub fn try_for_plan(
        table: &PatchTable,
        plan: &SurfacePlan,
        derivatives: Derivatives,
        normals: bool,
    ) -> Result<Self, std::collections::TryReserveError> {
        let (dim, n, orders) = (table.dim(), plan.vertices.len(), derivatives.order());
        let plane = |asked: bool, width: usize| asked.then(|| zeros(width * n)).transpose();
        let triangles = match &plan.triangles {
            Some(t) => Some(collected(t.len(), t.iter().copied())?),
            None => None,
        };
        Ok(SurfaceSamples {
            dim,
            uv: collected(n, plan.vertices.iter().map(|v| v.uv))?,
            patch: match table.patch_indices() {
                Some(_) => Some(collected(n, plan.vertices.iter().map(|v| v.patch))?),
                None => None,
            },
            points: zeros(dim * n)?,
            du: plane(orders >= 1, dim)?,
            dv: plane(orders >= 1, dim)?,
            duu: plane(orders >= 2, dim)?,
            duv: plane(orders >= 2, dim)?,
            dvv: plane(orders >= 2, dim)?,
            normals: plane(normals, 3)?,
            triangles,
        })
    }

    /// The planes present, in the GPU kernel's order: positions, du, dv, duu, duv, dvv,
    /// normals.
    pub(crate) fn value_planes(&mut self) -> Vec<&mut [F]> {
        [
            Some(&mut self.points),
            self.du.as_mut(),
            self.dv.as_mut(),
            self.duu.as_mut(),
            self.duv.as_mut(),
            self.dvv.as_mut(),
            self.normals.as_mut(),
        ]
        .into_iter()
        .flatten()
        .map(Vec::as_mut_slice)
        .collect()
    }

    /// The value planes this holds, for
    /// [`SurfaceJob::evaluate_into`](super::SurfaceJob::evaluate_into).
    pub fn planes_mut(&mut self) -> SurfacePlanes<'_, F> {
        SurfacePlanes {
            points: &mut self.points,
            du: self.du.as_deref_mut(),
            dv: self.dv.as_deref_mut(),
            duu: self.duu.as_deref_mut(),
            duv: self.duv.as_deref_mut(),
            dvv: self.dvv.as_deref_mut(),
            normals: self.normals.as_deref_mut(),
        }
    }
}

/// A caller's memory for one surface's values, vertex-major as [`SurfaceSamples`] holds them:
/// `dim` values a vertex in each plane (normals: 3). The planes present are the ones formed.
#[derive(Debug)]
pub struct SurfacePlanes<'a, F> {
    /// Positions.
    pub points: &'a mut [F],
    /// d/du, to be formed when present.
    pub du: Option<&'a mut [F]>,
    /// d/dv.
    pub dv: Option<&'a mut [F]>,
    /// d²/du².
    pub duu: Option<&'a mut [F]>,
    /// d²/dudv.
    pub duv: Option<&'a mut [F]>,
    /// d²/dv².
    pub dvv: Option<&'a mut [F]>,
    /// Unit normals (3-D surfaces only).
    pub normals: Option<&'a mut [F]>,
}

/// Vertices evaluated per task on the pool.
const CHUNK: usize = 4096;

/// Evaluates `plan` on `table` in f64 into new memory: positions, the derivatives asked for,
/// and unit normals when `normals` (a [`SurfaceJob`](super::SurfaceJob) has checked that the
/// table is then 3-D).
///
/// # Errors
/// The memory for the samples refused.
pub(crate) fn evaluate_surfaces(
    table: &PatchTable,
    plan: &SurfacePlan,
    derivatives: Derivatives,
    normals: bool,
) -> Result<SurfaceSamples, std::collections::TryReserveError> {
    let mut samples = SurfaceSamples::try_for_plan(table, plan, derivatives, normals)?;
    evaluate_surfaces_into(table, plan, samples.planes_mut());
    Ok(samples)
}

/// The `n` items of `items` in a new vector, the allocation fallible.
fn collected<T>(
    n: usize,
    items: impl Iterator<Item = T>,
) -> Result<Vec<T>, std::collections::TryReserveError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n)?;
    v.extend(items);
    Ok(v)
}

/// `n` zeros, the allocation fallible (zeroed by the allocator, on huge pages where large).
fn zeros<F: SampleFloat>(n: usize) -> Result<Vec<F>, std::collections::TryReserveError> {
    crate::memory::try_zeroed(n)
}

/// Evaluates `plan` on `table` into a caller's planes on every thread: the planes present are
/// formed (each value computed in f64, rounded to `F` as it is stored), nothing is allocated
/// per vertex. The planes' lengths and the normals' dimension are the job's to check
/// ([`SurfaceJob::evaluate_into`](super::SurfaceJob::evaluate_into)).
pub(crate) fn evaluate_surfaces_into<F: SampleFloat>(
    table: &PatchTable,
    plan: &SurfacePlan,
    planes: SurfacePlanes<'_, F>,
) {
    let dim = table.dim();
    let n = plan.vertices.len();
    debug_assert!(
        planes.normals.is_none() || dim == 3,
        "normals need 3-D points"
    );
    let planes = [
        Some(planes.points),
        planes.du,
        planes.dv,
        planes.duu,
        planes.duv,
        planes.dvv,
        planes.normals,
    ];
    let widths = [dim, dim, dim, dim, dim, dim, 3];
    for (plane, width) in planes.iter().zip(widths) {
        if let Some(plane) = plane {
            debug_assert_eq!(plane.len(), width * n, "a plane of {n} vertices");
        }
    }
    // The planes to form: S_u and S_v for normals too; the u-stage orders they need.
    let wanted = |m: usize| planes[m].is_some() || (m <= 2 && planes[6].is_some());
    let count = (0..6).rev().find(|&m| wanted(m)).map_or(1, |m| m + 1);
    let count = match count {
        1 => 1,
        2 | 3 => 3,
        _ => 6,
    };
    let stage_orders = match count {
        1 => 1,
        3 => 2,
        _ => 3,
    };
    // Every plane cut into the same chunks of vertices, one task each.
    let mut views: Vec<Vec<Option<&mut [F]>>> = planes
        .into_iter()
        .zip(widths)
        .map(|(plane, width)| match plane {
            Some(plane) => plane.chunks_mut(width * CHUNK).map(Some).collect(),
            None => Vec::new(),
        })
        .collect();
    let mut tasks: Vec<(usize, [Option<&mut [F]>; 7])> = (0..n.div_ceil(CHUNK))
        .map(|c| {
            let parts = std::array::from_fn(|m| views[m].get_mut(c).and_then(Option::take));
            (c * CHUNK, parts)
        })
        .collect();
    let chunk = |first: usize, parts: &mut [Option<&mut [F]>; 7]| {
        let vertices = &plan.vertices[first..(first + CHUNK).min(n)];
        let job = Chunk {
            table,
            vertices,
            count,
            stage_orders,
        };
        match (table.is_rational(), dim) {
            (false, 1) => job.polynomial::<F, 1>(parts),
            (false, 2) => job.polynomial::<F, 2>(parts),
            (false, 3) => job.polynomial::<F, 3>(parts),
            (false, 4) => job.polynomial::<F, 4>(parts),
            _ => job.general(parts),
        }
    };
    tasks
        .par_iter_mut()
        .for_each(|(first, parts)| chunk(*first, parts));
}

/// One task's vertices and what to form of them.
struct Chunk<'a> {
    table: &'a PatchTable,
    vertices: &'a [Vertex],
    /// Planes formed: 1 (S), 3 (and S_u, S_v) or 6.
    count: usize,
    /// Orders of the u-stage those planes need: 1, 2 or 3.
    stage_orders: usize,
}

impl Chunk<'_> {
    /// Polynomial patches of `D` coordinates, run by run (a run: the vertices of one patch at
    /// one u, a grid row's k_v). At the run's u, Horner in u over each power b of v gives the
    /// stage C_b = Σ_a u^a A_ab (A_00 left out), its u-derivative C'_b and C''_b; then per
    /// vertex Horner in v: S = A_00 + C_0 + v (C_1 + v (C_2 + v C_3)), S_v from the same C_b
    /// differentiated in v, S_u from C'_b, and the second derivatives alike.
    fn polynomial<F: SampleFloat, const D: usize>(&self, parts: &mut [Option<&mut [F]>; 7]) {
        let vertices = self.vertices;
        let mut block = NormalBlock::default();
        let (mut filled, mut block_start) = (0, 0);
        let mut current: Option<(u32, Patch<'_>)> = None;
        let mut a = [[[0.0; D]; 4]; 4];
        let (mut origin, mut scale) = ([0.0; D], [1.0; 6]);
        let mut i = 0;
        while i < vertices.len() {
            let (p, u) = (vertices[i].patch, vertices[i].local[0]);
            let run = vertices[i..]
                .iter()
                .take_while(|w| w.patch == p && w.local[0] == u)
                .count();
            if current.map(|c| c.0) != Some(p) {
                let patch = self.table.patch(p as usize);
                // A_ab at a[a][b], the origin A_00 apart.
                for (ab, x) in patch.coefficients().chunks_exact(D).enumerate() {
                    a[ab / 4][ab % 4] = std::array::from_fn(|k| x[k]);
                }
                origin = std::mem::replace(&mut a[0][0], [0.0; D]);
                scale = patch.parameter_scales();
                current = Some((p, patch));
            }
            let (_, patch) = current.expect("the run's patch");
            let stage: [[[f64; D]; 4]; 3] = [
                std::array::from_fn(|b| {
                    std::array::from_fn(|k| {
                        a[0][b][k] + u * (a[1][b][k] + u * (a[2][b][k] + u * a[3][b][k]))
                    })
                }),
                std::array::from_fn(|b| {
                    std::array::from_fn(|k| {
                        a[1][b][k] + u * (2.0 * a[2][b][k] + 3.0 * u * a[3][b][k])
                    })
                }),
                std::array::from_fn(|b| {
                    std::array::from_fn(|k| 2.0 * a[2][b][k] + 6.0 * u * a[3][b][k])
                }),
            ];
            for (j, vertex) in vertices[i..i + run].iter().enumerate() {
                let v = vertex.local[1];
                let value = |c: &[[f64; D]; 4]| -> [f64; D] {
                    std::array::from_fn(|k| c[0][k] + v * (c[1][k] + v * (c[2][k] + v * c[3][k])))
                };
                let slope = |c: &[[f64; D]; 4]| -> [f64; D] {
                    std::array::from_fn(|k| c[1][k] + v * (2.0 * c[2][k] + 3.0 * v * c[3][k]))
                };
                let curvature = |c: &[[f64; D]; 4]| -> [f64; D] {
                    std::array::from_fn(|k| 2.0 * c[2][k] + 6.0 * v * c[3][k])
                };
                let position = value(&stage[0]);
                let position: [f64; D] = std::array::from_fn(|k| origin[k] + position[k]);
                put(&mut parts[0], i + j, position, 1.0);
                if self.count >= 3 {
                    let (su, sv) = (value(&stage[1]), slope(&stage[0]));
                    put(&mut parts[1], i + j, su, scale[1]);
                    put(&mut parts[2], i + j, sv, scale[2]);
                    block.put(filled, &su, &sv, &patch);
                }
                if self.count >= 6 {
                    put(&mut parts[3], i + j, value(&stage[2]), scale[3]);
                    put(&mut parts[4], i + j, slope(&stage[1]), scale[4]);
                    put(&mut parts[5], i + j, curvature(&stage[0]), scale[5]);
                }
                filled += 1;
                if filled == BLOCK {
                    self.normals(
                        &block,
                        block_start,
                        &vertices[block_start..][..BLOCK],
                        parts,
                    );
                    (filled, block_start) = (0, i + j + 1);
                }
            }
            i += run;
        }
        self.normals(&block, block_start, &vertices[block_start..], parts);
    }

    /// Any patch: [`Patch::contract_u`] and [`Patch::finish_v`] (the quotient rule on rational
    /// patches), the dimension read at run time.
    fn general<F: SampleFloat>(&self, parts: &mut [Option<&mut [F]>; 7]) {
        let mut local: Derivs = Default::default();
        let mut along = AlongU::default();
        let mut held: Option<(u32, f64)> = None;
        let mut block = NormalBlock::default();
        for (b, vertices) in self.vertices.chunks(BLOCK).enumerate() {
            for (j, vertex) in vertices.iter().enumerate() {
                let patch = self.table.patch(vertex.patch as usize);
                let [u, v] = vertex.local;
                if held != Some((vertex.patch, u)) {
                    patch.contract_u(u, self.stage_orders, &mut along);
                    held = Some((vertex.patch, u));
                }
                patch.finish_v(&along, v, self.count, &mut local);
                store(parts, b * BLOCK + j, &local, &patch.parameter_scales());
                block.put(j, &local[1], &local[2], &patch);
            }
            self.normals(&block, b * BLOCK, vertices, parts);
        }
    }

    /// The unit normals of one block's `vertices` (the chunk's from `first` on) into the
    /// normals plane, when present: in lanes where regular, else [`unit_normal`]'s limit.
    fn normals<F: SampleFloat>(
        &self,
        block: &NormalBlock,
        first: usize,
        vertices: &[Vertex],
        parts: &mut [Option<&mut [F]>; 7],
    ) {
        if parts[6].is_none() {
            return;
        }
        let mut unit = [[0.0; BLOCK]; 3];
        let regular = block.normals(vertices.len(), &mut unit);
        for (j, vertex) in vertices.iter().enumerate() {
            let normal = if regular[j] {
                [unit[0][j], unit[1][j], unit[2][j]]
            } else {
                let [u, v] = vertex.local;
                let patch = self.table.patch(vertex.patch as usize);
                let lane = |f: &[[f64; BLOCK]; 3]| [f[0][j], f[1][j], f[2][j]];
                unit_normal(&patch, u, v, lane(&block.su), lane(&block.sv))
            };
            put(&mut parts[6], first + j, normal, 1.0);
        }
    }
}

/// Vertex `i`'s `D` values times `scale` into `plane`, when present.
#[inline(always)]
fn put<F: SampleFloat, const D: usize>(
    plane: &mut Option<&mut [F]>,
    i: usize,
    values: [f64; D],
    scale: f64,
) {
    if let Some(plane) = plane {
        for (t, x) in plane[i * D..(i + 1) * D].iter_mut().zip(values) {
            *t = F::from_f64(x * scale);
        }
    }
}

/// Vertex `i`'s local values (S, S_u, S_v, S_uu, S_uv, S_vv; the ones formed) into the planes
/// present, times `scale` (to the surface's parameters: [`Patch::parameter_scales`]).
fn store<F: SampleFloat, V: AsRef<[f64]>>(
    parts: &mut [Option<&mut [F]>; 7],
    i: usize,
    values: &[V; 6],
    scale: &[f64; 6],
) {
    for (m, part) in parts.iter_mut().take(6).enumerate() {
        if let Some(part) = part {
            let values = values[m].as_ref();
            let dim = values.len();
            for (t, x) in part[i * dim..(i + 1) * dim].iter_mut().zip(values) {
                *t = F::from_f64(x * scale[m]);
            }
        }
    }
}
