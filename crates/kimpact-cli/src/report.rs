//! The JSON report of one run.

use serde::Serialize;

use crate::scene::{Effect, Precision, Scene};
use crate::sim::{RunOutput, Sample};

/// The report of one run. Same scene, same mode, same build: identical
/// apart from `timing`.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// The scene file, as given.
    pub scene: String,
    /// The scene's one-line purpose.
    pub description: Option<String>,
    /// 2 or 3.
    pub dim: usize,
    /// `"f32"` or `"f64"`.
    pub precision: &'static str,
    /// The mode run.
    pub mode: String,
    /// Steps taken.
    pub steps: u64,
    /// Time step in seconds.
    pub dt: f64,
    /// Every body at the end, in scene order.
    pub bodies: Vec<BodyReport>,
    /// Energies at the start and the end.
    pub energy: Energy,
    /// Momenta at the start and the end.
    pub momentum: Momentum,
    /// kimpact's impact totals (zero in native mode).
    pub impacts: Impacts,
    /// Wall time of the physics steps.
    pub timing: Timing,
    /// The effects that were active.
    pub effects: Vec<&'static str>,
    /// What the run was built with.
    pub setup: Setup,
    /// Health checks of the run.
    pub checks: Checks,
    /// Warnings about the scene (from loading it) and about the run: energy
    /// unexplained, or momentum changed in a scene that conserves it, beyond
    /// [`Checks::tolerance`].
    pub warnings: Vec<String>,
}

/// One body at the end of the run.
#[derive(Clone, Debug, Serialize)]
pub struct BodyReport {
    /// The body's label, if any.
    pub name: Option<String>,
    /// `"ball"`, `"box"`, `"capsule"` or `"convex"`.
    pub shape: &'static str,
    /// Mass as simulated (`null` for fixed bodies).
    pub mass: Option<f64>,
    /// Fixed body.
    pub fixed: bool,
    /// Follows the law.
    pub law: bool,
    /// Final position.
    pub position: Vec<f64>,
    /// Final velocity.
    pub velocity: Vec<f64>,
    /// Final orientation, as scene files write it: 2D the angle in
    /// radians, 3D the rotation vector (axis times angle).
    pub rotation: Angular,
    /// Final angular velocity in rad/s: 2D a number, 3D a vector (world
    /// frame).
    pub angular_velocity: Angular,
}

/// A rotation or an angular velocity: a number in 2D, a vector in 3D.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Angular {
    /// 2D.
    Scalar(f64),
    /// 3D.
    Vector(Vec<f64>),
}

impl Angular {
    /// From the simulation's `[x]` (2D) or `[x, y, z]` (3D).
    fn of(v: &[f64]) -> Self {
        match v {
            [x] => Angular::Scalar(*x),
            _ => Angular::Vector(v.to_vec()),
        }
    }

    /// From the simulation's orientation: `[angle]` (2D) or the quaternion
    /// `[x, y, z, w]` (3D), as its rotation vector.
    fn rotation(r: &[f64]) -> Self {
        use kimpact::nalgebra::{Quaternion, UnitQuaternion};
        match r {
            [x, y, z, w] => {
                let q = UnitQuaternion::from_quaternion(Quaternion::new(*w, *x, *y, *z));
                let v = q.scaled_axis();
                Angular::Vector(vec![v.x, v.y, v.z])
            }
            _ => Angular::of(r),
        }
    }
}

/// Energies (joules in SI scenes).
#[derive(Clone, Debug, Serialize)]
pub struct Energy {
    /// Kinetic energy at the start.
    pub kinetic_initial: f64,
    /// Kinetic energy at the end.
    pub kinetic_final: f64,
    /// Potential energy `−Σ m g·x` at the start.
    pub potential_initial: f64,
    /// Potential energy at the end.
    pub potential_final: f64,
    /// `(kinetic + potential)` at the end minus at the start.
    pub total_change: f64,
}

