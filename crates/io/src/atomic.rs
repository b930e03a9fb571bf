//! Atomic, all-or-nothing file output.
//!
//! Every output is first *staged*: streamed to a temporary file beside its
//! target (`.NAME.PID.N.tmp`, same directory, so the final rename is one
//! step), flushed and synced. A [`StagedFile`] is then *committed* by renaming
//! it over the target; dropped uncommitted, its temporary is removed. So a
//! failure at any point (full disk, permission, an encoder error) leaves the
//! targets as they were and no partial output ([error behaviour]).
//!
//! [`commit_all`] commits several staged files together: if one rename
//! fails, the targets already replaced get their old contents back (kept
//! through a hard link while committing), so a command's outputs appear
//! all together or not at all.
//!
//! Every live temporary is listed in a process-wide registry, so a signal
//! handler can delete them with [`remove_staged_files`] before the process
//! exits (a SIGKILL cannot be handled: it may leave a `.tmp` file, never a
//! partial target). [`stop_commits`] is what a handler calls first: it
//! waits for a [`commit_all`] under way to finish (or roll back), so that
//! no target is left half-replaced, keeps every later one from starting,
//! and says how many completed — the handler's exit code can then say what
//! is on disk.
//!
//! A target is only ever a regular file: staging refuses a path that names a
//! directory, a FIFO, a device or a socket, or a symbolic link to one
//! ([`IoError::NotAFile`]), and so does the commit (a rename would replace
//! the special file) — the one destination check of every writer here
//! ([`crate::fs::destination`]).
//!
//! [error behaviour]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-error-behaviour-and-exit-codes

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

use crate::error::{Ctx, IoError};

/// Temporaries (staged files and commit backups) that exist right now.
static LIVE_TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    // A panic while holding the lock cannot leave the list inconsistent.
    LIVE_TEMPORARIES.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Held by [`commit_all`] while it renames, and forever by [`stop_commits`].
static COMMITS: Mutex<()> = Mutex::new(());

/// [`commit_all`] calls that completed (every file in place).
static COMMITTED: AtomicU64 = AtomicU64::new(0);

fn forget(path: &Path) {
    live().retain(|p| p != path);
}

/// Deletes every temporary file this process has staged and not yet
/// committed or dropped. For signal handlers (SIGINT, SIGTERM) that exit
/// right after: files staged later are still cleaned up by their drop.
pub fn remove_staged_files() {
    for path in live().drain(..) {
        let _ = fs::remove_file(path);
    }
}

/// For a signal handler about to exit: waits until a [`commit_all`] under
/// way has finished (all its files in place, or all rolled back), keeps
/// every later commit from starting (it blocks until the process exits),
/// removes the temporaries ([`remove_staged_files`]) and returns how many
/// [`commit_all`] calls completed. A command that commits its outputs once,
/// at its end, has them all in place when this returns 1, and none when it
/// returns 0.
pub fn stop_commits() -> u64 {
    let held = COMMITS.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    // Never released: the process is about to exit.
    std::mem::forget(held);
    remove_staged_files();
    COMMITTED.load(Ordering::SeqCst)
}

/// The number of [`commit_all`] calls that completed so far.
pub fn commits_completed() -> u64 {
    COMMITTED.load(Ordering::SeqCst)
}

/// Refuses a target that is not a regular file or absent (see the module
/// documentation): renaming over a FIFO or a device would replace it.
fn check_target(path: &Path) -> Result<(), IoError> {
    use crate::fs::{destination, Destination};
    let kind = match destination(path) {
        Destination::Absent | Destination::File => return Ok(()),
        Destination::Directory => "a directory",
        Destination::Special => match fs::symlink_metadata(path) {
            Ok(m) => crate::file_kind(m.file_type()),
            Err(_) => "a special file",
        },
        Destination::LinkToNonFile => "a link to something that is not a regular file",
    };
    Err(IoError::NotAFile { path: path.to_path_buf(), kind })
}

