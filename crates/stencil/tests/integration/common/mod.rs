//! Helpers shared by the integration tests: fixture lookup and loading.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use subdiv_mesh::Mesh;

/// The repository's `fixtures/` folder.
pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// The shared collection next to the repository (`../shared`), if present.
pub fn shared() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared")
}

/// Subfolders of a mesh collection, in lookup order.
pub const MESH_DIRS: [&str; 5] = ["canonical", "quad", "tri", "poly", "open"];

/// The input mesh with file stem `stem`: `fixtures/<dir>/<stem>.{obj,off}`,
/// else the same under `../shared/meshes/`.
pub fn find_mesh(stem: &str) -> Option<PathBuf> {
    for root in [fixtures(), shared().join("meshes")] {
        for dir in MESH_DIRS {
            for ext in ["obj", "off"] {
                let p = root.join(dir).join(format!("{stem}.{ext}"));
                if p.is_file() {
                    return Some(p);
                }
            }
        }
    }
    None
}

/// Reads and validates a mesh file (panics with the file name on failure).
pub fn load(path: &Path) -> Mesh {
    let soup = subdiv_io::read_mesh(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (mesh, _warnings) = Mesh::from_soup(soup).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    mesh
}

/// A fixture by stem (panics if missing: fixtures are part of the repository).
pub fn fixture(stem: &str) -> Mesh {
    load(&find_mesh(stem).unwrap_or_else(|| panic!("fixture {stem} not found")))
}

use subdiv_mesh::{FaceId, Topology};
use subdiv_stencil::doo_sabin::{CornerMask, StandardCorners};
use subdiv_stencil::StencilError;

/// Corner masks for the tests of the Doo-Sabin step's machinery: the
/// standard one, and V' = λV + (1 − λ)A (A the face centroid) with one λ
/// or one per face, given by its weights only (the default images). The
/// interpolation methods' own rules, with their closed-form images, are
/// `subdiv_interp::CornerRule`, tested in subdiv-interp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mask<'a> {
    /// [`StandardCorners`].
    Standard,
    /// One λ ∈ (0, 1) for every face.
    Uniform(f64),
    /// λ_f per face.
    PerFace(&'a [f64]),
}

impl CornerMask for Mask<'_> {
    fn validate(&self, t: &Topology) -> Result<(), StencilError> {
        let bad = |l: f64| !(l > 0.0 && l < 1.0);
        match *self {
            Mask::Standard => Ok(()),
            Mask::Uniform(l) if bad(l) => Err(StencilError::InvalidParameter(format!("λ = {l}"))),
            Mask::PerFace(ls) if ls.len() != t.face_count() || ls.iter().any(|&l| bad(l)) => {
                Err(StencilError::InvalidParameter(format!("{ls:?}")))
            }
            Mask::Uniform(_) | Mask::PerFace(_) => Ok(()),
        }
    }

    fn weights(&self, face: FaceId, out: &mut [f64]) {
        let lambda = match *self {
            Mask::Standard => return StandardCorners.weights(face, out),
            Mask::Uniform(l) => l,
            Mask::PerFace(ls) => ls[face.index()],
        };
        let share = (1.0 - lambda) / out.len() as f64;
        out.fill(share);
        out[0] = lambda + share;
    }
}

/// The rows in solve order (as `subdiv_interp::solve_blocks`, which the
/// methods use; built here from the matrix's fields): the corner rows, the
/// other rows of the sharp block, every other row.
pub struct Blocks {
    pub corners: Vec<u32>,
    pub creases: Vec<u32>,
    pub interior: Vec<u32>,
}

pub fn solve_blocks(a: &subdiv_stencil::LimitMatrix) -> Blocks {
    let (mut corners, mut creases, mut interior) = (Vec::new(), Vec::new(), Vec::new());
    for v in 0..a.size() as u32 {
        let block = match a.row_kinds[v as usize] {
            subdiv_stencil::RowKind::Corner => &mut corners,
            _ if a.boundary_rows.binary_search(&v).is_ok() => &mut creases,
            _ => &mut interior,
        };
        block.push(v);
    }
    Blocks { corners, creases, interior }
}
