//! Stanford PLY, ASCII and binary (both byte orders), read and written by hand.
//!
//! Read: the `vertex` element's `x`, `y`, `z` properties of any scalar type
//! (`char`…`double` and the `int8`…`float64` aliases), other vertex
//! properties skipped by their size; the `face` element's list property
//! `vertex_indices` (or `vertex_index`) with any count and item types; every
//! other element skipped (its tokens in ASCII, the property sizes in
//! binary, lists included). An element without properties takes no bytes,
//! whatever its count, and is skipped at once (a `vertex` or `face` element
//! without properties lacks the ones it needs and is an error). A leading
//! UTF-8 byte-order mark is skipped; UTF-16, binary data where the `ply` magic
//! should be, and binary data after an ASCII header are reported as such.
//! Counts, list lengths and indices too large for their type are "out of
//! range"; allocations are capped by what the remaining bytes can hold.
//!
//! Texture coordinates ([`PolygonSoup::uvs`]) come from per-vertex
//! properties — the first pair present of `u v`, `s t`, `texture_u
//! texture_v`, `texture_s texture_t`, any scalar type — as one value per
//! vertex (value indices = the faces' vertex indices), or from the face list
//! property `texcoord` (two values per corner, as MeshLab writes it), which
//! wins when both are present. Per-corner values are welded per vertex:
//! corners of one vertex with the same (u, v) share one value, so a seam is
//! where the values differ (a seam between equal values is not kept). A
//! `texcoord` list whose length is not twice the face's corner count is an
//! error; when only some face elements have `texcoord`, it is not used.
//!
//! Write: `binary_little_endian` ([`Format::PlyBinary`](crate::Format::PlyBinary))
//! or `ascii` ([`Format::PlyAscii`](crate::Format::PlyAscii)); `double x y z`,
//! `double nx ny nz` when normals are given, and `list uchar int
//! vertex_indices` (`uint` counts when a face has more than 255 corners,
//! `uint` indices beyond `i32::MAX`). Doubles keep every bit of the positions.
//! Texture coordinates are written as `double u v` per vertex when every
//! vertex's corners use one value (no seams), otherwise as the face list
//! `list uchar double texcoord` (`uint` counts when a face has more than
//! 127 corners).

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::collections::HashMap;
use std::io::{self, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use subdiv_mesh::{FaceList, FaceVarying, PolygonSoup};

use crate::error::{Ctx, IoError};
use crate::text::{
    is_blank, parse_bounded, parse_f64, parse_integer, show, sniff, strip_bom, tokens, IntError, Lines, NotText,
    TextOut,
};
use crate::{Format, MeshView};

mod stream;
pub(crate) use stream::read_streamed;

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &[u8]) -> Option<Self> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

/// What a property means to us.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Skip,
    Coordinate(usize),
    /// Texture coordinate `u` (0) or `v` (1) of a vertex.
    Uv(usize),
    Indices,
    /// Texture coordinates of a face, two per corner.
    TexCoords,
}

/// Names of per-vertex texture coordinate pairs, in order of preference.
const UV_NAMES: [[&str; 2]; 4] = [["u", "v"], ["s", "t"], ["texture_u", "texture_v"], ["texture_s", "texture_t"]];

#[derive(Clone, Debug)]
struct Property {
    name: String,
    /// `Some(count type)` for a list property.
    list: Option<Scalar>,
    ty: Scalar,
    role: Role,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
    line: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    LittleEndian,
    BigEndian,
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    body_offset: usize,
    body_line: usize,
}

