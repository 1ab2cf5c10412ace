//! Many surfaces' patches packed for the kernel in f32: each patch's 15 non-constant power
//! coefficients A_ab relative to its origin, the origin split into o_hi = f32(A_00) and
//! o_lo = f32(A_00 − o_hi), a rational patch's W, and (when normals are asked for) its normal
//! nets; each surface's first patch.

use std::ops::Range;

use rayon::prelude::*;

use crate::gpu::surfaces::abi::GpuPatch;
use crate::surface::PatchTable;

/// Many surfaces' patches packed for the kernel: patch records and coefficients, and where
/// each surface's patches start.
#[derive(Debug, Default)]
pub(crate) struct PackedPatches {
    pub patches: Vec<GpuPatch>,
    pub coeffs: Vec<f32>,
    pub first_patch: Vec<u32>,
}

impl PackedPatches {
    /// Packs every table's patches (see the module docs); the normal nets only when `normals`
    /// are asked for. Tables are packed on every thread, then laid end to end.
    pub(crate) fn new(tables: &[&PatchTable], normals: bool) -> Self {
        let whole: Vec<(&PatchTable, Range<usize>)> =
            tables.iter().map(|&t| (t, 0..t.len())).collect();
        Self::of_ranges(&whole, normals)
    }

    /// [`PackedPatches::new`] of the patches of each table's range only (a piece of a large
    /// surface uses a few rows of its patches): `first_patch[s]` is then the record of table
    /// s's `range.start`.
    pub(crate) fn of_ranges(tables: &[(&PatchTable, Range<usize>)], normals: bool) -> Self {
        let parts: Vec<Self> = tables
            .par_iter()
            .map(|(table, range)| Self::of_table(table, range.clone(), normals))
            .collect();
        let mut packed = Self::default();
        packed
            .patches
            .reserve(parts.iter().map(|p| p.patches.len()).sum());
        packed
            .coeffs
            .reserve(parts.iter().map(|p| p.coeffs.len()).sum());
        for part in parts {
            let base = packed.coeffs.len() as u32;
            packed.first_patch.push(packed.patches.len() as u32);
            packed.patches.extend(part.patches.iter().map(|p| GpuPatch {
                coeff_offset: p.coeff_offset + base,
                normal_offset: if normals { p.normal_offset + base } else { 0 },
                ..*p
            }));
            packed.coeffs.extend_from_slice(&part.coeffs);
        }
        packed
    }

    /// One table's patches, their offsets from its own first float.
    fn of_table(table: &PatchTable, range: Range<usize>, normals: bool) -> Self {
        let mut packed = Self::default();
        let dim = table.dim();
        for p in range {
            let patch = table.patch(p);
            let [lu, lv] = patch.length();
            let rational = patch.denominator();
            packed.patches.push(GpuPatch {
                coeff_offset: packed.coeffs.len() as u32,
                dim: dim as u32,
                rational: u32::from(rational.is_some()),
                inv_du: (1.0 / lu) as f32,
                inv_dv: (1.0 / lv) as f32,
                ..GpuPatch::default()
            });
            for ab in 1..16 {
                packed
                    .coeffs
                    .extend(patch.coefficient(ab / 4, ab % 4).iter().map(|&x| x as f32));
            }
            let origin = patch.coefficient(0, 0);
            let hi: Vec<f32> = origin.iter().map(|&x| x as f32).collect();
            packed.coeffs.extend(&hi);
            packed.coeffs.extend(
                origin
                    .iter()
                    .zip(&hi)
                    .map(|(&x, &h)| (x - f64::from(h)) as f32),
            );
            if let Some(w) = rational {
                packed.coeffs.extend(w.iter().map(|&x| x as f32));
            }
            if normals {
                let nets = normal_nets(&patch);
                let record = packed.patches.last_mut().expect("pushed above");
                record.normal_offset = packed.coeffs.len() as u32;
                packed.coeffs.extend(nets.iter().map(|&x| x as f32));
            }
        }
        packed
    }
}

/// Floats of a patch's normal nets: 16 points, 12 + 12 differences (3 each), 24 lengths.
pub(crate) const NORMAL_NET_FLOATS: usize = 48 + 72 + 24;

/// A 3-D patch's normal nets (see `shaders/surface.wgsl`): the Bezier points N_ij of its
/// numerator relative to its origin (16 x 3, i along u), their differences along u
/// (N_(i+1)j − N_ij, 12 x 3) and along v (N_i(j+1) − N_ij, 12 x 3), then the differences'
/// lengths (12 along u, 12 along v), in f64.
fn normal_nets(patch: &crate::surface::Patch<'_>) -> Vec<f64> {
    // Power to Bernstein along one direction of a cubic: b_j = Σ_{k <= j} C(j,k)/C(3,k) c_k.
    const TO_BERNSTEIN: [[f64; 4]; 4] = [
        [1.0, 0.0, 0.0, 0.0],
        [1.0, 1.0 / 3.0, 0.0, 0.0],
        [1.0, 2.0 / 3.0, 1.0 / 3.0, 0.0],
        [1.0, 1.0, 1.0, 1.0],
    ];
    let power = |a: usize, b: usize, k: usize| {
        if a + b == 0 {
            0.0 // the numerator relative to the origin (a polynomial's too)
        } else {
            patch.coefficient(a, b)[k]
        }
    };
    let mut n = [[[0.0f64; 3]; 4]; 4];
    for (i, row) in n.iter_mut().enumerate() {
        for (j, point) in row.iter_mut().enumerate() {
            for (k, x) in point.iter_mut().enumerate() {
                for (a, wa) in TO_BERNSTEIN[i].iter().enumerate() {
                    for (b, wb) in TO_BERNSTEIN[j].iter().enumerate() {
                        *x += wa * wb * power(a, b, k);
                    }
                }
            }
        }
    }
    let mut out = Vec::with_capacity(NORMAL_NET_FLOATS);
    let mut lengths = Vec::with_capacity(24);
    out.extend(n.iter().flatten().flatten());
    let mut differences = |d: &dyn Fn(usize, usize, usize) -> f64, rows: usize, cols: usize| {
        let net: Vec<[f64; 3]> = (0..rows)
            .flat_map(|i| (0..cols).map(move |j| [0, 1, 2].map(|k| d(i, j, k))))
            .collect();
        // Points that coincide (a collapsed edge) differ by rounding only: exactly zero here,
        // so that the kernel sees a vanishing derivative as one.
        let length = |p: &[f64; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let largest = net.iter().map(length).fold(0.0, f64::max);
        for p in &net {
            let kept = if length(p) <= 1e-12 * largest {
                [0.0; 3]
            } else {
                *p
            };
            out.extend(kept);
            lengths.push(length(&kept));
        }
    };
    differences(&|i, j, k| n[i + 1][j][k] - n[i][j][k], 3, 4);
    differences(&|i, j, k| n[i][j + 1][k] - n[i][j][k], 4, 3);
    out.extend(lengths);
    out
}
