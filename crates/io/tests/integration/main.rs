//! The integration tests of subdiv-io, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `common` holds their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-io --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).
//! Proptest keeps failure seeds in `tests/proptest-regressions/<module>.txt`.

mod common;

mod bad_inputs;
mod mesh_files;
mod obj_chunks;
mod odd_inputs;
mod peer_creases;
mod ply_layouts;
mod proptests;
mod round_trip;
mod special_files;
mod staged_cleanup;
mod tag_files;
mod tobj_differential;
mod triangulate_fixtures;
mod usd;
mod uvs_and_tags;
