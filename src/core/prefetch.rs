//! Software prefetch: asks the CPU to start loading a value's cache lines now so that a later read
//! finds them in the L1 cache. Useful where a loop knows its next addresses one step ahead of
//! reading them and has independent work to do in between (software pipelining, Chen et al.,
//! "Improving hash join performance through prefetching", ICDE 2004). A prefetch never faults
//! and never changes a result; on targets other than x86-64 it does nothing.

/// Bytes in a cache line (x86-64 and most aarch64 cores).
const LINE: usize = 64;

/// Starts loading the cache line at `p` (a hint: the address need not be valid).
#[inline(always)]
fn prefetch_line(p: *const u8) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: PREFETCHT0 is a hint that reads no memory architecturally and never faults, and
    // SSE is part of the x86-64 baseline
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// Starts loading the first cache line of `value`.
#[inline(always)]
pub fn prefetch<T>(value: &T) {
    prefetch_line((value as *const T).cast());
}

/// Starts loading every cache line `value` spans.
#[inline(always)]
pub fn prefetch_all<T>(value: &T) {
    let start = (value as *const T).cast::<u8>();
    let first = start as usize / LINE;
    let last = (start as usize + std::mem::size_of::<T>().max(1) - 1) / LINE;
    for line in 0..=last - first {
        prefetch_line(start.wrapping_add(line * LINE));
    }
}
