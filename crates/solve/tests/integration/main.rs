//! The integration tests of subdiv-solve, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `common` holds their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-solve --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).
//! Proptest keeps failure seeds in `tests/proptest-regressions/<module>.txt`.

mod common;

mod agreement;
mod determinism;
mod errors;
mod gauss_seidel_orders;
mod gmres;
mod minres;
mod options;
mod proptest_spd;
mod singular_indefinite;
mod spectrum;
