//! What the replay is made of: its nodes (a body as a rigid state on a
//! piecewise-linear path, or a collider without a body), its pairs, and the
//! hit a pair's cast finds.

use kimpact::Mass;

use crate::math::{DIM, Pose, Real, Vector};
use crate::rapier::prelude::*;

/// No pair: the end of a node's list of pairs.
pub(super) const NO_PAIR: u32 = u32::MAX;

/// The law's angular velocity in this dimension.
pub(super) type LawAngular = kimpact::Angular<Real, DIM>;

/// The law's world inverse inertia in this dimension.
pub(super) type LawInverseInertia = kimpact::InverseInertia<Real, DIM>;

/// What a node of the replay stands for.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub(super) enum Key {
    Body(RigidBodyHandle),
    /// A collider without a body (static geometry).
    Collider(ColliderHandle),
}

impl Key {
    /// The body it stands for, if any.
    pub(super) fn body(self) -> Option<RigidBodyHandle> {
        match self {
            Key::Body(h) => Some(h),
            Key::Collider(_) => None,
        }
    }
}

/// How the law takes a node's body.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Motion {
    /// A dynamic body whose translations are free: the law moves it.
    Moves,
    /// A dynamic body with some translations locked and others free: the
    /// law, which takes one mass for every direction, leaves its pairs to
    /// rapier.
    PartlyLocked,
    /// A fixed or kinematic body, a dynamic one with every translation
    /// locked, or a collider without a body: immovable to the law.
    Immovable,
}

/// A body of the replay as a rigid state at the instant its path last
/// bent ([`Node::t_ref`]).
#[derive(Copy, Clone, Debug)]
pub(super) struct RigidState {
    /// Its pose at `t_ref`: the translation is the path's point there; the
    /// rotation is the body's at the end of rapier's step (the replay
    /// moves balls centred on their bodies, whose shape does not depend on
    /// it, and partners that the law does not turn).
    pub pose: Pose,
    /// The linear velocity the law sees (`v_rapier + ΣΔv`). It differs
    /// from the path velocity ([`Node::v`]) when rapier's solver pushed the
    /// body this step (position correction), so that the law conserves the
    /// energy of the velocities the bodies really have.
    pub linvel: Vector,
    /// The angular velocity the law sees: rapier's at the step's end plus
    /// the changes so far.
    pub angvel: LawAngular,
    /// The inverse mass as rapier keeps it (zero for a node that is not
    /// dynamic).
    pub inv_mass: Real,
    /// The world inverse inertia as rapier's solver uses it (locked
    /// rotations zero).
    pub inv_inertia: LawInverseInertia,
}

/// A body on a piecewise-linear path: at `t_ref` it is at
/// `body.pose.translation`, moving at `v`.
#[derive(Copy, Clone, Debug)]
pub(super) struct Node {
    pub key: Key,
    pub motion: Motion,
    /// Position at the end of rapier's step.
    pub x1: Vector,
    /// The body's rigid state at `t_ref`.
    pub body: RigidState,
    /// Path velocity: moves the body (`v̄ + ΣΔv`).
    pub v: Vector,
    pub t_ref: Real,
    /// What gravity adds to the body's velocity over the step (`g s dt`,
    /// with its gravity scale `s`; zero for non-dynamic bodies).
    pub g_dt: Vector,
    /// Gravity over half the body's substep (`g s h / 2`, see
    /// [`crate::frame::StepFrame::half_substep`]; zero for non-dynamic
    /// bodies): what separates rapier's velocity from the velocity of the
    /// parabola its substeps put the body on.
    pub g_half: Vector,
    /// Whether its touching neighbours were brought into the run.
    pub expanded: bool,
    /// Whether the law bent its path this run.
    pub hit: bool,
    /// The last box swept for one of the node's colliders this run: a later
    /// sweep of that collider inside it would find nothing new (a ball
    /// bouncing back along its path in a pile).
    pub swept: Option<(ColliderHandle, Aabb)>,
    /// The collider of the node last put in the replay's list of bent
    /// paths (`None` once swept).
    pub sweep_due: Option<ColliderHandle>,
    /// The body's dominance group (rapier's; 0 unless it moves).
    pub dominance: i8,
    /// What the changes of its angular velocity so far add to its
    /// orientation by the step's end (`Σ Δω (dt − t)`, a rotation vector).
    pub turn: LawAngular,
    /// Whether an impact changed its angular velocity.
    pub turned: bool,
}

impl Node {
    /// Whether the law may move it (a dynamic body, translations free or
    /// partly locked).
    pub(super) fn dynamic(&self) -> bool {
        self.motion != Motion::Immovable
    }

    /// Where it is at time `t`.
    pub(super) fn at(&self, t: Real) -> Vector {
        self.body.pose.translation + self.v * (t - self.t_ref)
    }

    /// The mass the law takes it with: `None` for a body with some
    /// translations locked (the pair is rapier's).
    pub(super) fn law_mass(&self) -> Option<Mass<Real>> {
        match self.motion {
            Motion::Moves => Some(Mass::Finite(inverse(self.body.inv_mass))),
            Motion::PartlyLocked => None,
            Motion::Immovable => Some(Mass::Infinite),
        }
    }

