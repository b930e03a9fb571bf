//! The integration tests of subdiv-mesh, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `support` holds their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-mesh --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).
//! Proptest keeps failure seeds in `tests/proptest-regressions/<module>.txt`.

mod support {
    pub mod triangulation;
}

mod arrays;
mod doo_sabin_creases;
mod features;
mod linear_time;
mod scale;
mod sqrt3;
mod topology;
mod triangulate;
