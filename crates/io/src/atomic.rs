//! Atomic file output: write a temporary file beside the target, then rename.
//!
//! A rename within one directory replaces the target in one step, so a
//! reader sees the old file or the whole new one, and a failure at any point
//! (full disk, killed process aside) leaves the old file untouched and no
//! partial output (SPEC §7).

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter};
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

/// Output buffer between an encoder and the temporary file.
const BUFFER_BYTES: usize = 1 << 20;

/// Writes what `encode` produces to `path` atomically, streamed through a
/// buffer (never the whole file in memory). An error from `encode` or from
/// the file system removes the temporary file and leaves `path` as it was.
pub(crate) fn write_with(
    path: &Path,
    encode: impl FnOnce(&mut BufWriter<&mut File>) -> Result<(), IoError>,
) -> Result<(), IoError> {
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
    let mut out = BufWriter::with_capacity(BUFFER_BYTES, &mut file);
    encode(&mut out)?;
    out.into_inner().map_err(|e| ctx.io(e.into_error()))?;
    file.sync_all().map_err(|e| ctx.io(e))?;
    drop(file);
    fs::rename(&temp.path, path).map_err(|e| ctx.io(e))?;
    temp.keep = true;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn an_encoder_failing_after_streaming_leaves_the_old_file_and_no_temporary() {
        let dir = std::env::temp_dir().join(format!("subdiv-io-atomic-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let target = dir.join("out.obj");
        fs::write(&target, "old contents").unwrap();
        // More than the buffer, so part of it reaches the temporary file first.
        let e = write_with(&target, |out| {
            out.write_all(&vec![b'x'; 3 * BUFFER_BYTES]).map_err(|e| Ctx::new(&target).io(e))?;
            Err(Ctx::new(&target).invalid("failed half-way"))
        })
        .unwrap_err();
        assert!(e.to_string().contains("failed half-way"), "{e}");
        assert_eq!(fs::read_to_string(&target).unwrap(), "old contents");
        let left: Vec<_> = fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left, ["out.obj"]);
        // A complete stream replaces the file whole.
        write_with(&target, |out| out.write_all(b"new").map_err(|e| Ctx::new(&target).io(e))).unwrap();
        assert_eq!(fs::read_to_string(&target).unwrap(), "new");
        fs::remove_dir_all(&dir).unwrap();
    }
}
