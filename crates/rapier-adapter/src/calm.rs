//! Calm neighbourhoods: which fast bodies can go without the contact hook
//! this step.
//!
//! A pair needs kimpact's hook only if it can be an impact: a fresh contact
//! closing faster than the rest speed. `prepare` flags a body faster than
//! half the rest speed, so that two unflagged bodies never close faster than
//! the rest speed. In a pile that creeps or falls as a whole, most bodies are
//! that fast while every neighbour moves with them (a 2D pile creeps long
//! after it has landed), and each hooked body costs rapier its contact
//! recycling.
//!
//! This test keeps the guarantee with relative velocities. Every governed
//! collider a fast body could touch this step is found from boxes: each
//! collider's box at the start of the step, grown by rapier's contact reach
//! (its skin and half the prediction distance) and by how far any of its
//! points can move this step (on the straight path of the body's velocity
//! and gravity, and the turn of its angular velocity), then swept over the
//! step. Two colliders whose boxes do not meet can neither be in contact at
//! the step's narrow phase nor come into contact during the step on the
//! paths rapier integrates (the velocities at the start of the step, as the
//! speed threshold assumes too). A fast
//! body is left unflagged ("calm") when every governed collider whose box
//! meets one of its own belongs to a body whose velocity differs from its by
//! at most the rest speed: such a pair is not an impact whatever its
//! contact, and a pair with a body that is not calm is hooked through that
//! body. The partners are the awake bodies (in a grid, joined cell by cell)
//! and every other governed collider in their region, found among the leaves
//! of rapier's broad-phase tree: fixed and kinematic colliders (at their
//! velocity), sleeping bodies (at rest), bodies woken since the last step.
//!
//! A body with a non-finite velocity or box is never calm, and makes its
//! neighbours not calm either, so that the hook's runtime guard sees its
//! pairs. Boxes much larger than the typical one (walls, a floor, a large
//! body) are tested one by one against the grid, and a large body is never
//! calm itself.
//!
//! The test is tried when at least `Calm::MIN_FAST` (256) bodies, and one in
//! eight awake bodies, are fast (a try reads every awake body), and
//! backs off (waits 1, 2, 4, ... up to 16 steps, or 64 when the pairs kept
//! are fewer than a tenth of the members) when a try leaves fewer
//! than one in eight fast bodies calm or keeps fewer pairs in contact reach
//! unhooked than a third of the members: what it saves is rapier's
//! recycling of such pairs, and in a gas, where contacts are rare, a try
//! costs more than it saves (the bench's `--no-calm` measures the test
//! against none).
//!
//! Limit: a collider the user moved (teleported) since the last step, if
//! its body is fixed or asleep, is found where rapier's broad phase last saw
//! it (its tree leaf is updated inside the step).

use std::cmp::Ordering;

use crate::body_view::{path_velocity, translations_locked};
use crate::handle_map::HandleMap;
use crate::leaves::for_each_leaf;
use crate::marks::Marks;
use crate::math::{Real, Vector};
use crate::rapier::parry::bounding_volume::{Aabb, BoundingVolume};
use crate::rapier::parry::query::DefaultQueryDispatcher;
use crate::rapier::prelude::*;
use crate::sweep_grid::SweepGrid;

/// What the test reads of the world for one step.
pub(crate) struct Frame<'a> {
    pub bodies: &'a RigidBodySet,
    pub colliders: &'a ColliderSet,
    pub broad_phase: &'a BroadPhaseBvh,
    pub marks: &'a Marks,
    pub fixed_partners: bool,
    pub gravity: Vector,
    pub dt: Real,
    pub prediction: Real,
    /// The velocity of the frame the world shares this step
    /// ([`StepFrame::shared`](crate::frame::StepFrame::shared)), zero
    /// without one: the reach boxes sweep the motion against it.
    pub shared: Vector,
}

/// What a try found.
#[derive(Copy, Clone, Debug, Default)]
pub(crate) struct Judged {
    /// Fast dynamic bodies.
    pub fast: usize,
    /// Of which calm.
    pub calm: usize,
    /// Members (governed colliders of awake bodies).
    pub members: usize,
    /// Pairs of members of different bodies within contact reach at the
    /// start of the step (their contact boxes meet) and at most the rest
    /// speed apart: what rapier can recycle when neither is hooked.
    pub kept: usize,
}

