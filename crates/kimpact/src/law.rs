//! The mass-weighted k-update, in a form that is exact to a few ulps.

use nalgebra::{RealField, SVector};

use crate::error::{LawError, Which};

/// Relative tolerance by which the dissipation is reduced below its largest
/// admissible value when the note's quadratic has complex roots (the
/// "clamped" case). A clamped impact keeps `sqrt(1e-6) = 1e-3` of its normal
/// approach speed.
pub const CLAMP_TOLERANCE: f64 = 1e-6;

/// The mass of a body taking part in an impact.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Mass<T> {
    /// A finite, positive mass.
    Finite(T),
    /// A fixed or kinematic body: its velocity is prescribed and the impact
    /// does not change it. See [`FixedPartner`] for how the law treats it.
    Infinite,
}

impl<T: RealField + Copy> Mass<T> {
    /// A finite mass, checked to be finite and positive.
    pub fn finite(mass: T) -> Result<Self, LawError> {
        check_mass(mass, Which::Body).map(Mass::Finite)
    }

    /// Whether this is [`Mass::Infinite`].
    pub fn is_infinite(&self) -> bool {
        matches!(self, Mass::Infinite)
    }

    fn checked(self, which: Which) -> Result<Self, LawError> {
        match self {
            Mass::Finite(m) => check_mass(m, which).map(Mass::Finite),
            Mass::Infinite => Ok(Mass::Infinite),
        }
    }
}

/// A body as the law sees it: a mass and a linear velocity. Built only
/// through checked constructors, so every `Body` holds finite data.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Body<T: RealField + Copy, const D: usize> {
    mass: Mass<T>,
    velocity: SVector<T, D>,
}

impl<T: RealField + Copy, const D: usize> Body<T, D> {
    /// A body of finite mass `mass` moving at `velocity`.
    ///
    /// # Errors
    /// [`LawError::NonFiniteMass`], [`LawError::NonPositiveMass`] or
    /// [`LawError::NonFiniteVelocity`].
    pub fn new(mass: T, velocity: SVector<T, D>) -> Result<Self, LawError> {
        Ok(Self {
            mass: Mass::Finite(check_mass(mass, Which::Body)?),
            velocity: check_velocity(velocity, Which::Body)?,
        })
    }

    /// A fixed or kinematic body (infinite mass) moving at `velocity`
    /// (zero for a fixed body).
    ///
    /// # Errors
    /// [`LawError::NonFiniteVelocity`].
    pub fn immovable(velocity: SVector<T, D>) -> Result<Self, LawError> {
        Ok(Self {
            mass: Mass::Infinite,
            velocity: check_velocity(velocity, Which::Body)?,
        })
    }

    /// The body's mass.
    pub fn mass(&self) -> Mass<T> {
        self.mass
    }

    /// The body's velocity.
    pub fn velocity(&self) -> &SVector<T, D> {
        &self.velocity
    }

    /// Kinetic energy `½ m |v|²`; zero for an immovable body (whose energy
    /// the law never changes).
    pub fn kinetic_energy(&self) -> T {
        kinetic_energy(self.mass, &self.velocity)
    }
}

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
/// into a [`Law`] with [`Law::new`], which checks them.
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
    /// here: [`Law::new`] checks the result, as any parameters.
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
    ///   `q = 2 d̃ ρ (t + 2 + 1/t)` (see [`Law`]) has `t = 1` and `ρ = 1`
    ///   there, so `e = sqrt(1 − 8 d̃)` and
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
    /// clamped (to `e = 1e-3`, see [`CLAMP_TOLERANCE`]) where the root would
    /// be negative: with `e_ball = 0.8` a head-on impact of masses 1:10 is
    /// already clamped. `docs/restitution.md` tabulates `e` over mass ratio
    /// and angle.
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

