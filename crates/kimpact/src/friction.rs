//! The tangential part of an impact, opt-in: Coulomb friction with a
//! tangential restitution after Walton's three-parameter model.

use nalgebra::{Const, RealField, SVector};

use crate::dim::RigidDim;
use crate::error::LawError;
use crate::law::Law;
use crate::num::{half, to_f64};
use crate::rigid::{Angular, Contact, RigidBody};
use crate::rigid_law::{FrictionRegime, NormalPart, RigidImpact};

/// The impact friction of a pair: Coulomb's coefficient `μ ≥ 0`
/// (`impact_friction`) and the tangential restitution `β ∈ [−1, 1]`
/// (`tangential_restitution`: −1 leaves the contact points' tangential
/// velocity as it is, 0 stops it, 1 reverses it). Built only through
/// [`ImpactFriction::new`], which checks both.
///
/// Within this range the impact friction never raises the kinetic energy
/// (proof: [`Law::resolve_rigid_with_friction`]); `β > 1` would, and is
/// refused.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ImpactFriction<T> {
    mu: T,
    beta: T,
}

impl<T: RealField + Copy> ImpactFriction<T> {
    /// Impact friction with Coulomb coefficient `impact_friction` (μ) and
    /// tangential restitution `tangential_restitution` (β).
    ///
    /// # Errors
    /// [`LawError::InvalidFriction`] naming `impact_friction` if μ is NaN,
    /// infinite or negative, or `tangential_restitution` if β is NaN or
    /// outside `[−1, 1]`.
    pub fn new(impact_friction: T, tangential_restitution: T) -> Result<Self, LawError> {
        // NaN fails every comparison.
        if !(impact_friction.is_finite() && impact_friction >= T::zero()) {
            return Err(LawError::InvalidFriction {
                parameter: "impact_friction",
                expected: "finite and >= 0",
                value: to_f64(impact_friction),
            });
        }
        let one = T::one();
        if !(tangential_restitution >= -one && tangential_restitution <= one) {
            return Err(LawError::InvalidFriction {
                parameter: "tangential_restitution",
                expected: "in [-1, 1]",
                value: to_f64(tangential_restitution),
            });
        }
        Ok(Self {
            mu: impact_friction,
            beta: tangential_restitution,
        })
    }

    /// No impact friction (`μ = 0`; β is then irrelevant and −1).
    pub fn frictionless() -> Self {
        Self {
            mu: T::zero(),
            beta: -T::one(),
        }
    }

    /// Coulomb's coefficient μ.
    pub fn impact_friction(&self) -> T {
        self.mu
    }

    /// The tangential restitution β.
    pub fn tangential_restitution(&self) -> T {
        self.beta
    }

    /// Whether μ is zero (the impact is the frictionless law's).
    pub fn is_frictionless(&self) -> bool {
        self.mu == T::zero()
    }
}

impl<T: RealField + Copy> Default for ImpactFriction<T> {
    fn default() -> Self {
        Self::frictionless()
    }
}

