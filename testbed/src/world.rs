//! A bundled scene as a rapier2d world and its kimpact resolver, as the CLI
//! builds it: the same bodies, shapes, orientations, masses, coefficients,
//! effects, joints and marks. Every law body is marked whatever the starting mode, so that the
//! mode can change while the scene runs (in native mode kimpact leaves the
//! marked pairs to rapier).

use kimpact_scene::{CombineRule, Effect, JointEnd, JointKind, Scene, Shape};
use kimpact2d::math::{Real, Vector};
use kimpact2d::rapier::prelude::*;
use kimpact2d::{Kimpact, Law, Material, Mode, ResolverConfig};

/// Why a scene cannot be opened in the 2D testbed.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The testbed app is rapier_testbed2d: 3D scenes need rapier_testbed3d.
    #[error("{file}: a {dim}D scene; this testbed is 2D")]
    NotTwoDimensional {
        /// The scene file.
        file: String,
        /// The scene's dimension.
        dim: usize,
    },
    /// The law or a material does not hold in f32 (the testbed's precision).
    #[error("{file}: {what}: {source}")]
    Law {
        /// The scene file.
        file: String,
        /// The law or the material's name.
        what: String,
        /// The law's own error.
        source: kimpact2d::LawError,
    },
}

/// A scene ready to run: rapier's world and kimpact's resolver for it.
pub struct Built {
    /// rapier's world (time step, gravity, bodies).
    pub world: PhysicsWorld,
    /// kimpact, in the starting mode, with the scene's law bodies marked.
    pub kimpact: Kimpact,
}

