//! STL (stereolithography), ASCII and binary.
//!
//! STL stores every triangle with its own three corners, so reading *welds*:
//! corners with bit-identical coordinates (`-0.0` counted equal to `0.0`)
//! become one vertex, numbered in order of first appearance. A mesh written
//! from distinct positions therefore reads back with the same vertex count
//! (unreferenced vertices are lost: STL has no place for them).
//!
//! Binary or ASCII is decided from the content, not the name: a file is
//! binary when its size is exactly `84 + 50·n` for the triangle count `n` in
//! its header (some binary files begin with `solid` too), unless it is plain
//! ASCII text that ends its solid with `endsolid`. A UTF-8 byte-order mark
//! before `solid` is skipped; a file that starts with `solid` but holds
//! binary data is read as binary (it is a binary STL whose size does not
//! match its triangle count, or is truncated); UTF-16 text is reported as such.
//!
//! Write: binary ([`Format::StlBinary`](crate::Format::StlBinary), `f32`
//! coordinates: positions are rounded to single precision) or ASCII
//! ([`Format::StlAscii`](crate::Format::StlAscii), shortest round-trip `f64`
//! in `{:e}` form). Polygons are triangulated as fans from their first corner;
//! facet normals are computed from the triangles (per-vertex normals have no
//! place in STL).

use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;
use std::io::{self, Write};
use subdiv_mesh::{FaceList, PolygonSoup};

use crate::error::{Ctx, IoError};
use crate::text::{is_blank, parse_f64, show, sniff, strip_bom, tokens, Lines, NotText, TextOut};
use crate::{fan, MeshView};

/// Merges bit-identical positions, numbering vertices by first appearance.
struct Welder {
    positions: Vec<DVec3>,
    index: HashMap<[u64; 3], u32, ahash::RandomState>,
}

impl Welder {
    /// Room for `vertices` distinct positions before the table grows.
    fn with_capacity(vertices: usize) -> Self {
        Welder {
            positions: Vec::with_capacity(vertices),
            index: HashMap::with_capacity_and_hasher(vertices, ahash::RandomState::new()),
        }
    }

    /// The vertex at `p`, a new one when no corner so far had its bits.
    fn vertex(&mut self, p: [f64; 3]) -> u32 {
        let next = self.positions.len() as u32;
        let v = *self.index.entry(f64_key(p)).or_insert(next);
        if v == next {
            self.positions.push(DVec3::from(p));
        }
        v
    }

    /// The positions so far; the welder starts again, keeping its table's room.
    fn take(&mut self) -> Vec<DVec3> {
        self.index.clear();
        std::mem::take(&mut self.positions)
    }
}

/// Adding +0.0 turns -0.0 into +0.0 and leaves every other value alone.
fn f64_key(p: [f64; 3]) -> [u64; 3] {
    p.map(|x| (x + 0.0).to_bits())
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    bytes[start..].get(..5).is_some_and(|s| s.eq_ignore_ascii_case(b"solid"))
}

/// True when the size is exactly that of a binary STL with the triangle
/// count in its header, and the content is not ASCII STL text.
fn has_binary_size(bytes: &[u8]) -> bool {
    let Some(&[a, b, c, d]) = bytes.get(80..84) else { return false };
    if 84 + 50 * u64::from(u32::from_le_bytes([a, b, c, d])) != bytes.len() as u64 {
        return false;
    }
    let text = strip_bom(bytes);
    let ascii_text = text.is_ascii() && text.windows(8).any(|w| w.eq_ignore_ascii_case(b"endsolid"));
    !(starts_with_solid(text) && ascii_text)
}

pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonSoup, IoError> {
    let text = strip_bom(bytes);
    if is_blank(text) {
        return Err(ctx.empty());
    }
    if has_binary_size(bytes) {
        return read_binary(bytes, ctx);
    }
    match (starts_with_solid(text), sniff(text)) {
        (true, None) => read_ascii(text, ctx),
        (false, Some(NotText::Utf16)) => Err(ctx.utf16()),
        // Binary data, whether or not its 80-byte header starts with "solid".
        _ => read_binary(bytes, ctx),
    }
}

