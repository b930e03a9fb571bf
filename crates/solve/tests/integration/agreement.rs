//! Differential tests: every solver reaches the dense solution on the
//! nonsingular model problems (a)-(c), and the reported stopping quantity is
//! the true max row residual, recomputed here without the crate's kernels.

use crate::common;

use crate::common::{dense_a, max_row_gap, max_row_residual, nonsingular_cases, reference};
use subdiv_solve::{
    cg, chebyshev, chebyshev_with, extreme_eigenvalues, internals::model_problems, weighted_pia_with, FactoredMatrix,
    SolveError, SolveOptions, Solver,
};

#[test]
fn every_solver_reaches_the_dense_solution() {
    for (name, a) in nonsingular_cases() {
        let dense = dense_a(&a);
        let p = common::data(a.n(), 3);
        let (x_ref, inv_norm) = reference(&dense, &p);
        let scale = 2.5;
        let opts = SolveOptions::default().with_tol(1e-8).with_scale(scale);
        for solver in Solver::ALL {
            if solver == Solver::Jacobi && name.starts_with("(b)") {
                // Not diagonally dominant: λ_max(S) = 36 > 2·16, so Jacobi's
                // iteration matrix has an eigenvalue −1.25 (jacobi.rs).
                let e = solver.solve(&a, &p, &opts).map(|s| s.iterations).unwrap_err();
                assert!(matches!(e, SolveError::Diverged { .. } | SolveError::NotConverged { .. }), "{name}: {e:?}");
                continue;
            }
            let sol = solver.solve(&a, &p, &opts).unwrap_or_else(|e| panic!("{name}, {solver}: {e}"));
            let true_res = max_row_residual(&dense, &sol.x, &p);
            assert!(sol.converged);
            assert_eq!(sol.solver, solver.name());
            // The reported residual is the true one, and it meets tol.
            assert!(true_res / scale <= 1e-8, "{name}, {solver}: true residual {}", true_res / scale);
            assert!((sol.residual - true_res / scale).abs() <= 1e-12 + 1e-6 * sol.residual, "{name}, {solver}");
            // Forward error within the bound the residual implies (plus the reference's own error).
            let gap = max_row_gap(&sol.x, &x_ref);
            let bound = inv_norm * (true_res + max_row_residual(&dense, &x_ref, &p)) * (1.0 + 1e-6) + 1e-13;
            assert!(gap <= bound, "{name}, {solver}: |X − X*| = {gap:e} > {bound:e}");
            if solver.name().contains("ldl") || solver.name() == "dense" {
                continue;
            }
            assert_eq!(sol.history.len(), sol.iterations + 1, "{name}, {solver}");
            assert!(
                (sol.history.last().unwrap() - sol.residual).abs() <= 1e-6 * sol.residual.max(1e-300)
                    || solver.name().starts_with("cg")
            );
            assert!(sol.matvecs > sol.iterations, "{name}, {solver}");
        }
    }
}

#[test]
fn accelerated_solvers_beat_pia_as_theory_predicts() {
    // (b): κ = 9 → PIA contracts by 8/9, weighted PIA by 0.8, Chebyshev/CG by ≈ ½.
    let a = model_problems::bicubic_torus(30, 30);
    let p = common::data(a.n(), 5);
    let opts = SolveOptions::default().with_tol(1e-6);
    let it = |s: Solver| s.solve(&a, &p, &opts).unwrap().iterations;
    let (pia, wpia, cheb, cgj) =
        (it(Solver::Pia), it(Solver::WeightedPia), it(Solver::Chebyshev), it(Solver::Cg { jacobi: true }));
    assert!(wpia < pia && cheb < wpia && cgj < wpia, "pia {pia}, wpia {wpia}, cheb {cheb}, cg {cgj}");
    let e0 = 2.0; // |P − A·P| ≤ 2·max|P|·√3 at the start; log ratio bound
    assert!((pia as f64) < (1e-6f64 / (e0 * 4.0)).ln() / (8.0f64 / 9.0).ln() + 5.0, "pia {pia}");
    assert!(cheb < 35 && cgj < 35, "cheb {cheb}, cg {cgj}");
}

