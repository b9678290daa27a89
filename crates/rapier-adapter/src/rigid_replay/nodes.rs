//! The rigid replay's nodes and pairs: which bodies and colliders take
//! part, their motions, and the pairs the claims, the sweeps and the
//! neighbours of bent bodies bring in.

use crate::body_view::translations_locked;
use crate::cast::Rewind;
use crate::math::{Real, Vector};
use crate::policy::RigidSweep;
use crate::rapier::parry::query::ContactManifold;
use crate::rapier::prelude::*;
use crate::rigid_view::inverse_inertia;

use super::motion::Motion;
use super::toi::{Mover, apart_for_narrow_phase, time_of_impact};
use super::{Key, Node, Pair, RigidInput, RigidReplay, World, toi_share};

/// Where a sweep along a body's path starts.
#[derive(Copy, Clone, Debug)]
enum SweepFrom {
    /// The step's start, before any impact: only the pairs rapier's solver
    /// did not touch this step come in (those it touched are rapier's),
    /// their times of impact found afterwards with every other pair's.
    Start,
    /// An impact at this time bent the path: every pair the rest of the
    /// path reaches comes in, with its time of impact.
    Impact(Real),
}

impl RigidReplay {
    /// The node of collider `ch` (its body's, or its own without a body),
    /// made on first use.
    fn node(
        &mut self,
        input: &RigidInput,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        ch: ColliderHandle,
    ) -> Option<usize> {
        let co = colliders.get(ch)?;
        if let Some(n) = self.node_of(co, ch) {
            return Some(n);
        }
        let key = match co.parent() {
            Some(h) => Key::Body(h),
            None => Key::Collider(ch),
        };
        let node = match key {
            Key::Collider(_) => Node {
                key,
                dynamic: false,
                motion: Motion::still(*co.position()),
                u: Vector::ZERO,
                omega: super::motion::zero_angvel(),
                g_dt: Vector::ZERO,
                g_half: Vector::ZERO,
                inverse_inertia: Default::default(),
                hit: false,
                off_rapier: false,
            },
            Key::Body(h) => {
                let rb = bodies.get(h)?;
                self.body_node(input, h, rb)
            }
        };
        let n = self.nodes.len();
        self.nodes.push(node);
        if self.pairs_of.len() <= n {
            self.pairs_of.push(Vec::new());
        }
        match key {
            Key::Body(h) => self.body_nodes.insert(h, n),
            Key::Collider(ch) => self.collider_nodes.insert(ch, n),
        }
        Some(n)
    }

    /// The node collider `ch` (`co`) rides, if the run has made it.
    fn node_of(&self, co: &Collider, ch: ColliderHandle) -> Option<usize> {
        match co.parent() {
            Some(h) => self.body_nodes.get(h),
            None => self.collider_nodes.get(ch),
        }
        .copied()
    }

    /// The node of body `h` (`rb`): its motion over the step from its
    /// start (stored by `begin`; a translation in `Prepare::starts`, turned
    /// back by its angular velocity; else its end carried back along its
    /// velocities) to its end.
    fn body_node(&self, input: &RigidInput, h: RigidBodyHandle, rb: &RigidBody) -> Node {
        let dt = input.frame.dt;
        let end = *rb.position();
        let com = rb.local_center_of_mass();
        let back = Motion {
            pose: end,
            local_com: com,
            linvel: rb.linvel(),
            angvel: rb.angvel(),
            t_ref: dt,
        };
        let start = self.start_of(h).or_else(|| {
            let translation = input.starts.of(h).filter(|_| rb.is_dynamic())?;
            let mut pose = back.pose_at(0.0);
            pose.translation = translation;
            Some(pose)
        });
        let falls = rb.is_dynamic() && !translations_locked(rb);
        let g = if falls {
            input.frame.gravity * rb.gravity_scale()
        } else {
            Vector::ZERO
        };
        let g_half = g * input.frame.half_substep(rb);
        // rapier's CCD stops a fast body short at a fixed collider (every
        // fast body sweeps those), without a response: its chord then ends
        // at rapier's time of impact, slower than the body, and the law
        // would meet that collider late (as the ball replay,
        // `moving_node`). Such a body's path is its velocities' from its
        // start: the chord rapier's substeps give a free body,
        // `v − g dt/2 + g h/2`, turning at its angular velocity.
        let chord = rb.linvel() - g * (0.5 * dt) + g_half;
        let stopped = start
            .filter(|start| rb.is_ccd_active() && cut_short(end * com - *start * com, chord * dt));
        let motion = match (stopped, start) {
            (Some(start), _) => Motion {
                pose: start,
                local_com: com,
                linvel: chord,
                angvel: rb.angvel(),
                t_ref: 0.0,
            },
            (None, Some(start)) => Motion::between(start, end, com, rb.angvel(), dt),
            (None, None) => back,
        };
        Node {
            key: Key::Body(h),
            dynamic: rb.is_dynamic(),
            motion,
            u: rb.linvel(),
            omega: rb.angvel(),
            g_dt: g * dt,
            g_half,
            inverse_inertia: inverse_inertia(rb),
            hit: false,
            // Exact mode sweeps every moving rigid body along its path:
            // what rapier's CCD stopped it for, the replay has met.
            off_rapier: stopped.is_some() && input.policy.rigid_sweep == RigidSweep::Every,
        }
    }

