//! A small CSV reader: records split on commas, fields in double quotes
//! may hold commas, doubled quotes and line breaks (as the bench's
//! `csv_field` writes them). Each record keeps the line it starts on.

/// One record: the line it starts on (1-based, the header is line 1) and
/// its fields.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// The line the record starts on.
    pub line: usize,
    /// Its fields, unquoted.
    pub fields: Vec<String>,
}

/// A quoted field that never closes: the line it opens on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Unterminated {
    /// The line of the opening quote.
    pub line: usize,
}

/// The records of `text`; blank lines are skipped.
///
/// # Errors
/// [`Unterminated`] when a quoted field does not close.
pub fn records(text: &str) -> Result<Vec<Record>, Unterminated> {
    let mut out = Vec::new();
    let mut fields = Vec::new();
    let mut field = String::new();
    let (mut line, mut start) = (1usize, 1usize);
    let mut quoted: Option<usize> = None;
    let mut chars = text.chars().peekable();
    // A record in progress: some field or separator seen on it.
    let mut open = false;
    while let Some(c) = chars.next() {
        if quoted.is_some() {
            match c {
                '"' if chars.peek() == Some(&'"') => {
                    chars.next();
                    field.push('"');
                }
                '"' => quoted = None,
                '\n' => {
                    line += 1;
                    field.push('\n');
                }
                _ => field.push(c),
            }
            continue;
        }
        match c {
            '"' if field.is_empty() => {
                quoted = Some(line);
                open = true;
            }
            ',' => {
                fields.push(std::mem::take(&mut field));
                open = true;
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            '\n' => {
                if open || !field.is_empty() {
                    fields.push(std::mem::take(&mut field));
                    out.push(Record {
                        line: start,
                        fields: std::mem::take(&mut fields),
                    });
                }
                open = false;
                line += 1;
                start = line;
            }
            _ => {
                field.push(c);
                open = true;
            }
        }
    }
    if let Some(line) = quoted {
        return Err(Unterminated { line });
    }
    if open || !field.is_empty() {
        fields.push(field);
        out.push(Record {
            line: start,
            fields,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(line: usize, fields: &[&str]) -> Record {
        Record {
            line,
            fields: fields.iter().map(|f| (*f).to_owned()).collect(),
        }
    }

    #[test]
    fn plain_quoted_and_empty_fields() {
        assert_eq!(
            records("a,b,c\n1,,\"x, \"\"y\"\"\"\n\n2,3,4"),
            Ok(vec![
                rec(1, &["a", "b", "c"]),
                rec(2, &["1", "", "x, \"y\""]),
                rec(4, &["2", "3", "4"]),
            ])
        );
    }

    #[test]
    fn a_line_break_inside_quotes_stays_in_the_field() {
        assert_eq!(
            records("a,b\r\n\"one\ntwo\",z\nlast,1\n"),
            Ok(vec![
                rec(1, &["a", "b"]),
                rec(2, &["one\ntwo", "z"]),
                rec(4, &["last", "1"]),
            ])
        );
    }

    #[test]
    fn an_unclosed_quote_names_its_line() {
        assert_eq!(records("a\n\"open\n"), Err(Unterminated { line: 2 }));
    }
}
