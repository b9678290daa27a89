//! A counting global allocator around `std::alloc::System`: every
//! allocation (and reallocation) on every thread.
//!
//! Attribution: while [`attribute`] is on, every allocation is classified
//! from its stack (file paths of the frames, from the allocation outwards):
//! the first frame in kimpact's sources (`crates/kimpact/src`, and the
//! adapters' `crates/rapier-adapter/src`, which the debug info names by the
//! link each adapter crate compiles it through, `crates/kimpact3d/src`…)
//! makes it kimpact's own (this includes kimpact's
//! contact hook, which rapier calls, and parry calls made by kimpact's
//! replay); the first frame in rapier's `pipeline/physics_pipeline`, or none
//! of the two, makes it rapier's. Each allocation costs a stack walk; each
//! distinct stack (by its frame addresses) is symbolized once, which needs
//! line tables (the workspace's release profile has them).
//! `KIMPACT_BENCH_TRACE_ALLOCS=N` prints kimpact's `N` most frequent stacks
//! to stderr (see [`stop_attribute`]).
//!
//! Why not a crate: `stats_alloc` counts allocations but cannot tell whose
//! they are; `dhat` records each allocation's stack, but only into the
//! JSON file its profiler writes when dropped (its API gives totals), and
//! its author calls it experimental. The bench needs the classification
//! in the process, per allocation, against kimpact's source paths.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

static COUNT: AtomicU64 = AtomicU64::new(0);

static ATTRIBUTING: AtomicBool = AtomicBool::new(false);
static SEEN: AtomicU64 = AtomicU64::new(0);
static OWN: AtomicU64 = AtomicU64::new(0);
static TRACE_OWN: AtomicU64 = AtomicU64::new(0);
/// Distinct stacks seen while attributing, by frame addresses: whether
/// kimpact's, the frames' paths in the workspace's crates, rapier and
/// parry, and how many allocations had that stack.
type Stacks = HashMap<Box<[usize]>, (bool, Vec<String>, u64)>;
static STACKS: Mutex<Option<Stacks>> = Mutex::new(None);
/// Frames kept of a stack: enough to reach the pipeline's step from any
/// allocation in it.
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

/// Classify this allocation; `false` when it is made by the classifier
/// itself (not counted).
#[cold]
fn sample() -> bool {
    if IN_TRACE.with(|t| t.get()) {
        return false;
    }
    SEEN.fetch_add(1, Relaxed);
    IN_TRACE.with(|t| t.set(true));
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
        let own = is_kimpact(paths.iter().map(String::as_str));
        let shown = paths
            .into_iter()
            .filter(|p| {
                (p.contains("/crates/") || p.contains("/rapier") || p.contains("/parry"))
                    && !p.contains("kimpact-bench/src/alloc")
            })
            .collect();
        (own, shown, 0)
    });
    entry.2 += 1;
    if entry.0 {
        OWN.fetch_add(1, Relaxed);
    }
    IN_TRACE.with(|t| t.set(false));
    true
}

/// The source file and line of every frame (inlined ones first, as they
/// nest) of the stack `ips`, innermost first; `?` where there is none.
fn symbolize(ips: &[usize]) -> Vec<String> {
    let mut paths = Vec::new();
    for &ip in ips {
        backtrace::resolve(ip as *mut std::ffi::c_void, |symbol| {
            let file = symbol.filename().map(|f| f.display().to_string());
            let line = symbol.lineno().unwrap_or(0);
            paths.push(match file {
                Some(f) => format!("{f}:{line}"),
                None => "?".to_owned(),
            });
        });
    }
    paths
}

/// kimpact's source directories: the core, the adapters' one source and
/// the four links to it (`src` of each adapter crate), by which rustc names
/// the adapter's files in the debug info.
const KIMPACT_SOURCES: [&str; 6] = [
    "crates/kimpact/src/",
    "rapier-adapter/src/",
    "crates/kimpact2d/src/",
    "crates/kimpact3d/src/",
    "crates/kimpact2d-f64/src/",
    "crates/kimpact3d-f64/src/",
];

