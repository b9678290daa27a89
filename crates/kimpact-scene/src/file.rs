//! The file as written: serde structs with every key optional, so that a
//! missing key is reported by the validator with its path.

use std::collections::BTreeMap;
use std::fmt;

use kimpact::LawParams;
use serde::Deserialize;

use crate::{CombineRule, FixedPartner};

/// The whole scene file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// One line: what the scene is for.
    pub description: Option<String>,
    /// 2 or 3.
    pub dim: Option<u32>,
    /// `"f32"` (default) or `"f64"`.
    pub precision: Option<String>,
    /// Time step in seconds (default 1/60).
    pub dt: Option<f64>,
    /// Number of steps.
    pub steps: Option<u64>,
    /// Gravity vector (default zero).
    pub gravity: Option<Vec<f64>>,
    /// `"native"`, `"restitution"`, `"impulse"` or `"exact"` (default).
    pub mode: Option<String>,
    /// The law's parameters.
    pub law: Option<LawFile>,
    /// Named materials (law parameters per body), by name.
    pub materials: Option<BTreeMap<String, MaterialFile>>,
    /// The bodies, listed one by one.
    pub bodies: Option<Vec<BodyFile>>,
    /// Grids of bodies, appended after `bodies`.
    pub generators: Option<Vec<GeneratorFile>>,
    /// Joints between two bodies, or a body and the world.
    pub joints: Option<Vec<JointFile>>,
    /// What the scene calls for: `gravity`, `dissipation`, `friction`,
    /// `spin`, `fixed_walls`.
    pub effects: Option<Vec<String>>,
    /// Whether the command chooses CCD for the bodies that do not say
    /// (default false: rapier's default, no CCD).
    pub auto_ccd: Option<bool>,
    /// The law modes' rebound cut-off in m/s (kimpact's
    /// `ResolverConfig::rebound_cutoff`; default none).
    pub rebound_cutoff: Option<f64>,
    /// How pictures are drawn.
    pub view: Option<ViewFile>,
}

/// The `law` table: the core's [`LawParams`] as written, every key
/// optional, its policy read by name in every format (RON would otherwise
/// want an identifier, `OwnMass`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LawFile {
    /// d̃ ≥ 0 (default 0, elastic).
    pub dissipation: Option<f64>,
    /// d̃ against fixed bodies (default: same as `dissipation`).
    pub wall_dissipation: Option<f64>,
    /// The restitution of two equal masses meeting head-on, instead of
    /// `dissipation` ([`LawParams::from_restitution`]).
    pub restitution: Option<f64>,
    /// The restitution of a head-on impact on a fixed body, instead of
    /// `wall_dissipation` (default: `restitution`).
    pub wall_restitution: Option<f64>,
    /// `"own_mass"` (default) or `"literal"`.
    #[serde(default, deserialize_with = "by_name")]
    pub fixed_partner: Option<FixedPartner>,
}

impl LawFile {
    /// The parameters written as d̃, defaults filled in (not checked yet;
    /// `restitution` and `wall_restitution` are converted by the
    /// validator, which checks them).
    pub fn params(&self) -> LawParams<f64> {
        LawParams {
            dissipation: self.dissipation.unwrap_or(0.0),
            wall_dissipation: self.wall_dissipation,
            fixed_partner: self.fixed_partner.unwrap_or_default(),
        }
    }

    /// Whether the table sets any of the law's constants (d̃, the wall's
    /// d̃, or a restitution).
    pub fn sets_constants(&self) -> bool {
        self.dissipation.is_some()
            || self.wall_dissipation.is_some()
            || self.restitution.is_some()
            || self.wall_restitution.is_some()
    }
}

/// An optional value written as its name (a string in every format),
/// parsed by its `FromStr`: a bad name is an error at its key, with its
/// line and column.
fn by_name<'de, D, T>(de: D) -> Result<Option<T>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: std::str::FromStr,
    T::Err: fmt::Display,
{
    match Option::<String>::deserialize(de)? {
        None => Ok(None),
        Some(name) => name.parse().map(Some).map_err(serde::de::Error::custom),
    }
}