/// Build `scene` (2D) in f32 for rapier_testbed2d, kimpact in `mode`.
///
/// # Errors
/// [`BuildError`] for a 3D scene or a law the f32 build rejects.
pub fn build(scene: &Scene, mode: Mode) -> Result<Built, BuildError> {
    if scene.dim != 2 {
        return Err(BuildError::NotTwoDimensional {
            file: scene.file.clone(),
            dim: scene.dim,
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
        ..ResolverConfig::default()
    };
    let mut kimpact = Kimpact::with_config(law, mode, config)
        .expect("the default configuration with fixed_partners set is valid");
    let spin = scene.active(Effect::Spin);
    let friction = scene.active(Effect::Friction);
    let ccd = scene.ccd_flags();
    let mut handles = Vec::with_capacity(scene.bodies.len());
    for (i, b) in scene.bodies.iter().enumerate() {
        let mut rb = if b.fixed {
            RigidBodyBuilder::fixed()
        } else {
            RigidBodyBuilder::dynamic()
        }
        .translation(vector(&b.position))
        .rotation(b.rotation[0] as Real)
        .linvel(vector(&b.velocity))
        .angvel(b.angular_velocity[0] as Real)
        .ccd_enabled(ccd[i])
        .allow_fast_rotation(b.allow_fast_rotation);
        if !spin && !b.fixed {
            rb = rb.lock_rotations();
        }
        let mut co = match &b.shape {
            Shape::Ball { radius } => ColliderBuilder::ball(*radius as Real),
            Shape::Box { half_extents: h } => ColliderBuilder::cuboid(h[0] as Real, h[1] as Real),
            Shape::Capsule {
                half_height,
                radius,
            } => ColliderBuilder::capsule_y(*half_height as Real, *radius as Real),
            Shape::Convex { points } => {
                let points: Vec<Vector> = points.iter().map(|p| vector(p)).collect();
                ColliderBuilder::convex_hull(&points)
                    .expect("the scene's points were checked to span an area")
            }
        }
        .restitution(b.restitution as Real)
        .restitution_combine_rule(combine_rule(b.restitution_combine))
        .friction(if friction { b.friction as Real } else { 0.0 });
        if let Some(m) = b.mass {
            co = co.mass(m as Real);
        }
        let (h, c) = world.insert(rb, co);
        handles.push(h);
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
        // A fixed body is marked only to carry its material.
        match material {
            Some(m) if b.fixed || b.law => kimpact.mark_with(&world.colliders, c, m),
            None if b.law && !b.fixed => kimpact.mark(&world.colliders, c),
            _ => Ok(()),
        }
        .expect("inserted just above");
    }
    // Joints, as the CLI builds them: a world end is a fixed body without a
    // collider at the world anchor.
    for j in &scene.joints {
        let mut end = |e: JointEnd, anchor: &[f64]| match e {
            JointEnd::World => (
                world
                    .bodies
                    .insert(RigidBodyBuilder::fixed().translation(vector(anchor))),
                Vector::ZERO,
            ),
            JointEnd::Body(i) => (handles[i], vector(anchor)),
        };
        let (h1, a1) = end(j.body1, &j.anchor1);
        let (h2, a2) = end(j.body2, &j.anchor2);
        let limits = |l: &[f64; 2]| [l[0] as Real, l[1] as Real];
        let data: GenericJoint = match &j.kind {
            JointKind::Fixed => FixedJointBuilder::new()
                .local_anchor1(a1)
                .local_anchor2(a2)
                .contacts_enabled(j.contacts_enabled)
                .into(),
            // A 2D scene has no spherical joint (the validator says so): the
            // 2D joint that turns freely about its anchor is the revolute.
            JointKind::Revolute { .. } | JointKind::Spherical => {
                let l = match &j.kind {
                    JointKind::Revolute { limits, .. } => *limits,
                    _ => None,
                };
                let mut b = RevoluteJointBuilder::new()
                    .local_anchor1(a1)
                    .local_anchor2(a2)
                    .contacts_enabled(j.contacts_enabled);
                if let Some(l) = l {
                    b = b.limits(limits(&l));
                }
                b.into()
            }
            JointKind::Prismatic { axis, limits: l } => {
                let mut b = PrismaticJointBuilder::new(vector(axis))
                    .local_anchor1(a1)
                    .local_anchor2(a2)
                    .contacts_enabled(j.contacts_enabled);
                if let Some(l) = l {
                    b = b.limits(limits(l));
                }
                b.into()
            }
            JointKind::Rope { max_distance } => RopeJointBuilder::new(*max_distance as Real)
                .local_anchor1(a1)
                .local_anchor2(a2)
                .contacts_enabled(j.contacts_enabled)
                .into(),
        };
        world.impulse_joints.insert(h1, h2, data, true);
    }
    Ok(Built { world, kimpact })
}

/// The centre and the zoom (pixels per metre) that show the scene's
/// bounding box within `width` × `height` pixels.
pub fn frame(scene: &Scene, width: Real, height: Real) -> (Vector, Real) {
    let (lo, hi) = scene.extent();
    if !lo.iter().chain(&hi).all(|x| x.is_finite()) {
        return (Vector::ZERO, 100.0);
    }
    let centre = Vector::new(
        ((lo[0] + hi[0]) / 2.0) as Real,
        ((lo[1] + hi[1]) / 2.0) as Real,
    );
    let w = (hi[0] - lo[0]).max(1e-3) as Real;
    let h = (hi[1] - lo[1]).max(1e-3) as Real;
    (centre, (width / w).min(height / h))
}

fn vector(v: &[f64]) -> Vector {
    Vector::new(v[0] as Real, v[1] as Real)
}

fn combine_rule(rule: CombineRule) -> CoefficientCombineRule {
    match rule {
        CombineRule::Average => CoefficientCombineRule::Average,
        CombineRule::Min => CoefficientCombineRule::Min,
        CombineRule::Multiply => CoefficientCombineRule::Multiply,
        CombineRule::Max => CoefficientCombineRule::Max,
        CombineRule::ClampedSum => CoefficientCombineRule::ClampedSum,
        CombineRule::GeometricMean => CoefficientCombineRule::GeometricMean,
    }
}