/// Whether a stack (its frames' source paths, innermost first) reaches
/// kimpact's sources before rapier's pipeline step (see the module docs).
/// An allocation inside rapier's `RigidBodySet` is rapier's even when
/// kimpact's velocity write caused it: rapier hands its list of modified
/// bodies to the pipeline at every step (`mem::take`, so the list starts
/// again without capacity), and the list regrows for whoever sets a
/// velocity through `RigidBodySet::get_mut`, kimpact or the user's own code.
fn is_kimpact<'a>(paths: impl IntoIterator<Item = &'a str>) -> bool {
    for path in paths {
        if KIMPACT_SOURCES.iter().any(|dir| path.contains(dir)) {
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
    let trace = std::env::var("KIMPACT_BENCH_TRACE_ALLOCS").ok();
    TRACE_OWN.store(trace.and_then(|v| v.parse().ok()).unwrap_or(0), Relaxed);
    SEEN.store(0, Relaxed);
    OWN.store(0, Relaxed);
    if let Some(stacks) = STACKS.lock().unwrap_or_else(|e| e.into_inner()).as_mut() {
        stacks.clear();
    }
    ATTRIBUTING.store(true, Relaxed);
}

/// Stop classifying: (allocations classified, of which kimpact's). With
/// `KIMPACT_BENCH_TRACE_ALLOCS=N`, print kimpact's `N` most frequent
/// stacks and their counts to stderr (frames in the workspace's crates,
/// rapier and parry).
pub fn stop_attribute() -> (u64, u64) {
    ATTRIBUTING.store(false, Relaxed);
    let stacks = STACKS.lock().unwrap_or_else(|e| e.into_inner());
    let mut own: Vec<_> = stacks
        .iter()
        .flat_map(|s| s.values())
        .filter(|s| s.0)
        .collect();
    own.sort_by(|a, b| b.2.cmp(&a.2).then_with(|| a.1.cmp(&b.1)));
    for (_, paths, n) in own.iter().take(TRACE_OWN.load(Relaxed) as usize) {
        eprintln!("== {n} allocations, kimpact's, from\n{}", paths.join("\n"));
    }
    (SEEN.load(Relaxed), OWN.load(Relaxed))
}

#[cfg(test)]
mod tests {
    use super::is_kimpact;

    #[test]
    fn attribution_reads_the_innermost_known_frame() {
        let hook = [
            "/r/alloc/src/raw_vec.rs:1",
            "./crates/rapier-adapter/src/resolver.rs:270",
            "/c/rapier3d-0.36.1/src/pipeline/physics_pipeline.rs:1",
        ];
        assert!(is_kimpact(hook));
        // The adapter's files as rustc names them, through a crate's link.
        for krate in ["kimpact2d", "kimpact3d", "kimpact2d-f64", "kimpact3d-f64"] {
            let file = format!("./crates/{krate}/src/replay.rs:1");
            assert!(is_kimpact(["/r/alloc/src/raw_vec.rs:1", file.as_str()]));
        }
        let rapier = [
            "/r/alloc/src/raw_vec.rs:1",
            "/c/rapier3d-0.36.1/src/pipeline/physics_pipeline/mod.rs:1",
            "./crates/rapier-adapter/src/resolver.rs:1",
        ];
        assert!(!is_kimpact(rapier));
        // rapier's modified-bodies list regrowing under kimpact's velocity
        // write is rapier's.
        let write = [
            "/r/alloc/src/raw_vec.rs:1",
            "/c/rapier2d-0.36.1/src/dynamics/rigid_body_set.rs:277",
            "./crates/rapier-adapter/src/replay.rs:1",
        ];
        assert!(!is_kimpact(write));
        // Neither: rapier's (the user's own code, std).
        assert!(!is_kimpact(["/r/alloc/src/raw_vec.rs:1", "?"]));
    }
}
