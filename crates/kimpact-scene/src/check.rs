//! The validator's checks of single values, vectors and the law's
//! constants, each error naming its field.

use kimpact::{ImpactFriction, Law, LawError, LawParams};

use crate::{FixedPartner, Precision, SceneError};

/// Collects errors of one scene (the first one wins).
pub(crate) struct Checker<'a> {
    pub(crate) file: &'a str,
    pub(crate) dim: usize,
    /// The scene's precision: law parameters are checked in it.
    pub(crate) precision: Precision,
    /// The names of the scene's materials, sorted (a body's material is its
    /// index here).
    pub(crate) materials: Vec<String>,
}

/// A validation result.
pub(crate) type Check<T> = Result<T, SceneError>;

/// The law's constants as a `law` table or a material writes them: each
/// reference impact by its d̃ or by its restitution.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Written {
    pub(crate) dissipation: Option<f64>,
    pub(crate) wall_dissipation: Option<f64>,
    pub(crate) restitution: Option<f64>,
    pub(crate) wall_restitution: Option<f64>,
}

/// [`Written`] constants as d̃.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Constants {
    /// d̃ (default 0).
    pub(crate) dissipation: f64,
    /// The wall's d̃, if set (by itself or by a restitution).
    pub(crate) wall_dissipation: Option<f64>,
    /// `[ball, wall]` restitutions when both came from restitutions.
    pub(crate) restitution: Option<[f64; 2]>,
}

