//! Reading the accuracy study's `accuracy-summary.json`: its headline
//! errors, every entry checked field by field (the errors name the entry,
//! as `errors[3].quantity`).

use std::path::Path;

use kimpact::{Mode, Precision};
use serde_json::{Map, Value};

use crate::error::LadderError;

/// One headline error of the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorEntry {
    /// Its place in the summary's `errors` list.
    pub index: usize,
    /// The accuracy scene (`gas`, `cradle`…).
    pub scene: String,
    /// 2 or 3.
    pub dimension: usize,
    /// The build's precision.
    pub precision: Precision,
    /// The mode.
    pub mode: Mode,
    /// The time step is rapier's default divided by this.
    pub dt_div: usize,
    /// What the error measures (`impact_rate_error`, `energy_error`…).
    pub quantity: String,
    /// The error against the exact reference (NaN where the summary has
    /// `null`, as serde_json writes a NaN).
    pub error: f64,
    /// The noise floor, on the chaotic scenes (NaN where `null`).
    pub noise_floor: Option<f64>,
}

/// What the ladder reads of the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// The command that wrote it.
    pub command: String,
    /// Whether it was a `--quick` smoke run (its errors mean nothing).
    pub quick: bool,
    /// The headline errors.
    pub errors: Vec<ErrorEntry>,
}

/// Read and check `path`.
///
/// # Errors
/// The file cannot be read, or [`parse`]'s.
pub fn read(path: &Path) -> Result<Summary, LadderError> {
    let text = std::fs::read_to_string(path).map_err(|source| LadderError::Read {
        path: path.to_owned(),
        source,
    })?;
    parse(path, &text)
}

/// The summary in `text`, the JSON of `path` (named in the errors).
///
/// # Errors
/// Not JSON, or an entry without a field the join needs or with a value of
/// the wrong kind.
pub fn parse(path: &Path, text: &str) -> Result<Summary, LadderError> {
    let root: Value = serde_json::from_str(text).map_err(|source| LadderError::Json {
        path: path.to_owned(),
        source,
    })?;
    let top = Entry {
        path,
        name: String::new(),
        value: &root,
    };
    let object = top.object()?;
    let errors = top
        .field(object, "errors")?
        .value
        .as_array()
        .ok_or_else(|| top.bad("errors", "not a list"))?;
    let errors = errors
        .iter()
        .enumerate()
        .map(|(index, value)| {
            let e = Entry {
                path,
                name: format!("errors[{index}]"),
                value,
            };
            let o = e.object()?;
            Ok(ErrorEntry {
                index,
                scene: e.field(o, "scene")?.string()?.to_owned(),
                dimension: e.field(o, "dimension")?.count()?,
                precision: e.field(o, "precision")?.parsed("f32 or f64")?,
                mode: e.field(o, "mode")?.parsed("a mode")?,
                dt_div: e.field(o, "dt_div")?.count()?,
                quantity: e.field(o, "quantity")?.string()?.to_owned(),
                error: e.field(o, "error")?.number()?,
                noise_floor: match o.get("noise_floor") {
                    None => None,
                    Some(_) => Some(e.field(o, "noise_floor")?.number()?),
                },
            })
        })
        .collect::<Result<Vec<_>, LadderError>>()?;
    Ok(Summary {
        command: match object.get("command") {
            Some(_) => top.field(object, "command")?.string()?.to_owned(),
            None => String::new(),
        },
        quick: match object.get("quick") {
            Some(_) => top.field(object, "quick")?.boolean()?,
            None => false,
        },
        errors,
    })
}

/// A value of the summary and where it is.
struct Entry<'a> {
    path: &'a Path,
    name: String,
    value: &'a Value,
}

impl<'a> Entry<'a> {
    /// An error at the field `field` of this entry.
    fn bad(&self, field: &str, problem: &str) -> LadderError {
        let entry = match (self.name.is_empty(), field.is_empty()) {
            (true, _) => field.to_owned(),
            (false, true) => self.name.clone(),
            (false, false) => format!("{}.{field}", self.name),
        };
        LadderError::BadEntry {
            path: self.path.to_owned(),
            entry: if entry.is_empty() {
                "the top level".to_owned()
            } else {
                entry
            },
            problem: problem.to_owned(),
        }
    }

