//! Properties of the operators that follow from the theory, each checked
//! against an independent derivation (B-spline evaluators, box-spline masks,
//! curve schemes, brute-force subdivision), never against our own output.

use crate::common;
use crate::common::Mask;

use glam::DVec3;
use subdiv_mesh::refine::{DualFace, DualVertex};
use subdiv_mesh::shapes::{self, SplitMix64};
use subdiv_mesh::{Mesh, Topology, VertexId};
use subdiv_rules::curves;
use subdiv_stencil::doo_sabin;
use subdiv_stencil::{apply, catmull_clark, deng_ma, loop_subdivision, row_sums};
use subdiv_stencil::{LoopBeta, Scheme, SparseMatrix, SubdivisionPlan, Tension};

// ---------------------------------------------------------------- helpers

fn is_triangle_mesh(t: &Topology) -> bool {
    t.faces().all_of_size(3)
}

/// Positions after each level of a plan: `out[k]` = level k (`out[0]` = input).
fn positions_per_level(plan: &SubdivisionPlan, p0: &[DVec3]) -> Vec<Vec<DVec3>> {
    let mut out = vec![p0.to_vec()];
    let mut coarse = plan.base();
    for level in plan.levels() {
        let current = out.last().expect("level 0");
        let next = match (&level.stencil, plan.scheme()) {
            (Some(r), _) => apply(r, current),
            (None, Scheme::DengMa(tension)) => deng_ma::step_positions(coarse, current, tension).unwrap(),
            (None, s) => panic!("{s:?} level without a stencil"),
        };
        out.push(next);
        coarse = &level.topology;
    }
    out
}

fn max_dist(a: &[DVec3], b: &[DVec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| x.distance(*y)).fold(0.0, f64::max)
}

fn face_centroid(t: &Topology, p: &[DVec3], f: subdiv_mesh::FaceId) -> DVec3 {
    let face = t.face(f);
    face.iter().map(|&v| p[v as usize]).sum::<DVec3>() / face.len() as f64
}

/// The closed mesh fixtures and shapes used by several tests.
fn closed_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("cube with a split edge (valence 2)", cube_with_split_edge()),
        ("cube_quad", common::fixture("cube_quad")),
        ("pyramid_mixed", common::fixture("pyramid_mixed")),
        ("mpi", common::fixture("mpi")),
        ("P", common::fixture("P")),
        ("torus 8x6", shapes::torus(8, 6)),
        ("icosahedron", shapes::icosahedron()),
        (
            "plate mix (closed, 2 holes)",
            shapes::polygon_mix(&shapes::plate_with_holes(6, 5, &[(1, 1), (3, 3)], true), 11, 0.3, 0.2, 0.1),
        ),
    ]
}

/// Open meshes: with corners, several boundary loops, triangles.
fn open_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("grid_quad_8x8_open", common::fixture("grid_quad_8x8_open")),
        ("halftunnel", common::fixture("halftunnel")),
        ("nefertiti_small", common::fixture("nefertiti_small")),
        ("grid (tri)", common::fixture("grid")),
        (
            "plate mix (open, 2 holes)",
            shapes::polygon_mix(&shapes::plate_with_holes(7, 6, &[(2, 1), (4, 3)], false), 5, 0.3, 0.2, 0.1),
        ),
        ("triangle_grid 5x4", shapes::triangle_grid(5, 4)),
    ]
}

fn schemes_for(t: &Topology) -> Vec<Scheme> {
    let mut s = vec![Scheme::CatmullClark, Scheme::DooSabin];
    if is_triangle_mesh(t) {
        s.push(Scheme::Loop(LoopBeta::Warren));
        s.push(Scheme::Loop(LoopBeta::Loop));
    }
    if t.is_closed() {
        s.push(Scheme::DengMa(Tension::Global(1.0)));
        s.push(Scheme::DengMa(Tension::Global(0.4)));
    }
    s
}

fn assert_affine(name: &str, what: &str, r: &SparseMatrix) {
    for (i, s) in row_sums(r).iter().enumerate() {
        assert!((s - 1.0).abs() <= 1e-14, "{name}: {what}: row {i} sums to {s:.17}");
    }
}

// ---------------------------------------------------------------- row sums

#[test]
fn every_stencil_row_sums_to_one() {
    let mut count = 0;
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let t = mesh.topology();
        for scheme in schemes_for(t) {
            let plan = SubdivisionPlan::new(t, scheme, 3).unwrap();
            let mut coarse = t;
            for (k, level) in plan.levels().iter().enumerate() {
                let what = format!("{scheme:?} R level {}", k + 1);
                match (&level.stencil, scheme) {
                    (Some(r), _) => assert_affine(name, &what, r),
                    // The plan evaluates Deng-Ma geometrically; its matrix is built on request.
                    (None, Scheme::DengMa(Tension::Global(omega))) => {
                        assert_affine(name, &what, &deng_ma::stencil(coarse, omega).unwrap())
                    }
                    (None, _) => panic!("{name}: {what}: no stencil"),
                }
                count += 1;
                coarse = &level.topology;
            }
            if let Some(Ok(l)) = plan.limit_stencil() {
                assert_affine(name, &format!("{scheme:?} limit stencil after 3 levels"), &l);
            }
        }
        assert_affine(name, "catmull-clark limit stencil (Cheng Eq. 5)", &catmull_clark::limit_stencil(t));
        assert_affine(name, "doo-sabin limit stencil", &doo_sabin::limit_stencil(t));
        if is_triangle_mesh(t) {
            for beta in [LoopBeta::Warren, LoopBeta::Loop] {
                assert_affine(
                    name,
                    &format!("loop {beta:?} limit stencil"),
                    &loop_subdivision::limit_stencil(t, beta).unwrap(),
                );
            }
        }
        let mut rng = SplitMix64(7);
        let lambdas: Vec<f64> = (0..t.face_count()).map(|_| 0.05 + 0.9 * rng.next_f64()).collect();
        for rule in [Mask::Uniform(0.5), Mask::Uniform(0.85), Mask::PerFace(&lambdas)] {
            assert_affine(name, &format!("doo-sabin {rule:?}"), &doo_sabin::refinement_stencil(t, &rule).unwrap());
        }
    }
    assert!(count > 100);
}

// ---------------------------------------------------------------- Doo-Sabin

