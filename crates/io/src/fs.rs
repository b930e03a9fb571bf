//! The file-system operations of the tools other than reading and writing
//! meshes and text: the checks of a command's destinations before anything
//! is written, the identity of files (to refuse overwriting an input), the
//! listing and the directories of a batch. Every `std::fs` call of the
//! library crates is here or elsewhere in this crate (the tidy test's rule 1),
//! so each read passes one special-file check: text, records and `/proc`
//! files go through [`crate::read_text`] (regular files only, size capped,
//! UTF-8 checked), and nothing here opens a file that could block (a FIFO)
//! except [`probe_writable`], which creates its own new file.

use std::io;
use std::path::{Path, PathBuf};
use std::time::UNIX_EPOCH;

/// A file's identity: (device, inode). Two paths with the same identity
/// name the same file (a hard link, a symbolic link, another spelling).
pub type FileIdentity = (u64, u64);

/// The identity of the file at `path` (following symbolic links); `None`
/// when it does not exist or cannot be looked at.
#[cfg(unix)]
pub fn file_identity(path: &Path) -> Option<FileIdentity> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

/// The canonical path of an existing file or directory (symbolic links and
/// `..` resolved); `None` when it does not exist or cannot be resolved.
pub fn canonical(path: &Path) -> Option<PathBuf> {
    std::fs::canonicalize(path).ok()
}

/// `path` with its directory resolved (symbolic links, `..`), whether or not
/// the file itself exists: the canonical path of an existing file, else the
/// canonical directory joined with the file name; `None` when the directory
/// does not exist (or `path` has no file name).
pub fn resolve(path: &Path) -> Option<PathBuf> {
    if let Some(p) = canonical(path) {
        return Some(p);
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    Some(canonical(dir)?.join(path.file_name()?))
}

/// Whether `dir` is a directory: `Ok(true)`, `Ok(false)` when it exists and
/// is something else (following symbolic links).
///
/// # Errors
/// The error of looking at it (it does not exist, permission denied).
pub fn is_directory(dir: &Path) -> io::Result<bool> {
    std::fs::metadata(dir).map(|m| m.is_dir())
}

/// What a destination path names now, before a file is written there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Destination {
    /// Nothing (or nothing that can be looked at): a new file.
    Absent,
    /// A regular file, or a symbolic link to one (or a dangling one): replaced.
    File,
    /// A directory (not through a symbolic link).
    Directory,
    /// A FIFO, device or socket.
    Special,
    /// A symbolic link to something that is not a regular file.
    LinkToNonFile,
}

/// What `path` names ([`Destination`]), without opening it.
pub fn destination(path: &Path) -> Destination {
    match std::fs::symlink_metadata(path) {
        Err(_) => Destination::Absent,
        Ok(m) if m.is_dir() => Destination::Directory,
        Ok(m) if m.file_type().is_symlink() => match std::fs::metadata(path) {
            Ok(target) if !target.is_file() => Destination::LinkToNonFile,
            _ => Destination::File,
        },
        Ok(m) if m.is_file() => Destination::File,
        Ok(_) => Destination::Special,
    }
}

/// Creates and removes a new file in `dir`: the one reliable test that the
/// directory accepts new files (permissions, read-only mounts, ACLs). Each
/// call uses a new name (the jobs of a batch probe the same directory at
/// once), created with `create_new`, so no existing file is opened.
///
/// # Errors
/// The error of creating or removing the probe.
pub fn probe_writable(dir: &Path) -> io::Result<()> {
    static PROBES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = PROBES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let probe = dir.join(format!(".subdiv-probe.{}.{n}", std::process::id()));
    std::fs::OpenOptions::new().write(true).create_new(true).open(&probe)?;
    std::fs::remove_file(&probe)
}

/// Creates `dir` and its missing parents (nothing when it exists).
///
/// # Errors
/// The error of creating a directory (or `dir` exists and is a file).
pub fn ensure_dir(dir: &Path) -> io::Result<()> {
    std::fs::create_dir_all(dir)
}

/// The paths of the entries of directory `dir`, in the order the system
/// lists them (entries that cannot be read are left out). Nothing is opened.
///
/// # Errors
/// The error of opening the directory for listing.
pub fn list_dir(dir: &Path) -> io::Result<Vec<PathBuf>> {
    Ok(std::fs::read_dir(dir)?.filter_map(|e| e.ok().map(|e| e.path())).collect())
}

/// Size and modification time of a file, to tell whether it changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileStamp {
    /// Its size in bytes.
    pub size: u64,
    /// Its modification time, nanoseconds since the Unix epoch (saturated).
    pub modified_ns: u64,
}

