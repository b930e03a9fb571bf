//! Feature edges by dihedral angle (`subdiv_mesh::features`): exact counts on
//! procedural shapes, the fandisk CAD part checked against angles measured
//! here with plain vector maths, and monotonicity in the threshold on random
//! polygon mixes.

use proptest::prelude::*;
use std::f64::consts::PI;
use std::path::Path;
use subdiv_mesh::shapes::{self, polygon_mix};
use subdiv_mesh::{
    dihedral_turning_angle, feature_edges, DVec3, EdgeId, FaceId, FaceList, FeatureEdges, Mesh, Tags,
    SHARPNESS_INFINITE,
};

/// The unit normal of face `f` by the textbook Newell sum Σ pᵢ × pᵢ₊₁ on raw
/// coordinates (no offsets, no scaling), or `None` when it is zero.
fn plain_normal(mesh: &Mesh, f: FaceId) -> Option<DVec3> {
    let face = mesh.topology().face(f);
    let p = |k: usize| mesh.positions()[face[k % face.len()] as usize];
    let n: DVec3 = (0..face.len()).map(|k| p(k).cross(p(k + 1))).sum();
    (n.length() > 0.0).then(|| n / n.length())
}

/// The angle between the two faces' normals of an interior edge by `acos` of
/// the clamped dot product; `None` on the boundary or at a degenerate face.
fn plain_angle(mesh: &Mesh, e: EdgeId) -> Option<f64> {
    let (f1, f2) = mesh.topology().edge_faces(e);
    let (n1, n2) = (plain_normal(mesh, f1)?, plain_normal(mesh, f2?)?);
    Some(n1.dot(n2).clamp(-1.0, 1.0).acos())
}

/// `acos` near 0 and π loses about 1e-8 rad; edges closer than this to the
/// threshold are not checked for which side they fall on.
const ANGLE_TOL: f64 = 1e-7;

/// Every invariant of a feature set on `mesh` at `degrees`, against the
/// plain re-measurement; returns the number of edges within [`ANGLE_TOL`] of
/// the threshold (whose side was not checked).
fn check(mesh: &Mesh, degrees: f64, features: &FeatureEdges) -> usize {
    let t = mesh.topology();
    let threshold = degrees.to_radians();
    assert_eq!(features.threshold_radians, threshold);
    assert_eq!(features.angles.len(), t.edge_count());
    assert_eq!(features.edges.len(), features.list.creases.len());
    assert!(features.list.corners.is_empty(), "corners are left to the rules");
    assert!(features.edges.windows(2).all(|w| w[0] < w[1]), "edge order");
    let mut tagged = vec![false; t.edge_count()];
    for (&e, tag) in features.edges.iter().zip(&features.list.creases) {
        tagged[e.index()] = true;
        assert_eq!(tag.sharpness, SHARPNESS_INFINITE);
        let (a, b) = t.edge_vertices(e);
        assert_eq!((tag.a, tag.b), (a.0, b.0));
        assert!(!t.is_boundary_edge(e), "boundary edge {e} tagged");
    }
    let mut near = 0;
    for e in t.edges() {
        let ours = features.angles[e.index()];
        assert_eq!(ours, dihedral_turning_angle(mesh, e), "edge {e}");
        let plain = plain_angle(mesh, e);
        assert_eq!(ours.is_some(), plain.is_some(), "edge {e}: {ours:?} vs {plain:?}");
        let (Some(ours), Some(plain)) = (ours, plain) else {
            assert!(!tagged[e.index()], "edge {e} without an angle tagged");
            continue;
        };
        assert!((0.0..=PI).contains(&ours));
        assert!((ours - plain).abs() < ANGLE_TOL, "edge {e}: {ours} vs {plain}");
        // Tagged exactly when the angle reaches the threshold.
        assert_eq!(tagged[e.index()], ours >= threshold, "edge {e}: {ours} vs {threshold}");
        if (plain - threshold).abs() < ANGLE_TOL {
            near += 1;
        } else {
            assert_eq!(tagged[e.index()], plain >= threshold, "edge {e}: plain {plain} vs {threshold}");
        }
    }
    // The list resolves on the mesh to exactly these creases.
    let tags = Tags::from_list(t, &features.list).expect("features are edges");
    assert_eq!(tags.crease_count(), features.edges.len());
    for e in t.edges() {
        let expected = if tagged[e.index()] { SHARPNESS_INFINITE } else { 0.0 };
        assert_eq!(tags.edge_sharpness(e), expected);
    }
    near
}

