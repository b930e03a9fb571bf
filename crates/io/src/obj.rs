//! Wavefront OBJ, read and written by hand.
//!
//! Read: `v x y z [w]` (further columns such as vertex colours ignored),
//! `vt u [v] [w]` (texture coordinates; `v` defaults to 0 as the OBJ spec
//! says, `w` is ignored), `f` with `v`, `v/vt`, `v/vt/vn` or `v//vn` corners
//! and negative (relative) indices for `v` and `vt`, `g`/`o` names recorded
//! as face groups, and OpenSubdiv's tag lines (below); `vn` (normals are
//! recomputed), `s`, `usemtl`, `mtllib`, `l`, `p` and unknown statements are
//! ignored. `#` starts a comment anywhere, `\` at the end of a line
//! continues it, CRLF is accepted, a UTF-8 byte-order mark is skipped.
//! UTF-16 and binary data are reported as such (from the first 4 KiB, and
//! from any statement keyword holding a control character), not read as
//! unknown statements.
//!
//! Files of 1 MiB or more are first cut at line ends into chunks parsed on
//! every thread by the same statement functions ([`chunks`]); a file with
//! what a chunk cannot read alone (relative indices, `t` lines, `\`
//! continuations, faces with and without `vt`, any error) is read again
//! from the start by the serial reader, so results, errors and warnings
//! never depend on the path taken.
//!
//! Texture coordinates become [`PolygonSoup::uvs`]: the `vt` pool and, per
//! face corner, its 0-based `vt` index, when every face gives them. A face
//! that gives them for some corners only is a parse error; a file in which
//! whole faces have them and others do not (several exported objects, only
//! some with a UV map) is read without them, with
//! [`ReadWarning::UvsDropped`]. `vt` lines that no face uses give no channel.
//!
//! Tags ([`PolygonSoup::tags`]), as OpenSubdiv's regression shapes write
//! them (`regression/common/shape_utils.cpp`): `t NAME NI/NF/NS` followed by
//! NI integers, NF floats and NS strings.
//! - `t crease NI/NF/0 a b [c d …] s…`: the integers are vertex pairs
//!   (0-based), each pair an edge: `t crease 4/1/0 a b c d s` tags the edges
//!   a-b and c-d, not a chain. NF is 1 (one sharpness for every pair) or
//!   NI/2 (pair k gets float k).
//! - `t corner NI/NF/0 v… s…`: corner sharpness of vertices (0-based); NF is
//!   1 or NI.
//! - `t hole NI/0/0 f…`: faces (0-based) that are holes
//!   ([`TagList::holes`]).
//! - OpenSubdiv's option tags, as its regression harness reads them
//!   (`far_utils.h`, `GetSdcOptions`) into [`TagList::options`]:
//!   `interpolateboundary 1/0/0 K` (0 none, 1 edge-and-corner, 2
//!   edge-only), `facevaryinginterpolateboundary 1/0/0 K` (0 linear-none …
//!   5 linear-all), `creasemethod 0/0/1 normal|chaikin`, `smoothtriangles
//!   0/0/1 catmark|smooth`; another value is a parse error.
//! - `facevaryingpropagatecorners` is refused (a parse error: OpenSubdiv 3
//!   has no such option).
//! - Any other name (the hierarchical edits `vertexedit`, `edgeedit`,
//!   `faceedit`, which OpenSubdiv 3 does not apply either, …) is checked for
//!   form and not applied, with a warning naming it
//!   ([`ReadWarning::TagsIgnored`]).
//!
//! A `t` line whose counts do not match its values, a crease with an odd
//! number of integers, a float count other than those above, a value that is
//! not a number, or a vertex index that is negative or beyond `u32` is a
//! parse error naming the line. Sharpness is read as `f32` (as OpenSubdiv
//! stores it) and passed through unchecked: a negative or NaN value, or a
//! pair that is not an edge, is for the validator (`subdiv_mesh::Tags`).
//!
//! Not `tobj`: it renumbers vertices per model in order of first use and
//! drops unreferenced ones, which loses the input vertex order (the order
//! interpolation results are reported in) and the isolated vertices the
//! validator must see.
//!
//! Write: `v` with the shortest decimal form that parses back to the same
//! `f64` bits, `vn` when normals are given, `vt` (same form) when texture
//! coordinates are given, 1-based `f` lines (`f a/t`, `f a//a` with normals,
//! `f a/t/a` with both), then one `t crease 2/1/0 a b s` line per crease tag
//! and one `t corner 1/1/0 v s` line per corner tag, sharpness in the
//! shortest form that reads back to the same `f32`, `t hole` lines, and the
//! option tags of the options the mesh carries.

