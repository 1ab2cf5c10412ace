//! `PatchTable`: a fitted surface, every patch in power form, formed in f64.
//!
//! Patch p is S(u, v) = Σ_{a,b=0..3} A_ab u^a v^b in its local u, v in [0, 1]; A_ab is stored at
//! `(4a + b) · dim` of the patch's `16 · dim` values (a the power of u). A_00 = S(0, 0) is the
//! patch's origin and every other A_ab a difference of points, so nothing but A_00 grows with
//! the distance from the origin (the GPU's f32 promise rests on it).
//!
//! A rational patch (a weighted nurbs surface) is S = O + Ñ/W: W = Σ ω_ij N_i(u) N_j(v) the
//! denominator, its weights ω divided by the patch's smallest (so W >= 1 on the patch),
//! O = S(0, 0) in the A_00 slot, and Ñ = N − O·W the numerator relative to O (its constant term
//! zero), the same power layout.

use crate::basis::bezier_rows;
use crate::segment::SegmentTable;
use crate::surface::Net;
use crate::surface::direction::Direction;

/// A fitted surface: its patches in power form.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchTable {
    dim: usize,
    extent: f64,
    /// Per patch `16 · dim` values, A_ab at `(4a + b) · dim`.
    coeffs: Vec<f64>,
    /// Per patch of a rational surface: W's 16 power coefficients (b fastest) and ρ, the
    /// largest over the smallest of its 16 weights; empty for a polynomial surface.
    denominators: Vec<([f64; 16], f64)>,
    /// Per patch its derivative sizes s_u, s_v ([`Patch::derivative_sizes`]).
    sizes: Vec<[f64; 2]>,
    layout: Layout,
}

/// How the patches lie in the parameters.
#[derive(Clone, Debug, PartialEq)]
enum Layout {
    /// A net's patches, row-major (u outer): segment boundaries along u and v, and whether
    /// each direction closes on itself.
    Grid {
        knots: [Vec<f64>; 2],
        closed: [bool; 2],
    },
    /// A patch list: each patch on [0, 1]², its 16 control indices.
    List { patches: Vec<[usize; 16]> },
}

/// One patch of a table.
#[derive(Clone, Copy, Debug)]
pub struct Patch<'a> {
    coeffs: &'a [f64],
    dim: usize,
    /// s_u, s_v (formed with the table; zero while it is being formed).
    sizes: [f64; 2],
    /// The largest over the smallest of its 16 weights (1 without weights).
    rho: f64,
    /// Start and length of the patch's interval along u and along v.
    start: [f64; 2],
    length: [f64; 2],
    denominator: Option<&'a [f64; 16]>,
}

/// A patch's value and derivatives at one local (u, v), each `dim` values: S, S_u, S_v, S_uu,
/// S_uv, S_vv, in this order.
pub type Derivs = [Vec<f64>; 6];

/// A patch's evaluation stage at one u ([`Patch::contract_u`]), kept for the vertices that share
/// it.
#[derive(Clone, Debug, Default)]
pub(crate) struct AlongU {
    /// Orders of the u-weights formed (1 to 3).
    pub(crate) orders: usize,
    /// Σ_a w_m(a) A_ab at `(m * 4 + b) * dim`.
    pub(crate) c: Vec<f64>,
    /// W's, on a rational patch.
    pub(crate) w: [[f64; 4]; 3],
}

/// Values of a band's fit along v that [`PatchTable::from_directions`] holds at a time.
const BAND_VALUES: usize = 1 << 20;

