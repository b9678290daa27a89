//! The validator's check of the joints: their bodies, their keys, and that
//! each holds at the start (a joint that is not satisfied at the start
//! would pull its bodies together, an energy no law is responsible for).

use crate::check::{Check, Checker};
use crate::{Body, BodyRef, Joint, JointEnd, JointFile, JointKind};

/// The joint kinds' names, for messages.
const KINDS: &str = "\"fixed\", \"revolute\", \"spherical\", \"prismatic\" or \"rope\"";

impl Checker<'_> {
    /// Every joint of the scene, between `bodies` (all of them, generated
    /// ones included).
    pub(crate) fn joints(&self, raw: &[JointFile], bodies: &[Body]) -> Check<Vec<Joint>> {
        raw.iter()
            .enumerate()
            .map(|(i, j)| self.joint(i, j, bodies))
            .collect()
    }

    /// The end of a joint named at `field`.
    fn end(&self, field: &str, r: Option<&BodyRef>, bodies: &[Body]) -> Check<JointEnd> {
        match r {
            None => self.err(field, "missing: a body index, a body name or \"world\""),
            Some(BodyRef::Index(i)) => match usize::try_from(*i) {
                Ok(i) if i < bodies.len() => Ok(JointEnd::Body(i)),
                _ => self.err(
                    field,
                    format!(
                        "no body {i}: the scene has {} bodies (indices 0 to {}: `bodies`, then the generators')",
                        bodies.len(),
                        bodies.len() - 1
                    ),
                ),
            },
            Some(BodyRef::Name(n)) if n == "world" => Ok(JointEnd::World),
            Some(BodyRef::Name(n)) => {
                let named: Vec<usize> = bodies
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| b.name.as_deref() == Some(n.as_str()))
                    .map(|(i, _)| i)
                    .collect();
                match named.as_slice() {
                    [] => self.err(
                        field,
                        format!("unknown body {n:?}: no body has this `name` (or give an index)"),
                    ),
                    [i] => Ok(JointEnd::Body(*i)),
                    many => self.err(
                        field,
                        format!(
                            "{} bodies are named {n:?} ({}): give an index",
                            many.len(),
                            many.iter()
                                .take(4)
                                .map(|i| bodies[*i].origin.clone())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ),
                }
            }
        }
    }

    /// `joints[i]`.
    fn joint(&self, i: usize, j: &JointFile, bodies: &[Body]) -> Check<Joint> {
        let at = format!("joints[{i}]");
        let f = |k: &str| format!("{at}.{k}");
        let Some(kind_name) = j.kind.as_deref() else {
            return self.err(&f("kind"), format!("missing: {KINDS}"));
        };
        if !matches!(
            kind_name,
            "fixed" | "revolute" | "spherical" | "prismatic" | "rope"
        ) {
            return self.err(
                &f("kind"),
                format!("unknown joint kind {kind_name:?}: expected {KINDS}"),
            );
        }
        if kind_name == "spherical" && self.dim == 2 {
            return self.err(
                &f("kind"),
                "\"spherical\" is for 3D scenes: in 2D, a joint that turns freely about its anchor is \"revolute\"",
            );
        }
        let body1 = self.end(&f("body1"), j.body1.as_ref(), bodies)?;
        let body2 = self.end(&f("body2"), j.body2.as_ref(), bodies)?;
        let name = |e: JointEnd| match e {
            JointEnd::World => "the world".to_owned(),
            JointEnd::Body(b) => bodies[b].origin.clone(),
        };
        if body1 == body2 {
            return self.err(&f("body2"), format!("joins {} to itself", name(body1)));
        }
        let moving = |e: JointEnd| matches!(e, JointEnd::Body(b) if !bodies[b].fixed);
        if !moving(body1) && !moving(body2) {
            return self.err(
                &f("body2"),
                format!(
                    "joins {} to {}: nothing that moves (one end must be a body that is not fixed)",
                    name(body1),
                    name(body2)
                ),
            );
        }
        let anchor = |k: &str, v: &Option<Vec<f64>>| match v {
            Some(v) => self.vector(&f(k), v),
            None => Ok(vec![0.0; self.dim]),
        };
        let anchor1 = anchor("anchor1", &j.anchor1)?;
        let anchor2 = anchor("anchor2", &j.anchor2)?;
        let kind = self.kind(&at, kind_name, j)?;
        let joint = Joint {
            origin: at.clone(),
            kind,
            body1,
            body2,
            anchor1,
            anchor2,
            contacts_enabled: j.contacts_enabled.unwrap_or(true),
        };
        self.holds_at_start(&joint, bodies)?;
        Ok(joint)
    }

    /// The kind's own keys (`axis`, `limits`, `max_distance`), each allowed
    /// only where it means something.
    fn kind(&self, at: &str, kind: &str, j: &JointFile) -> Check<JointKind> {
        let f = |k: &str| format!("{at}.{k}");
        let takes_axis = kind == "prismatic" || (kind == "revolute" && self.dim == 3);
        let axis = match (&j.axis, takes_axis) {
            (Some(a), true) => Some(self.unit(&f("axis"), a)?),
            (None, true) => {
                return self.err(
                    &f("axis"),
                    format!(
                        "missing: a {kind} joint needs an axis ({} components)",
                        self.dim
                    ),
                );
            }
            (Some(_), false) if kind == "revolute" => {
                return self.err(
                    &f("axis"),
                    "a 2D revolute joint turns about z: remove `axis`",
                );
            }
            (Some(_), false) => {
                return self.err(&f("axis"), format!("a {kind} joint has no `axis`"));
            }
            (None, false) => None,
        };
        let limits = match &j.limits {
            None => None,
            Some(_) if !matches!(kind, "revolute" | "prismatic") => {
                return self.err(
                    &f("limits"),
                    format!("a {kind} joint has no `limits` (revolute and prismatic joints do)"),
                );
            }
            Some(l) => {
                for (k, x) in l.iter().enumerate() {
                    self.finite(&format!("{}[{k}]", f("limits")), *x)?;
                }
                match l.as_slice() {
                    [lo, hi] if lo <= hi => Some([*lo, *hi]),
                    _ => {
                        return self.err(
                            &f("limits"),
                            format!("must be [min, max] with min <= max, got {l:?}"),
                        );
                    }
                }
            }
        };
        match (j.max_distance, kind) {
            (Some(_), k) if k != "rope" => {
                return self.err(
                    &f("max_distance"),
                    format!("a {kind} joint has no `max_distance` (rope joints do)"),
                );
            }
            (None, "rope") => {
                return self.err(
                    &f("max_distance"),
                    "missing: a rope joint needs its length, the longest distance between its anchors",
                );
            }
            _ => {}
        }
        Ok(match kind {
            "fixed" => JointKind::Fixed,
            "spherical" => JointKind::Spherical,
            "revolute" => JointKind::Revolute { axis, limits },
            "prismatic" => JointKind::Prismatic {
                axis: axis.unwrap_or_default(),
                limits,
            },
            _ => JointKind::Rope {
                max_distance: self
                    .non_negative(&f("max_distance"), j.max_distance.unwrap_or_default())?,
            },
        })
    }

    /// A `dim`-vector of non-zero length, normalised.
    fn unit(&self, field: &str, v: &[f64]) -> Check<Vec<f64>> {
        let v = self.vector(field, v)?;
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 0.0 && n.is_finite() {
            Ok(v.into_iter().map(|x| x / n).collect())
        } else {
            self.err(field, format!("must not be zero (a direction), got {v:?}"))
        }
    }

    /// The joint holds at the start, to 1e-4 of the smaller jointed body's
    /// size: the anchors meet (fixed, revolute, spherical), are apart only
    /// along the axis and within the limits (prismatic), or no farther
    /// apart than the rope.
    fn holds_at_start(&self, j: &Joint, bodies: &[Body]) -> Check<()> {
        let world = |end: JointEnd, anchor: &[f64]| -> Vec<f64> {
            match end {
                JointEnd::World => anchor.to_vec(),
                JointEnd::Body(b) => bodies[b].to_world(anchor),
            }
        };
        // A joint that holds relative orientations or takes an axis in both
        // bodies' frames holds at the start only if the frames agree.
        let rotation = |end: JointEnd| match end {
            JointEnd::World => None,
            JointEnd::Body(b) => Some(&bodies[b].rotation).filter(|r| r.iter().any(|x| *x != 0.0)),
        };
        let framed = match &j.kind {
            JointKind::Fixed | JointKind::Prismatic { .. } => true,
            JointKind::Revolute { axis, .. } => axis.is_some(),
            JointKind::Spherical | JointKind::Rope { .. } => false,
        };
        if framed && rotation(j.body1) != rotation(j.body2) {
            return self.err(
                &format!("{}.kind", j.origin),
                format!(
                    "a {} joint holds its bodies' frames together, and its bodies start turned differently (`rotation`): give both the same rotation (the world's is none)",
                    j.kind.name()
                ),
            );
        }
        let p1 = world(j.body1, &j.anchor1);
        let p2 = world(j.body2, &j.anchor2);
        let d: Vec<f64> = p2.iter().zip(&p1).map(|(a, b)| a - b).collect();
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let size = [j.body1, j.body2]
            .into_iter()
            .filter_map(|e| match e {
                JointEnd::Body(b) => Some(bodies[b].shape.min_size()),
                JointEnd::World => None,
            })
            .fold(f64::INFINITY, f64::min);
        let tol = 1e-4 * size;
        let at = |k: &str| format!("{}.{k}", j.origin);
        let places = format!("anchor1 is at {p1:?} and anchor2 at {p2:?} in the world");
        match &j.kind {
            JointKind::Fixed | JointKind::Revolute { .. } | JointKind::Spherical => {
                let gap = norm(&d);
                if gap > tol {
                    return self.err(
                        &at("anchor2"),
                        format!(
                            "the anchors are {gap:.3e} apart at the start ({places}): the joint would pull the bodies together; put the anchors on the same point"
                        ),
                    );
                }
            }
            JointKind::Prismatic { axis, limits } => {
                let along: f64 = d.iter().zip(axis).map(|(a, b)| a * b).sum();
                let off: Vec<f64> = d.iter().zip(axis).map(|(x, a)| x - along * a).collect();
                let gap = norm(&off);
                if gap > tol {
                    return self.err(
                        &at("anchor2"),
                        format!(
                            "the anchors are {gap:.3e} apart across the axis at the start ({places}): the joint would pull the bodies onto its axis"
                        ),
                    );
                }
                if let Some([lo, hi]) = limits
                    && !(along >= lo - tol && along <= hi + tol)
                {
                    return self.err(
                        &at("limits"),
                        format!(
                            "the anchors start {along} apart along the axis, outside [{lo}, {hi}] ({places})"
                        ),
                    );
                }
            }
            JointKind::Rope { max_distance } => {
                let gap = norm(&d);
                if gap > max_distance + tol {
                    return self.err(
                        &at("max_distance"),
                        format!(
                            "the anchors start {gap} apart, more than the rope's {max_distance} ({places}): the rope would snap them together"
                        ),
                    );
                }
            }
        }
        Ok(())
    }
}
