//! `subdiv_mesh::triangulate` on every fixture of `fixtures/quad`, `poly`,
//! `open` and `canonical` (read here because the mesh crate cannot depend on
//! this one), each result checked by the mesh crate's triangulation checks:
//! valid manifold mesh, same vertices, Euler characteristic, boundary loops
//! and genus, triangles over each face's corners in its order, and for every
//! face that can be split into triangles of its orientation (its projection
//! on its best-fit plane is simple, or brute force finds such a split), such
//! triangles.
//!
//! Run with `--nocapture` for the table.

#[path = "../../../mesh/tests/integration/support/triangulation.rs"]
mod triangulation;

use crate::common::fixture;
use subdiv_mesh::{triangulate, Mesh};

#[test]
fn every_polygon_fixture_triangulates_into_a_valid_mesh() {
    let mut names = Vec::new();
    for dir in ["quad", "poly", "open", "canonical"] {
        let mut files: Vec<String> = std::fs::read_dir(fixture(dir))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".obj") || n.ends_with(".off"))
            .map(|n| format!("{dir}/{n}"))
            .collect();
        files.sort();
        names.extend(files);
    }
    assert!(names.len() >= 30, "fixtures missing: {names:?}");
    println!("| fixture | faces | split | valid | planar | impossible | triangles |");
    println!("|---|---|---|---|---|---|---|");
    let mut split_total = 0;
    for name in &names {
        let soup = subdiv_io::read_mesh(&fixture(name)).unwrap_or_else(|e| panic!("{e}"));
        let (mesh, _) = Mesh::from_soup(soup).unwrap_or_else(|e| panic!("{name}: {e}"));
        let tri = triangulate(&mesh).unwrap_or_else(|e| panic!("{name}: {e}"));
        let checked = triangulation::check(&mesh, &tri).unwrap_or_else(|e| panic!("{name}: {e}"));
        println!(
            "| {name} | {} | {} | {} | {} | {} | {} |",
            mesh.topology().face_count(),
            checked.split,
            checked.valid,
            checked.planar,
            checked.impossible,
            tri.mesh.topology().face_count(),
        );
        split_total += checked.split;
        // Every split face was checked geometrically, or shown to have no oriented triangulation.
        assert_eq!(checked.valid + checked.impossible, checked.split, "{name}: faces not checked");
    }
    assert!(split_total > 20_000, "the fixtures should exercise the splitting: {split_total}");
}
