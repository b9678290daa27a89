//! Scene files: the serde structs (`*File`), read from `.json`, `.ron` or
//! `.toml`, and their validation into a typed [`Scene`].
//!
//! Every error names the file and the field (`bodies[3].radius: must be > 0,
//! got 0`), with line and column for parse errors. See `docs/scenes.md` for
//! every key.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::Path;

use kimpact::{Law, LawError, LawParams};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use serde::Deserialize;

pub use kimpact::{FixedPartner, Mode, Precision};

/// The file as written: every key optional, so that a missing key is
/// reported by the validator with its path.
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
    /// What the scene calls for: `gravity`, `dissipation`, `friction`,
    /// `spin`, `fixed_walls`.
    pub effects: Option<Vec<String>>,
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
    /// `"own_mass"` (default) or `"literal"`.
    #[serde(default, deserialize_with = "by_name")]
    pub fixed_partner: Option<FixedPartner>,
}

impl LawFile {
    /// The parameters written, defaults filled in (not checked yet).
    pub fn params(&self) -> LawParams<f64> {
        LawParams {
            dissipation: self.dissipation.unwrap_or(0.0),
            wall_dissipation: self.wall_dissipation,
            fixed_partner: self.fixed_partner.unwrap_or_default(),
        }
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
    /// How two materials combine (default `"average"`).
    #[serde(default, deserialize_with = "by_name")]
    pub combine: Option<CombineRule>,
}

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

/// One entry of `bodies` (or a generator's `body` template).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyFile {
    /// A label for messages and pictures.
    pub name: Option<String>,
    /// `"ball"` or `"box"`.
    pub shape: Option<String>,
    /// Ball radius.
    pub radius: Option<f64>,
    /// Box half extents (one per dimension).
    pub half_extents: Option<Vec<f64>>,
    /// Centre position.
    pub position: Option<Vec<f64>>,
    /// Initial velocity (default zero).
    pub velocity: Option<Vec<f64>>,
    /// Mass (required for bodies that are not fixed).
    pub mass: Option<f64>,
    /// Fixed (immovable) body (default false).
    pub fixed: Option<bool>,
    /// rapier's restitution coefficient (default 0).
    pub restitution: Option<f64>,
    /// rapier's friction coefficient (default 0).
    pub friction: Option<f64>,
    /// Whether the body follows kimpact's law (default true for balls that
    /// are not fixed).
    pub law: Option<bool>,
    /// Continuous collision detection (default: automatic).
    pub ccd: Option<bool>,
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

/// A body's shape.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A ball (disk in 2D).
    Ball {
        /// Radius.
        radius: f64,
    },
    /// An axis-aligned box.
    Box {
        /// Half extents, one per dimension.
        half_extents: Vec<f64>,
    },
}

impl Shape {
    /// The smallest half size (radius or smallest half extent).
    pub fn min_size(&self) -> f64 {
        match self {
            Shape::Ball { radius } => *radius,
            Shape::Box { half_extents } => {
                half_extents.iter().copied().fold(f64::INFINITY, f64::min)
            }
        }
    }

    /// Half extents of the axis-aligned bounding box.
    pub fn half_box(&self, dim: usize) -> Vec<f64> {
        match self {
            Shape::Ball { radius } => vec![*radius; dim],
            Shape::Box { half_extents } => half_extents.clone(),
        }
    }

    /// `"ball"` or `"box"`.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Ball { .. } => "ball",
            Shape::Box { .. } => "box",
        }
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
    /// Position (length `dim`).
    pub position: Vec<f64>,
    /// Velocity (length `dim`).
    pub velocity: Vec<f64>,
    /// Mass (`None` for fixed bodies).
    pub mass: Option<f64>,
    /// Fixed body.
    pub fixed: bool,
    /// rapier's restitution coefficient.
    pub restitution: f64,
    /// rapier's friction coefficient (as written; zeroed by the simulation
    /// when `friction` is not an active effect).
    pub friction: f64,
    /// Follows kimpact's law.
    pub law: bool,
    /// CCD as written (`None`: automatic).
    pub ccd: Option<bool>,
    /// Index of its material in [`Scene::materials`] (`None`: the scene's
    /// law).
    pub material: Option<usize>,
}

