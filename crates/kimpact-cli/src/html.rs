//! `compare.html`: the four modes side by side, animated in sync from the
//! recorded trajectories, with the energy and momentum curves and the
//! summary table, in one self-contained page (no network: the script, the
//! style and the data are inlined, and a content security policy forbids
//! any fetch).
//!
//! The page itself is the template `compare.html` next to this file; this
//! module chooses which steps it shows ([`stride`]) and fills in the data:
//! body shapes and colours (the pictures' colours, [`crate::render::color`],
//! and the plots' mode colours, [`crate::palette::mode_color`]), the view
//! (the pictures' projection and bounds), and per mode the positions (and
//! rotations of the turning bodies that are not balls) at every shown step
//! as little-endian `f32`
//! arrays in base64.

use base64::Engine as _;
use serde::Serialize;

use crate::palette::mode_color;
use crate::render::{self, Bounds};
use crate::scene::{Effect, Scene, Shape};
use crate::sim::{Frame, RunOutput};

/// The template (`compare.html`).
const TEMPLATE: &str = include_str!("compare.html");

/// Where the template takes the data (a JSON object).
const DATA_SLOT: &str = "/*KIMPACT_DATA*/";

/// Where the template takes the page title (HTML-escaped text).
const TITLE_SLOT: &str = "<!--KIMPACT_TITLE-->";

/// At most this many `f32` values of positions and rotations in a page (4
/// bytes each, a third more in base64): longer runs show every `stride`-th
/// step only.
pub const MAX_VALUES: u64 = 500_000;

/// Width (or, for a view taller than wide, height) of a panel in the
/// page, in CSS pixels (the pictures' panels are [`render::PANEL_WIDTH`]
/// wide; the page draws the same view larger).
pub const PAGE_PANEL_WIDTH: u32 = 560;

/// `f32` values recorded per mode and shown step: the moving bodies'
/// positions, and the rotation of the moving bodies that are not balls
/// when they may turn.
pub fn values_per_step(scene: &Scene) -> u64 {
    let rot = rotation_len(scene);
    scene
        .bodies
        .iter()
        .filter(|b| !b.fixed)
        .map(|b| {
            let turning = !matches!(b.shape, Shape::Ball { .. }) && rot > 0;
            scene.dim as u64 + if turning { rot as u64 } else { 0 }
        })
        .sum()
}

/// Length of a recorded rotation: 0 when bodies cannot turn (rapier locks
/// their rotations without the `spin` effect), else 1 (2D angle) or 4 (3D
/// quaternion).
fn rotation_len(scene: &Scene) -> usize {
    match (scene.active(Effect::Spin), scene.dim) {
        (false, _) => 0,
        (true, 2) => 1,
        (true, _) => 4,
    }
}

/// Show every `stride`-th step: the smallest stride that keeps `modes` runs
/// of `steps` steps (plus the start) within [`MAX_VALUES`] values, with
/// `values` values per mode and step.
pub fn stride(steps: u64, values: u64, modes: u64) -> u64 {
    let per_step = values.saturating_mul(modes).max(1);
    let shown = (MAX_VALUES / per_step).max(2);
    // `shown` frames: the start, every stride-th step, and the last step.
    steps.div_ceil(shown - 1).max(1)
}

/// One body as the page draws it.
#[derive(Serialize)]
struct PageBody {
    /// Its label, if any.
    name: Option<String>,
    /// `"ball"`, `"box"`, `"capsule"` or `"convex"`.
    shape: &'static str,
    /// Ball radius.
    #[serde(skip_serializing_if = "Option::is_none")]
    radius: Option<f64>,
    /// Other shapes: points in the body's frame whose hull, turned and
    /// projected, is drawn ([`crate::scene::Shape::outline`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    outline: Option<Vec<Vec<f64>>>,
    /// The orientation a body keeps when its rotation is not recorded
    /// (fixed, or rotations locked): 2D `[angle]`, 3D quaternion `[x, y,
    /// z, w]`; `None`: unrotated.
    #[serde(skip_serializing_if = "Option::is_none")]
    rotation: Option<Vec<f64>>,
    /// Fixed: drawn first at its position, which never changes.
    fixed: bool,
    /// `#rrggbb`, as in the pictures.
    color: String,
    /// Initial position (the only one of a fixed body).
    position: Vec<f64>,
    /// Index in the recorded positions (`None` for fixed bodies).
    moving: Option<usize>,
    /// Index in the recorded rotations (`None`: not recorded, identity).
    turning: Option<usize>,
}

