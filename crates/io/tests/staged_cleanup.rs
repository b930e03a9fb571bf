//! `remove_staged_files` (what the CLI's SIGINT/SIGTERM handler calls) deletes
//! every live temporary. Alone in its test binary: it removes the temporaries
//! of the whole process.

use std::fs;
use subdiv_io::{remove_staged_files, stage_bytes};

#[test]
fn remove_staged_files_deletes_every_live_temporary() {
    let dir = std::env::temp_dir().join(format!("subdiv-io-cleanup-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
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
    fs::remove_dir_all(&dir).unwrap();
}
