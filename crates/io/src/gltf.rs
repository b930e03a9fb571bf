//! glTF 2.0 (`.gltf` JSON) and GLB (binary container).
//!
//! Read: the JSON is parsed and validated by the `gltf` crate; the GLB
//! container, the buffers and the accessors are read here with every offset
//! checked, so a corrupt file is an error, never a panic. A UTF-8 byte-order
//! mark before the JSON is skipped; UTF-16 and binary data that is not a GLB
//! container are reported as such. Every triangle-mode primitive
//! (`TRIANGLES`, `TRIANGLE_STRIP`, `TRIANGLE_FAN`) of every mesh is read as
//! stored, without node transforms; non-indexed primitives take consecutive
//! vertices. Primitives that share a `POSITION` accessor share its vertices
//! (they are read once, so a mesh split into primitives by material stays
//! connected); other primitives' vertices are appended, with their indices
//! offset. Points and lines are skipped; a file with nothing but points and
//! lines is [`IoError::Unsupported`] ("no triangle primitives (found: …)").
//! Positions are `f32` in glTF. Because primitives are concatenated, an index
//! past its own primitive's vertices is an error here rather than passed
//! through.
//!
//! `TEXCOORD_0` (`FLOAT`, or `UNSIGNED_BYTE` / `UNSIGNED_SHORT` normalized,
//! as the spec allows) becomes [`PolygonSoup::uvs`], one value per vertex of
//! its accessor (an accessor shared by primitives is read once); a primitive
//! whose `TEXCOORD_0` count differs from its `POSITION` count is an error. When
//! some triangle primitives have `TEXCOORD_0` and others do not, or one is
//! stored in another type, the mesh is read without texture coordinates
//! ([`ReadWarning::UvsDropped`]). glTF puts the origin of texture space at the
//! top left, OBJ and PLY at the bottom left: `v` is flipped (`1 − v`) on
//! read and on write, as Blender's importer and exporter do, so that a
//! texture maps the same way in every format.
//!
//! Buffers come from the GLB `BIN` chunk, from `data:` URIs, or from files
//! named by *relative* URIs that resolve (percent-decoded, symbolic links
//! followed) to a regular file inside the glTF file's own directory; at most
//! the buffer's `byteLength` is read. Anything else — a scheme (`file:`,
//! `http:`), an absolute path, a `..` that leaves the directory, a FIFO or a
//! device — is [`IoError::RefusedUri`]: nothing is ever fetched from the
//! network or read from outside the directory.
//!
//! Work is bounded by the bytes present: accessors are checked against their
//! buffer views before anything is allocated, and a file whose primitives
//! reuse accessors for more vertices, texture coordinates and triangles than
//! it has bytes (a few kilobytes of JSON can repeat one accessor a million
//! times) is refused.
//!
//! Write: faces triangulated as fans from their first corner, positions as
//! `f32` (rounded from `f64`: relative error up to 2⁻²⁴; coordinates must be
//! finite and within `f32` range), `NORMAL` when normals are given
//! (normalised, as glTF requires; a zero normal is written as +Z), `u32`
//! indices, and the `min`/`max` bounds the spec requires on `POSITION`.
//! `.glb` holds the buffer in its `BIN` chunk, `.gltf` embeds it as a base64
//! `data:` URI, so either output is a single file. Texture coordinates are
//! written as `TEXCOORD_0` (`f32`). glTF attributes are per vertex, so where a
//! vertex has several texture coordinates (a seam) it is split, as every
//! exporter does: the vertices keep their order and positions, each vertex
//! gets the coordinate of its first corner, and a copy of it is appended for
//! every other coordinate its corners use (value indices, not values, tell
//! them apart). Such a file reads back with more vertices, cut open along the
//! seams ([`Format::splits_uv_seams`]). Crease and corner tags are not written:
//! glTF has no standard place for them ([`Format::carries_tags`]).

use glam::{DVec2, DVec3, Vec2, Vec3};
use serde_json::json;
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use subdiv_mesh::{FaceList, FaceVarying, PolygonSoup};

use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::buffer::Source;
use ::gltf::mesh::{Mode, Semantic};
use ::gltf::{Accessor, Document};

