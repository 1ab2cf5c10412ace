//! Tolerance cross-sections for geometry: where a tube's rings, a ribbon's pairs and a
//! stroke's cross-sections go, and how many sides a tube gets, so that the mesh is certified
//! within `tol` of the exact shape (the contract's "Tolerance (certified)"; docs/geometry.md
//! holds the derivation this module follows).
//!
//! Everything is measured in the local parameter u of each segment of the widened table (the
//! position's D coordinates and the width as coordinate D). A cell is [u_a, u_b] of one
//! segment, h = u_b − u_a. On a cell, [`CellBounds`] holds proven bounds, from Taylor
//! expansions about the cell's midpoint m (every derivative of a polynomial is a polynomial,
//! and |p(m + x)| <= Σ |p^(j)(m)| |x|^j / j!):
//!
//! - K2, K3 >= max |C''|, max |C'''|; v_lo <= min |C'| (and v_hi >= max |C'|);
//! - for the width w: max |w|, a lower bound of w, max |w'|, max |w''|.
//!
//! A segment is P(u) = D + N(u) / W(u), W ≡ 1 for a polynomial one; with c = P(m) − D and
//! Ñ = N − c W (so P − P(m) = Ñ / W and K0 >= |P − P(m)|), the quotient rule gives
//!
//! ```text
//! K1 = (|Ñ'| + K0 |W'|) / W_lo,   K2 = (|Ñ''| + 2 K1 |W'| + K0 |W''|) / W_lo,
//! K3 = (|Ñ'''| + 3 K2 |W'| + 3 K1 |W''| + K0 |W'''|) / W_lo,
//! |C'| = |Ñ' W − Ñ W'| / W²  >=  min |Ñ' W − Ñ W'| / W_hi²,
//! ```
//!
//! each |·| the cell's maximum of a polynomial's norm. With T = C'/|C'|:
//! |T'| <= T1 = K2 / v_lo and |T''| <= T2 = K3 / v_lo + 3 K2² / v_lo².
//!
//! The frames of tubes and ribbons are the exact rotation-minimizing frame turned by an
//! angle φ(u) that is linear between cross-sections, |φ'| <= P (see [`FrameSlack`]); the
//! unit vectors e of the frame's normal plane then have |e_u| <= E1 = T1 + P and
//! |e_uu| <= F2 = T2 + T1² + E1². A cell's error (`CellBounds::error`) is:
//!
//! - tube (s sides, α = π/s; r = w): r(1 − cos α) + A h² / 8, A = K2 + |r''| + 2 |r'| E1 +
//!   r F2, plus the most any of the cell's quads stands out of its plane, measured on the
//!   quads as the mesh makes them ([`Carried`]);
//! - ribbon (r = w/2, the strip linear across): A h²/8 with A as a tube's, plus the height of
//!   the cell's quad out of its plane, measured on the quad as the mesh makes it
//!   ([`Carried`]);
//! - stroke (r = w/2, offsets C ± r n in the plane): (K2 + |r''| + 2 |r'| T1 + r T2) h² / 8;
//!
//! plus 2 max(0, −w) (a tube's, w below 0 counting as 0) or max(0, −w) (the others'). A cell
//! whose speed may vanish, or on which the tangent may turn by more than 1/2 rad (the
//! rotation-minimizing frame's bound needs it), fails. Placement: an interval's bounds hold
//! on every cell inside it, so each interval (a segment at first) takes the fewest equal
//! cells, up to 8, that pass under its own bounds; an interval that needs more is cut into
//! parts of about 8 cells each (the error falls as h² once the bounds are tight) and each
//! part is bounded again.

use rayon::prelude::*;

use super::frames::{self, Vec3};
use crate::error::{InputError, Shown};
use crate::sampling::SampleLoc;
use crate::segment::{Segment, SegmentTable};

/// The largest turn of the tangent across one cell (radians): the rotation-minimizing frame
/// against the minimal rotation is bounded for it (see [`FrameSlack`]).
const LARGEST_TURN: f64 = 0.5;

/// The most coordinates a widened table has here: a tube's or ribbon's 3 and the width (a
/// stroke's table has 3).
const COORDS: usize = 4;

/// The smallest turn between a joint's tangents that makes it a corner, in radians (as a
/// stroke's).
const CORNER: f64 = 1e-6;

/// The most equal cells placed under one interval's bounds: more would be placed under
/// bounds looser than a smaller interval's (more cells), fewer would compute bounds more often.
const CELLS_PER_BOUND: usize = 8;

/// The fewest cells a thread takes at once when a curve's cells are checked on every thread.
const CELLS_PER_TASK: usize = 64;

/// Below this width in u a cell that cannot be certified is given up on.
const SMALLEST_CELL: f64 = 1.0 / (1u64 << 40) as f64;

/// What a cell's error is measured for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Swept {
    /// A tube of this many sides; `sagitta` is a ring's sagitta over its radius,
    /// 1 − cos(π/sides), made once ([`Swept::tube`]): computed in [`CellBounds::error`], the
    /// cosine was evaluated on every call, strokes' and ribbons' too (libm's cos was 4-5 % of
    /// a stroke's planning in `perf`).
    Tube { sides: u32, sagitta: f64 },
    /// A ribbon.
    Ribbon,
    /// A 2-D stroke's body.
    Stroke,
}

