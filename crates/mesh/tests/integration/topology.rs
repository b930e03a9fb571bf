//! Topology invariants on procedural shapes, error detection, and property tests.

use glam::DVec3;
use proptest::prelude::*;
use subdiv_mesh::shapes::{self, polygon_mix};
use subdiv_mesh::{FaceList, Mesh, MeshError, PolygonSoup, Topology, VertexId, Warning};

/// Checks every structural invariant a consumer relies on.
fn assert_invariants(t: &Topology) {
    let mut boundary_half_edges = 0;
    for f in t.face_ids() {
        for h in t.face_half_edges(f) {
            assert_eq!(t.he_face(h), f);
            assert_eq!(t.he_prev(t.he_next(h)), h);
            assert_eq!(t.he_from(t.he_next(h)), t.he_to(h));
            match t.he_twin(h) {
                Some(g) => {
                    assert_eq!(t.he_twin(g), Some(h));
                    assert_eq!((t.he_from(g), t.he_to(g)), (t.he_to(h), t.he_from(h)));
                    assert_eq!(t.he_edge(g), t.he_edge(h));
                    assert_ne!(t.he_face(g), f);
                }
                None => boundary_half_edges += 1,
            }
        }
    }
    assert_eq!(2 * t.edge_count(), t.half_edge_count() + boundary_half_edges);
    let loop_edges: usize = t.boundary_loops().map(<[_]>::len).sum();
    assert_eq!(loop_edges, boundary_half_edges);
    for lp in t.boundary_loops() {
        for k in 0..lp.len() {
            assert_eq!(t.he_to(lp[k]), t.he_from(lp[(k + 1) % lp.len()]), "loop is connected");
        }
    }
    let mut corners_seen = 0;
    for v in t.vertices() {
        let fan = t.vertex_fan(v);
        corners_seen += fan.len();
        let nbrs: Vec<VertexId> = t.vertex_neighbors(v).collect();
        assert_eq!(nbrs.len(), t.valence(v));
        for (i, &h) in fan.iter().enumerate() {
            assert_eq!(t.he_from(h), v);
            // Face fᵢ = (V, Eᵢ, …, Eᵢ₊₁): it enters V from Eᵢ₊₁.
            let e_next = nbrs[(i + 1) % nbrs.len()];
            assert_eq!(t.he_from(t.he_prev(h)), e_next, "fan order at vertex {v}");
            let c = t.he_corner(h);
            assert_eq!(t.face(c.face)[c.index as usize], v.0);
        }
        if t.is_boundary_vertex(v) {
            assert!(t.he_twin(fan[0]).is_none());
            let (prev, next) = t.boundary_neighbors(v).unwrap();
            assert_eq!((prev, next), (nbrs[nbrs.len() - 1], nbrs[0]));
        }
    }
    assert_eq!(corners_seen, t.half_edge_count());
}

#[test]
fn platonic_solids_have_exact_combinatorics() {
    for (mesh, v, e, f, valence) in [
        (shapes::tetrahedron(), 4, 6, 4, 3),
        (shapes::cube(), 8, 12, 6, 3),
        (shapes::octahedron(), 6, 12, 8, 4),
        (shapes::icosahedron(), 12, 30, 20, 5),
    ] {
        let t = mesh.topology();
        assert_invariants(t);
        assert_eq!((t.vertex_count(), t.edge_count(), t.face_count()), (v, e, f));
        assert!(t.vertices().all(|x| t.valence(x) == valence && !t.is_boundary_vertex(x)));
        assert!(t.is_closed());
        assert_eq!((t.component_count(), t.genus(), t.euler_characteristic()), (1, Some(0), 2));
        // Outward orientation: the Newell normal of every face points away from the centre.
        for face in t.face_ids() {
            assert!(mesh.face_normal(face).dot(mesh.face_centroid(face) - DVec3::splat(mesh_center(&mesh))) > 0.0);
        }
    }
}

fn mesh_center(mesh: &Mesh) -> f64 {
    let b = mesh.bbox();
    (b.min.x + b.max.x) / 2.0
}

