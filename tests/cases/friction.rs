// Impact friction through the adapter (issue 40): Walton's model at the
// impacts the law resolves, written once for 2D/3D and f32/f64 (included
// by tests/adapter.rs after cases/adapter.rs, whose imports and `tol` it
// uses).

/// `I = q m R²` for rapier's ball: a solid sphere in 3D, a disc in 2D.
fn ball_inertia_share() -> f64 {
    if DIM == 3 { 0.4 } else { 0.5 }
}

/// A marked ball with impact friction (`μ`, `β`) and rotations free.
fn rough_ball(
    w: &mut TestWorld,
    position: Vector,
    velocity: Vector,
    spin: Real,
    (mu, beta): (Real, Real),
) -> (RigidBodyHandle, ColliderHandle) {
    let omega = <Angular as SpinAbout>::about_z(spin);
    let body = RigidBodyBuilder::dynamic()
        .translation(position)
        .linvel(velocity)
        .angvel(omega)
        .can_sleep(false);
    let collider = ColliderBuilder::ball(0.5)
        .density(1.0)
        .friction(0.0)
        .restitution(1.0);
    let (b, c) = w.world.insert(body, collider);
    let material = k::Material::new(0.0, 0.0)
        .unwrap()
        .with_impact_friction(mu, beta)
        .unwrap();
    w.kimpact
        .mark_with(&w.world.colliders, c, material)
        .expect("inserted just above");
    (b, c)
}

/// What the law keeps of momentum and angular momentum, relative: 1e-12
/// in f64 (the bound), 1e-5 in f32.
fn kept() -> f64 {
    if std::mem::size_of::<Real>() == 8 {
        1e-12
    } else {
        1e-5
    }
}

/// rapier's angular velocity in this dimension (a scalar in 2D).
type Angular = k::rapier::math::AngVector;

/// An angular velocity about z in either dimension.
trait SpinAbout: Sized {
    fn about_z(x: Real) -> Self;
    fn z_of(&self) -> f64;
}

impl SpinAbout for Real {
    fn about_z(x: Real) -> Self {
        x
    }
    fn z_of(&self) -> f64 {
        f64::from(*self)
    }
}

impl SpinAbout for Vector {
    fn about_z(x: Real) -> Self {
        let mut v = Vector::ZERO;
        v[DIM - 1] = x;
        v
    }
    fn z_of(&self) -> f64 {
        f64::from(self[DIM - 1])
    }
}

/// Kinetic energy with rotation, linear momentum, and angular momentum
/// about the origin (its z component) of the dynamic bodies.
fn totals(w: &TestWorld) -> (f64, [f64; 3], f64) {
    let (mut energy, mut momentum, mut angular) = (0.0, [0.0; 3], 0.0);
    for (_, rb) in w.world.bodies.iter().filter(|(_, b)| b.is_dynamic()) {
        let m = f64::from(rb.mass());
        let (x, v) = (rb.translation(), rb.linvel());
        let wz = rb.angvel().z_of();
        let i = f64::from(rb.mass_properties().local_mprops.principal_inertia().z_of_inertia());
        energy += 0.5 * m * f64::from(v.length_squared()) + 0.5 * rb_rot_energy(rb);
        for a in 0..DIM {
            momentum[a] += m * f64::from(v[a]);
        }
        angular += m * (f64::from(x[0]) * f64::from(v[1]) - f64::from(x[1]) * f64::from(v[0]))
            + i * wz;
    }
    (energy, momentum, angular)
}

/// Twice the rotational energy of `rb` (`ω·Iω`; the balls are isotropic).
fn rb_rot_energy(rb: &RigidBody) -> f64 {
    let i = f64::from(rb.mass_properties().local_mprops.principal_inertia().z_of_inertia());
    let w = rb.angvel();
    i * spin_norm_squared(&w)
}

/// `|ω|²` in either dimension.
trait SpinNorm {
    fn norm2(&self) -> f64;
}

impl SpinNorm for Real {
    fn norm2(&self) -> f64 {
        f64::from(*self) * f64::from(*self)
    }
}

impl SpinNorm for Vector {
    fn norm2(&self) -> f64 {
        f64::from(self.length_squared())
    }
}

fn spin_norm_squared<W: SpinNorm>(w: &W) -> f64 {
    w.norm2()
}

/// The principal inertia about z in either dimension.
trait InertiaZ {
    fn z_of_inertia(&self) -> Real;
}

impl InertiaZ for Real {
    fn z_of_inertia(&self) -> Real {
        *self
    }
}

impl InertiaZ for Vector {
    fn z_of_inertia(&self) -> Real {
        self[DIM - 1]
    }
}

