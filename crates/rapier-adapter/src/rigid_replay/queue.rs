//! The rigid replay's next events: each pair's time of impact in a heap,
//! earliest first (of equal times, the pair brought in first), where a
//! pair's earlier times go stale when it gets a new one.

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

use crate::math::Real;

/// A pair's time of impact as it was set.
#[derive(Copy, Clone, Debug)]
struct Entry {
    t: Real,
    pair: usize,
    /// The pair's version when this time was set.
    version: u32,
}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        self.t
            .total_cmp(&other.t)
            .then(self.pair.cmp(&other.pair))
            .then(self.version.cmp(&other.version))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}

/// The pairs' times of impact, earliest first.
#[derive(Debug, Default)]
pub(super) struct Queue {
    heap: BinaryHeap<Reverse<Entry>>,
    /// Per pair: how many times its time was set.
    versions: Vec<u32>,
}

impl Queue {
    /// No pair, no time.
    pub(super) fn clear(&mut self) {
        self.heap.clear();
        self.versions.clear();
    }

    /// Pair `pair`'s time of impact is now `toi` (`None`: it does not meet
    /// before the step's end, or not until either body's path changes).
    pub(super) fn set(&mut self, pair: usize, toi: Option<Real>) {
        if self.versions.len() <= pair {
            self.versions.resize(pair + 1, 0);
        }
        let version = self.versions[pair].wrapping_add(1);
        self.versions[pair] = version;
        if let Some(t) = toi {
            self.heap.push(Reverse(Entry { t, pair, version }));
        }
    }

    /// The earliest time of impact and its pair (of equal times, the lowest
    /// pair index), left in the queue.
    pub(super) fn next(&mut self) -> Option<(Real, usize)> {
        while let Some(Reverse(e)) = self.heap.peek() {
            if self.versions[e.pair] == e.version {
                return Some((e.t, e.pair));
            }
            self.heap.pop();
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The queue gives what a scan of the pairs' current times would: the
    /// smallest, the lowest index among equal ones, never a replaced time.
    #[test]
    fn the_queue_gives_the_earliest_current_time() {
        let mut q = Queue::default();
        let mut current: Vec<Option<Real>> = vec![None; 6];
        let mut state: u32 = 7;
        for step in 0..400 {
            state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            let pair = (state >> 8) as usize % current.len();
            let toi = match (state >> 4) % 5 {
                0 => None,
                k => Some(k as Real * 0.25),
            };
            current[pair] = toi;
            q.set(pair, toi);
            let scan = current
                .iter()
                .enumerate()
                .filter_map(|(i, t)| t.map(|t| (t, i)))
                .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
            assert_eq!(q.next(), scan, "after set {step}");
        }
    }
}
