//! Peak resident memory of this process, and the clock its steps are timed
//! by.

use std::sync::atomic::{AtomicBool, Ordering};

/// `VmHWM` from `/proc/self/status`, in KiB (0 where there is none).
pub fn peak_rss_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let hwm = status.lines().find_map(|l| l.strip_prefix("VmHWM:"));
    let kib = hwm.map(|v| v.trim().trim_end_matches("kB").trim());
    kib.and_then(|v| v.parse().ok()).unwrap_or(0)
}

/// Whether steps are timed by the wall clock (`--threads`: the CPU time of
/// a pool of threads is their sum, not the step's duration).
pub static WALL_CLOCK: AtomicBool = AtomicBool::new(false);

/// The clock steps are timed by, in microseconds: CPU time used by this
/// process so far (all threads), or with [`WALL_CLOCK`] the monotonic wall
/// clock.
pub fn step_clock_us() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    let clock = match WALL_CLOCK.load(Ordering::Relaxed) {
        true => libc::CLOCK_MONOTONIC,
        false => libc::CLOCK_PROCESS_CPUTIME_ID,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock ids are
    // constants every Linux knows. On failure `ts` stays zero.
    unsafe { libc::clock_gettime(clock, &mut ts) };
    ts.tv_sec as f64 * 1e6 + ts.tv_nsec as f64 / 1e3
}
