//! Reading the bench's `results.csv`: the columns the join needs, found by
//! their header names, every row checked; and the command that wrote it,
//! from the `results.md` beside it.

use std::path::Path;
use std::str::FromStr;

use kimpact::{Mode, Precision};

use crate::csv;
use crate::error::LadderError;

/// One row of the bench's CSV, as far as the join needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    /// The row's line in the file.
    pub line: usize,
    /// The bench scene (`gas2d`, `pit3d`…).
    pub scene: String,
    /// Its dimension.
    pub dim: usize,
    /// The build's precision.
    pub precision: Precision,
    /// Whether rapier ran with its `parallel` feature.
    pub parallel: bool,
    /// Balls of the scene.
    pub balls: usize,
    /// The mode.
    pub mode: Mode,
    /// ×native: the mode's median time per step over native rapier's, from
    /// the same processes (NaN when the bench could not measure it).
    pub ratio: f64,
    /// The bench's error message for the row (empty when none, or when
    /// the CSV has no `error` column).
    pub error: String,
}

/// The columns read, all required.
pub const COLUMNS: [&str; 7] = [
    "scene",
    "dim",
    "precision",
    "parallel",
    "balls",
    "mode",
    "ratio",
];

/// The column of the bench's error message, read when present.
const ERROR_COLUMN: &str = "error";

/// Read and check `path`.
///
/// # Errors
/// The file cannot be read, or [`parse`]'s.
pub fn read(path: &Path) -> Result<Vec<BenchRow>, LadderError> {
    let text = std::fs::read_to_string(path).map_err(|source| LadderError::Read {
        path: path.to_owned(),
        source,
    })?;
    parse(path, &text)
}

/// The rows of `text`, the CSV of `path` (named in the errors).
///
/// # Errors
/// No header, a missing column, a row with another number of fields than
/// the header, a field that does not read as its column's kind.
pub fn parse(path: &Path, text: &str) -> Result<Vec<BenchRow>, LadderError> {
    let records = csv::records(text).map_err(|u| LadderError::Unterminated {
        path: path.to_owned(),
        line: u.line,
    })?;
    let mut records = records.into_iter();
    let header = records.next().ok_or_else(|| LadderError::NoHeader {
        path: path.to_owned(),
    })?;
    let index = |column: &'static str| {
        header
            .fields
            .iter()
            .position(|h| h.trim() == column)
            .ok_or_else(|| LadderError::MissingColumn {
                path: path.to_owned(),
                column,
            })
    };
    let mut at = [0usize; COLUMNS.len()];
    for (slot, column) in at.iter_mut().zip(COLUMNS) {
        *slot = index(column)?;
    }
    let error_at = index(ERROR_COLUMN).ok();
    let [scene, dim, precision, parallel, balls, mode, ratio] = at;
    records
        .map(|r| {
            if r.fields.len() != header.fields.len() {
                return Err(LadderError::FieldCount {
                    path: path.to_owned(),
                    line: r.line,
                    found: r.fields.len(),
                    expected: header.fields.len(),
                });
            }
            let field = Field { path, record: &r };
            Ok(BenchRow {
                line: r.line,
                scene: r.fields[scene].trim().to_owned(),
                dim: field.parse(dim, COLUMNS[1], "a dimension (2 or 3)")?,
                precision: field.parse(precision, COLUMNS[2], "a precision (f32 or f64)")?,
                parallel: field.parse(parallel, COLUMNS[3], "true or false")?,
                balls: field.parse(balls, COLUMNS[4], "a count of balls")?,
                mode: field.parse(mode, COLUMNS[5], "a mode")?,
                ratio: field.parse(ratio, COLUMNS[6], "a number")?,
                error: error_at.map_or_else(String::new, |i| r.fields[i].trim().to_owned()),
            })
        })
        .collect()
}

/// A field of one record, parsed with errors naming the file, line and
/// column.
struct Field<'a> {
    path: &'a Path,
    record: &'a csv::Record,
}

impl Field<'_> {
    fn parse<T: FromStr>(
        &self,
        index: usize,
        column: &'static str,
        expected: &'static str,
    ) -> Result<T, LadderError> {
        let value = self.record.fields[index].trim();
        value.parse().map_err(|_| LadderError::BadField {
            path: self.path.to_owned(),
            line: self.record.line,
            column,
            value: value.to_owned(),
            expected,
        })
    }
}

/// The command that wrote the bench's CSV at `csv_path`, from the
/// `- command: `…`` line of the `results.md` written beside it (the same
/// name with `.md`), if there is one.
pub fn command(csv_path: &Path) -> Option<String> {
    let md = std::fs::read_to_string(csv_path.with_extension("md")).ok()?;
    md.lines().find_map(|l| {
        let rest = l.trim().strip_prefix("- command: `")?;
        Some(rest.strip_suffix('`').unwrap_or(rest).to_owned())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "scene,dim,precision,parallel,balls,mode,rounds,ratio,error\n";

    #[test]
    fn reads_the_columns_by_name_whatever_their_order() {
        let text = format!(
            "{HEAD}gas2d,2,f32,false,1000,exact,1,1.6040,\ngas3d,3,f64,true,10,native,3,NaN,\"timed out, twice\"\n"
        );
        let rows = parse(Path::new("r.csv"), &text).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(
            rows[0],
            BenchRow {
                line: 2,
                scene: "gas2d".into(),
                dim: 2,
                precision: Precision::F32,
                parallel: false,
                balls: 1000,
                mode: Mode::Exact,
                ratio: 1.604,
                error: String::new(),
            }
        );
        assert!(rows[1].ratio.is_nan());
        assert_eq!(rows[1].error, "timed out, twice");
        assert_eq!(rows[1].line, 3);
    }

    #[test]
    fn a_missing_column_is_named() {
        let e = parse(
            Path::new("r.csv"),
            "scene,dim,precision,parallel,balls,mode\n",
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                LadderError::MissingColumn {
                    column: "ratio",
                    ..
                }
            ),
            "{e}"
        );
        assert_eq!(
            e.to_string(),
            "r.csv: no column `ratio` in the header (line 1)"
        );
    }

    #[test]
    fn a_bad_field_names_its_line_and_column() {
        let text = format!("{HEAD}gas2d,2,f32,false,1000,exact,1,fast,\n");
        let e = parse(Path::new("r.csv"), &text).unwrap_err();
        assert_eq!(
            e.to_string(),
            "r.csv, line 2, column `ratio`: cannot read \"fast\" as a number"
        );
        let text = format!("{HEAD}gas2d,2,f32,false,1000,fastest,1,1.0,\n");
        let e = parse(Path::new("r.csv"), &text).unwrap_err();
        assert!(e.to_string().contains("column `mode`"), "{e}");
        let text = format!("{HEAD}gas2d,2,f32,false,1000,exact,1\n");
        let e = parse(Path::new("r.csv"), &text).unwrap_err();
        assert!(
            matches!(
                e,
                LadderError::FieldCount {
                    line: 2,
                    found: 7,
                    expected: 9,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn an_empty_file_has_no_header() {
        let e = parse(Path::new("r.csv"), "").unwrap_err();
        assert!(matches!(e, LadderError::NoHeader { .. }), "{e}");
    }
}