#[test]
fn grids_tori_prisms_plates() {
    let g = shapes::quad_grid(5, 3);
    let t = g.topology();
    assert_invariants(t);
    assert_eq!((t.vertex_count(), t.edge_count(), t.face_count()), (24, 5 * 4 + 6 * 3, 15));
    assert_eq!((t.boundary_loop_count(), t.genus()), (1, Some(0)));
    assert_eq!(t.boundary_loops().next().unwrap().len(), 16);
    assert_eq!(t.valence(VertexId(0)), 2);
    assert_eq!(t.valence(VertexId(1)), 3);
    assert_eq!(t.valence(VertexId(7)), 4);

    let tg = shapes::triangle_grid(4, 4);
    assert_invariants(tg.topology());
    assert_eq!(tg.topology().valence(VertexId(6)), 6);

    let torus = shapes::torus(8, 5);
    assert_invariants(torus.topology());
    assert_eq!((torus.topology().euler_characteristic(), torus.topology().genus()), (0, Some(1)));

    for n in 3..9 {
        let p = shapes::prism(n);
        assert_invariants(p.topology());
        assert_eq!(p.topology().genus(), Some(0));
        let pyr = shapes::pyramid(n);
        assert_eq!(pyr.topology().valence(VertexId(n as u32)), n);
    }
    let pillow = shapes::pillow();
    assert_invariants(pillow.topology());
    assert!(pillow.topology().vertices().all(|v| pillow.topology().valence(v) == 2));

    let holes = [(1, 1), (3, 1), (5, 3)];
    for k in 0..=holes.len() {
        let closed = shapes::plate_with_holes(7, 5, &holes[..k], true);
        assert_invariants(closed.topology());
        assert_eq!(closed.topology().genus(), Some(k as u32));
        assert!(closed.topology().is_closed());
        let open = shapes::plate_with_holes(7, 5, &holes[..k], false);
        assert_invariants(open.topology());
        assert_eq!((open.topology().boundary_loop_count(), open.topology().genus()), (k + 1, Some(0)));
    }
}

#[test]
fn two_components_are_counted() {
    let a = shapes::tetrahedron();
    let mut positions = a.positions().to_vec();
    positions.extend(a.positions().iter().map(|p| *p + DVec3::X * 5.0));
    let mut faces = a.topology().faces().clone();
    for f in a.topology().faces().iter() {
        faces.push(&f.iter().map(|&v| v + 4).collect::<Vec<_>>());
    }
    let m = Mesh::new(positions, faces).unwrap();
    assert_eq!(m.topology().component_count(), 2);
    assert_eq!(m.topology().euler_characteristic(), 4);
    assert_eq!(m.topology().genus(), Some(0));
}

fn soup(positions: usize, faces: &[&[u32]]) -> PolygonSoup {
    let p = (0..positions).map(|i| DVec3::new(i as f64, (i * i % 7) as f64, (i % 3) as f64)).collect();
    PolygonSoup::new(p, FaceList::from_faces(faces.iter().copied()))
}