impl Swept {
    /// A tube of `sides` sides.
    pub(crate) fn tube(sides: u32) -> Self {
        let sagitta = 1.0 - (std::f64::consts::PI / f64::from(sides)).cos();
        Swept::Tube { sides, sagitta }
    }

    /// Whether its cross-sections carry rotation-minimizing frames.
    fn framed(self) -> bool {
        !matches!(self, Swept::Stroke)
    }
}

/// Proven bounds over one cell (the module's docs), in u.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CellBounds {
    k2: f64,
    k3: f64,
    /// Lower and upper bounds of the speed |C'|.
    v_lo: f64,
    v_hi: f64,
    /// max |w|, a lower bound of w, max |w'|, max |w''|.
    w_max: f64,
    w_lo: f64,
    w1: f64,
    w2: f64,
}

/// A polynomial's Taylor coefficients about m (p(m + x) = Σ c_j x^j), up to degree 5.
type Taylor = [f64; 6];

/// The Taylor coefficients about m of the cubic Σ_i coeffs[i] u^i.
fn taylor(coeffs: [f64; 4], m: f64) -> Taylor {
    let [c0, c1, c2, c3] = coeffs;
    [
        c0 + m * (c1 + m * (c2 + m * c3)),
        c1 + m * (2.0 * c2 + 3.0 * m * c3),
        c2 + 3.0 * m * c3,
        c3,
        0.0,
        0.0,
    ]
}

/// The norm of each Taylor coefficient of a vector polynomial given by its coordinates'.
fn norms(coords: &[Taylor]) -> [f64; 6] {
    std::array::from_fn(|j| coords.iter().map(|c| c[j] * c[j]).sum::<f64>().sqrt())
}

