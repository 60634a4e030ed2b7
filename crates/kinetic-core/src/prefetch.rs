//! A hint that data is wanted soon. The hard-sphere structures are bound by memory: they ask
//! for the spheres of the next events while they work on this one; the broad phases ask for
//! the engine's bodies a few ahead of the one they read.

/// Asks the processor to bring the cache line holding `value` into its caches, without
/// waiting for it. A hint only: nothing is read into the program, and nothing can fault.
#[inline(always)]
pub fn prefetch<T: ?Sized>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch never faults and reads nothing into the program; `value` is a live
    // reference, and SSE, which provides the instruction, is part of every x86-64 processor.
    #[allow(unsafe_code)]
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(value).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// [`prefetch`] of every cache line `value` spans (a record larger than a line).
#[inline(always)]
pub fn prefetch_all<T>(value: &T) {
    let start = std::ptr::from_ref(value).cast::<u8>();
    // From the line the value starts in to the one it ends in (it need not start on one).
    let end = start.addr() + std::mem::size_of::<T>();
    let mut at = start.wrapping_sub(start.addr() % 64);
    while at.addr() < end {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as in `prefetch`; the address lies within `value`, and a prefetch of any
        // address is harmless.
        #[allow(unsafe_code)]
        unsafe {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            _mm_prefetch::<_MM_HINT_T0>(at.cast());
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = at;
        at = at.wrapping_add(64);
    }
}
