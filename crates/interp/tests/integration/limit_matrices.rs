//! The limit matrices A = D·S ([limit matrices]): theorems of the papers (row sums,
//! exact symmetry, diagonal dominance, spectra) and brute force (subdivide
//! 8 levels and watch the tracked points converge to A·P).
//!
//! [limit matrices]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule

use crate::support::fixture_named as fixture;
use glam::DVec3;
use nalgebra::{DMatrix, SymmetricEigen};
use subdiv_interp::{
    catmull_clark_degeneracy, limit_matrix_nasri, limit_matrix_two_phase, limit_matrix_zheng_cai, CornerRule,
    Degeneracy,
};
use subdiv_mesh::refine::DualFace;
use subdiv_mesh::{shapes, Mesh, Topology};
use subdiv_stencil::doo_sabin;
use subdiv_stencil::{
    apply, limit_matrix_catmull_clark, limit_matrix_loop, LimitMatrix, LoopBeta, Scheme, SubdivisionPlan,
};

fn closed_polygon_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("cube_quad", fixture("cube_quad")),
        ("pyramid_mixed", fixture("pyramid_mixed")),
        ("mpi", fixture("mpi")),
        ("P", fixture("P")),
        ("spot_control_mesh", fixture("spot_control_mesh")),
        ("torus mix", shapes::polygon_mix(&shapes::torus(8, 6), 3, 0.2, 0.2, 0.05)),
    ]
}

fn open_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("halftunnel", fixture("halftunnel")),
        ("mesh_with_colors", fixture("mesh_with_colors")),
        ("plate mix", shapes::polygon_mix(&shapes::plate_with_holes(7, 5, &[(2, 2)], false), 5, 0.2, 0.2, 0.05)),
    ]
}

fn tri_meshes() -> Vec<(&'static str, Mesh)> {
    vec![("icosphere_2", fixture("icosphere_2")), ("eight", fixture("eight")), ("grid (open)", fixture("grid"))]
}

/// Every matrix applicable to a mesh, with its name.
fn matrices(mesh: &Mesh) -> Vec<(&'static str, LimitMatrix)> {
    let t = mesh.topology();
    let lambdas: Vec<f64> = (0..t.face_count()).map(|f| 0.3 + 0.5 * ((f * 7919) % 13) as f64 / 13.0).collect();
    let mut out = vec![
        ("C", limit_matrix_nasri(t)),
        ("Z", limit_matrix_zheng_cai(t)),
        ("B(λ)", limit_matrix_two_phase(t, CornerRule::PerFace(&lambdas)).unwrap()),
        ("A", limit_matrix_catmull_clark(t)),
    ];
    for beta in [LoopBeta::Warren, LoopBeta::Loop] {
        if let Ok(l) = limit_matrix_loop(t, beta) {
            out.push(("L", l));
        }
    }
    out
}

fn all_meshes() -> Vec<(&'static str, Mesh)> {
    let mut all = closed_polygon_meshes();
    all.extend(open_meshes());
    all.extend(tri_meshes());
    all
}

#[test]
fn rows_sum_to_one() {
    for (name, mesh) in all_meshes() {
        for (m, a) in matrices(&mesh) {
            let csr = a.to_csr();
            for (i, row) in csr.outer_iterator().enumerate() {
                let sum: f64 = row.data().iter().sum();
                assert!((sum - 1.0).abs() < 1e-14, "{m} on {name}: row {i} sums to {sum}");
            }
        }
    }
}

#[test]
fn s_is_exactly_symmetric_on_closed_meshes_and_in_the_interior_block() {
    for (name, mesh) in all_meshes() {
        for (m, a) in matrices(&mesh) {
            if mesh.topology().is_closed() {
                assert!(a.is_symmetric(), "{m} on {name}");
            }
            // Interior × interior block: symmetric bit for bit.
            let boundary: std::collections::HashSet<u32> = a.boundary_rows.iter().copied().collect();
            for (i, row) in a.s.outer_iterator().enumerate() {
                if boundary.contains(&(i as u32)) {
                    continue;
                }
                for (j, &x) in row.iter() {
                    if !boundary.contains(&(j as u32)) {
                        let y = *a.s.get(j, i).expect("symmetric pattern");
                        assert_eq!(x.to_bits(), y.to_bits(), "{m} on {name}: S[{i}][{j}]");
                    }
                }
            }
        }
    }
}

