//! The one error type of the crate, and the small context every reader and
//! writer uses to build it.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::Format;

/// Everything that can go wrong reading or writing a mesh file.
///
/// Every variant names the file; errors in text formats also carry the
/// 1-based line, so the message reads like a compiler's:
/// `mesh.obj:12: face index 'x' is not an integer`.
///
/// Topological defects (out-of-range or repeated indices, faces with fewer
/// than three corners, NaN coordinates) are *not* errors of the readers:
/// they pass them through and `subdiv_mesh` reports them when it validates
/// the soup — as [`IoError::Validation`] when [`crate::load_mesh`] does.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IoError {
    /// The operating system refused to read or write the file.
    #[error("{}: {source}", .path.display())]
    Io {
        /// The file being read or written.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The file name has no extension this crate knows.
    #[error(
        "{}: unknown mesh format (expected extension .obj, .off, .ply, .stl, .gltf, .glb, .usda, .usdc, .usd or .usdz)",
        .path.display()
    )]
    UnknownFormat {
        /// The file whose extension was not recognised.
        path: PathBuf,
    },
    /// The file holds no mesh data at all (zero bytes, or only blanks and comments).
    #[error("{}: file is empty (no vertices and no faces)", .path.display())]
    Empty {
        /// The empty file.
        path: PathBuf,
    },
    /// The file does not follow its format.
    #[error("{}: {message}", Location(.path, *.line))]
    Parse {
        /// The file being read.
        path: PathBuf,
        /// 1-based line of the problem (text formats only).
        line: Option<usize>,
        /// What is wrong, naming the offending token or element.
        message: String,
    },
    /// The file ends before the data its header or syntax promises.
    #[error("{}: file is truncated: {what}", Location(.path, *.line))]
    Truncated {
        /// The file being read.
        path: PathBuf,
        /// 1-based line where the file ends (text formats only).
        line: Option<usize>,
        /// What is missing, e.g. "expected 6 faces, found 3".
        what: String,
    },
    /// A valid file that uses a feature this crate does not read.
    #[error("{}: unsupported: {what}", .path.display())]
    Unsupported {
        /// The file being read.
        path: PathBuf,
        /// The unsupported feature.
        what: String,
    },
    /// The path names something that is not a regular file (a directory, a
    /// FIFO, a device, a socket): refused before it is opened, because
    /// opening a FIFO blocks and reading a device may never end.
    #[error("{}: not a regular file (it is {kind})", .path.display())]
    NotAFile {
        /// The path that was to be read.
        path: PathBuf,
        /// What it is instead, with its article: `a directory`, `a FIFO`, …
        kind: &'static str,
    },
    /// A glTF buffer URI that this crate will not follow: anything but a
    /// `data:` URI or a relative path that resolves to a regular file inside
    /// the glTF file's own directory.
    #[error("{}: buffer uri '{uri}' refused: {reason}", .path.display())]
    RefusedUri {
        /// The glTF file that holds the URI.
        path: PathBuf,
        /// The URI as written in the file (cut to a readable length).
        uri: String,
        /// Why it is refused, e.g. "it is an absolute path".
        reason: String,
    },
    /// A text format holds UTF-16 text (a UTF-16 byte-order mark, or NUL
    /// bytes interleaved with ASCII).
    #[error("{}: UTF-16 text is not supported; save the file as UTF-8", .path.display())]
    Utf16 {
        /// The file being read.
        path: PathBuf,
    },
    /// A text format holds binary data (NUL bytes, or mostly bytes that are
    /// neither printable nor whitespace): most likely the wrong file, or a
    /// binary file with the wrong extension.
    #[error("{}: binary data, not {}", Location(.path, *.line), a_file_of(*.format))]
    BinaryData {
        /// The file being read.
        path: PathBuf,
        /// 1-based line where the binary data was found, when it was found
        /// past the start of the file.
        line: Option<usize>,
        /// The text format the file was read as (its family: ASCII PLY and
        /// STL stand for PLY and STL).
        format: Format,
    },
    /// The mesh handed to a writer cannot be written in the requested format
    /// (an index out of range, a normal count that does not match, …).
    #[error("{}: cannot write mesh: {message}", .path.display())]
    InvalidMesh {
        /// The file that was to be written (`<memory>` for in-memory output).
        path: PathBuf,
        /// What is wrong with the mesh.
        message: String,
    },
    /// A USD file holds several `Mesh` prims where one mesh was asked for
    /// ([`crate::read_mesh`]): read it as a scene ([`crate::usd::read_scene`])
    /// or pick one prim ([`crate::usd::UsdScene::select`]; `--prim` on the
    /// command line).
    #[error(
        "{}: {} Mesh prims ({}); choose one with --prim, or write a USD file to keep them all",
        .path.display(), .prims.len(), shown_prims(.prims)
    )]
    SeveralMeshes {
        /// The file that was read.
        path: PathBuf,
        /// The prim paths of its meshes, in the file's order.
        prims: Vec<String>,
    },
    /// The file was read, but what it holds is no valid mesh (non-manifold,
    /// an index out of range, a NaN coordinate, …): [`crate::load_mesh`].
    #[error("{}: {source}", .path.display())]
    Validation {
        /// The file that was read.
        path: PathBuf,
        /// Why its mesh is not valid, naming the offending element.
        #[source]
        source: subdiv_mesh::MeshError,
    },
}

