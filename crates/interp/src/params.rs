//! Parameter files of the methods' options: vertex subsets
//! ([`CommonOptions::subset`](crate::CommonOptions::subset)), prescribed
//! normals (Zheng-Cai, Deng-Wang), Brunet shape handles (Zheng-Cai) and
//! Fan-Cheng-Lai's per-face shape parameters λ ([`Shape::PerFace`](crate::Shape::PerFace)).
//!
//! Each parser takes the text of its file ([`parse_subset`],
//! [`parse_normals`], [`parse_handles`], [`parse_shape_file`]) and returns
//! exactly what the options take. This crate touches no file: the caller
//! reads it (the `subdiv` CLI through `subdiv_io::read_text`, which refuses
//! FIFOs and devices before opening them, caps the size and checks UTF-8)
//! and names it in the error ([`ParamFileError::with_path`]).
//!
//! | file | text form (one entry a line) | JSON form | result |
//! |---|---|---|---|
//! | subset | `i j k …` | `[i, j, k, …]` | `Vec<u32>` |
//! | normals | `i nx ny nz` | `{"i": [nx, ny, nz]}` | `Vec<Option<DVec3>>`, unit length |
//! | shape handles | `i S` | `{"i": S}` | `Vec<f64>`, default 1 |
//! | shape file | — | `{"default": λ, "faces": {"f": λ}, "groups": {"name": λ}}` | `Vec<f64>`, one λ per face |
//!
//! Vertex and face indices are 0-based. A text file has `#` comments and
//! separates its fields by whitespace or commas; a file whose first
//! non-blank character is `[` or `{` is JSON. A UTF-8 byte-order mark is
//! skipped (text read with `read_to_string` keeps it).
//!
//! Parsing is strict, because a parameter that is silently ignored gives a
//! wrong surface with no error: unknown keys, wrong shapes, numbers written as
//! strings, repeated entries (a JSON key given twice included, which a
//! generic JSON reader would collapse to the last) and files that set nothing
//! are errors. Every error is a [`ParamFileError`], one line that names the
//! parameter file, the line (text and JSON alike) and the offending item,
//! e.g. `normals.txt:7: vertex 12 is listed twice (first on line 3)`.
//!
//! ```
//! use subdiv_interp::params;
//! // Vertex 3's normal, scaled to unit length; the others are free.
//! let normals = params::parse_normals("3 0 0 2  # up\n", 8).unwrap();
//! assert_eq!(normals[3], Some(subdiv_mesh::DVec3::Z));
//! assert_eq!(normals[0], None);
//! let error = params::parse_normals("3 0 0 1\n3 0 1 0\n", 8).unwrap_err().with_path("normals.txt");
//! assert_eq!(error.to_string(), "normals.txt:2: vertex 3 is listed twice (first on line 1)");
//! ```

use serde::de::{DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use std::cell::Cell;
use std::collections::hash_map::{Entry as MapEntry, HashMap};
use std::fmt;
use std::hash::Hash;
use std::path::{Path, PathBuf};
use subdiv_mesh::{DVec3, Mesh};
use thiserror::Error;

/// The shape file's format, quoted in its messages.
const SHAPE_FORMAT: &str = r#"{"default": λ, "faces": {"face index": λ}, "groups": {"group name": λ}}"#;

/// Longest piece of user text quoted in a message (keys, fields, names).
const QUOTE_MAX_CHARS: usize = 40;

/// Group names listed when a group is not found.
const GROUPS_LISTED: usize = 10;

/// Why a parameter file (or its text) was refused.
///
/// Displayed on one line as `path:line: message`, `path: message` when no
/// line applies (an empty subset, a file that sets nothing), and
/// `line N: message` or the bare message for text that
/// [`with_path`](Self::with_path) did not name.
///
/// ```
/// use subdiv_interp::params;
/// let error = params::parse_handles("\n2 -1.5\n", 10).unwrap_err();
/// assert_eq!((error.line(), error.message()), (Some(2), "vertex 2: shape handle -1.5 must be positive"));
/// assert_eq!(error.to_string(), "line 2: vertex 2: shape handle -1.5 must be positive");
/// assert_eq!(error.with_path("h.txt").to_string(), "h.txt:2: vertex 2: shape handle -1.5 must be positive");
/// ```
#[derive(Debug, Error)]
#[error("{}", Shown(self))]
pub struct ParamFileError {
    path: Option<PathBuf>,
    line: Option<usize>,
    message: String,
}

impl ParamFileError {
    /// An error on no particular line.
    fn new(message: impl fmt::Display) -> Self {
        ParamFileError { path: None, line: None, message: message.to_string() }
    }

    /// The same error, naming `path` as the parameter file its text came
    /// from.
    pub fn with_path(mut self, path: impl Into<PathBuf>) -> Self {
        self.path = Some(path.into());
        self
    }

    /// The parameter file, when named.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The line (1-based) of the offending entry, when there is one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// What is wrong, without the path and the line.
    pub fn message(&self) -> &str {
        &self.message
    }
}

/// The display of a [`ParamFileError`].
struct Shown<'a>(&'a ParamFileError);

impl fmt::Display for Shown<'_> {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let ParamFileError { path, line, message } = self.0;
        match (path, line) {
            (Some(path), Some(line)) => write!(f, "{}:{line}: {message}", path.display()),
            (Some(path), None) => write!(f, "{}: {message}", path.display()),
            (None, Some(line)) => write!(f, "line {line}: {message}"),
            (None, None) => f.write_str(message),
        }
    }
}

/// `line: message`, the path added by the caller.
fn at(line: usize, message: impl fmt::Display) -> ParamFileError {
    ParamFileError { line: Some(line), ..ParamFileError::new(message) }
}

/// `text` without a leading UTF-8 byte-order mark.
fn without_bom(text: &str) -> &str {
    text.strip_prefix('\u{FEFF}').unwrap_or(text)
}

/// `"text"`, escaped (one line whatever it holds) and shortened; formatted
/// only when a message is, since labels are built for every entry.
struct Quoted<'a>(&'a str);

impl fmt::Display for Quoted<'_> {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self.0.char_indices().nth(QUOTE_MAX_CHARS) {
            Some((cut, _)) => write!(f, "{:?}…", &self.0[..cut]),
            None => write!(f, "{:?}", self.0),
        }
    }
}

