//! Plain hand-written loops doing a bench workload's work, with none of the crate's machinery
//! (no plans, layouts, runs or blocks): the floor any path of ours must beat (bench path
//! "plain-loop"). Each takes what the timed paths take and writes what they write.

use splinegpu::EvalJob;

/// w1's work: every curve's segments at u = j/k, j = 0..k, and the final point, as f32 by Horner
/// on the fitted power coefficients, on `threads` threads.
pub fn grid(job: &EvalJob, k: u32, out: &mut [f32], threads: usize) {
    job.layout().per_thread_curves(out, threads, |curves, out| {
        let mut at = 0;
        for c in curves {
            let table = job.table(c);
            let dim = table.dim();
            for s in 0..table.len() {
                let segment = table.segment(s);
                let [a, b, cc, d] = segment.power();
                for j in 0..k {
                    let u = f64::from(j) / f64::from(k);
                    for i in 0..dim {
                        out[at + i] = (d[i] + u * (cc[i] + u * (b[i] + u * a[i]))) as f32;
                    }
                    at += dim;
                }
            }
            let segment = table.segment(table.len() - 1);
            let [a, b, cc, d] = segment.power();
            for i in 0..dim {
                out[at + i] = (a[i] + b[i] + cc[i] + d[i]) as f32;
            }
            at += dim;
        }
    });
}

/// w1-nurbs's work: as [`grid`] on rational segments, P(u) = D + u(C + u(B + uA)) / W(u) with
/// W(u) = d + u(c + u(b + ua)) (the crate's rational power form).
pub fn rational_grid(job: &EvalJob, k: u32, out: &mut [f32], threads: usize) {
    job.layout().per_thread_curves(out, threads, |curves, out| {
        let mut at = 0;
        for c in curves {
            let table = job.table(c);
            let dim = table.dim();
            for s in 0..table.len() {
                let segment = table.segment(s);
                let [a, b, cc, d] = segment.power();
                let [wa, wb, wc, wd] = segment.denominator().expect("a rational segment").coeffs;
                for j in 0..k {
                    let u = f64::from(j) / f64::from(k);
                    let w = wd + u * (wc + u * (wb + u * wa));
                    for i in 0..dim {
                        out[at + i] = (d[i] + u * (cc[i] + u * (b[i] + u * a[i])) / w) as f32;
                    }
                    at += dim;
                }
            }
            let segment = table.segment(table.len() - 1);
            let [a, b, cc, d] = segment.power();
            let w = segment
                .denominator()
                .expect("a rational segment")
                .coeffs
                .iter()
                .sum::<f64>();
            for i in 0..dim {
                out[at + i] = (d[i] + (a[i] + b[i] + cc[i]) / w) as f32;
            }
            at += dim;
        }
    });
}

/// eval-at's work from scratch: each t located by binary search among its curve's knots, then
/// Horner there, as f32, on `threads` threads (`ts[c]` are curve c's parameters).
pub fn at(job: &EvalJob, ts: &[Vec<f64>], out: &mut [f32], threads: usize) {
    job.layout().per_thread_curves(out, threads, |curves, out| {
        let mut at = 0;
        for c in curves {
            let table = job.table(c);
            let (dim, knots) = (table.dim(), table.knots());
            let last = table.len() - 1;
            for &t in &ts[c] {
                let s = knots
                    .partition_point(|&x| x <= t)
                    .saturating_sub(1)
                    .min(last);
                let segment = table.segment(s);
                let u = (t - knots[s]) / segment.dt();
                let [a, b, cc, d] = segment.power();
                for i in 0..dim {
                    out[at + i] = (d[i] + u * (cc[i] + u * (b[i] + u * a[i]))) as f32;
                }
                at += dim;
            }
        }
    });
}