use crate::error::{Ctx, IoError, ReadWarning};
use crate::text::{check_text, is_blank, strip_bom};
use crate::{base64, fan, Format, MeshView};

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a GLB container into its JSON and optional BIN chunks.
fn split_glb<'a>(bytes: &'a [u8], ctx: Ctx<'_>) -> Result<(&'a [u8], Option<&'a [u8]>), IoError> {
    let (Some(version), Some(length)) = (u32_at(bytes, 4), u32_at(bytes, 8)) else {
        return Err(ctx.truncated(None, "GLB header needs 12 bytes"));
    };
    if version != 2 {
        return Err(ctx.unsupported(format!("GLB container version {version} (only 2 is read)")));
    }
    let data = bytes
        .get(..length as usize)
        .ok_or_else(|| ctx.truncated(None, format!("GLB header says {length} bytes, the file has {}", bytes.len())))?;
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    while at < data.len() {
        let (Some(len), Some(kind)) = (u32_at(data, at), u32_at(data, at + 4)) else {
            return Err(ctx.truncated(None, format!("GLB chunk header at byte {at} is cut off")));
        };
        let start = at + 8;
        let end = start.checked_add(len as usize);
        let chunk = end
            .and_then(|end| data.get(start..end))
            .ok_or_else(|| ctx.truncated(None, format!("GLB chunk at byte {at} claims {len} bytes")))?;
        match kind {
            CHUNK_JSON if json.is_none() => json = Some(chunk),
            CHUNK_BIN if bin.is_none() => bin = Some(chunk),
            _ => {}
        }
        at = start + chunk.len();
    }
    let json = json.ok_or_else(|| ctx.parse(None, "GLB file has no JSON chunk"))?;
    Ok((json, bin))
}

/// Decodes `%XX` escapes of a URI path.
fn percent_decode(uri: &str) -> Vec<u8> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    out
}

/// A decoded URI path as a file system path (bytes as they are on Unix).
fn path_of(decoded: Vec<u8>) -> PathBuf {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStringExt;
        PathBuf::from(std::ffi::OsString::from_vec(decoded))
    }
    #[cfg(not(unix))]
    {
        PathBuf::from(String::from_utf8_lossy(&decoded).into_owned())
    }
}

/// The bytes a buffer URI points to: at most `length` of them from a file.
fn uri_data(uri: &str, length: usize, base_dir: Option<&Path>, ctx: Ctx<'_>) -> Result<Vec<u8>, IoError> {
    if uri.get(..5).is_some_and(|scheme| scheme.eq_ignore_ascii_case("data:")) {
        let (meta, payload) =
            uri[5..].split_once(',').ok_or_else(|| ctx.parse(None, "data: URI without a ',' before its payload"))?;
        return if meta.ends_with(";base64") {
            base64::decode(payload.as_bytes()).ok_or_else(|| ctx.parse(None, "data: URI payload is not valid base64"))
        } else {
            Ok(percent_decode(payload))
        };
    }
    let path = resolve(uri, base_dir, ctx)?;
    // A file longer than the buffer is fine (the rest is not part of it); shorter is truncated.
    crate::read_file(&path, Some(length as u64), &mut |_, _| {}).map_err(|e| match e {
        IoError::NotAFile { kind, .. } => ctx.refused_uri(uri, format!("it names {kind}, not a regular file")),
        e => e,
    })
}

/// The file a relative buffer URI names, checked to lie inside `base_dir`:
/// no scheme, not absolute, no `..` above the directory (read lexically,
/// before the file system is asked), and — comparing canonical paths — no
/// symbolic link out of it.
fn resolve(uri: &str, base_dir: Option<&Path>, ctx: Ctx<'_>) -> Result<PathBuf, IoError> {
    // RFC 3986 §4.2: a relative reference has no ':' before its first '/'.
    if uri.find(':').is_some_and(|colon| !uri[..colon].contains('/')) {
        return Err(ctx.refused_uri(
            uri,
            "it has a scheme; only data: URIs and relative paths are read (nothing is fetched from the network)",
        ));
    }
    let decoded = percent_decode(uri);
    if decoded.contains(&0) {
        return Err(ctx.refused_uri(uri, "it holds a NUL byte"));
    }
    if decoded.starts_with(b"/") || decoded.starts_with(b"\\") {
        return Err(ctx.refused_uri(uri, "it is an absolute path"));
    }
    let relative = path_of(decoded);
    if relative.has_root() || relative.is_absolute() {
        return Err(ctx.refused_uri(uri, "it is an absolute path"));
    }
    let mut depth = 0usize;
    for component in relative.components() {
        match component {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth > 0 => depth -= 1,
            _ => return Err(ctx.refused_uri(uri, "it leads out of the glTF file's directory")),
        }
    }
    let Some(dir) = base_dir else {
        return Err(ctx.unsupported(format!(
            "external buffer '{}' cannot be resolved without the file's directory",
            crate::error::show_uri(uri)
        )));
    };
    let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
    let path = dir.join(&relative);
    let canonical_dir = dir.canonicalize().map_err(|source| IoError::Io { path: dir.to_path_buf(), source })?;
    let canonical = path.canonicalize().map_err(|source| IoError::Io { path: path.clone(), source })?;
    if !canonical.starts_with(&canonical_dir) {
        return Err(ctx.refused_uri(uri, "it leads out of the glTF file's directory (through a symbolic link)"));
    }
    Ok(canonical)
}

