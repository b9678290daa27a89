//! The time of impact and the contact patch against closed forms evaluated
//! here.
// One source for f32 and f64: `as Real` is a cast in one build only.
#![allow(clippy::unnecessary_cast)]

use super::*;
use crate::math::{DIM, Vector};
use crate::rapier::math::AngVector;
use crate::rapier::parry::shape::{Ball, Compound, Cuboid, HeightField, Segment, SharedShape};

use super::super::motion::{Motion, zero_angvel};
use super::super::patch::{Placed, patch};
use crate::cast::Rewind;

use super::super::test_support::{about_z, first_root, tol, xy};

/// A fixed floor whose top lies at y = 0.
fn floor() -> (Cuboid, Motion) {
    let mut half = Vector::splat(10.0);
    half[1] = 1.0;
    (
        Cuboid::new(half),
        Motion::still(Pose::from_translation(xy(0.0, -1.0))),
    )
}

fn body(at: Vector, angle: Real, linvel: Vector, angvel: AngVector) -> Motion {
    Motion {
        pose: Pose::new(at, about_z(angle)),
        local_com: Vector::ZERO,
        linvel,
        angvel,
        t_ref: 0.0,
    }
}

/// The floor of [`floor`] riding its still motion.
fn floor_mover<'a>(still: &'a Motion, ground: &'a Cuboid) -> Mover<'a> {
    Mover {
        motion: still,
        offset: None,
        shape: ground,
        reach: 10.1 * (DIM as Real).sqrt(),
    }
}

/// A cube of half-extent 0.5 riding `motion`.
fn cube_mover<'a>(motion: &'a Motion, cube: &'a Cuboid) -> Mover<'a> {
    Mover {
        motion,
        offset: Some(Pose::IDENTITY),
        shape: cube,
        reach: 0.87,
    }
}

/// Issue 39, rigid replay A: a rod of length L turning at ω about its
/// centre while it falls at `vy` meets the floor when its lowest end,
/// `y(t) = y₀ + vy t − (L/2)|sin(θ₀ + ω t)|`, reaches 0 (its first root,
/// found by bisection here), for turns that bring the end down faster than
/// the fall, slower, and against it.
#[test]
fn a_turning_rod_meets_the_floor_when_its_lowest_end_does() {
    let (floor, still) = floor();
    let length = 1.6;
    let rod = Segment::new(xy(-0.5 * length, 0.0), xy(0.5 * length, 0.0));
    let mut manifolds = Vec::new();
    for (y0, vy, theta0, omega) in [
        (0.6, -2.0, 0.2, 3.0),
        (0.6, -2.0, 0.2, -1.5),
        (0.9, -0.5, 1.2, 6.0),
        (0.3, -1.0, 0.0, 8.0),
        (1.0, -3.0, 2.5, -4.0),
    ] {
        let (y0, vy, theta0, omega): (Real, Real, Real, Real) = (y0, vy, theta0, omega);
        let end = 1.0;
        let lowest = |t: f64| {
            f64::from(y0) + f64::from(vy) * t
                - 0.5 * f64::from(length) * (f64::from(theta0) + f64::from(omega) * t).sin().abs()
        };
        let expected = first_root(lowest, end).expect("the rod lands within the interval");
        let motion = body(xy(0.3, y0), theta0, xy(0.0, vy), about_z(omega));
        let a = Mover {
            motion: &motion,
            offset: Some(Pose::IDENTITY),
            shape: &rod,
            reach: 0.5 * length,
        };
        let b = Mover {
            motion: &still,
            offset: None,
            shape: &floor,
            reach: 0.0,
        };
        let tolerance = (1e-3 * tol()) as Real;
        let t = time_of_impact(
            &a,
            &b,
            0.0,
            end as Real,
            tolerance,
            Rewind::Never,
            &mut manifolds,
        )
        .expect("an impact");
        let speed = f64::from(vy.abs() + omega.abs() * 0.5 * length);
        assert!(
            (f64::from(t) - expected).abs() * speed < tol(),
            "y0 {y0}, vy {vy}, θ0 {theta0}, ω {omega}: t = {t}, closed form {expected}"
        );
    }
}

/// A rod that turns away from the floor faster than it falls, or falls
/// too slowly, does not meet it within the interval.
#[test]
fn a_rod_that_does_not_reach_the_floor_has_no_impact() {
    let (floor, still) = floor();
    let rod = Segment::new(xy(-0.5, 0.0), xy(0.5, 0.0));
    let mut manifolds = Vec::new();
    let motion = body(xy(0.0, 1.0), 0.0, xy(0.0, -0.2), about_z(0.0));
    let a = Mover {
        motion: &motion,
        offset: Some(Pose::IDENTITY),
        shape: &rod,
        reach: 0.5,
    };
    let b = Mover {
        motion: &still,
        offset: None,
        shape: &floor,
        reach: 0.0,
    };
    assert_eq!(
        time_of_impact(&a, &b, 0.0, 1.0, 1e-9, Rewind::Never, &mut manifolds),
        None
    );
}