/// Closed meshes whose face rings repeat a vertex (so an entry of S sums
/// contributions of several faces beyond the two at an edge): the pillow
/// (each vertex a far corner of both quads) and quads around two
/// poles (a lantern), where each pole is a far corner of every face of the other.
#[test]
fn s_is_exactly_symmetric_when_face_rings_repeat_vertices() {
    // k quads (N, eᵢ, S, eᵢ₊₁) around the poles N = 0 and S = 1.
    let lantern = |k: u32| {
        let mut p = vec![DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.0, 0.0, -1.0)];
        p.extend((0..k).map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / f64::from(k);
            DVec3::new(a.cos(), a.sin(), 0.1 * f64::from(i % 2))
        }));
        let faces = subdiv_mesh::FaceList::from_faces((0..k).map(|i| [0, 2 + i, 1, 2 + (i + 1) % k]));
        Mesh::new(p, faces).expect("a valid closed mesh")
    };
    for (name, mesh) in [("pillow", shapes::pillow()), ("lantern 3", lantern(3)), ("lantern 7", lantern(7))] {
        let t = mesh.topology();
        // The repeat is there: some row has fewer distinct columns than its ring has corners.
        let repeats = t.vertices().any(|v| {
            let mut ring: Vec<u32> = t.vertex_corners(v).flat_map(|c| t.face(c.face).to_vec()).collect();
            let corners = 1 + ring.len() - 2 * t.vertex_face_count(v);
            ring.sort_unstable();
            ring.dedup();
            ring.len() < corners
        });
        assert!(repeats, "{name}");
        // Every vertex of the pillow and the lanterns' equators have valence
        // 2: the Doo-Sabin rows there are the (unsymmetric) valence-2 mask,
        // tested by `doo_sabin_matrices_at_valence_two`; here only the rows of
        // the other vertices must agree with their mirrors.
        let v2: std::collections::HashSet<usize> =
            t.vertices().filter(|&v| !t.is_boundary_vertex(v) && t.valence(v) == 2).map(|v| v.index()).collect();
        for (m, a) in matrices(&mesh) {
            if m == "A" || m == "L" {
                assert!(a.is_symmetric(), "{m} on {name}");
            } else {
                for (i, row) in a.s.outer_iterator().enumerate().filter(|(i, _)| !v2.contains(i)) {
                    for (j, &x) in row.iter().filter(|(j, _)| !v2.contains(j)) {
                        assert_eq!(x.to_bits(), a.s.get(j, i).unwrap().to_bits(), "{m} on {name}: S[{i}][{j}]");
                    }
                }
            }
            let csr = a.to_csr();
            for (i, row) in csr.outer_iterator().enumerate() {
                let sum: f64 = row.data().iter().sum();
                assert!((sum - 1.0).abs() < 1e-14, "{m} on {name}: row {i} sums to {sum}");
            }
        }
    }
}

#[test]
fn zheng_cai_z_is_strictly_diagonally_dominant() {
    for (name, mesh) in all_meshes() {
        let z = limit_matrix_zheng_cai(mesh.topology()).to_csr();
        for (i, row) in z.outer_iterator().enumerate() {
            let diag = *row.get(i).unwrap();
            let off: f64 = row.iter().filter(|(j, _)| *j != i).map(|(_, x)| x.abs()).sum();
            assert!(diag > off, "{name}: row {i}: {diag} vs {off}");
        }
    }
}

/// Eigenvalues of A = D·S on a closed mesh, via the similar symmetric D^½ S D^½.
fn eigenvalues(a: &LimitMatrix) -> Vec<f64> {
    let n = a.size();
    let mut m = DMatrix::zeros(n, n);
    for (i, row) in a.s.outer_iterator().enumerate() {
        for (j, &x) in row.iter() {
            m[(i, j)] = a.d[i].sqrt() * x * a.d[j].sqrt();
        }
    }
    let mut ev: Vec<f64> = SymmetricEigen::new(m).eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    ev
}

