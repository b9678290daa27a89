//! Which colliders follow the law, and which pairs the law governs.

use kimpact::{ImpactFriction, Law};

use crate::body_view::translations_locked;
use crate::handle_map::HandleMap;
use crate::material::{Material, pair_friction, pair_law};
use crate::math::Real;
use crate::rapier::prelude::*;

/// The marked colliders, each with whether it is a point collider and its
/// material (per handle: a collider rapier inserts in a removed one's slot
/// is not marked by accident).
#[derive(Clone, Debug, Default)]
pub(crate) struct Marks {
    marked: HandleMap<ColliderHandle, Mark>,
    /// How many marked colliders carry a material: while none does, a
    /// pair's law is the base law without a lookup.
    with_material: usize,
    /// How many marked colliders are not balls centred on their body (see
    /// [`is_point_collider`]): while none is, no pair turns, without a
    /// lookup.
    extended: usize,
}

/// What the law needs of one marked collider.
#[derive(Copy, Clone, Debug, Default)]
struct Mark {
    /// Not a point collider (see [`is_point_collider`]).
    extended: bool,
    material: Option<Material>,
}

/// How the law governs a pair ([`Marks::governance`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Governed {
    /// As points ([`Marks::governs`]).
    Points,
    /// As rigid bodies ([`Marks::governs_rigid`]).
    Rigid,
}

/// Which partners of a marked collider the law governs besides marked
/// ones ([`crate::ResolverConfig::fixed_partners`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Partners {
    /// Only marked colliders.
    Marked,
    /// Marked colliders, and immovable ones (fixed, kinematic, dynamic with
    /// every translation locked), marked or not.
    MarkedOrImmovable,
}

impl Partners {
    /// The partners of a configuration with `fixed_partners`.
    pub(crate) fn of(fixed_partners: bool) -> Self {
        if fixed_partners {
            Partners::MarkedOrImmovable
        } else {
            Partners::Marked
        }
    }
}

/// Whether the law can govern collider `co` on a dynamic body: a ball
/// centred on its body's origin (or a ball without a body). The law moves
/// bodies as points (it changes linear velocities only, along the normal
/// through both centres); any other shape, or a ball off its body's
/// centre, turns under an impact, which the law does not know.
pub(crate) fn is_point_collider(co: &Collider) -> bool {
    let Some(ball) = co.shape().as_ball() else {
        return false;
    };
    co.position_wrt_parent()
        .is_none_or(|local| local.translation.length() <= 1e-4 * ball.radius)
}

impl Marks {
    /// Mark `handle` (the caller has checked it is in the collider set, so
    /// its index is bounded by the set's size); `point`: whether it is a
    /// point collider ([`is_point_collider`]). Marking a marked collider
    /// again keeps its material.
    pub(crate) fn insert(&mut self, handle: ColliderHandle, point: bool) {
        let mark = self.marked.get_or_insert_with(handle, Mark::default);
        self.extended -= usize::from(mark.extended);
        mark.extended = !point;
        self.extended += usize::from(mark.extended);
    }

