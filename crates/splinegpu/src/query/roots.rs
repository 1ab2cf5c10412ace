//! Real roots of a polynomial of low degree on [0, 1], isolated by its derivatives.
//!
//! The argument (Yuksel's "High-Performance Polynomial Root Finding", 2022, after Collins and
//! Loos): between two neighbouring real roots of p' the polynomial p is monotone, so it has at
//! most one root there, and it has one exactly when its values at the two ends differ in sign.
//! The roots of p' come the same way from p'', down to a linear polynomial. Each root is then
//! found inside its sign-changing bracket by Newton's method kept inside the bracket (a step
//! that leaves it, or does not halve it, is replaced by bisection), so it cannot be missed or
//! found twice. A root of even multiplicity, where p touches zero without changing sign, is not
//! reported: the callers here look for extrema of a function whose derivative is p, and such a
//! root is not one (they also try the breakpoints, where such a touch would be).

/// The highest degree handled: the squared distance's derivative on a rational cubic
/// (N − rW)·(N'W − NW') is of degree 3 + 5.
pub(crate) const MAX_DEGREE: usize = 8;

/// A polynomial Σ c[i] u^i of degree at most [`MAX_DEGREE`], coefficients from the constant up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Poly {
    pub c: [f64; MAX_DEGREE + 1],
    /// The index of the highest coefficient that is not zero (0 for a constant).
    pub degree: usize,
}

impl Poly {
    /// The polynomial with these coefficients (constant first; at most MAX_DEGREE + 1 of them),
    /// its trailing zeros trimmed.
    pub(crate) fn new(coeffs: &[f64]) -> Self {
        let mut c = [0.0; MAX_DEGREE + 1];
        c[..coeffs.len()].copy_from_slice(coeffs);
        let degree = (0..coeffs.len()).rev().find(|&i| c[i] != 0.0).unwrap_or(0);
        Self { c, degree }
    }

    /// p(u), by Horner.
    #[inline]
    pub(crate) fn at(&self, u: f64) -> f64 {
        self.c[..=self.degree]
            .iter()
            .rev()
            .fold(0.0, |acc, &c| acc * u + c)
    }

    /// p(u) and p'(u) in one Horner pass.
    #[inline]
    fn at_with_slope(&self, u: f64) -> (f64, f64) {
        let mut p = 0.0;
        let mut dp = 0.0;
        for &c in self.c[..=self.degree].iter().rev() {
            dp = dp * u + p;
            p = p * u + c;
        }
        (p, dp)
    }

    /// p'.
    pub(crate) fn derivative(&self) -> Self {
        let mut c = [0.0; MAX_DEGREE + 1];
        for i in 1..=self.degree {
            c[i - 1] = self.c[i] * i as f64;
        }
        Self::new(&c[..self.degree.max(1)])
    }
}

/// Up to [`MAX_DEGREE`] values in increasing order, on the stack.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Roots {
    values: [f64; MAX_DEGREE],
    len: usize,
}

impl Roots {
    pub(crate) fn as_slice(&self) -> &[f64] {
        &self.values[..self.len]
    }

    fn push(&mut self, u: f64) {
        if self.len < MAX_DEGREE {
            self.values[self.len] = u;
            self.len += 1;
        }
    }
}

/// The roots of `p` in [0, 1] where it changes sign, in increasing order, and the breakpoints
/// used to isolate them (the sign-changing roots of p' in [0, 1]), which the callers may also
/// want to try.
pub(crate) fn sign_change_roots(p: &Poly) -> (Roots, Roots) {
    let mut roots = Roots::default();
    if p.degree == 0 {
        return (roots, Roots::default());
    }
    let breakpoints = if p.degree == 1 {
        Roots::default()
    } else {
        sign_change_roots(&p.derivative()).0
    };
    let mut a = 0.0;
    let mut pa = p.at(0.0);
    for &b in breakpoints.as_slice().iter().chain(std::iter::once(&1.0)) {
        let pb = p.at(b);
        if pa == 0.0 {
            if roots.as_slice().last() != Some(&a) {
                roots.push(a);
            }
        } else if pa.signum() != pb.signum() && pb != 0.0 {
            roots.push(bracketed_root(p, a, b, pa));
        }
        (a, pa) = (b, pb);
    }
    if pa == 0.0 && roots.as_slice().last() != Some(&a) {
        roots.push(a);
    }
    (roots, breakpoints)
}

