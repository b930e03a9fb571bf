//! The one error type of the crate, and the small context every reader and
//! writer uses to build it.

use std::fmt;
use std::path::{Path, PathBuf};

/// Everything that can go wrong reading or writing a mesh file.
///
/// Every variant names the file; errors in text formats also carry the
/// 1-based line, so the message reads like a compiler's:
/// `mesh.obj:12: face index 'x' is not an integer`.
///
/// Topological defects (out-of-range or repeated indices, faces with fewer
/// than three corners, NaN coordinates) are *not* errors here: readers pass
/// them through and `subdiv_mesh` reports them when it validates the soup.
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
        "{}: unknown mesh format (expected extension .obj, .off, .ply, .stl, .gltf or .glb)",
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
    /// The mesh handed to a writer cannot be written in the requested format
    /// (an index out of range, a normal count that does not match, …).
    #[error("{}: cannot write mesh: {message}", .path.display())]
    InvalidMesh {
        /// The file that was to be written (`<memory>` for in-memory output).
        path: PathBuf,
        /// What is wrong with the mesh.
        message: String,
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
            | IoError::InvalidMesh { path, .. } => path,
        }
    }

    /// The 1-based line the error is about, when the format is text and the
    /// problem sits on a line.
    pub fn line(&self) -> Option<usize> {
        match self {
            IoError::Parse { line, .. } | IoError::Truncated { line, .. } => *line,
            _ => None,
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
    }
}
