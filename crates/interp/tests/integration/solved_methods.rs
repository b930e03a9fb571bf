//! Nasri, Cheng and Fan-Cheng-Lai: interpolation within tolerance on real
//! fixtures (closed and open, every face mix), checked independently from the
//! output control mesh alone; degenerate cases; subsets; shape control.

use crate::support::{candidate_limit_points, fixture, nearest_gap, volume};
use glam::DVec3;
use proptest::prelude::*;
use subdiv_interp::{
    cheng, fan_cheng_lai, nasri, ChengOptions, CommonOptions, FanChengLaiOptions, InterpError, Interpolant,
    NasriOptions, Shape, SolverChoice,
};
use subdiv_mesh::{shapes, Mesh};
use subdiv_solve::Solver;
use subdiv_stencil::{Scheme, SubdivisionPlan};

const TOL: f64 = 1e-6;

fn closed() -> Vec<&'static str> {
    vec![
        "poly/mpi.off",
        "poly/P.off",
        "poly/chamfer-cube.off",
        "quad/spot_control_mesh.obj",
        "quad/penguin_control_mesh.obj",
        "quad/3torus.off",
        "quad/fandisk_quads.off",
        "canonical/dodecahedron.obj",
        "canonical/torus_quad_16x8.obj",
        "tri/eight.off",
        "tri/decimated-knight.off",
    ]
}

fn open() -> Vec<&'static str> {
    vec!["open/halftunnel.off", "open/nefertiti_small.off", "canonical/grid_quad_8x8_open.obj", "open/grid.off"]
}

fn check(name: &str, mesh: &Mesh, result: &Interpolant, plain: Scheme, tol: f64) -> f64 {
    let all = vec![true; mesh.topology().vertex_count()];
    let d = mesh.bbox_diagonal();
    let reported = result.error(mesh.positions(), &all, d);
    assert!(reported.max_rel <= tol, "{name}: reported error {:e}", reported.max_rel);
    let independent = nearest_gap(mesh.positions(), &candidate_limit_points(&result.control, plain), d);
    assert!(independent <= tol * (1.0 + 1e-9), "{name}: independent error {independent:e}");
    reported.max_rel
}

#[test]
fn every_fixture_interpolates_within_tolerance() {
    for name in closed().into_iter().chain(open()) {
        let mesh = fixture(name);
        let t = mesh.topology();
        let common = CommonOptions::default().with_tol(TOL);
        let ds_ok = t.vertices().all(|v| t.is_boundary_vertex(v) || t.vertex_face_count(v) != 2);
        if ds_ok {
            let r = nasri::interpolate(&mesh, &NasriOptions::default().with_common(common.clone())).unwrap();
            let e = check(&format!("nasri {name}"), &mesh, &r, Scheme::DooSabin, TOL);
            let f =
                fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default().with_common(common.clone())).unwrap();
            let e2 = check(&format!("fan-cheng-lai {name}"), &mesh, &f, Scheme::DooSabin, TOL);
            eprintln!(
                "{name}: nasri {e:.2e} ({} it), fcl {e2:.2e} ({} it)",
                r.solve.as_ref().unwrap().iterations,
                f.solve.as_ref().unwrap().iterations
            );
        }
        match cheng::interpolate(&mesh, &ChengOptions::default().with_common(common.clone())) {
            Ok(r) => {
                let e = check(&format!("cheng {name}"), &mesh, &r, Scheme::CatmullClark, TOL);
                eprintln!("{name}: cheng {e:.2e} ({} it)", r.solve.as_ref().unwrap().iterations);
            }
            Err(e) => panic!("cheng on {name}: {e}"),
        }
    }
}

#[test]
fn every_solver_reaches_the_same_control_mesh() {
    let mesh = fixture("quad/spot_control_mesh.obj");
    let reference =
        cheng::interpolate(&mesh, &ChengOptions::default().with_solver(SolverChoice::Use(Solver::Ldl)).with_tol(1e-12))
            .unwrap();
    // Jacobi needs diagonal dominance, which Cheng's A lacks (4/9 vs 5/9 for a
    // regular vertex): it must report divergence, not return garbage.
    let jacobi = CommonOptions::default().with_solver(SolverChoice::Use(Solver::Jacobi));
    let err = cheng::interpolate(&mesh, &ChengOptions::default().with_common(jacobi.clone())).unwrap_err();
    assert!(err.is_not_converged(), "{err}");
    // Nasri's C is diagonally dominant: Jacobi converges to the LDLᵀ solution.
    let by_jacobi = nasri::interpolate(&mesh, &NasriOptions::default().with_common(jacobi.with_tol(1e-9))).unwrap();
    let by_ldl =
        nasri::interpolate(&mesh, &NasriOptions::default().with_solver(SolverChoice::Use(Solver::Ldl)).with_tol(1e-12))
            .unwrap();
    let gap = by_jacobi
        .control
        .positions()
        .iter()
        .zip(by_ldl.control.positions())
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f64::max);
    assert!(gap <= 1e-7 * mesh.bbox_diagonal(), "jacobi vs ldl on nasri: {gap:e}");
    for solver in [
        "pia",
        "weighted-pia",
        "gauss-seidel",
        "gauss-seidel-symmetric",
        "chebyshev",
        "cg",
        "cg-jacobi",
        "minres",
        "gmres",
        "dense",
    ] {
        let s: Solver = solver.parse().unwrap();
        let common = CommonOptions::default().with_solver(SolverChoice::Use(s)).with_tol(1e-9);
        let r = cheng::interpolate(&mesh, &ChengOptions::default().with_common(common))
            .unwrap_or_else(|e| panic!("{solver}: {e}"));
        let gap = r
            .control
            .positions()
            .iter()
            .zip(reference.control.positions())
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(gap <= 1e-7 * mesh.bbox_diagonal(), "{solver}: control differs by {gap:e}");
    }
}

