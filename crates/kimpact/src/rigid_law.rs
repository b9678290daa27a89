//! The k-update for rigid bodies: the impulse of the ball law acting at
//! the contact point, with the rotation it causes.

use nalgebra::{Const, RealField, SVector};

use crate::dim::RigidDim;
use crate::law::Law;
use crate::num::half;
use crate::rigid::{Angular, Contact, RigidBody};

/// The outcome of one impact between rigid bodies `a` (1) and `b` (2), as
/// [`Law::resolve_rigid`] computes it. With `n̄` the unit normal from `a`
/// towards `b`, `kᵢ = rᵢ × n̄` and the normal impulse `J ≥ 0` (`+J n̄` on `b`
/// at the contact point, `−J n̄` on `a`):
///
/// ```text
/// Δv_a = −(J/m_a) n̄,   Δω_a = −J I_a⁻¹ k_a,
/// Δv_b =  (J/m_b) n̄,   Δω_b =  J I_b⁻¹ k_b.
/// ```
///
/// With impact friction ([`Law::resolve_rigid_with_friction`]) the
/// impulse on `b` is `P = J n̄ + P_t` (`P_t` the
/// [`tangential_impulse`](Self::tangential_impulse)), and then
/// `Δv_b = P/m_b`, `Δω_b = I_b⁻¹(r_b × P)`, `Δv_a = −P/m_a`,
/// `Δω_a = −I_a⁻¹(r_a × P)`. Immovable bodies' changes are zero.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RigidImpact<T: RealField + Copy, const D: usize>
where
    Const<D>: RigidDim<T, D>,
{
    /// The unit normal `n̄₁`, from `a` towards `b`.
    pub normal: SVector<T, D>,
    /// `U = −(u_b − u_a)·n̄ > 0`, the normal approach speed of the contact
    /// points before (`uᵢ = vᵢ + ωᵢ × rᵢ`).
    pub approach_speed: T,
    /// `Δv_a = m_b k n̄₂ = −(J/m_a) n̄`.
    pub delta_v_a: SVector<T, D>,
    /// `Δv_b = m_a k n̄₁ = (J/m_b) n̄`.
    pub delta_v_b: SVector<T, D>,
    /// `Δω_a = m_a m_b k I_a⁻¹(r_a × n̄₂) = −J I_a⁻¹ k_a` (zero for an
    /// immovable body).
    pub delta_omega_a: Angular<T, D>,
    /// `Δω_b = m_a m_b k I_b⁻¹(r_b × n̄₁) = J I_b⁻¹ k_b` (zero for an
    /// immovable body).
    pub delta_omega_b: Angular<T, D>,
    /// The normal impulse `J = m_a m_b k = m_eff U (1 + e) ≥ 0`.
    pub impulse: T,
    /// The effective mass at the contact along the normal,
    /// `m_eff = 1/(1/m_a + 1/m_b + a_a + a_b)`, `aᵢ = kᵢ·I⁻¹ᵢ kᵢ` (an
    /// immovable body contributes nothing).
    pub effective_mass: T,
    /// The effective restitution `e = U'/U` of the contact points' normal
    /// velocity.
    pub restitution: T,
    /// The kinetic energy (translation and rotation) lost: the law's `d`
    /// as used, plus [`friction_dissipated`](Self::friction_dissipated).
    pub dissipated: T,
    /// Whether `d` was reduced because the roots would have been complex.
    pub clamped: bool,
    /// `asked d − used d = ½ m_eff U² (q − (1 − 10⁻⁶))`: zero unless
    /// clamped; `+∞` only when the ask is unbounded, as
    /// [`Impact::unmet_dissipation`](crate::Impact::unmet_dissipation).
    pub unmet_dissipation: T,
    /// The tangential impulse `P_t ⟂ n̄` of the impact friction, applied as
    /// `+P_t` to `b` and `−P_t` to `a` at the contact point (zero without
    /// friction; see [`Law::resolve_rigid_with_friction`]).
    pub tangential_impulse: SVector<T, D>,
    /// What the impact friction did.
    pub friction: FrictionRegime,
    /// The kinetic energy the impact friction took (`≥ 0`; zero without
    /// friction), included in [`dissipated`](Self::dissipated).
    pub friction_dissipated: T,
}