/// A validated material: constants checked in the scene's precision, as the
/// adapter's `Material::new` checks them.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Its name in `materials`.
    pub name: String,
    /// d̃ against other law bodies.
    pub dissipation: f64,
    /// d̃ against fixed bodies.
    pub wall_dissipation: f64,
    /// The combine rule.
    pub combine: CombineRule,
}

impl Material {
    /// Whether the material dissipates (d̃ or the wall's d̃ positive).
    pub fn dissipates(&self) -> bool {
        self.dissipation > 0.0 || self.wall_dissipation > 0.0
    }
}

/// An effect a scene can call for.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Effect {
    /// The scene's gravity vector.
    Gravity,
    /// The law's dissipation (d̃ > 0 or wall d̃ > 0).
    Dissipation,
    /// The bodies' friction coefficients.
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
    /// The materials that bodies use, in name order.
    pub materials: Vec<Material>,
    /// Every body: `bodies`, then the generators' bodies.
    pub bodies: Vec<Body>,
    /// The effects the scene calls for (listed, or derived when `effects`
    /// is absent).
    pub effects: BTreeSet<Effect>,
    /// Pictures.
    pub view: View,
    /// Things worth telling the user (values ignored because their effect is
    /// not listed).
    pub warnings: Vec<String>,
}

impl Scene {
    /// Whether `effect` is active: called for and present in the scene.
    pub fn active(&self, effect: Effect) -> bool {
        if !self.effects.contains(&effect) {
            return false;
        }
        match effect {
            Effect::Gravity => self.gravity.iter().any(|g| *g != 0.0),
            Effect::Dissipation => {
                law_dissipates(&self.law) || self.materials.iter().any(Material::dissipates)
            }
            Effect::Friction => self.bodies.iter().any(|b| b.friction > 0.0),
            Effect::Spin => self.bodies.iter().any(|b| !b.fixed),
            Effect::FixedWalls => self.bodies.iter().any(|b| b.fixed),
        }
    }

