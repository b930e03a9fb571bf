//! Large OBJ files read on every thread: the text is cut into chunks at line
//! ends, each chunk parsed into its own arrays by the statement functions of
//! [`super::read_serial`] ([`vertex`], [`tex_coord`], [`face_corners`],
//! [`group_name`]), and the arrays laid end to end in file order.
//!
//! A chunk does not know how many vertices and texture coordinates come
//! before it, nor its line numbers, so this path only reads what needs
//! neither: positive indices (a relative index, like any error, makes it
//! decline), `g`/`o` names (recorded per chunk with the face they precede,
//! then interned in file order as the serial reader does), and texture
//! coordinates given by every face or by none (a file that mixes them gets
//! a warning naming lines). It declines `t` tag lines, `\` continuation
//! lines, binary data and empty files too. Whatever it declines is read by
//! [`super::read_serial`] from the start, so the errors, their line numbers
//! and the warnings are the serial reader's; whatever it reads is the soup
//! [`super::read_serial`] reads, with no warnings (the tests compare the
//! two).

use super::{continued, face_corners, group_name, tex_coord, vertex, GroupTable, Statement};
use crate::error::{Ctx, ReadWarning};
use crate::text::{sniff, strip_bom, strip_comment, tokens, Lines};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use subdiv_mesh::{FaceGroups, FaceList, FaceVarying, PolygonSoup, TagList};

/// Files shorter than this are read by the serial reader alone.
pub(crate) const MIN_BYTES: usize = 1 << 20;

/// The chunk size [`chunk_size`] picks at most and at least.
const CHUNK_BYTES: std::ops::RangeInclusive<usize> = (256 << 10)..=(8 << 20);

/// Elements one thread copies at least when the chunks are laid end to end.
const COPY_MIN: usize = 1 << 16;

/// The chunk size for a file of `len` bytes: four chunks per thread or
/// more (so that a thread slowed by other work on the machine holds up
/// little), within [`CHUNK_BYTES`].
pub(crate) fn chunk_size(len: usize) -> usize {
    (len / (4 * rayon::current_num_threads())).clamp(*CHUNK_BYTES.start(), *CHUNK_BYTES.end())
}

/// Reads an OBJ file in chunks of about `chunk` bytes (each ends at the
/// first line end from there on). `None`: the file has something this path
/// does not read (see the module documentation).
pub(crate) fn read(bytes: &[u8], chunk: usize, ctx: Ctx<'_>) -> Option<(PolygonSoup, Vec<ReadWarning>)> {
    let bytes = strip_bom(bytes);
    if sniff(bytes).is_some() {
        return None;
    }
    // The first chunk that declines stops the others.
    let parts = split(bytes, chunk).into_par_iter().map(|text| Part::parse(text, ctx)).collect::<Option<Vec<_>>>()?;
    merge(parts)
}

/// `bytes` cut after the first `\n` at or past every `chunk` bytes: a `\n`
/// always ends a line (alone or after `\r`), so every piece is whole lines,
/// numbered and split by [`Lines`] as in the whole file.
fn split(bytes: &[u8], chunk: usize) -> Vec<&[u8]> {
    let chunk = chunk.max(1);
    let mut pieces = Vec::with_capacity(bytes.len() / chunk + 1);
    let mut rest = bytes;
    while rest.len() > chunk {
        let Some(newline) = memchr::memchr(b'\n', &rest[chunk - 1..]) else { break };
        let (piece, tail) = rest.split_at(chunk + newline);
        pieces.push(piece);
        rest = tail;
    }
    if !rest.is_empty() {
        pieces.push(rest);
    }
    pieces
}

/// What one chunk holds, numbered from the chunk's start.
#[derive(Default)]
struct Part {
    positions: Vec<DVec3>,
    uv_values: Vec<DVec2>,
    /// Per face, the end of its corners in `indices`.
    ends: Vec<u32>,
    indices: Vec<u32>,
    /// Per corner, when the chunk's faces give texture coordinates.
    corner_uvs: Vec<u32>,
    /// Faces (with corners) with and without texture coordinates.
    faces_with_uvs: usize,
    faces_without_uvs: usize,
    /// `g`/`o` names, each with the number of the chunk's faces before it.
    groups: Vec<(usize, String)>,
}

impl Part {
    /// Parses one chunk (whole lines); `None` when it holds what this path
    /// does not read. Errors are not kept: the serial reader reports them.
    fn parse(text: &[u8], ctx: Ctx<'_>) -> Option<Part> {
        let mut part = Part::default();
        // Line numbers and the counts before the chunk are unknown: 0 for
        // messages, and 0 vertices and texture coordinates so far, which
        // makes every relative index an error (that is, declined).
        for (_, raw) in Lines::new(text) {
            let line = strip_comment(raw);
            if continued(line).is_some() {
                return None;
            }
            let mut toks = tokens(line);
            let Some(keyword) = toks.next() else { continue };
            match Statement::of(keyword) {
                Statement::Vertex => part.positions.push(vertex(toks, 0, ctx).ok()?),
                Statement::TexCoord => part.uv_values.push(tex_coord(toks, 0, ctx).ok()?),
                Statement::Face => {
                    let (start, uv_start) = (part.indices.len(), part.corner_uvs.len());
                    face_corners(toks, (0, 0), 0, 0, ctx, &mut part.indices, &mut part.corner_uvs).ok()?;
                    if part.indices.len() > start {
                        if part.corner_uvs.len() > uv_start {
                            part.faces_with_uvs += 1;
                        } else {
                            part.faces_without_uvs += 1;
                        }
                        // Mixed: the serial reader's warning names lines.
                        if part.faces_with_uvs > 0 && part.faces_without_uvs > 0 {
                            return None;
                        }
                    }
                    // A chunk holds fewer corners than bytes, and all of
                    // them fewer than 2³² (checked in `merge`).
                    part.ends.push(part.indices.len() as u32);
                }
                Statement::Group => part.groups.push((part.ends.len(), group_name(toks))),
                Statement::Tag | Statement::Binary => return None,
                Statement::Ignored => {}
            }
        }
        Some(part)
    }
}

