//! A software prefetch: the hint to start loading a value into the cache before it is read, for data
//! read in an order the hardware prefetchers cannot predict (by satellite id while the satellites are
//! evaluated in the sensing grid's cell order). It changes no value, only when the memory is read.

/// Starts loading the cache line of `value` into every cache level (nothing on targets without a
/// prefetch instruction the standard library exposes).
#[inline]
pub(crate) fn read<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    #[allow(unsafe_code)]
    // SAFETY: SSE, the intrinsic's only feature, is part of the x86-64 baseline; a prefetch never
    // faults and reads nothing the program sees (and `value` is a valid reference anyway).
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(value).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}