fn parse_header(bytes: &[u8], ctx: Ctx<'_>) -> Result<Header, IoError> {
    let mut lines = Lines::new(bytes);
    match lines.next() {
        Some((_, magic)) if magic.trim_ascii() == b"ply" => {}
        _ => {
            return Err(match sniff(bytes) {
                Some(NotText::Utf16) => ctx.utf16(),
                Some(NotText::Binary) => ctx.binary(None, Format::PlyAscii),
                None => ctx.parse(1, "missing the 'ply' magic line"),
            })
        }
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some((n, line)) = lines.next() else {
            return Err(ctx.truncated(lines.line(), "header has no end_header line"));
        };
        let t: Vec<&[u8]> = tokens(line).collect();
        match t.first().copied() {
            None | Some(b"comment" | b"obj_info") => {}
            Some(b"end_header") => break,
            Some(b"format") => {
                encoding = Some(match t.get(1).copied() {
                    Some(b"ascii") => Encoding::Ascii,
                    Some(b"binary_little_endian") => Encoding::LittleEndian,
                    Some(b"binary_big_endian") => Encoding::BigEndian,
                    other => return Err(ctx.parse(n, format!("unknown format '{}'", show(other.unwrap_or(b""))))),
                });
            }
            Some(b"element") => {
                let (Some(name), Some(count)) = (t.get(1), t.get(2)) else {
                    return Err(ctx.parse(n, "element line needs a name and a count"));
                };
                let count = parse_bounded(count, "element count").map_err(|message| ctx.parse(n, message))?;
                let name = show(name).into_owned();
                elements.push(Element { name, count, properties: Vec::new(), line: n });
            }
            Some(b"property") => {
                let Some(element) = elements.last_mut() else {
                    return Err(ctx.parse(n, "property before any element"));
                };
                let ty = |i: usize| -> Result<Scalar, IoError> {
                    let name = t.get(i).copied().unwrap_or(b"");
                    Scalar::parse(name).ok_or_else(|| ctx.parse(n, format!("unknown property type '{}'", show(name))))
                };
                let (list, ty, name) = if t.get(1).copied() == Some(b"list") {
                    (Some(ty(2)?), ty(3)?, t.get(4))
                } else {
                    (None, ty(1)?, t.get(2))
                };
                let name = name.ok_or_else(|| ctx.parse(n, "property has no name"))?;
                let name = show(name).into_owned();
                element.properties.push(Property { name, list, ty, role: Role::Skip });
            }
            Some(other) => return Err(ctx.parse(n, format!("unknown header keyword '{}'", show(other)))),
        }
    }
    let encoding = encoding.ok_or_else(|| ctx.parse(None, "header has no format line"))?;

    for element in &mut elements {
        match element.name.as_str() {
            "vertex" => {
                for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                    let p = element.properties.iter_mut().find(|p| p.name == name && p.list.is_none());
                    let p =
                        p.ok_or_else(|| ctx.parse(element.line, format!("vertex element has no '{name}' property")))?;
                    p.role = Role::Coordinate(axis);
                }
                let scalar = |properties: &[Property], name: &str| {
                    properties.iter().position(|p| p.name == name && p.list.is_none() && p.role == Role::Skip)
                };
                let pair = UV_NAMES
                    .iter()
                    .find_map(|[u, v]| Some((scalar(&element.properties, u)?, scalar(&element.properties, v)?)));
                if let Some((u, v)) = pair {
                    element.properties[u].role = Role::Uv(0);
                    element.properties[v].role = Role::Uv(1);
                }
            }
            "face" => {
                let p = element
                    .properties
                    .iter_mut()
                    .find(|p| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"));
                let p = p.ok_or_else(|| ctx.unsupported("face element without a 'vertex_indices' list property"))?;
                p.role = Role::Indices;
                if let Some(p) = element.properties.iter_mut().find(|p| p.list.is_some() && p.name == "texcoord") {
                    p.role = Role::TexCoords;
                }
            }
            _ => {}
        }
    }
    Ok(Header { encoding, elements, body_offset: lines.offset(), body_line: lines.line() + 1 })
}

/// Converts a list length or index read as `f64` (exact for every PLY
/// integer type) to a `u32`; otherwise says why not, after the value's name.
fn u32_from_f64(x: f64) -> Result<u32, String> {
    if x.is_nan() || (x.is_finite() && x.fract() != 0.0) {
        Err(format!("{x} is not an integer"))
    } else if x < 0.0 {
        Err(format!("{x} is negative"))
    } else if x > f64::from(u32::MAX) {
        Err(format!("{x} out of range"))
    } else {
        Ok(x as u32)
    }
}

/// What stopped a record from being read.
enum Stop {
    /// The data ended (binary) — or the file ended (ASCII, at this line).
    Ends(Option<usize>),
    /// A value is wrong; the message names it.
    Bad(Option<usize>, String),
}

impl Stop {
    /// Puts the name of the value in front of the message of [`Values::integer`].
    fn about(self, subject: impl FnOnce() -> String) -> Stop {
        match self {
            Stop::Bad(line, message) => Stop::Bad(line, format!("{} {message}", subject())),
            ends => ends,
        }
    }
}

/// A source of property values: binary words or ASCII tokens.
trait Values {
    fn value(&mut self, ty: Scalar) -> Result<f64, Stop>;
    /// A list length or index; the error message leaves out the value's name
    /// ([`Stop::about`] adds it).
    fn integer(&mut self, ty: Scalar) -> Result<u32, Stop> {
        let x = self.value(ty)?;
        u32_from_f64(x).map_err(|message| Stop::Bad(self.line(), message))
    }
    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), Stop>;
    /// Upper bound on how many more values of this type can follow (caps allocations).
    fn room(&self, ty: Scalar) -> usize;
    /// The fewest bytes a value of this type takes.
    fn min_size(&self, ty: Scalar) -> usize;
    /// Line of the last value (ASCII only).
    fn line(&self) -> Option<usize>;
    /// Reads all records of a vertex element at once, when they have a fixed
    /// layout that the data holds in full; false (nothing read) otherwise.
    fn fast_vertices(
        &mut self,
        _element: &Element,
        _positions: &mut Vec<DVec3>,
        _uvs: Option<&mut Vec<DVec2>>,
    ) -> bool {
        false
    }
    /// Reads all records of a face element that holds nothing but its
    /// integer index list into `faces` (empty before), when every value is
    /// in range and the data holds them all; false (nothing read) otherwise.
    fn fast_faces(&mut self, _element: &Element, _faces: &mut FaceList) -> bool {
        false
    }
}