use glam::{DVec2, DVec3};
use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;
use subdiv_mesh::{EdgeTag, FaceGroups, FaceList, FaceVarying, FileOptions, PolygonSoup, TagList, VertexTag};
use subdiv_rules::{BoundaryInterpolation, CreaseMethod, FVarInterpolation, TriangleRule};

use crate::error::{Ctx, IoError, ReadWarning};
use crate::text::{
    check_text, is_control, parse_bounded, parse_f64, parse_integer, show, strip_bom, strip_comment, tokens, IntError,
    Lines, TextOut,
};
use crate::{Format, MeshView};

mod chunks;

/// Group names interned in order of first appearance.
#[derive(Default)]
struct GroupTable {
    groups: FaceGroups,
    index: HashMap<String, u32>,
}

impl GroupTable {
    fn intern(&mut self, name: String) -> u32 {
        if let Some(&i) = self.index.get(&name) {
            return i;
        }
        let i = self.groups.names.len() as u32;
        self.groups.names.push(name.clone());
        self.index.insert(name, i);
        i
    }

    /// The group of a face when `current` was named last (`None`: no
    /// `g`/`o` line yet, the face is in `default`, interned then).
    fn face_group(&mut self, current: &mut Option<u32>) -> u32 {
        match *current {
            Some(g) => g,
            None => *current.insert(self.intern("default".to_owned())),
        }
    }
}

/// Without trailing whitespace.
fn trim_end(line: &[u8]) -> &[u8] {
    let end = line.iter().rposition(|b| !b.is_ascii_whitespace()).map_or(0, |i| i + 1);
    &line[..end]
}

/// The line without its continuation backslash, if it has one.
fn continued(line: &[u8]) -> Option<&[u8]> {
    trim_end(line).strip_suffix(b"\\")
}

/// The texture coordinates of the faces read so far, and whether every face
/// (with corners) has them.
#[derive(Default)]
struct UvChannel {
    values: Vec<DVec2>,
    /// One per corner of the faces read so far, while all of them have
    /// texture coordinates (cleared once a face without them is mixed in).
    indices: Vec<u32>,
    faces_with: usize,
    faces_without: usize,
    /// (face, line) of the first face with and the first without.
    first_with: Option<(usize, usize)>,
    first_without: Option<(usize, usize)>,
}

impl UvChannel {
    /// Records face `face` of line `line`; `corner_uvs` is empty when the
    /// face gives no texture coordinates.
    fn face(&mut self, face: usize, line: usize, corner_uvs: &[u32]) {
        if corner_uvs.is_empty() {
            self.faces_without += 1;
            self.first_without.get_or_insert((face, line));
            // Mixed: the channel is lost, and its indices need not be kept.
            self.indices = Vec::new();
        } else {
            self.faces_with += 1;
            self.first_with.get_or_insert((face, line));
            if self.faces_without == 0 {
                self.indices.extend_from_slice(corner_uvs);
            }
        }
    }

    /// The channel when every face has texture coordinates; otherwise why not.
    fn finish(self, path: &Path) -> (Option<FaceVarying>, Option<ReadWarning>) {
        match (self.first_with, self.first_without) {
            (None, _) => (None, None),
            (Some(_), None) => (Some(FaceVarying { values: self.values, indices: self.indices }), None),
            (Some((with_face, with_line)), Some((without_face, without_line))) => {
                let (line, reason) = if with_face < without_face {
                    let reason = format!(
                        "face {without_face} has none, but {} faces have them (the first, face {with_face}, \
                         on line {with_line})",
                        self.faces_with
                    );
                    (without_line, reason)
                } else {
                    let reason = format!(
                        "face {with_face} has them, but {} faces have none (the first, face {without_face}, \
                         on line {without_line})",
                        self.faces_without
                    );
                    (with_line, reason)
                };
                (None, Some(ReadWarning::UvsDropped { path: path.to_path_buf(), line: Some(line), reason }))
            }
        }
    }
}