fn quoted(text: &str) -> Quoted<'_> {
    Quoted(text)
}

fn is_json(text: &str) -> bool {
    matches!(text.trim_start().chars().next(), Some('[' | '{'))
}

/// What an index counts.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Vertex,
    Face,
}

impl Kind {
    fn one(self) -> &'static str {
        match self {
            Kind::Vertex => "vertex",
            Kind::Face => "face",
        }
    }
    fn many(self) -> &'static str {
        match self {
            Kind::Vertex => "vertices",
            Kind::Face => "faces",
        }
    }
    fn not_an_index(self, shown: &str) -> String {
        format!("{shown} is not a {} index (0-based, non-negative integers)", self.one())
    }
    fn out_of_range(self, shown: &str, count: usize) -> String {
        format!("{} {shown} is out of range (the mesh has {count} {}, 0-based)", self.one(), self.many())
    }
    fn checked(self, index: u64, shown: &str, count: usize) -> Result<u32, String> {
        match u32::try_from(index) {
            Ok(i) if (i as usize) < count => Ok(i),
            _ => Err(self.out_of_range(shown, count)),
        }
    }

    /// An index written as text: a text-file field or a JSON key.
    fn parse(self, field: &str, count: usize) -> Result<u32, String> {
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        if digits(field) {
            // All digits but too long for u64: still an index, just out of range.
            return self.checked(field.parse().unwrap_or(u64::MAX), field, count);
        }
        // A number ("-1", "2.5") is shown as written, anything else quoted.
        let numeric = field.parse::<f64>().is_ok();
        Err(self.not_an_index(&if numeric { field.to_owned() } else { quoted(field).to_string() }))
    }

    /// An index written as a JSON value (the subset array).
    fn of_node(self, node: &Node, count: usize) -> Result<u32, String> {
        match &node.json {
            Json::Unsigned(i) => self.checked(*i, &i.to_string(), count),
            Json::Negative(i) => Err(self.not_an_index(&i.to_string())),
            // serde_json reads integers beyond u64 as floats.
            Json::Float(x) if *x >= u64::MAX as f64 => Err(self.out_of_range(&format!("{x:?}"), count)),
            Json::Float(x) => Err(self.not_an_index(&format!("{x:?}"))),
            Json::String(s) => {
                Err(format!("{} is a string, not a {} index (write it without quotes)", quoted(s), self.one()))
            }
            other => Err(self.not_an_index(other.kind())),
        }
    }
}

/// The line `key` was first seen on, if it was: a repeated entry is an
/// error, never "the last one wins".
fn repeated<K: Hash + Eq>(seen: &mut HashMap<K, usize>, key: K, line: usize) -> Option<usize> {
    match seen.entry(key) {
        MapEntry::Occupied(first) => Some(*first.get()),
        MapEntry::Vacant(slot) => {
            slot.insert(line);
            None
        }
    }
}

/// Numeric lines of a text file: `(line number, fields)`, comments and blank lines skipped.
fn text_rows(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, line)| {
        let line = line.split('#').next().unwrap_or("").trim();
        (!line.is_empty())
            .then(|| (i + 1, line.split(|c: char| c.is_whitespace() || c == ',').filter(|s| !s.is_empty()).collect()))
    })
}

fn number(field: &str) -> Result<f64, String> {
    let x: f64 = field.parse().map_err(|_| format!("{} is not a number", quoted(field)))?;
    if !x.is_finite() {
        return Err(format!("{} is not finite", quoted(field)));
    }
    Ok(x)
}

/// A JSON value and the line it starts on. Unlike `serde_json::Value`,
/// objects keep every entry in file order, so a repeated key is reported
/// instead of silently keeping the last.
#[derive(Debug)]
struct Node {
    line: usize,
    json: Json,
}

#[derive(Debug)]
enum Json {
    Null,
    Bool,
    Unsigned(u64),
    Negative(i64),
    Float(f64),
    String(String),
    Array(Vec<Node>),
    Object(Vec<Member>),
}

/// `"key": value`, with the key's line.
#[derive(Debug)]
struct Member {
    key: String,
    line: usize,
    value: Node,
}

impl Json {
    fn kind(&self) -> &'static str {
        match self {
            Json::Null => "null",
            Json::Bool => "a boolean",
            Json::Unsigned(_) | Json::Negative(_) | Json::Float(_) => "a number",
            Json::String(_) => "a string",
            Json::Array(_) => "an array",
            Json::Object(_) => "an object",
        }
    }
}

impl Node {
    /// A finite number (serde_json refuses literals beyond f64).
    fn number(&self) -> Result<f64, String> {
        match &self.json {
            Json::Unsigned(i) => Ok(*i as f64),
            Json::Negative(i) => Ok(*i as f64),
            Json::Float(x) => Ok(*x),
            Json::String(s) => Err(format!("{} is a string, expected a number (write it without quotes)", quoted(s))),
            other => Err(format!("expected a number, found {}", other.kind())),
        }
    }
}

/// The line serde_json is on, fed by [`TrackedReader`].
///
/// serde_json reads at most one byte ahead of the token it hands a visitor
/// (to see where a number ends), so the line is counted over every byte
/// handed out but the last: then it is the line of the token just read.
#[derive(Default)]
struct LineTracker {
    line: Cell<usize>,
    last_was_newline: Cell<bool>,
}

impl LineTracker {
    fn line(&self) -> usize {
        1 + self.line.get()
    }
}

/// Hands serde_json the text one byte at a time, counting lines.
struct TrackedReader<'a> {
    rest: &'a [u8],
    tracker: &'a LineTracker,
}

impl std::io::Read for TrackedReader<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let (Some((&byte, rest)), Some(slot)) = (self.rest.split_first(), buf.first_mut()) else { return Ok(0) };
        let t = self.tracker;
        if t.last_was_newline.get() {
            t.line.set(t.line.get() + 1);
        }
        t.last_was_newline.set(byte == b'\n');
        *slot = byte;
        self.rest = rest;
        Ok(1)
    }
}

/// Builds a [`Node`] from serde_json's events.
#[derive(Clone, Copy)]
struct NodeSeed<'a>(&'a LineTracker);