/// Issue 40.4: a cut shot between equal balls without spin (stun), in free
/// space, elastic normal law, `β = 0`: the object ball's throw angle against
/// the closed form of Alciatore's TP A-14, `tan θ = min(μ, tan φ / 7)` for
/// solid spheres (in general `tan φ / (2 (1 + 1/q))` with `I = q m R²`: a
/// disc in 2D gives `tan φ / 6`), over cut angles 0-60°, sticking below the
/// crossover and sliding above it, with `φ` the angle of the normal the law
/// acted along (the impact's). The replay (impulse and exact mode) applies
/// the law itself: to rounding. Restitution mode hands it to rapier's
/// solver: exact when sliding, within the bound its contact's arms give
/// when sticking. Momentum and angular momentum are kept and the energy
/// never rises.
#[test]
fn a_cut_shot_throws_the_object_ball_as_tp_a14_says() {
    let q = ball_inertia_share();
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        for mu in [0.06 as Real, 0.2] {
            for degrees in [0.0 as Real, 5.0, 15.0, 30.0, 45.0, 60.0] {
                let case = format!("{mode:?}, μ = {mu}, φ = {degrees}°");
                let phi = degrees.to_radians();
                let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
                // The line of centres at the impact, at φ to the cue's path (x).
                let mut n = Vector::ZERO;
                n[0] = phi.cos();
                n[1] = phi.sin();
                let object = Vector::ZERO;
                let mut back = Vector::ZERO;
                back[0] = 0.25;
                let cue_start = object - n * 1.0 - back;
                let mut speed = Vector::ZERO;
                speed[0] = 1.0;
                let (cue, _) = rough_ball(&mut w, cue_start, speed, 0.0, (mu, 0.0));
                let (ob, _) = rough_ball(&mut w, object, Vector::ZERO, 0.0, (mu, 0.0));
                let before = totals(&w);
                let mut events = Vec::new();
                for _ in 0..40 {
                    w.step();
                    events.extend_from_slice(w.kimpact.events());
                }
                assert_eq!(events.len(), 1, "{case}");
                let after = totals(&w);
                // The line of centres the law acted along: the impact's own
                // (restitution mode bounces along rapier's contact normal at
                // the start of the step, a little off the line of centres at
                // the impact when the balls were not touching yet).
                let normal = events[0].normal * events[0].normal.dot(n).signum();
                let cut = f64::from(normal[1]).atan2(f64::from(normal[0]));
                let tangent = {
                    let mut t = Vector::ZERO;
                    t[0] = -normal[1];
                    t[1] = normal[0];
                    t
                };
                let v = w.vel(ob);
                let (along, across) = (f64::from(v.dot(normal)), f64::from(v.dot(tangent)));
                let tan_phi = cut.tan();
                let expected = f64::from(mu).min(tan_phi / (2.0 * (1.0 + 1.0 / q)));
                let throw = across.abs() / along;
                // Restitution mode: rapier's solver applies the impulse at
                // its contact of the start of the step, the balls up to
                // `U dt` apart (`U = 1`), its arms up to `R + U dt/2` long:
                // a sticking impact's tangential mass, `1/m + R'²/I` per
                // ball, is that much larger and the throw that much smaller
                // (sliding takes `μ J_n` whatever the arms).
                let low = if mode == Mode::Restitution {
                    let stretch = 1.0 + (1.0 / 60.0) / (2.0 * 0.5);
                    expected * (1.0 + 1.0 / q) / (1.0 + stretch * stretch / q)
                } else {
                    expected
                };
                assert!(
                    throw >= low - tol() * (1.0 + expected)
                        && throw <= expected + tol() * (1.0 + expected),
                    "{case}: tan θ = {throw}, TP A-14 {expected} (at least {low})"
                );
                // The throw is along the cue ball's tangential motion (−t).
                if degrees > 0.0 {
                    assert!(across < 0.0, "{case}: thrown the wrong way ({across})");
                }
                let scale = 0.5 * f64::from(w.world.bodies[cue].mass());
                assert!(after.0 <= before.0 * (1.0 + tol()), "{case}: energy rose {before:?} → {after:?}");
                for a in 0..DIM {
                    assert!(
                        (after.1[a] - before.1[a]).abs() <= kept() * scale,
                        "{case}: momentum"
                    );
                }
                // Restitution mode's impulses act along the normal of the
                // start of the step, through points the bodies carry on
                // their own paths to the impact: rapier's contact conserves
                // angular momentum only as far as those stay one point.
                if mode != Mode::Restitution {
                    assert!(
                        (after.2 - before.2).abs() <= kept() * scale,
                        "{case}: angular momentum {} → {}",
                        before.2,
                        after.2
                    );
                }
            }
        }
    }
}

