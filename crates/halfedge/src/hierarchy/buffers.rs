//! Memory for a build's output made ahead: vectors whose pages are mapped before the
//! build writes them, and handing their contents over.

/// Fewest records expected for [`Hierarchy::prefault`] to make buffers ahead (a smaller
/// build is over before they would be ready).
pub(super) const PREFAULT_RECORDS: usize = 1 << 12;

/// An empty vector with room for `capacity` elements, the memory of the first `touched`
/// mapped (an element a page written with zero bytes).
pub(super) fn prefaulted<T>((capacity, touched): (usize, usize)) -> Vec<T> {
    let mut v = Vec::with_capacity(capacity);
    let step = (4096 / std::mem::size_of::<T>().max(1)).max(1);
    for slot in v.spare_capacity_mut()[..touched.min(capacity)]
        .iter_mut()
        .step_by(step)
    {
        *slot = std::mem::MaybeUninit::zeroed();
    }
    std::hint::black_box(&mut v);
    v
}

/// Makes `new` (empty) hold `old`'s elements and take its place.
pub(super) fn adopt<T: Copy>(old: &mut Vec<T>, mut new: Vec<T>) {
    new.clear();
    new.extend_from_slice(old);
    *old = new;
}
