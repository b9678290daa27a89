//! Bad input gives typed errors naming the culprit; borderline good input
//! (touching balls, balls touching walls) is accepted.

use kimpact::Law;
use kimpact_reference::nalgebra::{Vector2, Vector3};
use kimpact_reference::{Ball, BoxBounds, Quantity, Reference, ReferenceError};

fn unit() -> BoxBounds<2> {
    BoxBounds::new(Vector2::zeros(), Vector2::new(1.0, 1.0))
}

fn ok_ball(x: f64) -> Ball<2> {
    Ball::new(0.1, 1.0, Vector2::new(x, 0.5), Vector2::new(0.3, -0.2))
}

fn new2(balls: Vec<Ball<2>>) -> Result<Reference<2>, ReferenceError> {
    Reference::new(balls, unit(), Vector2::zeros(), Law::elastic())
}

#[test]
fn non_finite_values() {
    let mut b = ok_ball(0.5);
    b.radius = f64::NAN;
    let err = new2(vec![ok_ball(0.2), b]).unwrap_err();
    assert!(matches!(
        err,
        ReferenceError::NonFinite { ball: 1, quantity: Quantity::Radius, component: 0, value } if value.is_nan()
    ));
    let mut b = ok_ball(0.5);
    b.mass = f64::INFINITY;
    assert_eq!(
        new2(vec![b]).unwrap_err(),
        ReferenceError::NonFinite {
            ball: 0,
            quantity: Quantity::Mass,
            component: 0,
            value: f64::INFINITY
        }
    );
    let mut b = ok_ball(0.5);
    b.position.y = f64::NEG_INFINITY;
    assert_eq!(
        new2(vec![b]).unwrap_err(),
        ReferenceError::NonFinite {
            ball: 0,
            quantity: Quantity::Position,
            component: 1,
            value: f64::NEG_INFINITY
        }
    );
    let mut b = ok_ball(0.5);
    b.velocity.x = f64::INFINITY;
    let err = new2(vec![ok_ball(0.2), ok_ball(0.8), b]).unwrap_err();
    assert_eq!(
        err,
        ReferenceError::NonFinite {
            ball: 2,
            quantity: Quantity::Velocity,
            component: 0,
            value: f64::INFINITY
        }
    );
    assert_eq!(
        err.to_string(),
        "ball 2: velocity (component 0) must be finite, got inf"
    );
}

#[test]
fn non_positive_radius_or_mass() {
    let mut b = ok_ball(0.5);
    b.radius = 0.0;
    assert_eq!(
        new2(vec![b]).unwrap_err(),
        ReferenceError::NonPositiveRadius {
            ball: 0,
            value: 0.0
        }
    );
    let mut b = ok_ball(0.5);
    b.mass = -2.0;
    let err = new2(vec![ok_ball(0.2), b]).unwrap_err();
    assert_eq!(
        err,
        ReferenceError::NonPositiveMass {
            ball: 1,
            value: -2.0
        }
    );
    assert_eq!(err.to_string(), "ball 1: mass must be positive, got -2");
}

#[test]
fn bad_box_and_gravity() {
    let ball = vec![ok_ball(0.5)];
    let flat = BoxBounds::new(Vector2::zeros(), Vector2::new(1.0, 0.0));
    assert_eq!(
        Reference::new(ball.clone(), flat, Vector2::zeros(), Law::elastic()).unwrap_err(),
        ReferenceError::InvalidBox {
            axis: 1,
            lo: 0.0,
            hi: 0.0
        }
    );
    let open = BoxBounds::new(Vector2::new(f64::NEG_INFINITY, 0.0), Vector2::new(1.0, 1.0));
    assert!(matches!(
        Reference::new(ball.clone(), open, Vector2::zeros(), Law::elastic()),
        Err(ReferenceError::InvalidBox { axis: 0, .. })
    ));
    assert!(matches!(
        Reference::new(ball, unit(), Vector2::new(0.0, f64::NAN), Law::elastic()),
        Err(ReferenceError::NonFiniteGravity { component: 1, .. })
    ));
}

#[test]
fn ball_outside_box() {
    let stick_out = Ball::new(0.1, 1.0, Vector2::new(0.5, 0.95), Vector2::zeros());
    assert_eq!(
        new2(vec![ok_ball(0.2), stick_out]).unwrap_err(),
        ReferenceError::OutsideBox {
            ball: 1,
            axis: 1,
            position: 0.95,
            radius: 0.1,
            lo: 0.0,
            hi: 1.0
        }
    );
    let gone = Ball::new(0.1, 1.0, Vector3::new(0.5, 0.5, -3.0), Vector3::zeros());
    let bounds = BoxBounds::new(Vector3::zeros(), Vector3::repeat(1.0));
    assert!(matches!(
        Reference::new(vec![gone], bounds, Vector3::zeros(), Law::elastic()),
        Err(ReferenceError::OutsideBox {
            ball: 0,
            axis: 2,
            ..
        })
    ));
    // Too big for the box on any position.
    let huge = Ball::new(0.6, 1.0, Vector2::new(0.5, 0.5), Vector2::zeros());
    assert!(matches!(
        new2(vec![huge]),
        Err(ReferenceError::OutsideBox { axis: 0, .. })
    ));
}

#[test]
fn overlapping_balls() {
    let err = new2(vec![ok_ball(0.15), ok_ball(0.5), ok_ball(0.65)]).unwrap_err();
    let ReferenceError::Overlap {
        first,
        second,
        distance,
        contact,
    } = err
    else {
        panic!("{err:?}")
    };
    assert_eq!((first.min(second), first.max(second)), (1, 2));
    assert!((distance - 0.15).abs() < 1e-15);
    assert_eq!(contact, 0.2);
}

#[test]
fn touching_is_allowed() {
    // Touching each other (up to rounding) and touching walls.
    let mut sim = new2(vec![
        Ball::new(0.1, 1.0, Vector2::new(0.1, 0.1), Vector2::zeros()),
        Ball::new(0.1, 1.0, Vector2::new(0.3, 0.1), Vector2::zeros()),
        Ball::new(0.1, 1.0, Vector2::new(0.5, 0.1), Vector2::new(0.0, 1.0)),
        Ball::new(0.1, 1.0, Vector2::new(0.9, 0.9), Vector2::new(-1.0, 0.0)),
    ])
    .unwrap();
    sim.advance_to(1.0).unwrap();
    assert_eq!(sim.balls().len(), 4);
}

#[test]
fn empty_is_fine() {
    let mut sim = new2(Vec::new()).unwrap();
    sim.advance_to(10.0).unwrap();
    assert_eq!(sim.kinetic_energy(), 0.0);
    assert_eq!(sim.stats().impacts(), 0);
}

#[test]
fn bad_target_times() {
    let mut sim = new2(vec![ok_ball(0.5)]).unwrap();
    sim.advance_to(1.0).unwrap();
    assert_eq!(
        sim.advance_to(0.5).unwrap_err(),
        ReferenceError::InvalidTime {
            target: 0.5,
            now: 1.0
        }
    );
    assert!(matches!(
        sim.advance_to(f64::NAN),
        Err(ReferenceError::InvalidTime { .. })
    ));
    assert!(matches!(
        sim.advance_to(f64::INFINITY),
        Err(ReferenceError::InvalidTime { .. })
    ));
    assert!(matches!(
        sim.advance_by(-1.0),
        Err(ReferenceError::InvalidTime { .. })
    ));
    // The failed calls changed nothing.
    assert_eq!(sim.time(), 1.0);
    sim.advance_to(1.0).unwrap();
}
