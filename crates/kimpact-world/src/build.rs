// The builder, written once: included by the four modules of lib.rs, each
// with its own `k` (the adapter crate) and the helpers of dim2.rs or dim3.rs.

use kimpact_scene::{CombineRule, Effect, Joint, JointEnd, JointKind, Scene, Shape};

use k::math::{Real, Vector};
use k::rapier::prelude::*;
use k::{Kimpact, Law, Material, Mode, ResolverConfig};

use crate::BuildError;

/// A scene ready to run: rapier's world, kimpact's resolver for it, and
/// where each scene body went.
pub struct SceneWorld {
    /// rapier's world (time step, gravity, bodies, colliders, joints).
    pub world: PhysicsWorld,
    /// kimpact, with the scene's law, effects, materials and law bodies.
    pub kimpact: Kimpact,
    /// Each scene body's rigid body, in the scene's order.
    pub bodies: Vec<RigidBodyHandle>,
    /// Each scene body's collider, in the scene's order.
    pub colliders: Vec<ColliderHandle>,
    /// Each scene body's soft CCD prediction in native mode (0: none).
    native_soft_ccd: Vec<Real>,
}

impl std::fmt::Debug for SceneWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SceneWorld")
            .field("mode", &self.kimpact.mode())
            .field("bodies", &self.bodies.len())
            .field("joints", &self.world.impulse_joints.len())
            .finish_non_exhaustive()
    }
}

/// Build `scene` with kimpact in `mode` (the world as
/// [`SceneWorld::set_mode`] sets it for `mode`).
///
/// Law bodies (`law`, not fixed) are marked, with their material if they
/// have one; a fixed body is marked only to carry its material. Rotations
/// are locked without the `spin` effect, friction is zero without
/// `friction`, fixed walls are the law's partners with `fixed_walls`. A
/// joint's end at the world is a fixed body without a collider at the world
/// anchor (as rapier's own examples build it), its local anchor the origin.
///
/// # Errors
/// [`BuildError::Dimension`] for a scene of another dimension;
/// [`BuildError::Law`] for a law or material the build's precision rejects.
pub fn build(scene: &Scene, mode: Mode) -> Result<SceneWorld, BuildError> {
    if scene.dim != k::math::DIM {
        return Err(BuildError::Dimension {
            file: scene.file.clone(),
            scene: scene.dim,
            world: k::math::DIM,
        });
    }
    let law_error = |what: &str| {
        let file = scene.file.clone();
        let what = what.to_string();
        move |source| BuildError::Law { file, what, source }
    };
    let mut world = PhysicsWorld {
        gravity: vector(&scene.effective_gravity()),
        ..PhysicsWorld::default()
    };
    world.integration_parameters.dt = scene.dt as Real;
    let law = Law::new(scene.effective_law().map(|x| x as Real)).map_err(law_error("law"))?;
    let config = ResolverConfig {
        fixed_partners: scene.active(Effect::FixedWalls),
        rebound_cutoff: scene.rebound_cutoff.map(|v| v as Real),
        ..ResolverConfig::default()
    };
    let mut kimpact = Kimpact::with_config(law, mode, config)
        .expect("the default configuration with fixed_partners and a checked cut-off is valid");

    let spin = scene.active(Effect::Spin);
    let friction = scene.active(Effect::Friction);
    let ccd = scene.ccd_flags();
    let native_soft_ccd: Vec<Real> = scene
        .soft_ccd_predictions()
        .iter()
        .map(|p| *p as Real)
        .collect();
    let soft_ccd = |i: usize| soft_ccd_in(mode, native_soft_ccd[i]);
    let mut bodies = Vec::with_capacity(scene.bodies.len());
    let mut colliders = Vec::with_capacity(scene.bodies.len());
    for (i, b) in scene.bodies.iter().enumerate() {
        let rb = if b.fixed {
            RigidBodyBuilder::fixed()
        } else {
            RigidBodyBuilder::dynamic()
        };
        let mut rb = turned(rb, &b.rotation, &b.angular_velocity)
            .translation(vector(&b.position))
            .linvel(vector(&b.velocity))
            .ccd_enabled(ccd[i])
            .soft_ccd_prediction(soft_ccd(i))
            .allow_fast_rotation(b.allow_fast_rotation);
        if !spin && !b.fixed {
            rb = rb.lock_rotations();
        }
        let mut co = collider(&b.shape)
            .restitution(b.restitution as Real)
            .restitution_combine_rule(combine_rule(b.restitution_combine))
            .friction(if friction { b.friction as Real } else { 0.0 });
        if let Some(m) = b.mass {
            co = co.mass(m as Real);
        }
        let (h, c) = world.insert(rb, co);
        // Impact friction (μ = 0, β = −1 when off) is the adapter's too.
        let material = match scene.effective_material(i) {
            Some(m) => Some(
                Material::new(m.dissipation as Real, m.wall_dissipation as Real)
                    .and_then(|k| {
                        k.with_impact_friction(
                            m.impact_friction as Real,
                            m.tangential_restitution as Real,
                        )
                    })
                    .map_err(law_error(&m.name))?
                    .with_combine_rule(combine_rule(m.combine)),
            ),
            None => None,
        };
        match material {
            Some(m) if b.fixed || b.law => kimpact.mark_with(&world.colliders, c, m),
            None if b.law && !b.fixed => kimpact.mark(&world.colliders, c),
            _ => Ok(()),
        }
        .expect("inserted just above");
        bodies.push(h);
        colliders.push(c);
    }
    let origin = Vector::ZERO;
    for j in &scene.joints {
        let mut end = |e: JointEnd, anchor: &[f64]| match e {
            JointEnd::World => (
                world
                    .bodies
                    .insert(RigidBodyBuilder::fixed().translation(vector(anchor))),
                origin,
            ),
            JointEnd::Body(i) => (bodies[i], vector(anchor)),
        };
        let (h1, a1) = end(j.body1, &j.anchor1);
        let (h2, a2) = end(j.body2, &j.anchor2);
        world.impulse_joints.insert(h1, h2, joint(j, a1, a2), true);
    }
    world.integration_parameters.contact_recycling = contact_recycling_in(mode, &native_soft_ccd);
    Ok(SceneWorld {
        world,
        kimpact,
        bodies,
        colliders,
        native_soft_ccd,
    })
}

