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

/// A scratch folder for one test (`subdiv-cli-{suite}-XXXXXX` in the temporary
/// directory), removed when the guard drops — kept, and its path printed, when
/// the test is failing (panicking), so that a failure can be inspected. Each
/// test creates its own (`let scratch = Scratch::new("suite");`) and keeps it
/// alive to its end: the tests share one process under `cargo test` and run
/// one per process under `cargo nextest`, and either way leave nothing behind.
pub struct Scratch(Option<tempfile::TempDir>);

impl Scratch {
    /// A fresh, empty folder named after `suite`.
    pub fn new(suite: &str) -> Self {
        let dir = tempfile::Builder::new()
            .prefix(&format!("subdiv-cli-{suite}-"))
            .tempdir()
            .unwrap_or_else(|e| panic!("scratch folder for {suite}: {e}"));
        Scratch(Some(dir))
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        self.0.as_ref().expect("the scratch folder lives until the guard drops").path()
    }

    /// `name` in the folder (not created).
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir().join(name)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            if let Some(dir) = self.0.take() {
                eprintln!("scratch kept: {}", dir.keep().display());
            }
        }
    }
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