#[test]
fn singular_cube_consistent_data_warns_and_inconsistent_data_fails_with_the_error_reached() {
    let cube = shapes::cube();
    let r = cheng::interpolate(&cube, &ChengOptions::default()).expect("the exact cube lies in the range of A");
    assert!(r.warnings.iter().any(|w| w.contains("not unique")), "{:?}", r.warnings);
    check("cube", &cube, &r, Scheme::CatmullClark, TOL);
    let mut p = cube.positions().to_vec();
    p[0] += DVec3::new(0.05, -0.02, 0.03);
    let bent = cube.with_positions(p);
    let err =
        cheng::interpolate(&bent, &ChengOptions::default()).expect_err("no CC surface interpolates a generic cube");
    assert!(err.is_not_converged(), "{err}");
    let msg = err.to_string();
    assert!(msg.contains("singular") && msg.contains("zheng-cai") && msg.contains("residual"), "{msg}");
    // The Doo-Sabin methods take the cube.
    check("nasri cube", &bent, &nasri::interpolate(&bent, &NasriOptions::default()).unwrap(), Scheme::DooSabin, TOL);
}

#[test]
fn valence_two_is_solved_by_default_and_refused_only_for_solvers_that_need_a_definite_matrix() {
    // The pillow (every vertex of valence 2): A is indefinite, λ_min = −1/7.
    let pillow = shapes::pillow();
    let r = cheng::interpolate(&pillow, &ChengOptions::default()).unwrap();
    assert_eq!(r.solve.as_ref().unwrap().solver, "minres");
    check("pillow auto", &pillow, &r, Scheme::CatmullClark, TOL);
    for solver in [Solver::Pia, Solver::Cg { jacobi: false }, Solver::Cg { jacobi: true }] {
        let common = CommonOptions::default().with_solver(SolverChoice::Use(solver));
        let err = cheng::interpolate(&pillow, &ChengOptions::default().with_common(common)).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, InterpError::UnsupportedMesh { .. }), "{solver}: {msg}");
        assert!(msg.contains("Solver::Minres") && msg.contains("Solver::Ldl"), "{solver}: {msg}");
    }
    let common = CommonOptions::default().with_solver(SolverChoice::Use(Solver::Ldl));
    let r = cheng::interpolate(&pillow, &ChengOptions::default().with_common(common)).unwrap();
    assert!(r.warnings.iter().any(|w| w.contains("indefinite")), "{:?}", r.warnings);
    check("pillow ldl", &pillow, &r, Scheme::CatmullClark, TOL);
}

#[test]
fn subsets_interpolate_only_the_listed_vertices() {
    let mesh = fixture("quad/spot_control_mesh.obj");
    let n = mesh.topology().vertex_count();
    let subset: Vec<u32> = (0..n as u32).step_by(3).collect();
    let flags: Vec<bool> = (0..n).map(|v| v % 3 == 0).collect();
    let common = CommonOptions::default().with_subset(subset);
    let d = mesh.bbox_diagonal();
    let results = [
        cheng::interpolate(&mesh, &ChengOptions::default().with_common(common.clone())).unwrap(),
        nasri::interpolate(&mesh, &NasriOptions::default().with_common(common.clone())).unwrap(),
        fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default().with_common(common.clone())).unwrap(),
    ];
    for r in &results {
        assert!(r.error(mesh.positions(), &flags, d).max_rel <= TOL);
        let others: Vec<bool> = flags.iter().map(|f| !f).collect();
        assert!(r.error(mesh.positions(), &others, d).max_rel > 1e-4, "non-listed vertices are not interpolated");
    }
    // Nasri and Cheng keep the non-interpolated control points at the data (Zheng-Cai §2).
    for r in &results[..2] {
        for v in (0..n).filter(|v| v % 3 != 0) {
            assert_eq!(r.control.positions()[v], mesh.positions()[v]);
        }
    }
}