#[test]
fn spectra_lie_where_the_theorems_say() {
    const EPS: f64 = 1e-12;
    for (name, mesh) in closed_polygon_meshes().into_iter().chain(tri_meshes().into_iter().take(2)) {
        let t = mesh.topology();
        if t.vertex_count() > 400 {
            continue;
        }
        let c = eigenvalues(&limit_matrix_nasri(t));
        assert!(
            c[0] >= 0.25 - EPS && *c.last().unwrap() <= 1.0 + EPS,
            "C on {name}: [{}, {}]",
            c[0],
            c.last().unwrap()
        );
        let z = eigenvalues(&limit_matrix_zheng_cai(t));
        assert!(z[0] >= 0.5 - EPS && *z.last().unwrap() <= 1.0 + EPS, "Z on {name}");
        let lambdas: Vec<f64> = (0..t.face_count()).map(|f| 0.2 + 0.7 * ((f * 31) % 11) as f64 / 11.0).collect();
        let lmin = lambdas.iter().copied().fold(1.0, f64::min);
        let b = eigenvalues(&limit_matrix_two_phase(t, CornerRule::PerFace(&lambdas)).unwrap());
        assert!(b[0] >= lmin - EPS && *b.last().unwrap() <= 1.0 + EPS, "B(λ) on {name}: {} < {lmin}", b[0]);
        let a = eigenvalues(&limit_matrix_catmull_clark(t));
        if t.vertices().all(|v| t.valence(v) >= 3) {
            assert!(a[0] >= -EPS && *a.last().unwrap() <= 1.0 + EPS, "A on {name}: [{}, {}]", a[0], a.last().unwrap());
        }
        if let Ok(l) = limit_matrix_loop(t, LoopBeta::Warren) {
            let l = eigenvalues(&l);
            assert!(l[0] > 0.0 && *l.last().unwrap() <= 1.0 + EPS, "L on {name}");
        }
    }
}

#[test]
fn cube_is_singular_and_pillow_indefinite_and_both_are_detected() {
    let cube = shapes::cube();
    let ev = eigenvalues(&limit_matrix_catmull_clark(cube.topology()));
    assert!(ev[0].abs() < 1e-14, "cube: λ_min = {}", ev[0]);
    assert!(matches!(catmull_clark_degeneracy(cube.topology()), Some(Degeneracy::Singular { .. })));
    for n in [4, 6, 8] {
        let prism = shapes::prism(n);
        assert!(eigenvalues(&limit_matrix_catmull_clark(prism.topology()))[0].abs() < 1e-14, "prism {n}");
        assert!(matches!(catmull_clark_degeneracy(prism.topology()), Some(Degeneracy::Singular { .. })));
    }
    // Odd prisms are not bipartite: nonsingular, and not flagged.
    let prism5 = shapes::prism(5);
    assert!(eigenvalues(&limit_matrix_catmull_clark(prism5.topology()))[0] > 1e-3);
    assert_eq!(catmull_clark_degeneracy(prism5.topology()), None);
    let pillow = shapes::pillow();
    let ev = eigenvalues(&limit_matrix_catmull_clark(pillow.topology()));
    assert!((ev[0] + 1.0 / 7.0).abs() < 1e-12, "pillow: λ_min = {} (correction C3 in docs/REFERENCES.md: −1/7)", ev[0]);
    assert!(matches!(catmull_clark_degeneracy(pillow.topology()), Some(Degeneracy::Indefinite { .. })));
    // Per component: a cube beside an icosahedron is still singular (whichever comes first).
    let union = |a: &Mesh, b: &Mesh| {
        let offset = a.topology().vertex_count() as u32;
        let mut p = a.positions().to_vec();
        p.extend(b.positions().iter().map(|&x| x + DVec3::new(5.0, 0.0, 0.0)));
        let faces = a.topology().faces().iter().map(|f| f.to_vec());
        let shifted = b.topology().faces().iter().map(|f| f.iter().map(|&v| v + offset).collect::<Vec<_>>());
        Mesh::new(p, subdiv_mesh::FaceList::from_faces(faces.chain(shifted))).expect("two closed components")
    };
    let (ico, torus) = (shapes::icosahedron(), shapes::torus(6, 4));
    for mesh in [union(&ico, &cube), union(&cube, &ico)] {
        assert!(matches!(catmull_clark_degeneracy(mesh.topology()), Some(Degeneracy::Singular { .. })));
    }
    assert_eq!(catmull_clark_degeneracy(union(&ico, &torus).topology()), None);
    // Fixtures with every valence ≥ 3 and not bipartite-cubic are not flagged.
    for stem in ["spot_control_mesh", "mpi", "torus_quad_16x8"] {
        assert_eq!(catmull_clark_degeneracy(fixture(stem).topology()), None, "{stem}");
    }
}