/// Momentum of the law bodies and of all bodies.
#[derive(Clone, Debug, Serialize)]
pub struct MomentumPair {
    /// Bodies that follow the law.
    pub law: Vec<f64>,
    /// Every body.
    pub all: Vec<f64>,
}

/// Momenta at the start and the end.
#[derive(Clone, Debug, Serialize)]
pub struct Momentum {
    /// At the start.
    pub initial: MomentumPair,
    /// At the end.
    pub r#final: MomentumPair,
}

/// kimpact's statistics.
#[derive(Clone, Debug, Serialize)]
pub struct Impacts {
    /// Impacts resolved by the law.
    pub count: u64,
    /// Of which clamped (complex roots).
    pub clamped: u64,
    /// Energy dissipated by the law.
    pub dissipated: f64,
    /// Dissipation the clamped impacts asked for beyond what their normal
    /// motion held (`kimpact::Stats::unmet_dissipation`).
    pub unmet_dissipation: f64,
    /// Clamped impacts whose ask was unbounded (walls under
    /// `fixed_partner: "literal"`).
    pub unbounded_clamps: u64,
    /// When at least a tenth of the impacts were clamped: whose clamps they
    /// are (the law's, or rounding) and what to do (see `crate::clamps`).
    pub clamps: Option<String>,
    /// Pairs skipped for non-finite data.
    pub skipped_non_finite: u64,
    /// Exact-mode steps that hit the event cap.
    pub event_cap_hits: u64,
}

/// Wall time (the only part of the report that changes between runs).
#[derive(Clone, Debug, Serialize)]
pub struct Timing {
    /// Seconds spent in the physics steps.
    pub wall_seconds: f64,
    /// The same per step.
    pub seconds_per_step: f64,
}

/// What the world was built with.
#[derive(Clone, Debug, Serialize)]
pub struct Setup {
    /// Gravity as simulated.
    pub gravity: Vec<f64>,
    /// d̃ as simulated.
    pub dissipation: f64,
    /// Bodies with rapier's CCD: written `ccd: true`, or chosen by the
    /// scene's `auto_ccd`.
    pub ccd_bodies: usize,
    /// Of which chosen by `auto_ccd` (a setting the command adds).
    pub auto_ccd_bodies: usize,
    /// Bodies given rapier's soft CCD (`auto_ccd`, native mode only).
    pub soft_ccd_bodies: usize,
    /// rapier's contact recycling (`IntegrationParameters::contact_recycling`),
    /// off with soft CCD.
    pub contact_recycling: bool,
    /// Moving bodies whose rotations were locked (`spin` not active).
    pub locked_rotations: usize,
    /// Bodies whose friction was set to zero (`friction` not active).
    pub zeroed_friction: usize,
    /// Joints (rapier's impulse joints).
    pub joints: usize,
    /// Every setting the command adds to rapier beyond what the scene
    /// writes, one sentence each (empty: the world is the scene as rapier
    /// builds it). `docs/scenes.md`, "What the command adds", says why.
    pub added: Vec<String>,
    /// Bodies marked for the law (0 in native mode).
    pub marked_bodies: usize,
    /// Bodies in the scene.
    pub body_count: usize,
    /// rapier's substeps per step (`IntegrationParameters::num_solver_iterations`).
    pub substeps: usize,
}

