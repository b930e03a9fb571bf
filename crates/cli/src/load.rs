//! Reading and validating the input mesh, shared by every command.

use crate::failure::{bad_input, Failure};
use anyhow::anyhow;
use std::path::Path;
use subdiv_mesh::Mesh;

/// Reads and validates a mesh; warnings go to stderr (one line each).
pub fn load_mesh(path: &Path) -> Result<Mesh, Failure> {
    let soup = subdiv_io::read_mesh(path).map_err(bad_input)?;
    let (mesh, warnings) = Mesh::from_soup(soup).map_err(|e| bad_input(anyhow!("{}: {e}", path.display())))?;
    for w in warnings {
        eprintln!("subdiv: warning: {}: {w}", path.display());
    }
    Ok(mesh)
}
