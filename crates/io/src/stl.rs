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
use std::collections::HashMap;
use std::io::{self, Write};
use subdiv_mesh::{FaceList, PolygonSoup};

use crate::error::{Ctx, IoError};
use crate::text::{is_blank, parse_f64, show, sniff, strip_bom, tokens, Lines, NotText};
use crate::{fan, MeshView};

/// Merges bit-identical positions, numbering vertices by first appearance.
#[derive(Default)]
struct Welder {
    positions: Vec<DVec3>,
    index: HashMap<[u64; 3], u32>,
}

impl Welder {
    fn vertex(&mut self, p: DVec3) -> u32 {
        // Adding +0.0 turns -0.0 into +0.0 and leaves every other value alone.
        let key = (p + DVec3::ZERO).to_array().map(f64::to_bits);
        let next = self.positions.len() as u32;
        let v = *self.index.entry(key).or_insert(next);
        if v == next {
            self.positions.push(p);
        }
        v
    }
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
    let mut welder = Welder::default();
    let mut faces = FaceList::with_capacity(n, 3 * n);
    for record in bytes[84..84 + 50 * n].chunks_exact(50) {
        let mut corners = [0u32; 3];
        for (k, corner) in corners.iter_mut().enumerate() {
            let at = 12 + 12 * k;
            let c = [0, 4, 8].map(|o| {
                let b = &record[at + o..at + o + 4];
                f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            });
            *corner = welder.vertex(DVec3::from(c));
        }
        faces.push(&corners);
    }
    Ok(PolygonSoup::new(welder.positions, faces))
}

fn read_ascii(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonSoup, IoError> {
    let mut welder = Welder::default();
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
            corners.push(welder.vertex(DVec3::from(c)));
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
        out.write_all(b"solid subdiv\n")?;
        for t in triangles {
            let n = facet_normal(mesh, t);
            writeln!(out, "  facet normal {:e} {:e} {:e}\n    outer loop", n.x, n.y, n.z)?;
            for v in t {
                let p = mesh.positions[v as usize];
                writeln!(out, "      vertex {:e} {:e} {:e}", p.x, p.y, p.z)?;
            }
            out.write_all(b"    endloop\n  endfacet\n")?;
        }
        out.write_all(b"endsolid subdiv\n")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn welding_merges_signed_zeros_and_keeps_first_appearance_order() {
        let src = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex -0.0 0 0\n\
            endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 0 0 1\n\
            endloop\nendfacet\nendsolid t\n";
        let soup = read(src, Ctx::new(Path::new("t.stl"))).unwrap();
        assert_eq!(soup.positions.len(), 4);
        assert_eq!(soup.faces.face(1), &[2, 1, 3]);
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
