//! What the simulation derives from a validated scene: the effects in
//! force, the law and materials as simulated, speed bounds and CCD.

use kimpact::LawParams;

use crate::{Effect, JointEnd, Material, Scene};

/// Whether law parameters dissipate (d̃ or the wall's d̃ positive).
pub(crate) fn law_dissipates(law: &LawParams<f64>) -> bool {
    law.dissipation > 0.0 || law.wall_dissipation.is_some_and(|w| w > 0.0)
}

impl Scene {
    /// Whether `effect` is active: called for and present in the scene.
    pub fn active(&self, effect: Effect) -> bool {
        if !self.effects.contains(&effect) {
            return false;
        }
        match effect {
            Effect::Gravity => self.gravity.iter().any(|g| *g != 0.0),
            Effect::Dissipation => {
                law_dissipates(&self.law) || self.materials.iter().any(Material::dissipates)
            }
            Effect::Friction => self.bodies.iter().any(|b| {
                b.friction > 0.0
                    || b.material
                        .is_some_and(|i| self.materials[i].has_impact_friction())
            }),
            Effect::Spin => self.bodies.iter().any(|b| !b.fixed),
            Effect::FixedWalls => self.bodies.iter().any(|b| b.fixed),
        }
    }

    /// The active effects' names.
    pub fn active_effects(&self) -> Vec<&'static str> {
        Effect::ALL
            .into_iter()
            .filter(|e| self.active(*e))
            .map(Effect::name)
            .collect()
    }

    /// Gravity as simulated (zero unless the effect is active).
    pub fn effective_gravity(&self) -> Vec<f64> {
        if self.active(Effect::Gravity) {
            self.gravity.clone()
        } else {
            vec![0.0; self.dim]
        }
    }

    /// The law as simulated (elastic unless `dissipation` is active).
    pub fn effective_law(&self) -> LawParams<f64> {
        if self.active(Effect::Dissipation) {
            self.law
        } else {
            LawParams {
                dissipation: 0.0,
                wall_dissipation: None,
                ..self.law
            }
        }
    }

    /// Whether the law's impacts have friction: `friction` is active and a
    /// body's material gives impact friction.
    pub fn impact_friction_active(&self) -> bool {
        self.active(Effect::Friction)
            && self.bodies.iter().any(|b| {
                b.material
                    .is_some_and(|i| self.materials[i].has_impact_friction())
            })
    }

    /// Body `i`'s material as simulated: none unless `dissipation` is
    /// active or [impact friction](Self::impact_friction_active) is (the
    /// elastic law, without impact friction, then governs every pair);
    /// without `dissipation` its d̃ and wall d̃ are zero, without impact
    /// friction it has none (μ = 0, β =
    /// [`Material::NO_TANGENTIAL_RESTITUTION`]). With impact friction a
    /// body whose material has none is marked with it too, so that a pair
    /// combines the two materials' μ whether `dissipation` is on or not.
    pub fn effective_material(&self, i: usize) -> Option<Material> {
        let dissipation = self.active(Effect::Dissipation);
        let friction = self.impact_friction_active();
        if !dissipation && !friction {
            return None;
        }
        let mut m = self.materials.get(self.bodies[i].material?)?.clone();
        if !dissipation {
            m.dissipation = 0.0;
            m.wall_dissipation = 0.0;
        }
        if !friction {
            m.impact_friction = 0.0;
            m.tangential_restitution = Material::NO_TANGENTIAL_RESTITUTION;
        }
        Some(m)
    }

    /// The speed no moving body can exceed (`None` for fixed bodies): the
    /// energy bound `sqrt(2 E / m)`, as fast as if the body held all the
    /// scene's energy, `E` the kinetic energy plus, with gravity, the
    /// potential energy of every body falling across the whole scene
    /// (`Σ m |g| H`, `H` its largest extent). It holds for any sequence of
    /// elastic or dissipative impacts (a light ball trapped by a heavy one
    /// gains far more than twice any initial speed).
    pub fn speed_bounds(&self) -> Vec<Option<f64>> {
        let speed2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
        let kinetic: f64 = self
            .bodies
            .iter()
            .filter_map(|b| b.mass.map(|m| 0.5 * m * speed2(&b.velocity)))
            .sum();
        let g = speed2(&self.effective_gravity()).sqrt();
        let (lo, hi) = self.extent();
        let height = (0..self.dim).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let potential: f64 = g * height * self.bodies.iter().filter_map(|b| b.mass).sum::<f64>();
        let energy = kinetic + potential;
        self.bodies
            .iter()
            .map(|b| match (b.fixed, b.mass) {
                (false, Some(m)) => Some((2.0 * energy / m).sqrt()),
                _ => None,
            })
            .collect()
    }

    /// Which bodies get rapier's CCD: as written (`ccd`); for a moving body
    /// that does not say, none (rapier's default), or, with
    /// [`auto_ccd`](Scene::auto_ccd), CCD when it could move more than its
    /// smallest half size in one step at its
    /// [speed bound](Self::speed_bounds). Slow bodies keep CCD cheap:
    /// rapier does time-of-impact work only for CCD bodies that actually
    /// move fast in a step.
    pub fn ccd_flags(&self) -> Vec<bool> {
        let auto = self.auto_ccd_flags();
        self.bodies
            .iter()
            .zip(auto)
            .map(|(b, auto)| !b.fixed && b.ccd.unwrap_or(auto))
            .collect()
    }

    /// Which bodies the `auto_ccd` rule gives CCD (moving bodies without a
    /// written `ccd`, fast at their speed bound; none without `auto_ccd`).
    pub fn auto_ccd_flags(&self) -> Vec<bool> {
        if !self.auto_ccd {
            return vec![false; self.bodies.len()];
        }
        self.bodies
            .iter()
            .zip(self.speed_bounds())
            .map(|(b, bound)| match (b.fixed, b.ccd, bound) {
                (false, None, Some(v)) => v * self.dt > b.shape.min_size(),
                _ => false,
            })
            .collect()
    }

    /// rapier's soft-CCD prediction distance of each body (0: none), with
    /// [`auto_ccd`](Scene::auto_ccd) only: the distance a CCD body can
    /// cover in one step at its [speed bound](Self::speed_bounds). rapier's
    /// CCD never sweeps one CCD body against another; soft CCD also catches
    /// such pairs, by predicting contacts as far ahead as the pair closes in
    /// the step (each body's velocity capped at this distance per step, so
    /// the bound caps nothing). A slow body that a fast one hits later has
    /// the same bound, and the fast one carries the prediction meanwhile.
    /// The simulation uses it in native mode only (see `docs/scenes.md`,
    /// "CCD").
    pub fn soft_ccd_predictions(&self) -> Vec<f64> {
        if !self.auto_ccd {
            return vec![0.0; self.bodies.len()];
        }
        self.ccd_flags()
            .into_iter()
            .zip(self.speed_bounds())
            .map(|(ccd, bound)| match (ccd, bound) {
                (true, Some(v)) => v * self.dt,
                _ => 0.0,
            })
            .collect()
    }

    /// Whether the scene conserves momentum: no fixed body, no gravity, no
    /// joint to the world or to a fixed body.
    pub fn conserves_momentum(&self) -> bool {
        let anchored = |end: JointEnd| match end {
            JointEnd::World => true,
            JointEnd::Body(i) => self.bodies[i].fixed,
        };
        !self.active(Effect::FixedWalls)
            && !self.active(Effect::Gravity)
            && !self
                .joints
                .iter()
                .any(|j| anchored(j.body1) || anchored(j.body2))
    }

    /// The bounding box of every body at the start.
    pub fn extent(&self) -> (Vec<f64>, Vec<f64>) {
        let mut lo = vec![f64::INFINITY; self.dim];
        let mut hi = vec![f64::NEG_INFINITY; self.dim];
        for b in &self.bodies {
            let (l, h) = b.aabb(self.dim);
            for k in 0..self.dim {
                lo[k] = lo[k].min(l[k]);
                hi[k] = hi[k].max(h[k]);
            }
        }
        (lo, hi)
    }

    /// The picture times: as written (clamped to the run), or five evenly
    /// spaced from 0 to the end.
    pub fn picture_times(&self, steps: u64) -> Vec<f64> {
        let end = steps as f64 * self.dt;
        match &self.view.times {
            Some(t) => t.iter().map(|t| t.min(end)).collect(),
            None => (0..5).map(|i| end * i as f64 / 4.0).collect(),
        }
    }
}