/// j!/(j−i)!, for i <= 3 and j < 6.
const FALLING: [[f64; 6]; 4] = [
    [1.0, 1.0, 1.0, 1.0, 1.0, 1.0],
    [0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
    [0.0, 0.0, 2.0, 6.0, 12.0, 20.0],
    [0.0, 0.0, 0.0, 6.0, 24.0, 60.0],
];

/// max over |x| <= ρ of the norms of a vector polynomial's derivatives 0..3, from its
/// coefficients' norms: Σ_{j>=i} |c_j| j!/(j−i)! ρ^(j−i).
fn derivative_maxima(norms: &[f64; 6], rho: f64) -> [f64; 4] {
    std::array::from_fn(|i| {
        let mut total = 0.0;
        for j in (i..6).rev() {
            total = total * rho + norms[j] * FALLING[i][j];
        }
        total
    })
}

/// min over |x| <= ρ of a vector polynomial's norm, from below: |c_0| − Σ_{j>=1} |c_j| ρ^j.
fn min_norm(norms: &[f64; 6], rho: f64) -> f64 {
    let mut rest = 0.0;
    for j in (1..6).rev() {
        rest = (rest + norms[j]) * rho;
    }
    norms[0] - rest
}

/// The product's Taylor coefficients (degrees beyond 5 are 0 here: cubic times quadratic).
fn product(a: &Taylor, b: &Taylor) -> Taylor {
    let mut out = [0.0; 6];
    for (i, ai) in a.iter().enumerate() {
        for (j, bj) in b.iter().enumerate().take(6 - i) {
            out[i + j] += ai * bj;
        }
    }
    out
}

fn derivative(a: &Taylor) -> Taylor {
    let mut out = [0.0; 6];
    for j in 1..6 {
        out[j - 1] = a[j] * j as f64;
    }
    out
}

/// The quotient-rule bounds K1..K3 from the numerator's and denominator's maxima.
fn quotient_bounds(n: [f64; 4], w: [f64; 4], w_lo: f64) -> [f64; 4] {
    let k0 = n[0] / w_lo;
    let k1 = (n[1] + k0 * w[1]) / w_lo;
    let k2 = (n[2] + 2.0 * k1 * w[1] + k0 * w[2]) / w_lo;
    let k3 = (n[3] + 3.0 * k2 * w[1] + 3.0 * k1 * w[2] + k0 * w[3]) / w_lo;
    [k0, k1, k2, k3]
}

impl CellBounds {
    /// The bounds over [ua, ub] of `segment` (the widened table's: its last coordinate the
    /// width); `None` where they cannot be had (a denominator that may vanish, numbers that
    /// overflow).
    pub(crate) fn of(segment: &Segment<'_>, ua: f64, ub: f64) -> Option<Self> {
        let dim = segment.power()[0].len();
        if dim > COORDS {
            return None;
        }
        let (m, rho) = (0.5 * (ua + ub), 0.5 * (ub - ua));
        if segment.denominator().is_none() {
            return Self::of_polynomial(segment, m, rho);
        }
        Self::general(segment, m, rho)
    }

    /// [`CellBounds::of`] about m, radius ρ, for any segment (W ≡ 1 for a polynomial one).
    fn general(segment: &Segment<'_>, m: f64, rho: f64) -> Option<Self> {
        let dim = segment.power()[0].len();
        let position = dim - 1;
        let [a, b, c, d] = segment.power();
        let rational = segment.denominator().is_some();
        let w_coeffs = segment.denominator().map_or([1.0, 0.0, 0.0, 0.0], |w| {
            let [wa, wb, wc, wd] = w.coeffs;
            [wd, wc, wb, wa]
        });
        let w = taylor(w_coeffs, m);
        let w_max = derivative_maxima(&norms(&[w]), rho);
        let w_lo = w[0] - (w_max[0] - w[0].abs());
        if w_lo.is_nan() || w_lo <= 0.0 {
            return None;
        }
        // Ñ = N − c W about m, coordinate by coordinate (N has no constant term).
        let mut shifted = [[0.0; 6]; COORDS];
        // The width at m: D + N(m) / W(m).
        let mut w_mid = 0.0;
        for k in 0..dim {
            let n = taylor([0.0, c[k], b[k], a[k]], m);
            let value = n[0] / w[0];
            for j in 0..6 {
                shifted[k][j] = n[j] - value * w[j];
            }
            if k == position {
                w_mid = d[k] + value;
            }
        }
        let (pos, width) = shifted[..dim].split_at(position);
        let n_max = derivative_maxima(&norms(pos), rho);
        let [_, _, k2, k3] = quotient_bounds(n_max, w_max, w_lo);
        let nw_max = derivative_maxima(&norms(width), rho);
        let [kw0, kw1, kw2, _] = quotient_bounds(nw_max, w_max, w_lo);
        // The speed's numerator Ñ' W − Ñ W' (Ñ' where W ≡ 1).
        let dw = derivative(&w);
        let mut speed = [[0.0; 6]; COORDS - 1];
        for (out, n) in speed.iter_mut().zip(pos) {
            *out = if rational {
                let (a, b) = (product(&derivative(n), &w), product(n, &dw));
                std::array::from_fn(|j| a[j] - b[j])
            } else {
                derivative(n)
            };
        }
        let speed = norms(&speed[..pos.len()]);
        let w_hi = w_max[0];
        let v_lo = min_norm(&speed, rho) / (w_hi * w_hi);
        let v_hi = derivative_maxima(&speed, rho)[0] / (w_lo * w_lo);
        Self::finite([k2, k3], [v_lo, v_hi], w_mid, [kw0, kw1, kw2])
    }

    /// [`CellBounds::of`] for a polynomial segment (W ≡ 1) about m, radius ρ, with the same
    /// arithmetic and so the same bits: Ñ is N without its constant term, the quotient rule's
    /// bounds are Ñ's own maxima, and the sums over Taylor coefficients stop at the cubic's
    /// (the general path adds zeros past them). Nine square roots where the general path takes
    /// twenty-four; a stroke's placement asks for bounds several times a segment.
    fn of_polynomial(segment: &Segment<'_>, m: f64, rho: f64) -> Option<Self> {
        let [a, b, c, d] = segment.power();
        let position = a.len() - 1;
        // Each coordinate's Taylor coefficients about m less the constant: [0, n1, n2, n3].
        let shifted = |k: usize| {
            let n = taylor([0.0, c[k], b[k], a[k]], m);
            (n[0], [n[1], n[2], n[3]])
        };
        // Per power, the norm over the position's coordinates (of Ñ, then of Ñ' = the speed).
        let (mut n_sq, mut v_sq) = ([0.0; 3], [0.0; 3]);
        for k in 0..position {
            let (_, n) = shifted(k);
            let v = [n[0], n[1] * 2.0, n[2] * 3.0];
            for j in 0..3 {
                n_sq[j] += n[j] * n[j];
                v_sq[j] += v[j] * v[j];
            }
        }
        let v_norm = v_sq.map(f64::sqrt);
        // Ñ's norms per power, its constant's 0.
        let n_norm = [0.0, n_sq[0].sqrt(), n_sq[1].sqrt(), n_sq[2].sqrt()];
        // derivative_maxima's Horner sums, from the cubic's term down.
        let maxima = |norms: [f64; 4], i: usize| {
            let mut total = 0.0;
            for j in (i..4).rev() {
                total = total * rho + norms[j] * FALLING[i][j];
            }
            total
        };
        let (k2, k3) = (maxima(n_norm, 2), maxima(n_norm, 3));
        let (value, w) = shifted(position);
        let w_abs = [
            0.0,
            (w[0] * w[0]).sqrt(),
            (w[1] * w[1]).sqrt(),
            (w[2] * w[2]).sqrt(),
        ];
        let [kw0, kw1, kw2] = [0, 1, 2].map(|i| maxima(w_abs, i));
        // The speed's norms as a quadratic's: min_norm and the value's maximum.
        let rest = ((v_norm[2] * rho) + v_norm[1]) * rho;
        let v_lo = v_norm[0] - rest;
        let v_hi = (v_norm[2] * rho + v_norm[1]) * rho + v_norm[0];
        let w_mid = d[position] + value;
        Self::finite([k2, k3], [v_lo, v_hi], w_mid, [kw0, kw1, kw2])
    }

    /// The bounds from K2, K3, the speed's bounds, the width at m and the width's maxima
    /// about it; `None` where one is not finite.
    fn finite(k: [f64; 2], v: [f64; 2], w_mid: f64, kw: [f64; 3]) -> Option<Self> {
        let bounds = Self {
            k2: k[0],
            k3: k[1],
            v_lo: v[0],
            v_hi: v[1],
            w_max: w_mid.abs() + kw[0],
            w_lo: w_mid - kw[0],
            w1: kw[1],
            w2: kw[2],
        };
        k.iter()
            .chain(&v)
            .chain(&kw)
            .all(|x| x.is_finite())
            .then_some(bounds)
    }

    /// max |T'| (T1 of the module's docs), infinite where the speed may vanish.
    fn turning(&self) -> f64 {
        if self.v_lo > 0.0 {
            self.k2 / self.v_lo
        } else {
            f64::INFINITY
        }
    }

    /// The cell's error bound for `swept` over a cell of width `h`, with the frames turned at
    /// most `p` radians per unit u away from the rotation-minimizing frame (the module's docs).
    pub(crate) fn error(&self, swept: Swept, h: f64, p: f64) -> f64 {
        let t1 = self.turning();
        if !t1.is_finite() || (swept.framed() && h * t1 > LARGEST_TURN) {
            return f64::INFINITY;
        }
        let t2 = self.k3 / self.v_lo + 3.0 * t1 * t1;
        let half = if matches!(swept, Swept::Tube { .. }) {
            1.0
        } else {
            0.5
        };
        let (r0, r1, r2) = (half * self.w_max, half * self.w1, half * self.w2);
        let clamp = 2.0 * half * (-self.w_lo).max(0.0);
        let e1 = t1 + p;
        let f2 = t2 + t1 * t1 + e1 * e1;
        let a = self.k2 + r2 + 2.0 * r1 * e1 + r0 * f2;
        let error = match swept {
            // The quads' twists across the cell are measured on the quads ([`Carried`]).
            Swept::Tube { sagitta, .. } => r0 * sagitta + a * h * h / 8.0,
            Swept::Ribbon => a * h * h / 8.0,
            Swept::Stroke => (self.k2 + r2 + 2.0 * r1 * t1 + r0 * t2) * h * h / 8.0,
        };
        error + clamp
    }

    /// The most the rotation-minimizing frame turns against the minimal rotation over a step
    /// of width `h` inside this cell, per unit u (see [`FrameSlack`]).
    fn transport_slope(&self, h: f64) -> f64 {
        let turn = h * self.turning();
        2.0 * turn * turn / std::f64::consts::PI / h
    }
}

/// How far the mesh's frames may turn from the exact rotation-minimizing frame, per unit u,
/// on a step between two consecutive places where frames are carried.
///
/// The rotation-minimizing normal is the parallel transport of N along the tangent's path on
/// the unit sphere; the minimal rotation taking T_a to T_b transports it along the great
/// circle. The two differ by the holonomy of the loop they make, its enclosed area, which
/// for a loop of length 2ℓ <= 1 (ℓ = h T1 the tangent's path) is at most (2ℓ)² / (2π). The
/// double-reflection step differs from the minimal rotation by an angle computed exactly
/// ([`frames::step_twist`]), and a closed curve's closing-up turns N by at most
/// π Δs / L more. Spread linearly over the step, the sum divided by h is the slope.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrameSlack {
    /// The closed curve's length L, where its frames are closed up.
    pub(crate) closed_length: Option<f64>,
}

