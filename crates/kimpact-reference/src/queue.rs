//! The event queue: an indexed 4-ary min-heap holding one entry per ball,
//! keyed by the time of the ball's next predicted event.
//!
//! A ball's entry is updated in place (sifted up or down) whenever its next
//! event is predicted again, so the queue never holds superseded entries
//! and always has exactly one entry per ball: `O(log N)` per update, `O(1)`
//! to find the earliest event. Four children per node halve the depth of a
//! binary heap, and the smallest child is found without branches.

/// Children per node.
const ARITY: usize = 4;

/// An indexed 4-ary min-heap of `(time, ball)`.
#[derive(Clone, Debug)]
pub(crate) struct Queue {
    /// The heap, by time: `entries[0]` is the earliest. `len` balls, then
    /// `ARITY - 1` sentinels at `+∞` so that every node has `ARITY`
    /// children to compare (a sentinel never moves: no entry is later).
    entries: Vec<(f64, u32)>,
    /// The number of balls.
    len: usize,
    /// `slot[ball]`: the position of the ball's entry in `entries`.
    slot: Vec<u32>,
}

impl Queue {
    /// A queue of `n` balls, all with no event (time `+∞`).
    pub fn new(n: usize) -> Self {
        let mut entries: Vec<(f64, u32)> = (0..n as u32).map(|i| (f64::INFINITY, i)).collect();
        entries.extend([(f64::INFINITY, u32::MAX); ARITY - 1]);
        Self {
            entries,
            len: n,
            slot: (0..n as u32).collect(),
        }
    }

    /// The earliest entry, if any ball is queued.
    #[inline]
    pub fn first(&self) -> Option<(f64, u32)> {
        (self.len > 0).then(|| self.entries[0])
    }

    /// The time of `ball`'s entry.
    #[cfg(test)]
    pub fn time_of(&self, ball: u32) -> f64 {
        self.entries[self.slot[ball as usize] as usize].0
    }

    /// Set the time of `ball`'s next event (`+∞` for none). Times must not
    /// be NaN.
    #[inline]
    pub fn update(&mut self, ball: u32, time: f64) {
        let at = self.slot[ball as usize] as usize;
        let old = self.entries[at].0;
        if time < old {
            self.sift_up(at, (time, ball));
        } else {
            self.sift_down(at, (time, ball));
        }
    }

    #[inline]
    fn place(&mut self, at: usize, entry: (f64, u32)) {
        self.entries[at] = entry;
        self.slot[entry.1 as usize] = at as u32;
    }

    fn sift_up(&mut self, mut at: usize, entry: (f64, u32)) {
        while at > 0 {
            let parent = (at - 1) / ARITY;
            let above = self.entries[parent];
            if above.0 <= entry.0 {
                break;
            }
            self.place(at, above);
            at = parent;
        }
        self.place(at, entry);
    }

    /// Move `entry`, placed at `at` with a later time than before, down to
    /// its place. Floyd's way: the hole goes all the way down along the
    /// earliest children (no test against `entry` on the way, so no
    /// unpredictable exit), then `entry` rises from there (rarely far: a
    /// later time belongs low in the heap).
    fn sift_down(&mut self, mut at: usize, entry: (f64, u32)) {
        loop {
            let first = ARITY * at + 1;
            if first >= self.len {
                break;
            }
            // The earliest child; the sentinels make all ARITY of them
            // readable, and the first of equal times wins, so a sentinel is
            // never chosen over a ball.
            let children = &self.entries[first..first + ARITY];
            let mut child = 0;
            let mut time = children[0].0;
            for (k, c) in children.iter().enumerate().skip(1) {
                let earlier = c.0 < time;
                child = if earlier { k } else { child };
                time = if earlier { c.0 } else { time };
            }
            let below = first + child;
            self.place(at, self.entries[below]);
            at = below;
        }
        self.sift_up(at, entry);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_the_earliest_on_top() {
        let mut q = Queue::new(50);
        let mut times = [f64::INFINITY; 50];
        use rand::rngs::Xoshiro256PlusPlus;
        use rand::{RngExt, SeedableRng};
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(12345);
        for step in 0..2000 {
            let ball = rng.random_range(0..50u32);
            let t = if step % 7 == 0 {
                f64::INFINITY
            } else {
                rng.random_range(0..1u64 << 44) as f64 / 1e6
            };
            q.update(ball, t);
            times[ball as usize] = t;
            let (first, _) = q.first().unwrap();
            let min = times.iter().copied().fold(f64::INFINITY, f64::min);
            assert_eq!(first, min);
            for (b, &t) in times.iter().enumerate() {
                assert_eq!(q.time_of(b as u32), t);
            }
        }
    }
}
