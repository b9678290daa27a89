//! A body as the ball law sees it: a mass (finite or infinite) and a
//! linear velocity, checked when built.

use nalgebra::{RealField, SVector};

use crate::error::{LawError, Which};
use crate::num::{half, to_f64};

/// The mass of a body taking part in an impact.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Mass<T> {
    /// A finite, positive mass.
    Finite(T),
    /// A fixed or kinematic body: its velocity is prescribed and the impact
    /// does not change it. See [`FixedPartner`](crate::FixedPartner) for
    /// how the law treats it.
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

    pub(crate) fn checked(self, which: Which) -> Result<Self, LawError> {
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
    pub(crate) mass: Mass<T>,
    pub(crate) velocity: SVector<T, D>,
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

pub(crate) fn check_mass<T: RealField + Copy>(mass: T, which: Which) -> Result<T, LawError> {
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

pub(crate) fn check_velocity<T: RealField + Copy, const D: usize>(
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

#[inline]
pub(crate) fn kinetic_energy<T: RealField + Copy, const D: usize>(
    mass: Mass<T>,
    v: &SVector<T, D>,
) -> T {
    match mass {
        Mass::Finite(m) => m * v.norm_squared() * half::<T>(),
        Mass::Infinite => T::zero(),
    }
}
