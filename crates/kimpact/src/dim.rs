//! What changes with the dimension for a rotating body: the type of an
//! angular velocity and of an inverse inertia, the cross products, and the
//! checks of the inertia. Implemented for 2 and 3 dimensions only.

use core::fmt::Debug;

use nalgebra::{Const, Matrix3, RealField, SVector, Vector2, Vector3};

use crate::error::{LawError, Which};
use crate::num::to_f64;

mod sealed {
    /// Only `Const<2>` and `Const<3>` are rigid dimensions.
    pub trait Sealed {}
    impl Sealed for nalgebra::Const<2> {}
    impl Sealed for nalgebra::Const<3> {}
}

/// The dimensions a rigid body lives in, `Const<2>` and `Const<3>` (sealed):
/// the types and products that differ between them.
///
/// | | 2D (`Const<2>`) | 3D (`Const<3>`) |
/// | --- | --- | --- |
/// | [`Angular`](Self::Angular) (angular velocity, `r × n`) | `T` (counter-clockwise) | `Vector3<T>` |
/// | [`InverseInertia`](Self::InverseInertia) (world frame) | `T ≥ 0` | symmetric positive semidefinite `Matrix3<T>` |
/// | `r × n` | `r_x n_y − r_y n_x` | the cross product |
/// | `ω × r` | `ω (−r_y, r_x)` | the cross product |
///
/// The methods are the building blocks of
/// [`Law::resolve_rigid`](crate::Law::resolve_rigid); only the `check_`
/// ones check anything.
pub trait RigidDim<T: RealField + Copy, const D: usize>: sealed::Sealed {
    /// An angular velocity or a moment arm `r × n`: `T` in 2D,
    /// `Vector3<T>` in 3D.
    type Angular: Copy + Debug + PartialEq + Send + Sync + 'static;
    /// A world-frame inverse inertia: `T ≥ 0` in 2D, a symmetric positive
    /// semidefinite `Matrix3<T>` in 3D (zero for an immovable body or
    /// locked rotations).
    type InverseInertia: Copy + Debug + PartialEq + Send + Sync + 'static;

    /// The zero angular velocity.
    fn zero_angular() -> Self::Angular;
    /// The zero inverse inertia (infinite inertia: the body does not turn).
    fn zero_inverse_inertia() -> Self::InverseInertia;
    /// `r × n` (a scalar in 2D).
    fn cross(r: &SVector<T, D>, n: &SVector<T, D>) -> Self::Angular;
    /// `ω × r`, the velocity of the point at arm `r` from the centre of a
    /// body turning at `ω`, relative to the centre.
    fn velocity_at(omega: &Self::Angular, r: &SVector<T, D>) -> SVector<T, D>;
    /// `I⁻¹ k`.
    fn apply(inverse_inertia: &Self::InverseInertia, k: &Self::Angular) -> Self::Angular;
    /// `a · b`.
    fn dot(a: &Self::Angular, b: &Self::Angular) -> T;
    /// `a s`.
    fn scale(a: &Self::Angular, s: T) -> Self::Angular;
    /// `a + b`.
    fn add(a: &Self::Angular, b: &Self::Angular) -> Self::Angular;
    /// Whether every component of `a` is finite.
    fn is_finite(a: &Self::Angular) -> bool;
    /// The second unit tangent `n̄ × t̄₁` of the contact plane for unit
    /// `n̄ ⟂ t̄₁` (3D), or `None` (2D: the tangent is a line).
    fn second_tangent(n: &SVector<T, D>, t1: &SVector<T, D>) -> Option<SVector<T, D>>;
    /// `a` if every component is finite, else
    /// [`LawError::NonFiniteAngularVelocity`] naming the first bad one.
    ///
    /// # Errors
    /// As said.
    fn check_angular_velocity(a: Self::Angular, which: Which) -> Result<Self::Angular, LawError>;
    /// The inverse inertia, checked: finite ([`LawError::NonFiniteInertia`]),
    /// in 3D symmetric to rounding ([`LawError::AsymmetricInertia`], and
    /// then made exactly symmetric), and positive semidefinite to rounding
    /// ([`LawError::NegativeInertia`]).
    ///
    /// # Errors
    /// As said.
    fn check_inverse_inertia(
        inverse_inertia: Self::InverseInertia,
        which: Which,
    ) -> Result<Self::InverseInertia, LawError>;
}

/// 64 ulps: the tolerance of the 3D inertia checks, relative to the
/// largest entry.
fn tolerance<T: RealField + Copy>() -> T {
    T::default_epsilon() * T::from_subset(&64.0)
}

impl<T: RealField + Copy> RigidDim<T, 2> for Const<2> {
    type Angular = T;
    type InverseInertia = T;

