//! The integration tests of subdiv-mesh, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `support` holds their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-mesh --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).
//! Proptest keeps failure seeds in `tests/proptest-regressions/<module>.txt`.
//!
//! `#[cfg(feature = "internals")]` marks the modules that use `subdiv_mesh::internals`:
//! built with the feature, which the crate's self dev-dependency turns on; left out
//! where it is off (a build without the dev-dependency).

mod support {
    pub mod triangulation;
}

mod arrays;
#[cfg(feature = "internals")]
mod doo_sabin_creases;
mod features;
mod linear_time;
mod scale;
#[cfg(feature = "internals")]
mod sqrt3;
#[cfg(feature = "internals")]
mod topology;
mod triangulate;
