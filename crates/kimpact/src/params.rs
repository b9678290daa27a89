//! The law's parameters as plain data: the dissipation constants, the
//! policy for partners of infinite mass, and their choice from restitution
//! coefficients.

use nalgebra::RealField;

use crate::error::LawError;
use crate::num::{half, to_f64};

/// How the law treats a partner of infinite mass (a fixed or kinematic body:
/// a wall, a cushion, a floor, a paddle).
///
/// The literal law sets `d = d̃ (m₁ + m₂) |v₂ − v₁|²`, which grows without
/// bound with `m₂`: against an infinite mass every impact with `d̃ > 0` is
/// clamped, i.e. perfectly plastic up to the `1e-6` tolerance. That is
/// rarely what a billiards cushion or a pinball wall should do, so the
/// default is [`FixedPartner::OwnMass`].
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum FixedPartner {
    /// The default. The impact uses the finite body's own mass in place of
    /// the pair's: `d = d̃_w m |v₂ − v₁|²`, with `d̃_w` the law's
    /// `wall_dissipation` (equal to `dissipation` unless set). The effective
    /// restitution against a wall is then `e = sqrt(1 − 2 d̃_w |w|²/u²)`,
    /// independent of the ball's mass; `d̃_w = 0` is an elastic wall.
    #[default]
    OwnMass,
    /// The note's law taken literally, as the limit `m₂ → ∞`: elastic if
    /// `dissipation` is zero, otherwise always clamped (the ball keeps
    /// `1e-3` of its normal speed). `wall_dissipation` is ignored.
    Literal,
}

impl FixedPartner {
    /// Both policies, the default first.
    pub const ALL: [FixedPartner; 2] = [FixedPartner::OwnMass, FixedPartner::Literal];

    /// The policy's name as in scene files and serde: `"own_mass"` or
    /// `"literal"`.
    pub fn name(self) -> &'static str {
        match self {
            FixedPartner::OwnMass => "own_mass",
            FixedPartner::Literal => "literal",
        }
    }
}

impl core::fmt::Display for FixedPartner {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown [`FixedPartner`] name (the name given).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown fixed partner policy {0:?}: expected \"own_mass\" or \"literal\"")]
pub struct ParseFixedPartnerError(pub String);

impl core::str::FromStr for FixedPartner {
    type Err = ParseFixedPartnerError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        FixedPartner::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| ParseFixedPartnerError(s.to_owned()))
    }
}

/// The law's parameters, as plain data (for configuration files). Turn them
/// into a [`Law`](crate::Law) with [`Law::new`](crate::Law::new), which
/// checks them.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(
        deny_unknown_fields,
        bound(
            serialize = "T: serde::Serialize",
            deserialize = "T: RealField + Copy + serde::Deserialize<'de>"
        )
    )
)]
pub struct LawParams<T> {
    /// `d̃ ≥ 0`, the dissipation constant of the note. Zero is elastic.
    #[cfg_attr(feature = "serde", serde(default = "zero"))]
    pub dissipation: T,
    /// `d̃_w ≥ 0`, the dissipation constant against fixed and kinematic
    /// partners under [`FixedPartner::OwnMass`]; `None` means "same as
    /// `dissipation`".
    #[cfg_attr(feature = "serde", serde(default))]
    pub wall_dissipation: Option<T>,
    /// The policy for partners of infinite mass.
    #[cfg_attr(feature = "serde", serde(default))]
    pub fixed_partner: FixedPartner,
}

#[cfg(feature = "serde")]
fn zero<T: RealField>() -> T {
    T::zero()
}

impl<T: RealField + Copy> Default for LawParams<T> {
    fn default() -> Self {
        Self {
            dissipation: T::zero(),
            wall_dissipation: None,
            fixed_partner: FixedPartner::OwnMass,
        }
    }
}

