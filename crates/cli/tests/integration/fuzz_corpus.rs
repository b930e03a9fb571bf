//! Replays the fuzz corpus without a fuzzer (issue #14): every file of
//! `fuzz/corpus/<target>/` and `fuzz/regressions/<target>/` through the
//! target's body in `fuzz/src/lib.rs`, included here so that the fuzzer and
//! this test run one copy of the checks. A body panics when the contract
//! breaks; every failing file is reported, not just the first.

#[path = "../../../../fuzz/src/lib.rs"]
mod fuzz_bodies;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// Regression inputs that still break the contract on this branch because
/// the fix is in flight (issue #14's numeric rule, another branch). Each one
/// must keep failing until then — when it passes, this test fails and asks
/// for its removal, so the list only shrinks. Paths relative to
/// `fuzz/regressions/`.
const PENDING_FIX: &[&str] = &[];

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

/// The files of `fuzz/<kind>/<target>/`, sorted (none if the directory is missing).
fn inputs(kind: &str, target: &str) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(fuzz_dir().join(kind).join(target)) else { return Vec::new() };
    let mut files: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).filter(|p| p.is_file()).collect();
    files.sort();
    files
}

/// Runs `body` on `input`; the panic message if it panics.
fn run(body: fn(&[u8]), input: &Path) -> Result<(), String> {
    let data = std::fs::read(input).unwrap_or_else(|e| panic!("{}: {e}", input.display()));
    catch_unwind(AssertUnwindSafe(|| body(&data))).map_err(|payload| {
        payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "non-string panic".into())
    })
}

/// Replays the corpus and the regressions of `target`; panics listing every
/// input that breaks the contract (or passes although listed in [`PENDING_FIX`]).
fn replay(target: &str, body: fn(&[u8])) {
    let corpus = inputs("corpus", target);
    assert!(!corpus.is_empty(), "fuzz/corpus/{target}/ has no seeds");
    let mut problems = Vec::new();
    for input in &corpus {
        if let Err(message) = run(body, input) {
            problems.push(format!("{}: {message}", input.display()));
        }
    }
    for input in inputs("regressions", target) {
        let key = format!("{target}/{}", input.file_name().unwrap().to_string_lossy());
        match (run(body, &input), PENDING_FIX.contains(&key.as_str())) {
            (Ok(()), true) => problems.push(format!("{key} passes now: remove it from PENDING_FIX")),
            (Err(message), false) => problems.push(format!("{}: {message}", input.display())),
            _ => {}
        }
    }
    assert!(
        problems.is_empty(),
        "{} input(s) of {target} break the contract:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn pending_fixes_name_existing_regressions() {
    for key in PENDING_FIX {
        assert!(fuzz_dir().join("regressions").join(key).is_file(), "PENDING_FIX names a missing file {key}");
    }
}

#[test]
fn obj_corpus_replays() {
    replay("obj", fuzz_bodies::obj);
}

#[test]
fn off_corpus_replays() {
    replay("off", fuzz_bodies::off);
}

#[test]
fn ply_corpus_replays() {
    replay("ply", fuzz_bodies::ply);
}

#[test]
fn stl_corpus_replays() {
    replay("stl", fuzz_bodies::stl);
}

#[test]
fn gltf_corpus_replays() {
    replay("gltf", fuzz_bodies::gltf);
}

#[test]
fn usd_corpus_replays() {
    replay("usd", fuzz_bodies::usd);
}

#[test]
fn from_soup_corpus_replays() {
    replay("from_soup", fuzz_bodies::from_soup);
}

#[test]
fn end_to_end_corpus_replays() {
    replay("end_to_end", fuzz_bodies::end_to_end);
}

#[test]
fn evaluate_corpus_replays() {
    replay("evaluate", fuzz_bodies::evaluate);
}

#[test]
fn sample_corpus_replays() {
    replay("sample", fuzz_bodies::sample);
}

#[test]
fn project_corpus_replays() {
    replay("project", fuzz_bodies::project);
}

#[test]
fn fit_corpus_replays() {
    replay("fit", fuzz_bodies::fit);
}

/// The bodies accept any bytes, empty and short ones included (every decoder
/// reads zeros past the end).
#[test]
fn bodies_take_empty_and_short_inputs() {
    let bodies: [fn(&[u8]); 12] = [
        fuzz_bodies::obj,
        fuzz_bodies::off,
        fuzz_bodies::ply,
        fuzz_bodies::stl,
        fuzz_bodies::gltf,
        fuzz_bodies::usd,
        fuzz_bodies::from_soup,
        fuzz_bodies::end_to_end,
        fuzz_bodies::evaluate,
        fuzz_bodies::sample,
        fuzz_bodies::project,
        fuzz_bodies::fit,
    ];
    for body in bodies {
        for input in [&b""[..], b"\0", b"\xff\xff\xff"] {
            body(input);
        }
    }
}
