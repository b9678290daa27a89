//! Law parameters per collider: materials, and how a pair combines them.

use kimpact::{FixedPartner, ImpactFriction, Law, LawError, LawParams};

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
///
/// A material may also carry impact friction (off by default, see
/// [`Material::with_impact_friction`]): Coulomb's `μ` and the tangential
/// restitution `β` of [`kimpact::ImpactFriction`]. A pair's `μ` is
/// `combine(μ₁, μ₂)`, its `β` is `2 combine((1+β₁)/2, (1+β₂)/2) − 1` (the
/// rules combine numbers in `[0, 1]`, so `β` stays in `[−1, 1]`); a
/// material without impact friction counts as `μ = 0, β = −1`.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct Material {
    dissipation: Real,
    wall_dissipation: Real,
    combine: CoefficientCombineRule,
    /// Coulomb's coefficient at the impact (0: off).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    impact_friction: Real,
    /// The tangential restitution at the impact (−1 while `impact_friction`
    /// is 0).
    #[cfg_attr(
        feature = "serde-serialize",
        serde(default = "frictionless_tangential_restitution")
    )]
    tangential_restitution: Real,
}

/// β of a material without impact friction (snapshots saved before
/// materials carried it).
#[cfg(feature = "serde-serialize")]
fn frictionless_tangential_restitution() -> Real {
    -1.0
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
            impact_friction: 0.0,
            tangential_restitution: -1.0,
        })
    }

    /// The same material with impact friction: Coulomb's coefficient
    /// `impact_friction` (μ ≥ 0) and the tangential restitution
    /// `tangential_restitution` (β ∈ [−1, 1]: −1 leaves the contact points'
    /// tangential velocity as it is, 0 stops it, 1 reverses it), applied at
    /// every impact the law resolves for the pair (Walton's model, see
    /// [`kimpact::Law::resolve_rigid_with_friction`]). Friction turns the
    /// bodies: with rotations locked, the tangential impulse moves them
    /// only along the contact.
    ///
    /// # Errors
    /// [`LawError::InvalidFriction`] naming the parameter out of range.
    pub fn with_impact_friction(
        mut self,
        impact_friction: Real,
        tangential_restitution: Real,
    ) -> Result<Self, LawError> {
        let friction = ImpactFriction::new(impact_friction, tangential_restitution)?;
        self.impact_friction = friction.impact_friction();
        self.tangential_restitution = friction.tangential_restitution();
        Ok(self)
    }

    /// The material's impact friction ([`ImpactFriction::frictionless`]
    /// unless [`Material::with_impact_friction`] set it).
    pub fn impact_friction(&self) -> ImpactFriction<Real> {
        ImpactFriction::new(self.impact_friction, self.tangential_restitution)
            .unwrap_or_else(|_| ImpactFriction::frictionless())
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

/// The impact friction for a pair whose colliders carry materials `m1` and
/// `m2` (see [`Material`]); frictionless when neither has a material.
pub(crate) fn pair_friction(m1: Option<&Material>, m2: Option<&Material>) -> ImpactFriction<Real> {
    let (mu, beta) = match (m1, m2) {
        (None, None) => return ImpactFriction::frictionless(),
        (Some(m), None) | (None, Some(m)) => (m.impact_friction, m.tangential_restitution),
        (Some(a), Some(b)) => {
            let combine =
                |x: Real, y: Real| CoefficientCombineRule::combine(x, y, a.combine, b.combine);
            let mu = combine(a.impact_friction, b.impact_friction);
            let half = combine(
                (1.0 + a.tangential_restitution) * 0.5,
                (1.0 + b.tangential_restitution) * 0.5,
            );
            (mu, 2.0 * half - 1.0)
        }
    };
    // Rounding may leave β a hair outside [−1, 1].
    ImpactFriction::new(mu, beta.clamp(-1.0, 1.0))
        .unwrap_or_else(|_| ImpactFriction::frictionless())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pair_combines_impact_friction_by_its_rule() {
        let rough = Material::new(0.0, 0.0)
            .unwrap()
            .with_impact_friction(0.4, 0.5)
            .unwrap();
        let smooth = Material::new(0.0, 0.0).unwrap();
        let both = pair_friction(Some(&rough), Some(&rough));
        assert_eq!(both.impact_friction(), 0.4);
        assert!((both.tangential_restitution() - 0.5).abs() < 1e-6);
        // Average of μ = 0.4 and 0; of (1+β)/2 = 0.75 and 0.
        let mixed = pair_friction(Some(&rough), Some(&smooth));
        assert!((mixed.impact_friction() - 0.2).abs() < 1e-6);
        assert!((mixed.tangential_restitution() - (2.0 * 0.375 - 1.0)).abs() < 1e-6);
        let max = pair_friction(
            Some(&rough.with_combine_rule(CoefficientCombineRule::Max)),
            Some(&smooth),
        );
        assert_eq!(max.impact_friction(), 0.4);
        assert!(pair_friction(Some(&smooth), None).is_frictionless());
        assert!(pair_friction(None, None).is_frictionless());
    }

    #[test]
    fn impact_friction_out_of_range_is_refused_by_name() {
        let m = Material::new(0.0, 0.0).unwrap();
        for (mu, beta, name) in [
            (-0.1, 0.0, "impact_friction"),
            (Real::NAN, 0.0, "impact_friction"),
            (0.3, 1.5, "tangential_restitution"),
            (0.3, Real::NAN, "tangential_restitution"),
        ] {
            match m.with_impact_friction(mu, beta) {
                Err(LawError::InvalidFriction { parameter, .. }) => assert_eq!(parameter, name),
                other => panic!("{mu}, {beta}: {other:?}"),
            }
        }
    }
}
