//! A [`Snapshot`]'s serde form: `format`, then `state`. The format is read
//! first, so that a snapshot of another format is refused by its format
//! and not by whatever field its state no longer has.

use std::fmt;

use serde::de::{self, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde::ser::SerializeStruct;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::{Snapshot, SnapshotError, State};

const FIELDS: &[&str] = &["format", "state"];

impl Serialize for Snapshot {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut s =
            serializer.serialize_struct("Snapshot", 1 + usize::from(self.state.is_some()))?;
        s.serialize_field("format", &self.format)?;
        match &self.state {
            Some(state) => s.serialize_field("state", state)?,
            None => s.skip_field("state")?,
        }
        s.end()
    }
}

impl<'de> Deserialize<'de> for Snapshot {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_struct("Snapshot", FIELDS, SnapshotVisitor)
    }
}

/// The refusal of a snapshot of format `found`.
fn other_format(found: u32) -> SnapshotError {
    SnapshotError::Format {
        found,
        expected: Snapshot::FORMAT,
    }
}

struct SnapshotVisitor;

impl<'de> Visitor<'de> for SnapshotVisitor {
    type Value = Snapshot;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a kimpact snapshot: its format, then its state")
    }

    /// A format that does not name its fields: the state of another format
    /// cannot be skipped, so the snapshot is refused here.
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Snapshot, A::Error> {
        let format: u32 = seq
            .next_element()?
            .ok_or_else(|| de::Error::invalid_length(0, &self))?;
        if format != Snapshot::FORMAT {
            return Err(de::Error::custom(other_format(format)));
        }
        let state: State = seq
            .next_element()?
            .ok_or_else(|| de::Error::invalid_length(1, &self))?;
        Ok(Snapshot {
            format,
            state: Some(state),
        })
    }

    /// A format that names its fields: the state of another format is
    /// skipped (when `format` comes first, as written) and the snapshot
    /// holds its format alone.
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Snapshot, A::Error> {
        let mut format: Option<u32> = None;
        let mut state: Option<State> = None;
        let mut unknown: Option<String> = None;
        while let Some(field) = map.next_key::<Field>()? {
            match field {
                Field::Format => {
                    if format.is_some() {
                        return Err(de::Error::duplicate_field("format"));
                    }
                    format = Some(map.next_value()?);
                }
                Field::State if format.is_none_or(|f| f == Snapshot::FORMAT) => {
                    if state.is_some() {
                        return Err(de::Error::duplicate_field("state"));
                    }
                    state = Some(map.next_value()?);
                }
                Field::State => {
                    map.next_value::<IgnoredAny>()?;
                }
                Field::Other(name) => {
                    map.next_value::<IgnoredAny>()?;
                    unknown.get_or_insert(name);
                }
            }
        }
        let format = format.ok_or_else(|| de::Error::missing_field("format"))?;
        if format != Snapshot::FORMAT {
            return Ok(Snapshot {
                format,
                state: None,
            });
        }
        if let Some(name) = unknown {
            return Err(de::Error::unknown_field(&name, FIELDS));
        }
        let state = state.ok_or_else(|| de::Error::missing_field("state"))?;
        Ok(Snapshot {
            format,
            state: Some(state),
        })
    }
}

/// A field name of the snapshot.
enum Field {
    Format,
    State,
    Other(String),
}

impl<'de> Deserialize<'de> for Field {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_identifier(FieldVisitor)
    }
}

struct FieldVisitor;

impl Visitor<'_> for FieldVisitor {
    type Value = Field;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("`format` or `state`")
    }

    fn visit_u64<E: de::Error>(self, index: u64) -> Result<Field, E> {
        Ok(match index {
            0 => Field::Format,
            1 => Field::State,
            _ => Field::Other(index.to_string()),
        })
    }

    fn visit_str<E: de::Error>(self, name: &str) -> Result<Field, E> {
        Ok(match name {
            "format" => Field::Format,
            "state" => Field::State,
            _ => Field::Other(name.to_owned()),
        })
    }

    fn visit_bytes<E: de::Error>(self, name: &[u8]) -> Result<Field, E> {
        self.visit_str(&String::from_utf8_lossy(name))
    }
}
