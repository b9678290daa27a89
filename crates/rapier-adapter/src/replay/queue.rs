//! The replay's pair queue.

use std::cmp::Ordering;

use crate::math::Real;

/// The pairs' next meetings, earliest first, with at most one entry per
/// pair, keyed by (time, rank, pair index) so that the order of equal times
/// never depends on the queue's history. A pair's entry is replaced in place
/// whenever it is predicted again (after every impact of either of its
/// bodies), so the queue never holds a superseded prediction. In a settling
/// pile each impact predicts many pairs again, and a heap of every
/// prediction, skipped on the way out when superseded, would sift through
/// all the stale ones.
///
/// Two indexed binary min-heaps: the meetings at `now` (the time of the
/// last entry taken) and all others. A pile resolves most of its impacts at
/// one instant, and most predictions after such an impact are meetings at
/// that instant (overlapping pairs still approaching): they go in the
/// small heap, a few cache lines, instead of sifting through the large
/// one. Taking the earlier of the two tops gives the order of one heap.
#[derive(Default)]
pub(super) struct PairQueue {
    /// `[at now, the others]`: `(time, rank, pair)`, the earliest first.
    heaps: [Vec<Entry>; 2],
    /// `slot[pair]`: the heap ([`PairQueue::LATER`] bit) and place of the
    /// pair's entry, or `NONE`.
    slot: Vec<u32>,
    /// The time of the last entry taken while the first heap was empty.
    now: Real,
}

/// A queued meeting: time, rank among meetings at the same time (lower
/// first: see `Replay::predict`), pair.
type Entry = (Real, Real, u32);

impl PairQueue {
    const NONE: u32 = u32::MAX;
    /// The bit of a slot in the second heap.
    const LATER: u32 = 1 << 31;

    pub(super) fn clear(&mut self) {
        self.heaps[0].clear();
        self.heaps[1].clear();
        self.slot.clear();
        self.now = Real::NAN;
    }

    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.heaps[0].len() + self.heaps[1].len()
    }

    /// `a` comes before `b`.
    #[inline]
    fn before(a: Entry, b: Entry) -> bool {
        a.0.total_cmp(&b.0)
            .then(a.1.total_cmp(&b.1))
            .then(a.2.cmp(&b.2))
            == Ordering::Less
    }

    #[inline]
    fn place(&mut self, h: usize, at: usize, entry: Entry) {
        self.heaps[h][at] = entry;
        self.slot[entry.2 as usize] = at as u32 | if h == 1 { Self::LATER } else { 0 };
    }

    /// The heap of a meeting at time `t`: the first at `now`.
    #[inline]
    fn heap_for(&self, t: Real) -> usize {
        usize::from(t != self.now)
    }

    /// Pair `pair` next meets at time `t` with rank `r`: `Some((t, r))`
    /// (`None`: not this step).
    pub(super) fn set(&mut self, pair: usize, meeting: Option<(Real, Real)>) {
        if self.slot.len() <= pair {
            self.slot.resize(pair + 1, Self::NONE);
        }
        let old = self.slot[pair];
        if old != Self::NONE {
            let (h, at) = (
                usize::from(old & Self::LATER != 0),
                (old & !Self::LATER) as usize,
            );
            match meeting {
                Some((t, r)) if self.heap_for(t) == h => {
                    let entry = (t, r, pair as u32);
                    if Self::before(entry, self.heaps[h][at]) {
                        self.sift_up(h, at, entry);
                    } else {
                        self.sift_down(h, at, entry);
                    }
                    return;
                }
                _ => self.remove_at(h, at),
            }
        }
        if let Some((t, r)) = meeting {
            let h = self.heap_for(t);
            self.heaps[h].push((t, r, pair as u32));
            self.sift_up(h, self.heaps[h].len() - 1, (t, r, pair as u32));
        }
    }

    /// The heap whose top comes first (`None`: the queue is empty).
    fn first_heap(&self) -> Option<usize> {
        match (self.heaps[0].first(), self.heaps[1].first()) {
            (Some(&a), Some(&b)) => Some(usize::from(Self::before(b, a))),
            (Some(_), None) => Some(0),
            (None, Some(_)) => Some(1),
            (None, None) => None,
        }
    }

    /// The earliest entry's time.
    pub(super) fn peek(&self) -> Option<Real> {
        self.first_heap().map(|h| self.heaps[h][0].0)
    }

    /// Take the earliest entry.
    pub(super) fn pop(&mut self) -> Option<(Real, usize)> {
        let h = self.first_heap()?;
        let first = self.heaps[h][0];
        self.remove_at(h, 0);
        if self.heaps[0].is_empty() {
            self.now = first.0;
        }
        Some((first.0, first.2 as usize))
    }

    fn remove_at(&mut self, h: usize, at: usize) {
        let gone = self.heaps[h][at];
        self.slot[gone.2 as usize] = Self::NONE;
        let last = self.heaps[h].pop().expect("a queued entry");
        if at < self.heaps[h].len() {
            // The last entry fills the hole, then moves to its place.
            if Self::before(last, gone) {
                self.sift_up(h, at, last);
            } else {
                self.sift_down(h, at, last);
            }
        }
    }

    fn sift_up(&mut self, h: usize, mut at: usize, entry: Entry) {
        while at > 0 {
            let parent = (at - 1) / 2;
            let above = self.heaps[h][parent];
            if !Self::before(entry, above) {
                break;
            }
            self.place(h, at, above);
            at = parent;
        }
        self.place(h, at, entry);
    }

    fn sift_down(&mut self, h: usize, mut at: usize, entry: Entry) {
        let len = self.heaps[h].len();
        loop {
            let left = 2 * at + 1;
            if left >= len {
                break;
            }
            let right = left + 1;
            let heap = &self.heaps[h];
            let child = if right < len && Self::before(heap[right], heap[left]) {
                right
            } else {
                left
            };
            if !Self::before(heap[child], entry) {
                break;
            }
            self.place(h, at, heap[child]);
            at = child;
        }
        self.place(h, at, entry);
    }
}

