//! The colour of each simulator, the same in every plot of this package
//! (`kimpact-accuracy`'s and `kimpact-ladder`'s).

use kimpact::Mode;
use plotters::style::RGBColor;

use crate::Method;

/// The colour of a simulator's points and lines: black for the reference,
/// then red, orange, green and blue up the ladder (native, restitution,
/// impulse, exact).
pub fn color(method: Method) -> RGBColor {
    match method {
        Method::Reference => RGBColor(0, 0, 0),
        Method::Rapier(Mode::Native) => RGBColor(214, 39, 40),
        Method::Rapier(Mode::Restitution) => RGBColor(255, 127, 14),
        Method::Rapier(Mode::Impulse) => RGBColor(44, 160, 44),
        Method::Rapier(Mode::Exact) => RGBColor(31, 119, 180),
    }
}
