//! The law's effective restitution across mass ratios and impact angles.
//!
//! `cargo run -p kimpact --example law_table [dissipation]` prints, for d̃ (default
//! 0.01), the restitution e = u'/u the law gives a ball hitting another at
//! 1 m/s, and the energy it dissipates, as a table. It shows what d̃ means:
//! the law dissipates more for unequal masses and grazing impacts.

use kimpact::nalgebra::Vector2;
use kimpact::{Body, Law, LawParams};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dissipation: f64 = match std::env::args().nth(1) {
        Some(arg) => arg
            .parse()
            .map_err(|e| format!("dissipation {arg:?}: {e}"))?,
        None => 0.01,
    };
    let law = Law::new(LawParams {
        dissipation,
        ..Default::default()
    })?;
    println!(
        "d̃ = {dissipation}: effective restitution e (energy lost, J) for a 1 kg ball at 1 m/s"
    );
    print!("{:>10}", "m2/m1");
    let angles = [0.0, 30.0, 60.0, 80.0];
    for a in angles {
        print!(" | {:>20}", format!("{a}° off-centre"));
    }
    println!();
    for ratio in [1.0, 10.0, 1000.0] {
        print!("{ratio:>10}");
        for a in angles {
            let a: f64 = a;
            let v = Vector2::new(a.to_radians().cos(), a.to_radians().sin());
            let impact = law
                .resolve(
                    &Body::new(1.0, v)?,
                    &Body::new(ratio, Vector2::zeros())?,
                    &Vector2::x(),
                )?
                .ok_or("not approaching")?;
            let tag = if impact.clamped { " (clamped)" } else { "" };
            print!(
                " | {:>20}",
                format!("{:.4} ({:.4}){tag}", impact.restitution, impact.dissipated)
            );
        }
        println!();
    }
    Ok(())
}