impl FrameSlack {
    /// The slope on the step from `a` to `b` (positions, unit tangents and, for closed curves,
    /// the arc length to each) of width `h` in u, inside a cell of bounds `bounds`.
    pub(crate) fn slope(
        &self,
        bounds: &CellBounds,
        h: f64,
        a: (Vec3, Vec3, f64),
        b: (Vec3, Vec3, f64),
    ) -> f64 {
        if h <= 0.0 {
            return 0.0;
        }
        let twist = frames::step_twist(a.0, b.0, a.1, b.1).abs();
        let closing = self.closed_length.map_or(0.0, |length| {
            std::f64::consts::PI * (b.2 - a.2).abs() / length
        });
        twist / h + closing / h + bounds.transport_slope(h)
    }

    /// The slope known before the frames are carried: the transport's and the closing-up's
    /// (π |C'| / L), without the double reflection's own twist, which [`Carried`] adds.
    pub(crate) fn a_priori(&self, bounds: &CellBounds, h: f64) -> f64 {
        let closing = self
            .closed_length
            .map_or(0.0, |length| std::f64::consts::PI * bounds.v_hi / length);
        closing + bounds.transport_slope(h)
    }
}

/// The places where frames are carried (in order of t), with the position, unit tangent,
/// normal (as the mesh carries it) and width at each and, on a closed curve, the arc length
/// to each.
pub(crate) struct Carried<'a> {
    table: &'a SegmentTable,
    places: &'a [SampleLoc],
    positions: Vec<Vec3>,
    tangents: Vec<Vec3>,
    normals: Vec<Vec3>,
    widths: Vec<f64>,
    lengths: Option<&'a [f64]>,
}

/// Where a cell or step between places a and b lies: a's segment from a's u to b's (or to
/// the end of a's segment, where b starts the next).
fn span(a: &SampleLoc, b: &SampleLoc) -> (usize, f64, f64) {
    let ub = if b.segment == a.segment { b.u } else { 1.0 };
    (a.segment, a.u, ub)
}

