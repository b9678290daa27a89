//! The rigid replay (impulse and exact mode): the impacts of marked
//! colliders of another shape than a ball centred on a dynamic body (and
//! of their partners) resolved at their time of impact along the motion
//! rapier gave the bodies over the step, after rapier's step.
//!
//! The contact hook claims such a pair ([`Claims::claim`]) when its
//! contacts meet as an impact, and clears its solver contacts: rapier's
//! solver does not respond to it, and integrates the two bodies as if
//! they did not touch. After the step each body involved moves, over the
//! step, on rapier's motion: its centre of mass on the straight line from
//! its start to its end, turning about it at a constant angular velocity
//! from its start orientation to its end one ([`motion::Motion`]). Exact
//! mode also sweeps every moving rigid body (`Prepare::rigid`) for
//! partners rapier's contacts did not reach yet. Then, event by event,
//! earliest first: the pair's time of impact ([`toi::time_of_impact`]),
//! its contact patch there ([`patch::patch`]: the centroid of the closing
//! contacts of the manifold, so a face lands at its centre), the law
//! ([`kimpact::Law::resolve_rigid_with_friction`]) at that point with the
//! bodies' velocities at that instant, the two paths bent there; the
//! pairs of the two bodies touching then are met at that instant again,
//! and once no impact is left at it (a pile resolves many at one instant)
//! the bent bodies' other pairs are searched again from it and their
//! neighbours (their rapier contact pairs, and what a sweep along the new
//! path reaches) brought in ([`Instant`]). At the end each body
//! whose path was bent gets the pose its path reaches at the step's end
//! and its velocities: rapier's end-of-step velocities plus the changes.
//!
//! The law meets a body at time `t` with the velocity its path has then
//! under gravity, as the ball replay does (rapier's end-of-step velocity,
//! less gravity over the rest of the step, plus gravity over half a
//! substep), and with its angular velocity and its world inverse inertia
//! turned to its orientation at `t`.
//!
//! A ball centred on its dynamic body meeting a governed rigid body: the
//! pair is this replay's (the ball is a rigid body of zero arm here), and
//! runs after the ball replay, on the path the ball replay left the ball
//! (from its start to the end the ball replay wrote).

mod claim;
mod motion;
mod nodes;
mod patch;
mod queue;
mod resolve;
#[cfg(test)]
mod test_support;
mod toi;

use kimpact::Law;

use crate::body_view::Starts;
use crate::cast::Rewind;
use crate::config::ResolverConfig;
use crate::frame::StepFrame;
use crate::handle_map::HandleMap;
use crate::marks::Marks;
use crate::math::{Pose, Real, Vector};
use crate::pair_filter::PairFilter;
use crate::policy::Policy;
use crate::rapier::math::AngVector;
use crate::rapier::parry::query::ContactManifold;
use crate::rapier::prelude::*;
use crate::replay::{ReplayOutput, ReplaySets};
use crate::rigid_view::LawRigid;
use resolve::Idle;

pub(crate) use claim::{Claim, Claims};
use motion::Motion;
use queue::Queue;

/// The time-of-impact tolerance, relative to the pair's size: the gap at
/// which two colliders are taken as touching, `ε^(2/3)` (3.7e-11 in f64,
/// 4.9e-5 in f32).
fn toi_share() -> Real {
    Real::EPSILON.powf(2.0 / 3.0)
}

/// Contacts within this many time-of-impact tolerances of the deepest
/// closing one are in its patch.
const PATCH_TOLERANCES: Real = 4.0;

/// Approach speeds below this times the sum of the two bodies' speeds are
/// resting contacts: rounding level.
const REST_FLOOR: Real = 64.0 * Real::EPSILON;

/// What the rigid replay reads: the law, the settings and marks in force,
/// the moving rigid colliders of the step (`Prepare::rigid`), where the
/// bodies started it (`Prepare::starts`, translations), the step's
/// constants, the pair filter and what the step's mode does.
pub(crate) struct RigidInput<'a> {
    pub law: &'a Law<Real>,
    pub config: &'a ResolverConfig,
    pub marks: &'a Marks,
    pub rigid: &'a [ColliderHandle],
    pub starts: &'a Starts,
    pub frame: StepFrame,
    pub filter: PairFilter<'a>,
    pub policy: Policy,
}

/// rapier's sets as the rigid replay reads them while it resolves.
#[derive(Copy, Clone)]
struct World<'a> {
    bodies: &'a RigidBodySet,
    colliders: &'a ColliderSet,
    narrow_phase: &'a NarrowPhase,
    broad_phase: &'a BroadPhaseBvh,
}

/// What a node of the replay stands for.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
enum Key {
    Body(RigidBodyHandle),
    /// A collider without a body (static geometry).
    Collider(ColliderHandle),
}