/// Health checks: none of these should be large.
#[derive(Clone, Debug, Serialize)]
pub struct Checks {
    /// Deepest contact penetration seen over the run.
    pub max_penetration: f64,
    /// The same relative to the smaller body's smallest half size.
    pub max_penetration_ratio: f64,
    /// Balls that passed through each other, counted once per pair and step:
    /// moving both centres straight from where they started a step to where
    /// they ended it, their centre-to-centre vector reverses along a path
    /// closer than the smaller radius to the other centre. Tunnelling,
    /// whatever the depths seen at step ends (every pair is checked, not
    /// only those rapier saw).
    pub crossings: u64,
    /// Moving bodies that ended outside the bounding box of the fixed
    /// bodies (`null` unless the fixed bodies' box holds every moving body
    /// at the start).
    pub escaped: Option<usize>,
    /// Bodies with a non-finite position or velocity at the end.
    pub non_finite: usize,
    /// The integrator's share of `energy.total_change`:
    /// `−(h/2) Σ m g·(v_final − v_initial)`, `h = dt / setup.substeps`.
    /// rapier integrates each substep by symplectic Euler (`v += g h`, then
    /// `x += v h`), which keeps `½ m |v|² − m g·x + (h/2) m g·v` exactly
    /// through free flight, not `½ m |v|² − m g·x`: a body falling freely
    /// from rest for a time `τ` reports `−(h/2) m |g|² τ` of total energy
    /// change that is neither an impact nor a contact. Zero without gravity.
    pub energy_integrator: f64,
    /// `energy.total_change + impacts.dissipated − energy_integrator`: the
    /// change of total energy that neither the law's dissipation nor
    /// rapier's integrator explains. Negative: energy lost in rapier's
    /// contacts (all of it in native mode: restitution below 1, resting
    /// contacts, friction), or in an impact's change of velocity under
    /// gravity (see docs/report.md); positive: energy created, which no mode
    /// should do. Warned about beyond `tolerance · energy_scale`.
    pub energy_unexplained: f64,
    /// The largest `Σ ½ m |v|² + Σ m |g·x|` over the run's steps (rotation
    /// included with `spin`): the size of the energies the balance sums.
    pub energy_scale: f64,
    /// `|Δp|`, the change of the momentum of all bodies over the run.
    pub momentum_change: f64,
    /// The largest `Σ m |v|` over the run's steps.
    pub momentum_scale: f64,
    /// Whether the scene conserves momentum: no fixed body, no gravity, no
    /// joint to the world or a fixed body. Only then is `momentum_change`
    /// warned about beyond `tolerance · momentum_scale`.
    pub momentum_conserved: bool,
    /// The relative tolerance of both warnings, after the precision and the
    /// integrator's rounding: [`tolerance`].
    pub tolerance: f64,
}

/// The least relative tolerance of the energy and momentum warnings in f64
/// scenes (docs/report.md, "The energy balance").
pub const TOLERANCE_F64: f64 = 1e-9;

/// The same in f32 scenes.
pub const TOLERANCE_F32: f64 = 1e-5;

/// The relative tolerance of the energy and momentum warnings for a run
/// of `steps` steps of `substeps` substeps in `precision`:
///
/// ```text
/// max(base, u · steps · substeps),   base = 1e-9 (f64), 1e-5 (f32),
///                                     u = 2⁻⁵³ (f64), 2⁻²⁴ (f32),
/// ```
///
/// `u` the unit roundoff. Each substep of rapier's integrator (`v += g h`,
/// `x += v h`) rounds every velocity and position to the nearest value of
/// the precision, changing `½ m |v|² − m g·x` by up to about `u` of the
/// energy scale, and a long fall rounds the same way step after step: the
/// rounding of a run grows with its substeps, not as their square root.
pub fn tolerance(precision: Precision, steps: u64, substeps: usize) -> f64 {
    let (base, u) = match precision {
        Precision::F64 => (TOLERANCE_F64, f64::EPSILON / 2.0),
        Precision::F32 => (TOLERANCE_F32, f64::from(f32::EPSILON) / 2.0),
    };
    base.max(u * steps as f64 * substeps.max(1) as f64)
}