#[test]
fn doo_sabin_first_step_equals_the_stencil_product() {
    // A big face too (m = 40 > the weight table), beside the fixtures.
    let big = {
        let ring: Vec<DVec3> =
            (0..40).map(|k| DVec3::new((k as f64 * 0.157).cos(), (k as f64 * 0.157).sin(), 0.0)).collect();
        let mut p = ring.clone();
        p.push(DVec3::new(0.0, 0.0, 0.0));
        let mut faces = vec![(0..40u32).collect::<Vec<_>>()];
        faces.extend((0..40u32).map(|k| vec![(k + 1) % 40, k, 40]));
        ("40-gon with a triangle fan", Mesh::new(p, subdiv_mesh::FaceList::from_faces(faces)).unwrap())
    };
    let mut meshes = closed_meshes();
    meshes.extend(open_meshes());
    meshes.push(big);
    // Enough corners (> 8192) for parallel chunks, which then start inside faces.
    let mix = shapes::polygon_mix(&shapes::plate_with_holes(80, 60, &[(20, 20)], false), 2, 0.3, 0.2, 0.1);
    assert!(mix.topology().half_edge_count() > 3 * 4096);
    let starts_inside = |h: u32| mix.topology().faces().offsets().binary_search(&h).is_err();
    assert!(starts_inside(4096) || starts_inside(8192), "a chunk boundary falls inside a face");
    meshes.push(("large plate mix (open)", mix));
    for (name, mesh) in meshes {
        let t = mesh.topology();
        let x = mesh.positions();
        let d = mesh.bbox_diagonal();
        let mut rng = SplitMix64(3);
        let lambdas: Vec<f64> = (0..t.face_count()).map(|_| 0.05 + 0.9 * rng.next_f64()).collect();
        for rule in [Mask::Standard, Mask::Uniform(0.5), Mask::PerFace(&lambdas)] {
            let direct = doo_sabin::first_step(t, &rule, x).unwrap();
            let product = apply(&doo_sabin::refinement_stencil(t, &rule).unwrap(), x);
            assert_eq!(direct.len(), product.len(), "{name}, {rule:?}");
            let gap = max_dist(&direct, &product);
            assert!(gap <= 1e-15 * d, "{name}, {rule:?}: {gap:e}");
        }
    }
    let cube = shapes::cube();
    assert!(doo_sabin::first_step(cube.topology(), &Mask::PerFace(&[2.0]), cube.positions()).is_err());
}

/// The limit points evaluated row by row (what surfaces and error reports
/// use) equal the limit stencil's product, on every mesh kind — boundaries,
/// corners, valence 2, an isolated vertex, a 40-gon, and a refined mesh large
/// enough for parallel chunks — and do not depend on the thread count.
#[test]
fn limit_points_equal_the_limit_stencil_product() {
    let with_isolated = {
        let base = shapes::octahedron();
        let mut p = base.positions().to_vec();
        p.push(DVec3::new(5.0, -3.0, 2.0));
        ("octahedron + isolated vertex", Mesh::new(p, base.topology().faces().clone()).unwrap())
    };
    let large = shapes::polygon_mix(&shapes::plate_with_holes(60, 50, &[(20, 20)], false), 2, 0.3, 0.2, 0.1);
    let large_tri = {
        let t = shapes::triangle_grid(70, 60);
        bumpy(t, 5)
    };
    let mut meshes = closed_meshes();
    meshes.extend(open_meshes());
    meshes.push(with_isolated);
    meshes.push(("large plate mix (open)", large));
    meshes.push(("large triangle grid", large_tri));
    let mut large_rows = 0;
    for (name, mesh) in meshes {
        let (t, x, d) = (mesh.topology(), mesh.positions(), mesh.bbox_diagonal());
        let check = |what: &str, direct: Vec<DVec3>, product: Vec<DVec3>| {
            assert_eq!(direct.len(), product.len(), "{name}: {what}");
            let gap = max_dist(&direct, &product);
            assert!(gap <= 2e-15 * d, "{name}: {what}: {gap:e}");
        };
        check("doo-sabin", doo_sabin::limit_points(t, x), apply(&doo_sabin::limit_stencil(t), x));
        check("catmull-clark", catmull_clark::limit_points(t, x), apply(&catmull_clark::limit_stencil(t), x));
        if is_triangle_mesh(t) {
            for beta in [LoopBeta::Warren, LoopBeta::Loop] {
                let product = apply(&loop_subdivision::limit_stencil(t, beta).unwrap(), x);
                check("loop", loop_subdivision::limit_points(t, beta, x).unwrap(), product);
            }
        } else {
            assert!(loop_subdivision::limit_points(t, LoopBeta::Warren, x).is_err(), "{name}");
        }
        for scheme in schemes_for(t) {
            let plan = SubdivisionPlan::new(t, scheme, 2).unwrap();
            let q = plan.apply(x);
            match (plan.limit_points(&q), plan.limit_stencil().transpose().unwrap()) {
                (Some(direct), Some(l)) => check(&format!("{scheme:?} after 2 levels"), direct, apply(&l, &q)),
                (None, None) => assert!(matches!(scheme, Scheme::DengMa(_))),
                _ => panic!("{name}: {scheme:?}: limit points and stencil disagree on existing"),
            }
            if scheme == Scheme::CatmullClark && q.len() > 8 * 4096 {
                large_rows += 1;
                let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
                let serial = one.install(|| plan.limit_points(&q).unwrap());
                let parallel = plan.limit_points(&q).unwrap();
                assert!(serial
                    .iter()
                    .zip(&parallel)
                    .all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits)));
            }
        }
    }
    assert!(large_rows >= 2, "two meshes are large enough for parallel chunks");
}

/// The single-use `subdivide` (level by level, Doo-Sabin without stencils)
/// gives the plan's mesh: the same faces, points equal up to round-off.
#[test]
fn single_use_subdivide_equals_the_plan() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let d = mesh.bbox_diagonal();
        for scheme in schemes_for(mesh.topology()) {
            for (levels, limit) in [(0, true), (1, false), (2, true), (3, false)] {
                let planned =
                    SubdivisionPlan::new(mesh.topology(), scheme, levels).unwrap().subdivide(&mesh, limit).unwrap();
                let single = subdiv_stencil::subdivide(&mesh, scheme, levels, limit).unwrap();
                let what = format!("{name}: {scheme:?}, {levels} levels, limit {limit}");
                assert_eq!(single.topology().faces(), planned.topology().faces(), "{what}");
                let gap = max_dist(single.positions(), planned.positions());
                assert!(gap <= 2e-15 * d, "{what}: {gap:e}");
            }
        }
    }
    let cube = shapes::cube();
    assert!(subdiv_stencil::subdivide(&cube, Scheme::Loop(LoopBeta::Warren), 1, false).is_err());
}

#[test]
fn doo_sabin_f_faces_keep_their_centroids() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let d = mesh.bbox_diagonal();
        let plan = SubdivisionPlan::new(mesh.topology(), Scheme::DooSabin, 3).unwrap();
        let p = positions_per_level(&plan, mesh.positions());
        let mut coarse = mesh.topology();
        for (k, level) in plan.levels().iter().enumerate() {
            let dual = level.dual.as_ref().expect("Doo-Sabin provenance");
            let mut checked = 0;
            for (fi, origin) in dual.face_origin.iter().enumerate() {
                if let DualFace::F(f) = *origin {
                    let new_c = face_centroid(&level.topology, &p[k + 1], subdiv_mesh::FaceId(fi as u32));
                    let old_c = face_centroid(coarse, &p[k], f);
                    let e = new_c.distance(old_c) / d;
                    assert!(e <= 1e-14, "{name} level {}: F-face {fi} of face {f}: centroid moved by {e:e}·d", k + 1);
                    assert_eq!(level.topology.face_size(subdiv_mesh::FaceId(fi as u32)), coarse.face_size(f));
                    checked += 1;
                }
            }
            assert_eq!(checked, coarse.face_count(), "{name}: one F-face per old face");
            coarse = &level.topology;
        }
    }
}