impl IoError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            IoError::Io { path, .. }
            | IoError::UnknownFormat { path }
            | IoError::Empty { path }
            | IoError::Parse { path, .. }
            | IoError::Truncated { path, .. }
            | IoError::Unsupported { path, .. }
            | IoError::InvalidMesh { path, .. }
            | IoError::NotAFile { path, .. }
            | IoError::RefusedUri { path, .. }
            | IoError::Utf16 { path }
            | IoError::BinaryData { path, .. }
            | IoError::Validation { path, .. }
            | IoError::SeveralMeshes { path, .. } => path,
        }
    }

    /// The 1-based line the error is about, when the format is text and the
    /// problem sits on a line.
    pub fn line(&self) -> Option<usize> {
        match self {
            IoError::Parse { line, .. } | IoError::Truncated { line, .. } | IoError::BinaryData { line, .. } => *line,
            _ => None,
        }
    }
}

/// Something a reader dropped or did not apply instead of failing: the mesh
/// is read, and the caller decides whether to tell the user
/// ([`crate::read_mesh_with_warnings`]). The message names the file and,
/// for text formats, the line, like an [`IoError`]'s.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ReadWarning {
    /// Some faces have texture coordinates and others have none, so there
    /// is no face-varying channel to build: the mesh is read without
    /// texture coordinates. This is what an OBJ exported from several
    /// objects looks like when only some of them have a UV map (Blender
    /// writes `f v/vt/vn` for those and `f v//vn` for the others).
    UvsDropped {
        /// The file being read.
        path: PathBuf,
        /// 1-based line of the first face that breaks the pattern (text formats only).
        line: Option<usize>,
        /// Which faces or primitives have them and which do not.
        reason: String,
    },
    /// OBJ tag lines (`t NAME …`) of a name the reader does not apply:
    /// OpenSubdiv's hierarchical edits (`vertexedit`, `edgeedit`,
    /// `faceedit`, which OpenSubdiv 3 does not apply either) and unknown
    /// names. They are well formed but not applied.
    TagsIgnored {
        /// The file being read.
        path: PathBuf,
        /// 1-based line of the first such tag.
        line: usize,
        /// How many such lines there are.
        lines: usize,
        /// Their distinct names in order of first appearance, at most
        /// [`ReadWarning::NAMES_KEPT`] of them.
        names: Vec<String>,
    },
    /// A defect of the validated mesh that does not stop its use
    /// ([`subdiv_mesh::Warning`]: isolated vertices, zero-area faces), from
    /// [`crate::load_mesh_with_warnings`].
    MeshDefect {
        /// The file that was read.
        path: PathBuf,
        /// The defect.
        warning: subdiv_mesh::Warning,
    },
}

impl ReadWarning {
    /// How many distinct ignored tag names [`ReadWarning::TagsIgnored`] keeps.
    pub const NAMES_KEPT: usize = 8;

    /// The file the warning is about.
    pub fn path(&self) -> &Path {
        match self {
            ReadWarning::UvsDropped { path, .. }
            | ReadWarning::TagsIgnored { path, .. }
            | ReadWarning::MeshDefect { path, .. } => path,
        }
    }
}

impl fmt::Display for ReadWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadWarning::UvsDropped { path, line, reason } => {
                write!(f, "{}: texture coordinates dropped: {reason}", Location(path, *line))
            }
            ReadWarning::TagsIgnored { path, line, lines, names } => {
                let more = if *lines > names.len() && names.len() == Self::NAMES_KEPT { ", …" } else { "" };
                let plural = if *lines == 1 { "line" } else { "lines" };
                write!(
                    f,
                    "{}: {lines} tag {plural} not applied ({}{more}): hierarchical edits and unknown tags are not \
                     supported (crease, corner, hole and OpenSubdiv's option tags are)",
                    Location(path, Some(*line)),
                    names.join(", ")
                )
            }
            ReadWarning::MeshDefect { path, warning } => write!(f, "{}: {warning}", path.display()),
        }
    }
}

/// `path` or `path:line`, for messages.
struct Location<'a>(&'a Path, Option<usize>);

impl fmt::Display for Location<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.1 {
            Some(line) => write!(f, "{}:{line}", self.0.display()),
            None => write!(f, "{}", self.0.display()),
        }
    }
}

/// A URI for a message: cut to a length enough for any real path, control
/// characters escaped (a JSON string may hold a newline).
pub(crate) fn show_uri(uri: &str) -> String {
    const MAX: usize = 200;
    let cut = match uri.char_indices().nth(MAX) {
        Some((end, _)) => std::borrow::Cow::Owned(format!("{}…", &uri[..end])),
        None => std::borrow::Cow::Borrowed(uri),
    };
    crate::text::escape_controls(cut).into_owned()
}

