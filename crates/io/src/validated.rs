//! A validated [`Mesh`] in one call: [`load_mesh`] reads and validates a
//! file, [`write_mesh`] writes a mesh with its texture coordinates, tags
//! and, on request, vertex normals ([`WriteOptions`]).

use std::path::Path;

use subdiv_mesh::{DVec3, FaceId, FaceList, FaceVarying, Mesh, TagList};

use crate::{read_mesh_with_warnings, write_mesh_as, Format, IoError, MeshView, ReadWarning};
use std::fmt;

/// What [`write_mesh`] writes, and in which format. Defaults: the format of
/// the path's extension ([`Format::from_path`]: binary for `.ply` and
/// `.stl`), no vertex normals, the mesh's tags and texture coordinates where
/// the format has a place for them ([`Format::carries_tags`],
/// [`Format::carries_uvs`]).
///
/// Built from [`WriteOptions::default`] with the `with_*` setters, so that
/// options added later keep existing code compiling:
///
/// ```
/// use subdiv_io::{Format, WriteOptions};
/// let options = WriteOptions::default().with_format(Format::PlyAscii).with_normals(true);
/// assert_eq!(options.format, Some(Format::PlyAscii));
/// assert!(options.normals && options.tags && options.uvs);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct WriteOptions {
    /// The format to write, whatever the extension; `None`: from the extension.
    pub format: Option<Format>,
    /// Write angle-weighted unit vertex normals ([`Mesh::vertex_normals`]),
    /// in the formats that store them (OBJ, OFF, PLY, glTF; STL writes its
    /// facet normals anyway).
    pub normals: bool,
    /// Write the crease and corner tags (OBJ's `t` lines; no other format
    /// has a place for them).
    pub tags: bool,
    /// Write the texture coordinates (OBJ, PLY, glTF). glTF stores them per
    /// vertex and splits the vertices at seams ([`Format::splits_uv_seams`]):
    /// the file's mesh is cut open along them, and where two UV islands
    /// touch at a vertex only, it is no longer manifold ([`load_mesh`]
    /// refuses it). Without them, glTF keeps the connectivity.
    pub uvs: bool,
}

impl Default for WriteOptions {
    fn default() -> Self {
        Self { format: None, normals: false, tags: true, uvs: true }
    }
}

impl WriteOptions {
    /// With this format, whatever the path's extension (e.g.
    /// [`Format::PlyAscii`] for an ASCII `.ply`).
    pub fn with_format(self, format: Format) -> Self {
        Self { format: Some(format), ..self }
    }

    /// With or without vertex normals.
    pub fn with_normals(self, normals: bool) -> Self {
        Self { normals, ..self }
    }

    /// With or without the crease and corner tags.
    pub fn with_tags(self, tags: bool) -> Self {
        Self { tags, ..self }
    }

    /// With or without the texture coordinates.
    pub fn with_uvs(self, uvs: bool) -> Self {
        Self { uvs, ..self }
    }
}

