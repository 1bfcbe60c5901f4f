//! The bidirectional methods keep their per-iteration lists (camera batches, photon deposits,
//! grid build, film batch statistics, gather depths) between iterations: a render's heap
//! allocations do not grow with the number of iterations once the lists have grown
//! (BENCHMARKS.md "Allocation-free bidirectional iterations"). Counted by a global allocator that
//! wraps the system's; this file holds one test so that no other test allocates meanwhile.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};

use common::{bidir_ov, render_file, shipped};
use quasar::render::job::JobOverrides;

/// The system allocator, counting allocations and reallocations.
struct Counting;

const THREADS: usize = 2;
static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

// SAFETY: every call is forwarded unchanged to the system allocator.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: the caller's contract is the system allocator's
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as above
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as above
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations of a whole render (scene load to image) of `iterations`.
fn allocations(method: &str, width: u32, height: u32, iterations: u32) -> u64 {
    let ov = JobOverrides {
        threads: Some(THREADS),
        ..bidir_ov(width, height, method, iterations, 2 * (width * height) as u64, 7)
    };
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    let out = render_file(&shipped("glass-plate/glass-plate.toml"), &ov);
    let n = ALLOCATIONS.load(Ordering::Relaxed) - before;
    drop(out);
    n
}

#[test]
fn iterations_allocate_nothing_once_their_lists_have_grown() {
    // the process's first render also makes its lazily built tables
    allocations("adaptive+quasi", 8, 8, 2);
    // iterations 41-80 run after the lists have grown and after the adaptive depth's pilots
    for method in ["adaptive+quasi", "vismap"] {
        for (w, h) in [(32, 24), (96, 72)] {
            let (a, b) = (allocations(method, w, h, 40), allocations(method, w, h, 80));
            println!("{method} {w}x{h}: {a} allocations for 40 iterations, {b} for 80");
            // one allocation per iteration (an image-sized list made afresh, say) adds 40; the
            // lists kept by iterations 1-40 may still grow a few times in iterations 41-80.
            // Before they were kept: about 2 per camera batch of 64 pixels, 4 per chunk of 256
            // photons and 5 per chunk of 256 grid points (270 per iteration at 96x72)
            assert!(b <= a + 10, "{method} {w}x{h}: {} allocations in iterations 41-80", b as i64 - a as i64);
        }
    }
}