#[test]
fn doo_sabin_step_makes_every_vertex_valence_four() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let t = mesh.topology();
        let plan = SubdivisionPlan::new(t, Scheme::DooSabin, 1).unwrap();
        let level = &plan.levels()[0];
        let (r, dual) = (&level.topology, level.dual.as_ref().unwrap());
        let mut boundary_points = 0;
        for v in r.vertices() {
            match dual.vertex_origin[v.index()] {
                DualVertex::Boundary { .. } => {
                    boundary_points += 1;
                    assert!(r.is_boundary_vertex(v), "{name}: Chaikin point {v} not on the boundary");
                    assert_eq!((r.valence(v), r.vertex_face_count(v)), (3, 2), "{name}: Chaikin point {v}");
                }
                DualVertex::Corner { vertex, .. } => {
                    assert!(!r.is_boundary_vertex(v), "{name}: corner image {v} on the boundary");
                    // The documented exception: an interior vertex of valence 2
                    // gets no (digon) V-face, so its two images have valence 3.
                    let expect = if !t.is_boundary_vertex(vertex) && t.valence(vertex) == 2 { 3 } else { 4 };
                    assert_eq!(
                        r.valence(v),
                        expect,
                        "{name}: image {v} of vertex {vertex} (valence {})",
                        t.valence(vertex)
                    );
                }
            }
        }
        let old_boundary_edges: usize = t.boundary_loops().map(<[_]>::len).sum();
        assert_eq!(boundary_points, 2 * old_boundary_edges, "{name}");
        assert_eq!(t.is_closed(), boundary_points == 0);
    }
}

// ---------------------------------------------------------------- regular grids vs tensor-product B-splines

/// Centred uniform cubic B-spline (support [−2, 2], value 2/3 at 0).
fn bspline3(t: f64) -> f64 {
    let a = t.abs();
    if a < 1.0 {
        2.0 / 3.0 - a * a + 0.5 * a * a * a
    } else if a < 2.0 {
        (2.0 - a).powi(3) / 6.0
    } else {
        0.0
    }
}

/// Centred uniform quadratic B-spline (support [−3/2, 3/2], value 3/4 at 0).
fn bspline2(t: f64) -> f64 {
    let a = t.abs();
    if a < 0.5 {
        0.75 - a * a
    } else if a < 1.5 {
        0.5 * (1.5 - a) * (1.5 - a)
    } else {
        0.0
    }
}

/// Tensor-product surface Σ B(u − i)B(v − j)P_ij over an (nx+1)×(ny+1) net
/// stored row by row (P_ij at index j(nx+1) + i).
fn tensor_surface(net: &[DVec3], (nx, ny): (usize, usize), basis: fn(f64) -> f64, u: f64, v: f64) -> DVec3 {
    assert_eq!(net.len(), (nx + 1) * (ny + 1));
    let mut s = DVec3::ZERO;
    for j in 0..=ny {
        for i in 0..=nx {
            s += basis(u - i as f64) * basis(v - j as f64) * net[j * (nx + 1) + i];
        }
    }
    s
}

/// A quad or triangle grid with random heights z ∈ [−1, 1] (x, y = i, j).
fn bumpy(mesh: Mesh, seed: u64) -> Mesh {
    let mut rng = SplitMix64(seed);
    let p = mesh.positions().iter().map(|p| DVec3::new(p.x, p.y, 2.0 * rng.next_f64() - 1.0)).collect();
    mesh.with_positions(p)
}

#[test]
fn catmull_clark_on_a_regular_grid_is_the_bicubic_bspline() {
    let (nx, ny) = (9, 8);
    let grid = bumpy(shapes::quad_grid(nx, ny), 42);
    let d = grid.bbox_diagonal();
    for levels in [3, 4] {
        let plan = SubdivisionPlan::new(grid.topology(), Scheme::CatmullClark, levels).unwrap();
        let limit = apply(&plan.limit_stencil().unwrap().unwrap(), &plan.apply(grid.positions()));
        // Parameters of the refined vertices, from the combinatorics of the
        // split alone: old vertices keep theirs, face points take the face's
        // centre, edge points the edge's midpoint.
        let mut params: Vec<DVec3> = shapes::quad_grid(nx, ny).positions().to_vec();
        let mut t = grid.topology();
        for level in plan.levels() {
            let mut next = params.clone();
            next.extend(t.face_ids().map(|f| face_centroid(t, &params, f)));
            next.extend(t.edges().map(|e| {
                let (a, b) = t.edge_vertices(e);
                0.5 * (params[a.index()] + params[b.index()])
            }));
            params = next;
            t = &level.topology;
        }
        assert_eq!(params.len(), limit.len());
        let mut worst: f64 = 0.0;
        let mut checked = 0;
        for (uv, l) in params.iter().zip(&limit) {
            // At least two coarse rings from the boundary.
            if uv.x < 2.0 || uv.x > (nx - 2) as f64 || uv.y < 2.0 || uv.y > (ny - 2) as f64 {
                continue;
            }
            let expect = tensor_surface(grid.positions(), (nx, ny), bspline3, uv.x, uv.y);
            worst = worst.max(expect.distance(*l) / d);
            checked += 1;
        }
        assert!(checked >= 25 * 4usize.pow(levels as u32 - 1), "only {checked} points checked");
        assert!(worst <= 1e-13, "levels {levels}: limit points off the bicubic B-spline by {worst:e}·d");
    }
}

#[test]
fn doo_sabin_on_a_regular_grid_is_the_biquadratic_bspline() {
    let (nx, ny) = (8, 9);
    let grid = bumpy(shapes::quad_grid(nx, ny), 17);
    let d = grid.bbox_diagonal();
    let plan = SubdivisionPlan::new(grid.topology(), Scheme::DooSabin, 3).unwrap();
    let p = plan.apply(grid.positions());
    // Parameters from provenance alone: the image of V in face f sits half
    // way between V and the face's centre; a Chaikin point at ¾a + ¼b.
    let mut params: Vec<DVec3> = shapes::quad_grid(nx, ny).positions().to_vec();
    let mut t = grid.topology();
    for level in plan.levels() {
        let dual = level.dual.as_ref().unwrap();
        params = dual
            .vertex_origin
            .iter()
            .map(|o| match *o {
                DualVertex::Corner { face, vertex, .. } => {
                    0.5 * (params[vertex.index()] + face_centroid(t, &params, face))
                }
                DualVertex::Boundary { half_edge, near_start } => {
                    let (a, b) = (params[t.he_from(half_edge).index()], params[t.he_to(half_edge).index()]);
                    if near_start {
                        0.75 * a + 0.25 * b
                    } else {
                        0.25 * a + 0.75 * b
                    }
                }
            })
            .collect();
        t = &level.topology;
    }
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for f in t.face_ids() {
        let uv = face_centroid(t, &params, f);
        if uv.x < 2.0 || uv.x > (nx - 2) as f64 || uv.y < 2.0 || uv.y > (ny - 2) as f64 {
            continue;
        }
        assert_eq!(t.face_size(f), 4, "regular region");
        let expect = tensor_surface(grid.positions(), (nx, ny), bspline2, uv.x, uv.y);
        worst = worst.max(expect.distance(face_centroid(t, &p, f)) / d);
        checked += 1;
    }
    assert!(checked >= 4 * 5 * 50, "only {checked} faces checked");
    assert!(worst <= 1e-13, "face centroids off the biquadratic B-spline by {worst:e}·d");
}

