//! A job's input as a **scene**: the named meshes of one file, which the pipeline runs one by
//! one. A mesh file of any format but USD is a scene of one unnamed mesh; a USD file is a scene
//! of its `Mesh` prims, named by their prim paths (`--prim PATH` keeps one), with the layer they
//! came from, so that the outputs can be written back into it at the same prim paths
//! ([`subdiv_io::usd`]). `subdiv interpolate`, `subdiv subdivide`, every job of `subdiv batch`
//! and the Python package's file functions load their input here.

use crate::error::{ErrorKind, JobError};
use crate::load::{load_tagged_mesh, tagged_mesh_from_soup};
use crate::options::TagOptions;
use crate::progress::{Phase, Progress};
use std::path::Path;
use subdiv_io::usd::{SubdivisionScheme, UsdScene};
use subdiv_io::Format;
use subdiv_mesh::Mesh;

/// One mesh of a scene.
#[derive(Debug)]
#[non_exhaustive]
pub struct SceneMesh {
    /// Its prim path in a USD file; `None` for the one mesh of another format.
    pub prim: Option<String>,
    /// The subdivision scheme its file gives it (USD's `subdivisionScheme`).
    pub scheme: Option<SubdivisionScheme>,
    /// The validated mesh, with its tags.
    pub mesh: Mesh,
}

impl SceneMesh {
    /// How messages name it: the file, with the prim path of a USD mesh (`scene.usda:/World/Body`).
    pub fn label(&self, input: &Path) -> String {
        match &self.prim {
            Some(prim) => format!("{}:{prim}", input.display()),
            None => input.display().to_string(),
        }
    }
}

/// The meshes of one input file.
#[derive(Debug)]
#[non_exhaustive]
pub struct Scene {
    /// In the file's order (a USD layer's path order).
    pub meshes: Vec<SceneMesh>,
    /// The USD layer the meshes came from, to write outputs into.
    pub usd: Option<UsdScene>,
}

impl Scene {
    /// Whether the scene has more than one mesh (then only a USD output holds them all).
    pub fn is_several(&self) -> bool {
        self.meshes.len() > 1
    }
}

/// Reads and validates every mesh of `path` with the tags of `tags` (`tags.prim`: one Mesh prim
/// of a USD file).
///
/// # Errors
/// Bad input for an unreadable file or an invalid mesh, `--prim` on a file that is not USD or
/// naming no Mesh prim of it, and a tag file (`--tags`, which numbers the vertices of one mesh)
/// with several meshes.
pub fn load_scene(path: &Path, tags: &TagOptions, progress: &mut dyn Progress) -> Result<Scene, JobError> {
    let is_usd = Format::from_path(path).is_ok_and(Format::is_usd);
    if !is_usd {
        if let Some(prim) = &tags.prim {
            return Err(JobError::bad_input(format!(
                "--prim {prim}: {} is not a USD file (.usda, .usdc, .usd, .usdz)",
                path.display()
            )));
        }
        let mesh = load_tagged_mesh(path, tags, progress)?;
        return Ok(Scene { meshes: vec![SceneMesh { prim: None, scheme: None, mesh }], usd: None });
    }
    progress.begin(Phase::Read, &format!("reading {}", path.display()), 0);
    let read = subdiv_io::usd::read_scene(path);
    progress.end();
    let (mut usd, warnings) = read.map_err(|e| JobError::from_error(ErrorKind::BadInput, &e))?;
    for w in warnings {
        progress.warn(&w.to_string());
    }
    if let Some(prim) = &tags.prim {
        if usd.select(prim).is_none() {
            return Err(JobError::bad_input(format!(
                "--prim {prim}: {} has no Mesh prim at that path (its Mesh prims: {})",
                path.display(),
                usd.prim_paths().join(", ")
            )));
        }
    }
    if usd.meshes.len() > 1 && tags.tags.is_some() {
        return Err(JobError::bad_input(format!(
            "--tags: {} has {} Mesh prims, and a tag file numbers the vertices of one; choose it with --prim",
            path.display(),
            usd.meshes.len()
        )));
    }
    let mut meshes = Vec::with_capacity(usd.meshes.len());
    for m in std::mem::take(&mut usd.meshes) {
        let what = format!("{}:{}", path.display(), m.path);
        let mesh = tagged_mesh_from_soup(path, &what, m.soup, tags, progress)?;
        meshes.push(SceneMesh { prim: Some(m.path), scheme: Some(m.scheme), mesh });
    }
    Ok(Scene { meshes, usd: Some(usd) })
}

/// Refuses (bad input) a mesh output that is not USD when the scene has several meshes.
pub fn check_output(scene: &Scene, input: &Path, flag: &str, output: &Path, format: Format) -> Result<(), JobError> {
    if scene.is_several() && !format.is_usd() {
        let prims: Vec<&str> = scene.meshes.iter().filter_map(|m| m.prim.as_deref()).collect();
        return Err(JobError::bad_input(format!(
            "{flag} {}: {} has {} Mesh prims ({}); write a USD file (.usda, .usdc) to keep them all, or choose \
             one with --prim",
            output.display(),
            input.display(),
            prims.len(),
            prims.join(", ")
        )));
    }
    Ok(())
}
