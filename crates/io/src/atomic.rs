//! Atomic file output: write a temporary file beside the target, then rename.
//!
//! A rename within one directory replaces the target in one step, so a
//! reader sees the old file or the whole new one, and a failure at any point
//! (full disk, killed process aside) leaves the old file untouched and no
//! partial output (SPEC §7).

use std::ffi::OsString;
use std::fs::{self, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Ctx, IoError};

/// Removes the temporary file unless it was renamed into place.
struct TempFile {
    path: PathBuf,
    keep: bool,
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.keep {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Writes `bytes` to `path` atomically.
pub(crate) fn write(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let ctx = Ctx::new(path);
    let name = path
        .file_name()
        .ok_or_else(|| ctx.io(io::Error::new(io::ErrorKind::InvalidInput, "output path has no file name")))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let (mut file, mut temp) = loop {
        let mut temp_name = OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".{}.{}.tmp", std::process::id(), COUNTER.fetch_add(1, Ordering::Relaxed)));
        let temp_path = dir.join(temp_name);
        match OpenOptions::new().write(true).create_new(true).open(&temp_path) {
            Ok(file) => break (file, TempFile { path: temp_path, keep: false }),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(ctx.io(e)),
        }
    };
    file.write_all(bytes).and_then(|()| file.sync_all()).map_err(|e| ctx.io(e))?;
    drop(file);
    fs::rename(&temp.path, path).map_err(|e| ctx.io(e))?;
    temp.keep = true;
    Ok(())
}