/// The first few prim paths, for [`IoError::SeveralMeshes`].
fn shown_prims(prims: &[String]) -> String {
    const SHOWN: usize = 4;
    let mut shown = prims.iter().take(SHOWN).map(String::as_str).collect::<Vec<_>>().join(", ");
    if prims.len() > SHOWN {
        shown.push_str(&format!(", … {} more", prims.len() - SHOWN));
    }
    shown
}

/// "an OBJ file", "a PLY file", …: the format family with its article.
fn a_file_of(format: Format) -> &'static str {
    match format {
        Format::Obj => "an OBJ file",
        Format::Off => "an OFF file",
        Format::PlyAscii | Format::PlyBinary => "a PLY file",
        Format::StlAscii | Format::StlBinary => "an STL file",
        Format::Gltf => "a glTF file",
        Format::Glb => "a GLB file",
        Format::Usda | Format::Usdc | Format::Usdz => "a USD file",
    }
}

/// The file being read or written; builds errors that name it.
#[derive(Clone, Copy)]
pub(crate) struct Ctx<'a> {
    pub(crate) path: &'a Path,
}

impl<'a> Ctx<'a> {
    pub(crate) fn new(path: &'a Path) -> Self {
        Self { path }
    }

    pub(crate) fn parse(&self, line: impl Into<Option<usize>>, message: impl Into<String>) -> IoError {
        IoError::Parse { path: self.path.to_path_buf(), line: line.into(), message: message.into() }
    }

    pub(crate) fn truncated(&self, line: impl Into<Option<usize>>, what: impl Into<String>) -> IoError {
        IoError::Truncated { path: self.path.to_path_buf(), line: line.into(), what: what.into() }
    }

    pub(crate) fn unsupported(&self, what: impl Into<String>) -> IoError {
        IoError::Unsupported { path: self.path.to_path_buf(), what: what.into() }
    }

    pub(crate) fn empty(&self) -> IoError {
        IoError::Empty { path: self.path.to_path_buf() }
    }

    pub(crate) fn invalid(&self, message: impl Into<String>) -> IoError {
        IoError::InvalidMesh { path: self.path.to_path_buf(), message: message.into() }
    }

    pub(crate) fn utf16(&self) -> IoError {
        IoError::Utf16 { path: self.path.to_path_buf() }
    }

    pub(crate) fn binary(&self, line: impl Into<Option<usize>>, format: Format) -> IoError {
        IoError::BinaryData { path: self.path.to_path_buf(), line: line.into(), format }
    }

    pub(crate) fn refused_uri(&self, uri: &str, reason: impl Into<String>) -> IoError {
        IoError::RefusedUri { path: self.path.to_path_buf(), uri: show_uri(uri), reason: reason.into() }
    }

    pub(crate) fn io(&self, source: std::io::Error) -> IoError {
        IoError::Io { path: self.path.to_path_buf(), source }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_file_and_line() {
        let ctx = Ctx::new(Path::new("mesh.obj"));
        let e = ctx.parse(12, "face index 'x' is not an integer");
        assert_eq!(e.to_string(), "mesh.obj:12: face index 'x' is not an integer");
        assert_eq!(e.line(), Some(12));
        let e = ctx.truncated(None, "binary data ends inside vertex 3 of 8");
        assert_eq!(e.to_string(), "mesh.obj: file is truncated: binary data ends inside vertex 3 of 8");
        assert_eq!(ctx.binary(None, Format::Obj).to_string(), "mesh.obj: binary data, not an OBJ file");
        assert_eq!(ctx.binary(7, Format::StlAscii).to_string(), "mesh.obj:7: binary data, not an STL file");
        assert_eq!(ctx.binary(7, Format::StlAscii).line(), Some(7));
        assert_eq!(ctx.utf16().to_string(), "mesh.obj: UTF-16 text is not supported; save the file as UTF-8");
    }

    #[test]
    fn every_variant_names_its_file() {
        let ctx = Ctx::new(Path::new("dir/m.gltf"));
        let errors = [
            ctx.parse(1, "p"),
            ctx.truncated(None, "t"),
            ctx.unsupported("u"),
            ctx.empty(),
            ctx.invalid("i"),
            ctx.io(std::io::Error::other("o")),
            ctx.utf16(),
            ctx.binary(None, Format::Gltf),
            ctx.refused_uri("/etc/hostname", "it is an absolute path"),
            IoError::NotAFile { path: ctx.path.to_path_buf(), kind: "a FIFO" },
            IoError::UnknownFormat { path: ctx.path.to_path_buf() },
            IoError::Validation { path: ctx.path.to_path_buf(), source: subdiv_mesh::MeshError::NoFaces },
            IoError::SeveralMeshes { path: ctx.path.to_path_buf(), prims: (0..6).map(|i| format!("/m{i}")).collect() },
        ];
        for e in errors {
            assert_eq!(e.path(), Path::new("dir/m.gltf"));
            assert!(e.to_string().starts_with("dir/m.gltf"), "{e}");
            assert!(!e.to_string().contains('\n'), "{e}");
        }
    }
}
