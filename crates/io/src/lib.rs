//! Mesh files for subdiv: the only library crate that touches the file system.
//!
//! Reads OBJ, OFF, PLY, STL, glTF, GLB and USD (`.usda`, `.usdc`, `.usdz`)
//! into an unvalidated [`PolygonSoup`], and writes any of them from a
//! [`MeshView`]. One file per format: `obj.rs`, `off.rs`, `ply.rs`,
//! `stl.rs`, `gltf.rs`, `usd.rs` (also files of several meshes by prim
//! path: [`usd::read_scene`], [`usd::stage_scene`]), and
//! `tag_file.rs` for JSON tag files ([`read_tag_file`], [`parse_tag_json`]),
//! `text_file.rs` for the other small text files the tools read (parameter
//! files, evaluation parameters, query points: [`read_text`]).
//!
//! In one call, for a validated [`Mesh`]: [`load_mesh`] reads and validates
//! a file (a [`MeshError`] becomes [`IoError::Validation`];
//! [`load_mesh_with_warnings`] also gives the warnings), [`write_mesh`]
//! writes a mesh with its texture coordinates and tags, and vertex normals
//! on request ([`WriteOptions`]):
//!
//! ```
//! use subdiv_io::{load_mesh, write_mesh, Format, WriteOptions};
//! use subdiv_mesh::{Mesh, VertexId};
//!
//! let dir = std::env::temp_dir().join(format!("subdiv-io-crate-example-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! // A tetrahedron from plain arrays, written as OBJ.
//! let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
//! let mesh = Mesh::from_arrays(&positions, &[[0u32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])?;
//! let input = dir.join("tetrahedron.obj");
//! write_mesh(&input, &mesh, &WriteOptions::default())?;
//!
//! // Read → modify → write: lift the apex, save as binary PLY (from the
//! // extension) with vertex normals.
//! let mut mesh = load_mesh(&input)?;
//! mesh.positions_mut()[3].z = 2.0;
//! let output = dir.join("lifted.ply");
//! write_mesh(&output, &mesh, &WriteOptions::default().with_normals(true))?;
//!
//! let back = load_mesh(&output)?;
//! assert_eq!(back.position(VertexId(3)).z, 2.0);
//! assert_eq!(back.topology().faces(), mesh.topology().faces());
//! // glTF stores f32 and triangles: the format overrides the extension.
//! write_mesh(dir.join("lifted.bin"), &mesh, &WriteOptions::default().with_format(Format::Glb))?;
//! std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! At the level of soups and views:
//!
//! - Texture coordinates ([`PolygonSoup::uvs`], one [`FaceVarying`]
//!   channel) are read from OBJ `vt`, PLY, glTF `TEXCOORD_0` and OFF `ST`;
//!   crease and corner tags ([`PolygonSoup::tags`], a [`TagList`]) from
//!   OpenSubdiv's OBJ `t` lines or a tag file. Writers write them where the
//!   format has a place for them ([`Format::carries_uvs`],
//!   [`Format::carries_tags`]) and leave them out elsewhere.
//!   [`read_mesh_with_warnings`] also returns what a reader dropped instead of
//!   failing ([`ReadWarning`]).
//! - [`read_mesh`] picks the reader by extension ([`Format::from_path`]) and
//!   tells ASCII from binary (PLY, STL) and JSON from GLB by content.
//!   [`read_mesh_with_progress`] does the same and reports the bytes read.
//!   Only regular files are read: a directory, FIFO, device or socket is
//!   [`IoError::NotAFile`], refused before it is opened.
//! - Hostile input costs time and memory in proportion to its size: no
//!   count in a header drives an allocation or a loop beyond what the bytes
//!   present can hold, and glTF buffer URIs are only followed to regular
//!   files inside the glTF file's directory ([`IoError::RefusedUri`]).
//! - Text formats skip a UTF-8 byte-order mark and report UTF-16 text
//!   ([`IoError::Utf16`]) and binary data ([`IoError::BinaryData`]) as such,
//!   not as an empty or malformed file.
//! - [`write_mesh_view`] / [`write_mesh_as`] (and [`write_mesh`]) write
//!   atomically: a temporary file in the same directory is renamed over the
//!   target, so a failed write never leaves a partial file; the encoding is
//!   streamed to it through a 1 MiB buffer (glTF, whose header needs the
//!   buffer length, is assembled first).
//!   [`stage_mesh`] and [`stage_bytes`] stop before the rename, so that a
//!   command's outputs can be committed together ([`commit_all`]: all of them
//!   or none); [`remove_staged_files`] is for signal handlers.
//!   [`write_mesh_to_vec`] encodes in memory.
//! - [`IoError`] names the file, and the 1-based line for text formats:
//!   `mesh.obj:12: face index 'x' is not an integer`.
//!
//! What the readers do **not** do: validate topology ([`load_mesh`] leaves
//! that to `subdiv_mesh`, [`Mesh::from_soup`]). Out-of-range and repeated
//! indices, faces with fewer than three corners and NaN/infinite coordinates
//! are read as they are, so that `subdiv_mesh`'s validator can report them;
//! so are texture coordinate indices past the `vt` pool, crease pairs that
//! are not edges and negative or NaN sharpness.
//! The one exception is what a `u32` cannot hold (an OBJ index 0, a relative
//! index before the first vertex, a negative index, an index of 2³² or
//! more: "face index 99999999999999999999 out of range"), which is a parse
//! error.
//!
//! Precision: OBJ, OFF, PLY (doubles) and ASCII STL write the shortest
//! decimal (or the bits) that reads back to the same `f64`; binary STL and
//! glTF store `f32`. STL and glTF triangulate polygons as fans on write.
//!
//! ```
//! use subdiv_io::{read_mesh_from_bytes, write_mesh_to_vec, Format, MeshView};
//! use subdiv_mesh::{DVec3, FaceList};
//!
//! // A unit square and a triangle on top of it, written as OBJ and read back.
//! let positions = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y, DVec3::new(0.5, 2.0, 0.1)];
//! let faces = FaceList::from_faces([vec![0u32, 1, 2, 3], vec![3, 2, 4]]);
//! let bytes = write_mesh_to_vec(MeshView::new(&positions, &faces), Format::Obj)?;
//! let soup = read_mesh_from_bytes(&bytes, Format::Obj, "square.obj")?;
//! assert_eq!(soup.positions, positions);
//! assert_eq!(soup.faces, faces);
//!
//! // STL keeps triangles only: the square becomes two.
//! let bytes = write_mesh_to_vec(MeshView::new(&positions, &faces), Format::StlBinary)?;
//! let soup = read_mesh_from_bytes(&bytes, Format::StlBinary, "square.stl")?;
//! assert_eq!(soup.faces.len(), 3);
//!
//! // Texture coordinates and OpenSubdiv's tag lines survive OBJ.
//! let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nt crease 2/1/0 0 1 2.5\n";
//! let soup = read_mesh_from_bytes(obj.as_bytes(), Format::Obj, "tagged.obj")?;
//! assert_eq!(soup.uvs.as_ref().unwrap().indices, [0, 1, 2]);
//! assert_eq!(soup.tags.creases[0].sharpness, 2.5);
//! let bytes = write_mesh_to_vec(MeshView::from(&soup), Format::Obj)?;
//! assert_eq!(read_mesh_from_bytes(&bytes, Format::Obj, "back.obj")?, soup);
//!
//! // Errors name the file and the line.
//! let err = read_mesh_from_bytes(b"v 0 0 0\nf 1 x 1\n", Format::Obj, "bad.obj").unwrap_err();
//! assert_eq!(err.to_string(), "bad.obj:2: face index 'x' is not an integer");
//! # Ok::<(), subdiv_io::IoError>(())
//! ```
#![warn(missing_docs)]