#[test]
fn every_error_names_its_element() {
    let tet: [&[u32]; 4] = [&[0, 1, 2], &[0, 2, 3], &[0, 3, 1], &[1, 3, 2]];
    // Both entry points refuse alike; `try_from_soup` gives the soup back as it was.
    let err = |s: PolygonSoup| {
        let rejected = Mesh::try_from_soup(s.clone()).expect_err("must be rejected");
        // (Debug text: a NaN coordinate is not == itself.)
        assert_eq!(format!("{:?}", rejected.soup), format!("{s:?}"), "the refused soup comes back unchanged");
        assert_eq!(format!("{:?}", Mesh::from_soup(s).expect_err("must be rejected")), format!("{:?}", rejected.error));
        rejected.error
    };

    assert_eq!(err(soup(4, &[])), MeshError::NoFaces);
    assert_eq!(err(soup(4, &[&[0, 1]])), MeshError::FaceTooSmall { face: 0, size: 2 });
    assert_eq!(err(soup(4, &[&[0, 1, 7]])), MeshError::IndexOutOfRange { face: 0, vertex: 7, vertex_count: 4 });
    assert_eq!(err(soup(4, &[&[0, 1, 2, 1]])), MeshError::RepeatedIndex { face: 0, vertex: 1 });
    let mut nan = soup(4, &tet);
    nan.positions[2].y = f64::NAN;
    assert!(matches!(err(nan), MeshError::NonFiniteCoordinate { vertex: 2, .. }));
    // Fourth face reversed: edges traversed twice in the same direction.
    let flipped: [&[u32]; 4] = [&[0, 1, 2], &[0, 2, 3], &[0, 3, 1], &[2, 3, 1]];
    assert!(matches!(err(soup(4, &flipped)), MeshError::InconsistentOrientation { .. }));
    // Three triangles on edge (0, 1).
    let fin: [&[u32]; 3] = [&[0, 1, 2], &[1, 0, 3], &[0, 1, 4]];
    assert_eq!(err(soup(5, &fin)), MeshError::NonManifoldEdge { a: 0, b: 1, faces: 3 });
    // Bow-tie: two triangles sharing only vertex 0 (open fans).
    let bowtie: [&[u32]; 2] = [&[0, 1, 2], &[0, 3, 4]];
    assert_eq!(err(soup(5, &bowtie)), MeshError::NonManifoldVertex { vertex: 0, fans: 2 });
    // Two closed tetrahedra sharing vertex 0 (closed fans).
    let two_tets: [&[u32]; 8] =
        [&[0, 1, 2], &[0, 2, 3], &[0, 3, 1], &[1, 3, 2], &[0, 4, 5], &[0, 5, 6], &[0, 6, 4], &[4, 6, 5]];
    assert_eq!(err(soup(7, &two_tets)), MeshError::NonManifoldVertex { vertex: 0, fans: 2 });
    // Valid connectivity, every vertex in one place.
    let mut point = soup(4, &tet);
    point.positions.fill(glam::DVec3::ONE);
    assert!(matches!(err(point), MeshError::AllVerticesCoincide { vertices: 4, .. }));
    for e in [MeshError::NonManifoldEdge { a: 0, b: 1, faces: 3 }, MeshError::NonManifoldVertex { vertex: 0, fans: 2 }]
    {
        assert!(e.to_string().contains('0'));
    }
}

#[test]
fn warnings_and_repair() {
    let mut s = shapes::tetrahedron().into_soup();
    s.positions.push(DVec3::new(9.0, 9.0, 9.0));
    s.positions.insert(0, DVec3::new(-9.0, 0.0, 0.0));
    let shifted: Vec<u32> = s.faces.indices().iter().map(|&v| v + 1).collect();
    s.faces = FaceList::from_raw(s.faces.offsets().to_vec(), shifted);
    let (mesh, warnings) = Mesh::from_soup(s.clone()).unwrap();
    assert_eq!(warnings, vec![Warning::IsolatedVertices { vertices: vec![0, 5] }]);
    assert_eq!(mesh.topology().valence(VertexId(0)), 0);
    assert_eq!(mesh.topology().euler_characteristic(), 2);
    // The bounding box ignores isolated vertices.
    assert!(mesh.bbox_diagonal() < 4.0);
    let (repaired, map) = s.without_isolated_vertices();
    assert_eq!(map, vec![None, Some(0), Some(1), Some(2), Some(3), None]);
    let (_, w) = Mesh::from_soup(repaired).unwrap();
    assert!(w.is_empty());

    let mut flat = shapes::pyramid(4).into_soup();
    flat.positions[4] = DVec3::new(1.0, 0.0, 0.0); // apex onto a base corner's line
    flat.positions[4] = (flat.positions[0] + flat.positions[1]) / 2.0;
    let (_, w) = Mesh::from_soup(flat).unwrap();
    assert!(matches!(&w[..], [Warning::ZeroAreaFaces { faces }] if faces == &vec![1]));
}

