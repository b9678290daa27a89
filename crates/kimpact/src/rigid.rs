//! A rigid body as the law sees it (mass, linear and angular velocity,
//! world inverse inertia) and the contact between two of them (the arms
//! from each centre of mass to the contact point, and the normal).

use nalgebra::{Const, RealField, SVector};

use crate::body::{Body, Mass, check_mass, check_velocity};
use crate::dim::RigidDim;
use crate::error::{LawError, Which};
use crate::num::{to_f64, unit_normal};

/// The angular velocity type of dimension `D`: `T` in 2D, `Vector3<T>` in
/// 3D.
pub type Angular<T, const D: usize> = <Const<D> as RigidDim<T, D>>::Angular;

/// The world inverse inertia type of dimension `D`: `T` in 2D,
/// `Matrix3<T>` in 3D.
pub type InverseInertia<T, const D: usize> = <Const<D> as RigidDim<T, D>>::InverseInertia;

/// A rigid body as the law sees it: mass `m`, velocity `v` of the centre
/// of mass, angular velocity `ω` and world-frame inverse inertia `I⁻¹`.
/// Built only through checked constructors, so every `RigidBody` holds
/// finite data and a positive semidefinite, symmetric `I⁻¹`.
///
/// A fixed or kinematic body ([`RigidBody::immovable`]) has infinite mass
/// and inertia: `I⁻¹ = 0`, and the impact changes neither of its
/// velocities, which still move its contact point (`v + ω × r`).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RigidBody<T: RealField + Copy, const D: usize>
where
    Const<D>: RigidDim<T, D>,
{
    pub(crate) mass: Mass<T>,
    pub(crate) velocity: SVector<T, D>,
    pub(crate) angular_velocity: Angular<T, D>,
    pub(crate) inverse_inertia: InverseInertia<T, D>,
}

impl<T: RealField + Copy, const D: usize> RigidBody<T, D>
where
    Const<D>: RigidDim<T, D>,
{
    /// A body of finite mass `mass`, moving at `velocity` and turning at
    /// `angular_velocity`, with world-frame inverse inertia
    /// `inverse_inertia` (`1/I ≥ 0` in 2D; in 3D the symmetric positive
    /// semidefinite `R diag(1/I₁, 1/I₂, 1/I₃) Rᵀ`, `R` the body's principal
    /// axes in the world; zero rows and columns lock rotations).
    ///
    /// A 3D matrix is accepted when symmetric and semidefinite to
    /// rounding (64 ulps of its largest entry) and then used exactly
    /// symmetric, `(I⁻¹ + I⁻ᵀ)/2`.
    ///
    /// # Errors
    /// [`LawError::NonFiniteMass`], [`LawError::NonPositiveMass`],
    /// [`LawError::NonFiniteVelocity`], [`LawError::NonFiniteAngularVelocity`],
    /// [`LawError::NonFiniteInertia`], [`LawError::AsymmetricInertia`] or
    /// [`LawError::NegativeInertia`], each naming the component.
    pub fn new(
        mass: T,
        velocity: SVector<T, D>,
        angular_velocity: Angular<T, D>,
        inverse_inertia: InverseInertia<T, D>,
    ) -> Result<Self, LawError> {
        Ok(Self {
            mass: Mass::Finite(check_mass(mass, Which::Body)?),
            velocity: check_velocity(velocity, Which::Body)?,
            angular_velocity: <Const<D>>::check_angular_velocity(angular_velocity, Which::Body)?,
            inverse_inertia: <Const<D>>::check_inverse_inertia(inverse_inertia, Which::Body)?,
        })
    }

    /// A fixed or kinematic body (infinite mass and inertia) moving at
    /// `velocity` and turning at `angular_velocity` (both zero for a fixed
    /// body).
    ///
    /// # Errors
    /// [`LawError::NonFiniteVelocity`] or
    /// [`LawError::NonFiniteAngularVelocity`].
    pub fn immovable(
        velocity: SVector<T, D>,
        angular_velocity: Angular<T, D>,
    ) -> Result<Self, LawError> {
        Ok(Self {
            mass: Mass::Infinite,
            velocity: check_velocity(velocity, Which::Body)?,
            angular_velocity: <Const<D>>::check_angular_velocity(angular_velocity, Which::Body)?,
            inverse_inertia: <Const<D>>::zero_inverse_inertia(),
        })
    }

    /// The body's mass.
    pub fn mass(&self) -> Mass<T> {
        self.mass
    }

    /// The velocity of the centre of mass.
    pub fn velocity(&self) -> &SVector<T, D> {
        &self.velocity
    }

    /// The angular velocity (world frame).
    pub fn angular_velocity(&self) -> &Angular<T, D> {
        &self.angular_velocity
    }

    /// The world-frame inverse inertia (zero for an immovable body).
    pub fn inverse_inertia(&self) -> &InverseInertia<T, D> {
        &self.inverse_inertia
    }

    /// `u = v + ω × r`, the velocity of the body's material point at arm
    /// `r` from its centre of mass.
    pub fn point_velocity(&self, arm: &SVector<T, D>) -> SVector<T, D> {
        self.velocity + <Const<D>>::velocity_at(&self.angular_velocity, arm)
    }
}