#[test]
fn loop_on_the_regular_triangle_grid_has_the_box_spline_masks() {
    let (nx, ny) = (6, 5);
    let grid = shapes::triangle_grid(nx, ny);
    let t = grid.topology();
    // Lattice position of every vertex (the grid puts vertex (i, j) at (i, j, 0)).
    let ij = |v: VertexId| {
        let p = grid.position(v);
        (p.x.round() as i64, p.y.round() as i64)
    };
    let id = |i: i64, j: i64| -> Option<u32> {
        (i >= 0 && j >= 0 && i <= nx as i64 && j <= ny as i64).then(|| (j * (nx as i64 + 1) + i) as u32)
    };
    // The three directions of the quartic box spline for this diagonal.
    let dirs = [(1i64, 0i64), (0, 1), (1, 1)];
    let adjacent = |a: (i64, i64), b: (i64, i64)| {
        let d = (b.0 - a.0, b.1 - a.1);
        dirs.iter().any(|&e| e == d || (-e.0, -e.1) == d)
    };
    for beta in [LoopBeta::Warren, LoopBeta::Loop] {
        let r = loop_subdivision::refinement_stencil(t, beta).unwrap();
        let row = |i: usize| -> Vec<(u32, f64)> {
            let mut v: Vec<(u32, f64)> = r.outer_view(i).unwrap().iter().map(|(c, &w)| (c as u32, w)).collect();
            v.sort_by_key(|e| e.0);
            v
        };
        let check = |got: Vec<(u32, f64)>, mut want: Vec<(u32, f64)>, what: String| {
            want.sort_by_key(|e| e.0);
            assert_eq!(got.len(), want.len(), "{beta:?} {what}: {got:?} vs {want:?}");
            for (g, w) in got.iter().zip(&want) {
                assert!(g.0 == w.0 && (g.1 - w.1).abs() <= 1e-15, "{beta:?} {what}: {got:?} vs {want:?}");
            }
        };
        let mut vertices = 0;
        for v in t.vertices() {
            let (i, j) = ij(v);
            if i == 0 || j == 0 || i == nx as i64 || j == ny as i64 {
                continue;
            }
            // Vertex mask of the box spline: 10/16 centre, 1/16 on the six lattice neighbours.
            let mut want = vec![(v.0, 10.0 / 16.0)];
            for &(di, dj) in &dirs {
                for s in [1, -1] {
                    want.push((id(i + s * di, j + s * dj).unwrap(), 1.0 / 16.0));
                }
            }
            check(row(v.index()), want, format!("vertex ({i}, {j})"));
            vertices += 1;
        }
        let mut edges = 0;
        for e in t.edges() {
            if t.is_boundary_edge(e) {
                continue;
            }
            let (a, b) = t.edge_vertices(e);
            let (pa, pb) = (ij(a), ij(b));
            assert!(adjacent(pa, pb));
            // Edge mask: 3/8 on the ends, 1/8 on the two lattice points adjacent to both.
            let mut want = vec![(a.0, 3.0 / 8.0), (b.0, 3.0 / 8.0)];
            for ci in pa.0.min(pb.0) - 1..=pa.0.max(pb.0) + 1 {
                for cj in pa.1.min(pb.1) - 1..=pa.1.max(pb.1) + 1 {
                    let c = (ci, cj);
                    if c != pa && c != pb && adjacent(c, pa) && adjacent(c, pb) {
                        want.push((id(ci, cj).expect("interior edge"), 1.0 / 8.0));
                    }
                }
            }
            assert_eq!(want.len(), 4);
            check(row(t.vertex_count() + e.index()), want, format!("edge {pa:?}-{pb:?}"));
            edges += 1;
        }
        assert_eq!(vertices, (nx - 1) * (ny - 1));
        assert_eq!(edges, 3 * nx * ny - nx - ny);
    }
}

// ---------------------------------------------------------------- Deng-Ma

/// Closed meshes for Deng-Ma: cube, torus, icosahedron, a polygon mix.
fn deng_ma_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("cube_quad", common::fixture("cube_quad")),
        ("torus 8x6", shapes::torus(8, 6)),
        ("icosahedron", shapes::icosahedron()),
        ("torus mix", shapes::polygon_mix(&shapes::torus(6, 5), 3, 0.3, 0.3, 0.1)),
    ]
}

#[test]
fn deng_ma_keeps_old_vertices_and_converges() {
    for (name, mesh) in deng_ma_meshes() {
        for tension in [Tension::Global(1.0), Tension::Variable { lambda: 0.5 }] {
            let plan = SubdivisionPlan::new(mesh.topology(), Scheme::DengMa(tension), 5).unwrap();
            let p = positions_per_level(&plan, mesh.positions());
            let mut t = mesh.topology();
            let mut displacement = Vec::new();
            for (k, level) in plan.levels().iter().enumerate() {
                let (coarse, fine) = (&p[k], &p[k + 1]);
                // Interpolatory: old vertices kept bit for bit.
                assert!(
                    coarse.iter().zip(fine).all(|(a, b)| a == b),
                    "{name} {tension:?} level {}: an old vertex moved",
                    k + 1
                );
                // Edge points are numbered after old vertices and face points.
                let base = t.vertex_count() + t.face_count();
                let dmax = t
                    .edges()
                    .map(|e| {
                        let (a, b) = t.edge_vertices(e);
                        fine[base + e.index()].distance(0.5 * (coarse[a.index()] + coarse[b.index()]))
                    })
                    .fold(0.0, f64::max);
                displacement.push(dmax);
                t = &level.topology;
            }
            eprintln!("{name} {tension:?}: max edge-point displacement per level {}", fmt_gaps(&displacement));
            // Geometric decay: per level from the second refinement on (the
            // first ratio compares a step of the coarse, non-smooth control
            // net with one of its refinement and may be larger), and on
            // average over all five levels.
            for k in 2..displacement.len() {
                let ratio = displacement[k] / displacement[k - 1];
                assert!(
                    ratio < 0.6,
                    "{name} {tension:?}: edge-point displacement {} shrinks by {ratio} at level {}",
                    fmt_gaps(&displacement),
                    k + 1
                );
            }
            let mean_ratio = (displacement[4] / displacement[0]).powf(0.25);
            assert!(mean_ratio < 0.6, "{name} {tension:?}: mean ratio {mean_ratio} ({})", fmt_gaps(&displacement));
        }
    }
}

