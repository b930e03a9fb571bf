//! Reading and validating the input mesh, shared by every command.

use crate::failure::{bad_input, Failure};
use crate::progress;
use anyhow::anyhow;
use std::path::Path;
use subdiv_mesh::{Mesh, PolygonSoup};

/// Reads a mesh file as it is (unvalidated), with a progress bar for large files.
pub fn read_soup(path: &Path) -> Result<PolygonSoup, Failure> {
    let bar = progress::bytes(format!("reading {}", path.display()), 0);
    let soup = subdiv_io::read_mesh_with_progress(path, &mut |done, total| {
        bar.set_length(total);
        bar.set_position(done);
    });
    bar.finish_and_clear();
    soup.map_err(bad_input)
}

/// Reads and validates a mesh; warnings go to stderr (one line each).
pub fn load_mesh(path: &Path) -> Result<Mesh, Failure> {
    let soup = read_soup(path)?;
    let spinner = progress::spinner(format!("validating {}", path.display()));
    let validated = Mesh::from_soup(soup);
    spinner.finish_and_clear();
    let (mesh, warnings) = validated.map_err(|e| bad_input(anyhow!("{}: {e}", path.display())))?;
    for w in warnings {
        progress::warn(format!("{}: {w}", path.display()));
    }
    Ok(mesh)
}