/// The [`FileStamp`] of the file at `path` (following symbolic links);
/// `None` when its metadata or modification time cannot be read.
pub fn file_stamp(path: &Path) -> Option<FileStamp> {
    let metadata = std::fs::metadata(path).ok()?;
    let modified = metadata.modified().ok()?.duration_since(UNIX_EPOCH).ok()?;
    Some(FileStamp { size: metadata.len(), modified_ns: u64::try_from(modified.as_nanos()).unwrap_or(u64::MAX) })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh scratch folder (`subdiv-io-fs-{name}-XXXXXX`), removed when it drops.
    fn dir(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new().prefix(&format!("subdiv-io-fs-{name}-")).tempdir().unwrap()
    }

    #[cfg(unix)]
    #[test]
    fn identities_and_canonical_paths_see_through_links() {
        let tmp = dir("links");
        let d = tmp.path();
        let file = d.join("a.obj");
        std::fs::write(&file, "v 0 0 0\n").unwrap();
        std::os::unix::fs::symlink(&file, d.join("link.obj")).unwrap();
        std::fs::hard_link(&file, d.join("hard.obj")).unwrap();
        let id = file_identity(&file).unwrap();
        assert_eq!(file_identity(&d.join("link.obj")), Some(id));
        assert_eq!(file_identity(&d.join("hard.obj")), Some(id));
        assert_eq!(file_identity(&d.join("missing.obj")), None);
        let c = canonical(&file).unwrap();
        assert_eq!(canonical(&d.join("link.obj")), Some(c.clone()));
        assert_eq!(canonical(&d.join("sub/../a.obj")), None, "sub does not exist");
        assert_eq!(resolve(&d.join("link.obj")), Some(c.clone()));
        assert_eq!(resolve(&d.join("new.obj")), Some(c.parent().unwrap().join("new.obj")));
        assert_eq!(resolve(&d.join("nowhere/new.obj")), None);
    }

    #[cfg(unix)]
    #[test]
    fn destinations_are_classified_without_opening_them() {
        let tmp = dir("dest");
        let d = tmp.path();
        let file = d.join("f.obj");
        std::fs::write(&file, "").unwrap();
        let fifo = d.join("p.fifo");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        std::os::unix::fs::symlink(&file, d.join("to-file")).unwrap();
        std::os::unix::fs::symlink(d, d.join("to-dir")).unwrap();
        std::os::unix::fs::symlink(d.join("missing"), d.join("dangling")).unwrap();
        assert_eq!(destination(&d.join("new.obj")), Destination::Absent);
        assert_eq!(destination(&file), Destination::File);
        assert_eq!(destination(d), Destination::Directory);
        assert_eq!(destination(&fifo), Destination::Special);
        assert_eq!(destination(&d.join("to-file")), Destination::File);
        assert_eq!(destination(&d.join("to-dir")), Destination::LinkToNonFile);
        assert_eq!(destination(&d.join("dangling")), Destination::File);
        assert!(is_directory(d).unwrap() && !is_directory(&file).unwrap() && is_directory(&d.join("x")).is_err());
    }

    #[test]
    fn directories_are_made_listed_and_probed() {
        let tmp = dir("dirs");
        let d = tmp.path();
        let deep = d.join("a/b/c");
        ensure_dir(&deep).unwrap();
        ensure_dir(&deep).unwrap(); // exists: nothing to do
        std::fs::write(d.join("a/x.obj"), "").unwrap();
        assert!(ensure_dir(&d.join("a/x.obj")).is_err(), "a file is in the way");
        let mut listed = list_dir(&d.join("a")).unwrap();
        listed.sort();
        assert_eq!(listed, [d.join("a/b"), d.join("a/x.obj")]);
        assert!(list_dir(&d.join("none")).is_err());
        probe_writable(&deep).unwrap();
        assert_eq!(list_dir(&deep).unwrap(), Vec::<PathBuf>::new(), "the probe is removed");
        assert!(probe_writable(&d.join("none")).is_err());
    }

    #[test]
    fn stamps_change_with_the_content() {
        let tmp = dir("stamp");
        let d = tmp.path();
        let file = d.join("s.txt");
        std::fs::write(&file, "12345").unwrap();
        let stamp = file_stamp(&file).unwrap();
        assert_eq!(stamp.size, 5);
        assert!(stamp.modified_ns > 0);
        std::fs::write(&file, "123456").unwrap();
        assert_eq!(file_stamp(&file).unwrap().size, 6);
        assert_eq!(file_stamp(&d.join("none")), None);
    }

    /// `/proc` files report size 0 and are read to their end all the same.
    #[cfg(target_os = "linux")]
    #[test]
    fn proc_files_are_read_by_read_text() {
        assert_eq!(std::fs::metadata("/proc/meminfo").unwrap().len(), 0);
        let meminfo = crate::read_text(Path::new("/proc/meminfo")).unwrap();
        assert!(meminfo.lines().any(|l| l.starts_with("MemTotal:")), "{meminfo}");
        let status = crate::read_text(Path::new("/proc/self/status")).unwrap();
        assert!(status.lines().any(|l| l.starts_with("VmSize:") || l.starts_with("Name:")), "{status}");
    }
}
