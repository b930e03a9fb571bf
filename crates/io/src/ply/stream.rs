//! Binary PLY straight from the file: the body is decoded chunk by chunk as
//! it is read, through one reused buffer, instead of being copied whole
//! into memory first. A file of 344 MB then needs no 344 MB buffer (whose
//! fresh pages the kernel would zero, then unmap), and its records are
//! decoded on every thread ([`VertexLayout::decode`], [`FaceLayout::decode`],
//! the same decoders as [`super::read`]'s).
//!
//! Only what the fast decoders handle is streamed: a binary file whose
//! elements are vertices of a fixed layout, at most one face element holding
//! nothing but its integer index list, and other elements of fixed size
//! (skipped). Anything else — ASCII, list properties besides the indices, a
//! `texcoord` list, a negative index, a file shorter than its header says —
//! is left to [`super::read`] on the whole file, which reads it or reports
//! the error exactly as for bytes in memory.

use super::{parse_header, soup_of, CornerUvs, Element, Encoding, FaceArrays, FaceLayout, Role, VertexLayout};
use crate::error::Ctx;
use crate::text::strip_bom;
use glam::{DVec2, DVec3};
use std::io::{self, Read};
use subdiv_mesh::{FaceList, PolygonSoup};

/// Bytes read per call, and decoded per step.
const CHUNK: usize = 4 << 20;

/// The most header bytes looked at: a longer header is read the slow way.
const HEADER_LIMIT: usize = 1 << 16;

/// How one element is read from the stream.
enum Plan {
    Vertices(VertexLayout, bool),
    Faces(FaceLayout),
    /// Fixed-size records of no interest: this many bytes each.
    Skip(usize),
}

/// Reads a PLY file from `file` (`total` bytes, the first not yet read) as
/// it streams, reporting `progress(bytes_read, total)` after every chunk.
/// `Ok(None)`: the file is not one this path reads (see the module
/// documentation); the caller reads it whole instead, from the start.
///
/// # Errors
/// Only a failing read: the content's errors are the whole-file reader's.
pub(crate) fn read_streamed(
    file: &mut impl Read,
    total: u64,
    ctx: Ctx<'_>,
    progress: &mut dyn FnMut(u64, u64),
) -> io::Result<Option<PolygonSoup>> {
    let mut body = Body { file, buf: Vec::with_capacity(CHUNK), start: 0, read: 0, total, progress };
    (body.progress)(0, total);
    body.fill(HEADER_LIMIT)?;
    let bytes = &body.buf[..];
    let stripped = strip_bom(bytes);
    let bom = bytes.len() - stripped.len();
    // The header must end inside what was read, at a line end (a prefix of
    // the file parses as the file does up to there).
    let Ok(header) = parse_header(stripped, ctx) else { return Ok(None) };
    let offset = bom + header.body_offset;
    if header.encoding == Encoding::Ascii || offset > bytes.len() || bytes[offset - 1] != b'\n' {
        return Ok(None);
    }
    let Some(plans) = plan(&header.elements, header.encoding == Encoding::BigEndian) else { return Ok(None) };
    body.start = offset;

    let mut positions: Vec<DVec3> = Vec::new();
    let mut vertex_uvs: Vec<DVec2> = Vec::new();
    let mut faces = FaceList::new();
    for (element, plan) in header.elements.iter().zip(plans) {
        let done = match plan {
            Plan::Vertices(layout, has_uv) => {
                let bound = body.bound(layout.stride);
                positions.reserve(element.count.min(bound));
                if has_uv {
                    vertex_uvs.reserve(element.count.min(bound));
                }
                body.vertices(element.count, &layout, &mut positions, has_uv.then_some(&mut vertex_uvs))?
            }
            Plan::Faces(layout) => match body.faces(element.count, &layout)? {
                Some(read) => {
                    faces = read.into_face_list();
                    true
                }
                None => false,
            },
            Plan::Skip(stride) => match element.count.checked_mul(stride) {
                Some(bytes) => body.skip(bytes)?,
                None => false,
            },
        };
        if !done {
            return Ok(None);
        }
    }
    Ok(Some(soup_of(positions, vertex_uvs, faces, CornerUvs::default())))
}

