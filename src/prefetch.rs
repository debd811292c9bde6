//! A software prefetch: the hint to start loading a value into the cache before it is read, for data
//! read in an order the hardware prefetchers cannot predict (by satellite id while the satellites are
//! evaluated in the sensing grid's cell order). It changes no value, only when the memory is read.

/// Starts loading the cache line of `value` into every cache level (nothing on targets without a
/// prefetch instruction the standard library exposes).
#[inline]
pub(crate) fn read<T>(value: &T) {
    line(std::ptr::from_ref(value).cast());
}

/// [`read`] for every cache line the value at `value` spans (a value larger than a line, or one
/// straddling two). Takes a pointer, so that a value another part of the pass will write can be hinted
/// without a reference to it; nothing is read through it.
#[inline]
pub(crate) fn read_all<T>(value: *const T) {
    const LINE: usize = 64;
    let start = value.cast::<u8>();
    let size = std::mem::size_of::<T>();
    let mut offset = 0;
    while offset < size {
        line(start.wrapping_add(offset));
        offset += LINE;
    }
    if size > 0 {
        line(start.wrapping_add(size - 1));
    }
}

/// Starts loading the cache line holding `address` into every cache level.
#[inline]
fn line(address: *const u8) {
    #[cfg(target_arch = "x86_64")]
    #[allow(unsafe_code)]
    // SAFETY: SSE, the intrinsic's only feature, is part of the x86-64 baseline; a prefetch never
    // faults and reads nothing the program sees (and `address` lies inside a valid value anyway).
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(address.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = address;
}
