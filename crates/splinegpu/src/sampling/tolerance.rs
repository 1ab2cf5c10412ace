//! Tolerance sampling: as few samples per segment as this method can guarantee, such that the
//! polyline through them stays within `tol` of the curve (contract: "tolerance").
//!
//! **Placement.** For a circle arc the distance from a chord of length h to the arc is about
//! κh²/8, so a chord is within tol when h·sqrt(κ) <= sqrt(8 tol). Placing samples so that each
//! interval carries an equal share of ∫ sqrt(κ) ds equidistributes the error (R. Levien,
//! "Flattening quadratic Béziers", 2019, and kurbo's `flatten`). In any dimension
//! sqrt(κ) ds = (G/Q)^(1/4) du with Q = |P'|², G = |P'|²|P''|² − (P'·P'')², that is
//! sqrt(|P''⊥|) du with P''⊥ the part of P'' normal to the tangent: no angles needed. The count
//! starts at ∫ (G/Q)^(1/4) du / sqrt(8 tol), and each u_k inverts the tabulated integral.
//!
//! **Guarantee.** The estimate is asymptotic, so every interval [u_a, u_b] is then checked with
//! a bound that holds exactly. Let e be the chord's direction and Δ = u_b − u_a. The residual
//! r(u) = (P(u) − P(u_a)) minus its component along e vanishes at both ends and r'' is the part
//! of P'' normal to e, an affine function of u, so |r| <= Δ²/8 · max(|P''⊥e(u_a)|, |P''⊥e(u_b)|).
//! That is the distance to the chord's line; it is the distance to the chord itself when the
//! curve's projection on e moves forward throughout (P'·e > 0 on the interval). Otherwise the
//! bound used is Δ²/8 · max |P''| over the interval, the interpolation bound that Wang's formula
//! rests on (|P(u) − L(u)| for the chord's linear interpolant L). Both bounds take the exact
//! shape of r (see `residual_bound`) rather than Δ²/8 · max |r''|. If an interval fails, the
//! count grows by an eighth and the placement is redone, and once a count passes, the counts
//! between it and the last that failed are bisected for the fewest that passes; at Wang's
//! count n_W =
//! max(1, ceil(sqrt(M/(8 tol)))), M = max |P''| on the segment, uniform placement always passes,
//! so the count never exceeds n_W. (Past 2^16 samples on a segment the search stops and n_W is
//! used at once.)
//!
//! **Rational segments** (a weighted NURBS, see [`rational`](crate::rational)): P'' is no
//! longer affine, so the chord check uses the interpolation bound h²/8 · M̂ throughout, with
//! M̂ a proven bound on max |P''| over the segment
//! ([`RationalCubic::second_derivative_bound`]: the largest |P''| on a grid plus the most it
//! can grow between grid points, refined until M̂ <= 2 max |P''|). Under that bound the
//! fewest samples that pass are uniform ones, so the segment gets Wang's count with M̂,
//! n_W = max(1, ceil(sqrt(M̂ / (8 tol)))), placed uniformly: at most about sqrt(2) times the
//! count with the true maximum (the contract allows 2x).

use crate::points::MAX_DIM;
use crate::rational::RationalCubic;
use crate::segment::Segment;

/// The most samples a segment may need: more is bad input.
pub const MAX_SAMPLES_PER_SEGMENT: u64 = 1 << 20;

/// Up to this many samples on a segment the placement is searched for the fewest that pass;
/// past it, Wang's uniform count is used at once (it always passes), so that a tolerance near
/// the limit costs no repeated checks of a million chords.
const SEARCHED_SAMPLES: u32 = 1 << 16;

/// Intervals of the tabulated placement integral.
const TABLE: usize = 32;

/// How a segment is sampled: `count` samples at u_0 = 0 < u_1 < ... (the next segment's first
/// sample, or the curve's final point, closes the last interval).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Placement {
    /// Samples on the segment (>= 1).
    pub count: u32,
    /// Uniform placement (u_k = k / count), used at Wang's count.
    pub uniform: bool,
    /// ∫ sqrt(|P''⊥|) du from 0 to k/32, k = 0..=32: u_j inverts it at j / count.
    integral: [f64; TABLE + 1],
}

/// A segment's cubic as plain vectors, for the bounds, divided by `1/inv` (a power of two
/// near its largest coefficient, so that squares neither overflow nor underflow); distances and
/// tolerances are measured in the same units.
struct Cubic<'a> {
    a: &'a [f64],
    b: &'a [f64],
    c: &'a [f64],
    inv: f64,
}

