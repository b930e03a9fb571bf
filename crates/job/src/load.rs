//! Reading and validating a job's input: the file's own tags and texture coordinates, a tag
//! file's tags, feature edges by angle; what the reader skipped and the mesh's defects as
//! warnings.

use crate::error::{ErrorKind, JobError};
use crate::options::TagOptions;
use crate::progress::{Phase, Progress};
use std::path::Path;
use subdiv_mesh::{Mesh, PolygonSoup};

/// Reads a mesh file as it is (unvalidated), reporting the bytes read; what the reader skipped
/// (texture coordinates on only some faces, tag lines other than creases and corners) becomes
/// warnings.
pub fn read_soup(path: &Path, progress: &mut dyn Progress) -> Result<PolygonSoup, JobError> {
    progress.begin(Phase::Read, &format!("reading {}", path.display()), 0);
    let read = subdiv_io::read_mesh_with_warnings(path, &mut |done, total| {
        progress.set_total(total);
        progress.advance(done);
    });
    progress.end();
    let (soup, warnings) = read.map_err(|e| JobError::from_error(ErrorKind::BadInput, &e))?;
    for w in warnings {
        progress.warn(&w.to_string());
    }
    Ok(soup)
}

/// Reads and validates a mesh with the tags of `tags`: the file's own, then the tag file's (a
/// later tag of the same edge or vertex wins), the feature edges of `feature_angle` under both.
pub fn load_tagged_mesh(path: &Path, tags: &TagOptions, progress: &mut dyn Progress) -> Result<Mesh, JobError> {
    let mesh = load_mesh_with_tags(path, tags.tags.as_deref(), progress)?;
    with_feature_edges(path, mesh, tags)
}

/// A soup read from `path` (one mesh of it: `what` names it in messages), validated with the
/// tags of `tags`, as [`load_tagged_mesh`] validates a whole file's.
pub fn tagged_mesh_from_soup(
    path: &Path,
    what: &str,
    soup: PolygonSoup,
    tags: &TagOptions,
    progress: &mut dyn Progress,
) -> Result<Mesh, JobError> {
    let mesh = validate(what, soup, tags.tags.as_deref(), progress)?;
    with_feature_edges(path, mesh, tags)
}

/// The feature edges of `tags.feature_angle` added under the mesh's own tags.
fn with_feature_edges(path: &Path, mesh: Mesh, tags: &TagOptions) -> Result<Mesh, JobError> {
    let Some(deg) = tags.feature_angle else { return Ok(mesh) };
    let t = mesh.topology();
    let mut list = subdiv_mesh::feature_edges(&mesh, deg).list;
    let given = mesh.tags().to_list(t);
    list.creases.extend(given.creases);
    list.corners = given.corners;
    list.holes = given.holes;
    list.options = given.options;
    let tags =
        subdiv_mesh::Tags::from_list(t, &list).map_err(|e| JobError::bad_input(format!("{}: {e}", path.display())))?;
    Ok(mesh.with_tags(tags))
}

/// Reads and validates a mesh, with the crease and corner tags of `tag_file` (JSON) added to
/// the file's own (a later tag of the same edge or vertex wins).
fn load_mesh_with_tags(path: &Path, tag_file: Option<&Path>, progress: &mut dyn Progress) -> Result<Mesh, JobError> {
    let soup = read_soup(path, progress)?;
    validate(&path.display().to_string(), soup, tag_file, progress)
}

/// Validates a soup with the tag file's tags added; `what` names it in messages.
fn validate(
    what: &str,
    mut soup: PolygonSoup,
    tag_file: Option<&Path>,
    progress: &mut dyn Progress,
) -> Result<Mesh, JobError> {
    if let Some(file) = tag_file {
        let tags = subdiv_io::read_tag_file(file).map_err(|e| JobError::from_error(ErrorKind::BadInput, &e))?;
        soup.tags.creases.extend(tags.creases);
        soup.tags.corners.extend(tags.corners);
        soup.tags.holes.extend(tags.holes);
    }
    progress.begin(Phase::Validate, &format!("validating {what}"), 0);
    let validated = Mesh::from_soup_covering(soup);
    progress.end();
    let (mesh, warnings) = validated.map_err(|e| {
        let tags = tag_file.map(|f| format!(" (with the tags of {})", f.display())).unwrap_or_default();
        JobError::bad_input(format!("{what}{tags}: {e}"))
    })?;
    for w in warnings {
        progress.warn(&format!("{what}: {w}"));
    }
    Ok(mesh)
}
