//! Test helpers shared by the corps crates: a counting global allocator (real-time
//! discipline: "no heap allocation once the workspaces exist") and a relative closeness check.
//!
//! ```
//! #[global_allocator]
//! static GLOBAL: corps_testkit::CountingAllocator = corps_testkit::CountingAllocator;
//! let n = corps_testkit::allocations_during(|| { /* a control tick */ });
//! assert_eq!(n, 0);
//! ```

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// A global allocator that counts allocations and reallocations per thread (so parallel
/// tests do not see each other's), delegating to the system allocator.
pub struct CountingAllocator;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        System.alloc(l)
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        System.dealloc(p, l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        System.realloc(p, l, n)
    }
}

/// Allocations made by this thread so far (meaningful only with [`CountingAllocator`]
/// installed as the global allocator).
pub fn allocations() -> usize {
    ALLOCS.with(|c| c.get())
}

/// Allocations made by this thread while running `f`.
pub fn allocations_during(f: impl FnOnce()) -> usize {
    let before = allocations();
    f();
    allocations() - before
}

/// Asserts max |a − b| ≤ tol · max(1, max |b|), naming `what` and the error on failure.
pub fn assert_close(what: &str, a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len(), "{what}: sizes differ");
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let err = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(
        err <= tol * scale,
        "{what}: max error {err:.3e} > {tol:.1e} × scale {scale:.3e}"
    );
}

/// A global allocator that tracks the bytes alive on the heap, across all threads, and their
/// peak: for tests that memory does not grow with a run's length. Install it in a test binary
/// of its own (its figures are global).
pub struct PeakAllocator;

static LIVE: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
static PEAK: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

fn grew(bytes: usize) {
    use std::sync::atomic::Ordering::Relaxed;
    let now = LIVE.fetch_add(bytes, Relaxed) + bytes;
    PEAK.fetch_max(now, Relaxed);
}

unsafe impl GlobalAlloc for PeakAllocator {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = System.alloc(l);
        if !p.is_null() {
            grew(l.size());
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size(), std::sync::atomic::Ordering::Relaxed);
        System.dealloc(p, l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        let q = System.realloc(p, l, n);
        if !q.is_null() {
            LIVE.fetch_sub(l.size(), std::sync::atomic::Ordering::Relaxed);
            grew(n);
        }
        q
    }
}

/// The peak of the heap bytes alive while running `f` (with [`PeakAllocator`] installed).
pub fn peak_heap_during<T>(f: impl FnOnce() -> T) -> (T, usize) {
    use std::sync::atomic::Ordering::Relaxed;
    PEAK.store(LIVE.load(Relaxed), Relaxed);
    let out = f();
    (out, PEAK.load(Relaxed))
}
