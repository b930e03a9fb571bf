//! A command's outputs: checked before any work starts, staged as they are
//! built, committed together at the end (all of them or none).
//!
//! Checked up front, for every output: the extension is a mesh format (mesh
//! outputs), it is not one of the command's inputs nor another output (also
//! through a hard link or symbolic link), the target is a regular file or does
//! not exist yet, and its directory exists and accepts new files. Nothing is
//! renamed into place until every output has been staged completely.

use crate::error::{ErrorKind, JobError};
use crate::progress::{Phase, Progress};
use std::path::{Path, PathBuf};
use subdiv_io::fs::{self, Destination, FileIdentity};
use subdiv_io::{Format, StagedFile};

struct Planned {
    flag: String,
    path: PathBuf,
    resolved: PathBuf,
}

/// The outputs of one command.
pub struct Outputs {
    inputs: Vec<(PathBuf, Option<PathBuf>, Option<FileIdentity>)>,
    planned: Vec<Planned>,
    staged: Vec<StagedFile>,
}

impl Outputs {
    /// Outputs of a command reading `inputs` (the mesh and parameter files).
    pub fn new<'a>(inputs: impl IntoIterator<Item = &'a Path>) -> Self {
        let inputs = inputs.into_iter().map(|p| (p.to_path_buf(), fs::canonical(p), fs::file_identity(p))).collect();
        Self { inputs, planned: Vec::new(), staged: Vec::new() }
    }

    /// Plans a mesh output given by `flag`; returns its format.
    pub fn mesh(&mut self, flag: &str, path: &Path) -> Result<Format, JobError> {
        let format = Format::from_path(path).map_err(|e| JobError::bad_input(format!("{flag} {e}")))?;
        self.plan(flag, path)?;
        Ok(format)
    }

    /// Plans a non-mesh output (the JSON report) given by `flag`.
    pub fn other(&mut self, flag: &str, path: &Path) -> Result<(), JobError> {
        self.plan(flag, path)
    }

    fn plan(&mut self, flag: &str, path: &Path) -> Result<(), JobError> {
        let shown = path.display();
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        if path.file_name().is_none() {
            return Err(JobError::bad_input(format!("{flag} {shown}: not a file name")));
        }
        match fs::is_directory(dir) {
            Ok(true) => {}
            Ok(false) => {
                return Err(JobError::write_failed(format!("{flag} {shown}: {} is not a directory", dir.display())))
            }
            Err(e) => return Err(JobError::write_failed(format!("{flag} {shown}: directory {}: {e}", dir.display()))),
        }
        let resolved =
            fs::resolve(path).ok_or_else(|| JobError::write_failed(format!("{flag} {shown}: cannot resolve")))?;
        let id = fs::file_identity(path);
        for (input, canonical, input_id) in &self.inputs {
            if canonical.as_ref() == Some(&resolved) || (id.is_some() && id == *input_id) {
                return Err(JobError::bad_input(format!(
                    "{flag} {shown} is the input file {}: refusing to overwrite an input",
                    input.display()
                )));
            }
        }
        if let Some(other) = self.planned.iter().find(|p| p.resolved == resolved) {
            return Err(JobError::bad_input(format!("{flag} and {} both name {shown}", other.flag)));
        }
        match fs::destination(path) {
            Destination::Directory => return Err(JobError::bad_input(format!("{flag} {shown} is a directory"))),
            Destination::Special => {
                return Err(JobError::bad_input(format!("{flag} {shown} exists and is not a regular file")))
            }
            Destination::LinkToNonFile => {
                return Err(JobError::bad_input(format!(
                    "{flag} {shown} links to something that is not a regular file"
                )))
            }
            Destination::Absent | Destination::File => {}
        }
        fs::probe_writable(dir).map_err(|e| {
            JobError::write_failed(format!("{flag} {shown}: cannot create files in {}: {e}", dir.display()))
        })?;
        self.planned.push(Planned { flag: flag.to_string(), path: path.to_path_buf(), resolved });
        Ok(())
    }

    /// Adds a staged output (one of the planned paths).
    pub fn stage(&mut self, file: StagedFile) {
        debug_assert!(self.planned.iter().any(|p| p.path == file.target()));
        self.staged.push(file);
    }

    /// Puts every staged output in place, or none (exit 4 on failure).
    pub fn commit(self) -> Result<Vec<PathBuf>, JobError> {
        let paths = self.staged.iter().map(|s| s.target().to_path_buf()).collect();
        subdiv_io::commit_all(self.staged).map_err(|e| JobError::from_error(ErrorKind::WriteFailed, &e))?;
        Ok(paths)
    }
}

