//! Non-manifold meshes through their manifold cover (`subdiv_mesh::nonmanifold`):
//!
//! - brute force: the limit positions of a non-manifold mesh are where uniform refinement
//!   carried 7–8 levels goes (vertex points of the input's vertices, welded), for fins (an edge of
//!   three and four faces), bow-ties, two tetrahedra sharing a vertex, a degenerate quad pole, and
//!   OpenSubdiv's shapes with non-manifold vertices and edges, under Catmull-Clark and Loop;
//! - copies agree: refined by the rules, every copy of a vertex lands exactly where the vertex
//!   it copies does, on every level (what makes the welded output one surface);
//! - random soups with edges of many faces, repeated and flipped faces and shared apices never
//!   panic: they are refused with a typed error or refined, welded, and their copies agree.
//!
//! (Equality with OpenSubdiv's own refinement of its non-manifold shapes is `opensubdiv_shapes.rs`.)

use glam::DVec3;
use proptest::prelude::*;
use std::path::Path;
use subdiv_mesh::{FaceList, Mesh, PolygonSoup};
use subdiv_stencil::{limit_points_with_options, subdivide, LoopBeta, Options, Scheme};

fn mesh(positions: &[[f64; 3]], faces: &[&[u32]]) -> Mesh {
    let positions = positions.iter().map(|p| DVec3::from_array(*p)).collect();
    let soup = PolygonSoup::new(positions, FaceList::from_faces(faces.iter().copied()));
    Mesh::from_soup_covering(soup).expect("a mesh OpenSubdiv refines").0
}

fn welded(mesh: &Mesh, points: Vec<DVec3>) -> Vec<DVec3> {
    match mesh.welds() {
        Some(welds) => welds.weld(&points),
        None => points,
    }
}

/// The largest distance between two copies of one vertex, relative to d.
fn copies_apart(mesh: &Mesh, d: f64) -> f64 {
    let Some(welds) = mesh.welds() else { return 0.0 };
    let members = welds.weld(mesh.positions());
    (mesh.positions().iter().enumerate())
        .map(|(v, p)| (*p - members[welds.vertex(subdiv_mesh::VertexId(v as u32)) as usize]).length() / d)
        .fold(0.0, f64::max)
}

/// Limit positions vs the vertex points of `levels` uniform levels, welded, relative to d; and
/// the same at `levels − 2` (the deviation must shrink).
fn brute_force(mesh: &Mesh, scheme: Scheme, levels: usize) -> (f64, f64) {
    let options = Options::from(scheme);
    let d = mesh.bbox_diagonal();
    let limits = limit_points_with_options(mesh.topology(), mesh.tags(), options, mesh.positions()).unwrap().unwrap();
    let limits = welded(mesh, limits);
    let deviation = |levels: usize| {
        let refined = subdivide(mesh, options, levels, false).unwrap();
        let apart = copies_apart(&refined, d);
        assert!(apart <= 1e-14, "copies of a vertex {apart:.2e}·d apart on level {levels}");
        let points = welded(&refined, refined.positions().to_vec());
        // The first welded vertices of every level are the input's, in order.
        limits.iter().zip(&points).map(|(l, p)| (*l - *p).length() / d).fold(0.0, f64::max)
    };
    (deviation(levels), deviation(levels - 2))
}

