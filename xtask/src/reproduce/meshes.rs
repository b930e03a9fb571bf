//! Generated meshes of a requested size, and fixture labels.

use subdiv_mesh::{shapes, Mesh};

/// A closed polygon mix (genus 1) with about `vertices` vertices: a quad
/// torus with some faces merged into 5-8-gons and some quads split.
pub fn closed_mix(vertices: usize) -> Mesh {
    let nv = ((vertices as f64 / 2.0).sqrt().round() as usize).max(4);
    let nu = (vertices / nv).max(4);
    shapes::polygon_mix(&shapes::torus(nu, nv), 7, 0.1, 0.1, 0.05)
}

/// The file stem of a fixture path.
pub fn label(file: &str) -> String {
    std::path::Path::new(file).file_stem().map_or(file.to_string(), |s| s.to_string_lossy().into_owned())
}

/// The dual of a closed mesh: one vertex per face (its centroid), one face per
/// vertex (the centroids of its faces in fan order). The dual of a triangle
/// mesh has only valence-3 vertices, the hard case for Catmull-Clark's A.
pub fn dual(mesh: &Mesh) -> Mesh {
    let t = mesh.topology();
    assert!(t.is_closed(), "the dual is built for closed meshes");
    let mut faces = subdiv_mesh::FaceList::new();
    for v in t.vertices() {
        let fan: Vec<u32> = t.vertex_fan(v).iter().map(|&h| t.he_face(h).0).collect();
        if !fan.is_empty() {
            faces.push(&fan);
        }
    }
    Mesh::new(mesh.face_centroids(), faces).expect("the dual of a closed manifold mesh is valid")
}