/// On a regular quad torus with data that varies along one direction only,
/// the Deng-Ma step is the 4-point curve scheme along that direction with
/// tension ω/16 ([correction D4]), and constant across it.
///
/// [correction D4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d4
#[test]
fn deng_ma_on_one_dimensional_data_is_the_four_point_scheme() {
    let (nu, nv) = (11, 6);
    let t = shapes::torus(nu, nv).topology().clone();
    let mut rng = SplitMix64(99);
    let curve: Vec<[f64; 3]> = (0..nu)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / nu as f64;
            [3.0 * a.cos() + 0.3 * rng.next_f64(), 2.0 * a.sin() + 0.3 * rng.next_f64(), rng.next_f64()]
        })
        .collect();
    // Vertex (i, j) of the torus is i·nv + j.
    let p: Vec<DVec3> = (0..nu * nv).map(|v| DVec3::from_array(curve[v / nv])).collect();
    for omega in [1.0, 0.5] {
        let fine = curves::four_point(&curve, true, omega / 16.0);
        let q = apply(&deng_ma::stencil(&t, omega).unwrap(), &p);
        // Expected position of a point half way between rows i and i + 1, or on row i.
        let expect = |ia: usize, ib: usize| -> DVec3 {
            if ia == ib {
                DVec3::from_array(fine[2 * ia])
            } else {
                let lo = if (ia + 1) % nu == ib { ia } else { ib };
                DVec3::from_array(fine[2 * lo + 1])
            }
        };
        let row = |v: u32| v as usize / nv;
        let mut worst: f64 = 0.0;
        for f in t.face_ids() {
            let rows: Vec<usize> = t.face(f).iter().map(|&v| row(v)).collect();
            let (lo, hi) = (rows.iter().copied().min().unwrap(), rows.iter().copied().max().unwrap());
            let (a, b) = if hi - lo == 1 { (lo, hi) } else { (hi, lo) }; // wrap-around face
            worst = worst.max(q[t.vertex_count() + f.index()].distance(expect(a, b)));
        }
        for e in t.edges() {
            let (a, b) = t.edge_vertices(e);
            worst = worst.max(q[t.vertex_count() + t.face_count() + e.index()].distance(expect(row(a.0), row(b.0))));
        }
        assert!(worst <= 1e-14 * 8.0, "ω = {omega}: Deng-Ma differs from the 4-point scheme by {worst:e}");
    }
}

#[test]
fn deng_ma_stencil_equals_the_geometric_step() {
    for (name, mesh) in deng_ma_meshes().into_iter().chain([("mpi", common::fixture("mpi"))]) {
        let (t, d) = (mesh.topology(), mesh.bbox_diagonal());
        for omega in [1.0, 0.5, 0.125] {
            let linear = apply(&deng_ma::stencil(t, omega).unwrap(), mesh.positions());
            let geometric = deng_ma::step_positions(t, mesh.positions(), Tension::Global(omega)).unwrap();
            let e = max_dist(&linear, &geometric) / d;
            assert!(e <= 1e-14, "{name} ω = {omega}: stencil and step differ by {e:e}·d");
        }
    }
}

// ---------------------------------------------------------------- boundaries vs curve schemes

/// The vertices of the boundary loop through `start`, in loop order from it.
fn boundary_walk(t: &Topology, start: VertexId) -> Vec<VertexId> {
    let mut out = vec![start];
    let mut v = start;
    loop {
        let h = t.vertex_fan(v)[0]; // first fan half-edge = outgoing boundary half-edge
        v = t.he_to(h);
        if v == start {
            return out;
        }
        out.push(v);
        assert!(out.len() <= t.vertex_count(), "boundary walk does not close");
    }
}

fn to_pts(p: &[DVec3], ids: &[VertexId]) -> Vec<[f64; 3]> {
    ids.iter().map(|v| p[v.index()].to_array()).collect()
}

/// `levels` cubic B-spline refinements of a boundary loop whose corner
/// vertices (in one face: they stay) split it into open chains; a loop with
/// no corner is a closed curve.
fn cubic_boundary(points: &[[f64; 3]], corners: &[bool], levels: usize) -> Vec<[f64; 3]> {
    let n = points.len();
    let Some(first) = corners.iter().position(|&c| c) else {
        return (0..levels).fold(points.to_vec(), |p, _| curves::cubic_bspline(&p, true));
    };
    // Rotate to start at a corner, cut into chains corner-to-corner.
    let mut out = Vec::new();
    let mut chain = vec![points[first]];
    for k in 1..=n {
        let i = (first + k) % n;
        chain.push(points[i]);
        if corners[i] {
            let refined = (0..levels).fold(chain.clone(), |p, _| curves::cubic_bspline(&p, false));
            out.extend_from_slice(&refined[..refined.len() - 1]);
            chain = vec![points[i]];
        }
    }
    // Back to the loop's own starting point.
    let shift = first << levels;
    let len = out.len();
    out.rotate_right(shift % len);
    out
}

#[test]
fn primal_boundaries_are_cubic_bspline_curves() {
    const LEVELS: usize = 3;
    for (name, mesh) in open_meshes() {
        let (t, d) = (mesh.topology(), mesh.bbox_diagonal());
        let mut schemes = vec![Scheme::CatmullClark];
        if is_triangle_mesh(t) {
            schemes.extend([Scheme::Loop(LoopBeta::Warren), Scheme::Loop(LoopBeta::Loop)]);
        }
        for scheme in schemes {
            let plan = SubdivisionPlan::new(t, scheme, LEVELS).unwrap();
            let (fine_t, fine_p) = (plan.topology(), plan.apply(mesh.positions()));
            assert_eq!(fine_t.boundary_loop_count(), t.boundary_loop_count());
            for lp in t.boundary_loops() {
                let start = t.he_from(lp[0]);
                let coarse = boundary_walk(t, start);
                assert_eq!(coarse.len(), lp.len());
                let corners: Vec<bool> = coarse.iter().map(|&v| t.vertex_face_count(v) == 1).collect();
                let expect = cubic_boundary(&to_pts(mesh.positions(), &coarse), &corners, LEVELS);
                // Old vertex ids survive primal splits, so the fine loop starts at `start` too.
                let got = to_pts(&fine_p, &boundary_walk(fine_t, start));
                assert_eq!(got.len(), expect.len(), "{name} {scheme:?}: boundary loop size");
                let e = got
                    .iter()
                    .zip(&expect)
                    .map(|(a, b)| DVec3::from_array(*a).distance(DVec3::from_array(*b)))
                    .fold(0.0, f64::max)
                    / d;
                assert!(e <= 1e-14, "{name} {scheme:?}: boundary off the cubic B-spline curve by {e:e}·d");
            }
        }
    }
}