/// One mode's trajectory.
#[derive(Serialize)]
struct PageMode {
    /// The mode's name.
    name: &'static str,
    /// `#rrggbb`, as in the plots.
    color: String,
    /// Positions, `[shown step][moving body][axis]`, `f32` LE in base64.
    positions: String,
    /// Rotations, `[shown step][turning body][component]`, `f32` LE in
    /// base64 (empty when nothing turns).
    rotations: String,
    /// Kinetic energy at each curve time, `f32` LE in base64.
    kinetic: String,
    /// |momentum| of all bodies at each curve time, `f32` LE in base64.
    momentum: String,
}

/// The summary table.
#[derive(Serialize)]
pub struct Table {
    /// Column titles.
    pub header: Vec<String>,
    /// One row per mode.
    pub rows: Vec<Vec<String>>,
    /// What the columns mean.
    pub note: String,
}

/// Everything the page needs.
#[derive(Serialize)]
struct PageData<'a> {
    name: &'a str,
    description: Option<&'a str>,
    /// One line: dimension, precision, bodies, steps, effects.
    setup: String,
    dim: usize,
    dt: f64,
    steps: u64,
    stride: u64,
    /// The steps shown, in order.
    shown_steps: Vec<u64>,
    /// The two world axes drawn horizontally and vertically.
    axes: [usize; 2],
    /// The view plane's lower and upper corners.
    bounds: [[f64; 2]; 2],
    /// Panel size in CSS pixels.
    panel: [u32; 2],
    /// Values per shown step: position axes, rotation components.
    rotation_len: usize,
    moving_count: usize,
    turning_count: usize,
    bodies: Vec<PageBody>,
    /// Times of the curve points, `f32` LE in base64.
    curve_times: String,
    modes: Vec<PageMode>,
    table: &'a Table,
}

/// `#rrggbb`.
fn hex((r, g, b): (u8, u8, u8)) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// Values as little-endian `f32` in base64.
fn b64(values: impl IntoIterator<Item = f64>) -> String {
    let bytes: Vec<u8> = values
        .into_iter()
        .flat_map(|v| (v as f32).to_le_bytes())
        .collect();
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// Escape text for HTML.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The steps a page shows and each run's frames at them.
pub struct Shown<'a> {
    /// The steps ([`crate::shown::shown_steps`]).
    pub steps: &'a [u64],
    /// One step in `stride` ([`stride`]).
    pub stride: u64,
    /// `frames[m]`: run `m`'s frames at `steps`, in order.
    pub frames: &'a [Vec<&'a Frame>],
}

