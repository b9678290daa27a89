//! Reading scene text: the format from the extension, serde errors with
//! their field path and 1-based line and column.

use std::path::Path;

use crate::{Scene, SceneError, SceneFile, validate};

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