mod atomic;
mod base64;
mod error;
mod format;
pub mod fs;
mod gltf;
mod obj;
mod off;
mod ply;
mod stl;
mod tag_file;
mod text;
mod text_file;
pub mod usd;
mod validated;

use glam::DVec3;
use std::io::{Read, Seek};
use std::path::Path;

pub use atomic::{commit_all, commits_completed, remove_staged_files, stage_bytes, stop_commits, StagedFile};
pub use error::{IoError, ReadWarning};
pub use format::Format;
pub use subdiv_mesh::{EdgeTag, FaceGroups, FaceList, FaceVarying, Mesh, MeshError, PolygonSoup, TagList, VertexTag};
pub use tag_file::{parse_tag_json, read_tag_file, TAG_FILE_LIMIT};
pub use text_file::{read_text, TEXT_FILE_LIMIT};
pub use validated::{
    faces_without_holes, load_mesh, load_mesh_with_warnings, view_for_format, write_mesh, LeftOut, WriteOptions,
};

use error::Ctx;

/// Reads a mesh file; the format comes from the extension, ASCII or binary
/// from the content.
///
/// # Errors
/// [`IoError::UnknownFormat`] for an unknown extension, [`IoError::NotAFile`]
/// for a directory, FIFO, device or socket, [`IoError::Io`] when the file
/// cannot be read, and the errors of [`read_mesh_from_bytes`]. External glTF
/// buffers are looked up relative to the file's directory, and only there
/// ([`IoError::RefusedUri`] otherwise).
pub fn read_mesh(path: &Path) -> Result<PolygonSoup, IoError> {
    read_mesh_with_progress(path, &mut |_, _| {})
}