/// A complete output in a temporary file beside its target, not yet in place.
///
/// [`StagedFile::commit`] (or [`commit_all`]) renames it over the target;
/// dropping it removes the temporary and leaves the target untouched.
#[derive(Debug)]
#[must_use = "a staged file is removed when dropped; commit it"]
pub struct StagedFile {
    temp: PathBuf,
    target: PathBuf,
    bytes: u64,
}

impl StagedFile {
    /// The file this will become.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Bytes written.
    pub fn len(&self) -> u64 {
        self.bytes
    }

    /// True when nothing was written.
    pub fn is_empty(&self) -> bool {
        self.bytes == 0
    }

    /// Renames the staged file over its target.
    ///
    /// # Errors
    /// [`IoError::Io`] naming the target; the target is then as it was.
    pub fn commit(self) -> Result<(), IoError> {
        commit_all(vec![self])
    }
}

impl Drop for StagedFile {
    fn drop(&mut self) {
        // Empty after a commit (the temporary became the target).
        if !self.temp.as_os_str().is_empty() {
            let _ = fs::remove_file(&self.temp);
            forget(&self.temp);
        }
    }
}

/// Renames every staged file over its target, in order. If a rename fails,
/// the targets replaced before it are restored (their old contents were kept
/// through a hard link; where the file system has no hard links, a replaced
/// target that existed before cannot be restored and keeps its new, complete
/// contents) and the remaining staged files are removed.
///
/// Commits are serialised across threads, and a signal handler's
/// [`stop_commits`] waits for the one under way: the targets are never left
/// with some files replaced and others not.
///
/// # Errors
/// [`IoError::Io`] naming the target that could not be replaced;
/// [`IoError::NotAFile`] when a target has become a directory, FIFO, device
/// or socket since it was staged (nothing is replaced then).
pub fn commit_all(files: Vec<StagedFile>) -> Result<(), IoError> {
    let _commit = COMMITS.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    // Checked before the first rename, so a refusal replaces nothing.
    for file in &files {
        check_target(&file.target)?;
    }
    // (target, backup of its old contents if it had any) for each renamed file.
    let mut replaced: Vec<(PathBuf, Option<PathBuf>)> = Vec::new();
    let mut files = files.into_iter();
    let failure = loop {
        let Some(mut file) = files.next() else { break None };
        let backup = file.target.is_file().then(|| file.temp.with_extension("old")).and_then(|backup| {
            live().push(backup.clone());
            match fs::hard_link(&file.target, &backup) {
                Ok(()) => Some(backup),
                Err(_) => {
                    forget(&backup);
                    None
                }
            }
        });
        match fs::rename(&file.temp, &file.target) {
            Ok(()) => {
                forget(&file.temp);
                file.temp = PathBuf::new();
                replaced.push((std::mem::take(&mut file.target), backup));
            }
            Err(e) => {
                if let Some(b) = backup {
                    let _ = fs::remove_file(&b);
                    forget(&b);
                }
                break Some(Ctx::new(&file.target).io(e));
            }
        }
    };
    for (target, backup) in replaced {
        match (&failure, backup) {
            (None, Some(b)) => {
                let _ = fs::remove_file(&b);
                forget(&b);
            }
            (Some(_), Some(b)) => {
                let _ = fs::rename(&b, &target);
                forget(&b);
            }
            (Some(_), None) => {
                let _ = fs::remove_file(&target);
            }
            (None, None) => {}
        }
    }
    // The remaining staged files are dropped (removed) with the iterator.
    if failure.is_none() {
        COMMITTED.fetch_add(1, Ordering::SeqCst);
    }
    failure.map_or(Ok(()), Err)
}

/// Output buffer between an encoder and the temporary file.
const BUFFER_BYTES: usize = 1 << 20;

/// How often (in bytes) the progress callback hears from a write.
const PROGRESS_EVERY: u64 = 4 << 20;

