//! The CPU twin of `shaders/eval.wgsl`: an f32 interpreter of the packed runs, to be read side
//! by side with the kernel (same names, same loop order, same f32 arithmetic in the same
//! order). It reads the Pod records and coefficient blocks the kernel reads, runs every
//! invocation of every dispatch in turn, and copies each dispatch's output out as
//! [`GpuContext::evaluate`](crate::GpuContext::evaluate) does, so the packer and every kernel
//! shape are tested without a GPU.
//!
//! The f64 reference (`cpu::evaluate_reference`) is not the kernel's twin: it evaluates the f64
//! power form, with D whole and 1/Δ applied after Horner. This interpreter is.

use super::abi::{
    GpuLoc, GpuSegment, MODE_ARC, MODE_EXPLICIT, MODE_VECTOR, Params, Run, kernel_mode,
};
use super::pack::{self, BatchLimits, Packed};
use crate::error::GpuError;
use crate::gpu::KernelShape;
use crate::gpu::readback::unpack_device_planes;
use crate::job::EvalJob;
use crate::job::samples::{Samples, fill_t};

/// Evaluates `job` as the kernel does, in f32 on the CPU: packs it for `shape` within
/// `limits`, runs every invocation of every dispatch, and lays the samples out as the GPU
/// path does.
///
/// # Errors
/// A value outside the f32 range ([`GpuError::OutOfRange`]), as the GPU path.
pub(super) fn evaluate_interpreted(
    job: &EvalJob,
    shape: KernelShape,
    limits: BatchLimits,
) -> Result<Samples<f32>, GpuError> {
    let packed = pack::pack(job, shape, limits)?;
    let mut samples = Samples::for_job(job);
    let (download, locs) = run_dispatches(&packed, shape.lanes);
    let layout = job.layout();
    let (t, planes) = samples.planes_for(job).checked(job);
    unpack_device_planes(&download, layout, layout.device_values(), planes);
    fill_t(job, &packed.computed_t, &locs[packed.arc_locs..], t);
    Ok(samples)
}

/// Every dispatch of `packed` into one output buffer (as `GpuContext::run` binds it), each
/// dispatch's planes copied to their place in the device layout, as the download buffer
/// receives them; and the sample places as the kernel leaves them.
fn run_dispatches(packed: &Packed, lanes: u32) -> (Vec<f32>, Vec<GpuLoc>) {
    let mut download = vec![0.0f32; packed.device_values * packed.planes];
    let mut locs = packed.locs.clone();
    let mut output = vec![[0.0f32; 4]; packed.plane_stride * packed.planes / 4];
    for batch in &packed.batches {
        // One dispatch per mode, as `GpuContext::dispatch` records them.
        for (mode, runs) in batch.modes.iter().enumerate() {
            let (mode, rational) = kernel_mode(mode as u32);
            let mut kernel = Kernel {
                params: Params {
                    run_count: runs.len() as u32,
                    row_width: 0,
                    plane_stride: packed.plane_stride as u32,
                    derivatives: (packed.planes - 1) as u32,
                    out_base: 0,
                    first_run: runs.start as u32,
                    _padding: [0; 2],
                },
                mode,
                rational,
                segments: &packed.segments,
                coeffs: &packed.coeffs,
                coeff_floats: bytemuck::cast_slice(&packed.coeffs),
                runs: &packed.runs[batch.runs.clone()],
                samples: &mut output,
                locs: &mut locs,
                arcs: &packed.arcs,
                lanes,
            };
            for index in 0..runs.len() as u32 * lanes {
                kernel.main(index);
            }
        }
        let floats: &[f32] = bytemuck::cast_slice(&output);
        let skip = batch.values.start - batch.base;
        for p in 0..packed.planes {
            let from = &floats[p * packed.plane_stride + skip..][..batch.values.len()];
            download[p * packed.device_values + batch.values.start..][..batch.values.len()]
                .copy_from_slice(from);
        }
    }
    (download, locs)
}

type Vec4 = [f32; 4];

/// WGSL `Cubic`: hi + (lo + u(c + u(b + u a))) in 4 coordinates.
#[derive(Clone, Copy)]
struct Cubic {
    a: Vec4,
    b: Vec4,
    c: Vec4,
    lo: Vec4,
    hi: Vec4,
}

