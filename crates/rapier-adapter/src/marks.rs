//! Which colliders follow the law, and which pairs the law governs.

use kimpact::{ImpactFriction, Law};

use crate::body_view::translations_locked;
use crate::material::{Material, pair_friction, pair_law};
use crate::math::Real;
use crate::rapier::prelude::*;

/// The marked colliders: by collider index, the generation + 1 of the
/// marked handle (0: not marked), so a handle whose slot rapier reused for
/// another collider is not marked by accident; and their materials.
#[derive(Clone, Debug, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct Marks {
    tags: Vec<u32>,
    /// By collider index, the material of a marked collider that has one;
    /// empty while no collider has one (a scene without materials pays one
    /// length test per law it asks for).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    materials: Vec<Option<Material>>,
    /// By collider index, whether a marked collider is not a ball centred
    /// on its body (see [`is_point_collider`]); empty while every marked
    /// collider is one (a scene of balls pays one length test per pair).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    extended: Vec<bool>,
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
    /// point collider ([`is_point_collider`]).
    pub(crate) fn insert(&mut self, handle: ColliderHandle, point: bool) {
        let (index, generation) = handle.into_raw_parts();
        let index = index as usize;
        if self.tags.len() <= index {
            self.tags.resize(index + 1, 0);
        }
        self.tags[index] = generation.wrapping_add(1);
        if !point && self.extended.len() <= index {
            self.extended.resize(index + 1, false);
        }
        if let Some(e) = self.extended.get_mut(index) {
            *e = !point;
        }
    }

    /// The marked colliders in index order, each with whether it is a
    /// point collider and its material.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (ColliderHandle, bool, Option<&Material>)> {
        self.tags.iter().enumerate().filter_map(|(index, &tag)| {
            let handle = ColliderHandle::from_raw_parts(index as u32, tag.checked_sub(1)?);
            Some((handle, !self.is_extended(handle), self.material(handle)))
        })
    }

    /// How many colliders are marked.
    pub(crate) fn len(&self) -> usize {
        self.tags.iter().filter(|&&tag| tag != 0).count()
    }

    /// Whether marked collider `handle` is not a point collider.
    pub(crate) fn is_extended(&self, handle: ColliderHandle) -> bool {
        self.extended
            .get(handle.into_raw_parts().0 as usize)
            .copied()
            .unwrap_or(false)
    }

    /// Unmark `handle`; whether it was marked. A handle of another
    /// generation than the marked one leaves the mark alone.
    pub(crate) fn remove(&mut self, handle: ColliderHandle) -> bool {
        let (index, generation) = handle.into_raw_parts();
        match self.tags.get_mut(index as usize) {
            Some(m) if *m == generation.wrapping_add(1) => {
                *m = 0;
                if let Some(slot) = self.materials.get_mut(index as usize) {
                    *slot = None;
                }
                if let Some(e) = self.extended.get_mut(index as usize) {
                    *e = false;
                }
                true
            }
            _ => false,
        }
    }

    /// Set (or clear) the material of marked collider `handle`.
    pub(crate) fn set_material(&mut self, handle: ColliderHandle, material: Option<Material>) {
        let index = handle.into_raw_parts().0 as usize;
        if material.is_none() && self.materials.len() <= index {
            return;
        }
        if self.materials.len() <= index {
            self.materials.resize(index + 1, None);
        }
        self.materials[index] = material;
    }

    /// The material of `handle`, if it is marked with one.
    pub(crate) fn material(&self, handle: ColliderHandle) -> Option<&Material> {
        if !self.contains(handle) {
            return None;
        }
        self.materials
            .get(handle.into_raw_parts().0 as usize)?
            .as_ref()
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
        if self.materials.is_empty() {
            return *base;
        }
        pair_law(base, self.material(c1), self.material(c2))
    }

    /// The impact friction for the pair `c1`/`c2`: frictionless unless
    /// either carries a material with it (see [`Material`]).
    #[inline]
    pub(crate) fn friction(&self, c1: ColliderHandle, c2: ColliderHandle) -> ImpactFriction<Real> {
        if self.materials.is_empty() {
            return ImpactFriction::frictionless();
        }
        pair_friction(self.material(c1), self.material(c2))
    }

    /// Whether `handle` is marked.
    #[inline]
    pub(crate) fn contains(&self, handle: ColliderHandle) -> bool {
        let (index, generation) = handle.into_raw_parts();
        self.tags.get(index as usize) == Some(&(generation.wrapping_add(1)))
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
        !self.turning(colliders, bodies, c1, c2) && self.pairs(partners, colliders, bodies, c1, c2)
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
        self.turning(colliders, bodies, c1, c2) && self.pairs(partners, colliders, bodies, c1, c2)
    }

    /// Whether a marked collider of the pair is extended on a dynamic body.
    fn turning(
        &self,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> bool {
        !self.extended.is_empty()
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
