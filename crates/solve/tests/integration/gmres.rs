//! GMRES on nonsymmetric (and symmetric, and singular) systems: solutions
//! equal the dense LU solution, residuals are recomputed with a dense product
//! (no crate kernel), full GMRES terminates in at most n steps and never
//! increases the residual, and the bits do not depend on the thread count.

use crate::common;

use crate::common::{dense_a, max_row_gap, max_row_residual, reference};
use proptest::prelude::*;
use subdiv_solve::{
    dense_lu, gmres, gmres_restarted, internals::model_problems, FactoredMatrix, SolveError, SolveOptions, Solver,
    StopReason,
};

/// A nonsymmetric A with the structure of an open-mesh limit matrix: the
/// regular Loop grid with one row's off-diagonal weights halved.
fn perturbed_loop_grid() -> FactoredMatrix {
    let base = model_problems::loop_regular(9, 9).to_csr();
    let mut tri = sprs::TriMatI::<f64, u32>::new((81, 81));
    for (&v, (i, j)) in base.iter() {
        let (i, j) = (i as usize, j as usize);
        tri.add_triplet(i, j, if i == 0 && j != 0 { v * 0.5 } else { v });
    }
    tri.add_triplet(0, 0, 0.25);
    FactoredMatrix::from_general(tri.to_csr()).unwrap()
}

