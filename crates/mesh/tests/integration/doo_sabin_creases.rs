//! The Doo-Sabin split with infinitely sharp creases and corners
//! (`refine::dual_split_tagged`): at every level the refined mesh is a valid
//! manifold (the direct construction equals `Topology::new` on its faces,
//! field by field), keeps the Euler characteristic, genus, components and
//! boundary loops, and its tags carry the refined crease polygon and the
//! corners to the next level.

use proptest::prelude::*;
use subdiv_mesh::internals::dual_split_tagged_by_validation;
use subdiv_mesh::refine::{dual_split, dual_split_tagged, DualFeatures, SharpPoint};
use subdiv_mesh::shapes::{self, SplitMix64};
use subdiv_mesh::{EdgeTag, Mesh, TagList, Tags, Topology, VertexId, VertexTag, SHARPNESS_INFINITE};

/// Tags with the given creases (vertex pairs) and corners, all at 10.
fn tags(t: &Topology, creases: &[(u32, u32)], corners: &[u32]) -> Tags {
    let list = TagList {
        creases: creases.iter().map(|&(a, b)| EdgeTag { a, b, sharpness: SHARPNESS_INFINITE }).collect(),
        corners: corners.iter().map(|&vertex| VertexTag { vertex, sharpness: SHARPNESS_INFINITE }).collect(),
        ..Default::default()
    };
    Tags::from_list(t, &list).expect("the test tags name edges and vertices of the mesh")
}

/// Number of sharp (crease or boundary) edges at `v`.
fn sharp_count(t: &Topology, f: &DualFeatures, v: VertexId) -> usize {
    f.sharp_neighbors(t, v).count()
}

/// One tagged split checked against the validated one and against the
/// counts the construction implies; returns the refined level.
fn checked_split(name: &str, t: &Topology, tags: &Tags) -> (Topology, Tags) {
    let (direct, provenance, new_tags) = dual_split_tagged(t, tags);
    let (validated, _, validated_tags) = dual_split_tagged_by_validation(t, tags)
        .unwrap_or_else(|e| panic!("{name}: the tagged split is not a valid mesh: {e}"));
    assert_eq!(format!("{direct:?}"), format!("{validated:?}"), "{name}: direct and validated splits differ");
    assert_eq!(new_tags, validated_tags);
    assert_eq!(direct.euler_characteristic(), t.euler_characteristic(), "{name}");
    assert_eq!(direct.genus(), t.genus(), "{name}");
    assert_eq!(direct.boundary_loop_count(), t.boundary_loop_count(), "{name}");
    assert_eq!(direct.component_count(), t.component_count(), "{name}");
    assert_eq!(direct.vertex_count(), t.half_edge_count() + provenance.sharp_points.len(), "{name}");
    assert_eq!(provenance.face_origin.len(), direct.face_count(), "{name}");

    // The refined sharp polygon: one piece per crease edge (two when both
    // ends are corners) and one at every interior vertex with exactly two
    // creases that is no corner.
    let features = DualFeatures::new(t, tags);
    let mut pieces = 0;
    for e in t.edges().filter(|&e| features.is_crease(e)) {
        let (a, b) = t.edge_vertices(e);
        pieces += 1 + usize::from(features.is_corner(a) && features.is_corner(b));
    }
    let crease_vertices = t
        .vertices()
        .filter(|&v| !t.is_boundary_vertex(v) && !features.is_corner(v) && sharp_count(t, &features, v) == 2)
        .count();
    assert_eq!(new_tags.crease_count(), pieces + crease_vertices, "{name}: crease edges of the refined level");
    assert!(new_tags.edge_values().iter().all(|&s| s == 0.0 || s >= SHARPNESS_INFINITE), "{name}");

    // Corners stay corners (as their points), and nothing else becomes one;
    // darts stay darts.
    let refined = DualFeatures::new(&direct, &new_tags);
    let mut corners: Vec<u32> =
        t.vertices().filter(|&v| features.is_corner(v)).map(|v| provenance.corner_point[v.index()]).collect();
    corners.sort_unstable();
    let new_corners: Vec<u32> = direct.vertices().filter(|&v| refined.is_corner(v)).map(|v| v.0).collect();
    assert_eq!(new_corners, corners, "{name}: corners of the refined level");
    let darts =
        |t: &Topology, f: &DualFeatures| t.vertices().filter(|&v| !f.is_corner(v) && sharp_count(t, f, v) == 1).count();
    assert_eq!(darts(&direct, &refined), darts(t, &features), "{name}: darts");
    for (i, point) in provenance.sharp_points.iter().enumerate() {
        let v = VertexId((t.half_edge_count() + i) as u32);
        match *point {
            SharpPoint::Corner { .. } => assert!(refined.is_corner(v), "{name}: corner point {v}"),
            _ => assert!(sharp_count(&direct, &refined, v) >= 1, "{name}: sharp point {v} on no sharp edge"),
        }
    }
    (direct, new_tags)
}

