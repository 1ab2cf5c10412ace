//! Tubes', ribbons' and strokes' plans packed for `shaders/geometry.wgsl`: each curve's widened
//! segments as blocks of f32 power coefficients relative to the curve's origin (its first
//! point, kept as o_hi + o_lo); a tube's or ribbon's cross-sections as (segment, u, s_j / L)
//! and the frame's start made in f64; a stroke's vertices as (segment, u, v), v planned in f64.

use crate::error::GpuError;
use crate::geometry::frames::unit_tangent;
use crate::geometry::job::{KernelPlan, SweptPlan};
use crate::geometry::mesh::{Shape, counts};
use crate::geometry::stroke::StrokePlan;
use crate::gpu::geometry::abi::{
    GpuMeshCurve, GpuSection, GpuStrokeVertex, NONE, SHAPE_RIBBON, SHAPE_STROKE, SHAPE_TUBE,
    VERTEX_FLOATS,
};
use crate::segment::SegmentTable;
use rayon::prelude::*;

/// Many curves' tables for one dispatch.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct PackedGeometry {
    pub(crate) curves: Vec<GpuMeshCurve>,
    pub(crate) blocks: Vec<[f32; 4]>,
    pub(crate) sections: Vec<GpuSection>,
    pub(crate) stroke_vertices: Vec<GpuStrokeVertex>,
    /// Vertices of all the curves.
    pub(crate) vertices: usize,
}

/// Vec4s a segment's block takes (x, y, z and the width: 4 coordinates).
fn block_vec4s(rational: bool) -> usize {
    if rational { 6 } else { 5 }
}

/// The vertices of a plan's mesh: its pieces' (open), or the whole curve's.
pub(crate) fn plan_vertices(plan: &SweptPlan<'_>) -> u64 {
    match plan.dashes {
        Some(pieces) => pieces
            .iter()
            .map(|p| counts(plan.shape, p.len() as u64, false).0)
            .sum(),
        None => counts(plan.shape, plan.locs.len() as u64, plan.closed()).0,
    }
}

/// The vertices of a plan's mesh.
pub(crate) fn kernel_plan_vertices(plan: &KernelPlan<'_>) -> u64 {
    match plan {
        KernelPlan::Swept(plan) => plan_vertices(plan),
        KernelPlan::Stroke { pieces, .. } => pieces.iter().map(|p| p.vertices).sum(),
    }
}

/// The bytes a plan takes in each binding: its curve record, blocks, sections, output and
/// stroke vertices.
pub(crate) fn binding_bytes(plan: &KernelPlan<'_>) -> [u64; 5] {
    let [blocks, sections, stroke_vertices, vertices] = shares(plan);
    [
        std::mem::size_of::<GpuMeshCurve>(),
        blocks * 16,
        sections * std::mem::size_of::<GpuSection>(),
        vertices * VERTEX_FLOATS * 4,
        stroke_vertices * std::mem::size_of::<GpuStrokeVertex>(),
    ]
    .map(|bytes| bytes as u64)
}

/// A plan's share of each table: blocks (vec4s), sections, stroke vertices, output vertices.
fn shares(plan: &KernelPlan<'_>) -> [usize; 4] {
    let table = plan.table();
    let blocks = table.len() * block_vec4s(table.is_rational());
    let vertices = kernel_plan_vertices(plan) as usize;
    match plan {
        KernelPlan::Swept(plan) => [blocks, plan.locs.len(), 0, vertices],
        KernelPlan::Stroke { .. } => [blocks, 0, vertices, vertices],
    }
}

/// One plan's part of the tables, and where it starts in the dispatch: its curve's index and
/// its first block, section and output vertex.
struct Part<'a> {
    curve: u32,
    first_block: usize,
    first_section: usize,
    first_vertex: usize,
    blocks: &'a mut [[f32; 4]],
    sections: &'a mut [GpuSection],
    stroke_vertices: &'a mut [GpuStrokeVertex],
}

