//! Reading and validating the input mesh, shared by every command.

use crate::failure::{bad_input, Failure};
use crate::progress;
use anyhow::anyhow;
use std::path::{Path, PathBuf};
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

/// Reads a text input that is not a mesh (a parameter file, `--at`, `.xyz`
/// points) through [`subdiv_io::read_text`]: a FIFO or a device is refused
/// before it is opened, the size is capped, the text must be UTF-8 (exit 2).
pub fn read_text(path: &Path) -> Result<String, Failure> {
    subdiv_io::read_text(path).map_err(bad_input)
}

/// Reads a parameter file ([`read_text`]) and parses it with one of
/// `subdiv_interp::params`' parsers, the error naming the file (exit 2).
pub fn read_param_file<T>(
    path: &Path,
    parse: impl FnOnce(&str) -> Result<T, subdiv_interp::ParamFileError>,
) -> Result<T, Failure> {
    parse(&read_text(path)?).map_err(|e| bad_input(e.with_path(path)))
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

/// Reads and validates a mesh with the tags of `tags`: the file's own, then
/// the tag file's (a later tag of the same edge or vertex wins), the feature
/// edges of `--feature-angle` under both; warnings go to stderr.
pub fn load_tagged_mesh(path: &Path, tags: &TagArgs) -> Result<Mesh, Failure> {
    if let Some(deg) = tags.feature_angle {
        if !(deg > 0.0 && deg <= 180.0) {
            return Err(bad_input(anyhow!("--feature-angle: {deg}° is outside (0, 180]")));
        }
    }
    let mesh = load_mesh_with_tags(path, tags.tags.as_deref())?;
    let Some(deg) = tags.feature_angle else { return Ok(mesh) };
    let t = mesh.topology();
    let mut list = subdiv_mesh::feature_edges(&mesh, deg).list;
    let given = mesh.tags().to_list(t);
    list.creases.extend(given.creases);
    list.corners = given.corners;
    let tags = subdiv_mesh::Tags::from_list(t, &list).map_err(|e| bad_input(anyhow!("{}: {e}", path.display())))?;
    Ok(mesh.with_tags(tags))
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
