// The simulation, written once: included by the four modules of mod.rs,
// each with its own `k` (the adapter crate) and the helpers of dim2.rs or
// dim3.rs.

/// Run the scene (see [`super::run`]).
pub(super) fn run(
    scene: &crate::scene::Scene,
    mode: kimpact::Mode,
    steps: u64,
    frame_steps: &[u64],
    progress: Option<&indicatif::ProgressBar>,
) -> super::RunOutput {
    use crate::scene::Effect;
    use k::math::Real;
    use k::rapier::prelude::*;

    let mut world = PhysicsWorld {
        gravity: vector(&scene.effective_gravity()),
        ..PhysicsWorld::default()
    };
    world.integration_parameters.dt = scene.dt as Real;

    let spin = scene.active(Effect::Spin);
    let friction = scene.active(Effect::Friction);
    // Checked in the scene's precision when the scene was loaded.
    let law = k::Law::new(scene.effective_law().map(|x| x as Real))
        .expect("the scene's law was checked in its precision");
    let config = k::ResolverConfig {
        fixed_partners: scene.active(Effect::FixedWalls),
        ..k::ResolverConfig::default()
    };
    let mut kimpact = k::Kimpact::with_config(law, mode, config)
        .expect("the default configuration with fixed_partners set is valid");

    let ccd = scene.ccd_flags();
    // rapier's CCD sweeps a fast body against fixed colliders, and a CCD
    // ("bullet") body against moving bodies that are not bullets, never
    // bullet against bullet: in native mode, soft CCD (contacts predicted as
    // far as the pair closes in a step) keeps a fast ball from sinking into
    // another one. The law modes resolve moving pairs themselves and do
    // without it: rapier's solver would stop a ball at a predicted contact
    // before the law sees the impact (impulse mode lost 10% of the billiards
    // break's energy that way).
    let soft_ccd = if mode == k::Mode::Native {
        scene.soft_ccd_predictions()
    } else {
        vec![0.0; scene.bodies.len()]
    };
    if soft_ccd.iter().any(|p| *p > 0.0) {
        // rapier keeps a pair's contacts (none, for a pair not yet in
        // contact) without looking again while the pair has moved less than
        // the prediction distance since its last look: a pair closing by
        // most of that in one step then meets unseen, whatever soft CCD
        // predicts. Look at every pair at every step.
        world.integration_parameters.contact_recycling = false;
    }
    let mut handles = Vec::with_capacity(scene.bodies.len());
    // Scene index and smallest half size of each collider (by collider index).
    let mut of_collider: Vec<Option<(usize, f64)>> = Vec::new();
    let mut law_bodies = 0;
    // What the command changes of the scene's bodies (see `RunOutput`).
    let mut locked_rotations = 0;
    let mut zeroed_friction = 0;
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
            .soft_ccd_prediction(soft_ccd[i] as Real)
            .allow_fast_rotation(b.allow_fast_rotation);
        if !spin && !b.fixed {
            rb = rb.lock_rotations();
            locked_rotations += 1;
        }
        if !friction && b.friction > 0.0 {
            zeroed_friction += 1;
        }
        let mut co = collider(&b.shape)
            .restitution(b.restitution as Real)
            .restitution_combine_rule(combine_rule(b.restitution_combine))
            .friction(if friction { b.friction as Real } else { 0.0 });
        if let Some(m) = b.mass {
            co = co.mass(m as Real);
        }
        let (h, c) = world.insert(rb, co);
        // Only bodies that can meet the law are marked (never in native
        // mode, where kimpact does nothing), with their material if they
        // have one; a fixed body is marked only to carry its material.
        // Impact friction (μ = 0, β = −1 when off) is the adapter's too.
        let material = scene.effective_material(i).map(|m| {
            k::Material::new(m.dissipation as Real, m.wall_dissipation as Real)
                .and_then(|k| {
                    k.with_impact_friction(
                        m.impact_friction as Real,
                        m.tangential_restitution as Real,
                    )
                })
                .expect("the scene's materials were checked in its precision")
                .with_combine_rule(combine_rule(m.combine))
        });
        if mode != k::Mode::Native {
            match material {
                Some(m) if b.fixed || b.law => kimpact
                    .mark_with(&world.colliders, c, m)
                    .expect("inserted just above"),
                None if b.law && !b.fixed => kimpact
                    .mark(&world.colliders, c)
                    .expect("inserted just above"),
                _ => {}
            }
            if b.law && !b.fixed {
                law_bodies += 1;
            }
        }
        let (index, _) = c.into_raw_parts();
        let index = index as usize;
        if of_collider.len() <= index {
            of_collider.resize(index + 1, None);
        }
        of_collider[index] = Some((i, b.shape.min_size()));
        handles.push(h);
    }
    // Joints, with rapier's impulse joints. An end at the world is a fixed
    // body without a collider at the world anchor (as rapier's own
    // examples build it), its local anchor the origin.
    let origin = vec![0.0; scene.dim];
    for j in &scene.joints {
        let mut end = |e: crate::scene::JointEnd, anchor: &[f64]| match e {
            crate::scene::JointEnd::World => (
                world
                    .bodies
                    .insert(RigidBodyBuilder::fixed().translation(vector(anchor))),
                vector(&origin),
            ),
            crate::scene::JointEnd::Body(i) => (handles[i], vector(anchor)),
        };
        let (h1, a1) = end(j.body1, &j.anchor1);
        let (h2, a2) = end(j.body2, &j.anchor2);
        world.impulse_joints.insert(h1, h2, joint(j, a1, a2), true);
    }

    let gravity = scene.effective_gravity();
    let dim = scene.dim;
    let masses: Vec<Option<f64>> = handles
        .iter()
        .zip(&scene.bodies)
        .map(|(h, b)| (!b.fixed).then(|| world.bodies[*h].mass() as f64))
        .collect();
    let law_mask: Vec<bool> = scene.bodies.iter().map(|b| b.law && !b.fixed).collect();

    let sample = |world: &PhysicsWorld, time: f64| -> super::Sample {
        let mut kinetic = 0.0;
        let mut potential = 0.0;
        let mut momentum_all = vec![0.0; dim];
        let mut momentum_law = vec![0.0; dim];
        let mut gravity_power = 0.0;
        let mut potential_scale = 0.0;
        let mut momentum_scale = 0.0;
        for (i, h) in handles.iter().enumerate() {
            let Some(m) = masses[i] else { continue };
            let rb = &world.bodies[*h];
            let v = to_vec(rb.linvel());
            let x = to_vec(rb.translation());
            let v2: f64 = v.iter().map(|c| c * c).sum();
            let translational = 0.5 * m * v2;
            kinetic += translational;
            if spin {
                // rapier's total minus its own translational part.
                let lin = rb.linvel();
                let own = 0.5 * rb.mass() * lin.dot(lin);
                kinetic += (rb.kinetic_energy() - own).max(0.0) as f64;
            }
            let gx = gravity.iter().zip(&x).map(|(g, x)| g * x).sum::<f64>();
            potential -= m * gx;
            potential_scale += m * gx.abs();
            gravity_power += m * gravity.iter().zip(&v).map(|(g, v)| g * v).sum::<f64>();
            momentum_scale += m * v2.sqrt();
            for kk in 0..dim {
                momentum_all[kk] += m * v[kk];
                if law_mask[i] {
                    momentum_law[kk] += m * v[kk];
                }
            }
        }
        super::Sample {
            time,
            kinetic,
            potential,
            momentum_all,
            momentum_law,
            gravity_power,
            energy_scale: kinetic + potential_scale,
            momentum_scale,
        }
    };
    let state = |world: &PhysicsWorld| -> Vec<super::BodyState> {
        handles
            .iter()
            .map(|h| {
                let rb = &world.bodies[*h];
                super::BodyState {
                    position: to_vec(rb.translation()),
                    velocity: to_vec(rb.linvel()),
                    rotation: rotation(rb),
                    angular_velocity: angular_velocity(rb),
                }
            })
            .collect()
    };

    let mut samples = Vec::with_capacity(steps as usize + 1);
    let mut frames = Vec::with_capacity(frame_steps.len());
    samples.push(sample(&world, 0.0));
    let mut next_frame = 0;
    while next_frame < frame_steps.len() && frame_steps[next_frame] == 0 {
        frames.push(super::Frame {
            time: 0.0,
            bodies: state(&world),
        });
        next_frame += 1;
    }
    let mut wall = std::time::Duration::ZERO;
    let mut max_penetration: f64 = 0.0;
    let mut max_ratio: f64 = 0.0;
    let mut crossings: u64 = 0;
    let ball_radius: Vec<Option<f64>> = scene
        .bodies
        .iter()
        .map(|b| match b.shape {
            crate::scene::Shape::Ball { radius } => Some(radius),
            _ => None,
        })
        .collect();
    let centre =
        |world: &PhysicsWorld, h: &RigidBodyHandle| to_point(world.bodies[*h].translation());
    // Where every body started and ended the step (for the crossing check).
    let mut before: Vec<super::crossing::Point> = handles.iter().map(|h| centre(&world, h)).collect();
    let mut after = before.clone();
    let mut crossing = super::crossing::Crossings::default();
    for step in 1..=steps {
        let start = std::time::Instant::now();
        kimpact.step_world(&mut world, &(), &());
        wall += start.elapsed();
        let time = step as f64 * scene.dt;
        let of = |c: ColliderHandle| {
            let (index, _) = c.into_raw_parts();
            of_collider.get(index as usize).copied().flatten()
        };
        for pair in world.narrow_phase.contact_pairs() {
            if !pair.has_any_active_contact() {
                continue;
            }
            let size = |c: ColliderHandle| of(c).map_or(f64::INFINITY, |x| x.1);
            let smaller = size(pair.collider1).min(size(pair.collider2));
            for manifold in pair.manifolds() {
                for point in &manifold.points {
                    let depth = -(point.dist as f64);
                    if depth > max_penetration {
                        max_penetration = depth;
                    }
                    if depth / smaller > max_ratio {
                        max_ratio = depth / smaller;
                    }
                }
            }
        }
        for (x, h) in after.iter_mut().zip(&handles) {
            *x = centre(&world, h);
        }
        crossings += crossing.count(&before, &after, &ball_radius);
        std::mem::swap(&mut before, &mut after);
        samples.push(sample(&world, time));
        while next_frame < frame_steps.len() && frame_steps[next_frame] == step {
            frames.push(super::Frame {
                time,
                bodies: state(&world),
            });
            next_frame += 1;
        }
        if let Some(p) = progress {
            p.inc(1);
        }
    }
    let s = kimpact.stats();
    super::RunOutput {
        mode,
        steps,
        masses,
        final_bodies: state(&world),
        samples,
        frames,
        stats: s,
        wall_seconds: wall.as_secs_f64(),
        max_penetration,
        max_penetration_ratio: max_ratio,
        crossings,
        ccd_bodies: ccd.iter().filter(|c| **c).count(),
        auto_ccd_bodies: scene.auto_ccd_flags().iter().filter(|c| **c).count(),
        soft_ccd_bodies: soft_ccd.iter().filter(|p| **p > 0.0).count(),
        contact_recycling: world.integration_parameters.contact_recycling,
        locked_rotations,
        zeroed_friction,
        joints: scene.joints.len(),
        law_bodies,
        substeps: world.integration_parameters.num_solver_iterations,
    }
}

/// rapier's combine rule for a scene's.
fn combine_rule(rule: crate::scene::CombineRule) -> k::rapier::prelude::CoefficientCombineRule {
    use crate::scene::CombineRule as S;
    use k::rapier::prelude::CoefficientCombineRule as R;
    match rule {
        S::Average => R::Average,
        S::Min => R::Min,
        S::Multiply => R::Multiply,
        S::Max => R::Max,
        S::ClampedSum => R::ClampedSum,
        S::GeometricMean => R::GeometricMean,
    }
}