/// [`read_mesh`], calling `progress(bytes_read, total_bytes)` as the file is
/// read: once with 0 before the first byte, then after every chunk of 4 MiB
/// (and the last, shorter one). `total_bytes` is the file's size when it was
/// opened (or the bytes read, should the file have grown since). Parsing,
/// which follows the reading, reports nothing; a binary PLY is decoded as
/// its chunks arrive, and one that path does not take (see the PLY reader)
/// is read again from the start, its reports again from 0.
///
/// # Errors
/// Those of [`read_mesh`].
pub fn read_mesh_with_progress(path: &Path, progress: &mut dyn FnMut(u64, u64)) -> Result<PolygonSoup, IoError> {
    read_mesh_with_warnings(path, progress).map(|(soup, _)| soup)
}

/// [`read_mesh_with_progress`], also returning what the reader dropped or
/// did not apply instead of failing ([`ReadWarning`]: texture coordinates
/// on only some faces, OBJ tag lines other than creases and corners), for
/// the caller to print. [`read_mesh`] and [`read_mesh_with_progress`] read
/// the same soup and leave the warnings out.
///
/// # Errors
/// Those of [`read_mesh`].
pub fn read_mesh_with_warnings(
    path: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
    let format = Format::from_path(path)?;
    if matches!(format, Format::PlyAscii | Format::PlyBinary) {
        // Binary PLY is decoded as it is read (no copy of the whole file);
        // what that path does not take is read whole, from the start.
        let ctx = Ctx::new(path);
        let (mut file, size) = open_regular_file(path)?;
        if let Some(soup) = ply::read_streamed(&mut file, size, ctx, progress).map_err(|e| ctx.io(e))? {
            return checked(soup, Vec::new(), ctx);
        }
        file.rewind().map_err(|e| ctx.io(e))?;
        let bytes = read_open_file(file, size, None, READ_CHUNK, ctx, progress)?;
        return read_bytes(&bytes, format, path, None);
    }
    let bytes = read_file(path, None, progress)?;
    read_bytes(&bytes, format, path, Some(path.parent().unwrap_or(Path::new("."))))
}

/// How much [`read_file`] reads between two progress reports.
const READ_CHUNK: u64 = 4 << 20;

