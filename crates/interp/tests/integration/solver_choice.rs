//! The automatic solver choice: Cheng's method on quad meshes with interior
//! valence-2 vertices (an edge shared by two quads split by a new vertex,
//! as DCC exports leave them) succeeds with the default options through
//! MINRES, measured by the plain Catmull-Clark limit rules on the output
//! (`Interpolant::error`, and independently by `subdiv_interp::verify`),
//! never by the solver's residual; explicitly requested solvers that need a
//! positive definite matrix are still refused with the remedy.

use crate::support;

use crate::support::{candidate_limit_points, nearest_gap, Scheme};
use proptest::prelude::*;
use subdiv_interp::{cheng, ChengOptions, InterpError, Interpolant, SolverChoice};
use subdiv_mesh::{shapes, EdgeId, Mesh};
use subdiv_solve::Solver;

const TOL: f64 = 1e-6;

/// The edge of `mesh` between vertices a and b.
fn edge(mesh: &Mesh, a: u32, b: u32) -> EdgeId {
    let t = mesh.topology();
    t.edges()
        .find(|&e| {
            let (x, y) = t.edge_vertices(e);
            (x.0, y.0) == (a, b) || (x.0, y.0) == (b, a)
        })
        .unwrap_or_else(|| panic!("no edge ({a}, {b})"))
}

/// `mesh` with one new vertex in each edge of `singles` and two adjacent ones
/// in each edge of `doubles` ((a, b) becomes a–w–v–b in both faces).
fn with_valence_two(mesh: &Mesh, singles: &[(u32, u32)], doubles: &[(u32, u32)]) -> Mesh {
    let first: Vec<EdgeId> = singles.iter().chain(doubles).map(|&(a, b)| edge(mesh, a, b)).collect();
    let once = shapes::split_edges(mesh, &first, 0.1);
    let n = mesh.topology().vertex_count() as u32;
    let second: Vec<EdgeId> =
        doubles.iter().enumerate().map(|(k, &(a, _))| edge(&once, a, n + (singles.len() + k) as u32)).collect();
    shapes::split_edges(&once, &second, 0.1)
}

/// Interior vertices of valence 2 and, among them, those with a valence-2 neighbour.
fn valence_two_counts(mesh: &Mesh) -> (usize, usize) {
    let t = mesh.topology();
    let two = |v: subdiv_mesh::VertexId| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2;
    let all: Vec<_> = t.vertices().filter(|&v| two(v)).collect();
    let adjacent = all.iter().filter(|&&v| t.vertex_neighbors(v).any(two)).count();
    (all.len(), adjacent)
}

/// The test meshes: closed torus and cube, open grid; separate, several,
/// and adjacent valence-2 vertices.
fn meshes() -> Vec<(&'static str, Mesh)> {
    let torus = shapes::torus(12, 8); // vertex (i, j) = 8i + j
    let cube = shapes::cube();
    let (c0, c1) = cube.topology().edge_vertices(EdgeId(0));
    let grid = shapes::quad_grid(8, 8); // vertex (i, j) = 9j + i
    vec![
        ("torus, one", with_valence_two(&torus, &[(0, 8)], &[])),
        ("torus, three separate", with_valence_two(&torus, &[(0, 8), (40, 41), (70, 78)], &[])),
        ("torus, two in one quad", with_valence_two(&torus, &[(16, 24), (24, 25)], &[])),
        ("torus, an adjacent pair", with_valence_two(&torus, &[], &[(0, 8)])),
        ("torus, several and two adjacent pairs", with_valence_two(&torus, &[(40, 41), (70, 78)], &[(0, 8), (52, 60)])),
        ("cube, one", with_valence_two(&cube, &[(c0.0, c1.0)], &[])),
        ("cube, an adjacent pair", with_valence_two(&cube, &[], &[(c0.0, c1.0)])),
        ("open grid, several and an adjacent pair", with_valence_two(&grid, &[(30, 31), (50, 59)], &[(21, 22)])),
        ("pillow", shapes::pillow()),
    ]
}

/// The error measured from the control mesh alone, by `Interpolant::error`
/// (the plain Catmull-Clark limit masks) and by `verify`'s nearest limit point.
fn check(name: &str, mesh: &Mesh, r: &Interpolant, tol: f64) -> f64 {
    let d = mesh.bbox_diagonal();
    let all = vec![true; mesh.topology().vertex_count()];
    let e = r.error(mesh.positions(), &all, d);
    assert!(e.max_rel <= tol, "{name}: error {:e}", e.max_rel);
    let independent = nearest_gap(mesh.positions(), &candidate_limit_points(&r.control, Scheme::CatmullClark), d);
    assert!(independent <= tol * (1.0 + 1e-9), "{name}: independent error {independent:e}");
    e.max_rel
}

fn with_solver(solver: Solver, tol: f64) -> ChengOptions {
    ChengOptions::default().with_solver(SolverChoice::Use(solver)).with_tol(tol)
}