/// The mass-weighted k-update of `shared/seed/collision-events.md`.
///
/// For bodies 1 and 2 with masses `m₁, m₂`, velocities `v₁, v₂` and unit
/// normal `n̄₁ = n̄` from 1 towards the contact (`n̄₂ = −n̄`):
///
/// ```text
/// v₁' = v₁ + m₂ k n̄₂,      v₂' = v₂ + m₁ k n̄₁,
/// (m₁m₂(m₁+m₂)/2) k² + k m₁m₂ (v₁·n̄₂ + v₂·n̄₁) + d = 0,
/// d = d̃ (m₁+m₂) |v₂ − v₁|²,
/// ```
///
/// with the root of larger magnitude. Momentum is conserved, kinetic energy
/// drops by exactly `d`, and `d̃ = 0` is elastic. When the roots would be
/// complex, `d` is reduced to `(1 − 1e-6)` times its largest admissible value.
///
/// # How it is computed
/// With `w = v₂ − v₁`, the approach speed `u = −w·n̄ > 0`, the reduced mass
/// `μ = m₁m₂/M`, `M = m₁ + m₂` and `s = M k` (the change of the normal
/// relative velocity), the quadratic becomes
///
/// ```text
/// s² − 2 u s + 2 d / μ = 0   ⇒   s = u (1 + e),   e = sqrt(1 − q),
/// q = 2 d / (μ u²) = 2 d̃ (|w|/u)² (M²/(m₁m₂)),    M²/(m₁m₂) = t + 2 + 1/t,
/// ```
///
/// `t` the ratio of the smaller to the larger mass. The velocity changes are
/// `Δv₁ = −(m₂/M) s n̄` and `Δv₂ = (m₁/M) s n̄`, the mass fractions computed
/// from `t` alone. Nothing multiplies two masses, nothing subtracts nearly
/// equal energies: the result is exact to a few ulps in f32 and f64 for any
/// masses and speeds whose ratios the type can hold, and `e` is the
/// effective restitution (`u' = e u`). The note's `k` is reported as `s/M`.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(
        try_from = "LawParams<T>",
        into = "LawParams<T>",
        bound(
            serialize = "T: RealField + Copy + serde::Serialize",
            deserialize = "T: RealField + Copy + serde::Deserialize<'de>"
        )
    )
)]
pub struct Law<T: RealField + Copy> {
    dissipation: T,
    wall_dissipation: T,
    wall_dissipation_set: bool,
    fixed_partner: FixedPartner,
}

/// The effective restitution of one impact, the view of the law a solver
/// with a restitution coefficient needs.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Restitution<T> {
    /// `e = u'/u ∈ [0, 1]`: the normal separation speed after the impact
    /// over the approach speed before.
    pub coefficient: T,
    /// Whether `d` had to be reduced (the note's complex-root case).
    pub clamped: bool,
}

/// The outcome of one impact between bodies `a` (1) and `b` (2).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Impact<T: RealField + Copy, const D: usize> {
    /// The unit normal `n̄₁`, from `a` towards `b`.
    pub normal: SVector<T, D>,
    /// `u = −(v_b − v_a)·n̄ > 0`, the normal approach speed before.
    pub approach_speed: T,
    /// `Δv_a = m_b k n̄₂ = −(m_b/M) s n̄`.
    pub delta_v_a: SVector<T, D>,
    /// `Δv_b = m_a k n̄₁ = (m_a/M) s n̄`.
    pub delta_v_b: SVector<T, D>,
    /// The impulse `J = μ s ≥ 0` along `n̄`, applied as `+J n̄` to `b` and
    /// `−J n̄` to `a` (for an immovable partner, `μ` is the finite mass).
    pub impulse: T,
    /// The effective restitution `e = u'/u`.
    pub restitution: T,
    /// The dissipation `d` actually used: the energy lost.
    pub dissipated: T,
    /// Whether `d` was reduced because the roots would have been complex.
    pub clamped: bool,
}

/// The kinetic energy of a pair of finite bodies before and after an impact
/// (immovable bodies count zero): see [`Impact::energies`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Energies<T> {
    /// `½ m_a |v_a|² + ½ m_b |v_b|²` before the impact.
    pub before: T,
    /// `½ m_a |v_a + Δv_a|² + ½ m_b |v_b + Δv_b|²` after it.
    pub after: T,
}

impl<T: RealField + Copy, const D: usize> Impact<T, D> {
    /// The speed change along the normal, `s = u (1 + e)`: the relative
    /// normal velocity goes from `−u` to `e u`.
    pub fn speed_change(&self) -> T {
        self.approach_speed * (T::one() + self.restitution)
    }

