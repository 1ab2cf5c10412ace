//! PCHIP's slopes, as SciPy's `PchipInterpolator` makes them (Fritsch and Carlson; Fritsch
//! and Butland's weights): with h_i = t_{i+1} − t_i and the secants m_i = (y_{i+1} − y_i)/h_i,
//! at an interior point 0 where m_{i−1} and m_i differ in sign or either is 0, else the
//! weighted harmonic mean 1/d = (w_1/m_{i−1} + w_2/m_i)/(w_1 + w_2) with w_1 = 2h_i + h_{i−1},
//! w_2 = h_i + 2h_{i−1}; at an end the three-point estimate
//! d = ((2h_0 + h_1)m_0 − h_0 m_1)/(h_0 + h_1), 0 where its sign differs from m_0's and 3m_0
//! where m_0 and m_1 differ in sign and |d| > 3|m_0|; on two points the line. The gridded
//! PCHIP (`grid`) and `splinegpu`'s PCHIP curves both take them from here.

/// PCHIP's derivative at every point, `dim` values per point (SciPy's `PchipInterpolator`
/// slopes: the weighted harmonic mean inside, the three-point estimate at the ends, the line
/// on two points), into a caller's memory (`t.len() · dim` values): for callers that take
/// the slopes of many short runs (a gridded PCHIP's windows of up to four points).
///
/// # Panics
/// If `t` has fewer than 2 points, or `values` or `d` is not `t.len() · dim` long.
pub fn pchip_slopes_into(t: &[f64], values: &[f64], dim: usize, d: &mut [f64]) {
    let n = t.len();
    assert!(n >= 2 && values.len() == n * dim && d.len() == n * dim);
    for k in 0..dim {
        let h = |i: usize| t[i + 1] - t[i];
        let m = |i: usize| (values[(i + 1) * dim + k] - values[i * dim + k]) / h(i);
        if n == 2 {
            (d[k], d[dim + k]) = (m(0), m(0));
            continue;
        }
        for i in 1..n - 1 {
            let (m0, m1) = (m(i - 1), m(i));
            d[i * dim + k] = if sign(m0) != sign(m1) || m0 == 0.0 || m1 == 0.0 {
                0.0
            } else {
                let w1 = 2.0 * h(i) + h(i - 1);
                let w2 = h(i) + 2.0 * h(i - 1);
                1.0 / ((w1 / m0 + w2 / m1) / (w1 + w2))
            };
        }
        d[k] = pchip_end(h(0), h(1), m(0), m(1));
        d[(n - 1) * dim + k] = pchip_end(h(n - 2), h(n - 3), m(n - 2), m(n - 3));
    }
}

/// PCHIP's derivative at an end: h0 and m0 of the end's interval, h1 and m1 of its neighbour.
fn pchip_end(h0: f64, h1: f64, m0: f64, m1: f64) -> f64 {
    let d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
    if sign(d) != sign(m0) {
        0.0
    } else if sign(m0) != sign(m1) && d.abs() > 3.0 * m0.abs() {
        3.0 * m0
    } else {
        d
    }
}

/// −1, 0 or 1, as NumPy's `sign`.
fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}
