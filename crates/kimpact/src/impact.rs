//! What one impact of the ball law did: the velocity changes, the impulse,
//! the restitution and the energy taken.

use nalgebra::{RealField, SVector};

use crate::body::{Body, Mass, kinetic_energy};

/// The effective restitution of one impact, the view of the law a solver
/// with a restitution coefficient needs.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Restitution<T> {
    /// `e = u'/u ∈ [0, 1]`: the normal separation speed after the impact
    /// over the approach speed before.
    pub coefficient: T,
    /// Whether `d` had to be reduced (the note's complex-root case).
    pub clamped: bool,
    /// The dissipation asked for beyond what the impact could take,
    /// `asked d − used d = ½ μ u² (q − (1 − 10⁻⁶))` with `q` the asked
    /// `2 d/(μ u²)`: zero unless [`clamped`](Self::clamped); `+∞` only
    /// when the ask is unbounded (a [`FixedPartner::Literal`](crate::FixedPartner::Literal) wall with
    /// `d̃ > 0`, or `q` or this product beyond the type's range). Never NaN.
    /// See [`Impact::unmet_dissipation`].
    pub unmet_dissipation: T,
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
    /// The dissipation the law's formula asked for beyond what it could
    /// take: `asked d − used d = ½ μ u² (q − (1 − 10⁻⁶))`, `q = 2 d/(μ u²)`
    /// the asked ratio ([`Law`](crate::Law)). Zero unless [`clamped`](Self::clamped).
    /// A clamp from rounding (`q` a few ulps over 1) leaves about `10⁻⁶` of
    /// `½ μ u²` unmet; a clamp of the law itself (an oblique impact under a
    /// law for small `e`, see
    /// [`LawParams::from_restitution`](crate::LawParams::from_restitution)) leaves a
    /// share of the order of `½ μ u²` or more.
    ///
    /// `+∞` only when the ask is unbounded: a [`FixedPartner::Literal`](crate::FixedPartner::Literal)
    /// wall with `d̃ > 0` (whose `d` grows without bound with the wall's
    /// mass), or `q` (or the product) beyond the type's range. Never NaN.
    /// [`Stats::record_unmet`](crate::Stats::record_unmet) accumulates it.
    pub unmet_dissipation: T,
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
    /// [`Law::resolve`](crate::Law::resolve): an engine integration never needs it, and computing it for
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
