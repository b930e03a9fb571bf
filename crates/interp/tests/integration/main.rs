//! The integration tests of subdiv-interp, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `support` holds their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-interp --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).
//! Proptest keeps failure seeds in `tests/proptest-regressions/<module>.txt`.

mod support;

mod advice;
mod cheng_schemes;
mod creases;
mod deng_ma;
mod deng_wang;
mod deng_wang_creases;
mod fair;
mod fair_bound;
mod fair_threads;
mod first_step;
mod limit_matrices;
mod limit_matrices_doo_sabin_creases;
mod numeric_rule;
mod solved_methods;
mod solver_choice;
mod valence_two;
mod zheng_cai;