/// A body (or a collider without one) in the replay.
#[derive(Copy, Clone, Debug)]
struct Node {
    key: Key,
    /// A dynamic body: the law may bend its path.
    dynamic: bool,
    motion: Motion,
    /// Its velocity: rapier's end-of-step velocity plus the changes.
    u: Vector,
    /// Its angular velocity: rapier's end-of-step one plus the changes.
    omega: AngVector,
    /// What gravity adds to its velocity over the step (zero but for a
    /// dynamic body whose translations are free).
    g_dt: Vector,
    /// Gravity over half its substep (see `StepFrame::half_substep`).
    g_half: Vector,
    /// Its world inverse inertia at the end of rapier's step.
    inverse_inertia: kimpact::InverseInertia<Real, { crate::math::DIM }>,
    /// An impact bent its path.
    hit: bool,
    /// Its path does not end where rapier's step left it (a CCD stop the
    /// replay looks past): its end is written back even without an impact.
    off_rapier: bool,
}

impl Node {
    /// The velocity the law meets the body with at time `t` (the ball
    /// replay's `Node::law_velocity`).
    fn law_velocity(&self, t: Real, dt: Real) -> Vector {
        self.u - self.g_dt * ((dt - t) / dt) + self.g_half
    }

    /// The velocity, at time `t`, of the body's material point at `point`.
    fn point_velocity(&self, point: Vector, t: Real, dt: Real) -> Vector {
        let arm = point - self.motion.com_at(t);
        self.law_velocity(t, dt) + cross(self.omega, arm)
    }
}

/// `ω × r` in this dimension.
#[cfg(feature = "dim2")]
fn cross(w: AngVector, r: Vector) -> Vector {
    Vector::new(-w * r.y, w * r.x)
}

/// `ω × r` in this dimension.
#[cfg(feature = "dim3")]
fn cross(w: AngVector, r: Vector) -> Vector {
    w.cross(r)
}

/// A pair of colliders in the replay, on nodes `a` and `b`.
#[derive(Copy, Clone, Debug)]
struct Pair {
    a: usize,
    b: usize,
    c1: ColliderHandle,
    c2: ColliderHandle,
}

/// The instant of the latest impacts, and what waits for its end. A pile
/// resolves many impacts at one instant, pair by pair through a cluster
/// of touching bodies, each body hit several times: a pair apart at that
/// instant cannot meet then, so its search (and the sweep of a bent body)
/// runs once the instant is over, along the last paths, not after every
/// impact.
#[derive(Debug, Default)]
struct Instant {
    /// The instant.
    at: Real,
    /// Pairs apart at it, searched at its end.
    deferred: Vec<usize>,
    /// Nodes bent at it, expanded at its end.
    bent: Vec<usize>,
    /// Per pair: the instant it was last judged at and whether it touched
    /// then (poses at an instant do not change with its impacts).
    touching: Vec<(Real, bool)>,
}

impl Instant {
    /// None yet.
    fn clear(&mut self) {
        self.at = Real::NAN;
        self.deferred.clear();
        self.bent.clear();
        self.touching.clear();
    }

    /// Whether work waits for the instant's end.
    fn pending(&self) -> bool {
        !(self.deferred.is_empty() && self.bent.is_empty())
    }
}

/// The rigid replay's state: the hook's claims, the start poses of the
/// step's moving rigid bodies, and the scratch of a run (kept between
/// steps, so a steady state allocates little).
#[derive(Default)]
pub(crate) struct RigidReplay {
    pub(crate) claims: Claims,
    /// Start poses of the moving rigid bodies, sorted by handle.
    starts: Vec<(RigidBodyHandle, Pose)>,
    nodes: Vec<Node>,
    /// The node of each body in the run, and of each collider without one.
    body_nodes: HandleMap<RigidBodyHandle, usize>,
    collider_nodes: HandleMap<ColliderHandle, usize>,
    pairs: Vec<Pair>,
    /// Per node: the indices of its pairs.
    pairs_of: Vec<Vec<usize>>,
    /// The pairs' next times of impact (none: none before the step's end,
    /// or touching without closing, until either body's path changes).
    queue: Queue,
    /// Scratch of `resolve`: the pairs whose times an impact changes.
    stale: Vec<usize>,
    /// The instant's work left for its end (see [`Instant`]).
    instant: Instant,
    manifolds: Vec<ContactManifold<(), ()>>,
    /// Scratch of the sweeps.
    met: Vec<ColliderHandle>,
}

impl std::fmt::Debug for RigidReplay {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RigidReplay")
            .field("starts", &self.starts.len())
            .finish_non_exhaustive()
    }
}

