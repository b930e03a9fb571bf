//! Object File Format (Geomview OFF), ASCII and binary.
//!
//! Read: the headers `OFF`, `COFF`, `NOFF`, `CNOFF`, `STOFF` (any of the `ST`,
//! `C`, `N` prefixes; their extra vertex columns are ignored), counts on the
//! header line or the next one, `#` comments anywhere (also trailing a data
//! line), blank lines, CRLF, per-face colour columns after the indices.
//! A file without the `OFF` keyword (counts first) is accepted too, and so
//! is a leading UTF-8 byte-order mark; UTF-16 and binary data (other than
//! `OFF BINARY`) are reported as such. Counts and indices too large for their
//! type are "out of range", quoting the token.
//! `4OFF` and `nOFF` (other dimensions) are reported as unsupported.
//!
//! With the `ST` prefix every vertex carries texture coordinates `s t`
//! after its position, normal and colour (Geomview's order); they become
//! [`PolygonSoup::uvs`], one value per vertex. In ASCII a colour takes one
//! to four values, so with `C` the texture coordinates are the line's last
//! two values. They are not written (OFF writes positions and normals:
//! [`Format::carries_uvs`](crate::Format::carries_uvs)).
//!
//! ASCII data is read one vertex or face per line, which is how every writer
//! we know lays it out, and lets errors name the line.
//!
//! Binary OFF (`OFF BINARY`): counts, vertices and faces as 32-bit ints and
//! floats. Geomview's spec says big-endian with a colour count after every
//! face; real files (e.g. pmp-library's `fairing-cross.off`) are little-endian
//! without it. We pick the byte order whose counts fit the file size (the
//! spec's big-endian when both do) and the face layout that consumes the data
//! exactly (the spec's when both do).
//!
//! Write: ASCII `OFF` (`NOFF` with per-vertex normals), numbers in the shortest
//! form that parses back to the same `f64` bits.

use glam::{DVec2, DVec3};
use std::io::{self, Write};
use subdiv_mesh::{FaceList, FaceVarying, PolygonSoup};

use crate::error::{Ctx, IoError};
use crate::text::{
    check_text, is_blank, parse_bounded, parse_f64, parse_integer, show, strip_bom, strip_comment, tokens, IntError,
    Lines, TextOut,
};
use crate::{Format, MeshView};

/// What the header keyword announces.
#[derive(Clone, Copy, Debug, Default)]
struct Header {
    texture: bool,
    colour: bool,
    normal: bool,
}

/// Parses `[ST][C][N][4][n]OFF`; `None` when the token is not such a keyword.
fn parse_keyword(token: &[u8], ctx: Ctx<'_>) -> Result<Option<Header>, IoError> {
    let Some(mut rest) = token.strip_suffix(b"OFF") else { return Ok(None) };
    let mut header = Header::default();
    if let Some(r) = rest.strip_prefix(b"ST") {
        header.texture = true;
        rest = r;
    }
    if let Some(r) = rest.strip_prefix(b"C") {
        header.colour = true;
        rest = r;
    }
    if let Some(r) = rest.strip_prefix(b"N") {
        header.normal = true;
        rest = r;
    }
    match rest {
        b"" => Ok(Some(header)),
        b"4" | b"n" | b"4n" => Err(ctx.unsupported(format!("'{}' (OFF in other than 3 dimensions)", show(token)))),
        _ => Ok(None),
    }
}

/// The next line with content after comment stripping.
fn next_content<'a>(lines: &mut Lines<'a>) -> Option<(usize, &'a [u8])> {
    lines.map(|(n, l)| (n, strip_comment(l))).find(|(_, l)| !is_blank(l))
}

/// True when nothing but blanks and comments follows.
fn at_end(lines: &Lines<'_>, bytes: &[u8]) -> bool {
    let mut rest = Lines::new(&bytes[lines.offset()..]);
    next_content(&mut rest).is_none()
}

pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonSoup, IoError> {
    let bytes = strip_bom(bytes);
    let mut lines = Lines::new(bytes);
    let Some((header_line, first)) = next_content(&mut lines) else { return Err(ctx.empty()) };
    let mut toks = tokens(first).peekable();
    // A first token that is an integer (even one too large) starts the counts of a headerless file.
    let keyword = toks.peek().copied().filter(|&t| parse_integer(t) == Err(IntError::NotInteger));
    let expected_header = |keyword: &[u8]| {
        ctx.parse(header_line, format!("expected an OFF header ('OFF', 'COFF', 'NOFF', …), found '{}'", show(keyword)))
    };
    if let Some(keyword) = keyword {
        toks.next();
        if toks.peek() == Some(&&b"BINARY"[..]) {
            // ASCII data is read per line, so only binary needs the header's columns.
            let header = parse_keyword(keyword, ctx)?.ok_or_else(|| expected_header(keyword))?;
            return read_binary(&bytes[lines.offset()..], header, ctx);
        }
    }
    // Binary OFF is binary by design; everything else must be text.
    check_text(bytes, Format::Off, ctx)?;
    let header = match keyword {
        Some(keyword) => parse_keyword(keyword, ctx)?.ok_or_else(|| expected_header(keyword))?,
        None => Header::default(),
    };

    // Counts: on the header line, or the next line with content.
    let mut counts: Vec<&[u8]> = toks.collect();
    let mut counts_line = header_line;
    if counts.is_empty() {
        let Some((n, line)) = next_content(&mut lines) else {
            return Err(ctx.truncated(lines.line(), "file ends before the vertex and face counts"));
        };
        counts = tokens(line).collect();
        counts_line = n;
    }
    let count = |i: usize, what: &str| -> Result<usize, IoError> {
        let t = counts.get(i).ok_or_else(|| ctx.parse(counts_line, format!("missing {what} count")))?;
        parse_bounded(t, &format!("{what} count")).map_err(|message| ctx.parse(counts_line, message))
    };
    let nv = count(0, "vertex")?;
    let nf = count(1, "face")?;

    // Every vertex line has at least 6 bytes ("0 0 0\n"), every face line 8.
    let mut positions = Vec::with_capacity(nv.min(bytes.len() / 6));
    let mut uvs: Vec<DVec2> = Vec::new();
    while positions.len() < nv {
        let Some((n, line)) = next_content(&mut lines) else {
            return Err(
                ctx.truncated(lines.line(), format!("expected {nv} vertices, file ends after {}", positions.len()))
            );
        };
        let mut c = [0.0; 3];
        let mut t = tokens(line);
        for (i, slot) in c.iter_mut().enumerate() {
            let Some(tok) = t.next() else {
                let what = format!("vertex {} has {i} coordinates, 3 needed", positions.len());
                return Err(if at_end(&lines, bytes) { ctx.truncated(n, what) } else { ctx.parse(n, what) });
            };
            *slot = parse_f64(tok)
                .ok_or_else(|| ctx.parse(n, format!("vertex coordinate '{}' is not a number", show(tok))))?;
        }
        if header.texture {
            let values: Vec<&[u8]> = tokens(line).collect();
            let first =
                if header.colour { values.len().saturating_sub(2) } else { 3 + if header.normal { 3 } else { 0 } };
            let st = values.get(first..first + 2).filter(|_| first >= 3);
            let Some(st) = st else {
                let what =
                    format!("vertex {} has no texture coordinates 's t' ({} values)", positions.len(), values.len());
                return Err(if at_end(&lines, bytes) { ctx.truncated(n, what) } else { ctx.parse(n, what) });
            };
            let number = |t: &[u8]| {
                parse_f64(t).ok_or_else(|| ctx.parse(n, format!("texture coordinate '{}' is not a number", show(t))))
            };
            uvs.push(DVec2::new(number(st[0])?, number(st[1])?));
        }
        positions.push(DVec3::from(c));
    }

    let mut faces = FaceList::with_capacity(nf.min(bytes.len() / 8), 0);
    let mut corners = Vec::new();
    while faces.len() < nf {
        let Some((n, line)) = next_content(&mut lines) else {
            return Err(ctx.truncated(lines.line(), format!("expected {nf} faces, file ends after {}", faces.len())));
        };
        let mut t = tokens(line);
        let Some(size_token) = t.next() else { continue }; // never: content lines have a token
        let size: u64 = parse_bounded(size_token, "face corner count").map_err(|message| ctx.parse(n, message))?;
        corners.clear();
        for i in 0..size {
            let Some(tok) = t.next() else {
                let what = format!("face {} declares {size} corners but lists {i}", faces.len());
                return Err(if at_end(&lines, bytes) { ctx.truncated(n, what) } else { ctx.parse(n, what) });
            };
            corners.push(parse_bounded(tok, "face index").map_err(|message| ctx.parse(n, message))?);
        }
        faces.push(&corners);
    }
    Ok(with_vertex_uvs(PolygonSoup::new(positions, faces), header.texture.then_some(uvs)))
}