impl<T: RealField + Copy, const D: usize> From<Body<T, D>> for RigidBody<T, D>
where
    Const<D>: RigidDim<T, D>,
{
    /// The ball law's body as a rigid body that does not turn (`ω = 0`,
    /// `I⁻¹ = 0`): [`Law::resolve_rigid`](crate::Law::resolve_rigid) gives
    /// it the ball law's result bit for bit.
    fn from(body: Body<T, D>) -> Self {
        Self {
            mass: body.mass,
            velocity: body.velocity,
            angular_velocity: <Const<D>>::zero_angular(),
            inverse_inertia: <Const<D>>::zero_inverse_inertia(),
        }
    }
}

/// Where two rigid bodies touch: the arms `r_a = p − c_a`, `r_b = p − c_b`
/// from each centre of mass `c` to the contact point `p`, and the unit
/// normal `n̄` from `a` towards `b`. Built only through checked
/// constructors.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Contact<T: RealField + Copy, const D: usize> {
    arm_a: SVector<T, D>,
    arm_b: SVector<T, D>,
    normal: SVector<T, D>,
}

impl<T: RealField + Copy, const D: usize> Contact<T, D> {
    /// A contact with arms `arm_a`, `arm_b` and a normal from `a` towards
    /// `b` of any length (it is normalized).
    ///
    /// # Errors
    /// [`LawError::NonFiniteArm`] (naming the first or second body),
    /// [`LawError::NonFiniteNormal`] or [`LawError::ZeroNormal`].
    pub fn new(
        arm_a: SVector<T, D>,
        arm_b: SVector<T, D>,
        normal: SVector<T, D>,
    ) -> Result<Self, LawError> {
        let normal = unit_normal(&normal)?;
        Self::with_unit_normal(arm_a, arm_b, normal)
    }

    /// A contact at point `point` between bodies whose centres of mass are
    /// `centre_a` and `centre_b`: arms `point − centre`.
    ///
    /// # Errors
    /// As [`Contact::new`]; a non-finite arm (from non-finite points, or an
    /// overflowing difference) is [`LawError::NonFiniteArm`].
    pub fn at_point(
        point: SVector<T, D>,
        centre_a: SVector<T, D>,
        centre_b: SVector<T, D>,
        normal: SVector<T, D>,
    ) -> Result<Self, LawError> {
        Self::new(point - centre_a, point - centre_b, normal)
    }

    /// [`Contact::new`] for a normal the caller guarantees to be a finite
    /// unit vector (as a physics engine's contact normal is): only the
    /// arms are checked, nothing is normalized.
    ///
    /// # Errors
    /// [`LawError::NonFiniteArm`].
    pub fn with_unit_normal(
        arm_a: SVector<T, D>,
        arm_b: SVector<T, D>,
        normal: SVector<T, D>,
    ) -> Result<Self, LawError> {
        Ok(Self {
            arm_a: check_arm(arm_a, Which::First)?,
            arm_b: check_arm(arm_b, Which::Second)?,
            normal,
        })
    }

    /// `r_a = p − c_a`.
    pub fn arm_a(&self) -> &SVector<T, D> {
        &self.arm_a
    }

    /// `r_b = p − c_b`.
    pub fn arm_b(&self) -> &SVector<T, D> {
        &self.arm_b
    }

    /// The unit normal `n̄`, from `a` towards `b`.
    pub fn normal(&self) -> &SVector<T, D> {
        &self.normal
    }
}

fn check_arm<T: RealField + Copy, const D: usize>(
    arm: SVector<T, D>,
    which: Which,
) -> Result<SVector<T, D>, LawError> {
    match arm.iter().position(|c| !c.is_finite()) {
        None => Ok(arm),
        Some(component) => Err(LawError::NonFiniteArm {
            which,
            component,
            value: to_f64(arm[component]),
        }),
    }
}