/// Reads a regular file, at most `limit` bytes of it, in chunks (see
/// [`read_mesh_with_progress`]).
///
/// The path is checked before it is opened (opening a FIFO blocks until a
/// writer comes, a device may never end), and the opened file again (the
/// path may have changed in between). Memory is reserved for the file's size
/// with a fallible allocation, so a file that does not fit is an error, not
/// an abort.
pub(crate) fn read_file(
    path: &Path,
    limit: Option<u64>,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Vec<u8>, IoError> {
    read_file_in_chunks(path, limit, READ_CHUNK, progress)
}

fn read_file_in_chunks(
    path: &Path,
    limit: Option<u64>,
    chunk: u64,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Vec<u8>, IoError> {
    let (file, size) = open_regular_file(path)?;
    read_open_file(file, size, limit, chunk, Ctx::new(path), progress)
}

/// Opens a regular file (see [`read_file`]); returns it with its size.
fn open_regular_file(path: &Path) -> Result<(std::fs::File, u64), IoError> {
    let ctx = Ctx::new(path);
    let regular = |metadata: std::fs::Metadata| {
        if metadata.is_file() {
            Ok(metadata)
        } else {
            Err(IoError::NotAFile { path: path.to_path_buf(), kind: file_kind(metadata.file_type()) })
        }
    };
    regular(std::fs::metadata(path).map_err(|e| ctx.io(e))?)?;
    let file = std::fs::File::open(path).map_err(|e| ctx.io(e))?;
    let size = regular(file.metadata().map_err(|e| ctx.io(e))?)?.len();
    Ok((file, size))
}

/// Reads the opened file of `size` bytes (at most `limit` of them) into
/// memory, `chunk` bytes between two progress reports.
fn read_open_file(
    file: std::fs::File,
    size: u64,
    limit: Option<u64>,
    chunk: u64,
    ctx: Ctx<'_>,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Vec<u8>, IoError> {
    let limit = limit.unwrap_or(u64::MAX);
    let total = size.min(limit);
    let mut bytes = Vec::new();
    usize::try_from(total).ok().and_then(|n| bytes.try_reserve_exact(n).ok()).ok_or_else(|| {
        let message = format!("the file's {total} bytes do not fit in memory");
        ctx.io(std::io::Error::new(std::io::ErrorKind::OutOfMemory, message))
    })?;
    progress(0, total);
    let mut reader = file.take(limit);
    while (&mut reader).take(chunk).read_to_end(&mut bytes).map_err(|e| ctx.io(e))? > 0 {
        let read = bytes.len() as u64;
        progress(read, total.max(read));
    }
    Ok(bytes)
}

/// What a file type that is not a regular file is, for [`IoError::NotAFile`].
pub(crate) fn file_kind(file_type: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO";
        } else if file_type.is_char_device() {
            return "a character device";
        } else if file_type.is_block_device() {
            return "a block device";
        } else if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else {
        "a special file"
    }
}

/// Reads a mesh from memory. `format_hint` picks the reader family (ASCII or
/// binary is still detected from the content); `name` stands for the file in
/// error messages. A glTF file that refers to external buffer files cannot be
/// read this way ([`IoError::Unsupported`]).
///
/// # Errors
/// [`IoError::Empty`] when there are no vertices and no faces (nothing but
/// blanks and comments), [`IoError::Utf16`] and [`IoError::BinaryData`] when
/// a text format gets UTF-16 or binary data, [`IoError::Parse`] (naming the
/// offending token: "face index 99999999999999999999 out of range"),
/// [`IoError::Truncated`], [`IoError::Unsupported`] or
/// [`IoError::RefusedUri`] when the bytes do not follow the format or use
/// what is not read.
pub fn read_mesh_from_bytes(bytes: &[u8], format_hint: Format, name: &str) -> Result<PolygonSoup, IoError> {
    read_mesh_from_bytes_with_warnings(bytes, format_hint, name).map(|(soup, _)| soup)
}

/// [`read_mesh_from_bytes`], also returning the reader's [`ReadWarning`]s
/// (see [`read_mesh_with_warnings`]).
///
/// # Errors
/// Those of [`read_mesh_from_bytes`].
pub fn read_mesh_from_bytes_with_warnings(
    bytes: &[u8],
    format_hint: Format,
    name: &str,
) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
    read_bytes(bytes, format_hint, Path::new(name), None)
}