/// Writes a validated mesh, atomically (as [`write_mesh_as`]: a failed write
/// leaves the target as it was), in the format of `options` or else of the
/// path's extension, with what `options` asks for.
///
/// ```
/// use subdiv_io::{load_mesh, write_mesh, Format, WriteOptions};
/// use subdiv_mesh::Mesh;
///
/// let dir = std::env::temp_dir().join(format!("subdiv-io-write-mesh-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let square = Mesh::from_arrays(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]], &[[0u32, 1, 2, 3]])?;
///
/// let path = dir.join("square.obj");
/// write_mesh(&path, &square, &WriteOptions::default().with_normals(true))?;
/// assert!(std::fs::read_to_string(&path)?.contains("\nvn 0.0 0.0 1.0\n"));
/// assert_eq!(load_mesh(&path)?.positions(), square.positions());
///
/// // The format overrides the extension: an ASCII PLY.
/// let path = dir.join("square.ply");
/// write_mesh(&path, &square, &WriteOptions::default().with_format(Format::PlyAscii))?;
/// assert!(std::fs::read(&path)?.starts_with(b"ply\nformat ascii 1.0"));
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`IoError::UnknownFormat`] for an extension of no format when `options`
/// names none; [`IoError::InvalidMesh`] for a coordinate that is not finite
/// (changed through [`Mesh::positions_mut`] since the mesh was validated),
/// and for coordinates or texture coordinates beyond the `f32` range of
/// binary STL and glTF; [`IoError::Io`] when the file cannot be written.
/// On any error the target file is left as it was.
pub fn write_mesh(path: impl AsRef<Path>, mesh: &Mesh, options: &WriteOptions) -> Result<(), IoError> {
    let path = path.as_ref();
    let format = match options.format {
        Some(format) => format,
        None => Format::from_path(path)?,
    };
    // A mesh is finite when validated, but its positions can be changed since.
    if let Some((v, p)) = mesh.positions().iter().enumerate().find(|(_, p)| !p.is_finite()) {
        let message = format!("vertex {v} at {p} is not finite (NaN or infinite)");
        return Err(IoError::InvalidMesh { path: path.to_path_buf(), message });
    }
    // A non-manifold mesh's cover is written welded: the input's vertices, not their copies.
    let normals = options.normals.then(|| match mesh.welds() {
        Some(welds) => welds.weld(&mesh.vertex_normals()),
        None => mesh.vertex_normals(),
    });
    let (positions, faces, tags) = mesh.welded();
    let tags = (options.tags && format.carries_tags() && !tags.is_empty()).then_some(tags);
    let view = MeshView {
        positions: &positions,
        faces: &faces,
        normals: normals.as_deref(),
        uvs: mesh.uvs().filter(|_| options.uvs),
        tags: tags.as_ref(),
    };
    write_mesh_as(path, view, format)
}

/// What a format has no place for, left out of the view [`view_for_format`]
/// makes; its `Display` is the warning to give (prefixed with the file).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum LeftOut {
    /// The crease and corner tags (only OBJ keeps them).
    Tags {
        /// The format written.
        format: Format,
        /// Crease tags not written.
        creases: usize,
        /// Corner tags not written.
        corners: usize,
        /// Hole tags not written.
        holes: usize,
    },
    /// The texture coordinates (OBJ, PLY and glTF keep them).
    Uvs {
        /// The format written.
        format: Format,
    },
}

impl fmt::Display for LeftOut {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LeftOut::Tags { format, creases, corners, holes } => {
                write!(f, "{format} has no tags: {creases} crease and {corners} corner tags")?;
                if *holes > 0 {
                    write!(f, ", {holes} hole tags")?;
                }
                write!(f, " not written (OBJ keeps them)")
            }
            LeftOut::Uvs { format } => {
                write!(f, "{format} has no texture coordinates: not written (OBJ, PLY and glTF keep them)")
            }
        }
    }
}

/// The view of `mesh` that `format` can hold: `positions` (the mesh's, or
/// a rounded copy) on its faces, with `tags` (the mesh's tags as a list,
/// owned by the caller) and its texture coordinates where the format has
/// a place for them ([`Format::carries_tags`], [`Format::carries_uvs`]),
/// and what was left out (a warning each). Add normals with
/// [`MeshView::with_normals`].
pub fn view_for_format<'a>(
    mesh: &'a Mesh,
    positions: &'a [DVec3],
    tags: &'a TagList,
    format: Format,
) -> (MeshView<'a>, Vec<LeftOut>) {
    let mut view = MeshView::new(positions, mesh.topology().faces());
    let mut left_out = Vec::new();
    if !tags.is_empty() {
        if format.carries_tags() {
            view = view.with_tags(tags);
        } else {
            let (creases, corners, holes) = (tags.creases.len(), tags.corners.len(), tags.holes.len());
            if creases + corners + holes > 0 {
                left_out.push(LeftOut::Tags { format, creases, corners, holes });
            }
        }
    }
    if let Some(uvs) = mesh.uvs() {
        if format.carries_uvs() {
            view = view.with_uvs(uvs);
        } else {
            left_out.push(LeftOut::Uvs { format });
        }
    }
    (view, left_out)
}

