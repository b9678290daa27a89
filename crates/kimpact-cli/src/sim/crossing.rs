//! Tunnelling check: balls that passed through each other within a step.
//!
//! Two balls *passed through* each other in a step if, moving each centre on
//! the straight line from where it started the step to where it ended it,
//! their centre-to-centre vector reverses its direction (`d₀·d₁ < 0`) along a
//! path that comes closer than the smaller radius to the other centre. A ball
//! that merely sweeps past another (a peg) also turns that vector, but stays
//! about a diameter away; a ball that bounces never reverses it.
//!
//! Every pair is considered, whether or not rapier saw it: candidates come
//! from a sort-and-sweep of the balls' swept bounding boxes, so a ball that
//! crossed another without ever touching it at a step's end is counted too.

/// Centres are stored as three coordinates (`z = 0` in 2D).
pub type Point = [f64; 3];

/// Reusable buffers of the sweep (no allocation per step once warm).
#[derive(Debug, Default)]
pub struct Crossings {
    order: Vec<usize>,
    lo: Vec<Point>,
    hi: Vec<Point>,
}

impl Crossings {
    /// The pairs of balls that passed through each other between `before`
    /// and `after` (same indexing; `radius[i]` is `None` for a body that is
    /// not a ball and is ignored), each pair once.
    pub fn count(&mut self, before: &[Point], after: &[Point], radius: &[Option<f64>]) -> u64 {
        self.lo.clear();
        self.hi.clear();
        self.order.clear();
        for (i, ((a, b), r)) in before.iter().zip(after).zip(radius).enumerate() {
            let r = r.unwrap_or(0.0);
            let mut lo = [0.0; 3];
            let mut hi = [0.0; 3];
            for k in 0..3 {
                lo[k] = a[k].min(b[k]) - r;
                hi[k] = a[k].max(b[k]) + r;
            }
            self.lo.push(lo);
            self.hi.push(hi);
            // A non-finite box (a NaN body) never overlaps anything.
            if radius[i].is_some() && lo.iter().chain(&hi).all(|x| x.is_finite()) {
                self.order.push(i);
            }
        }
        let lo = &self.lo;
        self.order
            .sort_unstable_by(|&a, &b| lo[a][0].total_cmp(&lo[b][0]));
        let mut count = 0;
        for (n, &i) in self.order.iter().enumerate() {
            for &j in &self.order[n + 1..] {
                if self.lo[j][0] > self.hi[i][0] {
                    break;
                }
                let overlap = (1..3)
                    .all(|k| self.lo[j][k] <= self.hi[i][k] && self.lo[i][k] <= self.hi[j][k]);
                if overlap {
                    let smaller = radius[i].unwrap_or(0.0).min(radius[j].unwrap_or(0.0));
                    if passed(before[i], after[i], before[j], after[j], smaller) {
                        count += 1;
                    }
                }
            }
        }
        count
    }
}

/// Whether centres moving `a0 → a1` and `b0 → b1` passed through each other
/// (see the module's documentation).
fn passed(a0: Point, a1: Point, b0: Point, b1: Point, smaller: f64) -> bool {
    let dot = |x: Point, y: Point| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let d0 = [a0[0] - b0[0], a0[1] - b0[1], a0[2] - b0[2]];
    let d1 = [a1[0] - b1[0], a1[1] - b1[1], a1[2] - b1[2]];
    if dot(d0, d1) >= 0.0 {
        return false;
    }
    let path = [d1[0] - d0[0], d1[1] - d0[1], d1[2] - d0[2]];
    let s = (-dot(d0, path) / dot(path, path)).clamp(0.0, 1.0);
    let closest = [
        d0[0] + s * path[0],
        d0[1] + s * path[1],
        d0[2] + s * path[2],
    ];
    dot(closest, closest).sqrt() < smaller
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count(before: &[Point], after: &[Point], radius: &[Option<f64>]) -> u64 {
        Crossings::default().count(before, after, radius)
    }

    #[test]
    fn a_ball_flying_through_another_is_counted_once() {
        // 1 m per step, radius 0.05: never overlapping at a step's end.
        let before = [[-0.5, 0.0, 0.0], [0.0, 0.0, 0.0]];
        let after = [[0.5, 0.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(count(&before, &after, &[Some(0.05), Some(0.05)]), 1);
        // Off-centre by less than the smaller radius: still through.
        let after_off = [[0.5, 0.04, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(count(&before, &after_off, &[Some(0.05), Some(0.05)]), 1);
    }

    #[test]
    fn sweeping_past_bouncing_and_non_balls_are_not_crossings() {
        let r = [Some(0.05), Some(0.05)];
        // Passing a diameter beside it.
        let before = [[-0.5, 0.1, 0.0], [0.0, 0.0, 0.0]];
        let after = [[0.5, 0.1, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(count(&before, &after, &r), 0);
        // Touching and coming back.
        let before = [[-0.2, 0.0, 0.0], [0.0, 0.0, 0.0]];
        let after = [[-0.15, 0.0, 0.0], [0.05, 0.0, 0.0]];
        assert_eq!(count(&before, &after, &r), 0);
        // A box (no radius) on the path.
        let before = [[-0.5, 0.0, 0.0], [0.0, 0.0, 0.0]];
        let after = [[0.5, 0.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(count(&before, &after, &[Some(0.05), None]), 0);
        // A NaN body is ignored, not a crossing.
        let after = [[f64::NAN, 0.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(count(&before, &after, &r), 0);
    }

    #[test]
    fn the_sweep_finds_every_crossing_among_many_balls() {
        // A row of resting balls and one ball flying through all of them
        // (and two moving balls swapping places in 3D further on).
        let mut before: Vec<Point> = (0..10).map(|i| [i as f64, 0.0, 0.0]).collect();
        let mut after = before.clone();
        before.push([-1.0, 0.0, 0.0]);
        after.push([10.0, 0.0, 0.0]);
        before.push([20.0, 0.0, 1.0]);
        after.push([20.0, 0.0, -1.0]);
        before.push([20.0, 0.0, -1.0]);
        after.push([20.0, 0.0, 1.0]);
        let radius = vec![Some(0.1); before.len()];
        assert_eq!(count(&before, &after, &radius), 11);
    }
}