    /// Bring the pair `c1`, `c2` into the replay (once); its index.
    pub(super) fn add_pair(
        &mut self,
        input: &RigidInput,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> Option<usize> {
        if c1 == c2 {
            return None;
        }
        let a = self.node(input, bodies, colliders, c1)?;
        let b = self.node(input, bodies, colliders, c2)?;
        if a == b || self.paired(a, b, c1, c2) {
            return None;
        }
        let i = self.pairs.len();
        self.pairs.push(Pair { a, b, c1, c2 });
        self.pairs_of[a].push(i);
        self.pairs_of[b].push(i);
        Some(i)
    }

    /// Whether colliders `c1` (on node `a`) and `c2` (on node `b`) are a
    /// pair of the replay already: read from the shorter of the two nodes'
    /// lists (a domino's few pairs, not those of the floor under it).
    fn paired(&self, a: usize, b: usize, c1: ColliderHandle, c2: ColliderHandle) -> bool {
        let (of_a, of_b) = (&self.pairs_of[a], &self.pairs_of[b]);
        let shorter = if of_a.len() <= of_b.len() { of_a } else { of_b };
        shorter.iter().any(|&i| {
            let p = &self.pairs[i];
            (p.c1 == c1 && p.c2 == c2) || (p.c1 == c2 && p.c2 == c1)
        })
    }

    /// Collider `ch` on node `n` riding the node's path.
    pub(super) fn mover<'a>(
        &'a self,
        colliders: &'a ColliderSet,
        n: usize,
        ch: ColliderHandle,
    ) -> Option<Mover<'a>> {
        let co = colliders.get(ch)?;
        let node = &self.nodes[n];
        let offset = match node.key {
            Key::Body(_) => Some(co.position_wrt_parent().copied().unwrap_or_default()),
            Key::Collider(_) => None,
        };
        let sphere = co.shape().compute_local_bounding_sphere();
        let centre = offset.map_or(sphere.center(), |o| o * sphere.center());
        let reach = (centre - node.motion.local_com).length() + sphere.radius();
        Some(Mover {
            motion: &node.motion,
            offset,
            shape: co.shape(),
            reach,
        })
    }

    /// The time-of-impact tolerance of pair `i`: [`toi_share`] of the
    /// smaller collider's bounding radius.
    pub(super) fn tolerance(&self, colliders: &ColliderSet, i: usize) -> Real {
        let p = &self.pairs[i];
        pair_tolerance(colliders, p.c1, p.c2)
    }

    /// Pair `i`'s first time of impact in `[from, to]` (rewound into the
    /// previous step if it overlaps at `from` = 0, see
    /// [`time_of_impact`]).
    pub(super) fn time_of_impact(
        &mut self,
        colliders: &ColliderSet,
        i: usize,
        from: Real,
        to: Real,
    ) -> Option<Real> {
        self.on_movers(colliders, i, |a, b, tolerance, manifolds| {
            time_of_impact(a, b, from, to, tolerance, Rewind::at(from), manifolds)
        })
    }

    /// `f` of pair `i`'s two colliders riding their paths, its tolerance
    /// and the run's scratch manifolds; `None` when a collider is gone.
    pub(super) fn on_movers<T>(
        &mut self,
        colliders: &ColliderSet,
        i: usize,
        f: impl FnOnce(&Mover, &Mover, Real, &mut Vec<ContactManifold<(), ()>>) -> Option<T>,
    ) -> Option<T> {
        let p = self.pairs[i];
        let tolerance = self.tolerance(colliders, i);
        let mut manifolds = std::mem::take(&mut self.manifolds);
        let out = match (
            self.mover(colliders, p.a, p.c1),
            self.mover(colliders, p.b, p.c2),
        ) {
            (Some(a), Some(b)) => f(&a, &b, tolerance, &mut manifolds),
            _ => None,
        };
        self.manifolds = manifolds;
        out
    }

    /// Before any impact, in exact mode, and in impulse mode for a body
    /// that falls (moves along gravity: a landing rapier's contacts did
    /// not see coming is then resolved at its time, not rewound from an
    /// overlap): the pairs moving rigid collider `ch`'s path over the step
    /// reaches that rapier's solver did not touch this step (pairs with
    /// solver contacts are rapier's).
    pub(super) fn sweep_start(&mut self, input: &RigidInput, world: World, ch: ColliderHandle) {
        let Some(n) = self.node(input, world.bodies, world.colliders, ch) else {
            return;
        };
        let falls = self.nodes[n].motion.linvel.dot(input.frame.gravity) > 0.0;
        let swept = match input.policy.rigid_sweep {
            RigidSweep::Every => true,
            RigidSweep::Falling => falls,
            RigidSweep::Nobody => false,
        };
        if swept {
            self.sweep(input, world, n, ch, SweepFrom::Start);
        }
    }

    /// After an impact bent node `n`'s path at `t`: its colliders' rapier
    /// contact pairs (touching or within rapier's prediction) and what
    /// their sweep along the new path reaches, if the law governs them as
    /// rigid pairs.
    pub(super) fn expand(&mut self, input: &RigidInput, world: World, n: usize, t: Real) {
        let World {
            bodies,
            colliders,
            narrow_phase,
            ..
        } = world;
        let Key::Body(h) = self.nodes[n].key else {
            return;
        };
        let Some(rb) = bodies.get(h) else { return };
        let fixed = input.policy.partners;
        for &ch in rb.colliders() {
            for cp in narrow_phase.contact_pairs_with(ch) {
                let (c1, c2) = (cp.collider1, cp.collider2);
                if input.marks.governs_rigid(fixed, colliders, bodies, c1, c2)
                    && let Some(i) = self.add_pair(input, bodies, colliders, c1, c2)
                {
                    let toi = self.time_of_impact(colliders, i, t, input.frame.dt);
                    self.queue.set(i, toi);
                }
            }
            self.sweep(input, world, n, ch, SweepFrom::Impact(t));
        }
    }

    /// Whether the start sweep of node `n` can leave out contact pair `cp`
    /// of one of its colliders: rapier's narrow phase found no contact
    /// within its prediction distance at the step's start, and the two
    /// cannot close that far within the step (see
    /// [`apart_for_narrow_phase`]): the pair's time of impact would be
    /// none. A box whose broad-phase box overlaps a leaning domino's, or a
    /// resting neighbour's, costs no search.
    fn stays_apart(
        &mut self,
        input: &RigidInput,
        world: World,
        cp: &ContactPair,
        (n, ch): (usize, ColliderHandle),
    ) -> bool {
        if cp.manifolds().iter().any(|m| !m.points.is_empty()) {
            return false;
        }
        let colliders = world.colliders;
        let other = if cp.collider1 == ch {
            cp.collider2
        } else {
            cp.collider1
        };
        let Some(m) = self.node(input, world.bodies, colliders, other) else {
            return false;
        };
        let (Some(a), Some(b)) = (
            self.mover(colliders, n, ch),
            self.mover(colliders, m, other),
        ) else {
            return false;
        };
        let tolerance = pair_tolerance(colliders, ch, other);
        apart_for_narrow_phase(
            &a,
            &b,
            0.0,
            input.frame.dt,
            tolerance,
            input.frame.prediction,
        )
    }

    /// Sweep collider `ch` of node `n` along its path from `when` to the
    /// step's end: every collider whose broad-phase box meets the swept box
    /// and that the law governs as a rigid pair with it (and rapier would
    /// let touch) comes into the replay; after an impact also those
    /// rapier's solver touched this step, with their times of impact.
    fn sweep(
        &mut self,
        input: &RigidInput,
        world: World,
        n: usize,
        ch: ColliderHandle,
        when: SweepFrom,
    ) {
        let World {
            bodies,
            colliders,
            narrow_phase,
            broad_phase,
        } = world;
        let (t, all) = match when {
            SweepFrom::Start => (0.0, false),
            SweepFrom::Impact(t) => (t, true),
        };
        let dt = input.frame.dt;
        let Some(co) = colliders.get(ch) else { return };
        let Some(mover) = self.mover(colliders, n, ch) else {
            return;
        };
        let (p0, p1) = (mover.pose_at(t), mover.pose_at(dt));
        let mut swept = co
            .shape()
            .compute_aabb(&p0)
            .merged(&co.shape().compute_aabb(&p1));
        // A turning body bulges out of its two boxes by at most its reach
        // times the turn.
        let turn = mover.motion.turn_speed(1.0) * (dt - t);
        swept = swept.loosened(mover.reach * turn.min(2.0) + input.frame.prediction);
        let near = !all && stays_near(&mover, co, (t, dt), input.frame.prediction);
        let mut met = std::mem::take(&mut self.met);
        met.clear();
        if near {
            // Rapier's broad phase paired it with every collider within its
            // prediction distance: nothing else is within its reach. Those
            // whose boxes meet the swept box, as the broad phase's query
            // would give them.
            let other = |cp: &ContactPair| {
                if cp.collider1 == ch {
                    cp.collider2
                } else {
                    cp.collider1
                }
            };
            let meets = |oh: &ColliderHandle| {
                colliders
                    .get(*oh)
                    .is_some_and(|oc| oc.compute_aabb().intersects(&swept))
            };
            met.extend(narrow_phase.contact_pairs_with(ch).map(other).filter(meets));
        } else {
            let dispatcher = crate::rapier::parry::query::DefaultQueryDispatcher;
            let query = broad_phase.as_query_pipeline(
                &dispatcher,
                bodies,
                colliders,
                QueryFilter::default(),
            );
            met.extend(
                query
                    .intersect_aabb_conservative(swept)
                    .map(|(other, _)| other),
            );
        }
        met.sort_unstable_by_key(|h| h.into_raw_parts());
        let fixed = input.policy.partners;
        for &other in &met {
            let Some(oc) = colliders.get(other) else {
                continue;
            };
            // A pair the run holds already (or a collider of the same
            // body) adds nothing.
            let known = |m: usize| m == n || self.paired(n, m, ch, other);
            if other == ch || self.node_of(oc, other).is_some_and(known) {
                continue;
            }
            // Before any impact, a pair rapier's solver touches is rapier's
            // (the most common: a resting neighbour, the floor).
            let contact = (!all)
                .then(|| narrow_phase.contact_pair(ch, other))
                .flatten();
            if contact.is_some_and(|cp| cp.has_any_active_contact())
                || !input
                    .marks
                    .governs_rigid(fixed, colliders, bodies, ch, other)
                || !input
                    .filter
                    .admits(bodies, colliders, [(ch, co), (other, oc)], true)
                || contact.is_some_and(|cp| self.stays_apart(input, world, cp, (n, ch)))
            {
                continue;
            }
            if let Some(i) = self.add_pair(input, bodies, colliders, ch, other)
                && all
            {
                let toi = self.time_of_impact(colliders, i, t, dt);
                self.queue.set(i, toi);
            }
        }
        self.met = met;
    }
}

