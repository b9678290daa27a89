//! Exact mode: the impacts of one step, resolved in time order at their
//! analytic times of impact, after rapier's step (and impulse mode's pass
//! before it).
//!
//! rapier integrates positions with the velocity it solved, so within a step
//! every body moves on a straight line from its start `x₀` to its end `x₁`,
//! at `v̄ = (x₁ − x₀)/dt` (which includes gravity and the contacts rapier kept,
//! such as the table under a billiard ball). The replay takes those lines as
//! the motion, finds when the pairs the hook handed over meet (a linear
//! cast: closed form for two balls and for a ball and a cuboid, parry's
//! shape cast otherwise), applies the law there,
//! bends the two lines, and repeats, in time order. A body whose velocity
//! changes brings its touching neighbours into the replay (chains: a row of
//! touching balls is a chain of impacts within one step). Pairs first seen
//! overlapping are rewound into the previous step, along the same lines.
//! The law itself acts on the velocities the bodies really have (rapier's
//! end-of-step velocity plus the changes so far), which differ from the path
//! velocity when rapier's solver pushed a body apart from an overlap.
//! At the end each body that took part gets `x = x(dt)` and
//! `v = v_rapier + Σ Δv`.
//!
//! Impulse mode runs the same replay *before* rapier's step (`run_pre`):
//! the lines are the ones rapier is about to integrate (`x₀ + (v + g dt) t`),
//! a body's line after an impact restarts from `x₀` with its new velocity
//! (that is how rapier will move it), and only velocities are written back.

use std::cmp::Ordering;

use kimpact::Mass;

use crate::math::{DIM, Pose, Real, Vector, from_law, to_law};
use crate::rapier::parry::partitioning::{Bvh, BvhNode, TraversalAction};
use crate::rapier::prelude::*;
use crate::resolver::{Candidate, Kimpact, LawBody, checked, governs, law_body, path_velocity};

/// No pair: the end of a node's list of pairs.
const NO_PAIR: u32 = u32::MAX;

/// What a node of the replay stands for.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
enum Key {
    Body(RigidBodyHandle),
    /// A collider without a body (static geometry).
    Collider(ColliderHandle),
}

/// A body on a piecewise-linear path: at `t_ref` it is at `p`, moving at `v`.
#[derive(Copy, Clone, Debug)]
struct Node {
    key: Key,
    dynamic: bool,
    /// Position at the end of rapier's step.
    x1: Vector,
    p: Vector,
    /// Path velocity: moves the body (`v̄ + ΣΔv`).
    v: Vector,
    /// Dynamic velocity: what the law sees (`v_rapier + ΣΔv`). It differs
    /// from `v` when rapier's solver pushed the body this step (position
    /// correction), so that the law conserves the energy of the velocities
    /// the bodies really have.
    u: Vector,
    t_ref: Real,
    /// What gravity adds to the body's velocity over the step (`g s dt`,
    /// with its gravity scale `s`; zero for non-dynamic bodies).
    g_dt: Vector,
    expanded: bool,
    hit: bool,
    /// The last box swept for one of the node's colliders this run: a later
    /// sweep of that collider inside it would find nothing new (a ball
    /// bouncing back along its path in a pile).
    swept: Option<(ColliderHandle, Aabb)>,
    /// The collider of the node last put in [`Replay::bent`] (`None` once
    /// swept).
    sweep_due: Option<ColliderHandle>,
    /// The body's mass as the law takes it, read at the node's first
    /// impact (NaN until then; a dynamic body's mass does not change
    /// during the run, and a pile hits the same nodes again and again).
    mass: Real,
}

impl Node {
    fn at(&self, t: Real) -> Vector {
        self.p + self.v * (t - self.t_ref)
    }

    /// The velocity the law meets the body with at time `t`. After the
    /// step, `u` is the velocity at its end: the law meets the bodies at
    /// `t`, before gravity's share of the rest of the step (which they keep
    /// afterwards). Against a fixed partner this is what keeps a bouncing
    /// ball from gaining `m g dt` of momentum, and energy, at every bounce.
    fn law_velocity(&self, phase: Phase, t: Real, dt: Real) -> Vector {
        match phase {
            Phase::Post => self.u - self.g_dt * ((dt - t) / dt),
            Phase::Pre => self.u,
        }
    }

    /// The box a ball riding the node's path sweeps from `from` to `to`:
    /// its centre (`ball.1` off the path) ± its radius `ball.0`, as parry's.
    fn swept_ball(&self, (radius, offset): BallOnPath, from: Real, to: Real) -> Aabb {
        let r = Vector::splat(radius);
        let (start, end) = (self.at(from) + offset, self.at(to) + offset);
        Aabb::new(start.min(end) - r, start.max(end) + r)
    }

    /// `rest`, the pose of one of the node's colliders where the node is
    /// now (`x1`), carried along the node's path to time `t`.
    fn moved(&self, rest: Pose, t: Real) -> Pose {
        let mut pose = rest;
        pose.translation += self.at(t) - self.x1;
        pose
    }
}

/// A ball riding a node's path: its radius, and where its centre sits
/// relative to the path (`centre(t) = node.at(t) + offset`).
type BallOnPath = (Real, Vector);

#[derive(Copy, Clone, Debug)]
struct Pair {
    a: usize,
    b: usize,
    c1: ColliderHandle,
    c2: ColliderHandle,
    /// Two balls: their radii and where their centres sit relative to
    /// their nodes' paths (`centre(t) = node.at(t) + offset`), so that a
    /// cast of the pair reads neither collider nor body. `None` for any
    /// other pair of shapes.
    balls: Option<[BallOnPath; 2]>,
    /// The queued meeting's world normal (from `c1` towards `c2`) and
    /// point (see [`crate::cast::Hit`]).
    normal: Vector,
    point: Vector,
    /// The instant at which the pair, two balls apart then, waits in
    /// [`Replay::apart`] to be predicted (see [`Replay::defer_if_apart`]);
    /// −∞ when it does not.
    apart_at: Real,
    /// The next pair of node `a`'s list and of node `b`'s (`NO_PAIR` at the
    /// end; see [`Replay::ends`]).
    next: [u32; 2],
}

impl Pair {
    /// Which of [`Pair::next`] threads node `n`'s list (`n` is `a` or `b`).
    fn side(&self, n: usize) -> usize {
        usize::from(self.a != n)
    }
}

/// The pairs' next meetings, earliest first, with at most one entry per
/// pair, keyed by (time, rank, pair index) so that the order of equal times
/// never depends on the queue's history. A pair's entry is replaced in place
/// whenever it is predicted again (after every impact of either of its
/// bodies), so the queue never holds a superseded prediction. In a settling
/// pile each impact predicts a dozen pairs again: a heap of every
/// prediction, skipped on the way out when superseded, was 5-11% of an
/// exact step of the 10,000-ball 2D pit (`perf`).
///
/// Two indexed binary min-heaps: the meetings at `now` (the time of the
/// last entry taken) and all others. A pile resolves most of its impacts at
/// one instant, and most predictions after such an impact are meetings at
/// that instant (overlapping pairs still approaching: 99,000 of 113,000
/// meetings predicted per step in the 10,000-ball 2D pit): they go in the
/// small heap, a few cache lines, instead of sifting through the large
/// one. Taking the earlier of the two tops gives the order of one heap.
#[derive(Default)]
struct PairQueue {
    /// `[at now, the others]`: `(time, rank, pair)`, the earliest first.
    heaps: [Vec<Entry>; 2],
    /// `slot[pair]`: the heap ([`PairQueue::LATER`] bit) and place of the
    /// pair's entry, or `NONE`.
    slot: Vec<u32>,
    /// The time of the last entry taken while the first heap was empty.
    now: Real,
}

/// A queued meeting: time, rank among meetings at the same time (lower
/// first: see [`Replay::predict`]), pair.
type Entry = (Real, Real, u32);

impl PairQueue {
    const NONE: u32 = u32::MAX;
    /// The bit of a slot in the second heap.
    const LATER: u32 = 1 << 31;

    fn clear(&mut self) {
        self.heaps[0].clear();
        self.heaps[1].clear();
        self.slot.clear();
        self.now = Real::NAN;
    }