/// The norm of a vector.
pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Build the report of `run` on `scene`.
pub fn build(scene: &Scene, run: &RunOutput) -> Report {
    let first: &Sample = &run.samples[0];
    let last: &Sample = run.samples.last().unwrap_or(first);
    let bodies: Vec<BodyReport> = scene
        .bodies
        .iter()
        .zip(&run.final_bodies)
        .zip(&run.masses)
        .map(|((b, s), m)| BodyReport {
            name: b.name.clone(),
            shape: b.shape.name(),
            mass: *m,
            fixed: b.fixed,
            law: b.law && !b.fixed,
            position: s.position.clone(),
            velocity: s.velocity.clone(),
            rotation: Angular::rotation(&s.rotation),
            angular_velocity: Angular::of(&s.angular_velocity),
        })
        .collect();
    let non_finite = run
        .final_bodies
        .iter()
        .filter(|s| !s.position.iter().chain(&s.velocity).all(|x| x.is_finite()))
        .count();
    let escaped = fixed_box(scene).map(|(lo, hi)| {
        scene
            .bodies
            .iter()
            .zip(&run.final_bodies)
            .filter(|(b, s)| {
                !b.fixed
                    && (0..scene.dim).any(|k| !(s.position[k] >= lo[k] && s.position[k] <= hi[k]))
            })
            .count()
    });
    let wall = run.wall_seconds;
    let total_change = (last.kinetic + last.potential) - (first.kinetic + first.potential);
    let balance = Balance::of(scene, run, total_change);
    let mut warnings = scene.warnings.clone();
    warnings.extend(balance.warnings(scene, run));
    Report {
        scene: scene.file.clone(),
        description: scene.description.clone(),
        dim: scene.dim,
        precision: scene.precision.name(),
        mode: run.mode.name().to_owned(),
        steps: run.steps,
        dt: scene.dt,
        bodies,
        energy: Energy {
            kinetic_initial: first.kinetic,
            kinetic_final: last.kinetic,
            potential_initial: first.potential,
            potential_final: last.potential,
            total_change,
        },
        momentum: Momentum {
            initial: MomentumPair {
                law: first.momentum_law.clone(),
                all: first.momentum_all.clone(),
            },
            r#final: MomentumPair {
                law: last.momentum_law.clone(),
                all: last.momentum_all.clone(),
            },
        },
        impacts: Impacts {
            count: run.stats.impacts,
            clamped: run.stats.clamped,
            dissipated: run.stats.dissipated,
            unmet_dissipation: run.stats.unmet_dissipation,
            unbounded_clamps: run.stats.unbounded_clamps,
            clamps: crate::clamps::Clamps::of(&run.stats).explain(run.mode),
            skipped_non_finite: run.stats.skipped_non_finite,
            event_cap_hits: run.stats.event_cap_hits,
        },
        timing: Timing {
            wall_seconds: wall,
            seconds_per_step: if run.steps > 0 {
                wall / run.steps as f64
            } else {
                0.0
            },
        },
        effects: scene.active_effects(),
        setup: Setup {
            gravity: scene.effective_gravity(),
            dissipation: scene.effective_law().dissipation,
            ccd_bodies: run.ccd_bodies,
            auto_ccd_bodies: run.auto_ccd_bodies,
            soft_ccd_bodies: run.soft_ccd_bodies,
            contact_recycling: run.contact_recycling,
            locked_rotations: run.locked_rotations,
            zeroed_friction: run.zeroed_friction,
            joints: run.joints,
            added: added(scene, run),
            marked_bodies: run.law_bodies,
            body_count: scene.bodies.len(),
            substeps: run.substeps,
        },
        checks: Checks {
            max_penetration: run.max_penetration,
            max_penetration_ratio: run.max_penetration_ratio,
            crossings: run.crossings,
            escaped,
            non_finite,
            energy_integrator: balance.integrator,
            energy_unexplained: balance.unexplained,
            energy_scale: balance.energy_scale,
            momentum_change: balance.momentum_change,
            momentum_scale: balance.momentum_scale,
            momentum_conserved: balance.momentum_conserved,
            tolerance: balance.tolerance,
        },
        warnings,
    }
}