/// One governed collider of an awake body.
#[derive(Copy, Clone, Debug)]
struct Member {
    /// Everywhere it can reach this step.
    aabb: Aabb,
    /// Its contact box at the start of the step.
    contact: Aabb,
    velocity: Vector,
    /// Its body's place in `Calm::taken`.
    body: u32,
}

/// An awake body the test looked at.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Taken {
    pub handle: RigidBodyHandle,
    /// Its members: `Calm::members[first..end]`.
    first: u32,
    end: u32,
    /// Faster than half the rest speed, and dynamic: flagged unless calm.
    pub fast: bool,
    /// Whether its members can be calm (none large, none non-finite).
    eligible: bool,
    /// Judged calm: fast, eligible, and no member closing on a partner
    /// faster than the rest speed.
    pub calm: bool,
}

/// When the test is tried next: what [`Calm`] carries from one step to the
/// next (its scratch space aside).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub(crate) struct CalmSchedule {
    /// Steps to wait before the next try (the test backs off where it does
    /// not pay: few calm bodies, or few pairs in contact reach among them,
    /// as in a gas).
    pub wait: u32,
    /// The last wait, doubled at each try that pays too little.
    pub backoff: u32,
    /// Fast bodies at the last `prepare`.
    pub last_fast: u32,
    /// Awake bodies at the last `prepare`.
    pub last_awake: u32,
}

/// The state and scratch space of the test; nothing is allocated in a
/// steady state.
#[derive(Default)]
pub(crate) struct Calm {
    /// When the test is tried next.
    pub schedule: CalmSchedule,
    scratch: Scratch,
}

#[derive(Default)]
struct Scratch {
    /// Per collider: the epoch at which it was a member or belonged to an
    /// awake body.
    stamp: HandleMap<ColliderHandle, u32>,
    epoch: u32,
    members: Vec<Member>,
    taken: Vec<Taken>,
    /// Fast dynamic bodies among `taken`.
    fast: usize,
    /// Per member: not found closing on a partner faster than the rest
    /// speed.
    calm: Vec<bool>,
    /// The grid's boxes: member index of each.
    in_grid: Vec<u32>,
    /// Boxes tested one by one: large members and the colliders that are
    /// not members (with their velocity, and their member index or
    /// `u32::MAX`).
    one_by_one: Vec<(Aabb, Vector, u32)>,
    grid: SweepGrid,
    region: Option<Aabb>,
    /// Scratch of the join on rayon's pool (`parallel`).
    #[cfg(feature = "parallel")]
    verdicts: Vec<Verdict>,
}

/// Whether two velocities are more than the rest speed apart (a NaN is
/// apart).
#[derive(Copy, Clone)]
struct Apart {
    /// The rest speed, squared.
    rest2: Real,
}

impl Apart {
    fn test(self, a: Vector, b: Vector) -> bool {
        !matches!(
            (a - b).length_squared().partial_cmp(&self.rest2),
            Some(Ordering::Less | Ordering::Equal)
        )
    }
}

impl Scratch {
    /// Members whose boxes are more than `Calm::BIG` times the mean size
    /// go to the boxes tested one by one (their bodies are never calm);
    /// the others into the grid.
    fn set_large_apart(&mut self) {
        let mut sum: f64 = 0.0;
        for m in &self.members {
            sum += f64::from((m.aabb.maxs - m.aabb.mins).max_element());
        }
        let mean = sum / self.members.len().max(1) as f64;
        // f64 → Real: a conversion in the f32 build only.
        #[allow(clippy::unnecessary_cast)]
        let cut = Calm::BIG * mean as Real;
        self.in_grid.clear();
        for (i, m) in self.members.iter().enumerate() {
            if (m.aabb.maxs - m.aabb.mins).max_element() > cut {
                // Never calm itself: its body is not eligible.
                self.taken[m.body as usize].eligible = false;
                self.one_by_one.push((m.aabb, m.velocity, i as u32));
            } else {
                self.in_grid.push(i as u32);
            }
        }
    }