#[test]
fn limits_are_where_refinement_goes() {
    // Three and four quads on one edge (a fin and a cross), their far sides open.
    let fin3 = mesh(
        &[
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [1., -0.5, 0.8],
            [0., -0.5, 0.8],
            [1., -0.6, -0.9],
            [0., -0.7, -0.8],
        ],
        &[&[0, 1, 2, 3], &[1, 0, 5, 4], &[0, 1, 6, 7]],
    );
    let cross = mesh(
        &[
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [1., 0., 1.],
            [0., 0., 1.],
            [1., -1., 0.1],
            [0., -1., 0.],
            [1., 0.1, -1.],
            [0., 0., -1.],
        ],
        &[&[0, 1, 2, 3], &[1, 0, 5, 4], &[0, 1, 6, 7], &[1, 0, 9, 8]],
    );
    // Two square pyramids (closed with their bases) touching at their apices: a bow-tie vertex.
    let mut p = vec![[0., 0., 0.]];
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for (side, z) in [(1u32, 1.0), (5, -1.0)] {
        for k in 0..4 {
            let a = std::f64::consts::FRAC_PI_2 * f64::from(k) + 0.3 * z;
            p.push([a.cos(), a.sin(), z]);
        }
        for k in 0..4 {
            let (a, b) = (side + k, side + (k + 1) % 4);
            faces.push(if z > 0.0 { vec![0, a, b] } else { vec![0, b, a] });
        }
        faces.push(if z > 0.0 { vec![side + 3, side + 2, side + 1, side] } else { (side..side + 4).collect() });
    }
    let face_refs: Vec<&[u32]> = faces.iter().map(Vec::as_slice).collect();
    let bowtie = mesh(&p, &face_refs);
    assert_eq!(bowtie.non_manifold().unwrap().corners, [0]);
    // A pole of degenerate quads (vertex 0 twice in a row), as OpenSubdiv's quadpole shapes.
    let mut p = vec![[0., 0., 0.5]];
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for k in 0..6 {
        let a = std::f64::consts::TAU * f64::from(k) / 6.0;
        p.push([a.cos(), a.sin(), 0.1 * f64::from(k % 2)]);
    }
    for k in 0..6u32 {
        faces.push(vec![0, 0, 1 + k, 1 + (k + 1) % 6]);
    }
    let face_refs: Vec<&[u32]> = faces.iter().map(Vec::as_slice).collect();
    let pole = mesh(&p, &face_refs);
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/opensubdiv/shapes");
    let shape = |name: &str| subdiv_io::load_mesh(fixtures.join(format!("{name}.obj"))).unwrap();
    let catmull_clark = Scheme::CatmullClark;
    let loop_ = Scheme::Loop(LoopBeta::Loop);
    let cases = [
        ("fin of 3 quads", fin3, catmull_clark),
        ("cross of 4 quads", cross, catmull_clark),
        ("bow-tie pyramids", bowtie, catmull_clark),
        ("degenerate quad pole", pole, catmull_clark),
        ("catmark_fan", shape("catmark_fan"), catmull_clark),
        ("catmark_nonman_verts", shape("catmark_nonman_verts"), catmull_clark),
        ("catmark_nonman_edges", shape("catmark_nonman_edges"), catmull_clark),
        ("loop_nonman_verts", shape("loop_nonman_verts"), loop_),
        ("loop_nonman_edges", shape("loop_nonman_edges"), loop_),
    ];
    for (name, mesh, scheme) in cases {
        assert!(mesh.welds().is_some(), "{name} is non-manifold");
        // 7 levels of the larger shapes (10⁵–10⁶ faces), 8 of the small ones.
        let levels = if mesh.topology().face_count() > 30 { 7 } else { 8 };
        let (at, before) = brute_force(&mesh, scheme, levels);
        println!("{name}: limit vs level {levels} {at:.2e}·d (level {} {before:.2e}·d)", levels - 2);
        assert!(at <= 2e-5, "{name}: {at:.2e}·d");
        assert!(at <= before, "{name}: refinement must approach the limit ({before:.2e} → {at:.2e})");
    }
}

/// A random soup over a few vertices, biased to non-manifold features: faces from a small pool
/// of vertex loops, some repeated, flipped, sharing edges with many others or an apex.
fn soups() -> impl Strategy<Value = PolygonSoup> {
    let positions = prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), 6..14);
    positions.prop_flat_map(|positions| {
        let n = positions.len() as u32;
        let face = prop::collection::vec(0..n, 3..6);
        prop::collection::vec(face, 1..14).prop_map(move |faces| {
            let positions = positions.iter().map(|p| DVec3::from_array(*p)).collect();
            PolygonSoup::new(positions, FaceList::from_faces(faces))
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn random_soups_are_refused_or_refined_with_agreeing_copies(soup in soups()) {
        let Ok((mesh, _)) = Mesh::from_soup_covering(soup) else { return Ok(()) };
        let d = mesh.bbox_diagonal();
        let triangles = mesh.topology().faces().all_of_size(3);
        for scheme in [Scheme::CatmullClark, Scheme::Loop(LoopBeta::Loop)] {
            if matches!(scheme, Scheme::Loop(_)) && !triangles {
                continue;
            }
            let refined = subdivide(&mesh, scheme, 2, false).unwrap();
            prop_assert!(copies_apart(&refined, d) <= 1e-12, "{scheme}: copies apart");
            let limits = subdivide(&mesh, scheme, 1, true).unwrap();
            prop_assert!(limits.positions().iter().all(|p| p.is_finite()));
            if let Some(welds) = refined.welds() {
                let faces = welds.faces(refined.topology());
                prop_assert!(faces.indices().iter().all(|&v| (v as usize) < welds.vertex_count()));
            }
        }
        // Doo-Sabin and √3 refuse a non-manifold mesh with a typed error.
        if mesh.welds().is_some() {
            prop_assert!(subdivide(&mesh, Scheme::DooSabin, 1, false).is_err());
        }
    }
}
