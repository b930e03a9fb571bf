//! Reading and validating the input mesh of the evaluation commands, through the one pipeline's
//! loader ([`subdiv::job::load`]): the file's tags, a tag file's, feature edges by angle.

use crate::failure::{bad_input, Failure};
use std::path::{Path, PathBuf};
use subdiv::job::TagOptions;
use subdiv_mesh::{Mesh, PolygonSoup};

/// Reads a mesh file as it is (unvalidated), with a progress bar for large files.
pub fn read_soup(path: &Path) -> Result<PolygonSoup, Failure> {
    Ok(subdiv::job::load::read_soup(path, &mut crate::progress::Terminal::default())?)
}

/// Reads a text input that is not a mesh (a parameter file, `--at`, `.xyz`
/// points) through [`subdiv_io::read_text`]: a FIFO or a device is refused
/// before it is opened, the size is capped, the text must be UTF-8 (exit 2).
pub fn read_text(path: &Path) -> Result<String, Failure> {
    subdiv_io::read_text(path).map_err(bad_input)
}

/// Where a command's tags come from besides the file's own `t` lines.
#[derive(clap::Args, Debug, Default)]
pub struct TagArgs {
    /// Crease and corner tags for formats without them (or in addition to an OBJ's `t` lines):
    /// JSON {"creases": [[v0, v1, sharpness], …], "corners": [[v, sharpness], …]}, 0-based vertex
    /// indices, sharpness 0 smooth … ≥ 10 infinitely sharp.
    #[arg(long)]
    pub tags: Option<PathBuf>,
    /// Tag every interior edge whose two faces' normals turn by at least DEG degrees as an
    /// infinitely sharp crease (feature edges of a CAD-like mesh); tags from the file or --tags
    /// on the same edges win.
    #[arg(long, value_name = "DEG")]
    pub feature_angle: Option<f64>,
}

impl TagArgs {
    /// The tag file, an input no output may overwrite.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        self.tags.as_deref().into_iter()
    }
}

/// Reads and validates a mesh with the tags of `tags` (the file's own, the tag file's, feature
/// edges); warnings go to stderr.
pub fn load_tagged_mesh(path: &Path, tags: &TagArgs) -> Result<Mesh, Failure> {
    let mut options = TagOptions::default();
    options.tags.clone_from(&tags.tags);
    options.feature_angle = tags.feature_angle;
    if let Some(deg) = tags.feature_angle {
        if !(deg > 0.0 && deg <= 180.0) {
            return Err(subdiv::job::JobError::bad_input(format!("--feature-angle: {deg}° is outside (0, 180]")).into());
        }
    }
    Ok(subdiv::job::load::load_tagged_mesh(path, &options, &mut crate::progress::Terminal::default())?)
}