    /// The other governed colliders in the members' region, to the boxes
    /// tested one by one.
    fn add_region_partners(&mut self, f: &Frame) {
        let Some(region) = self.region else {
            return;
        };
        let dispatcher = DefaultQueryDispatcher;
        let tree = f
            .broad_phase
            .as_query_pipeline(&dispatcher, f.bodies, f.colliders, QueryFilter::default())
            .bvh;
        let (stamp, epoch) = (&self.stamp, self.epoch);
        let one_by_one = &mut self.one_by_one;
        for_each_leaf(tree, |index, node| {
            // (The tree's leaves hold live colliders: the index is one's.)
            if stamp.get_by_index(index) == Some(&epoch) || !region.intersects(&node.aabb()) {
                return;
            }
            if let Some(other) = partner(f, index) {
                one_by_one.push(other);
            }
        });
    }

    /// The grid's members judged against each other: two of different
    /// bodies whose boxes meet are not calm if `apart`, a pair kept if in
    /// contact reach. The number of pairs kept; `None` when the boxes are
    /// not griddable.
    fn join_members(&mut self, apart: Apart) -> Option<usize> {
        let members = &self.members;
        let in_grid = &self.in_grid;
        let calm = &mut self.calm;
        if !self
            .grid
            .build(in_grid.iter().map(|&i| members[i as usize].aabb))
        {
            return None;
        }
        let mut kept = 0;
        // Two members whose boxes meet, judged.
        let verdict = |a: u32, b: u32| {
            let (i, j) = (in_grid[a as usize] as usize, in_grid[b as usize] as usize);
            let (p, q) = (&members[i], &members[j]);
            if p.body == q.body {
                None
            } else if apart.test(p.velocity, q.velocity) {
                Some(Verdict::Apart(i as u32, j as u32))
            } else if p.contact.intersects(&q.contact) {
                Some(Verdict::Kept)
            } else {
                None
            }
        };
        let mut apply = |v: Verdict| match v {
            Verdict::Apart(i, j) => {
                calm[i as usize] = false;
                calm[j as usize] = false;
            }
            Verdict::Kept => kept += 1,
        };
        #[cfg(not(feature = "parallel"))]
        self.grid
            .self_join(|a, b| verdict(a, b).into_iter().for_each(&mut apply));
        #[cfg(feature = "parallel")]
        {
            // Judged on rayon's pool; applied here (in any order: the
            // same flags and count).
            let mut verdicts = std::mem::take(&mut self.verdicts);
            verdicts.clear();
            self.grid.par_self_join(verdict, &mut verdicts);
            verdicts.iter().copied().for_each(&mut apply);
            self.verdicts = verdicts;
        }
        Some(kept)
    }

    /// The boxes tested one by one against the grid's members: a member of
    /// another body whose box meets one and whose velocity is `apart` is
    /// not calm.
    fn join_one_by_one(&mut self, apart: Apart) {
        let (members, in_grid, calm) = (&self.members, &self.in_grid, &mut self.calm);
        for &(aabb, velocity, own) in &self.one_by_one {
            let body = members.get(own as usize).map(|m| m.body);
            self.grid.overlaps(&aabb, |g| {
                let i = in_grid[g as usize] as usize;
                if Some(members[i].body) != body && apart.test(members[i].velocity, velocity) {
                    calm[i] = false;
                }
            });
        }
    }
}

/// What the join of the members' boxes makes of two members whose boxes
/// meet (none: they are one body's, or neither apart nor in contact reach).
#[derive(Copy, Clone)]
enum Verdict {
    /// Velocities more than the rest speed apart: neither is calm.
    Apart(u32, u32),
    /// In contact reach and calm together: a pair kept unhooked.
    Kept,
}