fn read_bytes(
    bytes: &[u8],
    format: Format,
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
    let ctx = Ctx::new(path);
    let (soup, warnings) = match format {
        Format::Obj => obj::read(bytes, ctx)?,
        Format::Off => (off::read(bytes, ctx)?, Vec::new()),
        Format::PlyAscii | Format::PlyBinary => (ply::read(bytes, ctx)?, Vec::new()),
        Format::StlAscii | Format::StlBinary => (stl::read(bytes, ctx)?, Vec::new()),
        Format::Gltf | Format::Glb => gltf::read(bytes, ctx, base_dir)?,
        Format::Usda | Format::Usdc | Format::Usdz => usd::read(bytes, ctx)?,
    };
    checked(soup, warnings, ctx)
}

/// What every reader's soup must be besides: not empty, and within
/// `FaceList`'s `u32` offsets.
fn checked(
    soup: PolygonSoup,
    warnings: Vec<ReadWarning>,
    ctx: Ctx<'_>,
) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
    if soup.positions.is_empty() && soup.faces.is_empty() {
        return Err(ctx.empty());
    }
    // `FaceList` offsets are u32: past 2³² corners (a 4 GiB PLY of u8
    // indices can hold that many) they would wrap and misplace faces.
    if u32::try_from(soup.faces.corner_count()).is_err() {
        return Err(ctx.unsupported(format!("{} face corners (at most 2^32 - 1 are read)", soup.faces.corner_count())));
    }
    Ok((soup, warnings))
}

/// The OBJ reader's two paths apart, for the crate's tests and benchmarks;
/// not part of the API (no stability promised).
#[doc(hidden)]
pub mod internals {
    use super::{Ctx, IoError, Path, PolygonSoup, ReadWarning};

    /// The serial OBJ reader alone, as [`crate::read_mesh_from_bytes_with_warnings`]
    /// runs it for small files (without the checks every reader's soup gets).
    ///
    /// # Errors
    /// Those of the OBJ reader.
    pub fn read_obj_serial(bytes: &[u8], name: &str) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
        crate::obj::read_serial(bytes, Ctx::new(Path::new(name)))
    }

    /// The parallel OBJ path alone, in chunks of about `chunk_bytes` (at
    /// least 1), whatever the file's size: `None` where it declines the
    /// file (and the serial reader would read it).
    pub fn read_obj_chunked(bytes: &[u8], name: &str, chunk_bytes: usize) -> Option<(PolygonSoup, Vec<ReadWarning>)> {
        crate::obj::read_chunked(bytes, chunk_bytes, Ctx::new(Path::new(name)))
    }

    /// The size under which the OBJ reader does not try the parallel path.
    pub const OBJ_CHUNKED_MIN_BYTES: usize = crate::obj::CHUNKED_MIN_BYTES;
}

/// A mesh to write: borrowed positions, faces and optional per-vertex
/// normals, texture coordinates and sharpness tags.
///
/// Faces index `positions`; `normals`, when given, has one entry per
/// position; `uvs`, when given, one index per face corner. A writer writes
/// what its format can hold ([`Format::carries_uvs`],
/// [`Format::carries_tags`]) and leaves the rest out.
#[derive(Clone, Copy, Debug)]
pub struct MeshView<'a> {
    /// Vertex positions.
    pub positions: &'a [DVec3],
    /// Faces as 0-based indices into `positions`.
    pub faces: &'a FaceList,
    /// Optional per-vertex normals (written by OBJ, OFF, PLY and glTF; STL
    /// computes facet normals instead).
    pub normals: Option<&'a [DVec3]>,
    /// Optional texture coordinates, one channel (written by OBJ, PLY and
    /// glTF: [`Format::carries_uvs`]).
    pub uvs: Option<&'a FaceVarying>,
    /// Optional crease and corner tags by vertex index (written by OBJ only:
    /// [`Format::carries_tags`]).
    pub tags: Option<&'a TagList>,
}

