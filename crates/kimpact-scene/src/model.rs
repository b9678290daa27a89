//! The validated scene's types: what the simulation builds from.

use std::collections::BTreeSet;
use std::fmt;

use kimpact::LawParams;

use crate::{Mode, Precision, Shape, rotate};

/// The most bodies a scene may have.
pub const MAX_BODIES: usize = 200_000;

/// The most steps a scene may ask for.
pub const MAX_STEPS: u64 = 100_000_000;

/// A scene that failed to load.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The file, as given.
    pub file: String,
    /// Line and column (1-based) for parse errors.
    pub location: Option<(usize, usize)>,
    /// The field (`bodies[3].radius`), empty when the whole file is at fault.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some((line, col)) = self.location {
            write!(f, ":{line}:{col}")?;
        }
        if self.field.is_empty() {
            write!(f, ": {}", self.message)
        } else {
            write!(f, ": {}: {}", self.field, self.message)
        }
    }
}

impl std::error::Error for SceneError {}

/// How the constants of two materials combine for a pair: rapier's
/// `CoefficientCombineRule`, whose rule wins when the two differ
/// (`geometric_mean > clamped_sum > max > multiply > min > average`).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CombineRule {
    /// `(a + b) / 2`.
    #[default]
    Average,
    /// The smaller.
    Min,
    /// `a b`.
    Multiply,
    /// The larger.
    Max,
    /// `a + b`, clamped to `[0, 1]`.
    ClampedSum,
    /// `sqrt(a b)`.
    GeometricMean,
}

impl CombineRule {
    /// Every rule, lowest priority first.
    pub const ALL: [CombineRule; 6] = [
        CombineRule::Average,
        CombineRule::Min,
        CombineRule::Multiply,
        CombineRule::Max,
        CombineRule::ClampedSum,
        CombineRule::GeometricMean,
    ];

    /// The rule's name in scene files.
    pub fn name(self) -> &'static str {
        match self {
            CombineRule::Average => "average",
            CombineRule::Min => "min",
            CombineRule::Multiply => "multiply",
            CombineRule::Max => "max",
            CombineRule::ClampedSum => "clamped_sum",
            CombineRule::GeometricMean => "geometric_mean",
        }
    }
}

/// An unknown combine rule name (the name given).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown combine rule {0:?}: expected one of \"average\", \"min\", \"multiply\", \"max\", \"clamped_sum\", \"geometric_mean\""
)]
pub struct ParseCombineRuleError(pub String);

impl std::str::FromStr for CombineRule {
    type Err = ParseCombineRuleError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        CombineRule::ALL
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| ParseCombineRuleError(s.to_owned()))
    }
}

/// A validated body.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Where it came from (`bodies[3]`, `generators[0][17]`), for messages.
    pub origin: String,
    /// Label.
    pub name: Option<String>,
    /// Shape.
    pub shape: Shape,
    /// Position (length `dim`): the body's origin, where its shape's own
    /// frame sits.
    pub position: Vec<f64>,
    /// Velocity (length `dim`).
    pub velocity: Vec<f64>,
    /// Orientation: 2D `[angle]` in radians, 3D a rotation vector `[x, y,
    /// z]` (axis times angle); zero when not written.
    pub rotation: Vec<f64>,
    /// Angular velocity in rad/s: 2D `[ω]`, 3D `[x, y, z]` (world frame).
    pub angular_velocity: Vec<f64>,
    /// Mass (`None` for fixed bodies).
    pub mass: Option<f64>,
    /// Fixed body.
    pub fixed: bool,
    /// rapier's restitution coefficient.
    pub restitution: f64,
    /// rapier's combine rule for the restitution.
    pub restitution_combine: CombineRule,
    /// rapier's friction coefficient (as written; zeroed by the simulation
    /// when `friction` is not an active effect).
    pub friction: f64,
    /// Follows kimpact's law.
    pub law: bool,
    /// CCD as written (`None`: automatic).
    pub ccd: Option<bool>,
    /// rapier's `allow_fast_rotation` as written (default false: rapier
    /// caps the angular speed at π/4 per step).
    pub allow_fast_rotation: bool,
    /// Index of its material in [`Scene::materials`] (`None`: the scene's
    /// law): a named one, or the one its written `restitution` stands for
    /// (see [`Material::named`]).
    pub material: Option<usize>,
}

impl Body {
    /// Whether the body starts turned (a non-zero `rotation`).
    pub fn rotated(&self) -> bool {
        self.rotation.iter().any(|x| *x != 0.0)
    }

