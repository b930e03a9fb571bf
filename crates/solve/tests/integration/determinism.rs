//! Bitwise determinism: the same bits whatever the rayon thread count, on a
//! 200,000-row system (above the parallel threshold, so the chunked
//! parallel kernels and reductions really run on several threads).

use subdiv_solve::{
    internals::model_problems, internals::tolerances::PARALLEL_MIN_ROWS, Solution, SolveOptions, Solver, SweepOrder,
};

fn bits(sol: &Solution) -> Vec<u64> {
    sol.x.iter().flat_map(|r| r.iter().map(|v| v.to_bits())).chain(sol.history.iter().map(|v| v.to_bits())).collect()
}

fn run_in_pool(threads: usize, f: impl FnOnce() -> Solution + Send) -> Solution {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
}

#[test]
fn solvers_give_identical_bits_on_one_and_two_threads() {
    let a = model_problems::bicubic_torus(500, 400);
    assert!(a.n() == 200_000 && a.n() >= 2 * PARALLEL_MIN_ROWS);
    let p: Vec<[f64; 3]> = (0..a.n())
        .map(|i| {
            let (x, y) = ((i % 500) as f64, (i / 500) as f64);
            [x.sin() + 0.01 * y, (0.1 * y).cos() * x / 500.0, ((i * 7919) % 1000) as f64 / 1000.0]
        })
        .collect();
    let opts = SolveOptions::default().with_tol(1e-9);
    for solver in [
        Solver::Cg { jacobi: true },
        Solver::Cg { jacobi: false },
        Solver::Chebyshev,
        Solver::GaussSeidel(SweepOrder::Multicolor),
    ] {
        let one = run_in_pool(1, || solver.solve(&a, &p, &opts).unwrap());
        let two = run_in_pool(2, || solver.solve(&a, &p, &opts).unwrap());
        assert_eq!(one.iterations, two.iterations, "{solver}");
        assert_eq!(one.residual.to_bits(), two.residual.to_bits(), "{solver}");
        assert!(bits(&one) == bits(&two), "{solver}: results differ between 1 and 2 threads");
        // The parallel run really computed something non-trivial.
        assert!(one.iterations > 5 && one.residual <= 1e-9, "{solver}");
    }
    let s1 = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| subdiv_solve::extreme_eigenvalues(&a, 20).unwrap());
    let s2 = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| subdiv_solve::extreme_eigenvalues(&a, 20).unwrap());
    assert_eq!(s1.ritz_min.to_bits(), s2.ritz_min.to_bits());
    assert_eq!(s1.ritz_max.to_bits(), s2.ritz_max.to_bits());
}