#[test]
fn normals_are_angle_weighted() {
    // On a cube corner the three faces meet at right angles: the normal is the diagonal.
    let cube = shapes::cube();
    let n = cube.vertex_normals();
    let expected = DVec3::new(-1.0, -1.0, -1.0).normalize();
    assert!((n[0] - expected).length() < 1e-15);
    // A pyramid apex: unequal angles still give a unit normal along the axis by symmetry.
    let pyr = shapes::pyramid(5);
    assert!((pyr.vertex_normals()[5] - DVec3::Z).length() < 1e-12);
    // On the icosahedron every vertex normal is radial.
    let ico = shapes::icosahedron();
    for (p, n) in ico.positions().iter().zip(ico.vertex_normals()) {
        assert!((p.normalize() - n).length() < 1e-12);
    }
}

fn generated_mesh() -> impl Strategy<Value = Mesh> {
    (3usize..9, 3usize..9, 0usize..4, any::<bool>(), any::<u64>(), 0.0f64..0.5, 0.0f64..0.5).prop_map(
        |(nx, ny, nholes, closed, seed, merge, split)| {
            let (nx, ny) = (nx + 2 * nholes, ny);
            let holes: Vec<(usize, usize)> = (0..nholes).map(|k| (1 + 2 * k, 1)).collect();
            let base = shapes::plate_with_holes(nx, ny.max(3), &holes, closed);
            polygon_mix(&base, seed, merge, split, 0.1)
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn generated_meshes_satisfy_invariants(mesh in generated_mesh()) {
        assert_invariants(mesh.topology());
    }

    #[test]
    fn relabelled_faces_give_the_same_counts(mesh in generated_mesh(), seed in any::<u64>()) {
        // Rotating every face's corner list and permuting faces must not change the topology summary.
        let t = mesh.topology();
        let mut rng = shapes::SplitMix64(seed);
        let mut faces: Vec<Vec<u32>> = t.faces().iter().map(|f| {
            let r = rng.below(f.len());
            (0..f.len()).map(|k| f[(k + r) % f.len()]).collect()
        }).collect();
        for i in (1..faces.len()).rev() { faces.swap(i, rng.below(i + 1)); }
        let other = Topology::new(FaceList::from_faces(faces), t.vertex_count()).unwrap();
        prop_assert_eq!(other.edge_count(), t.edge_count());
        prop_assert_eq!(other.genus(), t.genus());
        prop_assert_eq!(other.boundary_loop_count(), t.boundary_loop_count());
        prop_assert_eq!(other.valence_histogram(), t.valence_histogram());
        prop_assert_eq!(other.component_count(), t.component_count());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn polygon_mix_creates_no_valence_two_vertices(seed in any::<u64>(), merge in 0.0f64..0.6) {
        let base = shapes::torus(10, 8);
        let mixed = polygon_mix(&base, seed, merge, 0.3, 0.0);
        let t = mixed.topology();
        prop_assert!(t.vertices().all(|v| t.valence(v) >= 3));
    }
}

/// Rotates a cyclic sequence to start at its smallest element.
fn canonical_cycle(s: &[subdiv_mesh::HalfEdgeId]) -> Vec<u32> {
    let k = (0..s.len()).min_by_key(|&i| s[i].0).unwrap_or(0);
    (0..s.len()).map(|i| s[(k + i) % s.len()].0).collect()
}

/// How closely a direct split must match the one rebuilt by `Topology::new`.
#[derive(Clone, Copy, PartialEq)]
enum Match {
    /// Interior fans and boundary loops may start elsewhere on their cycle
    /// (the quad and triangle splits inherit the coarse fans' starts).
    UpToRotation,
    /// Every field equal, in order (the dual split); the `Debug` output, which
    /// lists every field, is compared last as a catch-all.
    Exact,
}

/// A direct split (index arithmetic) equals the one rebuilt from its face
/// list by `Topology::new`, element by element: faces, per-half-edge face,
/// twin and edge, per-edge half-edge, boundary flags, fans, boundary loops,
/// components.
fn assert_same_topology(direct: &Topology, rebuilt: &Topology, how: Match) {
    assert_eq!(direct.vertex_count(), rebuilt.vertex_count());
    assert_eq!(direct.faces(), rebuilt.faces());
    assert_eq!(direct.half_edge_count(), rebuilt.half_edge_count());
    for f in direct.face_ids() {
        for h in direct.face_half_edges(f) {
            assert_eq!(direct.he_face(h), rebuilt.he_face(h), "face of {h}");
            assert_eq!(direct.he_twin(h), rebuilt.he_twin(h), "twin of {h}");
            assert_eq!(direct.he_edge(h), rebuilt.he_edge(h), "edge of {h}");
        }
    }
    assert_eq!(direct.edge_count(), rebuilt.edge_count());
    for e in direct.edges() {
        assert_eq!(direct.edge_half_edge(e), rebuilt.edge_half_edge(e), "half-edge of edge {e}");
    }
    for v in direct.vertices() {
        assert_eq!(direct.is_boundary_vertex(v), rebuilt.is_boundary_vertex(v), "boundary flag of {v}");
        if how == Match::Exact || direct.is_boundary_vertex(v) {
            assert_eq!(direct.vertex_fan(v), rebuilt.vertex_fan(v), "fan of {v}");
        } else {
            assert_eq!(canonical_cycle(direct.vertex_fan(v)), canonical_cycle(rebuilt.vertex_fan(v)), "fan of {v}");
        }
    }
    match how {
        Match::Exact => {
            assert_eq!(direct.boundary_loops().collect::<Vec<_>>(), rebuilt.boundary_loops().collect::<Vec<_>>())
        }
        Match::UpToRotation => {
            let loops = |t: &Topology| {
                let mut l: Vec<Vec<u32>> = t.boundary_loops().map(canonical_cycle).collect();
                l.sort();
                l
            };
            assert_eq!(loops(direct), loops(rebuilt));
        }
    }
    assert_eq!(direct.component_count(), rebuilt.component_count());
    for f in direct.face_ids() {
        assert_eq!(direct.face_component(f), rebuilt.face_component(f), "component of face {f}");
    }
    assert_eq!(direct.genus(), rebuilt.genus());
    if how == Match::Exact {
        assert_eq!(format!("{direct:?}"), format!("{rebuilt:?}"));
    }
}

#[test]
fn direct_quad_split_equals_the_validated_one_on_shapes() {
    use subdiv_mesh::internals::quad_split_by_validation;
    use subdiv_mesh::refine::quad_split;
    let mut with_isolated = shapes::cube().into_soup();
    with_isolated.positions.push(DVec3::new(3.0, 3.0, 3.0));
    let isolated = Mesh::from_soup(with_isolated).unwrap().0;
    for mesh in [
        shapes::cube(),
        shapes::quad_grid(3, 2),
        shapes::pillow(),
        shapes::pyramid(5),
        isolated,
        shapes::plate_with_holes(6, 5, &[(2, 2)], false),
    ] {
        let t = mesh.topology();
        assert_same_topology(&quad_split(t), &quad_split_by_validation(t), Match::UpToRotation);
        let twice = quad_split(&quad_split(t));
        assert_same_topology(&twice, &quad_split_by_validation(&quad_split_by_validation(t)), Match::UpToRotation);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn direct_quad_split_equals_the_validated_one(mesh in generated_mesh()) {
        let t = mesh.topology();
        assert_same_topology(&subdiv_mesh::refine::quad_split(t), &subdiv_mesh::internals::quad_split_by_validation(t), Match::UpToRotation);
    }
}

fn triangulated(mesh: &Mesh) -> Mesh {
    subdiv_mesh::triangulate(mesh).unwrap().mesh
}

#[test]
fn direct_triangle_split_equals_the_validated_one_on_shapes() {
    use subdiv_mesh::internals::triangle_split_by_validation;
    use subdiv_mesh::refine::triangle_split;
    for mesh in [
        shapes::tetrahedron(),
        shapes::icosahedron(),
        shapes::triangle_grid(3, 2),
        triangulated(&shapes::plate_with_holes(6, 5, &[(2, 2)], false)),
    ] {
        let t = mesh.topology();
        let direct = triangle_split(t).unwrap();
        assert_same_topology(&direct, &triangle_split_by_validation(t).unwrap(), Match::UpToRotation);
        assert_same_topology(
            &triangle_split(&direct).unwrap(),
            &triangle_split_by_validation(&direct).unwrap(),
            Match::UpToRotation,
        );
    }
    assert!(triangle_split(shapes::cube().topology()).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn direct_triangle_split_equals_the_validated_one(mesh in generated_mesh()) {
        let tri = triangulated(&mesh);
        let t = tri.topology();
        assert_same_topology(&subdiv_mesh::refine::triangle_split(t).unwrap(), &subdiv_mesh::internals::triangle_split_by_validation(t).unwrap(), Match::UpToRotation);
    }
}

/// The direct Doo-Sabin split and its provenance equal the validated ones
/// exactly; returns the direct split.
fn assert_dual_split_matches(t: &Topology) -> Topology {
    use subdiv_mesh::internals::dual_split_by_validation;
    use subdiv_mesh::refine::dual_split;
    let (direct, dp) = dual_split(t);
    let (rebuilt, rp) = dual_split_by_validation(t);
    assert_same_topology(&direct, &rebuilt, Match::Exact);
    assert_invariants(&direct);
    assert_eq!(dp.vertex_origin, rp.vertex_origin);
    assert_eq!(dp.face_origin, rp.face_origin);
    assert_eq!(dp.vertex_face, rp.vertex_face);
    assert_eq!(dp.boundary_point, rp.boundary_point);
    direct
}

/// `mesh` with a new vertex at the midpoint of edge `e`: an interior valence-2
/// vertex (or, on a boundary edge, a boundary vertex with one face).
fn with_vertex_on_edge(mesh: &Mesh, e: subdiv_mesh::EdgeId) -> Mesh {
    let t = mesh.topology();
    let (a, b) = t.edge_vertices(e);
    let w = t.vertex_count() as u32;
    let mut faces = FaceList::new();
    for f in t.faces().iter() {
        let mut face = Vec::with_capacity(f.len() + 1);
        for (k, &x) in f.iter().enumerate() {
            face.push(x);
            let y = f[(k + 1) % f.len()];
            if (x, y) == (a.0, b.0) || (x, y) == (b.0, a.0) {
                face.push(w);
            }
        }
        faces.push(&face);
    }
    let mut positions = mesh.positions().to_vec();
    positions.push((mesh.position(a) + mesh.position(b)) / 2.0);
    Mesh::new(positions, faces).unwrap()
}

/// Two copies of `mesh`, the second shifted, as one mesh of two components.
fn two_copies(mesh: &Mesh) -> Mesh {
    let n = mesh.topology().vertex_count() as u32;
    let mut positions = mesh.positions().to_vec();
    positions.extend(mesh.positions().iter().map(|p| *p + DVec3::X * 10.0));
    let mut faces = mesh.topology().faces().clone();
    for f in mesh.topology().faces().iter() {
        faces.push(&f.iter().map(|&v| v + n).collect::<Vec<_>>());
    }
    Mesh::new(positions, faces).unwrap()
}

#[test]
fn direct_dual_split_equals_the_validated_one_on_shapes() {
    use subdiv_mesh::refine::{dual_split, quad_split, triangle_split};
    let mut with_isolated = shapes::quad_grid(3, 2).into_soup();
    with_isolated.positions.insert(0, DVec3::new(9.0, 9.0, 9.0));
    with_isolated.positions.push(DVec3::new(-9.0, 9.0, 9.0));
    let shifted: Vec<u32> = with_isolated.faces.indices().iter().map(|&v| v + 1).collect();
    with_isolated.faces = FaceList::from_raw(with_isolated.faces.offsets().to_vec(), shifted);
    let isolated = Mesh::from_soup(with_isolated).unwrap().0;
    assert!(isolated.topology().is_isolated(VertexId(0)));
    let holes = [(1, 1), (3, 3), (5, 1)];
    let cube = shapes::cube();
    let cube_edge = with_vertex_on_edge(&cube, subdiv_mesh::EdgeId(0));
    let grid_edge = with_vertex_on_edge(&shapes::quad_grid(3, 3), subdiv_mesh::EdgeId(5));
    assert!(cube_edge.topology().vertices().any(|v| cube_edge.topology().valence(v) == 2));
    let open_grid = shapes::quad_grid(4, 3);
    let boundary_edge = open_grid.topology().edges().find(|&e| open_grid.topology().is_boundary_edge(e)).unwrap();
    let shapes = [
        shapes::tetrahedron(),
        cube.clone(),
        shapes::icosahedron(),
        shapes::quad_grid(1, 1),
        shapes::quad_grid(4, 3),
        shapes::triangle_grid(3, 2),
        shapes::torus(5, 4),
        shapes::prism(12),
        shapes::pyramid(9),
        shapes::pillow(),
        two_copies(&shapes::pillow()),
        cube_edge,
        grid_edge,
        with_vertex_on_edge(&open_grid, boundary_edge),
        isolated,
        two_copies(&cube),
        two_copies(&shapes::plate_with_holes(7, 5, &holes[..2], false)),
        shapes::plate_with_holes(7, 5, &holes, false),
        shapes::plate_with_holes(7, 5, &holes, true),
        shapes::polygon_mix(&shapes::plate_with_holes(7, 5, &holes, false), 3, 0.5, 0.3, 0.1),
        shapes::polygon_mix(&shapes::plate_with_holes(7, 5, &holes, true), 4, 0.5, 0.3, 0.1),
        shapes::polygon_mix(&shapes::torus(12, 9), 5, 0.6, 0.2, 0.1),
    ];
    for mesh in &shapes {
        let t = mesh.topology();
        let once = assert_dual_split_matches(t);
        // Refined meshes as input: one built directly, their loops not
        // necessarily starting at their smallest half-edge.
        assert_dual_split_matches(&once);
        assert_dual_split_matches(&quad_split(t));
        if t.faces().all_of_size(3) {
            assert_dual_split_matches(&triangle_split(t).unwrap());
        }
    }
    let (pillow, _) = dual_split(shapes::pillow().topology());
    assert_eq!((pillow.vertex_count(), pillow.face_count()), (8, 2 + 4));
    assert!(pillow.vertices().all(|v| pillow.valence(v) == 3));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn direct_dual_split_equals_the_validated_one(mesh in generated_mesh(), edge in any::<u32>()) {
        assert_dual_split_matches(mesh.topology());
        // A vertex on a random edge: an interior valence-2 vertex, or a boundary vertex with one face.
        let e = subdiv_mesh::EdgeId(edge % mesh.topology().edge_count() as u32);
        assert_dual_split_matches(with_vertex_on_edge(&mesh, e).topology());
    }
}

/// The counts `subdiv info` prints, each against a count made here from
/// the face list alone: undirected edges as distinct vertex pairs, boundary
/// edges as pairs used once, valences as distinct neighbours, face sizes
/// one by one.
fn counts_match_brute_force(t: &Topology) -> Result<(), TestCaseError> {
    use std::collections::{BTreeMap, BTreeSet, HashMap};
    let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
    let mut neighbours: Vec<BTreeSet<u32>> = vec![BTreeSet::new(); t.vertex_count()];
    let mut sizes = BTreeMap::new();
    for face in t.faces().iter() {
        *sizes.entry(face.len()).or_insert(0) += 1;
        for (k, &a) in face.iter().enumerate() {
            let b = face[(k + 1) % face.len()];
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            neighbours[a as usize].insert(b);
            neighbours[b as usize].insert(a);
        }
    }
    let mut valences = BTreeMap::new();
    for n in &neighbours {
        *valences.entry(n.len()).or_insert(0) += 1;
    }
    prop_assert_eq!(t.edge_count(), uses.len());
    prop_assert_eq!(t.edges().count(), uses.len());
    prop_assert_eq!(t.boundary_edge_count(), uses.values().filter(|&&n| n == 1).count());
    prop_assert_eq!(t.boundary_edge_count(), t.edges().filter(|&e| t.is_boundary_edge(e)).count());
    prop_assert_eq!(t.valence_histogram(), valences);
    prop_assert_eq!(t.faces().size_histogram(), sizes);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn counts_equal_brute_force_counts(mesh in generated_mesh()) {
        counts_match_brute_force(mesh.topology())?;
    }
}

#[test]
fn counts_of_a_big_mixed_mesh_equal_brute_force_counts() {
    // Past the thresholds where construction and counting run across
    // threads (2¹⁶ corners, blocks of 2¹⁴ faces and 2¹⁶ vertices), open and
    // closed, with faces of many sizes.
    let plate = shapes::plate_with_holes(300, 260, &[(5, 5), (40, 9)], false);
    // (shape, merge, split): all quads (the face of a half-edge by
    // arithmetic), then mixed sizes (by table).
    for (base, merge, split) in
        [(shapes::torus(320, 240), 0.0, 0.0), (shapes::torus(320, 240), 0.3, 0.2), (plate, 0.3, 0.2)]
    {
        let mixed = polygon_mix(&base, 7, merge, split, 0.0);
        assert!(mixed.topology().vertex_count() > 1 << 16);
        counts_match_brute_force(mixed.topology()).unwrap();
        // The same topology rebuilt from its faces: the lazily numbered
        // edges and the face of every half-edge agree with a fresh build.
        let t = mixed.topology();
        let rebuilt = Topology::new(t.faces().clone(), t.vertex_count()).unwrap();
        assert_eq!(format!("{rebuilt:?}"), format!("{t:?}"));
    }
}

/// The fitting starts of `shapes`: `perturbed` moves every vertex by exactly
/// `fraction`·d, `smoothly_perturbed` by at most that (neighbours alike),
/// `bumpy_torus` moves radially within ±amplitude; all keep the faces and
/// repeat bit for bit from the seed.
#[test]
fn fitting_starts_move_as_documented() {
    let torus = shapes::torus(12, 8);
    let d = torus.bbox_diagonal();
    let moved = shapes::perturbed(&torus, 0.02, 7);
    for (a, b) in torus.positions().iter().zip(moved.positions()) {
        assert!(((*a - *b).length() - 0.02 * d).abs() <= 1e-12 * d);
    }
    let smooth = shapes::smoothly_perturbed(&torus, 0.02, 7);
    let steps: Vec<f64> = torus.positions().iter().zip(smooth.positions()).map(|(a, b)| (*a - *b).length()).collect();
    assert!(steps.iter().all(|&s| s <= 0.02 * d * (1.0 + 1e-12)));
    assert!(steps.iter().any(|&s| s > 0.002 * d), "the field moves the mesh");
    // Smooth: the displacements of the two ends of an edge differ far less than 2·fraction·d.
    let t = torus.topology();
    for e in t.edges() {
        let (a, b) = t.edge_vertices(e);
        let da = smooth.position(a) - torus.position(a);
        let db = smooth.position(b) - torus.position(b);
        assert!((da - db).length() <= 0.25 * 0.02 * d);
    }
    let bumpy = shapes::bumpy_torus(12, 8, 0.075, 7);
    for (a, b) in torus.positions().iter().zip(bumpy.positions()) {
        let axis = DVec3::new(a.x, a.y, 0.0).normalize() * 2.0;
        let off = *b - *a;
        assert!(off.length() <= 0.075 * (1.0 + 1e-12));
        assert!(off.cross(*a - axis).length() <= 1e-12, "radial from the tube's axis");
    }
    for m in [&moved, &smooth, &bumpy] {
        assert_eq!(m.topology().faces(), t.faces());
    }
    assert_eq!(shapes::perturbed(&torus, 0.02, 7).positions(), moved.positions());
    assert_eq!(shapes::smoothly_perturbed(&torus, 0.02, 7).positions(), smooth.positions());
}