impl<T> LawParams<T> {
    /// The same parameters with each constant converted by `f` (a scene
    /// file's `f64` to an `f32` build's scalar, say). Nothing is checked
    /// here: [`Law::new`](crate::Law::new) checks the result, as any
    /// parameters.
    ///
    /// ```
    /// use kimpact::{Law, LawParams};
    ///
    /// let read = LawParams { dissipation: 0.02_f64, ..Default::default() };
    /// let law = Law::new(read.map(|x| x as f32))?;
    /// assert_eq!(law.dissipation(), 0.02_f32);
    /// assert!(Law::new(LawParams { dissipation: 1e300_f64, ..read }.map(|x| x as f32)).is_err());
    /// # Ok::<(), kimpact::LawError>(())
    /// ```
    pub fn map<U>(self, f: impl Fn(T) -> U) -> LawParams<U> {
        LawParams {
            dissipation: f(self.dissipation),
            wall_dissipation: self.wall_dissipation.map(&f),
            fixed_partner: self.fixed_partner,
        }
    }
}

impl<T: RealField + Copy> LawParams<T> {
    /// The parameters under which two reference impacts have the
    /// restitution coefficients (`e = u'/u`, normal separation speed over
    /// normal approach speed) `ball_restitution` and `wall_restitution`:
    ///
    /// - `ball_restitution`: two bodies of **equal mass** meeting
    ///   **head-on** (their relative velocity along the normal, no
    ///   tangential part). The law's `e = sqrt(1 − q)` with
    ///   `q = 2 d̃ ρ (t + 2 + 1/t)` (see [`Law`](crate::Law)) has `t = 1` and
    ///   `ρ = 1` there, so `e = sqrt(1 − 8 d̃)` and
    ///
    ///   ```text
    ///   d̃ = (1 − e_ball²) / 8.
    ///   ```
    /// - `wall_restitution`: a body of any mass hitting a **fixed or
    ///   kinematic** body **head-on** under [`FixedPartner::OwnMass`] (which
    ///   these parameters select): `q = 2 d̃_w ρ`, so `e = sqrt(1 − 2 d̃_w)` and
    ///
    ///   ```text
    ///   d̃_w = (1 − e_wall²) / 2.
    ///   ```
    ///
    /// `1 − e²` is computed as `(1 − e)(1 + e)` (accurate near `e = 1`); the
    /// law resolves either reference impact back to its `e` with `q` within
    /// a few ulps `ε` of `1 − e²` (`crates/kimpact/tests/restitution.rs`),
    /// so `e` within about `ε/e`: 1e-12 in f64 for `e ≥ 4e-4`, 1e-5 in f32
    /// for `e ≥ 0.05`. `e = 1` is elastic (`d̃ = 0`); `e = 0` is exactly
    /// plastic (`q = 1`, not clamped) along an axis, and sits on the clamp:
    /// along another normal, `ρ` rounded a few ulps off 1 gives
    /// `e ≈ sqrt(ε)` or the clamp's `1e-3`, never more.
    ///
    /// **Every other impact has another restitution**, because the law
    /// dissipates `d = d̃ (m₁ + m₂) |w|²` (`w` the relative velocity,
    /// tangential part included) out of the normal motion alone. With `r`
    /// the mass ratio (`t = 1/r`) and `θ` the angle between `w` and the
    /// normal (`ρ = 1/cos²θ`):
    ///
    /// ```text
    /// e = sqrt(1 − (1 − e_ball²) (r + 2 + 1/r) / (4 cos²θ))   two finite masses,
    /// e = sqrt(1 − (1 − e_wall²) / cos²θ)                      against a wall,
    /// ```
    ///
    /// clamped (to `e = 1e-3`, see [`CLAMP_TOLERANCE`](crate::CLAMP_TOLERANCE))
    /// where the root would be negative: with `e_ball = 0.8` a head-on impact
    /// of masses 1:10 is already clamped. `docs/restitution.md` tabulates `e` over mass ratio
    /// and angle.
    ///
    /// # Why a law for small `e` clamps oblique impacts
    ///
    /// `d` includes the tangential speed, but only the normal motion can
    /// give it up. With `θ` the impact angle (between `w` and the normal),
    /// `ρ = (|w|/u)² = 1 + tan²θ`, and the share of the normal energy
    /// `½ μ u²` the law asks for is
    ///
    /// ```text
    /// q = 2 d̃ ρ (M/μ)      (M/μ = 4 for equal masses, so q = (1 − e_ball²) ρ)
    /// ```
    ///
    /// For equal masses the impact is clamped as soon as
    /// `(1 − e_ball²)(1 + tan²θ) > 1`, i.e. beyond `θ = arcsin(e_ball)`: a
    /// law for `e = 0` clamps **every** oblique impact (only head-on ones
    /// are plastic without a clamp), one for `e = 0.5` everything beyond
    /// 30°, one for `e = 0.9` beyond 64.2°. That is the law, not a
    /// numerical failure: the clamp keeps `e = 1e-3` and takes what the
    /// normal motion holds. The impact reports what it could not take in
    /// [`Impact::unmet_dissipation`](crate::Impact::unmet_dissipation)
    /// (`½ μ u² (q − 1 + 10⁻⁶)`), so a rounding clamp (`q` a few ulps over
    /// 1, unmet about `10⁻⁶ · ½ μ u²`) is told from a law clamp (unmet of
    /// the order of `½ μ u²`). Effective restitution for equal masses, or
    /// "clamped" with the `q` asked (the unmet share of `½ μ u²` is
    /// `q − 1 + 10⁻⁶`):
    ///
    // table: begin (generated by crates/kimpact/tests/clamps.rs)
    /// | impact angle θ | e = 0 | e = 0.5 | e = 0.9 |
    /// | ---: | ---: | ---: | ---: |
    /// | 0° | 0.0000 | 0.5000 | 0.9000 |
    /// | 10° | clamped, q = 1.03 | 0.4761 | 0.8967 |
    /// | 20° | clamped, q = 1.13 | 0.3881 | 0.8859 |
    /// | 25° | clamped, q = 1.22 | 0.2948 | 0.8767 |
    /// | 35° | clamped, q = 1.49 | clamped, q = 1.12 | 0.8467 |
    /// | 45° | clamped, q = 2.00 | clamped, q = 1.50 | 0.7874 |
    /// | 60° | clamped, q = 4.00 | clamped, q = 3.00 | 0.4899 |
    /// | 63° | clamped, q = 4.85 | clamped, q = 3.64 | 0.2796 |
    /// | 66° | clamped, q = 6.04 | clamped, q = 4.53 | clamped, q = 1.15 |
    /// | 80° | clamped, q = 33.16 | clamped, q = 24.87 | clamped, q = 6.30 |
    /// | clamps beyond | 0.0° | 30.0° | 64.2° |
    // table: end
    ///
    /// # Errors
    /// [`LawError::InvalidRestitution`] naming `ball_restitution` or
    /// `wall_restitution` if it is NaN or outside `[0, 1]`.
    ///
    /// ```
    /// use kimpact::{Body, Law, LawParams};
    /// use kimpact::nalgebra::Vector2;
    ///
    /// let law = Law::new(LawParams::from_restitution(0.8_f64, 0.9)?)?;
    /// let a = Body::new(2.0, Vector2::new(3.0, 0.0))?;
    /// let b = Body::new(2.0, Vector2::zeros())?;
    /// let impact = law.resolve(&a, &b, &Vector2::x())?.expect("approaching");
    /// assert!((impact.restitution - 0.8).abs() < 1e-12);
    /// # Ok::<(), kimpact::LawError>(())
    /// ```
    pub fn from_restitution(ball_restitution: T, wall_restitution: T) -> Result<Self, LawError> {
        let ball = check_restitution(ball_restitution, "ball_restitution")?;
        let wall = check_restitution(wall_restitution, "wall_restitution")?;
        let one = T::one();
        let loss = |e: T| (one - e) * (one + e);
        Ok(Self {
            dissipation: loss(ball) * T::from_subset(&0.125),
            wall_dissipation: Some(loss(wall) * half::<T>()),
            fixed_partner: FixedPartner::OwnMass,
        })
    }
}

fn check_restitution<T: RealField + Copy>(
    value: T,
    parameter: &'static str,
) -> Result<T, LawError> {
    // NaN fails both comparisons.
    if value >= T::zero() && value <= T::one() {
        Ok(value)
    } else {
        Err(LawError::InvalidRestitution {
            parameter,
            value: to_f64(value),
        })
    }
}

pub(crate) fn check_dissipation<T: RealField + Copy>(
    value: T,
    parameter: &'static str,
) -> Result<T, LawError> {
    if value.is_finite() && value >= T::zero() {
        Ok(value)
    } else {
        Err(LawError::InvalidDissipation {
            parameter,
            value: to_f64(value),
        })
    }
}