impl PatchTable {
    /// A net's patches from its two directions' rules; `weights` (one per point) makes them
    /// rational.
    pub(crate) fn from_directions(
        net: &Net,
        directions: &[Direction; 2],
        weights: Option<&[f64]>,
    ) -> Self {
        let (rows, cols) = net.shape();
        let dim = net.dim();
        let extent = net.extent();
        // Homogeneous points (w P, w) where weighted.
        let width = dim + usize::from(weights.is_some());
        let lines: Vec<f64> = match weights {
            None => net.coords().to_vec(),
            Some(w) => net
                .coords()
                .chunks_exact(dim)
                .zip(w)
                .flat_map(|(p, &w)| p.iter().map(move |x| w * x).chain([w]))
                .collect(),
        };
        // Along u: the rows are the points of one curve of cols · width coordinates.
        let mut along_u = SegmentTable::default();
        directions[0].fit_lines(&lines, cols * width, extent, &mut along_u);
        drop(lines);
        let segments_u = along_u.len();
        let segments_v = directions[1].segments(cols);
        // Patch (iu, iv): A_ab, a = 3 − r (u), b = 3 − s (v).
        let mut coeffs = vec![0.0; segments_u * segments_v * 16 * dim];
        let mut denominators = Vec::new();
        let mut homogeneous = vec![0.0; 16 * width];
        // A weighted net's spans along u and v: patch (iu, iv) has the weights of rows
        // spans[0][iu] − 3 ..= spans[0][iu] and likewise columns.
        let spans = |d: &Direction, n: usize| match d {
            Direction::Knots { knots } => crate::fit::nurbs::spans(knots, n).collect(),
            _ => Vec::new(),
        };
        let spans: [Vec<usize>; 2] = [spans(&directions[0], rows), spans(&directions[1], cols)];
        // Along v, a band of u-segments at a time: column j's point holds the band's
        // u-segments' four coefficients. The fit is linear and coordinate by coordinate, so a
        // band's is the whole fit's, bit for bit, and memory holds one band's fit (about 2^20
        // values) beside the table rather than the whole net's four times over.
        let band = (BAND_VALUES / (16 * cols * width)).clamp(1, segments_u);
        let mut along_v = SegmentTable::default();
        let mut columns = Vec::new();
        for first in (0..segments_u).step_by(band) {
            let band = first..(first + band).min(segments_u);
            let stride = band.len() * 4 * width;
            columns.clear();
            columns.resize(cols * stride, 0.0);
            for iu in band.clone() {
                for (r, row) in along_u.segment(iu).power().iter().enumerate() {
                    for j in 0..cols {
                        let to = j * stride + ((iu - first) * 4 + r) * width;
                        columns[to..to + width].copy_from_slice(&row[j * width..(j + 1) * width]);
                    }
                }
            }
            directions[1].fit_lines(&columns, stride, extent, &mut along_v);
            for iu in band {
                for iv in 0..segments_v {
                    let segment = along_v.segment(iv);
                    let power = segment.power();
                    for (s, row) in power.iter().enumerate() {
                        for r in 0..4 {
                            let (a, b) = (3 - r, 3 - s);
                            let from = ((iu - first) * 4 + r) * width;
                            homogeneous[(4 * a + b) * width..][..width]
                                .copy_from_slice(&row[from..from + width]);
                        }
                    }
                    let out = &mut coeffs[(iu * segments_v + iv) * 16 * dim..][..16 * dim];
                    match weights {
                        None => out.copy_from_slice(&homogeneous),
                        Some(w) => {
                            let (su, sv) = (spans[0][iu], spans[1][iv]);
                            let (ru, rv) = (su - 3..=su, sv - 3..=sv);
                            let (mut least, mut most) = (f64::INFINITY, 0.0f64);
                            for i in ru {
                                for j in rv.clone() {
                                    least = least.min(w[i * cols + j]);
                                    most = most.max(w[i * cols + j]);
                                }
                            }
                            denominators.push(rational_patch(&homogeneous, dim, least, most, out));
                        }
                    }
                }
            }
        }
        Self::with_sizes(Self {
            dim,
            extent,
            coeffs,
            denominators,
            sizes: Vec::new(),
            layout: Layout::Grid {
                knots: [along_u.knots().to_vec(), along_v.knots().to_vec()],
                closed: [directions[0].is_closed(), directions[1].is_closed()],
            },
        })
    }

    /// The table with every patch's derivative sizes formed.
    fn with_sizes(mut self) -> Self {
        self.sizes = (0..self.len())
            .map(|p| self.patch(p).sizes_of_coefficients())
            .collect();
        self
    }

