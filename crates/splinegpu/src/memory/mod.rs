//! Large buffers backed by transparent huge pages where Linux allows it.
//!
//! A fresh page costs a fault on its first touch (docs/benchmarks.md has what it cost a
//! million-knot fit's table on the machines this crate is measured on). NumPy asks for huge pages on its large arrays
//! (`madvise(MADV_HUGEPAGE)`), and a system whose transparent huge pages are set to "madvise"
//! (the usual default) gives them only where asked: a 2 MiB page costs one fault. The crate's
//! own large buffers ask the same before they are first touched.
//!
//! `available`: the memory a job may still take, under every limit the process runs under.

mod available;

pub use available::available_memory;

/// Bytes below which a buffer is left as the allocator made it (a huge page is 2 MiB; the
/// advice covers only the whole huge pages inside the buffer).
const ADVISED_BYTES: usize = 4 << 20;

/// Makes room in `v` for `n` elements in all (its length unchanged). Where that takes a new
/// allocation of at least 4 MiB, its untouched part is advised onto huge pages.
pub(crate) fn reserve_on_huge_pages<T>(v: &mut Vec<T>, n: usize) {
    if v.capacity() >= n {
        return;
    }
    v.reserve_exact(n - v.len());
    let spare = v.spare_capacity_mut();
    if size_of_val(spare) >= ADVISED_BYTES {
        advise_huge_pages(spare.as_mut_ptr().cast(), size_of_val(spare));
    }
}

/// `n` zeros in a new vector, the allocation fallible and zeroed by the allocator (fresh pages
/// from the system come zeroed: nothing is written until the caller writes, as `vec![0; n]`
/// does); from 4 MiB on, advised onto huge pages before the caller's first touch.
pub(crate) fn try_zeroed<T: bytemuck::Zeroable>(
    n: usize,
) -> Result<Vec<T>, std::collections::TryReserveError> {
    // bytemuck's refusal carries no reason: the standard one is made from an impossible
    // reservation, which fails the same way.
    let mut zeros: Box<[T]> = bytemuck::allocation::try_zeroed_slice_box(n)
        .map_err(|()| Vec::<u8>::new().try_reserve_exact(usize::MAX).unwrap_err())?;
    if size_of_val(&*zeros) >= ADVISED_BYTES {
        advise_huge_pages(zeros.as_mut_ptr().cast(), size_of_val(&*zeros));
    }
    Ok(Vec::from(zeros))
}

/// [`try_zeroed`] where the caller has checked the job against the memory it may take: an
/// allocation that fails nonetheless ends the process as `vec![0; n]`'s does.
pub(crate) fn zeroed<T: bytemuck::Zeroable>(n: usize) -> Vec<T> {
    try_zeroed(n).unwrap_or_else(|_| {
        let layout = std::alloc::Layout::array::<T>(n).unwrap_or(std::alloc::Layout::new::<T>());
        std::alloc::handle_alloc_error(layout)
    })
}

/// Sets `v`'s length to `n` for a caller that writes every value before it reads one. A
/// vector with room for `n` is resized in place (its old values kept, new ones zero); a
/// smaller one is replaced by [`zeroed`]'s fresh allocation, which nothing writes here: its
/// pages are zeroed by the system where the caller first touches them, on the caller's
/// threads, where `resize` would write every value once more on this one (a million-knot
/// fit's table and scratch are 150 MB of fresh pages).
pub(crate) fn resize_for_overwrite<T: bytemuck::Zeroable + Clone>(v: &mut Vec<T>, n: usize) {
    if v.capacity() >= n {
        v.resize(n, T::zeroed());
    } else {
        *v = zeroed(n);
    }
}

/// Asks Linux to back the whole 2 MiB pages inside `[start, start + bytes)` with huge pages.
#[cfg(target_os = "linux")]
fn advise_huge_pages(start: *mut u8, bytes: usize) {
    const HUGE_PAGE: usize = 2 << 20;
    let first = (start as usize).next_multiple_of(HUGE_PAGE);
    let end = (start as usize + bytes) / HUGE_PAGE * HUGE_PAGE;
    if end <= first {
        return;
    }
    #[allow(
        unsafe_code,
        reason = "madvise is a system call without a safe wrapper; the range is memory this \
                  crate owns"
    )]
    // SAFETY: [first, end) lies inside the spare capacity of a Vec this crate owns, which
    // nothing reads or writes yet; MADV_HUGEPAGE changes how the kernel backs those pages,
    // never their contents. A refusal (an old kernel, huge pages off) changes nothing, so
    // its result is not needed.
    unsafe {
        libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
    }
}

/// Elsewhere the allocator's pages are kept as they are.
#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_start: *mut u8, _bytes: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_buffer_for_overwriting_has_its_length() {
        for (start, n) in [(0, 0), (7, 3), (7, 7), (3, 10), (0, (8 << 20) / 8 + 3)] {
            let mut v: Vec<f64> = vec![1.5; start];
            resize_for_overwrite(&mut v, n);
            assert_eq!(v.len(), n);
            // Kept where there was room, zero where new.
            let kept = if start >= n { n } else { 0 };
            assert!(v[..kept].iter().all(|&x| x == 1.5));
            assert!(v[kept..].iter().all(|&x| x == 0.0));
        }
    }

    #[test]
    fn room_is_made_and_the_contents_kept() {
        for n in [0, 10, (8 << 20) / 8 + 3] {
            let mut v: Vec<f64> = vec![1.5; 7];
            reserve_on_huge_pages(&mut v, n.max(7));
            assert!(v.capacity() >= n);
            assert_eq!(v, [1.5; 7]);
            v.resize(n.max(7), 2.0);
            assert!(v[7..].iter().all(|&x| x == 2.0));
        }
    }
}