/// The soup with one texture coordinate per vertex, when the file has them.
fn with_vertex_uvs(soup: PolygonSoup, uvs: Option<Vec<DVec2>>) -> PolygonSoup {
    let uvs = uvs.map(|values| FaceVarying { values, indices: soup.faces.indices().to_vec() });
    PolygonSoup { uvs, ..soup }
}

/// Reads 32-bit words in one byte order.
#[derive(Clone, Copy)]
struct Words<'a> {
    data: &'a [u8],
    big_endian: bool,
}

impl Words<'_> {
    fn word(&self, at: usize) -> Option<[u8; 4]> {
        let bytes: [u8; 4] = self.data.get(at..at.checked_add(4)?)?.try_into().ok()?;
        Some(if self.big_endian { bytes } else { [bytes[3], bytes[2], bytes[1], bytes[0]] })
    }
    fn i32(&self, at: usize) -> Option<i32> {
        self.word(at).map(i32::from_be_bytes)
    }
    fn f32(&self, at: usize) -> Option<f32> {
        self.word(at).map(f32::from_be_bytes)
    }
}

fn read_binary(data: &[u8], header: Header, ctx: Ctx<'_>) -> Result<PolygonSoup, IoError> {
    let floats_per_vertex =
        3 + if header.normal { 3 } else { 0 } + if header.colour { 4 } else { 0 } + if header.texture { 2 } else { 0 };
    let fits = |w: Words<'_>| -> Option<(usize, usize)> {
        let nv = usize::try_from(w.i32(0)?).ok()?;
        let nf = usize::try_from(w.i32(4)?).ok()?;
        w.i32(8).filter(|&ne| ne >= 0)?;
        // Each face needs at least its corner count.
        let need = nv.checked_mul(4 * floats_per_vertex)?.checked_add(nf.checked_mul(4)?)?.checked_add(12)?;
        (need <= data.len()).then_some((nv, nf))
    };
    if data.len() < 12 {
        return Err(ctx.truncated(None, "binary OFF ends before its vertex, face and edge counts"));
    }
    let big = Words { data, big_endian: true };
    let little = Words { data, big_endian: false };
    let (words, nv, nf) = match (fits(big), fits(little)) {
        (Some((nv, nf)), _) => (big, nv, nf),
        (None, Some((nv, nf))) => (little, nv, nf),
        (None, None) => {
            return Err(
                ctx.parse(None, "binary OFF counts are negative or do not fit the file size in either byte order")
            )
        }
    };

    let mut positions = Vec::with_capacity(nv);
    let mut uvs = Vec::with_capacity(if header.texture { nv } else { 0 });
    // Geomview's order: position, normal, colour (4 floats in binary), texture.
    let texture_at = 4 * (3 + if header.normal { 3 } else { 0 } + if header.colour { 4 } else { 0 });
    let mut at = 12;
    for _ in 0..nv {
        let c = [0, 4, 8].map(|o| words.f32(at + o).map_or(f64::NAN, f64::from));
        positions.push(DVec3::from(c));
        if header.texture {
            let [s, t] = [0, 4].map(|o| words.f32(at + texture_at + o).map_or(f64::NAN, f64::from));
            uvs.push(DVec2::new(s, t));
        }
        at += 4 * floats_per_vertex;
    }

    // The spec's layout first; the plain one when the spec's does not end
    // exactly at the end of the file.
    let spec = binary_faces(words, at, nf, true);
    let plain = match &spec {
        Ok((_, end)) if *end == data.len() => None,
        _ => Some(binary_faces(words, at, nf, false)),
    };
    let result = match (spec, plain) {
        (_, Some(Ok((faces, end)))) if end == data.len() => faces,
        (Ok((faces, _)), _) | (Err(_), Some(Ok((faces, _)))) => faces,
        (Err(spec), plain) => {
            let (truncated, what) = match plain {
                Some(Err(plain)) if !words.big_endian => plain,
                _ => spec,
            };
            return Err(if truncated { ctx.truncated(None, what) } else { ctx.parse(None, what) });
        }
    };
    Ok(with_vertex_uvs(PolygonSoup::new(positions, result), header.texture.then_some(uvs)))
}