impl<'a> MeshView<'a> {
    /// A view of positions and faces, without normals, texture coordinates or tags.
    pub fn new(positions: &'a [DVec3], faces: &'a FaceList) -> Self {
        Self { positions, faces, normals: None, uvs: None, tags: None }
    }

    /// The same view with per-vertex normals.
    pub fn with_normals(self, normals: &'a [DVec3]) -> Self {
        Self { normals: Some(normals), ..self }
    }

    /// The same view with texture coordinates (one value index per face corner).
    pub fn with_uvs(self, uvs: &'a FaceVarying) -> Self {
        Self { uvs: Some(uvs), ..self }
    }

    /// The same view with crease and corner tags.
    pub fn with_tags(self, tags: &'a TagList) -> Self {
        Self { tags: Some(tags), ..self }
    }
}

impl<'a> From<&'a PolygonSoup> for MeshView<'a> {
    /// Positions, faces, the soup's texture coordinates (if any) and its tags
    /// (if any).
    fn from(soup: &'a PolygonSoup) -> Self {
        let view = MeshView::new(&soup.positions, &soup.faces);
        let view = match &soup.uvs {
            Some(uvs) => view.with_uvs(uvs),
            None => view,
        };
        if soup.tags.is_empty() {
            view
        } else {
            view.with_tags(&soup.tags)
        }
    }
}

/// The fan triangulation of a face from its first corner:
/// `(v0, v1, v2), (v0, v2, v3), …`; nothing for fewer than three corners.
pub(crate) fn fan(face: &[u32]) -> impl Iterator<Item = [u32; 3]> + '_ {
    (2..face.len()).map(move |i| [face[0], face[i - 1], face[i]])
}

/// Writes a mesh view in the format of the path's extension (binary for
/// `.ply` and `.stl`), atomically. [`write_mesh`] writes a validated
/// [`Mesh`].
///
/// # Errors
/// [`IoError::UnknownFormat`], [`IoError::InvalidMesh`] (see
/// [`write_mesh_to_vec`]) or [`IoError::Io`]; on any error the target file is
/// left as it was.
pub fn write_mesh_view(path: &Path, mesh: MeshView<'_>) -> Result<(), IoError> {
    write_mesh_as(path, mesh, Format::from_path(path)?)
}

/// Writes a mesh in the given format, atomically: the mesh is checked, its
/// encoding streamed to a temporary file in the target's directory, which is
/// then renamed over the target.
///
/// # Errors
/// [`IoError::InvalidMesh`] (see [`write_mesh_to_vec`]) or [`IoError::Io`];
/// on any error the target file is left as it was.
pub fn write_mesh_as(path: &Path, mesh: MeshView<'_>, format: Format) -> Result<(), IoError> {
    stage_mesh(path, mesh, format, &mut |_| {})?.commit()
}

/// Encodes a mesh into a temporary file beside `path` without replacing
/// `path` yet: commit the returned [`StagedFile`] (alone, or with a command's
/// other outputs through [`commit_all`]) to put it in place. `progress`
/// hears the bytes written so far, every few MiB and at the end.
///
/// # Errors
/// [`IoError::InvalidMesh`] (see [`write_mesh_to_vec`]) or [`IoError::Io`];
/// no temporary is left behind.
pub fn stage_mesh(
    path: &Path,
    mesh: MeshView<'_>,
    format: Format,
    progress: &mut dyn FnMut(u64),
) -> Result<StagedFile, IoError> {
    let ctx = Ctx::new(path);
    check(&mesh, format, ctx)?;
    atomic::stage_with(path, progress, |out| encode(&mesh, format, ctx, out))
}