/// A cube falling flat meets the floor at `(y₀ − h)/|vy|`, and its patch is
/// the centre of its lower face (no arm: no spin); tilted about z it lands
/// on an edge (3D) or a corner (2D), whose patch is the edge's midpoint:
/// under the centre along z.
#[test]
fn a_face_lands_at_its_centre_and_an_edge_at_its_midpoint() {
    let (floor, still) = floor();
    let cube = Cuboid::new(Vector::splat(0.5));
    let mut manifolds = Vec::new();
    for angle in [0.0 as Real, 0.3] {
        let motion = body(xy(0.2, 1.5), angle, xy(0.1, -2.0), zero_angvel());
        let a = Mover {
            motion: &motion,
            offset: Some(Pose::IDENTITY),
            shape: &cube,
            reach: 0.9,
        };
        let b = Mover {
            motion: &still,
            offset: None,
            shape: &floor,
            reach: 0.0,
        };
        let tolerance = (1e-3 * tol()) as Real;
        let t = time_of_impact(&a, &b, 0.0, 1.0, tolerance, Rewind::Never, &mut manifolds).unwrap();
        // The lowest point's depth below the centre: h (cos θ + sin θ).
        let drop = 0.5 * (f64::from(angle).cos() + f64::from(angle).sin());
        let expected = (1.5 - drop) / 2.0;
        assert!(
            (f64::from(t) - expected).abs() < tol(),
            "angle {angle}: t = {t} for {expected}"
        );
        let approach = |_: Vector, _: Vector| 1.0;
        let found = patch(
            Placed {
                shape: &cube,
                pose: a.pose_at(t),
            },
            Placed {
                shape: &floor,
                pose: b.pose_at(t),
            },
            (1e-4, 1e-6),
            0.0,
            approach,
            &mut manifolds,
        )
        .expect("a patch");
        let centre = a.pose_at(t).translation;
        let normal = found.normal;
        assert!(
            (normal - xy(0.0, -1.0)).length() < 1e-6,
            "normal {normal:?}"
        );
        let lowest_x = if angle == 0.0 {
            f64::from(centre.x)
        } else {
            // The lowest corner (2D) or edge (3D): (−h, −h) turned by θ.
            let (c, s) = (f64::from(angle).cos(), f64::from(angle).sin());
            f64::from(centre.x) + 0.5 * (-c + s)
        };
        assert!(
            (f64::from(found.point.x) - lowest_x).abs() < 1e2 * tol(),
            "angle {angle}: {found:?}"
        );
        assert!(f64::from(found.point.y).abs() < 1e2 * tol(), "{found:?}");
        if DIM == 3 {
            assert!(
                (found.point[DIM - 1] - centre[DIM - 1]).abs() < 1e-6,
                "{found:?}"
            );
        }
    }
}

/// Partners parry's nonlinear cast does not take (a heightfield) and
/// composite bodies (a compound) meet a falling ball at `(y₀ − r)/|vy|`.
#[test]
fn heightfields_and_compounds_are_met_in_time() {
    let mut manifolds = Vec::new();
    #[cfg(feature = "dim2")]
    let field = HeightField::new(vec![0.0; 5], xy(8.0, 1.0));
    #[cfg(feature = "dim3")]
    let field = HeightField::new(
        crate::rapier::parry::utils::Array2::new(3, 3, vec![0.0; 9]),
        Vector::new(8.0, 1.0, 8.0),
    );
    let compound = Compound::new(vec![
        (
            Pose::from_translation(xy(-0.3, 0.0)),
            SharedShape::ball(0.25),
        ),
        (
            Pose::from_translation(xy(0.3, 0.1)),
            SharedShape::ball(0.25),
        ),
    ]);
    let still = Motion::still(Pose::IDENTITY);
    let ball = Ball::new(0.25);
    let falling = body(xy(0.1, 1.25), 0.0, xy(0.0, -2.0), zero_angvel());
    for (name, shape) in [("ball", &ball as &dyn Shape), ("compound", &compound)] {
        let a = Mover {
            motion: &falling,
            offset: Some(Pose::IDENTITY),
            shape,
            reach: 0.7,
        };
        let b = Mover {
            motion: &still,
            offset: None,
            shape: &field,
            reach: 0.0,
        };
        let t = time_of_impact(
            &a,
            &b,
            0.0,
            1.0,
            (1e-3 * tol()) as Real,
            Rewind::Never,
            &mut manifolds,
        )
        .unwrap();
        // The compound's lowest ball is 0.1 below the other's centre line.
        let expected = (1.25 - 0.25) / 2.0;
        assert!(
            (f64::from(t) - expected).abs() < tol(),
            "{name}: t = {t} for {expected}"
        );
    }
}