/// Reads `nf` binary faces from `at`; with `colour_count`, each face is
/// followed by a count of colour floats and the floats (Geomview's layout).
/// Returns the faces and the end offset, or what went wrong (and whether
/// that is the data ending early).
fn binary_faces(
    words: Words<'_>,
    mut at: usize,
    nf: usize,
    colour_count: bool,
) -> Result<(FaceList, usize), (bool, String)> {
    let len = words.data.len();
    let mut faces = FaceList::with_capacity(nf, 3 * nf);
    let mut corners = Vec::new();
    let ends = |f: usize| (true, format!("binary data ends inside face {f} of {nf}"));
    for f in 0..nf {
        let size = words.i32(at).ok_or_else(|| ends(f))?;
        let size = usize::try_from(size).map_err(|_| (false, format!("face {f} has a negative corner count")))?;
        at += 4;
        if size > (len - at) / 4 {
            return Err(ends(f));
        }
        corners.clear();
        for k in 0..size {
            let index = words.i32(at + 4 * k).ok_or_else(|| ends(f))?;
            corners.push(u32::try_from(index).map_err(|_| (false, format!("face {f} has a negative index")))?);
        }
        at += 4 * size;
        faces.push(&corners);
        if colour_count {
            let colours = words.i32(at).ok_or_else(|| ends(f))?;
            let colours = usize::try_from(colours)
                .ok()
                .filter(|&c| c <= 4)
                .ok_or_else(|| (false, format!("face {f} has an invalid colour count")))?;
            at += 4 + 4 * colours;
            if at > len {
                return Err(ends(f));
            }
        }
    }
    Ok((faces, at))
}

pub(crate) fn write(mesh: &MeshView<'_>, out: &mut impl Write) -> io::Result<()> {
    out.write_all(if mesh.normals.is_some() { b"NOFF\n" } else { b"OFF\n" })?;
    writeln!(out, "{} {} 0", mesh.positions.len(), mesh.faces.len())?;
    let mut text = TextOut::new(out);
    for (i, p) in mesh.positions.iter().enumerate() {
        let normal = mesh.normals.map(|n| n[i].to_array());
        for (k, x) in p.to_array().into_iter().chain(normal.into_iter().flatten()).enumerate() {
            if k > 0 {
                text.bytes(b" ");
            }
            text.f64(x);
        }
        text.end_line()?;
    }
    for face in mesh.faces.iter() {
        text.int(face.len());
        for &v in face {
            text.bytes(b" ");
            text.int(v);
        }
        text.end_line()?;
    }
    text.finish()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn read_str(s: &[u8]) -> Result<PolygonSoup, IoError> {
        read(s, Ctx::new(Path::new("t.off")))
    }

    #[test]
    fn keyword_prefixes() {
        let ctx = Ctx::new(Path::new("t.off"));
        assert!(parse_keyword(b"STCNOFF", ctx).unwrap().is_some_and(|h| h.texture && h.colour && h.normal));
        assert!(parse_keyword(b"PLY", ctx).unwrap().is_none());
        assert!(matches!(parse_keyword(b"4OFF", ctx), Err(IoError::Unsupported { .. })));
    }

    #[test]
    fn binary_big_endian_with_colour_counts() {
        let mut data = b"OFF BINARY\n".to_vec();
        let words: [i32; 3] = [3, 1, 0];
        words.iter().for_each(|w| data.extend(w.to_be_bytes()));
        for x in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
            data.extend(x.to_be_bytes());
        }
        for w in [3i32, 0, 1, 2, 0] {
            data.extend(w.to_be_bytes());
        }
        let soup = read_str(&data).unwrap();
        assert_eq!(soup.positions[1], DVec3::X);
        assert_eq!(soup.faces.face(0), &[0, 1, 2]);
    }

    #[test]
    fn negative_counts_are_errors() {
        assert!(matches!(read_str(b"OFF\n-1 2 0\n"), Err(IoError::Parse { line: Some(2), .. })));
    }
}
