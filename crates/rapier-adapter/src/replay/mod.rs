//! The law's modes' replay: the impacts of one step, resolved in time
//! order at their analytic times of impact, after rapier's step (impulse
//! and exact mode: every governed impact; restitution mode: those of the
//! bodies fast enough to tunnel).
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
//! The pairs are those rapier's contacts hold (the hook's candidates) and
//! those of bodies that move more than half their size per step (swept, as
//! they can cross a partner unseen). Exact mode also sweeps every body that
//! moves more than half rapier's prediction distance, which can meet a
//! partner rapier's contacts did not reach yet; impulse mode does so only
//! for a body that falls (moves along gravity: a landing on a pile at
//! rest), and leaves any other such pair to the next step, where rapier
//! first sees it overlapping and the replay rewinds it (a graze that
//! begins and ends within the step is missed).
//!
//! Restitution mode hands the replay only the bodies that move more than
//! a quarter of their size per step (and their pairs, which rapier's solver then
//! leaves alone): rapier's solver bounces every other pair with the law's
//! restitution. A body an impact bends chains on (brings its touching
//! neighbours in, and is swept again) only while it still moves that
//! fast. A line that crosses its box several times per step is bent at
//! every wall, and the body is written back inside.

use std::cmp::Ordering;

use kimpact::{Law, Mass};

use crate::body_view::{LawBody, Starts, dominate, law_body};
use crate::candidates::Candidate;
use crate::config::ResolverConfig;
use crate::events::{EventLog, Outcome};
use crate::frame::StepFrame;
use crate::leaves::{LeafGrid, for_each_leaf};
use crate::marks::Marks;
use crate::math::{Pose, Real, Vector, from_law, to_law};
use crate::mode::Mode;
use crate::pair_filter::PairFilter;
use crate::rapier::prelude::*;
use crate::sweep_grid::SweepGrid;

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
    /// Gravity over half the body's substep (`g s h / 2`, see
    /// [`StepFrame::half_substep`]; zero for non-dynamic bodies): what
    /// separates rapier's velocity from the velocity of the parabola its
    /// substeps put the body on.
    g_half: Vector,
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
    /// The body's dominance group (rapier's), read with `mass`.
    dominance: i8,
    /// Its rotation in [`Replay::spins`] once a pair with impact friction
    /// meets it ([`spin::NO_SPIN`] until then).
    spin: u32,
}

impl Node {
    fn at(&self, t: Real) -> Vector {
        self.p + self.v * (t - self.t_ref)
    }

    /// The velocity the law meets the body with at time `t`: the velocity,
    /// at `t`, of the parabola rapier's substeps put the body on (rapier's
    /// velocity plus gravity over half a substep, [`Node::g_half`]). After
    /// the step, `u` is the velocity at its end: the law meets the bodies
    /// at `t`, before gravity's share of the rest of the step (which they
    /// keep afterwards).
    ///
    /// Between two bodies under the same gravity the offsets cancel (the
    /// law conserves momentum); against a fixed partner they are what
    /// keeps a bounce elastic: rapier's integrator conserves
    /// `½ m |v + g h/2|² − m g·x` in free flight, so a law that reversed `v`
    /// itself would change the next flight's energy by `m h g·Δv / 2`
    /// (a lower apex at every bounce).
    fn law_velocity(&self, t: Real, dt: Real) -> Vector {
        self.u - self.g_dt * ((dt - t) / dt) + self.g_half
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

mod nodes;
mod predict;
mod queue;
mod spin;
mod sweep;

use queue::PairQueue;
use spin::{NO_SPIN, Spin};

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

/// What a replay run reads: the law, the settings and marks in force, the
/// colliders flagged this step, where the bodies started it, the pairs the
/// hook handed over, and the step's constants.
pub(crate) struct ReplayInput<'a> {
    pub law: &'a Law<Real>,
    pub config: &'a ResolverConfig,
    pub marks: &'a Marks,
    pub flagged: &'a [ColliderHandle],
    pub starts: &'a Starts,
    pub candidates: &'a [Candidate],
    pub frame: StepFrame,
    /// Whether rapier would let a pair the sweeps find touch.
    pub filter: PairFilter<'a>,
}

/// What a replay run produces besides the bodies it changes: the impact
/// events and totals, and the bodies it gave a new velocity (woken).
pub(crate) struct ReplayOutput<'a> {
    pub log: &'a mut EventLog,
    pub woken: &'a mut Vec<RigidBodyHandle>,
}