/// Tag lines read but not applied, for [`ReadWarning::TagsIgnored`].
#[derive(Default)]
struct IgnoredTags {
    first_line: Option<usize>,
    lines: usize,
    names: Vec<String>,
}

impl IgnoredTags {
    fn add(&mut self, name: &[u8], line: usize) {
        self.first_line.get_or_insert(line);
        self.lines += 1;
        let name = show(name);
        if self.names.len() < ReadWarning::NAMES_KEPT && !self.names.iter().any(|n| *n == name) {
            self.names.push(name.into_owned());
        }
    }

    fn finish(self, path: &Path) -> Option<ReadWarning> {
        let line = self.first_line?;
        Some(ReadWarning::TagsIgnored { path: path.to_path_buf(), line, lines: self.lines, names: self.names })
    }
}

/// Reads an OBJ file: large files through the parallel path ([`chunks`]),
/// which declines whatever it does not read exactly as [`read_serial`]
/// does; the rest, and everything it declines, through [`read_serial`]
/// from the start, which gives every error and warning.
pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
    if bytes.len() >= chunks::MIN_BYTES {
        if let Some(read) = chunks::read(bytes, chunks::chunk_size(bytes.len()), ctx) {
            return Ok(read);
        }
    }
    read_serial(bytes, ctx)
}

/// The parallel path alone, in chunks of about `chunk` bytes (see [`chunks`]).
pub(crate) fn read_chunked(bytes: &[u8], chunk: usize, ctx: Ctx<'_>) -> Option<(PolygonSoup, Vec<ReadWarning>)> {
    chunks::read(bytes, chunk, ctx)
}

/// Files shorter than this are read by [`read_serial`] alone.
pub(crate) const CHUNKED_MIN_BYTES: usize = chunks::MIN_BYTES;

/// The reader of record: the file line by line, on one thread.
pub(crate) fn read_serial(bytes: &[u8], ctx: Ctx<'_>) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
    let bytes = strip_bom(bytes);
    check_text(bytes, Format::Obj, ctx)?;
    let mut positions: Vec<DVec3> = Vec::new();
    let mut faces = FaceList::new();
    let mut uvs = UvChannel::default();
    let mut tags = TagList::default();
    let mut ignored = IgnoredTags::default();
    let mut table = GroupTable::default();
    let mut face_group: Vec<u32> = Vec::new();
    let mut current_group: Option<u32> = None;
    let mut saw_group_statement = false;
    let mut corners: Vec<u32> = Vec::new();
    let mut corner_uvs: Vec<u32> = Vec::new();
    let mut joined: Vec<u8> = Vec::new();

    let mut lines = Lines::new(bytes);
    while let Some((n, raw)) = lines.next() {
        let first = strip_comment(raw);
        let line: &[u8] = match continued(first) {
            None => first,
            Some(head) => {
                joined.clear();
                joined.extend_from_slice(head);
                for (_, next) in lines.by_ref() {
                    let next = strip_comment(next);
                    joined.push(b' ');
                    match continued(next) {
                        Some(head) => joined.extend_from_slice(head),
                        None => {
                            joined.extend_from_slice(next);
                            break;
                        }
                    }
                }
                &joined
            }
        };

        let mut toks = tokens(line);
        let Some(keyword) = toks.next() else { continue };
        match Statement::of(keyword) {
            Statement::Vertex => positions.push(vertex(toks, n, ctx)?),
            Statement::TexCoord => uvs.values.push(tex_coord(toks, n, ctx)?),
            Statement::Face => {
                corners.clear();
                corner_uvs.clear();
                let counts = (positions.len(), uvs.values.len());
                face_corners(toks, counts, faces.len(), n, ctx, &mut corners, &mut corner_uvs)?;
                // A face without corners (a defect the validator reports) has
                // no corner to give a texture coordinate to.
                if !corners.is_empty() {
                    uvs.face(faces.len(), n, &corner_uvs);
                }
                faces.push(&corners);
                face_group.push(table.face_group(&mut current_group));
            }
            Statement::Group => {
                saw_group_statement = true;
                current_group = Some(table.intern(group_name(toks)));
            }
            Statement::Tag => read_tag(toks, n, ctx, &mut tags, &mut ignored)?,
            Statement::Binary => return Err(ctx.binary(n, Format::Obj)),
            Statement::Ignored => {}
        }
    }

    if positions.is_empty() && faces.is_empty() {
        return Err(ctx.empty());
    }
    let groups =
        if saw_group_statement { FaceGroups { names: table.groups.names, face_group } } else { FaceGroups::default() };
    let (uvs, uv_warning) = uvs.finish(ctx.path);
    let warnings = uv_warning.into_iter().chain(ignored.finish(ctx.path)).collect();
    Ok((PolygonSoup { positions, faces, groups, tags, uvs }, warnings))
}