/// Every buffer's bytes, each at least as long as its declared `byteLength`.
fn load_buffers<'a>(
    doc: &Document,
    bin: Option<&'a [u8]>,
    base_dir: Option<&Path>,
    ctx: Ctx<'_>,
) -> Result<Vec<Cow<'a, [u8]>>, IoError> {
    doc.buffers()
        .map(|buffer| {
            let data: Cow<'a, [u8]> = match buffer.source() {
                Source::Bin => Cow::Borrowed(bin.ok_or_else(|| {
                    ctx.parse(None, format!("buffer {} refers to a missing BIN chunk", buffer.index()))
                })?),
                Source::Uri(uri) => Cow::Owned(uri_data(uri, buffer.length(), base_dir, ctx)?),
            };
            if data.len() < buffer.length() {
                return Err(ctx.truncated(
                    None,
                    format!("buffer {} declares {} bytes but holds {}", buffer.index(), buffer.length(), data.len()),
                ));
            }
            Ok(data)
        })
        .collect()
}

/// The elements of an accessor, checked to lie inside their buffer view:
/// element `k` starts at byte `k · stride` of `data`.
struct Elements<'b> {
    data: &'b [u8],
    stride: usize,
    count: usize,
}

impl Elements<'_> {
    /// The first `N` bytes of element `k`.
    fn get<const N: usize>(&self, k: usize) -> [u8; N] {
        let at = k * self.stride;
        let mut out = [0; N];
        out.copy_from_slice(&self.data[at..at + N]);
        out
    }
}

/// The bytes of an accessor's elements, without reading them.
fn accessor_data<'b>(
    accessor: &Accessor<'_>,
    buffers: &'b [Cow<'_, [u8]>],
    ctx: Ctx<'_>,
) -> Result<Elements<'b>, IoError> {
    let i = accessor.index();
    if accessor.sparse().is_some() {
        return Err(ctx.unsupported(format!("sparse accessor {i}")));
    }
    let Some(view) = accessor.view() else {
        return Err(ctx.unsupported(format!("accessor {i} without a buffer view")));
    };
    let element = accessor.size();
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(
            ctx.parse(None, format!("accessor {i}: stride {stride} is smaller than its element size {element}"))
        );
    }
    let buffer = buffers.get(view.buffer().index()).map_or(&[][..], |b| &b[..]);
    let view_data = view
        .offset()
        .checked_add(view.length())
        .and_then(|end| buffer.get(view.offset()..end))
        .ok_or_else(|| ctx.truncated(None, format!("buffer view {} lies outside its buffer", view.index())))?;
    let count = accessor.count();
    if count == 0 {
        return Ok(Elements { data: &[], stride, count });
    }
    let end = stride
        .checked_mul(count - 1)
        .and_then(|b| b.checked_add(element))
        .and_then(|b| b.checked_add(accessor.offset()));
    let data = end
        .and_then(|end| view_data.get(accessor.offset()..end))
        .ok_or_else(|| ctx.truncated(None, format!("accessor {i} reaches past its buffer view")))?;
    Ok(Elements { data, stride, count })
}