/// The faces of `mesh` that are not holes, with their texture coordinates:
/// what a refined surface writes (OpenSubdiv draws no hole face; the
/// vertices stay, numbered as on the level). `None` when no face is a hole.
pub fn faces_without_holes(mesh: &Mesh) -> Option<(FaceList, Option<FaceVarying>)> {
    let tags = mesh.tags();
    if tags.hole_count() == 0 {
        return None;
    }
    let faces = mesh.topology().faces();
    let kept = (0..faces.len()).filter(|&f| !tags.is_hole(FaceId(f as u32)));
    let kept_faces = FaceList::from_faces(kept.clone().map(|f| faces.face(f)));
    let uvs = mesh.uvs().map(|uvs| {
        let offsets = faces.offsets();
        let indices =
            kept.flat_map(|f| uvs.indices[offsets[f] as usize..offsets[f + 1] as usize].iter().copied()).collect();
        FaceVarying { values: uvs.values.clone(), indices }
    });
    Some((kept_faces, uvs))
}

/// Reads a mesh file and validates it ([`crate::read_mesh`], then
/// [`Mesh::from_soup`]), with the file's texture coordinates and tags;
/// warnings are dropped ([`load_mesh_with_warnings`] keeps them).
///
/// ```
/// use subdiv_io::{load_mesh, write_mesh_view, IoError, MeshView};
/// use subdiv_mesh::{DVec3, FaceList, MeshError};
///
/// let dir = std::env::temp_dir().join(format!("subdiv-io-load-mesh-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// // Three triangles on one edge: a non-manifold mesh, refined as OpenSubdiv does (the edge
/// // infinitely sharp) through its manifold cover, which has a copy of each end per face.
/// let positions = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z, DVec3::NEG_Y];
/// let faces = FaceList::from_faces([[0u32, 1, 2], [1, 0, 3], [0, 1, 4]]);
/// let path = dir.join("fin.off");
/// write_mesh_view(&path, MeshView::new(&positions, &faces))?;
/// let fin = load_mesh(&path)?;
/// assert_eq!(fin.non_manifold().unwrap().edges, [[0, 1]]);
/// assert_eq!((fin.positions().len(), fin.welds().unwrap().vertex_count()), (9, 5));
/// // A face with two corners is no mesh at all.
/// let faces = FaceList::from_faces([&[0u32, 1, 2][..], &[1, 0][..]]);
/// write_mesh_view(&path, MeshView::new(&positions, &faces))?;
/// let e = load_mesh(&path).unwrap_err();
/// assert!(matches!(e, IoError::Validation { source: MeshError::FaceTooSmall { face: 1, size: 2 }, .. }), "{e}");
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// Those of [`crate::read_mesh`], and [`IoError::Validation`] with the
/// [`subdiv_mesh::MeshError`] of a file that is no valid mesh.
pub fn load_mesh(path: impl AsRef<Path>) -> Result<Mesh, IoError> {
    load_mesh_with_warnings(path).map(|(mesh, _)| mesh)
}

/// [`load_mesh`], also returning the warnings, each naming the file: what
/// the reader dropped or did not apply, then the mesh's warning-level
/// defects ([`ReadWarning::MeshDefect`]: isolated vertices, zero-area
/// faces), in that order.
///
/// # Errors
/// Those of [`load_mesh`].
pub fn load_mesh_with_warnings(path: impl AsRef<Path>) -> Result<(Mesh, Vec<ReadWarning>), IoError> {
    let path = path.as_ref();
    let (soup, mut warnings) = read_mesh_with_warnings(path, &mut |_, _| {})?;
    let (mesh, defects) =
        Mesh::from_soup_covering(soup).map_err(|source| IoError::Validation { path: path.to_path_buf(), source })?;
    warnings.extend(defects.into_iter().map(|warning| ReadWarning::MeshDefect { path: path.to_path_buf(), warning }));
    Ok((mesh, warnings))
}