/// One entry of `materials`: the law's parameters for the bodies that
/// name it.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// d̃ ≥ 0 against other law bodies (default 0, elastic).
    pub dissipation: Option<f64>,
    /// d̃ against fixed bodies (default: same as `dissipation`).
    pub wall_dissipation: Option<f64>,
    /// The restitution of two equal masses meeting head-on, instead of
    /// `dissipation` ([`LawParams::from_restitution`]).
    pub restitution: Option<f64>,
    /// The restitution of a head-on impact on a fixed body, instead of
    /// `wall_dissipation` (default: `restitution`).
    pub wall_restitution: Option<f64>,
    /// How two materials combine (default `"average"`).
    #[serde(default, deserialize_with = "by_name")]
    pub combine: Option<CombineRule>,
    /// Coulomb's coefficient μ ≥ 0 at the impacts the law resolves (with
    /// the `friction` effect; default 0, none).
    pub impact_friction: Option<f64>,
    /// The tangential restitution β in `[−1, 1]` at those impacts (default
    /// 0 when `impact_friction` is written: a sticking impact stops the
    /// contact points' tangential velocity).
    pub tangential_restitution: Option<f64>,
}

/// One entry of `bodies` (or a generator's `body` template).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyFile {
    /// A label for messages and pictures.
    pub name: Option<String>,
    /// `"ball"`, `"box"`, `"capsule"` or `"convex"`.
    pub shape: Option<String>,
    /// Ball and capsule radius.
    pub radius: Option<f64>,
    /// Box half extents (one per dimension).
    pub half_extents: Option<Vec<f64>>,
    /// Capsule: half the distance between its two end centres, along the
    /// body's local y axis.
    pub half_height: Option<f64>,
    /// Convex shape: points in the body's frame (`dim` components each),
    /// whose convex hull is the shape.
    pub points: Option<Vec<Vec<f64>>>,
    /// Centre position (the body's origin).
    pub position: Option<Vec<f64>>,
    /// Initial velocity (default zero).
    pub velocity: Option<Vec<f64>>,
    /// Initial orientation: 2D an angle in radians, 3D a rotation vector
    /// (axis times angle). Default none.
    pub rotation: Option<Angular>,
    /// Initial angular velocity in rad/s: 2D a number, 3D a vector (world
    /// frame). Default zero.
    pub angular_velocity: Option<Angular>,
    /// Mass (required for bodies that are not fixed).
    pub mass: Option<f64>,
    /// Fixed (immovable) body (default false).
    pub fixed: Option<bool>,
    /// rapier's restitution coefficient (default 0); when written, also
    /// the law's for this body if nothing else sets it (see
    /// `docs/scenes.md`, "Restitution and the law").
    pub restitution: Option<f64>,
    /// rapier's combine rule for the restitution (default `"average"`).
    #[serde(default, deserialize_with = "by_name")]
    pub restitution_combine: Option<CombineRule>,
    /// rapier's friction coefficient (default 0).
    pub friction: Option<f64>,
    /// Whether the body follows kimpact's law (default true for balls that
    /// are not fixed).
    pub law: Option<bool>,
    /// Continuous collision detection (default: none, or the command's
    /// choice with `auto_ccd`).
    pub ccd: Option<bool>,
    /// rapier's `allow_fast_rotation`: the body may turn more than a
    /// quarter turn per step (default false: rapier caps its angular
    /// speed at π/4 per step).
    pub allow_fast_rotation: Option<bool>,
    /// The name of one of the scene's `materials` (default: none, the
    /// scene's `law`).
    pub material: Option<String>,
}