#[test]
fn doo_sabin_boundary_is_the_chaikin_curve() {
    const LEVELS: usize = 3;
    for (name, mesh) in open_meshes() {
        let (t, d) = (mesh.topology(), mesh.bbox_diagonal());
        let plan = SubdivisionPlan::new(t, Scheme::DooSabin, LEVELS).unwrap();
        let fine_p = plan.apply(mesh.positions());
        for lp in t.boundary_loops() {
            let start = t.he_from(lp[0]);
            let coarse = boundary_walk(t, start);
            let expect = (0..LEVELS).fold(to_pts(mesh.positions(), &coarse), |p, _| curves::chaikin(&p, true));
            // Follow the loop's start through the levels: the first Chaikin
            // point of the outgoing boundary half-edge of the current start.
            let mut s = start;
            let mut coarse_t = t;
            for level in plan.levels() {
                let h = coarse_t.vertex_fan(s)[0];
                s = VertexId(level.dual.as_ref().unwrap().boundary_point[h.index()]);
                coarse_t = &level.topology;
            }
            let got = to_pts(&fine_p, &boundary_walk(coarse_t, s));
            assert_eq!(got.len(), expect.len(), "{name}: boundary loop size");
            let e = got
                .iter()
                .zip(&expect)
                .map(|(a, b)| DVec3::from_array(*a).distance(DVec3::from_array(*b)))
                .fold(0.0, f64::max)
                / d;
            assert!(e <= 1e-14, "{name}: Doo-Sabin boundary off the Chaikin curve by {e:e}·d");
        }
    }
}

// ---------------------------------------------------------------- limit stencils vs brute force

fn fmt_gaps(gaps: &[f64]) -> String {
    gaps.iter().map(|g| format!("{g:.2e}")).collect::<Vec<_>>().join(" ")
}

/// Ratio and final-gap checks on a convergence history `gaps[k]` (level k+1).
fn assert_converges(what: &str, gaps: &[f64], max_ratio: f64, final_gap: f64) {
    let last = *gaps.last().unwrap();
    assert!(last <= final_gap, "{what}: gap {last:e}·d after {} levels (history {})", gaps.len(), fmt_gaps(gaps));
    for k in 3..gaps.len() {
        if gaps[k - 1] > 1e-13 {
            let ratio = gaps[k] / gaps[k - 1];
            assert!(ratio <= max_ratio, "{what}: gap ratio {ratio} at level {} (history {})", k + 1, fmt_gaps(gaps));
        }
    }
}

const BRUTE_LEVELS: usize = 8;

#[test]
fn primal_limit_stencils_agree_with_brute_force() {
    // Levels per case: the vertex gap shrinks by ~¼ per level (the
    // subdominant symmetric eigenvalue), so some meshes need a ninth level to
    // get below 1e-6·d.
    let cases: Vec<(&str, Mesh, Scheme, usize)> = vec![
        ("cube", shapes::cube(), Scheme::CatmullClark, 9),
        ("pyramid_mixed", common::fixture("pyramid_mixed"), Scheme::CatmullClark, 9),
        ("quad_grid 2x2 (open)", bumpy(shapes::quad_grid(2, 2), 3), Scheme::CatmullClark, 9),
        ("tetrahedron", shapes::tetrahedron(), Scheme::Loop(LoopBeta::Warren), 9),
        ("octahedron", shapes::octahedron(), Scheme::Loop(LoopBeta::Loop), 9),
        ("triangle_grid 2x1 (open)", bumpy(shapes::triangle_grid(2, 1), 4), Scheme::Loop(LoopBeta::Warren), 9),
    ];
    for (name, mesh, scheme, levels) in cases {
        let d = mesh.bbox_diagonal();
        let nv = mesh.topology().vertex_count();
        // `--levels 0 --limit`: the plan keeps the input, the stencil is in input order.
        let plan0 = SubdivisionPlan::new(mesh.topology(), scheme, 0).unwrap();
        assert_eq!(plan0.topology().faces().indices(), mesh.topology().faces().indices());
        assert_eq!(plan0.apply(mesh.positions()), mesh.positions());
        let predicted = apply(&plan0.limit_stencil().unwrap().unwrap(), mesh.positions());
        assert_eq!(predicted.len(), nv);
        // Brute force: the vertex with the same index persists at every level.
        let plan = SubdivisionPlan::new(mesh.topology(), scheme, levels).unwrap();
        let p = positions_per_level(&plan, mesh.positions());
        let gaps: Vec<f64> = p[1..].iter().map(|q| max_dist(&q[..nv], &predicted) / d).collect();
        eprintln!("{name} {scheme:?}: brute-force gap per level {}", fmt_gaps(&gaps));
        assert_converges(&format!("{name} {scheme:?}"), &gaps, 0.45, 1e-6);
    }
}

