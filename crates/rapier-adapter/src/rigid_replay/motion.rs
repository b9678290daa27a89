//! A body's motion over a step as rapier integrates it: its centre of mass
//! on a straight line, its rotation about that centre at a constant
//! angular velocity (parry's `NonlinearRigidMotion`), and the angular
//! quantities of this dimension between rapier (glam) and the law
//! (nalgebra).

use crate::math::{Pose, Real, Vector};
use crate::rapier::math::AngVector;
use crate::rapier::parry::query::NonlinearRigidMotion;

/// A body on a path: at `t_ref` it has the pose `pose`; its centre of mass
/// (`local_com` in its own frame) moves at `linvel` and it turns about that
/// centre at `angvel`.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Motion {
    pub pose: Pose,
    pub local_com: Vector,
    pub linvel: Vector,
    pub angvel: AngVector,
    pub t_ref: Real,
}

impl Motion {
    /// A body that stays at `pose`.
    pub(crate) fn still(pose: Pose) -> Self {
        Self {
            pose,
            local_com: Vector::ZERO,
            linvel: Vector::ZERO,
            angvel: zero_angvel(),
            t_ref: 0.0,
        }
    }

    /// The path from `start` (at time 0) to `end` (at `dt`) of a body whose
    /// centre of mass is `local_com` in its frame: the centre's straight
    /// line, and the rotation between the two orientations about it (the
    /// turn nearest to `angvel dt`, rapier's angular velocity over the
    /// step, in 2D; the shortest one in 3D).
    pub(crate) fn between(
        start: Pose,
        end: Pose,
        local_com: Vector,
        angvel: AngVector,
        dt: Real,
    ) -> Self {
        let (c0, c1) = (start * local_com, end * local_com);
        Self {
            pose: start,
            local_com,
            linvel: (c1 - c0) / dt,
            angvel: turn_between(&start, &end, angvel, dt) / dt,
            t_ref: 0.0,
        }
    }

    /// parry's motion of this path, rebased to start at time `t`.
    pub(crate) fn nonlinear_at(&self, t: Real) -> NonlinearRigidMotion {
        NonlinearRigidMotion::new(self.pose_at(t), self.local_com, self.linvel, self.angvel)
    }

    /// The body's pose at time `t`.
    pub(crate) fn pose_at(&self, t: Real) -> Pose {
        NonlinearRigidMotion::new(self.pose, self.local_com, self.linvel, self.angvel)
            .position_at_time(t - self.t_ref)
    }

    /// The world centre of mass at time `t`: on its straight line (the
    /// turn is about it), without the turn's rotation.
    pub(crate) fn com_at(&self, t: Real) -> Vector {
        self.pose * self.local_com + self.linvel * (t - self.t_ref)
    }

    /// Bend the path at time `t`: from there the centre moves at
    /// `linvel + dv` and the body turns at `angvel + dw`.
    pub(crate) fn bend(&mut self, t: Real, dv: Vector, dw: AngVector) {
        self.pose = self.pose_at(t);
        self.t_ref = t;
        self.linvel += dv;
        self.angvel += dw;
    }

    /// The largest speed of a point of the body within `reach` of its
    /// centre of mass relative to the centre.
    pub(crate) fn turn_speed(&self, reach: Real) -> Real {
        angular_speed(self.angvel) * reach
    }

    /// The largest speed along the unit vector `n` of a point of the body
    /// within `reach` of its centre of mass relative to the centre:
    /// `(ω × r)·n = r·(n × ω) ≤ reach |n × ω|` (in 2D, where `ω` is normal
    /// to every `n`, [`Motion::turn_speed`]).
    pub(crate) fn turn_speed_along(&self, n: Vector, reach: Real) -> Real {
        turn_across(self.angvel, n) * reach
    }
}