    /// The note's `k = s / M` for the masses this impact was resolved with
    /// (zero when a partner is immovable), so that `Δv_a = m_b k n̄₂` and
    /// `Δv_b = m_a k n̄₁`. For reference only: `k` can under- or overflow
    /// where `M = m_a + m_b` leaves the range of the type, and the law
    /// computes no velocity through it.
    pub fn k(&self, a: Mass<T>, b: Mass<T>) -> T {
        match (a, b) {
            (Mass::Finite(ma), Mass::Finite(mb)) => self.speed_change() / (ma + mb),
            _ => T::zero(),
        }
    }

    /// The kinetic energy of `a` and `b` (the bodies this impact was
    /// resolved with) before and after it. Computed on demand, not by
    /// [`Law::resolve`]: the adapters never need it, and computing it for
    /// every impact would slow each one. `before − after` equals
    /// [`dissipated`](Self::dissipated) up to rounding; the energies can
    /// overflow where `|v|²` leaves the type's range.
    pub fn energies(&self, a: &Body<T, D>, b: &Body<T, D>) -> Energies<T> {
        Energies {
            before: a.kinetic_energy() + b.kinetic_energy(),
            after: kinetic_energy(a.mass, &(a.velocity + self.delta_v_a))
                + kinetic_energy(b.mass, &(b.velocity + self.delta_v_b)),
        }
    }
}

/// `M / μ` of a pair, evaluated lazily (elastic impacts never need it).
#[derive(Copy, Clone, Debug)]
enum Growth<T> {
    /// Two finite masses with ratio `t = m_small / m_large`: `t + 2 + 1/t`.
    Ratio(T),
    /// An immovable partner under `OwnMass`: 1.
    One,
    /// An immovable partner under `Literal`: infinite.
    Infinite,
}

/// The mass factors of a pair, computed without multiplying masses.
#[derive(Copy, Clone, Debug)]
struct PairMasses<T> {
    /// `m_a / M`: scales `Δv_b`.
    frac_a: T,
    /// `m_b / M`: scales `Δv_a`.
    frac_b: T,
    /// `μ = m_a m_b / M` (the finite mass against an immovable partner).
    reduced: T,
    /// `M / μ = M² / (m_a m_b)`, computed only when d̃ > 0.
    growth: Growth<T>,
    /// Whether one partner is immovable.
    wall: bool,
}

fn check_mass<T: RealField + Copy>(mass: T, which: Which) -> Result<T, LawError> {
    if !mass.is_finite() {
        Err(LawError::NonFiniteMass {
            which,
            value: to_f64(mass),
        })
    } else if mass <= T::zero() {
        Err(LawError::NonPositiveMass {
            which,
            value: to_f64(mass),
        })
    } else {
        Ok(mass)
    }
}

fn check_velocity<T: RealField + Copy, const D: usize>(
    velocity: SVector<T, D>,
    which: Which,
) -> Result<SVector<T, D>, LawError> {
    match velocity.iter().position(|c| !c.is_finite()) {
        None => Ok(velocity),
        Some(component) => Err(LawError::NonFiniteVelocity {
            which,
            component,
            value: to_f64(velocity[component]),
        }),
    }
}

