//! Helpers shared by the CLI integration tests.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

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

/// The numbers of each line of a text output (`evaluate`'s rows).
pub fn numbers(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
        .collect()
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

/// Runs `subdiv` with `args`, killing it and failing (naming `what`) if it
/// has not exited within `limit` (a blocked read), or if it panicked;
/// returns the exit code and stderr.
pub fn run_bounded(args: &[impl AsRef<OsStr>], what: &str, limit: Duration) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_subdiv"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            child.kill().unwrap();
            panic!("{what}: subdiv blocked");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    (status.code(), stderr)
}
