//! The options and results of the crate seen from outside it, as a user sees
//! them. [`SolveOptions`] is `#[non_exhaustive]`: `Default` and the `with_*`
//! setters are the only way to build one here (a struct literal does not
//! compile: the `compile_fail` doc-test on `SolveOptions`), so a new option is
//! not a breaking change. The results ([`Solution`], [`Spectrum`]) are
//! `#[non_exhaustive]` too: read through their fields, made by the crate (or
//! [`Spectrum::bracket`]).

use std::sync::{Arc, Mutex};
use subdiv_mesh::shapes;
use subdiv_solve::{
    chebyshev_with, weighted_pia_with, FactoredMatrix, IterationObserver, Solution, SolveOptions, Spectrum,
    DEFAULT_MAX_ITER, DEFAULT_TOL,
};

#[test]
fn solve_options_are_built_from_default_and_setters_only() {
    let d = SolveOptions::default();
    assert_eq!((d.tol, d.scale, d.max_iter, d.history), (DEFAULT_TOL, 1.0, DEFAULT_MAX_ITER, true));
    assert!(d.initial.is_none());

    let heard = Arc::new(Mutex::new(Vec::new()));
    let log = heard.clone();
    let opts = SolveOptions::default()
        .with_tol(1e-9)
        .with_scale(4.0)
        .with_max_iter(17)
        .with_history(false)
        .with_initial(Some(vec![[1.0, 2.0, 3.0]]))
        .with_observer(IterationObserver::new(move |k, r| log.lock().unwrap().push((k, r))));
    assert_eq!((opts.tol, opts.scale, opts.max_iter, opts.history), (1e-9, 4.0, 17, false));
    assert_eq!(opts.initial.as_deref(), Some(&[[1.0, 2.0, 3.0]][..]));
    opts.observer.notify(3, 0.5);
    assert_eq!(*heard.lock().unwrap(), [(3, 0.5)]);

    // Each setter changes its own field only.
    let base = SolveOptions::default();
    assert_eq!(base.clone().with_tol(1e-3).scale, base.scale);
    assert_eq!(base.clone().with_max_iter(5).tol, base.tol);
    assert_eq!(base.clone().with_initial(None), base);
}

/// Cheng's A of a regular quad torus is the bicubic limit mask, spec(A) =
/// [1/9, 1] exactly: the solvers that take a spectrum run on the known
/// bracket without a Lanczos estimate.
#[test]
fn a_known_spectrum_is_a_bracket() {
    let m = subdiv_stencil::limit_matrix_catmull_clark(shapes::torus(12, 12).topology());
    let a = FactoredMatrix::new(m.d, m.s).unwrap();
    let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [(i % 12) as f64, (i / 12) as f64, (i % 5) as f64]).collect();
    let known = Spectrum::bracket(1.0 / 9.0, 1.0);
    assert_eq!((known.ritz_min, known.ritz_max, known.steps, known.matvecs), (1.0 / 9.0, 1.0, 0, 0));
    let opts = SolveOptions::default().with_tol(1e-10).with_scale(12.0);
    for sol in [chebyshev_with(&a, &p, &opts, &known).unwrap(), weighted_pia_with(&a, &p, &opts, &known).unwrap()] {
        let sol: Solution = sol;
        assert!(sol.converged && a.max_residual(&sol.x, &p) / opts.scale <= 1e-10, "{}", sol.solver);
    }
    let wider = known.with_bracket(0.1, 1.1);
    assert_eq!((wider.min, wider.max, wider.ritz_min), (0.1, 1.1, 1.0 / 9.0));
    // A bracket that reaches 0 is refused by weighted PIA.
    assert!(weighted_pia_with(&a, &p, &opts, &Spectrum::bracket(0.0, 1.0)).is_err());
}