/// A minimal OFF reader (the mesh crate cannot depend on `subdiv-io`): header,
/// counts, coordinates, faces as `n i₀ … iₙ₋₁`.
fn read_off(path: &Path) -> Mesh {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut words = text.lines().filter(|l| !l.trim_start().starts_with('#')).flat_map(str::split_whitespace);
    assert_eq!(words.next(), Some("OFF"));
    let mut number = || words.next().expect("more numbers").parse::<f64>().expect("a number");
    let (nv, nf, _) = (number() as usize, number() as usize, number());
    let positions = (0..nv).map(|_| DVec3::new(number(), number(), number())).collect();
    let mut faces = FaceList::new();
    for _ in 0..nf {
        let n = number() as usize;
        faces.push(&(0..n).map(|_| number() as u32).collect::<Vec<_>>());
    }
    Mesh::new(positions, faces).expect("a valid fixture")
}

fn fandisk() -> Mesh {
    read_off(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/quad/fandisk_quads.off"))
}

#[test]
fn cube_at_30_degrees_tags_all_12_edges() {
    let cube = shapes::cube();
    let features = feature_edges(&cube, 30.0);
    assert_eq!(check(&cube, 30.0, &features), 0);
    assert_eq!(features.edges.len(), 12);
    // All eight vertices have three creases: corners by the rules, no corner tag.
    let tagged = cube.clone().with_tags(Tags::from_list(cube.topology(), &features.list).unwrap());
    assert_eq!((tagged.tags().crease_count(), tagged.tags().corner_count()), (12, 0));
}

#[test]
fn flat_grids_have_no_features() {
    for grid in [shapes::quad_grid(5, 4), shapes::triangle_grid(4, 3)] {
        for degrees in [1e-6, 1.0, 30.0] {
            let features = feature_edges(&grid, degrees);
            check(&grid, degrees, &features);
            assert!(features.edges.is_empty());
        }
    }
}

#[test]
fn prism_above_its_side_angle_tags_only_the_cap_rims() {
    for n in [6, 12, 24] {
        let prism = shapes::prism(n);
        let t = prism.topology();
        let side = 360.0 / n as f64; // consecutive side quads turn by 2π/n, the caps by π/2
        let rims = feature_edges(&prism, (side + 90.0) / 2.0);
        check(&prism, (side + 90.0) / 2.0, &rims);
        assert_eq!(rims.edges.len(), 2 * n);
        // Every rim edge borders a cap (faces 0 and 1), no side edge is tagged.
        for &e in &rims.edges {
            let (f1, f2) = t.edge_faces(e);
            assert!([f1, f2.unwrap()].iter().any(|f| f.0 < 2), "edge {e} is not on a rim");
        }
        let all = feature_edges(&prism, side / 2.0);
        check(&prism, side / 2.0, &all);
        assert_eq!(all.edges.len(), 3 * n);
    }
}

#[test]
fn open_meshes_never_tag_boundary_edges() {
    // The top of a plate with a hole: flat, two boundary loops; at 0° every interior edge, no boundary edge.
    let plate = shapes::plate_with_holes(5, 5, &[(2, 2)], false);
    let features = feature_edges(&plate, 0.0);
    check(&plate, 0.0, &features);
    let t = plate.topology();
    assert_eq!(features.edges.len(), t.edges().filter(|&e| !t.is_boundary_edge(e)).count());
}

#[test]
fn degenerate_faces_make_no_features() {
    // A tetrahedron with one face flattened to a line (0, 1, 2 collinear):
    // its three edges have no angle and are never tagged.
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 1.0),
    ];
    let faces = FaceList::from_faces([[0u32, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]);
    let mesh = Mesh::new(positions, faces).unwrap();
    let features = feature_edges(&mesh, 0.0);
    check(&mesh, 0.0, &features);
    let t = mesh.topology();
    for e in t.edges() {
        let (f1, f2) = t.edge_faces(e);
        let on_flat = f1 == FaceId(0) || f2 == Some(FaceId(0));
        assert_eq!(features.angles[e.index()].is_none(), on_flat, "edge {e}");
    }
    assert_eq!(features.edges.len(), 3);
}

