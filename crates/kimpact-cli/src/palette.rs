//! The colour of each mode, shared by the plots, the pictures, the page
//! and the animation.

use kimpact::Mode;

/// The colour of each mode in plots, pictures, the page and the animation.
pub fn mode_color(mode: Mode) -> (u8, u8, u8) {
    match mode {
        Mode::Native => (90, 90, 90),
        Mode::Restitution => (230, 159, 0),
        Mode::Impulse => (0, 158, 115),
        Mode::Exact => (0, 114, 178),
    }
}
