//! Validation ([`Mesh::from_soup`]) and [`diagnose`] stay linear in the number
//! of corners on the inputs that made them quadratic (issue #14, class 3:
//! 10,000 copies of one face took 7.8 s, 20,000 took 32 s).
//!
//! No time is measured: each input is large enough that a quadratic pass over
//! it (a per-edge face list scanned per face, a per-vertex fan searched per
//! half-edge, a face's corners compared pairwise) would take minutes, while
//! the linear code takes well under a second in the dev profile. A
//! regression shows up as a hung test. The counts are checked too, and on
//! small random soups `diagnose` is compared with a brute-force reference.

use proptest::prelude::*;
use subdiv_mesh::shapes::{self, polygon_mix, SplitMix64};
use subdiv_mesh::{diagnose, DVec3, Diagnosis, FaceList, Mesh, MeshError, PolygonSoup, VertexId};

fn triangle() -> Vec<DVec3> {
    vec![DVec3::ZERO, DVec3::X, DVec3::Y]
}

/// `n` points on the unit circle in the xy-plane.
fn circle(n: usize) -> Vec<DVec3> {
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect()
}

fn error(soup: &PolygonSoup) -> MeshError {
    Mesh::from_soup(soup.clone()).expect_err("the soup is invalid")
}

#[test]
fn duplicate_faces_are_refused_and_diagnosed_in_linear_time() {
    const COPIES: u32 = 200_000;
    let soup = PolygonSoup::new(triangle(), FaceList::from_faces((0..COPIES).map(|_| [0u32, 1, 2])));
    assert_eq!(error(&soup), MeshError::NonManifoldEdge { a: 0, b: 1, faces: COPIES as usize });
    let d = diagnose(&soup);
    assert_eq!((d.edges, d.non_manifold_edges, d.inconsistently_oriented_edges), (3, 3, 0));
    assert_eq!((d.components, d.non_manifold_vertices, d.faces), (1, 0, COPIES as usize));
    assert_eq!(d.first_error, Some(error(&soup)));
}

#[test]
fn duplicate_faces_of_alternating_orientation_are_refused_in_linear_time() {
    const COPIES: u32 = 200_000;
    let faces = FaceList::from_faces((0..COPIES).map(|k| if k % 2 == 0 { [0u32, 1, 2] } else { [0, 2, 1] }));
    let soup = PolygonSoup::new(triangle(), faces);
    assert_eq!(error(&soup), MeshError::NonManifoldEdge { a: 0, b: 1, faces: COPIES as usize });
    let d = diagnose(&soup);
    assert_eq!((d.edges, d.non_manifold_edges, d.components, d.non_manifold_vertices), (3, 3, 1, 0));
}

#[test]
fn faces_repeating_an_index_are_refused_and_counted_in_linear_time() {
    const FACES: u32 = 200_000;
    let soup = PolygonSoup::new(triangle(), FaceList::from_faces((0..FACES).map(|_| [0u32, 1, 0, 2])));
    assert_eq!(error(&soup), MeshError::RepeatedIndex { face: 0, vertex: 0 });
    let d = diagnose(&soup);
    assert_eq!((d.faces_with_repeated_index, d.edges, d.isolated_vertices), (FACES as usize, 0, 0));
}

#[test]
fn a_face_of_half_a_million_corners_is_checked_in_linear_time() {
    const CORNERS: u32 = 500_000;
    let positions = circle(CORNERS as usize);
    let polygon: Vec<u32> = (0..CORNERS).collect();
    let (mesh, warnings) =
        Mesh::from_soup(PolygonSoup::new(positions.clone(), FaceList::from_faces([&polygon]))).unwrap();
    assert!(warnings.is_empty());
    assert_eq!(mesh.topology().edge_count(), CORNERS as usize);
    // A repeat at the very end: found without comparing corners pairwise.
    let mut repeating = polygon;
    repeating[CORNERS as usize - 1] = 0;
    let soup = PolygonSoup::new(positions, FaceList::from_faces([&repeating]));
    assert_eq!(error(&soup), MeshError::RepeatedIndex { face: 0, vertex: 0 });
    let d = diagnose(&soup);
    assert_eq!((d.faces_with_repeated_index, d.isolated_vertices), (1, 1));
}

