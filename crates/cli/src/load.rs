//! Reading and validating the input mesh, shared by every command.

use crate::failure::{bad_input, Failure};
use crate::progress;
use anyhow::anyhow;
use std::path::Path;
use subdiv_mesh::{Mesh, PolygonSoup};

/// Reads a mesh file as it is (unvalidated), with a progress bar for large
/// files; what the reader skipped (texture coordinates on only some faces,
/// tag lines other than creases and corners) goes to stderr.
pub fn read_soup(path: &Path) -> Result<PolygonSoup, Failure> {
    let bar = progress::bytes(format!("reading {}", path.display()), 0);
    let read = subdiv_io::read_mesh_with_warnings(path, &mut |done, total| {
        bar.set_length(total);
        bar.set_position(done);
    });
    bar.finish_and_clear();
    let (soup, warnings) = read.map_err(bad_input)?;
    for w in warnings {
        progress::warn(w.to_string());
    }
    Ok(soup)
}

/// Reads and validates a mesh, with the crease and corner tags of
/// `tag_file` (`--tags`, JSON) added to the file's own (a later tag of the
/// same edge or vertex wins); warnings go to stderr (one line each).
pub fn load_mesh_with_tags(path: &Path, tag_file: Option<&Path>) -> Result<Mesh, Failure> {
    let mut soup = read_soup(path)?;
    if let Some(file) = tag_file {
        let tags = subdiv_io::read_tag_file(file).map_err(bad_input)?;
        soup.tags.creases.extend(tags.creases);
        soup.tags.corners.extend(tags.corners);
    }
    let spinner = progress::spinner(format!("validating {}", path.display()));
    let validated = Mesh::from_soup(soup);
    spinner.finish_and_clear();
    let (mesh, warnings) = validated.map_err(|e| {
        let tags = tag_file.map(|f| format!(" (with the tags of {})", f.display())).unwrap_or_default();
        bad_input(anyhow!("{}{tags}: {e}", path.display()))
    })?;
    for w in warnings {
        progress::warn(format!("{}: {w}", path.display()));
    }
    Ok(mesh)
}
