// The simulation, written once: included by the four modules of mod.rs,
// each with its own `k` (the adapter crate) and `w` (kimpact-world's
// builder for it).

/// Run the scene (see [`super::run`]).
pub(super) fn run(
    scene: &crate::scene::Scene,
    mode: kimpact::Mode,
    steps: u64,
    frame_steps: &[u64],
    progress: Option<&indicatif::ProgressBar>,
) -> super::RunOutput {
    use crate::scene::Effect;
    use k::rapier::prelude::*;
    use w::{angular_velocity, rotation, to_vec};

    let built = w::build(scene, mode).expect("the scene was checked in its precision when loaded");
    let soft_ccd_bodies = built.soft_ccd_bodies();
    let w::SceneWorld {
        mut world,
        mut kimpact,
        bodies: handles,
        colliders,
        ..
    } = built;
    let spin = scene.active(Effect::Spin);
    let friction = scene.active(Effect::Friction);
    let ccd = scene.ccd_flags();
    // Scene index and smallest half size of each collider (by collider index).
    let mut of_collider: Vec<Option<(usize, f64)>> = Vec::new();
    for (i, (c, b)) in colliders.iter().zip(&scene.bodies).enumerate() {
        let (index, _) = c.into_raw_parts();
        let index = index as usize;
        if of_collider.len() <= index {
            of_collider.resize(index + 1, None);
        }
        of_collider[index] = Some((i, b.shape.min_size()));
    }
    // What the command changes of the scene's bodies (see `RunOutput`).
    let locked_rotations = if spin {
        0
    } else {
        scene.bodies.iter().filter(|b| !b.fixed).count()
    };
    let zeroed_friction = if friction {
        0
    } else {
        scene.bodies.iter().filter(|b| b.friction > 0.0).count()
    };
    // The bodies the law governs: marked in every mode, left to rapier in
    // native mode.
    let law_bodies = if mode == k::Mode::Native {
        0
    } else {
        scene.bodies.iter().filter(|b| b.law && !b.fixed).count()
    };

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
    // A point of the crossing check (`z = 0` in 2D).
    let centre = |world: &PhysicsWorld, h: &RigidBodyHandle| -> super::crossing::Point {
        let mut p = [0.0; 3];
        for (p, x) in p.iter_mut().zip(to_vec(world.bodies[*h].translation())) {
            *p = x;
        }
        p
    };
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
        soft_ccd_bodies,
        contact_recycling: world.integration_parameters.contact_recycling,
        locked_rotations,
        zeroed_friction,
        joints: scene.joints.len(),
        law_bodies,
        substeps: world.integration_parameters.num_solver_iterations,
    }
}