impl<'a> Carried<'a> {
    pub(crate) fn of(
        table: &'a SegmentTable,
        places: &'a [SampleLoc],
        n0: Vec3,
        lengths: Option<&'a [f64]>,
    ) -> Self {
        let mut positions = Vec::with_capacity(places.len());
        let mut widths = Vec::with_capacity(places.len());
        let (mut d1s, mut d2s) = (Vec::with_capacity(places.len()), Vec::new());
        let mut p = [0.0; COORDS];
        let dim = table.dim();
        for loc in places {
            let segment = table.segment(loc.segment);
            let (mut d1, mut d2) = ([0.0; COORDS], [0.0; COORDS]);
            segment.jet(loc.u, &mut p[..dim], &mut d1[..dim], &mut d2[..dim]);
            positions.push([p[0], p[1], p[2]]);
            widths.push(p[dim - 1].max(0.0));
            d1s.push([d1[0], d1[1], d1[2]]);
            d2s.push([d2[0], d2[1], d2[2]]);
        }
        let tangents = frames::tangents(&d1s, &d2s);
        let mut normals = frames::rotation_minimizing(&positions, &tangents, n0);
        if let Some(lengths) = lengths {
            frames::close_up(&tangents, &mut normals, lengths);
        }
        Self {
            table,
            places,
            positions,
            tangents,
            normals,
            widths,
            lengths,
        }
    }

    /// How far a ribbon's two triangles between places i and j stray from the bilinear patch
    /// through their corners, and back ([`quad_warp`]).
    fn ribbon_warp(&self, i: usize, j: usize) -> f64 {
        let corner = |k: usize, side: f64| {
            let b = frames::cross(self.tangents[k], self.normals[k]);
            let half = 0.5 * side * self.widths[k];
            let x = self.positions[k];
            [x[0] + half * b[0], x[1] + half * b[1], x[2] + half * b[2]]
        };
        quad_warp([
            corner(i, -1.0),
            corner(j, -1.0),
            corner(j, 1.0),
            corner(i, 1.0),
        ])
    }

    /// The most any of a tube's quads between the rings at places i and j strays from the
    /// bilinear patch through its corners, and back ([`quad_warp`]); `circle` the sides'
    /// (sin θ_k, cos θ_k).
    fn tube_warp(&self, i: usize, j: usize, circle: &[(f64, f64)]) -> f64 {
        let ring = |k: usize| {
            let (n, x, r) = (self.normals[k], self.positions[k], self.widths[k]);
            let b = frames::cross(self.tangents[k], n);
            move |side: usize| {
                let (sin, cos) = circle[side];
                std::array::from_fn(|d| x[d] + r * (cos * n[d] + sin * b[d]))
            }
        };
        let (a, b) = (ring(i), ring(j));
        let sides = circle.len();
        (0..sides)
            .map(|k| {
                let next = (k + 1) % sides;
                quad_warp([a(k), b(k), b(next), a(next)])
            })
            .fold(0.0, f64::max)
    }

    /// The midpoints of the mesh cells whose error, with the frames' slope measured on the
    /// steps inside each, exceeds `tol`: the cells of each piece (indices into the places) or
    /// of the whole curve.
    ///
    /// # Errors
    /// A joint where the tangent turns a corner ("tolerance": one ring or pair cannot stand
    /// for the two sides' circles).
    pub(crate) fn failing_cells(
        &self,
        pieces: Option<&[Vec<usize>]>,
        swept: Swept,
        tol: f64,
        slack: FrameSlack,
    ) -> Result<Vec<SampleLoc>, InputError> {
        let n = self.places.len();
        // Each step's slope, and the turn at its end where a joint ends it.
        let mut slopes = vec![0.0; n.saturating_sub(1)];
        let mut corners = vec![0.0; n.saturating_sub(1)];
        // Each step's bounds, kept for a cell that is one step (every cell of an undashed curve).
        let mut step_bounds = vec![None; n.saturating_sub(1)];
        for k in 0..n.saturating_sub(1) {
            let (a, b) = (&self.places[k], &self.places[k + 1]);
            let (s, ua, ub) = span(a, b);
            let segment = self.table.segment(s);
            if b.segment != a.segment || ub == 1.0 {
                // The tangent the ring at b stands for, against the arriving side's.
                let mut d = [[0.0; COORDS]; 2];
                let dim = self.table.dim();
                let [d1, d2] = &mut d;
                segment.deriv(1.0, &mut d1[..dim]);
                segment.deriv2(1.0, &mut d2[..dim]);
                let arriving =
                    frames::unit_tangent([d1[0], d1[1], d1[2]], [d2[0], d2[1], d2[2]], true);
                let turn = arriving.map_or(std::f64::consts::PI, |t| {
                    let c = frames::cross(t, self.tangents[k + 1]);
                    frames::dot(c, c)
                        .sqrt()
                        .atan2(frames::dot(t, self.tangents[k + 1]))
                });
                if turn > CORNER {
                    return Err(InputError::field(
                        "tolerance",
                        format!(
                            "cannot be certified across the corner at t = {} (the tangent \
                             turns by {turn} rad there): a tube's or ribbon's tolerance needs \
                             a curve whose tangent is continuous",
                            b.t
                        ),
                    ));
                }
                corners[k] = turn;
            }
            let h = ub - ua;
            if h <= 0.0 {
                continue;
            }
            step_bounds[k] = CellBounds::of(&segment, ua, ub);
            let Some(bounds) = step_bounds[k] else {
                slopes[k] = f64::INFINITY;
                continue;
            };
            let at = |i: usize| {
                let length = self.lengths.map_or(0.0, |l| l[i]);
                (self.positions[i], self.tangents[i], length)
            };
            slopes[k] = slack.slope(&bounds, h, at(k), at(k + 1)) + corners[k] / h;
        }
        let all: Vec<usize>;
        let pieces: Vec<&[usize]> = match pieces {
            Some(pieces) => pieces.iter().map(Vec::as_slice).collect(),
            None => {
                all = (0..n).collect();
                vec![&all]
            }
        };
        // A tube's sides' angles, θ_k = 2πk/sides, as the mesh writer makes them.
        let circle: Vec<(f64, f64)> = match swept {
            Swept::Tube { sides, .. } => (0..sides)
                .map(|k| (std::f64::consts::TAU * f64::from(k) / f64::from(sides)).sin_cos())
                .collect(),
            _ => Vec::new(),
        };
        // Every cell on every thread (a tube's quads make a cell as costly as its rings), the
        // failing ones in order.
        let failing_midpoint = |i: usize, j: usize| -> Option<SampleLoc> {
            let (s, ua, ub) = span(&self.places[i], &self.places[j]);
            let h = ub - ua;
            if h <= 0.0 {
                return None;
            }
            let segment = self.table.segment(s);
            let slope = slopes[i..j].iter().copied().fold(0.0, f64::max);
            let turn: f64 = corners[i..j].iter().sum();
            let bounds = if j == i + 1 {
                step_bounds[i]
            } else {
                CellBounds::of(&segment, ua, ub)
            };
            let error = bounds.map_or(f64::INFINITY, |b| b.error(swept, h, slope) + b.w_max * turn);
            // The quads' warp adds to the error: measured only for a cell within tol without
            // it (a tube's is a loop over its sides).
            let fails = error.is_nan()
                || error > tol
                || match swept {
                    Swept::Ribbon => error + self.ribbon_warp(i, j) > tol,
                    Swept::Tube { .. } => error + self.tube_warp(i, j, &circle) > tol,
                    Swept::Stroke => false,
                };
            fails.then(|| loc(&segment, s, 0.5 * (ua + ub)))
        };
        let mut failing = Vec::new();
        for piece in pieces {
            failing.par_extend(
                piece
                    .par_windows(2)
                    .with_min_len(CELLS_PER_TASK)
                    .filter_map(|cell| failing_midpoint(cell[0], cell[1])),
            );
        }
        Ok(failing)
    }
}