fn position_data<'b>(
    accessor: &Accessor<'_>,
    buffers: &'b [Cow<'_, [u8]>],
    ctx: Ctx<'_>,
) -> Result<Elements<'b>, IoError> {
    if accessor.dimensions() != Dimensions::Vec3 || accessor.data_type() != DataType::F32 || accessor.normalized() {
        return Err(ctx.unsupported(format!(
            "POSITION accessor {} is {:?} {:?} (only VEC3 FLOAT is read)",
            accessor.index(),
            accessor.dimensions(),
            accessor.data_type()
        )));
    }
    accessor_data(accessor, buffers, ctx)
}

fn read_positions<'a>(elements: &'a Elements<'_>) -> impl Iterator<Item = DVec3> + 'a {
    (0..elements.count).map(|k| {
        let b: [u8; 12] = elements.get(k);
        let c = [0, 4, 8].map(|o| f64::from(f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]])));
        DVec3::from(c)
    })
}

/// The index accessor's elements and their size in bytes.
fn index_data<'b>(
    accessor: &Accessor<'_>,
    buffers: &'b [Cow<'_, [u8]>],
    ctx: Ctx<'_>,
) -> Result<(Elements<'b>, usize), IoError> {
    let size = match (accessor.dimensions(), accessor.data_type()) {
        (Dimensions::Scalar, DataType::U8) => 1,
        (Dimensions::Scalar, DataType::U16) => 2,
        (Dimensions::Scalar, DataType::U32) => 4,
        (d, t) => {
            return Err(ctx.parse(
                None,
                format!("index accessor {} is {d:?} {t:?} (must be an unsigned integer SCALAR)", accessor.index()),
            ))
        }
    };
    Ok((accessor_data(accessor, buffers, ctx)?, size))
}

/// How a `TEXCOORD_0` accessor stores its values, if it is one the spec
/// allows (glTF 2.0 §3.7.2.1: `FLOAT`, normalized `UNSIGNED_BYTE` or
/// `UNSIGNED_SHORT`, as `VEC2`); otherwise why not.
fn texcoord_type(accessor: &Accessor<'_>) -> Result<DataType, String> {
    match (accessor.dimensions(), accessor.data_type(), accessor.normalized()) {
        (Dimensions::Vec2, DataType::F32, false) => Ok(DataType::F32),
        (Dimensions::Vec2, t @ (DataType::U8 | DataType::U16), true) => Ok(t),
        (d, t, normalized) => Err(format!(
            "TEXCOORD_0 accessor {} is {d:?} {t:?}{} (only VEC2 FLOAT and normalized UNSIGNED_BYTE or \
             UNSIGNED_SHORT are read)",
            accessor.index(),
            if normalized { " normalized" } else { "" }
        )),
    }
}

/// The texture coordinates of an accessor that passed [`texcoord_type`],
/// `v` flipped from glTF's top-left origin to the bottom-left one of OBJ.
fn read_texcoords<'a>(elements: &'a Elements<'_>, ty: DataType) -> impl Iterator<Item = DVec2> + 'a {
    (0..elements.count).map(move |k| {
        let [u, v] = match ty {
            DataType::U8 => elements.get::<2>(k).map(|c| f64::from(c) / 255.0),
            DataType::U16 => {
                let b: [u8; 4] = elements.get(k);
                [0, 2].map(|o| f64::from(u16::from_le_bytes([b[o], b[o + 1]])) / 65535.0)
            }
            _ => {
                let b: [u8; 8] = elements.get(k);
                [0, 4].map(|o| f64::from(f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]])))
            }
        };
        DVec2::new(u, 1.0 - v)
    })
}

/// The texture coordinates of the primitives read so far: the values of
/// every `TEXCOORD_0` accessor (each read once) and one index per corner,
/// while every primitive has them.
#[derive(Default)]
struct UvChannel {
    values: Vec<DVec2>,
    indices: Vec<u32>,
    /// First value of every accessor read so far.
    first_value: HashMap<usize, u32>,
    /// A primitive that has them and one that has not, by name.
    with: Option<String>,
    without: Option<String>,
    /// Why they are dropped, once they are.
    dropped: Option<String>,
}

impl UvChannel {
    fn finish(self, path: &Path) -> (Option<FaceVarying>, Option<ReadWarning>) {
        let reason = match (self.dropped, self.with, self.without) {
            (Some(reason), _, _) => reason,
            (None, Some(with), Some(without)) => format!("{without} has no TEXCOORD_0, but {with} has"),
            (None, Some(_), None) => return (Some(FaceVarying { values: self.values, indices: self.indices }), None),
            (None, None, _) => return (None, None),
        };
        (None, Some(ReadWarning::UvsDropped { path: path.to_path_buf(), line: None, reason }))
    }
}

