//! The event-driven simulator.

use std::hint::select_unpredictable;

use kimpact::{Body, Law};
use nalgebra::SVector;

use crate::error::{Quantity, ReferenceError};
use crate::grid::Grid;
use crate::kinematics::{gap_closing_time, pair_contact_time};
use crate::model::{Ball, BoxBounds, StallGuard, Stats};
use crate::queue::Queue;

/// The largest number of balls a [`Reference`] holds (indices are stored in
/// 32 bits).
pub const MAX_BALLS: usize = (u32::MAX - 128) as usize;

/// "No ball" in the cell lists.
const NONE: u32 = u32::MAX;
/// Event partner codes at and above this value are walls: `WALL + 2k` is the
/// lower wall of axis `k`, `WALL + 2k + 1` the upper one.
const WALL: u32 = u32::MAX - 96;
/// Event partner codes at and above this value are cell crossings: `CROSS +
/// 2k` downwards along axis `k`, `CROSS + 2k + 1` upwards.
const CROSS: u32 = u32::MAX - 64;

/// Relative tolerance of the overlap check of [`Reference::new`]: balls
/// placed touching (centre distance equal to the sum of the radii up to
/// rounding) are accepted.
pub const OVERLAP_TOLERANCE: f64 = 1e-12;

/// A ball as stored: its state at its own last update time `t`. The fields
/// read for every neighbour during a prediction come first (`repr(C)`
/// keeps them together).
#[derive(Copy, Clone, Debug)]
#[repr(C)]
struct Particle<const D: usize> {
    pos: SVector<f64, D>,
    vel: SVector<f64, D>,
    t: f64,
    radius: f64,
    /// The next ball in the same cell, or `NONE`.
    next: u32,
    /// Flat index of the cell.
    cell: u32,
    /// Impacts this ball took part in: a pair event carries the partner's,
    /// so that a later impact of the partner invalidates it.
    count: u64,
    mass: f64,
    /// The previous ball in the same cell, or `NONE`.
    prev: u32,
    /// Interior cell coordinates (1 to `n[k]`).
    coords: [u32; D],
}

/// What the predicted next event of a ball is (its time is in the queue):
/// it meets `other`, a ball, a wall (`WALL + code`) or a cell boundary
/// (`CROSS + code`). A pair event holds only while the partner has made no
/// impact since the prediction (its count is still `count_b`).
#[derive(Copy, Clone, Debug)]
struct Pending {
    other: u32,
    count_b: u64,
}

/// Position and velocity of a stored ball at time `t`.
#[inline]
fn state_at<const D: usize>(
    p: &Particle<D>,
    t: f64,
    gravity: &SVector<f64, D>,
    has_gravity: bool,
) -> (SVector<f64, D>, SVector<f64, D>) {
    let dt = t - p.t;
    if has_gravity {
        (
            p.pos + (p.vel + gravity * (0.5 * dt)) * dt,
            p.vel + gravity * dt,
        )
    } else {
        (p.pos + p.vel * dt, p.vel)
    }
}

/// An exact event-driven simulation of hard balls in a box under the
/// kimpact law. See the [crate documentation](crate) for the method.
#[derive(Clone, Debug)]
pub struct Reference<const D: usize> {
    parts: Vec<Particle<D>>,
    view: Vec<Ball<D>>,
    head: Vec<u32>,
    grid: Grid<D>,
    queue: Queue,
    pending: Vec<Pending>,
    /// Room for the balls around the one being predicted: every ball at
    /// most once, plus the heads of the `3^D` cells.
    scratch: Vec<u32>,
    time: f64,
    bounds: BoxBounds<D>,
    gravity: SVector<f64, D>,
    has_gravity: bool,
    law: Law<f64>,
    stats: Stats<D>,
    guard: StallGuard,
    guard_start: f64,
    guard_events: u64,
}

fn check_finite<const D: usize>(
    ball: usize,
    quantity: Quantity,
    v: &SVector<f64, D>,
) -> Result<(), ReferenceError> {
    match v.iter().position(|c| !c.is_finite()) {
        None => Ok(()),
        Some(component) => Err(ReferenceError::NonFinite {
            ball,
            quantity,
            component,
            value: v[component],
        }),
    }
}

