//! Lanczos and power-iteration estimates against dense eigenvalues
//! (nalgebra SymmetricEigen on D^{1/2} S D^{1/2}) and against the known
//! spectra of the model problems.

use crate::common;

use subdiv_solve::{
    extreme_eigenvalues, internals::model_problems, internals::tolerances::SPECTRUM_MARGIN, power_iteration,
};

fn check_bracket(name: &str, a: &subdiv_solve::FactoredMatrix, steps: usize) {
    let ev = common::eigenvalues(a);
    let (lo, hi) = (ev[0], ev[ev.len() - 1]);
    let s = extreme_eigenvalues(a, steps).unwrap();
    // Interlacing: Ritz values lie inside the spectrum.
    assert!(s.ritz_min >= lo - 1e-10 && s.ritz_max <= hi + 1e-10, "{name}: {s:?} vs [{lo}, {hi}]");
    // The bracket contains the spectrum …
    assert!(s.min <= lo + 1e-12 && s.max >= hi - 1e-12, "{name}: [{}, {}] vs [{lo}, {hi}]", s.min, s.max);
    // … within a few per cent.
    let width = hi - lo;
    assert!(lo - s.min <= 0.05 * lo.abs().max(0.05 * width), "{name}: min {} vs {lo}", s.min);
    assert!(s.max - hi <= 0.05 * hi.abs(), "{name}: max {} vs {hi}", s.max);
    assert!(s.ritz_min - lo <= 0.5 * SPECTRUM_MARGIN * lo.abs().max(1e-3), "{name}: θ_min {} vs {lo}", s.ritz_min);
    assert!(hi - s.ritz_max <= 0.5 * SPECTRUM_MARGIN * hi.abs(), "{name}: θ_max {} vs {hi}", s.ritz_max);
}

#[test]
fn lanczos_brackets_the_dense_spectrum() {
    for (name, a) in common::nonsingular_cases() {
        check_bracket(name, &a, 60);
    }
    check_bracket("pillow", &model_problems::pillow(), 30);
    check_bracket("cube", &model_problems::cube_checkerboard(), 30);
    check_bracket("shifted torus", &common::shifted_torus(12, 14), 60);
}

#[test]
fn known_spectra_of_the_regular_masks() {
    // Bicubic: (4 + 2cos a)(4 + 2cos b)/36 ∈ [1/9, 1] on even grids.
    let a = model_problems::bicubic_torus(40, 40);
    let s = extreme_eigenvalues(&a, 60).unwrap();
    assert!((s.ritz_max - 1.0).abs() < 1e-8, "{s:?}");
    assert!((s.ritz_min - 1.0 / 9.0).abs() < 1e-3, "{s:?}");
    assert!(s.min < 1.0 / 9.0 && s.max >= 1.0);
    // The upper end is capped by ‖A‖_∞ = 1 (rows of non-negative weights summing to 1).
    assert!(s.max <= 1.0 + 1e-12);
    // Loop: ½ + (cos a + cos b + cos(a − b))/6 ∈ [¼, 1] on grids divisible by 3.
    let a = model_problems::loop_regular(30, 33);
    let s = extreme_eigenvalues(&a, 60).unwrap();
    assert!((s.ritz_max - 1.0).abs() < 1e-8 && (s.ritz_min - 0.25).abs() < 1e-3, "{s:?}");
    assert!((s.optimal_omega() - 2.0 / 1.25).abs() < 0.05);
    // Pillow: {1, 1/7, 1/7, −1/7} exactly (Krylov space exhausted).
    let s = extreme_eigenvalues(&model_problems::pillow(), 10).unwrap();
    assert!((s.ritz_min + 1.0 / 7.0).abs() < 1e-12 && (s.ritz_max - 1.0).abs() < 1e-12, "{s:?}");
    assert!(s.steps <= 4);
    assert_eq!(s.condition(), f64::INFINITY);
    // Cube: λ = 0 (checkerboard).
    let s = extreme_eigenvalues(&model_problems::cube_checkerboard(), 10).unwrap();
    assert!(s.ritz_min.abs() < 1e-12, "{s:?}");
}

#[test]
fn plain_lanczos_without_reorthogonalisation_still_finds_the_extremes() {
    // 300 × 300 = 90,000 rows × 100 steps is above the reorthogonalisation budget.
    let a = model_problems::bicubic_torus(300, 300);
    assert!(a.n() * 100 > subdiv_solve::internals::tolerances::LANCZOS_REORTH_MAX_STORE);
    let s = extreme_eigenvalues(&a, 100).unwrap();
    assert!(s.ritz_min >= 1.0 / 9.0 - 1e-9 && s.ritz_max <= 1.0 + 1e-9, "{s:?}");
    assert!(s.min <= 1.0 / 9.0 && s.max >= 1.0, "{s:?}");
    assert!(s.ritz_min - 1.0 / 9.0 < 0.01 / 9.0, "{s:?}");
}

#[test]
fn power_iteration_approaches_lambda_max() {
    for (name, a) in common::nonsingular_cases() {
        let ev = common::eigenvalues(&a);
        let hi = ev[ev.len() - 1];
        let est = power_iteration(&a, 300).unwrap();
        assert!(est <= hi * (1.0 + 1e-12) && est >= 0.98 * hi, "{name}: {est} vs {hi}");
    }
    // Non-symmetric input: the norm ratio of A·v.
    let g = subdiv_solve::FactoredMatrix::from_general(model_problems::loop_regular(6, 6).to_csr()).unwrap();
    let est = power_iteration(&g, 200).unwrap();
    assert!((est - 1.0).abs() < 1e-3, "{est}");
    assert!(power_iteration(&g, 0).is_err());
}