/// The energy and momentum balance of a run (see [`Checks`]).
struct Balance {
    integrator: f64,
    unexplained: f64,
    energy_scale: f64,
    momentum_change: f64,
    momentum_scale: f64,
    momentum_conserved: bool,
    tolerance: f64,
}

impl Balance {
    fn of(scene: &Scene, run: &RunOutput, total_change: f64) -> Self {
        let first = &run.samples[0];
        let last = run.samples.last().unwrap_or(first);
        // The substep rapier integrates with (a run always has at least one).
        let h = scene.dt / run.substeps.max(1) as f64;
        // −(h/2) ΔP, written so that no gravity gives +0, not −0.
        let integrator = 0.5 * h * (first.gravity_power - last.gravity_power);
        let largest = |f: fn(&Sample) -> f64| run.samples.iter().map(f).fold(0.0, f64::max);
        let dp: Vec<f64> = last
            .momentum_all
            .iter()
            .zip(&first.momentum_all)
            .map(|(a, b)| a - b)
            .collect();
        Self {
            integrator,
            unexplained: total_change + run.stats.dissipated - integrator,
            energy_scale: largest(|s| s.energy_scale),
            momentum_change: norm(&dp),
            momentum_scale: largest(|s| s.momentum_scale),
            momentum_conserved: scene.conserves_momentum(),
            tolerance: tolerance(scene.precision, run.steps, run.substeps),
        }
    }

    /// The warnings of the run: energy unexplained, or momentum changed in a
    /// scene that conserves it, beyond the tolerance (written so that a NaN
    /// warns), each saying what the user can do.
    fn warnings(&self, scene: &Scene, run: &RunOutput) -> Vec<String> {
        let mut w = Vec::new();
        let mode = run.mode.name();
        if !(self.unexplained.abs() <= self.tolerance * self.energy_scale) {
            w.push(format!(
                "{}: {mode}: energy unexplained {:.3e} is {:.3e} of the energy scale {:.3e} (tolerance {:.1e}): \
                 neither the law's dissipation ({:.3e}) nor rapier's integrator ({:.3e}) accounts for it: {}",
                scene.file,
                self.unexplained,
                self.unexplained.abs() / self.energy_scale,
                self.energy_scale,
                self.tolerance,
                run.stats.dissipated,
                self.integrator,
                if self.unexplained > 0.0 {
                    created(scene)
                } else {
                    LOST
                },
            ));
        }
        if self.momentum_conserved
            && !(self.momentum_change <= self.tolerance * self.momentum_scale)
        {
            w.push(format!(
                "{}: {mode}: momentum changed by {:.3e} ({:.3e} of the momentum scale {:.3e}, tolerance {:.1e}) \
                 in a scene with no fixed body, no gravity and no joint to the world: for example a body \
                 fell asleep (rapier zeroes the velocity of a body slower than its sleep threshold) or met \
                 rapier's speed cap; compare the modes with `kimpact compare`, and if no body slows to rest \
                 or reaches 400 m/s, report the scene",
                scene.file,
                self.momentum_change,
                self.momentum_change / self.momentum_scale,
                self.momentum_scale,
                self.tolerance,
            ));
        }
        w
    }
}