impl<'a> Cubic<'a> {
    fn of(segment: &'a Segment<'a>) -> Self {
        let [a, b, c, _] = segment.power();
        let largest = [a, b, c]
            .iter()
            .flat_map(|v| v.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let inv = 1.0 / crate::sampling::arc_length::power_of_two_near(largest);
        Self { a, b, c, inv }
    }

    /// A tolerance in the curve's units, in this cubic's.
    fn scaled(&self, tol: f64) -> f64 {
        tol * self.inv
    }

    fn dim(&self) -> usize {
        self.a.len()
    }

    /// P(u) − D, scaled: the constant term cancels in every difference taken here.
    fn point(&self, u: f64, k: usize) -> f64 {
        let inv = self.inv;
        crate::segment::position(self.a[k] * inv, self.b[k] * inv, self.c[k] * inv, 0.0, u)
    }

    fn d1(&self, u: f64, k: usize) -> f64 {
        (self.c[k] + u * (2.0 * self.b[k] + 3.0 * u * self.a[k])) * self.inv
    }

    fn d2(&self, u: f64, k: usize) -> f64 {
        (2.0 * self.b[k] + 6.0 * u * self.a[k]) * self.inv
    }

    /// max |P''| over [u_a, u_b]: P'' is affine, so its norm is largest at an end.
    fn max_d2(&self, ua: f64, ub: f64) -> f64 {
        let norm = |u: f64| (0..self.dim()).map(|k| self.d2(u, k).powi(2)).sum::<f64>();
        norm(ua).max(norm(ub)).sqrt()
    }

    /// sqrt(|P''⊥|) at u, the part of P'' normal to the tangent: (G/Q)^(1/4).
    fn density(&self, u: f64) -> f64 {
        let (mut q, mut dd, mut pd) = (0.0, 0.0, 0.0);
        for k in 0..self.dim() {
            let (p1, p2) = (self.d1(u, k), self.d2(u, k));
            q += p1 * p1;
            dd += p2 * p2;
            pd += p1 * p2;
        }
        // Where the speed vanishes, the whole of P'' counts.
        let normal = if q > 1e-24 * dd {
            (dd - pd * pd / q).max(0.0)
        } else {
            dd
        };
        let normal = if normal.is_finite() { normal } else { dd };
        normal.sqrt().sqrt()
    }

    /// A bound on the distance from the curve on [u_a, u_b] to the chord P(u_a)P(u_b) (see the
    /// module docs): it holds exactly, up to rounding.
    fn chord_bound(&self, ua: f64, ub: f64) -> f64 {
        // Scratch on the stack, sized for the common 1 to 4 coordinates where it can be:
        // zeroing MAX_DIM's worth on every interval checked costs more than the check.
        if self.dim() <= 4 {
            self.chord_bound_in::<4>(ua, ub)
        } else {
            self.chord_bound_in::<MAX_DIM>(ua, ub)
        }
    }

    /// [`Cubic::chord_bound`] with scratch for N >= dim coordinates.
    fn chord_bound_in<const N: usize>(&self, ua: f64, ub: f64) -> f64 {
        let dim = self.dim();
        let h = ub - ua;
        let mut d2 = [[0.0; N]; 2];
        let [at_a, at_b] = &mut d2;
        for (k, (a, b)) in at_a.iter_mut().zip(at_b.iter_mut()).enumerate().take(dim) {
            (*a, *b) = (self.d2(ua, k), self.d2(ub, k));
        }
        let full = residual_bound(&d2[0][..dim], &d2[1][..dim], h);
        // The chord's direction e, on the stack (this runs for every interval placed).
        let mut e = [0.0; N];
        for (k, v) in e.iter_mut().enumerate().take(dim) {
            *v = self.point(ub, k) - self.point(ua, k);
        }
        let len = e[..dim].iter().map(|v| v * v).sum::<f64>().sqrt();
        if len == 0.0 {
            return full;
        }
        for v in &mut e[..dim] {
            *v /= len;
        }
        // P'·e is a quadratic in u: forward throughout when positive at both ends and at its
        // vertex (if inside).
        let along = |u: f64| (0..dim).map(|k| self.d1(u, k) * e[k]).sum::<f64>();
        let (qa, qb) = (
            (0..dim).map(|k| 3.0 * self.a[k] * e[k]).sum::<f64>(),
            (0..dim).map(|k| 2.0 * self.b[k] * e[k]).sum::<f64>(),
        );
        let mut forward = along(ua) > 0.0 && along(ub) > 0.0;
        if qa != 0.0 {
            let vertex = -qb / (2.0 * qa);
            if vertex > ua && vertex < ub {
                forward &= along(vertex) > 0.0;
            }
        }
        if !forward {
            return full;
        }
        // The parts of P'' at the ends normal to e.
        for end in &mut d2 {
            let t: f64 = (0..dim).map(|k| end[k] * e[k]).sum();
            for k in 0..dim {
                end[k] -= t * e[k];
            }
        }
        residual_bound(&d2[0][..dim], &d2[1][..dim], h).min(full)
    }
}

/// Pieces of [0, 1] over which [`residual_bound`] bounds its two factors (16: within 12 % of
/// the largest |r|; 32 gave 0.1 % fewer samples on w1-tol).
const RESIDUAL_PIECES: usize = 16;

/// A bound on max |r| over an interval of width `h` in u, for r vanishing at both ends with r''
/// affine, α at the start and β at the end (vectors). In x = (u − u_a)/h,
/// r(x) = −h²/6 · x(1−x) · (α(2−x) + β(1+x)), so |r| is at most h²/6 times the largest, over
/// sixteen pieces of [0, 1], of the largest x(1−x) on the piece (a parabola) times the largest
/// |α(2−x) + β(1+x)| on it (a norm of an affine function: convex, so largest at an end). Never
/// more than h²/8 · max(|α|, |β|) (Wang's form), and up to half of it where α and β differ.
fn residual_bound(alpha: &[f64], beta: &[f64], h: f64) -> f64 {
    let (aa, ab, bb) = alpha
        .iter()
        .zip(beta)
        .fold((0.0, 0.0, 0.0), |(aa, ab, bb), (a, b)| {
            (aa + a * a, ab + a * b, bb + b * b)
        });
    let norm = |x: f64| {
        let (p, q) = (2.0 - x, 1.0 + x);
        (aa * p * p + 2.0 * ab * p * q + bb * q * q).max(0.0).sqrt()
    };
    let mut largest = 0.0f64;
    let mut at_start = norm(0.0);
    for i in 0..RESIDUAL_PIECES {
        let (x0, x1) = (
            i as f64 / RESIDUAL_PIECES as f64,
            (i + 1) as f64 / RESIDUAL_PIECES as f64,
        );
        let at_end = norm(x1);
        let x = 0.5f64.clamp(x0, x1);
        largest = largest.max(x * (1.0 - x) * at_start.max(at_end));
        at_start = at_end;
    }
    let wang = 0.75 * aa.max(bb).sqrt();
    h * h / 6.0 * largest.min(wang)
}

/// Wang's count for `segment` at `tol`: max(1, ceil(sqrt(M / (8 tol)))), M = max |P''| (at an
/// end of the segment; on a rational segment the proven bound M̂ of the module docs). As f64,
/// since it may be huge.
#[must_use]
pub fn wang_count(segment: &Segment<'_>, tol: f64) -> f64 {
    if let Some(w) = segment.denominator() {
        let [a, b, c, _] = segment.power();
        let m = RationalCubic { a, b, c, w }.second_derivative_bound();
        return (m / (8.0 * tol)).sqrt().ceil().max(1.0);
    }
    let cubic = Cubic::of(segment);
    let m = cubic.max_d2(0.0, 1.0);
    (m / (8.0 * cubic.scaled(tol))).sqrt().ceil().max(1.0)
}

/// The placement of `segment` at `tol`.
///
/// # Errors
/// The count the segment needs, when that exceeds [`MAX_SAMPLES_PER_SEGMENT`] (as f64: it can
/// pass 2^64).
pub(crate) fn place(segment: &Segment<'_>, tol: f64) -> Result<Placement, f64> {
    if segment.denominator().is_some() {
        let wang = wang_count(segment, tol);
        if wang > MAX_SAMPLES_PER_SEGMENT as f64 {
            return Err(wang);
        }
        return Ok(Placement {
            count: wang as u32,
            uniform: true,
            integral: [0.0; TABLE + 1],
        });
    }
    let cubic = Cubic::of(segment);
    let wang = wang_count(segment, tol);
    let tol = cubic.scaled(tol);
    let table = integral_table(&cubic);
    let estimate = (table[TABLE] / (8.0 * tol).sqrt()).ceil().max(1.0);
    if estimate.min(wang) > MAX_SAMPLES_PER_SEGMENT as f64 {
        return Err(estimate.min(wang));
    }
    let wang = wang as u32;
    let mut placement = Placement {
        count: (estimate as u32).clamp(1, wang),
        uniform: false,
        integral: table,
    };
    let mut us = Vec::new();
    let integral = placement.integral;
    let mut passes = |count: u32| {
        let trial = Placement {
            count,
            uniform: false,
            integral,
        };
        trial.us_into(&mut us);
        us.push(1.0);
        us.windows(2).all(|w| cubic.chord_bound(w[0], w[1]) <= tol)
    };
    // The largest count seen to fail (0: none tried).
    let mut failed = 0;
    while placement.count < wang && placement.count <= SEARCHED_SAMPLES {
        if passes(placement.count) {
            // Bisect down to the last count that failed: near the fewest, counts pass or fail
            // almost monotonically, and whichever count is kept has passed.
            let mut passed = placement.count;
            while passed - failed > 1 {
                let mid = failed + (passed - failed) / 2;
                if passes(mid) {
                    passed = mid;
                } else {
                    failed = mid;
                }
            }
            placement.count = passed;
            return Ok(placement);
        }
        failed = placement.count;
        placement.count += (placement.count / 8).max(1);
    }
    if u64::from(wang) > MAX_SAMPLES_PER_SEGMENT {
        return Err(f64::from(wang));
    }
    placement.count = wang;
    placement.uniform = true;
    Ok(placement)
}

impl Placement {
    /// The samples' u, into `out` (`count` values, from 0).
    pub(crate) fn us_into(&self, out: &mut Vec<f64>) {
        out.clear();
        out.extend((0..self.count).map(|j| self.u(j)));
    }

