//! A global allocator that counts allocations, for the "allocates nothing" tests. Included by
//! path from the core's geometry allocation test and, in test builds, from the core's `lib.rs`
//! (for the DAE hot-path test in `dae/alloc_tests.rs`).
//!
//! The count is per thread: only allocations made by the thread that reads [`allocs`] are
//! seen. The process-wide counter this replaces also saw the test harness's own threads, and
//! the allocation tests failed now and then under `cargo test --workspace` on a loaded machine
//! (4 allocations in one run of three) while passing alone. The code under test runs on the
//! calling thread, so nothing it does escapes the per-thread count.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// Counts `alloc` and `realloc` calls of the current thread, then forwards to the system
/// allocator.
pub(crate) struct Counting;

thread_local! {
    // `const` initialisation: reading it never allocates (no lazy init inside the allocator).
    static THREAD_ALLOCS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: during thread teardown the slot may be gone; such allocations are not ours.
    let _ = THREAD_ALLOCS.try_with(|c| c.set(c.get() + 1));
}

/// Allocations made so far by the calling thread.
pub(crate) fn allocs() -> usize {
    THREAD_ALLOCS.with(|c| c.get())
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;