    /// The active effects' names.
    pub fn active_effects(&self) -> Vec<&'static str> {
        Effect::ALL
            .into_iter()
            .filter(|e| self.active(*e))
            .map(Effect::name)
            .collect()
    }

    /// Gravity as simulated (zero unless the effect is active).
    pub fn effective_gravity(&self) -> Vec<f64> {
        if self.active(Effect::Gravity) {
            self.gravity.clone()
        } else {
            vec![0.0; self.dim]
        }
    }

    /// The law as simulated (elastic unless `dissipation` is active).
    pub fn effective_law(&self) -> LawParams<f64> {
        if self.active(Effect::Dissipation) {
            self.law
        } else {
            LawParams {
                dissipation: 0.0,
                wall_dissipation: None,
                ..self.law
            }
        }
    }

    /// Body `i`'s material as simulated: none unless `dissipation` is
    /// active (the elastic law then governs every pair).
    pub fn effective_material(&self, i: usize) -> Option<&Material> {
        if !self.active(Effect::Dissipation) {
            return None;
        }
        self.materials.get(self.bodies[i].material?)
    }

    /// The speed no moving body can exceed (`None` for fixed bodies): the
    /// energy bound `sqrt(2 E / m)`, as fast as if the body held all the
    /// scene's energy, `E` the kinetic energy plus, with gravity, the
    /// potential energy of every body falling across the whole scene
    /// (`Σ m |g| H`, `H` its largest extent). It holds for any sequence of
    /// elastic or dissipative impacts (a light ball trapped by a heavy one
    /// gains far more than twice any initial speed).
    pub fn speed_bounds(&self) -> Vec<Option<f64>> {
        let speed2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
        let kinetic: f64 = self
            .bodies
            .iter()
            .filter_map(|b| b.mass.map(|m| 0.5 * m * speed2(&b.velocity)))
            .sum();
        let g = speed2(&self.effective_gravity()).sqrt();
        let (lo, hi) = self.extent();
        let height = (0..self.dim).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let potential: f64 = g * height * self.bodies.iter().filter_map(|b| b.mass).sum::<f64>();
        let energy = kinetic + potential;
        self.bodies
            .iter()
            .map(|b| match (b.fixed, b.mass) {
                (false, Some(m)) => Some((2.0 * energy / m).sqrt()),
                _ => None,
            })
            .collect()
    }

    /// Which bodies get CCD: as written (`ccd`), or automatically when a
    /// body could move more than its smallest half size in one step at its
    /// [speed bound](Self::speed_bounds). Slow bodies keep CCD cheap:
    /// rapier does time-of-impact work only for CCD bodies that actually
    /// move fast in a step.
    pub fn ccd_flags(&self) -> Vec<bool> {
        self.bodies
            .iter()
            .zip(self.speed_bounds())
            .map(|(b, bound)| match (b.fixed, b.ccd, bound) {
                (true, _, _) | (false, None, None) => false,
                (false, Some(c), _) => c,
                (false, None, Some(v)) => v * self.dt > b.shape.min_size(),
            })
            .collect()
    }

    /// rapier's soft-CCD prediction distance of each body (0: none): the
    /// distance a CCD body can cover in one step at its
    /// [speed bound](Self::speed_bounds). rapier's CCD never sweeps one CCD
    /// body against another; soft CCD also catches such pairs, by predicting
    /// contacts as far ahead as the pair closes in the step (each body's
    /// velocity capped at this distance per step, so the bound caps
    /// nothing). A slow body that a fast one hits later has the same bound,
    /// and the fast one carries the prediction meanwhile. The simulation
    /// uses it in native mode only (see `docs/scenes.md`, "CCD").
    pub fn soft_ccd_predictions(&self) -> Vec<f64> {
        self.ccd_flags()
            .into_iter()
            .zip(self.speed_bounds())
            .map(|(ccd, bound)| match (ccd, bound) {
                (true, Some(v)) => v * self.dt,
                _ => 0.0,
            })
            .collect()
    }

    /// The bounding box of every body at the start.
    pub fn extent(&self) -> (Vec<f64>, Vec<f64>) {
        let mut lo = vec![f64::INFINITY; self.dim];
        let mut hi = vec![f64::NEG_INFINITY; self.dim];
        for b in &self.bodies {
            let h = b.shape.half_box(self.dim);
            for k in 0..self.dim {
                lo[k] = lo[k].min(b.position[k] - h[k]);
                hi[k] = hi[k].max(b.position[k] + h[k]);
            }
        }
        (lo, hi)
    }

    /// The picture times: as written (clamped to the run), or five evenly
    /// spaced from 0 to the end.
    pub fn picture_times(&self, steps: u64) -> Vec<f64> {
        let end = steps as f64 * self.dt;
        match &self.view.times {
            Some(t) => t.iter().map(|t| t.min(end)).collect(),
            None => (0..5).map(|i| end * i as f64 / 4.0).collect(),
        }
    }
}

/// Read and validate a scene file (format from the extension).
///
/// # Errors
/// A [`SceneError`] naming the file and the field.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let file = path.display().to_string();
    let err = |field: &str, message: String| SceneError {
        file: file.clone(),
        location: None,
        field: field.to_owned(),
        message,
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !matches!(ext.as_str(), "json" | "ron" | "toml") {
        return Err(err(
            "",
            format!("unknown scene format {ext:?}: the file name must end in .json, .ron or .toml"),
        ));
    }
    let text =
        std::fs::read_to_string(path).map_err(|e| err("", format!("cannot read the file: {e}")))?;
    let raw = parse(&text, &ext).map_err(|mut e| {
        e.file = file.clone();
        e
    })?;
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_owned();
    validate(raw, &file, &name)
}