/// Scratch space of the replay, kept between steps so that a steady state
/// allocates nothing.
#[derive(Default)]
pub(crate) struct Replay {
    /// `g dt`: what rapier adds to a dynamic body's velocity this step.
    gravity_dt: Vector,
    /// The rest speed of this run.
    rest_speed: Real,
    /// How far a body must move this step (besides more than half its
    /// size) to be swept for partners: see [`Replay::run`].
    sweep_reach: Real,
    /// `sweep_reach` for a body that falls (moves along gravity): see
    /// [`Replay::run`].
    fall_reach: Real,
    /// Restitution mode: a body an impact bends chains on (see
    /// [`Replay::chains`]) only while it moves more than this share of its
    /// half-size over the rest of the step; zero (always) in the others.
    chain_share: Real,
    nodes: Vec<Node>,
    /// The rotations of the nodes that pairs with impact friction met
    /// this run (see [`Node::spin`]).
    spins: Vec<Spin>,
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
    /// per node in a vector of its own would reallocate in steady state
    /// (which node a body gets changes from step to step, and a ball's list
    /// could land in a slot too small for it); these need no allocation
    /// beyond `pairs`' and `nodes`' own.
    ends: Vec<[u32; 2]>,
    /// For each node, how many pairs it is in.
    degrees: Vec<u32>,
    /// The pairs of crowded nodes (see [`nodes::CROWD`]), by
    /// [`nodes::pair_key`]: a crowded node's list is too long to walk for
    /// every pair a sweep or its neighbours bring (kept between runs, so a
    /// steady state allocates nothing).
    crowd_pairs: std::collections::HashSet<u64>,
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
    /// Never sweep in bulk, nor through `leaves` (the unit tests compare
    /// both ways).
    pub(crate) per_body_sweep: bool,
    /// Runs that swept in bulk (for the unit tests).
    #[cfg(test)]
    pub(crate) bulk_sweeps: u64,
    #[cfg(feature = "parallel")]
    par: sweep::ParScratch,
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

impl Replay {
    /// Bring the governed contacts of node `n`'s marked colliders into the
    /// replay (once), and predict them from time `t`.
    #[allow(clippy::too_many_arguments)]
    fn expand(
        &mut self,
        input: &ReplayInput,
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
        let config = input.config;
        for &ch in rb.colliders() {
            for cp in narrow_phase.contact_pairs_with(ch) {
                // Only the contacts rapier saw (touching neighbours).
                if !cp.has_any_active_contact()
                    || self.has_pair(cp.collider1, cp.collider2)
                    || !input.marks.governs(
                        config.fixed_partners,
                        colliders,
                        bodies,
                        cp.collider1,
                        cp.collider2,
                    )
                {
                    continue;
                }
                if let Some(i) =
                    self.add_pair(input, bodies, colliders, cp.collider1, cp.collider2, dt)
                {
                    self.predict(bodies, colliders, i, t, dt, false);
                }
            }
        }
    }

    /// Whether node `n`, whose path an impact on its collider `collider`
    /// (a ball of radius and offset `ball`, if it is one) bent at `from`,
    /// chains on: brings its touching neighbours into the replay and is
    /// swept along its new path. Always, but in restitution mode, where it
    /// does only while it moves more than a quarter of its size over the
    /// rest of the step (as `Prepare::is_swept` hands a body to the replay):
    /// slower, it cannot tunnel before rapier's contacts see it, and its
    /// pairs outside the replay are rapier's solver's next step, bounced
    /// with the law's restitution. (A row of touching balls struck hard
    /// chains on while the struck balls move that fast; a pile a falling
    /// ball lands on is not replayed through.)
    fn chains(
        &self,
        colliders: &ColliderSet,
        n: usize,
        collider: ColliderHandle,
        ball: Option<BallOnPath>,
        from: Real,
        dt: Real,
    ) -> bool {
        if self.chain_share == 0.0 {
            return true;
        }
        let half = match ball {
            Some((radius, _)) => radius,
            None => colliders
                .get(collider)
                .map_or(0.0, crate::body_view::half_size),
        };
        (self.nodes[n].v * (dt - from)).length() > self.chain_share * half
    }

    /// Collider `ch`'s sweep reached collider `other`: if the law governs the
    /// pair, bring it into the replay and predict it from `from`.
    #[allow(clippy::too_many_arguments)]
    fn meet(
        &mut self,
        input: &ReplayInput,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        ch: ColliderHandle,
        other: ColliderHandle,
        from: Real,
        dt: Real,
    ) {
        if other == ch
            || self.has_pair(ch, other)
            || !input
                .marks
                .governs(input.config.fixed_partners, colliders, bodies, ch, other)
        {
            return;
        }
        if let Some(i) = self.add_pair(input, bodies, colliders, ch, other, dt) {
            self.predict(bodies, colliders, i, from, dt, from == 0.0);
        }
    }