/// The rotation angle (2D) taking `start` to `end`, the one nearest
/// `angvel dt`.
#[cfg(feature = "dim2")]
#[allow(clippy::unnecessary_cast)] // f64's π is the f64 build's `Real`
fn turn_between(start: &Pose, end: &Pose, angvel: AngVector, dt: Real) -> AngVector {
    use std::f64::consts::PI;
    let expected = angvel * dt;
    let turn = end.rotation.angle() - start.rotation.angle() - expected;
    let pi = PI as Real;
    let wrapped = turn - (2.0 * pi) * ((turn + pi) / (2.0 * pi)).floor();
    expected + wrapped
}

/// The rotation vector (3D, axis times angle) taking `start` to `end`, the
/// shortest.
#[cfg(feature = "dim3")]
fn turn_between(start: &Pose, end: &Pose, _angvel: AngVector, _dt: Real) -> AngVector {
    let mut q = end.rotation * start.rotation.inverse();
    if q.w < 0.0 {
        q = -q;
    }
    q.to_scaled_axis()
}

/// No rotation.
pub(crate) fn zero_angvel() -> AngVector {
    Default::default()
}

/// `|n × ω|` for a unit `n` in the plane: `|ω|`.
#[cfg(feature = "dim2")]
fn turn_across(w: AngVector, _n: Vector) -> Real {
    w.abs()
}

/// `|n × ω|`.
#[cfg(feature = "dim3")]
fn turn_across(w: AngVector, n: Vector) -> Real {
    n.cross(w).length()
}

/// `|ω|`.
#[cfg(feature = "dim2")]
pub(crate) fn angular_speed(w: AngVector) -> Real {
    w.abs()
}

/// `|ω|`.
#[cfg(feature = "dim3")]
pub(crate) fn angular_speed(w: AngVector) -> Real {
    w.length()
}

/// rapier's angular velocity as the law's.
#[cfg(feature = "dim2")]
pub(crate) fn to_law_angular(w: AngVector) -> kimpact::Angular<Real, { crate::math::DIM }> {
    w
}

/// rapier's angular velocity as the law's.
#[cfg(feature = "dim3")]
pub(crate) fn to_law_angular(w: AngVector) -> kimpact::Angular<Real, { crate::math::DIM }> {
    nalgebra::Vector3::new(w.x, w.y, w.z)
}

/// The law's angular velocity as rapier's.
#[cfg(feature = "dim2")]
pub(crate) fn from_law_angular(w: &kimpact::Angular<Real, { crate::math::DIM }>) -> AngVector {
    *w
}

/// The law's angular velocity as rapier's.
#[cfg(feature = "dim3")]
pub(crate) fn from_law_angular(w: &kimpact::Angular<Real, { crate::math::DIM }>) -> AngVector {
    AngVector::new(w[0], w[1], w[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path between two poses passes through both, with its centre of
    /// mass on the straight line between them at every instant.
    #[test]
    fn a_path_between_two_poses_reaches_the_second_at_dt() {
        let com = Vector::splat(0.1);
        #[cfg(feature = "dim2")]
        let (start, end, w) = (
            Pose::new(Vector::new(1.0, 2.0), 0.3),
            Pose::new(Vector::new(1.5, 1.0), 0.5),
            10.0,
        );
        #[cfg(feature = "dim3")]
        let (start, end, w) = (
            Pose::new(Vector::new(1.0, 2.0, 0.5), AngVector::new(0.1, 0.2, 0.3)),
            Pose::new(Vector::new(1.5, 1.0, 0.2), AngVector::new(0.2, 0.1, 0.35)),
            AngVector::ZERO,
        );
        let dt = 0.02;
        let motion = Motion::between(start, end, com, w, dt);
        let at = motion.pose_at(dt);
        let tol = 1e3 * Real::EPSILON;
        assert!(
            (at.translation - end.translation).length() < tol,
            "{at:?} {end:?}"
        );
        assert!(((at * com) - (end * com)).length() < tol);
        let mid = motion.com_at(0.5 * dt);
        assert!((mid - 0.5 * (start * com + end * com)).length() < tol);
    }
}