#[cfg(test)]
#[allow(clippy::unnecessary_cast)]
mod tests {
    use super::*;
    use crate::test_rng::TestRng;

    /// The pair queue always yields its earliest entry (ties by rank, then
    /// by pair index), with one entry per pair, through random insertions,
    /// updates to earlier and later times and removals, many of them at the
    /// time of the last entry taken (the first heap's) and moving between
    /// the two heaps: against a plain list.
    #[test]
    fn the_pair_queue_keeps_the_earliest_first() {
        let mut rng = TestRng::new(11);
        let mut queue = PairQueue::default();
        queue.clear();
        let mut meetings: Vec<Option<(Real, Real)>> = vec![None; 60];
        let mut last = 0.0;
        let (mut now_heap, mut later_heap) = (0, 0);
        for step in 0..20_000 {
            let pair = (rng.next() * 60.0) as usize % 60;
            // Coarse times and ranks: many ties; a third at the time taken last.
            let t = if step % 3 == 0 {
                last
            } else {
                (rng.next() * 8.0).floor()
            };
            let meeting = (step % 5 != 0).then(|| (t, (rng.next() * 3.0).floor()));
            queue.set(pair, meeting);
            meetings[pair] = meeting;
            now_heap += queue.heaps[0].len();
            later_heap += queue.heaps[1].len();
            if step % 3 == 0 {
                let expected = meetings
                    .iter()
                    .enumerate()
                    .filter_map(|(p, m)| m.map(|(t, r)| (t, r, p)))
                    .min_by(|a, b| {
                        a.0.total_cmp(&b.0)
                            .then(a.1.total_cmp(&b.1))
                            .then(a.2.cmp(&b.2))
                    })
                    .map(|(t, _, p)| (t, p));
                assert_eq!(queue.pop(), expected, "step {step}");
                if let Some((t, p)) = expected {
                    meetings[p] = None;
                    last = t;
                }
            }
            assert_eq!(queue.len(), meetings.iter().flatten().count());
        }
        // Both heaps were used.
        assert!(
            now_heap > 20_000 && later_heap > 20_000,
            "{now_heap} {later_heap}"
        );
        while let Some((_, p)) = queue.pop() {
            assert!(meetings[p].take().is_some());
        }
        assert!(meetings.iter().all(Option::is_none));
    }
}
