//! Proven bounds on a bicubic patch's second derivatives over [0, 1]², the certificate the
//! tolerance mesher counts its vertices from: the convex hull of a polynomial's Bernstein
//! coefficients holds its values, tightened by a sampled grid and the rise between its nodes;
//! a rational patch's second derivatives are quotients whose hull is the ratios'
//! (docs/input-format.md, a surface's "tolerance"). A leaf module: it takes a patch's power
//! coefficients, not the patch.

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
///
/// The patch is given as its power coefficients, `coefficient(a, b, k)` = A_ab's k-th
/// coordinate (A_00 holding a rational patch's origin, which the bound does not use), and its
/// denominator's 16 power coefficients W_ab at `4a + b`, if rational.
#[must_use]
pub(crate) fn second_derivative_bounds(
    dim: usize,
    coefficient: impl Fn(usize, usize, usize) -> f64,
    denominator: Option<&[f64; 16]>,
) -> [f64; 3] {
    let Some(w) = denominator else {
        let s = Poly::patch(coefficient, dim);
        return [(2, 0), (1, 1), (0, 2)].map(|(ou, ov)| s.derivative(ou, ov).tight_bound());
    };
    // Ñ (the A_00 slot holds the origin O: Ñ's constant term is zero) and W.
    let n = Poly::patch(
        |a, b, k| {
            if a + b == 0 {
                0.0
            } else {
                coefficient(a, b, k)
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