/// Whether collider `co` riding `mover` moves less over `[t, dt]`, at its
/// closing bound with the time-of-impact tolerance on both sides, than
/// rapier's prediction distance `prediction`: then every collider it can
/// reach by its own motion was within that distance at the step's start,
/// and rapier's broad phase made a contact pair of it (the start sweep
/// reads those instead of querying the broad phase). A partner's own
/// motion is its own sweep's, as with the swept box.
fn stays_near(mover: &Mover, co: &Collider, (t, dt): (Real, Real), prediction: Real) -> bool {
    let tolerance = toi_share() * co.shape().compute_local_bounding_sphere().radius();
    let moves = (mover.motion.linvel.length() + mover.motion.turn_speed(mover.reach)) * (dt - t);
    moves + 2.0 * tolerance < prediction
}

/// The time-of-impact tolerance of colliders `c1` and `c2`: [`toi_share`]
/// of the smaller one's bounding radius.
fn pair_tolerance(colliders: &ColliderSet, c1: ColliderHandle, c2: ColliderHandle) -> Real {
    let radius = |ch| {
        colliders.get(ch).map_or(Real::INFINITY, |co: &Collider| {
            co.shape().compute_local_bounding_sphere().radius()
        })
    };
    toi_share() * radius(c1).min(radius(c2))
}

/// Whether a body that moved by `moved` over the step, and would have
/// moved by `free` in free flight, was stopped short on its way: moved
/// along `free` (to a thousandth of its length) by less of it. A body
/// whose velocity rapier's solver changed moves off that line.
fn cut_short(moved: Vector, free: Vector) -> bool {
    let length2 = free.length_squared();
    if length2.is_nan() || length2 <= 0.0 {
        return false;
    }
    let share = moved.dot(free) / length2;
    let off = (moved - free * share).length_squared();
    share < 1.0 - 1e-3 && off <= 1e-6 * length2
}
