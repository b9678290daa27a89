//! A counting global allocator around `std::alloc::System`: every
//! allocation (and reallocation) on every thread, with its size.
//!
//! Attribution: while [`attribute`] is on, every `n`-th allocation is
//! classified from its backtrace (file paths of the frames, from the
//! allocation outwards): the first frame in kimpact's sources
//! (`crates/rapier-adapter/src`, `crates/kimpact/src`) makes it kimpact's
//! own (this includes kimpact's contact hook, which rapier calls, and parry
//! calls made by kimpact's replay); the first frame in rapier's
//! `pipeline/physics_pipeline`, or none of the two, makes it rapier's. This needs
//! line tables (the workspace's release profile has them) and costs about a
//! millisecond per sampled allocation, so it runs on a few steps only.
//! `KIMPACT_BENCH_TRACE_ALLOCS=N` prints the first `N` backtraces
//! attributed to kimpact to stderr.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

static COUNT: AtomicU64 = AtomicU64::new(0);
static BYTES: AtomicU64 = AtomicU64::new(0);

static ATTRIBUTING: AtomicBool = AtomicBool::new(false);
static EVERY: AtomicU64 = AtomicU64::new(1);
static SEEN: AtomicU64 = AtomicU64::new(0);
static SAMPLED: AtomicU64 = AtomicU64::new(0);
static OWN: AtomicU64 = AtomicU64::new(0);
static TRACE_LEFT: AtomicU64 = AtomicU64::new(0);

thread_local! {
    /// Set while this thread classifies an allocation (which allocates).
    static IN_TRACE: Cell<bool> = const { Cell::new(false) };
}

/// `System`, counting.
pub struct Counting;

#[inline]
fn count(size: usize) {
    if ATTRIBUTING.load(Relaxed) && !sample() {
        return; // the classifier's own allocation
    }
    COUNT.fetch_add(1, Relaxed);
    BYTES.fetch_add(size as u64, Relaxed);
}

/// Classify this allocation if it is a sampled one; `false` when it is made
/// by the classifier itself (not counted).
#[cold]
fn sample() -> bool {
    if IN_TRACE.with(|t| t.get()) {
        return false;
    }
    let n = SEEN.fetch_add(1, Relaxed);
    if !n.is_multiple_of(EVERY.load(Relaxed).max(1)) {
        return true;
    }
    IN_TRACE.with(|t| t.set(true));
    let text = std::backtrace::Backtrace::force_capture().to_string();
    SAMPLED.fetch_add(1, Relaxed);
    if is_kimpact(&text) {
        OWN.fetch_add(1, Relaxed);
        if TRACE_LEFT
            .fetch_update(Relaxed, Relaxed, |n| n.checked_sub(1))
            .is_ok()
        {
            eprintln!("== an allocation in kimpact's code\n{text}");
        }
    }
    IN_TRACE.with(|t| t.set(false));
    true
}

/// Whether a formatted backtrace reaches kimpact's sources before rapier's
/// pipeline step (see the module docs). An allocation inside rapier's
/// `RigidBodySet` is rapier's even when kimpact's velocity write caused it:
/// rapier hands its list of modified bodies to the pipeline at every step
/// (`mem::take`, so the list starts again without capacity), and the list
/// regrows for whoever sets a velocity through `RigidBodySet::get_mut`,
/// kimpact or the user's own code.
pub fn is_kimpact(backtrace: &str) -> bool {
    for line in backtrace.lines() {
        let Some(path) = line.trim_start().strip_prefix("at ") else {
            continue;
        };
        if path.contains("rapier-adapter/src/") || path.contains("crates/kimpact/src/") {
            return true;
        }
        if path.contains("/src/pipeline/physics_pipeline")
            || path.contains("/src/dynamics/rigid_body_set.rs")
        {
            return false;
        }
    }
    false
}

// SAFETY: every method forwards to `System` with the caller's arguments
// unchanged; the bookkeeping never allocates, except the classifier, which
// is guarded against re-entry.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        // SAFETY: forwarded contract of `GlobalAlloc::alloc`.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        // SAFETY: forwarded contract of `GlobalAlloc::alloc_zeroed`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size);
        // SAFETY: forwarded contract of `GlobalAlloc::realloc`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded contract of `GlobalAlloc::dealloc`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Allocations and bytes requested so far, all threads.
pub fn snapshot() -> (u64, u64) {
    (COUNT.load(Relaxed), BYTES.load(Relaxed))
}

/// Start classifying every `every`-th allocation.
pub fn attribute(every: u64) {
    let trace = std::env::var("KIMPACT_BENCH_TRACE_ALLOCS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    TRACE_LEFT.store(trace, Relaxed);
    EVERY.store(every.max(1), Relaxed);
    SEEN.store(0, Relaxed);
    SAMPLED.store(0, Relaxed);
    OWN.store(0, Relaxed);
    ATTRIBUTING.store(true, Relaxed);
}

/// Stop classifying: (allocations seen, sampled, of which kimpact's).
pub fn stop_attribute() -> (u64, u64, u64) {
    ATTRIBUTING.store(false, Relaxed);
    (SEEN.load(Relaxed), SAMPLED.load(Relaxed), OWN.load(Relaxed))
}

#[cfg(test)]
mod tests {
    use super::is_kimpact;

    #[test]
    fn attribution_reads_the_innermost_known_frame() {
        let hook = "   0: alloc\n             at /r/alloc/src/raw_vec.rs:1:1\n   1: record\n             at ./crates/rapier-adapter/src/resolver.rs:270:9\n   2: process_pair\n             at /c/rapier3d-0.36.1/src/pipeline/physics_pipeline.rs:1:1\n";
        assert!(is_kimpact(hook));
        let rapier = "   0: alloc\n             at /r/alloc/src/raw_vec.rs:1:1\n   1: step\n             at /c/rapier3d-0.36.1/src/pipeline/physics_pipeline/mod.rs:1:1\n   2: step\n             at ./crates/rapier-adapter/src/resolver.rs:1:1\n";
        assert!(!is_kimpact(rapier));
        // rapier's modified-bodies list regrowing under kimpact's velocity
        // write is rapier's.
        let write = "   0: alloc\n             at /r/alloc/src/raw_vec.rs:1:1\n   1: push_once\n             at /c/rapier2d-0.36.1/src/dynamics/rigid_body_set.rs:277:9\n   2: run\n             at ./crates/rapier-adapter/src/replay.rs:1:1\n";
        assert!(!is_kimpact(write));
    }
}