#[test]
fn fandisk_features_at_30_and_40_degrees() {
    let mesh = fandisk();
    let t = mesh.topology();
    let interior = t.edges().filter(|&e| !t.is_boundary_edge(e)).count();
    let mut previous: Option<FeatureEdges> = None;
    for degrees in [20.0, 30.0, 40.0, 60.0] {
        let features = feature_edges(&mesh, degrees);
        let near = check(&mesh, degrees, &features);
        // Corners of the CAD part: vertices with three or more features.
        let mut at_vertex = vec![0usize; t.vertex_count()];
        for &e in &features.edges {
            let (a, b) = t.edge_vertices(e);
            at_vertex[a.index()] += 1;
            at_vertex[b.index()] += 1;
        }
        let corners = at_vertex.iter().filter(|&&k| k >= 3).count();
        let darts = at_vertex.iter().filter(|&&k| k == 1).count();
        println!(
            "fandisk at {degrees}°: {} of {interior} interior edges are features, {corners} corners, {darts} \
             dart ends, {near} within {ANGLE_TOL:e} rad of the threshold",
            features.edges.len()
        );
        // A CAD part of 764 quads: features are a small fraction of the edges but far more than none.
        assert!(features.edges.len() >= 50 && features.edges.len() * 5 <= interior, "{}", features.edges.len());
        if let Some(prev) = &previous {
            assert!(features.edges.iter().all(|e| prev.edges.binary_search(e).is_ok()), "not monotone");
        }
        previous = Some(features);
    }
}

#[test]
fn rigid_motions_and_scaling_keep_the_features() {
    let mesh = fandisk();
    let (c, s) = (0.6_f64, 0.8_f64); // a rotation about (1, 1, 1)/√3 by acos(0.6), then × 3.7 and a shift
    let axis = DVec3::ONE.normalize();
    let moved: Vec<DVec3> = mesh
        .positions()
        .iter()
        .map(|&p| {
            let r = p * c + axis.cross(p) * s + axis * axis.dot(p) * (1.0 - c);
            r * 3.7 + DVec3::new(10.0, -4.0, 2.5)
        })
        .collect();
    let moved = mesh.with_positions(moved);
    for degrees in [30.0, 40.0] {
        let (a, b) = (feature_edges(&mesh, degrees), feature_edges(&moved, degrees));
        for (x, y) in a.angles.iter().zip(&b.angles) {
            assert!((x.unwrap() - y.unwrap()).abs() < 1e-12, "{x:?} vs {y:?}");
        }
        let near = |e: &EdgeId| (a.angles[e.index()].unwrap() - a.threshold_radians).abs() < 1e-12;
        let mut differ = a
            .edges
            .iter()
            .filter(|e| b.edges.binary_search(e).is_err())
            .chain(b.edges.iter().filter(|e| a.edges.binary_search(e).is_err()));
        assert!(differ.all(near), "features moved by more than round-off");
    }
}

// ---- property tests -------------------------------------------------------------------------

/// Random valid meshes from `shapes`: polygon mixes of plates (open or
/// closed, with a hole), tori, icosahedra, prisms and pyramids, jittered.
fn any_mesh() -> impl Strategy<Value = Mesh> {
    let plate = (3usize..7, 3usize..7, any::<bool>(), any::<u64>()).prop_map(|(nx, ny, closed, seed)| {
        polygon_mix(&shapes::plate_with_holes(nx + 2, ny, &[(1, 1)], closed), seed, 0.3, 0.3, 0.2)
    });
    let torus = (3usize..8, 3usize..8, any::<u64>())
        .prop_map(|(nu, nv, seed)| polygon_mix(&shapes::torus(nu, nv), seed, 0.3, 0.3, 0.2));
    let ico = any::<u64>().prop_map(|seed| polygon_mix(&shapes::icosahedron(), seed, 0.0, 0.0, 0.2));
    let prism = (3usize..10, any::<u64>()).prop_map(|(n, seed)| polygon_mix(&shapes::prism(n), seed, 0.0, 0.3, 0.1));
    let pyramid =
        (3usize..10, any::<u64>()).prop_map(|(n, seed)| polygon_mix(&shapes::pyramid(n), seed, 0.0, 0.0, 0.1));
    prop_oneof![plate, torus, ico, prism, pyramid]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn a_larger_threshold_gives_a_subset(mesh in any_mesh(), a in 0.0f64..180.0, b in 0.0f64..180.0) {
        let (low, high) = (a.min(b), a.max(b));
        let (lo, hi) = (feature_edges(&mesh, low), feature_edges(&mesh, high));
        check(&mesh, low, &lo);
        check(&mesh, high, &hi);
        prop_assert_eq!(&lo.angles, &hi.angles);
        prop_assert!(hi.edges.iter().all(|e| lo.edges.binary_search(e).is_ok()));
        // The difference is exactly the edges with an angle in [low, high).
        let between = lo.angles.iter().filter(|x| x.is_some_and(|x| x >= low.to_radians() && x < high.to_radians())).count();
        prop_assert_eq!(lo.edges.len() - hi.edges.len(), between);
    }
}
