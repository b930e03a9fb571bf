//! Tag files: crease and corner sharpness, for meshes in formats that have
//! no place for them (everything but OBJ), as JSON:
//!
//! ```json
//! {"creases": [[0, 1, 2.5], [1, 2, 10]], "corners": [[3, 10]], "holes": [7, 8]}
//! ```
//!
//! - `creases`: `[v0, v1, sharpness]` entries, the edge between vertices
//!   `v0` and `v1` (0-based); `corners`: `[v, sharpness]` entries; `holes`:
//!   face indices (0-based), faces that are holes (OpenSubdiv's `t hole`).
//!   Every key is optional; any other key, a key given twice, or a top level
//!   that is not an object is an error.
//! - A vertex index is a non-negative integer below 2³² (`3` or `3.0`, not
//!   `3.5`); a sharpness is a number ≥ 0 (0 smooth, ≥ 10 infinitely sharp),
//!   stored as the nearest `f32`, as OpenSubdiv stores it.
//! - Errors are [`IoError::Parse`] naming the line and the entry:
//!   `tags.json:3: creases[1]: vertex index -1 is negative`. Whether a pair
//!   is an edge of the mesh, and the index range, is the validator's
//!   (`subdiv_mesh::Tags::from_list`).
//!
//! Reading is bounded like the mesh readers': only regular files
//! ([`IoError::NotAFile`]), at most [`TAG_FILE_LIMIT`] bytes, and entries
//! are converted one at a time as they are parsed, so memory stays in
//! proportion to the tags (no JSON tree of the whole file).

use serde::de::{DeserializeSeed, Deserializer, Error as _, MapAccess, SeqAccess, Visitor};
use serde_json::Value;
use std::fmt;
use std::path::Path;
use subdiv_mesh::{EdgeTag, TagList, VertexTag};

use crate::error::{Ctx, IoError};
use crate::text::{escape_controls, is_blank, show, sniff, strip_bom, NotText};

/// The largest tag file [`read_tag_file`] reads: 256 MiB, about ten million
/// crease entries.
pub const TAG_FILE_LIMIT: u64 = 256 << 20;

/// Reads a JSON tag file (see the module documentation for the format).
///
/// # Errors
/// [`IoError::NotAFile`] for a directory, FIFO, device or socket,
/// [`IoError::Io`] when the file cannot be read, [`IoError::Unsupported`]
/// for a file larger than [`TAG_FILE_LIMIT`], [`IoError::Utf16`] for UTF-16
/// text, and the errors of [`parse_tag_json`].
pub fn read_tag_file(path: &Path) -> Result<TagList, IoError> {
    let ctx = Ctx::new(path);
    let too_large =
        |size: u64| ctx.unsupported(format!("tag file of {size} bytes (at most {TAG_FILE_LIMIT} are read)"));
    // The size first, so that a huge file is refused before memory is
    // reserved for it; `read_file` refuses what is not a regular file.
    let metadata = std::fs::metadata(path).map_err(|e| ctx.io(e))?;
    if metadata.is_file() && metadata.len() > TAG_FILE_LIMIT {
        return Err(too_large(metadata.len()));
    }
    let bytes = crate::read_file(path, Some(TAG_FILE_LIMIT + 1), &mut |_, _| {})?;
    if bytes.len() as u64 > TAG_FILE_LIMIT {
        // The file grew after it was looked at.
        return Err(too_large(bytes.len() as u64));
    }
    parse(&bytes, ctx)
}

/// Parses a JSON tag document held in memory (errors name `<memory>`).
///
/// # Errors
/// [`IoError::Parse`] with the line, naming the entry: not JSON, not an
/// object, an unknown or repeated key, an entry of the wrong shape, a vertex
/// index that is not an integer in `0..2³²`, a sharpness that is not a
/// number ≥ 0.
pub fn parse_tag_json(json: &str) -> Result<TagList, IoError> {
    parse(json.as_bytes(), Ctx::new(Path::new("<memory>")))
}