/// Encodes a mesh in memory.
///
/// # Errors
/// [`IoError::InvalidMesh`] (with path `<memory>`) when a face index is out
/// of range, the normals do not match the positions in number, a face has
/// fewer than three corners for a triangulating format (STL, glTF), or glTF
/// gets coordinates that are not finite in `f32`.
pub fn write_mesh_to_vec(mesh: MeshView<'_>, format: Format) -> Result<Vec<u8>, IoError> {
    let ctx = Ctx::new(Path::new("<memory>"));
    check(&mesh, format, ctx)?;
    // Binary PLY's size is known up to its header: one allocation, no
    // copies as the vector grows.
    let records =
        |per_vertex: usize| per_vertex * mesh.positions.len() + mesh.faces.len() + 4 * mesh.faces.corner_count();
    let mut out = Vec::with_capacity(if format == Format::PlyBinary { 1024 + records(24) } else { 0 });
    encode(&mesh, format, ctx, &mut out)?;
    Ok(out)
}

/// Streams a mesh that passed [`check`] to `out` (glTF is assembled in
/// memory first: its JSON header gives the binary buffer's length).
fn encode(mesh: &MeshView<'_>, format: Format, ctx: Ctx<'_>, out: &mut impl std::io::Write) -> Result<(), IoError> {
    match format {
        Format::Obj => obj::write(mesh, out),
        Format::Off => off::write(mesh, out),
        Format::PlyAscii => ply::write(mesh, false, out),
        Format::PlyBinary => ply::write(mesh, true, out),
        Format::StlAscii => stl::write(mesh, false, out),
        Format::StlBinary => stl::write(mesh, true, out),
        Format::Gltf => out.write_all(&gltf::write(mesh, false, ctx)?),
        Format::Glb => out.write_all(&gltf::write(mesh, true, ctx)?),
        Format::Usda | Format::Usdc | Format::Usdz => out.write_all(&usd::write(mesh, format, ctx)?),
    }
    .map_err(|e| ctx.io(e))
}

