//! The throw of a cut shot through the adapter against Alciatore's TP A-14
//! (docs/friction.md): equal solid spheres, stun, elastic normal law,
//! β = 0, in exact mode (3D, f64); the object ball's throw angle over cut
//! angles 0–60° for μ = 0.06 and μ = 0.2, beside the closed form
//! `tan θ = min(μ, tan φ / 7)`. Writes docs/throw.svg:
//!
//!     cargo run --release --example throw_plot

use k::math::Vector;
use k::rapier::prelude::*;
use k::{Law, LawParams, Material, Mode};
use kimpact3d_f64 as k;
use plotters::prelude::*;

/// The object ball's throw (degrees) at cut angle `phi` (degrees) with
/// impact friction `mu`, measured along the normal the impact used; and
/// that normal's cut angle (degrees).
fn throw(mu: f64, phi: f64) -> Option<(f64, f64)> {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::ZERO;
    let mut kimpact = k::Kimpact::new(Law::new(LawParams::default()).ok()?, Mode::Exact);
    let material = Material::new(0.0, 0.0)
        .ok()?
        .with_impact_friction(mu, 0.0)
        .ok()?;
    let n = Vector::new(phi.to_radians().cos(), phi.to_radians().sin(), 0.0);
    let mut ball = |p: Vector, v: Vector| {
        let body = RigidBodyBuilder::dynamic().translation(p).linvel(v);
        let (b, c) = world.insert(body, ColliderBuilder::ball(0.5).friction(0.0));
        kimpact.mark_with(&world.colliders, c, material).ok()?;
        Some(b)
    };
    ball(-n - Vector::X * 0.25, Vector::X)?;
    let object = ball(Vector::ZERO, Vector::ZERO)?;
    for _ in 0..40 {
        kimpact.step_world(&mut world, &(), &());
        if let Some(e) = kimpact.events().first() {
            let normal = e.normal * e.normal.dot(n).signum();
            let v = world.bodies[object].linvel();
            let tangent = Vector::new(-normal.y, normal.x, 0.0);
            let angle = v.dot(tangent).abs().atan2(v.dot(normal)).to_degrees();
            return Some((angle, normal.y.atan2(normal.x).to_degrees()));
        }
    }
    None
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/throw.svg");
    let mut svg = String::new();
    draw(&mut svg)?;
    // Whole or not at all: a temporary file beside it (readable by all, as
    // the file it replaces), then renamed.
    let mut builder = tempfile::Builder::new();
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    let mut temp = builder.tempfile_in(path.parent().ok_or("no folder")?)?;
    std::io::Write::write_all(&mut temp, svg.as_bytes())?;
    temp.persist(&path)?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The plot, as an SVG document into `svg`.
fn draw(svg: &mut String) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::with_string(svg, (720, 420)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Cut-shot throw: kimpact (exact mode) vs TP A-14",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..60.0, 0.0..12.0)?;
    chart
        .configure_mesh()
        .x_desc("cut angle φ (degrees)")
        .y_desc("throw θ (degrees)")
        .draw()?;
    for (mu, color) in [(0.06, BLUE), (0.2, RED)] {
        let theory = (0..=600).map(|i| {
            let phi = f64::from(i) * 0.1;
            let t = mu.min(phi.to_radians().tan() / 7.0);
            (phi, t.atan().to_degrees())
        });
        chart
            .draw_series(LineSeries::new(theory, color.stroke_width(2)))?
            .label(format!("TP A-14, μ = {mu}"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], color.stroke_width(2)));
        let mut points = Vec::new();
        for i in 0..=24 {
            let (angle, cut) = throw(mu, f64::from(i) * 2.5).ok_or("no impact")?;
            points.push((cut, angle));
        }
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))?
            .label(format!("kimpact, μ = {mu}"))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, color.filled()));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()?;
    root.present()?;
    Ok(())
}