/// How each element is read, or `None` if one cannot be streamed.
fn plan(elements: &[Element], big_endian: bool) -> Option<Vec<Plan>> {
    let mut face_elements = 0;
    elements
        .iter()
        .map(|element| {
            let has = |role: Role| element.properties.iter().any(|p| p.role == role);
            if has(Role::Indices) {
                face_elements += 1;
                // A second face element adds to the first: the slow path.
                return FaceLayout::of(element, big_endian).filter(|_| face_elements == 1).map(Plan::Faces);
            }
            let layout = VertexLayout::of(element, big_endian)?;
            if element.properties.iter().any(|p| matches!(p.role, Role::Coordinate(_))) {
                Some(Plan::Vertices(layout, has(Role::Uv(0))))
            } else if element.properties.is_empty() {
                Some(Plan::Skip(0))
            } else {
                Some(Plan::Skip(layout.stride))
            }
        })
        .collect()
}

/// The file's bytes as they come: `buf[start..]` is read but not yet used.
struct Body<'a, R> {
    file: &'a mut R,
    buf: Vec<u8>,
    start: usize,
    read: u64,
    total: u64,
    progress: &'a mut dyn FnMut(u64, u64),
}

impl<R: Read> Body<'_, R> {
    /// Makes at least `want` unused bytes available, fewer only where the
    /// file ends; returns how many there are.
    fn fill(&mut self, want: usize) -> io::Result<usize> {
        if self.buf.len() - self.start >= want {
            return Ok(self.buf.len() - self.start);
        }
        self.buf.drain(..self.start);
        self.start = 0;
        let target = want.max(CHUNK);
        while self.buf.len() < want {
            let room = (target - self.buf.len()) as u64;
            let n = (&mut *self.file).take(room).read_to_end(&mut self.buf)?;
            if n == 0 {
                break;
            }
            self.read += n as u64;
            (self.progress)(self.read, self.total.max(self.read));
        }
        Ok(self.buf.len())
    }

    /// The unused bytes.
    fn data(&self) -> &[u8] {
        &self.buf[self.start..]
    }

    /// At most how many records of `size` bytes the rest of the file holds
    /// (caps allocations by what is there, not by the header's counts).
    fn bound(&self, size: usize) -> usize {
        let left = self.total.saturating_sub(self.read) as usize + self.data().len();
        left / size.max(1)
    }

    /// `count` vertex records into `positions` (and `uvs`); false if the
    /// file ends first.
    fn vertices(
        &mut self,
        mut count: usize,
        layout: &VertexLayout,
        positions: &mut Vec<DVec3>,
        mut uvs: Option<&mut Vec<DVec2>>,
    ) -> io::Result<bool> {
        let per_chunk = (CHUNK / layout.stride).max(1);
        while count > 0 {
            let available = self.fill(count.min(per_chunk) * layout.stride)?;
            let records = count.min(available / layout.stride);
            if records == 0 {
                return Ok(false);
            }
            let bytes = records * layout.stride;
            layout.decode(&self.data()[..bytes], positions, uvs.as_deref_mut());
            self.start += bytes;
            count -= records;
        }
        Ok(true)
    }

    /// `count` face records; `None` if the file ends first or a value is
    /// one the record loop must report.
    fn faces(&mut self, mut count: usize, layout: &FaceLayout) -> io::Result<Option<FaceArrays>> {
        let (count_size, size) = (layout.count_ty.size(), layout.ty.size());
        let mut faces = FaceArrays::with_capacity(count.min(self.bound(count_size)), self.bound(size));
        let mut want = CHUNK;
        while count > 0 {
            let available = self.fill(want)?;
            let Some((records, bytes)) = layout.decode(self.data(), count, &mut faces) else { return Ok(None) };
            if records == 0 {
                // The next record is longer than what is here: ask for all of
                // it, unless the file ended or cannot hold it.
                let Some(n) = layout.count(self.data()) else { return Ok(None) };
                let needed = n.checked_mul(size).and_then(|b| b.checked_add(count_size));
                match needed {
                    Some(needed) if available >= want && needed > available && needed <= self.bound(1) => want = needed,
                    _ => return Ok(None),
                }
                continue;
            }
            self.start += bytes;
            count -= records;
            want = CHUNK;
        }
        Ok(Some(faces))
    }

    /// Skips `bytes` bytes; false if the file ends first.
    fn skip(&mut self, mut bytes: usize) -> io::Result<bool> {
        while bytes > 0 {
            let available = self.fill(bytes.min(CHUNK))?;
            if available == 0 {
                return Ok(false);
            }
            let n = bytes.min(available);
            self.start += n;
            bytes -= n;
        }
        Ok(true)
    }
}
