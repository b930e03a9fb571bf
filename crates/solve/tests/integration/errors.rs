//! Bad user data gives typed errors naming the problem; caller bugs panic.

use subdiv_solve::{
    dense_lu_capped, internals::model_problems, FactoredMatrix, SolveError, SolveOptions, Solver, SparseMatrix,
};

#[test]
fn invalid_input_is_reported_by_every_solver() {
    let a = model_problems::loop_regular(6, 6);
    let good = vec![[0.5, 1.0, -1.0]; a.n()];
    let mut nan = good.clone();
    nan[7][1] = f64::NAN;
    let short = vec![[0.0; 3]; a.n() - 1];
    let cases: Vec<(&str, Vec<[f64; 3]>, SolveOptions)> = vec![
        ("row 7", nan, SolveOptions::default()),
        ("35 rows", short, SolveOptions::default()),
        ("tol", good.clone(), SolveOptions::default().with_tol(0.0)),
        ("scale", good.clone(), SolveOptions::default().with_scale(f64::INFINITY)),
        ("initial guess has 2 rows", good.clone(), SolveOptions::default().with_initial(Some(vec![[0.0; 3]; 2]))),
        ("initial guess row 0", good.clone(), SolveOptions::default().with_initial(Some(vec![[f64::NAN; 3]; 36]))),
    ];
    for (needle, p, opts) in &cases {
        for s in Solver::ALL {
            match s.solve(&a, p, opts) {
                Err(SolveError::InvalidInput(msg)) => assert!(msg.contains(needle), "{s}: {msg:?} lacks {needle:?}"),
                other => panic!("{s}, {needle}: {:?}", other.map(|s| s.iterations)),
            }
        }
    }
}

#[test]
fn dense_refuses_above_its_cap() {
    let a = model_problems::bicubic_torus(10, 10);
    let p = vec![[1.0, 0.0, 0.0]; 100];
    assert_eq!(
        dense_lu_capped(&a, &p, &SolveOptions::default(), 99).unwrap_err(),
        SolveError::TooLarge { n: 100, cap: 99 }
    );
    assert!(dense_lu_capped(&a, &p, &SolveOptions::default(), 100).is_ok());
    let msg = SolveError::TooLarge { n: 100, cap: 99 }.to_string();
    assert!(msg.contains("100") && msg.contains("99"));
}

#[test]
fn matrix_validation_names_the_entry() {
    let s = SparseMatrix::new((2, 2), vec![0, 1, 2], vec![0, 1], vec![1.0, 1.0]);
    let e = FactoredMatrix::new(vec![1.0, -2.0], s.clone()).unwrap_err();
    assert!(e.to_string().contains("d[1]"), "{e}");
    let e = FactoredMatrix::new(vec![1.0], s).unwrap_err();
    assert!(e.to_string().contains("1 entries"), "{e}");
}

#[test]
fn not_converged_error_is_small_and_readable() {
    // The last iterate travels in the error but is not dumped by Debug.
    let a = model_problems::bicubic_torus(40, 40);
    let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [i as f64, 0.0, 0.0]).collect();
    let e = Solver::Pia.solve(&a, &p, &SolveOptions::default().with_max_iter(3)).unwrap_err();
    let debug = format!("{e:?}");
    assert!(debug.contains("LastIterate(<1600 rows>)") && debug.len() < 400, "{debug}");
    assert!(e.to_string().contains("iteration limit") && e.to_string().contains("3 iterations"), "{e}");
    assert!(std::mem::size_of::<SolveError>() <= 128);
}

#[test]
#[should_panic(expected = "apply: x has 3 rows")]
fn apply_with_wrong_length_is_a_caller_bug() {
    let a = model_problems::pillow();
    let mut out = vec![[0.0; 3]; 4];
    a.apply(&[[0.0; 3]; 3], &mut out);
}
