//! `JobLayout`: where every curve's samples go, on the host and on the device. It is the one
//! place that knows offsets and sizes; [`EvalJob`](crate::EvalJob) extends it as curves are
//! added, and [`Samples`](crate::Samples), both CPU evaluators, the GPU packer, the renderer
//! path ([`OutputLayout`](crate::OutputLayout)) and the streaming writers read it.
//!
//! Curve c owns samples `samples(c)`. Each plane (positions, dP/dt, d2P/dt2) holds `dim(c)`
//! values per sample:
//! - on the host, curves follow each other without gaps: curve c's values are `values(c)`;
//! - on the device, every curve starts at a multiple of 4 floats (16 bytes), so that vector
//!   stores of 4 samples stay aligned: curve c's values start at `device_start(c)`.

use std::ops::Range;

/// Offsets and sizes of a job's samples (see the module docs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JobLayout {
    dims: Vec<usize>,
    /// `sample_offsets[c]..sample_offsets[c + 1]` are curve c's samples.
    sample_offsets: Vec<usize>,
    /// Host planes: curve c's values from `value_offsets[c]` on, packed.
    value_offsets: Vec<usize>,
    /// Device planes: curve c's values from `device_offsets[c]` on, a multiple of 4.
    device_offsets: Vec<usize>,
}

impl Default for JobLayout {
    fn default() -> Self {
        Self {
            dims: Vec::new(),
            sample_offsets: vec![0],
            value_offsets: vec![0],
            device_offsets: vec![0],
        }
    }
}

impl JobLayout {
    /// Appends a curve of `samples` samples with `dim` values each.
    ///
    /// # Errors
    /// `None` (nothing appended) when an offset would not fit in `usize`.
    pub(crate) fn push(&mut self, dim: usize, samples: usize) -> Option<()> {
        let values = samples.checked_mul(dim)?;
        let sample_end = self.samples().checked_add(samples)?;
        let value_end = self.values().checked_add(values)?;
        let device_end = self
            .device_values()
            .checked_add(values)?
            .checked_next_multiple_of(4)?;
        self.dims.push(dim);
        self.sample_offsets.push(sample_end);
        self.value_offsets.push(value_end);
        self.device_offsets.push(device_end);
        Some(())
    }

    /// Number of curves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.dims.len()
    }

    /// True when there are no curves.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.dims.is_empty()
    }

    /// Curve `c`'s coordinates per sample.
    #[must_use]
    pub fn dim(&self, c: usize) -> usize {
        self.dims[c]
    }

    /// The largest dimension of any curve (0 without curves).
    #[must_use]
    pub fn max_dim(&self) -> usize {
        self.dims.iter().copied().max().unwrap_or(0)
    }

    /// Curve `c`'s samples, as indices into the job's samples.
    #[must_use]
    pub fn samples_of(&self, c: usize) -> Range<usize> {
        self.sample_offsets[c]..self.sample_offsets[c + 1]
    }

    /// Curve `c`'s values in each host plane.
    #[must_use]
    pub fn values_of(&self, c: usize) -> Range<usize> {
        self.value_offsets[c]..self.value_offsets[c + 1]
    }

    /// Runs `each(curves, part)` on `threads` threads (at most one per curve), each given a
    /// contiguous range of curves and the part of the host `plane` that holds their values
    /// (from the first curve's first value on).
    pub fn per_thread_curves<T: Send>(
        &self,
        mut plane: &mut [T],
        threads: usize,
        each: impl Fn(Range<usize>, &mut [T]) + Sync,
    ) {
        let parts: Vec<_> = crate::parallel::even_ranges(self.len(), threads)
            .map(|curves| {
                let values = self.value_offsets[curves.end] - self.value_offsets[curves.start];
                let part = std::mem::take(&mut plane).split_at_mut(values);
                plane = part.1;
                (curves, part.0)
            })
            .collect();
        crate::parallel::fan_out(parts, |(curves, part)| each(curves, part));
    }

    /// Where curve `c`'s values start in each device plane (a multiple of 4).
    #[must_use]
    pub fn device_start(&self, c: usize) -> usize {
        self.device_offsets[c]
    }

    /// Samples of the whole job.
    #[must_use]
    pub fn samples(&self) -> usize {
        self.sample_offsets[self.len()]
    }

    /// Values per host plane.
    #[must_use]
    pub fn values(&self) -> usize {
        self.value_offsets[self.len()]
    }

    /// Floats per device plane (a multiple of 4).
    #[must_use]
    pub fn device_values(&self) -> usize {
        self.device_offsets[self.len()]
    }

    /// The curve that holds sample `i` (`i < samples()`).
    #[must_use]
    pub fn curve_of_sample(&self, i: usize) -> usize {
        self.sample_offsets.partition_point(|&s| s <= i) - 1
    }

    /// Where sample `i` (`i <= samples()`) starts in each host plane.
    #[must_use]
    pub fn value_of_sample(&self, i: usize) -> usize {
        if i == self.samples() {
            return self.values();
        }
        let c = self.curve_of_sample(i);
        self.value_offsets[c] + (i - self.sample_offsets[c]) * self.dims[c]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_curves_start_aligned_and_host_curves_packed() {
        let mut layout = JobLayout::default();
        for (dim, n) in [(3, 5), (1, 2), (64, 1), (2, 0), (5, 7)] {
            layout.push(dim, n).unwrap();
        }
        assert_eq!(layout.samples(), 15);
        assert_eq!(layout.values(), 15 + 2 + 64 + 35);
        assert_eq!(
            (0..5).map(|c| layout.device_start(c)).collect::<Vec<_>>(),
            [0, 16, 20, 84, 84]
        );
        assert_eq!(layout.device_values(), 84 + 36);
        assert_eq!(layout.values_of(2), 17..81);
        assert_eq!(layout.curve_of_sample(7), 2);
        assert_eq!(
            layout.curve_of_sample(8),
            4,
            "the empty curve holds no sample"
        );
        assert_eq!(layout.value_of_sample(9), 81 + 5);
        assert_eq!(layout.value_of_sample(15), layout.values());
    }

    #[test]
    fn offsets_that_overflow_are_refused_and_nothing_is_appended() {
        let mut layout = JobLayout::default();
        layout.push(3, 10).unwrap();
        assert_eq!(layout.push(64, usize::MAX / 8), None);
        assert_eq!(layout.push(1, usize::MAX - 5), None);
        assert_eq!(layout.len(), 1);
        assert_eq!(layout.device_values(), 32);
    }
}
