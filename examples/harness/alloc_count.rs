//! A counting global allocator: wraps `System` and tracks live bytes, the
//! peak of live bytes, and allocation counts — for the whole process and,
//! separately, for the calling thread (so a test can measure itself while
//! other tests run in parallel in the same binary).
//!
//! Install it in an example or test binary:
//!
//! ```ignore
//! #[global_allocator]
//! static ALLOC: harness::alloc_count::CountingAlloc = harness::alloc_count::CountingAlloc::new();
//! ```
//!
//! Then `ALLOC.reset_peak()` before the part to measure and
//! `ALLOC.snapshot()` after it. Counters are relaxed atomics: exact for a
//! single thread, a consistent-enough picture across threads (the peak is
//! maintained with `fetch_max` after every allocation).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering::Relaxed};

/// What the allocator has counted, at one moment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AllocSnapshot {
    /// Bytes live now.
    pub current_bytes: usize,
    /// Highest `current_bytes` since start or the last `reset_peak`.
    pub peak_bytes: usize,
    /// Allocations since start (`alloc`, `alloc_zeroed`; each successful
    /// `realloc` counts as one deallocation plus one allocation).
    pub allocations: u64,
    /// Deallocations since start.
    pub deallocations: u64,
    /// Bytes requested in all allocations since start.
    pub total_allocated_bytes: u64,
}

/// Per-thread counters (signed: a block may be freed by another thread).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ThreadSnapshot {
    /// Bytes allocated minus bytes freed by this thread.
    pub current_bytes: isize,
    /// Highest `current_bytes` since the thread started or its last
    /// `reset_thread_peak`.
    pub peak_bytes: isize,
    /// Allocations made by this thread.
    pub allocations: u64,
}

thread_local! {
    // Const-initialised `Cell`s of plain integers: no lazy init, no
    // destructor, so reading them inside the allocator never allocates and
    // never fails, even during thread teardown.
    static T_CURRENT: Cell<isize> = const { Cell::new(0) };
    static T_PEAK: Cell<isize> = const { Cell::new(0) };
    static T_ALLOCS: Cell<u64> = const { Cell::new(0) };
}

/// The counting allocator (see the module docs).
pub struct CountingAlloc {
    current: AtomicUsize,
    peak: AtomicUsize,
    allocations: AtomicU64,
    deallocations: AtomicU64,
    total: AtomicU64,
}

impl Default for CountingAlloc {
    fn default() -> Self {
        Self::new()
    }
}

impl CountingAlloc {
    /// A fresh allocator with all counters at zero (usable in a `static`).
    pub const fn new() -> Self {
        CountingAlloc {
            current: AtomicUsize::new(0),
            peak: AtomicUsize::new(0),
            allocations: AtomicU64::new(0),
            deallocations: AtomicU64::new(0),
            total: AtomicU64::new(0),
        }
    }

    /// The process-wide counters now.
    pub fn snapshot(&self) -> AllocSnapshot {
        AllocSnapshot {
            current_bytes: self.current.load(Relaxed),
            peak_bytes: self.peak.load(Relaxed),
            allocations: self.allocations.load(Relaxed),
            deallocations: self.deallocations.load(Relaxed),
            total_allocated_bytes: self.total.load(Relaxed),
        }
    }

    /// Sets the process-wide peak to the bytes live now.
    pub fn reset_peak(&self) {
        self.peak.store(self.current.load(Relaxed), Relaxed);
    }

    /// The calling thread's counters now.
    pub fn thread_snapshot(&self) -> ThreadSnapshot {
        ThreadSnapshot {
            current_bytes: T_CURRENT.with(Cell::get),
            peak_bytes: T_PEAK.with(Cell::get),
            allocations: T_ALLOCS.with(Cell::get),
        }
    }

    /// Sets the calling thread's peak to its live bytes now.
    pub fn reset_thread_peak(&self) {
        let cur = T_CURRENT.with(Cell::get);
        T_PEAK.with(|p| p.set(cur));
    }

    fn added(&self, size: usize) {
        let now = self.current.fetch_add(size, Relaxed) + size;
        self.peak.fetch_max(now, Relaxed);
        self.allocations.fetch_add(1, Relaxed);
        self.total.fetch_add(size as u64, Relaxed);
        let _ = T_CURRENT.try_with(|c| {
            let now = c.get() + size as isize;
            c.set(now);
            let _ = T_PEAK.try_with(|p| p.set(p.get().max(now)));
        });
        let _ = T_ALLOCS.try_with(|a| a.set(a.get() + 1));
    }

    fn removed(&self, size: usize) {
        self.current.fetch_sub(size, Relaxed);
        self.deallocations.fetch_add(1, Relaxed);
        let _ = T_CURRENT.try_with(|c| c.set(c.get() - size as isize));
    }
}

// SAFETY: every method forwards the caller's arguments unchanged to
// `System`, which upholds the `GlobalAlloc` contract; the bookkeeping around
// the calls only touches atomics and allocation-free thread-locals, never
// the memory blocks, and counts a block only when `System` succeeded.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded contract (non-zero-size layout from the caller).
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            self.added(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as for `alloc`.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            self.added(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by this allocator (i.e. by `System`)
        // with `layout`, as the caller guarantees.
        unsafe { System.dealloc(ptr, layout) };
        self.removed(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller guarantees `ptr`/`layout` describe a live block
        // of this allocator and `new_size` is valid for `layout.align()`.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            // Counted as freeing the old block and allocating the new one.
            self.removed(layout.size());
            self.added(new_size);
        }
        p
    }
}