/// Parse scene text in `format` (`json`, `ron`, `toml`). The error's `file`
/// is left empty.
///
/// # Errors
/// A [`SceneError`] with the field path and line/column.
pub fn parse(text: &str, format: &str) -> Result<SceneFile, SceneError> {
    let make = |location: Option<(usize, usize)>, field: String, message: String| SceneError {
        file: String::new(),
        location,
        field,
        message,
    };
    let field_of = |p: &serde_path_to_error::Path| {
        let s = p.to_string();
        if s == "." { String::new() } else { s }
    };
    // serde_json reports column 0 for an error at the start of a line
    // (the end of an empty file): locations are 1-based.
    let json_location = |line: usize, column: usize| Some((line, column.max(1)));
    match format {
        "json" => {
            let mut de = serde_json::Deserializer::from_str(text);
            let result: Result<SceneFile, _> = serde_path_to_error::deserialize(&mut de);
            let value = result.map_err(|e| {
                let field = field_of(e.path());
                let inner = e.into_inner();
                let msg = strip_location(&inner.to_string());
                make(json_location(inner.line(), inner.column()), field, msg)
            })?;
            de.end().map_err(|e| {
                make(
                    json_location(e.line(), e.column()),
                    String::new(),
                    strip_location(&e.to_string()),
                )
            })?;
            Ok(value)
        }
        "ron" => {
            // Options without `Some(…)`: plain values are accepted for optional keys.
            let options = ron::Options::default()
                .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
            let mut de = ron::Deserializer::from_str_with_options(text, &options).map_err(|e| {
                make(
                    Some((e.position.line, e.position.col)),
                    String::new(),
                    e.code.to_string(),
                )
            })?;
            let result: Result<SceneFile, _> = serde_path_to_error::deserialize(&mut de);
            let value = result.map_err(|e| {
                let field = field_of(e.path());
                let spanned = de.span_error(e.into_inner());
                make(
                    Some((spanned.position.line, spanned.position.col)),
                    field,
                    spanned.code.to_string(),
                )
            })?;
            de.end().map_err(|e| {
                let spanned = de.span_error(e);
                make(
                    Some((spanned.position.line, spanned.position.col)),
                    String::new(),
                    spanned.code.to_string(),
                )
            })?;
            Ok(value)
        }
        "toml" => {
            let de = toml::Deserializer::parse(text).map_err(|e| {
                make(
                    toml_location(text, &e),
                    String::new(),
                    e.message().trim().to_owned(),
                )
            })?;
            let result: Result<SceneFile, _> = serde_path_to_error::deserialize(de);
            result.map_err(|e| {
                let field = field_of(e.path());
                let inner = e.into_inner();
                make(
                    toml_location(text, &inner),
                    field,
                    inner.message().trim().to_owned(),
                )
            })
        }
        other => Err(make(
            None,
            String::new(),
            format!("unknown scene format {other:?}"),
        )),
    }
}

/// serde_json appends " at line L column C"; the location is printed
/// separately.
fn strip_location(msg: &str) -> String {
    match msg.rfind(" at line ") {
        Some(i) => msg[..i].to_owned(),
        None => msg.to_owned(),
    }
}

fn toml_location(text: &str, e: &toml::de::Error) -> Option<(usize, usize)> {
    let start = e.span()?.start.min(text.len());
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    Some((line, col))
}

/// Collects errors of one scene (the first one wins).
struct Checker<'a> {
    file: &'a str,
    dim: usize,
    /// The scene's precision: law parameters are checked in it.
    precision: Precision,
    /// The names of the scene's materials, sorted (a body's material is its
    /// index here).
    materials: Vec<String>,
}

/// Whether law parameters dissipate (d̃ or the wall's d̃ positive).
fn law_dissipates(law: &LawParams<f64>) -> bool {
    law.dissipation > 0.0 || law.wall_dissipation.is_some_and(|w| w > 0.0)
}

type Check<T> = Result<T, SceneError>;