/// What the tangential part of an impact did
/// ([`Law::resolve_rigid_with_friction`]).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum FrictionRegime {
    /// No tangential impulse: no friction asked (`μ = 0`), or no
    /// tangential motion of the contact points.
    #[default]
    None,
    /// The impact stuck: the contact points' tangential velocity went from
    /// `g_t` to `−β g_t` with an impulse within `μ J_n`.
    Stick,
    /// The impact slid: the tangential impulse `μ J_n` against the slip.
    Slide,
    /// The tangential impulse was reduced below Walton's: in 3D, where the
    /// sliding impulse `μ J_n` would have reversed the slip beyond `β` and
    /// added energy through an anisotropic tangential effective mass;
    /// where the normal–tangential coupling of an off-centre contact would
    /// have made the contact points approach again; or where the rounding
    /// of an ill-conditioned contact would have raised the energy.
    Limited,
}

impl<T: RealField + Copy, const D: usize> RigidImpact<T, D>
where
    Const<D>: RigidDim<T, D>,
{
    /// The bodies `a` and `b` (those this impact was resolved with) after
    /// it: their velocities and angular velocities changed, their masses
    /// and inertias as they were.
    pub fn apply(
        &self,
        a: &RigidBody<T, D>,
        b: &RigidBody<T, D>,
    ) -> (RigidBody<T, D>, RigidBody<T, D>) {
        let after = |body: &RigidBody<T, D>, dv: &SVector<T, D>, dw: &Angular<T, D>| RigidBody {
            velocity: body.velocity + dv,
            angular_velocity: <Const<D>>::add(&body.angular_velocity, dw),
            ..*body
        };
        (
            after(a, &self.delta_v_a, &self.delta_omega_a),
            after(b, &self.delta_v_b, &self.delta_omega_b),
        )
    }
}

