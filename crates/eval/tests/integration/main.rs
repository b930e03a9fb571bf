//! The integration tests of subdiv-eval, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `bspline_torus` and `common` hold their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-eval --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).
//! Proptest keeps failure seeds in `tests/proptest-regressions/<module>.txt`.

mod bspline_torus;
mod common;

mod dart;
mod doo_sabin;
mod dyadic;
mod fit;
mod fit_recovery;
mod project;
mod properties;
mod sample;