impl Checker<'_> {
    fn err<T>(&self, field: &str, message: impl Into<String>) -> Check<T> {
        Err(SceneError {
            file: self.file.to_owned(),
            location: None,
            field: field.to_owned(),
            message: message.into(),
        })
    }

    fn finite(&self, field: &str, v: f64) -> Check<f64> {
        if v.is_finite() {
            Ok(v)
        } else {
            self.err(field, format!("must be a finite number, got {v}"))
        }
    }

    fn positive(&self, field: &str, v: f64) -> Check<f64> {
        self.finite(field, v)?;
        if v > 0.0 {
            Ok(v)
        } else {
            self.err(field, format!("must be > 0, got {v}"))
        }
    }

    fn non_negative(&self, field: &str, v: f64) -> Check<f64> {
        self.finite(field, v)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            self.err(field, format!("must be >= 0, got {v}"))
        }
    }

    /// Check law parameters (at `at`: `law`, `materials.NAME`) as the
    /// adapter of the scene's precision will: an invalid constant is named
    /// (`law.dissipation`), and one that f32 cannot hold is an error in an
    /// f32 scene (it would reach the adapter as infinity).
    fn law(&self, at: &str, params: LawParams<f64>) -> Check<()> {
        // One check, in the precision the adapter will build the law in.
        let result = match self.precision {
            Precision::F64 => Law::new(params).map(drop),
            Precision::F32 => Law::new(params.map(|x| x as f32)).map(drop),
        };
        match result {
            Ok(()) => Ok(()),
            Err(LawError::InvalidDissipation { parameter, .. }) => {
                let field = format!("{at}.{parameter}");
                let written = if parameter == "wall_dissipation" {
                    params.wall_dissipation.unwrap_or(params.dissipation)
                } else {
                    params.dissipation
                };
                if written.is_finite() && written >= 0.0 {
                    self.err(
                        &field,
                        format!(
                            "{written:e} is beyond f32's range (at most {:e}): use a smaller value or precision \"f64\"",
                            f32::MAX
                        ),
                    )
                } else {
                    self.err(&field, format!("must be finite and >= 0, got {written}"))
                }
            }
            Err(e) => self.err(at, e.to_string()),
        }
    }

    /// The index of the material named `name` (at `field`).
    fn material(&self, field: &str, name: &str) -> Check<usize> {
        match self.materials.binary_search_by(|m| m.as_str().cmp(name)) {
            Ok(i) => Ok(i),
            Err(_) if self.materials.is_empty() => self.err(
                field,
                format!("unknown material {name:?}: the scene defines no `materials`"),
            ),
            Err(_) => {
                let known: Vec<String> = self.materials.iter().map(|m| format!("{m:?}")).collect();
                self.err(
                    field,
                    format!(
                        "unknown material {name:?}: expected one of {}",
                        known.join(", ")
                    ),
                )
            }
        }
    }

    fn vector(&self, field: &str, v: &[f64]) -> Check<Vec<f64>> {
        if v.len() != self.dim {
            return self.err(
                field,
                format!(
                    "must have {} components (dim = {}), got {}",
                    self.dim,
                    self.dim,
                    v.len()
                ),
            );
        }
        for (i, x) in v.iter().enumerate() {
            self.finite(&format!("{field}[{i}]"), *x)?;
        }
        Ok(v.to_vec())
    }

    fn body(&self, at: &str, origin: &str, b: &BodyFile, generated: bool) -> Check<Body> {
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
        Ok(Body {
            origin: origin.to_owned(),
            name: b.name.clone(),
            shape,
            position,
            velocity,
            mass,
            fixed,
            restitution,
            friction,
            law,
            ccd: b.ccd,
            material,
        })
    }

    fn generator(
        &self,
        gi: usize,
        g: &GeneratorFile,
        first_index: usize,
        out: &mut Vec<Body>,
    ) -> Check<()> {
        let at = format!("generators[{gi}]");
        let f = |k: &str| format!("{at}.{k}");
        let origin = self.vector(
            &f("origin"),
            g.origin
                .as_deref()
                .ok_or(())
                .or_else(|_| self.err(&f("origin"), "missing"))?,
        )?;
        let spacing = self.vector(
            &f("spacing"),
            g.spacing
                .as_deref()
                .ok_or(())
                .or_else(|_| self.err(&f("spacing"), "missing"))?,
        )?;
        let count = match &g.count {
            Some(c) if c.len() == self.dim => c.clone(),
            Some(c) => {
                return self.err(
                    &f("count"),
                    format!(
                        "must have {} components (dim = {}), got {}",
                        self.dim,
                        self.dim,
                        c.len()
                    ),
                );
            }
            None => return self.err(&f("count"), "missing"),
        };
        let total = count
            .iter()
            .try_fold(1u64, |a, c| a.checked_mul(*c))
            .unwrap_or(u64::MAX);
        if count.contains(&0) {
            return self.err(&f("count"), "every count must be >= 1");
        }
        if total > MAX_BODIES as u64 {
            return self.err(&f("count"), format!("{total} bodies: at most {MAX_BODIES}"));
        }
        let Some(template) = &g.body else {
            return self.err(&f("body"), "missing: the template of the generated bodies");
        };
        let base = self.body(&f("body"), &f("body"), template, true)?;
        let masses = match &g.masses {
            Some(ms) if ms.is_empty() => return self.err(&f("masses"), "must not be empty"),
            Some(ms) => {
                for (i, m) in ms.iter().enumerate() {
                    self.positive(&format!("{}[{i}]", f("masses")), *m)?;
                }
                if base.fixed {
                    return self.err(
                        &f("masses"),
                        "the template is fixed: fixed bodies have no mass",
                    );
                }
                ms.clone()
            }
            None => {
                if !base.fixed && base.mass.is_none() {
                    return self.err(
                        &f("body.mass"),
                        "missing: give the template a mass or the generator `masses`",
                    );
                }
                Vec::new()
            }
        };
        let radii = match &g.radii {
            Some(rs) if rs.is_empty() => return self.err(&f("radii"), "must not be empty"),
            Some(rs) => {
                if !matches!(base.shape, Shape::Ball { .. }) {
                    return self.err(&f("radii"), "only for a ball template");
                }
                for (i, r) in rs.iter().enumerate() {
                    self.positive(&format!("{}[{i}]", f("radii")), *r)?;
                }
                rs.clone()
            }
            None => Vec::new(),
        };
        let materials = match &g.materials {
            Some(ms) if ms.is_empty() => return self.err(&f("materials"), "must not be empty"),
            Some(_) if !base.fixed && !base.law => {
                return self.err(
                    &f("materials"),
                    "the template does not follow the law (`law: false`): its bodies have no material",
                );
            }
            Some(ms) => {
                let mut out = Vec::with_capacity(ms.len());
                for (i, m) in ms.iter().enumerate() {
                    out.push(self.material(&format!("{}[{i}]", f("materials")), m)?);
                }
                out
            }
            None => Vec::new(),
        };
        let speed = self.non_negative(&f("speed"), g.speed.unwrap_or(0.0))?;
        if speed > 0.0 && base.fixed {
            return self.err(
                &f("speed"),
                "the template is fixed: fixed bodies cannot move",
            );
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(g.seed.unwrap_or(1));
        let mut index = vec![0u64; self.dim];
        for n in 0..total as usize {
            let mut b = base.clone();
            b.origin = format!("{at}[{n}] (bodies[{}])", first_index + out.len());
            for k in 0..self.dim {
                b.position[k] = origin[k] + spacing[k] * index[k] as f64;
            }
            if !masses.is_empty() {
                b.mass = Some(masses[n % masses.len()]);
            }
            if !radii.is_empty() {
                b.shape = Shape::Ball {
                    radius: radii[n % radii.len()],
                };
            }
            if !materials.is_empty() {
                b.material = Some(materials[n % materials.len()]);
            }
            if speed > 0.0 {
                let dir = direction(&mut rng, self.dim);
                for (v, d) in b.velocity.iter_mut().zip(&dir) {
                    *v += speed * d;
                }
            }
            // Finite inputs can still overflow here (found by fuzzing): a
            // generated body's vectors must be finite like written ones.
            if let Some(k) = b.position.iter().position(|x| !x.is_finite()) {
                return self.err(
                    &f("spacing"),
                    format!(
                        "{} would be at position[{k}] = {}: origin + spacing x index overflows",
                        b.origin, b.position[k]
                    ),
                );
            }
            if let Some(k) = b.velocity.iter().position(|x| !x.is_finite()) {
                return self.err(
                    &f("speed"),
                    format!(
                        "{} would move at velocity[{k}] = {}: the template's velocity + speed overflows",
                        b.origin, b.velocity[k]
                    ),
                );
            }
            out.push(b);
            for k in 0..self.dim {
                index[k] += 1;
                if index[k] < count[k] {
                    break;
                }
                index[k] = 0;
            }
        }
        Ok(())
    }
}

