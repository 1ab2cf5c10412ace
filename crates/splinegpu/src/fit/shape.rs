//! Derivatives at the points for the shape-preserving kinds, each coordinate on its own, as
//! SciPy defines them (`PchipInterpolator`, `Akima1DInterpolator`); the pieces between the
//! points are then cubic Hermite (the `hermite` fit, which calls these).
//!
//! With h_i = t_{i+1} − t_i and the secant slopes m_i = (y_{i+1} − y_i)/h_i:
//!
//! - **PCHIP** (Fritsch and Carlson; Fritsch and Butland's weights): at an interior point, 0
//!   where m_{i−1} and m_i differ in sign or either is 0 (a local extremum or a flat run stays
//!   flat), else the weighted harmonic mean 1/d = (w_1/m_{i−1} + w_2/m_i)/(w_1 + w_2) with
//!   w_1 = 2h_i + h_{i−1}, w_2 = h_i + 2h_{i−1}. At an end, the three-point estimate
//!   d = ((2h_0 + h_1)m_0 − h_0 m_1)/(h_0 + h_1), set to 0 where its sign differs from m_0's,
//!   and to 3m_0 where m_0 and m_1 differ in sign and |d| > 3|m_0|. Two points: the line.
//! - **Akima**: the secants extended by two on each side (m_{−1} = 2m_0 − m_1,
//!   m_{−2} = 2m_{−1} − m_0, and likewise past the end); at point i, with
//!   f_1 = |m_{i+1} − m_i| and f_2 = |m_{i−1} − m_{i−2}|, d = (f_1 m_{i−1} + f_2 m_i)/(f_1 + f_2),
//!   or (m_{i−2} + m_{i+1})/2 where f_1 + f_2 is at most 1e-9 of its largest value over every
//!   point and coordinate of the curve. **makima** adds |m_{i+1} + m_i|/2 to f_1 and
//!   |m_{i−1} + m_{i−2}|/2 to f_2 (no overshoot where the data have flat runs). Two points:
//!   the line.

/// PCHIP's derivative at every point, `dim` values per point (see the module's documentation).
pub(crate) fn pchip_slopes(t: &[f64], values: &[f64], dim: usize) -> Vec<f64> {
    let mut d = vec![0.0; t.len() * dim];
    pchip_slopes_into(t, values, dim, &mut d);
    d
}

pub use bsplines::pchip::pchip_slopes_into;

/// Akima's (or, `modified`, makima's) derivative at every point, `dim` values per point (see
/// the module's documentation).
pub(crate) fn akima_slopes(t: &[f64], values: &[f64], dim: usize, modified: bool) -> Vec<f64> {
    let n = t.len();
    // Per coordinate: the secants with two more on each side (index j + 2 holds m_j), and
    // the weights f_1, f_2 of every point.
    let mut secants = vec![0.0; n + 3];
    let mut weights = vec![(0.0, 0.0); n * dim];
    let mut extended = vec![0.0; (n + 3) * dim];
    for k in 0..dim {
        for j in 0..n - 1 {
            let rise = values[(j + 1) * dim + k] - values[j * dim + k];
            secants[j + 2] = rise / (t[j + 1] - t[j]);
        }
        if n == 2 {
            secants[3] = secants[2];
        }
        secants[1] = 2.0 * secants[2] - secants[3];
        secants[0] = 2.0 * secants[1] - secants[2];
        secants[n + 1] = 2.0 * secants[n] - secants[n - 1];
        secants[n + 2] = 2.0 * secants[n + 1] - secants[n];
        let weight = |j: usize| {
            let change = (secants[j + 1] - secants[j]).abs();
            if modified {
                change + 0.5 * (secants[j + 1] + secants[j]).abs()
            } else {
                change
            }
        };
        for i in 0..n {
            weights[i * dim + k] = (weight(i + 2), weight(i));
        }
        for (j, &m) in secants.iter().enumerate() {
            extended[j * dim + k] = m;
        }
    }
    let largest = weights
        .iter()
        .map(|&(f1, f2)| f1 + f2)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut d = vec![0.0; n * dim];
    for i in 0..n {
        for k in 0..dim {
            let m = |j: usize| extended[j * dim + k];
            let (f1, f2) = weights[i * dim + k];
            d[i * dim + k] = if f1 + f2 > 1e-9 * largest {
                let blend = (f1 * m(i + 1) + f2 * m(i + 2)) / (f1 + f2);
                if blend.is_finite() {
                    blend
                } else {
                    // Weights and secants so large that their products overflow (a jump
                    // of 1e160): the same mean with the weights scaled to at most 1.
                    let (a, b) = (f1 / f1.max(f2), f2 / f1.max(f2));
                    (a * m(i + 1) + b * m(i + 2)) / (a + b)
                }
            } else {
                0.5 * (m(i + 3) + m(i))
            };
        }
    }
    d
}