impl Calm {
    /// Fewest fast bodies for which the test is tried.
    pub const MIN_FAST: u32 = 256;
    /// A try that leaves fewer than one in `PAYS` fast bodies calm backs
    /// off.
    const PAYS: usize = 8;
    /// A try pays only if it keeps at least one pair in contact reach per
    /// `KEPT` members unhooked (see the module docs).
    const KEPT: usize = 3;
    /// The longest back-off, in steps, after a try that came close to
    /// paying (at least one kept pair per `FAR` members)...
    const MAX_WAIT: u32 = 16;
    /// ...and after one that did not (a gas keeps none, so every try there
    /// is pure cost).
    const MAX_WAIT_FAR: u32 = 64;
    const FAR: usize = 10;
    /// A box is tested one by one when its largest side exceeds this many
    /// times the members' mean.
    const BIG: Real = 4.0;

    /// A test that tries next as `schedule` says, with an empty scratch
    /// space.
    pub fn with_schedule(schedule: CalmSchedule) -> Self {
        Self {
            schedule,
            scratch: Scratch::default(),
        }
    }

    /// Whether to try the test at this step (counts the wait down): at
    /// least `MIN_FAST` fast bodies, and one in `PAYS` awake bodies fast (a
    /// try reads every awake body; it can save at most the fast ones' hooks).
    pub fn wanted(&mut self) -> bool {
        if self.schedule.last_fast < Self::MIN_FAST
            || (self.schedule.last_fast as usize) * Self::PAYS < self.schedule.last_awake as usize
        {
            return false;
        }
        if self.schedule.wait > 0 {
            self.schedule.wait -= 1;
            return false;
        }
        true
    }

    /// Start a try.
    pub fn begin(&mut self) {
        let s = &mut self.scratch;
        s.epoch = s.epoch.wrapping_add(1).max(1);
        s.members.clear();
        s.taken.clear();
        s.one_by_one.clear();
        s.region = None;
        s.fast = 0;
    }

    /// Take awake body `handle`: its governed colliders become members (a
    /// dynamic body's marked colliders; a kinematic body's marked ones, or
    /// all with `fixed_partners`). `fast`: it is flagged unless calm.
    pub fn take(&mut self, f: &Frame, handle: RigidBodyHandle, rb: &RigidBody, fast: bool) {
        let s = &mut self.scratch;
        let dynamic = rb.is_dynamic();
        let first = s.members.len() as u32;
        let mut eligible = true;
        let velocity = rb.linvel();
        let path = path_velocity(rb, f.gravity * f.dt);
        let turn = angular_speed(rb) * f.dt;
        let com = rb.center_of_mass();
        let body = s.taken.len() as u32;
        for &ch in rb.colliders() {
            s.stamp.insert(ch, s.epoch);
            if !(f.marks.contains(ch) || (!dynamic && f.fixed_partners)) {
                continue;
            }
            let Some(co) = f.colliders.get(ch) else {
                continue;
            };
            let contact = contact_box(co, f);
            let (aabb, velocity) = match reach(co, contact, com, path, turn, f) {
                Some(aabb) => (aabb, velocity),
                None => {
                    // Non-finite: never calm, and its neighbours neither
                    // (a NaN velocity fails every comparison).
                    eligible = false;
                    match finite(contact) {
                        Some(aabb) => (aabb, Vector::splat(Real::NAN)),
                        None => continue,
                    }
                }
            };
            s.region = Some(match s.region {
                Some(r) => r.merged(&aabb),
                None => aabb,
            });
            s.members.push(Member {
                aabb,
                contact,
                velocity,
                body,
            });
        }
        s.fast += usize::from(fast && dynamic);
        s.taken.push(Taken {
            handle,
            first,
            end: s.members.len() as u32,
            fast: fast && dynamic,
            eligible,
            calm: false,
        });
    }

    /// Judge the bodies taken against each other and against every other
    /// governed collider in their region.
    pub fn judge(&mut self, f: &Frame, rest_speed: Real) -> Judged {
        let s = &mut self.scratch;
        let apart = Apart {
            rest2: rest_speed * rest_speed,
        };
        s.calm.clear();
        s.calm.resize(s.members.len(), true);
        s.set_large_apart();
        s.add_region_partners(f);
        let Some(kept) = s.join_members(apart) else {
            // Not griddable (extents the scalar cannot hold): none calm.
            return Judged {
                fast: s.fast,
                ..Judged::default()
            };
        };
        s.join_one_by_one(apart);
        let mut count = 0;
        for t in &mut s.taken {
            t.calm = t.eligible && t.fast && (t.first..t.end).all(|i| s.calm[i as usize]);
            count += usize::from(t.calm);
        }
        Judged {
            fast: s.fast,
            calm: count,
            members: s.members.len(),
            kept,
        }
    }