/// What a statement is, from its keyword: the one dispatch of both readers.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Statement {
    /// `v`: [`vertex`].
    Vertex,
    /// `vt`: [`tex_coord`].
    TexCoord,
    /// `f`, `fo`: [`face_corners`].
    Face,
    /// `g`, `o`: [`group_name`].
    Group,
    /// `t`: [`read_tag`].
    Tag,
    /// A keyword holding a control character: binary data past the part
    /// [`check_text`] looked at (a text file with a binary tail).
    Binary,
    /// `vn` (normals are recomputed), `s`, `usemtl`, `mtllib`, `l`, `p` and
    /// unknown statements.
    Ignored,
}

impl Statement {
    fn of(keyword: &[u8]) -> Self {
        match keyword {
            b"v" => Self::Vertex,
            b"vt" => Self::TexCoord,
            b"f" | b"fo" => Self::Face,
            b"g" | b"o" => Self::Group,
            b"t" => Self::Tag,
            _ if keyword.iter().any(|&b| is_control(b)) => Self::Binary,
            _ => Self::Ignored,
        }
    }
}

/// The position of a `v` line of number `line`, from the tokens after its
/// keyword: the first three (a `w` and vertex colours after them are ignored).
fn vertex<'a>(mut toks: impl Iterator<Item = &'a [u8]>, line: usize, ctx: Ctx<'_>) -> Result<DVec3, IoError> {
    let mut c = [0.0; 3];
    for (i, slot) in c.iter_mut().enumerate() {
        let Some(t) = toks.next() else {
            return Err(ctx.truncated(line, format!("vertex has {i} coordinates, 3 needed")));
        };
        *slot =
            parse_f64(t).ok_or_else(|| ctx.parse(line, format!("vertex coordinate '{}' is not a number", show(t))))?;
    }
    Ok(DVec3::from(c))
}

/// The texture coordinate of a `vt` line: `u [v] [w]`, `v` 0 when absent,
/// `w` and anything after it ignored.
fn tex_coord<'a>(mut toks: impl Iterator<Item = &'a [u8]>, line: usize, ctx: Ctx<'_>) -> Result<DVec2, IoError> {
    let Some(u) = toks.next() else {
        return Err(ctx.truncated(line, "texture coordinate has no value"));
    };
    let number = |t: &[u8]| {
        parse_f64(t).ok_or_else(|| ctx.parse(line, format!("texture coordinate '{}' is not a number", show(t))))
    };
    let u = number(u)?;
    let v = toks.next().map_or(Ok(0.0), number)?;
    Ok(DVec2::new(u, v))
}

/// Appends the corners of face number `face` (an `f` line of number
/// `line`) to `corners`, and their texture coordinate indices, if it gives
/// them, to `corner_uvs`: as many as corners, or none (a face giving them
/// for some corners only is an error). `counts` are the vertices and
/// texture coordinates read so far, which relative indices count back
/// from; the `vn` part of a corner is not looked at.
fn face_corners<'a>(
    toks: impl Iterator<Item = &'a [u8]>,
    counts: (usize, usize),
    face: usize,
    line: usize,
    ctx: Ctx<'_>,
    corners: &mut Vec<u32>,
    corner_uvs: &mut Vec<u32>,
) -> Result<(), IoError> {
    let (start, uv_start) = (corners.len(), corner_uvs.len());
    for t in toks {
        let mut parts = t.split(|&b| b == b'/');
        let v = parts.next().unwrap_or(t);
        corners.push(obj_index(v, t, Element::Vertex, counts.0, line, ctx)?);
        if let Some(vt) = parts.next().filter(|vt| !vt.is_empty()) {
            corner_uvs.push(obj_index(vt, t, Element::Texture, counts.1, line, ctx)?);
        }
    }
    let (n, with_uvs) = (corners.len() - start, corner_uvs.len() - uv_start);
    if with_uvs != 0 && with_uvs != n {
        return Err(ctx.parse(line, format!("face {face} gives texture coordinates for {with_uvs} of its {n} corners")));
    }
    Ok(())
}