#[test]
fn doo_sabin_limit_stencil_agrees_with_brute_force() {
    let cases: Vec<(&str, Mesh)> = vec![
        ("cube", shapes::cube()),
        ("pyramid_mixed", common::fixture("pyramid_mixed")),
        ("quad_grid 2x2 (open)", bumpy(shapes::quad_grid(2, 2), 3)),
    ];
    for (name, mesh) in cases {
        let (t, d) = (mesh.topology(), mesh.bbox_diagonal());
        let plan0 = SubdivisionPlan::new(t, Scheme::DooSabin, 0).unwrap();
        let predicted = apply(&plan0.limit_stencil().unwrap().unwrap(), mesh.positions());
        let plan = SubdivisionPlan::new(t, Scheme::DooSabin, BRUTE_LEVELS).unwrap();
        let p = positions_per_level(&plan, mesh.positions());
        let first = &plan.levels()[0];
        let mut worst = vec![0.0f64; BRUTE_LEVELS];
        let mut local_levels = 0;
        let dual = first.dual.as_ref().unwrap();
        for v in t.vertices() {
            // What to track: interior vertex — its V-face, whose F-face
            // descendants keep the face id (F-faces come first) and the
            // centroid; boundary vertex — the boundary edge between its two
            // Chaikin points, whose Chaikin descendants keep the midpoint.
            let mut gaps = Vec::new();
            let mut centroid_err: f64 = 0.0;
            // The tracked polygon at the last two levels (face corners, or the edge's ends).
            let mut tracked: Vec<Vec<DVec3>> = Vec::new();
            if !t.is_boundary_vertex(v) {
                let f = dual.vertex_face[v.index()].expect("interior vertex of valence ≥ 3");
                for (k, level) in plan.levels().iter().enumerate() {
                    let q = &p[k + 1];
                    let face = level.topology.face(f);
                    centroid_err =
                        centroid_err.max(face_centroid(&level.topology, q, f).distance(predicted[v.index()]) / d);
                    gaps.push(
                        face.iter().map(|&c| q[c as usize].distance(predicted[v.index()])).fold(0.0, f64::max) / d,
                    );
                    tracked.push(face.iter().map(|&c| q[c as usize]).collect());
                }
            } else {
                let fan = t.vertex_fan(v);
                let c_out = dual.boundary_point[fan[0].index()];
                let c_in = dual.boundary_point[t.he_prev(fan[fan.len() - 1]).index()] + 1;
                let (mut a, mut b) = (VertexId(c_in), VertexId(c_out));
                for (k, level) in plan.levels().iter().enumerate() {
                    let q = &p[k + 1];
                    let lt = &level.topology;
                    assert_eq!(lt.he_to(lt.vertex_fan(a)[0]), b, "{name}: tracked boundary edge");
                    let mid = 0.5 * (q[a.index()] + q[b.index()]);
                    centroid_err = centroid_err.max(mid.distance(predicted[v.index()]) / d);
                    gaps.push(
                        q[a.index()].distance(predicted[v.index()]).max(q[b.index()].distance(predicted[v.index()]))
                            / d,
                    );
                    tracked.push(vec![q[a.index()], q[b.index()]]);
                    if let Some(next) = plan.levels().get(k + 1) {
                        let h = lt.vertex_fan(a)[0];
                        let c = next.dual.as_ref().unwrap().boundary_point[h.index()];
                        (a, b) = (VertexId(c), VertexId(c + 1));
                    }
                }
            }
            assert!(
                centroid_err <= 1e-14,
                "{name} vertex {v}: tracked centroid off the prediction by {centroid_err:e}·d"
            );
            // The tracked polygon shrinks by ½ per level (the face circulant's
            // subdominant eigenvalue, correction Z8 (docs/REFERENCES.md); Chaikin on an edge), so the
            // whole-mesh run gives ~2⁻⁸ of the first size. Its descendants
            // depend on its own corners only (Eq. 1 within an F-face; Chaikin
            // on a boundary edge): check that locality on the last whole-mesh
            // level, then continue locally until the gap is below 1e-6·d.
            let local = |poly: &[DVec3]| -> Vec<DVec3> {
                let m = poly.len();
                if m == 2 {
                    return vec![0.75 * poly[0] + 0.25 * poly[1], 0.25 * poly[0] + 0.75 * poly[1]];
                }
                let mut w = vec![0.0; m];
                subdiv_rules::doo_sabin_weights(m, &mut w);
                (0..m).map(|i| (0..m).map(|k| w[k] * poly[(i + k) % m]).sum()).collect()
            };
            let n = tracked.len();
            let e = max_dist(&local(&tracked[n - 2]), &tracked[n - 1]) / d;
            assert!(e <= 1e-15, "{name} vertex {v}: tracked polygon is not refined locally ({e:e}·d)");
            let mut poly = tracked[n - 1].clone();
            while gaps.len() < 40 && *gaps.last().unwrap() > 1e-6 {
                poly = local(&poly);
                gaps.push(poly.iter().map(|x| x.distance(predicted[v.index()])).fold(0.0, f64::max) / d);
            }
            assert_converges(&format!("{name} DS vertex {v}"), &gaps, 0.5 + 1e-9, 1e-6);
            worst.iter_mut().zip(&gaps[..BRUTE_LEVELS]).for_each(|(w, g)| *w = w.max(*g));
            local_levels = local_levels.max(gaps.len());
        }
        eprintln!(
            "{name} DooSabin: tracked-face radius per level (max over vertices) {}; below 1e-6·d by level {local_levels}",
            fmt_gaps(&worst)
        );
    }
}

// ---------------------------------------------------------------- isolated vertices, valence 2

/// An isolated vertex (a repaired-input warning, [error behaviour]) is carried through
/// primal splits unchanged and dropped by the dual split.
///
/// [error behaviour]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-error-behaviour-and-exit-codes
#[test]
fn isolated_vertices_are_kept_by_primal_schemes_and_dropped_by_doo_sabin() {
    let extra = DVec3::new(5.0, -3.0, 2.0);
    for base in [shapes::cube(), shapes::octahedron()] {
        let mut p = base.positions().to_vec();
        p.push(extra);
        let mesh = Mesh::new(p, base.topology().faces().clone()).unwrap();
        let t = mesh.topology();
        let iso = t.vertex_count() - 1;
        assert!(t.is_isolated(VertexId(iso as u32)));
        let mut schemes = vec![Scheme::CatmullClark, Scheme::DengMa(Tension::Global(1.0))];
        if is_triangle_mesh(t) {
            schemes.push(Scheme::Loop(LoopBeta::Warren));
        }
        for scheme in schemes {
            let plan = SubdivisionPlan::new(t, scheme, 2).unwrap();
            let q = plan.apply(mesh.positions());
            assert_eq!(q[iso], extra, "{scheme:?}");
            assert!(plan.topology().is_isolated(VertexId(iso as u32)), "{scheme:?}");
            if let Some(Ok(l)) = plan.limit_stencil() {
                assert_eq!(apply(&l, &q)[iso], extra, "{scheme:?} limit");
            }
        }
        let ds = SubdivisionPlan::new(t, Scheme::DooSabin, 1).unwrap();
        assert_eq!(ds.topology().vertex_count(), t.half_edge_count());
        assert_eq!(ds.topology().referenced_vertex_count(), ds.topology().vertex_count());
        assert_eq!(apply(&doo_sabin::limit_stencil(t), mesh.positions())[iso], extra);
    }
}

/// The unit cube with the edge (0,0,0)–(1,0,0) split by a vertex pushed
/// slightly outwards: that vertex has valence 2 inside two pentagons.
fn cube_with_split_edge() -> Mesh {
    let mut p = shapes::cube().positions().to_vec();
    p.push(DVec3::new(0.5, -0.1, -0.1));
    let faces = subdiv_mesh::FaceList::from_faces([
        &[0u32, 2, 3, 1, 8][..],
        &[4, 5, 7, 6],
        &[0, 8, 1, 5, 4],
        &[2, 6, 7, 3],
        &[0, 4, 6, 2],
        &[1, 3, 7, 5],
    ]);
    Mesh::new(p, faces).unwrap()
}

/// Catmull-Clark's limit stencil (Cheng Eq. 5) also holds at interior
/// vertices of valence 2 (the pillow; a cube with a split edge): brute force
/// converges to it at the rate ¼.
#[test]
fn catmull_clark_limit_stencil_holds_at_valence_two() {
    for (name, mesh, levels) in [("pillow", shapes::pillow(), 9), ("cube with a split edge", cube_with_split_edge(), 8)]
    {
        let (t, d) = (mesh.topology(), mesh.bbox_diagonal());
        let v2: Vec<usize> =
            t.vertices().filter(|&v| !t.is_boundary_vertex(v) && t.valence(v) == 2).map(|v| v.index()).collect();
        assert!(!v2.is_empty(), "{name} has no valence-2 vertex");
        let predicted = apply(&catmull_clark::limit_stencil(t), mesh.positions());
        let plan = SubdivisionPlan::new(t, Scheme::CatmullClark, levels).unwrap();
        let p = positions_per_level(&plan, mesh.positions());
        let gaps: Vec<f64> =
            p[1..].iter().map(|q| v2.iter().map(|&v| q[v].distance(predicted[v])).fold(0.0, f64::max) / d).collect();
        assert_converges(&format!("{name} CC, valence-2 vertices"), &gaps, 0.45, 2e-6);
    }
}

