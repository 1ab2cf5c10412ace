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
//! # Watertight
//!
//! A finer grid than a patch's counts still meets tol, so neighbours agree on one count along
//! every shared edge: on a net, the patches of a row of patches take the largest n_u of the
//! row and those of a column the largest n_v (the mesh is then one grid, as per_segment's);
//! on a patch list, the directions joined by shared edges (the same four control indices) form
//! classes, by union-find, each taking its members' largest count. The vertices of a shared
//! edge are then made once ([`welded`]): bit-identical, and no T-junctions.

use crate::error::InputError;
use crate::surface::mesh::{SurfacePlan, grid, welded};
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
        if !(tol.is_finite() && tol > 0.0) {
            return Err(InputError::field(
                "tolerance",
                format!("must be a finite number > 0, got {tol}"),
            ));
        }
        let counts = (0..table.len())
            .map(|p| patch_counts(&table.patch(p), tol).map_err(|e| at_patch(e, p)))
            .collect::<Result<Vec<_>, _>>()?;
        match (table.knots(), table.patch_indices()) {
            (Some(knots), _) => {
                let across = knots[1].len() - 1;
                let rows = knots[0].len() - 1;
                let ku: Vec<usize> = (0..rows)
                    .map(|i| {
                        (0..across)
                            .map(|j| counts[i * across + j][0])
                            .max()
                            .unwrap_or(1)
                    })
                    .collect();
                let kv: Vec<usize> = (0..across)
                    .map(|j| {
                        (0..rows)
                            .map(|i| counts[i * across + j][1])
                            .max()
                            .unwrap_or(1)
                    })
                    .collect();
                grid(knots, table.closed(), [&ku, &kv])
            }
            (None, Some(patches)) => welded(patches, &shared_counts(patches, &counts)),
            (None, None) => unreachable!("a table is a net or a patch list"),
        }
    }
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
    let [m_uu, m_uv, m_vv] = second_derivative_bounds(patch);
    let count = |m: f64| ((m / (4.0 * tol)).sqrt().ceil()).max(1.0);
    let (nu, nv) = (count(m_uu + m_uv), count(m_vv + m_uv));
    let vertices = (nu + 1.0) * (nv + 1.0);
    if vertices.is_nan() || vertices > MAX_PATCH_VERTICES as f64 {
        return Err(InputError::field(
            "sampling",
            format!(
                "needs {vertices} vertices on one patch at this tolerance, more than 2^20 \
                 ({nu} x {nv} cells)"
            ),
        ));
    }
    Ok([nu as usize, nv as usize])
}

/// Counts every patch of a list can share: the classes of directions joined by shared edges,
/// each its members' largest count.
fn shared_counts(patches: &[[usize; 16]], own: &[[usize; 2]]) -> Vec<[usize; 2]> {
    // Node 2p is patch p's u direction, 2p + 1 its v direction.
    let mut parent: Vec<usize> = (0..2 * patches.len()).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut first_seen = std::collections::HashMap::new();
    for (p, c) in patches.iter().enumerate() {
        // The edges u = 0 and u = 1 run along v; v = 0 and v = 1 along u.
        let edges = [
            ([c[0], c[1], c[2], c[3]], 2 * p + 1),
            ([c[12], c[13], c[14], c[15]], 2 * p + 1),
            ([c[0], c[4], c[8], c[12]], 2 * p),
            ([c[3], c[7], c[11], c[15]], 2 * p),
        ];
        for (mut indices, node) in edges {
            if indices.iter().all(|&i| i == indices[0]) {
                continue; // a collapsed edge joins nothing
            }
            let mut reversed = indices;
            reversed.reverse();
            if reversed < indices {
                indices = reversed;
            }
            let other = *first_seen.entry(indices).or_insert(node);
            let (a, b) = (root(&mut parent, node), root(&mut parent, other));
            parent[a] = b;
        }
    }
    let mut largest = vec![0usize; 2 * patches.len()];
    for (p, counts) in own.iter().enumerate() {
        for (d, &count) in counts.iter().enumerate() {
            let r = root(&mut parent, 2 * p + d);
            largest[r] = largest[r].max(count);
        }
    }
    (0..patches.len())
        .map(|p| [0, 1].map(|d| largest[root(&mut parent, 2 * p + d)]))
        .collect()
}

