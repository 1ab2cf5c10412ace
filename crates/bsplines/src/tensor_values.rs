//! The values (no derivative) of a tensor-product B-spline whose axes share one degree K − 1
//! and number at most three: the common case of `NdBSpline` and of every spline method of
//! `RegularGridInterpolator`, specialised so that a point costs a few tens of nanoseconds.
//!
//! Per axis, made once per call ([`Axis`]):
//! - the knot span of x found in O(1): the base interval cut into equal buckets, each holding
//!   the span of its start; x's span is its bucket's, stepped forward over the knots in
//!   between (a binary search there, so uneven knots cost a few steps, never a scan);
//!
//! and x's basis by the triangular form of the Cox-de Boor recurrence (Piegl and Tiller's
//! algorithm A2.2: k (k + 1) / 2 divisions, every divisor a knot difference that spans x's span,
//! so positive where the span is not empty; an empty span, reached only past an end, takes
//! `de_boor::basis`, which treats a term over a zero width as zero).
//!
//! The contraction over the K^d products is unrolled for d = 1, 2, 3.

/// One axis: its knots and span lookup.
#[derive(Debug)]
pub struct Axis<'a> {
    t: &'a [f64],
    k: usize,
    /// Coefficients along the axis (len(t) − k − 1).
    n: usize,
    /// The base interval's start and buckets per unit.
    lo: f64,
    scale: f64,
    /// Per bucket, the span of its start (k ..= n − 1); one more entry: n − 1.
    buckets: Vec<u32>,
}

impl<'a> Axis<'a> {
    /// The axis of knots t, degree k, its span lookup built.
    pub fn new(t: &'a [f64], k: usize) -> Self {
        let n = t.len() - k - 1;
        let (lo, hi) = (t[k], t[n]);
        let count = 2 * (n - k) + 1;
        let scale = count as f64 / (hi - lo);
        let mut buckets = Vec::with_capacity(count + 1);
        let mut l = k;
        for b in 0..count {
            let start = lo + b as f64 / scale;
            while l < n - 1 && t[l + 1] <= start {
                l += 1;
            }
            buckets.push(l as u32);
        }
        buckets.push((n - 1) as u32);
        Self {
            t,
            k,
            n,
            lo,
            scale,
            buckets,
        }
    }

    /// The span of x: clamp(#{t_j <= x} − 1, k, n − 1), as `de_boor::basis` takes it.
    #[inline]
    fn span(&self, x: f64) -> usize {
        let place = (x - self.lo) * self.scale;
        // Below the base interval (x < t_k; NaN is refused before).
        if place < 0.0 {
            return self.k;
        }
        let b = (place as usize).min(self.buckets.len() - 2);
        let (first, last) = (self.buckets[b] as usize, self.buckets[b + 1] as usize);
        // The last l in first..=last with t_l <= x; a bucket's start rounded past x can put
        // `first` one knot too far, which the step back mends.
        let mut l = first + self.t[first + 1..=last].partition_point(|&v| v <= x);
        while l > self.k && self.t[l] > x {
            l -= 1;
        }
        l
    }

