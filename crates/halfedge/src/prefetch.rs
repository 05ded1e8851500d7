//! Software prefetching for walks whose next addresses are known ahead of time.
//!
//! Refining a hierarchy splits hundreds of thousands of records in a row, each touching a
//! handful of halfedges, slot states and positions scattered over arrays far larger than
//! the caches: the walk waits on memory, not on arithmetic. The records say ahead which
//! elements the next splits touch, so the hierarchy asks for them a few splits early
//! (the classic software pipelining of pointer-chasing loops) and the loads overlap.

/// Asks the processor to bring the cache line holding `slice[i]` closer; does nothing when
/// `i` is out of bounds or on targets without a prefetch instruction. Never changes what
/// a program computes, only when its memory arrives.
#[inline(always)]
pub(crate) fn prefetch<T>(slice: &[T], i: usize) {
    if let Some(item) = slice.get(i) {
        prefetch_line(item);
    }
}

#[cfg(target_arch = "x86_64")]
#[inline(always)]
#[allow(unsafe_code)]
fn prefetch_line<T>(item: &T) {
    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
    // SAFETY: `_mm_prefetch` is a hint that never faults and never reads or writes the
    // memory architecturally; SSE, which it needs, is part of the x86_64 baseline. The
    // pointer comes from a live reference anyway.
    unsafe { _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(item).cast::<i8>()) }
}

#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn prefetch_line<T>(_item: &T) {}

#[cfg(test)]
mod tests {
    use super::prefetch;

    #[test]
    fn out_of_range_indices_are_ignored() {
        let empty: [u64; 0] = [];
        prefetch(&empty, 0);
        prefetch(&[1u32, 2, 3], 3);
        prefetch(&[1u32, 2, 3], usize::MAX);
        prefetch(&[1u32, 2, 3], 2);
    }
}