    /// The marked colliders in index order, each with whether it is a
    /// point collider and its material.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (ColliderHandle, bool, Option<&Material>)> {
        self.marked
            .iter()
            .map(|(handle, mark)| (handle, !mark.extended, mark.material.as_ref()))
    }

    /// How many colliders are marked.
    pub(crate) fn len(&self) -> usize {
        self.marked.iter().count()
    }

    /// Whether any marked collider is not a point collider.
    pub(crate) fn has_extended(&self) -> bool {
        self.extended > 0
    }

    /// Whether marked collider `handle` is not a point collider.
    pub(crate) fn is_extended(&self, handle: ColliderHandle) -> bool {
        self.extended > 0 && self.marked.get(handle).is_some_and(|m| m.extended)
    }

    /// Unmark `handle`; whether it was marked. A handle of another
    /// generation than the marked one leaves the mark alone.
    pub(crate) fn remove(&mut self, handle: ColliderHandle) -> bool {
        let Some(mark) = self.marked.remove(handle) else {
            return false;
        };
        self.extended -= usize::from(mark.extended);
        self.with_material -= usize::from(mark.material.is_some());
        true
    }

    /// Set (or clear) the material of marked collider `handle`.
    pub(crate) fn set_material(&mut self, handle: ColliderHandle, material: Option<Material>) {
        let Some(mark) = self.marked.get_mut(handle) else {
            return;
        };
        self.with_material -= usize::from(mark.material.is_some());
        mark.material = material;
        self.with_material += usize::from(mark.material.is_some());
    }

    /// The material of `handle`, if it is marked with one.
    pub(crate) fn material(&self, handle: ColliderHandle) -> Option<&Material> {
        self.marked.get(handle)?.material.as_ref()
    }

    /// The law for the pair `c1`/`c2`: `base` unless either carries a
    /// material (see [`Material`]).
    #[inline]
    pub(crate) fn law(
        &self,
        base: &Law<Real>,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> Law<Real> {
        if self.with_material == 0 {
            return *base;
        }
        pair_law(base, self.material(c1), self.material(c2))
    }

    /// The impact friction for the pair `c1`/`c2`: frictionless unless
    /// either carries a material with it (see [`Material`]).
    #[inline]
    pub(crate) fn friction(&self, c1: ColliderHandle, c2: ColliderHandle) -> ImpactFriction<Real> {
        if self.with_material == 0 {
            return ImpactFriction::frictionless();
        }
        pair_friction(self.material(c1), self.material(c2))
    }

    /// Whether `handle` is marked.
    #[inline]
    pub(crate) fn contains(&self, handle: ColliderHandle) -> bool {
        self.marked.get(handle).is_some()
    }

    /// Whether the law governs the pair: both marked, or one marked and the
    /// other immovable (fixed, kinematic, or dynamic with every translation
    /// locked; with [`Partners::MarkedOrImmovable`]); and every marked collider of
    /// a dynamic body in it a point collider (the pairs of any other are
    /// rapier's, as if it were not marked, but in restitution mode: see
    /// [`Marks::governs_rigid`]).
    pub(crate) fn governs(
        &self,
        partners: Partners,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> bool {
        self.governance(partners, colliders, bodies, c1, c2) == Some(Governed::Points)
    }

    /// Whether the law governs the pair as rigid bodies at the manifold's
    /// contact (restitution mode): a pair [`Marks::governs`] would govern
    /// but for a marked collider of another shape than a centred ball on a
    /// dynamic body.
    pub(crate) fn governs_rigid(
        &self,
        partners: Partners,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> bool {
        self.governance(partners, colliders, bodies, c1, c2) == Some(Governed::Rigid)
    }

    /// How the law governs the pair, if it does: as points
    /// ([`Marks::governs`]) or as rigid bodies ([`Marks::governs_rigid`]),
    /// in one look at the marks (the contact hook asks both of every pair
    /// it sees).
    pub(crate) fn governance(
        &self,
        partners: Partners,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> Option<Governed> {
        if !self.pairs(partners, colliders, bodies, c1, c2) {
            return None;
        }
        Some(if self.turning(colliders, bodies, c1, c2) {
            Governed::Rigid
        } else {
            Governed::Points
        })
    }

    /// Whether a marked collider of the pair is extended on a dynamic body.
    fn turning(
        &self,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> bool {
        self.extended > 0
            && ((self.contains(c1) && self.turns(colliders, bodies, c1))
                || (self.contains(c2) && self.turns(colliders, bodies, c2)))
    }

    /// Whether the pair is the law's by its marks: both marked, or one
    /// marked and the other immovable (with
    /// [`Partners::MarkedOrImmovable`]).
    fn pairs(
        &self,
        partners: Partners,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> bool {
        let (m1, m2) = (self.contains(c1), self.contains(c2));
        if m1 && m2 {
            return true;
        }
        if !(partners == Partners::MarkedOrImmovable && (m1 || m2)) {
            return false;
        }
        let other = if m1 { c2 } else { c1 };
        let parent = colliders.get(other).and_then(|c| c.parent());
        match parent.and_then(|h| bodies.get(h)) {
            Some(rb) => !rb.is_dynamic() || translations_locked(rb),
            None => true,
        }
    }

    /// Whether marked collider `c` is extended (not a point collider) on a
    /// dynamic body.
    fn turns(&self, colliders: &ColliderSet, bodies: &RigidBodySet, c: ColliderHandle) -> bool {
        self.is_extended(c)
            && colliders
                .get(c)
                .and_then(|co| co.parent())
                .and_then(|h| bodies.get(h))
                .is_some_and(|rb| rb.is_dynamic())
    }
}
