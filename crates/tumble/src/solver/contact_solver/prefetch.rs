//! Asking the cache for memory before it is read: the one home of the
//! solver's software prefetches (x86-64's `prefetcht0`; nothing elsewhere).
//!
//! Where a pass reads records scattered over a large array (a joint's
//! record a few KB past its rows, a bundle's four patches and their points
//! spread over the narrow stage's output), each read waits for memory in
//! turn; asked for ahead, the waits overlap. A prefetch is only a hint: it
//! changes no value, so no result depends on it.

/// Asks for the cache lines of `value`, from its start, at most `bytes`
/// of them (the size of a large record's first parts).
#[inline(always)]
pub(crate) fn prefetch<T: ?Sized>(value: &T, bytes: usize) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is a hint; it reads nothing and cannot fault,
    // whatever the address.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let start = (value as *const T).cast::<i8>();
        let bytes = bytes.min(std::mem::size_of_val(value));
        for line in 0..bytes.div_ceil(64) {
            _mm_prefetch(start.wrapping_add(64 * line), _MM_HINT_T0);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (value, bytes);
}