impl NodeSeed<'_> {
    fn node(self, json: Json) -> Node {
        Node { line: self.0.line(), json }
    }
}

impl<'de> DeserializeSeed<'de> for NodeSeed<'_> {
    type Value = Node;
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Node, D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for NodeSeed<'_> {
    type Value = Node;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_unit<E>(self) -> Result<Node, E> {
        Ok(self.node(Json::Null))
    }
    fn visit_bool<E>(self, _: bool) -> Result<Node, E> {
        Ok(self.node(Json::Bool))
    }
    fn visit_u64<E>(self, i: u64) -> Result<Node, E> {
        Ok(self.node(Json::Unsigned(i)))
    }
    fn visit_i64<E>(self, i: i64) -> Result<Node, E> {
        Ok(self.node(if i >= 0 { Json::Unsigned(i as u64) } else { Json::Negative(i) }))
    }
    fn visit_f64<E>(self, x: f64) -> Result<Node, E> {
        Ok(self.node(Json::Float(x)))
    }
    fn visit_str<E>(self, s: &str) -> Result<Node, E> {
        Ok(self.node(Json::String(s.to_owned())))
    }
    fn visit_string<E>(self, s: String) -> Result<Node, E> {
        Ok(self.node(Json::String(s)))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Node, A::Error> {
        let line = self.0.line();
        let mut items = Vec::new();
        while let Some(item) = seq.next_element_seed(self)? {
            items.push(item);
        }
        Ok(Node { line, json: Json::Array(items) })
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Node, A::Error> {
        let line = self.0.line();
        let mut members = Vec::new();
        while let Some(key) = map.next_key::<String>()? {
            let key_line = self.0.line();
            let value = map.next_value_seed(self)?;
            members.push(Member { key, line: key_line, value });
        }
        Ok(Node { line, json: Json::Object(members) })
    }
}

/// Parses JSON text into [`Node`]s; syntax errors give the line and column.
fn parse_json(text: &str) -> Result<Node, ParamFileError> {
    let tracker = LineTracker::default();
    let mut de = serde_json::Deserializer::from_reader(TrackedReader { rest: text.as_bytes(), tracker: &tracker });
    let node = NodeSeed(&tracker).deserialize(&mut de).and_then(|node| de.end().map(|()| node));
    node.map_err(|e| {
        let position = format!(" at line {} column {}", e.line(), e.column());
        let message = e.to_string();
        let message = message.strip_suffix(&position).unwrap_or(&message);
        at(e.line(), format_args!("invalid JSON: {message} (column {})", e.column()))
    })
}

/// The vertex subset in `text` (a subset file's contents), for a mesh of
/// `n` vertices: vertex indices (0-based),
/// whitespace or comma separated (`#` comments), or a JSON array; each vertex
/// at most once, at least one. For [`CommonOptions::subset`](crate::CommonOptions::subset).
///
/// ```
/// use subdiv_interp::params;
/// assert_eq!(params::parse_subset("0 1\n# comment\n2,3 # tail\n", 8).unwrap(), [0, 1, 2, 3]);
/// assert_eq!(params::parse_subset("[0, 5, 7]", 8).unwrap(), [0, 5, 7]);
/// assert_eq!(
///     params::parse_subset("0 1\n2 1", 8).unwrap_err().to_string(),
///     "line 2: vertex 1 is listed twice (first on line 1)"
/// );
/// ```
pub fn parse_subset(text: &str, n: usize) -> Result<Vec<u32>, ParamFileError> {
    subset_from(without_bom(text), n)
}

fn subset_from(text: &str, n: usize) -> Result<Vec<u32>, ParamFileError> {
    let mut out = Vec::new();
    let mut seen = HashMap::new();
    let mut add = |v: u32, line: usize| match repeated(&mut seen, v, line) {
        Some(first) => Err(at(line, format_args!("vertex {v} is listed twice (first on line {first})"))),
        None => {
            out.push(v);
            Ok(())
        }
    };
    if is_json(text) {
        let root = parse_json(text)?;
        let Json::Array(items) = &root.json else {
            return Err(at(
                root.line,
                format_args!("expected a JSON array of vertex indices, found {}", root.json.kind()),
            ));
        };
        for item in items {
            add(Kind::Vertex.of_node(item, n).map_err(|e| at(item.line, e))?, item.line)?;
        }
    } else {
        for (line, fields) in text_rows(text) {
            for field in fields {
                add(Kind::Vertex.parse(field, n).map_err(|e| at(line, e))?, line)?;
            }
        }
    }
    if out.is_empty() {
        return Err(ParamFileError::new("the subset is empty: the file lists no vertex index"));
    }
    Ok(out)
}

/// One line of a per-vertex file: the vertex and its `W` numbers.
struct VertexValues<const W: usize> {
    vertex: u32,
    line: usize,
    values: [f64; W],
}

/// How a per-vertex file spells one entry, for its messages.
struct PerVertexFormat {
    /// What the file gives, plural ("normals").
    what: &'static str,
    /// A text line ("i nx ny nz").
    text: &'static str,
    /// A JSON value ("an array [nx, ny, nz]").
    json: &'static str,
}

/// Per-vertex values from lines `i x…` (`W` numbers) or JSON `{"i": x}` (`W`
/// = 1) / `{"i": [x…]}`; each vertex at most once, at least one.
fn per_vertex<const W: usize>(
    text: &str,
    n: usize,
    format: &PerVertexFormat,
) -> Result<Vec<VertexValues<W>>, ParamFileError> {
    let mut out = Vec::new();
    let mut seen = HashMap::new();
    let mut add = |vertex: u32, line: usize, values: [f64; W]| match repeated(&mut seen, vertex, line) {
        Some(first) => Err(at(line, format_args!("vertex {vertex} is listed twice (first on line {first})"))),
        None => {
            out.push(VertexValues { vertex, line, values });
            Ok(())
        }
    };
    if is_json(text) {
        let root = parse_json(text)?;
        let Json::Object(members) = &root.json else {
            return Err(at(
                root.line,
                format_args!(
                    "expected a JSON object {{\"vertex index\": {}}}, found {}",
                    format.json,
                    root.json.kind()
                ),
            ));
        };
        for Member { key, line, value } in members {
            let vertex = Kind::Vertex.parse(key, n).map_err(|e| at(*line, e))?;
            let values = json_values::<W>(value, format.json)
                .map_err(|e| at(value.line, format_args!("vertex {vertex}: {e}")))?;
            add(vertex, *line, values)?;
        }
    } else {
        for (line, fields) in text_rows(text) {
            if fields.len() != W + 1 {
                return Err(at(
                    line,
                    format_args!(
                        "expected \"{}\", found {} field{}",
                        format.text,
                        fields.len(),
                        if fields.len() == 1 { "" } else { "s" }
                    ),
                ));
            }
            let vertex = Kind::Vertex.parse(fields[0], n).map_err(|e| at(line, e))?;
            let mut values = [0.0; W];
            for (slot, field) in values.iter_mut().zip(&fields[1..]) {
                *slot = number(field).map_err(|e| at(line, format_args!("vertex {vertex}: {e}")))?;
            }
            add(vertex, line, values)?;
        }
    }
    if out.is_empty() {
        return Err(ParamFileError::new(format_args!("no {} given: the file lists no vertex", format.what)));
    }
    Ok(out)
}

/// The `W` numbers of one JSON entry: a number when `W` = 1, else an array of `W`.
fn json_values<const W: usize>(node: &Node, expected: &str) -> Result<[f64; W], String> {
    let mut values = [0.0; W];
    match &node.json {
        Json::Array(items) if W > 1 && items.len() == W => {
            for (slot, item) in values.iter_mut().zip(items) {
                *slot = item.number()?;
            }
        }
        Json::Array(items) if W > 1 => return Err(format!("expected {expected}, found an array of {}", items.len())),
        Json::String(_) | Json::Unsigned(_) | Json::Negative(_) | Json::Float(_) if W == 1 => {
            values[0] = node.number()?
        }
        other => return Err(format!("expected {expected}, found {}", other.kind())),
    }
    Ok(values)
}

/// Per-vertex normals in `text` (a normals file's contents): lines `i nx ny nz` or JSON
/// `{"i": [nx, ny, nz]}`, for a mesh of `n` vertices; each normal is scaled
/// to unit length, zero vectors are refused, unlisted vertices are `None`.
/// For Zheng-Cai's and Deng-Wang's `normals`.
///
/// ```
/// use subdiv_interp::params;
/// use subdiv_mesh::DVec3;
/// let normals = params::parse_normals(r#"{"1": [0, 1e200, 0]}"#, 3).unwrap();
/// assert_eq!(normals, [None, Some(DVec3::Y), None]);
/// assert_eq!(params::parse_normals("1 0 0 0", 3).unwrap_err().message(), "vertex 1: the normal is zero");
/// ```
pub fn parse_normals(text: &str, n: usize) -> Result<Vec<Option<DVec3>>, ParamFileError> {
    normals_from(without_bom(text), n)
}

fn normals_from(text: &str, n: usize) -> Result<Vec<Option<DVec3>>, ParamFileError> {
    let format = PerVertexFormat { what: "normals", text: "i nx ny nz", json: "an array [nx, ny, nz]" };
    let mut out = vec![None; n];
    for VertexValues { vertex, line, values } in per_vertex::<3>(text, n, &format)? {
        let normal = DVec3::from_array(values);
        // Scaled by the largest component first, so that neither 1e200 (whose
        // length overflows) nor 1e-170 (whose squares underflow) becomes zero.
        let scale = normal.abs().max_element();
        if scale == 0.0 {
            return Err(at(line, format_args!("vertex {vertex}: the normal is zero")));
        }
        out[vertex as usize] = Some((normal / scale).normalize());
    }
    Ok(out)
}

/// Per-vertex Brunet shape handles in `text` (a handles file's contents): lines `i S` or
/// JSON `{"i": S}`, for a mesh of `n` vertices; S must be positive (and
/// finite), unlisted vertices keep 1. For Zheng-Cai's `handles`.
///
/// ```
/// use subdiv_interp::params;
/// assert_eq!(params::parse_handles("2 0.5\n3 4", 4).unwrap(), [1.0, 1.0, 0.5, 4.0]);
/// assert_eq!(
///     params::parse_handles(r#"{"2": "0.5"}"#, 4).unwrap_err().to_string(),
///     r#"line 1: vertex 2: "0.5" is a string, expected a number (write it without quotes)"#
/// );
/// ```
pub fn parse_handles(text: &str, n: usize) -> Result<Vec<f64>, ParamFileError> {
    handles_from(without_bom(text), n)
}

fn handles_from(text: &str, n: usize) -> Result<Vec<f64>, ParamFileError> {
    let format = PerVertexFormat { what: "shape handles", text: "i S", json: "a number S" };
    let mut out = vec![1.0; n];
    for VertexValues { vertex, line, values: [s] } in per_vertex::<1>(text, n, &format)? {
        if s <= 0.0 {
            return Err(at(line, format_args!("vertex {vertex}: shape handle {s} must be positive")));
        }
        out[vertex as usize] = s;
    }
    Ok(out)
}

/// Fan-Cheng-Lai's per-face shape parameters λ in `text` (a shape file's
/// contents), JSON `{"default": λ, "faces": {"f": λ}, "groups": {"name": λ}}`:
/// groups are the mesh's face groups ([`Mesh::groups`], OBJ `g`/`o` names),
/// faces override groups, groups the default (½ when not given). Every λ in
/// (0, 1); at least one key must set something. For
/// [`Shape::PerFace`](crate::Shape::PerFace).
///
/// ```
/// use subdiv_interp::params;
/// use subdiv_mesh::shapes;
/// assert_eq!(params::parse_shape_file(r#"{"default": 0.25}"#, &shapes::cube()).unwrap(), [0.25; 6]);
/// assert_eq!(
///     params::parse_shape_file("{\"default\": 0.5,\n \"facez\": {}}", &shapes::cube()).unwrap_err().to_string(),
///     r#"line 2: unknown key "facez" (allowed: default, faces, groups)"#
/// );
/// ```
pub fn parse_shape_file(text: &str, mesh: &Mesh) -> Result<Vec<f64>, ParamFileError> {
    shape_from(without_bom(text), mesh)
}

/// λ of one shape entry, checked against the open interval the two-phase scheme needs.
fn lambda(node: &Node, label: impl fmt::Display) -> Result<f64, ParamFileError> {
    let l = node.number().map_err(|e| at(node.line, format_args!("{label}: {e}")))?;
    if !(l > 0.0 && l < 1.0) {
        return Err(at(node.line, format_args!("{label}: λ = {l} is outside (0, 1)")));
    }
    Ok(l)
}

/// The members of the object under `key`, or an error naming the key and the expected shape.
fn members<'a>(key: &str, node: &'a Node, shape: &str) -> Result<&'a [Member], ParamFileError> {
    match &node.json {
        Json::Object(members) => Ok(members),
        other => Err(at(node.line, format_args!("\"{key}\" must be an object {shape}, not {}", other.kind()))),
    }
}