/// "small"'s and "frame"'s work for one curve from its points: a uniform Catmull-Rom curve
/// through `points` (`dim` per point; control ends, or closed), each segment's coefficients
/// formed from its four points, then `k` samples per segment and the final point, f32 by Horner,
/// into `out`. Returns the values written.
pub fn catmull_rom(points: &[f64], dim: usize, closed: bool, k: u32, out: &mut [f32]) -> usize {
    let n = points.len() / dim;
    let (segments, first) = if closed { (n, n - 1) } else { (n - 3, 0) };
    let p = |j: usize, i: usize| points[((first + j) % n) * dim + i];
    let mut at = 0;
    for s in 0..segments {
        for i in 0..dim {
            let (p0, p1, p2, p3) = (p(s, i), p(s + 1, i), p(s + 2, i), p(s + 3, i));
            let a = 0.5 * (-p0 + 3.0 * p1 - 3.0 * p2 + p3);
            let b = 0.5 * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3);
            let c = 0.5 * (p2 - p0);
            for j in 0..k {
                let u = f64::from(j) / f64::from(k);
                out[at + j as usize * dim + i] = (p1 + u * (c + u * (b + u * a))) as f32;
            }
        }
        at += k as usize * dim;
    }
    // The final point: the last segment at u = 1 is its third point.
    for i in 0..dim {
        out[at + i] = p(segments + 1, i) as f32;
    }
    at + dim
}

