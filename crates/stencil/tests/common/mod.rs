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