    /// Sample `j`'s u.
    pub(crate) fn u(&self, j: u32) -> f64 {
        let f = f64::from(j) / f64::from(self.count);
        if self.uniform {
            f
        } else {
            inverse(&self.integral, f)
        }
    }
}

/// ∫ sqrt(|P''⊥|) du from 0 to k/TABLE, k = 0..=TABLE, by Simpson's rule on each interval.
fn integral_table(cubic: &Cubic<'_>) -> [f64; TABLE + 1] {
    let mut table = [0.0; TABLE + 1];
    let h = 1.0 / TABLE as f64;
    let mut left = cubic.density(0.0);
    for k in 0..TABLE {
        let (a, b) = (k as f64 * h, (k + 1) as f64 * h);
        let (mid, right) = (cubic.density(0.5 * (a + b)), cubic.density(b));
        table[k + 1] = table[k] + h / 6.0 * (left + 4.0 * mid + right);
        left = right;
    }
    table
}

/// The u where the tabulated integral reaches the fraction `f` of its total (linear within a
/// table interval; a flat stretch maps to its start).
fn inverse(table: &[f64; TABLE + 1], f: f64) -> f64 {
    let total = table[TABLE];
    if total <= 0.0 || f <= 0.0 {
        return f.clamp(0.0, 1.0);
    }
    let target = f * total;
    let k = (table.partition_point(|&x| x < target).max(1) - 1).min(TABLE - 1);
    let (lo, hi) = (table[k], table[k + 1]);
    let within = if hi > lo {
        (target - lo) / (hi - lo)
    } else {
        0.0
    };
    (k as f64 + within) / TABLE as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The residual of the chord's linear interpolant, |P(u) − L(u)|, sampled densely on
    /// cubics whose P'' at the interval's ends are random: never above the bound, and the bound
    /// within 15 % of the largest residual seen.
    #[test]
    fn the_residual_bound_holds_and_is_nearly_tight() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut worst = 1.0f64;
        for _ in 0..500 {
            let dim = 3;
            let (a, b, c): (Vec<f64>, Vec<f64>, Vec<f64>) = (
                (0..dim).map(|_| next()).collect(),
                (0..dim).map(|_| next()).collect(),
                (0..dim).map(|_| next()).collect(),
            );
            let cubic = Cubic {
                a: &a,
                b: &b,
                c: &c,
                inv: 1.0,
            };
            let ua = 0.5 * (next() + 1.0);
            let ub = ua + (1.0 - ua) * 0.5 * (next() + 1.0);
            let h = ub - ua;
            let d2 = |u: f64| (0..dim).map(|k| cubic.d2(u, k)).collect::<Vec<_>>();
            let bound = residual_bound(&d2(ua), &d2(ub), h);
            let mut largest = 0.0f64;
            for i in 0..=2000 {
                let x = f64::from(i) / 2000.0;
                let u = ua + x * h;
                let r: f64 = (0..dim)
                    .map(|k| {
                        let line =
                            cubic.point(ua, k) + x * (cubic.point(ub, k) - cubic.point(ua, k));
                        (cubic.point(u, k) - line).powi(2)
                    })
                    .sum::<f64>()
                    .sqrt();
                largest = largest.max(r);
            }
            assert!(
                largest <= bound * (1.0 + 1e-12) + 1e-15,
                "{largest} > {bound}"
            );
            worst = worst.min(largest / bound);
            assert!(bound <= h * h / 8.0 * cubic.max_d2(ua, ub) * (1.0 + 1e-12));
        }
        // 16 pieces: measured no more than 12 % above the largest residual.
        assert!(
            worst >= 0.85,
            "the largest residual is {worst} of the bound somewhere"
        );
    }
}