/// A pair first seen overlapping is rewound along its motions to the last
/// instant it was apart (a ball sunk 0.1 into the floor at 2 m/s: 0.05 s
/// back).
#[test]
fn an_overlap_is_rewound_to_its_contact() {
    let (floor, still) = floor();
    let ball = Ball::new(0.5);
    let mut manifolds = Vec::new();
    let motion = body(xy(0.0, 0.4), 0.0, xy(0.0, -2.0), zero_angvel());
    let a = Mover {
        motion: &motion,
        offset: Some(Pose::IDENTITY),
        shape: &ball,
        reach: 0.5,
    };
    let b = Mover {
        motion: &still,
        offset: None,
        shape: &floor,
        reach: 0.0,
    };
    let t = time_of_impact(&a, &b, 0.0, 0.1, 1e-9, Rewind::Allowed, &mut manifolds).unwrap();
    assert!((f64::from(t) + 0.05).abs() < tol(), "t = {t}");
}

/// A pair that starts a search touching (within the tolerance) meets at
/// the search's start, whether it closes or parts; one farther apart than
/// it can close by the end of the search never meets, and one that can
/// meets at `(gap − tolerance) / speed`, as a cube falling flat onto the
/// floor does.
#[test]
fn a_search_starting_in_contact_meets_at_its_start() {
    let mut manifolds = Vec::new();
    let (ground, still) = floor();
    let cube = Cuboid::new(Vector::splat(0.5));
    let tolerance = (1e-3 * tol()) as Real;
    let search = |height: Real, vy: Real, manifolds: &mut Vec<_>| {
        // At `height` above the floor at 0.25, the search's start.
        let mut falling = body(xy(0.0, 0.5 + height), 0.0, xy(0.0, vy), zero_angvel());
        falling.t_ref = 0.25;
        let (a, b) = (cube_mover(&falling, &cube), floor_mover(&still, &ground));
        time_of_impact(&a, &b, 0.25, 1.0, tolerance, Rewind::Never, manifolds)
    };
    for vy in [-2.0, 0.0, 2.0] {
        assert_eq!(search(0.0, vy, &mut manifolds), Some(0.25), "vy = {vy}");
        assert_eq!(
            search(0.5 * tolerance, vy, &mut manifolds),
            Some(0.25),
            "vy = {vy}"
        );
    }
    // At 2 m/s for the 0.75 s left, 1.5 apart at most is reached.
    assert_eq!(search(1.6, -2.0, &mut manifolds), None);
    let t = search(1.0, -2.0, &mut manifolds).expect("reached");
    let expected = 0.25 + (1.0 - f64::from(tolerance)) / 2.0;
    assert!(
        (f64::from(t) - expected).abs() < tol(),
        "t = {t} for {expected}"
    );
}

/// The touch an impact's instant judges its bodies' other pairs by
/// (`touching_at`) is the one the search from that instant starts with: a
/// cube touching the floor meets it at once, one apart does not (whether
/// it falls, rests or rises, level or turned); a shape that is not convex
/// is left to its search.
#[test]
fn the_instant_s_touch_is_the_search_s() {
    let mut manifolds = Vec::new();
    let (ground, still) = floor();
    let cube = Cuboid::new(Vector::splat(0.5));
    let tolerance = (1e-3 * tol()) as Real;
    let b = floor_mover(&still, &ground);
    // The lowest point of a cube turned by `angle` about z is this far
    // below its centre.
    let low = |angle: Real| 0.5 * (angle.cos().abs() + angle.sin().abs());
    let mut seen = [0usize; 2];
    for angle in [0.0, 0.3] {
        for gap in [0.0, 0.5 * tolerance, 3.0 * tolerance, 0.1, 2.0] {
            for vy in [-2.0, 0.0, 2.0] {
                let mut falling = body(xy(0.0, low(angle) + gap), angle, xy(0.0, vy), about_z(1.5));
                falling.t_ref = 0.25;
                let a = cube_mover(&falling, &cube);
                let touching = touching_at(&a, &b, 0.25, tolerance).expect("two convex shapes");
                let searched =
                    time_of_impact(&a, &b, 0.25, 1.0, tolerance, Rewind::Never, &mut manifolds);
                assert_eq!(
                    touching,
                    searched == Some(0.25),
                    "angle {angle}, gap {gap}, vy {vy}: search {searched:?}"
                );
                seen[usize::from(touching)] += 1;
            }
        }
    }
    assert!(seen[0] > 0 && seen[1] > 0, "both answers met: {seen:?}");
    let compound = Compound::new(vec![(Pose::IDENTITY, SharedShape::new(cube))]);
    let motion = body(xy(0.0, 0.5), 0.0, Vector::ZERO, zero_angvel());
    let a = Mover {
        motion: &motion,
        offset: Some(Pose::IDENTITY),
        shape: &compound,
        reach: 0.87,
    };
    assert_eq!(touching_at(&a, &b, 0.25, tolerance), None);
}