#[test]
fn a_cone_of_two_hundred_thousand_triangles_validates_in_linear_time() {
    const FAN: u32 = 200_000;
    let mut positions = vec![DVec3::Z];
    positions.extend(circle(FAN as usize));
    let mut faces = FaceList::from_faces((0..FAN).map(|k| [0, 1 + k, 1 + (k + 1) % FAN]));
    faces.push(&(0..FAN).rev().map(|k| 1 + k).collect::<Vec<_>>());
    let soup = PolygonSoup::new(positions, faces);
    let (mesh, warnings) = Mesh::from_soup(soup.clone()).unwrap();
    assert!(warnings.is_empty());
    let t = mesh.topology();
    assert_eq!((t.valence(VertexId(0)), t.genus(), t.is_closed()), (FAN as usize, Some(0), true));
    let n = mesh.vertex_normals();
    assert!((n[0] - DVec3::Z).length() < 1e-12, "apex normal {}", n[0]);
    let d = diagnose(&soup);
    assert_eq!((d.non_manifold_vertices, d.non_manifold_edges, d.components, d.first_error), (0, 0, 1, None));
}

/// `count` tetrahedra sharing vertex 0: `count` closed fans at one vertex.
fn tetrahedra_sharing_a_vertex(count: u32) -> PolygonSoup {
    let mut positions = vec![DVec3::ZERO];
    let mut faces = FaceList::new();
    for k in 0..count {
        let (b, x) = (1 + 3 * k, f64::from(k));
        positions.extend([DVec3::new(1.0 + x, 0.0, 0.0), DVec3::new(x, 1.0, 0.0), DVec3::new(x, 0.0, 1.0)]);
        for f in [[0, b, b + 1], [0, b + 1, b + 2], [0, b + 2, b], [b, b + 2, b + 1]] {
            faces.push(&f);
        }
    }
    PolygonSoup::new(positions, faces)
}

#[test]
fn a_vertex_joining_a_hundred_thousand_closed_fans_is_refused_in_linear_time() {
    const FANS: u32 = 100_000;
    let soup = tetrahedra_sharing_a_vertex(FANS);
    assert_eq!(error(&soup), MeshError::NonManifoldVertex { vertex: 0, fans: FANS as usize });
    let d = diagnose(&soup);
    assert_eq!((d.non_manifold_vertices, d.non_manifold_edges, d.components), (1, 0, FANS as usize));
}

#[test]
fn open_and_closed_fans_at_one_vertex_are_all_counted_in_linear_time() {
    // One closed fan (a tetrahedron) plus 10⁵ lone triangles at vertex 0: the
    // count covers the closed fan too, not only the boundary half-edges.
    const OPEN: u32 = 100_000;
    let mut soup = tetrahedra_sharing_a_vertex(1);
    for k in 0..OPEN {
        let b = soup.positions.len() as u32;
        soup.positions.extend([DVec3::new(1.0, f64::from(k), 5.0), DVec3::new(0.0, f64::from(k), 6.0)]);
        soup.faces.push(&[0, b, b + 1]);
    }
    assert_eq!(error(&soup), MeshError::NonManifoldVertex { vertex: 0, fans: OPEN as usize + 1 });
    assert_eq!(diagnose(&soup).non_manifold_vertices, 1);
}

#[test]
fn an_edge_shared_by_two_hundred_thousand_faces_is_refused_in_linear_time() {
    const PAGES: u32 = 200_000;
    let mut positions = vec![DVec3::ZERO, DVec3::X];
    positions.extend((0..PAGES).map(|k| DVec3::new(0.5, f64::from(k), 1.0)));
    let soup = PolygonSoup::new(positions, FaceList::from_faces((0..PAGES).map(|k| [0, 1, 2 + k])));
    assert_eq!(error(&soup), MeshError::NonManifoldEdge { a: 0, b: 1, faces: PAGES as usize });
    let d = diagnose(&soup);
    assert_eq!((d.non_manifold_edges, d.edges, d.components), (1, 1 + 2 * PAGES as usize, 1));
}