/// How far the two triangles of the quad P00, P10, P11, P01 (in order around) and the
/// bilinear patch through its corners stray from each other: where the corners project onto
/// the plane through three of them as a convex quad, both lie in the tetrahedron of the four
/// and project onto that same quad, so each point of one is within the tetrahedron's height
/// over that plane of a point of the other; otherwise a quarter of the patch's twist
/// |P11 − P10 − P01 + P00| (the bilinear patch minus the triangles' interpolant is −y(1 − x)
/// times it).
fn quad_warp(quad: [Vec3; 4]) -> f64 {
    let sub = |a: Vec3, b: Vec3| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let twist = sub(sub(quad[2], quad[1]), sub(quad[3], quad[0]));
    let mut best = 0.25 * frames::dot(twist, twist).sqrt();
    for omit in 0..4 {
        let [a, b, c] = [1, 2, 3].map(|k| quad[(omit + k) % 4]);
        let Some(n) = frames::unit(frames::cross(sub(b, a), sub(c, a))) else {
            continue;
        };
        let Some(e1) = frames::unit(sub(b, a)) else {
            continue;
        };
        let e2 = frames::cross(n, e1);
        let flat = quad.map(|p| {
            let d = sub(p, a);
            [frames::dot(d, e1), frames::dot(d, e2)]
        });
        let turn = |k: usize| {
            let (p, q, r) = (flat[k], flat[(k + 1) % 4], flat[(k + 2) % 4]);
            (q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0])
        };
        let turns = [turn(0), turn(1), turn(2), turn(3)];
        let convex = turns.iter().all(|&x| x > 0.0) || turns.iter().all(|&x| x < 0.0);
        if convex {
            best = best.min(frames::dot(sub(quad[omit], a), n).abs());
        }
    }
    best
}