/// The group a `g` or `o` line names: its tokens joined by single spaces
/// (lossy UTF-8), `default` when it names none.
fn group_name<'a>(toks: impl Iterator<Item = &'a [u8]>) -> String {
    let name: Vec<_> = toks.map(String::from_utf8_lossy).collect();
    if name.is_empty() {
        "default".to_owned()
    } else {
        name.join(" ")
    }
}

/// What an OBJ index refers to.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Element {
    Vertex,
    Texture,
}

/// Maps one index of a face corner (`v`, `v/vt`, `v/vt/vn`, `v//vn`: the
/// `v` or the `vt` part of `token`) to a 0-based index. Positive indices
/// beyond the count so far pass through (the validator reports them); 0,
/// relative indices before the first element and indices beyond what a
/// `u32` holds cannot be stored and are errors.
fn obj_index(
    part: &[u8],
    token: &[u8],
    element: Element,
    so_far: usize,
    line: usize,
    ctx: Ctx<'_>,
) -> Result<u32, IoError> {
    let (what, first) = match element {
        Element::Vertex => ("face index", "vertex"),
        Element::Texture => ("texture index", "texture coordinate"),
    };
    let k = match parse_integer(part) {
        Ok(k) => k,
        Err(IntError::NotInteger) => {
            let quoted = if element == Element::Vertex { token } else { part };
            return Err(ctx.parse(line, format!("{what} '{}' is not an integer", show(quoted))));
        }
        Err(IntError::OutOfRange) => return Err(ctx.parse(line, format!("{what} {} out of range", show(part)))),
    };
    let index = match k {
        0 => return Err(ctx.parse(line, format!("{what} 0 is invalid (OBJ indices start at 1)"))),
        k if k > 0 => k - 1,
        k => so_far as i128 + k,
    };
    if index < 0 {
        let counted = if element == Element::Vertex { "vertices" } else { "texture coordinates" };
        return Err(
            ctx.parse(line, format!("relative {what} {k} points before the first {first} ({so_far} {counted} so far)"))
        );
    }
    u32::try_from(index)
        .map_err(|_| ctx.parse(line, format!("{what} {k} out of range (the largest is {})", u64::from(u32::MAX) + 1)))
}