/// The most bodies a scene may have.
pub const MAX_BODIES: usize = 200_000;

/// A uniformly random unit vector of `dim` components (rejection sampling
/// in the cube), for the generators' random directions: the scene's seeded
/// generator gives the same scene on every machine.
fn direction(rng: &mut Xoshiro256PlusPlus, dim: usize) -> Vec<f64> {
    loop {
        let v: Vec<f64> = (0..dim).map(|_| rng.random_range(-1.0..1.0)).collect();
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 1e-3 && n <= 1.0 {
            return v.into_iter().map(|x| x / n).collect();
        }
    }
}

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
    let law = raw.law.as_ref().map(LawFile::params).unwrap_or_default();
    c.law("law", law)?;
    let mut materials = Vec::new();
    for (name, m) in raw.materials.iter().flatten() {
        let at = format!("materials.{name}");
        if name.is_empty() {
            return c.err("materials", "a material needs a non-empty name");
        }
        let dissipation = m.dissipation.unwrap_or(0.0);
        let wall_dissipation = m.wall_dissipation.unwrap_or(dissipation);
        c.law(
            &at,
            LawParams {
                dissipation,
                wall_dissipation: Some(wall_dissipation),
                fixed_partner: FixedPartner::default(),
            },
        )?;
        materials.push(Material {
            name: name.clone(),
            dissipation,
            wall_dissipation,
            combine: m.combine.unwrap_or_default(),
        });
    }
    // A BTreeMap iterates in name order: the checker's binary search holds.
    c.materials = materials.iter().map(|m| m.name.clone()).collect();

    let mut bodies = Vec::new();
    for (i, b) in raw.bodies.iter().flatten().enumerate() {
        let at = format!("bodies[{i}]");
        bodies.push(c.body(&at, &at, b, false)?);
    }
    let first = bodies.len();
    let mut generated = Vec::new();
    for (gi, g) in raw.generators.iter().flatten().enumerate() {
        c.generator(gi, g, first, &mut generated)?;
        if first + generated.len() > MAX_BODIES {
            return c.err(
                &format!("generators[{gi}]"),
                format!("the scene has more than {MAX_BODIES} bodies"),
            );
        }
    }
    bodies.append(&mut generated);
    if bodies.is_empty() {
        return c.err(
            "bodies",
            "missing: the scene has no bodies (give `bodies` or `generators`)",
        );
    }
    if bodies.iter().all(|b| b.fixed) {
        return c.err("bodies", "every body is fixed: nothing would move");
    }

    let mut warnings = Vec::new();
    for (i, m) in materials.iter().enumerate() {
        if !bodies.iter().any(|b| b.material == Some(i)) {
            warnings.push(format!("{file}: materials.{}: no body uses it", m.name));
        }
    }
    let dissipates = law_dissipates(&law)
        || bodies
            .iter()
            .filter_map(|b| b.material)
            .any(|i| materials[i].dissipates());
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
            if !set.contains(&Effect::Friction) && bodies.iter().any(|b| b.friction > 0.0) {
                warnings.push(format!(
                    "{file}: friction: ignored (zero friction), \"friction\" is not in `effects`"
                ));
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
            if bodies.iter().any(|b| b.friction > 0.0) {
                set.insert(Effect::Friction);
            }
            if bodies.iter().any(|b| b.fixed) {
                set.insert(Effect::FixedWalls);
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

    check_overlaps(&c, &bodies)?;

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
        effects,
        view,
        warnings,
    })
}

