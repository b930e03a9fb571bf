//! Which format a file is in, from its extension.

use std::fmt;
use std::path::Path;

use crate::IoError;

/// A mesh file format.
///
/// Reading needs only the family: [`crate::read_mesh`] tells ASCII from
/// binary PLY and STL, JSON glTF from GLB, and text, binary and zipped USD
/// by the content. Writing uses the exact variant; [`Format::from_path`]
/// picks the binary one for `.ply`, `.stl` and `.usd`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Wavefront OBJ: polygons kept, `f64` positions round-trip exactly.
    Obj,
    /// Geomview OFF (ASCII written; ASCII and binary read).
    Off,
    /// PLY with an ASCII body.
    PlyAscii,
    /// PLY with a binary little-endian body (big-endian is read too).
    PlyBinary,
    /// ASCII STL: triangles only, `f64` positions kept in `{:e}` form.
    StlAscii,
    /// Binary STL: triangles only, `f32` positions.
    StlBinary,
    /// glTF 2.0 JSON with the buffer embedded as a base64 `data:` URI.
    Gltf,
    /// glTF 2.0 binary container.
    Glb,
    /// USD text layer (`.usda`): every `UsdGeomMesh` prim, with its
    /// subdivision scheme, tags and `primvars:st` ([`crate::usd`]); `f32`
    /// points.
    Usda,
    /// USD binary crate layer (`.usdc`, and `.usd` when written).
    Usdc,
    /// USD zip package (`.usdz`): its first layer, text or binary; written
    /// with a binary layer inside.
    Usdz,
}

impl Format {
    /// Every format, in declaration order.
    pub const ALL: [Format; 11] = [
        Format::Obj,
        Format::Off,
        Format::PlyAscii,
        Format::PlyBinary,
        Format::StlAscii,
        Format::StlBinary,
        Format::Gltf,
        Format::Glb,
        Format::Usda,
        Format::Usdc,
        Format::Usdz,
    ];

    /// The format for a file name's extension (case-insensitive): `.obj`,
    /// `.off`, `.ply` (binary), `.stl` (binary), `.gltf`, `.glb`, `.usda`,
    /// `.usdc`, `.usd` (binary when written; read by its content), `.usdz`.
    ///
    /// # Errors
    /// [`IoError::UnknownFormat`] for any other or a missing extension.
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        path.extension()
            .and_then(|e| e.to_str())
            .and_then(Format::from_extension)
            .ok_or_else(|| IoError::UnknownFormat { path: path.to_path_buf() })
    }

    /// The format for an extension without its dot, case-insensitive.
    pub fn from_extension(extension: &str) -> Option<Format> {
        Some(match extension.to_ascii_lowercase().as_str() {
            "obj" => Format::Obj,
            "off" => Format::Off,
            "ply" => Format::PlyBinary,
            "stl" => Format::StlBinary,
            "gltf" => Format::Gltf,
            "glb" => Format::Glb,
            "usda" => Format::Usda,
            "usdc" | "usd" => Format::Usdc,
            "usdz" => Format::Usdz,
            _ => return None,
        })
    }

    /// The usual extension, without its dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Off => "off",
            Format::PlyAscii | Format::PlyBinary => "ply",
            Format::StlAscii | Format::StlBinary => "stl",
            Format::Gltf => "gltf",
            Format::Glb => "glb",
            Format::Usda => "usda",
            Format::Usdc => "usdc",
            Format::Usdz => "usdz",
        }
    }

    /// True when writing splits polygons into triangles (STL, glTF).
    pub fn triangulates(self) -> bool {
        matches!(self, Format::StlAscii | Format::StlBinary | Format::Gltf | Format::Glb)
    }

    /// True when written `f64` positions read back bit-exactly (all but
    /// binary STL, glTF and USD, which store `f32`: USD's `point3f[]`
    /// points and `texCoord2f[]` texture coordinates).
    pub fn keeps_f64(self) -> bool {
        !matches!(self, Format::StlBinary | Format::Gltf | Format::Glb) && !self.is_usd()
    }

    /// True for the USD formats (`.usda`, `.usdc`, `.usdz`): files that hold
    /// any number of meshes by prim path ([`crate::usd`]).
    pub fn is_usd(self) -> bool {
        matches!(self, Format::Usda | Format::Usdc | Format::Usdz)
    }

    /// True when vertex order and unreferenced vertices survive a write and
    /// read (all but STL, which stores corners per triangle and is welded on
    /// read). glTF keeps them too, but a mesh with texture-coordinate seams
    /// gains vertices there ([`Format::splits_uv_seams`]).
    pub fn keeps_vertices(self) -> bool {
        !matches!(self, Format::StlAscii | Format::StlBinary)
    }

    /// True when the writer writes texture coordinates ([`crate::MeshView::uvs`]):
    /// OBJ (`vt`, seams kept), PLY (per vertex, or per face corner when
    /// there are seams) and glTF (`TEXCOORD_0`, vertices split at seams).
    /// glTF (`TEXCOORD_0`, vertices split at seams) and USD (`primvars:st`,
    /// face-varying and indexed: seams kept).
    /// OFF and STL leave them out (OFF's `ST` variant is read, not written).
    pub fn carries_uvs(self) -> bool {
        matches!(self, Format::Obj | Format::PlyAscii | Format::PlyBinary | Format::Gltf | Format::Glb) || self.is_usd()
    }

    /// True when the writer splits vertices where the texture coordinates
    /// have seams (glTF: its attributes are per vertex), so that a mesh with
    /// seams reads back with more vertices, cut open along the seams.
    pub fn splits_uv_seams(self) -> bool {
        matches!(self, Format::Gltf | Format::Glb)
    }

    /// True when the writer writes crease and corner tags
    /// ([`crate::MeshView::tags`]): OBJ, as OpenSubdiv's `t` lines, and USD,
    /// as `UsdGeomMesh`'s crease, corner and hole attributes and its
    /// subdivision options. No other format has a standard place for them
    /// (glTF included).
    pub fn carries_tags(self) -> bool {
        matches!(self, Format::Obj) || self.is_usd()
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::Off => "OFF",
            Format::PlyAscii => "PLY (ASCII)",
            Format::PlyBinary => "PLY (binary)",
            Format::StlAscii => "STL (ASCII)",
            Format::StlBinary => "STL (binary)",
            Format::Gltf => "glTF",
            Format::Glb => "GLB",
            Format::Usda => "USD (text)",
            Format::Usdc => "USD (binary)",
            Format::Usdz => "USDZ",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_are_case_insensitive_and_round_trip() {
        assert_eq!(Format::from_path(Path::new("a/B.PLY")).unwrap(), Format::PlyBinary);
        assert!(matches!(Format::from_path(Path::new("mesh")), Err(IoError::UnknownFormat { .. })));
        assert!(matches!(Format::from_path(Path::new("mesh.xyz")), Err(IoError::UnknownFormat { .. })));
        for f in Format::ALL {
            let back = Format::from_extension(f.extension()).unwrap();
            assert_eq!(back.extension(), f.extension());
        }
    }
}
