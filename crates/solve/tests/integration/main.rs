//! The integration tests of subdiv-solve, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `common` holds their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-solve --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).
//! Proptest keeps failure seeds in `tests/proptest-regressions/<module>.txt`.
//!
//! `#[cfg(feature = "internals")]` marks the modules that use `subdiv_solve::internals`:
//! built with the feature, which the crate's self dev-dependency turns on; left out
//! where it is off (a packaged copy without the dev-dependency).

#[cfg(feature = "internals")]
mod common;

#[cfg(feature = "internals")]
mod agreement;
#[cfg(feature = "internals")]
mod determinism;
#[cfg(feature = "internals")]
mod errors;
#[cfg(feature = "internals")]
mod gauss_seidel_orders;
#[cfg(feature = "internals")]
mod gmres;
#[cfg(feature = "internals")]
mod minres;
mod options;
#[cfg(feature = "internals")]
mod proptest_spd;
#[cfg(feature = "internals")]
mod singular_indefinite;
#[cfg(feature = "internals")]
mod spectrum;
