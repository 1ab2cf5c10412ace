//! A patch as Bernstein nets relative to its origin, for the surface queries: the homogeneous
//! control points (ω Q, ω) of any rectangle of it by de Casteljau, and a lower bound of the
//! squared distance to it from the Bernstein coefficients of its numerator and denominator.
//!
//! A patch is S(u, v) = O + N(u, v) / W(u, v) (W ≡ 1 on a polynomial patch; W > 0, its
//! Bernstein coefficients the normalised weights), N and W bicubic. In the Bernstein basis on a
//! rectangle, N_k = Σ n_ij B_i(u) B_j(v) and W = Σ w_ij B_i B_j; the rectangle of the patch lies
//! in the convex hull of the points O + n_ij / w_ij (w_ij > 0).

use crate::surface::Patch;

/// A rectangle of a patch: its homogeneous Bernstein net, `dim + 1` values per control point
/// (N's coordinates, then W), i fastest along v: point (i, j) at `(4 i + j) (dim + 1)`.
#[derive(Clone, Debug)]
pub(crate) struct Net {
    pub(crate) values: Vec<f64>,
    pub(crate) dim: usize,
}

/// A patch's origin O and its whole net.
pub(crate) fn patch_net(patch: &Patch<'_>) -> (Vec<f64>, Net) {
    let dim = patch.dim();
    let width = dim + 1;
    let origin = patch.coefficient(0, 0).to_vec();
    // Power coefficients (relative numerator, then W), a the power of u.
    let mut power = vec![0.0; 16 * width];
    for a in 0..4 {
        for b in 0..4 {
            let at = (4 * a + b) * width;
            if (a, b) != (0, 0) {
                power[at..at + dim].copy_from_slice(patch.coefficient(a, b));
            }
            power[at + dim] = patch
                .denominator()
                .map_or(if (a, b) == (0, 0) { 1.0 } else { 0.0 }, |w| w[4 * a + b]);
        }
    }
    // Power to Bernstein in each direction: b_i = Σ_{j <= i} C(i, j) / C(3, j) a_j.
    const TO_BERNSTEIN: [[f64; 4]; 4] = [
        [1.0, 0.0, 0.0, 0.0],
        [1.0, 1.0 / 3.0, 0.0, 0.0],
        [1.0, 2.0 / 3.0, 1.0 / 3.0, 0.0],
        [1.0, 1.0, 1.0, 1.0],
    ];
    let mut values = vec![0.0; 16 * width];
    for i in 0..4 {
        for j in 0..4 {
            for a in 0..=i {
                for b in 0..=j {
                    let m = TO_BERNSTEIN[i][a] * TO_BERNSTEIN[j][b];
                    for k in 0..width {
                        values[(4 * i + j) * width + k] += m * power[(4 * a + b) * width + k];
                    }
                }
            }
        }
    }
    (origin, Net { values, dim })
}

impl Net {
    fn width(&self) -> usize {
        self.dim + 1
    }

    /// The net of the rectangle [u0, u1] x [v0, v1] of this net's rectangle (in its own
    /// [0, 1]² parameters), by de Casteljau along u and then along v.
    pub(crate) fn part(&self, [u0, u1]: [f64; 2], [v0, v1]: [f64; 2]) -> Self {
        let width = self.width();
        let mut values = self.values.clone();
        // Along u: the four points (i = 0..3) of each column; along v, of each row.
        for (along_u, (lo, hi)) in [(true, (u0, u1)), (false, (v0, v1))] {
            let index = |i: usize, line: usize, k: usize| {
                let (row, column) = if along_u { (i, line) } else { (line, i) };
                (4 * row + column) * width + k
            };
            for line in 0..4 {
                for k in 0..width {
                    let mut p: [f64; 4] = std::array::from_fn(|i| values[index(i, line, k)]);
                    p = restrict(p, lo, hi);
                    for (i, x) in p.into_iter().enumerate() {
                        values[index(i, line, k)] = x;
                    }
                }
            }
        }
        Self {
            values,
            dim: self.dim,
        }
    }

    /// The projected control points relative to the origin, n_ij / w_ij, for each (i, j).
    pub(crate) fn projected(&self) -> impl Iterator<Item = impl Iterator<Item = f64> + '_> + '_ {
        (0..16).map(move |ij| {
            let p = &self.values[ij * self.width()..][..self.width()];
            let w = p[self.dim];
            p[..self.dim].iter().map(move |x| x / w)
        })
    }