/// The most steps a scene may ask for.
pub const MAX_STEPS: u64 = 100_000_000;

/// Penetration depth of two bodies at their start positions (axis-aligned
/// boxes), positive when they overlap.
fn depth(a: &Body, b: &Body) -> f64 {
    let d: Vec<f64> = a
        .position
        .iter()
        .zip(&b.position)
        .map(|(x, y)| y - x)
        .collect();
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    match (&a.shape, &b.shape) {
        (Shape::Ball { radius: r1 }, Shape::Ball { radius: r2 }) => r1 + r2 - norm(&d),
        (Shape::Box { half_extents: h1 }, Shape::Box { half_extents: h2 }) => d
            .iter()
            .zip(h1.iter().zip(h2))
            .map(|(dk, (a, b))| a + b - dk.abs())
            .fold(f64::INFINITY, f64::min),
        (Shape::Ball { radius }, Shape::Box { half_extents })
        | (Shape::Box { half_extents }, Shape::Ball { radius }) => {
            // Offset of the ball's centre from the box's centre.
            let (ball, bx) = if matches!(a.shape, Shape::Ball { .. }) {
                (a, b)
            } else {
                (b, a)
            };
            let rel: Vec<f64> = ball
                .position
                .iter()
                .zip(&bx.position)
                .map(|(p, c)| p - c)
                .collect();
            let outside: Vec<f64> = rel
                .iter()
                .zip(half_extents)
                .map(|(r, h)| (r.abs() - h).max(0.0))
                .collect();
            let dist = norm(&outside);
            if dist > 0.0 {
                radius - dist
            } else {
                let inside = rel
                    .iter()
                    .zip(half_extents)
                    .map(|(r, h)| h - r.abs())
                    .fold(f64::INFINITY, f64::min);
                radius + inside
            }
        }
    }
}