/// The page of `runs` (the four modes, in order) showing `shown`, in the
/// pictures' view `bounds`, with the summary `table` and the `setup` line.
///
/// # Errors
/// The data cannot be encoded (serde_json's message).
pub fn page(
    scene: &Scene,
    setup: String,
    runs: &[RunOutput],
    shown: &Shown<'_>,
    bounds: &Bounds,
    table: &Table,
) -> Result<String, String> {
    let (shown, stride, frames) = (shown.steps, shown.stride, shown.frames);
    let rot = rotation_len(scene);
    let mut moving = 0;
    let mut turning = 0;
    let bodies: Vec<PageBody> = scene
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let (radius, outline) = match &b.shape {
                Shape::Ball { radius } => (Some(*radius), None),
                other => (None, Some(other.outline(scene.dim))),
            };
            let shape = b.shape.name();
            let m = (!b.fixed).then(|| {
                moving += 1;
                moving - 1
            });
            let t = (!b.fixed && outline.is_some() && rot > 0).then(|| {
                turning += 1;
                turning - 1
            });
            PageBody {
                name: b.name.clone(),
                shape,
                radius,
                outline,
                rotation: b.rotated().then(|| orientation(&b.rotation)),
                fixed: b.fixed,
                color: hex(render::color(scene, i)),
                position: b.position.clone(),
                moving: m,
                turning: t,
            }
        })
        .collect();
    let curve_points = |r: &RunOutput, f: &dyn Fn(&crate::sim::Sample) -> f64| {
        crate::plot::thin(&r.samples.iter().map(|s| (s.time, f(s))).collect::<Vec<_>>())
    };
    let curve_times = runs
        .first()
        .map(|r| b64(curve_points(r, &|s| s.kinetic).iter().map(|p| p.0)))
        .unwrap_or_default();
    let modes: Vec<PageMode> = runs
        .iter()
        .zip(frames)
        .map(|(r, fs)| {
            let positions = b64(fs.iter().flat_map(|f| {
                f.bodies
                    .iter()
                    .zip(&scene.bodies)
                    .filter(|(_, b)| !b.fixed)
                    .flat_map(|(s, _)| s.position.iter().copied())
            }));
            let rotations = b64(fs.iter().flat_map(|f| {
                f.bodies
                    .iter()
                    .zip(&bodies)
                    .filter(|(_, b)| b.turning.is_some())
                    .flat_map(|(s, _)| s.rotation.iter().copied().take(rot))
            }));
            PageMode {
                name: r.mode.name(),
                color: hex(mode_color(r.mode)),
                positions,
                rotations,
                kinetic: b64(curve_points(r, &|s| s.kinetic).iter().map(|p| p.1)),
                momentum: b64(curve_points(r, &|s| crate::report::norm(&s.momentum_all))
                    .iter()
                    .map(|p| p.1)),
            }
        })
        .collect();
    // At most PAGE_PANEL_WIDTH wide and high: tall views get narrower.
    let aspect = (bounds.1[1] - bounds.0[1]) / (bounds.1[0] - bounds.0[0]);
    let width = if aspect > 1.0 {
        (f64::from(PAGE_PANEL_WIDTH) / aspect.min(2.0)).round() as u32
    } else {
        PAGE_PANEL_WIDTH
    };
    let (w, h) = render::panel_size_for(width, bounds);
    let data = PageData {
        name: &scene.name,
        description: scene.description.as_deref(),
        setup,
        dim: scene.dim,
        dt: scene.dt,
        steps: runs.first().map_or(0, |r| r.steps),
        stride,
        shown_steps: shown.to_vec(),
        axes: scene.view.axes,
        bounds: [bounds.0, bounds.1],
        panel: [w, h],
        rotation_len: rot,
        moving_count: moving,
        turning_count: turning,
        bodies,
        curve_times,
        modes,
        table,
    };
    let json = serde_json::to_string(&data).map_err(|e| e.to_string())?;
    // Inside a <script> element: no "</script>" or "<!--" may appear.
    let json = json.replace('<', "\\u003c");
    Ok(TEMPLATE
        .replacen(
            TITLE_SLOT,
            &escape(&format!("{} — kimpact compare", scene.name)),
            1,
        )
        .replacen(DATA_SLOT, &json, 1))
}

/// A scene rotation (2D `[angle]`, 3D rotation vector) as the page turns
/// bodies: 2D `[angle]`, 3D quaternion `[x, y, z, w]`.
fn orientation(rotation: &[f64]) -> Vec<f64> {
    use kimpact::nalgebra::{UnitQuaternion, Vector3};
    match rotation {
        [x, y, z] => {
            let q = UnitQuaternion::from_scaled_axis(Vector3::new(*x, *y, *z));
            vec![q.i, q.j, q.k, q.w]
        }
        _ => rotation.to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shown::shown_steps;

    #[test]
    fn short_runs_show_every_step() {
        assert_eq!(stride(240, 32, 4), 1);
        assert_eq!(shown_steps(3, 1), [0, 1, 2, 3]);
    }

    #[test]
    fn long_runs_are_subsampled_within_the_budget() {
        for (steps, values) in [(70_000, 4), (1_000_000, 2000), (7, 1_000_000), (99_999, 3)] {
            let s = stride(steps, values, 4);
            let shown = shown_steps(steps, s);
            assert!(
                shown.len() as u64 * values * 4 <= MAX_VALUES.max(2 * values * 4),
                "{steps} steps × {values}: stride {s}, {} shown",
                shown.len()
            );
            // The smallest such stride: one less would exceed the budget.
            if s > 1 {
                let more = shown_steps(steps, s - 1).len() as u64;
                assert!(more * values * 4 > MAX_VALUES, "{steps} × {values}: {s}");
            }
            assert_eq!(shown.first(), Some(&0));
            assert_eq!(shown.last(), Some(&steps));
            assert!(shown.windows(2).all(|w| w[0] < w[1] && w[1] - w[0] <= s));
        }
    }

    #[test]
    fn the_data_cannot_close_its_script_element() {
        let table = Table {
            header: vec!["</script><!--".into()],
            rows: vec![],
            note: String::new(),
        };
        let json = serde_json::to_string(&table)
            .unwrap()
            .replace('<', "\\u003c");
        assert!(!json.contains("</script") && !json.contains("<!--"));
        let back: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(back["header"][0], "</script><!--");
    }
}