/// The positions as `format` stores them: `f32` formats round every
/// coordinate (the error must be measured on what is written). Errors
/// (exit 2) when a coordinate does not fit in `f32`.
pub fn as_written<'a>(
    flag: &str,
    path: &Path,
    format: Format,
    positions: &'a [subdiv_mesh::DVec3],
) -> Result<std::borrow::Cow<'a, [subdiv_mesh::DVec3]>, JobError> {
    if format.keeps_f64() {
        return Ok(std::borrow::Cow::Borrowed(positions));
    }
    let rounded: Vec<subdiv_mesh::DVec3> = positions.iter().map(|p| p.as_vec3().as_dvec3()).collect();
    if let Some(i) = rounded.iter().position(|p| !p.is_finite()) {
        return Err(JobError::bad_input(format!(
            "{flag} {}: {format} stores 32-bit floats, which cannot hold vertex {i} at {}; use .obj, .off or .ply",
            path.display(),
            positions[i]
        )));
    }
    Ok(std::borrow::Cow::Owned(rounded))
}

/// Refuses (exit 3) a result with a coordinate or normal that is not finite:
/// nothing non-finite is ever written.
pub fn require_finite(
    what: &str,
    mesh: &subdiv_mesh::Mesh,
    normals: Option<&[subdiv_mesh::DVec3]>,
) -> Result<(), JobError> {
    let bad = mesh.positions().iter().filter(|p| !p.is_finite()).count();
    if bad > 0 {
        return Err(JobError::not_converged(format!(
            "{what}: {bad} of {} vertices are not finite (NaN or infinite); nothing written",
            mesh.positions().len()
        )));
    }
    if let Some(n) = normals {
        let bad = n.iter().filter(|p| !p.is_finite()).count();
        if bad > 0 {
            return Err(JobError::not_converged(format!(
                "{what}: {bad} vertex normals are not finite; nothing written"
            )));
        }
    }
    Ok(())
}

/// A mesh made ready for its format: welded, positions as the format stores them, holes left
/// out of a surface, tags and texture coordinates where the format has a place for them.
struct Prepared {
    positions: Vec<subdiv_mesh::DVec3>,
    faces: subdiv_mesh::FaceList,
    tags: subdiv_mesh::TagList,
    normals: Option<Vec<subdiv_mesh::DVec3>>,
    uvs: Option<subdiv_mesh::FaceVarying>,
    keep_tags: bool,
}

impl Prepared {
    fn new(
        flag: &str,
        path: &Path,
        format: Format,
        mesh: &subdiv_mesh::Mesh,
        normals: bool,
        surface: bool,
        progress: &mut dyn Progress,
    ) -> Result<Self, JobError> {
        // A non-manifold mesh's cover is written welded: the input's vertices, not their copies.
        let weld = |values: Vec<subdiv_mesh::DVec3>| match mesh.welds() {
            Some(welds) => welds.weld(&values),
            None => values,
        };
        let n = normals.then(|| weld(mesh.vertex_normals()));
        require_finite(&format!("{flag} {}", path.display()), mesh, n.as_deref())?;
        let (welded_positions, welded_faces, mut tags) = mesh.welded();
        let positions = as_written(flag, path, format, &welded_positions)?.into_owned();
        // Tags and texture coordinates where the format has a place for them.
        let without_holes = if surface { subdiv_io::faces_without_holes(mesh) } else { None };
        let without_holes = without_holes.map(|(faces, uvs)| match mesh.welds() {
            Some(welds) => (welds.weld_faces(&faces), uvs),
            None => (faces, uvs),
        });
        if without_holes.is_some() {
            tags.holes.clear();
        }
        let (view, left_out) = subdiv_io::view_for_format(mesh, &positions, &tags, format);
        let keep_tags = view.tags.is_some();
        let mut uvs = view.uvs.cloned();
        let mut faces = welded_faces.into_owned();
        if let Some((kept, kept_uvs)) = without_holes {
            faces = kept;
            uvs = uvs.and(kept_uvs);
        }
        for what in left_out {
            progress.warn(&format!("{flag} {}: {what}", path.display()));
        }
        Ok(Self { positions, faces, tags, normals: n, uvs, keep_tags })
    }