/// Gaps of the tracked points from the prediction after each level, relative to d.
fn assert_geometric(name: &str, gaps: &[f64], ratio: f64, final_tol: f64) {
    for w in gaps.windows(2).skip(1) {
        if w[0] > 1e-13 {
            assert!(w[1] <= ratio * w[0] + 1e-15, "{name}: gaps {:.3e} do not shrink by {ratio}", Gaps(gaps));
        }
    }
    assert!(*gaps.last().unwrap() <= final_tol, "{name}: final gap {:.3e}", gaps.last().unwrap());
}

fn jittered(mesh: &Mesh, seed: u64) -> Mesh {
    let mut rng = shapes::SplitMix64(seed);
    let scale = shapes::mean_edge_length(mesh) * 0.2;
    let p = mesh
        .positions()
        .iter()
        .map(|&p| p + scale * DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5))
        .collect();
    mesh.with_positions(p)
}

/// Primal schemes: input vertex v keeps index v at every level; its position
/// converges to row v of A·P.
#[test]
fn brute_force_primal_limits() {
    const LEVELS: usize = 9;
    let cases: Vec<(String, Mesh, Scheme, LimitMatrix)> = {
        let mut v = Vec::new();
        for stem in ["pyramid_mixed", "cube_poly", "corner_poly"] {
            let m = jittered(&fixture(stem), 1);
            let a = limit_matrix_catmull_clark(m.topology());
            v.push((format!("A on {stem}"), m, Scheme::CatmullClark, a));
        }
        let open = jittered(&shapes::polygon_mix(&shapes::quad_grid(3, 2), 9, 0.0, 0.0, 0.1), 2);
        let a = limit_matrix_catmull_clark(open.topology());
        v.push(("A on open grid".into(), open, Scheme::CatmullClark, a));
        for (stem, m) in [
            ("octahedron", fixture("octahedron")),
            ("tetrahedron", fixture("tetrahedron")),
            ("open tri grid", shapes::triangle_grid(2, 2)),
        ] {
            let m = jittered(&m, 3);
            for beta in [LoopBeta::Warren, LoopBeta::Loop] {
                let l = limit_matrix_loop(m.topology(), beta).unwrap();
                v.push((format!("L({beta:?}) on {stem}"), m.clone(), Scheme::Loop(beta), l));
            }
        }
        v
    };
    for (name, mesh, scheme, a) in cases {
        let d = mesh.bbox_diagonal();
        let predicted = a.apply(mesh.positions());
        let plan = SubdivisionPlan::new(mesh.topology(), scheme, LEVELS).unwrap();
        let mut positions = mesh.positions().to_vec();
        let mut gaps = vec![gap(&positions, &predicted, d)];
        for level in plan.levels() {
            positions = apply(level.stencil.as_ref().unwrap(), &positions);
            gaps.push(gap(&positions, &predicted, d));
        }
        eprintln!("{name}: {:.2e}", Gaps(&gaps));
        assert_geometric(&name, &gaps, 0.6, 1e-6);
    }
}

/// Prints a gap sequence in scientific notation.
struct Gaps<'a>(&'a [f64]);

impl std::fmt::LowerExp for Gaps<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = f.precision().unwrap_or(2);
        let parts: Vec<String> = self.0.iter().map(|g| format!("{g:.p$e}")).collect();
        write!(f, "[{}]", parts.join(", "))
    }
}

fn gap(positions: &[DVec3], predicted: &[DVec3], d: f64) -> f64 {
    predicted.iter().zip(positions).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max) / d
}