#[test]
fn many_non_manifold_edges_are_counted_in_linear_time() {
    // A strip of 10⁵ quads, every quad listed three times: all 3·10⁵ + 1 edges non-manifold.
    const QUADS: u32 = 100_000;
    let positions: Vec<DVec3> =
        (0..2 * QUADS + 2).map(|k| DVec3::new(f64::from(k / 2), f64::from(k % 2), 0.0)).collect();
    let faces = FaceList::from_faces((0..3 * QUADS).map(|k| {
        let i = 2 * (k / 3);
        [i, i + 2, i + 3, i + 1]
    }));
    let soup = PolygonSoup::new(positions, faces);
    assert_eq!(error(&soup), MeshError::NonManifoldEdge { a: 0, b: 2, faces: 3 });
    let d = diagnose(&soup);
    assert_eq!((d.non_manifold_edges, d.edges, d.components), (3 * QUADS as usize + 1, 3 * QUADS as usize + 1, 1));
}

// ---- diagnose against a brute-force reference -------------------------------------------------

/// The defect counts of `diagnose`, by definition and in quadratic time:
/// faces are good when they have ≥ 2 corners, all in range and distinct; an
/// edge's faces are the good faces with it as a side; two good faces at a
/// vertex are in one fan when they share a side at that vertex (transitively).
fn reference(soup: &PolygonSoup) -> Diagnosis {
    let n = soup.positions.len();
    let faces: Vec<&[u32]> = soup.faces.iter().collect();
    let in_range = |f: &[u32]| f.iter().all(|&v| (v as usize) < n);
    let repeats = |f: &[u32]| (0..f.len()).any(|i| (0..i).any(|j| f[i] == f[j]));
    let good: Vec<bool> = faces.iter().map(|f| f.len() >= 2 && in_range(f) && !repeats(f)).collect();
    let sides = |f: &[u32]| -> Vec<(u32, u32)> { (0..f.len()).map(|k| (f[k], f[(k + 1) % f.len()])).collect() };
    let key = |(a, b): (u32, u32)| (a.min(b), a.max(b));
    let mut edges: Vec<(u32, u32)> =
        (0..faces.len()).filter(|&f| good[f]).flat_map(|f| sides(faces[f])).map(key).collect();
    edges.sort_unstable();
    edges.dedup();
    let has_side = |f: usize, e: (u32, u32)| good[f] && sides(faces[f]).into_iter().any(|s| key(s) == e);
    let mut d = Diagnosis::default();
    (d.vertices, d.faces, d.edges) = (n, faces.len(), edges.len());
    for &e in &edges {
        let directed: Vec<(u32, u32)> =
            (0..faces.len()).filter(|&f| good[f]).flat_map(|f| sides(faces[f])).filter(|&s| key(s) == e).collect();
        let forward = directed.iter().filter(|s| s.0 < s.1).count();
        if directed.len() > 2 {
            d.non_manifold_edges += 1;
        } else if directed.len() == 2 && (forward == 2 || forward == 0) {
            d.inconsistently_oriented_edges += 1;
        }
    }
    // Components of a graph over `nodes`, joined by `linked`, by flood fill.
    let components = |nodes: &[usize], linked: &dyn Fn(usize, usize) -> bool| {
        let mut label = vec![usize::MAX; nodes.len()];
        let mut count = 0;
        for s in 0..nodes.len() {
            if label[s] != usize::MAX {
                continue;
            }
            label[s] = count;
            let mut stack = vec![s];
            while let Some(i) = stack.pop() {
                for j in 0..nodes.len() {
                    if label[j] == usize::MAX && linked(nodes[i], nodes[j]) {
                        label[j] = count;
                        stack.push(j);
                    }
                }
            }
            count += 1;
        }
        count
    };
    let good_faces: Vec<usize> = (0..faces.len()).filter(|&f| good[f]).collect();
    d.components = components(&good_faces, &|f, g| edges.iter().any(|&e| has_side(f, e) && has_side(g, e)));
    for v in 0..n as u32 {
        let at_v: Vec<usize> = good_faces.iter().copied().filter(|&f| faces[f].contains(&v)).collect();
        let fans = components(&at_v, &|f, g| {
            edges.iter().any(|&e| (e.0 == v || e.1 == v) && has_side(f, e) && has_side(g, e))
        });
        d.non_manifold_vertices += usize::from(fans > 1);
    }
    for f in &faces {
        *d.face_sizes.entry(f.len()).or_insert(0) += 1;
    }
    d.faces_too_small = faces.iter().filter(|f| f.len() < 3).count();
    d.out_of_range_indices = faces.iter().map(|f| f.iter().filter(|&&v| v as usize >= n).count()).sum();
    d.faces_with_repeated_index = faces.iter().filter(|f| repeats(f)).count();
    d.non_finite_vertices = soup.positions.iter().filter(|p| !p.is_finite()).count();
    let used = |v: u32| faces.iter().any(|f| f.contains(&v));
    d.isolated_vertices = (0..n as u32).filter(|&v| !used(v)).count();
    d
}