    /// The bounding box of the shape as the body starts (at its position,
    /// turned by its rotation): lower and upper corners.
    pub fn aabb(&self, dim: usize) -> (Vec<f64>, Vec<f64>) {
        let mut lo = self.position.clone();
        let mut hi = self.position.clone();
        let mut grow = |v: &[f64], pad: f64| {
            for k in 0..dim {
                lo[k] = lo[k].min(self.position[k] + v[k] - pad);
                hi[k] = hi[k].max(self.position[k] + v[k] + pad);
            }
        };
        match &self.shape {
            Shape::Ball { radius } => grow(&vec![0.0; dim], *radius),
            Shape::Capsule {
                half_height,
                radius,
            } => {
                let mut axis = vec![0.0; dim];
                axis[1] = *half_height;
                let end = rotate(&self.rotation, &axis);
                let other: Vec<f64> = end.iter().map(|x| -x).collect();
                grow(&end, *radius);
                grow(&other, *radius);
            }
            shape => {
                for p in shape.outline(dim) {
                    grow(&rotate(&self.rotation, &p), 0.0);
                }
            }
        }
        (lo, hi)
    }

    /// Half extents of a box centred on the body's position that holds the
    /// shape as the body starts (turned by its rotation).
    pub fn half_box(&self, dim: usize) -> Vec<f64> {
        let (lo, hi) = self.aabb(dim);
        (0..dim)
            .map(|k| (self.position[k] - lo[k]).max(hi[k] - self.position[k]))
            .collect()
    }

    /// A point given in the body's frame, in the world as the body starts.
    pub fn to_world(&self, local: &[f64]) -> Vec<f64> {
        self.position
            .iter()
            .zip(rotate(&self.rotation, local))
            .map(|(p, x)| p + x)
            .collect()
    }
}

/// A validated material: constants checked in the scene's precision, as the
/// adapter's `Material::new` checks them.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Its name in `materials`, or `restitution E` for the material a
    /// body's own `restitution` stands for.
    pub name: String,
    /// d̃ against other law bodies.
    pub dissipation: f64,
    /// d̃ against fixed bodies.
    pub wall_dissipation: f64,
    /// The combine rule.
    pub combine: CombineRule,
    /// The restitutions of the two reference impacts it was made from
    /// (`[ball, wall]`, [`kimpact::LawParams::from_restitution`]), or
    /// `None` when one constant or both were written as d̃.
    pub restitution: Option<[f64; 2]>,
    /// Listed in the scene's `materials` (false: made from a body's
    /// `restitution`).
    pub named: bool,
    /// Coulomb's coefficient μ ≥ 0 at the impact (0 when not written).
    pub impact_friction: f64,
    /// The tangential restitution β in `[−1, 1]`: as written; 0 when only
    /// `impact_friction` is written; −1 (the adapter's material without
    /// impact friction) when neither is.
    pub tangential_restitution: f64,
}

impl Material {
    /// β of a material that writes neither `impact_friction` nor
    /// `tangential_restitution` (the adapter's material without impact
    /// friction: the contact points' tangential velocity left as it is).
    pub const NO_TANGENTIAL_RESTITUTION: f64 = -1.0;

    /// Whether the material dissipates (d̃ or the wall's d̃ positive).
    pub fn dissipates(&self) -> bool {
        self.dissipation > 0.0 || self.wall_dissipation > 0.0
    }

    /// Whether the material gives impact friction (μ positive).
    pub fn has_impact_friction(&self) -> bool {
        self.impact_friction > 0.0
    }
}

/// An effect a scene can call for.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Effect {
    /// The scene's gravity vector.
    Gravity,
    /// The law's dissipation (d̃ > 0 or wall d̃ > 0).
    Dissipation,
    /// The bodies' friction coefficients, and the impact friction of
    /// their materials (which needs [`Effect::Spin`] too).
    Friction,
    /// Rotation of the bodies (rolling, spin); locked otherwise.
    Spin,
    /// Fixed bodies (walls, cushions, pegs, floors).
    FixedWalls,
}

impl Effect {
    /// Every effect.
    pub const ALL: [Effect; 5] = [
        Effect::Gravity,
        Effect::Dissipation,
        Effect::Friction,
        Effect::Spin,
        Effect::FixedWalls,
    ];

