//! A hint to the processor that memory will be read soon.

/// Asks for the cache line holding `x` to be loaded, where the target can be asked; otherwise
/// does nothing. A hint only: it changes no result.
#[inline(always)]
pub(crate) fn read<T>(x: &T) {
    // SAFETY: SSE is part of every x86_64 processor, and a prefetch reads nothing the program
    // sees (it never faults, whatever the address; here the address is a live reference).
    #[cfg(target_arch = "x86_64")]
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            (x as *const T).cast::<i8>(),
        )
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}