/// Reads one tag line after its `t`: `NAME NI/NF/NS`, then NI integers, NF
/// floats and NS strings (see the module doc). Crease and corner tags go to
/// `tags`, others to `ignored`. Nothing is allocated beyond the line's own
/// tokens, whatever the counts say.
fn read_tag<'a>(
    mut toks: impl Iterator<Item = &'a [u8]>,
    line: usize,
    ctx: Ctx<'_>,
    tags: &mut TagList,
    ignored: &mut IgnoredTags,
) -> Result<(), IoError> {
    let bad = |message: String| ctx.parse(line, message);
    let (Some(name), Some(counts)) = (toks.next(), toks.next()) else {
        return Err(bad("tag line needs a name and its counts (t NAME NI/NF/NS …)".to_owned()));
    };
    let shown = show(name);
    let mut parts = counts.split(|&b| b == b'/');
    let (Some(ni), Some(nf), Some(ns), None) = (parts.next(), parts.next(), parts.next(), parts.next()) else {
        return Err(bad(format!("tag '{shown}': counts '{}' are not NI/NF/NS", show(counts))));
    };
    // Messages are formatted only on error: a tag line can hold millions of values.
    let count = |t: &[u8], what: &str| -> Result<usize, IoError> {
        parse_bounded(t, what).map_err(|m| bad(format!("tag '{shown}': {m}")))
    };
    let (ni, nf, ns) = (count(ni, "integer count")?, count(nf, "float count")?, count(ns, "string count")?);
    // The counts are checked against the tokens the line has before anything else.
    let values: Vec<&[u8]> = toks.collect();
    let declared = ni.checked_add(nf).and_then(|c| c.checked_add(ns));
    if declared != Some(values.len()) {
        return Err(bad(format!(
            "tag '{shown}' declares {ni}/{nf}/{ns} values but has {} after its counts",
            values.len()
        )));
    }
    let (ints, rest) = values.split_at(ni);
    let floats = &rest[..nf];
    let floats: Vec<f32> = floats
        .iter()
        .map(|t| {
            std::str::from_utf8(t)
                .ok()
                .and_then(|s| s.parse::<f32>().ok())
                .ok_or_else(|| bad(format!("tag '{shown}': float '{}' is not a number", show(t))))
        })
        .collect::<Result<_, _>>()?;
    let vertex = |t: &[u8]| -> Result<u32, IoError> {
        parse_bounded::<u32>(t, "vertex index").map_err(|m| bad(format!("tag '{shown}': {m}")))
    };
    match name {
        b"crease" => {
            if ni == 0 || ni % 2 != 0 {
                return Err(bad(format!("crease tag needs vertex pairs, found {ni} integers")));
            }
            let pairs = ni / 2;
            if nf != 1 && nf != pairs {
                return Err(bad(format!(
                    "crease tag has {pairs} vertex pairs and {nf} floats (1, or one per pair, needed)"
                )));
            }
            for (k, pair) in ints.chunks_exact(2).enumerate() {
                let sharpness = floats[if nf == 1 { 0 } else { k }];
                tags.creases.push(EdgeTag { a: vertex(pair[0])?, b: vertex(pair[1])?, sharpness });
            }
        }
        b"corner" => {
            if ni == 0 {
                return Err(bad("corner tag names no vertex".to_owned()));
            }
            if nf != 1 && nf != ni {
                return Err(bad(format!(
                    "corner tag has {ni} vertices and {nf} floats (1, or one per vertex, needed)"
                )));
            }
            for (k, &v) in ints.iter().enumerate() {
                let sharpness = floats[if nf == 1 { 0 } else { k }];
                tags.corners.push(VertexTag { vertex: vertex(v)?, sharpness });
            }
        }
        b"hole" => {
            if ni == 0 || nf != 0 {
                return Err(bad(format!("hole tag needs face indices and no floats, found {ni}/{nf}")));
            }
            for &f in ints {
                tags.holes.push(parse_bounded::<u32>(f, "face index").map_err(|m| bad(format!("tag 'hole': {m}")))?);
            }
        }
        b"interpolateboundary" | b"facevaryinginterpolateboundary" | b"creasemethod" | b"smoothtriangles" => {
            read_option_tag(name, ints, &rest[nf..], &mut tags.options)
                .map_err(|m| bad(format!("tag '{shown}': {m}")))?;
        }
        b"facevaryingpropagatecorners" => {
            return Err(bad("tag 'facevaryingpropagatecorners' is not supported (OpenSubdiv 3 has no such option: \
                 remove the line or choose a face-varying interpolation)"
                .to_owned()));
        }
        _ => {
            if let Some(t) = ints.iter().find(|t| parse_integer(t) == Err(IntError::NotInteger)) {
                return Err(bad(format!("tag '{shown}': integer '{}' is not an integer", show(t))));
            }
            ignored.add(name, line);
        }
    }
    Ok(())
}

