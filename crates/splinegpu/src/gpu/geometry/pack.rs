//! Tubes' and ribbons' plans packed for `shaders/geometry.wgsl`: each curve's widened segments
//! as blocks of f32 power coefficients relative to the curve's origin (its first point, kept as
//! o_hi + o_lo), its cross-sections as (segment, u, s_j / L), and the frame's start made in f64.

use crate::error::GpuError;
use crate::geometry::frames::unit_tangent;
use crate::geometry::job::SweptPlan;
use crate::geometry::mesh::{Shape, counts};
use crate::gpu::geometry::abi::{
    GpuMeshCurve, GpuSection, NONE, SHAPE_RIBBON, SHAPE_TUBE, VERTEX_FLOATS,
};

/// Many curves' tables for one dispatch.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct PackedGeometry {
    pub(crate) curves: Vec<GpuMeshCurve>,
    pub(crate) blocks: Vec<[f32; 4]>,
    pub(crate) sections: Vec<GpuSection>,
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

/// The bytes a plan takes in each binding: its curve record, blocks, sections and output.
pub(crate) fn binding_bytes(plan: &SweptPlan<'_>) -> [u64; 4] {
    let blocks = plan.table.len() * block_vec4s(plan.table.is_rational()) * 16;
    let vertices = plan_vertices(plan);
    [
        std::mem::size_of::<GpuMeshCurve>() as u64,
        blocks as u64,
        (plan.locs.len() * std::mem::size_of::<GpuSection>()) as u64,
        vertices * (VERTEX_FLOATS * 4) as u64,
    ]
}

impl PackedGeometry {
    /// Packs `plans` (`index` of each: its curve in the job, for errors), their vertices laid
    /// one curve after the other from 0.
    ///
    /// # Errors
    /// [`GpuError::OutOfRange`] for a curve whose coefficients, relative to its origin, do not
    /// fit f32.
    pub(crate) fn new(plans: &[(usize, SweptPlan<'_>)]) -> Result<Self, GpuError> {
        let mut packed = Self::default();
        for (index, plan) in plans {
            packed.push(*index, plan)?;
        }
        Ok(packed)
    }

    fn push(&mut self, index: usize, plan: &SweptPlan<'_>) -> Result<(), GpuError> {
        let table = plan.table;
        let rational = table.is_rational();
        let closed = plan.lengths.is_some();
        let first = table.segment(0);
        let mut start = [0.0; 4];
        first.eval(0.0, &mut start);
        let origin = [start[0], start[1], start[2]];
        let hi = origin.map(|x| x as f32);
        let lo: [f32; 3] = std::array::from_fn(|k| (origin[k] - f64::from(hi[k])) as f32);
        let first_block = self.blocks.len();
        let (knots, power) = (table.knots(), table.power_coefficients());
        for (s, (coeffs, span)) in power.chunks_exact(16).zip(knots.windows(2)).enumerate() {
            let term = |t: usize| -> [f32; 4] { std::array::from_fn(|k| coeffs[4 * t + k] as f32) };
            let d: [f32; 4] = std::array::from_fn(|k| {
                let relative = if k < 3 {
                    coeffs[12 + k] - origin[k]
                } else {
                    coeffs[12 + k]
                };
                relative as f32
            });
            let inv_dt = (1.0 / (span[1] - span[0])) as f32;
            self.blocks.extend([term(0), term(1), term(2), d]);
            match table.segment(s).denominator().filter(|_| rational) {
                Some(w) => {
                    let w = w.coeffs.map(|x| x as f32);
                    self.blocks.push([inv_dt, w[0], w[1], w[2]]);
                    self.blocks.push([w[3], 0.0, 0.0, 0.0]);
                }
                None => self.blocks.push([inv_dt, 0.0, 0.0, 0.0]),
            }
        }
        if !self.blocks[first_block..]
            .iter()
            .flatten()
            .all(|x| x.is_finite())
        {
            return Err(GpuError::OutOfRange {
                curve: index,
                what: "a coefficient relative to the curve's start, or 1/Δ of a segment,",
            });
        }
        let length = plan.lengths.and_then(|l| l.last().copied());
        let first_section = self.sections.len();
        let last = plan.locs.len() - 1;
        let mut t_first = None;
        for ((j, loc), slot) in plan.locs.iter().enumerate().zip(plan.slots()) {
            let along = match (plan.lengths, length) {
                (Some(s), Some(l)) if l > 0.0 && l.is_finite() => (s[j] / l) as f32,
                _ => 0.0,
            };
            let first_vertex = slot.map_or(NONE, |s| s.first_vertex);
            let (cap_vertex, cap_sign) = slot.and_then(|s| s.cap).unwrap_or((NONE, 0));
            self.sections.push(GpuSection {
                segment: loc.segment as u32,
                u: loc.u as f32,
                along,
                first_vertex,
                cap_vertex,
                cap_sign,
                _padding0: 0,
                _padding1: 0,
            });
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
        let vertices = plan_vertices(plan);
        let four = |v: [f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32, 0.0];
        self.curves.push(GpuMeshCurve {
            first_block: first_block as u32,
            block_vec4s: block_vec4s(rational) as u32,
            rational: u32::from(rational),
            first_section: first_section as u32,
            sections: plan.locs.len() as u32,
            shape,
            sides,
            _padding2: 0,
            closed: u32::from(closed),
            first_vertex: self.vertices as u32,
            _padding0: 0,
            _padding1: 0,
            origin_hi: [hi[0], hi[1], hi[2], 0.0],
            origin_lo: [lo[0], lo[1], lo[2], 0.0],
            n0: four(plan.n0),
            t_first: four(t_first),
        });
        self.vertices += vertices as usize;
        Ok(())
    }
}