    #[cfg(test)]
    fn len(&self) -> usize {
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
    fn set(&mut self, pair: usize, meeting: Option<(Real, Real)>) {
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
    fn peek(&self) -> Option<Real> {
        self.first_heap().map(|h| self.heaps[h][0].0)
    }

    /// Take the earliest entry.
    fn pop(&mut self) -> Option<(Real, usize)> {
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

/// Before the step, how far past its end (relative to `dt`) a meeting is
/// still taken in this step.
pub(crate) const PRE_HORIZON: Real = 1e-3;

/// Approach speeds below this times the sum of the two bodies' speeds are
/// resting contacts: rounding level (7.6e-6 in f32, 1.4e-14 in f64).
const REST_FLOOR: Real = 64.0 * Real::EPSILON;

/// A body's or collider's node in the current run.
#[derive(Copy, Clone, Debug, Default)]
struct Slot {
    /// The run that wrote it (0: never).
    stamp: u32,
    node: u32,
}

impl Slot {
    /// `slots[index]` is `node` in the run stamped `stamp`.
    fn set(slots: &mut Vec<Slot>, index: u32, stamp: u32, node: usize) {
        let index = index as usize;
        if slots.len() <= index {
            slots.resize(index + 1, Slot::default());
        }
        slots[index] = Slot {
            stamp,
            node: node as u32,
        };
    }
}

/// When the replay runs, relative to rapier's step.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
enum Phase {
    /// `Exact`: after the step, on the straight lines rapier moved the
    /// bodies along; positions and velocities are written back.
    #[default]
    Post,
    /// `Impulse`: before the step, on the lines the bodies are about to
    /// follow (`v + g dt`); only velocities are written back, so rapier's
    /// solver integrates the new velocities with every contact it keeps.
    Pre,
}

/// Scratch space of the replay, kept between steps so that a steady state
/// allocates nothing.
#[derive(Default)]
pub(crate) struct Replay {
    phase: Phase,
    /// `g dt`: what rapier adds to a dynamic body's velocity this step.
    gravity_dt: Vector,
    /// The rest speed of this run.
    rest_speed: Real,
    /// How far a body must move this step (besides more than half its
    /// size) to be swept for partners: see [`Replay::run`].
    sweep_reach: Real,
    nodes: Vec<Node>,
    /// The dynamic nodes whose path the law bent this run, in the order of
    /// their first impact (the write-back walks these, not every node).
    hit: Vec<usize>,
    /// Node of a body, by the body's index (valid when stamped this run):
    /// dense arrays rather than hash maps (hashing was a fifth of a step).
    body_slots: Vec<Slot>,
    /// Node of a collider (its body's, or its own for a collider without a
    /// body), by the collider's index: which pairs are in the replay
    /// already is known without reading the collider (see
    /// [`Replay::has_pair`]).
    collider_slots: Vec<Slot>,
    /// This run's stamp.
    stamp: u32,
    pairs: Vec<Pair>,
    /// For each node, the first and the last pair it is in (`NO_PAIR`
    /// when none): the node's pairs are a list threaded through the pairs
    /// themselves ([`Pair::next`]), in the order they were added. One list
    /// per node in a vector of its own reallocated in steady state (which
    /// node a body gets changes from step to step, and a ball's list could
    /// land in a slot too small for it: 100 allocations per step in the
    /// 10,000-ball 3D pit, restitution mode); these need no allocation
    /// beyond `pairs`' and `nodes`' own.
    ends: Vec<[u32; 2]>,
    /// Each pair's next meeting.
    queue: PairQueue,
    /// Scratch of the bulk sweep: the colliders to sweep.
    sweepers: Vec<Sweeper>,
    /// After the step, pairs of sweepers (numbers into `sweepers`, the
    /// lower first) whose boxes meet but whose balls do not, on the paths
    /// they have before any impact: left out of the replay until an impact
    /// changes the path of either (see [`Replay::bring_deferred`]).
    deferred: Vec<(u32, u32)>,
    /// For each node made before the bulk sweep, its range of
    /// `deferred_by` (emptied once brought in).
    deferred_range: Vec<(u32, u32)>,
    /// Indices into `deferred`, grouped by node.
    deferred_by: Vec<u32>,
    /// Scratch of the bulk sweep: a uniform grid over the swept boxes.
    grid: SweepGrid,
    /// Scratch of the bulk sweep: (sweeper, collider index) pairs found.
    found: Vec<(u32, u32)>,
    /// Scratch of the bulk sweep, by collider index: the stamp of the run
    /// in which the collider is a sweeper (its pairs with other sweepers
    /// come from the grid alone).
    sweeping: Vec<u32>,
    /// The colliders (with their nodes) whose path an impact bent at the
    /// instant being resolved: swept once the instant is over, along their
    /// last path (see [`Replay::resolve`]).
    /// With each, the collider's radius and centre offset when a pair of
    /// balls gave them (see [`Replay::swept_aabb`]).
    bent: Vec<(usize, ColliderHandle, Option<BallOnPath>)>,
    /// The pairs of balls apart at the instant being resolved whose bodies
    /// an impact there bent: predicted once the instant is over (see
    /// [`Replay::defer_if_apart`]).
    apart: Vec<u32>,
    /// Scratch of a single sweep: the collider indices it met.
    met: Vec<u32>,
    /// rapier's broad-phase boxes in a grid, for the single sweeps of a run
    /// that makes many (see [`LeafGrid`]).
    leaves: LeafGrid,
    /// Never sweep in bulk (tests compare both ways).
    pub(crate) per_body_sweep: bool,
}

/// A collider the replay sweeps along its node's path this run.
#[derive(Copy, Clone, Debug)]
struct Sweeper {
    collider: ColliderHandle,
    node: usize,
    /// The box it sweeps.
    aabb: Aabb,
    /// Its radius and centre offset if it is a ball (see [`Pair::balls`]).
    ball: Option<BallOnPath>,
}

/// A uniform grid of boxes (the swept boxes of the bulk sweep), in
/// compressed rows: each box is stored once, in the cell of its low corner,
/// and the boxes of cell `c` are `items[start[c]..start[c + 1]]`. Cells are
/// a quarter larger than the largest box, so a box meeting a query has its
/// low corner less than one cell (by a fifth of a cell, far more than any
/// rounding of the cell coordinates) below the query's. Kept between steps:
/// no allocation in a steady state.
pub(crate) struct SweepGrid {
    origin: Vector,
    inv_cell: Real,
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<GridItem>,
    /// Scratch of `build`: each box's cell, from the counting pass to the
    /// placing pass.
    box_cells: Vec<u32>,
}

/// A box in a [`SweepGrid`] cell.
#[derive(Copy, Clone, Debug)]
struct GridItem {
    /// The box's number in the order it was given to [`SweepGrid::build`].
    index: u32,
    aabb: Aabb,
}

impl Default for SweepGrid {
    fn default() -> Self {
        Self {
            origin: Vector::ZERO,
            inv_cell: 1.0,
            dims: [1; 3],
            start: Vec::new(),
            items: Vec::new(),
            box_cells: Vec::new(),
        }
    }
}

impl SweepGrid {
    /// Cells per box at most (the grid coarsens beyond).
    const CELLS_PER_BOX: usize = 8;

    /// Grid the boxes: cells a quarter larger than the largest box, coarser
    /// if that would make more than `CELLS_PER_BOX` cells per box.
    /// `false` (nothing built) if the boxes span more than the scalar type
    /// can hold.
    pub(crate) fn build(&mut self, boxes: impl Iterator<Item = Aabb> + Clone) -> bool {
        let mut lo = Vector::splat(Real::MAX);
        let mut hi = Vector::splat(Real::MIN);
        let mut largest: Real = 0.0;
        let mut n = 0;
        for b in boxes.clone() {
            lo = lo.min(b.mins);
            hi = hi.max(b.maxs);
            largest = largest.max((b.maxs - b.mins).max_element());
            n += 1;
        }
        let extent = hi - lo;
        if !(extent.is_finite() && largest.is_finite()) {
            return false;
        }
        let mut cell = (1.25 * largest)
            .max(Real::EPSILON * extent.max_element())
            .max(Real::MIN_POSITIVE);
        // Counted in floating point: no overflow whatever the extents.
        let count = |cell: Real| -> f64 {
            (0..DIM)
                .map(|k| (f64::from(extent[k]) / f64::from(cell)).floor() + 1.0)
                .product()
        };
        while count(cell) > (Self::CELLS_PER_BOX * n.max(1)) as f64 {
            cell *= 2.0;
        }
        if !cell.is_finite() {
            return false;
        }
        self.origin = lo;
        self.inv_cell = 1.0 / cell;
        self.dims = [1; 3];
        for (k, d) in self.dims.iter_mut().enumerate().take(DIM) {
            *d = (extent[k] * self.inv_cell) as usize + 1;
        }
        let cells: usize = self.dims.iter().product();
        // Counting sort of the boxes by the cell of their low corner:
        // `start[c + 1]` counts cell c, then (prefix sums, shifted by one)
        // is cell c's next free slot, which ends as the start of cell c + 1.
        self.start.clear();
        self.start.resize(cells + 1, 0);
        let mut box_cells = std::mem::take(&mut self.box_cells);
        box_cells.clear();
        for b in boxes.clone() {
            let c = self.cell_of(b.mins);
            self.start[c + 1] += 1;
            box_cells.push(c as u32);
        }
        // The sum runs in a register: `start[c + 1] += start[c]` would
        // wait on the store of the previous cell at every cell.
        let mut sum = 0;
        for s in &mut self.start {
            sum += *s;
            *s = sum;
        }
        self.start.rotate_right(1);
        self.start[0] = 0;
        let placeholder = GridItem {
            index: 0,
            aabb: Aabb::new_invalid(),
        };
        self.items.clear();
        self.items.resize(n, placeholder);
        for (i, (b, &c)) in boxes.zip(&box_cells).enumerate() {
            let c = c as usize;
            self.items[self.start[c + 1] as usize] = GridItem {
                index: i as u32,
                aabb: b,
            };
            self.start[c + 1] += 1;
        }
        self.box_cells = box_cells;
        true
    }

    /// The cell of a point inside the grid's extent.
    fn cell_of(&self, p: Vector) -> usize {
        let mut c = 0;
        for k in (0..DIM).rev() {
            let x = ((p[k] - self.origin[k]) * self.inv_cell) as usize;
            c = c * self.dims[k] + x.min(self.dims[k] - 1);
        }
        c
    }

    /// The cells whose boxes may meet `b` (their low corners lie between
    /// one cell below `b`'s and `b`'s high corner), clamped to the grid;
    /// `None` if there are none (or `b` is not finite).
    fn range(&self, b: &Aabb) -> Option<[[usize; 2]; 3]> {
        let mut r = [[0, 0]; 3];
        for (k, rk) in r.iter_mut().enumerate().take(DIM) {
            let lo = (b.mins[k] - self.origin[k]) * self.inv_cell - 1.0;
            let hi = (b.maxs[k] - self.origin[k]) * self.inv_cell;
            let last = (self.dims[k] - 1) as Real;
            if !(hi >= 0.0 && lo < last + 1.0) {
                return None;
            }
            *rk = [
                lo.max(0.0).min(last) as usize,
                hi.max(0.0).min(last) as usize,
            ];
        }
        Some(r)
    }

    /// Call `f(a, b)` once for every two boxes `a < b` that meet, in no
    /// particular order. Boxes that meet have low corners less than a box
    /// (so less than a cell) apart on every axis: their cells are the same
    /// or neighbours. Each cell is joined with itself and with the
    /// neighbours after it in memory order (along x, then the three cells
    /// of each later row it touches), so each pair of cells once.
    pub(crate) fn self_join(&self, mut f: impl FnMut(u32, u32)) {
        let [nx, ny, nz] = self.dims;
        let mut test = |a: &GridItem, b: &GridItem| {
            if a.aabb.intersects(&b.aabb) {
                f(a.index.min(b.index), a.index.max(b.index));
            }
        };
        // The items of cells x0..=x1 (clamped) of row (y, z).
        let run = |x0: usize, x1: usize, y: usize, z: usize| -> &[GridItem] {
            let row = (z * ny + y) * nx;
            let (from, to) = (row + x0, row + x1.min(nx - 1));
            &self.items[self.start[from] as usize..self.start[to + 1] as usize]
        };
        // The later rows a row touches: (dy, dz) after (0, 0).
        let later: &[(isize, isize)] = if DIM == 2 {
            &[(1, 0)]
        } else {
            &[(1, 0), (-1, 1), (0, 1), (1, 1)]
        };
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let here = run(x, x, y, z);
                    if here.is_empty() {
                        continue;
                    }
                    for (i, a) in here.iter().enumerate() {
                        for b in &here[i + 1..] {
                            test(a, b);
                        }
                    }
                    let mut others: [&[GridItem]; 5] = [&[]; 5];
                    if x + 1 < nx {
                        others[0] = run(x + 1, x + 1, y, z);
                    }
                    for (slot, &(dy, dz)) in others[1..].iter_mut().zip(later) {
                        let (Some(y2), Some(z2)) =
                            (y.checked_add_signed(dy), z.checked_add_signed(dz))
                        else {
                            continue;
                        };
                        if y2 < ny && z2 < nz {
                            *slot = run(x.saturating_sub(1), x + 1, y2, z2);
                        }
                    }
                    for a in here {
                        for other in others {
                            for b in other {
                                test(a, b);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Call `f` once with the index of every box that meets `aabb`, in
    /// no particular order.
    pub(crate) fn overlaps(&self, aabb: &Aabb, mut f: impl FnMut(u32)) {
        let Some(r) = self.range(aabb) else { return };
        for z in r[2][0]..=r[2][1] {
            for y in r[1][0]..=r[1][1] {
                // A row of cells along x is one run of items.
                let row = (z * self.dims[1] + y) * self.dims[0];
                let (from, to) = (row + r[0][0], row + r[0][1]);
                for item in &self.items[self.start[from] as usize..self.start[to + 1] as usize] {
                    if aabb.intersects(&item.aabb) {
                        f(item.index);
                    }
                }
            }
        }
    }
}

/// The boxes of rapier's broad phase (its tree's leaves) in a [`SweepGrid`],
/// for the single sweeps of a run that makes many: the re-sweeps after
/// impacts in a settling pile (one per impact that sets a ball moving
/// further than rapier's contacts reach; a tree descent from the root each
/// was a tenth of an exact step of the 10,000-ball 2D pit) and the
/// sweepers of a run too few for the bulk sweep. Built once a run has made
/// [`LeafGrid::QUERY_SHARE`]-th as many tree queries as the tree has
/// leaves (a build costs a pass over the leaves, about as much as that many
/// queries). It finds every leaf box a query meets, as the bulk sweep's
/// grid does, including those a tree descent misses under an inner node
/// not yet refitted. Boxes much larger than the typical one (walls, a
/// floor) stay out of the grid, whose cells would grow to their size, and
/// are tested one by one.
#[derive(Default)]
struct LeafGrid {
    /// Tree queries made this run.
    queries: usize,
    /// Built this run (`Some(false)`: tried and not possible).
    built: Option<bool>,
    grid: SweepGrid,
    /// The boxes in `grid`, with their collider index (a box's number in
    /// the grid is its place here).
    small: Vec<(u32, Aabb)>,
    /// The boxes left out of the grid, with their collider index.
    big: Vec<(u32, Aabb)>,
}

impl LeafGrid {
    /// A run builds the grid after `leaves / QUERY_SHARE` tree queries.
    const QUERY_SHARE: usize = 16;
    /// and never before this many.
    const MIN_QUERIES: usize = 64;
    /// A box is left out of the grid when its largest side exceeds this
    /// many times the mean of the leaves' largest sides.
    const BIG: Real = 4.0;
    /// The grid is not built when more boxes than this would be left out
    /// (each query would test them all).
    const MAX_BIG: usize = 64;

    /// Forget the last run.
    fn clear(&mut self) {
        self.queries = 0;
        self.built = None;
    }

    /// Count one tree query of this run; whether the grid is now to be
    /// used (built at this call if need be) for a tree of `tree` leaves.
    fn wanted(&mut self, tree: &Bvh) -> bool {
        match self.built {
            Some(built) => built,
            None => {
                self.queries += 1;
                let leaves = tree.leaf_count() as usize;
                if self.queries < Self::MIN_QUERIES.max(leaves / Self::QUERY_SHARE) {
                    return false;
                }
                let built = self.build(tree);
                self.built = Some(built);
                built
            }
        }
    }

    /// Grid the leaves of `tree`; `false` if they cannot be gridded.
    fn build(&mut self, tree: &Bvh) -> bool {
        let mut small = std::mem::take(&mut self.small);
        small.clear();
        self.big.clear();
        let mut sum: f64 = 0.0;
        for_each_leaf(tree, |key, node| {
            let b = node.aabb();
            sum += f64::from((b.maxs - b.mins).max_element());
            small.push((key, b));
        });
        let mean = sum / small.len().max(1) as f64;
        let cut = Self::BIG * mean as Real;
        // A box with a NaN side stays in, and the grid's build refuses it.
        if !cut.is_finite() {
            self.small = small;
            return false;
        }
        let mut i = 0;
        while i < small.len() {
            if (small[i].1.maxs - small[i].1.mins).max_element() > cut {
                self.big.push(small.swap_remove(i));
            } else {
                i += 1;
            }
        }
        let ok = self.big.len() <= Self::MAX_BIG && self.grid.build(small.iter().map(|&(_, b)| b));
        self.small = small;
        ok
    }

    /// Push the collider index of every box that meets `aabb` onto `met`,
    /// in no particular order.
    fn overlaps(&self, aabb: &Aabb, met: &mut Vec<u32>) {
        self.grid
            .overlaps(aabb, |i| met.push(self.small[i as usize].0));
        met.extend(
            self.big
                .iter()
                .filter(|(_, b)| aabb.intersects(b))
                .map(|&(key, _)| key),
        );
    }
}

/// The linear cast ([`crate::cast::ball_ball`]) of two balls riding nodes
/// `n1` and `n2`, each given as (radius, centre offset from its node's path;
/// see [`Pair::balls`]), from time `from` over `window` seconds. The one
/// cast of a pair of balls: `Replay::cast`, and the bulk sweep's test of
/// whether a pair may be deferred, must agree.
fn cast_balls(
    n1: &Node,
    (r1, o1): BallOnPath,
    n2: &Node,
    (r2, o2): BallOnPath,
    from: Real,
    window: Real,
) -> Option<crate::cast::Hit> {
    let (c1, c2) = (n1.at(from) + o1, n2.at(from) + o2);
    crate::cast::ball_ball(c1, n1.v, r1, c2, n2.v, r2, window, false)
}

/// Whether rapier's solver would let colliders `co1` and `co2` push each
/// other, as its narrow phase decides it: both enabled, neither a sensor,
/// their collision and solver groups admitting each other, and their
/// active collision types (either collider's) admitting their bodies'
/// types; `dynamic` says whether either body is dynamic, which is all the
/// default types ask. A pair the sweeps find (a swept box meets any box of
/// the broad phase) gets the law only then. Not applied: a user's
/// `filter_contact_pair` hook and joints with contacts disabled
/// (documented limits).
fn interacts(bodies: &RigidBodySet, co1: &Collider, co2: &Collider, dynamic: bool) -> bool {
    if !(co1.is_enabled()
        && co2.is_enabled()
        && !co1.is_sensor()
        && !co2.is_sensor()
        && co1.collision_groups().test(co2.collision_groups())
        && co1.solver_groups().test(co2.solver_groups()))
    {
        return false;
    }
    let (a1, a2) = (co1.active_collision_types(), co2.active_collision_types());
    if a1 == ActiveCollisionTypes::default() && a2 == ActiveCollisionTypes::default() {
        return dynamic;
    }
    let body_type = |co: &Collider| {
        co.parent()
            .and_then(|h| bodies.get(h))
            .map_or(RigidBodyType::Fixed, |rb| rb.body_type())
    };
    let (t1, t2) = (body_type(co1), body_type(co2));
    a1.test(t1, t2) || a2.test(t1, t2)
}

/// Call `f` with the key (rapier: the collider's index) and the box of every
/// leaf of `tree`, once each, in no particular order. The keys are looked up
/// one by one from 0 (rapier's collider indices are dense: no tree descent,
/// and nothing read for a leaf `f` skips but its index) until every leaf
/// is seen; keys beyond twice the leaf count (a set that had many colliders
/// removed) are found by a walk down the tree.
pub(crate) fn for_each_leaf(tree: &Bvh, mut f: impl FnMut(u32, &BvhNode)) {
    let leaves = tree.leaf_count();
    let limit = leaves.saturating_mul(2).saturating_add(64);
    let mut seen = 0;
    let mut key = 0;
    while seen < leaves && key < limit {
        if let Some(node) = tree.leaf_node(key) {
            seen += 1;
            f(key, node);
        }
        key += 1;
    }
    if seen < leaves {
        tree.traverse(|node| {
            if !node.is_leaf() {
                return TraversalAction::Continue;
            }
            if let Some(key) = node.leaf_data()
                && key >= limit
            {
                f(key, node);
            }
            TraversalAction::Prune
        });
    }
}

/// The bulk sweep replaces one broad-phase query per swept collider when at
/// least this many colliders sweep, and at least one in `BULK_SHARE` of all
/// colliders does (a gas: every ball moves more than rapier's prediction
/// distance per step).
const BULK_MIN: usize = 64;
const BULK_SHARE: usize = 8;

/// Where collider `co` is: its body's pose composed with its own offset
/// (rapier syncs collider poses only inside its step, so before the step a
/// body the user moved has a stale collider pose), or its own pose when it
/// has no body. The replay shifts it along the body's path.
fn rest_pose(bodies: &RigidBodySet, co: &Collider) -> Pose {
    match (
        co.parent().and_then(|h| bodies.get(h)),
        co.position_wrt_parent(),
    ) {
        (Some(rb), Some(local)) => *rb.position() * *local,
        _ => *co.position(),
    }
}

impl Replay {
    fn clear(&mut self) {
        self.nodes.clear();
        self.ends.clear();
        self.hit.clear();
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            // Wrapped: forget every old stamp.
            self.body_slots.clear();
            self.collider_slots.clear();
            self.sweeping.clear();
            self.stamp = 1;
        }
        self.pairs.clear();
        self.bent.clear();
        self.apart.clear();
        self.deferred_range.clear();
        self.queue.clear();
        self.leaves.clear();
    }

    /// The node of collider `collider` (whose parent is `parent`): its
    /// body's, or its own for a collider without a body; made if the run
    /// has none yet.
    fn node(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        collider: ColliderHandle,
        parent: Option<RigidBodyHandle>,
        dt: Real,
    ) -> usize {
        if let Some(n) = self.collider_node(collider) {
            return n;
        }
        // A body's node may have been made for another of its colliders.
        let n = match parent {
            Some(h) => match self.body_node(Some(h)) {
                Some(n) => n,
                None => self.new_node(k, bodies, Key::Body(h), dt),
            },
            None => self.new_node(k, bodies, Key::Collider(collider), dt),
        };
        let index = collider.into_raw_parts().0;
        Slot::set(&mut self.collider_slots, index, self.stamp, n);
        n
    }

    /// The node of collider `c` in this run, if it has one.
    fn collider_node(&self, c: ColliderHandle) -> Option<usize> {
        let slot = self.collider_slots.get(c.into_raw_parts().0 as usize)?;
        (slot.stamp == self.stamp).then_some(slot.node as usize)
    }

    /// Colliders `c1` and `c2` are a pair of the replay already (in either
    /// order). Reads only the replay's own arrays: most colliders a sweep
    /// meets in a pile are paired already (19 of 20 in the 10,000-ball 2D
    /// pit), and reading them from rapier is a cache miss each.
    fn has_pair(&self, c1: ColliderHandle, c2: ColliderHandle) -> bool {
        let (Some(a), Some(_)) = (self.collider_node(c1), self.collider_node(c2)) else {
            return false;
        };
        self.pairs_of(a).any(|i| {
            let p = &self.pairs[i];
            (p.c1 == c1 && p.c2 == c2) || (p.c1 == c2 && p.c2 == c1)
        })
    }

    /// A new node for `key` (a body, or a collider without one).
    fn new_node(&mut self, k: &Kimpact, bodies: &RigidBodySet, key: Key, dt: Real) -> usize {
        let parent = match key {
            Key::Body(h) => Some(h),
            Key::Collider(_) => None,
        };
        let rb = parent.and_then(|h| bodies.get(h));
        let node = match rb {
            Some(rb) if rb.is_dynamic() && self.phase == Phase::Pre => {
                let x = rb.translation();
                let u = rb.linvel();
                Node {
                    key,
                    dynamic: true,
                    x1: x,
                    p: x,
                    v: u + self.gravity_dt * rb.gravity_scale(),
                    u,
                    t_ref: 0.0,
                    g_dt: self.gravity_dt * rb.gravity_scale(),
                    expanded: false,
                    hit: false,
                    swept: None,
                    sweep_due: None,
                    mass: Real::NAN,
                }
            }
            Some(rb) if rb.is_dynamic() => {
                let x1 = rb.translation();
                let handle = parent.expect("a body has a handle");
                let x0 = k.start_of(handle).unwrap_or(x1);
                // rapier's velocity when the body moved with it (free flight:
                // exact, where (x₁ − x₀)/dt would round), the chord otherwise;
                // but not the chord of a motion rapier's CCD cut short (a fast
                // body sweeps fixed colliders, a CCD-enabled one everything):
                // that stop is at rapier's time of impact, with rapier's
                // response, which the law replaces (the chord of a ball a CCD
                // pass stopped at a wall is slower than the ball, and the law
                // would meet the wall late).
                let v1 = rb.linvel();
                let moved = x1 - x0;
                let slack = 8.0 * Real::EPSILON * (x1.abs() + x0.abs()).max_element();
                let free = (moved - v1 * dt).abs().max_element() <= slack;
                let v_bar = if free || rb.is_ccd_active() {
                    v1
                } else {
                    moved / dt
                };
                Node {
                    key,
                    dynamic: true,
                    x1,
                    p: x0,
                    v: v_bar,
                    u: v1,
                    t_ref: 0.0,
                    g_dt: self.gravity_dt * rb.gravity_scale(),
                    expanded: false,
                    hit: false,
                    swept: None,
                    sweep_due: None,
                    mass: Real::NAN,
                }
            }
            Some(rb) => {
                let x1 = rb.translation();
                let v = rb.linvel();
                Node {
                    key,
                    dynamic: false,
                    x1,
                    p: x1,
                    v,
                    u: v,
                    // Where the body is now: the end of the step after
                    // rapier's step, its start before it.
                    t_ref: if self.phase == Phase::Pre { 0.0 } else { dt },
                    g_dt: Vector::ZERO,
                    expanded: true,
                    hit: false,
                    swept: None,
                    sweep_due: None,
                    mass: Real::NAN,
                }
            }
            None => Node {
                key,
                dynamic: false,
                x1: Vector::ZERO,
                p: Vector::ZERO,
                v: Vector::ZERO,
                u: Vector::ZERO,
                t_ref: dt,
                g_dt: Vector::ZERO,
                expanded: true,
                hit: false,
                swept: None,
                sweep_due: None,
                mass: Real::NAN,
            },
        };
        let i = self.nodes.len();
        self.nodes.push(node);
        self.ends.push([NO_PAIR; 2]);
        if let Key::Body(h) = key {
            Slot::set(&mut self.body_slots, h.into_raw_parts().0, self.stamp, i);
        }
        i
    }

    fn add_pair(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        c1: ColliderHandle,
        c2: ColliderHandle,
        dt: Real,
    ) -> Option<usize> {
        // Already in (a node has a handful of pairs: a scan beats a set).
        if self.has_pair(c1, c2) {
            return None;
        }
        let (co1, co2) = (colliders.get(c1)?, colliders.get(c2)?);
        let (p1, p2) = (co1.parent(), co2.parent());
        let a = self.node(k, bodies, c1, p1, dt);
        let b = self.node(k, bodies, c2, p2, dt);
        let dynamic = self.nodes[a].dynamic || self.nodes[b].dynamic;
        if a == b || !interacts(bodies, co1, co2, dynamic) {
            return None;
        }
        let balls = match (
            self.ball(bodies, colliders, a, c1),
            self.ball(bodies, colliders, b, c2),
        ) {
            (Some(b1), Some(b2)) => Some([b1, b2]),
            _ => None,
        };
        let i = self.pairs.len();
        self.pairs.push(Pair {
            a,
            b,
            c1,
            c2,
            balls,
            normal: Vector::ZERO,
            point: Vector::ZERO,
            apart_at: Real::NEG_INFINITY,
            next: [NO_PAIR; 2],
        });
        for n in [a, b] {
            match self.ends[n] {
                [NO_PAIR, _] => self.ends[n] = [i as u32; 2],
                [_, last] => {
                    let last = last as usize;
                    let side = self.pairs[last].side(n);
                    self.pairs[last].next[side] = i as u32;
                    self.ends[n][1] = i as u32;
                }
            }
        }
        Some(i)
    }

    /// The pair after pair `i` in node `n`'s list (`n` is one of its two).
    fn next_pair(&self, i: usize, n: usize) -> u32 {
        let p = &self.pairs[i];
        p.next[p.side(n)]
    }

    /// Node `n`'s pairs, in the order they were added.
    fn pairs_of(&self, n: usize) -> impl Iterator<Item = usize> + '_ {
        let mut i = self.ends[n][0];
        std::iter::from_fn(move || {
            let this = (i != NO_PAIR).then_some(i as usize)?;
            i = self.next_pair(this, n);
            Some(this)
        })
    }

    /// Before the step, a cheap test that colliders `c1` and `c2` cannot
    /// have an impact this step: their velocities differ by no more than the
    /// rest speed (the law would leave them to rapier), or their bounding
    /// spheres stay apart on the bodies' current lines. A node whose velocity
    /// the law changes later has its pairs tested again then.
    fn may_meet(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        c1: ColliderHandle,
        c2: ColliderHandle,
        dt: Real,
    ) -> bool {
        // (centre, path velocity, the law's velocity, bounding radius)
        let sphere = |c: ColliderHandle| -> Option<(Vector, Vector, Vector, Real)> {
            let co = colliders.get(c)?;
            let local = co.shape().compute_local_bounding_sphere();
            let r = local.center().length() + local.radius();
            match co.parent().and_then(|h| bodies.get(h)) {
                Some(rb) => {
                    // A node's velocities are the ones the law changed.
                    let (v, u) = match self.body_node(co.parent()) {
                        Some(n) => (self.nodes[n].v, self.nodes[n].u),
                        None => (path_velocity(rb, self.gravity_dt), rb.linvel()),
                    };
                    let offset = co
                        .position_wrt_parent()
                        .map_or(0.0, |p| p.translation.length());
                    Some((rb.translation(), v, u, r + offset))
                }
                None => Some((co.position().translation, Vector::ZERO, Vector::ZERO, r)),
            }
        };
        let (Some((x1, v1, u1, r1)), Some((x2, v2, u2, r2))) = (sphere(c1), sphere(c2)) else {
            return true;
        };
        // Anything not finite (NaN) is left to the exact test.
        if (u2 - u1).length().partial_cmp(&self.rest_speed) != Some(Ordering::Greater) {
            return (u2 - u1).length().is_nan();
        }
        let gap = (x2 - x1).length() - r1 - r2;
        let reach = (v2 - v1).length() * dt * (1.0 + 2.0 * PRE_HORIZON);
        gap.partial_cmp(&reach) != Some(Ordering::Greater)
    }

    /// The node of body `h` in this run, if it has one.
    fn body_node(&self, h: Option<RigidBodyHandle>) -> Option<usize> {
        let h = h?;
        let slot = self.body_slots.get(h.into_raw_parts().0 as usize)?;
        (slot.stamp == self.stamp).then_some(slot.node as usize)
    }

    /// The pose of collider `c` of node `n` at time `t`. Taken from the
    /// body's pose (rapier syncs collider poses only inside its step, so
    /// before the step a body the user moved has a stale collider pose).
    fn pose(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        n: usize,
        c: ColliderHandle,
        t: Real,
    ) -> Option<Pose> {
        Some(self.nodes[n].moved(rest_pose(bodies, colliders.get(c)?), t))
    }

    /// Collider `c` of node `n`, if it is a ball: its radius and its
    /// centre's offset from the node's path (see [`Pair::balls`]).
    fn ball(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        n: usize,
        c: ColliderHandle,
    ) -> Option<BallOnPath> {
        let co = colliders.get(c)?;
        let radius = co.shape().as_ball()?.radius;
        Some((radius, rest_pose(bodies, co).translation - self.nodes[n].x1))
    }

    /// When pair `i` next meets, from time `from` (within the step), with
    /// the nodes' current velocities. For a candidate first seen overlapping
    /// at the start, the meeting is searched back to `−dt` (a rewind).
    fn predict(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        i: usize,
        from: Real,
        dt: Real,
        allow_rewind: bool,
    ) {
        let pair = self.pairs[i];
        // Before the step, a meeting right at its end (up to rounding) is
        // taken now: rapier would otherwise see the pair touching, fresh and
        // approaching, and bounce it itself.
        let end = match self.phase {
            Phase::Post => dt,
            Phase::Pre => dt * (1.0 + PRE_HORIZON),
        };
        let Some(hit) = self.cast(bodies, colliders, &pair, from, end - from) else {
            self.queue.set(i, None);
            return;
        };
        let (mut t, mut normal, mut point) = (from + hit.0, hit.1, hit.2);
        if allow_rewind && hit.0 == 0.0 {
            // Overlapping at `from`: look for the true meeting in [−dt, 0].
            if let Some(back) = self.cast(bodies, colliders, &pair, from - dt, dt)
                && back.0 > 0.0
            {
                (t, normal, point) = (from - dt + back.0, back.1, back.2);
            }
        }
        self.pairs[i].normal = normal;
        self.pairs[i].point = point;
        let (na, nb) = (&self.nodes[pair.a], &self.nodes[pair.b]);
        if !self.takes(na, nb, normal, t, dt) {
            // The law would not act there: not queued at all (two thirds
            // of the meetings a landing pile predicts are overlapping
            // pairs that rapier's paths bring together but that approach
            // slower than the rest speed).
            self.queue.set(i, None);
            return;
        }
        // Meetings at the same instant (a pile's overlapping cluster) are
        // taken the fastest approach first: the order then does not depend
        // on the order in which the pairs were found (rapier's collider
        // indices), and the cluster settles in fewer impacts (19,600
        // instead of 21,500 per step in the 10,000-ball 2D pit).
        let rank = (nb.u - na.u).dot(normal);
        self.queue.set(i, Some((t, rank)));
    }

    /// After an impact at instant `at` (≥ 0, after the step), whether pair
    /// `i` is two balls apart then: it cannot meet at that instant, and
    /// where it meets later depends only on the velocities its bodies have
    /// when the instant is over, so it is predicted once then (pushed to
    /// [`Replay::apart`]), not after every impact of the instant. Its
    /// bodies' positions at `at` do not change within the instant (a path
    /// bends there), so the test holds for the whole instant. Before the
    /// step a path restarts from the start of the step, and an impact
    /// rewound before it (`t < 0`) moves the bodies at `0`: neither defers.
    fn defer_if_apart(&mut self, i: usize, at: Real) -> bool {
        let pair = &self.pairs[i];
        if pair.apart_at == at {
            return true;
        }
        let Some([(r1, o1), (r2, o2)]) = pair.balls else {
            return false;
        };
        // As `cast::ball_ball` tests it.
        let gap = (self.nodes[pair.b].at(at) + o2) - (self.nodes[pair.a].at(at) + o1);
        let reach = r1 + r2;
        if (gap.length_squared() - reach * reach).partial_cmp(&0.0) != Some(Ordering::Greater) {
            return false;
        }
        self.pairs[i].apart_at = at;
        self.apart.push(i as u32);
        true
    }

    /// Whether the law takes an impact of nodes `a` and `b` meeting at time
    /// `t` with world normal `normal` (from `a` towards `b`): they approach
    /// faster than the rest speed, and faster than rounding level relative
    /// to their speeds. Slower, the contact is a resting one (rapier's);
    /// and without gravity the rest speed is 0, where a dissipative law
    /// (grazing impacts are clamped to e = 1e-3) would otherwise chase an
    /// inelastic collapse, three touching balls exchanging ever smaller
    /// impulses forever. Anything not finite is taken, for the law's checks
    /// to refuse and count.
    fn takes(&self, a: &Node, b: &Node, normal: Vector, t: Real, dt: Real) -> bool {
        let (va, vb) = (
            a.law_velocity(self.phase, t, dt),
            b.law_velocity(self.phase, t, dt),
        );
        let approach = (va - vb).dot(normal);
        // Not at or below (NaN passes).
        let above = |x: Real| {
            !matches!(
                approach.partial_cmp(&x),
                Some(Ordering::Less | Ordering::Equal)
            )
        };
        above(self.rest_speed) && above(REST_FLOOR * (a.u.length() + b.u.length()))
    }

    /// The linear cast ([`crate::cast`]) of pair `pair` from time `from`, over
    /// `window` seconds: (time after `from`, world normal, world point).
    fn cast(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        pair: &Pair,
        from: Real,
        window: Real,
    ) -> Option<(Real, Vector, Vector)> {
        if let Some([b1, b2]) = pair.balls {
            return cast_balls(
                &self.nodes[pair.a],
                b1,
                &self.nodes[pair.b],
                b2,
                from,
                window,
            );
        }
        let pos1 = self.pose(bodies, colliders, pair.a, pair.c1, from)?;
        let pos2 = self.pose(bodies, colliders, pair.b, pair.c2, from)?;
        let s1 = colliders.get(pair.c1)?.shape();
        let s2 = colliders.get(pair.c2)?.shape();
        let (va, vb) = (self.nodes[pair.a].v, self.nodes[pair.b].v);
        crate::cast::cast(&pos1, va, s1, &pos2, vb, s2, window, false)
            .ok()
            .flatten()
    }

    /// Bring the governed contacts of node `n`'s marked colliders into the
    /// replay (once), and predict them from time `t`.
    #[allow(clippy::too_many_arguments)]
    fn expand(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        narrow_phase: &NarrowPhase,
        n: usize,
        t: Real,
        dt: Real,
    ) {
        if self.nodes[n].expanded {
            return;
        }
        self.nodes[n].expanded = true;
        let Key::Body(handle) = self.nodes[n].key else {
            return;
        };
        let Some(rb) = bodies.get(handle) else { return };
        let config = k.config_ref();
        for &ch in rb.colliders() {
            for cp in narrow_phase.contact_pairs_with(ch) {
                // After the step, only the contacts rapier saw (touching
                // neighbours); before it, every pair the broad phase keeps.
                if self.has_pair(cp.collider1, cp.collider2)
                    || (self.phase == Phase::Post && !cp.has_any_active_contact())
                    || (self.phase == Phase::Pre
                        && !self.may_meet(bodies, colliders, cp.collider1, cp.collider2, dt))
                    || !governs(
                        k.marked_ref(),
                        config.fixed_partners,
                        colliders,
                        bodies,
                        cp.collider1,
                        cp.collider2,
                    )
                {
                    continue;
                }
                if let Some(i) = self.add_pair(k, bodies, colliders, cp.collider1, cp.collider2, dt)
                {
                    self.predict(bodies, colliders, i, t, dt, false);
                }
            }
        }
    }

    /// Bodies that move more than their own half-size this step can cross a
    /// partner without a contact ever being seen (rapier's CCD does not
    /// sweep dynamic against dynamic): query the broad phase along their
    /// path over the step and bring every governed collider it meets into
    /// the replay.
    ///
    /// Before the step, the box is grown by twice the body's own step: a
    /// partner's box in rapier's broad phase is up to a step old, and the
    /// partner moves during this one (enough for every slower partner; a
    /// faster one finds the pair from its own sweep).
    fn sweep_fast_bodies(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        broad_phase: &BroadPhaseBvh,
        dt: Real,
    ) {
        let mut sweepers = std::mem::take(&mut self.sweepers);
        sweepers.clear();
        for j in 0..k.flagged_ref().len() {
            let ch = k.flagged_ref()[j];
            let Some(handle) = colliders.get(ch).and_then(|co| co.parent()) else {
                continue;
            };
            if self.phase == Phase::Post && k.start_of(handle).is_none() {
                continue;
            }
            let n = self.node(k, bodies, ch, Some(handle), dt);
            if let Some((aabb, ball)) = self.swept_aabb(bodies, colliders, ch, n, 0.0, dt, None) {
                sweepers.push(Sweeper {
                    collider: ch,
                    node: n,
                    aabb,
                    ball,
                });
                self.nodes[n].swept = Some((ch, aabb));
            }
        }
        let bulk = !self.per_body_sweep
            && sweepers.len() >= BULK_MIN
            && sweepers.len() * BULK_SHARE >= colliders.len();
        if !(bulk && self.sweep_in_bulk(k, bodies, colliders, broad_phase, &sweepers, dt)) {
            for &Sweeper {
                collider: ch, aabb, ..
            } in &sweepers
            {
                self.sweep_query(k, bodies, colliders, broad_phase, ch, aabb, 0.0, dt);
            }
        }
        self.sweepers = sweepers;
    }

    /// The box collider `ch` of node `n` sweeps from `from` to the end of the
    /// step, if it moves far enough over that time to be swept (more than
    /// half its size, or more than `sweep_reach`); with it, the collider's
    /// radius and centre offset if it is a ball (as [`Replay::ball`]).
    /// `known` is that radius and offset when the caller has them (a pair
    /// of balls keeps them): then neither the collider nor its body is read.
    #[allow(clippy::too_many_arguments)]
    fn swept_aabb(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        ch: ColliderHandle,
        n: usize,
        from: Real,
        dt: Real,
        known: Option<BallOnPath>,
    ) -> Option<(Aabb, Option<BallOnPath>)> {
        let node = &self.nodes[n];
        let moved = node.v * (dt - from);
        let far_enough = |half: Real| moved.length() > half.min(self.sweep_reach);
        let (swept, ball) = match known {
            Some(ball) => {
                if !far_enough(ball.0) {
                    return None;
                }
                (node.swept_ball(ball, from, dt), known)
            }
            None => {
                let co = colliders.get(ch)?;
                let shape = co.shape();
                let ball = shape.as_ball();
                let half = match ball {
                    Some(ball) => ball.radius,
                    None => {
                        let aabb = co.compute_aabb();
                        0.5 * (aabb.maxs - aabb.mins).min_element()
                    }
                };
                if !far_enough(half) {
                    return None;
                }
                let rest = rest_pose(bodies, co);
                match ball {
                    Some(ball) => {
                        let ball = (ball.radius, rest.translation - node.x1);
                        (node.swept_ball(ball, from, dt), Some(ball))
                    }
                    None => {
                        let at = |t: Real| shape.compute_aabb(&node.moved(rest, t));
                        (at(from).merged(&at(dt)), None)
                    }
                }
            }
        };
        let swept = match self.phase {
            Phase::Pre => swept.loosened(2.0 * moved.length()),
            Phase::Post => swept,
        };
        // A box that is not finite (a body the runtime guard cuts off)
        // meets nothing.
        (swept.mins.is_finite() && swept.maxs.is_finite()).then_some((swept, ball))
    }

    /// Sweep collider `ch` of node `n` along the node's path from `from` to
    /// the end of the step, if it moves far enough over that time (more
    /// than half its size, or more than `sweep_reach`), and bring every
    /// governed collider the sweep meets into the replay, predicted from
    /// `from`.
    #[allow(clippy::too_many_arguments)]
    fn sweep(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        broad_phase: &BroadPhaseBvh,
        ch: ColliderHandle,
        n: usize,
        ball: Option<BallOnPath>,
        from: Real,
        dt: Real,
    ) {
        let Some((aabb, _)) = self.swept_aabb(bodies, colliders, ch, n, from, dt, ball) else {
            return;
        };
        if let Some((c, covered)) = self.nodes[n].swept
            && c == ch
            && covered.mins.cmple(aabb.mins).all()
            && aabb.maxs.cmple(covered.maxs).all()
        {
            // Every collider this box meets was met by the earlier sweep and
            // is in the replay already, predicted again after each impact.
            return;
        }
        self.nodes[n].swept = Some((ch, aabb));
        self.sweep_query(k, bodies, colliders, broad_phase, ch, aabb, from, dt);
    }

    /// The colliders of rapier's broad phase whose box meets `swept`, as
    /// rapier's tree query finds them (it can miss one under an inner node
    /// not yet refitted: see [`Replay::sweep_in_bulk`]), met by collider
    /// `ch` from time `from`.
    #[allow(clippy::too_many_arguments)]
    fn sweep_query(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        broad_phase: &BroadPhaseBvh,
        ch: ColliderHandle,
        swept: Aabb,
        from: Real,
        dt: Real,
    ) {
        let dispatcher = crate::rapier::parry::query::DefaultQueryDispatcher;
        let query =
            broad_phase.as_query_pipeline(&dispatcher, bodies, colliders, QueryFilter::default());
        // In collider order (as the bulk sweep takes them), not the tree's.
        let mut met = std::mem::take(&mut self.met);
        met.clear();
        if !self.per_body_sweep && self.leaves.wanted(query.bvh) {
            self.leaves.overlaps(&swept, &mut met);
        } else {
            met.extend(
                query
                    .intersect_aabb_conservative(swept)
                    .map(|(other, _)| other.into_raw_parts().0),
            );
        }
        met.sort_unstable();
        for &index in &met {
            if let Some((_, other)) = colliders.get_unknown_gen(index) {
                self.meet(k, bodies, colliders, ch, other, from, dt);
            }
        }
        self.met = met;
    }

    /// The sweep of many colliders at once: the swept boxes go in a uniform
    /// grid, every box of rapier's broad phase (the leaves its queries test)
    /// looks up the cells whose boxes may meet it, and every overlap of a
    /// swept box with a broad-phase box is taken, sweeper by sweeper, each
    /// in collider order (the order of [`Replay::sweep_query`] too). It finds every pair one
    /// [`Replay::sweep_query`] each would, and the few such a query misses.
    /// `false`, having done nothing, if the boxes cannot be gridded (the
    /// caller then sweeps them one query each). One pass over the
    /// colliders replaces a tree descent per swept collider (a third of an
    /// exact step in a gas, where every ball is swept).
    fn sweep_in_bulk(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        broad_phase: &BroadPhaseBvh,
        sweepers: &[Sweeper],
        dt: Real,
    ) -> bool {
        let dispatcher = crate::rapier::parry::query::DefaultQueryDispatcher;
        let tree = broad_phase
            .as_query_pipeline(&dispatcher, bodies, colliders, QueryFilter::default())
            .bvh;
        let mut grid = std::mem::take(&mut self.grid);
        if !grid.build(sweepers.iter().map(|x| x.aabb)) {
            self.grid = grid;
            return false;
        }
        let mut found = std::mem::take(&mut self.found);
        found.clear();
        // Two sweepers can meet only where their swept boxes do: each such
        // pair is taken once, from the grid alone, by the sweeper numbered
        // first (the one that would reach it first in the order below).
        let mut sweeping = std::mem::take(&mut self.sweeping);
        for sweeper in sweepers {
            let index = sweeper.collider.into_raw_parts().0 as usize;
            if sweeping.len() <= index {
                sweeping.resize(index + 1, 0);
            }
            sweeping[index] = self.stamp;
        }
        // Before the step a swept box is grown by twice its body's motion
        // (a partner's box in rapier's tree is up to a step old), so two
        // grown boxes meet far more often than a pair can: such a pair is
        // taken, as one query per sweeper would take it, only if either
        // grown box meets the other collider's box in rapier's tree (a
        // sweeper whose velocity an impact changes later is swept again
        // against those boxes).
        //
        // After the step, a pair of balls that does not meet on the paths
        // the bodies have now is deferred: its prediction would be "never",
        // and it matters only once an impact bends either path (most
        // pairs of a gas: their boxes meet, their balls do not).
        let pre = self.phase == Phase::Pre;
        let mut deferred = std::mem::take(&mut self.deferred);
        deferred.clear();
        let nodes = &self.nodes;
        grid.self_join(|s, t| {
            let (a, b) = (&sweepers[s as usize], &sweepers[t as usize]);
            let (ka, kb) = (a.collider.into_raw_parts().0, b.collider.into_raw_parts().0);
            let meets = |grown: &Aabb, key: u32| {
                tree.leaf_node(key)
                    .is_some_and(|leaf| grown.intersects(&leaf.aabb()))
            };
            if pre {
                if meets(&a.aabb, kb) || meets(&b.aabb, ka) {
                    found.push((s, kb));
                }
            } else if let (Some((r1, o1)), Some((r2, o2))) = (a.ball, b.ball) {
                // The first cast `Replay::predict` would make of the pair.
                let hit = cast_balls(&nodes[a.node], (r1, o1), &nodes[b.node], (r2, o2), 0.0, dt);
                if hit.is_some() {
                    found.push((s, kb));
                } else {
                    deferred.push((s, t));
                }
            } else {
                found.push((s, kb));
            }
        });
        if !deferred.is_empty() {
            self.group_deferred(&deferred, sweepers);
        }
        self.deferred = deferred;
        // Every other leaf of rapier's tree (walls, slow bodies): a leaf's
        // box looks up the cells whose boxes may meet it. Every leaf, not
        // only those under inner nodes that meet a swept box: between steps
        // some inner boxes do not enclose the leaves below them (rapier
        // refits the ancestors of moved leaves lazily), so a query
        // descending from the root can miss a collider whose own box meets
        // the query's (measured: 2 to 11 of 400 to 870 pairs per step in a
        // falling pile of 300 balls).
        for_each_leaf(tree, |index, node| {
            if sweeping.get(index as usize) != Some(&self.stamp) {
                grid.overlaps(&node.aabb(), |s| found.push((s, index)));
            }
        });
        self.grid = grid;
        self.sweeping = sweeping;
        // Sweeper by sweeper, each in collider order, as one query each
        // would take them.
        found.sort_unstable();
        for &(s, index) in &found {
            let Some((_, other)) = colliders.get_unknown_gen(index) else {
                continue;
            };
            let ch = sweepers[s as usize].collider;
            self.meet(k, bodies, colliders, ch, other, 0.0, dt);
        }
        self.found = found;
        true
    }

    /// Group the deferred pairs by node (`deferred_range`, `deferred_by`).
    fn group_deferred(&mut self, deferred: &[(u32, u32)], sweepers: &[Sweeper]) {
        let n = self.nodes.len();
        self.deferred_range.clear();
        self.deferred_range.resize(n, (0, 0));
        let ends = |&(s, t): &(u32, u32)| [sweepers[s as usize].node, sweepers[t as usize].node];
        for pair in deferred {
            for node in ends(pair) {
                self.deferred_range[node].1 += 1;
            }
        }
        let mut sum = 0;
        for range in &mut self.deferred_range {
            let count = range.1;
            *range = (sum, sum);
            sum += count;
        }
        self.deferred_by.clear();
        self.deferred_by.resize(sum as usize, 0);
        for (i, pair) in deferred.iter().enumerate() {
            for node in ends(pair) {
                let range = &mut self.deferred_range[node];
                self.deferred_by[range.1 as usize] = i as u32;
                range.1 += 1;
            }
        }
    }

    /// Node `n`'s path is about to bend: bring its deferred pairs into the
    /// replay (once), to be predicted with the rest of its pairs.
    #[allow(clippy::too_many_arguments)]
    fn bring_deferred(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        n: usize,
        from: Real,
        dt: Real,
    ) {
        let Some(&(start, end)) = self.deferred_range.get(n) else {
            return;
        };
        self.deferred_range[n] = (start, start);
        for j in start..end {
            let (s, t) = self.deferred[self.deferred_by[j as usize] as usize];
            let (c1, c2) = (
                self.sweepers[s as usize].collider,
                self.sweepers[t as usize].collider,
            );
            self.meet(k, bodies, colliders, c1, c2, from, dt);
        }
    }

    /// Collider `ch`'s sweep reached collider `other`: if the law governs the
    /// pair, bring it into the replay and predict it from `from`.
    #[allow(clippy::too_many_arguments)]
    fn meet(
        &mut self,
        k: &Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        ch: ColliderHandle,
        other: ColliderHandle,
        from: Real,
        dt: Real,
    ) {
        if other == ch
            || self.has_pair(ch, other)
            || !governs(
                k.marked_ref(),
                k.config_ref().fixed_partners,
                colliders,
                bodies,
                ch,
                other,
            )
        {
            return;
        }
        if let Some(i) = self.add_pair(k, bodies, colliders, ch, other, dt) {
            self.predict(bodies, colliders, i, from, dt, from == 0.0);
        }
    }

    /// Before rapier's step: the impacts the bodies are about to have this
    /// step, resolved in time order on the velocities they have now. The
    /// pairs are those the broad phase finds along the path of fast bodies
    /// (more than half their size per step, which rapier could miss) and,
    /// with `narrow` (`Impulse` mode), every governed pair rapier's narrow
    /// phase holds for a moving marked collider. Only velocities change;
    /// rapier's solver then integrates them with every contact in place (the
    /// law's pairs separate, so their contacts carry no impulse unless
    /// something pushes the pair together again).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn run_pre(
        &mut self,
        k: &mut Kimpact,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        narrow_phase: &NarrowPhase,
        broad_phase: &BroadPhaseBvh,
        gravity: Vector,
        dt: Real,
        rest_speed: Real,
        narrow: bool,
        prediction: Real,
    ) {
        if !self.begin(Phase::Pre, gravity, dt, rest_speed) {
            return;
        }
        // Impulse mode sweeps what the narrow phase cannot have seen (see
        // `run`); restitution only what could tunnel.
        self.sweep_reach = if narrow {
            0.5 * prediction
        } else {
            Real::INFINITY
        };
        let config = *k.config_ref();
        let seeded = if narrow { k.flagged_ref().len() } else { 0 };
        for j in 0..seeded {
            let ch = k.flagged_ref()[j];
            for cp in narrow_phase.contact_pairs_with(ch) {
                if !governs(
                    k.marked_ref(),
                    config.fixed_partners,
                    colliders,
                    bodies,
                    cp.collider1,
                    cp.collider2,
                ) || !self.may_meet(bodies, colliders, cp.collider1, cp.collider2, dt)
                {
                    continue;
                }
                if let Some(i) = self.add_pair(k, bodies, colliders, cp.collider1, cp.collider2, dt)
                {
                    self.predict(bodies, colliders, i, 0.0, dt, true);
                }
            }
        }
        self.sweep_fast_bodies(k, bodies, colliders, broad_phase, dt);
        self.resolve(k, bodies, colliders, narrow_phase, broad_phase, dt);
        // In node order, as a walk over every node would take them.
        self.hit.sort_unstable();
        for &n in &self.hit {
            let node = &self.nodes[n];
            let Key::Body(h) = node.key else { continue };
            if let Some(rb) = bodies.get_mut(h)
                && node.u.is_finite()
            {
                rb.set_linvel(node.u, true);
                k.woke(h);
            }
        }
    }

    /// Start a run: empty scratch, the phase and the step's constants;
    /// whether the step can be replayed at all (`dt > 0`).
    fn begin(&mut self, phase: Phase, gravity: Vector, dt: Real, rest_speed: Real) -> bool {
        self.clear();
        self.phase = phase;
        self.gravity_dt = gravity * dt;
        self.rest_speed = rest_speed;
        dt > 0.0
    }

    /// The bodies whose velocity the last run changed.
    pub(crate) fn hit_bodies(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.hit.iter().filter_map(|&n| match self.nodes[n].key {
            Key::Body(h) => Some(h),
            Key::Collider(_) => None,
        })
    }

    /// Resolve this step's impacts in time order and write the results back.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn run(
        &mut self,
        k: &mut Kimpact,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        narrow_phase: &NarrowPhase,
        broad_phase: &BroadPhaseBvh,
        gravity: Vector,
        dt: Real,
        rest_speed: Real,
        prediction: Real,
    ) {
        if !self.begin(Phase::Post, gravity, dt, rest_speed) {
            return;
        }
        // rapier's contacts (hence the candidates) reach `prediction` beyond
        // the start-of-step shapes. Two bodies each moving at most half of
        // that close at most all of it, so they were seen; a body moving
        // more may reach a partner unseen (a gas ball at 3 m/s moves 0.05
        // per step at 60 Hz, the prediction is 0.02), and is swept.
        self.sweep_reach = 0.5 * prediction;
        for j in 0..k.candidates_sorted().len() {
            let c: Candidate = k.candidates_sorted()[j];
            if let Some(i) = self.add_pair(k, bodies, colliders, c.collider1, c.collider2, dt) {
                self.predict(bodies, colliders, i, 0.0, dt, true);
            }
        }
        self.sweep_fast_bodies(k, bodies, colliders, broad_phase, dt);
        self.resolve(k, bodies, colliders, narrow_phase, broad_phase, dt);
        // Write back the bodies whose path the law bent, in node order.
        self.hit.sort_unstable();
        for &n in &self.hit {
            let node = &self.nodes[n];
            let Key::Body(h) = node.key else { continue };
            let Some(rb) = bodies.get_mut(h) else {
                continue;
            };
            let x = node.at(dt);
            let v = node.u;
            if x.is_finite() && v.is_finite() {
                rb.set_translation(x, true);
                rb.set_linvel(v, true);
                k.woke(h);
            }
        }
    }

    /// The impacts on the heap, in time order, each bending the paths of
    /// its two bodies and bringing their neighbours in.
    #[allow(clippy::too_many_arguments)]
    fn resolve(
        &mut self,
        k: &mut Kimpact,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        narrow_phase: &NarrowPhase,
        broad_phase: &BroadPhaseBvh,
        dt: Real,
    ) {
        let max_events = k.config_ref().max_events_per_step;
        let mut events = 0usize;
        // The instant of the impacts whose bodies are in `bent`.
        let mut instant = Real::NEG_INFINITY;
        loop {
            // A pile resolves most of its impacts at one instant, pair by
            // pair through the overlapping cluster, each body hit several
            // times: its path is swept only once the instant is over, along
            // the last velocity it got then (the paths of the impacts in
            // between last no time), and its pairs with balls apart at
            // that instant are predicted then (`defer_if_apart`). The
            // sweep and those predictions may bring in pairs meeting at
            // that instant still: the loop takes them before any later.
            if !(self.bent.is_empty() && self.apart.is_empty())
                && self.queue.peek().is_none_or(|t| t.max(0.0) > instant)
            {
                let apart = std::mem::take(&mut self.apart);
                for &j in &apart {
                    self.pairs[j as usize].apart_at = Real::NEG_INFINITY;
                    self.predict(bodies, colliders, j as usize, instant, dt, false);
                }
                self.apart = apart;
                self.apart.clear();
                let bent = std::mem::take(&mut self.bent);
                for &(n, collider, ball) in &bent {
                    self.nodes[n].sweep_due = None;
                    self.sweep(
                        k,
                        bodies,
                        colliders,
                        broad_phase,
                        collider,
                        n,
                        ball,
                        instant,
                        dt,
                    );
                }
                self.bent = bent;
                self.bent.clear();
                continue;
            }
            let Some((t, i)) = self.queue.pop() else {
                break;
            };
            let pair = self.pairs[i];
            if pair.apart_at == t {
                // Queued before an impact at this instant bent either body:
                // predicted again once the instant is over.
                continue;
            }
            if events >= max_events {
                k.count_cap_hit();
                log::warn!(
                    "kimpact: more than {max_events} impacts in one step; the rest is left to rapier"
                );
                break;
            }
            let mut mass = |n: usize, c: ColliderHandle| -> Mass<Real> {
                let node = &mut self.nodes[n];
                if !node.dynamic {
                    return Mass::Infinite;
                }
                if node.mass.is_nan() {
                    let parent = colliders.get(c).and_then(|co| co.parent());
                    match law_body(bodies, parent).mass {
                        Mass::Finite(m) => node.mass = m,
                        // Not dynamic after all: as before, not cached.
                        Mass::Infinite => return Mass::Infinite,
                    }
                }
                Mass::Finite(node.mass)
            };
            let ma = mass(pair.a, pair.c1);
            let mb = mass(pair.b, pair.c2);
            let (na, nb) = (self.nodes[pair.a], self.nodes[pair.b]);
            let la = LawBody {
                mass: ma,
                velocity: na.law_velocity(self.phase, t, dt),
            };
            let lb = LawBody {
                mass: mb,
                velocity: nb.law_velocity(self.phase, t, dt),
            };
            let candidate = Candidate {
                collider1: pair.c1,
                collider2: pair.c2,
                normal: pair.normal,
                point: pair.point,
                dist: 0.0,
                start1: la,
                start2: lb,
            };
            let (Ok(ba), Ok(bb)) = (checked(&la), checked(&lb)) else {
                k.skip(&candidate);
                continue;
            };
            // The pair approaches faster than the rest speed: `predict`
            // queued it only then, and neither velocity has changed since.
            let Some(impact) = k.law_ref().resolve_unit(&ba, &bb, &to_law(pair.normal)) else {
                continue;
            };
            events += 1;
            for (n, dv) in [(pair.a, impact.delta_v_a), (pair.b, impact.delta_v_b)] {
                let node = &mut self.nodes[n];
                if !node.dynamic {
                    continue;
                }
                // After the step the path bends at the impact. Before it,
                // rapier will move the body with its new velocity from the
                // start of the step: predict along that line.
                if self.phase == Phase::Post {
                    node.p = node.at(t);
                    node.t_ref = t;
                }
                let dv = from_law(&dv);
                node.v += dv;
                node.u += dv;
                if !node.hit {
                    node.hit = true;
                    self.hit.push(n);
                }
            }
            k.push_event(&candidate, t, pair.point, &impact, false);
            // Chains: neighbours of both bodies, then fresh predictions for
            // every pair of the two bodies from now on.
            let from = t.max(0.0);
            instant = from;
            for n in [pair.a, pair.b] {
                if self.nodes[n].dynamic {
                    self.expand(k, bodies, colliders, narrow_phase, n, from, dt);
                    self.bring_deferred(k, bodies, colliders, n, from, dt);
                    // The new path may reach what neither the narrow phase
                    // nor the sweep along the old one saw: swept once this
                    // instant is over.
                    let side = pair.side(n);
                    let collider = [pair.c1, pair.c2][side];
                    if self.nodes[n].sweep_due != Some(collider) {
                        self.nodes[n].sweep_due = Some(collider);
                        self.bent.push((n, collider, pair.balls.map(|b| b[side])));
                    }
                }
            }
            let defer = self.phase == Phase::Post && t == from;
            for n in [pair.a, pair.b] {
                // The pairs listed now (a prediction adds none, but the
                // list is walked up to its present end regardless); the
                // impact's own pair once, in `a`'s list.
                let [mut j, last] = self.ends[n];
                while j != NO_PAIR {
                    let next = self.next_pair(j as usize, n);
                    if (n == pair.a || j as usize != i)
                        && !(defer && self.defer_if_apart(j as usize, from))
                    {
                        self.predict(bodies, colliders, j as usize, from, dt, false);
                    }
                    if j == last {
                        break;
                    }
                    j = next;
                }
            }
        }
    }
}

#[cfg(test)]
#[allow(clippy::unnecessary_cast)]
mod tests {
    use super::*;

    /// A small deterministic generator.
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> Real {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 / (1u64 << 53) as f64) as Real
        }
        fn aabb(&mut self, spread: Real, size: Real) -> Aabb {
            let mut lo = Vector::ZERO;
            let mut ext = Vector::ZERO;
            for k in 0..DIM {
                lo[k] = spread * self.next();
                ext[k] = size * self.next();
            }
            Aabb::new(lo, lo + ext)
        }
    }

    /// Every two boxes `s < t` that meet, by brute force, in order.
    fn overlapping_pairs(boxes: &[Aabb]) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        for (s, a) in boxes.iter().enumerate() {
            for (t, b) in boxes.iter().enumerate().skip(s + 1) {
                if a.intersects(b) {
                    pairs.push((s as u32, t as u32));
                }
            }
        }
        pairs
    }

    /// The grid's lookups, deduplicated as the bulk sweep does, give every
    /// overlapping (box, query) pair exactly once: against brute force, for
    /// boxes of mixed sizes, queries partly or wholly outside the grid, and
    /// one query larger than the whole grid (a wall).
    #[test]
    fn the_sweep_grid_finds_every_overlap_once() {
        let mut rng = Lcg(7);
        for size in [0.05, 0.5, 3.0] {
            let boxes: Vec<Aabb> = (0..300).map(|_| rng.aabb(10.0, size)).collect();
            let mut queries: Vec<Aabb> = (0..300).map(|_| rng.aabb(14.0, 1.0)).collect();
            queries.push(Aabb::new(Vector::splat(-100.0), Vector::splat(100.0)));
            let mut grid = SweepGrid::default();
            assert!(grid.build(boxes.iter().copied()));
            let mut found = Vec::new();
            for (q, aabb) in queries.iter().enumerate() {
                grid.overlaps(aabb, |s| found.push((s, q)));
            }
            found.sort_unstable();
            let mut brute = Vec::new();
            for (s, b) in boxes.iter().enumerate() {
                for (q, aabb) in queries.iter().enumerate() {
                    if aabb.intersects(b) {
                        brute.push((s as u32, q));
                    }
                }
            }
            brute.sort_unstable();
            assert!(brute.len() > 300, "size {size}: {} overlaps", brute.len());
            assert_eq!(found, brute, "size {size}");
            // The boxes against each other, as the bulk sweep joins the
            // sweepers: each overlapping pair once, from its first box.
            let mut joined = Vec::new();
            grid.self_join(|s, t| joined.push((s, t)));
            joined.sort_unstable();
            let brute = overlapping_pairs(&boxes);
            assert!(
                size < 3.0 || brute.len() > 100,
                "size {size}: {} pairs",
                brute.len()
            );
            assert_eq!(joined, brute, "size {size}: the join");
        }
    }

    /// The leaf grid is built once a run has made its share of tree
    /// queries, and then finds for every query exactly the leaves whose box
    /// in the tree meets it (brute force over the tree's leaves), among
    /// them every leaf a descent of the tree finds; four walls far larger
    /// than the balls' boxes stay out of the grid and are still found.
    #[test]
    fn the_leaf_grid_finds_every_leaf_box_a_query_meets() {
        let mut rng = Lcg(5);
        // As dense in 3D as in 2D.
        let spread = if DIM == 2 { 40.0 } else { 12.0 };
        let mut tree = Bvh::new();
        let mut key = 0;
        for _ in 0..2000 {
            tree.insert(rng.aabb(spread, 0.6), key);
            key += 1;
        }
        for axis in 0..2 {
            for side in [-1.0, spread] {
                let (mut lo, mut hi) = (Vector::splat(-1.0), Vector::splat(spread + 1.0));
                lo[axis] = side;
                hi[axis] = side + 1.0;
                tree.insert(Aabb::new(lo, hi), key);
                key += 1;
            }
        }
        let mut leaves = LeafGrid::default();
        let needed = LeafGrid::MIN_QUERIES.max(key as usize / LeafGrid::QUERY_SHARE);
        for _ in 1..needed {
            assert!(!leaves.wanted(&tree));
        }
        assert!(leaves.wanted(&tree));
        assert_eq!(leaves.big.len(), 4, "the walls");
        let mut boxes = Vec::new();
        for_each_leaf(&tree, |key, node| boxes.push((key, node.aabb())));
        let mut found = 0;
        for q in 0..400 {
            // Some queries reach past the walls, one covers everything.
            let query = if q == 0 {
                Aabb::new(Vector::splat(-50.0), Vector::splat(90.0))
            } else {
                let b = rng.aabb(spread + 6.0, 2.5);
                Aabb::new(b.mins - Vector::splat(3.0), b.maxs - Vector::splat(3.0))
            };
            let mut met = Vec::new();
            leaves.overlaps(&query, &mut met);
            met.sort_unstable();
            let mut brute: Vec<u32> = boxes
                .iter()
                .filter(|(_, b)| query.intersects(b))
                .map(|&(key, _)| key)
                .collect();
            brute.sort_unstable();
            assert_eq!(met, brute, "query {q}");
            for key in tree.leaves(|node: &BvhNode| node.aabb().intersects(&query)) {
                assert!(brute.binary_search(&key).is_ok(), "query {q}: leaf {key}");
            }
            found += brute.len();
        }
        assert!(found > 2000 + 400, "{found} leaves found");
        // The next run counts its own queries.
        leaves.clear();
        assert!(!leaves.wanted(&tree));
    }

    /// Every leaf of a tree is visited once with its own box, whether its
    /// key is found by the look-up from 0 or, beyond twice the leaf count,
    /// by the walk down the tree: against the keys inserted, for a tree
    /// with removed leaves (holes), sparse keys far beyond the leaf count,
    /// and an empty tree.
    #[test]
    fn every_leaf_is_visited_once() {
        let mut rng = Lcg(3);
        let mut tree = Bvh::new();
        let mut visited = Vec::new();
        for_each_leaf(&tree, |key, _| visited.push(key));
        assert!(visited.is_empty());
        let mut keys: Vec<u32> = (0..200).collect();
        keys.extend([500, 1_000, 77_777]);
        let boxes: Vec<Aabb> = keys.iter().map(|_| rng.aabb(10.0, 1.0)).collect();
        for (&key, aabb) in keys.iter().zip(&boxes) {
            tree.insert(*aabb, key);
        }
        for key in (0..200).step_by(3) {
            tree.remove(key);
        }
        let expected: Vec<(u32, Aabb)> = keys
            .iter()
            .zip(&boxes)
            .filter(|(k, _)| **k >= 200 || **k % 3 != 0)
            .map(|(k, b)| (*k, *b))
            .collect();
        let mut visited = Vec::new();
        for_each_leaf(&tree, |key, node| visited.push((key, node.aabb())));
        visited.sort_unstable_by_key(|v| v.0);
        assert_eq!(visited.len(), expected.len());
        for (v, e) in visited.iter().zip(&expected) {
            assert_eq!(v.0, e.0);
            assert!(v.1.contains(&e.1), "leaf {}: its box", e.0);
        }
    }

    /// The pair queue always yields its earliest entry (ties by rank, then
    /// by pair index), with one entry per pair, through random insertions,
    /// updates to earlier and later times and removals, many of them at the
    /// time of the last entry taken (the first heap's) and moving between
    /// the two heaps: against a plain list.
    #[test]
    fn the_pair_queue_keeps_the_earliest_first() {
        let mut rng = Lcg(11);
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

    /// Boxes that only touch a query (a shared face or corner: `intersects`
    /// counts them) are found too, far from the grid's origin and at the
    /// largest box size, where a box's low corner lies a whole box below
    /// the query's.
    #[test]
    fn the_sweep_grid_finds_boxes_that_only_touch() {
        let size = 0.5;
        let base = Vector::splat(1000.0);
        let at = |i: usize| -> Vector {
            let mut p = base;
            for k in 0..DIM {
                p[k] += size * ((i >> (4 * k)) % 16) as Real;
            }
            p
        };
        // A lattice of boxes, each touching its neighbours.
        let boxes: Vec<Aabb> = (0..1 << (4 * DIM))
            .map(|i| Aabb::new(at(i), at(i) + Vector::splat(size)))
            .collect();
        let mut grid = SweepGrid::default();
        assert!(grid.build(boxes.iter().copied()));
        for (q, query) in boxes.iter().enumerate().step_by(7) {
            let mut found = Vec::new();
            grid.overlaps(query, |s| found.push(s));
            found.sort_unstable();
            let brute: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&s| query.intersects(&boxes[s as usize]))
                .collect();
            assert!(brute.len() > 1, "box {q} touches its neighbours");
            assert_eq!(found, brute, "box {q}");
        }
        // And against each other, as the bulk sweep joins the sweepers.
        let mut joined = Vec::new();
        grid.self_join(|s, t| joined.push((s, t)));
        joined.sort_unstable();
        assert_eq!(joined, overlapping_pairs(&boxes), "the join");
    }

    /// Boxes further apart than the scalar type can measure are not
    /// gridded (the caller falls back to one query per box) rather than
    /// looping or indexing out of range.
    #[test]
    fn the_sweep_grid_refuses_boxes_it_cannot_measure() {
        let far = Real::MAX * 0.75;
        let boxes = [
            Aabb::new(Vector::splat(-far), Vector::splat(-far + 1.0)),
            Aabb::new(Vector::splat(far - 1.0), Vector::splat(far)),
        ];
        let mut grid = SweepGrid::default();
        assert!(!grid.build(boxes.iter().copied()));
        let near = [Aabb::new(Vector::ZERO, Vector::splat(1.0)); 2];
        assert!(grid.build(near.iter().copied()));
    }
}
