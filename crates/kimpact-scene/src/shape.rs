//! Body shapes and orientations: sizes, bounding boxes and outlines, in
//! the body's frame and turned by its rotation.

use kimpact::nalgebra::{Rotation2, Rotation3, Vector3};

/// A body's shape, in the body's own frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A ball (disk in 2D) centred on the body.
    Ball {
        /// Radius.
        radius: f64,
    },
    /// A box centred on the body, along its axes.
    Box {
        /// Half extents, one per dimension.
        half_extents: Vec<f64>,
    },
    /// A capsule centred on the body along its y axis: the points within
    /// `radius` of the segment from `−half_height` to `half_height` on y.
    Capsule {
        /// Half the distance between the two end centres.
        half_height: f64,
        /// Radius.
        radius: f64,
    },
    /// The convex hull of points given in the body's frame.
    Convex {
        /// The points (`dim` components each).
        points: Vec<Vec<f64>>,
    },
}

impl Shape {
    /// The smallest half size: the radius (ball, capsule), the smallest
    /// half extent (box), half the smallest extent of the points' bounding
    /// box (convex).
    pub fn min_size(&self) -> f64 {
        match self {
            Shape::Ball { radius } | Shape::Capsule { radius, .. } => *radius,
            Shape::Box { half_extents } => {
                half_extents.iter().copied().fold(f64::INFINITY, f64::min)
            }
            Shape::Convex { points } => {
                let dim = points.first().map_or(0, Vec::len);
                (0..dim)
                    .map(|k| {
                        let xs = points.iter().map(|p| p[k]);
                        let hi = xs.clone().fold(f64::NEG_INFINITY, f64::max);
                        let lo = xs.fold(f64::INFINITY, f64::min);
                        0.5 * (hi - lo)
                    })
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }

    /// Half extents of a box centred on the body's origin that holds the
    /// unrotated shape.
    pub fn half_box(&self, dim: usize) -> Vec<f64> {
        match self {
            Shape::Ball { radius } => vec![*radius; dim],
            Shape::Box { half_extents } => half_extents.clone(),
            Shape::Capsule {
                half_height,
                radius,
            } => (0..dim)
                .map(|k| radius + if k == 1 { *half_height } else { 0.0 })
                .collect(),
            Shape::Convex { points } => (0..dim)
                .map(|k| points.iter().map(|p| p[k].abs()).fold(0.0, f64::max))
                .collect(),
        }
    }

    /// `"ball"`, `"box"`, `"capsule"` or `"convex"`.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Ball { .. } => "ball",
            Shape::Box { .. } => "box",
            Shape::Capsule { .. } => "capsule",
            Shape::Convex { .. } => "convex",
        }
    }

    /// Points in the body's frame whose convex hull is the shape (a box's
    /// corners, a convex shape's points) or, for round shapes, follows its
    /// outline closely (points on the circles or spheres around a
    /// capsule's end centres, or a ball's centre): for drawing.
    pub fn outline(&self, dim: usize) -> Vec<Vec<f64>> {
        let round = |centre: &[f64], r: f64| -> Vec<Vec<f64>> {
            directions(dim)
                .into_iter()
                .map(|d| centre.iter().zip(d).map(|(c, x)| c + r * x).collect())
                .collect()
        };
        match self {
            Shape::Ball { radius } => round(&vec![0.0; dim], *radius),
            Shape::Box { half_extents } => (0..1usize << dim)
                .map(|c| {
                    (0..dim)
                        .map(|k| {
                            if c >> k & 1 == 1 {
                                half_extents[k]
                            } else {
                                -half_extents[k]
                            }
                        })
                        .collect()
                })
                .collect(),
            Shape::Capsule {
                half_height,
                radius,
            } => {
                let end = |s: f64| -> Vec<f64> {
                    (0..dim)
                        .map(|k| if k == 1 { s * half_height } else { 0.0 })
                        .collect()
                };
                let mut out = round(&end(1.0), *radius);
                out.extend(round(&end(-1.0), *radius));
                out
            }
            Shape::Convex { points } => points.clone(),
        }
    }
}

/// Unit directions around a circle (2D, 32) or a sphere (3D, 98): the
/// outline of round shapes.
fn directions(dim: usize) -> Vec<Vec<f64>> {
    if dim == 2 {
        return (0..32)
            .map(|i| {
                let (s, c) = (i as f64 * std::f64::consts::TAU / 32.0).sin_cos();
                vec![c, s]
            })
            .collect();
    }
    let mut out = vec![vec![0.0, 1.0, 0.0], vec![0.0, -1.0, 0.0]];
    for i in 1..8 {
        let (sl, cl) = (i as f64 * std::f64::consts::PI / 8.0).sin_cos();
        for j in 0..12 {
            let (sa, ca) = (j as f64 * std::f64::consts::TAU / 12.0).sin_cos();
            out.push(vec![sl * ca, cl, sl * sa]);
        }
    }
    out
}

/// `v` (`dim` components, the body's frame) turned by `rotation` (2D
/// `[angle]`, 3D a rotation vector) into the world's axes.
pub fn rotate(rotation: &[f64], v: &[f64]) -> Vec<f64> {
    if rotation.iter().all(|x| *x == 0.0) {
        return v.to_vec();
    }
    match (rotation, v) {
        ([angle], [x, y]) => {
            let r = Rotation2::new(*angle) * kimpact::nalgebra::Vector2::new(*x, *y);
            vec![r.x, r.y]
        }
        ([a, b, c], [x, y, z]) => {
            let r = Rotation3::new(Vector3::new(*a, *b, *c)) * Vector3::new(*x, *y, *z);
            vec![r.x, r.y, r.z]
        }
        _ => v.to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_turn_points_about_the_origin() {
        let q = std::f64::consts::FRAC_PI_2;
        let v = rotate(&[q], &[1.0, 0.0]);
        assert!((v[0]).abs() < 1e-15 && (v[1] - 1.0).abs() < 1e-15);
        // A quarter turn about z: x to y.
        let v = rotate(&[0.0, 0.0, q], &[1.0, 0.0, 0.0]);
        assert!((v[0]).abs() < 1e-15 && (v[1] - 1.0).abs() < 1e-15 && v[2].abs() < 1e-15);
    }

    #[test]
    fn outlines_and_boxes_hold_their_shapes() {
        let capsule = Shape::Capsule {
            half_height: 1.0,
            radius: 0.5,
        };
        assert_eq!(capsule.half_box(3), vec![0.5, 1.5, 0.5]);
        assert_eq!(capsule.min_size(), 0.5);
        for p in capsule.outline(3) {
            let y = p[1].abs() - 1.0;
            assert!(((p[0] * p[0] + y * y + p[2] * p[2]).sqrt() - 0.5).abs() < 1e-12);
        }
        let convex = Shape::Convex {
            points: vec![vec![0.0, 0.0], vec![2.0, 0.0], vec![0.0, 1.0]],
        };
        assert_eq!(convex.half_box(2), vec![2.0, 1.0]);
        assert_eq!(convex.min_size(), 0.5);
        assert_eq!(
            Shape::Box {
                half_extents: vec![1.0, 2.0]
            }
            .outline(2)
            .len(),
            4
        );
    }
}