    fn view(&self) -> subdiv_io::MeshView<'_> {
        let mut view = subdiv_io::MeshView::new(&self.positions, &self.faces);
        if self.keep_tags {
            view = view.with_tags(&self.tags);
        }
        if let Some(uvs) = &self.uvs {
            view = view.with_uvs(uvs);
        }
        if let Some(n) = &self.normals {
            view = view.with_normals(n);
        }
        view
    }
}

/// One mesh of a USD output: its prim path, the mesh, the scheme a renderer is to subdivide it with.
pub struct UsdOutput<'a> {
    /// The prim path.
    pub prim: &'a str,
    /// The mesh.
    pub mesh: &'a subdiv_mesh::Mesh,
    /// `subdivisionScheme`.
    pub scheme: subdiv_io::usd::SubdivisionScheme,
}

impl Outputs {
    /// Checks and stages a mesh output (with vertex normals when `normals`),
    /// showing the bytes written on a progress bar. A `surface` (a refined
    /// mesh) is written without its hole faces, as OpenSubdiv draws it; a
    /// control mesh keeps them, tagged where the format has tags.
    pub fn stage_mesh(
        &mut self,
        flag: &str,
        path: &Path,
        mesh: &subdiv_mesh::Mesh,
        normals: bool,
        surface: bool,
        progress: &mut dyn Progress,
    ) -> Result<(), JobError> {
        let format = Format::from_path(path).map_err(|e| JobError::bad_input(format!("{flag} {e}")))?;
        let prepared = Prepared::new(flag, path, format, mesh, normals, surface, progress)?;
        let view = prepared.view();
        // A rough size for the bar's ETA: text formats take ~40 bytes a vertex and ~8 a corner.
        let estimate = 40 * prepared.positions.len() as u64 + 8 * mesh.topology().half_edge_count() as u64;
        progress.begin(Phase::Write, &format!("writing {}", path.display()), estimate);
        let mut most = estimate;
        let staged = subdiv_io::stage_mesh(path, view, format, &mut |done| {
            if done > most {
                most = done;
                progress.set_total(most);
            }
            progress.advance(done);
        });
        progress.end();
        self.stage(staged.map_err(staging_error)?);
        Ok(())
    }

    /// Checks and stages a USD output of several meshes at their prim paths, into a copy of
    /// `template`'s layer when given (see [`Outputs::stage_mesh`] for `normals` and `surface`).
    #[allow(clippy::too_many_arguments)]
    pub fn stage_usd(
        &mut self,
        flag: &str,
        path: &Path,
        meshes: &[UsdOutput<'_>],
        template: Option<&subdiv_io::usd::UsdScene>,
        normals: bool,
        surface: bool,
        progress: &mut dyn Progress,
    ) -> Result<(), JobError> {
        let format = Format::from_path(path).map_err(|e| JobError::bad_input(format!("{flag} {e}")))?;
        let prepared = meshes
            .iter()
            .map(|m| Prepared::new(flag, path, format, m.mesh, normals, surface, progress))
            .collect::<Result<Vec<_>, _>>()?;
        let scene: Vec<subdiv_io::usd::SceneMesh<'_>> = meshes
            .iter()
            .zip(&prepared)
            .map(|(m, p)| subdiv_io::usd::SceneMesh { path: m.prim, view: p.view(), scheme: Some(m.scheme) })
            .collect();
        progress.begin(Phase::Write, &format!("writing {}", path.display()), 0);
        let staged = subdiv_io::usd::stage_scene(path, template, &scene, format);
        progress.end();
        self.stage(staged.map_err(staging_error)?);
        Ok(())
    }
    /// Stages a non-mesh output.
    pub fn stage_bytes(&mut self, path: &Path, bytes: &[u8]) -> Result<(), JobError> {
        let staged =
            subdiv_io::stage_bytes(path, bytes).map_err(|e| JobError::from_error(ErrorKind::WriteFailed, &e))?;
        self.stage(staged);
        Ok(())
    }
}

/// A failed staging: a write failure (exit 4) or a mesh the format cannot hold (exit 2).
fn staging_error(e: subdiv_io::IoError) -> JobError {
    match e {
        subdiv_io::IoError::Io { .. } => JobError::from_error(ErrorKind::WriteFailed, &e),
        other => JobError::from_error(ErrorKind::BadInput, &other),
    }
}