impl RigidReplay {
    /// Before rapier's step: forget the last step's claims and, in impulse
    /// and exact mode, store where the bodies of the moving rigid
    /// colliders `rigid` start the step (pose and orientation).
    pub(crate) fn begin(
        &mut self,
        policy: Policy,
        rigid: &[ColliderHandle],
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) {
        self.claims.clear();
        self.starts.clear();
        if !policy.replays_rigid() {
            return;
        }
        for &ch in rigid {
            if let Some(h) = colliders.get(ch).and_then(|co| co.parent())
                && let Some(rb) = bodies.get(h)
            {
                self.starts.push((h, *rb.position()));
            }
        }
        self.starts
            .sort_unstable_by_key(|(h, _)| h.into_raw_parts());
        self.starts.dedup_by_key(|(h, _)| *h);
    }

    /// The start pose stored for body `h`.
    fn start_of(&self, h: RigidBodyHandle) -> Option<Pose> {
        let key = h.into_raw_parts();
        self.starts
            .binary_search_by_key(&key, |(h, _)| h.into_raw_parts())
            .ok()
            .map(|i| self.starts[i].1)
    }

    /// After rapier's step (impulse and exact mode): resolve the claimed
    /// pairs, and in exact mode those the sweeps of the moving rigid bodies
    /// find, at their times of impact in time order, and write the bent
    /// bodies back.
    pub(crate) fn run(&mut self, input: &RigidInput, out: &mut ReplayOutput, sets: ReplaySets) {
        let ReplaySets {
            bodies,
            colliders,
            narrow_phase,
            broad_phase,
        } = sets;
        self.claims.collect();
        self.nodes.clear();
        self.body_nodes.clear();
        self.collider_nodes.clear();
        self.pairs.clear();
        self.queue.clear();
        for pairs in &mut self.pairs_of {
            pairs.clear();
        }
        let dt = input.frame.dt;
        if dt.is_nan() || dt <= 0.0 {
            return;
        }
        let world = World {
            bodies,
            colliders,
            narrow_phase,
            broad_phase,
        };
        let claimed = std::mem::take(&mut self.claims);
        for &(c1, c2) in claimed.sorted() {
            self.add_pair(input, bodies, colliders, c1, c2);
        }
        self.claims = claimed;
        for &ch in input.rigid {
            self.sweep_start(input, world, ch);
        }
        for i in 0..self.pairs.len() {
            let toi = self.time_of_impact(colliders, i, 0.0, dt);
            self.queue.set(i, toi);
        }
        self.resolve(input, out, world);
        for n in 0..self.nodes.len() {
            let node = &self.nodes[n];
            let Key::Body(h) = node.key else { continue };
            if !(node.hit || node.off_rapier) {
                continue;
            }
            let pose = node.motion.pose_at(dt);
            let Some(rb) = bodies.get_mut(h) else {
                continue;
            };
            if pose.is_finite()
                && node.u.is_finite()
                && motion::angular_speed(node.omega).is_finite()
            {
                write_back(rb, pose, node.u, node.omega);
                out.woken.push(h);
            }
        }
    }

    /// The events, earliest first, until no pair meets before the step's
    /// end (or the event cap).
    fn resolve(&mut self, input: &RigidInput, out: &mut ReplayOutput, world: World) {
        let colliders = world.colliders;
        let bodies = world.bodies;
        let dt = input.frame.dt;
        let max_events = input.config.max_events_per_step;
        let mut events = 0usize;
        self.instant.clear();
        loop {
            let next = self.queue.next();
            if self.instant.pending() && next.is_none_or(|(t, _)| t != self.instant.at) {
                self.finish_instant(input, world);
                continue;
            }
            let Some((t, i)) = next else { break };
            if events >= max_events {
                out.log.cap_hit();
                log::warn!(
                    "kimpact: more than {max_events} rigid impacts in one step; the rest is left to rapier"
                );
                break;
            }
            let bent = match self.impact(input, out, bodies, colliders, i, t) {
                Ok(bent) => bent,
                // Idle until either body's path changes, unless the pair
                // meets again within the step, which counts towards the
                // cap: after a parting touch, a spinning die's next corner;
                // after a held one, the contact its manifold lists striking
                // from farther (a rocking box's other corner).
                Err(idle) => {
                    let again = match idle {
                        Idle::Parting => self.reentry(input, colliders, i, t),
                        Idle::Held => self.strikes_later(input, colliders, i, t),
                        Idle::Other => None,
                    };
                    events += usize::from(again.is_some());
                    self.queue.set(i, again);
                    continue;
                }
            };
            events += 1;
            // Only a body the impact bent has a new path: the pairs of an
            // immovable or dominant partner (a floor under a pile) keep
            // their times.
            let (a, b) = (self.pairs[i].a, self.pairs[i].b);
            let changed = |n: usize| (n == a && bent[0]) || (n == b && bent[1]);
            self.instant.at = t;
            let mut stale = std::mem::take(&mut self.stale);
            stale.clear();
            for n in [a, b] {
                if changed(n) {
                    stale.extend(self.pairs_of[n].iter().copied());
                    self.instant.bent.push(n);
                }
            }
            stale.sort_unstable();
            stale.dedup();
            for &j in &stale {
                self.restart(colliders, j, t, dt);
            }
            self.stale = stale;
        }
    }