impl<T: RealField + Copy> Law<T> {
    /// Resolve one impact between rigid bodies `a` and `b` touching at
    /// `contact` (arms `rᵢ = p − cᵢ`, unit normal `n̄₁` from `a` towards
    /// `b`, `n̄₂ = −n̄₁`). With world inverse inertias `Iᵢ⁻¹` and the
    /// contact points' velocities `uᵢ = vᵢ + ωᵢ × rᵢ`:
    ///
    /// ```text
    /// v₁' = v₁ + m₂ k n̄₂,   v₂' = v₂ + m₁ k n̄₁,
    /// ω₁' = ω₁ + m₁m₂ k I₁⁻¹(r₁ × n̄₂),   ω₂' = ω₂ + m₁m₂ k I₂⁻¹(r₂ × n̄₁),
    /// (m₁m₂/2)[(m₁+m₂) + m₁m₂(a₁+a₂)] k² + k m₁m₂ (u₁·n̄₂ + u₂·n̄₁) + d = 0,
    /// aᵢ = (rᵢ × n̄)·Iᵢ⁻¹(rᵢ × n̄),   d = d̃ (m₁+m₂) |u₂ − u₁|²,
    /// ```
    ///
    /// with the root of larger magnitude (2D: scalar inertia, `r × n̄ =
    /// r_x n_y − r_y n_x`). The impulse `J = m₁m₂ k` acts along `n̄` at the
    /// contact point, so linear and angular momentum are kept and the
    /// kinetic energy (translation and rotation) falls by exactly `d`.
    ///
    /// **The choice of `d`**: `w = u₂ − u₁` is the relative velocity of
    /// the contact points, the velocity of the material that collides. It
    /// reduces to the ball law's `d` for bodies that do not spin (`ω = 0`
    /// gives `uᵢ = vᵢ`), and a centred ball (`rᵢ ∥ n̄`) has `aᵢ = 0`: the
    /// ball law's equation. A spinning ball's `d` counts its surface speed.
    /// Against an immovable partner under [`FixedPartner::OwnMass`] the
    /// pair's mass is replaced by the body's own mass `m` (its mass, not an
    /// effective mass): `d = d̃_w m |w|²`. Fixed and kinematic partners are
    /// the limit of infinite mass and inertia (`a = 0`, their velocities
    /// unchanged).
    ///
    /// # How it is computed
    /// As the ball law ([`Law`]), from ratios: with the reduced mass
    /// `μ = m₁m₂/M` (the finite mass against an immovable partner),
    /// `g = μ (a₁ + a₂) ≥ 0` and `f = 1 + g`, the effective mass is
    /// `m_eff = 1/(1/m₁ + 1/m₂ + a₁ + a₂) = μ/f`, and
    ///
    /// ```text
    /// U = −w·n̄ = −((v₂ − v₁)·n̄ + ω₂·k₂ − ω₁·k₁),  kᵢ = rᵢ × n̄,
    /// q = 2d/(m_eff U²) = 2 d̃ (|w|/U)² (M/μ) f,  e = sqrt(1 − q),
    /// s = U (1 + e),  J = μ (s/f),  Δv₁ = −(m₂/M)(s/f) n̄,  Δv₂ = (m₁/M)(s/f) n̄,
    /// ```
    ///
    /// clamped as the ball law (`q > 1` ⇒ `e² = 10⁻⁶`). `U` takes the
    /// spins' part as `ωᵢ·kᵢ`, not from the summed `w`: a fast spin's
    /// surface velocity is mostly tangential, and its normal part taken
    /// from `w` would keep little but rounding. No product of two
    /// masses, nothing that fails as `aᵢ → 0`; with `a₁ = a₂ = 0` and
    /// `ω = 0`, `f = 1` exactly and the result is [`Law::resolve_unit`]'s
    /// bit for bit. `aᵢ` is taken as `max(aᵢ, 0)`, so an inverse inertia
    /// semidefinite only to rounding cannot make `m_eff` negative (the
    /// energy then falls by `d` or a rounding more, never less).
    ///
    /// The rotational part is as precise as the world inverse inertia: an
    /// anisotropic body (principal inverse inertias far apart) loses about
    /// `ε · cond(I)` of its small components to the rounding of the
    /// matrix, whoever computes it.
    ///
    /// Returns `None` when the contact points do not approach along the
    /// normal (`U ≤ 0`), when both bodies are immovable, or when `U` or a
    /// velocity change overflows the type; never a NaN.
    ///
    /// [`FixedPartner::OwnMass`]: crate::FixedPartner::OwnMass
    pub fn resolve_rigid<const D: usize>(
        &self,
        a: &RigidBody<T, D>,
        b: &RigidBody<T, D>,
        contact: &Contact<T, D>,
    ) -> Option<RigidImpact<T, D>>
    where
        Const<D>: RigidDim<T, D>,
    {
        self.normal_part(a, b, contact).map(|(impact, _)| impact)
    }