/// A body's soft CCD prediction in `mode`, given its prediction in native
/// mode (see [`SceneWorld::set_mode`]).
fn soft_ccd_in(mode: Mode, native: Real) -> Real {
    if mode == Mode::Native { native } else { 0.0 }
}

/// Whether rapier recycles contacts in `mode`: not when a body has soft CCD.
fn contact_recycling_in(mode: Mode, native_soft_ccd: &[Real]) -> bool {
    !native_soft_ccd.iter().any(|p| soft_ccd_in(mode, *p) > 0.0)
}

impl SceneWorld {
    /// Switch kimpact to `mode` at the next step, and the world with it: in
    /// native mode soft CCD on the scene's fast bodies and, if any has it,
    /// contact recycling off; in the law modes neither.
    ///
    /// rapier's CCD sweeps a fast body against fixed colliders, and a CCD
    /// ("bullet") body against moving bodies that are not bullets, never
    /// bullet against bullet: in native mode, soft CCD (contacts predicted
    /// as far as the pair closes in a step) keeps a fast ball from sinking
    /// into another one. rapier keeps a pair's contacts without looking
    /// again while the pair has moved less than the prediction distance
    /// since its last look, so a pair closing by most of that in one step
    /// would meet unseen: with soft CCD, every pair is looked at every step.
    /// The law modes resolve moving pairs themselves and do without both:
    /// rapier's solver would stop a ball at a predicted contact before the
    /// law sees the impact.
    pub fn set_mode(&mut self, mode: Mode) {
        self.kimpact.set_mode(mode);
        for (h, p) in self.bodies.iter().zip(&self.native_soft_ccd) {
            let p = soft_ccd_in(mode, *p);
            let rb = &mut self.world.bodies[*h];
            if rb.soft_ccd_prediction() != p {
                rb.set_soft_ccd_prediction(p);
            }
        }
        self.world.integration_parameters.contact_recycling =
            contact_recycling_in(mode, &self.native_soft_ccd);
    }

    /// How many scene bodies have soft CCD in the current mode.
    pub fn soft_ccd_bodies(&self) -> usize {
        self.bodies
            .iter()
            .filter(|h| self.world.bodies[**h].soft_ccd_prediction() > 0.0)
            .count()
    }
}

/// Scene vector → rapier vector.
pub fn vector(v: &[f64]) -> Vector {
    let v: Vec<Real> = v.iter().map(|x| *x as Real).collect();
    Vector::from_slice(&v)
}

/// rapier vector → scene vector.
pub fn to_vec(v: Vector) -> Vec<f64> {
    v.to_array().iter().map(|x| *x as f64).collect()
}

/// The collider of a scene shape.
fn collider(shape: &Shape) -> ColliderBuilder {
    match shape {
        Shape::Ball { radius } => ColliderBuilder::ball(*radius as Real),
        Shape::Box { half_extents } => cuboid(half_extents),
        Shape::Capsule {
            half_height,
            radius,
        } => ColliderBuilder::capsule_y(*half_height as Real, *radius as Real),
        Shape::Convex { points } => {
            let points: Vec<Vector> = points.iter().map(|p| vector(p)).collect();
            ColliderBuilder::convex_hull(&points)
                .expect("the scene's points were checked to span a hull")
        }
    }
}

/// rapier's joint for a scene joint, with its local anchors.
fn joint(j: &Joint, a1: Vector, a2: Vector) -> GenericJoint {
    let limits = |l: &Option<[f64; 2]>| l.map(|l| [l[0] as Real, l[1] as Real]);
    let mut joint: GenericJoint = match &j.kind {
        JointKind::Fixed => FixedJointBuilder::new().into(),
        JointKind::Revolute { axis, limits: l } => {
            let b = revolute(axis.as_deref());
            match limits(l) {
                Some(l) => b.limits(l).into(),
                None => b.into(),
            }
        }
        JointKind::Spherical => spherical(),
        JointKind::Prismatic { axis, limits: l } => {
            let b = PrismaticJointBuilder::new(vector(axis));
            match limits(l) {
                Some(l) => b.limits(l).into(),
                None => b.into(),
            }
        }
        JointKind::Rope { max_distance } => RopeJointBuilder::new(*max_distance as Real).into(),
    };
    joint
        .set_local_anchor1(a1)
        .set_local_anchor2(a2)
        .set_contacts_enabled(j.contacts_enabled);
    joint
}

/// rapier's combine rule for a scene's.
pub fn combine_rule(rule: CombineRule) -> CoefficientCombineRule {
    use CoefficientCombineRule as R;
    match rule {
        CombineRule::Average => R::Average,
        CombineRule::Min => R::Min,
        CombineRule::Multiply => R::Multiply,
        CombineRule::Max => R::Max,
        CombineRule::ClampedSum => R::ClampedSum,
        CombineRule::GeometricMean => R::GeometricMean,
    }
}
