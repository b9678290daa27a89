//! The validator's check of one body.

use crate::check::{Check, Checker};
use crate::{Angular, Body, BodyFile, Shape};

/// The most points a convex shape may have.
pub const MAX_POINTS: usize = 1000;

/// The shapes' names, for messages.
const SHAPES: &str = "\"ball\", \"box\", \"capsule\" or \"convex\"";

impl Checker<'_> {
    /// The body written at `at` (a generator's template when `generated`),
    /// and whether its `restitution` was written (it then speaks to the law
    /// where nothing else does, see [`crate::validate`]).
    pub(crate) fn body(
        &self,
        at: &str,
        origin: &str,
        b: &BodyFile,
        generated: bool,
    ) -> Check<(Body, bool)> {
        let f = |k: &str| format!("{at}.{k}");
        let shape = self.shape(at, b)?;
        let position = match (&b.position, generated) {
            (Some(p), false) => self.vector(&f("position"), p)?,
            (None, false) => return self.err(&f("position"), "missing"),
            (Some(_), true) => {
                return self.err(
                    &f("position"),
                    "a generator places its bodies: remove `position` from the template",
                );
            }
            (None, true) => vec![0.0; self.dim],
        };
        let fixed = b.fixed.unwrap_or(false);
        let rotation = self.angular(&f("rotation"), b.rotation.as_ref(), "rotation")?;
        let angular_velocity = self.angular(
            &f("angular_velocity"),
            b.angular_velocity.as_ref(),
            "angular velocity",
        )?;
        if fixed && angular_velocity.iter().any(|x| *x != 0.0) {
            return self.err(
                &f("angular_velocity"),
                "a fixed body cannot turn: remove `angular_velocity` or set `fixed = false`",
            );
        }
        let velocity = match &b.velocity {
            Some(v) => self.vector(&f("velocity"), v)?,
            None => vec![0.0; self.dim],
        };
        if fixed && velocity.iter().any(|x| *x != 0.0) {
            return self.err(
                &f("velocity"),
                "a fixed body cannot move: remove `velocity` or set `fixed = false`",
            );
        }
        let mass = match (b.mass, fixed) {
            (Some(_), true) => {
                return self.err(
                    &f("mass"),
                    "a fixed body has no mass: remove `mass` or set `fixed = false`",
                );
            }
            (None, true) => None,
            (Some(m), false) => Some(self.positive(&f("mass"), m)?),
            (None, false) if generated => None, // may come from `masses`
            (None, false) => {
                return self.err(&f("mass"), "missing: a body that is not fixed needs a mass");
            }
        };
        let restitution = self.non_negative(&f("restitution"), b.restitution.unwrap_or(0.0))?;
        let friction = self.non_negative(&f("friction"), b.friction.unwrap_or(0.0))?;
        let law = match b.law {
            Some(true) if fixed => {
                return self.err(
                    &f("law"),
                    "a fixed body cannot follow the law (law bodies meet fixed ones through `law.fixed_partner`): remove `law` or set it to false",
                );
            }
            Some(l) => l,
            None => !fixed,
        };
        if b.ccd == Some(true) && fixed {
            return self.err(
                &f("ccd"),
                "a fixed body does not move: CCD is for moving bodies",
            );
        }
        if b.allow_fast_rotation == Some(true) && fixed {
            return self.err(
                &f("allow_fast_rotation"),
                "a fixed body does not turn: `allow_fast_rotation` is for moving bodies",
            );
        }
        let material = match &b.material {
            Some(_) if !fixed && !law => {
                return self.err(
                    &f("material"),
                    "a body that does not follow the law has no material: remove `material`, or set `law` to true",
                );
            }
            Some(name) => Some(self.material(&f("material"), name)?),
            None => None,
        };
        let body = Body {
            origin: origin.to_owned(),
            name: b.name.clone(),
            shape,
            position,
            velocity,
            rotation,
            angular_velocity,
            mass,
            fixed,
            restitution,
            restitution_combine: b.restitution_combine.unwrap_or_default(),
            friction,
            law,
            ccd: b.ccd,
            allow_fast_rotation: b.allow_fast_rotation.unwrap_or(false),
            material,
        };
        Ok((body, b.restitution.is_some()))
    }

    /// The shape written at `at`: its name and exactly the keys it takes.
    fn shape(&self, at: &str, b: &BodyFile) -> Check<Shape> {
        let f = |k: &str| format!("{at}.{k}");
        let Some(name) = b.shape.as_deref() else {
            return self.err(&f("shape"), format!("missing: {SHAPES}"));
        };
        let takes: &[&str] = match name {
            "ball" => &["radius"],
            "box" => &["half_extents"],
            "capsule" => &["half_height", "radius"],
            "convex" => &["points"],
            other => {
                return self.err(
                    &f("shape"),
                    format!("unknown shape {other:?}: expected {SHAPES}"),
                );
            }
        };
        let written = [
            ("radius", b.radius.is_some()),
            ("half_extents", b.half_extents.is_some()),
            ("half_height", b.half_height.is_some()),
            ("points", b.points.is_some()),
        ];
        for (key, given) in written {
            if given && !takes.contains(&key) {
                let keys: Vec<String> = takes.iter().map(|k| format!("`{k}`")).collect();
                return self.err(
                    &f(key),
                    format!("a {name} has {}, not `{key}`", keys.join(" and ")),
                );
            }
        }
        for key in takes {
            if !written.iter().any(|(k, given)| k == key && *given) {
                return self.err(&f(key), format!("missing: a {name} needs `{key}`"));
            }
        }
        Ok(match name {
            "ball" => Shape::Ball {
                radius: self.positive(&f("radius"), b.radius.unwrap_or_default())?,
            },
            "box" => {
                let h = self.vector(
                    &f("half_extents"),
                    b.half_extents.as_deref().unwrap_or_default(),
                )?;
                for (i, x) in h.iter().enumerate() {
                    self.positive(&format!("{}[{i}]", f("half_extents")), *x)?;
                }
                Shape::Box { half_extents: h }
            }
            "capsule" => Shape::Capsule {
                half_height: self.positive(&f("half_height"), b.half_height.unwrap_or_default())?,
                radius: self.positive(&f("radius"), b.radius.unwrap_or_default())?,
            },
            _ => Shape::Convex {
                points: self.points(&f("points"), b.points.as_deref().unwrap_or_default())?,
            },
        })
    }

    /// A convex shape's points: `dim + 1` to [`MAX_POINTS`] of them, each a
    /// finite `dim`-vector, spanning an area (2D) or a volume (3D) whose
    /// size is more than 1e-9 of the points' extent.
    fn points(&self, field: &str, points: &[Vec<f64>]) -> Check<Vec<Vec<f64>>> {
        let dim = self.dim;
        if points.len() <= dim || points.len() > MAX_POINTS {
            return self.err(
                field,
                format!(
                    "must list {} to {MAX_POINTS} points (their convex hull is the shape), got {}",
                    dim + 1,
                    points.len()
                ),
            );
        }
        let mut out = Vec::with_capacity(points.len());
        for (i, p) in points.iter().enumerate() {
            out.push(self.vector(&format!("{field}[{i}]"), p)?);
        }
        // The points span the space: from the first, the farthest point,
        // then the point farthest from that line (and, in 3D, from that
        // plane).
        let sub =
            |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x - y).collect() };
        let dot = |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| x * y).sum() };
        let o = &out[0];
        let rel: Vec<Vec<f64>> = out.iter().map(|p| sub(p, o)).collect();
        let far = rel.iter().map(|v| dot(v, v).sqrt()).fold(0.0, f64::max);
        let mut basis: Vec<Vec<f64>> = Vec::new();
        for _ in 0..dim {
            // Gram-Schmidt: the point farthest from the span so far.
            let residual = |v: &Vec<f64>| {
                let mut r = v.clone();
                for e in &basis {
                    let c = dot(&r, e);
                    r = r.iter().zip(e).map(|(x, y)| x - c * y).collect();
                }
                r
            };
            let best = rel
                .iter()
                .map(residual)
                .max_by(|a, b| dot(a, a).total_cmp(&dot(b, b)))
                .unwrap_or_default();
            let n = dot(&best, &best).sqrt();
            if n <= 1e-9 * far {
                return self.err(
                    field,
                    format!(
                        "the points lie on a {}: their hull has no {}",
                        if basis.is_empty() {
                            "point"
                        } else if basis.len() == 1 {
                            "line"
                        } else {
                            "plane"
                        },
                        if dim == 2 { "area" } else { "volume" }
                    ),
                );
            }
            basis.push(best.into_iter().map(|x| x / n).collect());
        }
        Ok(out)
    }

    /// A rotation or an angular velocity (`what`): a number in 2D, a
    /// 3-vector in 3D, as `[x]` or `[x, y, z]`; zero when not written.
    fn angular(&self, field: &str, a: Option<&Angular>, what: &str) -> Check<Vec<f64>> {
        let n = if self.dim == 2 { 1 } else { 3 };
        match (a, self.dim) {
            (None, _) => Ok(vec![0.0; n]),
            (Some(Angular::Scalar(x)), 2) => Ok(vec![self.finite(field, *x)?]),
            (Some(Angular::Vector(v)), 3) => self.vector(field, v),
            (Some(Angular::Scalar(_)), _) => self.err(
                field,
                format!("a 3D {what} is a vector [x, y, z] (for a rotation: axis times angle)"),
            ),
            (Some(Angular::Vector(_)), _) => {
                self.err(field, format!("a 2D {what} is a number (radians)"))
            }
        }
    }
}
