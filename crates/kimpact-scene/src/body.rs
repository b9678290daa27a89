//! The validator's check of one body.

use crate::check::{Check, Checker};
use crate::{Body, BodyFile, Shape};

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
        let shape_name = match b.shape.as_deref() {
            Some(s) => s,
            None => return self.err(&f("shape"), "missing: \"ball\" or \"box\""),
        };
        let shape = match shape_name {
            "ball" => {
                if b.half_extents.is_some() {
                    return self.err(
                        &f("half_extents"),
                        "a ball has a `radius`, not `half_extents`",
                    );
                }
                match b.radius {
                    Some(r) => Shape::Ball {
                        radius: self.positive(&f("radius"), r)?,
                    },
                    None => return self.err(&f("radius"), "missing: a ball needs a radius"),
                }
            }
            "box" => {
                if b.radius.is_some() {
                    return self.err(&f("radius"), "a box has `half_extents`, not a `radius`");
                }
                match &b.half_extents {
                    Some(h) => {
                        let h = self.vector(&f("half_extents"), h)?;
                        for (i, x) in h.iter().enumerate() {
                            self.positive(&format!("{}[{i}]", f("half_extents")), *x)?;
                        }
                        Shape::Box { half_extents: h }
                    }
                    None => {
                        return self.err(&f("half_extents"), "missing: a box needs half_extents");
                    }
                }
            }
            other => {
                return self.err(
                    &f("shape"),
                    format!("unknown shape {other:?}: expected \"ball\" or \"box\""),
                );
            }
        };
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
            None => matches!(shape, Shape::Ball { .. }) && !fixed,
        };
        if b.ccd == Some(true) && fixed {
            return self.err(
                &f("ccd"),
                "a fixed body does not move: CCD is for moving bodies",
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
            mass,
            fixed,
            restitution,
            restitution_combine: b.restitution_combine.unwrap_or_default(),
            friction,
            law,
            ccd: b.ccd,
            material,
        };
        Ok((body, b.restitution.is_some()))
    }
}
