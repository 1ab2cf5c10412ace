//! The uniform families' fit: segment i of a sliding-window family (or a Bezier curve) is
//! `U · M · X_i`, with the product M·X formed here in f64 from the basis matrix's rows and the
//! window of four control points the end convention picks.

use crate::basis::Rows;
use crate::segment::SegmentTable;

/// Segments of a uniform 4x4-matrix spline: segment i is `U · M_i · X_i`, its knots i and i+1.
///
/// `rows(i)` gives segment i's basis matrix M_i (the same for every segment of a uniform
/// family, one per segment for local bias and tension); `window(i)` gives the indices (into `points`, `dim` values each) of segment i's four
/// control points. The power coefficients are M·X in f64: row r of M times the window gives
/// the coefficient of u^(3−r).
/// The table is written into `out`, whose buffers are reused (a curve refitted every frame
/// allocates nothing).
pub(crate) fn from_windows<'a>(
    dim: usize,
    points: &[f64],
    rows: impl Fn(usize) -> &'a Rows,
    segments: usize,
    extent: f64,
    window: impl Fn(usize) -> [usize; 4],
    out: &mut SegmentTable,
) {
    let (knots, coeffs) = out.parts_mut(dim, extent);
    knots.clear();
    knots.extend((0..=segments).map(|i| i as f64));
    coeffs.resize(segments * 4 * dim, 0.0);
    match dim {
        1 => fill::<1>(points, &rows, &window, coeffs),
        2 => fill::<2>(points, &rows, &window, coeffs),
        3 => fill::<3>(points, &rows, &window, coeffs),
        4 => fill::<4>(points, &rows, &window, coeffs),
        _ => {
            for (i, segment) in coeffs.chunks_exact_mut(4 * dim).enumerate() {
                let w = window(i);
                for (row, out) in rows(i).iter().zip(segment.chunks_exact_mut(dim)) {
                    for (k, out) in out.iter_mut().enumerate() {
                        *out = row_times_window(row, |j| points[w[j] * dim + k]);
                    }
                }
            }
        }
    }
}

/// [`from_windows`]'s products for `D` coordinates known at compile time (a fit of a few
/// segments is dominated by its loop overhead otherwise; docs/benchmarks.md).
#[inline(always)]
fn fill<'a, const D: usize>(
    points: &[f64],
    rows: &impl Fn(usize) -> &'a Rows,
    window: &impl Fn(usize) -> [usize; 4],
    coeffs: &mut [f64],
) {
    for (i, segment) in coeffs.chunks_exact_mut(4 * D).enumerate() {
        let x = window(i).map(|p| -> [f64; D] {
            points[p * D..(p + 1) * D]
                .try_into()
                .expect("D coordinates")
        });
        for (row, out) in rows(i).iter().zip(segment.chunks_exact_mut(D)) {
            for (k, out) in out.iter_mut().enumerate() {
                *out = row_times_window(row, |j| x[j][k]);
            }
        }
    }
}

/// One coefficient: row r of M times the window's coordinate, summed in the window's order
/// (the same order everywhere, so every build gives the same bits).
#[inline(always)]
fn row_times_window(row: &[f64; 4], x: impl Fn(usize) -> f64) -> f64 {
    let mut v = 0.0;
    for (j, m) in row.iter().enumerate() {
        v += m * x(j);
    }
    v
}