    /// A patch list's patches: each the Bezier patch of its 16 control points,
    /// A = M_B · B · M_Bᵀ with M_B the Bezier matrix.
    pub(crate) fn from_patch_list(net: &Net, patches: &[[usize; 16]]) -> Self {
        let dim = net.dim();
        let m = bezier_rows();
        let mut coeffs = vec![0.0; patches.len() * 16 * dim];
        for (patch, out) in patches.iter().zip(coeffs.chunks_exact_mut(16 * dim)) {
            for a in 0..4 {
                for b in 0..4 {
                    let to = &mut out[(4 * a + b) * dim..][..dim];
                    for i in 0..4 {
                        for j in 0..4 {
                            let weight = m[3 - a][i] * m[3 - b][j];
                            if weight != 0.0 {
                                let p = &net.coords()[patch[4 * i + j] * dim..][..dim];
                                for (t, x) in to.iter_mut().zip(p) {
                                    *t += weight * x;
                                }
                            }
                        }
                    }
                }
            }
        }
        Self::with_sizes(Self {
            dim,
            extent: net.extent(),
            coeffs,
            denominators: Vec::new(),
            sizes: Vec::new(),
            layout: Layout::List {
                patches: patches.to_vec(),
            },
        })
    }

    /// Coordinates per point.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of patches.
    #[must_use]
    pub fn len(&self) -> usize {
        self.coeffs.len() / (16 * self.dim)
    }

    /// True when the table holds no patch (never, for a fitted surface).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.coeffs.is_empty()
    }

    /// The extent E of the surface's points (the scale of the accuracy promise).
    #[must_use]
    pub fn extent(&self) -> f64 {
        self.extent
    }

    /// True for a weighted (rational) surface.
    #[must_use]
    pub fn is_rational(&self) -> bool {
        !self.denominators.is_empty()
    }

    /// A net's segment boundaries along u and along v (segments + 1 values each); `None` for a
    /// patch list.
    #[must_use]
    pub fn knots(&self) -> Option<[&[f64]; 2]> {
        match &self.layout {
            Layout::Grid { knots, .. } => Some([&knots[0], &knots[1]]),
            Layout::List { .. } => None,
        }
    }

    /// Whether each direction of a net closes on itself (closed ends, periodic condition).
    #[must_use]
    pub fn closed(&self) -> [bool; 2] {
        match &self.layout {
            Layout::Grid { closed, .. } => *closed,
            Layout::List { .. } => [false; 2],
        }
    }

    /// A patch list's control indices per patch; `None` for a net.
    #[must_use]
    pub fn patch_indices(&self) -> Option<&[[usize; 16]]> {
        match &self.layout {
            Layout::Grid { .. } => None,
            Layout::List { patches } => Some(patches),
        }
    }

    /// ρ of patch p: the largest over the smallest of its 16 weights (1 without weights).
    #[must_use]
    pub fn rho(&self, p: usize) -> f64 {
        self.denominators.get(p).map_or(1.0, |d| d.1)
    }

    /// Patch p (a net's patches row-major, u outer).
    ///
    /// # Panics
    /// If p is not a patch of the table.
    #[must_use]
    pub fn patch(&self, p: usize) -> Patch<'_> {
        let (start, length) = match &self.layout {
            Layout::Grid { knots, .. } => {
                let across = knots[1].len() - 1;
                let (iu, iv) = (p / across, p % across);
                (
                    [knots[0][iu], knots[1][iv]],
                    [
                        knots[0][iu + 1] - knots[0][iu],
                        knots[1][iv + 1] - knots[1][iv],
                    ],
                )
            }
            Layout::List { .. } => ([0.0; 2], [1.0; 2]),
        };
        Patch {
            coeffs: &self.coeffs[p * 16 * self.dim..][..16 * self.dim],
            dim: self.dim,
            sizes: self.sizes.get(p).copied().unwrap_or_default(),
            rho: self.rho(p),
            start,
            length,
            denominator: self.denominators.get(p).map(|d| &d.0),
        }
    }
}

/// Patch (A_ab of the homogeneous numerator and W, `dim + 1` values each) into its rational
/// form in `out`, the weights scaled by 1 / `least`; returns W's coefficients and ρ.
fn rational_patch(
    homogeneous: &[f64],
    dim: usize,
    least: f64,
    most: f64,
    out: &mut [f64],
) -> ([f64; 16], f64) {
    let width = dim + 1;
    let w: [f64; 16] = std::array::from_fn(|ab| homogeneous[ab * width + dim] / least);
    // O = N(0, 0) / W(0, 0).
    let origin: Vec<f64> = (0..dim).map(|k| homogeneous[k] / least / w[0]).collect();
    for ab in 0..16 {
        for k in 0..dim {
            out[ab * dim + k] = if ab == 0 {
                origin[k]
            } else {
                homogeneous[ab * width + k] / least - origin[k] * w[ab]
            };
        }
    }
    (w, most / least)
}