/// fit-1m's work: the natural cubic spline through `values` (`dim` per knot) at knots `t`, by
/// the textbook second-derivative system solved with the Thomas algorithm (one elimination for
/// every coordinate), then each segment's power coefficients in its local u, into `out`
/// ((len − 1) segments of a, b, c, d, `dim` values each). `m` and `scratch` are reused memory.
pub fn natural_fit(
    t: &[f64],
    values: &[f64],
    dim: usize,
    m: &mut Vec<f64>,
    scratch: &mut Vec<f64>,
    out: &mut [f64],
) {
    let n = t.len();
    // Second derivatives M_i, M_0 = M_{n-1} = 0; interior rows
    // h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (slope_i − slope_{i-1}).
    m.clear();
    m.resize(n * dim, 0.0);
    scratch.clear();
    scratch.resize(n, 0.0);
    let slope =
        |i: usize, k: usize| (values[(i + 1) * dim + k] - values[i * dim + k]) / (t[i + 1] - t[i]);
    for i in 1..n - 1 {
        let (h0, h1) = (t[i] - t[i - 1], t[i + 1] - t[i]);
        let below = if i > 1 { h0 } else { 0.0 };
        let pivot = 2.0 * (h0 + h1) - below * scratch[i - 1];
        scratch[i] = h1 / pivot;
        for k in 0..dim {
            let rhs = 6.0 * (slope(i, k) - slope(i - 1, k));
            m[i * dim + k] = (rhs - below * m[(i - 1) * dim + k]) / pivot;
        }
    }
    for i in (1..n - 2).rev() {
        for k in 0..dim {
            m[i * dim + k] -= scratch[i] * m[(i + 1) * dim + k];
        }
    }
    for i in 0..n - 1 {
        let h = t[i + 1] - t[i];
        let h6 = h * h / 6.0;
        let block = &mut out[i * 4 * dim..(i + 1) * 4 * dim];
        for k in 0..dim {
            let (m0, m1) = (m[i * dim + k], m[(i + 1) * dim + k]);
            let (y0, y1) = (values[i * dim + k], values[(i + 1) * dim + k]);
            block[k] = h6 * (m1 - m0);
            block[dim + k] = 3.0 * h6 * m0;
            block[2 * dim + k] = y1 - y0 - h6 * (2.0 * m0 + m1);
            block[3 * dim + k] = y0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use splinegpu::SegmentTable;
    use splinegpu::{Curve, CurveKind, Derivatives, Points, Sampling};
    use splinegpu::{EndCondition, Fitter};

    fn natural(t: &[f64], values: &[f64], dim: usize) -> SegmentTable {
        let mut table = SegmentTable::default();
        Fitter::new()
            .fit_into(t, values, dim, &EndCondition::Natural, &mut table)
            .unwrap();
        table
    }

    /// Seven knots, and 200,003 uneven ones: more than three of the blocks the crate's solve
    /// runs on its threads (`fit::blocked::SOLVE_BLOCK`), which the textbook pass here does not
    /// have.
    #[test]
    fn the_plain_fit_gives_the_crates_coefficients() {
        let long: Vec<f64> = (0..200_003)
            .scan(0.0, |at, i: i32| {
                *at += 0.05 + f64::from((i * 7919) % 1000) * 1e-3;
                Some(*at)
            })
            .collect();
        for t in [vec![0.0, 0.5, 1.75, 2.0, 4.0, 4.5, 7.0], long] {
            let values: Vec<f64> = (0..t.len() * 3)
                .map(|v| ((v * 7) % 5) as f64 - 2.0)
                .collect();
            let table = natural(&t, &values, 3);
            let (mut m, mut scratch) = (Vec::new(), Vec::new());
            let mut out = vec![0.0; (t.len() - 1) * 12];
            natural_fit(&t, &values, 3, &mut m, &mut scratch, &mut out);
            for s in 0..table.len() {
                for (term, want) in table.segment(s).power().iter().enumerate() {
                    for k in 0..3 {
                        let got = out[s * 12 + term * 3 + k];
                        assert!(
                            (got - want[k]).abs() < 1e-12,
                            "segment {s} term {term}: {got} vs {}",
                            want[k]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_plain_catmull_rom_writes_the_evaluators_values() {
        use splinegpu::{Basis, Ends};
        let coords: Vec<f64> = (0..27).map(|v| f64::from((v * 5) % 7) - 3.0).collect();
        for ends in [Ends::Control, Ends::Closed] {
            let kind = CurveKind::Uniform {
                basis: Basis::CatmullRom,
                ends,
            };
            let curve = Curve::new(kind, Points::new(3, coords.clone()).unwrap()).unwrap();
            let mut job = EvalJob::new(Derivatives::None);
            job.push(&curve, &Sampling::PerSegment(6)).unwrap();
            let want = splinegpu::evaluate_reference(&job);
            let mut out = vec![f32::NAN; job.layout().values()];
            let written = catmull_rom(&coords, 3, ends == Ends::Closed, 6, &mut out);
            assert_eq!(written, out.len());
            for (got, want) in out.iter().zip(want.planes()[0]) {
                assert!(
                    (f64::from(*got) - want).abs() < 1e-5,
                    "{ends:?}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn the_plain_loops_write_the_evaluators_values() {
        let t = vec![0.0, 1.0, 1.5, 3.0, 4.0];
        let points = Points::new(3, (0..15).map(|v| f64::from(v % 4) - 1.5).collect()).unwrap();
        let kind = CurveKind::Interpolating {
            condition: EndCondition::Natural,
            t: Some(t),
        };
        let curve = Curve::new(kind, points).unwrap();
        for (sampling, ts) in [
            (Sampling::PerSegment(8), None),
            (
                Sampling::At(vec![0.25, 4.0, 1.0, 2.5, 0.0]),
                Some(vec![0.25, 4.0, 1.0, 2.5, 0.0]),
            ),
        ] {
            let mut job = EvalJob::new(Derivatives::None);
            for _ in 0..3 {
                job.push(&curve, &sampling).unwrap();
            }
            let want = splinegpu::evaluate_reference(&job);
            let mut out = vec![0.0f32; job.layout().values()];
            match ts {
                None => grid(&job, 8, &mut out, 2),
                Some(ts) => at(&job, &[ts.clone(), ts.clone(), ts], &mut out, 2),
            }
            for c in 0..job.len() {
                let range = job.layout().values_of(c);
                for (got, want) in out[range].iter().zip(want.curve(c).points) {
                    assert!((f64::from(*got) - want).abs() < 1e-5, "{got} vs {want}");
                }
            }
        }
    }
}