impl<T: RealField + Copy> Law<T> {
    /// [`Law::resolve_rigid`] followed by the impact friction `friction`
    /// (Walton's three-parameter model: the law's normal restitution, μ
    /// and β). With `μ = 0` the result is `resolve_rigid`'s bit for bit.
    ///
    /// # The model
    /// With `K` the contact's inverse effective-mass matrix (the change of
    /// the contact points' relative velocity `w = u_b − u_a` per unit
    /// impulse at the contact, `K P = P (1/m_a + 1/m_b) + Σ (Iᵢ⁻¹(rᵢ × P)) × rᵢ`,
    /// symmetric positive definite) and `K_tt` its block on the contact
    /// plane (1×1 in 2D, 2×2 in 3D, inertia included), the law's normal
    /// impulse `J_n` is applied first; `g = w*_t` is then the contact
    /// points' tangential velocity (after `J_n`, which an off-centre
    /// contact couples into it through `K_nt`; before the impact for
    /// centred balls), and the tangential impulse `P_t` (on `b`) is
    ///
    /// ```text
    /// stick:  P_t = −(1 + β) K_tt⁻¹ g          if |P_t| ≤ μ J_n   (g' = −β g),
    /// slide:  P_t = −λ ĝ,  λ = min(μ J_n, (1 + β)|g| / (ĝ·K ĝ))    otherwise,
    /// ```
    ///
    /// `ĝ = g/|g|`. In 2D and for an isotropic `K_tt` (balls) the cap never
    /// binds: `λ = μ J_n`, Walton's sliding impulse. Then, if the coupling
    /// `n̄·K P_t` would make the contact points approach again after the
    /// impact (`e U + n̄·K P_t < 0`), `P_t` is scaled down until they
    /// separate at zero speed. The capped and scaled cases are reported as
    /// [`FrictionRegime::Limited`]. `P_t` acts at the contact point:
    /// linear and angular momentum are kept.
    ///
    /// # Kinetic energy never rises (for `μ ≥ 0`, `−1 ≤ β ≤ 1`)
    /// An impulse `P` at the contact changes the kinetic energy by
    /// `P·w + ½ PᵀK P`. The normal part takes `d` ([`Law::resolve_rigid`]);
    /// after it, `P_t ⟂ n̄` changes the energy by
    /// `ΔE_t = P_t·g + ½ P_tᵀK_tt P_t`. Stick:
    /// `ΔE_t = −½ (1 − β²) gᵀK_tt⁻¹g ≤ 0`. Slide:
    /// `ΔE_t = λ (½ λ ĝ·Kĝ − |g|) ≤ λ |g| ((1 + β)/2 − 1) ≤ 0` by the cap.
    /// Scaling `P_t` by `c ∈ [0, 1]`: `ΔE_t(c) = c P_t·g + ½ c² P_tᵀK P_t`
    /// is convex in `c`, zero at 0 and `≤ 0` at 1, so `≤ 0` between. `β > 1`
    /// would give `ΔE_t > 0` when sticking and is refused by
    /// [`ImpactFriction::new`].
    ///
    /// # How it is computed
    /// In velocity units (`P̃ = P_t/μ_r` with `μ_r` the reduced mass, and
    /// `K̃ = μ_r K = 𝟙 + μ_r Σ …`, whose eigenvalues are `≥ 1`), so nothing
    /// multiplies two masses; the 2×2 block is scaled by its first diagonal
    /// entry before it is solved, and sizes are taken without squaring, so
    /// f32 neither overflows nor underflows there. The stick solution is as
    /// precise as `K_tt` is conditioned; where its rounding would let
    /// `ΔE_t` exceed rounding above zero, `P_t` is scaled to the least
    /// energy along its direction ([`FrictionRegime::Limited`]), so the
    /// statement above holds in floating point too. Where anything would
    /// not be finite, the friction is skipped (the frictionless result is
    /// returned): never a NaN.
    pub fn resolve_rigid_with_friction<const D: usize>(
        &self,
        a: &RigidBody<T, D>,
        b: &RigidBody<T, D>,
        contact: &Contact<T, D>,
        friction: &ImpactFriction<T>,
    ) -> Option<RigidImpact<T, D>>
    where
        Const<D>: RigidDim<T, D>,
    {
        let (impact, normal) = self.normal_part(a, b, contact)?;
        if friction.is_frictionless() {
            return Some(impact);
        }
        Some(tangential(a, b, contact, friction, impact, &normal).unwrap_or(impact))
    }
}