    #[inline]
    fn zero_angular() -> T {
        T::zero()
    }
    #[inline]
    fn zero_inverse_inertia() -> T {
        T::zero()
    }
    #[inline]
    fn cross(r: &Vector2<T>, n: &Vector2<T>) -> T {
        r.x * n.y - r.y * n.x
    }
    #[inline]
    fn velocity_at(omega: &T, r: &Vector2<T>) -> Vector2<T> {
        Vector2::new(-(*omega * r.y), *omega * r.x)
    }
    #[inline]
    fn apply(inverse_inertia: &T, k: &T) -> T {
        *inverse_inertia * *k
    }
    #[inline]
    fn dot(a: &T, b: &T) -> T {
        *a * *b
    }
    #[inline]
    fn scale(a: &T, s: T) -> T {
        *a * s
    }
    #[inline]
    fn add(a: &T, b: &T) -> T {
        *a + *b
    }
    #[inline]
    fn is_finite(a: &T) -> bool {
        a.is_finite()
    }
    #[inline]
    fn second_tangent(_: &Vector2<T>, _: &Vector2<T>) -> Option<Vector2<T>> {
        None
    }
    fn check_angular_velocity(a: T, which: Which) -> Result<T, LawError> {
        if a.is_finite() {
            Ok(a)
        } else {
            Err(LawError::NonFiniteAngularVelocity {
                which,
                component: 0,
                value: to_f64(a),
            })
        }
    }
    fn check_inverse_inertia(inverse_inertia: T, which: Which) -> Result<T, LawError> {
        if !inverse_inertia.is_finite() {
            Err(LawError::NonFiniteInertia {
                which,
                row: 0,
                column: 0,
                value: to_f64(inverse_inertia),
            })
        } else if inverse_inertia < T::zero() {
            Err(LawError::NegativeInertia {
                which,
                value: to_f64(inverse_inertia),
            })
        } else {
            Ok(inverse_inertia)
        }
    }
}

impl<T: RealField + Copy> RigidDim<T, 3> for Const<3> {
    type Angular = Vector3<T>;
    type InverseInertia = Matrix3<T>;

    #[inline]
    fn zero_angular() -> Vector3<T> {
        Vector3::zeros()
    }
    #[inline]
    fn zero_inverse_inertia() -> Matrix3<T> {
        Matrix3::zeros()
    }
    #[inline]
    fn cross(r: &Vector3<T>, n: &Vector3<T>) -> Vector3<T> {
        r.cross(n)
    }
    #[inline]
    fn velocity_at(omega: &Vector3<T>, r: &Vector3<T>) -> Vector3<T> {
        omega.cross(r)
    }
    #[inline]
    fn apply(inverse_inertia: &Matrix3<T>, k: &Vector3<T>) -> Vector3<T> {
        inverse_inertia * k
    }
    #[inline]
    fn dot(a: &Vector3<T>, b: &Vector3<T>) -> T {
        a.dot(b)
    }
    #[inline]
    fn scale(a: &Vector3<T>, s: T) -> Vector3<T> {
        a * s
    }
    #[inline]
    fn add(a: &Vector3<T>, b: &Vector3<T>) -> Vector3<T> {
        a + b
    }
    #[inline]
    fn is_finite(a: &Vector3<T>) -> bool {
        a.iter().all(|x| x.is_finite())
    }
    #[inline]
    fn second_tangent(n: &Vector3<T>, t1: &Vector3<T>) -> Option<Vector3<T>> {
        Some(n.cross(t1))
    }
    fn check_angular_velocity(a: Vector3<T>, which: Which) -> Result<Vector3<T>, LawError> {
        match a.iter().position(|c| !c.is_finite()) {
            None => Ok(a),
            Some(component) => Err(LawError::NonFiniteAngularVelocity {
                which,
                component,
                value: to_f64(a[component]),
            }),
        }
    }
    fn check_inverse_inertia(m: Matrix3<T>, which: Which) -> Result<Matrix3<T>, LawError> {
        if let Some(i) = m.iter().position(|c| !c.is_finite()) {
            // Column-major storage.
            return Err(LawError::NonFiniteInertia {
                which,
                row: i % 3,
                column: i / 3,
                value: to_f64(m[i]),
            });
        }
        let scale = m.amax();
        if scale == T::zero() {
            return Ok(Matrix3::zeros());
        }
        let tol = tolerance::<T>();
        for (row, column) in [(0, 1), (0, 2), (1, 2)] {
            let difference = m[(row, column)] - m[(column, row)];
            if difference.abs() > tol * scale {
                return Err(LawError::AsymmetricInertia {
                    which,
                    row,
                    column,
                    difference: to_f64(difference),
                });
            }
        }
        let half = T::from_subset(&0.5);
        let s = (m + m.transpose()) * half;
        // Positive semidefinite iff every principal minor is >= 0. When
        // the rounded minors all are, the matrix is semidefinite to
        // rounding; otherwise its smallest eigenvalue decides (within 64
        // ulps of the largest entry) and is the error's value.
        let n = s / scale;
        let minor = |i: usize, j: usize| n[(i, i)] * n[(j, j)] - n[(i, j)] * n[(i, j)];
        let zero = T::zero();
        let minors_ok = (0..3).all(|i| n[(i, i)] >= zero)
            && minor(0, 1) >= zero
            && minor(0, 2) >= zero
            && minor(1, 2) >= zero
            && n.determinant() >= zero;
        if !minors_ok {
            let smallest = s.symmetric_eigenvalues().min();
            if smallest < -(tol * scale) {
                return Err(LawError::NegativeInertia {
                    which,
                    value: to_f64(smallest),
                });
            }
        }
        Ok(s)
    }
}
