//! The command's `native` mode is rapier as the scene configures it: a port
//! of rapier's restitution3 (balls of restitution 0 to 1 dropped on a
//! floor) ends with the energy plain rapier gives the same world, built
//! here as rapier's example builds it; and every setting the command adds
//! beyond the scene is named in the report's `setup.added`.

mod common;

use std::path::Path;

use kimpact3d::rapier::prelude::*;
use serde_json::Value;

use common::{f, kimpact_ok, report, scene, temp_dir, write};

/// rapier's examples3d/restitution3.rs, stepped `steps` times with
/// rapier's defaults (dt 1/60, gravity −9.81 y): the final kinetic energy
/// (rotation included) plus `−Σ m g·x`.
fn plain_rapier(steps: usize) -> f64 {
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81, 0.0),
        ..PhysicsWorld::default()
    };
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -1.0, 0.0)),
        ColliderBuilder::cuboid(20.0, 1.0, 2.0)
            .restitution(1.0)
            .restitution_combine_rule(CoefficientCombineRule::GeometricMean),
    );
    let mut balls = Vec::new();
    for j in 0..2 {
        for i in 0..=10 {
            let x = i as f32 - 5.0;
            let (h, _) = world.insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(
                    x * 2.0,
                    10.0 * (j as f32 + 1.0),
                    0.0,
                )),
                ColliderBuilder::ball(0.5)
                    .restitution(i as f32 / 10.0)
                    .restitution_combine_rule(CoefficientCombineRule::GeometricMean),
            );
            balls.push(h);
        }
    }
    for _ in 0..steps {
        world.step();
    }
    balls
        .iter()
        .map(|h| {
            let rb = &world.bodies[*h];
            f64::from(rb.kinetic_energy())
                + 9.81 * f64::from(rb.mass()) * f64::from(rb.translation().y)
        })
        .sum()
}

/// The port, in the command's native mode, ends with plain rapier's energy
/// (to the f32 rounding of the balls' masses, given in the scene and
/// computed by rapier from the density in the example), with nothing
/// added to the world. Run as the command ran it before (every ball a CCD
/// body, rotations locked), it would not.
#[test]
fn the_restitution3_port_ends_with_plain_rapier_s_energy() {
    let path = scene("restitution3d.ron");
    let p = path.to_str().unwrap();
    for steps in [120usize, 600] {
        let s = steps.to_string();
        let r = report(&["run", p, "--mode", "native", "--steps", &s]);
        let setup = &r["setup"];
        assert_eq!(setup["added"], Value::Array(vec![]), "{setup}");
        assert_eq!(setup["ccd_bodies"], 0);
        assert_eq!(setup["locked_rotations"], 0);
        assert_eq!(setup["contact_recycling"], true);
        let cli = f(&r["energy"]["kinetic_final"]) + f(&r["energy"]["potential_final"]);
        let rapier = plain_rapier(steps);
        assert!(
            (cli - rapier).abs() <= 1e-6 * rapier.abs(),
            "{steps} steps: the command's native {cli} J, plain rapier {rapier} J"
        );

        // The same scene with rotations locked and CCD chosen for every
        // fast ball: another world, another energy.
        let text = std::fs::read_to_string(&path).unwrap().replacen(
            "    mode: \"exact\",\n",
            "    mode: \"exact\",\n    auto_ccd: true,\n    effects: [\"gravity\", \"friction\", \"fixed_walls\"],\n",
            1,
        );
        let locked = write("locked.ron", text);
        let r = report(&[
            "run",
            locked.to_str().unwrap(),
            "--mode",
            "native",
            "--steps",
            &s,
        ]);
        assert_eq!(r["setup"]["locked_rotations"], 22);
        assert_eq!(r["setup"]["ccd_bodies"], 22);
        let added: Vec<&str> = r["setup"]["added"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a.as_str().unwrap())
            .collect();
        assert!(
            added.iter().any(|a| a.contains("rotations locked on 22")),
            "{added:?}"
        );
        assert!(
            added
                .iter()
                .any(|a| a.contains("CCD (`ccd_enabled`) on 22")),
            "{added:?}"
        );
        assert!(added.iter().any(|a| a.contains("soft CCD")), "{added:?}");
        assert!(
            added.iter().any(|a| a.contains("contact recycling off")),
            "{added:?}"
        );
        let other = f(&r["energy"]["kinetic_final"]) + f(&r["energy"]["potential_final"]);
        println!(
            "{steps} steps: plain rapier {rapier} J, the command {cli} J, locked and CCD {other} J"
        );
        assert!(
            (other - rapier).abs() > 1e-2 * rapier.abs(),
            "locked rotations and CCD changed nothing: {other} J"
        );
    }
}

/// `compare`'s summary names the settings the command adds, the ones every
/// mode shares and each mode's own, or says there are none.
#[test]
fn the_summary_names_the_settings_the_command_adds() {
    let dir = temp_dir("summary");
    let summary = |scene: &Path, name: &str| {
        let out = dir.join(name);
        let (scene, out_dir) = (scene.to_str().unwrap(), out.to_str().unwrap());
        kimpact_ok(&["compare", scene, "--steps", "3", "--out", out_dir]);
        std::fs::read_to_string(out.join("summary.md")).unwrap()
    };
    let s = summary(&scene("restitution3d.ron"), "restitution3d");
    assert!(s.contains("## Settings the command adds"), "{s}");
    assert!(
        s.contains("None: every mode runs the scene's bodies as rapier builds them."),
        "{s}"
    );
    let billiards = scene("billiards2d.ron");
    let s = summary(&billiards, "billiards2d");
    assert!(
        s.contains("- every mode: rotations locked on 16 moving bodies"),
        "{s}"
    );
    assert!(
        s.contains("- every mode: CCD (`ccd_enabled`) on 16 bodies"),
        "{s}"
    );
    assert!(
        s.contains("- native: soft CCD (`soft_ccd_prediction`) on 16 bodies"),
        "{s}"
    );
    assert!(s.contains("- native: contact recycling off"), "{s}");
    assert!(!s.contains("- exact: soft CCD"), "{s}");
}