#[test]
fn shape_parameter_moves_the_surface_monotonically_while_interpolating() {
    let mesh = fixture("poly/mpi.off");
    let mut volumes = Vec::new();
    for lambda in [0.2, 0.4, 0.6, 0.8] {
        let r = fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default().with_shape(Shape::Uniform(lambda)))
            .unwrap();
        check(&format!("λ = {lambda}"), &mesh, &r, Scheme::DooSabin, TOL);
        volumes.push(volume(&r.surface(3).unwrap()));
    }
    eprintln!("fan-cheng-lai on mpi: level-3 surface volume for λ = 0.2, 0.4, 0.6, 0.8: {volumes:?}");
    let increasing = volumes.windows(2).all(|w| w[1] > w[0]);
    let decreasing = volumes.windows(2).all(|w| w[1] < w[0]);
    assert!(increasing || decreasing, "volume not monotone in λ: {volumes:?}");
    // Local control: λ changed on one group of faces moves only the surface near them.
    let t = mesh.topology();
    let per_face: Vec<f64> = (0..t.face_count()).map(|f| if f < t.face_count() / 4 { 0.9 } else { 0.5 }).collect();
    let r =
        fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default().with_shape(Shape::PerFace(per_face))).unwrap();
    check("per-face λ", &mesh, &r, Scheme::DooSabin, TOL);
}

#[test]
fn open_meshes_use_the_boundary_curves() {
    let mesh = fixture("open/halftunnel.off");
    for r in [
        cheng::interpolate(&mesh, &ChengOptions::default()).unwrap(),
        nasri::interpolate(&mesh, &NasriOptions::default()).unwrap(),
    ] {
        // The boundary of the surface at level 3 passes through the boundary data.
        let s = r.surface(3).unwrap();
        let st = s.topology();
        let boundary: Vec<DVec3> = st.vertices().filter(|&v| st.is_boundary_vertex(v)).map(|v| s.position(v)).collect();
        let t = mesh.topology();
        let data: Vec<DVec3> = t.vertices().filter(|&v| t.is_boundary_vertex(v)).map(|v| mesh.position(v)).collect();
        let gap = nearest_gap(&data, &boundary, mesh.bbox_diagonal());
        eprintln!("{:?}: boundary data to level-3 boundary {gap:e}", r.method);
        if r.scheme == Scheme::CatmullClark {
            assert!(gap <= TOL, "Catmull-Clark boundary vertices are limit points: {gap:e}");
        }
    }
}

fn random_closed_mesh() -> impl Strategy<Value = Mesh> {
    (0usize..3, 3usize..12, 3usize..8, any::<u64>(), 0.0f64..0.4, 0.0f64..0.4).prop_map(
        |(genus, nx, ny, seed, merge, split)| {
            let holes: Vec<(usize, usize)> = (0..genus).map(|k| (1 + 2 * k, 1)).collect();
            let base = shapes::plate_with_holes(nx + 2 * genus, ny, &holes, true);
            shapes::polygon_mix(&base, seed, merge, split, 0.1)
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn random_closed_meshes_interpolate(mesh in random_closed_mesh()) {
        let t = mesh.topology();
        let no_digons = t.vertices().all(|v| t.vertex_face_count(v) != 2);
        if no_digons {
            check("nasri", &mesh, &nasri::interpolate(&mesh, &NasriOptions::default()).unwrap(), Scheme::DooSabin, TOL);
            check("fcl", &mesh, &fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default()).unwrap(), Scheme::DooSabin, TOL);
            match cheng::interpolate(&mesh, &ChengOptions::default()) {
                Ok(r) => { check("cheng", &mesh, &r, Scheme::CatmullClark, TOL); }
                Err(e) => prop_assert!(subdiv_interp::catmull_clark_degeneracy(t).is_some(), "cheng failed: {}", e),
            }
        }
    }
}

#[test]
fn surfaces_refine_the_control_mesh_with_its_plain_scheme() {
    let mesh = fixture("quad/spot_control_mesh.obj");
    let r = cheng::interpolate(&mesh, &ChengOptions::default()).unwrap();
    let s = r.surface(2).unwrap();
    let plan = SubdivisionPlan::new(r.control.topology(), Scheme::CatmullClark, 2).unwrap();
    assert_eq!(s.topology().face_count(), plan.topology().face_count());
    // Input vertex i is vertex i of the surface, at its limit position = the data.
    for (i, p) in mesh.positions().iter().enumerate() {
        assert!(s.positions()[i].distance(*p) <= TOL * mesh.bbox_diagonal());
    }
}