/// Doo-Sabin family: the limit of v is the centroid of its V-face after the
/// first step; that face's F-face descendants (same face id at every level)
/// keep the centroid and shrink onto it. Whole-mesh subdivision for 8 levels,
/// then the face alone (its F-face rule) until the gap is below 1e-6·d.
#[test]
fn brute_force_doo_sabin_limits() {
    let meshes = vec![
        ("mpi", jittered(&fixture("mpi"), 4)),
        ("pyramid_mixed", jittered(&fixture("pyramid_mixed"), 5)),
        ("open plate", jittered(&shapes::plate_with_holes(5, 4, &[(2, 1)], false), 6)),
    ];
    for (name, mesh) in meshes {
        let t = mesh.topology();
        let d = mesh.bbox_diagonal();
        let lambdas: Vec<f64> = (0..t.face_count()).map(|f| 0.25 + 0.5 * ((f * 17) % 7) as f64 / 7.0).collect();
        for (m, rule, a) in [
            ("C", CornerRule::Standard, limit_matrix_nasri(t)),
            ("Z", CornerRule::Uniform(0.5), limit_matrix_zheng_cai(t)),
            ("B(λ)", CornerRule::PerFace(&lambdas), limit_matrix_two_phase(t, CornerRule::PerFace(&lambdas)).unwrap()),
        ] {
            let predicted = a.apply(mesh.positions());
            // First step with the method's rule, then standard Doo-Sabin.
            let (t1, prov, r1) = doo_sabin::refine(t, &rule).unwrap();
            let p1 = apply(&r1, mesh.positions());
            let plan = SubdivisionPlan::new(&t1, Scheme::DooSabin, 7).unwrap();
            let interior: Vec<usize> = t.vertices().filter(|&v| !t.is_boundary_vertex(v)).map(|v| v.index()).collect();
            let mut positions = p1;
            let mut topo = &t1;
            let mut gaps = Vec::new();
            let track = |topo: &Topology, positions: &[DVec3]| {
                let mut worst = 0.0f64;
                for &v in &interior {
                    let Some(face) = prov.vertex_face[v] else { continue };
                    assert!(matches!(prov.face_origin[face.index()], DualFace::V(_)));
                    let corners: Vec<DVec3> = topo.face(face).iter().map(|&c| positions[c as usize]).collect();
                    let centroid = corners.iter().sum::<DVec3>() / corners.len() as f64;
                    assert!(centroid.distance(predicted[v]) <= 1e-12 * d, "{m} on {name}: centroid drifted");
                    worst = worst.max(corners.iter().map(|c| c.distance(predicted[v])).fold(0.0, f64::max));
                }
                worst / d
            };
            gaps.push(track(topo, &positions));
            for level in plan.levels() {
                positions = apply(level.stencil.as_ref().unwrap(), &positions);
                topo = &level.topology;
                gaps.push(track(topo, &positions));
            }
            // Continue on each tracked face alone: its F-face is Eq. 1 applied within the face.
            let mut faces: Vec<Vec<DVec3>> = interior
                .iter()
                .filter_map(|&v| {
                    prov.vertex_face[v].map(|f| topo.face(f).iter().map(|&c| positions[c as usize]).collect())
                })
                .collect();
            let targets: Vec<DVec3> =
                interior.iter().filter(|&&v| prov.vertex_face[v].is_some()).map(|&v| predicted[v]).collect();
            for _ in 0..14 {
                for face in &mut faces {
                    let m = face.len();
                    let mut w = vec![0.0; m];
                    subdiv_rules::doo_sabin_weights(m, &mut w);
                    *face = (0..m).map(|k| (0..m).map(|j| w[j] * face[(k + j) % m]).sum()).collect();
                }
                let worst = faces
                    .iter()
                    .zip(&targets)
                    .map(|(f, t)| f.iter().map(|c| c.distance(*t)).fold(0.0, f64::max))
                    .fold(0.0, f64::max);
                gaps.push(worst / d);
            }
            eprintln!("{m} on {name}: {:.2e}", Gaps(&gaps));
            assert_geometric(&format!("{m} on {name}"), &gaps, 0.75, 1e-6);
        }
    }
}

/// Meshes with interior valence-2 vertices (split edges; the pillow).
fn valence_two_meshes() -> Vec<(&'static str, Mesh)> {
    use subdiv_mesh::EdgeId;
    let spot = fixture("spot_control_mesh");
    let mix = shapes::polygon_mix(&shapes::torus(8, 6), 3, 0.2, 0.2, 0.05);
    let grid = shapes::quad_grid(5, 4);
    let interior: Vec<EdgeId> =
        grid.topology().edges().filter(|&e| grid.topology().edge_faces(e).1.is_some()).collect();
    let once = shapes::split_edges(&spot, &[EdgeId(3), EdgeId(40), EdgeId(41)], 0.05);
    // Split an edge next to the first new vertex again: two adjacent valence-2 vertices.
    let first = once.topology().vertex_fan(subdiv_mesh::VertexId(spot.topology().vertex_count() as u32))[0];
    let twice = shapes::split_edges(&once, &[once.topology().he_edge(first)], -0.05);
    vec![
        ("pillow", shapes::pillow()),
        ("spot, 4 valence-2 (2 adjacent)", twice),
        ("torus mix, 3 valence-2", shapes::split_edges(&mix, &[EdgeId(1), EdgeId(17), EdgeId(60)], 0.1)),
        ("open grid, 2 valence-2", shapes::split_edges(&grid, &[interior[2], interior[9]], 0.2)),
    ]
}