/// Bodies that overlap at the start are an error (they would be pushed
/// apart by rapier's penetration correction, an explosion of energy that no
/// law is responsible for). Touching is fine: the tolerance is 1e-4 of the
/// smaller body's size.
///
/// Sweep and prune: the bounding boxes are computed once and stored in sweep
/// order, the sweep runs along the axis where the centres spread most, and
/// boxes are compared on every axis before the exact depth. (Sweeping along
/// x with the boxes recomputed per pair, as before, took 12 s for a valid
/// 20,000-body column and timed out the fuzzer on an 8,690-body pit.)
fn check_overlaps(c: &Checker<'_>, bodies: &[Body]) -> Check<()> {
    let dim = c.dim;
    let spread = |k: usize| {
        let centres = bodies.iter().map(|b| b.position[k]);
        centres.clone().fold(f64::NEG_INFINITY, f64::max) - centres.fold(f64::INFINITY, f64::min)
    };
    let spreads: Vec<f64> = (0..dim).map(spread).collect();
    let axis = (0..dim).fold(
        0,
        |best, k| if spreads[k] > spreads[best] { k } else { best },
    );
    // Each body's box as `dim` lower then `dim` upper bounds.
    let boxes: Vec<Vec<f64>> = bodies
        .iter()
        .map(|b| {
            let h = b.shape.half_box(dim);
            let lo = (0..dim).map(|k| b.position[k] - h[k]);
            let hi = (0..dim).map(|k| b.position[k] + h[k]);
            lo.chain(hi).collect()
        })
        .collect();
    let mut order: Vec<usize> = (0..bodies.len()).collect();
    order.sort_by(|&a, &b| boxes[a][axis].total_cmp(&boxes[b][axis]).then(a.cmp(&b)));
    // The boxes and fixed flags in sweep order, contiguous: the inner loop
    // reads memory in sequence and touches a body only for a candidate pair.
    let sorted: Vec<f64> = order
        .iter()
        .flat_map(|&i| boxes[i].iter().copied())
        .collect();
    let fixed: Vec<bool> = order.iter().map(|&i| bodies[i].fixed).collect();
    let stride = 2 * dim;
    for (m, &i) in order.iter().enumerate() {
        let box_i = &sorted[m * stride..(m + 1) * stride];
        let end = box_i[dim + axis];
        for (q, &j) in order.iter().enumerate().skip(m + 1) {
            let box_j = &sorted[q * stride..(q + 1) * stride];
            if box_j[axis] > end {
                break;
            }
            // Boxes apart on some axis: the bodies cannot overlap.
            if (fixed[m] && fixed[q])
                || (0..dim).any(|k| box_i[dim + k] < box_j[k] || box_j[dim + k] < box_i[k])
            {
                continue;
            }
            let (a, b) = (&bodies[i], &bodies[j]);
            let tol = 1e-4 * a.shape.min_size().min(b.shape.min_size());
            let d = depth(a, b);
            if d > tol {
                let (first, second) = if i < j { (a, b) } else { (b, a) };
                return c.err(
                    &format!("{}.position", second.origin),
                    format!("overlaps {} by {d:.3e} at the start: move the bodies apart (touching is fine)", first.origin),
                );
            }
        }
    }
    Ok(())
}
