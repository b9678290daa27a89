//! Validation of a parsed scene into a [`Scene`].

use std::collections::BTreeSet;

use kimpact::LawParams;

use crate::check::{Checker, Written};
use crate::derived::law_dissipates;
use crate::overlap::check_overlaps;
use crate::{
    Body, CombineRule, Effect, FixedPartner, JointEnd, LawFile, MAX_BODIES, MAX_STEPS, Material,
    MaterialFile, Mode, Precision, Scene, SceneError, SceneFile, Shape, View,
};

/// Validate a parsed scene.
///
/// # Errors
/// A [`SceneError`] naming `file` and the field.
pub fn validate(raw: SceneFile, file: &str, name: &str) -> Result<Scene, SceneError> {
    let mut c = Checker {
        file,
        dim: 0,
        precision: Precision::F32,
        materials: Vec::new(),
    };
    let dim = match raw.dim {
        Some(d @ (2 | 3)) => d as usize,
        Some(d) => return c.err("dim", format!("must be 2 or 3, got {d}")),
        None => return c.err("dim", "missing: 2 or 3"),
    };
    c.dim = dim;
    let precision = match raw.precision.as_deref() {
        None => Precision::F32,
        Some(p) => match p.parse::<Precision>() {
            Ok(p) => p,
            Err(e) => return c.err("precision", e.to_string()),
        },
    };
    c.precision = precision;
    let dt = c.positive("dt", raw.dt.unwrap_or(1.0 / 60.0))?;
    let rebound_cutoff = match raw.rebound_cutoff {
        Some(v) => Some(c.non_negative("rebound_cutoff", v)?),
        None => None,
    };
    let steps = match raw.steps {
        Some(s) if (1..=MAX_STEPS).contains(&s) => s,
        Some(s) => {
            return c.err(
                "steps",
                format!("must be between 1 and {MAX_STEPS}, got {s}"),
            );
        }
        None => return c.err("steps", "missing: the number of steps"),
    };
    let gravity = match &raw.gravity {
        Some(g) => c.vector("gravity", g)?,
        None => vec![0.0; dim],
    };
    let mode = match raw.mode.as_deref() {
        None => Mode::Exact,
        Some(m) => match m.parse::<Mode>() {
            Ok(m) => m,
            Err(e) => return c.err("mode", e.to_string()),
        },
    };
    let law_file = raw.law.clone().unwrap_or_default();
    let fixed_partner = law_file.fixed_partner.unwrap_or_default();
    let constants = c.constants("law", written_law(&law_file), fixed_partner)?;
    let law = LawParams {
        dissipation: constants.dissipation,
        wall_dissipation: constants.wall_dissipation,
        fixed_partner,
    };
    c.law("law", law)?;
    let mut materials = Vec::new();
    for (name, m) in raw.materials.iter().flatten() {
        let at = format!("materials.{name}");
        if name.is_empty() {
            return c.err("materials", "a material needs a non-empty name");
        }
        let k = c.constants(&at, written_material(m), fixed_partner)?;
        let wall_dissipation = k.wall_dissipation.unwrap_or(k.dissipation);
        c.law(
            &at,
            LawParams {
                dissipation: k.dissipation,
                wall_dissipation: Some(wall_dissipation),
                fixed_partner: FixedPartner::default(),
            },
        )?;
        let (impact_friction, tangential_restitution) =
            c.impact_friction(&at, m.impact_friction, m.tangential_restitution)?;
        materials.push(Material {
            name: name.clone(),
            dissipation: k.dissipation,
            wall_dissipation,
            combine: m.combine.unwrap_or_default(),
            restitution: k.restitution,
            named: true,
            impact_friction,
            tangential_restitution,
        });
    }
    // A BTreeMap iterates in name order: the checker's binary search holds.
    c.materials = materials.iter().map(|m| m.name.clone()).collect();

    // Each body, and whether its `restitution` was written.
    let mut bodies = Vec::new();
    let mut written = Vec::new();
    for (i, b) in raw.bodies.iter().flatten().enumerate() {
        let at = format!("bodies[{i}]");
        let (body, restitution) = c.body(&at, &at, b, false)?;
        bodies.push(body);
        written.push(restitution);
    }
    let first = bodies.len();
    let mut generated = Vec::new();
    for (gi, g) in raw.generators.iter().flatten().enumerate() {
        let restitution = c.generator(gi, g, first, &mut generated)?;
        written.resize(first + generated.len(), restitution);
        if first + generated.len() > MAX_BODIES {
            return c.err(
                &format!("generators[{gi}]"),
                format!("the scene has more than {MAX_BODIES} bodies"),
            );
        }
    }
    bodies.append(&mut generated);
    if !law_file.sets_constants() {
        restitution_materials(&c, &mut bodies, &written, &mut materials, fixed_partner)?;
    }
    if bodies.is_empty() {
        return c.err(
            "bodies",
            "missing: the scene has no bodies (give `bodies` or `generators`)",
        );
    }
    if bodies.iter().all(|b| b.fixed) {
        return c.err("bodies", "every body is fixed: nothing would move");
    }

    let joints = c.joints(raw.joints.as_deref().unwrap_or_default(), &bodies)?;

    let mut warnings = Vec::new();
    for (i, m) in materials.iter().enumerate() {
        if m.named && !bodies.iter().any(|b| b.material == Some(i)) {
            warnings.push(format!("{file}: materials.{}: no body uses it", m.name));
        }
    }
    let dissipates = law_dissipates(&law)
        || bodies
            .iter()
            .filter_map(|b| b.material)
            .any(|i| materials[i].dissipates());
    // The first material a body uses that gives impact friction.
    let rough = bodies
        .iter()
        .filter_map(|b| b.material)
        .find(|i| materials[*i].has_impact_friction())
        .map(|i| &materials[i].name);
    let effects = match &raw.effects {
        Some(list) => {
            let mut set = BTreeSet::new();
            for (i, e) in list.iter().enumerate() {
                match Effect::ALL.into_iter().find(|x| x.name() == e) {
                    Some(x) => {
                        set.insert(x);
                    }
                    None => {
                        return c.err(
                            &format!("effects[{i}]"),
                            format!("unknown effect {e:?}: expected one of gravity, dissipation, friction, spin, fixed_walls"),
                        );
                    }
                }
            }
            if !set.contains(&Effect::FixedWalls)
                && let Some(b) = bodies.iter().find(|b| b.fixed)
            {
                return c.err(
                    "effects",
                    format!("{} is fixed but \"fixed_walls\" is not listed", b.origin),
                );
            }
            if !set.contains(&Effect::Gravity) && gravity.iter().any(|g| *g != 0.0) {
                warnings.push(format!(
                    "{file}: gravity: ignored, \"gravity\" is not in `effects`"
                ));
            }
            if !set.contains(&Effect::Dissipation) && dissipates {
                warnings.push(format!("{file}: law.dissipation, materials: ignored (elastic law), \"dissipation\" is not in `effects`"));
            }
            if !set.contains(&Effect::Spin)
                && bodies
                    .iter()
                    .any(|b| b.angular_velocity.iter().any(|w| *w != 0.0))
            {
                warnings.push(format!(
                    "{file}: angular_velocity: ignored (rotations locked), \"spin\" is not in `effects`"
                ));
            }
            if !set.contains(&Effect::Friction) && bodies.iter().any(|b| b.friction > 0.0) {
                warnings.push(format!(
                    "{file}: friction: ignored (zero friction), \"friction\" is not in `effects`"
                ));
            }
            if let Some(name) = rough {
                if !set.contains(&Effect::Friction) {
                    warnings.push(format!(
                        "{file}: materials.{name}.impact_friction: ignored (frictionless impacts), \"friction\" is not in `effects`"
                    ));
                } else if !set.contains(&Effect::Spin) {
                    return c.err(
                        "effects",
                        format!(
                            "materials.{name} gives impact friction and \"friction\" is listed, but \"spin\" is not: impact friction turns the bodies, so \"spin\" must be on too (list it, or drop \"friction\")"
                        ),
                    );
                }
            }
            set
        }
        None => {
            let mut set = BTreeSet::new();
            if gravity.iter().any(|g| *g != 0.0) {
                set.insert(Effect::Gravity);
            }
            if dissipates {
                set.insert(Effect::Dissipation);
            }
            if bodies.iter().any(|b| b.friction > 0.0) || rough.is_some() {
                set.insert(Effect::Friction);
            }
            if bodies.iter().any(|b| b.fixed) {
                set.insert(Effect::FixedWalls);
            }
            // rapier never locks rotations: spin is on wherever something
            // could turn a body (friction, a shape that is not a ball, a
            // joint) or a body turns from the start.
            let turns = bodies.iter().any(|b| {
                !b.fixed
                    && (!matches!(b.shape, Shape::Ball { .. })
                        || b.angular_velocity.iter().any(|w| *w != 0.0))
            });
            if set.contains(&Effect::Friction) || turns || !joints.is_empty() {
                set.insert(Effect::Spin);
            }
            set
        }
    };

    let vf = raw.view.clone().unwrap_or_default();
    let (axes, axes_name) = match (dim, vf.axes.as_deref()) {
        (_, None | Some("xy")) => ([0, 1], "xy"),
        (3, Some("xz")) => ([0, 2], "xz"),
        (3, Some("zy")) => ([2, 1], "zy"),
        (2, Some(a)) => {
            return c.err(
                "view.axes",
                format!("a 2D scene is drawn in \"xy\", got {a:?}"),
            );
        }
        (_, Some(a)) => {
            return c.err(
                "view.axes",
                format!("must be \"xy\", \"xz\" or \"zy\", got {a:?}"),
            );
        }
    };
    let times = match &vf.times {
        Some(t) if t.is_empty() || t.len() > 12 => {
            return c.err(
                "view.times",
                format!("must list 1 to 12 times, got {}", t.len()),
            );
        }
        Some(t) => {
            for (i, x) in t.iter().enumerate() {
                c.non_negative(&format!("view.times[{i}]"), *x)?;
            }
            Some(t.clone())
        }
        None => None,
    };
    let bounds = match (&vf.min, &vf.max) {
        (None, None) => None,
        (Some(lo), Some(hi)) => {
            let two = Checker {
                file,
                dim: 2,
                precision,
                materials: Vec::new(),
            };
            let lo = two.vector("view.min", lo)?;
            let hi = two.vector("view.max", hi)?;
            if !(hi[0] > lo[0] && hi[1] > lo[1]) {
                return c.err(
                    "view.max",
                    "must be greater than view.min in both components",
                );
            }
            Some(([lo[0], lo[1]], [hi[0], hi[1]]))
        }
        (Some(_), None) => return c.err("view.max", "missing: give both view.min and view.max"),
        (None, Some(_)) => return c.err("view.min", "missing: give both view.min and view.max"),
    };
    let view = View {
        axes,
        axes_name: axes_name.to_owned(),
        times,
        bounds,
    };

    let exempt: BTreeSet<(usize, usize)> = joints
        .iter()
        .filter(|j| !j.contacts_enabled)
        .filter_map(|j| match (j.body1, j.body2) {
            (JointEnd::Body(a), JointEnd::Body(b)) => Some((a.min(b), a.max(b))),
            _ => None,
        })
        .collect();
    check_overlaps(&c, &bodies, &exempt)?;

    Ok(Scene {
        file: file.to_owned(),
        name: name.to_owned(),
        description: raw.description,
        dim,
        precision,
        dt,
        steps,
        gravity,
        mode,
        law,
        materials,
        bodies,
        joints,
        effects,
        auto_ccd: raw.auto_ccd.unwrap_or(false),
        rebound_cutoff,
        view,
        warnings,
    })
}