/// Levels 1..=`levels` of the tagged split, each checked.
fn check_levels(name: &str, mesh: &Mesh, tags: Tags, levels: usize) -> Vec<(Topology, Tags)> {
    let mut out = vec![(mesh.topology().clone(), tags)];
    for level in 1..=levels {
        let (t, tags) = out.last().expect("level 0");
        let next = checked_split(&format!("{name}, level {level}"), t, tags);
        out.push(next);
    }
    out
}

/// The cube's vertex i sits at (i & 1, i >> 1 & 1, i >> 2 & 1); its top face (z = 1) is 4 5 7 6.
const CUBE_EDGES: [(u32, u32); 12] =
    [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];
const CUBE_TOP: [(u32, u32); 4] = [(4, 5), (5, 7), (7, 6), (6, 4)];

#[test]
fn cube_with_all_edges_sharp_is_valid_at_levels_1_to_4() {
    let cube = shapes::cube();
    let levels = check_levels("all-sharp cube", &cube, tags(cube.topology(), &CUBE_EDGES, &[]), 4);
    // Level 1: 24 images, 8 corner points, 12 midpoints; per cube face its
    // F-face and 4 pentagonal E-faces; every corner sector has one face, so
    // no V-face.
    let (t1, _) = &levels[1];
    assert_eq!((t1.vertex_count(), t1.face_count()), (24 + 8 + 12, 6 + 24));
    assert_eq!(t1.faces().iter().filter(|f| f.len() == 5).count(), 24);
    // The 8 corners have 3 sharp edges at every level.
    for (t, tags) in &levels {
        let f = DualFeatures::new(t, tags);
        assert_eq!(t.vertices().filter(|&v| f.is_corner(v)).count(), 8);
    }
}

#[test]
fn cube_with_a_crease_loop_is_valid_at_levels_1_to_4() {
    let cube = shapes::cube();
    let levels = check_levels("cube, top loop", &cube, tags(cube.topology(), &CUBE_TOP, &[]), 4);
    // A closed crease loop of n edges becomes one of 2n (Chaikin), no corners.
    for (k, (t, tags)) in levels.iter().enumerate() {
        assert_eq!(tags.crease_count(), 4 << k, "level {k}");
        assert_eq!(tags.corner_count(), 0);
        assert!(!t.vertices().any(|v| DualFeatures::new(t, tags).is_corner(v)));
    }
}

#[test]
fn cube_with_one_sharp_edge_has_darts_at_both_ends() {
    let cube = shapes::cube();
    let levels = check_levels("cube, one edge", &cube, tags(cube.topology(), &[(4, 5)], &[]), 4);
    // Between two darts one edge stays one edge: its two Chaikin points and
    // their segment, at every level.
    for (t, tags) in &levels {
        assert_eq!(tags.crease_count(), 1);
        let f = DualFeatures::new(t, tags);
        assert_eq!(t.vertices().filter(|&v| f.sharp_neighbors(t, v).count() == 1).count(), 2);
    }
    let (t1, _) = &levels[1];
    // 24 images + 2 Chaikin points; faces 6 F + 13 E (two on the crease) + 8 V.
    assert_eq!((t1.vertex_count(), t1.face_count()), (26, 6 + 13 + 8));
}

#[test]
fn open_grid_with_a_crease_row_to_the_boundary_is_valid_at_levels_1_to_4() {
    // 8×8 cells, vertex 9r + c; the row r = 4 from boundary to boundary.
    let grid = shapes::quad_grid(8, 8);
    let row: Vec<(u32, u32)> = (0..8).map(|c| (36 + c, 37 + c)).collect();
    let levels = check_levels("grid, crease row", &grid, tags(grid.topology(), &row, &[]), 4);
    // The row's ends have three sharp edges: corners, on the boundary.
    let f0 = DualFeatures::new(grid.topology(), &levels[0].1);
    let corners: Vec<u32> = grid.topology().vertices().filter(|&v| f0.is_corner(v)).map(|v| v.0).collect();
    assert_eq!(corners, [36, 44]);
    // Corner to corner, clamped Chaikin: n points become 2n − 2.
    let mut points = 9;
    for (k, (_, tags)) in levels.iter().enumerate() {
        assert_eq!(tags.crease_count(), points - 1, "level {k}");
        points = 2 * points - 2;
    }
}

