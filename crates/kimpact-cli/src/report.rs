//! The JSON report of one run.

use serde::Serialize;

use crate::scene::{Effect, Scene, Shape};
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
    /// Warnings about the scene.
    pub warnings: Vec<String>,
}

/// One body at the end of the run.
#[derive(Clone, Debug, Serialize)]
pub struct BodyReport {
    /// The body's label, if any.
    pub name: Option<String>,
    /// `"ball"` or `"box"`.
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
    /// Bodies with CCD.
    pub ccd_bodies: usize,
    /// Bodies marked for the law (0 in native mode).
    pub marked_bodies: usize,
    /// Bodies in the scene.
    pub body_count: usize,
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
    /// `energy.total_change + impacts.dissipated`: the change of total
    /// energy that the law's dissipation does not explain. Negative: energy
    /// lost in rapier's contacts (all of it in native mode); positive:
    /// energy created, which no mode should do.
    pub energy_unexplained: f64,
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
            total_change: (last.kinetic + last.potential) - (first.kinetic + first.potential),
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
            marked_bodies: run.law_bodies,
            body_count: scene.bodies.len(),
        },
        checks: Checks {
            max_penetration: run.max_penetration,
            max_penetration_ratio: run.max_penetration_ratio,
            crossings: run.crossings,
            escaped,
            non_finite,
            energy_unexplained: (last.kinetic + last.potential) - (first.kinetic + first.potential)
                + run.stats.dissipated,
        },
        warnings: scene.warnings.clone(),
    }
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
        let h = match &b.shape {
            Shape::Ball { radius } => vec![*radius; scene.dim],
            Shape::Box { half_extents } => half_extents.clone(),
        };
        for k in 0..scene.dim {
            lo[k] = lo[k].min(b.position[k] - h[k]);
            hi[k] = hi[k].max(b.position[k] + h[k]);
        }
    }
    let inside = scene
        .bodies
        .iter()
        .filter(|b| !b.fixed)
        .all(|b| (0..scene.dim).all(|k| b.position[k] >= lo[k] && b.position[k] <= hi[k]));
    inside.then_some((lo, hi))
}
