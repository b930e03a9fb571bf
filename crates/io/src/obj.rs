//! Wavefront OBJ, read and written by hand.
//!
//! Read: `v x y z [w]` (further columns such as vertex colours ignored), `f`
//! with `v`, `v/vt`, `v/vt/vn` or `v//vn` corners and negative (relative)
//! indices, `g`/`o` names recorded as face groups; `vt`, `vn`, `s`, `usemtl`,
//! `mtllib`, `l`, `p` and unknown statements are ignored. `#` starts a comment
//! anywhere, `\` at the end of a line continues it, CRLF is accepted, a
//! UTF-8 byte-order mark is skipped. UTF-16 and binary data are reported as
//! such (from the first 4 KiB, and from any statement keyword holding a
//! control character), not read as unknown statements.
//!
//! Not `tobj`: it renumbers vertices per model in order of first use and
//! drops unreferenced ones, which loses the input vertex order (the order
//! interpolation results are reported in) and the isolated vertices the
//! validator must see.
//!
//! Write: `v` with the shortest decimal form that parses back to the same
//! `f64` bits, `vn` when normals are given, 1-based `f` lines (`f a//a` with
//! normals).

use glam::DVec3;
use std::collections::HashMap;
use std::io::{self, Write};
use subdiv_mesh::{FaceGroups, FaceList, PolygonSoup};

use crate::error::{Ctx, IoError};
use crate::text::{
    check_text, is_control, parse_f64, parse_integer, show, strip_bom, strip_comment, tokens, write_f64, IntError,
    Lines,
};
use crate::{Format, MeshView};

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

pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonSoup, IoError> {
    let bytes = strip_bom(bytes);
    check_text(bytes, Format::Obj, ctx)?;
    let mut positions: Vec<DVec3> = Vec::new();
    let mut faces = FaceList::new();
    let mut table = GroupTable::default();
    let mut face_group: Vec<u32> = Vec::new();
    let mut current_group: Option<u32> = None;
    let mut saw_group_statement = false;
    let mut corners: Vec<u32> = Vec::new();
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
        match keyword {
            b"v" => {
                let mut c = [0.0; 3];
                for (i, slot) in c.iter_mut().enumerate() {
                    let Some(t) = toks.next() else {
                        return Err(ctx.truncated(n, format!("vertex has {i} coordinates, 3 needed")));
                    };
                    *slot = parse_f64(t)
                        .ok_or_else(|| ctx.parse(n, format!("vertex coordinate '{}' is not a number", show(t))))?;
                }
                positions.push(DVec3::from(c));
            }
            b"f" | b"fo" => {
                corners.clear();
                for t in toks {
                    corners.push(face_index(t, positions.len(), n, ctx)?);
                }
                faces.push(&corners);
                let g = match current_group {
                    Some(g) => g,
                    None => *current_group.insert(table.intern("default".to_owned())),
                };
                face_group.push(g);
            }
            b"g" | b"o" => {
                saw_group_statement = true;
                let name: Vec<_> = toks.map(String::from_utf8_lossy).collect();
                let name = if name.is_empty() { "default".to_owned() } else { name.join(" ") };
                current_group = Some(table.intern(name));
            }
            // Unknown statements are ignored, but not binary data past the
            // part `check_text` looked at (a text file with a binary tail).
            _ if keyword.iter().any(|&b| is_control(b)) => return Err(ctx.binary(n, Format::Obj)),
            _ => {}
        }
    }

    if positions.is_empty() && faces.is_empty() {
        return Err(ctx.empty());
    }
    let groups =
        if saw_group_statement { FaceGroups { names: table.groups.names, face_group } } else { FaceGroups::default() };
    Ok(PolygonSoup { positions, faces, groups, ..PolygonSoup::default() })
}

/// Maps one face corner (`v`, `v/vt`, `v/vt/vn`, `v//vn`) to a 0-based vertex
/// index. Positive indices beyond the vertex count pass through (the validator
/// reports them); 0, relative indices before the first vertex and indices
/// beyond what a `u32` holds cannot be stored and are errors.
fn face_index(token: &[u8], vertices_so_far: usize, line: usize, ctx: Ctx<'_>) -> Result<u32, IoError> {
    let v = token.split(|&b| b == b'/').next().unwrap_or(token);
    let k = match parse_integer(v) {
        Ok(k) => k,
        Err(IntError::NotInteger) => {
            return Err(ctx.parse(line, format!("face index '{}' is not an integer", show(token))))
        }
        Err(IntError::OutOfRange) => return Err(ctx.parse(line, format!("face index {} out of range", show(v)))),
    };
    let index = match k {
        0 => return Err(ctx.parse(line, "face index 0 is invalid (OBJ indices start at 1)")),
        k if k > 0 => k - 1,
        k => vertices_so_far as i128 + k,
    };
    if index < 0 {
        return Err(ctx.parse(
            line,
            format!("relative face index {k} points before the first vertex ({vertices_so_far} vertices so far)"),
        ));
    }
    u32::try_from(index).map_err(|_| {
        ctx.parse(line, format!("face index {k} out of range (the largest is {})", u64::from(u32::MAX) + 1))
    })
}

pub(crate) fn write(mesh: &MeshView<'_>, out: &mut impl Write) -> io::Result<()> {
    out.write_all(b"# written by subdiv-io\n")?;
    for p in mesh.positions {
        out.write_all(b"v")?;
        for x in p.to_array() {
            out.write_all(b" ")?;
            write_f64(out, x)?;
        }
        out.write_all(b"\n")?;
    }
    if let Some(normals) = mesh.normals {
        for n in normals {
            out.write_all(b"vn")?;
            for x in n.to_array() {
                out.write_all(b" ")?;
                write_f64(out, x)?;
            }
            out.write_all(b"\n")?;
        }
    }
    let with_normals = mesh.normals.is_some();
    for face in mesh.faces.iter() {
        out.write_all(b"f")?;
        for &v in face {
            let k = u64::from(v) + 1;
            if with_normals {
                write!(out, " {k}//{k}")?;
            } else {
                write!(out, " {k}")?;
            }
        }
        out.write_all(b"\n")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn read_str(s: &str) -> Result<PolygonSoup, IoError> {
        read(s.as_bytes(), Ctx::new(Path::new("t.obj")))
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