/// A scalar of type `ty` from the start of `b` (at least `ty.size()` bytes).
#[inline(always)]
fn decode(ty: Scalar, big_endian: bool, b: &[u8]) -> f64 {
    fn word<const N: usize>(b: &[u8], big_endian: bool) -> [u8; N] {
        let mut a = [0u8; N];
        a.copy_from_slice(&b[..N]);
        if big_endian {
            a.reverse();
        }
        a
    }
    match ty {
        Scalar::I8 => f64::from(b[0] as i8),
        Scalar::U8 => f64::from(b[0]),
        Scalar::I16 => f64::from(i16::from_le_bytes(word(b, big_endian))),
        Scalar::U16 => f64::from(u16::from_le_bytes(word(b, big_endian))),
        Scalar::I32 => f64::from(i32::from_le_bytes(word(b, big_endian))),
        Scalar::U32 => f64::from(u32::from_le_bytes(word(b, big_endian))),
        Scalar::F32 => f64::from(f32::from_le_bytes(word(b, big_endian))),
        Scalar::F64 => f64::from_le_bytes(word(b, big_endian)),
    }
}

/// An integer list length or index of type `ty` from the start of `b`, or
/// `None` for a float type or a negative value (which the record loop
/// reports).
#[inline(always)]
fn decode_index(ty: Scalar, big_endian: bool, b: &[u8]) -> Option<u32> {
    let word = |b: &[u8]| {
        let mut a = [0u8; 4];
        a.copy_from_slice(&b[..4]);
        if big_endian {
            u32::from_be_bytes(a)
        } else {
            u32::from_le_bytes(a)
        }
    };
    let x = match ty {
        Scalar::F32 | Scalar::F64 => return None,
        Scalar::U8 => return Some(u32::from(b[0])),
        Scalar::U32 => return Some(word(b)),
        // A negative `int` has the top bit set.
        Scalar::I32 => return Some(word(b)).filter(|&w| w <= i32::MAX as u32),
        _ => decode(ty, big_endian, b),
    };
    (x >= 0.0).then_some(x as u32)
}

struct Binary<'a> {
    data: &'a [u8],
    pos: usize,
    big_endian: bool,
}

impl Binary<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], Stop> {
        let end = self.pos + N;
        let bytes = self.data.get(self.pos..end).ok_or(Stop::Ends(None))?;
        let mut a: [u8; N] = bytes.try_into().map_err(|_| Stop::Ends(None))?;
        if self.big_endian {
            a.reverse();
        }
        self.pos = end;
        Ok(a)
    }
}

impl Values for Binary<'_> {
    fn value(&mut self, ty: Scalar) -> Result<f64, Stop> {
        Ok(match ty {
            Scalar::I8 => f64::from(i8::from_le_bytes(self.take()?)),
            Scalar::U8 => f64::from(u8::from_le_bytes(self.take()?)),
            Scalar::I16 => f64::from(i16::from_le_bytes(self.take()?)),
            Scalar::U16 => f64::from(u16::from_le_bytes(self.take()?)),
            Scalar::I32 => f64::from(i32::from_le_bytes(self.take()?)),
            Scalar::U32 => f64::from(u32::from_le_bytes(self.take()?)),
            Scalar::F32 => f64::from(f32::from_le_bytes(self.take()?)),
            Scalar::F64 => f64::from_le_bytes(self.take()?),
        })
    }

    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), Stop> {
        let end = n.checked_mul(ty.size()).and_then(|b| self.pos.checked_add(b)).ok_or(Stop::Ends(None))?;
        if end > self.data.len() {
            return Err(Stop::Ends(None));
        }
        self.pos = end;
        Ok(())
    }

    fn room(&self, ty: Scalar) -> usize {
        (self.data.len() - self.pos) / ty.size()
    }

    fn min_size(&self, ty: Scalar) -> usize {
        ty.size()
    }

    fn line(&self) -> Option<usize> {
        None
    }

    fn fast_vertices(&mut self, element: &Element, positions: &mut Vec<DVec3>, uvs: Option<&mut Vec<DVec2>>) -> bool {
        let Some(layout) = VertexLayout::of(element, self.big_endian) else { return false };
        let rest = &self.data[self.pos..];
        let Some(bytes) = element.count.checked_mul(layout.stride).filter(|&n| n <= rest.len()) else { return false };
        layout.decode(&rest[..bytes], positions, uvs);
        self.pos += bytes;
        true
    }

    fn fast_faces(&mut self, element: &Element, faces: &mut FaceList) -> bool {
        let Some(layout) = FaceLayout::of(element, self.big_endian) else { return false };
        let data = &self.data[self.pos..];
        let (count_size, size) = (layout.count_ty.size(), layout.ty.size());
        let mut out = FaceArrays::with_capacity(element.count.min(data.len() / count_size), data.len() / size);
        let (mut done, mut pos) = (0, 0);
        while done < element.count {
            match layout.decode(&data[pos..], element.count - done, &mut out) {
                Some((records, bytes)) if records > 0 => (done, pos) = (done + records, pos + bytes),
                _ => return false,
            }
        }
        *faces = out.into_face_list();
        self.pos += pos;
        true
    }
}