/// The tolerance places of a whole curve's widened `table`: every segment from u = 0, cut
/// into cells that pass for `swept` at `tol` with the frames' slope bounded a priori by
/// `slope` (per unit u, for each segment), then the end of the range.
///
/// # Errors
/// More than `limit` places ("sampling"), or a cell that cannot be certified however small
/// ("tolerance": the curve's speed vanishes there, or a tube's sides leave no room).
pub(crate) fn places(
    table: &SegmentTable,
    tol: f64,
    swept: Swept,
    slope: impl Fn(&CellBounds, f64) -> f64,
    limit: usize,
) -> Result<Vec<SampleLoc>, InputError> {
    let mut locs = Vec::new();
    // The intervals still to place, one segment's at a time.
    let mut stack = Vec::new();
    for s in 0..table.len() {
        let segment = table.segment(s);
        stack.push((0.0f64, 1.0f64));
        while let Some((ua, ub)) = stack.pop() {
            let width = ub - ua;
            // The interval's bounds hold on each of its cells: the fewest equal cells that
            // pass under them, up to CELLS_PER_BOUND.
            let bounds = CellBounds::of(&segment, ua, ub);
            let error = |n: usize| {
                let h = width / n as f64;
                bounds.map_or(f64::INFINITY, |b| b.error(swept, h, slope(&b, h)))
            };
            if let Some(n) = (1..=CELLS_PER_BOUND).find(|&n| error(n) <= tol) {
                for i in 0..n {
                    locs.push(loc(&segment, s, ua + width * i as f64 / n as f64));
                }
                if locs.len() > limit {
                    return Err(too_many(limit));
                }
                continue;
            }
            if width < SMALLEST_CELL {
                return Err(uncertified(
                    &segment,
                    ua,
                    swept,
                    tol,
                    error(CELLS_PER_BOUND),
                ));
            }
            // Each part about CELLS_PER_BOUND cells, as the error falls with h² once the bounds
            // are tight; while a loose bound (a speed near 0 at this width) inflates it,
            // cutting in many would overshoot: at most 8 parts.
            let most = error(CELLS_PER_BOUND);
            let parts = if most.is_finite() {
                (most / tol).sqrt().ceil().clamp(2.0, 8.0) as usize
            } else {
                2
            };
            if locs.len() + stack.len() + parts > 4 * limit {
                return Err(too_many(limit));
            }
            for i in (0..parts).rev() {
                let (a, b) = (i as f64 / parts as f64, (i + 1) as f64 / parts as f64);
                stack.push((
                    ua + a * width,
                    if i + 1 == parts { ub } else { ua + b * width },
                ));
            }
        }
    }
    let last = table.len() - 1;
    locs.push(loc(&table.segment(last), last, 1.0));
    if locs.len() > limit {
        return Err(too_many(limit));
    }
    Ok(locs)
}

fn loc(segment: &Segment<'_>, s: usize, u: f64) -> SampleLoc {
    SampleLoc {
        segment: s,
        u,
        t: segment.t0() + u * segment.dt(),
    }
}

fn too_many(limit: usize) -> InputError {
    InputError::field(
        "sampling",
        format!("tolerance places more than {limit} cross-sections"),
    )
}

/// A cell at `u` of `segment` that still fails as narrow as f64 cuts it, whose error bound
/// there is `finest`: where that bound has shrunk with the cell to a trace of the segment's
/// size (its speed's and width's bounds), the tolerance is below what f64 cells can reach;
/// where it has not, the speed vanishes there (or a tube's sides leave the rings no room).
fn uncertified(segment: &Segment<'_>, u: f64, swept: Swept, tol: f64, finest: f64) -> InputError {
    let t = segment.t0() + u * segment.dt();
    let size = CellBounds::of(segment, 0.0, 1.0).map_or(f64::NAN, |b| b.v_hi + b.w_max);
    let why = if finest <= 1e-9 * size {
        format!(
            "cells as narrow as f64 cuts them there still stray up to {} from the exact shape, \
             more than the tolerance {} (use a larger tolerance)",
            Shown(finest),
            Shown(tol)
        )
    } else {
        let sides = match swept {
            Swept::Tube { sides, .. } => {
                format!(", or {sides} sides leave the rings no room within it")
            }
            _ => String::new(),
        };
        format!("the curve's speed vanishes there{sides} (use per_segment or arc_length sampling)")
    };
    InputError::field(
        "tolerance",
        format!("cannot be certified near t = {t}: {why}"),
    )
}

/// The fewest sides that leave half of `tol` to the rings: r_max (1 − cos(π/s)) <= tol/2,
/// at least 3.
pub(crate) fn default_sides(r_max: f64, tol: f64) -> u32 {
    let ratio = tol / (2.0 * r_max);
    if ratio.is_nan() || ratio >= 2.0 {
        return 3;
    }
    let alpha = (1.0 - ratio).acos();
    let sides = (std::f64::consts::PI / alpha).ceil();
    if sides.is_finite() {
        sides.clamp(3.0, f64::from(u32::MAX)) as u32
    } else {
        u32::MAX
    }
}

/// The largest width anywhere on the widened table: the largest of its control values (a
/// rational segment's weights are positive, so its width is a convex combination of them).
pub(crate) fn largest_width(table: &SegmentTable) -> f64 {
    let dim = table.dim();
    (0..table.len())
        .flat_map(|s| {
            let (points, _) = table.segment(s).rational_bezier();
            points.into_iter().map(move |p| p[dim - 1])
        })
        .fold(0.0, f64::max)
}

