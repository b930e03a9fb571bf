//! The matrices no Catmull-Clark surface can be fitted through, or only by
//! some solvers: (d) the checkerboard cube (singular) and (e) indefinite
//! matrices (the pillow, λ_min = −1/7; a shifted torus). Every outcome is a
//! typed error or a verified solution, never a silent wrong answer.

use crate::common;

use crate::common::{dense_a, max_row_residual};
use subdiv_solve::{
    cg, chebyshev, dense_lu, extreme_eigenvalues, gauss_seidel, internals::model_problems, ldl, pia, weighted_pia,
    SolveError, SolveOptions, Solver, StopReason, SweepOrder,
};

fn cube_rhs_consistent() -> Vec<[f64; 3]> {
    let a = model_problems::cube_checkerboard();
    let x: Vec<[f64; 3]> = common::data(8, 4);
    let mut p = vec![[0.0; 3]; 8];
    a.apply(&x, &mut p);
    p
}

fn cube_rhs_inconsistent() -> Vec<[f64; 3]> {
    // Add a multiple of D·k: the range of A = D·S is D·range(S) = D·k^⊥.
    let k = model_problems::cube_kernel();
    let d = model_problems::cube_checkerboard().d().to_vec();
    cube_rhs_consistent()
        .iter()
        .enumerate()
        .map(|(i, r)| [r[0] + 0.3 * d[i] * k[i], r[1], r[2] - 0.1 * d[i] * k[i]])
        .collect()
}

/// Never Ok with a residual above tol.
fn assert_honest(
    name: &str,
    r: &Result<subdiv_solve::Solution, SolveError>,
    dense: &nalgebra::DMatrix<f64>,
    p: &[[f64; 3]],
    tol: f64,
) {
    if let Ok(sol) = r {
        let res = max_row_residual(dense, &sol.x, p);
        assert!(res <= tol * (1.0 + 1e-9), "{name}: Ok with true residual {res:e}");
        assert!(sol.x.iter().all(|r| r.iter().all(|v| v.is_finite())));
    }
}

#[test]
fn checkerboard_cube_consistent_rhs() {
    let a = model_problems::cube_checkerboard();
    let dense = dense_a(&a);
    let p = cube_rhs_consistent();
    let opts = SolveOptions::default().with_tol(1e-9);
    // Krylov and stationary methods converge on a consistent singular system.
    for s in [
        Solver::Cg { jacobi: false },
        Solver::Cg { jacobi: true },
        Solver::Pia,
        Solver::GaussSeidel(SweepOrder::Storage),
    ] {
        let sol = s.solve(&a, &p, &opts).unwrap_or_else(|e| panic!("{s}: {e}"));
        assert!(max_row_residual(&dense, &sol.x, &p) <= 1e-9, "{s}");
    }
    // The direct solvers detect the singularity.
    assert!(matches!(ldl(&a, &p, &opts), Err(SolveError::Singular { .. })), "{:?}", ldl(&a, &p, &opts));
    assert!(matches!(dense_lu(&a, &p, &opts), Err(SolveError::Singular { .. })));
    // So do the ones that need λ_min > 0.
    assert!(matches!(weighted_pia(&a, &p, &opts), Err(SolveError::Singular { .. })));
    assert!(matches!(chebyshev(&a, &p, &opts), Err(SolveError::Singular { .. })));
    let e = ldl(&a, &p, &opts).unwrap_err().to_string();
    assert!(e.contains("singular") && e.contains("null space"), "{e}");
}

#[test]
fn checkerboard_cube_inconsistent_rhs() {
    let a = model_problems::cube_checkerboard();
    let dense = dense_a(&a);
    let p = cube_rhs_inconsistent();
    let opts = SolveOptions::default().with_tol(1e-6);
    for s in Solver::ALL {
        let r = s.solve(&a, &p, &opts);
        assert_honest(s.name(), &r, &dense, &p, 1e-6);
        assert!(r.is_err(), "{s} returned Ok on an inconsistent singular system");
    }
    match cg(&a, &p, &opts, false) {
        Err(SolveError::NotConverged { residual, .. }) => assert!(residual > 1e-3),
        Err(SolveError::Singular { .. }) => {}
        other => panic!("{other:?}"),
    }
    match pia(&a, &p, &opts) {
        Err(SolveError::NotConverged { reason, iterations, .. }) => {
            assert_eq!(reason, StopReason::Stagnated);
            assert!(iterations < 1000);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn pillow_is_indefinite() {
    let a = model_problems::pillow();
    let dense = dense_a(&a);
    let p = common::data(4, 8);
    let opts = SolveOptions::default();
    for jacobi in [false, true] {
        let e = cg(&a, &p, &opts, jacobi).unwrap_err();
        assert!(matches!(e, SolveError::Indefinite { .. }), "{e:?}");
        assert!(e.to_string().contains("Solver::Ldl or Solver::Dense"));
    }
    assert!(matches!(pia(&a, &p, &opts), Err(SolveError::Diverged { .. } | SolveError::NotConverged { .. })));
    assert!(matches!(weighted_pia(&a, &p, &opts), Err(SolveError::Indefinite { .. })));
    assert!(matches!(chebyshev(&a, &p, &opts), Err(SolveError::Indefinite { .. })));
    // Nonsingular: the direct solvers solve it, LDLᵀ counts one negative eigenvalue.
    let sol = ldl(&a, &p, &opts).unwrap();
    assert_eq!(sol.negative_pivots, Some(1));
    assert!(max_row_residual(&dense, &sol.x, &p) <= 1e-12);
    let sol = dense_lu(&a, &p, &opts).unwrap();
    assert!(max_row_residual(&dense, &sol.x, &p) <= 1e-12);
    for order in [SweepOrder::Storage, SweepOrder::Symmetric, SweepOrder::Multicolor] {
        assert_honest("gs", &gauss_seidel(&a, &p, &opts, order), &dense, &p, 1e-6);
    }
}

#[test]
fn larger_indefinite_matrix() {
    let a = common::shifted_torus(12, 14);
    let dense = dense_a(&a);
    let p = common::data(a.n(), 12);
    let opts = SolveOptions::default();
    let neg = common::eigenvalues(&a).iter().filter(|v| **v < 0.0).count();
    assert!(neg >= 1);
    assert!(matches!(cg(&a, &p, &opts, true), Err(SolveError::Indefinite { .. })));
    let r = pia(&a, &p, &opts);
    assert!(
        matches!(r, Err(SolveError::Diverged { .. } | SolveError::NotConverged { .. })),
        "{:?}",
        r.map(|s| s.iterations)
    );
    let sol = ldl(&a, &p, &opts).unwrap();
    assert_eq!(sol.negative_pivots, Some(neg));
    assert!(max_row_residual(&dense, &sol.x, &p) <= 1e-6);
    assert!(extreme_eigenvalues(&a, 60).unwrap().ritz_min < 0.0);
    for s in Solver::ALL {
        assert_honest(s.name(), &s.solve(&a, &p, &opts), &dense, &p, 1e-6);
    }
}
