//! The √3 split built by index arithmetic equals, element by element, the
//! same triangle list validated from scratch, at both parities and over
//! several levels; counts and provenance as documented.

use proptest::prelude::*;
use subdiv_mesh::internals::sqrt3_split_by_validation;
use subdiv_mesh::refine::{sqrt3_split, Sqrt3Provenance, Sqrt3Vertex};
use subdiv_mesh::shapes::{self, polygon_mix};
use subdiv_mesh::{FaceList, Mesh, MeshError, Topology, VertexId};

fn triangulated(mesh: &Mesh) -> Mesh {
    subdiv_mesh::triangulate(mesh).unwrap().mesh
}

/// `levels` √3 steps (odd, even, odd, …) each checked against the
/// validated rebuild: everything the queries see (the `Debug` form) is equal.
fn check_levels(t: &Topology, levels: usize) -> Topology {
    let mut t = t.clone();
    for level in 0..levels {
        let trisect = level % 2 == 1;
        let (direct, provenance) = sqrt3_split(&t, trisect).unwrap();
        let rebuilt = sqrt3_split_by_validation(&t, trisect).unwrap();
        assert_eq!(format!("{direct:?}"), format!("{rebuilt:?}"), "level {}", level + 1);
        // Counts: V + F (+ B), one triangle per old corner, boundary tripled when trisecting.
        let b = t.boundary_edge_count();
        assert_eq!(direct.vertex_count(), t.vertex_count() + t.face_count() + if trisect { b } else { 0 });
        assert_eq!(direct.face_count(), 3 * t.face_count());
        assert_eq!(direct.boundary_edge_count(), if trisect { 3 * b } else { b });
        assert_eq!(direct.euler_characteristic(), t.euler_characteristic());
        assert_eq!(direct.boundary_loop_count(), t.boundary_loop_count());
        assert_eq!(direct.component_count(), t.component_count());
        assert_eq!(provenance.vertex_count(), direct.vertex_count());
        check_provenance(&t, &direct, &provenance);
        t = direct;
    }
    t
}

/// Every new vertex sits where its provenance says: old vertices keep their
/// boundary status; centroids are interior with one edge to each corner of
/// their triangle; trisection points lie on the boundary.
fn check_provenance(parent: &Topology, child: &Topology, p: &Sqrt3Provenance) {
    for v in child.vertices() {
        match p.origin(v) {
            Sqrt3Vertex::Old(old) => {
                assert_eq!(old, v);
                assert_eq!(child.is_boundary_vertex(v), parent.is_boundary_vertex(v));
                if !parent.is_isolated(v) && !parent.is_boundary_vertex(v) {
                    // After the flips an interior vertex's neighbours are the
                    // points of its triangles: one per triangle, two (the
                    // trisection points) for a triangle whose boundary edge
                    // a trisecting step splits.
                    let boundary_faces = parent
                        .vertex_fan(v)
                        .iter()
                        .filter(|&&h| p.trisects && parent.he_twin(parent.he_next(h)).is_none())
                        .count();
                    assert_eq!(child.valence(v), parent.valence(v) + boundary_faces, "vertex {v}");
                    for n in child.vertex_neighbors(v) {
                        assert!(!matches!(p.origin(n), Sqrt3Vertex::Old(_)), "vertex {v}");
                    }
                }
            }
            Sqrt3Vertex::Centroid(f) => {
                assert!(!child.is_boundary_vertex(v));
                for &corner in parent.face(f) {
                    assert!(child.find_edge(v, VertexId(corner)).is_some(), "centroid {v} joins {corner}");
                }
            }
            Sqrt3Vertex::Trisection { half_edge, .. } => {
                assert!(p.trisects && parent.he_twin(half_edge).is_none());
                assert!(child.is_boundary_vertex(v));
                assert_eq!(child.valence(v), 4, "a trisection point: 2 boundary, 2 interior edges");
            }
        }
    }
}

#[test]
fn direct_split_equals_the_validated_one_on_shapes() {
    let lone = Mesh::from_soup(subdiv_mesh::PolygonSoup::new(
        vec![glam::DVec3::ZERO, glam::DVec3::X, glam::DVec3::Y],
        FaceList::from_faces(vec![vec![0, 1, 2]]),
    ))
    .unwrap()
    .0;
    let meshes = [
        ("tetrahedron", shapes::tetrahedron(), 4),
        ("icosahedron", shapes::icosahedron(), 4),
        ("octahedron", shapes::octahedron(), 3),
        ("triangle grid", shapes::triangle_grid(3, 2), 4),
        ("one triangle", lone, 4),
        ("plate with holes", triangulated(&shapes::plate_with_holes(6, 5, &[(2, 2)], false)), 3),
        ("torus", triangulated(&shapes::torus(6, 4)), 2),
        ("pyramid", triangulated(&shapes::pyramid(7)), 3),
    ];
    for (name, mesh, levels) in meshes {
        let t = check_levels(mesh.topology(), levels);
        assert!(t.face_count() > 0, "{name}");
    }
}

#[test]
fn counts_of_two_steps_are_a_one_to_nine_refinement() {
    let ico = shapes::icosahedron();
    let (one, _) = sqrt3_split(ico.topology(), false).unwrap();
    assert_eq!((one.vertex_count(), one.face_count()), (32, 60));
    let (two, _) = sqrt3_split(&one, true).unwrap();
    assert_eq!((two.vertex_count(), two.face_count()), (92, 180));
    // Valences: old vertices keep theirs, every face point has 6.
    assert!(two.vertices().skip(12).all(|v| two.valence(v) == 6));
    assert!(two.vertices().take(12).all(|v| two.valence(v) == 5));
}

#[test]
fn refusals() {
    assert!(matches!(sqrt3_split(shapes::cube().topology(), false), Err(MeshError::NotTriangles { face: 0, size: 4 })));
    // A triangle with three boundary edges cannot be trisected directly.
    let grid = shapes::triangle_grid(1, 1);
    assert!(matches!(
        sqrt3_split(grid.topology(), true),
        Err(MeshError::TrisectionNeedsOneBoundaryEdge { boundary_edges: 2, .. })
    ));
}

fn generated_mesh() -> impl Strategy<Value = Mesh> {
    (3usize..7, 3usize..7, 0usize..3, any::<bool>(), any::<u64>(), 0.0f64..0.4, 0.0f64..0.4).prop_map(
        |(nx, ny, nholes, closed, seed, merge, split)| {
            let nx = nx + 2 * nholes;
            let holes: Vec<(usize, usize)> = (0..nholes).map(|k| (1 + 2 * k, 1)).collect();
            let base = shapes::plate_with_holes(nx, ny, &holes, closed);
            triangulated(&polygon_mix(&base, seed, merge, split, 0.1))
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn direct_split_equals_the_validated_one(mesh in generated_mesh()) {
        check_levels(mesh.topology(), 3);
    }
}
