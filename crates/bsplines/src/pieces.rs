//! Piecewise polynomials in SciPy's power form evaluated and integrated in f64, any degree and
//! any x (the end pieces continue past the breakpoints), for the calls the context's tables
//! do not take: x outside the knots, nu = 3 and above, `PPoly` of any degree, integrals.
//!
//! Piece i (breakpoints increasing) is `sum_j c[j][i] (x - x_i)^(k-1-j)`, the highest power
//! first, with k = c's rows; x's piece is the number of inner breakpoints at or below it (the
//! first piece below x_0, the last at and above x_P), as SciPy's PPoly locates it.

/// The piece of x among `breaks` (P + 1 of them): 0..P.
fn piece(breaks: &[f64], x: f64) -> usize {
    let inner = &breaks[1..breaks.len() - 1];
    inner.partition_point(|&b| b <= x)
}

/// p (p - 1) ... (p - nu + 1): the factor d^nu/dv^nu v^p brings down.
fn falling(p: usize, nu: usize) -> f64 {
    (0..nu).map(|j| (p - j) as f64).product()
}

/// Derivative `nu` at each x into `out` (len(x) rows of m): c is (k, P, m) row-major.
pub fn evaluate(
    breaks: &[f64],
    c: &[f64],
    k: usize,
    m: usize,
    x: &[f64],
    nu: usize,
    out: &mut [f64],
) {
    let pieces = breaks.len() - 1;
    if m == 0 {
        return;
    }
    for (row, &at) in out.chunks_exact_mut(m).zip(x) {
        let i = piece(breaks, at);
        let v = at - breaks[i];
        row.fill(0.0);
        for j in 0..k.saturating_sub(nu) {
            let factor = falling(k - 1 - j, nu);
            let coefficients = &c[(j * pieces + i) * m..(j * pieces + i + 1) * m];
            for (o, &cj) in row.iter_mut().zip(coefficients) {
                *o = *o * v + cj * factor;
            }
        }
    }
}

/// The integral from a to b (b < a: its negative) into `out` (m values), the end pieces
/// continuing past the breakpoints: P_i(v) = sum_j c_j v^(p+1) / (p + 1), the integral of
/// piece i from its start, at b's piece minus at a's, plus every whole piece between.
pub fn integrate(breaks: &[f64], c: &[f64], k: usize, m: usize, a: f64, b: f64, out: &mut [f64]) {
    let (lo, hi, sign) = if b < a { (b, a, -1.0) } else { (a, b, 1.0) };
    let pieces = breaks.len() - 1;
    let mut term = vec![0.0; m];
    let mut primitive = |i: usize, v: f64, out: &mut [f64], weight: f64| {
        term.fill(0.0);
        for j in 0..k {
            let power = (k - j) as f64;
            let coefficients = &c[(j * pieces + i) * m..(j * pieces + i + 1) * m];
            for (t, &cj) in term.iter_mut().zip(coefficients) {
                *t = (*t + cj / power) * v;
            }
        }
        for (o, t) in out.iter_mut().zip(&term) {
            *o += weight * t;
        }
    };
    out.fill(0.0);
    let (first, last) = (piece(breaks, lo), piece(breaks, hi));
    for i in first..last {
        primitive(i, breaks[i + 1] - breaks[i], out, sign);
    }
    primitive(last, hi - breaks[last], out, sign);
    primitive(first, lo - breaks[first], out, -sign);
}

/// The antiderivative of c (k, P, m), zero at `breaks[0]` and continuous, as (k + 1, P, m):
/// each term c_j v^p becomes c_j v^(p+1) / (p + 1), and each piece's new constant is the
/// integral of the pieces before it (their P_i over their whole width; breakpoints may
/// decrease, the widths then negative).
pub fn antiderivative(breaks: &[f64], c: &[f64], k: usize, m: usize) -> Vec<f64> {
    let pieces = breaks.len() - 1;
    let mut out = vec![0.0; (k + 1) * pieces * m];
    let mut running = vec![0.0; m];
    let mut whole = vec![0.0; m];
    for i in 0..pieces {
        let width = breaks[i + 1] - breaks[i];
        whole.fill(0.0);
        for j in 0..k {
            let power = (k - j) as f64;
            for col in 0..m {
                let lifted = c[(j * pieces + i) * m + col] / power;
                out[(j * pieces + i) * m + col] = lifted;
                whole[col] = (whole[col] + lifted) * width;
            }
        }
        for col in 0..m {
            out[(k * pieces + i) * m + col] = running[col];
            running[col] += whole[col];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{antiderivative, evaluate, integrate};

    /// The antiderivative of 2x in two pieces is x^2 in two pieces, zero at 0.
    #[test]
    fn the_antiderivative_of_a_line_is_a_parabola() {
        let breaks = [0.0, 1.0, 3.0];
        let c = [2.0, 2.0, 0.0, 2.0];
        let out = antiderivative(&breaks, &c, 2, 1);
        assert_eq!(out, vec![1.0, 1.0, 0.0, 2.0, 0.0, 1.0]);
    }

    /// x^2 on [0, 1] and 1 + 2 (x - 1) + (x - 1)^2 on [1, 3] (the same parabola), inside,
    /// past both ends and differentiated, against the parabola; its integral from -1 to 4
    /// (and back) against 125/3 - (-1)/3 ... = (64 + 1) / 3.
    #[test]
    fn a_parabola_in_two_pieces() {
        let breaks = [0.0, 1.0, 3.0];
        let c = [1.0, 1.0, 0.0, 2.0, 0.0, 1.0];
        let x = [-2.0, 0.5, 1.0, 2.5, 5.0];
        let mut out = [0.0; 5];
        evaluate(&breaks, &c, 3, 1, &x, 0, &mut out);
        for (o, &at) in out.iter().zip(&x) {
            assert!((o - at * at).abs() < 1e-12);
        }
        evaluate(&breaks, &c, 3, 1, &x, 1, &mut out);
        for (o, &at) in out.iter().zip(&x) {
            assert!((o - 2.0 * at).abs() < 1e-12);
        }
        evaluate(&breaks, &c, 3, 1, &x, 3, &mut out);
        assert!(out.iter().all(|&o| o == 0.0));
        // No values per x: nothing to write, and no panic.
        evaluate(&breaks, &[], 3, 0, &x, 0, &mut []);
        let mut total = [0.0];
        integrate(&breaks, &c, 3, 1, -1.0, 4.0, &mut total);
        assert!((total[0] - 65.0 / 3.0).abs() < 1e-12);
        integrate(&breaks, &c, 3, 1, 4.0, -1.0, &mut total);
        assert!((total[0] + 65.0 / 3.0).abs() < 1e-12);
    }
}