/// The Doo-Sabin matrices at valence 2: rows sum to 1, each valence-2 row
/// is D·S = the plain mask ⅜(v₀ + v₁) + 1/16(a₀ + a₁ + b₀ + b₁) of the first
/// step's images (for C: equal to the limit stencil's row, whose point the
/// brute-force tests of `properties.rs` track), S stays symmetric bit for
/// bit between vertices of valence ≥ 3, and the spectrum — no longer real in
/// general — keeps positive real parts and moduli ≤ 1 + ε, so progressive
/// iteration still converges and the systems are nonsingular.
#[test]
fn doo_sabin_matrices_at_valence_two() {
    for (name, mesh) in valence_two_meshes() {
        let t = mesh.topology();
        let v2: Vec<usize> =
            t.vertices().filter(|&v| !t.is_boundary_vertex(v) && t.valence(v) == 2).map(|v| v.index()).collect();
        assert!(!v2.is_empty(), "{name}");
        let c = limit_matrix_nasri(t).to_csr();
        let stencil = doo_sabin::limit_stencil(t);
        for &v in &v2 {
            let (a, b) = (c.outer_view(v).unwrap(), stencil.outer_view(v).unwrap());
            let cols = a.indices().to_vec();
            assert_eq!(cols, b.indices().to_vec(), "{name}: C row {v} pattern");
            for (x, y) in a.data().iter().zip(b.data()) {
                assert!((x - y).abs() <= 1e-15, "{name}: C row {v}: {x} vs {y}");
            }
        }
        let lambdas: Vec<f64> = (0..t.face_count()).map(|f| 0.2 + 0.6 * ((f * 7) % 5) as f64 / 4.0).collect();
        let ms = [
            ("C", limit_matrix_nasri(t)),
            ("Z", limit_matrix_zheng_cai(t)),
            ("B(λ)", limit_matrix_two_phase(t, CornerRule::PerFace(&lambdas)).unwrap()),
        ];
        for (m, a) in &ms {
            let csr = a.to_csr();
            for (i, row) in csr.outer_iterator().enumerate() {
                let sum: f64 = row.data().iter().sum();
                assert!((sum - 1.0).abs() < 1e-14, "{m} on {name}: row {i} sums to {sum}");
            }
            let special: std::collections::HashSet<u32> =
                a.boundary_rows.iter().copied().chain(v2.iter().map(|&v| v as u32)).collect();
            for (i, row) in a.s.outer_iterator().enumerate() {
                for (j, &x) in
                    row.iter().filter(|&(j, _)| !special.contains(&(i as u32)) && !special.contains(&(j as u32)))
                {
                    assert_eq!(x.to_bits(), a.s.get(j, i).unwrap().to_bits(), "{m} on {name}: S[{i}][{j}]");
                }
            }
            if a.size() <= 400 {
                let n = a.size();
                let mut dense = DMatrix::zeros(n, n);
                for (i, row) in csr.outer_iterator().enumerate() {
                    for (j, &x) in row.iter() {
                        dense[(i, j)] = x;
                    }
                }
                // Schur with an iteration cap (the uncapped form may not return).
                let schur = nalgebra::linalg::Schur::try_new(dense, 1e-14, 100_000)
                    .unwrap_or_else(|| panic!("{m} on {name}: Schur decomposition did not converge"));
                let ev = schur.complex_eigenvalues();
                let min_re = ev.iter().map(|z| z.re).fold(f64::INFINITY, f64::min);
                let max_abs = ev.iter().map(|z| z.norm()).fold(0.0, f64::max);
                let min_abs = ev.iter().map(|z| z.norm()).fold(f64::INFINITY, f64::min);
                eprintln!("{m} on {name}: min Re λ {min_re:.4}, |λ| in [{min_abs:.4}, {max_abs:.4}]");
                assert!(min_re > 0.0 && max_abs <= 1.0 + 1e-12, "{m} on {name}: min Re {min_re}, max |λ| {max_abs}");
            }
        }
    }
}