fn read_indices(elements: &Elements<'_>, size: usize) -> Vec<u32> {
    (0..elements.count)
        .map(|k| match size {
            1 => u32::from(elements.get::<1>(k)[0]),
            2 => u32::from(u16::from_le_bytes(elements.get(k))),
            _ => u32::from_le_bytes(elements.get(k)),
        })
        .collect()
}

/// The gltf crate's validation errors in one short line: the first three and
/// how many more (its own message lists every one, after a second "invalid glTF:").
fn validation_message(error: ::gltf::Error) -> String {
    const SHOWN: usize = 3;
    let ::gltf::Error::Validation(errors) = error else { return format!("invalid glTF: {error}") };
    let first: Vec<String> = errors.iter().take(SHOWN).map(|(path, e)| format!("{path}: {e}")).collect();
    let more = match errors.len().saturating_sub(SHOWN) {
        0 => String::new(),
        n => format!(" (and {n} more)"),
    };
    crate::text::escape_controls(format!("invalid glTF: {}{more}", first.join("; ")).into()).into_owned()
}

/// How a primitive that is not read is named in "no triangle primitives (found: …)".
fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "points",
        Mode::Lines => "lines",
        Mode::LineLoop => "line loops",
        Mode::LineStrip => "line strips",
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => "triangles without POSITION",
    }
}