    /// A lower bound of |S − q|² on this rectangle (r = q − O): the least ratio a_ij / c_ij of
    /// the Bernstein coefficients (degree 6 in each direction) of |N − r W|² and of W². As
    /// every c_ij > 0, |S − q|² = Σ a_ij B_ij / Σ c_ij B_ij is a convex combination of those
    /// ratios; the coefficients approach the polynomials' values quadratically as the
    /// rectangle shrinks, and so does the bound.
    pub(crate) fn lower_bound(&self, r: &[f64]) -> f64 {
        let width = self.width();
        // e_k = n_k − r_k w per control point, and w.
        let mut e = [0.0; 16 * (crate::MAX_DIM + 1)];
        for ij in 0..16 {
            let p = &self.values[ij * width..][..width];
            let w = p[self.dim];
            for k in 0..self.dim {
                e[ij * width + k] = p[k] - r[k] * w;
            }
            e[ij * width + self.dim] = w;
        }
        // Products of Bernstein polynomials: B_a B_c = C(3,a) C(3,c) / C(6,a+c) B_{a+c}.
        const PRODUCT: [[f64; 4]; 4] = [
            [1.0, 0.5, 0.2, 0.05],
            [0.5, 0.6, 0.45, 0.2],
            [0.2, 0.45, 0.6, 0.5],
            [0.05, 0.2, 0.5, 1.0],
        ];
        let (mut squares, mut weights) = ([0.0f64; 49], [0.0f64; 49]);
        for a in 0..4 {
            for b in 0..4 {
                let x = &e[(4 * a + b) * width..][..width];
                for c in 0..4 {
                    for d in 0..4 {
                        let y = &e[(4 * c + d) * width..][..width];
                        let m = PRODUCT[a][c] * PRODUCT[b][d];
                        let at = 7 * (a + c) + b + d;
                        let dot: f64 = (0..self.dim).map(|k| x[k] * y[k]).sum();
                        squares[at] += m * dot;
                        weights[at] += m * x[self.dim] * y[self.dim];
                    }
                }
            }
        }
        squares
            .iter()
            .zip(&weights)
            .map(|(a, c)| a / c)
            .fold(f64::INFINITY, f64::min)
    }
}

/// The cubic Bernstein coefficients `p` on [0, 1] restricted to [lo, hi] (de Casteljau: split
/// at hi, keep the left part, split that at lo / hi, keep the right part).
fn restrict(p: [f64; 4], lo: f64, hi: f64) -> [f64; 4] {
    let split = |p: [f64; 4], at: f64| {
        let lerp = |a: f64, b: f64| a + at * (b - a);
        let (a, b, c) = (lerp(p[0], p[1]), lerp(p[1], p[2]), lerp(p[2], p[3]));
        let (d, e) = (lerp(a, b), lerp(b, c));
        let f = lerp(d, e);
        ([p[0], a, d, f], [f, e, c, p[3]])
    };
    let left = if hi < 1.0 { split(p, hi).0 } else { p };
    if lo > 0.0 {
        split(left, lo / hi).1
    } else {
        left
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Net as Points, Surface, SurfaceKind};

    /// A rational bicubic patch's net: its rectangles' projected points hold the surface there,
    /// and the lower bound is below every sampled |S − q|².
    #[test]
    fn parts_hold_their_rectangles_and_bound_the_distance() {
        let coords: Vec<f64> = (0..16)
            .flat_map(|ij| {
                let (i, j) = ((ij / 4) as f64, (ij % 4) as f64);
                [i, j, (i * 1.3 - j).sin() + 100.0]
            })
            .collect();
        let net = Points::new(3, 4, 4, coords).unwrap();
        let clamped = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let kind = SurfaceKind::Nurbs {
            knots_u: clamped.clone(),
            knots_v: clamped,
            weights: Some((0..16).map(|i| 1.0 + (i % 5) as f64).collect()),
        };
        let surface = Surface::new(kind, net).unwrap();
        let table = surface.fit();
        let patch = table.patch(0);
        let (origin, whole) = patch_net(&patch);
        let q = [1.2, 2.5, 101.0];
        let r: Vec<f64> = q.iter().zip(&origin).map(|(q, o)| q - o).collect();
        for (u, v) in [([0.0, 1.0], [0.0, 1.0]), ([0.25, 0.5], [0.6, 0.9])] {
            let part = whole.part(u, v);
            let mut least = f64::INFINITY;
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for p in part.projected() {
                for (k, x) in p.enumerate() {
                    lo[k] = lo[k].min(x);
                    hi[k] = hi[k].max(x);
                }
            }
            let mut d = crate::surface::Derivs::default();
            for a in 0..=10 {
                for b in 0..=10 {
                    let (uu, vv) = (
                        u[0] + (u[1] - u[0]) * a as f64 / 10.0,
                        v[0] + (v[1] - v[0]) * b as f64 / 10.0,
                    );
                    d.iter_mut().for_each(|x| x.resize(3, 0.0));
                    patch.local_derivatives(uu, vv, &mut d);
                    let mut g = 0.0;
                    for k in 0..3 {
                        let local = d[0][k] - origin[k];
                        assert!(local >= lo[k] - 1e-9 && local <= hi[k] + 1e-9);
                        g += (d[0][k] - q[k]).powi(2);
                    }
                    least = least.min(g);
                }
            }
            // The bound is below every sampled value.
            assert!(part.lower_bound(&r) <= least + 1e-9);
        }
    }
}
