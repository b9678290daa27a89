//! How the law sees a rapier body: its mass (finite, or infinite for fixed
//! and kinematic bodies) and its velocity, the straight path rapier
//! integrates it along, where it started the step, and how fast its
//! surface turns.

use kimpact::{Body, LawError, Mass};

use crate::handle_map::HandleMap;
use crate::math::{DIM, Real, Vector, to_law};
use crate::rapier::math::AngVector;
use crate::rapier::prelude::*;

/// How a body takes part in the law.
#[derive(Copy, Clone, Debug)]
pub(crate) struct LawBody {
    pub mass: Mass<Real>,
    pub velocity: Vector,
}

impl LawBody {
    /// Whether the data can enter the law: a finite velocity and a finite,
    /// positive mass (or an infinite one).
    pub(crate) fn is_finite(&self) -> bool {
        self.velocity.is_finite()
            && match self.mass {
                Mass::Finite(m) => m.is_finite() && m > 0.0,
                Mass::Infinite => true,
            }
    }

    /// The body checked for the law: non-finite or non-positive data is an
    /// error.
    pub(crate) fn checked(&self) -> Result<Body<Real, DIM>, LawError> {
        match self.mass {
            Mass::Finite(m) => Body::new(m, to_law(self.velocity)),
            Mass::Infinite => Body::immovable(to_law(self.velocity)),
        }
    }
}

/// The translation axes of this dimension, as rapier's locked-axes flags.
#[cfg(feature = "dim2")]
const TRANSLATIONS: LockedAxes =
    LockedAxes::TRANSLATION_LOCKED_X.union(LockedAxes::TRANSLATION_LOCKED_Y);
/// The translation axes of this dimension, as rapier's locked-axes flags.
#[cfg(feature = "dim3")]
const TRANSLATIONS: LockedAxes = LockedAxes::TRANSLATION_LOCKED;

/// The body of a collider as the law sees it: a dynamic body with its mass
/// and velocity, any other (or none) immovable. A dynamic body whose every
/// translation is locked is immovable too (rapier's solver never moves it);
/// one with some translations locked and others free is `None`: the law,
/// which takes one mass for every direction, leaves its pairs to rapier.
pub(crate) fn law_body(bodies: &RigidBodySet, parent: Option<RigidBodyHandle>) -> Option<LawBody> {
    Some(match parent.and_then(|h| bodies.get(h)) {
        Some(rb) if rb.is_dynamic() => {
            let locked = rb.locked_axes() & TRANSLATIONS;
            if locked.is_empty() {
                LawBody {
                    mass: Mass::Finite(rb.mass()),
                    velocity: rb.linvel(),
                }
            } else if locked == TRANSLATIONS {
                LawBody {
                    mass: Mass::Infinite,
                    velocity: rb.linvel(),
                }
            } else {
                return None;
            }
        }
        Some(rb) => LawBody {
            mass: Mass::Infinite,
            velocity: rb.linvel(),
        },
        None => LawBody {
            mass: Mass::Infinite,
            velocity: Vector::ZERO,
        },
    })
}

/// The law's bodies `b1` and `b2` of a pair (of bodies `p1` and `p2`) with
/// rapier's dominance groups: when both are finite and the groups differ,
/// the dominant body is immovable to the other, as rapier's solver takes
/// it.
pub(crate) fn dominated(
    bodies: &RigidBodySet,
    (p1, b1): (Option<RigidBodyHandle>, LawBody),
    (p2, b2): (Option<RigidBodyHandle>, LawBody),
) -> (LawBody, LawBody) {
    if !(matches!(b1.mass, Mass::Finite(_)) && matches!(b2.mass, Mass::Finite(_))) {
        return (b1, b2);
    }
    let group = |p: Option<RigidBodyHandle>| {
        p.and_then(|h| bodies.get(h))
            .map_or(0, |rb| rb.dominance_group())
    };
    let (g1, g2) = (group(p1), group(p2));
    (dominate(b1, g1, g2), dominate(b2, g2, g1))
}