pub(crate) fn read(
    bytes: &[u8],
    ctx: Ctx<'_>,
    base_dir: Option<&Path>,
) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
    let glb = bytes.starts_with(GLB_MAGIC);
    let (json, bin) = if glb {
        split_glb(bytes, ctx)?
    } else {
        let text = strip_bom(bytes);
        if is_blank(text) {
            return Err(ctx.empty());
        }
        check_text(text, Format::Gltf, ctx)?;
        (text, None)
    };
    let root: ::gltf::json::Root = ::gltf::json::deserialize::from_slice(json).map_err(|e| {
        let line = (!glb && e.line() > 0).then_some(e.line());
        ctx.parse(line, crate::text::escape_controls(format!("invalid glTF JSON: {e}").into()))
    })?;
    // gltf-json 1.4.1 looks up the POSITION accessor without a bounds check
    // while validating (a panic on a dangling index): check indices first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some((semantic, index)) =
                primitive.attributes.iter().find(|(_, index)| index.value() >= root.accessors.len())
            {
                return Err(ctx.parse(
                    None,
                    format!("mesh {m} primitive {p}: attribute {semantic:?} refers to missing accessor {index}"),
                ));
            }
        }
    }
    let doc = Document::from_json(root).map_err(|e| ctx.parse(None, validation_message(e)))?;
    let buffers = load_buffers(&doc, bin, base_dir, ctx)?;

    // Vertices, texture coordinates and triangles produced, against the bytes
    // they come from: without accessor reuse every vertex takes 12 bytes,
    // every texture coordinate 2 and every triangle at least one (a strip of
    // u8 indices).
    let budget = bytes.len() + buffers.iter().map(|b| b.len()).sum::<usize>();
    let mut produced = 0usize;
    let mut positions: Vec<DVec3> = Vec::new();
    let mut faces = FaceList::new();
    // First vertex of every POSITION accessor read so far.
    let mut first_vertex: HashMap<usize, u32> = HashMap::new();
    let mut uvs = UvChannel::default();
    let mut any_triangles = false;
    let mut skipped: Vec<&'static str> = Vec::new();
    for mesh in doc.meshes() {
        for primitive in mesh.primitives() {
            let mode = primitive.mode();
            let accessor = primitive.get(&Semantic::Positions);
            let (true, Some(accessor)) =
                (matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan), accessor)
            else {
                if !skipped.contains(&mode_name(mode)) {
                    skipped.push(mode_name(mode));
                }
                continue;
            };
            any_triangles = true;
            let where_ = format!("mesh {} primitive {}", mesh.index(), primitive.index());
            // Check everything against the data before allocating anything.
            let points = position_data(&accessor, &buffers, ctx)?;
            let n = points.count;
            let index_elements = primitive.indices().map(|a| index_data(&a, &buffers, ctx)).transpose()?;
            let texcoords = match primitive.get(&Semantic::TexCoords(0)) {
                None => {
                    uvs.without.get_or_insert_with(|| where_.clone());
                    None
                }
                Some(accessor) => {
                    uvs.with.get_or_insert_with(|| where_.clone());
                    match texcoord_type(&accessor) {
                        Err(reason) => {
                            uvs.dropped.get_or_insert(format!("{where_}: {reason}"));
                            None
                        }
                        Ok(ty) => {
                            let elements = accessor_data(&accessor, &buffers, ctx)?;
                            if elements.count != n {
                                return Err(ctx.parse(
                                    None,
                                    format!("{where_}: TEXCOORD_0 has {} elements, POSITION {n}", elements.count),
                                ));
                            }
                            Some((accessor.index(), elements, ty))
                        }
                    }
                }
            };
            let index_count = index_elements.as_ref().map_or(n, |(e, _)| e.count);
            let triangle_count = match mode {
                Mode::Triangles if index_count % 3 != 0 => {
                    return Err(ctx.parse(None, format!("{where_}: {index_count} indices is not a multiple of 3")))
                }
                Mode::Triangles => index_count / 3,
                _ => index_count.saturating_sub(2),
            };
            let new_vertices = if first_vertex.contains_key(&accessor.index()) { 0 } else { n };
            // Texture coordinates are read while every primitive has them, each accessor once.
            let new_uvs = match &texcoords {
                Some((index, ..))
                    if uvs.without.is_none() && uvs.dropped.is_none() && !uvs.first_value.contains_key(index) =>
                {
                    n
                }
                _ => 0,
            };
            produced = produced.saturating_add(new_vertices).saturating_add(new_uvs).saturating_add(triangle_count);
            if produced > budget {
                return Err(ctx.unsupported(format!(
                    "{where_}: primitives reuse accessors for more vertices, texture coordinates and triangles \
                     ({produced} so far) than the file has bytes ({budget})"
                )));
            }

            let base = match first_vertex.get(&accessor.index()) {
                Some(&base) => base,
                None => {
                    let base = u32::try_from(positions.len() + n)
                        .map(|_| positions.len() as u32)
                        .map_err(|_| ctx.unsupported("more than 2^32 vertices"))?;
                    positions.extend(read_positions(&points));
                    first_vertex.insert(accessor.index(), base);
                    base
                }
            };
            let indices = match &index_elements {
                Some((elements, size)) => read_indices(elements, *size),
                None => (0..n as u32).collect(),
            };
            if let Some(&bad) = indices.iter().find(|&&v| v as usize >= n) {
                return Err(ctx.parse(None, format!("{where_}: index {bad} is out of range ({n} vertices)")));
            }
            // Texture coordinates are kept only while every primitive has them.
            let uv_base = match texcoords {
                Some((index, elements, ty)) if uvs.without.is_none() && uvs.dropped.is_none() => {
                    Some(match uvs.first_value.get(&index) {
                        Some(&base) => base,
                        None => {
                            let base = u32::try_from(uvs.values.len() + n)
                                .map(|_| uvs.values.len() as u32)
                                .map_err(|_| ctx.unsupported("more than 2^32 texture coordinates"))?;
                            uvs.values.extend(read_texcoords(&elements, ty));
                            uvs.first_value.insert(index, base);
                            base
                        }
                    })
                }
                _ => {
                    uvs.indices = Vec::new();
                    None
                }
            };
            for t in 0..triangle_count {
                let corners = match mode {
                    Mode::Triangles => [3 * t, 3 * t + 1, 3 * t + 2],
                    // glTF 2.0 §3.7.2.1: strip triangle i is (p_i, p_{i+1+i%2}, p_{i+2-i%2}).
                    Mode::TriangleStrip => [t, t + 1 + t % 2, t + 2 - t % 2],
                    // Fan triangle i is (p_{i+1}, p_{i+2}, p_0).
                    _ => [t + 1, t + 2, 0],
                };
                let corners = corners.map(|k| indices[k]);
                faces.push(&corners.map(|v| base + v));
                if let Some(uv_base) = uv_base {
                    uvs.indices.extend(corners.map(|v| uv_base + v));
                }
            }
        }
    }
    if !any_triangles && !skipped.is_empty() {
        return Err(ctx.unsupported(format!("no triangle primitives (found: {})", skipped.join(", "))));
    }
    let (uvs, warning) = uvs.finish(ctx.path);
    Ok((PolygonSoup { uvs, ..PolygonSoup::new(positions, faces) }, warning.into_iter().collect()))
}

