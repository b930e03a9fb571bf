//! Helpers shared by the CLI integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository's `fixtures/` folder.
pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// `../shared/meshes` beside the repository, when present.
pub fn shared_meshes() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes");
    p.join("README.md").exists().then_some(p)
}

/// Runs the `subdiv` binary with `args`.
pub fn subdiv(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_subdiv")).args(args).output().expect("run subdiv")
}

/// Asserts the process neither panicked nor printed a backtrace.
pub fn assert_no_panic(out: &Output) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"), "panic: {stderr}");
}

/// A path in `suite`'s scratch folder (`subdiv-cli-{suite}-{pid}` in the
/// temporary directory, created on first use). The test modules share one
/// process (one test binary), so each uses suite names of its own.
pub fn out_path(suite: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("subdiv-cli-{suite}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Reads a mesh file as it is (panics naming the file).
pub fn read(path: &Path) -> subdiv_mesh::PolygonSoup {
    subdiv_io::read_mesh(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Runs `subdiv` with `args`, asserts exit 0 without a panic, returns stderr.
pub fn run_ok(args: &[&str]) -> String {
    let run = subdiv(args);
    assert_no_panic(&run);
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    assert_eq!(run.status.code(), Some(0), "{args:?}: {stderr}");
    stderr
}