/// One of OpenSubdiv's option tags (`regression/common/far_utils.h`,
/// `GetSdcOptions`): `interpolateboundary 1/0/0 K` (0 none, 1
/// edge-and-corner, 2 edge-only), `facevaryinginterpolateboundary 1/0/0 K`
/// (0 linear-none … 5 linear-all, in `Sdc::Options::FVarLinearInterpolation`
/// order), `creasemethod 0/0/1 normal|chaikin`, `smoothtriangles 0/0/1
/// catmark|smooth`. A later line of the same option replaces an earlier one.
fn read_option_tag(name: &[u8], ints: &[&[u8]], strings: &[&[u8]], options: &mut FileOptions) -> Result<(), String> {
    let one_int = |max: usize| -> Result<usize, String> {
        let [value] = ints else { return Err(format!("expects one integer, found {}", ints.len())) };
        let k: usize = parse_bounded(value, "value")?;
        if k > max {
            return Err(format!("value {k} is not one of 0..={max}"));
        }
        Ok(k)
    };
    let one_string = || -> Result<&[u8], String> {
        match strings {
            [value] => Ok(value),
            _ => Err(format!("expects one string, found {}", strings.len())),
        }
    };
    match name {
        b"interpolateboundary" => {
            use BoundaryInterpolation as B;
            options.boundary = Some([B::None, B::EdgeAndCorner, B::EdgeOnly][one_int(2)?]);
        }
        b"facevaryinginterpolateboundary" => {
            use FVarInterpolation as F;
            let modes = [
                F::LinearNone,
                F::LinearCornersOnly,
                F::LinearCornersPlus1,
                F::LinearCornersPlus2,
                F::LinearBoundaries,
                F::LinearAll,
            ];
            options.fvar = Some(modes[one_int(5)?]);
        }
        b"creasemethod" => {
            options.crease_method = Some(match one_string()? {
                b"normal" => CreaseMethod::Uniform,
                b"chaikin" => CreaseMethod::Chaikin,
                other => return Err(format!("'{}' is neither 'normal' nor 'chaikin'", show(other))),
            });
        }
        _ => {
            options.triangle_rule = Some(match one_string()? {
                b"catmark" => TriangleRule::Catmark,
                b"smooth" => TriangleRule::Smooth,
                other => return Err(format!("'{}' is neither 'catmark' nor 'smooth'", show(other))),
            });
        }
    }
    Ok(())
}

pub(crate) fn write(mesh: &MeshView<'_>, out: &mut impl Write) -> io::Result<()> {
    let mut text = TextOut::new(out);
    text.bytes(b"# written by subdiv-io\n");
    let xyz = |text: &mut TextOut<'_, _>, keyword: &[u8], p: &DVec3| {
        text.bytes(keyword);
        for x in p.to_array() {
            text.bytes(b" ");
            text.f64(x);
        }
        text.end_line()
    };
    for p in mesh.positions {
        xyz(&mut text, b"v", p)?;
    }
    for n in mesh.normals.into_iter().flatten() {
        xyz(&mut text, b"vn", n)?;
    }
    if let Some(uvs) = mesh.uvs {
        for uv in &uvs.values {
            text.bytes(b"vt ");
            text.f64(uv.x);
            text.bytes(b" ");
            text.f64(uv.y);
            text.end_line()?;
        }
    }
    let with_normals = mesh.normals.is_some();
    let uv_indices = mesh.uvs.map(|uvs| uvs.indices.as_slice());
    for (f, face) in mesh.faces.iter().enumerate() {
        text.bytes(b"f");
        let start = mesh.faces.offsets()[f] as usize;
        for (j, &v) in face.iter().enumerate() {
            let k = u64::from(v) + 1;
            text.bytes(b" ");
            text.int(k);
            // `k/t`, `k//k` with normals, `k/t/k` with both.
            if let Some(uv) = uv_indices {
                text.bytes(b"/");
                text.int(u64::from(uv[start + j]) + 1);
            }
            if with_normals {
                text.bytes(if uv_indices.is_some() { b"/" } else { b"//" });
                text.int(k);
            }
        }
        text.end_line()?;
    }
    text.finish()?;
    if let Some(tags) = mesh.tags {
        // `{:?}` of an f32 is the shortest form that parses back to it.
        for t in &tags.creases {
            writeln!(out, "t crease 2/1/0 {} {} {:?}", t.a, t.b, written_sharpness(t.sharpness))?;
        }
        for t in &tags.corners {
            writeln!(out, "t corner 1/1/0 {} {:?}", t.vertex, written_sharpness(t.sharpness))?;
        }
        for chunk in tags.holes.chunks(HOLES_PER_LINE) {
            write!(out, "t hole {}/0/0", chunk.len())?;
            for f in chunk {
                write!(out, " {f}")?;
            }
            writeln!(out)?;
        }
        write_option_tags(&tags.options, out)?;
    }
    Ok(())
}

/// A sharpness as written: clamped to the largest finite `f32`. Every
/// sharpness from [`subdiv_mesh::SHARPNESS_INFINITE`] (10) up is infinitely
/// sharp, so the clamp keeps the meaning, and the file holds a number every
/// OBJ reader (OpenSubdiv's `f32` included) reads back, never `inf`: an
/// infinite sharpness (a tag of 1e39 read as `f32`, or `+∞` set through the
/// library) is written as `3.4028235e38`. Validated tags are never NaN or
/// negative.
fn written_sharpness(s: f32) -> f32 {
    s.min(f32::MAX)
}