    /// [`Law::resolve_rigid`], and what its tangential part needs.
    #[inline]
    pub(crate) fn normal_part<const D: usize>(
        &self,
        a: &RigidBody<T, D>,
        b: &RigidBody<T, D>,
        contact: &Contact<T, D>,
    ) -> Option<(RigidImpact<T, D>, NormalPart<T, D>)>
    where
        Const<D>: RigidDim<T, D>,
    {
        let n = contact.normal();
        let (ra, rb) = (contact.arm_a(), contact.arm_b());
        let spin = <Const<D>>::velocity_at(&b.angular_velocity, rb)
            - <Const<D>>::velocity_at(&a.angular_velocity, ra);
        let w = (b.velocity - a.velocity) + spin;
        let ka = <Const<D>>::cross(ra, n);
        let kb = <Const<D>>::cross(rb, n);
        // `−w·n̄` with the spin's part as `ωᵢ·kᵢ = (ωᵢ × rᵢ)·n̄`: a fast
        // spin's surface velocity is mostly tangential, and its normal
        // part taken from the summed vector would keep only its rounding.
        let approach_speed = -((b.velocity - a.velocity).dot(n)
            + <Const<D>>::dot(&b.angular_velocity, &kb)
            - <Const<D>>::dot(&a.angular_velocity, &ka));
        if !(approach_speed > T::zero() && approach_speed.is_finite()) {
            return None;
        }
        let pair = self.pair_masses(a.mass, b.mass)?;
        let zero = T::zero();
        let ia = <Const<D>>::apply(&a.inverse_inertia, &ka);
        let ib = <Const<D>>::apply(&b.inverse_inertia, &kb);
        let aa = <Const<D>>::dot(&ka, &ia).max(zero);
        let ab = <Const<D>>::dot(&kb, &ib).max(zero);
        let factor = T::one() + pair.reduced * (aa + ab);
        let c = self.coefficient(
            &pair,
            || {
                // As in `resolve_unit`: divide on the rare subnormal path.
                let inverse = T::one() / approach_speed;
                if inverse.is_finite() {
                    (w * inverse).norm_squared()
                } else {
                    (w / approach_speed).norm_squared()
                }
            },
            factor,
        );
        let e = c.e;
        let s = approach_speed * (T::one() + e);
        if !s.is_finite() {
            return None;
        }
        let s_eff = s / factor;
        let impulse = pair.reduced * s_eff;
        let turn = |body: &RigidBody<T, D>, response: &Angular<T, D>, j: T| {
            if body.mass.is_infinite() {
                Some(<Const<D>>::zero_angular())
            } else {
                let dw = <Const<D>>::scale(response, j);
                <Const<D>>::is_finite(&dw).then_some(dw)
            }
        };
        let delta_omega_a = turn(a, &ia, -impulse)?;
        let delta_omega_b = turn(b, &ib, impulse)?;
        let effective_mass = pair.reduced / factor;
        let normal = NormalPart {
            w,
            frac_a: pair.frac_a,
            frac_b: pair.frac_b,
            reduced: pair.reduced,
            speed_change: s_eff,
        };
        let impact = RigidImpact {
            normal: *n,
            approach_speed,
            delta_v_a: n * (-(pair.frac_b * s_eff)),
            delta_v_b: n * (pair.frac_a * s_eff),
            delta_omega_a,
            delta_omega_b,
            impulse,
            effective_mass,
            restitution: e,
            dissipated: if c.q == zero {
                zero
            } else {
                half::<T>() * effective_mass * approach_speed * approach_speed * c.q
            },
            clamped: c.clamped,
            unmet_dissipation: c.unmet(effective_mass, approach_speed),
            tangential_impulse: SVector::zeros(),
            friction: FrictionRegime::None,
            friction_dissipated: zero,
        };
        Some((impact, normal))
    }
}

/// What the tangential part of an impact needs from its normal part.
#[derive(Copy, Clone, Debug)]
pub(crate) struct NormalPart<T: RealField + Copy, const D: usize> {
    /// `w = u_b − u_a` before the impact.
    pub(crate) w: SVector<T, D>,
    /// `m_a / M`.
    pub(crate) frac_a: T,
    /// `m_b / M`.
    pub(crate) frac_b: T,
    /// `μ`, the reduced mass (the finite mass against an immovable body).
    pub(crate) reduced: T,
    /// `J_n / μ = s/f`, the normal impulse in velocity units.
    pub(crate) speed_change: T,
}
