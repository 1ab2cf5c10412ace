//! Fanning work over threads, written once: every stage that runs on several threads cuts its
//! work into parts with [`even_ranges`] (and its slices with [`take_front`]) and hands them to
//! [`fan_out`] or [`fan_out_map`], which run them on the process's one pool of threads
//! (rayon's global pool, started once) and return when all are done. A single part runs on the
//! calling thread, touching no pool.

use std::ops::Range;

/// `0..n` cut into at most `parts` contiguous ranges of sizes that differ by at most one (part
/// k is `n·k/parts .. n·(k+1)/parts`); no empty range unless `n` is 0, which gives one.
pub(crate) fn even_ranges(n: usize, parts: usize) -> impl Iterator<Item = Range<usize>> {
    let parts = parts.clamp(1, n.max(1));
    (0..parts).map(move |k| n * k / parts..n * (k + 1) / parts)
}

/// The first `n` values of `slice` (none of an empty slice, which stands for an absent plane),
/// leaving the rest in `slice`.
pub(crate) fn take_front<'a, T>(slice: &mut &'a mut [T], n: usize) -> &'a mut [T] {
    let n = if slice.is_empty() { 0 } else { n };
    let (head, tail) = std::mem::take(slice).split_at_mut(n);
    *slice = tail;
    head
}

/// Runs `work` on every part, each a task of the pool (the calling thread takes part too), all
/// done when this returns. A single part runs here alone.
pub(crate) fn fan_out<P: Send>(parts: Vec<P>, work: impl Fn(P) + Sync) {
    fan_out_map(parts, work);
}

/// [`fan_out`], returning each part's result in the parts' order.
///
/// # Panics
/// If `work` panicked on a part (the panic is resumed here).
pub(crate) fn fan_out_map<P: Send, R: Send>(parts: Vec<P>, work: impl Fn(P) -> R + Sync) -> Vec<R> {
    use rayon::iter::{IndexedParallelIterator, IntoParallelIterator, ParallelIterator};
    if parts.len() <= 1 {
        return parts.into_iter().map(work).collect();
    }
    // One task per part: the parts are already sized for a thread each.
    let work = &work;
    parts.into_par_iter().with_max_len(1).map(work).collect()
}

/// `answer(i)` for every i in `0..count`, in order, on every thread: the indices cut into a few
/// ranges a thread (so that uneven answers, as queries' are, even out).
pub(crate) fn map_indices<T: Send>(count: usize, answer: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let parts = even_ranges(count, crate::available_threads() * 4).collect();
    let answers = fan_out_map(parts, |range: Range<usize>| {
        range.map(&answer).collect::<Vec<_>>()
    });
    answers.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn even_ranges_cover_every_item_once_in_order() {
        for n in [0, 1, 2, 7, 100] {
            for parts in [1, 2, 3, 8, 200] {
                let ranges: Vec<_> = even_ranges(n, parts).collect();
                assert_eq!(ranges.first().map(|r| r.start), Some(0));
                assert_eq!(ranges.last().map(|r| r.end), Some(n));
                assert!(ranges.windows(2).all(|w| w[0].end == w[1].start));
                assert!(ranges.len() <= parts.max(1));
                assert!(
                    n == 0 || ranges.iter().all(|r| !r.is_empty()),
                    "{n} in {parts}"
                );
            }
        }
    }

    #[test]
    fn fan_out_map_keeps_the_parts_order() {
        let parts: Vec<usize> = (0..9).collect();
        assert_eq!(
            fan_out_map(parts, |p| p * p),
            [0, 1, 4, 9, 16, 25, 36, 49, 64]
        );
        assert!(fan_out_map(Vec::<usize>::new(), |p| p).is_empty());
    }
}