/// A bivariate polynomial of bidegree (du, dv) with `dim` values per coefficient, coefficient
/// (i, j) (of u^i v^j, or the Bernstein function B_i B_j) at `(i * (dv + 1) + j) * dim`.
#[derive(Clone, Debug)]
struct Poly {
    degree: [usize; 2],
    dim: usize,
    c: Vec<f64>,
}

impl Poly {
    fn zero(degree: [usize; 2], dim: usize) -> Self {
        Self {
            degree,
            dim,
            c: vec![0.0; (degree[0] + 1) * (degree[1] + 1) * dim],
        }
    }

    fn at(&self, i: usize, j: usize, k: usize) -> usize {
        (i * (self.degree[1] + 1) + j) * self.dim + k
    }

    /// A patch's power form (bidegree (3, 3)): `value(a, b, k)`.
    fn patch(value: impl Fn(usize, usize, usize) -> f64, dim: usize) -> Self {
        let mut p = Self::zero([3, 3], dim);
        for a in 0..4 {
            for b in 0..4 {
                for k in 0..dim {
                    let i = p.at(a, b, k);
                    p.c[i] = value(a, b, k);
                }
            }
        }
        p
    }

    /// The (ou, ov)-th partial derivative.
    fn derivative(&self, ou: usize, ov: usize) -> Self {
        let degree = [
            self.degree[0].saturating_sub(ou),
            self.degree[1].saturating_sub(ov),
        ];
        let mut out = Self::zero(degree, self.dim);
        let falling = |a: usize, m: usize| (0..m).map(|i| (a - i) as f64).product::<f64>();
        for a in ou..=self.degree[0] {
            for b in ov..=self.degree[1] {
                let f = falling(a, ou) * falling(b, ov);
                for k in 0..self.dim {
                    let i = out.at(a - ou, b - ov, k);
                    out.c[i] = f * self.c[self.at(a, b, k)];
                }
            }
        }
        out
    }

    /// The product with a scalar polynomial `w`.
    fn times(&self, w: &Poly) -> Self {
        let degree = [self.degree[0] + w.degree[0], self.degree[1] + w.degree[1]];
        let mut out = Self::zero(degree, self.dim);
        for a in 0..=self.degree[0] {
            for b in 0..=self.degree[1] {
                for c in 0..=w.degree[0] {
                    for d in 0..=w.degree[1] {
                        let f = w.c[w.at(c, d, 0)];
                        for k in 0..self.dim {
                            let i = out.at(a + c, b + d, k);
                            out.c[i] += f * self.c[self.at(a, b, k)];
                        }
                    }
                }
            }
        }
        out
    }

    /// `self − f · other`, at the larger bidegree.
    fn minus(&self, f: f64, other: &Poly) -> Self {
        let degree = [0, 1].map(|d| self.degree[d].max(other.degree[d]));
        let mut out = Self::zero(degree, self.dim);
        for (p, sign) in [(self, 1.0), (other, -f)] {
            for a in 0..=p.degree[0] {
                for b in 0..=p.degree[1] {
                    for k in 0..p.dim {
                        let i = out.at(a, b, k);
                        out.c[i] += sign * p.c[p.at(a, b, k)];
                    }
                }
            }
        }
        out
    }

    /// The same polynomial written at a higher bidegree (zero power coefficients above).
    fn padded(&self, degree: [usize; 2]) -> Self {
        self.minus(0.0, &Self::zero(degree, self.dim))
    }

    /// The same polynomial in the Bernstein basis of its bidegree:
    /// b_j = Σ_{k <= j} C(j, k) / C(m, k) c_k, along u and then along v.
    fn bernstein(&self) -> Self {
        let [du, dv] = self.degree;
        let binomial =
            |n: usize, k: usize| (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64);
        let mut along_u = Self::zero(self.degree, self.dim);
        for j in 0..=dv {
            for i in 0..=du {
                for m in 0..=i {
                    let w = binomial(i, m) / binomial(du, m);
                    for k in 0..self.dim {
                        let at = along_u.at(i, j, k);
                        along_u.c[at] += w * self.c[self.at(m, j, k)];
                    }
                }
            }
        }
        let mut out = Self::zero(self.degree, self.dim);
        for i in 0..=du {
            for j in 0..=dv {
                for m in 0..=j {
                    let w = binomial(j, m) / binomial(dv, m);
                    for k in 0..self.dim {
                        let at = out.at(i, j, k);
                        out.c[at] += w * along_u.c[along_u.at(i, m, k)];
                    }
                }
            }
        }
        out
    }