/// A valid polygon mix damaged at random: faces duplicated, flipped,
/// dropped or given stray indices, vertices glued together (bow-ties,
/// repeated indices), coordinates made non-finite.
fn damaged_soup() -> impl Strategy<Value = PolygonSoup> {
    (2usize..5, 2usize..5, any::<bool>(), any::<u64>(), 0usize..8).prop_map(|(nx, ny, closed, seed, damage)| {
        let base = shapes::plate_with_holes(nx + 2, ny + 2, &[(1, 1)], closed);
        let mesh = polygon_mix(&base, seed, 0.3, 0.3, 0.1);
        let mut rng = SplitMix64(seed ^ 0x5eed);
        let n = mesh.positions().len() as u32;
        let mut faces: Vec<Vec<u32>> = mesh.topology().faces().iter().map(<[u32]>::to_vec).collect();
        let mut positions = mesh.positions().to_vec();
        for _ in 0..damage {
            let f = rng.below(faces.len());
            match rng.below(7) {
                0 => faces.push(faces[f].clone()),
                1 => faces[f].reverse(),
                2 => drop(faces.swap_remove(f)),
                3 => {
                    let k = rng.below(faces[f].len());
                    faces[f][k] = n + rng.below(3) as u32; // out of range
                }
                4 => faces[f].truncate(1 + rng.below(2)), // too small
                5 => {
                    // Glue vertex a onto vertex b everywhere.
                    let (a, b) = (rng.below(n as usize) as u32, rng.below(n as usize) as u32);
                    faces.iter_mut().flatten().filter(|v| **v == a).for_each(|v| *v = b);
                }
                _ => positions[rng.below(n as usize)].y = f64::NAN,
            }
        }
        PolygonSoup::new(positions, FaceList::from_faces(faces))
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn diagnose_counts_what_the_brute_force_reference_counts(soup in damaged_soup()) {
        let d = diagnose(&soup);
        let expected = reference(&soup);
        prop_assert_eq!(
            (d.vertices, d.faces, d.edges, &d.face_sizes, d.faces_too_small, d.out_of_range_indices),
            (expected.vertices, expected.faces, expected.edges, &expected.face_sizes, expected.faces_too_small, expected.out_of_range_indices)
        );
        prop_assert_eq!(
            (d.faces_with_repeated_index, d.non_finite_vertices, d.isolated_vertices, d.components),
            (expected.faces_with_repeated_index, expected.non_finite_vertices, expected.isolated_vertices, expected.components)
        );
        prop_assert_eq!(
            (d.non_manifold_edges, d.inconsistently_oriented_edges, d.non_manifold_vertices),
            (expected.non_manifold_edges, expected.inconsistently_oriented_edges, expected.non_manifold_vertices)
        );
        // As text: a NaN coordinate in the error is not equal to itself.
        let text = |e: Option<MeshError>| e.map(|e| e.to_string());
        prop_assert_eq!(text(d.first_error), text(Mesh::from_soup(soup.clone()).err()));
    }
}

#[test]
fn diagnose_counts_repeats_among_out_of_range_indices() {
    // Vertex 9 does not exist and is used twice: out of range twice, repeated once.
    let soup = PolygonSoup::new(triangle(), FaceList::from_faces([&[0u32, 9, 1, 9][..], &[0, 1, 2]]));
    let d = diagnose(&soup);
    assert_eq!((d.out_of_range_indices, d.faces_with_repeated_index), (2, 1));
    let mut expected = reference(&soup);
    (expected.first_error, expected.bbox) = (d.first_error.clone(), d.bbox);
    assert_eq!(d, expected);
}