    /// The name used in scene files and reports.
    pub fn name(self) -> &'static str {
        match self {
            Effect::Gravity => "gravity",
            Effect::Dissipation => "dissipation",
            Effect::Friction => "friction",
            Effect::Spin => "spin",
            Effect::FixedWalls => "fixed_walls",
        }
    }
}

/// One end of a joint.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum JointEnd {
    /// The world (rapier: a fixed body without a collider).
    World,
    /// A body, by its index in [`Scene::bodies`].
    Body(usize),
}

/// What a joint holds.
#[derive(Clone, Debug, PartialEq)]
pub enum JointKind {
    /// Every relative motion locked (rapier's `FixedJointBuilder`).
    Fixed,
    /// A hinge: the anchors together, turning about one axis
    /// (`RevoluteJointBuilder`).
    Revolute {
        /// 3D: the hinge axis, unit length, in both bodies' frames (2D:
        /// `None`, the axis is z).
        axis: Option<Vec<f64>>,
        /// The angle's `[min, max]` in radians, if limited.
        limits: Option<[f64; 2]>,
    },
    /// A ball joint (3D): the anchors together, turning freely
    /// (`SphericalJointBuilder`).
    Spherical,
    /// Sliding along one axis (`PrismaticJointBuilder`).
    Prismatic {
        /// The axis, unit length, in both bodies' frames.
        axis: Vec<f64>,
        /// The distance's `[min, max]` along the axis, if limited.
        limits: Option<[f64; 2]>,
    },
    /// The anchors at most `max_distance` apart (`RopeJointBuilder`).
    Rope {
        /// The rope's length.
        max_distance: f64,
    },
}

impl JointKind {
    /// The kind's name in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            JointKind::Fixed => "fixed",
            JointKind::Revolute { .. } => "revolute",
            JointKind::Spherical => "spherical",
            JointKind::Prismatic { .. } => "prismatic",
            JointKind::Rope { .. } => "rope",
        }
    }
}

/// A validated joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Where it came from (`joints[2]`), for messages.
    pub origin: String,
    /// What it holds.
    pub kind: JointKind,
    /// The first body.
    pub body1: JointEnd,
    /// The second body.
    pub body2: JointEnd,
    /// The anchor on the first body, in its frame (the world's for
    /// [`JointEnd::World`]).
    pub anchor1: Vec<f64>,
    /// The anchor on the second body.
    pub anchor2: Vec<f64>,
    /// Whether the two bodies collide.
    pub contacts_enabled: bool,
}

/// How pictures are drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// The two world axes drawn horizontally and vertically (2D: `[0, 1]`).
    pub axes: [usize; 2],
    /// The axes' names (`"xy"`).
    pub axes_name: String,
    /// Picture times in seconds (`None`: five evenly spaced).
    pub times: Option<Vec<f64>>,
    /// Picture bounds (`None`: fit the scene).
    pub bounds: Option<([f64; 2], [f64; 2])>,
}

/// A validated scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The file, as given.
    pub file: String,
    /// The file's stem (`cradle2d`).
    pub name: String,
    /// One line: what the scene is for.
    pub description: Option<String>,
    /// 2 or 3.
    pub dim: usize,
    /// Precision.
    pub precision: Precision,
    /// Time step in seconds.
    pub dt: f64,
    /// Number of steps.
    pub steps: u64,
    /// Gravity as written (length `dim`).
    pub gravity: Vec<f64>,
    /// Mode.
    pub mode: Mode,
    /// The law (checked in the scene's precision).
    pub law: LawParams<f64>,
    /// The scene's `materials` in name order, then the materials that
    /// bodies' own `restitution` stands for.
    pub materials: Vec<Material>,
    /// Every body: `bodies`, then the generators' bodies.
    pub bodies: Vec<Body>,
    /// The joints.
    pub joints: Vec<Joint>,
    /// The effects the scene calls for (listed, or derived when `effects`
    /// is absent).
    pub effects: BTreeSet<Effect>,
    /// Whether the command chooses CCD for the bodies that do not say
    /// (see [`Scene::ccd_flags`]).
    pub auto_ccd: bool,
    /// The law modes' rebound cut-off in m/s, if any (kimpact's
    /// `ResolverConfig::rebound_cutoff`: a pair struck already in a step
    /// and meeting again slower than this waits for the next step).
    pub rebound_cutoff: Option<f64>,
    /// Pictures.
    pub view: View,
    /// Things worth telling the user (values ignored because their effect is
    /// not listed).
    pub warnings: Vec<String>,
}
