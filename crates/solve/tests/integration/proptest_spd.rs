//! Property test: on random SPD systems A = D·S of random sizes, CG (both
//! variants), Chebyshev and LDLᵀ agree with each other and with the dense
//! solution within the bound their residuals imply.

use crate::common;

use proptest::prelude::*;
use subdiv_solve::{internals::model_problems, SolveOptions, Solver};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    #[test]
    fn krylov_chebyshev_and_ldl_agree(n in 1usize..160, neighbours in 0usize..10, seed in any::<u64>(), scale in 0.1f64..100.0) {
        let a = model_problems::random_spd(n, neighbours, seed);
        let dense = common::dense_a(&a);
        let p: Vec<[f64; 3]> = common::data(n, seed ^ 0x55).iter().map(|r| [r[0] * scale, r[1] * scale, r[2] * scale]).collect();
        let (x_ref, inv_norm) = common::reference(&dense, &p);
        let ref_res = common::max_row_residual(&dense, &x_ref, &p);
        let opts = SolveOptions::default().with_tol(1e-9).with_scale(scale);
        let mut xs = Vec::new();
        for s in [Solver::Cg { jacobi: false }, Solver::Cg { jacobi: true }, Solver::Chebyshev, Solver::Ldl] {
            let sol = s.solve(&a, &p, &opts).map_err(|e| TestCaseError::fail(format!("{s}: {e}")))?;
            let res = common::max_row_residual(&dense, &sol.x, &p);
            prop_assert!(res <= 1e-9 * scale * (1.0 + 1e-9), "{}: residual {}", s, res);
            let gap = common::max_row_gap(&sol.x, &x_ref);
            prop_assert!(gap <= inv_norm * (res + ref_res) * (1.0 + 1e-6) + 1e-12 * scale, "{}: gap {}", s, gap);
            xs.push((s, sol.x, res));
        }
        // Pairwise: two solutions differ by at most ‖A⁻¹‖_∞ (r₁ + r₂).
        for i in 0..xs.len() {
            for j in i + 1..xs.len() {
                let gap = common::max_row_gap(&xs[i].1, &xs[j].1);
                prop_assert!(gap <= inv_norm * (xs[i].2 + xs[j].2) * (1.0 + 1e-6) + 1e-12 * scale, "{} vs {}", xs[i].0, xs[j].0);
            }
        }
    }
}