    /// An error at this value itself.
    fn wrong(&self, expected: &str) -> LadderError {
        self.bad("", &format!("{} is not {expected}", self.value))
    }

    fn object(&self) -> Result<&'a Map<String, Value>, LadderError> {
        self.value
            .as_object()
            .ok_or_else(|| self.wrong("an object"))
    }

    /// The field `name` of `object` (this entry's).
    fn field(&self, object: &'a Map<String, Value>, name: &str) -> Result<Entry<'a>, LadderError> {
        let value = object.get(name).ok_or_else(|| self.bad(name, "missing"))?;
        Ok(Entry {
            path: self.path,
            name: if self.name.is_empty() {
                name.to_owned()
            } else {
                format!("{}.{name}", self.name)
            },
            value,
        })
    }

    fn string(&self) -> Result<&'a str, LadderError> {
        self.value.as_str().ok_or_else(|| self.wrong("a string"))
    }

    fn boolean(&self) -> Result<bool, LadderError> {
        self.value
            .as_bool()
            .ok_or_else(|| self.wrong("true or false"))
    }

    fn count(&self) -> Result<usize, LadderError> {
        self.value
            .as_u64()
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| self.wrong("a whole number"))
    }

    /// A number; `null` (serde_json's NaN) is NaN.
    fn number(&self) -> Result<f64, LadderError> {
        match self.value {
            Value::Null => Ok(f64::NAN),
            v => v.as_f64().ok_or_else(|| self.wrong("a number")),
        }
    }

    fn parsed<T: std::str::FromStr>(&self, expected: &str) -> Result<T, LadderError> {
        self.string()?.parse().map_err(|_| self.wrong(expected))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_errors_with_and_without_a_noise_floor_and_nulls_as_nan() {
        let text = r#"{"command": "c", "quick": true, "errors": [
            {"scene": "gas", "dimension": 2, "precision": "f32", "mode": "exact", "dt_div": 1,
             "quantity": "impact_rate_error", "error": 0.004, "noise_floor": 0.0025},
            {"scene": "gas", "dimension": 3, "precision": "f64", "mode": "native", "dt_div": 2,
             "quantity": "energy_error", "error": null}
        ], "costs": []}"#;
        let s = parse(Path::new("s.json"), text).unwrap();
        assert_eq!(s.command, "c");
        assert!(s.quick);
        assert_eq!(s.errors[0].noise_floor, Some(0.0025));
        assert_eq!(s.errors[0].mode, Mode::Exact);
        assert_eq!(s.errors[1].noise_floor, None);
        assert!(s.errors[1].error.is_nan());
        assert_eq!(s.errors[1].index, 1);
    }

    #[test]
    fn a_missing_or_wrong_field_names_its_entry() {
        let text = r#"{"errors": [{"scene": "gas", "dimension": 2, "precision": "f32",
            "mode": "exact", "dt_div": 1, "error": 0.1}]}"#;
        let e = parse(Path::new("s.json"), text).unwrap_err();
        assert_eq!(e.to_string(), "s.json, errors[0].quantity: missing");
        let text = r#"{"errors": [{"scene": "gas", "dimension": 2, "precision": "f16",
            "mode": "exact", "dt_div": 1, "quantity": "q", "error": 0.1}]}"#;
        let e = parse(Path::new("s.json"), text).unwrap_err();
        assert_eq!(
            e.to_string(),
            "s.json, errors[0].precision: \"f16\" is not f32 or f64"
        );
        let e = parse(Path::new("s.json"), r#"{"costs": []}"#).unwrap_err();
        assert_eq!(e.to_string(), "s.json, errors: missing");
        let e = parse(Path::new("s.json"), "{").unwrap_err();
        assert!(matches!(e, LadderError::Json { .. }), "{e}");
    }
}