#[test]
fn tagged_corners_are_valid_at_levels_1_to_4() {
    let grid = shapes::quad_grid(6, 5);
    let t = grid.topology();
    // Vertex 7r + c: a boundary vertex tagged (splits the boundary curve),
    // a corner on the crease row r = 2, a corner on a dart (the crease row
    // r = 4 ends inside), and a corner with no sharp edge at all (a cone).
    let crease_row: Vec<(u32, u32)> = (0..6).map(|c| (14 + c, 15 + c)).collect();
    let dart_row = [(29, 30), (30, 31)];
    let creases: Vec<(u32, u32)> = crease_row.iter().chain(&dart_row).copied().collect();
    let corners = [3, 17, 31, 9];
    let tags = tags(t, &creases, &corners);
    let f = DualFeatures::new(t, &tags);
    for v in corners {
        assert!(f.is_corner(VertexId(v)), "vertex {v}");
    }
    assert_eq!(f.sharp_neighbors(t, VertexId(9)).count(), 0, "the cone corner");
    assert_eq!(f.sharp_neighbors(t, VertexId(31)).count(), 1, "the dart corner");
    let levels = check_levels("grid, tagged corners", &grid, tags, 4);
    for (t, tags) in &levels {
        assert_eq!(tags.corner_count(), 4, "tagged corners keep their tags");
        assert!(tags.vertex_values().iter().all(|&s| s == 0.0 || s == SHARPNESS_INFINITE));
        // The two crease ends on the boundary are corners too.
        assert_eq!(t.vertices().filter(|&v| DualFeatures::new(t, tags).is_corner(v)).count(), 6);
    }
}

#[test]
fn empty_and_zero_tags_give_the_untagged_split_bit_for_bit() {
    for mesh in [shapes::cube(), shapes::quad_grid(4, 3), shapes::torus(6, 5), shapes::pillow()] {
        let t = mesh.topology();
        let (plain, p) = dual_split(t);
        let zero = Tags::from_arrays(t, vec![0.0; t.edge_count()], vec![0.0; t.vertex_count()]).unwrap();
        // Semi-sharp values count as smooth here (subdiv-stencil rejects them).
        let semi = Tags::from_arrays(t, vec![2.5; t.edge_count()], vec![9.5; t.vertex_count()]).unwrap();
        for tags in [Tags::none(), zero, semi] {
            let (tagged, tp, new_tags) = dual_split_tagged(t, &tags);
            assert_eq!(format!("{tagged:?}"), format!("{plain:?}"));
            assert_eq!(tp.face_origin, p.face_origin);
            assert!(new_tags.is_empty());
            assert_eq!(tp.sharp_points.len(), plain.vertex_count() - t.half_edge_count());
        }
    }
}

/// A random mesh with random creases and corners.
fn random_tagged(seed: u64) -> (Mesh, Tags) {
    let mut rng = SplitMix64(seed);
    let base = match rng.below(3) {
        0 => shapes::torus(6, 5),
        1 => shapes::plate_with_holes(6, 5, &[(1, 1), (3, 2)], false),
        _ => shapes::plate_with_holes(5, 5, &[(2, 2)], true),
    };
    let mesh = shapes::polygon_mix(&base, seed, 0.3, 0.3, 0.0);
    let t = mesh.topology();
    let crease_fraction = [0.05, 0.2, 0.5][rng.below(3)];
    let edges = t.edges().map(|_| if rng.next_f64() < crease_fraction { f32::INFINITY } else { 0.0 }).collect();
    let vertices = t.vertices().map(|_| if rng.next_f64() < 0.05 { 12.0 } else { 0.0 }).collect();
    let tags = Tags::from_arrays(t, edges, vertices).unwrap();
    (mesh, tags)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn direct_tagged_split_equals_the_validated_one(seed in any::<u64>()) {
        let (mesh, tags) = random_tagged(seed);
        check_levels(&format!("seed {seed}"), &mesh, tags, 2);
    }
}