/// Issue 40.4: a spinning ball hitting a fixed floor obliquely (elastic
/// normal law): rebound velocity and spin against Walton's model in closed
/// form, evaluated here. The contact point slips at `g = v_x + ω R` (arm
/// `−R ŷ`); the tangential mass is `m/(1 + 1/q)`; sticking takes
/// `P = −(1 + β) g m/(1 + 1/q)` when `|P| ≤ μ J_n` with `J_n = 2 m v_n`,
/// sliding takes `P = −μ J_n sign(g)`; then `v_x' = v_x + P/m`,
/// `ω' = ω + R P/I`.
#[test]
fn a_spinning_ball_rebounds_off_a_floor_as_walton_s_model_says() {
    let q = ball_inertia_share();
    // Restitution mode too: rapier's solver takes the law's slip after the
    // impact as its contact's target.
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        for (mu, beta, spin) in [
            (0.5 as Real, 0.5 as Real, 3.0 as Real), // sticks
            (0.5, 0.0, -2.0),                        // sticks
            (0.05, 0.5, 3.0),                        // slides
            (0.1, -0.5, -6.0),                       // slides
        ] {
            let case = format!("{mode:?}, μ = {mu}, β = {beta}, ω = {spin}");
            let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
            w.floor();
            let (vx, vn) = (1.0 as Real, 2.0 as Real);
            let velocity = Vector::X * vx - Vector::Y * vn;
            let (b, _) = rough_ball(&mut w, Vector::Y * 0.71, velocity, spin, (mu, beta));
            let mut hit = false;
            for _ in 0..20 {
                w.step();
                if !w.kimpact.events().is_empty() {
                    hit = true;
                    break;
                }
            }
            assert!(hit, "{case}: no impact");
            let rb = &w.world.bodies[b];
            let m = f64::from(rb.mass());
            let i = q * m * 0.25;
            let (vx, vn, omega) = (f64::from(vx), f64::from(vn), f64::from(spin));
            let jn = 2.0 * m * vn;
            // Walton's model with the impulse at arm `arm` below the centre.
            let walton = |arm: f64| {
                let g = vx + omega * arm;
                let stick = -(1.0 + f64::from(beta)) * g / (1.0 / m + arm * arm / i);
                let p = if stick.abs() <= f64::from(mu) * jn {
                    stick
                } else {
                    -f64::from(mu) * jn * g.signum()
                };
                (vx + p / m, omega + arm * p / i)
            };
            // The replay applies it at the impact (arm R); restitution mode
            // at rapier's contact of the start of the step, midway across a
            // gap of at most `v_n dt`: between arm R and `R + v_n dt / 2`.
            let (low, high) = match mode {
                Mode::Restitution => (walton(0.5), walton(0.5 + vn / 60.0 / 2.0)),
                _ => (walton(0.5), walton(0.5)),
            };
            let within = |x: f64, a: f64, b: f64, slack: f64| {
                x >= a.min(b) - slack && x <= a.max(b) + slack
            };
            let v = rb.linvel();
            let w1 = rb.angvel().z_of();
            assert!(
                within(f64::from(v.x), low.0, high.0, tol() * 4.0),
                "{case}: v_x {} vs {low:?}..{high:?}",
                v.x
            );
            assert!((f64::from(v.y) - vn).abs() <= tol() * 4.0, "{case}: v_y {} vs {vn}", v.y);
            assert!(
                within(w1, low.1, high.1, tol() * 8.0),
                "{case}: ω {w1} vs {low:?}..{high:?}"
            );
        }
    }
}

/// Issue 40.1: with `μ = 0` a material's impact friction is off, and every
/// result is the frictionless law's bit for bit.
#[test]
fn zero_impact_friction_changes_nothing() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let run = |friction: Option<(Real, Real)>| {
            let mut w = TestWorld::new(mode, 0.1, Vector::Y * -9.81);
            w.closed_box(2.0, 0.2);
            let mut balls = Vec::new();
            for j in 0..6 {
                let mut p = Vector::splat(-1.2 + 0.45 * j as Real);
                p[1] = 0.3 * j as Real - 1.0;
                let mut v = Vector::splat(1.5);
                v[0] = if j % 2 == 0 { 3.0 } else { -2.0 };
                let (b, c) = w.ball(p, v, 0.2, 1.0);
                let mut material = k::Material::new(0.1, 0.1).unwrap();
                if let Some((mu, beta)) = friction {
                    material = material.with_impact_friction(mu, beta).unwrap();
                }
                w.kimpact.set_material(c, Some(material)).unwrap();
                balls.push(b);
            }
            for _ in 0..120 {
                w.step();
            }
            w.bits(&balls)
        };
        assert_eq!(run(None), run(Some((0.0, 0.5))), "{mode:?}");
    }
}