    /// Start a run: empty scratch and the step's constants; whether the
    /// step can be replayed at all (`dt > 0`).
    fn begin(&mut self, gravity: Vector, dt: Real, rest_speed: Real) -> bool {
        self.clear();
        self.gravity_dt = gravity * dt;
        self.rest_speed = rest_speed;
        dt > 0.0
    }

    /// After rapier's step (`Impulse`, `Exact`): resolve this step's impacts
    /// in time order and write the results back. Exact mode also sweeps the
    /// bodies that can reach a partner rapier's contacts did not.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn run(
        &mut self,
        input: &ReplayInput,
        out: &mut ReplayOutput,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        narrow_phase: &NarrowPhase,
        broad_phase: &BroadPhaseBvh,
        mode: Mode,
    ) {
        let StepFrame {
            gravity,
            dt,
            rest_speed,
            prediction,
            ..
        } = input.frame;
        if !self.begin(gravity, dt, rest_speed) {
            return;
        }
        // rapier's contacts (hence the candidates) reach `prediction` beyond
        // the start-of-step shapes. Two bodies each moving at most half of
        // that close at most all of it, so they were seen; a body moving
        // more may reach a partner unseen (a gas ball at 3 m/s moves 0.05
        // per step at 60 Hz, the prediction is 0.02), and is swept in exact
        // mode. Impulse mode sweeps only what could tunnel: a pair rapier
        // did not reach is first seen overlapping next step, and rewound.
        // Restitution mode hands over only the bodies that move more than
        // a quarter of their size (`Prepare::is_swept`): each is swept.
        // Impulse mode sweeps a falling body as exact mode does: it lands
        // on partners at rest, and a landing rapier first sees overlapping
        // the pile costs rapier's narrow phase more, at every step of the
        // landing, than the sweep costs (a gas has no gravity: nothing
        // falls).
        self.sweep_reach = match mode {
            Mode::Exact => 0.5 * prediction,
            Mode::Impulse => Real::INFINITY,
            Mode::Native | Mode::Restitution => 0.0,
        };
        self.fall_reach = match mode {
            Mode::Impulse => 0.5 * prediction,
            _ => self.sweep_reach,
        };
        // Restitution mode's replay keeps fast bodies from tunnelling
        // (`Prepare::is_swept`'s quarter of their size per step); a body
        // an impact slows below that is a slow body like any other, whose
        // pairs rapier's solver bounces.
        self.chain_share = match mode {
            Mode::Restitution => crate::body_view::SWEPT_SHARE,
            _ => 0.0,
        };
        for j in 0..input.candidates.len() {
            let c: Candidate = input.candidates[j];
            if !c.by_replay {
                continue; // bounced by rapier's solver (restitution mode)
            }
            if let Some(i) = self.add_pair(input, bodies, colliders, c.collider1, c.collider2, dt) {
                self.predict(bodies, colliders, i, 0.0, dt, true);
            }
        }
        self.sweep_fast_bodies(input, bodies, colliders, broad_phase, dt);
        self.resolve(input, out, bodies, colliders, narrow_phase, broad_phase, dt);
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
                self.write_spin(n, rb);
                out.woken.push(h);
            }
        }
    }

    /// The impacts on the heap, in time order, each bending the paths of
    /// its two bodies and bringing their neighbours in.
    #[allow(clippy::too_many_arguments)]
    fn resolve(
        &mut self,
        input: &ReplayInput,
        out: &mut ReplayOutput,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        narrow_phase: &NarrowPhase,
        broad_phase: &BroadPhaseBvh,
        dt: Real,
    ) {
        let max_events = input.config.max_events_per_step;
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
                        input,
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
                out.log.cap_hit();
                log::warn!(
                    "kimpact: more than {max_events} impacts in one step; the rest is left to rapier"
                );
                break;
            }
            let mut mass = |n: usize, c: ColliderHandle| -> Option<Mass<Real>> {
                let node = &mut self.nodes[n];
                if !node.dynamic {
                    return Some(Mass::Infinite);
                }
                if node.mass.is_nan() {
                    let parent = colliders.get(c).and_then(|co| co.parent());
                    match law_body(bodies, parent)?.mass {
                        Mass::Finite(m) => {
                            node.mass = m;
                            node.dominance = parent
                                .and_then(|h| bodies.get(h))
                                .map_or(0, |rb| rb.dominance_group());
                        }
                        // Not dynamic after all: as before, not cached.
                        Mass::Infinite => return Some(Mass::Infinite),
                    }
                }
                Some(Mass::Finite(node.mass))
            };
            // A body with some translations locked: the pair is rapier's.
            let (Some(ma), Some(mb)) = (mass(pair.a, pair.c1), mass(pair.b, pair.c2)) else {
                continue;
            };
            let (na, nb) = (self.nodes[pair.a], self.nodes[pair.b]);
            let la = LawBody {
                mass: ma,
                velocity: na.law_velocity(t, dt),
            };
            let lb = LawBody {
                mass: mb,
                velocity: nb.law_velocity(t, dt),
            };
            // Two dynamic bodies of different dominance groups: the dominant
            // one is immovable to the other, as rapier's solver takes it.
            let (la, lb) = if na.dominance == nb.dominance || ma.is_infinite() || mb.is_infinite() {
                (la, lb)
            } else {
                (
                    dominate(la, na.dominance, nb.dominance),
                    dominate(lb, nb.dominance, na.dominance),
                )
            };
            let candidate = Candidate {
                collider1: pair.c1,
                collider2: pair.c2,
                normal: pair.normal,
                point: pair.point,
                dist: 0.0,
                start1: la,
                start2: lb,
                by_replay: true,
                rigid: None,
            };
            let (Ok(ba), Ok(bb)) = (la.checked(), lb.checked()) else {
                out.log.skip(&candidate);
                continue;
            };
            // The pair approaches faster than the rest speed: `predict`
            // queued it only then, and neither velocity has changed since.
            let law = input.marks.law(input.law, pair.c1, pair.c2);
            let friction = input.marks.friction(pair.c1, pair.c2);
            let (outcome, delta_v) = if friction.is_frictionless() {
                let Some(impact) = law.resolve_unit(&ba, &bb, &to_law(pair.normal)) else {
                    continue;
                };
                (Outcome::from(&impact), [impact.delta_v_a, impact.delta_v_b])
            } else {
                let Some(impact) = self.resolve_with_friction(
                    bodies,
                    colliders,
                    &pair,
                    (&la, &lb),
                    &law,
                    &friction,
                    t,
                ) else {
                    continue;
                };
                self.turn(pair.a, &impact.delta_omega_a, t.max(0.0), dt);
                self.turn(pair.b, &impact.delta_omega_b, t.max(0.0), dt);
                (Outcome::from(&impact), [impact.delta_v_a, impact.delta_v_b])
            };
            events += 1;
            for (n, dv, m) in [(pair.a, delta_v[0], la.mass), (pair.b, delta_v[1], lb.mass)] {
                let node = &mut self.nodes[n];
                // (A dominant body's path stays as it is.)
                if !node.dynamic || m.is_infinite() {
                    continue;
                }
                // The path bends at the impact.
                node.p = node.at(t);
                node.t_ref = t;
                let dv = from_law(&dv);
                node.v += dv;
                node.u += dv;
                if !node.hit {
                    node.hit = true;
                    self.hit.push(n);
                }
            }
            out.log.push(&candidate, t, pair.point, outcome, false);
            // Chains: neighbours of both bodies, then fresh predictions for
            // every pair of the two bodies from now on.
            let from = t.max(0.0);
            instant = from;
            for n in [pair.a, pair.b] {
                if self.nodes[n].dynamic {
                    let side = pair.side(n);
                    let collider = [pair.c1, pair.c2][side];
                    let ball = pair.balls.map(|b| b[side]);
                    if !self.chains(colliders, n, collider, ball, from, dt) {
                        // Its touching neighbours are rapier's solver's next
                        // step; its pairs with the sweepers are the replay's.
                        self.bring_deferred(input, bodies, colliders, n, from, dt);
                        continue;
                    }
                    self.expand(input, bodies, colliders, narrow_phase, n, from, dt);
                    self.bring_deferred(input, bodies, colliders, n, from, dt);
                    // The new path may reach what neither the narrow phase
                    // nor the sweep along the old one saw: swept once this
                    // instant is over.
                    if self.nodes[n].sweep_due != Some(collider) {
                        self.nodes[n].sweep_due = Some(collider);
                        self.bent.push((n, collider, ball));
                    }
                }
            }
            let defer = t == from;
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