/// Face indices per `t hole` line written.
const HOLES_PER_LINE: usize = 32;

/// The options a mesh carries as OpenSubdiv's option tags ([`read_option_tag`]'s inverse).
fn write_option_tags(options: &FileOptions, out: &mut impl Write) -> io::Result<()> {
    if let Some(boundary) = options.boundary {
        let k = match boundary {
            BoundaryInterpolation::None => 0,
            BoundaryInterpolation::EdgeAndCorner => 1,
            BoundaryInterpolation::EdgeOnly => 2,
        };
        writeln!(out, "t interpolateboundary 1/0/0 {k}")?;
    }
    if let Some(fvar) = options.fvar {
        let k = match fvar {
            FVarInterpolation::LinearNone => 0,
            FVarInterpolation::LinearCornersOnly => 1,
            FVarInterpolation::LinearCornersPlus1 => 2,
            FVarInterpolation::LinearCornersPlus2 => 3,
            FVarInterpolation::LinearBoundaries => 4,
            FVarInterpolation::LinearAll => 5,
        };
        writeln!(out, "t facevaryinginterpolateboundary 1/0/0 {k}")?;
    }
    if let Some(method) = options.crease_method {
        let name = match method {
            CreaseMethod::Uniform => "normal",
            CreaseMethod::Chaikin => "chaikin",
        };
        writeln!(out, "t creasemethod 0/0/1 {name}")?;
    }
    if let Some(rule) = options.triangle_rule {
        writeln!(out, "t smoothtriangles 0/0/1 {rule}")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_str(s: &str) -> Result<PolygonSoup, IoError> {
        read(s.as_bytes(), Ctx::new(Path::new("t.obj"))).map(|(soup, _)| soup)
    }

    /// A sharpness read as +∞ (1e39 does not fit in `f32`) is written as the largest `f32`,
    /// which reads back as infinitely sharp: never `inf`.
    #[test]
    fn infinite_sharpness_is_written_as_the_largest_f32() {
        let soup =
            read_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0 1 1e39\nt corner 1/1/0 2 inf\n").unwrap();
        assert_eq!(soup.tags.creases[0].sharpness, f32::INFINITY);
        let bytes = crate::write_mesh_to_vec(crate::MeshView::from(&soup), crate::Format::Obj).unwrap();
        let text = String::from_utf8(bytes).unwrap();
        assert!(text.contains("t crease 2/1/0 0 1 3.4028235e38\n"), "{text}");
        assert!(text.contains("t corner 1/1/0 2 3.4028235e38\n"), "{text}");
        assert!(!text.contains("inf"), "{text}");
        let back = read_str(&text).unwrap();
        assert_eq!(back.tags.creases[0].sharpness, f32::MAX);
    }

    #[test]
    fn continuation_joins_lines_and_errors_name_the_first_line() {
        let soup = read_str("v 0 0 0\nv 1 0 \\\n 0\nv 0 1 0\nf 1 \\\n 2 3\n").unwrap();
        assert_eq!(soup.positions.len(), 3);
        assert_eq!(soup.faces.face(0), &[0, 1, 2]);
        let e = read_str("v 0 0 0\nf 1 \\\n 2 q\n").unwrap_err();
        assert_eq!(e.line(), Some(2));
    }

    #[test]
    fn groups_start_with_default_when_faces_precede_the_first_name() {
        let soup = read_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng top\nf 3 2 1\no top\nf 1 3 2\n").unwrap();
        assert_eq!(soup.groups.names, vec!["default", "top"]);
        assert_eq!(soup.groups.face_group, vec![0, 1, 1]);
        let plain = read_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        assert!(plain.groups.names.is_empty() && plain.groups.face_group.is_empty());
    }

    #[test]
    fn relative_index_before_first_vertex_is_an_error() {
        let e = read_str("v 0 0 0\nf -1 -2 -1\n").unwrap_err();
        assert!(matches!(e, IoError::Parse { line: Some(2), .. }), "{e}");
    }
}