impl Patch<'_> {
    /// Coordinates per point.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// All 16 A_ab, `dim` values each, A_ab at `(4a + b) · dim` (see
    /// [`Patch::coefficient`]).
    #[must_use]
    pub fn coefficients(&self) -> &[f64] {
        self.coeffs
    }

    /// The power coefficient vector A_ab (`dim` values): of a rational patch, its relative
    /// numerator's (A_00: its origin O).
    #[must_use]
    pub fn coefficient(&self, a: usize, b: usize) -> &[f64] {
        &self.coeffs[(4 * a + b) * self.dim..][..self.dim]
    }

    /// The denominator's 16 power coefficients W_ab at 4a + b, for a rational patch.
    #[must_use]
    pub fn denominator(&self) -> Option<&[f64; 16]> {
        self.denominator
    }

    /// ρ: the largest over the smallest of the patch's 16 weights (1 without weights).
    #[must_use]
    pub fn rho(&self) -> f64 {
        self.rho
    }

    /// The start of the patch's interval along u and along v (a patch list's: 0).
    #[must_use]
    pub fn start(&self) -> [f64; 2] {
        self.start
    }

    /// The patch's lengths Δu, Δv in the surface's parameters (a patch list's: 1).
    #[must_use]
    pub fn length(&self) -> [f64; 2] {
        self.length
    }

    /// S and its derivatives in the patch's local u, v (d/du on [0, 1], not the surface's
    /// parameter) into `out` (`dim` values each).
    pub fn local_derivatives(&self, u: f64, v: f64, out: &mut Derivs) {
        let mut along = AlongU::default();
        self.contract_u(u, 3, &mut along);
        self.finish_v(&along, v, 6, out);
    }

    /// The first stage of an evaluation at u: for the u-weights of orders 0 .. `orders`
    /// (u^a, then its first and second derivatives) and each power b of v, Σ_a w(a) A_ab (the
    /// origin's term A_00 left out), and W's likewise on a rational patch. Vertices that share
    /// a patch and a u (a grid's rows) share it: a vertex then costs 4 terms, not 16.
    pub(crate) fn contract_u(&self, u: f64, orders: usize, along: &mut AlongU) {
        let weights = [
            [1.0, u, u * u, u * u * u],
            [0.0, 1.0, 2.0 * u, 3.0 * u * u],
            [0.0, 0.0, 2.0, 6.0 * u],
        ];
        let dim = self.dim;
        along.c.clear();
        along.c.resize(orders * 4 * dim, 0.0);
        for (m, w) in weights.iter().enumerate().take(orders) {
            for b in 0..4 {
                let to = &mut along.c[(m * 4 + b) * dim..][..dim];
                for (a, &wa) in w.iter().enumerate() {
                    if a + b == 0 || wa == 0.0 {
                        continue;
                    }
                    let from = &self.coeffs[(4 * a + b) * dim..][..dim];
                    for (t, x) in to.iter_mut().zip(from) {
                        *t += wa * x;
                    }
                }
            }
        }
        if let Some(den) = self.denominator {
            for (m, w) in weights.iter().enumerate().take(orders) {
                for b in 0..4 {
                    along.w[m][b] = (0..4).map(|a| w[a] * den[4 * a + b]).sum();
                }
            }
        }
        along.orders = orders;
    }

    /// The second stage at v: S, S_u, S_v, S_uu, S_uv, S_vv (the first `planes` of them: 1, 3
    /// or 6; the u-stage must have orders 1, 2 or 3 for them) into `out`, in local u, v.
    #[expect(
        clippy::needless_range_loop,
        reason = "k indexes the six planes' coordinate in step, as the quotient rule is written"
    )]
    pub(crate) fn finish_v(&self, along: &AlongU, v: f64, planes: usize, out: &mut Derivs) {
        let dim = self.dim;
        let weights = [
            [1.0, v, v * v, v * v * v],
            [0.0, 1.0, 2.0 * v, 3.0 * v * v],
            [0.0, 0.0, 2.0, 6.0 * v],
        ];
        // Plane m: u-order, v-order.
        const ORDERS: [(usize, usize); 6] = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)];
        for (m, &(ou, ov)) in ORDERS.iter().enumerate().take(planes) {
            let o = &mut out[m];
            o.clear();
            o.resize(dim, 0.0);
            for (b, &wb) in weights[ov].iter().enumerate() {
                if wb == 0.0 {
                    continue;
                }
                let from = &along.c[(ou * 4 + b) * dim..][..dim];
                for (t, x) in o.iter_mut().zip(from) {
                    *t += wb * x;
                }
            }
        }
        match self.denominator {
            None => {
                for (t, x) in out[0].iter_mut().zip(&self.coeffs[..dim]) {
                    *t += x;
                }
            }
            Some(_) => {
                // S = O + R, R = Ñ / W: the quotient rule on each derivative.
                let w: [f64; 6] = std::array::from_fn(|m| {
                    let (ou, ov) = ORDERS[m];
                    if m >= planes {
                        return 0.0;
                    }
                    (0..4).map(|b| weights[ov][b] * along.w[ou][b]).sum()
                });
                for k in 0..dim {
                    let n: [f64; 6] =
                        std::array::from_fn(|m| if m < planes { out[m][k] } else { 0.0 });
                    let r = n[0] / w[0];
                    out[0][k] = self.coeffs[k] + r;
                    if planes >= 3 {
                        let ru = (n[1] - r * w[1]) / w[0];
                        let rv = (n[2] - r * w[2]) / w[0];
                        out[1][k] = ru;
                        out[2][k] = rv;
                        if planes >= 6 {
                            out[3][k] = (n[3] - 2.0 * ru * w[1] - r * w[3]) / w[0];
                            out[4][k] = (n[4] - ru * w[2] - rv * w[1] - r * w[4]) / w[0];
                            out[5][k] = (n[5] - 2.0 * rv * w[2] - r * w[5]) / w[0];
                        }
                    }
                }
            }
        }
    }

    /// What turns local derivatives (S, S_u, S_v, S_uu, S_uv, S_vv) into derivatives in the
    /// surface's parameters: 1, 1/Δu, 1/Δv, 1/Δu², 1/(Δu Δv), 1/Δv².
    #[must_use]
    pub fn parameter_scales(&self) -> [f64; 6] {
        let [lu, lv] = self.length;
        [
            1.0,
            1.0 / lu,
            1.0 / lv,
            1.0 / (lu * lu),
            1.0 / (lu * lv),
            1.0 / (lv * lv),
        ]
    }

    /// S and its derivatives with respect to the surface's parameters (d/du = local d/du
    /// divided by Δu) at local (u, v) into `out`.
    pub fn derivatives(&self, u: f64, v: f64, out: &mut Derivs) {
        self.local_derivatives(u, v, out);
        for (o, s) in out.iter_mut().zip(self.parameter_scales()).skip(1) {
            for x in o.iter_mut() {
                *x *= s;
            }
        }
    }

    /// Proven bounds on the largest |S_uu|, |S_uv|, |S_vv| over the patch, in its local u, v:
    /// the tolerance mesher's M_uu, M_uv, M_vv (see [`SurfacePlan::tolerance`]).
    ///
    /// [`SurfacePlan::tolerance`]: crate::surface::SurfacePlan::tolerance
    #[must_use]
    pub fn second_derivative_bounds(&self) -> [f64; 3] {
        let coefficient = |a: usize, b: usize, k: usize| self.coefficient(a, b)[k];
        super::bounds::second_derivative_bounds(self.dim(), coefficient, self.denominator())
    }

    /// The patch's derivative sizes s_u, s_v (contract, "Surfaces"): the Euclidean norms over
    /// coordinates of Σ_ab a |A_ab| and of Σ_ab b |A_ab|, in local u, v.
    #[must_use]
    pub fn derivative_sizes(&self) -> [f64; 2] {
        self.sizes
    }

    /// [`Patch::derivative_sizes`] from the coefficients.
    fn sizes_of_coefficients(&self) -> [f64; 2] {
        let mut sizes = [0.0; 2];
        for k in 0..self.dim {
            let (mut su, mut sv) = (0.0, 0.0);
            for a in 0..4 {
                for b in 0..4 {
                    let x = self.coeffs[(4 * a + b) * self.dim + k].abs();
                    if a + b > 0 {
                        su += a as f64 * x;
                        sv += b as f64 * x;
                    }
                }
            }
            sizes[0] += su * su;
            sizes[1] += sv * sv;
        }
        sizes.map(f64::sqrt)
    }
}