fn read_binary(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonSoup, IoError> {
    let Some(count) = bytes.get(80..84) else {
        return Err(ctx.truncated(None, "binary STL needs an 80-byte header and a triangle count"));
    };
    let n = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as usize;
    let stored = (bytes.len() - 84) / 50;
    if stored < n {
        return Err(ctx.truncated(None, format!("header promises {n} triangles, the file holds {stored}")));
    }
    let (positions, corners) = weld_binary(&bytes[84..84 + 50 * n]);
    Ok(PolygonSoup::new(positions, FaceList::from_uniform(3, corners)))
}

/// Triangles per welding chunk: a chunk's table (about 2¹³ vertices on a
/// closed mesh) stays in a core's cache.
const WELD_CHUNK: usize = 1 << 14;

/// Welds the corners of binary STL triangle records, numbered as the serial
/// [`Welder`] numbers them (first appearance), on every thread. One table of
/// all the mesh's positions is too big for any cache, and every lookup in it
/// waits on memory; so each chunk of [`WELD_CHUNK`] triangles welds its own
/// corners in a small table (chunks in parallel), the chunks' distinct
/// positions (a sixth of the corners on a closed mesh) are welded by
/// [`weld_distinct`], and each chunk's corners are renumbered. The chunks are
/// fixed by the triangle count, not the thread count: the same file gives
/// the same bits on any machine.
fn weld_binary(records: &[u8]) -> (Vec<DVec3>, Vec<u32>) {
    let mut corners = vec![0u32; 3 * (records.len() / 50)];
    let chunks: Vec<Vec<DVec3>> = records
        .par_chunks(50 * WELD_CHUNK)
        .zip(corners.par_chunks_mut(3 * WELD_CHUNK))
        .map_init(
            || Welder::with_capacity(WELD_CHUNK / 2),
            |local, (records, corners)| {
                for (record, corners) in records.chunks_exact(50).zip(corners.chunks_exact_mut(3)) {
                    for (k, corner) in corners.iter_mut().enumerate() {
                        let at = 12 + 12 * k;
                        *corner = local.vertex([0, 4, 8].map(|o| {
                            let b = &record[at + o..at + o + 4];
                            f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                        }));
                    }
                }
                local.take()
            },
        )
        .collect();
    // Chunk k's local vertex i is entry starts[k] + i of the concatenation.
    let starts: Vec<usize> = chunks
        .iter()
        .scan(0, |start, c| {
            let s = *start;
            *start += c.len();
            Some(s)
        })
        .collect();
    let (positions, global) = weld_distinct(&chunks.concat());
    corners.par_chunks_mut(3 * WELD_CHUNK).zip(&starts).for_each(|(corners, &start)| {
        for c in corners {
            *c = global[start + *c as usize];
        }
    });
    (positions, corners)
}

/// Entries per partition of [`weld_distinct`]: its table stays in a core's cache.
const WELD_PARTITION: usize = 1 << 12;

/// Welds `points` (bit-identical positions, `-0.0` = `0.0`) into vertices
/// numbered by first appearance: the vertices' positions, and each point's
/// vertex. The points are partitioned by a hash of their bits (equal points
/// land together, in their order), each partition finds in a small table
/// which of its points repeat an earlier one (partitions in parallel), and
/// one pass in order numbers the others. The partition hash's random key
/// decides only where a point is looked at, never the numbering.
fn weld_distinct(points: &[DVec3]) -> (Vec<DVec3>, Vec<u32>) {
    let bits = (points.len() / WELD_PARTITION).max(1).next_power_of_two().trailing_zeros();
    let partition_hash = ahash::RandomState::new();
    let partition = |p: &DVec3| (partition_hash.hash_one(f64_key(p.to_array())) >> (63 - bits) >> 1) as usize;
    // A stable counting sort of (key, point) by partition.
    let mut offsets = vec![0usize; (1 << bits) + 1];
    for p in points {
        offsets[partition(p) + 1] += 1;
    }
    for i in 1..offsets.len() {
        offsets[i] += offsets[i - 1];
    }
    let mut sorted = vec![([0u64; 3], 0u32); points.len()];
    let mut next = offsets.clone();
    for (i, p) in points.iter().enumerate() {
        let slot = &mut next[partition(p)];
        sorted[*slot] = (f64_key(p.to_array()), i as u32);
        *slot += 1;
    }
    // (point, the earlier point it repeats), in order.
    let mut repeats: Vec<(u32, u32)> = offsets
        .par_windows(2)
        .map_init(
            || HashMap::with_capacity_and_hasher(2 * WELD_PARTITION, ahash::RandomState::new()),
            |first, w| {
                first.clear();
                let mut repeats = Vec::new();
                for &(key, i) in &sorted[w[0]..w[1]] {
                    let f = *first.entry(key).or_insert(i);
                    if f != i {
                        repeats.push((i, f));
                    }
                }
                repeats
            },
        )
        .flatten()
        .collect();
    repeats.sort_unstable();
    let mut positions = Vec::with_capacity(points.len() - repeats.len());
    let mut vertex = Vec::with_capacity(points.len());
    let mut repeats = repeats.into_iter().peekable();
    for (i, &p) in points.iter().enumerate() {
        let v = match repeats.next_if(|&(r, _)| r as usize == i) {
            Some((_, f)) => vertex[f as usize],
            None => {
                positions.push(p);
                (positions.len() - 1) as u32
            }
        };
        vertex.push(v);
    }
    (positions, vertex)
}

fn read_ascii(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonSoup, IoError> {
    let mut welder = Welder::with_capacity(0);
    let mut faces = FaceList::new();
    let mut corners: Vec<u32> = Vec::new();
    let mut in_loop = false;
    let mut lines = Lines::new(bytes);
    for (n, line) in lines.by_ref() {
        let mut t = tokens(line);
        let Some(keyword) = t.next() else { continue };
        let is = |word: &[u8]| keyword.eq_ignore_ascii_case(word);
        if is(b"vertex") {
            if !in_loop {
                return Err(ctx.parse(n, "'vertex' outside an 'outer loop'"));
            }
            let mut c = [0.0; 3];
            for (i, slot) in c.iter_mut().enumerate() {
                let tok = t.next().ok_or_else(|| ctx.parse(n, format!("vertex has {i} coordinates, 3 needed")))?;
                *slot = parse_f64(tok)
                    .ok_or_else(|| ctx.parse(n, format!("vertex coordinate '{}' is not a number", show(tok))))?;
            }
            corners.push(welder.vertex(c));
        } else if is(b"outer") {
            corners.clear();
            in_loop = true;
        } else if is(b"endloop") {
            if !in_loop {
                return Err(ctx.parse(n, "'endloop' without 'outer loop'"));
            }
            faces.push(&corners);
            in_loop = false;
        } else if !(is(b"solid") || is(b"facet") || is(b"endfacet") || is(b"endsolid")) {
            return Err(ctx.parse(n, format!("unexpected '{}' in ASCII STL", show(keyword))));
        }
    }
    if in_loop {
        return Err(ctx.truncated(lines.line(), "file ends inside a facet"));
    }
    Ok(PolygonSoup::new(welder.positions, faces))
}

/// The unit normal of a triangle, or zero when it is degenerate.
fn facet_normal(mesh: &MeshView<'_>, t: [u32; 3]) -> DVec3 {
    let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
    (b - a).cross(c - a).try_normalize().unwrap_or(DVec3::ZERO)
}

pub(crate) fn write(mesh: &MeshView<'_>, binary: bool, out: &mut impl Write) -> io::Result<()> {
    let triangles = mesh.faces.iter().flat_map(fan);
    if binary {
        let mut header = [b' '; 80];
        let text = b"binary STL written by subdiv-io";
        header[..text.len()].copy_from_slice(text);
        out.write_all(&header)?;
        let count = mesh.faces.iter().map(|f| f.len().saturating_sub(2)).sum::<usize>();
        out.write_all(&(count as u32).to_le_bytes())?;
        for t in triangles {
            let normal = facet_normal(mesh, t);
            for p in std::iter::once(normal).chain(t.map(|v| mesh.positions[v as usize])) {
                for x in p.to_array() {
                    out.write_all(&(x as f32).to_le_bytes())?;
                }
            }
            out.write_all(&[0, 0])?;
        }
    } else {
        let mut text = TextOut::new(out);
        let xyz = |text: &mut TextOut<'_, _>, p: DVec3| {
            for x in p.to_array() {
                text.bytes(b" ");
                text.f64_exp(x);
            }
        };
        text.bytes(b"solid subdiv");
        text.end_line()?;
        for t in triangles {
            text.bytes(b"  facet normal");
            xyz(&mut text, facet_normal(mesh, t));
            text.bytes(b"\n    outer loop");
            text.end_line()?;
            for v in t {
                text.bytes(b"      vertex");
                xyz(&mut text, mesh.positions[v as usize]);
                text.end_line()?;
            }
            text.bytes(b"    endloop\n  endfacet");
            text.end_line()?;
        }
        text.bytes(b"endsolid subdiv");
        text.end_line()?;
        text.finish()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;
    use subdiv_mesh::shapes::SplitMix64;

    #[test]
    fn welding_merges_signed_zeros_and_keeps_first_appearance_order() {
        let src = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex -0.0 0 0\n\
            endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 0 0 1\n\
            endloop\nendfacet\nendsolid t\n";
        let soup = read(src, Ctx::new(Path::new("t.stl"))).unwrap();
        assert_eq!(soup.positions.len(), 4);
        assert_eq!(soup.faces.face(1), &[2, 1, 3]);
    }

    /// The serial welder over every corner in order: the numbering the
    /// parallel one must reproduce.
    fn weld_serially(records: &[u8]) -> (Vec<DVec3>, Vec<u32>) {
        let mut welder = Welder::with_capacity(0);
        let corners = records
            .chunks_exact(50)
            .flat_map(|r| {
                (0..3)
                    .map(move |k| [0, 4, 8].map(|o| f32::from_le_bytes(r[12 + 12 * k + o..][..4].try_into().unwrap())))
            })
            .map(|c| welder.vertex(c.map(f64::from)))
            .collect();
        (welder.positions, corners)
    }

    /// Binary records of `n` triangles whose corners are drawn from `pool`.
    fn records(n: usize, pool: &[[f32; 3]], rng: &mut SplitMix64) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(50 * n);
        for _ in 0..n {
            bytes.extend([0u8; 12]);
            for _ in 0..3 {
                pool[rng.below(pool.len())].iter().for_each(|x| bytes.extend(x.to_le_bytes()));
            }
            bytes.extend([0, 0]);
        }
        bytes
    }

    fn bits(positions: &[DVec3]) -> Vec<[u64; 3]> {
        positions.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
    }

    #[test]
    fn parallel_welding_numbers_as_the_serial_welder() {
        let mut rng = SplitMix64(7);
        // Small pools repeat points within and across chunks; signed zeros
        // weld (the first appearance's sign is kept); a big pool is mostly
        // distinct; the sizes straddle the chunk and partition sizes.
        let mut zeros = vec![[0.0f32, 1.0, 2.0], [-0.0, 1.0, 2.0], [0.0, -0.0, -0.0], [-0.0, 0.0, 0.0]];
        zeros.extend((0..60).map(|i| [i as f32, -0.0, 0.5]));
        for (pool_size, triangles) in [(3, 10), (500, 3 * WELD_CHUNK + 17), (200_000, 2 * WELD_CHUNK + 1), (0, 5000)] {
            let mut pool: Vec<[f32; 3]> =
                (0..pool_size).map(|_| [0; 3].map(|_| (rng.below(1000) as f32) / 8.0)).collect();
            if pool.is_empty() {
                pool = zeros.clone();
            }
            let bytes = records(triangles, &pool, &mut rng);
            let (positions, corners) = weld_binary(&bytes);
            let (want_positions, want_corners) = weld_serially(&bytes);
            assert_eq!(bits(&positions), bits(&want_positions), "pool {pool_size}, {triangles} triangles");
            assert_eq!(corners, want_corners, "pool {pool_size}, {triangles} triangles");
        }
        assert_eq!(weld_binary(&[]), (vec![], vec![]));
    }

    #[test]
    fn welding_distinct_points_keeps_the_first_of_each() {
        let p = |x: f64| DVec3::new(x, 0.0, 1.0);
        let points = [p(1.0), p(-0.0), p(1.0), p(0.0), p(2.0), p(-0.0)];
        let (positions, vertex) = weld_distinct(&points);
        assert_eq!(bits(&positions), bits(&[p(1.0), p(-0.0), p(2.0)]));
        assert_eq!(vertex, [0, 1, 0, 1, 2, 1]);
        let many: Vec<DVec3> = (0..3 * WELD_PARTITION).map(|i| p((i % 1000) as f64)).collect();
        let (positions, vertex) = weld_distinct(&many);
        assert_eq!(positions.len(), 1000);
        assert!(vertex.iter().enumerate().all(|(i, &v)| v as usize == i % 1000));
    }

    #[test]
    fn ascii_text_is_the_std_formatted_text() {
        let mut rng = SplitMix64(3);
        let mesh = subdiv_mesh::shapes::torus(6, 5);
        let positions: Vec<DVec3> = mesh
            .positions()
            .iter()
            .map(|&p| p * 10f64.powi(rng.below(40) as i32 - 20) + DVec3::splat(rng.next_f64() - 0.5))
            .chain([DVec3::new(-0.0, 0.0, 1e300), DVec3::new(5e-324, -1.0, 100.0)])
            .collect();
        let mut faces = mesh.topology().faces().clone();
        faces.push(&[0, 30, 31]);
        let view = MeshView::new(&positions, &faces);
        let mut ours = Vec::new();
        write(&view, false, &mut ours).unwrap();
        // The layout with std's `{:e}` (shortest round-trip digits).
        let mut want = String::from("solid subdiv\n");
        for t in faces.iter().flat_map(fan) {
            let n = facet_normal(&view, t);
            want += &format!("  facet normal {:e} {:e} {:e}\n    outer loop\n", n.x, n.y, n.z);
            for v in t {
                let p = positions[v as usize];
                want += &format!("      vertex {:e} {:e} {:e}\n", p.x, p.y, p.z);
            }
            want += "    endloop\n  endfacet\n";
        }
        want += "endsolid subdiv\n";
        assert_eq!(String::from_utf8(ours).unwrap(), want);
    }

    #[test]
    fn binary_file_starting_with_solid_is_binary() {
        let mut data = b"solid but binary".to_vec();
        data.resize(80, 0);
        data.extend(1u32.to_le_bytes());
        for x in [0.0f32, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
            data.extend(x.to_le_bytes());
        }
        data.extend([0, 0]);
        let soup = read(&data, Ctx::new(Path::new("t.stl"))).unwrap();
        assert_eq!(soup.positions.len(), 3);
    }
}