/// A writer that counts bytes and reports them every [`PROGRESS_EVERY`].
pub(crate) struct Counting<'p, W> {
    inner: W,
    written: u64,
    reported: u64,
    progress: &'p mut dyn FnMut(u64),
}

impl<W: Write> Write for Counting<'_, W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.written += n as u64;
        if self.written - self.reported >= PROGRESS_EVERY {
            self.reported = self.written;
            (self.progress)(self.written);
        }
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// Streams what `encode` produces to a new temporary file beside `path`,
/// through a buffer (never the whole file in memory), calling `progress`
/// with the bytes written so far. On any error the temporary is removed.
pub(crate) fn stage_with(
    path: &Path,
    progress: &mut dyn FnMut(u64),
    encode: impl FnOnce(&mut Counting<'_, BufWriter<&mut File>>) -> Result<(), IoError>,
) -> Result<StagedFile, IoError> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let ctx = Ctx::new(path);
    check_target(path)?;
    let name = path
        .file_name()
        .ok_or_else(|| ctx.io(io::Error::new(io::ErrorKind::InvalidInput, "output path has no file name")))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let (mut file, mut staged) = loop {
        let mut temp_name = OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".{}.{}.tmp", std::process::id(), COUNTER.fetch_add(1, Ordering::Relaxed)));
        let temp = dir.join(temp_name);
        // Registered before it exists, so a signal handler never misses it.
        let mut registry = live();
        registry.push(temp.clone());
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => break (file, StagedFile { temp, target: path.to_path_buf(), bytes: 0 }),
            Err(e) => {
                registry.pop();
                if e.kind() != io::ErrorKind::AlreadyExists {
                    return Err(ctx.io(e));
                }
            }
        }
    };
    let mut out =
        Counting { inner: BufWriter::with_capacity(BUFFER_BYTES, &mut file), written: 0, reported: 0, progress };
    encode(&mut out)?;
    staged.bytes = out.written;
    (out.progress)(out.written);
    let file = out.inner.into_inner().map_err(|e| ctx.io(e.into_error()))?;
    file.sync_all().map_err(|e| ctx.io(e))?;
    Ok(staged)
}

/// Stages `bytes` as the new contents of `path` (for reports and other
/// non-mesh outputs that must be committed with the meshes).
///
/// # Errors
/// [`IoError::Io`] naming `path`; [`IoError::NotAFile`] when `path` names a
/// directory, FIFO, device or socket.
pub fn stage_bytes(path: &Path, bytes: &[u8]) -> Result<StagedFile, IoError> {
    stage_with(path, &mut |_| {}, |out| out.write_all(bytes).map_err(|e| Ctx::new(path).io(e)))
}