/// The chunks' arrays end to end: the soup the serial reader reads, or
/// `None` where it would warn or fail.
fn merge(mut parts: Vec<Part>) -> Option<(PolygonSoup, Vec<ReadWarning>)> {
    let with_uvs: usize = parts.iter().map(|p| p.faces_with_uvs).sum();
    let without_uvs: usize = parts.iter().map(|p| p.faces_without_uvs).sum();
    let face_count: usize = parts.iter().map(|p| p.ends.len()).sum();
    let corner_count: usize = parts.iter().map(|p| p.indices.len()).sum();
    // Past 2³² corners the serial reader's `FaceList` offsets wrap and
    // `checked` refuses the soup: the serial reader's business too.
    if (with_uvs > 0 && without_uvs > 0) || u32::try_from(corner_count).is_err() {
        return None;
    }
    if face_count == 0 && parts.iter().all(|p| p.positions.is_empty()) {
        return None;
    }

    // Before the arrays are taken: the groups count the parts' faces.
    let groups = groups(&parts, face_count);
    let positions = concat(&mut parts, |p| &mut p.positions, |_, x| x);
    let mut offsets = Vec::with_capacity(face_count + 1);
    offsets.push(0);
    let bases: Vec<u32> = parts
        .iter()
        .scan(0u32, |base, p| {
            let this = *base;
            *base += p.indices.len() as u32;
            Some(this)
        })
        .collect();
    concat_into(&mut offsets, &mut parts, |p| &mut p.ends, |part, end| bases[part] + end);
    let indices = concat(&mut parts, |p| &mut p.indices, |_, v| v);
    let faces = FaceList::from_raw(offsets, indices);
    // `vt` lines that no face uses give no channel.
    let uvs = (with_uvs > 0).then(|| FaceVarying {
        values: concat(&mut parts, |p| &mut p.uv_values, |_, uv| uv),
        indices: concat(&mut parts, |p| &mut p.corner_uvs, |_, i| i),
    });
    Some((PolygonSoup { positions, faces, groups, tags: TagList::default(), uvs }, Vec::new()))
}

/// The face groups of the chunks' `g`/`o` names, as the serial reader
/// builds them: names interned in file order, a face before the first name
/// in `default`, and no groups at all in a file without names.
fn groups(parts: &[Part], face_count: usize) -> FaceGroups {
    if parts.iter().all(|p| p.groups.is_empty()) {
        return FaceGroups::default();
    }
    let mut table = GroupTable::default();
    let mut current = None;
    let mut face_group = Vec::with_capacity(face_count);
    for part in parts {
        let mut done = 0;
        // Every face of a run between two names is in the same group.
        let mut run = |table: &mut GroupTable, current: &mut Option<u32>, until: usize| {
            if until > done {
                let g = table.face_group(current);
                face_group.extend(std::iter::repeat_n(g, until - done));
                done = until;
            }
        };
        for (before, name) in &part.groups {
            run(&mut table, &mut current, *before);
            current = Some(table.intern(name.clone()));
        }
        run(&mut table, &mut current, part.ends.len());
    }
    FaceGroups { names: table.groups.names, face_group }
}

/// One array of every part (`field`), laid end to end on every thread
/// through `map(part, element)`; the parts' arrays are freed.
fn concat<T, U>(
    parts: &mut [Part],
    field: impl Fn(&mut Part) -> &mut Vec<T>,
    map: impl Fn(usize, T) -> U + Sync + Send,
) -> Vec<U>
where
    T: Copy + Sync,
    U: Send,
{
    let mut out = Vec::new();
    concat_into(&mut out, parts, field, map);
    out
}

/// [`concat()`], appended to `out`.
fn concat_into<T, U>(
    out: &mut Vec<U>,
    parts: &mut [Part],
    field: impl Fn(&mut Part) -> &mut Vec<T>,
    map: impl Fn(usize, T) -> U + Sync + Send,
) where
    T: Copy + Sync,
    U: Send,
{
    let arrays: Vec<Vec<T>> = parts.iter_mut().map(|p| std::mem::take(field(p))).collect();
    // starts[p]..starts[p + 1]: the elements of part p in the output.
    let starts: Vec<usize> = std::iter::once(0)
        .chain(arrays.iter().scan(0, |end, a| {
            *end += a.len();
            Some(*end)
        }))
        .collect();
    let total = starts[arrays.len()];
    out.reserve_exact(total);
    // An indexed iterator, so rayon writes each element into its place;
    // each job remembers the part it is in (its elements come in order).
    let part_of = |i: usize| starts.partition_point(|&s| s <= i) - 1;
    out.par_extend((0..total).into_par_iter().with_min_len(COPY_MIN).map_init(
        || 0,
        |part: &mut usize, i| {
            if !(starts[*part]..starts[*part + 1]).contains(&i) {
                *part = part_of(i);
            }
            map(*part, arrays[*part][i - starts[*part]])
        },
    ));
}