    /// The Euclidean norm of coefficient `n`.
    fn norm(&self, n: usize) -> f64 {
        self.c[n * self.dim..(n + 1) * self.dim]
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt()
    }

    /// The largest norm of the polynomial over [0, 1]², bounded by its Bernstein coefficients
    /// (their convex hull holds its values).
    fn bound(&self) -> f64 {
        let b = self.bernstein();
        (0..b.c.len() / b.dim)
            .map(|n| b.norm(n))
            .fold(0.0, f64::max)
    }

    /// A bound on the largest norm that tightens the Bernstein one: the largest of its values
    /// on a grid of `GRID` x `GRID`, plus how far it can rise between the nodes (every point is
    /// within h/2 of a node along each axis, h the spacing, and the partial derivatives are
    /// bounded by their own Bernstein coefficients).
    fn tight_bound(&self) -> f64 {
        let h = 1.0 / (GRID - 1) as f64;
        let mut sampled = 0.0f64;
        // Per node u: the coefficients of v, y_b = Σ_a u^a c_ab (Horner in u), then every
        // node v by Horner in v.
        let [du, dv] = self.degree;
        let mut y = vec![0.0; (dv + 1) * self.dim];
        for i in 0..GRID {
            let u = i as f64 * h;
            for b in 0..=dv {
                for k in 0..self.dim {
                    y[b * self.dim + k] = (0..=du)
                        .rev()
                        .fold(0.0, |x, a| x * u + self.c[self.at(a, b, k)]);
                }
            }
            for j in 0..GRID {
                let v = j as f64 * h;
                let square: f64 = (0..self.dim)
                    .map(|k| {
                        let x = (0..=dv).rev().fold(0.0, |x, b| x * v + y[b * self.dim + k]);
                        x * x
                    })
                    .sum();
                sampled = sampled.max(square.sqrt());
            }
        }
        let rise = h / 2.0 * (self.derivative(1, 0).bound() + self.derivative(0, 1).bound());
        self.bound().min(sampled + rise)
    }
}

/// Nodes per axis of [`Poly::tight_bound`]'s grid.
const GRID: usize = 9;

/// Proven bounds on max |S_uu|, |S_uv|, |S_vv| over the patch, in its local u, v.
///
/// A polynomial patch's are [`Poly::tight_bound`]s of its second derivatives. A rational
/// patch's second derivatives are quotients of polynomials, S_uu = (H_u W − 2 H W_u) / W³ with
/// H = Ñ_u W − Ñ W_u (S_u = H / W²), S_uv = (H_v W − 2 H W_v) / W³, and S_vv likewise with
/// K = Ñ_v W − Ñ W_v; numerator and W³ written in the Bernstein basis of one bidegree, the
/// quotient lies in the convex hull of the ratios of their coefficients (W's are > 0).
#[must_use]
pub(crate) fn second_derivative_bounds(patch: &Patch<'_>) -> [f64; 3] {
    let dim = patch.dim();
    let Some(w) = patch.denominator() else {
        let s = Poly::patch(|a, b, k| patch.coefficient(a, b)[k], dim);
        return [(2, 0), (1, 1), (0, 2)].map(|(ou, ov)| s.derivative(ou, ov).tight_bound());
    };
    // Ñ (the A_00 slot holds the origin O: Ñ's constant term is zero) and W.
    let n = Poly::patch(
        |a, b, k| {
            if a + b == 0 {
                0.0
            } else {
                patch.coefficient(a, b)[k]
            }
        },
        dim,
    );
    let w = Poly::patch(|a, b, _| w[4 * a + b], 1);
    let (w_u, w_v) = (w.derivative(1, 0), w.derivative(0, 1));
    let h = n.derivative(1, 0).times(&w).minus(1.0, &n.times(&w_u));
    let k = n.derivative(0, 1).times(&w).minus(1.0, &n.times(&w_v));
    let numerators = [
        h.derivative(1, 0).times(&w).minus(2.0, &h.times(&w_u)),
        h.derivative(0, 1).times(&w).minus(2.0, &h.times(&w_v)),
        k.derivative(0, 1).times(&w).minus(2.0, &k.times(&w_v)),
    ];
    let cube = w.times(&w).times(&w);
    let cube_b = cube.bernstein();
    numerators.map(|g| {
        let g = g.padded(cube.degree).bernstein();
        (0..cube_b.c.len())
            .map(|n| g.norm(n) / cube_b.c[n])
            .fold(0.0, f64::max)
    })
}