#[test]
fn stopping_rule_uses_scale_and_max_iter() {
    let a = model_problems::loop_regular(12, 12);
    let p = common::data(a.n(), 9);
    let dense = dense_a(&a);
    // A larger scale makes the relative test looser: fewer iterations.
    let tight = subdiv_solve::pia(&a, &p, &SolveOptions::default().with_tol(1e-6).with_scale(1.0)).unwrap();
    let loose = subdiv_solve::pia(&a, &p, &SolveOptions::default().with_tol(1e-6).with_scale(100.0)).unwrap();
    assert!(loose.iterations < tight.iterations);
    assert!(max_row_residual(&dense, &loose.x, &p) <= 1e-4);
    // Exactly max_iter updates, then NotConverged with the iterate and its history.
    let e = subdiv_solve::pia(&a, &p, &SolveOptions::default().with_tol(1e-12).with_max_iter(5)).unwrap_err();
    match e {
        SolveError::NotConverged { iterations, residual, history, x, reason, .. } => {
            assert_eq!(iterations, 5);
            assert_eq!(history.len(), 6);
            assert_eq!(reason, subdiv_solve::StopReason::MaxIterations);
            assert!((max_row_residual(&dense, &x.0, &p) - residual).abs() < 1e-12);
            assert!(history.windows(2).all(|w| w[1] < w[0]));
        }
        other => panic!("{other:?}"),
    }
    // history: false records nothing.
    let quiet = subdiv_solve::pia(&a, &p, &SolveOptions::default().with_history(false)).unwrap();
    assert!(quiet.history.is_empty());
    // A start that already satisfies the tolerance costs zero iterations.
    let exact = tight.x.clone();
    for s in Solver::ALL {
        let sol = s.solve(&a, &p, &SolveOptions::default().with_tol(1e-6).with_initial(Some(exact.clone()))).unwrap();
        if !matches!(s, Solver::Ldl | Solver::Dense) {
            assert_eq!(sol.iterations, 0, "{s}");
        }
    }
}

#[test]
fn general_matrices_work_with_the_non_symmetric_solvers_only() {
    // A non-symmetric, diagonally dominant A (an open-mesh-like boundary row).
    let base = model_problems::loop_regular(9, 9).to_csr();
    let mut tri = sprs::TriMatI::<f64, u32>::new((81, 81));
    for (&v, (i, j)) in base.iter() {
        let (i, j) = (i as usize, j as usize);
        tri.add_triplet(i, j, if i == 0 && j != 0 { v * 0.5 } else { v });
    }
    tri.add_triplet(0, 0, 0.25);
    let a = FactoredMatrix::from_general(tri.to_csr()).unwrap();
    assert!(!a.symmetric());
    let dense = dense_a(&a);
    let p = common::data(81, 1);
    let (x_ref, inv_norm) = reference(&dense, &p);
    for s in Solver::ALL {
        let r = s.solve(&a, &p, &SolveOptions::default());
        if s.needs_symmetric() {
            assert!(matches!(r, Err(SolveError::NotSymmetric { .. })), "{s}: {r:?}");
        } else {
            let sol = r.unwrap_or_else(|e| panic!("{s}: {e}"));
            let res = max_row_residual(&dense, &sol.x, &p);
            assert!(res <= 1e-6);
            assert!(max_row_gap(&sol.x, &x_ref) <= inv_norm * res * 1.01 + 1e-12);
        }
    }
    assert!(matches!(extreme_eigenvalues(&a, 20), Err(SolveError::NotSymmetric { .. })));
    // With a known interval, Chebyshev and weighted PIA need no symmetry.
    let spec = extreme_eigenvalues(&model_problems::loop_regular(9, 9), 40).unwrap();
    let wide = spec.with_bracket(spec.min * 0.8, spec.max * 1.1);
    assert!(chebyshev_with(&a, &p, &SolveOptions::default(), &wide).is_ok());
    assert!(weighted_pia_with(&a, &p, &SolveOptions::default(), &wide).is_ok());
    assert!(matches!(cg(&a, &p, &SolveOptions::default(), false), Err(SolveError::NotSymmetric { .. })));
    assert!(matches!(chebyshev(&a, &p, &SolveOptions::default()), Err(SolveError::NotSymmetric { .. })));
}

#[test]
fn empty_and_tiny_systems() {
    let empty =
        FactoredMatrix::new(Vec::new(), subdiv_solve::SparseMatrix::new((0, 0), vec![0], vec![], vec![])).unwrap();
    for s in Solver::ALL {
        let sol = s.solve(&empty, &[], &SolveOptions::default()).unwrap_or_else(|e| panic!("{s}: {e}"));
        assert!(sol.x.is_empty());
    }
    for n in 1..4 {
        let a = model_problems::random_spd(n, 2, n as u64);
        let p = common::data(n, 2);
        let (x_ref, _) = reference(&dense_a(&a), &p);
        for s in Solver::ALL {
            let sol =
                s.solve(&a, &p, &SolveOptions::default().with_tol(1e-10)).unwrap_or_else(|e| panic!("n {n}, {s}: {e}"));
            assert!(max_row_gap(&sol.x, &x_ref) < 1e-8, "n {n}, {s}");
        }
    }
}