/// The fewest chords of a round join or cap of turn `theta` and radius `radius` whose
/// sagitta radius (1 − cos(β/2)), β the chord's turn, is within `tol`: ceil(θ / β), at
/// least 1.
pub(crate) fn round_chords(theta: f64, radius: f64, tol: f64) -> u32 {
    if radius <= 0.0 || tol >= 2.0 * radius {
        return 1;
    }
    let beta = 2.0 * (1.0 - tol / radius).acos();
    (theta / beta).ceil().clamp(1.0, f64::from(u32::MAX)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::support::Rng;
    use crate::{Curve, CurveKind, EndCondition};

    /// Random 4-D curves (3 coordinates and a width): natural splines on uneven knots and
    /// weighted NURBS.
    fn tables(rng: &mut Rng) -> Vec<SegmentTable> {
        let mut out = Vec::new();
        for _ in 0..6 {
            let points = rng.points(6, 4, -2.0, 2.0);
            let mut t = vec![0.0];
            for _ in 1..6 {
                t.push(t[t.len() - 1] + rng.range(0.01, 3.0));
            }
            let natural = CurveKind::Interpolating {
                condition: EndCondition::Natural,
                t: Some(t),
            };
            out.push(Curve::new(natural, points.clone()).unwrap().fit());
            let nurbs = CurveKind::Nurbs {
                knots: vec![0.0, 0.0, 0.0, 0.0, 0.4, 0.7, 1.0, 1.0, 1.0, 1.0],
                weights: Some((0..6).map(|_| rng.range(0.2, 5.0)).collect()),
            };
            out.push(Curve::new(nurbs, points).unwrap().fit());
        }
        out
    }

    /// A polynomial segment's bounds are the general path's bit for bit (the general path
    /// with W ≡ 1 as a rational segment's would take it).
    #[test]
    fn polynomial_bounds_are_the_general_paths() {
        let mut rng = Rng(91);
        for table in tables(&mut rng) {
            for s in 0..table.len() {
                let segment = table.segment(s);
                if segment.denominator().is_some() {
                    continue;
                }
                for (ua, ub) in [(0.0, 1.0), (0.25, 0.5), (0.9, 0.95), (0.0, 1e-9)] {
                    let (m, rho) = (0.5 * (ua + ub), 0.5 * (ub - ua));
                    let general = CellBounds::general(&segment, m, rho).unwrap();
                    let polynomial = CellBounds::of(&segment, ua, ub).unwrap();
                    let bits = |b: CellBounds| {
                        [b.k2, b.k3, b.v_lo, b.v_hi, b.w_max, b.w_lo, b.w1, b.w2].map(f64::to_bits)
                    };
                    assert_eq!(bits(general), bits(polynomial), "segment {s} [{ua}, {ub}]");
                }
            }
        }
    }

    /// Every bound holds against the values on a dense grid of the cell (derivatives in u).
    #[test]
    fn cell_bounds_hold_on_polynomial_and_rational_segments() {
        let mut rng = Rng(47);
        let mut checked = 0;
        for table in tables(&mut rng) {
            for s in 0..table.len() {
                let segment = table.segment(s);
                let dt = segment.dt();
                for _ in 0..8 {
                    let (a, b) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
                    let (ua, ub) = (a.min(b), a.max(b));
                    let Some(bounds) = CellBounds::of(&segment, ua, ub) else {
                        continue;
                    };
                    checked += 1;
                    let mut d = [[0.0; 4]; 4];
                    for i in 0..=200 {
                        let u = ua + (ub - ua) * f64::from(i) / 200.0;
                        for (order, out) in d.iter_mut().enumerate() {
                            segment.derivative_into(order, u, out);
                            let scale = dt.powi(order as i32);
                            out.iter_mut().for_each(|x| *x *= scale);
                        }
                        let norm = |v: &[f64; 4]| v[..3].iter().map(|x| x * x).sum::<f64>().sqrt();
                        let slack = 1e-9 * (1.0 + bounds.k2 + bounds.k3 + bounds.v_hi);
                        assert!(norm(&d[2]) <= bounds.k2 + slack, "K2 {bounds:?}");
                        assert!(norm(&d[3]) <= bounds.k3 + slack, "K3 {bounds:?}");
                        assert!(norm(&d[1]) >= bounds.v_lo - slack, "v_lo {bounds:?}");
                        assert!(norm(&d[1]) <= bounds.v_hi + slack, "v_hi {bounds:?}");
                        let w = d[0][3];
                        assert!(w.abs() <= bounds.w_max + slack && w >= bounds.w_lo - slack);
                        assert!(d[1][3].abs() <= bounds.w1 + slack, "w1 {bounds:?}");
                        assert!(d[2][3].abs() <= bounds.w2 + slack, "w2 {bounds:?}");
                    }
                }
            }
        }
        assert!(checked > 300, "{checked} cells checked");
    }

    #[test]
    fn round_chords_are_the_fewest_within_the_sagitta() {
        for (theta, radius, tol) in [(PI, 1.0, 1e-3), (1.0, 0.5, 1e-4), (2.5, 3.0, 0.01)] {
            let c = round_chords(theta, radius, tol);
            let sagitta = |c: u32| radius * (1.0 - (theta / f64::from(c) / 2.0).cos());
            assert!(sagitta(c) <= tol && sagitta(c - 1) > tol, "{c} chords");
        }
        // A tolerance beyond the diameter, or no radius: one chord.
        assert_eq!(round_chords(PI, 1.0, 2.0), 1);
        assert_eq!(round_chords(PI, 0.0, 1e-3), 1);
    }

    #[test]
    fn default_sides_leave_half_the_tolerance_to_the_rings() {
        for (r, tol) in [(1.0, 1e-3), (0.05, 1e-4), (2.0, 0.3)] {
            let s = default_sides(r, tol);
            let sagitta = |s: u32| r * (1.0 - (PI / f64::from(s)).cos());
            assert!(sagitta(s) <= tol / 2.0 && (s == 3 || sagitta(s - 1) > tol / 2.0));
        }
        assert_eq!(default_sides(1.0, 10.0), 3);
    }

    use std::f64::consts::PI;
}