/// WGSL `Piece`.
#[derive(Clone, Copy)]
struct Piece {
    p: Cubic,
    inv_dt: f32,
}

const NO_SEGMENT: u32 = u32::MAX;

/// WGSL `Loaded`.
struct Loaded {
    segment: u32,
    piece: Piece,
    w: Vec4,
}

fn nothing_loaded() -> Loaded {
    let z = [0.0; 4];
    Loaded {
        w: z,
        segment: NO_SEGMENT,
        piece: Piece {
            p: Cubic {
                a: z,
                b: z,
                c: z,
                lo: z,
                hi: z,
            },
            inv_dt: 0.0,
        },
    }
}

/// WGSL `ArcHint`.
struct ArcHint {
    segment: u32,
    piece: u32,
}

/// The kernel's bindings, and its `LANES` and `MODE` overrides.
struct Kernel<'a> {
    params: Params,
    segments: &'a [GpuSegment],
    coeffs: &'a [Vec4],
    runs: &'a [Run],
    samples: &'a mut [Vec4],
    locs: &'a mut [GpuLoc],
    coeff_floats: &'a [f32],
    arcs: &'a [[u32; 4]],
    lanes: u32,
    /// The pipeline's `MODE`.
    mode: u32,
    /// The pipeline's `RATIONAL`.
    rational: bool,
}

/// `s * v`, component by component.
fn scale(s: f32, v: Vec4) -> Vec4 {
    v.map(|x| s * x)
}

fn horner(p: &Cubic, u: f32) -> Vec4 {
    std::array::from_fn(|i| p.hi[i] + (p.lo[i] + u * (p.c[i] + u * (p.b[i] + u * p.a[i]))))
}

/// WGSL `rational_value`: derivative `order` of a rational piece at u, by the quotient rule.
fn rational_value(piece: &Piece, w: Vec4, u: f32, order: u32) -> Vec4 {
    let p = piece.p;
    let s = piece.inv_dt;
    let inv = 1.0 / (w[3] + u * (w[2] + u * (w[1] + u * w[0])));
    let r: Vec4 = std::array::from_fn(|i| u * (p.c[i] + u * (p.b[i] + u * p.a[i])) * inv);
    if order == 0 {
        return std::array::from_fn(|i| p.hi[i] + (p.lo[i] + r[i]));
    }
    let w1 = w[2] + u * (2.0 * w[1] + 3.0 * u * w[0]);
    let r1: Vec4 = std::array::from_fn(|i| {
        ((p.c[i] + u * (2.0 * p.b[i] + 3.0 * u * p.a[i])) - r[i] * w1) * inv
    });
    if order == 1 {
        return scale(s, r1);
    }
    let w2 = 2.0 * w[1] + 6.0 * u * w[0];
    let r2: Vec4 = std::array::from_fn(|i| {
        ((2.0 * p.b[i] + 6.0 * u * p.a[i]) - 2.0 * r1[i] * w1 - r[i] * w2) * inv
    });
    scale(s * s, r2)
}

fn model_at(c: Vec4, c5: f32, x: f32) -> f32 {
    x * (c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * c5))))
}

fn derive(piece: &Piece, order: u32) -> Cubic {
    let p = piece.p;
    let s = piece.inv_dt;
    let zero = [0.0; 4];
    if order == 0 {
        return p;
    }
    if order == 1 {
        return Cubic {
            a: zero,
            b: scale(3.0 * s, p.a),
            c: scale(2.0 * s, p.b),
            lo: scale(s, p.c),
            hi: zero,
        };
    }
    Cubic {
        a: zero,
        b: zero,
        c: scale(6.0 * s * s, p.a),
        lo: scale(2.0 * s * s, p.b),
        hi: zero,
    }
}

