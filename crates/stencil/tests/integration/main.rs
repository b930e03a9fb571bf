//! The integration tests of subdiv-stencil, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `common` and `sharp_cases` hold their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-stencil --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).
//! Proptest keeps failure seeds in `tests/proptest-regressions/<module>.txt`.

mod common;
mod sharp_cases;

mod dart_limits;
mod deng_ma_creases;
mod doo_sabin_creases;
mod fvar_peers;
mod fvar_properties;
mod limit_matrices_creases;
mod limit_matrices_creases_brute_force;
mod non_manifold;
mod normalized;
mod opensubdiv_shapes;
mod opensubdiv_uvs;
mod options;
mod peers;
mod peers_creases;
mod properties;
mod proptest_topology;
mod scheme_table;
mod sqrt3;
mod triangles_and_holes;
