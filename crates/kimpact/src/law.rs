//! The mass-weighted k-update, in a form that is exact to a few ulps.

use nalgebra::{RealField, SVector};

use crate::body::{Body, Mass};
use crate::error::{LawError, Which};
use crate::impact::{Impact, Restitution};
use crate::num::{half, infinity, to_f64, unit_normal};
use crate::params::{FixedPartner, LawParams, check_dissipation};

/// Relative tolerance by which the dissipation is reduced below its largest
/// admissible value when the note's quadratic has complex roots (the
/// "clamped" case). A clamped impact keeps `sqrt(1e-6) = 1e-3` of its normal
/// approach speed.
pub const CLAMP_TOLERANCE: f64 = 1e-6;

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

/// What [`Law::coefficient`] found: `q` and `e` as used, and by how much
/// the asked `q` exceeded the used one.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Coefficient<T> {
    /// The `q = 2 d/(μ u²)` used (`1 − tol` when clamped).
    pub(crate) q: T,
    /// `e = sqrt(1 − q)`.
    pub(crate) e: T,
    /// Whether the asked `q` exceeded 1.
    pub(crate) clamped: bool,
    /// Asked `q` less used `q`: zero unless clamped, infinite when the ask
    /// is unbounded.
    pub(crate) excess: T,
}

impl<T: RealField + Copy> Coefficient<T> {
    /// The unmet dissipation `½ μ u² (q_asked − q_used)` for the effective
    /// mass `mass` and approach speed `u`: zero when not clamped, `+∞`
    /// when the ask is unbounded (never NaN: `∞ · 0` is not formed).
    #[inline]
    pub(crate) fn unmet(&self, mass: T, u: T) -> T {
        if self.excess == T::zero() {
            T::zero()
        } else if !self.excess.is_finite() {
            infinity()
        } else {
            half::<T>() * mass * u * u * self.excess
        }
    }
}

/// The mass factors of a pair, computed without multiplying masses.
#[derive(Copy, Clone, Debug)]
pub(crate) struct PairMasses<T> {
    /// `m_a / M`: scales `Δv_b`.
    pub(crate) frac_a: T,
    /// `m_b / M`: scales `Δv_a`.
    pub(crate) frac_b: T,
    /// `μ = m_a m_b / M` (the finite mass against an immovable partner).
    pub(crate) reduced: T,
    /// `M / μ = M² / (m_a m_b)`, computed only when d̃ > 0.
    growth: Growth<T>,
    /// Whether one partner is immovable.
    wall: bool,
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
    pub(crate) fn pair_masses(&self, a: Mass<T>, b: Mass<T>) -> Option<PairMasses<T>> {
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
    ///
    /// `factor` multiplies `M/μ` (the rigid law's `1 + μ (a₁ + a₂)`, so
    /// that `M/μ · factor = M/m_eff`); the ball law passes exactly 1.
    pub(crate) fn coefficient(
        &self,
        pair: &PairMasses<T>,
        rho: impl FnOnce() -> T,
        factor: T,
    ) -> Coefficient<T> {
        let dissipation = if pair.wall && self.fixed_partner == FixedPartner::OwnMass {
            self.wall_dissipation
        } else {
            self.dissipation
        };
        let one = T::one();
        if dissipation == T::zero() {
            return Coefficient {
                q: T::zero(),
                e: one,
                clamped: false,
                excess: T::zero(),
            };
        }
        let growth = match pair.growth {
            Growth::Ratio(t) => Some(t + (one + one) + one / t),
            Growth::One => Some(one),
            Growth::Infinite => None,
        };
        let q = growth.map(|growth| (dissipation + dissipation) * rho() * (growth * factor));
        match q {
            Some(q) if q <= one => Coefficient {
                q,
                e: (one - q).sqrt(),
                clamped: false,
                excess: T::zero(),
            },
            // Complex roots (or an infinite q): reduce d to (1 − tol) d_max,
            // so that e² = 1 − q = tol. `e` is taken from tol directly: in
            // f32, 1 − (1 − 1e-6) would be off by 1.3%.
            _ => {
                let tol = T::from_subset(&CLAMP_TOLERANCE);
                let used = one - tol;
                Coefficient {
                    q: used,
                    e: tol.sqrt(),
                    clamped: true,
                    // The asked q less the used one (≥ tol); infinite for a
                    // literal wall or a q beyond the type's range.
                    excess: match q {
                        Some(q) => q - used,
                        None => infinity(),
                    },
                }
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
        let c = self.coefficient(&pair, || rho, T::one());
        Ok(Some(Restitution {
            coefficient: c.e,
            clamped: c.clamped,
            unmet_dissipation: c.unmet(pair.reduced, approach_speed),
        }))
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
    /// no error path: the hot loop of an engine integration.
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
        let c = self.coefficient(
            &pair,
            || {
                // ρ = (|w|/u)². For a subnormal u, 1/u overflows and a zero
                // component of w would make ρ NaN (then misread as clamped):
                // divide instead on that rare path.
                let inverse = T::one() / approach_speed;
                if inverse.is_finite() {
                    (w * inverse).norm_squared()
                } else {
                    (w / approach_speed).norm_squared()
                }
            },
            T::one(),
        );
        let e = c.e;
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
            dissipated: if c.q == T::zero() {
                T::zero()
            } else {
                half::<T>() * pair.reduced * approach_speed * approach_speed * c.q
            },
            clamped: c.clamped,
            unmet_dissipation: c.unmet(pair.reduced, approach_speed),
        })
    }
}