    /// Pair `j` after an impact at `t` bent either body's path: if it
    /// touches at `t` it meets then (its patch decides); if it is apart
    /// it cannot meet at `t`, and its search waits for the instant's end,
    /// along the paths every impact of the instant left ([`Instant`]). A
    /// pair that is not two convex shapes, or one touching at the step's
    /// start (whose search may rewind it), is searched now.
    fn restart(&mut self, colliders: &ColliderSet, j: usize, t: Real, dt: Real) {
        let touching = match self.instant.touching.get(j) {
            Some(&(at, touching)) if at == t => Some(touching),
            _ => self.on_movers(colliders, j, |a, b, tolerance, _| {
                toi::touching_at(a, b, t, tolerance)
            }),
        };
        match touching {
            Some(false) => {
                self.queue.set(j, None);
                self.instant.deferred.push(j);
            }
            Some(true) if Rewind::at(t) == Rewind::Never => self.queue.set(j, Some(t)),
            _ => {
                let toi = self.time_of_impact(colliders, j, t, dt);
                self.queue.set(j, toi);
            }
        }
        if let Some(touching) = touching {
            if self.instant.touching.len() <= j {
                self.instant.touching.resize(j + 1, (Real::NAN, false));
            }
            self.instant.touching[j] = (t, touching);
        }
    }

    /// The end of an instant at which impacts bent paths: the pairs apart
    /// then searched along the paths they left, and the bent bodies'
    /// neighbours brought in.
    fn finish_instant(&mut self, input: &RigidInput, world: World) {
        let (t, dt) = (self.instant.at, input.frame.dt);
        let mut deferred = std::mem::take(&mut self.instant.deferred);
        deferred.sort_unstable();
        deferred.dedup();
        for &j in &deferred {
            let toi = self.time_of_impact(world.colliders, j, t, dt);
            self.queue.set(j, toi);
        }
        deferred.clear();
        self.instant.deferred = deferred;
        let mut bent = std::mem::take(&mut self.instant.bent);
        bent.sort_unstable();
        bent.dedup();
        for &n in &bent {
            self.expand(input, world, n, t);
        }
        bent.clear();
        self.instant.bent = bent;
    }

    /// The law's body of node `n` at time `t` with mass `mass`.
    fn law_rigid(
        &self,
        n: usize,
        mass: kimpact::Mass<Real>,
        t: Real,
        dt: Real,
    ) -> Option<LawRigid> {
        let node = &self.nodes[n];
        let v = crate::math::to_law(node.law_velocity(t, dt));
        let w = motion::to_law_angular(node.omega);
        match mass {
            // The world inverse inertia of the end of the step, where the
            // body's angular velocity (rapier's end-of-step one plus the
            // changes) is written back: the kinetic energy rapier then
            // holds changes by exactly the law's `−d`. (At the orientation
            // of the instant it would not for a body whose inertia differs
            // between axes: 2e-9 of a spinning capsule's energy.)
            kimpact::Mass::Finite(m) => LawRigid::new(m, v, w, node.inverse_inertia).ok(),
            kimpact::Mass::Infinite => LawRigid::immovable(v, w).ok(),
        }
    }
}

/// Give body `rb` the pose `pose`, the velocity `v` and the angular
/// velocity `w`, the law's outcome at the inertia of rapier's end pose. At
/// `pose` (where the replay's bent path ends, turned from rapier's end) a
/// body whose inertia differs between axes has another rotational energy at
/// `w`: `w` is scaled to keep the law's (a change of the order of the turn
/// times the anisotropy, 1e-9 of a spinning capsule's energy; none for a
/// body whose inertia is the same about every axis, nor in 2D).
fn write_back(rb: &mut RigidBody, pose: Pose, v: Vector, w: AngVector) {
    rb.set_linvel(v, true);
    rb.set_angvel(w, true);
    let rotational =
        |rb: &RigidBody| rb.kinetic_energy() - 0.5 * rb.mass() * rb.linvel().length_squared();
    let kept = rotational(rb);
    rb.set_position(pose, true);
    let now = rotational(rb);
    if now > 0.0 && kept >= 0.0 && (now - kept).abs() > 0.0 {
        let scale = (kept / now).sqrt();
        if scale.is_finite() {
            rb.set_angvel(w * scale, true);
        }
    }
}