    /// The bodies taken at this try, judged.
    pub fn taken(&self) -> &[Taken] {
        &self.scratch.taken
    }

    /// Record the outcome of a try. It pays when at least one in `PAYS`
    /// fast bodies is calm and the pairs it keeps are a third of the
    /// members or more.
    pub fn settle(&mut self, judged: &Judged) {
        if judged.calm * Self::PAYS < judged.fast || judged.kept * Self::KEPT < judged.members {
            let most = if judged.kept * Self::FAR < judged.members {
                Self::MAX_WAIT_FAR
            } else {
                Self::MAX_WAIT
            };
            self.schedule.backoff = (self.schedule.backoff * 2).clamp(1, most);
            self.schedule.wait = self.schedule.backoff;
        } else {
            self.schedule.backoff = 0;
            self.schedule.wait = 0;
        }
    }
}

#[cfg(feature = "dim2")]
fn angular_speed(rb: &RigidBody) -> Real {
    rb.angvel().abs()
}

#[cfg(feature = "dim3")]
fn angular_speed(rb: &RigidBody) -> Real {
    rb.angvel().length()
}

/// Collider `co`'s box at the start of the step, grown by rapier's contact
/// reach (skin and half the prediction distance): two colliders can have a
/// contact at the narrow phase only if these boxes meet.
fn contact_box(co: &Collider, f: &Frame) -> Aabb {
    co.compute_aabb()
        .loosened(co.contact_skin() + 0.5 * f.prediction)
}

/// `b` if finite.
fn finite(b: Aabb) -> Option<Aabb> {
    (b.mins.is_finite() && b.maxs.is_finite()).then_some(b)
}

/// Everywhere collider `co` with contact box `b` can reach this step: the
/// box grown by how far its farthest point turns (`turn` radians about
/// `com`), and swept along `path * dt` in the frame the world shares (so
/// that in a world falling as a whole the boxes are as short as the
/// bodies' motion against each other). A ball is the same shape however it
/// turns: only its centre moves, so a spinning ball centred on `com` reaches
/// no farther than a still one. `None` if not finite.
fn reach(co: &Collider, b: Aabb, com: Vector, path: Vector, turn: Real, f: &Frame) -> Option<Aabb> {
    let centre = (b.center() - com).length();
    let arm = if co.shape().as_ball().is_some() {
        centre
    } else {
        centre + 0.5 * (b.maxs - b.mins).length()
    };
    let b = b.loosened(turn.min(2.0) * arm);
    let shift = (path - f.shared) * f.dt;
    let moved = Aabb::new(b.mins + shift, b.maxs + shift);
    let swept = b.merged(&moved);
    finite(swept)
}

/// The collider at index `index` as a partner of the members, if the law
/// governs its pairs with them: a marked collider of a body not taken
/// (asleep, or woken since the last step), or, with `fixed_partners`, a
/// collider of a fixed or kinematic body or of none.
fn partner(f: &Frame, index: u32) -> Option<(Aabb, Vector, u32)> {
    let (co, ch) = f.colliders.get_unknown_gen(index)?;
    let rb = co.parent().and_then(|h| f.bodies.get(h));
    let governed = f.marks.contains(ch)
        || (f.fixed_partners && rb.is_none_or(|rb| !rb.is_dynamic() || translations_locked(rb)));
    if !governed {
        return None;
    }
    let contact = contact_box(co, f);
    let Some(rb) = rb else {
        return finite(contact).map(|b| (b, Vector::ZERO, u32::MAX));
    };
    let path = path_velocity(rb, f.gravity * f.dt);
    let turn = angular_speed(rb) * f.dt;
    match reach(co, contact, rb.center_of_mass(), path, turn, f) {
        Some(b) => Some((b, rb.linvel(), u32::MAX)),
        None => finite(contact).map(|b| (b, Vector::splat(Real::NAN), u32::MAX)),
    }
}
