//! Law parameters per collider: materials, and how a pair combines them.

use kimpact::{FixedPartner, Law, LawError, LawParams};

use crate::math::Real;
use crate::rapier::prelude::CoefficientCombineRule;

/// The law's parameters for one marked collider (rubber, steel, wood): its
/// dissipation constant `d̃` against other marked colliders, its `d̃_w`
/// against fixed and kinematic partners, and the rule combining each with
/// a partner's, after rapier's `CoefficientCombineRule` (if the two
/// colliders' rules differ, the higher one wins: `GeometricMean >
/// ClampedSum > Max > Multiply > Min > Average`).
///
/// For a pair, the law in force is:
/// - both colliders with a material: `d̃ = combine(d̃₁, d̃₂)` and
///   `d̃_w = combine(d̃_w₁, d̃_w₂)`;
/// - one with a material: that material's `d̃` and `d̃_w` (a wall you did not
///   mark, or marked without a material, takes the ball's own);
/// - neither: the resolver's law ([`crate::Kimpact::law`]).
///
/// The resolver's [`FixedPartner`] policy applies to every pair. A
/// collider's own rapier restitution coefficient plays no part in the law
/// (see the crate docs).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct Material {
    dissipation: Real,
    wall_dissipation: Real,
    combine: CoefficientCombineRule,
}

impl Material {
    /// A material with dissipation constants `dissipation` (`d̃`, against
    /// marked colliders) and `wall_dissipation` (`d̃_w`, against fixed and
    /// kinematic partners), combined by `CoefficientCombineRule::Average`.
    ///
    /// # Errors
    /// [`LawError::InvalidDissipation`] naming the constant that is
    /// negative, NaN or infinite.
    pub fn new(dissipation: Real, wall_dissipation: Real) -> Result<Self, LawError> {
        Self::from_params(LawParams {
            dissipation,
            wall_dissipation: Some(wall_dissipation),
            fixed_partner: FixedPartner::default(),
        })
    }

    /// The material of law parameters `params` (`wall_dissipation: None`
    /// means the same as `dissipation`; the policy is the resolver's).
    ///
    /// # Errors
    /// As [`Law::new`].
    pub fn from_params(params: LawParams<Real>) -> Result<Self, LawError> {
        let law = Law::new(params)?;
        Ok(Self {
            dissipation: law.dissipation(),
            wall_dissipation: law.wall_dissipation(),
            combine: CoefficientCombineRule::Average,
        })
    }

    /// The same material with combine rule `rule`.
    pub fn with_combine_rule(mut self, rule: CoefficientCombineRule) -> Self {
        self.combine = rule;
        self
    }

    /// `d̃` against other marked colliders.
    pub fn dissipation(&self) -> Real {
        self.dissipation
    }

    /// `d̃_w` against fixed and kinematic partners.
    pub fn wall_dissipation(&self) -> Real {
        self.wall_dissipation
    }

    /// The combine rule.
    pub fn combine_rule(&self) -> CoefficientCombineRule {
        self.combine
    }
}

/// The law for a pair whose colliders carry materials `m1` and `m2`, on top
/// of the resolver's law `base` (see [`Material`]).
pub(crate) fn pair_law(
    base: &Law<Real>,
    m1: Option<&Material>,
    m2: Option<&Material>,
) -> Law<Real> {
    let (dissipation, wall) = match (m1, m2) {
        (None, None) => return *base,
        (Some(m), None) | (None, Some(m)) => (m.dissipation, m.wall_dissipation),
        (Some(a), Some(b)) => (
            CoefficientCombineRule::combine(a.dissipation, b.dissipation, a.combine, b.combine),
            CoefficientCombineRule::combine(
                a.wall_dissipation,
                b.wall_dissipation,
                a.combine,
                b.combine,
            ),
        ),
    };
    // Every rule keeps two valid constants valid (finite, `≥ 0`).
    Law::new(LawParams {
        dissipation,
        wall_dissipation: Some(wall),
        fixed_partner: base.fixed_partner(),
    })
    .unwrap_or(*base)
}