/// The law table's constants as written.
fn written_law(l: &LawFile) -> Written {
    Written {
        dissipation: l.dissipation,
        wall_dissipation: l.wall_dissipation,
        restitution: l.restitution,
        wall_restitution: l.wall_restitution,
    }
}

/// A material's constants as written.
fn written_material(m: &MaterialFile) -> Written {
    Written {
        dissipation: m.dissipation,
        wall_dissipation: m.wall_dissipation,
        restitution: m.restitution,
        wall_restitution: m.wall_restitution,
    }
}

/// The scene's `law` sets no constant: each body that follows the law and
/// has no `material` but a written `restitution` `e` gets the material `e`
/// stands for, [`LawParams::from_restitution`]`(e, e)` combined by
/// `"average"`, shared by the bodies with the same `e`: it bounces off fixed
/// bodies with `e` (head-on), and two such bodies of equal mass meet
/// head-on with `sqrt((e₁² + e₂²)/2)`.
fn restitution_materials(
    c: &Checker<'_>,
    bodies: &mut [Body],
    written: &[bool],
    materials: &mut Vec<Material>,
    fixed_partner: FixedPartner,
) -> Result<(), SceneError> {
    for (b, written) in bodies.iter_mut().zip(written) {
        if !*written || b.material.is_some() || !b.law || b.fixed {
            continue;
        }
        let e = b.restitution;
        if e > 1.0 {
            return c.err(
                &format!("{}.restitution", b.origin),
                format!(
                    "{e} would be the law's restitution too (the scene's `law` sets no constant and the body has no `material`), and the law only takes energy away: give a restitution in [0, 1], or set the law's constants in `law` (a body's restitution is then rapier's only)"
                ),
            );
        }
        let name = format!("restitution {e}");
        if let Some(i) = materials.iter().position(|m| !m.named && m.name == name) {
            b.material = Some(i);
            continue;
        }
        let w = Written {
            restitution: Some(e),
            ..Written::default()
        };
        let k = c.constants(&b.origin, w, fixed_partner)?;
        materials.push(Material {
            name,
            dissipation: k.dissipation,
            wall_dissipation: k.wall_dissipation.unwrap_or(k.dissipation),
            combine: CombineRule::Average,
            restitution: k.restitution,
            named: false,
            impact_friction: 0.0,
            tangential_restitution: Material::NO_TANGENTIAL_RESTITUTION,
        });
        b.material = Some(materials.len() - 1);
    }
    Ok(())
}