/// A mesh with per-vertex texture coordinates: vertices split where their
/// corners use different value indices (see the module doc).
struct Split {
    /// The vertices that are copies, in order: the vertex each copies.
    copies: Vec<u32>,
    /// The faces on the split vertices.
    faces: FaceList,
    /// The texture coordinate index of every vertex, copies included
    /// (`None` for a vertex no face uses).
    uv_of_vertex: Vec<Option<u32>>,
}

fn split_at_seams(faces: &FaceList, vertex_count: usize, uvs: &FaceVarying) -> Split {
    let mut uv_of_vertex: Vec<Option<u32>> = vec![None; vertex_count];
    let mut copy_of: HashMap<(u32, u32), u32> = HashMap::new();
    let mut copies = Vec::new();
    let corners = (faces.indices().iter().zip(&uvs.indices))
        .map(|(&v, &uv)| match uv_of_vertex[v as usize] {
            None => {
                uv_of_vertex[v as usize] = Some(uv);
                v
            }
            Some(first) if first == uv => v,
            Some(_) => *copy_of.entry((v, uv)).or_insert_with(|| {
                copies.push(v);
                uv_of_vertex.push(Some(uv));
                (uv_of_vertex.len() - 1) as u32
            }),
        })
        .collect();
    Split { copies, faces: FaceList::from_raw(faces.offsets().to_vec(), corners), uv_of_vertex }
}