/// Every setting the command adds to rapier beyond the scene (see
/// [`Setup::added`]).
fn added(scene: &Scene, run: &RunOutput) -> Vec<String> {
    let mut out = Vec::new();
    let not_listed = |e: Effect| {
        if scene.effects.contains(&e) {
            "listed, but absent from the scene"
        } else {
            "not in `effects`"
        }
    };
    if scene.gravity.iter().any(|g| *g != 0.0) && !scene.active(Effect::Gravity) {
        out.push(format!(
            "gravity set to zero: \"gravity\" is {}",
            not_listed(Effect::Gravity)
        ));
    }
    if run.zeroed_friction > 0 {
        out.push(format!(
            "friction set to 0 on {} bodies: \"friction\" is not in `effects`",
            run.zeroed_friction
        ));
    }
    if run.locked_rotations > 0 {
        out.push(format!(
            "rotations locked on {} moving bodies (`RigidBodyBuilder::lock_rotations`): \"spin\" is not in `effects`",
            run.locked_rotations
        ));
    }
    if run.auto_ccd_bodies > 0 {
        out.push(format!(
            "CCD (`ccd_enabled`) on {} bodies that could move more than their size in a step: `auto_ccd`",
            run.auto_ccd_bodies
        ));
    }
    if run.soft_ccd_bodies > 0 {
        out.push(format!(
            "soft CCD (`soft_ccd_prediction`) on {} bodies: `auto_ccd`, native mode",
            run.soft_ccd_bodies
        ));
    }
    if !run.contact_recycling {
        out.push(
            "contact recycling off (`IntegrationParameters::contact_recycling`): soft CCD needs every pair looked at in every step"
                .to_owned(),
        );
    }
    let dissipates = law_dissipates(&scene.law) || scene.materials.iter().any(|m| m.dissipates());
    if run.mode != kimpact::Mode::Native && dissipates && !scene.active(Effect::Dissipation) {
        out.push(format!(
            "the elastic law for every pair: \"dissipation\" is {}",
            not_listed(Effect::Dissipation)
        ));
    }
    let rough = scene.bodies.iter().any(|b| {
        b.material
            .is_some_and(|i| scene.materials[i].has_impact_friction())
    });
    if run.mode != kimpact::Mode::Native && rough && !scene.impact_friction_active() {
        out.push(
            "frictionless impacts (the materials' `impact_friction` off): \"friction\" is not in `effects`"
                .to_owned(),
        );
    }
    out
}

/// The cause and the remedy of energy lost (a warning's end): the list of
/// causes is not complete, and says so.
const LOST: &str = "energy lost, for example in rapier's contacts (restitution below 1, friction, \
     resting or simultaneous contacts), in rapier's joints, to sleeping bodies, to rapier's speed \
     cap, or at impacts under gravity (an impact changes the integrator's energy by (h/2) m g·Δv, \
     docs/report.md, \"The energy balance\"): `kimpact compare` shows which modes lose it, and \
     running the scene without an effect (`effects`) shows which effect does";

/// The cause and the remedy of energy created (a warning's end).
fn created(scene: &Scene) -> &'static str {
    match scene.precision {
        Precision::F32 => {
            "energy created, which no mode should do unless a rapier restitution above 1 asks for \
             it: if it is f32 rounding, beyond the tolerance's one rounding per substep, the scene in \
             precision \"f64\" does not warn; if that warns too, report the scene"
        }
        Precision::F64 => {
            "energy created, which no mode should do unless a rapier restitution above 1 asks for \
             it: beyond f64's rounding, so report the scene"
        }
    }
}

/// Whether law parameters dissipate.
fn law_dissipates(law: &kimpact::LawParams<f64>) -> bool {
    law.dissipation > 0.0 || law.wall_dissipation.is_some_and(|w| w > 0.0)
}

/// The bounding box of the fixed bodies, if the scene has any and it holds
/// every moving body at the start (used for the `escaped` check).
fn fixed_box(scene: &Scene) -> Option<(Vec<f64>, Vec<f64>)> {
    if !scene.active(Effect::FixedWalls) {
        return None;
    }
    let mut lo = vec![f64::INFINITY; scene.dim];
    let mut hi = vec![f64::NEG_INFINITY; scene.dim];
    for b in scene.bodies.iter().filter(|b| b.fixed) {
        let (l, h) = b.aabb(scene.dim);
        for k in 0..scene.dim {
            lo[k] = lo[k].min(l[k]);
            hi[k] = hi[k].max(h[k]);
        }
    }
    let inside = scene
        .bodies
        .iter()
        .filter(|b| !b.fixed)
        .all(|b| (0..scene.dim).all(|k| b.position[k] >= lo[k] && b.position[k] <= hi[k]));
    inside.then_some((lo, hi))
}