/// Where a vertex record of fixed layout keeps its coordinates and texture
/// coordinates: the byte offset and type of x, y, z, u, v.
#[derive(Clone, Copy, Debug)]
struct VertexLayout {
    stride: usize,
    at: [(usize, Scalar); 5],
    big_endian: bool,
}

impl VertexLayout {
    /// The layout of `element`'s records; `None` when a list property makes
    /// their size vary.
    fn of(element: &Element, big_endian: bool) -> Option<Self> {
        if element.properties.iter().any(|p| p.list.is_some()) {
            return None;
        }
        let mut at = [(0usize, Scalar::F64); 5];
        let mut stride = 0;
        for p in &element.properties {
            match p.role {
                Role::Coordinate(axis) => at[axis] = (stride, p.ty),
                Role::Uv(k) => at[3 + k] = (stride, p.ty),
                _ => {}
            }
            stride += p.ty.size();
        }
        Some(Self { stride: stride.max(1), at, big_endian })
    }

    #[inline(always)]
    fn value(&self, record: &[u8], (offset, ty): (usize, Scalar)) -> f64 {
        decode(ty, self.big_endian, &record[offset..])
    }

    /// Decodes whole records (`bytes.len()` a multiple of the stride), in
    /// parallel, appending to `positions` (and `uvs`).
    fn decode(&self, bytes: &[u8], positions: &mut Vec<DVec3>, uvs: Option<&mut Vec<DVec2>>) {
        let records = bytes.par_chunks_exact(self.stride).with_min_len(DECODE_MIN_RECORDS);
        let at = self.at;
        positions.par_extend(
            records.clone().map(|r| DVec3::new(self.value(r, at[0]), self.value(r, at[1]), self.value(r, at[2]))),
        );
        if let Some(uvs) = uvs {
            uvs.par_extend(records.map(|r| DVec2::new(self.value(r, at[3]), self.value(r, at[4]))));
        }
    }
}

/// Records decoded per task at the least: below this, splitting costs more
/// than it saves.
const DECODE_MIN_RECORDS: usize = 1 << 12;

/// The layout of a face element that holds nothing but its index list, of
/// integer types.
#[derive(Clone, Copy, Debug)]
struct FaceLayout {
    count_ty: Scalar,
    ty: Scalar,
    big_endian: bool,
}

impl FaceLayout {
    fn of(element: &Element, big_endian: bool) -> Option<Self> {
        let [Property { list: Some(count_ty), ty, role: Role::Indices, .. }] = element.properties.as_slice() else {
            return None;
        };
        let integer = |t: &Scalar| !matches!(t, Scalar::F32 | Scalar::F64);
        (integer(count_ty) && integer(ty)).then_some(Self { count_ty: *count_ty, ty: *ty, big_endian })
    }

    /// The corner count of the record starting `bytes` (`None`: too short).
    #[inline(always)]
    fn count(&self, bytes: &[u8]) -> Option<usize> {
        bytes
            .get(..self.count_ty.size())
            .and_then(|b| decode_index(self.count_ty, self.big_endian, b))
            .map(|n| n as usize)
    }

    /// Decodes up to `records` whole records from the start of `bytes` into
    /// `faces`: returns how many, and the bytes they took. A run of records
    /// with the first one's corner count is decoded in parallel, the rest one
    /// by one. `None` for a negative index or past 2³² − 1 corners (the
    /// record loop reports those).
    fn decode(&self, bytes: &[u8], records: usize, faces: &mut FaceArrays) -> Option<(usize, usize)> {
        let (count_size, size) = (self.count_ty.size(), self.ty.size());
        let uniform = self.count(bytes).filter(|&n| n > 0).and_then(|n| {
            let stride = count_size + n * size;
            let k = records.min(bytes.len() / stride);
            let run = &bytes[..k * stride];
            let same = k >= DECODE_MIN_RECORDS
                && run.par_chunks_exact(stride).with_min_len(DECODE_MIN_RECORDS).all(|r| self.count(r) == Some(n));
            same.then_some((n, k, stride))
        });
        if let Some((n, k, stride)) = uniform {
            // Division by a constant for the common sizes.
            let run = &bytes[..k * stride];
            let ok = match n {
                3 => self.decode_uniform(3, run, faces, |c| (c / 3, c % 3)),
                4 => self.decode_uniform(4, run, faces, |c| (c / 4, c % 4)),
                _ => self.decode_uniform(n, run, faces, move |c| (c / n, c % n)),
            };
            return ok.then_some((k, k * stride));
        }
        let mut pos = 0;
        let mut done = 0;
        while done < records {
            let Some(n) = self.count(&bytes[pos..]) else { break };
            let end = n.checked_mul(size).and_then(|b| b.checked_add(pos + count_size)).filter(|&e| e <= bytes.len());
            let Some(end) = end else { break };
            for b in bytes[pos + count_size..end].chunks_exact(size) {
                faces.indices.push(decode_index(self.ty, self.big_endian, b)?);
            }
            faces.offsets.push(u32::try_from(faces.indices.len()).ok()?);
            pos = end;
            done += 1;
        }
        Some((done, pos))
    }