/// What every writer relies on: indices in range, one normal per position,
/// at least three corners per face where faces become triangles, and — for
/// the formats that write them — one texture coordinate index in range per
/// corner, tags on existing vertices, and texture coordinates that fit the
/// `f32` of glTF.
pub(crate) fn check(mesh: &MeshView<'_>, format: Format, ctx: Ctx<'_>) -> Result<(), IoError> {
    let n = mesh.positions.len();
    if let Some(normals) = mesh.normals {
        if normals.len() != n {
            return Err(ctx.invalid(format!("{} normals for {n} vertices", normals.len())));
        }
    }
    // The common case in two vectorised scans; the first offending face is
    // searched for only when one fails.
    let in_range = mesh.faces.indices().iter().all(|&v| (v as usize) < n);
    let big_enough = !format.triangulates() || mesh.faces.offsets().windows(2).all(|w| w[1] - w[0] >= 3);
    if !(in_range && big_enough) {
        for (f, face) in mesh.faces.iter().enumerate() {
            if let Some(&v) = face.iter().find(|&&v| v as usize >= n) {
                return Err(ctx.invalid(format!("face {f} refers to vertex {v}, but there are {n} vertices")));
            }
            if format.triangulates() && face.len() < 3 {
                return Err(ctx.invalid(format!("face {f} has {} corners; {format} needs at least 3", face.len())));
            }
        }
    }
    if !format.keeps_f64() {
        // f32 formats: a finite f64 beyond f32::MAX would be written as inf.
        if let Some((v, p)) = mesh.positions.iter().enumerate().find(|(_, p)| !p.as_vec3().is_finite()) {
            return Err(ctx.invalid(format!("vertex {v} at {p} does not fit the 32-bit floats of {format}")));
        }
    }
    if let Some(uvs) = mesh.uvs.filter(|_| format.carries_uvs()) {
        let corners = mesh.faces.corner_count();
        if uvs.indices.len() != corners {
            return Err(
                ctx.invalid(format!("{} texture coordinate indices for {corners} face corners", uvs.indices.len()))
            );
        }
        let values = uvs.values.len();
        if let Some((corner, &i)) = uvs.indices.iter().enumerate().find(|&(_, &i)| i as usize >= values) {
            return Err(
                ctx.invalid(format!("face corner {corner} refers to texture coordinate {i}, but there are {values}"))
            );
        }
        if !format.keeps_f64() {
            if let Some((i, uv)) = uvs.values.iter().enumerate().find(|(_, uv)| !uv.as_vec2().is_finite()) {
                return Err(ctx.invalid(format!(
                    "texture coordinate {i} ({:?}, {:?}) does not fit the 32-bit floats of {format}",
                    uv.x, uv.y
                )));
            }
        }
    }
    if let Some(tags) = mesh.tags.filter(|_| format.carries_tags()) {
        let out_of_range = |v: u32| v as usize >= n;
        if let Some(t) = tags.creases.iter().find(|t| out_of_range(t.a) || out_of_range(t.b)) {
            return Err(ctx.invalid(format!("crease tag {}-{} refers to a vertex beyond the {n} vertices", t.a, t.b)));
        }
        if let Some(t) = tags.corners.iter().find(|t| out_of_range(t.vertex)) {
            return Err(ctx.invalid(format!("corner tag {} refers to a vertex beyond the {n} vertices", t.vertex)));
        }
        if format.is_usd() {
            if let Some(&f) = tags.holes.iter().find(|&&f| f as usize >= mesh.faces.len()) {
                return Err(ctx.invalid(format!("hole tag {f} refers to a face beyond the {} faces", mesh.faces.len())));
            }
        }
    }
    // USD's indices are `int`s.
    if format.is_usd() {
        let most = i32::MAX as usize;
        let uv_values = mesh.uvs.map_or(0, |uvs| uvs.values.len());
        if n > most || mesh.faces.corner_count() > most || uv_values > most {
            return Err(ctx.invalid(format!("more than {most} points, face corners or texture coordinates for USD")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fan_triangulation() {
        let t: Vec<_> = fan(&[4, 5, 6, 7, 8]).collect();
        assert_eq!(t, vec![[4, 5, 6], [4, 6, 7], [4, 7, 8]]);
        assert_eq!(fan(&[1, 2]).count(), 0);
        assert_eq!(fan(&[]).count(), 0);
    }

    #[test]
    fn reading_in_chunks_reports_progress_up_to_the_size_and_stops_at_the_limit() {
        let tmp = tempfile::Builder::new().prefix("subdiv-io-chunks-").tempdir().unwrap();
        let dir = tmp.path();
        let path = dir.join("ten.bin");
        std::fs::write(&path, b"0123456789").unwrap();
        let mut calls = Vec::new();
        let bytes = read_file_in_chunks(&path, None, 4, &mut |read, total| calls.push((read, total))).unwrap();
        assert_eq!(bytes, b"0123456789");
        assert_eq!(calls, [(0, 10), (4, 10), (8, 10), (10, 10)]);
        calls.clear();
        let bytes = read_file_in_chunks(&path, Some(6), 4, &mut |read, total| calls.push((read, total))).unwrap();
        assert_eq!(bytes, b"012345");
        assert_eq!(calls, [(0, 6), (4, 6), (6, 6)]);
        let e = read_file_in_chunks(dir, None, 4, &mut |_, _| panic!("a directory is never read")).unwrap_err();
        assert!(matches!(e, IoError::NotAFile { kind: "a directory", .. }), "{e}");
    }

    #[test]
    fn writers_reject_out_of_range_indices_and_mismatched_normals() {
        let positions = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let faces = FaceList::from_faces([[0u32, 1, 3]]);
        let e = write_mesh_to_vec(MeshView::new(&positions, &faces), Format::Obj).unwrap_err();
        assert!(matches!(e, IoError::InvalidMesh { .. }), "{e}");
        let faces = FaceList::from_faces([[0u32, 1, 2]]);
        let view = MeshView::new(&positions, &faces).with_normals(&positions[..2]);
        assert!(write_mesh_to_vec(view, Format::Off).is_err());
        let two = FaceList::from_faces([[0u32, 1]]);
        assert!(write_mesh_to_vec(MeshView::new(&positions, &two), Format::Glb).is_err());
        assert!(write_mesh_to_vec(MeshView::new(&positions, &two), Format::Obj).is_ok());
    }
}