/// The turn's bound along a direction holds every point of the body
/// within its reach: `(ω × r)·n ≤ |n × ω| reach`, and it is never above
/// the bound on the whole turn (`|ω| reach`).
#[test]
fn the_turn_bound_along_a_normal_holds_every_point() {
    let mut rng = crate::test_rng::TestRng::new(11);
    let reach = 0.7 as Real;
    for _ in 0..2000 {
        let mut unit = || {
            let mut v = Vector::ZERO;
            for k in 0..DIM {
                v[k] = 2.0 * rng.next() - 1.0;
            }
            v.normalize_or_zero()
        };
        let (n, r) = (unit(), unit() * reach);
        if n == Vector::ZERO {
            continue;
        }
        #[cfg(feature = "dim2")]
        let w: AngVector = 5.0 * n.x;
        #[cfg(feature = "dim3")]
        let w: AngVector = 5.0 * unit();
        let motion = body(Vector::ZERO, 0.0, Vector::ZERO, w);
        let along = motion.turn_speed_along(n, reach);
        let speed = super::super::cross(w, r).dot(n);
        assert!(
            speed <= along * (1.0 + 1e-5) + 1e-6,
            "{speed} above {along}"
        );
        assert!(along <= motion.turn_speed(reach) * (1.0 + 1e-5) + 1e-6);
    }
}

/// The boxes' separating axis the convex search steps on when they are
/// well apart (`cuboid_separation`) is a pair of separating planes: every
/// corner of the first box lies on its side of the plane through its
/// farthest corner along the axis, every corner of the second at least the
/// gap beyond it, and the gap is at most their distance (GJK's, parry's).
#[test]
fn the_boxes_separating_axis_separates_them_by_its_gap() {
    let mut rng = crate::test_rng::TestRng::new(5);
    let mut v = |scale: Real| {
        let mut v = Vector::ZERO;
        for k in 0..DIM {
            v[k] = scale * (2.0 * rng.next() - 1.0);
        }
        v
    };
    fn corners(c: &Cuboid, pose: Pose) -> Vec<Vector> {
        (0..1usize << DIM)
            .map(|bits| {
                let mut p = c.half_extents;
                for k in 0..DIM {
                    if bits & (1 << k) != 0 {
                        p[k] = -p[k];
                    }
                }
                pose * p
            })
            .collect()
    }
    let mut separated = 0;
    for _ in 0..500 {
        let (a, b) = (
            Cuboid::new(v(0.5).abs() + Vector::splat(0.05)),
            Cuboid::new(v(0.5).abs() + Vector::splat(0.05)),
        );
        #[cfg(feature = "dim2")]
        let (ra, rb) = (v(3.0).x, v(3.0).x);
        #[cfg(feature = "dim3")]
        let (ra, rb) = (v(3.0), v(3.0));
        let pa = Pose::new(v(1.0), ra);
        let pb = Pose::new(v(3.0), rb);
        let (gap, n) = cuboid_separation(&a, &pa, &b, &pb);
        assert!((n.length() - 1.0).abs() < 1e-4, "a unit axis: {n:?}");
        let top = corners(&a, pa)
            .into_iter()
            .map(|p| p.dot(n))
            .fold(Real::MIN, Real::max);
        let bottom = corners(&b, pb)
            .into_iter()
            .map(|p| p.dot(n))
            .fold(Real::MAX, Real::min);
        let slack = 1e-4 as Real;
        assert!(
            (bottom - top - gap).abs() < slack,
            "gap {gap} between planes {}",
            bottom - top
        );
        let distance = DefaultQueryDispatcher
            .distance(&pa.inv_mul(&pb), &a, &b)
            .unwrap()
            .distance;
        assert!(
            gap <= distance + slack,
            "gap {gap} above the distance {distance}"
        );
        separated += usize::from(gap > 0.0);
    }
    assert!(separated > 100, "{separated} separated pairs");
}