/// `body`, of dominance group `group`, against a partner of group
/// `other`: immovable when it dominates the partner.
#[inline]
pub(crate) fn dominate(body: LawBody, group: i8, other: i8) -> LawBody {
    if group > other {
        LawBody {
            mass: Mass::Infinite,
            ..body
        }
    } else {
        body
    }
}

/// Whether every translation of `rb` is locked (rapier's solver and
/// gravity never move it: the law takes it as immovable, see
/// [`law_body`]).
#[inline]
pub(crate) fn translations_locked(rb: &RigidBody) -> bool {
    rb.locked_axes().contains(TRANSLATIONS)
}

/// Whether any translation of `rb` is locked.
#[inline]
pub(crate) fn translations_partly_locked(rb: &RigidBody) -> bool {
    rb.locked_axes().intersects(TRANSLATIONS)
}

/// Restitution mode hands a body to the replay, and the replay chains on
/// from a struck body, while it moves more than this share of its
/// [`half_size`] over the step (a quarter of its size).
pub(crate) const SWEPT_SHARE: Real = 0.5;

/// Half the size of collider `co`, the distance a body may move per step
/// before it can cross a partner unseen: a ball's radius, otherwise half
/// the shortest side of its box.
pub(crate) fn half_size(co: &Collider) -> Real {
    match co.shape().as_ball() {
        Some(ball) => ball.radius,
        None => {
            let aabb = co.compute_aabb();
            0.5 * (aabb.maxs - aabb.mins).min_element()
        }
    }
}

/// The velocity body `rb` moves along this step, on the straight path
/// rapier integrates: its velocity plus gravity's `gravity_dt` (scaled by
/// its gravity scale) for a dynamic body whose translations are not all
/// locked, its velocity for another.
pub(crate) fn path_velocity(rb: &RigidBody, gravity_dt: Vector) -> Vector {
    if rb.is_dynamic() && !translations_locked(rb) {
        rb.linvel() + gravity_dt * rb.gravity_scale()
    } else {
        rb.linvel()
    }
}

/// Where bodies started the step, per body (every law mode): what the
/// replay after the step needs to rebuild each body's straight path.
#[derive(Clone, Debug, Default)]
pub(crate) struct Starts {
    translations: HandleMap<RigidBodyHandle, Vector>,
}

impl Starts {
    /// Record where body `handle` starts the step.
    #[inline]
    pub(crate) fn store(&mut self, handle: RigidBodyHandle, translation: Vector) {
        self.translations.insert(handle, translation);
    }

    /// Where body `handle` started this step, if stored.
    pub(crate) fn of(&self, handle: RigidBodyHandle) -> Option<Vector> {
        self.translations.get(handle).copied()
    }
}

/// Whether a point of body `rb`'s colliders `counted`, turning with it,
/// may move faster than `threshold`: the speed of its centre plus its
/// angular speed times how far those colliders reach from its centre of
/// mass (their bounding spheres, in the body's frame). Never for a body
/// without such a collider.
pub(crate) fn turns_fast(
    rb: &RigidBody,
    colliders: &ColliderSet,
    threshold: Real,
    counted: impl Fn(ColliderHandle) -> bool,
) -> bool {
    let spin = spin_speed(rb.angvel());
    if spin.is_nan() || spin <= 0.0 {
        return false;
    }
    let com = rb.local_center_of_mass();
    let mut reach: Real = 0.0;
    for &ch in rb.colliders() {
        if !counted(ch) {
            continue;
        }
        if let Some(co) = colliders.get(ch) {
            let sphere = co.shape().compute_local_bounding_sphere();
            let offset = co.position_wrt_parent().copied().unwrap_or_default();
            reach = reach.max((offset * sphere.center() - com).length() + sphere.radius());
        }
    }
    reach > 0.0 && rb.linvel().length() + spin * reach > threshold
}

/// `|ω|`.
#[cfg(feature = "dim2")]
fn spin_speed(w: AngVector) -> Real {
    w.abs()
}

/// `|ω|`.
#[cfg(feature = "dim3")]
fn spin_speed(w: AngVector) -> Real {
    w.length()
}
