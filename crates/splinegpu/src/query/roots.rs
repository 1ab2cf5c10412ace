//! Real roots of a polynomial of low degree on an interval, isolated by its derivatives.
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
    pub(crate) fn at_with_slope(&self, u: f64) -> (f64, f64) {
        let mut p = 0.0;
        let mut dp = 0.0;
        for &c in self.c[..=self.degree].iter().rev() {
            dp = dp * u + p;
            p = p * u + c;
        }
        (p, dp)
    }

    /// The product p·q (of degrees adding up to at most [`MAX_DEGREE`]).
    pub(crate) fn times(&self, q: &Self) -> Self {
        let mut c = [0.0; MAX_DEGREE + 1];
        for i in 0..=self.degree {
            for j in 0..=q.degree {
                c[i + j] += self.c[i] * q.c[j];
            }
        }
        Self::new(&c[..=(self.degree + q.degree).min(MAX_DEGREE)])
    }

    /// p − q.
    pub(crate) fn minus(&self, q: &Self) -> Self {
        let c: [f64; MAX_DEGREE + 1] = std::array::from_fn(|i| self.c[i] - q.c[i]);
        Self::new(&c)
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

/// Every root of `p` in [lo, hi] where it changes sign, handed to `visit` (with, where the
/// fallback below runs, its breakpoints too), by Bernstein subdivision.
///
/// By Descartes' rule of signs in the Bernstein basis, p has at most as many roots in an
/// interval, counted with multiplicity, as its Bernstein coefficients there change sign, and
/// the two counts differ by an even number: no change means no root, one change exactly one
/// simple root, which the ends bracket (the first and last coefficients are p's values
/// there). An interval with more changes is halved (de Casteljau) and each half looked at
/// again, down to [`MAX_HALVINGS`]; one whose coefficients come too near zero for their signs
/// to be trusted (within 1e-12 of the largest), or that is still undecided there, is handed to
/// [`sign_change_roots`].
pub(crate) fn visit_sign_change_roots(p: &Poly, lo: f64, hi: f64, visit: &mut impl FnMut(f64)) {
    if p.degree == 0 {
        return;
    }
    let b = bernstein(p, lo, hi);
    isolate(p, &b[..=p.degree], lo, hi, 0, visit);
}

/// The deepest halving of [`visit_sign_change_roots`] before it falls back.
const MAX_HALVINGS: usize = 6;

fn isolate(p: &Poly, b: &[f64], lo: f64, hi: f64, depth: usize, visit: &mut impl FnMut(f64)) {
    let largest = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let trusted = b.iter().all(|v| v.abs() > 1e-12 * largest);
    if trusted {
        let changes = b
            .windows(2)
            .filter(|w| (w[0] < 0.0) != (w[1] < 0.0))
            .count();
        match changes {
            0 => return,
            1 => {
                visit(bracketed_root(p, lo, hi, p.at(lo)));
                return;
            }
            _ if depth < MAX_HALVINGS => {
                let (left, right) = halves(b);
                let mid = 0.5 * (lo + hi);
                isolate(p, &left[..b.len()], lo, mid, depth + 1, visit);
                isolate(p, &right[..b.len()], mid, hi, depth + 1, visit);
                return;
            }
            _ => {}
        }
    }
    let (roots, breakpoints) = sign_change_roots(p, lo, hi);
    for &u in roots.as_slice().iter().chain(breakpoints.as_slice()) {
        visit(u);
    }
}

/// The Bernstein coefficients of `p` on [lo, hi] (degree + 1 of them, then zeros): p's values
/// there lie between the least and the largest of them.
pub(crate) fn bernstein(p: &Poly, lo: f64, hi: f64) -> [f64; MAX_DEGREE + 1] {
    bernstein_of_degree(p, p.degree, lo, hi)
}

/// The Bernstein coefficients of a polynomial of degree at most 3 on [lo, hi], written in
/// degree 3, from its values and slopes at the ends (h = hi − lo): p(lo), p(lo) + h p'(lo)/3,
/// p(hi) − h p'(hi)/3, p(hi).
#[inline]
pub(crate) fn cubic_bernstein(p: &Poly, lo: f64, hi: f64) -> [f64; 4] {
    debug_assert!(p.degree <= 3);
    let h = hi - lo;
    let (a, da) = p.at_with_slope(lo);
    let (b, db) = p.at_with_slope(hi);
    [a, a + h * da / 3.0, b - h * db / 3.0, b]
}

/// [`bernstein`] written in degree `n` (>= p's degree, <= [`MAX_DEGREE`]): n + 1 coefficients.
pub(crate) fn bernstein_of_degree(p: &Poly, n: usize, lo: f64, hi: f64) -> [f64; MAX_DEGREE + 1] {
    // p(lo + w s) = Σ a_j s^j: a Taylor shift by lo (repeated synthetic division), then the
    // powers of w.
    let mut a = p.c;
    for i in 0..n {
        for j in (i..n).rev() {
            a[j] += lo * a[j + 1];
        }
    }
    let w = hi - lo;
    let mut scale = 1.0;
    for coefficient in a.iter_mut().take(n + 1) {
        *coefficient *= scale;
        scale *= w;
    }
    // b_i = Σ_{j <= i} C(i, j) / C(n, j) a_j.
    let mut b = [0.0; MAX_DEGREE + 1];
    for (i, bi) in b.iter_mut().enumerate().take(n + 1) {
        let mut ratio = 1.0; // C(i, j) / C(n, j), from j = 0
        for (j, &aj) in a.iter().enumerate().take(i + 1) {
            *bi += ratio * aj;
            ratio *= (i - j) as f64 / (n - j) as f64;
        }
    }
    b
}

/// Bernstein coefficients `b` split at the middle of their interval (de Casteljau): the left
/// half's and the right half's.
fn halves(b: &[f64]) -> ([f64; MAX_DEGREE + 1], [f64; MAX_DEGREE + 1]) {
    let n = b.len() - 1;
    let mut work = [0.0; MAX_DEGREE + 1];
    work[..=n].copy_from_slice(b);
    let (mut left, mut right) = ([0.0; MAX_DEGREE + 1], [0.0; MAX_DEGREE + 1]);
    for level in 0..=n {
        left[level] = work[0];
        right[n - level] = work[n - level];
        for i in 0..n - level {
            work[i] = 0.5 * (work[i] + work[i + 1]);
        }
    }
    (left, right)
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

/// The roots of `p` in [lo, hi] where it changes sign, in increasing order, and the breakpoints
/// used to isolate them (the sign-changing roots of p' in [lo, hi]), which the callers may
/// also want to try.
pub(crate) fn sign_change_roots(p: &Poly, lo: f64, hi: f64) -> (Roots, Roots) {
    let mut roots = Roots::default();
    if p.degree == 0 {
        return (roots, Roots::default());
    }
    let breakpoints = if p.degree == 1 {
        Roots::default()
    } else {
        sign_change_roots(&p.derivative(), lo, hi).0
    };
    let mut a = lo;
    let mut pa = p.at(lo);
    for &b in breakpoints.as_slice().iter().chain(std::iter::once(&hi)) {
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
pub(crate) fn bracketed_root(p: &Poly, mut a: f64, mut b: f64, pa: f64) -> f64 {
    let rising = pa < 0.0;
    // A Newton step this small leaves an error of about its square: converged.
    let converged = 1e-12 * (b - a);
    // The first guess by regula falsi, inside the bracket.
    let pb = p.at(b);
    let secant = a - pa * (b - a) / (pb - pa);
    let mut u = if secant > a && secant < b {
        secant
    } else {
        0.5 * (a + b)
    };
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
        let inside = newton > a && newton < b;
        if inside && (newton - u).abs() <= converged {
            return newton;
        }
        let next = if inside && (newton - u).abs() < 0.5 * width {
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
            let (got, _) = sign_change_roots(&p, 0.0, 1.0);
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
        let (roots, breakpoints) = sign_change_roots(&p, 0.0, 1.0);
        // Rounding may make the touch at 0.4 a change of sign: then it is found there.
        assert!(roots.as_slice().iter().any(|r| (r - 0.8).abs() < 1e-12));
        assert!(
            roots
                .as_slice()
                .iter()
                .all(|r| (r - 0.8).abs() < 1e-12 || (r - 0.4).abs() < 1e-6)
        );
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
        let (roots, _) = sign_change_roots(&p, 0.0, 1.0);
        assert_eq!(roots.as_slice().len(), 1);
        assert!((roots.as_slice()[0] - 0.3).abs() < 1e-5);
    }

    #[test]
    fn only_the_roots_inside_the_interval_are_found() {
        let p = from_roots(3.0, &[0.1, 0.35, 0.6, 0.9]);
        let (roots, _) = sign_change_roots(&p, 0.2, 0.7);
        assert_eq!(roots.as_slice().len(), 2);
        assert!((roots.as_slice()[0] - 0.35).abs() < 1e-12);
        assert!((roots.as_slice()[1] - 0.6).abs() < 1e-12);
    }

    #[test]
    fn subdivision_finds_the_same_roots_as_the_derivatives() {
        let cases: [&[f64]; 4] = [
            &[0.1, 0.35, 0.6, 1.5],
            &[0.01, 0.02, 0.03, 0.5, 0.51, 0.52, 0.98, 0.99],
            &[0.2, 0.2000001, 0.7],
            &[-1.0, 2.0],
        ];
        for roots in cases {
            let p = from_roots(-1.5, roots);
            let mut got = Vec::new();
            visit_sign_change_roots(&p, 0.0, 1.0, &mut |u| got.push(u));
            for &r in roots.iter().filter(|r| (0.0..=1.0).contains(*r)) {
                assert!(
                    got.iter().any(|g| (g - r).abs() < 1e-6),
                    "{roots:?}: {r} in {got:?}"
                );
            }
        }
    }

    #[test]
    fn halves_are_de_casteljaus() {
        let p = from_roots(1.0, &[0.3, 0.45, 0.9]);
        let (left, right) = halves(&bernstein(&p, 0.0, 1.0)[..4]);
        let (want_left, want_right) = (bernstein(&p, 0.0, 0.5), bernstein(&p, 0.5, 1.0));
        for (a, b) in left[..4]
            .iter()
            .chain(&right[..4])
            .zip(want_left[..4].iter().chain(&want_right[..4]))
        {
            assert!((a - b).abs() < 1e-15, "{a} {b}");
        }
    }

    #[test]
    fn cubic_bernstein_is_the_general_one_in_degree_3() {
        for p in [
            from_roots(2.0, &[0.1, 0.7, 1.3]),
            from_roots(-1.0, &[0.4, 0.5]),
            Poly::new(&[3.0]),
        ] {
            let (got, want) = (
                cubic_bernstein(&p, 0.2, 0.9),
                bernstein_of_degree(&p, 3, 0.2, 0.9),
            );
            for (a, b) in got.iter().zip(&want) {
                assert!((a - b).abs() < 1e-14, "{got:?} {want:?}");
            }
        }
    }

    #[test]
    fn constants_and_zero_have_no_roots() {
        assert!(
            sign_change_roots(&Poly::new(&[3.0]), 0.0, 1.0)
                .0
                .as_slice()
                .is_empty()
        );
        assert!(
            sign_change_roots(&Poly::new(&[0.0, 0.0]), 0.0, 1.0)
                .0
                .as_slice()
                .is_empty()
        );
    }
}