impl PackedGeometry {
    /// Packs `plans` (`index` of each: its curve in the job, for errors), their vertices laid
    /// one curve after the other from 0; each plan's records made on every thread into its
    /// own part of the tables, sized from the plans.
    ///
    /// # Errors
    /// [`GpuError::OutOfRange`] for the first curve whose coefficients, relative to its
    /// origin, do not fit f32.
    pub(crate) fn new(plans: &[(usize, KernelPlan<'_>)]) -> Result<Self, GpuError> {
        let shares: Vec<[usize; 4]> = plans.iter().map(|(_, plan)| shares(plan)).collect();
        let total = |k: usize| shares.iter().map(|s| s[k]).sum::<usize>();
        let mut packed = Self {
            curves: bytemuck::zeroed_vec(plans.len()),
            blocks: bytemuck::zeroed_vec(total(0)),
            sections: bytemuck::zeroed_vec(total(1)),
            stroke_vertices: bytemuck::zeroed_vec(total(2)),
            vertices: total(3),
        };
        let mut parts = Vec::with_capacity(plans.len());
        let (mut blocks, mut sections, mut stroke_vertices) = (
            packed.blocks.as_mut_slice(),
            packed.sections.as_mut_slice(),
            packed.stroke_vertices.as_mut_slice(),
        );
        let (mut first_block, mut first_section, mut first_vertex) = (0, 0, 0);
        for (curve, share) in shares.iter().enumerate() {
            let (b, rest_b) = std::mem::take(&mut blocks).split_at_mut(share[0]);
            let (s, rest_s) = std::mem::take(&mut sections).split_at_mut(share[1]);
            let (v, rest_v) = std::mem::take(&mut stroke_vertices).split_at_mut(share[2]);
            (blocks, sections, stroke_vertices) = (rest_b, rest_s, rest_v);
            parts.push(Part {
                curve: curve as u32,
                first_block,
                first_section,
                first_vertex,
                blocks: b,
                sections: s,
                stroke_vertices: v,
            });
            first_block += share[0];
            first_section += share[1];
            first_vertex += share[3];
        }
        let made: Vec<Result<GpuMeshCurve, GpuError>> = plans
            .par_iter()
            .zip(parts)
            .map(|((index, plan), part)| match plan {
                KernelPlan::Swept(plan) => swept(*index, plan, part),
                KernelPlan::Stroke { table, pieces } => stroke(*index, table, pieces, part),
            })
            .collect();
        for (slot, curve) in packed.curves.iter_mut().zip(made) {
            *slot = curve?;
        }
        Ok(packed)
    }
}

/// A stroke's curve record, its blocks and its vertices: each piece's in order, one after the
/// other.
fn stroke(
    index: usize,
    table: &SegmentTable,
    pieces: &[StrokePlan],
    part: Part<'_>,
) -> Result<GpuMeshCurve, GpuError> {
    let [origin_hi, origin_lo] = blocks(index, table, part.blocks)?;
    let mut records = part.stroke_vertices.iter_mut();
    let mut vertex = 0u32;
    for piece in pieces {
        piece.gpu_vertices(|segment, u, v| {
            *records.next().expect("counted by the plan") = GpuStrokeVertex {
                curve: part.curve,
                vertex,
                segment: segment as u32,
                u: u as f32,
                v: v.map(|x| x as f32),
            };
            vertex += 1;
        });
    }
    debug_assert!(records.next().is_none());
    Ok(GpuMeshCurve {
        first_block: part.first_block as u32,
        block_vec4s: block_vec4s(table.is_rational()) as u32,
        rational: u32::from(table.is_rational()),
        shape: SHAPE_STROKE,
        first_vertex: part.first_vertex as u32,
        origin_hi,
        origin_lo,
        ..GpuMeshCurve::default()
    })
}

/// `table`'s segments as blocks into `out` (its coordinates x, y, z and the width, a 2-D
/// stroke's z 0), relative to its first point; the origin (hi, lo).
fn blocks(
    index: usize,
    table: &SegmentTable,
    out: &mut [[f32; 4]],
) -> Result<[[f32; 4]; 2], GpuError> {
    let rational = table.is_rational();
    let dim = table.dim();
    // Where x, y, z and the width are among the table's coordinates (a stroke has no z).
    let lanes: [Option<usize>; 4] = if dim == 3 {
        [Some(0), Some(1), None, Some(2)]
    } else {
        [Some(0), Some(1), Some(2), Some(3)]
    };
    let mut start = [0.0; 4];
    table.segment(0).eval(0.0, &mut start[..dim]);
    let origin: [f64; 3] = std::array::from_fn(|k| lanes[k].map_or(0.0, |i| start[i]));
    let hi = origin.map(|x| x as f32);
    let lo: [f32; 3] = std::array::from_fn(|k| (origin[k] - f64::from(hi[k])) as f32);
    let (knots, power) = (table.knots(), table.power_coefficients());
    let per = block_vec4s(rational);
    for (s, ((coeffs, span), block)) in power
        .chunks_exact(4 * dim)
        .zip(knots.windows(2))
        .zip(out.chunks_exact_mut(per))
        .enumerate()
    {
        let lane = |t: usize, k: usize| lanes[k].map_or(0.0, |i| coeffs[dim * t + i]);
        let term = |t: usize| -> [f32; 4] { std::array::from_fn(|k| lane(t, k) as f32) };
        let d: [f32; 4] = std::array::from_fn(|k| {
            let relative = if k < 3 {
                lane(3, k) - origin[k]
            } else {
                lane(3, k)
            };
            relative as f32
        });
        let inv_dt = (1.0 / (span[1] - span[0])) as f32;
        block[..4].copy_from_slice(&[term(0), term(1), term(2), d]);
        match table.segment(s).denominator().filter(|_| rational) {
            Some(w) => {
                let w = w.coeffs.map(|x| x as f32);
                block[4] = [inv_dt, w[0], w[1], w[2]];
                block[5] = [w[3], 0.0, 0.0, 0.0];
            }
            None => block[4] = [inv_dt, 0.0, 0.0, 0.0],
        }
    }
    if !out.iter().flatten().all(|x| x.is_finite()) {
        return Err(GpuError::OutOfRange {
            curve: index,
            what: "a coefficient relative to the curve's start, or 1/Δ of a segment,",
        });
    }
    let four = |v: [f32; 3]| [v[0], v[1], v[2], 0.0];
    Ok([four(hi), four(lo)])
}

/// A tube's or ribbon's curve record, its blocks and its sections.
fn swept(index: usize, plan: &SweptPlan<'_>, part: Part<'_>) -> Result<GpuMeshCurve, GpuError> {
    let table = plan.table;
    let rational = table.is_rational();
    let closed = plan.lengths.is_some();
    let [origin_hi, origin_lo] = blocks(index, table, part.blocks)?;
    let length = plan.lengths.and_then(|l| l.last().copied());
    let last = plan.locs.len() - 1;
    let mut t_first = None;
    for (((j, loc), slot), record) in plan
        .locs
        .iter()
        .enumerate()
        .zip(plan.slots())
        .zip(part.sections.iter_mut())
    {
        let along = match (plan.lengths, length) {
            (Some(s), Some(l)) if l > 0.0 && l.is_finite() => (s[j] / l) as f32,
            _ => 0.0,
        };
        let first_vertex = slot.map_or(NONE, |s| s.first_vertex);
        let (cap_vertex, cap_sign) = slot.and_then(|s| s.cap).unwrap_or((NONE, 0));
        *record = GpuSection {
            segment: loc.segment as u32,
            u: loc.u as f32,
            along,
            first_vertex,
            cap_vertex,
            cap_sign,
            _padding0: 0,
            _padding1: 0,
        };
        if t_first.is_none() {
            let segment = table.segment(loc.segment);
            let (mut d1, mut d2) = ([0.0; 4], [0.0; 4]);
            segment.deriv(loc.u, &mut d1);
            segment.deriv2(loc.u, &mut d2);
            let three = |v: [f64; 4]| [v[0], v[1], v[2]];
            t_first = unit_tangent(three(d1), three(d2), j == last && j > 0);
        }
    }
    let t_first = t_first.unwrap_or([1.0, 0.0, 0.0]);
    let (shape, sides) = match plan.shape {
        Shape::Tube { sides, .. } => (SHAPE_TUBE, sides),
        Shape::Ribbon => (SHAPE_RIBBON, 0),
    };
    let four = |v: [f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32, 0.0];
    Ok(GpuMeshCurve {
        first_block: part.first_block as u32,
        block_vec4s: block_vec4s(rational) as u32,
        rational: u32::from(rational),
        first_section: part.first_section as u32,
        sections: plan.locs.len() as u32,
        shape,
        sides,
        _padding2: 0,
        closed: u32::from(closed),
        first_vertex: part.first_vertex as u32,
        _padding0: 0,
        _padding1: 0,
        origin_hi,
        origin_lo,
        n0: four(plan.n0),
        t_first: four(t_first),
    })
}