/// The structural kernel of Cheng's A: one checkerboard per closed
/// all-valence-3 bipartite component, each exactly in the kernel; none on
/// meshes with other valences or an odd cycle.
#[test]
fn catmull_clark_kernel_vectors_are_annihilated_by_a() {
    let two = |a: Mesh, b: Mesh| {
        let n = a.topology().vertex_count() as u32;
        let mut p = a.positions().to_vec();
        p.extend(b.positions().iter().map(|&x| x + DVec3::new(5.0, 0.0, 0.0)));
        let faces = subdiv_mesh::FaceList::from_faces(
            a.topology()
                .faces()
                .iter()
                .map(<[u32]>::to_vec)
                .chain(b.topology().faces().iter().map(|f| f.iter().map(|&v| v + n).collect::<Vec<_>>())),
        );
        Mesh::new(p, faces).unwrap()
    };
    let cases = [
        ("cube", shapes::cube(), 1),
        ("hexagonal prism", shapes::prism(6), 1),
        ("pentagonal prism (odd cycle)", shapes::prism(5), 0),
        ("cube + icosahedron", two(shapes::cube(), shapes::icosahedron()), 1),
        ("cube + cube", two(shapes::cube(), shapes::cube()), 2),
        ("torus", shapes::torus(6, 4), 0),
    ];
    for (name, mesh, expected) in cases {
        let t = mesh.topology();
        let kernel = subdiv_stencil::catmull_clark_kernel(t);
        assert_eq!(kernel.len(), expected, "{name}");
        let a = limit_matrix_catmull_clark(t).to_csr();
        for c in &kernel {
            let mut x = vec![0.0; t.vertex_count()];
            c.iter().for_each(|&(v, s)| x[v.index()] = s);
            for (i, row) in a.outer_iterator().enumerate() {
                let ax: f64 = row.iter().map(|(j, &w)| w * x[j]).sum();
                assert!(ax.abs() <= 1e-15, "{name}: (A·c)[{i}] = {ax}");
            }
        }
        assert_eq!(catmull_clark_degeneracy(t).is_some(), expected > 0, "{name}");
    }
}

/// The row kinds of the untagged matrices: boundary curve rows are crease
/// rows, corners and isolated vertices identity rows, the Doo-Sabin rows of
/// interior valence-2 vertices general rows, every other row smooth; the
/// sharp block is all boundary and corner rows, and the interior block is
/// asymmetric only at the valence-2 rows.
#[test]
fn row_kinds_of_the_untagged_matrices() {
    use subdiv_stencil::limit_matrix::RowKind;
    let mut meshes = all_meshes();
    meshes.extend(valence_two_meshes());
    for (name, mesh) in meshes {
        let t = mesh.topology();
        for (m, a) in matrices(&mesh) {
            let doo_sabin = !matches!(m, "A" | "L");
            for v in t.vertices() {
                let one_face_corner = t.is_boundary_vertex(v) && t.vertex_face_count(v) == 1 && !doo_sabin;
                let expected = if t.is_isolated(v) || one_face_corner {
                    RowKind::Corner
                } else if t.is_boundary_vertex(v) {
                    RowKind::Crease
                } else if doo_sabin && t.valence(v) == 2 {
                    RowKind::General
                } else {
                    RowKind::Smooth
                };
                assert_eq!(a.row_kinds[v.index()], expected, "{m} on {name}: vertex {}", v.0);
            }
            let mut sharp = a.rows_of(RowKind::Crease);
            sharp.extend(a.rows_of(RowKind::Corner));
            sharp.sort_unstable();
            assert_eq!(a.boundary_rows, sharp, "{m} on {name}");
            let general: std::collections::HashSet<usize> =
                a.rows_of(RowKind::General).into_iter().map(|v| v as usize).collect();
            for v in a.asymmetric_rows(&subdiv_interp::solve_blocks(&a).interior) {
                let row = a.s.outer_view(v as usize).unwrap();
                let near =
                    general.contains(&(v as usize)) || row.indices().iter().any(|&j| general.contains(&(j as usize)));
                assert!(near, "{m} on {name}: row {v} asymmetric away from valence 2");
            }
        }
    }
}