    /// The velocity the law meets the body with at time `t`: the velocity,
    /// at `t`, of the parabola rapier's substeps put the body on (rapier's
    /// velocity plus gravity over half a substep, [`Node::g_half`]). After
    /// the step, `body.linvel` is the velocity at its end: the law meets
    /// the bodies at `t`, before gravity's share of the rest of the step
    /// (which they keep afterwards).
    ///
    /// Between two bodies under the same gravity the offsets cancel (the
    /// law conserves momentum); against a fixed partner they are what
    /// keeps a bounce elastic: rapier's integrator conserves
    /// `½ m |v + g h/2|² − m g·x` in free flight, so a law that reversed `v`
    /// itself would change the next flight's energy by `m h g·Δv / 2`
    /// (a lower apex at every bounce).
    pub(super) fn law_velocity(&self, t: Real, dt: Real) -> Vector {
        self.body.linvel - self.g_dt * ((dt - t) / dt) + self.g_half
    }

    /// The path bends at `t` by `dv`.
    pub(super) fn bend(&mut self, t: Real, dv: Vector) {
        self.body.pose.translation = self.at(t);
        self.t_ref = t;
        self.v += dv;
        self.body.linvel += dv;
    }

    /// The angular velocity changes by `delta` at time `t` of a step of
    /// `dt`.
    pub(super) fn turn_by(&mut self, delta: &LawAngular, t: Real, dt: Real) {
        self.body.angvel += *delta;
        self.turn += *delta * (dt - t);
        self.turned = true;
    }

    /// The box a ball riding the node's path sweeps from `from` to `to`:
    /// its centre (`ball.1` off the path) ± its radius `ball.0`, as parry's,
    /// with the start moved by `lag` (how far the sweeps' frame moves from
    /// `from` to `to`: see [`StepFrame::lag`](crate::frame::StepFrame::lag)).
    pub(super) fn swept_ball(
        &self,
        (radius, offset): BallOnPath,
        (from, to): (Real, Real),
        lag: Vector,
    ) -> Aabb {
        let r = Vector::splat(radius);
        let (start, end) = (self.at(from) + offset + lag, self.at(to) + offset);
        Aabb::new(start.min(end) - r, start.max(end) + r)
    }

    /// `rest`, the pose of one of the node's colliders where the node is
    /// now (`x1`), carried along the node's path to time `t`.
    pub(super) fn moved(&self, rest: Pose, t: Real) -> Pose {
        let mut pose = rest;
        pose.translation += self.at(t) - self.x1;
        pose
    }
}

/// `1 / x`, and 0 for 0: how rapier reads a mass from its inverse (so the
/// mass the law takes is rapier's `RigidBody::mass`, bit for bit).
fn inverse(x: Real) -> Real {
    if x == 0.0 { 0.0 } else { 1.0 / x }
}

/// A ball riding a node's path: its radius, and where its centre sits
/// relative to the path (`centre(t) = node.at(t) + offset`).
pub(super) type BallOnPath = (Real, Vector);

/// Where a pair meets: the first contact its cast finds.
#[derive(Copy, Clone, Debug)]
pub(super) struct Hit {
    /// When, within the step (negative: rewound into the previous one).
    pub time: Real,
    /// The world contact point on the first collider, in its pose at the
    /// start of the cast.
    pub point: Vector,
    /// The world unit normal from the first collider towards the second.
    pub normal: Vector,
    /// The contact's arm on each body at `time`: from where the body is
    /// then to the contact (a ball: its radius along the normal).
    pub arms: [Vector; 2],
}

impl Hit {
    /// No meeting found yet.
    pub(super) const NONE: Hit = Hit {
        time: Real::NAN,
        point: Vector::ZERO,
        normal: Vector::ZERO,
        arms: [Vector::ZERO; 2],
    };
}

/// Two colliders the replay follows, on nodes `a` and `b`.
#[derive(Copy, Clone, Debug)]
pub(super) struct Pair {
    pub a: usize,
    pub b: usize,
    pub c1: ColliderHandle,
    pub c2: ColliderHandle,
    /// Two balls: their radii and where their centres sit relative to
    /// their nodes' paths (`centre(t) = node.at(t) + offset`), so that a
    /// cast of the pair reads neither collider nor body. `None` for any
    /// other pair of shapes.
    pub balls: Option<[BallOnPath; 2]>,
    /// The queued meeting.
    pub hit: Hit,
    /// The instant at which the pair, two balls apart then, waits to be
    /// predicted (see `Replay::defer_if_apart`); −∞ when it does not.
    pub apart_at: Real,
    /// Whether the law has struck the pair in this run (see
    /// `ResolverConfig::rebound_cutoff`).
    pub struck: bool,
    /// The next pair of node `a`'s list and of node `b`'s (`NO_PAIR` at the
    /// end; see `Replay::ends`).
    pub next: [u32; 2],
}

impl Pair {
    /// Which of [`Pair::next`] threads node `n`'s list (`n` is `a` or `b`).
    pub(super) fn side(&self, n: usize) -> usize {
        usize::from(self.a != n)
    }

    /// Its colliders, in order.
    pub(super) fn colliders(&self) -> [ColliderHandle; 2] {
        [self.c1, self.c2]
    }
}

/// A collider the replay sweeps along its node's path this run.
#[derive(Copy, Clone, Debug)]
pub(super) struct Sweeper {
    pub collider: ColliderHandle,
    pub node: usize,
    /// The box it sweeps.
    pub aabb: Aabb,
    /// Its radius and centre offset if it is a ball (see [`Pair::balls`]).
    pub ball: Option<BallOnPath>,
}

/// A body's or collider's node in the current run.
#[derive(Copy, Clone, Debug, Default)]
pub(super) struct Slot {
    /// The run that wrote it (0: never).
    pub stamp: u32,
    pub node: u32,
}