fn parse(bytes: &[u8], ctx: Ctx<'_>) -> Result<TagList, IoError> {
    let bytes = strip_bom(bytes);
    if is_blank(bytes) {
        return Err(ctx.parse(None, r#"tag file is empty (expected a JSON object such as {"creases": [[0, 1, 2.5]]})"#));
    }
    match sniff(bytes) {
        Some(NotText::Utf16) => return Err(ctx.utf16()),
        Some(NotText::Binary) => return Err(ctx.parse(None, "binary data, not a JSON tag file")),
        None => {}
    }
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let list = (&mut de).deserialize_map(TagFile).and_then(|list| de.end().map(|()| list));
    list.map_err(|e| json_error(&e, ctx))
}

/// A serde_json error as a parse error: its line in the field, its message
/// without serde_json's " at line L column C" suffix, on one line.
fn json_error(e: &serde_json::Error, ctx: Ctx<'_>) -> IoError {
    let full = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    let message = full.strip_suffix(&suffix).unwrap_or(&full);
    let line = (e.line() > 0).then_some(e.line());
    ctx.parse(line, escape_controls(message.into()).into_owned())
}

/// The top-level object.
struct TagFile;

impl<'de> Visitor<'de> for TagFile {
    type Value = TagList;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(
            r#"a tag object {"creases": [[v0, v1, sharpness], …], "corners": [[v, sharpness], …], "holes": [f, …]}"#,
        )
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<TagList, A::Error> {
        let mut list = TagList::default();
        let (mut creases, mut corners, mut holes) = (false, false, false);
        while let Some(key) = map.next_key::<String>()? {
            let seen = match key.as_str() {
                "creases" => &mut creases,
                "corners" => &mut corners,
                "holes" => &mut holes,
                other => {
                    return Err(A::Error::custom(format!(
                        r#"unknown key "{}" (a tag file has "creases", "corners" and "holes")"#,
                        show(other.as_bytes())
                    )))
                }
            };
            if std::mem::replace(seen, true) {
                return Err(A::Error::custom(format!(r#"key "{key}" appears twice"#)));
            }
            match key.as_str() {
                "creases" => {
                    list.creases =
                        map.next_value_seed(Entries { key: "creases", shape: "[v0, v1, sharpness]", convert: crease })?
                }
                "corners" => {
                    list.corners =
                        map.next_value_seed(Entries { key: "corners", shape: "[v, sharpness]", convert: corner })?
                }
                _ => {
                    let faces = map.next_value::<Vec<Value>>()?;
                    list.holes = (faces.iter().enumerate())
                        .map(|(k, f)| index(f, "face index").map_err(|m| A::Error::custom(format!("holes[{k}]: {m}"))))
                        .collect::<Result<_, _>>()?;
                }
            }
        }
        Ok(list)
    }
}

/// The entries of one list, converted one at a time as they are parsed.
struct Entries<T> {
    key: &'static str,
    shape: &'static str,
    convert: fn(&[Value]) -> Result<T, String>,
}

// Not derived: a derive would ask `T: Copy`, and only the function pointer is copied.
impl<T> Clone for Entries<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for Entries<T> {}

impl<'de, T> DeserializeSeed<'de> for Entries<T> {
    type Value = Vec<T>;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Vec<T>, D::Error> {
        deserializer.deserialize_seq(self)
    }
}

impl<'de, T> Visitor<'de> for Entries<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, r#""{}" as an array of {} entries"#, self.key, self.shape)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        let mut out = Vec::new();
        while let Some(tag) = seq.next_element_seed(Entry { entries: self, index: out.len() })? {
            out.push(tag);
        }
        Ok(out)
    }
}

/// One entry, checked where it is parsed, so that an error carries the
/// entry's own line (serde_json gives an error the position of the value
/// being deserialized when it is raised).
struct Entry<T> {
    entries: Entries<T>,
    index: usize,
}

impl<'de, T> DeserializeSeed<'de> for Entry<T> {
    type Value = T;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<T, D::Error> {
        deserializer.deserialize_seq(self)
    }
}

impl<'de, T> Visitor<'de> for Entry<T> {
    type Value = T;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} for {}[{}]", self.entries.shape, self.entries.key, self.index)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<T, A::Error> {
        let mut items = Vec::with_capacity(3);
        while let Some(item) = seq.next_element::<Value>()? {
            items.push(item);
        }
        (self.entries.convert)(&items)
            .map_err(|message| A::Error::custom(format!("{}[{}]: {message}", self.entries.key, self.index)))
    }
}

fn crease(items: &[Value]) -> Result<EdgeTag, String> {
    let [a, b, s] = items else {
        return Err(format!("expected [v0, v1, sharpness], found {} values", items.len()));
    };
    Ok(EdgeTag { a: vertex(a)?, b: vertex(b)?, sharpness: sharpness(s)? })
}

fn corner(items: &[Value]) -> Result<VertexTag, String> {
    let [v, s] = items else {
        return Err(format!("expected [v, sharpness], found {} values", items.len()));
    };
    Ok(VertexTag { vertex: vertex(v)?, sharpness: sharpness(s)? })
}

/// A vertex index: an integer (integral numbers such as `3.0` included) in `0..2³²`.
fn vertex(value: &Value) -> Result<u32, String> {
    index(value, "vertex index")
}

/// An index (`what`: "vertex index", "face index"): an integer (integral
/// numbers such as `3.0` included) in `0..2³²`.
fn index(value: &Value, what: &str) -> Result<u32, String> {
    let Value::Number(n) = value else {
        return Err(format!("{what} {} is not a number", brief(value)));
    };
    if let Some(u) = n.as_u64() {
        return u32::try_from(u).map_err(|_| format!("{what} {u} out of range (at most {})", u32::MAX));
    }
    if let Some(i) = n.as_i64() {
        return Err(format!("{what} {i} is negative"));
    }
    let x = n.as_f64().unwrap_or(f64::NAN);
    if x.fract() != 0.0 {
        Err(format!("{what} {n} is not an integer"))
    } else if x < 0.0 {
        Err(format!("{what} {n} is negative"))
    } else if x > f64::from(u32::MAX) {
        Err(format!("{what} {n} out of range (at most {})", u32::MAX))
    } else {
        Ok(x as u32)
    }
}

/// A sharpness: a number ≥ 0, as the nearest `f32`.
fn sharpness(value: &Value) -> Result<f32, String> {
    match value.as_f64() {
        Some(s) if s >= 0.0 => Ok(s as f32),
        Some(_) => Err(format!("sharpness {} is negative", brief(value))),
        None => Err(format!("sharpness {} is not a number", brief(value))),
    }
}

/// A JSON value for a message, cut to a readable length.
fn brief(value: &Value) -> String {
    show(value.to_string().as_bytes()).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_keys_are_optional_and_order_is_kept() {
        assert_eq!(parse_tag_json("{}").unwrap(), TagList::default());
        let list = parse_tag_json(r#"{"corners": [[3, 10], [0, 0.5]], "creases": [[0, 1, 2.5]]}"#).unwrap();
        assert_eq!(list.creases, vec![EdgeTag { a: 0, b: 1, sharpness: 2.5 }]);
        assert_eq!(
            list.corners,
            vec![VertexTag { vertex: 3, sharpness: 10.0 }, VertexTag { vertex: 0, sharpness: 0.5 }]
        );
    }

    #[test]
    fn integral_floats_are_indices_and_sharpness_rounds_to_f32() {
        let list = parse_tag_json(r#"{"creases": [[1.0, 4294967295, 0.1]]}"#).unwrap();
        assert_eq!(list.creases[0], EdgeTag { a: 1, b: u32::MAX, sharpness: 0.1f32 });
    }
}