impl Kernel<'_> {
    fn piece1(&self, at: u32) -> Piece {
        let v0 = self.coeffs[at as usize];
        let v1 = self.coeffs[at as usize + 1];
        let x = |v: f32| [v, 0.0, 0.0, 0.0];
        Piece {
            p: Cubic {
                a: x(v0[0]),
                b: x(v0[1]),
                c: x(v0[2]),
                lo: x(v0[3]),
                hi: x(v1[0]),
            },
            inv_dt: v1[1],
        }
    }

    fn piece2(&self, at: u32) -> Piece {
        let [v0, v1, v2] = [0, 1, 2].map(|i| self.coeffs[at as usize + i]);
        let xy = |x: f32, y: f32| [x, y, 0.0, 0.0];
        Piece {
            p: Cubic {
                a: xy(v0[0], v0[1]),
                b: xy(v0[2], v0[3]),
                c: xy(v1[0], v1[1]),
                lo: xy(v1[2], v1[3]),
                hi: xy(v2[0], v2[1]),
            },
            inv_dt: v2[2],
        }
    }

    fn piece3(&self, at: u32) -> Piece {
        let [v0, v1, v2, v3] = [0, 1, 2, 3].map(|i| self.coeffs[at as usize + i]);
        Piece {
            p: Cubic {
                a: [v0[0], v0[1], v0[2], 0.0],
                b: [v0[3], v1[0], v1[1], 0.0],
                c: [v1[2], v1[3], v2[0], 0.0],
                lo: [v2[1], v2[2], v2[3], 0.0],
                hi: [v3[0], v3[1], v3[2], 0.0],
            },
            inv_dt: v3[3],
        }
    }

    fn piece4(&self, at: u32) -> Piece {
        let v = |i: u32| self.coeffs[(at + i) as usize];
        Piece {
            p: Cubic {
                a: v(0),
                b: v(1),
                c: v(2),
                lo: v(3),
                hi: v(4),
            },
            inv_dt: v(5)[0],
        }
    }

    fn piece_small(&self, segment: GpuSegment) -> Piece {
        match segment.dim {
            1 => self.piece1(segment.coeff_offset),
            2 => self.piece2(segment.coeff_offset),
            3 => self.piece3(segment.coeff_offset),
            _ => self.piece4(segment.coeff_offset),
        }
    }

    fn piece_any(&self, segment: GpuSegment, q: u32) -> Piece {
        let block = 4 * segment.coeff_offset;
        let dim = segment.dim;
        let mut terms = [[0.0f32; 4]; 5];
        for k in 4 * q..dim.min(4 * q + 4) {
            for t in 0..5u32 {
                terms[t as usize][(k - 4 * q) as usize] =
                    self.coeff_floats[(block + t * dim + k) as usize];
            }
        }
        Piece {
            p: Cubic {
                a: terms[0],
                b: terms[1],
                c: terms[2],
                lo: terms[3],
                hi: terms[4],
            },
            inv_dt: self.coeff_floats[(block + 5 * dim) as usize],
        }
    }

    fn segment_start(&self, run: &Run, dim: u32, order: u32, s: u32) -> u32 {
        (run.out_offset + order * self.params.plane_stride) / 4 + s * run.count / 4 * dim
    }

    /// A float store, as `samples[f / 4u][f % 4u] = v`.
    fn store(&mut self, f: u32, v: f32) {
        self.samples[(f / 4) as usize][(f % 4) as usize] = v;
    }

    fn vector_run(&mut self, run: &Run, lane: u32) {
        let groups = run.count / 4;
        let du = run.du;
        let first = self.segments[run.segment as usize];
        let at = first.coeff_offset;
        // The kernel's `switch first.dim`: one loop nest per dimension, the same body each.
        let dim = first.dim.min(4);
        let mut den = [0.0; 4];
        for s in 0..run.segments {
            let block = at + s * self.block_vec4s(dim);
            let piece = match dim {
                1 => self.piece1(block),
                2 => self.piece2(block),
                3 => self.piece3(block),
                _ => self.piece4(block),
            };
            if self.rational {
                den = self.denominator(block, dim);
            }
            for order in 0..=self.params.derivatives {
                let p = derive(&piece, order);
                let w0 = self.segment_start(run, dim, order, s);
                let mut g = lane;
                while g < groups {
                    let u = run.u0 + (4 * g) as f32 * du;
                    let values = [
                        self.value_at(&piece, &p, den, u, order),
                        self.value_at(&piece, &p, den, u + du, order),
                        self.value_at(&piece, &p, den, u + 2.0 * du, order),
                        self.value_at(&piece, &p, den, u + 3.0 * du, order),
                    ];
                    // 4 samples of `dim` floats, written as `dim` whole vec4s.
                    let w = (w0 + dim * g) as usize;
                    let d = dim as usize;
                    let mut floats = [0.0f32; 16];
                    for (i, v) in values.iter().enumerate() {
                        floats[i * d..(i + 1) * d].copy_from_slice(&v[..d]);
                    }
                    for i in 0..d {
                        self.samples[w + i] = [0, 1, 2, 3].map(|c| floats[4 * i + c]);
                    }
                    g += self.lanes;
                }
            }
        }
    }

    fn write_group(&mut self, piece: &Piece, u: f32, q: u32, dim: u32, out: u32) {
        let last = dim.min(4 * q + 4);
        for order in 0..=self.params.derivatives {
            let v = horner(&derive(piece, order), u);
            let plane = out + order * self.params.plane_stride;
            for k in 4 * q..last {
                self.store(plane + k, v[(k - 4 * q) as usize]);
            }
        }
    }

    /// WGSL `block_vec4s`.
    fn block_vec4s(&self, dim: u32) -> u32 {
        (5 * dim + 1 + if self.rational { 4 } else { 0 }).div_ceil(4)
    }

    /// WGSL `denominator`.
    fn denominator(&self, block: u32, dim: u32) -> Vec4 {
        let at = (4 * block + 5 * dim + 1) as usize;
        std::array::from_fn(|i| self.coeff_floats[at + i])
    }

    /// WGSL `value_at`.
    fn value_at(&self, piece: &Piece, p: &Cubic, w: Vec4, u: f32, order: u32) -> Vec4 {
        if self.rational {
            return rational_value(piece, w, u, order);
        }
        horner(p, u)
    }

    fn write_rational(&mut self, piece: &Piece, w: Vec4, u: f32, q: u32, dim: u32, out: u32) {
        let last = dim.min(4 * q + 4);
        for order in 0..=self.params.derivatives {
            let v = rational_value(piece, w, u, order);
            let plane = out + order * self.params.plane_stride;
            for k in 4 * q..last {
                self.store(plane + k, v[(k - 4 * q) as usize]);
            }
        }
    }

    fn place_sample(&mut self, loc: GpuLoc, out_offset: u32, j: u32, loaded: &mut Loaded) {
        let segment = self.segments[loc.segment as usize];
        let out = out_offset + j * segment.dim;
        if segment.dim <= 4 {
            if loaded.segment != loc.segment {
                loaded.piece = self.piece_small(segment);
                if self.rational {
                    loaded.w = self.denominator(segment.coeff_offset, segment.dim);
                }
                loaded.segment = loc.segment;
            }
            let piece = loaded.piece;
            if self.rational {
                self.write_rational(&piece, loaded.w, loc.u, 0, segment.dim, out);
            } else {
                self.write_group(&piece, loc.u, 0, segment.dim, out);
            }
        } else {
            let mut q = 0;
            while 4 * q < segment.dim {
                let piece = self.piece_any(segment, q);
                if self.rational {
                    let w = self.denominator(segment.coeff_offset, segment.dim);
                    self.write_rational(&piece, w, loc.u, q, segment.dim, out);
                } else {
                    self.write_group(&piece, loc.u, q, segment.dim, out);
                }
                q += 1;
            }
        }
    }

    fn explicit_run(&mut self, run: &Run, lane: u32) {
        let mut loaded = nothing_loaded();
        let mut j = lane;
        while j < run.count {
            let loc = self.locs[(run.first_loc + j) as usize];
            self.place_sample(loc, run.out_offset, j, &mut loaded);
            j += self.lanes;
        }
    }

    fn last_start_at_or_before(
        &self,
        first: u32,
        stride: u32,
        start_at: u32,
        count: u32,
        x: f32,
    ) -> u32 {
        let start = |n: u32| f32::from_bits(self.arcs[(first + stride * n) as usize][0]);
        let mut lo = start_at;
        let mut step = 1;
        let mut hi = lo + step;
        while hi < count && start(hi) <= x {
            lo = hi;
            step *= 2;
            hi = lo + step;
        }
        hi = hi.min(count);
        while hi - lo > 1 {
            let mid = u32::midpoint(lo, hi);
            if start(mid) <= x {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    fn arc_place(&self, run: &Run, i: u32, hint: &mut ArcHint) -> GpuLoc {
        let arcs = self.arcs;
        let float = f32::from_bits;
        let header = arcs[run.arc as usize];
        if i == 0 {
            return GpuLoc {
                segment: run.segment,
                u: 0.0,
            };
        }
        if i >= header[0] {
            return GpuLoc {
                segment: run.segment + run.segments - 1,
                u: 1.0,
            };
        }
        let at_length = i as f32 * float(header[1]);
        let lo =
            self.last_start_at_or_before(run.arc + 1, 1, hint.segment, run.segments, at_length);
        if lo != hint.segment {
            hint.segment = lo;
            hint.piece = 0;
        }
        let record = arcs[(run.arc + 1 + lo) as usize];
        let k = self.last_start_at_or_before(record[1], 2, hint.piece, record[2], at_length);
        hint.piece = k;
        let piece = arcs[(record[1] + 2 * k) as usize].map(float);
        let c = arcs[(record[1] + 2 * k + 1) as usize].map(float);
        let end = float(arcs[(record[1] + 2 * k + 2) as usize][0]);
        let c14 = [piece[2], piece[3], c[0], c[1]];
        let c5 = c[2];
        let span = end - piece[0];
        let mut y = 0.0;
        if span > 0.0 {
            y = ((at_length - piece[0]) / span).clamp(0.0, 1.0);
        }
        let x = model_at(c14, c5, y).clamp(0.0, 1.0);
        GpuLoc {
            segment: run.segment + lo,
            u: (piece[1] + x * (c[3] - piece[1])).clamp(0.0, 1.0),
        }
    }

    fn arc_run(&mut self, run: &Run, lane: u32) {
        let mut hint = ArcHint {
            segment: 0,
            piece: 0,
        };
        let mut loaded = nothing_loaded();
        let mut j = lane;
        while j < run.count {
            let loc = self.arc_place(run, run.first + j, &mut hint);
            self.locs[(run.first_loc + j) as usize] = loc;
            self.place_sample(loc, run.out_offset, j, &mut loaded);
            j += self.lanes;
        }
    }

    fn scalar_block(&mut self, segment: GpuSegment, out: u32, run: &Run, lane: u32) {
        let mut q = 0;
        while 4 * q < segment.dim {
            let piece = self.piece_any(segment, q);
            let last = segment.dim.min(4 * q + 4);
            for order in 0..=self.params.derivatives {
                let p = derive(&piece, order);
                let plane = out + order * self.params.plane_stride;
                let mut j = lane;
                while j < run.count {
                    let v = horner(&p, run.u0 + j as f32 * run.du);
                    for k in 4 * q..last {
                        self.store(plane + j * segment.dim + k, v[(k - 4 * q) as usize]);
                    }
                    j += self.lanes;
                }
            }
            q += 1;
        }
    }

    fn rational_block(&mut self, segment: GpuSegment, out: u32, run: &Run, lane: u32) {
        let w = self.denominator(segment.coeff_offset, segment.dim);
        let mut q = 0;
        while 4 * q < segment.dim {
            let piece = self.piece_any(segment, q);
            let mut j = lane;
            while j < run.count {
                let u = run.u0 + j as f32 * run.du;
                self.write_rational(&piece, w, u, q, segment.dim, out + j * segment.dim);
                j += self.lanes;
            }
            q += 1;
        }
    }

    /// The entry point, for the invocation with flat index `index`.
    fn main(&mut self, index: u32) {
        let run_index = index / self.lanes;
        if run_index >= self.params.run_count {
            return;
        }
        let mut run = self.runs[(self.params.first_run + run_index) as usize];
        run.out_offset += self.params.out_base;
        let lane = index % self.lanes;
        if self.mode == MODE_VECTOR {
            self.vector_run(&run, lane);
        } else if self.mode == MODE_EXPLICIT {
            self.explicit_run(&run, lane);
        } else if self.mode == MODE_ARC {
            self.arc_run(&run, lane);
        } else {
            let mut out = run.out_offset;
            for s in 0..run.segments {
                let segment = self.segments[(run.segment + s) as usize];
                if self.rational {
                    self.rational_block(segment, out, &run, lane);
                } else {
                    self.scalar_block(segment, out, &run, lane);
                }
                out += run.count * segment.dim;
            }
        }
    }
}

#[cfg(test)]
#[path = "twin_tests.rs"]
mod tests;