fn shape_from(text: &str, mesh: &Mesh) -> Result<Vec<f64>, ParamFileError> {
    let sets_nothing = |line| at(line, "shape file sets nothing: expected at least one of default, faces, groups");
    if text.trim().is_empty() {
        return Err(ParamFileError::new(format_args!("the file is empty; expected JSON {SHAPE_FORMAT}")));
    }
    let root = parse_json(text)?;
    let top = match &root.json {
        Json::Object(members) => members,
        Json::Null => return Err(sets_nothing(root.line)),
        other => {
            return Err(at(root.line, format_args!("expected a JSON object {SHAPE_FORMAT}, found {}", other.kind())))
        }
    };
    let (mut default, mut faces, mut groups): (Option<&Node>, &[Member], &[Member]) = (None, &[], &[]);
    let mut keys = HashMap::new();
    for Member { key, line, value } in top {
        if let Some(first) = repeated(&mut keys, key.as_str(), *line) {
            return Err(at(*line, format_args!("key {} is given twice (first on line {first})", quoted(key))));
        }
        match key.as_str() {
            "default" => default = Some(value),
            "faces" => faces = members(key, value, r#"{"face index": λ}"#)?,
            "groups" => groups = members(key, value, r#"{"group name": λ}"#)?,
            _ => return Err(at(*line, format_args!("unknown key {} (allowed: default, faces, groups)", quoted(key)))),
        }
    }
    if default.is_none() && faces.is_empty() && groups.is_empty() {
        return Err(sets_nothing(root.line));
    }
    let default = default.map(|node| lambda(node, "\"default\"")).transpose()?.unwrap_or(0.5);
    let nf = mesh.topology().face_count();
    let mut lambdas = vec![default; nf];
    if !groups.is_empty() {
        let mesh_groups = mesh.groups();
        let id_of: HashMap<&str, usize> = mesh_groups.names.iter().enumerate().map(|(i, g)| (g.as_str(), i)).collect();
        let mut group_lambda = vec![None; mesh_groups.names.len()];
        let mut seen = HashMap::new();
        for Member { key: name, line, value } in groups {
            if let Some(first) = repeated(&mut seen, name.as_str(), *line) {
                return Err(at(*line, format_args!("group {} is listed twice (first on line {first})", quoted(name))));
            }
            let Some(&id) = id_of.get(name.as_str()) else {
                return Err(at(
                    *line,
                    format_args!("group {} is not in the mesh ({})", quoted(name), group_list(&mesh_groups.names)),
                ));
            };
            group_lambda[id] = Some(lambda(value, format_args!("group {}", quoted(name)))?);
        }
        // One pass over the faces, however many groups.
        for (l, &id) in lambdas.iter_mut().zip(&mesh_groups.face_group) {
            if let Some(Some(group)) = group_lambda.get(id as usize) {
                *l = *group;
            }
        }
    }
    let mut seen = HashMap::new();
    for Member { key, line, value } in faces {
        let f = Kind::Face.parse(key, nf).map_err(|e| at(*line, e))?;
        if let Some(first) = repeated(&mut seen, f, *line) {
            return Err(at(*line, format_args!("face {f} is listed twice (first on line {first})")));
        }
        lambdas[f as usize] = lambda(value, format_args!("face {f}"))?;
    }
    Ok(lambdas)
}

/// "it has: a, b, c" (the first few) or "the mesh has no groups".
fn group_list(names: &[String]) -> String {
    if names.is_empty() {
        return "the mesh has no groups".into();
    }
    let listed: Vec<String> = names.iter().take(GROUPS_LISTED).map(|g| quoted(g).to_string()).collect();
    let more = if names.len() > GROUPS_LISTED { format!(", … ({} in all)", names.len()) } else { String::new() };
    format!("it has: {}{more}", listed.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{shapes, FaceGroups};

    /// The message of a parse that must fail.
    fn error<T: fmt::Debug>(result: Result<T, ParamFileError>) -> String {
        let message = result.expect_err("must fail").to_string();
        assert!(!message.contains('\n'), "one line: {message}");
        message
    }

    /// The result of parsing the text of the file `name`.
    fn in_file<T>(name: &str, result: Result<T, ParamFileError>) -> Result<T, ParamFileError> {
        result.map_err(|e| e.with_path(name))
    }

    fn subset_of(text: &str, n: usize) -> Result<Vec<u32>, ParamFileError> {
        in_file("s.txt", subset_from(text, n))
    }

    /// A cube whose top face (0) is group "top" and the others "sides".
    fn grouped_cube() -> Mesh {
        let mut soup = shapes::cube().into_soup();
        soup.groups = FaceGroups { names: vec!["top".into(), "sides".into()], face_group: vec![0, 1, 1, 1, 1, 1] };
        Mesh::from_soup(soup).unwrap().0
    }

    fn shape_of(text: &str) -> Result<Vec<f64>, ParamFileError> {
        in_file("shape.json", shape_from(text, &grouped_cube()))
    }

    #[test]
    fn subset_reads_text_and_json() {
        assert_eq!(subset_of("0 1\n# comment\n2,3 # tail\n", 8).unwrap(), [0, 1, 2, 3]);
        assert_eq!(subset_of("[0, 5,\n 7]", 8).unwrap(), [0, 5, 7]);
    }

    #[test]
    fn empty_subset_is_an_error() {
        for text in ["", "\n  \n", "# only a comment\n"] {
            assert_eq!(error(subset_of(text, 8)), "s.txt: the subset is empty: the file lists no vertex index");
        }
        assert_eq!(error(subset_of(" [ ] ", 8)), "s.txt: the subset is empty: the file lists no vertex index");
    }

    #[test]
    fn subset_vertex_listed_twice_names_both_lines() {
        assert_eq!(error(subset_of("0 1\n\n2 1\n", 8)), "s.txt:3: vertex 1 is listed twice (first on line 1)");
        assert_eq!(error(subset_of("4 4", 8)), "s.txt:1: vertex 4 is listed twice (first on line 1)");
        assert_eq!(error(subset_of("[0,\n 1,\n 1]", 8)), "s.txt:3: vertex 1 is listed twice (first on line 2)");
    }

    /// serde_json reads one byte past a number; a number at the end of a
    /// line must still be on its own line, not the next.
    #[test]
    fn json_lines_are_exact_for_numbers_at_line_ends() {
        assert_eq!(error(subset_of("[\n0\n,\n0\n]", 8)), "s.txt:4: vertex 0 is listed twice (first on line 2)");
        assert_eq!(
            error(subset_of("[\r\n3,\r\n\r\n-1\r\n]", 8)),
            "s.txt:4: -1 is not a vertex index (0-based, non-negative integers)"
        );
    }

    #[test]
    fn subset_indices_must_be_non_negative_integers() {
        let not_an_index =
            |shown: &str| format!("s.txt:1: {shown} is not a vertex index (0-based, non-negative integers)");
        for (text, shown) in [
            ("-1", "-1"),
            ("2.5", "2.5"),
            ("1e3", "1e3"),
            ("x7", "\"x7\""),
            ("[-1]", "-1"),
            ("[2.5]", "2.5"),
            ("[2.0]", "2.0"),
            ("[null]", "null"),
            ("[[1]]", "an array"),
        ] {
            assert_eq!(error(subset_of(text, 8)), not_an_index(shown), "{text}");
        }
        assert_eq!(
            error(subset_of("[\"3\"]", 8)),
            "s.txt:1: \"3\" is a string, not a vertex index (write it without quotes)"
        );
        assert_eq!(
            error(subset_of("{\"0\": 1}", 8)),
            "s.txt:1: expected a JSON array of vertex indices, found an object"
        );
    }

    #[test]
    fn huge_indices_are_out_of_range_not_malformed() {
        let out_of_range =
            |shown: &str| format!("s.txt:1: vertex {shown} is out of range (the mesh has 8 vertices, 0-based)");
        assert_eq!(error(subset_of("8", 8)), out_of_range("8"));
        assert_eq!(error(subset_of("4294967296", 8)), out_of_range("4294967296"));
        assert_eq!(error(subset_of("99999999999999999999", 8)), out_of_range("99999999999999999999"));
        assert_eq!(error(subset_of("[8]", 8)), out_of_range("8"));
        assert_eq!(error(subset_of("[18446744073709551615]", 8)), out_of_range("18446744073709551615"));
        // Beyond u64 serde_json has only the float.
        assert_eq!(error(subset_of("[99999999999999999999]", 8)), out_of_range("1e20"));
    }

    fn normals_of(text: &str) -> Result<Vec<Option<DVec3>>, ParamFileError> {
        in_file("normals.txt", normals_from(text, 20))
    }

    #[test]
    fn normals_are_unit_vectors_even_at_extreme_scales() {
        let n = normals_of("0 0 0 2\n1, 1e200, 1e200, 0\n2 1e-170 0 1e-170\n3 5e-324 0 0\n").unwrap();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert_eq!(n[0], Some(DVec3::Z));
        for (v, expected) in [(1, DVec3::new(h, h, 0.0)), (2, DVec3::new(h, 0.0, h)), (3, DVec3::X)] {
            assert!(n[v].unwrap().abs_diff_eq(expected, 1e-15), "vertex {v}: {:?}", n[v]);
        }
        assert_eq!(n[4], None);
        let json = in_file("n.json", normals_from("{\"3\": [0, -1e300, 0]}", 20)).unwrap();
        assert_eq!(json[3], Some(DVec3::NEG_Y));
    }

    #[test]
    fn normal_listed_twice_names_both_lines() {
        assert_eq!(
            error(normals_of("3 0 0 1\n# x\n12 1 0 0\n\n\n\n12 0 1 0\n")),
            "normals.txt:7: vertex 12 is listed twice (first on line 3)"
        );
        // A repeated JSON key, which serde_json::Value would silently collapse to the last.
        assert_eq!(
            error(normals_of("{\n \"12\": [0, 0, 1],\n \"12\": [1, 0, 0]\n}")),
            "normals.txt:3: vertex 12 is listed twice (first on line 2)"
        );
        assert_eq!(
            error(normals_of("{\"12\": [0, 0, 1], \"012\": [1, 0, 0]}")),
            "normals.txt:1: vertex 12 is listed twice (first on line 1)"
        );
    }

    #[test]
    fn bad_normals_name_the_file_line_and_vertex() {
        for (text, message) in [
            ("4 0 0 0", "normals.txt:1: vertex 4: the normal is zero"),
            ("4 0 -0 0e5", "normals.txt:1: vertex 4: the normal is zero"),
            ("\n4 inf 0 1", "normals.txt:2: vertex 4: \"inf\" is not finite"),
            ("4 NaN 0 1", "normals.txt:1: vertex 4: \"NaN\" is not finite"),
            ("4 0 1", "normals.txt:1: expected \"i nx ny nz\", found 3 fields"),
            ("4 0 1 y", "normals.txt:1: vertex 4: \"y\" is not a number"),
            ("-4 0 0 1", "normals.txt:1: -4 is not a vertex index (0-based, non-negative integers)"),
            ("20 0 0 1", "normals.txt:1: vertex 20 is out of range (the mesh has 20 vertices, 0-based)"),
            ("{\"4\": [0, 0, 0]}", "normals.txt:1: vertex 4: the normal is zero"),
            (
                "{\"4\": [0, \"1\", 0]}",
                "normals.txt:1: vertex 4: \"1\" is a string, expected a number (write it without quotes)",
            ),
            ("{\"4\": [0, 1]}", "normals.txt:1: vertex 4: expected an array [nx, ny, nz], found an array of 2"),
            ("{\"4\": 1}", "normals.txt:1: vertex 4: expected an array [nx, ny, nz], found a number"),
            ("{\"4\": [0, null, 1]}", "normals.txt:1: vertex 4: expected a number, found null"),
            ("{\"x\": [0, 0, 1]}", "normals.txt:1: \"x\" is not a vertex index (0-based, non-negative integers)"),
            (
                "[[0, 0, 1]]",
                "normals.txt:1: expected a JSON object {\"vertex index\": an array [nx, ny, nz]}, found an array",
            ),
            ("", "normals.txt: no normals given: the file lists no vertex"),
            ("{}", "normals.txt: no normals given: the file lists no vertex"),
        ] {
            assert_eq!(error(normals_of(text)), message, "{text:?}");
        }
    }

    fn handles_of(text: &str) -> Result<Vec<f64>, ParamFileError> {
        in_file("h.txt", handles_from(text, 10))
    }

    #[test]
    fn handles_default_to_one_and_must_be_positive() {
        let h = handles_of("2 0.5\n7 3").unwrap();
        assert_eq!(h, [1.0, 1.0, 0.5, 1.0, 1.0, 1.0, 1.0, 3.0, 1.0, 1.0]);
        assert_eq!(handles_of("{\"2\": 0.5, \"7\": 3}").unwrap(), h);
        for (text, message) in [
            ("2 0", "h.txt:1: vertex 2: shape handle 0 must be positive"),
            ("2 -1.5", "h.txt:1: vertex 2: shape handle -1.5 must be positive"),
            ("2 inf", "h.txt:1: vertex 2: \"inf\" is not finite"),
            ("2 1\n2 1", "h.txt:2: vertex 2 is listed twice (first on line 1)"),
            ("{\"2\": 1,\n\"2\": 1}", "h.txt:2: vertex 2 is listed twice (first on line 1)"),
            ("{\"2\": \"0.5\"}", "h.txt:1: vertex 2: \"0.5\" is a string, expected a number (write it without quotes)"),
            ("{\"2\": [0.5]}", "h.txt:1: vertex 2: expected a number S, found an array"),
            ("{\"2\": -1}", "h.txt:1: vertex 2: shape handle -1 must be positive"),
            ("2", "h.txt:1: expected \"i S\", found 1 field"),
            ("# nothing\n", "h.txt: no shape handles given: the file lists no vertex"),
        ] {
            assert_eq!(error(handles_of(text)), message, "{text:?}");
        }
    }

    #[test]
    fn shape_file_sets_default_groups_and_faces() {
        assert_eq!(shape_of(r#"{"default": 0.3}"#).unwrap(), [0.3; 6]);
        // Faces override groups whatever their order in the file; groups override the default.
        let text = r#"{"faces": {"2": 0.9}, "groups": {"sides": 0.4}, "default": 0.3}"#;
        assert_eq!(shape_of(text).unwrap(), [0.3, 0.4, 0.9, 0.4, 0.4, 0.4]);
        assert_eq!(shape_of(r#"{"groups": {"top": 0.7}}"#).unwrap(), [0.7, 0.5, 0.5, 0.5, 0.5, 0.5]);
    }

    #[test]
    fn shape_file_that_sets_nothing_is_an_error() {
        let nothing = "shape.json:1: shape file sets nothing: expected at least one of default, faces, groups";
        for text in ["null", "{}", " { } ", r#"{"faces": {}}"#, r#"{"faces": {}, "groups": {}}"#] {
            assert_eq!(error(shape_of(text)), nothing, "{text}");
        }
        let not_an_object = |found: &str| format!("shape.json:1: expected a JSON object {SHAPE_FORMAT}, found {found}");
        assert_eq!(error(shape_of("[]")), not_an_object("an array"));
        assert_eq!(error(shape_of("0.5")), not_an_object("a number"));
        assert_eq!(error(shape_of("\"default\"")), not_an_object("a string"));
        assert_eq!(error(shape_of(" \n")), format!("shape.json: the file is empty; expected JSON {SHAPE_FORMAT}"));
    }

    #[test]
    fn shape_file_unknown_key_is_named_with_the_allowed_ones() {
        assert_eq!(
            error(shape_of("{\"default\": 0.5,\n \"facez\": {\"0\": 0.2}}")),
            "shape.json:2: unknown key \"facez\" (allowed: default, faces, groups)"
        );
        assert_eq!(
            error(shape_of(r#"{"Default": 0.5}"#)),
            "shape.json:1: unknown key \"Default\" (allowed: default, faces, groups)"
        );
        // User text is escaped and shortened: the message stays one line.
        let long = format!("{{\"a\\nb{}\": 1}}", "x".repeat(100));
        let message = error(shape_of(&long));
        assert!(message.starts_with(r#"shape.json:1: unknown key "a\nbxxx"#) && message.contains("…"), "{message}");
    }

    #[test]
    fn shape_file_wrong_shapes_name_the_key_and_the_expected_shape() {
        for (text, message) in [
            (r#"{"faces": [0.5]}"#, r#"shape.json:1: "faces" must be an object {"face index": λ}, not an array"#),
            (r#"{"faces": 0.5}"#, r#"shape.json:1: "faces" must be an object {"face index": λ}, not a number"#),
            (r#"{"groups": ["top"]}"#, r#"shape.json:1: "groups" must be an object {"group name": λ}, not an array"#),
            (
                r#"{"default": "0.5"}"#,
                r#"shape.json:1: "default": "0.5" is a string, expected a number (write it without quotes)"#,
            ),
            (r#"{"default": [0.5]}"#, r#"shape.json:1: "default": expected a number, found an array"#),
            (
                r#"{"faces": {"0": "0.5"}}"#,
                r#"shape.json:1: face 0: "0.5" is a string, expected a number (write it without quotes)"#,
            ),
            (r#"{"faces": {"0": {}}}"#, r#"shape.json:1: face 0: expected a number, found an object"#),
            (r#"{"groups": {"top": null}}"#, r#"shape.json:1: group "top": expected a number, found null"#),
        ] {
            assert_eq!(error(shape_of(text)), message, "{text}");
        }
    }

    /// λ ∈ (0, 1), as `CornerRule::validate` requires, checked at parse time with file and key.
    #[test]
    fn shape_lambdas_must_be_inside_the_open_unit_interval() {
        for (text, message) in [
            (r#"{"default": 0}"#, r#"shape.json:1: "default": λ = 0 is outside (0, 1)"#),
            (r#"{"default": 1}"#, r#"shape.json:1: "default": λ = 1 is outside (0, 1)"#),
            ("{\"faces\": {\n\"3\": 1.5}}", "shape.json:2: face 3: λ = 1.5 is outside (0, 1)"),
            (r#"{"groups": {"top": -0.25}}"#, r#"shape.json:1: group "top": λ = -0.25 is outside (0, 1)"#),
        ] {
            assert_eq!(error(shape_of(text)), message, "{text}");
        }
        assert_eq!(shape_of(r#"{"default": 1e-9, "faces": {"0": 0.999999}}"#).unwrap()[..2], [0.999999, 1e-9]);
    }

    #[test]
    fn shape_file_repeats_are_errors() {
        for (text, message) in [
            (
                "{\"default\": 0.5,\n\"default\": 0.6}",
                r#"shape.json:2: key "default" is given twice (first on line 1)"#,
            ),
            ("{\"faces\": {\"1\": 0.2,\n\"1\": 0.3}}", "shape.json:2: face 1 is listed twice (first on line 1)"),
            ("{\"faces\": {\"1\": 0.2, \"01\": 0.3}}", "shape.json:1: face 1 is listed twice (first on line 1)"),
            (
                "{\"groups\": {\"top\": 0.2,\n\n\"top\": 0.2}}",
                r#"shape.json:3: group "top" is listed twice (first on line 1)"#,
            ),
        ] {
            assert_eq!(error(shape_of(text)), message, "{text}");
        }
    }

    #[test]
    fn shape_file_faces_and_groups_must_exist() {
        for (text, message) in [
            (r#"{"faces": {"6": 0.5}}"#, "shape.json:1: face 6 is out of range (the mesh has 6 faces, 0-based)"),
            (r#"{"faces": {"-1": 0.5}}"#, "shape.json:1: -1 is not a face index (0-based, non-negative integers)"),
            (
                r#"{"faces": {"one": 0.5}}"#,
                r#"shape.json:1: "one" is not a face index (0-based, non-negative integers)"#,
            ),
            (
                r#"{"groups": {"bottom": 0.5}}"#,
                r#"shape.json:1: group "bottom" is not in the mesh (it has: "top", "sides")"#,
            ),
        ] {
            assert_eq!(error(shape_of(text)), message, "{text}");
        }
        let plain = in_file("shape.json", shape_from(r#"{"groups": {"top": 0.5}}"#, &shapes::cube()));
        assert_eq!(error(plain), r#"shape.json:1: group "top" is not in the mesh (the mesh has no groups)"#);
    }

    #[test]
    fn invalid_json_gives_line_and_column() {
        assert_eq!(
            error(shape_of("{\n\"default\": 0.5,,\n}")),
            "shape.json:2: invalid JSON: key must be a string (column 16)"
        );
        assert_eq!(
            error(shape_of(r#"{"default": 0.5} x"#)),
            "shape.json:1: invalid JSON: trailing characters (column 18)"
        );
        assert!(error(subset_of("[1, 2", 8)).starts_with("s.txt:1: invalid JSON: EOF while parsing a list"));
    }

    /// One group per face: applying groups face by face per group would be
    /// quadratic (10¹⁰ steps here); one pass is linear.
    #[test]
    fn many_groups_are_applied_in_linear_time() {
        let mut soup = shapes::quad_grid(320, 320).into_soup();
        let nf = soup.faces.len();
        soup.groups =
            FaceGroups { names: (0..nf).map(|f| format!("g{f}")).collect(), face_group: (0..nf as u32).collect() };
        let mesh = Mesh::from_soup(soup).unwrap().0;
        let entries: Vec<String> = (0..nf).map(|f| format!("\"g{f}\": {}", 0.1 + 0.8 * (f % 2) as f64)).collect();
        let text = format!("{{\"groups\": {{{}}}}}", entries.join(",\n"));
        let lambdas = in_file("shape.json", shape_from(&text, &mesh)).unwrap();
        assert_eq!(lambdas.len(), nf);
        assert!(lambdas.iter().enumerate().all(|(f, &l)| l == 0.1 + 0.8 * (f % 2) as f64));
    }

    /// Text parsed in memory: the same messages, with the line but no path
    /// until the caller names one.
    #[test]
    fn text_errors_have_the_line_and_no_path() {
        let e = parse_subset("0 1\n\n2 1\n", 8).unwrap_err();
        assert_eq!((e.path(), e.line(), e.message()), (None, Some(3), "vertex 1 is listed twice (first on line 1)"));
        assert_eq!(e.to_string(), "line 3: vertex 1 is listed twice (first on line 1)");
        assert_eq!(e.with_path("s.txt").to_string(), "s.txt:3: vertex 1 is listed twice (first on line 1)");
        let e = parse_normals("# none", 8).unwrap_err();
        assert_eq!((e.line(), e.to_string().as_str()), (None, "no normals given: the file lists no vertex"));
        assert_eq!(
            parse_shape_file(" ", &shapes::cube()).unwrap_err().to_string(),
            format!("the file is empty; expected JSON {SHAPE_FORMAT}")
        );
        assert_eq!(parse_handles("1 2", 3).unwrap(), [1.0, 2.0, 1.0]);
    }

    /// Text read by the caller (`read_to_string` keeps a BOM) parses as the file does.
    #[test]
    fn text_functions_skip_a_bom() {
        assert_eq!(parse_subset("\u{FEFF}0 1\n", 8).unwrap(), [0, 1]);
        assert_eq!(parse_normals("\u{FEFF}{\"1\": [0, 0, 3]}", 2).unwrap(), [None, Some(DVec3::Z)]);
        assert_eq!(parse_handles("\u{FEFF}1 2", 2).unwrap(), [1.0, 2.0]);
        assert_eq!(parse_shape_file("\u{FEFF}{\"default\": 0.25}", &shapes::cube()).unwrap(), [0.25; 6]);
    }
}