    /// Records of `n` corners each, in parallel; `split(c)` is corner `c`'s
    /// (record, position in it). False on a negative index or too many
    /// corners.
    fn decode_uniform(
        &self,
        n: usize,
        run: &[u8],
        faces: &mut FaceArrays,
        split: impl Fn(usize) -> (usize, usize) + Sync + Send,
    ) -> bool {
        let (offset, size) = (self.count_ty.size(), self.ty.size());
        let stride = offset + n * size;
        let k = run.len() / stride;
        self.append_offsets(n, k, faces)
            && self.append_indices(
                faces,
                (0..k * n).into_par_iter().map(|c| {
                    let (record, corner) = split(c);
                    record * stride + offset + corner * size
                }),
                run,
            )
    }

    /// The offsets of `k` more faces of `n` corners; false past 2³² − 1 corners.
    fn append_offsets(&self, n: usize, k: usize, faces: &mut FaceArrays) -> bool {
        let base = faces.indices.len();
        if u32::try_from(base + n * k).is_err() {
            return false;
        }
        faces
            .offsets
            .par_extend((1..k + 1).into_par_iter().with_min_len(DECODE_MIN_RECORDS).map(|f| (base + f * n) as u32));
        true
    }

    /// Appends the index at each byte position of `at` in `run`; false if one
    /// is negative.
    fn append_indices(
        &self,
        faces: &mut FaceArrays,
        at: impl IndexedParallelIterator<Item = usize>,
        run: &[u8],
    ) -> bool {
        let negative = AtomicBool::new(false);
        faces.indices.par_extend(at.with_min_len(DECODE_MIN_RECORDS).map(|p| {
            decode_index(self.ty, self.big_endian, &run[p..]).unwrap_or_else(|| {
                negative.store(true, Ordering::Relaxed);
                0
            })
        }));
        !negative.into_inner()
    }
}

/// A face list being decoded: CSR offsets (from 0) and indices.
struct FaceArrays {
    offsets: Vec<u32>,
    indices: Vec<u32>,
}

impl FaceArrays {
    fn with_capacity(faces: usize, corners: usize) -> Self {
        let mut offsets = Vec::with_capacity(faces + 1);
        offsets.push(0);
        Self { offsets, indices: Vec::with_capacity(corners) }
    }

    fn into_face_list(self) -> FaceList {
        FaceList::from_raw(self.offsets, self.indices)
    }
}

/// Whitespace-separated ASCII tokens with line numbers.
struct Ascii<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Ascii<'a> {
    fn token(&mut self) -> Result<&'a [u8], Stop> {
        while let Some(&b) = self.bytes.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            if b == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while self.bytes.get(self.pos).is_some_and(|b| !b.is_ascii_whitespace()) {
            self.pos += 1;
        }
        if start == self.pos {
            // Report the last line that has content.
            let last = self.line - usize::from(self.bytes.last() == Some(&b'\n'));
            return Err(Stop::Ends(Some(last.max(1))));
        }
        Ok(&self.bytes[start..self.pos])
    }
}

impl Values for Ascii<'_> {
    fn value(&mut self, _ty: Scalar) -> Result<f64, Stop> {
        let t = self.token()?;
        parse_f64(t).ok_or_else(|| Stop::Bad(Some(self.line), format!("'{}' is not a number", show(t))))
    }

    /// Parsed from the token, so that an integer too large for any type is
    /// quoted as written ("99999999999999999999 out of range"); `3.0` is 3.
    fn integer(&mut self, _ty: Scalar) -> Result<u32, Stop> {
        let t = self.token()?;
        let bad = |message: String| Stop::Bad(Some(self.line), message);
        match parse_integer(t) {
            Ok(v) if v < 0 => Err(bad(format!("{v} is negative"))),
            Ok(v) => u32::try_from(v).map_err(|_| bad(format!("{v} out of range"))),
            Err(IntError::OutOfRange) => Err(bad(format!("{} out of range", show(t)))),
            Err(IntError::NotInteger) => match parse_f64(t) {
                Some(x) => u32_from_f64(x).map_err(|_| bad(format!("'{}' is not an integer", show(t)))),
                None => Err(bad(format!("'{}' is not a number", show(t)))),
            },
        }
    }

    fn skip(&mut self, _ty: Scalar, n: usize) -> Result<(), Stop> {
        for _ in 0..n {
            self.token()?;
        }
        Ok(())
    }

    fn room(&self, _ty: Scalar) -> usize {
        (self.bytes.len() - self.pos) / 2
    }

    /// A digit and a separator (the last value of the file may lack the separator).
    fn min_size(&self, _ty: Scalar) -> usize {
        2
    }

    fn line(&self) -> Option<usize> {
        Some(self.line)
    }
}

/// What one record holds for us.
#[derive(Default)]
struct Record {
    xyz: [f64; 3],
    uv: [f64; 2],
    corners: Vec<u32>,
    /// Two per corner, from a face's `texcoord` list.
    texcoords: Vec<f64>,
}