fn check_ball<const D: usize>(
    i: usize,
    b: &Ball<D>,
    bounds: &BoxBounds<D>,
) -> Result<(), ReferenceError> {
    for (quantity, value) in [(Quantity::Radius, b.radius), (Quantity::Mass, b.mass)] {
        if !value.is_finite() {
            return Err(ReferenceError::NonFinite {
                ball: i,
                quantity,
                component: 0,
                value,
            });
        }
    }
    if b.radius <= 0.0 {
        return Err(ReferenceError::NonPositiveRadius {
            ball: i,
            value: b.radius,
        });
    }
    if b.mass <= 0.0 {
        return Err(ReferenceError::NonPositiveMass {
            ball: i,
            value: b.mass,
        });
    }
    check_finite(i, Quantity::Position, &b.position)?;
    check_finite(i, Quantity::Velocity, &b.velocity)?;
    for k in 0..D {
        let x = b.position[k];
        if !(x - b.radius >= bounds.lo[k] && x + b.radius <= bounds.hi[k]) {
            return Err(ReferenceError::OutsideBox {
                ball: i,
                axis: k,
                position: x,
                radius: b.radius,
                lo: bounds.lo[k],
                hi: bounds.hi[k],
            });
        }
    }
    Ok(())
}

impl<const D: usize> Reference<D> {
    /// A simulation of `balls` in the box `bounds`, under uniform `gravity`
    /// (zero for none), with the collision `law`, at time zero.
    ///
    /// # Errors
    /// [`ReferenceError::InvalidBox`], [`ReferenceError::NonFiniteGravity`],
    /// [`ReferenceError::NonFinite`], [`ReferenceError::NonPositiveRadius`],
    /// [`ReferenceError::NonPositiveMass`], [`ReferenceError::OutsideBox`]
    /// (a ball must lie inside the box, touching a wall at most) and
    /// [`ReferenceError::Overlap`] (balls may touch, not overlap by more than
    /// [`OVERLAP_TOLERANCE`] of the sum of their radii), and
    /// [`ReferenceError::TooManyBalls`] beyond [`MAX_BALLS`].
    pub fn new(
        balls: Vec<Ball<D>>,
        bounds: BoxBounds<D>,
        gravity: SVector<f64, D>,
        law: Law<f64>,
    ) -> Result<Self, ReferenceError> {
        const { assert!(D >= 1 && D <= 16, "1 to 16 dimensions") };
        for k in 0..D {
            let (lo, hi) = (bounds.lo[k], bounds.hi[k]);
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(ReferenceError::InvalidBox { axis: k, lo, hi });
            }
        }
        if let Some(component) = gravity.iter().position(|c| !c.is_finite()) {
            return Err(ReferenceError::NonFiniteGravity {
                component,
                value: gravity[component],
            });
        }
        if balls.len() > MAX_BALLS {
            return Err(ReferenceError::TooManyBalls {
                count: balls.len(),
                max: MAX_BALLS,
            });
        }
        for (i, b) in balls.iter().enumerate() {
            check_ball(i, b, &bounds)?;
        }
        let max_radius = balls.iter().map(|b| b.radius).fold(0.0, f64::max);
        let grid = Grid::new(
            &bounds.lo,
            &bounds.hi,
            2.0 * max_radius,
            4 * balls.len() + 64,
        );
        let n = balls.len();
        let parts = balls
            .iter()
            .map(|b| {
                let coords = grid.coords_of(&b.position);
                Particle {
                    pos: b.position,
                    vel: b.velocity,
                    t: 0.0,
                    radius: b.radius,
                    next: NONE,
                    cell: grid.flat(&coords) as u32,
                    count: 0,
                    mass: b.mass,
                    prev: NONE,
                    coords,
                }
            })
            .collect();
        let mut sim = Self {
            parts,
            view: balls,
            head: vec![NONE; grid.total],
            grid,
            queue: Queue::new(n),
            scratch: vec![NONE; n + 3usize.pow(D as u32) + 1],
            pending: vec![
                Pending {
                    other: NONE,
                    count_b: 0
                };
                n
            ],
            time: 0.0,
            bounds,
            gravity,
            has_gravity: gravity.iter().any(|&g| g != 0.0),
            law,
            stats: Stats::default(),
            guard: StallGuard::default(),
            guard_start: f64::NEG_INFINITY,
            guard_events: 0,
        };
        for i in 0..sim.parts.len() {
            sim.link(i);
        }
        sim.check_overlaps()?;
        for i in 0..sim.parts.len() {
            sim.predict(i, 0.0, NONE);
        }
        Ok(sim)
    }

    fn check_overlaps(&self) -> Result<(), ReferenceError> {
        for (i, p) in self.parts.iter().enumerate() {
            for &offset in &self.grid.neighbours {
                let mut j = self.head[(p.cell as isize + offset) as usize];
                while j != NONE {
                    let q = &self.parts[j as usize];
                    if j as usize > i {
                        let distance = (q.pos - p.pos).norm();
                        let contact = p.radius + q.radius;
                        if distance < contact * (1.0 - OVERLAP_TOLERANCE) {
                            return Err(ReferenceError::Overlap {
                                first: i,
                                second: j as usize,
                                distance,
                                contact,
                            });
                        }
                    }
                    j = q.next;
                }
            }
        }
        Ok(())
    }

    /// The current time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The balls at the current time, in the order given to
    /// [`Reference::new`].
    pub fn balls(&self) -> &[Ball<D>] {
        &self.view
    }

    /// The box.
    pub fn bounds(&self) -> &BoxBounds<D> {
        &self.bounds
    }

    /// The uniform gravity.
    pub fn gravity(&self) -> &SVector<f64, D> {
        &self.gravity
    }

    /// The collision law.
    pub fn law(&self) -> &Law<f64> {
        &self.law
    }

    /// Replace the collision law from now on (the events already predicted
    /// stay valid: they depend on positions and velocities only).
    pub fn set_law(&mut self, law: Law<f64>) {
        self.law = law;
    }

    /// The stall guard in force.
    pub fn stall_guard(&self) -> &StallGuard {
        &self.guard
    }

    /// Replace the stall guard.
    pub fn set_stall_guard(&mut self, guard: StallGuard) {
        self.guard = guard;
        self.guard_events = 0;
    }

    /// The counters since [`Reference::new`].
    pub fn stats(&self) -> &Stats<D> {
        &self.stats
    }

    /// Total kinetic energy `Σ ½ m |v|²` at the current time.
    pub fn kinetic_energy(&self) -> f64 {
        self.view.iter().map(Ball::kinetic_energy).sum()
    }

    /// Total potential energy in the gravity, `−Σ m g·x`, at the current
    /// time (zero at the origin).
    pub fn potential_energy(&self) -> f64 {
        -self
            .view
            .iter()
            .map(|b| b.mass * self.gravity.dot(&b.position))
            .sum::<f64>()
    }

    /// Total momentum `Σ m v` at the current time.
    pub fn momentum(&self) -> SVector<f64, D> {
        self.view
            .iter()
            .fold(SVector::zeros(), |acc, b| acc + b.momentum())
    }

    /// Advance the simulation by `dt`: [`Reference::advance_to`] at
    /// `time() + dt`.
    ///
    /// # Errors
    /// As [`Reference::advance_to`].
    pub fn advance_by(&mut self, dt: f64) -> Result<(), ReferenceError> {
        self.advance_to(self.time + dt)
    }

    /// Process every event up to time `target` (those exactly at `target`
    /// included) and present the balls at `target`.
    ///
    /// # Errors
    /// [`ReferenceError::InvalidTime`] if `target` is not finite or lies
    /// before [`Reference::time`]; [`ReferenceError::Stalled`] if the
    /// [`StallGuard`] trips, the simulation then being consistent at the
    /// time of the last event processed.
    pub fn advance_to(&mut self, target: f64) -> Result<(), ReferenceError> {
        if !(target.is_finite() && target >= self.time) {
            return Err(ReferenceError::InvalidTime {
                target,
                now: self.time,
            });
        }
        while let Some((time, a)) = self.queue.first() {
            if time > target {
                break;
            }
            let a = a as usize;
            let Pending { other, count_b } = self.pending[a];
            if other < WALL && self.parts[other as usize].count != count_b {
                // The partner has changed course since: this ball's next
                // event must be found again, from now.
                self.stats.stale_events += 1;
                self.time = time;
                self.predict(a, time, NONE);
                continue;
            }
            if time - self.guard_start > self.guard.window {
                self.guard_start = time;
                self.guard_events = 0;
            }
            self.guard_events += 1;
            if self.guard_events > self.guard.max_events {
                let events = self.guard_events - 1;
                self.guard_events = 0;
                self.stats.stalls += 1;
                self.sync();
                return Err(ReferenceError::Stalled {
                    time: self.time,
                    events,
                    window: self.guard.window,
                });
            }
            self.time = time;
            if other >= CROSS {
                self.cross(a, (other - CROSS) as usize, time);
            } else if other >= WALL {
                self.hit_wall(a, (other - WALL) as usize, time)?;
            } else {
                self.hit_pair(a, other as usize, time)?;
            }
        }
        self.time = target;
        self.sync();
        Ok(())
    }

    /// Present every ball at the current time.
    fn sync(&mut self) {
        for (b, p) in self.view.iter_mut().zip(&self.parts) {
            let (pos, vel) = state_at(p, self.time, &self.gravity, self.has_gravity);
            b.position = pos;
            b.velocity = vel;
        }
    }

    #[inline]
    fn state(&self, i: usize, t: f64) -> (SVector<f64, D>, SVector<f64, D>) {
        state_at(&self.parts[i], t, &self.gravity, self.has_gravity)
    }

    /// Store the state of ball `i` at `now` after an impact.
    fn settle(&mut self, i: usize, pos: SVector<f64, D>, vel: SVector<f64, D>, now: f64) {
        let p = &mut self.parts[i];
        p.pos = pos;
        p.vel = vel;
        p.t = now;
        p.count += 1;
    }

    fn hit_pair(&mut self, a: usize, b: usize, now: f64) -> Result<(), ReferenceError> {
        let (pos_a, mut vel_a) = self.state(a, now);
        let (pos_b, mut vel_b) = self.state(b, now);
        let r = pos_b - pos_a;
        let distance = r.norm();
        let impact = if distance > 0.0 {
            let body_a = Body::new(self.parts[a].mass, vel_a)?;
            let body_b = Body::new(self.parts[b].mass, vel_b)?;
            self.law.resolve_unit(&body_a, &body_b, &(r / distance))
        } else {
            None
        };
        match impact {
            Some(impact) => {
                vel_a += impact.delta_v_a;
                vel_b += impact.delta_v_b;
                self.stats.ball_impacts += 1;
                self.stats.clamped += u64::from(impact.clamped);
                self.stats.dissipated += impact.dissipated;
            }
            None => self.stats.missed += 1,
        }
        self.settle(a, pos_a, vel_a, now);
        self.settle(b, pos_b, vel_b, now);
        self.predict(a, now, b as u32);
        self.predict(b, now, a as u32);
        Ok(())
    }

    fn hit_wall(&mut self, i: usize, code: usize, now: f64) -> Result<(), ReferenceError> {
        let (axis, side) = (code / 2, code % 2);
        let (mut pos, mut vel) = self.state(i, now);
        let mut normal = SVector::<f64, D>::zeros();
        normal[axis] = if side == 1 { 1.0 } else { -1.0 };
        let ball = Body::new(self.parts[i].mass, vel)?;
        let wall = Body::immovable(SVector::zeros())?;
        match self.law.resolve_unit(&ball, &wall, &normal) {
            Some(impact) => {
                vel += impact.delta_v_a;
                self.stats.wall_impacts += 1;
                self.stats.wall_hits[axis][side] += 1;
                self.stats.wall_impulse[axis][side] += impact.impulse;
                self.stats.clamped += u64::from(impact.clamped);
                self.stats.dissipated += impact.dissipated;
            }
            None => self.stats.missed += 1,
        }
        // The ball touches the wall now: remove the rounding of its position
        // along the normal, so that it can never drift out of the box.
        let radius = self.parts[i].radius;
        pos[axis] = if side == 1 {
            self.bounds.hi[axis] - radius
        } else {
            self.bounds.lo[axis] + radius
        };
        self.settle(i, pos, vel, now);
        self.predict(i, now, NONE);
        Ok(())
    }

    fn cross(&mut self, i: usize, code: usize, now: f64) {
        let (axis, up) = (code / 2, code % 2);
        self.unlink(i);
        let stride = self.grid.stride[axis] as u32;
        let p = &mut self.parts[i];
        if up == 1 {
            p.coords[axis] += 1;
            p.cell += stride;
        } else {
            p.coords[axis] -= 1;
            p.cell -= stride;
        }
        self.link(i);
        self.stats.cell_crossings += 1;
        self.predict(i, now, NONE);
    }

    /// Predict the next event of ball `i` from `now` and queue it: the
    /// earliest of its next wall impact, its next cell crossing and its
    /// impacts with the balls of the `3^D` cells around (but `exclude`).
    /// Only this latest prediction of the ball stays valid.
    ///
    /// One event per ball suffices: the earliest event of the whole system,
    /// between `a` and `b`, is found by the one of the two that changed
    /// course or cell last (they were neighbours then, and neither changes
    /// cell before meeting). If that ball predicted an earlier event with a
    /// third ball, which that ball's own impact then cancelled, the stale
    /// event is met first and the prediction made again.
    fn predict(&mut self, i: usize, now: f64, exclude: u32) {
        let (pos, vel) = self.state(i, now);
        let (mut best, mut other) = self.boundary_time(i, &pos, &vel);
        let mut count_b = 0;
        let Self {
            parts,
            head,
            grid,
            scratch,
            gravity,
            has_gravity,
            ..
        } = self;
        let p = &parts[i];
        let (radius, base) = (p.radius, p.cell as isize);
        // Gather the balls of the cells around into `scratch` without
        // branching on whether a cell is empty (a coin toss in a gas): the
        // heads of the lists first, then each ball's successor as the ball
        // is examined. The slot after the last is written and not counted.
        // The ball itself is left out (its successor is taken up front).
        let me = i as u32;
        let mut len = 0;
        scratch[len] = p.next;
        len += usize::from(p.next != NONE);
        for &offset in &grid.neighbours {
            let j = head[(base + offset) as usize];
            scratch[len] = j;
            len += usize::from((j != NONE) & (j != me));
        }
        let mut at = 0;
        while at < len {
            let j = scratch[at];
            at += 1;
            let q = &parts[j as usize];
            scratch[len] = q.next;
            len += usize::from((q.next != NONE) & (q.next != me));
            // The partner of the impact just resolved is skipped (their
            // relative motion is linear and receding: they cannot meet
            // before one of them changes course).
            let (q_pos, q_vel) = state_at(q, now, gravity, *has_gravity);
            let dt = pair_contact_time(&(q_pos - pos), &(q_vel - vel), radius + q.radius);
            if (dt < best) & (j != exclude) {
                best = dt;
                other = j;
                count_b = q.count;
            }
        }
        self.pending[i] = Pending { other, count_b };
        self.queue.update(i as u32, now + best);
    }

    /// The time from now of the next wall impact or cell crossing of ball
    /// `i` (at `pos`, `vel` now), and its event code (infinite and `NONE` if
    /// none). Crossings towards the outside of the grid are never needed:
    /// the wall comes first.
    fn boundary_time(&self, i: usize, pos: &SVector<f64, D>, vel: &SVector<f64, D>) -> (f64, u32) {
        let p = &self.parts[i];
        let coords = &p.coords;
        let mut best = f64::INFINITY;
        let mut code = NONE;
        let mut consider = |t: f64, c: u32| {
            if t < best {
                best = t;
                code = c;
            }
        };
        for k in 0..D {
            let k2 = 2 * k as u32;
            let c = coords[k];
            let to_lower_wall = pos[k] - (self.bounds.lo[k] + p.radius);
            let to_upper_wall = (self.bounds.hi[k] - p.radius) - pos[k];
            let accel = 0.5 * self.gravity[k];
            if accel == 0.0 {
                // Uniform motion: only the side the ball moves towards, chosen
                // without branches. At rest, `inv = ∞` and the times are ∞
                // (or NaN for a zero gap, which `consider` ignores).
                let v = vel[k];
                let inv = 1.0 / v.abs();
                let up = v > 0.0;
                let wall_gap = select_unpredictable(up, to_upper_wall, to_lower_wall);
                let cell_gap = select_unpredictable(
                    up,
                    self.grid.upper(k, c) - pos[k],
                    pos[k] - self.grid.lower(k, c),
                );
                let inner = select_unpredictable(up, c < self.grid.n[k], c > 1);
                consider(wall_gap.max(0.0) * inv, WALL + k2 + u32::from(up));
                let cross = select_unpredictable(inner, cell_gap.max(0.0) * inv, f64::INFINITY);
                consider(cross, CROSS + k2 + u32::from(up));
                continue;
            }
            if let Some(t) = gap_closing_time(to_lower_wall, vel[k], accel) {
                consider(t, WALL + k2);
            }
            if let Some(t) = gap_closing_time(to_upper_wall, -vel[k], -accel) {
                consider(t, WALL + k2 + 1);
            }
            if c > 1
                && let Some(t) = gap_closing_time(pos[k] - self.grid.lower(k, c), vel[k], accel)
            {
                consider(t, CROSS + k2);
            }
            if c < self.grid.n[k]
                && let Some(t) = gap_closing_time(self.grid.upper(k, c) - pos[k], -vel[k], -accel)
            {
                consider(t, CROSS + k2 + 1);
            }
        }
        (best, code)
    }

    fn link(&mut self, i: usize) {
        let cell = self.parts[i].cell as usize;
        let first = self.head[cell];
        self.parts[i].prev = NONE;
        self.parts[i].next = first;
        if first != NONE {
            self.parts[first as usize].prev = i as u32;
        }
        self.head[cell] = i as u32;
    }

    fn unlink(&mut self, i: usize) {
        let Particle {
            next, cell, prev, ..
        } = self.parts[i];
        if prev != NONE {
            self.parts[prev as usize].next = next;
        } else {
            self.head[cell as usize] = next;
        }
        if next != NONE {
            self.parts[next as usize].prev = prev;
        }
    }
}