/// `dual_split` omits the digon V-face of an interior valence-2 vertex, so
/// its limit point is the centroid of the second-level E-face of the edge
/// between its two images (`doo_sabin::valence_two_corners`); that point is
/// on the surface: the level-6 surface (level 8 for the pillow and the cube)
/// has a vertex within 2e-3·d of it (its vertices are ~2⁻⁶ of an edge apart). (The former row, the
/// midpoint of the two images, stayed ~6e-2·d off the surface on the pillow.)
#[test]
fn doo_sabin_limit_stencil_at_valence_two_is_on_the_surface() {
    let mut failures = Vec::new();
    for (name, mesh) in valence_two_meshes() {
        let (t, d) = (mesh.topology(), mesh.bbox_diagonal());
        let predicted = apply(&doo_sabin::limit_stencil(t), mesh.positions());
        // Coarse meshes need more levels for their vertices to be as dense.
        let levels = if t.face_count() < 10 { 8 } else { 6 };
        let plan = SubdivisionPlan::new(t, Scheme::DooSabin, levels).unwrap();
        let q = plan.apply(mesh.positions());
        for v in t.vertices().filter(|&v| !t.is_boundary_vertex(v) && t.valence(v) == 2) {
            // Refined vertices are ~2⁻⁶ of an edge apart: a point of the
            // limit surface has one within a few 1e-3·d.
            let near = q.iter().map(|x| x.distance(predicted[v.index()])).fold(f64::INFINITY, f64::min) / d;
            eprintln!("{name} vertex {v}: predicted limit point {near:.2e}·d from the nearest refined vertex");
            failures.push((name, v, near));
        }
    }
    failures.retain(|f| f.2 > 2e-3);
    assert!(failures.is_empty(), "predicted limit points off the surface: {failures:?}");
}

/// Meshes with interior valence-2 vertices: the pillow (all four), a cube
/// with a split edge, a torus with three split edges of which two are
/// consecutive edges of one face pair (adjacent valence-2 vertices), an open
/// grid with split interior edges, and a polygon mix with split edges.
fn valence_two_meshes() -> Vec<(&'static str, Mesh)> {
    use subdiv_mesh::EdgeId;
    let torus = shapes::torus(8, 6);
    let t = torus.topology();
    // Two consecutive edges of face 0 (they share a vertex and both faces
    // only if the two faces share both; here they do not, so the split
    // vertices are adjacent through face 0), and one far away.
    let f0 = t.face_half_edges(subdiv_mesh::FaceId(0)).collect::<Vec<_>>();
    let torus_edges = [t.he_edge(f0[0]), t.he_edge(f0[1]), EdgeId(t.edge_count() as u32 / 2)];
    let grid = bumpy(shapes::quad_grid(4, 3), 5);
    let g = grid.topology();
    let interior: Vec<EdgeId> = g.edges().filter(|&e| g.edge_faces(e).1.is_some()).collect();
    let mix = shapes::polygon_mix(&shapes::torus(10, 6), 3, 0.25, 0.2, 0.1);
    let mix_edges: Vec<EdgeId> = (0..4).map(|k| EdgeId((k * 37 % mix.topology().edge_count()) as u32)).collect();
    vec![
        ("pillow", shapes::pillow()),
        ("cube with a split edge", cube_with_split_edge()),
        ("torus with 3 split edges", shapes::split_edges(&torus, &torus_edges, 0.1)),
        ("open grid with 2 split edges", shapes::split_edges(&grid, &[interior[1], interior[7]], -0.2)),
        ("polygon mix with 4 split edges", shapes::split_edges(&mix, &mix_edges, 0.05)),
    ]
}

/// Brute force for the valence-2 row: refine 8 levels and track the
/// second-level E-face of the edge between the vertex's two images; its
/// F-face descendants (same face id) keep its centroid, which is the
/// predicted limit point, and shrink to it by ½ per level.
#[test]
fn doo_sabin_valence_two_limit_row_is_the_tracked_face_limit() {
    for (name, mesh) in valence_two_meshes() {
        let (t, d) = (mesh.topology(), mesh.bbox_diagonal());
        let v2: Vec<VertexId> = t.vertices().filter(|&v| !t.is_boundary_vertex(v) && t.valence(v) == 2).collect();
        assert!(!v2.is_empty(), "{name} has no valence-2 vertex");
        let predicted = apply(&doo_sabin::limit_stencil(t), mesh.positions());
        let predicted_rows = doo_sabin::limit_points(t, mesh.positions());
        let plan = SubdivisionPlan::new(t, Scheme::DooSabin, BRUTE_LEVELS).unwrap();
        let p = positions_per_level(&plan, mesh.positions());
        let (l1, l2) = (&plan.levels()[0].topology, &plan.levels()[1]);
        for &v in &v2 {
            let target = predicted[v.index()];
            assert!(target.distance(predicted_rows[v.index()]) <= 1e-15 * d, "{name}: limit_points vs stencil");
            // Vertex h of level 1 is the image of corner h: find the level-1 edge v₀ → v₁.
            let [h0, h1] = [t.vertex_fan(v)[0], t.vertex_fan(v)[1]];
            let (v0, v1) = (VertexId(h0.0), VertexId(h1.0));
            let h = *l1.vertex_fan(v0).iter().find(|&&h| l1.he_to(h) == v1).expect("v₀v₁ is an edge of level 1");
            // The plain rule on level 1 gives the same point.
            let on_level1 = doo_sabin::edge_limit_point(l1, h, &p[1]);
            assert!(on_level1.distance(target) <= 1e-14 * d, "{name} vertex {v}: edge limit point of level 1");
            let e = l1.he_edge(h);
            let dual2 = l2.dual.as_ref().unwrap();
            let f = subdiv_mesh::FaceId(
                dual2.face_origin.iter().position(|o| *o == DualFace::E(e)).expect("E-face of v₀v₁") as u32,
            );
            let mut gaps = Vec::new();
            let mut poly = Vec::new();
            for (k, level) in plan.levels().iter().enumerate().skip(1) {
                let q = &p[k + 1];
                poly = level.topology.face(f).iter().map(|&c| q[c as usize]).collect::<Vec<_>>();
                let centroid = poly.iter().sum::<DVec3>() / poly.len() as f64;
                assert!(
                    centroid.distance(target) <= 1e-14 * d,
                    "{name} vertex {v}: level-{} centroid {:e}·d off",
                    k + 1,
                    centroid.distance(target) / d
                );
                gaps.push(poly.iter().map(|x| x.distance(target)).fold(0.0, f64::max) / d);
            }
            // Continue on the face alone (an F-face's descendants depend on its corners only).
            while gaps.len() < 40 && *gaps.last().unwrap() > 1e-6 {
                let m = poly.len();
                let mut w = vec![0.0; m];
                subdiv_rules::doo_sabin_weights(m, &mut w);
                poly = (0..m).map(|i| (0..m).map(|k| w[k] * poly[(i + k) % m]).sum()).collect();
                gaps.push(poly.iter().map(|x| x.distance(target)).fold(0.0, f64::max) / d);
            }
            eprintln!("{name} vertex {v}: tracked-face radius per level {}", fmt_gaps(&gaps));
            assert_converges(&format!("{name} DS valence-2 vertex {v}"), &gaps, 0.5 + 1e-9, 1e-6);
        }
    }
}
