//! A fixed number of worker threads taking jobs in order, longest first
//! as given (std's scoped threads: the jobs borrow from the caller).

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A job of the pool.
pub type Job<'a, T> = Box<dyn FnOnce() -> T + Send + 'a>;

/// Run `jobs` on `threads` threads, each taking the next job when it is
/// free; the results in job order.
pub fn run_jobs<T: Send>(jobs: Vec<Job<'_, T>>, threads: usize) -> Vec<T> {
    let n = jobs.len();
    let queue: Vec<Mutex<Option<Job<'_, T>>>> =
        jobs.into_iter().map(|j| Mutex::new(Some(j))).collect();
    let results: Vec<Mutex<Option<T>>> = (0..n).map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..threads.clamp(1, n.max(1)) {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    if i >= n {
                        break;
                    }
                    let job = queue[i].lock().map(|mut j| j.take()).ok().flatten();
                    if let Some(job) = job {
                        let r = job();
                        if let Ok(mut slot) = results[i].lock() {
                            *slot = Some(r);
                        }
                    }
                }
            });
        }
    });
    results
        .into_iter()
        .filter_map(|r| r.into_inner().ok().flatten())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_job_order_whatever_the_threads() {
        for threads in [1, 2, 5] {
            let jobs: Vec<Job<'_, usize>> = (0..7)
                .map(|i| -> Job<'_, usize> {
                    Box::new(move || {
                        std::thread::sleep(std::time::Duration::from_millis((7 - i) as u64));
                        i * i
                    })
                })
                .collect();
            assert_eq!(run_jobs(jobs, threads), vec![0, 1, 4, 9, 16, 25, 36]);
        }
    }
}
