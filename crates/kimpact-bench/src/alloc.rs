//! A counting global allocator around `std::alloc::System`: every
//! allocation (and reallocation) on every thread. While [`attribute`] is
//! on, each is classified from its stack ([`kimpact_harness::is_kimpact`]),
//! each distinct stack symbolized once (the release profile has line
//! tables). Not `stats_alloc` (it cannot tell whose an allocation is) nor
//! `dhat` (it records stacks only into its profile file).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

static COUNT: AtomicU64 = AtomicU64::new(0);
static ATTRIBUTING: AtomicBool = AtomicBool::new(false);
/// Distinct stacks by frame addresses: whether kimpact's, the frames'
/// paths and how many allocations had it.
type Stacks = HashMap<Box<[usize]>, (bool, Vec<String>, u64)>;
static STACKS: Mutex<Option<Stacks>> = Mutex::new(None);
/// Frames kept of a stack: enough to reach the pipeline's step.
const DEPTH: usize = 96;

thread_local! {
    /// Set while this thread classifies an allocation (which allocates).
    static IN_TRACE: Cell<bool> = const { Cell::new(false) };
}

/// `System`, counting.
pub struct Counting;

#[inline]
fn counted() {
    if ATTRIBUTING.load(Relaxed) && !sample() {
        return; // the classifier's own allocation
    }
    COUNT.fetch_add(1, Relaxed);
}

/// Classify this allocation; `false` for the classifier's own.
#[cold]
fn sample() -> bool {
    if IN_TRACE.with(|t| t.replace(true)) {
        return false;
    }
    let mut ips = [0usize; DEPTH];
    let mut len = 0;
    backtrace::trace(|frame| {
        ips[len] = frame.ip() as usize;
        len += 1;
        len < DEPTH
    });
    let mut stacks = STACKS.lock().unwrap_or_else(|e| e.into_inner());
    let stacks = stacks.get_or_insert_with(HashMap::new);
    let entry = stacks.entry(ips[..len].into()).or_insert_with(|| {
        let paths = symbolize(&ips[..len]);
        let own = kimpact_harness::is_kimpact(paths.iter().map(String::as_str));
        (own, paths, 0)
    });
    entry.2 += 1;
    IN_TRACE.with(|t| t.set(false));
    true
}

/// The source file and line of every frame of `ips`, innermost first.
fn symbolize(ips: &[usize]) -> Vec<String> {
    let mut paths = Vec::new();
    for &ip in ips {
        backtrace::resolve(ip as *mut std::ffi::c_void, |symbol| {
            let line = symbol.lineno().unwrap_or(0);
            let path = symbol.filename().map(|f| format!("{}:{line}", f.display()));
            paths.push(path.unwrap_or_else(|| "?".to_owned()));
        });
    }
    paths
}

// SAFETY: every method forwards to `System` with the caller's arguments
// unchanged; the bookkeeping never allocates, except the classifier, which
// is guarded against re-entry.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        counted();
        // SAFETY: forwarded contract of `GlobalAlloc::alloc`.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        counted();
        // SAFETY: forwarded contract of `GlobalAlloc::alloc_zeroed`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        counted();
        // SAFETY: forwarded contract of `GlobalAlloc::realloc`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded contract of `GlobalAlloc::dealloc`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Allocations so far, all threads.
pub fn count() -> u64 {
    COUNT.load(Relaxed)
}

/// Start classifying every allocation.
pub fn attribute() {
    if let Some(stacks) = STACKS.lock().unwrap_or_else(|e| e.into_inner()).as_mut() {
        stacks.clear();
    }
    ATTRIBUTING.store(true, Relaxed);
}

/// Stop classifying: (allocations classified, of which kimpact's), and
/// print kimpact's most frequent stacks as `KIMPACT_BENCH_TRACE_ALLOCS`
/// asks.
pub fn stop_attribute() -> (u64, u64) {
    ATTRIBUTING.store(false, Relaxed);
    let stacks = STACKS.lock().unwrap_or_else(|e| e.into_inner());
    let all: Vec<_> = stacks.iter().flat_map(|s| s.values()).collect();
    let mut own: Vec<_> = all.iter().filter(|s| s.0).collect();
    own.sort_by(|a, b| b.2.cmp(&a.2).then_with(|| a.1.cmp(&b.1)));
    let trace = std::env::var("KIMPACT_BENCH_TRACE_ALLOCS").ok();
    let shown = trace.and_then(|v| v.parse().ok()).unwrap_or(0);
    for (_, paths, n) in own.iter().take(shown) {
        eprintln!("== {n} allocations, kimpact's, from\n{}", paths.join("\n"));
    }
    (all.iter().map(|s| s.2).sum(), own.iter().map(|s| s.2).sum())
}