fn check_dissipation<T: RealField + Copy>(
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

/// The unit vector along `normal`, scaled first by its largest component so
/// that neither tiny nor huge normals under- or overflow.
pub(crate) fn unit_normal<T: RealField + Copy, const D: usize>(
    normal: &SVector<T, D>,
) -> Result<SVector<T, D>, LawError> {
    if let Some(component) = normal.iter().position(|c| !c.is_finite()) {
        return Err(LawError::NonFiniteNormal {
            component,
            value: to_f64(normal[component]),
        });
    }
    let scale = normal.amax();
    if scale == T::zero() {
        return Err(LawError::ZeroNormal);
    }
    let scaled = normal / scale;
    Ok(scaled / scaled.norm())
}

#[inline]
fn kinetic_energy<T: RealField + Copy, const D: usize>(mass: Mass<T>, v: &SVector<T, D>) -> T {
    match mass {
        Mass::Finite(m) => m * v.norm_squared() * half::<T>(),
        Mass::Infinite => T::zero(),
    }
}

fn half<T: RealField + Copy>() -> T {
    T::from_subset(&0.5)
}

fn to_f64<T: RealField + Copy>(x: T) -> f64 {
    x.to_subset().unwrap_or(f64::NAN)
}

impl<T: RealField + Copy> TryFrom<LawParams<T>> for Law<T> {
    type Error = LawError;
    fn try_from(params: LawParams<T>) -> Result<Self, LawError> {
        Law::new(params)
    }
}

impl<T: RealField + Copy> From<Law<T>> for LawParams<T> {
    fn from(law: Law<T>) -> Self {
        law.params()
    }
}

impl<T: RealField + Copy> Default for Law<T> {
    fn default() -> Self {
        Self::elastic()
    }
}

impl<T: RealField + Copy> Law<T> {
    /// The law with checked parameters.
    ///
    /// # Errors
    /// [`LawError::InvalidDissipation`] if `dissipation` or
    /// `wall_dissipation` is negative, NaN or infinite.
    pub fn new(params: LawParams<T>) -> Result<Self, LawError> {
        let dissipation = check_dissipation(params.dissipation, "dissipation")?;
        let wall_dissipation = match params.wall_dissipation {
            Some(w) => check_dissipation(w, "wall_dissipation")?,
            None => dissipation,
        };
        Ok(Self {
            dissipation,
            wall_dissipation,
            wall_dissipation_set: params.wall_dissipation.is_some(),
            fixed_partner: params.fixed_partner,
        })
    }

    /// The elastic law (`d̃ = 0`, elastic walls).
    pub fn elastic() -> Self {
        Self {
            dissipation: T::zero(),
            wall_dissipation: T::zero(),
            wall_dissipation_set: false,
            fixed_partner: FixedPartner::OwnMass,
        }
    }

    /// The law with dissipation constant `d̃` (also used against walls).
    ///
    /// `d̃` is not `1 − e`: two equal masses meeting head-on bounce with
    /// `e = sqrt(1 − 8 d̃)` (plastic from `d̃ = 1/8` on), a head-on impact
    /// on a wall with `e = sqrt(1 − 2 d̃)`. To choose the law from
    /// restitution coefficients, use [`Law::from_restitution`].
    ///
    /// # Errors
    /// [`LawError::InvalidDissipation`] if `d̃` is negative, NaN or infinite.
    pub fn with_dissipation(dissipation: T) -> Result<Self, LawError> {
        Self::new(LawParams {
            dissipation,
            ..LawParams::default()
        })
    }

    /// The law of [`LawParams::from_restitution`]: restitution
    /// `ball_restitution` for two equal masses meeting head-on, and
    /// `wall_restitution` for a head-on impact against a fixed or kinematic
    /// body ([`FixedPartner::OwnMass`]). Other impacts differ: see there.
    ///
    /// # Errors
    /// [`LawError::InvalidRestitution`] naming the coefficient that is NaN
    /// or outside `[0, 1]`.
    pub fn from_restitution(ball_restitution: T, wall_restitution: T) -> Result<Self, LawError> {
        Self::new(LawParams::from_restitution(
            ball_restitution,
            wall_restitution,
        )?)
    }

    /// The parameters this law was built from.
    pub fn params(&self) -> LawParams<T> {
        LawParams {
            dissipation: self.dissipation,
            wall_dissipation: self.wall_dissipation_set.then_some(self.wall_dissipation),
            fixed_partner: self.fixed_partner,
        }
    }

    /// `d̃`, the dissipation constant between two finite masses.
    pub fn dissipation(&self) -> T {
        self.dissipation
    }

    /// `d̃_w`, the dissipation constant against immovable partners under
    /// [`FixedPartner::OwnMass`].
    pub fn wall_dissipation(&self) -> T {
        self.wall_dissipation
    }

    /// The policy for immovable partners.
    pub fn fixed_partner(&self) -> FixedPartner {
        self.fixed_partner
    }

    /// Replace the parameters at run time. On error the law is unchanged.
    ///
    /// # Errors
    /// As [`Law::new`].
    pub fn set_params(&mut self, params: LawParams<T>) -> Result<(), LawError> {
        *self = Self::new(params)?;
        Ok(())
    }

    #[inline]
    fn pair_masses(&self, a: Mass<T>, b: Mass<T>) -> Option<PairMasses<T>> {
        let one = T::one();
        let wall_growth = match self.fixed_partner {
            FixedPartner::OwnMass => Growth::One,
            FixedPartner::Literal => Growth::Infinite,
        };
        match (a, b) {
            (Mass::Finite(ma), Mass::Finite(mb)) => {
                let a_lighter = ma <= mb;
                let lo = ma.min(mb);
                let hi = ma.max(mb);
                // t ∈ (0, 1]; every factor follows from t without a product
                // of two masses.
                let t = lo / hi;
                let frac_hi = one / (one + t);
                // frac_lo = t · frac_hi. Selecting the factor (t or 1)
                // rather than the product keeps the hot loop free of a
                // data-dependent branch (a random mass order mispredicts
                // half the time); multiplying by one is exact, so the
                // result is bit-for-bit the same.
                let (factor_a, factor_b) = if a_lighter { (t, one) } else { (one, t) };
                Some(PairMasses {
                    frac_a: factor_a * frac_hi,
                    frac_b: factor_b * frac_hi,
                    reduced: lo * frac_hi,
                    growth: Growth::Ratio(t),
                    wall: false,
                })
            }
            (Mass::Finite(m), Mass::Infinite) => Some(PairMasses {
                frac_a: T::zero(),
                frac_b: one,
                reduced: m,
                growth: wall_growth,
                wall: true,
            }),
            (Mass::Infinite, Mass::Finite(m)) => Some(PairMasses {
                frac_a: one,
                frac_b: T::zero(),
                reduced: m,
                growth: wall_growth,
                wall: true,
            }),
            (Mass::Infinite, Mass::Infinite) => None,
        }
    }

    /// `q = 2 d / (μ u²)` from `ρ = (|w|/u)²`, then the effective
    /// restitution. `q` may be infinite (grazing impacts, extreme mass
    /// ratios, literal walls): that is the clamped case, never a NaN.
    #[inline]
    fn coefficient(&self, pair: &PairMasses<T>, rho: impl FnOnce() -> T) -> (T, Restitution<T>) {
        let dissipation = if pair.wall && self.fixed_partner == FixedPartner::OwnMass {
            self.wall_dissipation
        } else {
            self.dissipation
        };
        let one = T::one();
        if dissipation == T::zero() {
            return (
                T::zero(),
                Restitution {
                    coefficient: one,
                    clamped: false,
                },
            );
        }
        let growth = match pair.growth {
            Growth::Ratio(t) => Some(t + (one + one) + one / t),
            Growth::One => Some(one),
            Growth::Infinite => None,
        };
        let q = growth.map(|growth| (dissipation + dissipation) * rho() * growth);
        match q {
            Some(q) if q <= one => (
                q,
                Restitution {
                    coefficient: (one - q).sqrt(),
                    clamped: false,
                },
            ),
            // Complex roots (or an infinite q): reduce d to (1 − tol) d_max,
            // so that e² = 1 − q = tol. `e` is taken from tol directly: in
            // f32, 1 − (1 − 1e-6) would be off by 1.3%.
            _ => {
                let tol = T::from_subset(&CLAMP_TOLERANCE);
                (
                    one - tol,
                    Restitution {
                        coefficient: tol.sqrt(),
                        clamped: true,
                    },
                )
            }
        }
    }

    /// The effective restitution for a pair of masses `a`, `b` approaching
    /// at normal speed `approach_speed` with relative tangential speed
    /// `tangential_speed`; `None` if `approach_speed <= 0` (no impact) or
    /// both masses are infinite.
    ///
    /// `e = sqrt(1 − q)`, `q = 2 d̃ (1 + (w_t/u)²)(m_a + m_b)²/(m_a m_b)`,
    /// clamped to `q = 1 − 1e-6`.
    ///
    /// # Errors
    /// On an invalid mass (naming the first or second body) or a non-finite
    /// or negative speed.
    pub fn restitution(
        &self,
        a: Mass<T>,
        b: Mass<T>,
        approach_speed: T,
        tangential_speed: T,
    ) -> Result<Option<Restitution<T>>, LawError> {
        let a = a.checked(Which::First)?;
        let b = b.checked(Which::Second)?;
        if !approach_speed.is_finite() {
            return Err(LawError::InvalidSpeed {
                quantity: "approach_speed",
                nonnegative: false,
                value: to_f64(approach_speed),
            });
        }
        if !(tangential_speed.is_finite() && tangential_speed >= T::zero()) {
            return Err(LawError::InvalidSpeed {
                quantity: "tangential_speed",
                nonnegative: true,
                value: to_f64(tangential_speed),
            });
        }
        if approach_speed <= T::zero() {
            return Ok(None);
        }
        let Some(pair) = self.pair_masses(a, b) else {
            return Ok(None);
        };
        let ratio = tangential_speed / approach_speed;
        let rho = T::one() + ratio * ratio;
        Ok(Some(self.coefficient(&pair, || rho).1))
    }

    /// Resolve one impact between `a` and `b`, `normal` pointing from `a`
    /// towards `b` (any length; it is normalized).
    ///
    /// Returns `Ok(None)` when the pair is not approaching along the normal
    /// (`(v_b − v_a)·n̄ >= 0`: the note's formula would pull it together),
    /// when both bodies are immovable, or when the relative velocity or the
    /// velocity change `u (1 + e) <= 2u` overflows the type (speeds beyond
    /// half its largest finite value): the law never reports a NaN.
    ///
    /// # Errors
    /// [`LawError::ZeroNormal`] or [`LawError::NonFiniteNormal`]. Bodies are
    /// checked when they are built.
    pub fn resolve<const D: usize>(
        &self,
        a: &Body<T, D>,
        b: &Body<T, D>,
        normal: &SVector<T, D>,
    ) -> Result<Option<Impact<T, D>>, LawError> {
        let n = unit_normal(normal)?;
        Ok(self.resolve_unit(a, b, &n))
    }

    /// [`Law::resolve`] for a normal the caller guarantees to be a finite
    /// unit vector (as a physics engine's contact normal is). No allocation,
    /// no error path: the hot loop of the adapters.
    #[inline]
    pub fn resolve_unit<const D: usize>(
        &self,
        a: &Body<T, D>,
        b: &Body<T, D>,
        n: &SVector<T, D>,
    ) -> Option<Impact<T, D>> {
        let w = b.velocity - a.velocity;
        let approach_speed = -w.dot(n);
        // `!(u > 0)` also rejects a NaN from an overflowing `w`.
        if !(approach_speed > T::zero() && approach_speed.is_finite()) {
            return None;
        }
        let pair = self.pair_masses(a.mass, b.mass)?;
        let (q, restitution) = self.coefficient(&pair, || {
            // ρ = (|w|/u)². For a subnormal u, 1/u overflows and a zero
            // component of w would make ρ NaN (then misread as clamped):
            // divide instead on that rare path.
            let inverse = T::one() / approach_speed;
            if inverse.is_finite() {
                (w * inverse).norm_squared()
            } else {
                (w / approach_speed).norm_squared()
            }
        });
        let e = restitution.coefficient;
        let s = approach_speed * (T::one() + e);
        // `s <= 2u` overflows only for u above half the largest finite
        // value: the velocity change is not representable (and `n̄ · ∞` would
        // put NaN into the zero components of Δv). No impact, as for an
        // overflowing `w`.
        if !s.is_finite() {
            return None;
        }
        let delta_v_a = n * (-(pair.frac_b * s));
        let delta_v_b = n * (pair.frac_a * s);
        Some(Impact {
            normal: *n,
            approach_speed,
            delta_v_a,
            delta_v_b,
            impulse: pair.reduced * s,
            restitution: e,
            // ½ μ u² may overflow: `∞ · 0` would be NaN for an elastic impact.
            dissipated: if q == T::zero() {
                T::zero()
            } else {
                half::<T>() * pair.reduced * approach_speed * approach_speed * q
            },
            clamped: restitution.clamped,
        })
    }
}