    /// The K B-splines of x's span at x into `values`; returns the index of the first one's
    /// coefficient (span − k).
    #[inline]
    fn basis<const K: usize>(&self, x: f64, values: &mut [f64; K]) -> usize {
        let (l, t) = (self.span(x), self.t);
        if t[l] == t[l + 1] {
            let mut scratch = [0.0; K];
            crate::de_boor::basis(t, self.k, x, 0, values, &mut scratch);
            return l - self.k;
        }
        // left[j] = x − t_{l+1−j}, right[j] = t_{l+j} − x; N_0 = 1, then degree by degree.
        let (mut left, mut right) = ([0.0; K], [0.0; K]);
        values[0] = 1.0;
        for j in 1..K {
            left[j] = x - t[l + 1 - j];
            right[j] = t[l + j] - x;
            let mut saved = 0.0;
            for r in 0..j {
                let temp = values[r] / (right[r + 1] + left[j - r]);
                values[r] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            values[j] = saved;
        }
        l - self.k
    }

    /// Whether x lies in the base interval [t_k, t_n].
    #[inline]
    fn holds(&self, x: f64) -> bool {
        (self.t[self.k]..=self.t[self.n]).contains(&x)
    }
}

/// s(x) at each point of `xi` (rows of d = axes.len() coordinates, d in 1..=3) into `out` (m per
/// point), the coefficients `c` in C order with `strides` (in values) per axis; every axis of
/// degree K − 1. NaN for a NaN coordinate, and outside an axis' base interval unless
/// `extrapolate`.
pub fn evaluate<const K: usize>(
    axes: &[Axis<'_>],
    c: &[f64],
    strides: &[usize],
    m: usize,
    xi: &[f64],
    extrapolate: bool,
    out: &mut [f64],
) {
    let d = axes.len();
    debug_assert!((1..=3).contains(&d));
    let mut w = [[0.0; K]; 3];
    let mut first = [0usize; 3];
    for (row, x) in out.chunks_exact_mut(m).zip(xi.chunks_exact(d)) {
        let mut inside = true;
        for a in 0..d {
            if x[a].is_nan() || !(extrapolate || axes[a].holds(x[a])) {
                inside = false;
                break;
            }
            first[a] = axes[a].basis::<K>(x[a], &mut w[a]) * strides[a];
        }
        if !inside {
            row.fill(f64::NAN);
            continue;
        }
        let start: usize = first[..d].iter().sum();
        if m == 1 {
            row[0] = match d {
                1 => dot::<K>(&w[0], c, start, strides[0]),
                2 => (0..K)
                    .map(|r| w[0][r] * dot::<K>(&w[1], c, start + r * strides[0], strides[1]))
                    .sum(),
                _ => (0..K)
                    .map(|r| {
                        let plane = start + r * strides[0];
                        w[0][r]
                            * (0..K)
                                .map(|q| {
                                    let line = plane + q * strides[1];
                                    w[1][q] * dot::<K>(&w[2], c, line, strides[2])
                                })
                                .sum::<f64>()
                    })
                    .sum(),
            };
            continue;
        }
        row.fill(0.0);
        let mut add = |weight: f64, at: usize| {
            for (o, &v) in row.iter_mut().zip(&c[at..at + m]) {
                *o += weight * v;
            }
        };
        match d {
            1 => (0..K).for_each(|r| add(w[0][r], start + r * strides[0])),
            2 => {
                for r in 0..K {
                    for q in 0..K {
                        add(w[0][r] * w[1][q], start + r * strides[0] + q * strides[1]);
                    }
                }
            }
            _ => {
                for r in 0..K {
                    for q in 0..K {
                        let weight = w[0][r] * w[1][q];
                        let line = start + r * strides[0] + q * strides[1];
                        for (s, &w2) in w[2].iter().enumerate() {
                            add(weight * w2, line + s * strides[2]);
                        }
                    }
                }
            }
        }
    }
}

/// Σ_r w_r c[at + r · stride].
#[inline]
fn dot<const K: usize>(w: &[f64; K], c: &[f64], at: usize, stride: usize) -> f64 {
    (0..K).map(|r| w[r] * c[at + r * stride]).sum()
}

#[cfg(test)]
mod tests {
    use super::Axis;

    /// The triangular recurrence gives de Boor's basis (the generic recurrence) on uneven,
    /// repeated knots, inside and past both ends (an empty end span included).
    #[test]
    fn the_basis_matches_de_boor() {
        let t = [
            0.0, 0.0, 0.0, 0.0, 0.0, 1e-3, 0.5, 0.5, 0.5005, 3.0, 3.0, 3.0, 3.0,
        ];
        let axis = Axis::new(&t, 3);
        let (mut fast, mut slow, mut scratch) = ([0.0; 4], [0.0; 4], [0.0; 4]);
        for i in 0..700 {
            let x = -0.5 + f64::from(i) * 5e-3;
            let first = axis.basis::<4>(x, &mut fast);
            let l = crate::de_boor::basis(&t, 3, x, 0, &mut slow, &mut scratch);
            assert_eq!(first, l - 3, "span at {x}");
            for (a, b) in fast.iter().zip(&slow) {
                assert!(
                    (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                    "{fast:?} {slow:?} at {x}"
                );
            }
        }
    }

    /// The span lookup agrees with the count of knots at or below x on uneven, repeated
    /// knots, below, inside and above the base interval.
    #[test]
    fn spans_match_the_knot_count() {
        let t = [
            0.0, 0.0, 0.0, 0.0, 1e-3, 1e-3, 0.5, 0.5005, 3.0, 3.0, 3.0, 3.0,
        ];
        let axis = Axis::new(&t, 3);
        let n = t.len() - 4;
        for i in 0..4000 {
            let x = -0.5 + f64::from(i) * 1e-3;
            let count = t.iter().filter(|&&v| v <= x).count();
            let want = count.saturating_sub(1).clamp(3, n - 1);
            assert_eq!(axis.span(x), want, "at {x}");
        }
        for x in [1e-3, 0.5, 0.5005, 3.0, 7.0] {
            let count = t.iter().filter(|&&v| v <= x).count();
            assert_eq!(
                axis.span(x),
                count.saturating_sub(1).clamp(3, n - 1),
                "at {x}"
            );
        }
    }
}
