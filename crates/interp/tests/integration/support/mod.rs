//! Shared by the method tests: fixtures, the independent check of
//! `subdiv_interp::verify`, and a volume measure.
#![allow(dead_code)]

pub mod tagged;

use glam::DVec3;
use std::path::{Path, PathBuf};
#[allow(unused_imports)]
pub use subdiv_interp::verify::nearest_gap;
use subdiv_mesh::Mesh;
#[allow(unused_imports)]
pub use subdiv_stencil::Scheme;

/// `mesh` with every vertex moved by a deterministic offset drawn uniformly
/// from [−amount/2, amount/2]³ (seeded: the same mesh every run).
pub fn perturbed(mesh: Mesh, amount: f64, seed: u64) -> Mesh {
    let mut rng = subdiv_mesh::shapes::SplitMix64(seed);
    let p = mesh
        .positions()
        .iter()
        .map(|&p| p + amount * DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5))
        .collect();
    mesh.with_positions(p)
}

/// [`perturbed`] by `amount` × the bounding-box diagonal.
pub fn bumpy(mesh: Mesh, amount: f64, seed: u64) -> Mesh {
    let d = mesh.bbox_diagonal();
    perturbed(mesh, amount * d, seed)
}

/// The repository's `fixtures/` folder.
pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// Reads and validates a mesh file (panics naming the file).
pub fn load(path: &Path) -> Mesh {
    let soup = subdiv_io::read_mesh(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Mesh::from_soup(soup).unwrap_or_else(|e| panic!("{}: {e}", path.display())).0
}

/// A fixture by path below `fixtures/`.
pub fn fixture(rel: &str) -> Mesh {
    load(&fixtures().join(rel))
}

/// A fixture by file stem: `fixtures/<dir>/<stem>.{obj,off}` for the
/// collection's subfolders, in lookup order (panics if missing).
pub fn fixture_named(stem: &str) -> Mesh {
    for dir in ["canonical", "quad", "tri", "poly", "open"] {
        for ext in ["obj", "off"] {
            let p = fixtures().join(dir).join(format!("{stem}.{ext}"));
            if p.is_file() {
                return load(&p);
            }
        }
    }
    panic!("fixture {stem} not found")
}

/// Every limit point the plain scheme exposes on `control`.
pub fn candidate_limit_points(control: &Mesh, plain: Scheme) -> Vec<DVec3> {
    subdiv_interp::verify::candidate_limit_points(control, plain).expect("plain scheme applies")
}

/// Signed volume enclosed by a closed mesh (divergence theorem, fan triangulation).
pub fn volume(mesh: &Mesh) -> f64 {
    let t = mesh.topology();
    let mut v = 0.0;
    for face in t.faces().iter() {
        let p0 = mesh.positions()[face[0] as usize];
        for k in 1..face.len() - 1 {
            let (p1, p2) = (mesh.positions()[face[k] as usize], mesh.positions()[face[k + 1] as usize]);
            v += p0.dot(p1.cross(p2)) / 6.0;
        }
    }
    v
}

/// The 7-vertex torus (every two vertices share an edge) with the star of
/// vertex 0 replaced by one hexagon: every diagonal of the hexagon is an
/// edge, so it has no triangulation keeping the mesh manifold.
pub fn torus_with_untriangulable_hexagon() -> Mesh {
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for i in 0..7u32 {
        for tri in [[i, i + 1, i + 3], [i, i + 3, i + 2]].map(|t| t.map(|v| v % 7)) {
            if !tri.contains(&0) {
                faces.push(tri.to_vec());
            }
        }
    }
    faces.push(vec![1, 3, 2, 6, 4, 5]);
    let mut rng = subdiv_mesh::shapes::SplitMix64(5);
    let p = (0..7).map(|_| DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64())).collect();
    Mesh::new(p, subdiv_mesh::FaceList::from_faces(&faces)).unwrap()
}
