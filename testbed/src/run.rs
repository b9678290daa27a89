//! One scene in the testbed's loop: build it, step it through kimpact in the
//! mode the settings panel (or the script) selects, until the window closes,
//! the user picks another scene, or the script ends.

use kimpact_scene::Scene;
use kimpact2d::Mode;
use rapier_testbed2d::TestbedViewer;
use rapier2d::prelude::PhysicsWorld;

use kimpact_world::BuildError;
use kimpact_world::dim2::build;

use crate::script::{Record, Script};
use crate::view;

/// The settings panel's mode menu.
const MODE_KEY: &str = "kimpact mode";
/// The settings panel's line of kimpact's impacts.
const IMPACTS_KEY: &str = "kimpact impacts";

/// How a scene's loop ended.
pub enum Ended {
    /// The script's frames are done: what the run did.
    Scripted(Record),
    /// The window closed, or the user restarted or picked a scene.
    Closed,
}

/// The names of the modes, as the menu lists them.
fn mode_names() -> Vec<String> {
    Mode::ALL.iter().map(|m| m.to_string()).collect()
}

fn mode_index(mode: Mode) -> usize {
    Mode::ALL.iter().position(|m| *m == mode).unwrap_or(0)
}

/// Kinetic energy of the world's bodies (translation and rotation).
fn kinetic(world: &PhysicsWorld) -> f64 {
    world
        .bodies
        .iter()
        .map(|(_, rb)| f64::from(rb.kinetic_energy()))
        .sum()
}

/// Run `scene` in `viewer`, starting in `start` (or in the mode the panel
/// kept from before a restart).
///
/// # Errors
/// [`BuildError`] when the scene cannot be built in 2D f32.
pub async fn run_scene(
    viewer: &mut TestbedViewer,
    scene: &Scene,
    start: Mode,
    script: &Script,
) -> Result<Ended, BuildError> {
    let settings = viewer.example_settings_mut();
    let chosen = settings.get_or_set_string(MODE_KEY, mode_index(start), mode_names());
    // The menu switches kimpact live: no restart.
    settings.set_restart_on_change(MODE_KEY, false);
    let mode = Mode::ALL.get(chosen).copied().unwrap_or(start);
    // The world the CLI runs, its mode switched in place (soft CCD and
    // contact recycling with it).
    let mut built = build(scene, mode)?;
    viewer.set_world(&mut built.world);
    // Most of the testbed's 1280 × 720 window.
    let (centre, zoom) = view::frame(scene, 1000.0, 600.0);
    viewer.look_at(centre, zoom);

    let mut record = Record::new(&scene.name, mode, kinetic(&built.world));
    let mut frame = 0;
    while viewer.render_frame(&mut built.world).await {
        let panel = viewer
            .example_settings()
            .get_string_id(MODE_KEY)
            .and_then(|i| Mode::ALL.get(i).copied());
        let mut wanted = panel.unwrap_or(built.kimpact.mode());
        if let Some(m) = script.switch_at(frame) {
            wanted = m;
            viewer
                .example_settings_mut()
                .set_string(MODE_KEY, mode_index(m), mode_names());
        }
        if wanted != built.kimpact.mode() {
            built.set_mode(wanted);
            record.switch(wanted, kinetic(&built.world));
        }
        if !viewer.simulating() {
            continue;
        }
        built.kimpact.step_world(&mut built.world, &(), &());
        frame += 1;
        record.step(built.kimpact.events().len());
        let stats = built.kimpact.stats();
        viewer.example_settings_mut().set_label(
            IMPACTS_KEY,
            format!("{} impacts in {} steps", stats.impacts, stats.steps),
        );
        if script.done(frame) {
            record.close(kinetic(&built.world));
            // Two frames without a step: the last one shows this step.
            for _ in 0..2 {
                if !viewer.render_frame(&mut built.world).await {
                    return Ok(Ended::Closed);
                }
            }
            return Ok(Ended::Scripted(record));
        }
    }
    Ok(Ended::Closed)
}