impl Checker<'_> {
    pub(crate) fn err<T>(&self, field: &str, message: impl Into<String>) -> Check<T> {
        Err(SceneError {
            file: self.file.to_owned(),
            location: None,
            field: field.to_owned(),
            message: message.into(),
        })
    }

    pub(crate) fn finite(&self, field: &str, v: f64) -> Check<f64> {
        if v.is_finite() {
            Ok(v)
        } else {
            self.err(field, format!("must be a finite number, got {v}"))
        }
    }

    pub(crate) fn positive(&self, field: &str, v: f64) -> Check<f64> {
        self.finite(field, v)?;
        if v > 0.0 {
            Ok(v)
        } else {
            self.err(field, format!("must be > 0, got {v}"))
        }
    }

    pub(crate) fn non_negative(&self, field: &str, v: f64) -> Check<f64> {
        self.finite(field, v)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            self.err(field, format!("must be >= 0, got {v}"))
        }
    }

    /// The constants written at `at` (`law`, `materials.NAME`) as d̃: a
    /// restitution `e` is converted by [`LawParams::from_restitution`]
    /// (`d̃ = (1 − e²)/8`, `d̃_w = (1 − e_w²)/2`, the wall's `e_w`
    /// defaulting to `e` unless `wall_dissipation` is written). A reference
    /// impact given both ways is an error naming both keys; a wall
    /// restitution below 1 needs `fixed_partner` `"own_mass"`, under which
    /// its reference impact holds.
    pub(crate) fn constants(
        &self,
        at: &str,
        w: Written,
        fixed_partner: FixedPartner,
    ) -> Check<Constants> {
        let both = |a: &str, b: &str, what: &str| {
            self.err::<Constants>(
                &format!("{at}.{a}"),
                format!(
                    "give `{at}.{a}` or `{at}.{b}`, not both: each sets {what} (a restitution is converted to d̃)"
                ),
            )
        };
        if w.restitution.is_some() && w.dissipation.is_some() {
            return both("restitution", "dissipation", "the law between two bodies");
        }
        if w.wall_restitution.is_some() && w.wall_dissipation.is_some() {
            return both(
                "wall_restitution",
                "wall_dissipation",
                "the law against fixed bodies",
            );
        }
        // The wall's restitution, and the key it was read from.
        let wall = match (w.wall_restitution, w.wall_dissipation, w.restitution) {
            (Some(e), _, _) => Some((e, "wall_restitution")),
            (None, None, Some(e)) => Some((e, "restitution")),
            _ => None,
        };
        for (e, key) in w
            .restitution
            .map(|e| (e, "restitution"))
            .into_iter()
            .chain(wall)
        {
            if !(0.0..=1.0).contains(&e) {
                return self.err(
                    &format!("{at}.{key}"),
                    format!(
                        "a restitution must be in [0, 1] (the law only takes energy away), got {e}"
                    ),
                );
            }
        }
        if let Some((e, key)) = wall
            && e < 1.0
            && fixed_partner == FixedPartner::Literal
        {
            return self.err(
                &format!("{at}.{key}"),
                format!(
                    "a wall restitution of {e} holds under `law.fixed_partner: \"own_mass\"`; under \"literal\" every impact on a fixed body with d̃_w > 0 is plastic: give `wall_dissipation`, or use \"own_mass\""
                ),
            );
        }
        let converted =
            LawParams::from_restitution(w.restitution.unwrap_or(1.0), wall.map_or(1.0, |(e, _)| e))
                .map_err(|e| SceneError {
                    file: self.file.to_owned(),
                    location: None,
                    field: at.to_owned(),
                    message: e.to_string(),
                })?;
        Ok(Constants {
            dissipation: match w.restitution {
                Some(_) => converted.dissipation,
                None => w.dissipation.unwrap_or(0.0),
            },
            wall_dissipation: match wall {
                Some(_) => converted.wall_dissipation,
                None => w.wall_dissipation,
            },
            restitution: w.restitution.zip(wall).map(|(b, (w, _))| [b, w]),
        })
    }

    /// Check law parameters (at `at`: `law`, `materials.NAME`) as the
    /// adapter of the scene's precision will: an invalid constant is named
    /// (`law.dissipation`), and one that f32 cannot hold is an error in an
    /// f32 scene (it would reach the adapter as infinity).
    pub(crate) fn law(&self, at: &str, params: LawParams<f64>) -> Check<()> {
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

    /// A material's impact friction as written at `at` (`materials.NAME`):
    /// `(μ, β)`, μ defaulting to 0, β to 0 when μ is written and to
    /// [`Material::NO_TANGENTIAL_RESTITUTION`] when neither is, checked as
    /// the adapter of the scene's precision will (μ finite and ≥ 0, within
    /// f32's range in an f32 scene; β in `[−1, 1]`), an error naming the
    /// key (`materials.felt.impact_friction`).
    ///
    /// [`Material::NO_TANGENTIAL_RESTITUTION`]: crate::Material::NO_TANGENTIAL_RESTITUTION
    pub(crate) fn impact_friction(
        &self,
        at: &str,
        impact_friction: Option<f64>,
        tangential_restitution: Option<f64>,
    ) -> Check<(f64, f64)> {
        let mu = impact_friction.unwrap_or(0.0);
        let beta = match (impact_friction, tangential_restitution) {
            (_, Some(beta)) => beta,
            (Some(_), None) => 0.0,
            (None, None) => crate::Material::NO_TANGENTIAL_RESTITUTION,
        };
        let result = match self.precision {
            Precision::F64 => ImpactFriction::new(mu, beta).map(drop),
            Precision::F32 => ImpactFriction::new(mu as f32, beta as f32).map(drop),
        };
        match result {
            Ok(()) => Ok((mu, beta)),
            Err(LawError::InvalidFriction {
                parameter,
                expected,
                ..
            }) => {
                let field = format!("{at}.{parameter}");
                let written = if parameter == "impact_friction" {
                    mu
                } else {
                    beta
                };
                if parameter == "impact_friction" && written.is_finite() && written >= 0.0 {
                    self.err(
                        &field,
                        format!(
                            "{written:e} is beyond f32's range (at most {:e}): use a smaller value or precision \"f64\"",
                            f32::MAX
                        ),
                    )
                } else {
                    self.err(&field, format!("must be {expected}, got {written}"))
                }
            }
            Err(e) => self.err(at, e.to_string()),
        }
    }

    /// The index of the material named `name` (at `field`).
    pub(crate) fn material(&self, field: &str, name: &str) -> Check<usize> {
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

    pub(crate) fn vector(&self, field: &str, v: &[f64]) -> Check<Vec<f64>> {
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
}