/// The tangential part on top of `impact`, or `None` where it would not
/// be finite or there is no tangential motion.
fn tangential<T: RealField + Copy, const D: usize>(
    a: &RigidBody<T, D>,
    b: &RigidBody<T, D>,
    contact: &Contact<T, D>,
    friction: &ImpactFriction<T>,
    impact: RigidImpact<T, D>,
    normal: &NormalPart<T, D>,
) -> Option<RigidImpact<T, D>>
where
    Const<D>: RigidDim<T, D>,
{
    let zero = T::zero();
    let one = T::one();
    let n = contact.normal();
    let (ra, rb) = (contact.arm_a(), contact.arm_b());
    let reduced = normal.reduced;
    // K̃ x = x + μ_r Σ (Iᵢ⁻¹(rᵢ × x)) × rᵢ over the bodies that can turn.
    let response = |body: &RigidBody<T, D>, r: &SVector<T, D>, x: &SVector<T, D>| {
        let turn = <Const<D>>::apply(&body.inverse_inertia, &<Const<D>>::cross(r, x));
        <Const<D>>::velocity_at(&turn, r)
    };
    let k = |x: &SVector<T, D>| {
        let mut out = *x;
        if !a.mass.is_infinite() {
            out += response(a, ra, x) * reduced;
        }
        if !b.mass.is_infinite() {
            out += response(b, rb, x) * reduced;
        }
        out
    };
    // The contact points' velocity after the normal impulse.
    let moved = |dv: &SVector<T, D>, dw: &Angular<T, D>, r: &SVector<T, D>| {
        dv + <Const<D>>::velocity_at(dw, r)
    };
    let w_star = normal.w + moved(&impact.delta_v_b, &impact.delta_omega_b, rb)
        - moved(&impact.delta_v_a, &impact.delta_omega_a, ra);
    let g_t = w_star - n * w_star.dot(n);
    // A second pass, so that a small tangential part of a large w* is
    // orthogonal to n̄ to rounding too.
    let g_t = g_t - n * g_t.dot(n);
    let g = g_t.norm();
    if !(g > zero && g.is_finite()) {
        return None;
    }
    let t1 = g_t / g;
    let beta1 = one + friction.beta;
    let kt1 = k(&t1);
    let k11 = t1.dot(&kt1);
    // Stick: K̃_tt P̃ = −(1 + β) g t̄₁, solved in the basis t̄₁, t̄₂ with
    // K̃_tt scaled by k₁₁ ≥ 1 (no overflow of its products in f32), and
    // the magnitude taken without squaring (no underflow).
    let scaled = beta1 * (g / k11);
    let (stick, stick_size) = match <Const<D>>::second_tangent(n, &t1) {
        Some(t2) => {
            let kt2 = k(&t2);
            let k22 = t2.dot(&kt2) / k11;
            let k12 = (t1.dot(&kt2) + t2.dot(&kt1)) * half::<T>() / k11;
            let det = k22 - k12 * k12;
            if det > zero && det.is_finite() {
                let x = scaled / det;
                (t1 * (-(x * k22)) + t2 * (x * k12), x * k22.hypot(k12))
            } else {
                (t1 * (-scaled), scaled)
            }
        }
        None => (t1 * (-scaled), scaled),
    };
    let bound = friction.mu * normal.speed_change;
    let (mut p, mut regime) = if stick_size <= bound {
        (stick, FrictionRegime::Stick)
    } else if bound <= scaled {
        (t1 * (-bound), FrictionRegime::Slide)
    } else {
        // The cap (1 + β) g / (ĝ·K̃ĝ).
        (t1 * (-scaled), FrictionRegime::Limited)
    };
    // The coupling must not make the contact points approach again.
    let separation = impact.restitution * impact.approach_speed;
    let coupling = n.dot(&k(&p));
    let slack = T::default_epsilon() * T::from_subset(&64.0) * (separation + k11 * p.norm());
    if separation + coupling < -slack {
        p *= separation / -coupling;
        regime = FrictionRegime::Limited;
    }
    // ΔE_t = μ_r (A + ½ B), A = P̃·g, B = P̃·K̃P̃ > 0: never positive, by the
    // proof; where the rounding of an ill-conditioned K̃_tt would make it
    // so, P̃ is scaled to the least energy along it (c = −A/B), or dropped.
    // (β = 1 sticks with ΔE_t = 0: rounding is let through.)
    let mut kp = k(&p);
    let (along, curvature) = (p.dot(&g_t), p.dot(&kp));
    let rounding = T::default_epsilon() * T::from_subset(&64.0) * curvature.abs();
    if along + half::<T>() * curvature > rounding {
        if !(along < zero && curvature > zero) {
            return None;
        }
        let c = -along / curvature;
        p *= c;
        kp *= c;
        regime = FrictionRegime::Limited;
    }
    // ΔE_t = μ_r (P̃·g + ½ P̃·K̃P̃) ≤ 0.
    let change = reduced * (p.dot(&g_t) + half::<T>() * p.dot(&kp));
    let lost = (-change).max(zero);
    let turn = |body: &RigidBody<T, D>, r: &SVector<T, D>, j: T| {
        if body.mass.is_infinite() {
            <Const<D>>::zero_angular()
        } else {
            let torque = <Const<D>>::cross(r, &p);
            <Const<D>>::scale(&<Const<D>>::apply(&body.inverse_inertia, &torque), j)
        }
    };
    let dw_a = turn(a, ra, -reduced);
    let dw_b = turn(b, rb, reduced);
    let out = RigidImpact {
        delta_v_a: impact.delta_v_a - p * normal.frac_b,
        delta_v_b: impact.delta_v_b + p * normal.frac_a,
        delta_omega_a: <Const<D>>::add(&impact.delta_omega_a, &dw_a),
        delta_omega_b: <Const<D>>::add(&impact.delta_omega_b, &dw_b),
        tangential_impulse: p * reduced,
        friction: regime,
        friction_dissipated: lost,
        dissipated: impact.dissipated + lost,
        ..impact
    };
    let finite = |v: &SVector<T, D>| v.iter().all(|x| x.is_finite());
    (finite(&out.delta_v_a)
        && finite(&out.delta_v_b)
        && finite(&out.tangential_impulse)
        && <Const<D>>::is_finite(&out.delta_omega_a)
        && <Const<D>>::is_finite(&out.delta_omega_b)
        && out.dissipated.is_finite())
    .then_some(out)
}
