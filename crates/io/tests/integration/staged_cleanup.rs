//! `remove_staged_files` (what the CLI's SIGINT/SIGTERM handler calls) deletes
//! every live temporary. It removes the temporaries of the whole process, so
//! the test runs its body alone: in a child process of this test binary that
//! runs this one test, never beside other tests that stage files.

use crate::common;
use std::fs;
use std::process::Command;
use subdiv_io::{remove_staged_files, stage_bytes};

/// Set in the child process that runs the body.
const CHILD: &str = "SUBDIV_IO_STAGED_CLEANUP_CHILD";

#[test]
fn remove_staged_files_deletes_every_live_temporary() {
    if std::env::var_os(CHILD).is_none() {
        // The test's name as the harness knows it: its module path without the crate's name.
        let name = "remove_staged_files_deletes_every_live_temporary";
        let name = match module_path!().split_once("::") {
            Some((_, module)) => format!("{module}::{name}"),
            None => name.to_string(),
        };
        let child = Command::new(std::env::current_exe().unwrap())
            .args([name.as_str(), "--exact", "--test-threads=1"])
            .env(CHILD, "1")
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&child.stdout);
        let stderr = String::from_utf8_lossy(&child.stderr);
        assert!(child.status.success(), "the child failed:\n{stdout}\n{stderr}");
        assert!(stdout.contains("test result: ok. 1 passed"), "the child ran no test {name}:\n{stdout}\n{stderr}");
        return;
    }
    let dir = common::scratch_dir("cleanup");
    let count = || fs::read_dir(&dir).unwrap().count();
    let first = stage_bytes(&dir.join("x.obj"), b"x").unwrap();
    let second = stage_bytes(&dir.join("y.json"), b"{}").unwrap();
    assert_eq!(count(), 2);
    remove_staged_files();
    assert_eq!(count(), 0);
    // Committing afterwards fails cleanly and creates nothing.
    assert!(first.commit().is_err());
    drop(second);
    assert_eq!(count(), 0);
}