/// The root of `p` in (a, b), where p(a) = `pa` and p(b) differ in sign and p is monotone:
/// Newton's method kept inside the bracket, bisection where a step leaves it or stalls.
fn bracketed_root(p: &Poly, mut a: f64, mut b: f64, pa: f64) -> f64 {
    let rising = pa < 0.0;
    let mut u = 0.5 * (a + b);
    for _ in 0..100 {
        let (value, slope) = p.at_with_slope(u);
        if value == 0.0 {
            return u;
        }
        // Shrink the bracket to the side the root is on.
        if (value < 0.0) == rising {
            a = u;
        } else {
            b = u;
        }
        let width = b - a;
        let newton = u - value / slope;
        let next = if newton > a && newton < b && (newton - u).abs() < 0.5 * width {
            newton
        } else {
            0.5 * (a + b)
        };
        if next == u || width <= f64::EPSILON * b.abs().max(f64::MIN_POSITIVE) {
            return next;
        }
        u = next;
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomial with these roots (and leading coefficient `lead`), expanded.
    fn from_roots(lead: f64, roots: &[f64]) -> Poly {
        let mut c = vec![lead];
        for &r in roots {
            let mut next = vec![0.0; c.len() + 1];
            for (i, &ci) in c.iter().enumerate() {
                next[i + 1] += ci;
                next[i] -= r * ci;
            }
            c = next;
        }
        Poly::new(&c)
    }

    #[test]
    fn finds_every_simple_root_in_the_unit_interval_once() {
        let cases: [&[f64]; 5] = [
            &[0.5],
            &[0.1, 0.9],
            &[-0.3, 0.2, 0.25, 0.7, 1.4],
            &[0.01, 0.02, 0.03, 0.5, 0.51, 0.52, 0.98, 0.99],
            &[0.0, 1.0, 0.3],
        ];
        for roots in cases {
            let p = from_roots(-2.5, roots);
            let mut want: Vec<f64> = roots
                .iter()
                .copied()
                .filter(|r| (0.0..=1.0).contains(r))
                .collect();
            want.sort_by(f64::total_cmp);
            let (got, _) = sign_change_roots(&p);
            assert_eq!(
                got.as_slice().len(),
                want.len(),
                "{roots:?}: {:?}",
                got.as_slice()
            );
            for (g, w) in got.as_slice().iter().zip(&want) {
                assert!((g - w).abs() < 1e-9, "{roots:?}: {g} for {w}");
            }
        }
    }

    #[test]
    fn a_double_root_is_not_a_sign_change_but_is_a_breakpoint() {
        let p = from_roots(1.0, &[0.4, 0.4, 0.8]);
        let (roots, breakpoints) = sign_change_roots(&p);
        assert_eq!(roots.as_slice().len(), 1);
        assert!((roots.as_slice()[0] - 0.8).abs() < 1e-12);
        assert!(
            breakpoints
                .as_slice()
                .iter()
                .any(|b| (b - 0.4).abs() < 1e-7)
        );
    }

    #[test]
    fn a_triple_root_changes_sign_and_is_found() {
        let p = from_roots(1.0, &[0.3, 0.3, 0.3]);
        let (roots, _) = sign_change_roots(&p);
        assert_eq!(roots.as_slice().len(), 1);
        assert!((roots.as_slice()[0] - 0.3).abs() < 1e-5);
    }

    #[test]
    fn constants_and_zero_have_no_roots() {
        assert!(
            sign_change_roots(&Poly::new(&[3.0]))
                .0
                .as_slice()
                .is_empty()
        );
        assert!(
            sign_change_roots(&Poly::new(&[0.0, 0.0]))
                .0
                .as_slice()
                .is_empty()
        );
    }
}