pub(crate) fn write(mesh: &MeshView<'_>, binary: bool, ctx: Ctx<'_>) -> Result<Vec<u8>, IoError> {
    let mut positions: Vec<Vec3> = mesh.positions.iter().map(|p| p.as_vec3()).collect();
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(
            ctx.invalid(format!("glTF needs finite coordinates within f32 range; vertex {i} is {}", mesh.positions[i]))
        );
    }
    let mut normals: Option<Vec<Vec3>> =
        mesh.normals.map(|ns| ns.iter().map(|n| n.as_vec3().try_normalize().unwrap_or(Vec3::Z)).collect());
    let split = mesh.uvs.map(|uvs| split_at_seams(mesh.faces, mesh.positions.len(), uvs));
    let faces = split.as_ref().map_or(mesh.faces, |s| &s.faces);
    let indices: Vec<u32> = faces.iter().flat_map(fan).flatten().collect();
    let texcoords: Option<Vec<Vec2>> = split.as_ref().zip(mesh.uvs).map(|(split, uvs)| {
        for &v in &split.copies {
            positions.push(positions[v as usize]);
            if let Some(normals) = &mut normals {
                normals.push(normals[v as usize]);
            }
        }
        // Flipped to glTF's top-left origin; a vertex no face uses gets (0, 0).
        let uv = |i: Option<u32>| i.map_or(DVec2::new(0.0, 1.0), |i| uvs.values[i as usize]);
        split.uv_of_vertex.iter().map(|&i| uv(i)).map(|p| Vec2::new(p.x as f32, (1.0 - p.y) as f32)).collect()
    });

    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut attributes = serde_json::Map::new();
    let mut primitive = serde_json::Map::new();
    if !positions.is_empty() {
        let (min, max) =
            positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let mut add_view = |bytes: &[u8], target: u32| {
            views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len(), "target": target}));
            bin.extend_from_slice(bytes);
            views.len() - 1
        };
        let vec3_bytes =
            |v: &[Vec3]| v.iter().flat_map(|p| p.to_array()).flat_map(f32::to_le_bytes).collect::<Vec<u8>>();
        let view = add_view(&vec3_bytes(&positions), 34962);
        accessors.push(json!({"bufferView": view, "componentType": 5126, "count": positions.len(), "type": "VEC3",
            "min": min.to_array(), "max": max.to_array()}));
        attributes.insert("POSITION".into(), json!(accessors.len() - 1));
        if let Some(normals) = &normals {
            let view = add_view(&vec3_bytes(normals), 34962);
            accessors.push(json!({"bufferView": view, "componentType": 5126, "count": normals.len(), "type": "VEC3"}));
            attributes.insert("NORMAL".into(), json!(accessors.len() - 1));
        }
        if let Some(texcoords) = &texcoords {
            let bytes: Vec<u8> = texcoords.iter().flat_map(|p| p.to_array()).flat_map(f32::to_le_bytes).collect();
            let view = add_view(&bytes, 34962);
            accessors
                .push(json!({"bufferView": view, "componentType": 5126, "count": texcoords.len(), "type": "VEC2"}));
            attributes.insert("TEXCOORD_0".into(), json!(accessors.len() - 1));
        }
        if indices.is_empty() {
            // No faces: keep the points (glTF has no empty index accessors).
            primitive.insert("mode".into(), json!(0));
        } else {
            let bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
            let view = add_view(&bytes, 34963);
            accessors
                .push(json!({"bufferView": view, "componentType": 5125, "count": indices.len(), "type": "SCALAR"}));
            primitive.insert("indices".into(), json!(accessors.len() - 1));
            primitive.insert("mode".into(), json!(4));
        }
        primitive.insert("attributes".into(), serde_json::Value::Object(attributes));
    }

    let mut root = json!({"asset": {"version": "2.0", "generator": "subdiv-io"}});
    if !bin.is_empty() {
        let mut buffer = json!({"byteLength": bin.len()});
        if !binary {
            buffer["uri"] = json!(format!("data:application/octet-stream;base64,{}", base64::encode(&bin)));
        }
        root["buffers"] = json!([buffer]);
        root["bufferViews"] = json!(views);
        root["accessors"] = json!(accessors);
        root["meshes"] = json!([{"primitives": [primitive]}]);
        root["nodes"] = json!([{"mesh": 0}]);
        root["scenes"] = json!([{"nodes": [0]}]);
        root["scene"] = json!(0);
    }
    let mut text = serde_json::to_vec(&root).map_err(|e| ctx.invalid(format!("glTF JSON: {e}")))?;
    if !binary {
        text.push(b'\n');
        return Ok(text);
    }

    // GLB: 12-byte header, JSON chunk padded with spaces, BIN chunk padded with zeros.
    text.resize(text.len().next_multiple_of(4), b' ');
    bin.resize(bin.len().next_multiple_of(4), 0);
    let bin_chunk = if bin.is_empty() { 0 } else { 8 + bin.len() };
    let total = 12 + 8 + text.len() + bin_chunk;
    let total = u32::try_from(total).map_err(|_| ctx.invalid("GLB output would exceed 4 GiB"))?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(GLB_MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(&text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("a%20b%2"), b"a b%2");
        assert_eq!(percent_decode("%zz%41"), b"%zzA");
    }

    #[test]
    fn uris_with_a_scheme_absolute_or_escaping_are_refused_before_the_file_system_is_asked() {
        let ctx = Ctx::new(Path::new("t.gltf"));
        // The directory does not exist: a refusal cannot come from looking at files.
        let dir = Some(Path::new("/nonexistent-subdiv-dir"));
        for (uri, reason) in [
            ("https://example.com/x.bin", "scheme"),
            ("file:///etc/hostname", "scheme"),
            ("FILE:x.bin", "scheme"),
            ("c:x.bin", "scheme"),
            ("/etc/hostname", "absolute"),
            ("%2Fetc/hostname", "absolute"),
            ("../x.bin", "out of the glTF file's directory"),
            ("a/../../x.bin", "out of the glTF file's directory"),
            ("%2E%2E/x.bin", "out of the glTF file's directory"),
            ("a/%2e%2e%2F..%2fx.bin", "out of the glTF file's directory"),
            ("x%00.bin", "NUL"),
        ] {
            let e = uri_data(uri, 4, dir, ctx).unwrap_err();
            assert!(matches!(&e, IoError::RefusedUri { uri: u, .. } if u == uri), "{uri}: {e}");
            assert!(e.to_string().contains(reason), "{uri}: {e}");
        }
        // A '..' that stays inside is resolved (here: the directory is missing).
        let e = uri_data("a/../x.bin", 4, dir, ctx).unwrap_err();
        assert!(matches!(e, IoError::Io { .. }), "{e}");
        assert_eq!(uri_data("data:application/octet-stream;base64,AAEC", 3, None, ctx).unwrap(), vec![0, 1, 2]);
        assert_eq!(uri_data("DATA:,a%20b", 3, None, ctx).unwrap(), b"a b");
    }
}