#[test]
fn cheng_with_defaults_interpolates_meshes_with_valence_two_vertices_through_minres() {
    for (name, mesh) in meshes() {
        let (count, adjacent) = valence_two_counts(&mesh);
        assert!(count > 0, "{name}");
        let r = cheng::interpolate(&mesh, &ChengOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        let e = check(name, &mesh, &r, TOL);
        let solve = r.solve.as_ref().unwrap();
        assert_eq!(solve.solver, "minres", "{name}");
        assert_eq!(r.parameters.solver.as_deref(), Some("minres"), "{name}");
        assert!(solve.converged && solve.residual <= TOL, "{name}");
        // The same control mesh as the direct solver's, and the inertia LDLᵀ sees:
        // adjacent valence-2 vertices (and the pillow) make A indefinite, lone ones do not.
        let by_ldl = cheng::interpolate(&mesh, &with_solver(Solver::Ldl, 1e-12)).unwrap();
        let negatives = by_ldl.solve.as_ref().unwrap().negative_pivots.unwrap();
        assert_eq!(negatives > 0, adjacent > 0 || name == "pillow", "{name}: {negatives} negative pivots");
        let tight = cheng::interpolate(&mesh, &with_solver(Solver::Minres, 1e-12)).unwrap();
        let gap = tight
            .control
            .positions()
            .iter()
            .zip(by_ldl.control.positions())
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(gap <= 1e-8 * mesh.bbox_diagonal(), "{name}: MINRES vs LDLᵀ control meshes differ by {gap:e}");
        eprintln!(
            "{name}: {count} valence-2 ({adjacent} adjacent), {negatives} negative eigenvalues; minres {} iterations, \
             {} matvecs, error {e:.2e}",
            solve.iterations, solve.matvecs
        );
    }
}

#[test]
fn requested_solvers_that_need_a_definite_matrix_are_refused_with_the_remedy() {
    let mesh = with_valence_two(&shapes::torus(12, 8), &[(40, 41)], &[(0, 8)]);
    for solver in [
        "pia",
        "weighted-pia",
        "jacobi",
        "gauss-seidel",
        "gauss-seidel-symmetric",
        "gauss-seidel-multicolor",
        "chebyshev",
        "cg",
        "cg-jacobi",
    ] {
        let s: Solver = solver.parse().unwrap();
        let err = cheng::interpolate(&mesh, &with_solver(s, TOL)).unwrap_err();
        assert!(matches!(err, InterpError::UnsupportedMesh { .. }), "{solver}: {err}");
        let msg = err.to_string();
        for needle in ["valence 2", solver, "Solver::Minres", "Solver::Ldl", "automatic"] {
            assert!(msg.contains(needle), "{solver}: {msg:?} lacks {needle:?}");
        }
    }
    // Solvers that do not need definiteness are used as asked.
    for s in [Solver::Minres, Solver::Gmres, Solver::Ldl, Solver::Dense] {
        let r = cheng::interpolate(&mesh, &with_solver(s, TOL)).unwrap_or_else(|e| panic!("{s}: {e}"));
        check(s.name(), &mesh, &r, TOL);
        assert_eq!(r.solve.as_ref().unwrap().solver, s.name());
    }
}

#[test]
fn meshes_without_valence_two_vertices_keep_cg() {
    for (name, mesh) in [("torus", shapes::torus(12, 8)), ("grid", shapes::quad_grid(6, 5))] {
        let r = cheng::interpolate(&mesh, &ChengOptions::default()).unwrap();
        check(name, &mesh, &r, TOL);
        assert_eq!(r.solve.as_ref().unwrap().solver, "cg-jacobi", "{name}");
    }
    let spot = support::fixture("quad/spot_control_mesh.obj");
    let r = cheng::interpolate(&spot, &ChengOptions::default()).unwrap();
    assert_eq!(r.solve.as_ref().unwrap().solver, "cg-jacobi");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Random tori and grids with random interior edges split once or twice.
    #[test]
    fn random_valence_two_meshes_interpolate(
        nu in 4usize..14,
        nv in 4usize..10,
        open in any::<bool>(),
        picks in proptest::collection::vec((any::<u32>(), any::<bool>()), 1..6),
    ) {
        let base = if open { shapes::quad_grid(nu, nv) } else { shapes::torus(nu, nv) };
        let t = base.topology();
        let interior: Vec<EdgeId> = t.edges().filter(|&e| !t.is_boundary_edge(e)).collect();
        let (mut singles, mut doubles) = (Vec::new(), Vec::new());
        let mut used = std::collections::HashSet::new();
        for (k, double) in picks {
            let e = interior[k as usize % interior.len()];
            if used.insert(e) {
                let (a, b) = t.edge_vertices(e);
                if double { doubles.push((a.0, b.0)) } else { singles.push((a.0, b.0)) }
            }
        }
        let mesh = with_valence_two(&base, &singles, &doubles);
        let r = match cheng::interpolate(&mesh, &ChengOptions::default()) {
            Ok(r) => r,
            // Some placements make Cheng's A exactly singular (two doubly split
            // edges at one grid vertex): then the dense LU, which does not share
            // MINRES's stopping rule, must find it singular too, and the
            // refusal is the right answer.
            Err(e) => {
                let dense = cheng::interpolate(&mesh, &ChengOptions::default().with_solver(SolverChoice::Use(Solver::Dense)));
                let singular = matches!(&dense, Err(d) if d.to_string().contains("singular"));
                prop_assert!(singular, "auto failed ({e}) on a matrix the dense LU solves");
                prop_assert!(e.is_not_converged(), "{e}");
                return Ok(());
            }
        };
        check("random", &mesh, &r, TOL);
        prop_assert_eq!(r.solve.as_ref().unwrap().solver.as_str(), "minres");
    }
}
