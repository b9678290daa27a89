//! Where the testbed's camera looks: a scene's bounding box within the
//! window.

use kimpact_scene::Scene;
use kimpact2d::math::{Real, Vector};

/// The centre and the zoom (pixels per metre) that show the scene's
/// bounding box within `width` × `height` pixels.
pub fn frame(scene: &Scene, width: Real, height: Real) -> (Vector, Real) {
    let (lo, hi) = scene.extent();
    if !lo.iter().chain(&hi).all(|x| x.is_finite()) {
        return (Vector::ZERO, 100.0);
    }
    let centre = Vector::new(
        ((lo[0] + hi[0]) / 2.0) as Real,
        ((lo[1] + hi[1]) / 2.0) as Real,
    );
    let w = (hi[0] - lo[0]).max(1e-3) as Real;
    let h = (hi[1] - lo[1]).max(1e-3) as Real;
    (centre, (width / w).min(height / h))
}