/// Reads one record of `element` into `out`.
fn record(src: &mut impl Values, element: &Element, out: &mut Record) -> Result<(), Stop> {
    for p in &element.properties {
        match (p.list, p.role) {
            (None, Role::Coordinate(axis)) => out.xyz[axis] = src.value(p.ty)?,
            (None, Role::Uv(k)) => out.uv[k] = src.value(p.ty)?,
            (None, _) => src.skip(p.ty, 1)?,
            (Some(count_ty), role) => {
                let count =
                    src.integer(count_ty).map_err(|s| s.about(|| format!("list '{}' length", p.name)))? as usize;
                if !matches!(role, Role::Indices | Role::TexCoords) {
                    src.skip(p.ty, count)?;
                    continue;
                }
                if count > src.room(p.ty) {
                    return Err(Stop::Ends(src.line()));
                }
                if role == Role::Indices {
                    out.corners.clear();
                    for _ in 0..count {
                        out.corners.push(src.integer(p.ty).map_err(|s| s.about(|| "vertex index".to_owned()))?);
                    }
                } else {
                    out.texcoords.clear();
                    for _ in 0..count {
                        out.texcoords.push(src.value(p.ty).map_err(|s| s.about(|| "texcoord".to_owned()))?);
                    }
                }
            }
        }
    }
    Ok(())
}

/// Per-corner texture coordinates, welded per vertex: corners of one vertex
/// with the same (u, v) (`-0.0` counted equal to `0.0`) share one value.
#[derive(Default)]
struct CornerUvs {
    values: Vec<DVec2>,
    indices: Vec<u32>,
    index: HashMap<(u32, [u64; 2]), u32>,
    /// Faces read with a `texcoord` list.
    faces: usize,
}

impl CornerUvs {
    fn push(&mut self, vertex: u32, uv: DVec2) {
        let key = (vertex, (uv + DVec2::ZERO).to_array().map(f64::to_bits));
        let next = self.values.len() as u32;
        let i = *self.index.entry(key).or_insert(next);
        if i == next {
            self.values.push(uv);
        }
        self.indices.push(i);
    }
}

fn read_body(
    src: &mut impl Values,
    elements: &[Element],
    body_len: usize,
    ctx: Ctx<'_>,
) -> Result<PolygonSoup, IoError> {
    let mut positions = Vec::new();
    let mut vertex_uvs: Vec<DVec2> = Vec::new();
    let mut faces = FaceList::new();
    let mut corner_uvs = CornerUvs::default();
    let mut rec = Record::default();
    for element in elements {
        if element.properties.is_empty() {
            // Records without properties take no bytes: nothing to read, and
            // a count of 2⁶⁴−1 must not become a loop.
            continue;
        }
        // Cap preallocation by the records the data can hold.
        let record_size: usize =
            element.properties.iter().map(|p| src.min_size(p.list.unwrap_or(p.ty))).sum::<usize>().max(1);
        let capacity = element.count.min(body_len / record_size + 1);
        match element.name.as_str() {
            "vertex" => positions.reserve(capacity),
            // A second face element adds to the first (FaceList cannot reserve).
            "face" if faces.is_empty() => faces = FaceList::with_capacity(capacity, 0),
            _ => {}
        }
        let has = |role: Role| element.properties.iter().any(|p| p.role == role);
        let is_face = has(Role::Indices);
        let is_vertex = element.properties.iter().any(|p| matches!(p.role, Role::Coordinate(_)));
        let (has_uv, has_texcoords) = (has(Role::Uv(0)), has(Role::TexCoords));
        // Binary records of fixed layout are decoded in one tight loop; the
        // loop below reads the rest (and reports every error).
        if is_vertex && src.fast_vertices(element, &mut positions, has_uv.then_some(&mut vertex_uvs)) {
            continue;
        }
        if is_face && !has_texcoords && faces.is_empty() && src.fast_faces(element, &mut faces) {
            continue;
        }
        for r in 0..element.count {
            rec.xyz = [0.0; 3];
            let at = |line| (line, format!("{} {r}", element.name));
            record(src, element, &mut rec)
                .and_then(|()| {
                    if has_texcoords && rec.texcoords.len() != 2 * rec.corners.len() {
                        let message = format!(
                            "texcoord has {} values for {} corners (two per corner needed)",
                            rec.texcoords.len(),
                            rec.corners.len()
                        );
                        return Err(Stop::Bad(src.line(), message));
                    }
                    Ok(())
                })
                .map_err(|stop| match stop {
                    Stop::Ends(line) => {
                        ctx.truncated(line, format!("data ends inside {} {r} of {}", element.name, element.count))
                    }
                    Stop::Bad(line, message) => {
                        let (line, what) = at(line);
                        ctx.parse(line, format!("{what}: {message}"))
                    }
                })?;
            if is_vertex {
                positions.push(DVec3::from(rec.xyz));
                if has_uv {
                    vertex_uvs.push(DVec2::from(rec.uv));
                }
            }
            if is_face {
                faces.push(&rec.corners);
                if has_texcoords {
                    corner_uvs.faces += 1;
                    for (&v, uv) in rec.corners.iter().zip(rec.texcoords.chunks_exact(2)) {
                        corner_uvs.push(v, DVec2::new(uv[0], uv[1]));
                    }
                }
            }
        }
    }
    Ok(soup_of(positions, vertex_uvs, faces, corner_uvs))
}