#[test]
fn gmres_equals_the_dense_lu_solution() {
    let cases: Vec<(&str, FactoredMatrix)> = vec![
        ("random nonsymmetric 50", model_problems::random_nonsymmetric(50, 4, 1)),
        ("random nonsymmetric 400", model_problems::random_nonsymmetric(400, 8, 2)),
        ("perturbed Loop grid", perturbed_loop_grid()),
        ("pillow (indefinite)", model_problems::pillow()),
        ("random indefinite", model_problems::random_indefinite(200, 6, 7, 3)),
        ("bicubic torus", model_problems::bicubic_torus(20, 24)),
    ];
    for (name, a) in cases {
        let p = common::data(a.n(), 11);
        let opts = SolveOptions::default().with_tol(1e-13);
        let sol = gmres(&a, &p, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        let lu = dense_lu(&a, &p, &opts).unwrap();
        let gap = max_row_gap(&sol.x, &lu.x);
        assert!(gap <= 1e-10, "{name}: GMRES vs dense LU differ by {gap:e}");
        let dense = dense_a(&a);
        let res = max_row_residual(&dense, &sol.x, &p);
        assert!(res <= 1e-13 * (1.0 + 1e-9), "{name}: true residual {res:e}");
        assert!((sol.residual - res).abs() <= 1e-15 + 1e-6 * res, "{name}: reported residual is the true one");
        assert_eq!(sol.history.len(), sol.iterations + 1);
        assert_eq!(sol.history.last().copied(), Some(sol.residual));
        assert_eq!(sol.solver, "gmres");
    }
}

#[test]
fn full_gmres_terminates_within_n_steps_and_never_increases_the_residual() {
    // Saad & Schultz 1986, Prop. 2: without restarts GMRES finds the solution in
    // at most n steps (the degree of the minimal polynomial), and its residual
    // norm ‖P − A X_k‖₂ is non-increasing (nested minimisation problems).
    let a = model_problems::random_nonsymmetric(24, 6, 5);
    let dense = dense_a(&a);
    let p = common::data(24, 3);
    let sol = gmres_restarted(&a, &p, &SolveOptions::default().with_tol(1e-12), 30).unwrap();
    assert!(sol.iterations <= 24, "{} iterations for n = 24", sol.iterations);
    let norm = |x: &[[f64; 3]], c: usize| -> f64 {
        (0..24).map(|i| (p[i][c] - (0..24).map(|j| dense[(i, j)] * x[j][c]).sum::<f64>()).powi(2)).sum::<f64>().sqrt()
    };
    let mut previous = [f64::INFINITY; 3];
    for k in 1..sol.iterations {
        let x = match gmres_restarted(&a, &p, &SolveOptions::default().with_tol(1e-15).with_max_iter(k), 30) {
            Err(SolveError::NotConverged { x, iterations, .. }) => {
                assert_eq!(iterations, k);
                x.0
            }
            other => panic!("k = {k}: {other:?}"),
        };
        for c in 0..3 {
            let r = norm(&x, c);
            assert!(r <= previous[c] * (1.0 + 1e-12) + 1e-15, "k = {k}, column {c}: {r} after {}", previous[c]);
            previous[c] = r;
        }
    }
}

#[test]
fn every_restart_length_converges() {
    let a = model_problems::random_nonsymmetric(1500, 6, 9);
    let dense = dense_a(&a);
    let p = common::data(1500, 4);
    let opts = SolveOptions::default().with_tol(1e-10);
    for m in [1, 2, 5, 10, 30, 60] {
        let sol = gmres_restarted(&a, &p, &opts, m).unwrap_or_else(|e| panic!("m = {m}: {e}"));
        assert!(max_row_residual(&dense, &sol.x, &p) <= 1e-10, "m = {m}");
        // One true-residual product per cycle, plus the start.
        assert!(sol.matvecs > sol.iterations + sol.iterations.div_ceil(m), "m = {m}: {} matvecs", sol.matvecs);
    }
}

#[test]
fn singular_systems_are_solved_when_consistent_and_never_return_garbage_otherwise() {
    let (torus, torus_kernel) = common::singular_torus(16, 12);
    for (name, a, kernel) in [
        ("cube", model_problems::cube_checkerboard(), model_problems::cube_kernel()),
        ("singular torus", torus, torus_kernel),
    ] {
        let dense = dense_a(&a);
        let (p, q) = common::consistent_and_inconsistent(&a, &kernel, 4);
        let opts = SolveOptions::default().with_tol(1e-9);
        // Consistent: the range D·k^⊥ of A and its kernel k meet only in 0 (kᵀD⁻¹k > 0),
        // so GMRES converges.
        let sol = gmres(&a, &p, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(max_row_residual(&dense, &sol.x, &p) <= 1e-9, "{name}");
        // Inconsistent: a least-squares stop (invariant Krylov space, singular Hessenberg)
        // or stagnation, with a finite iterate whose residual is reported truthfully.
        match gmres(&a, &q, &opts) {
            Err(SolveError::NotConverged { reason, x, residual, iterations, .. }) => {
                assert!(matches!(reason, StopReason::LeastSquares | StopReason::Stagnated), "{name}: {reason:?}");
                // Finite, but possibly with a large null-space component (gmres.rs).
                let xmax = x.0.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                assert!(xmax.is_finite(), "{name}");
                let gap = (max_row_residual(&dense, &x.0, &q) - residual).abs();
                assert!(gap <= 1e-12 + 1e-14 * xmax, "{name}: reported {residual:e}, |X| {xmax:e}");
                assert!(residual > 1e-3, "{name}");
                eprintln!("{name}: {reason:?} after {iterations} iterations, residual {residual:.3e}");
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}

#[test]
fn not_converged_carries_the_iterate_and_the_history_across_restarts() {
    let a = model_problems::random_nonsymmetric(600, 6, 1);
    let dense = dense_a(&a);
    let p = common::data(600, 2);
    let scale = 2.0;
    let opts = SolveOptions::default().with_tol(1e-15).with_max_iter(7).with_scale(scale);
    match gmres_restarted(&a, &p, &opts, 3).unwrap_err() {
        SolveError::NotConverged { solver, iterations, residual, history, x, reason } => {
            assert_eq!((solver, iterations, reason), ("gmres", 7, StopReason::MaxIterations));
            assert_eq!(history.len(), 8);
            assert!((max_row_residual(&dense, &x.0, &p) / scale - residual).abs() < 1e-12);
            assert!(history.iter().all(|h| h.is_finite() && *h > 0.0));
        }
        other => panic!("{other:?}"),
    }
    let e = gmres(&a, &p, &SolveOptions::default().with_max_iter(2)).unwrap_err();
    assert!(e.to_string().contains("gmres did not converge") && e.to_string().contains("2 iterations"), "{e}");
}

#[test]
fn the_non_symmetric_solvers_agree_where_the_symmetric_ones_refuse() {
    let a = perturbed_loop_grid();
    let p = common::data(81, 1);
    let (x_ref, inv_norm) = reference(&dense_a(&a), &p);
    assert!(matches!(Solver::Minres.solve(&a, &p, &SolveOptions::default()), Err(SolveError::NotSymmetric { .. })));
    assert!(!Solver::Gmres.needs_symmetric() && Solver::Minres.needs_symmetric());
    let sol = Solver::Gmres.solve(&a, &p, &SolveOptions::default()).unwrap();
    assert!(max_row_gap(&sol.x, &x_ref) <= inv_norm * 1e-6 * 1.01);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random nonsymmetric well-conditioned systems of many sizes, every
    /// restart length: GMRES reaches tol (independent residual) and the dense solution.
    #[test]
    fn random_nonsymmetric_systems(
        n in 1usize..260,
        neighbours in 0usize..10,
        seed in any::<u64>(),
        restart in 1usize..40,
        scale in 0.1f64..100.0,
    ) {
        let a = model_problems::random_nonsymmetric(n, neighbours, seed);
        let p: Vec<[f64; 3]> = common::data(n, seed ^ 0x99).iter().map(|r| [r[0] * scale, r[1] * scale, r[2] * scale]).collect();
        let opts = SolveOptions::default().with_tol(1e-10).with_scale(scale);
        let dense = dense_a(&a);
        let sol = gmres_restarted(&a, &p, &opts, restart).map_err(|e| TestCaseError::fail(format!("n {n}, m {restart}: {e}")))?;
        let res = max_row_residual(&dense, &sol.x, &p);
        prop_assert!(res <= 1e-10 * scale * (1.0 + 1e-9), "residual {}", res);
        let (x_ref, inv_norm) = reference(&dense, &p);
        let gap = max_row_gap(&sol.x, &x_ref);
        prop_assert!(gap <= inv_norm * (res + max_row_residual(&dense, &x_ref, &p)) * (1.0 + 1e-6) + 1e-12 * scale, "gap {}", gap);
    }
}

#[test]
fn gmres_gives_identical_bits_on_one_and_two_threads() {
    let a = model_problems::random_nonsymmetric(200_000, 6, 42);
    assert!(a.n() >= 2 * subdiv_solve::internals::tolerances::PARALLEL_MIN_ROWS);
    let p = common::data(a.n(), 8);
    let opts = SolveOptions::default().with_tol(1e-10);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| gmres_restarted(&a, &p, &opts, 5).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let bits = |s: &subdiv_solve::Solution| -> Vec<u64> {
        s.x.iter().flat_map(|r| r.iter().map(|v| v.to_bits())).chain(s.history.iter().map(|v| v.to_bits())).collect()
    };
    assert_eq!(one.iterations, two.iterations);
    assert!(bits(&one) == bits(&two), "GMRES results differ between 1 and 2 threads");
    // More than one cycle ran, and the result is a solution.
    assert!(one.iterations > 5 && a.max_residual(&one.x, &p) <= 1e-10);
}