/// One entry of `generators`: a grid of bodies.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorFile {
    /// Centre of the first body.
    pub origin: Option<Vec<f64>>,
    /// Bodies along each axis.
    pub count: Option<Vec<u64>>,
    /// Distance between neighbouring centres along each axis.
    pub spacing: Option<Vec<f64>>,
    /// The template of every body (without `position`).
    pub body: Option<BodyFile>,
    /// Masses used in turn (overrides the template's `mass`).
    pub masses: Option<Vec<f64>>,
    /// Radii used in turn (balls; overrides the template's `radius`).
    pub radii: Option<Vec<f64>>,
    /// Material names used in turn (overrides the template's `material`).
    pub materials: Option<Vec<String>>,
    /// A random velocity of this speed is added to each body.
    pub speed: Option<f64>,
    /// Seed of the random directions (default 1): `rand`'s
    /// `Xoshiro256PlusPlus::seed_from_u64`.
    pub seed: Option<u64>,
}

/// One entry of `joints`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointFile {
    /// `"fixed"`, `"revolute"`, `"spherical"` (3D), `"prismatic"` or
    /// `"rope"`.
    pub kind: Option<String>,
    /// The first body: its index in the scene's bodies, its `name`, or
    /// `"world"`.
    pub body1: Option<BodyRef>,
    /// The second body, written as `body1`.
    pub body2: Option<BodyRef>,
    /// The joint's point on the first body, in its own frame (the world's
    /// frame for `"world"`); default its centre.
    pub anchor1: Option<Vec<f64>>,
    /// The joint's point on the second body.
    pub anchor2: Option<Vec<f64>>,
    /// 3D revolute: the hinge axis; prismatic: the axis of sliding.
    pub axis: Option<Vec<f64>>,
    /// Revolute (angles, radians) and prismatic (distances): `[min, max]`.
    pub limits: Option<Vec<f64>>,
    /// Rope: the longest distance between the anchors.
    pub max_distance: Option<f64>,
    /// Whether the two bodies still collide (default true).
    pub contacts_enabled: Option<bool>,
}

/// A body named in a joint: an index, a name, or `"world"`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BodyRef {
    /// The index in the scene's bodies (`bodies`, then the generators').
    Index(u64),
    /// A body's `name`, or `"world"`.
    Name(String),
}

impl<'de> Deserialize<'de> for BodyRef {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = BodyRef;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a body index (an integer >= 0), a body name or \"world\"")
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<BodyRef, E> {
                Ok(BodyRef::Index(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<BodyRef, E> {
                u64::try_from(v)
                    .map(BodyRef::Index)
                    .map_err(|_| E::invalid_value(serde::de::Unexpected::Signed(v), &self))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<BodyRef, E> {
                Ok(BodyRef::Name(v.to_owned()))
            }
        }
        de.deserialize_any(Visitor)
    }
}

/// A rotation or an angular velocity as written: a number (2D) or a list
/// of numbers (3D).
#[derive(Debug, Clone, PartialEq)]
pub enum Angular {
    /// A 2D angle or angular velocity.
    Scalar(f64),
    /// A 3D rotation vector or angular velocity.
    Vector(Vec<f64>),
}

impl<'de> Deserialize<'de> for Angular {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = Angular;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number (2D) or a list of 3 numbers (3D)")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Angular, E> {
                Ok(Angular::Scalar(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Angular, E> {
                Ok(Angular::Scalar(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Angular, E> {
                Ok(Angular::Scalar(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Angular, A::Error> {
                let mut out = Vec::new();
                while let Some(x) = seq.next_element::<f64>()? {
                    out.push(x);
                }
                Ok(Angular::Vector(out))
            }
        }
        de.deserialize_any(Visitor)
    }
}

/// The `view` table.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewFile {
    /// 3D: the projection plane, `"xy"` (default), `"xz"` or `"zy"`.
    pub axes: Option<String>,
    /// Times of the pictures, in seconds.
    pub times: Option<Vec<f64>>,
    /// Lower corner of the picture (view-plane coordinates).
    pub min: Option<Vec<f64>>,
    /// Upper corner of the picture.
    pub max: Option<Vec<f64>>,
}