/// The soup of what the elements held: texture coordinates per corner when
/// every face had them, else per vertex when every vertex had them.
fn soup_of(positions: Vec<DVec3>, vertex_uvs: Vec<DVec2>, faces: FaceList, corner_uvs: CornerUvs) -> PolygonSoup {
    let uvs = if corner_uvs.faces > 0 && corner_uvs.faces == faces.len() {
        Some(FaceVarying { values: corner_uvs.values, indices: corner_uvs.indices })
    } else if !vertex_uvs.is_empty() && vertex_uvs.len() == positions.len() {
        Some(FaceVarying { values: vertex_uvs, indices: faces.indices().to_vec() })
    } else {
        None
    };
    PolygonSoup { uvs, ..PolygonSoup::new(positions, faces) }
}

pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonSoup, IoError> {
    let bytes = strip_bom(bytes);
    if is_blank(bytes) {
        return Err(ctx.empty());
    }
    let header = parse_header(bytes, ctx)?;
    let body = &bytes[header.body_offset..];
    match header.encoding {
        Encoding::Ascii => {
            if sniff(body).is_some() {
                return Err(ctx.parse(
                    header.body_line,
                    "the header says 'format ascii', but the data after end_header is binary",
                ));
            }
            let mut src = Ascii { bytes: body, pos: 0, line: header.body_line };
            read_body(&mut src, &header.elements, body.len(), ctx)
        }
        Encoding::LittleEndian | Encoding::BigEndian => {
            let big_endian = header.encoding == Encoding::BigEndian;
            let mut src = Binary { data: body, pos: 0, big_endian };
            read_body(&mut src, &header.elements, body.len(), ctx)
        }
    }
}

/// The texture coordinate of every vertex, when each vertex's corners all
/// use one value index (no seams); `(0, 0)` for a vertex no face uses.
fn per_vertex_uvs(faces: &FaceList, vertex_count: usize, uvs: &FaceVarying) -> Option<Vec<DVec2>> {
    let mut index: Vec<Option<u32>> = vec![None; vertex_count];
    for (&v, &uv) in faces.indices().iter().zip(&uvs.indices) {
        match index[v as usize] {
            None => index[v as usize] = Some(uv),
            Some(first) if first == uv => {}
            Some(_) => return None,
        }
    }
    Some(index.into_iter().map(|i| i.map_or(DVec2::ZERO, |i| uvs.values[i as usize])).collect())
}

/// Bytes a writer assembles before handing them on.
const BLOCK: usize = 1 << 16;

