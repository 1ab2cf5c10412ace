//! The uniform families' fit: segment i of a sliding-window family (or a Bezier curve) is
//! `U · M · X_i`, with the product M·X formed here in f64 from the basis matrix's rows and the
//! window of four control points the end convention picks.

use crate::basis::Rows;
use crate::segment::SegmentTable;

/// Segments of a uniform 4x4-matrix spline: segment i is `U · M · X_i`, its knots i and i+1.
///
/// `window(i)` gives the indices (into `points`, `dim` values each) of segment i's four
/// control points. The power coefficients are M·X in f64: row r of M times the window gives
/// the coefficient of u^(3−r).
pub(crate) fn from_windows(
    dim: usize,
    points: &[f64],
    rows: &Rows,
    segments: usize,
    extent: f64,
    window: impl Fn(usize) -> [usize; 4],
) -> SegmentTable {
    let mut coeffs = Vec::with_capacity(segments * 4 * dim);
    for i in 0..segments {
        let w = window(i);
        for row in rows {
            for k in 0..dim {
                let mut v = 0.0;
                for (m, &p) in row.iter().zip(&w) {
                    v += m * points[p * dim + k];
                }
                coeffs.push(v);
            }
        }
    }
    let knots = (0..=segments).map(|i| i as f64).collect();
    SegmentTable::from_parts(dim, knots, coeffs, extent)
}
