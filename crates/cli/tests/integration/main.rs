//! The integration tests of subdiv-cli, one test binary (issue #39: one link
//! instead of one per file). Each module below was a test binary of its own,
//! `tests/<module>.rs`; `common` holds their shared helpers, compiled once.
//! One module: `cargo test -p subdiv-cli --test integration <module>::` (a
//! substring filter over `<module>::<test>` names).

mod common;

mod bad_inputs;
mod batch;
mod cheng_schemes;
mod creases;
mod creases_opensubdiv;
mod deng_ma_open;
mod evaluate;
mod facade_pipeline;
mod fair;
mod fit_options;
mod fuzz_corpus;
mod hostile_inputs;
mod info_fixtures;
mod info_methods;
mod interpolate;
mod interpolate_uvs;
mod numeric_rule;
mod opensubdiv_options;
mod outputs_and_sizes;
mod params;
mod sample_project_fit;
mod subdivide;