/// Writes what `encode` produces to `path` atomically.
#[cfg(test)]
fn write_with(
    path: &Path,
    encode: impl FnOnce(&mut Counting<'_, BufWriter<&mut File>>) -> Result<(), IoError>,
) -> Result<(), IoError> {
    stage_with(path, &mut |_| {}, encode)?.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh scratch folder (`subdiv-io-atomic-{name}-XXXXXX`), removed when it drops.
    fn scratch(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new().prefix(&format!("subdiv-io-atomic-{name}-")).tempdir().unwrap()
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<_> =
            fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        names
    }

    #[test]
    fn an_encoder_failing_after_streaming_leaves_the_old_file_and_no_temporary() {
        let tmp = scratch("fail");
        let dir = tmp.path();
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
        assert_eq!(listing(dir), ["out.obj"]);
        // A complete stream replaces the file whole.
        write_with(&target, |out| out.write_all(b"new").map_err(|e| Ctx::new(&target).io(e))).unwrap();
        assert_eq!(fs::read_to_string(&target).unwrap(), "new");
    }

    #[test]
    fn staged_files_appear_only_on_commit_and_vanish_when_dropped() {
        let tmp = scratch("stage");
        let dir = tmp.path();
        let (a, b) = (dir.join("a.obj"), dir.join("b.json"));
        let sa = stage_bytes(&a, b"A").unwrap();
        let sb = stage_bytes(&b, b"B").unwrap();
        assert!(!a.exists() && !b.exists());
        assert_eq!(listing(dir).len(), 2, "two temporaries");
        commit_all(vec![sa, sb]).unwrap();
        assert_eq!(listing(dir), ["a.obj", "b.json"]);
        drop(stage_bytes(&a, b"never").unwrap());
        assert_eq!(fs::read_to_string(&a).unwrap(), "A");
        assert_eq!(listing(dir), ["a.obj", "b.json"]);
    }

    #[test]
    fn a_failed_rename_restores_the_outputs_already_replaced() {
        let tmp = scratch("rollback");
        let dir = tmp.path();
        let (a, new, blocked) = (dir.join("a.obj"), dir.join("new.off"), dir.join("c.ply"));
        fs::write(&a, "old a").unwrap();
        let sa = stage_bytes(&a, b"new a").unwrap();
        let sn = stage_bytes(&new, b"new file").unwrap();
        let sc = stage_bytes(&blocked, b"c").unwrap();
        // A directory (with an entry) in the way makes the third rename fail.
        fs::create_dir(&blocked).unwrap();
        fs::write(blocked.join("keep"), "").unwrap();
        let e = commit_all(vec![sa, sn, sc]).unwrap_err();
        assert!(e.to_string().contains("c.ply"), "{e}");
        assert_eq!(fs::read_to_string(&a).unwrap(), "old a");
        assert!(!new.exists(), "a file that did not exist before is removed again");
        assert_eq!(listing(dir), ["a.obj", "c.ply"]);
    }

    #[test]
    fn progress_hears_the_bytes_written() {
        let tmp = scratch("progress");
        let dir = tmp.path();
        let mut seen = Vec::new();
        let staged = stage_with(&dir.join("p.obj"), &mut |n| seen.push(n), |out| {
            // Encoders write small pieces.
            (0..144).try_for_each(|_| out.write_all(&[b'p'; 64 << 10])).map_err(|e| Ctx::new(Path::new("p")).io(e))
        })
        .unwrap();
        assert_eq!(staged.len(), 9 << 20);
        assert_eq!(seen.last(), Some(&(9 << 20)));
        assert!(seen.len() >= 3 && seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
        drop(staged);
    }

    /// One destination check: a FIFO (or a directory) as the target is refused when staged, and
    /// when it appears between staging and committing nothing is replaced.
    #[cfg(unix)]
    #[test]
    fn special_targets_are_refused_when_staged_and_committed() {
        let tmp = scratch("special");
        let dir = tmp.path();
        let fifo = dir.join("out.obj");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let e = stage_bytes(&fifo, b"x").unwrap_err();
        assert!(matches!(e, IoError::NotAFile { kind: "a FIFO", .. }), "{e}");
        assert!(matches!(stage_bytes(dir, b"x"), Err(IoError::NotAFile { kind: "a directory", .. })));
        fs::remove_file(&fifo).unwrap();
        let (a, b) = (dir.join("a.txt"), dir.join("b.txt"));
        let staged = vec![stage_bytes(&a, b"A").unwrap(), stage_bytes(&b, b"B").unwrap()];
        assert!(std::process::Command::new("mkfifo").arg(&b).status().unwrap().success());
        assert!(matches!(commit_all(staged), Err(IoError::NotAFile { .. })));
        assert!(!a.exists(), "nothing is replaced when one target is refused");
        assert_eq!(listing(dir), ["b.txt"], "temporaries removed");
    }

    #[test]
    fn completed_commits_are_counted() {
        let tmp = scratch("count");
        let dir = tmp.path();
        let before = commits_completed();
        stage_bytes(&dir.join("c.txt"), b"c").unwrap().commit().unwrap();
        assert!(commits_completed() > before);
    }
}