pub(crate) fn write(mesh: &MeshView<'_>, binary: bool, out: &mut impl Write) -> io::Result<()> {
    let big_faces = mesh.faces.iter().any(|f| f.len() > 255);
    let big_indices = mesh.faces.indices().iter().any(|&v| v > i32::MAX as u32);
    let vertex_uvs = mesh.uvs.and_then(|uvs| per_vertex_uvs(mesh.faces, mesh.positions.len(), uvs));
    // Texture coordinates per corner only where there are seams.
    let corner_uvs = mesh.uvs.filter(|_| vertex_uvs.is_none());
    let big_texcoords = corner_uvs.is_some() && mesh.faces.iter().any(|f| 2 * f.len() > 255);
    let format = if binary { "binary_little_endian" } else { "ascii" };
    let mut header = format!(
        "ply\nformat {format} 1.0\ncomment written by subdiv-io\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\n",
        mesh.positions.len()
    );
    if mesh.normals.is_some() {
        header.push_str("property double nx\nproperty double ny\nproperty double nz\n");
    }
    if vertex_uvs.is_some() {
        header.push_str("property double u\nproperty double v\n");
    }
    header.push_str(&format!(
        "element face {}\nproperty list {} {} vertex_indices\n",
        mesh.faces.len(),
        if big_faces { "uint" } else { "uchar" },
        if big_indices { "uint" } else { "int" },
    ));
    if corner_uvs.is_some() {
        header.push_str(&format!("property list {} double texcoord\n", if big_texcoords { "uint" } else { "uchar" }));
    }
    header.push_str("end_header\n");
    out.write_all(header.as_bytes())?;

    let vertex = |i: usize| {
        let normal = mesh.normals.map(|n| n[i].to_array());
        let uv = vertex_uvs.as_ref().map(|uvs| uvs[i].to_array());
        mesh.positions[i].to_array().into_iter().chain(normal.into_iter().flatten()).chain(uv.into_iter().flatten())
    };
    // The texture coordinates of the corners of face `f`, u and v in turn.
    let texcoords = |f: usize| {
        let uvs = corner_uvs.expect("called only with per-corner texture coordinates");
        let corners = mesh.faces.offsets()[f] as usize..mesh.faces.offsets()[f + 1] as usize;
        uvs.indices[corners].iter().flat_map(|&i| uvs.values[i as usize].to_array())
    };
    let write_count = |out: &mut dyn Write, n: usize, big: bool| -> io::Result<()> {
        if big {
            out.write_all(&(n as u32).to_le_bytes())
        } else {
            out.write_all(&[n as u8])
        }
    };
    if binary {
        // Records are assembled in a local buffer, written out in blocks.
        let mut buf = Vec::with_capacity(BLOCK + 4096);
        let plain = mesh.normals.is_none() && vertex_uvs.is_none();
        if plain {
            // Positions only (the common case): fixed 24-byte records filled
            // in place, a block at a time.
            for block in mesh.positions.chunks(BLOCK / 24) {
                buf.resize(24 * block.len(), 0);
                for (record, p) in buf.chunks_exact_mut(24).zip(block) {
                    record[..8].copy_from_slice(&p.x.to_le_bytes());
                    record[8..16].copy_from_slice(&p.y.to_le_bytes());
                    record[16..].copy_from_slice(&p.z.to_le_bytes());
                }
                out.write_all(&buf)?;
            }
            buf.clear();
        } else {
            for i in 0..mesh.positions.len() {
                for x in vertex(i) {
                    buf.extend_from_slice(&x.to_le_bytes());
                }
                if buf.len() >= BLOCK {
                    out.write_all(&buf)?;
                    buf.clear();
                }
            }
        }
        let faces = mesh.faces;
        let uniform = (!faces.is_empty()).then(|| faces.face_size(0)).filter(|&m| m > 0 && faces.all_of_size(m));
        if let Some(m) = uniform.filter(|_| !big_faces && corner_uvs.is_none()) {
            // One face size (all quads, all triangles): fixed records of a
            // count byte and m indices, filled in place as above.
            let record = 1 + 4 * m;
            out.write_all(&buf)?;
            for block in mesh.faces.indices().chunks(m * (BLOCK / record).max(1)) {
                buf.resize(record * (block.len() / m), 0);
                for (bytes, face) in buf.chunks_exact_mut(record).zip(block.chunks_exact(m)) {
                    bytes[0] = m as u8;
                    for (slot, &v) in bytes[1..].chunks_exact_mut(4).zip(face) {
                        slot.copy_from_slice(&v.to_le_bytes());
                    }
                }
                out.write_all(&buf)?;
            }
            return Ok(());
        }
        for (f, face) in mesh.faces.iter().enumerate() {
            if big_faces {
                buf.extend_from_slice(&(face.len() as u32).to_le_bytes());
            } else {
                buf.push(face.len() as u8);
            }
            for &v in face {
                // `int` and `uint` share their bits for every index ≤ i32::MAX.
                buf.extend_from_slice(&v.to_le_bytes());
            }
            if corner_uvs.is_some() {
                write_count(&mut buf, 2 * face.len(), big_texcoords)?;
                for x in texcoords(f) {
                    buf.extend_from_slice(&x.to_le_bytes());
                }
            }
            if buf.len() >= BLOCK {
                out.write_all(&buf)?;
                buf.clear();
            }
        }
        out.write_all(&buf)?;
    } else {
        let mut text = TextOut::new(out);
        for i in 0..mesh.positions.len() {
            for (k, x) in vertex(i).enumerate() {
                if k > 0 {
                    text.bytes(b" ");
                }
                text.f64(x);
            }
            text.end_line()?;
        }
        for (f, face) in mesh.faces.iter().enumerate() {
            text.int(face.len());
            for &v in face {
                text.bytes(b" ");
                text.int(v);
            }
            if corner_uvs.is_some() {
                text.bytes(b" ");
                text.int(2 * face.len());
                for x in texcoords(f) {
                    text.bytes(b" ");
                    text.f64(x);
                }
            }
            text.end_line()?;
        }
        text.finish()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn read_bytes(b: &[u8]) -> Result<PolygonSoup, IoError> {
        read(b, Ctx::new(Path::new("t.ply")))
    }

    #[test]
    fn other_elements_and_list_properties_are_skipped() {
        let src = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty list uchar int junk\n\
            property float y\nproperty float z\nelement edge 1\nproperty int a\nproperty int b\n\
            element face 1\nproperty uchar flags\nproperty list uint8 uint32 vertex_index\nend_header\n\
            0 2 7 8 0 0\n1 0 0 0\n0 1 9 1 0\n0 1\n5 3 0 1 2\n";
        let soup = read_bytes(src).unwrap();
        assert_eq!(soup.positions, vec![DVec3::ZERO, DVec3::X, DVec3::Y]);
        assert_eq!(soup.faces.face(0), &[0, 1, 2]);
    }

    #[test]
    fn ascii_errors_name_the_line() {
        let src = b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
            property float z\nend_header\n0 0 0\n1 q 0\n";
        let e = read_bytes(src).unwrap_err();
        assert_eq!(e.line(), Some(9), "{e}");
        let src = b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
            property float z\nend_header\n0 0 0\n1 1\n";
        let e = read_bytes(src).unwrap_err();
        assert!(matches!(e, IoError::Truncated { line: Some(9), .. }), "{e}");
    }

    #[test]
    fn huge_counts_do_not_allocate() {
        let src = b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n\
            property float y\nproperty float z\nend_header\n";
        assert!(matches!(read_bytes(src), Err(IoError::Truncated { .. })));
    }
}
