//! Small text files that are not meshes: the parameter files of the
//! interpolation methods (vertex subsets, normals, shape handles, shape
//! files), evaluation parameters (`subdiv evaluate --at`), query points
//! (`subdiv project --points`, `.xyz`). Their parsers take the text; this
//! module reads it with the checks every file read here gets:
//!
//! - only regular files ([`IoError::NotAFile`], refused before they are
//!   opened: opening a FIFO blocks until a writer comes, a device may never
//!   end);
//! - at most [`TEXT_FILE_LIMIT`] bytes ([`IoError::Unsupported`] above, before
//!   any memory is reserved);
//! - UTF-8 text: a byte-order mark is skipped, UTF-16 is [`IoError::Utf16`],
//!   a NUL byte or an invalid UTF-8 sequence is [`IoError::Parse`] naming its
//!   line and byte.

use std::path::Path;

use crate::error::{Ctx, IoError};
use crate::text::{sniff, strip_bom, NotText};

/// The largest text file [`read_text`] reads: 256 MiB (ten million normals
/// of `i nx ny nz`).
pub const TEXT_FILE_LIMIT: u64 = 256 << 20;

/// Reads a small UTF-8 text file (see the module documentation), without
/// its byte-order mark.
///
/// ```
/// let dir = std::env::temp_dir().join(format!("subdiv-io-read-text-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("subset.txt");
/// std::fs::write(&path, "\u{FEFF}0 1 2\n")?;
/// assert_eq!(subdiv_io::read_text(&path)?, "0 1 2\n");
/// std::fs::write(&path, b"0 1\n2 \xFF\n")?;
/// let error = subdiv_io::read_text(&path).unwrap_err();
/// assert_eq!(error.line(), Some(2));
/// assert!(error.to_string().ends_with("not UTF-8 text (byte 0xFF); save the file as UTF-8"));
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`IoError::NotAFile`] for a directory, FIFO, device or socket,
/// [`IoError::Io`] when the file cannot be read, [`IoError::Unsupported`]
/// for a file larger than [`TEXT_FILE_LIMIT`], [`IoError::Utf16`] for UTF-16
/// text, [`IoError::Parse`] for a NUL byte or bytes that are not UTF-8.
pub fn read_text(path: &Path) -> Result<String, IoError> {
    read_text_limited(path, TEXT_FILE_LIMIT)
}

/// [`read_text`] with the size limit as a parameter (tests use a small one).
fn read_text_limited(path: &Path, limit: u64) -> Result<String, IoError> {
    let ctx = Ctx::new(path);
    let too_large = |size: u64| ctx.unsupported(format!("text file of {size} bytes (at most {limit} are read)"));
    // The size first, so that a huge file is refused before memory is
    // reserved for it; `read_file` refuses what is not a regular file.
    let metadata = std::fs::metadata(path).map_err(|e| ctx.io(e))?;
    if metadata.is_file() && metadata.len() > limit {
        return Err(too_large(metadata.len()));
    }
    let bytes = crate::read_file(path, Some(limit + 1), &mut |_, _| {})?;
    if bytes.len() as u64 > limit {
        // The file grew after it was looked at.
        return Err(too_large(bytes.len() as u64));
    }
    decode(bytes, ctx)
}

/// The text of a file's bytes, without a UTF-8 byte-order mark.
fn decode(bytes: Vec<u8>, ctx: Ctx<'_>) -> Result<String, IoError> {
    if let Some(NotText::Utf16) = sniff(&bytes) {
        return Err(ctx.utf16());
    }
    let start = bytes.len() - strip_bom(&bytes).len();
    let line_of = |offset: usize| 1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count();
    if let Some(nul) = memchr::memchr(0, &bytes) {
        return Err(ctx.parse(line_of(nul), "NUL byte: binary data, not a text file (save it as UTF-8 text)"));
    }
    if let Err(e) = std::str::from_utf8(&bytes[start..]) {
        let offset = start + e.valid_up_to();
        let message = format!("not UTF-8 text (byte 0x{:02X}); save the file as UTF-8", bytes[offset]);
        return Err(ctx.parse(line_of(offset), message));
    }
    let mut bytes = bytes;
    bytes.drain(..start);
    // Checked just above.
    Ok(String::from_utf8(bytes).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use tempfile::TempDir;

    /// A fresh scratch folder, removed when it drops.
    fn dir() -> TempDir {
        tempfile::Builder::new().prefix("subdiv-io-text-file-").tempdir().unwrap()
    }

    fn read_bytes(name: &str, bytes: &[u8]) -> Result<String, IoError> {
        let dir = dir();
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        read_text(&path)
    }

    #[test]
    fn utf8_text_is_read_without_its_bom() {
        assert_eq!(read_bytes("plain.txt", "0 1\nλ 2\n".as_bytes()).unwrap(), "0 1\nλ 2\n");
        assert_eq!(read_bytes("bom.txt", "\u{FEFF}[0, 1]".as_bytes()).unwrap(), "[0, 1]");
        assert_eq!(read_bytes("empty.txt", b"").unwrap(), "");
    }

    #[test]
    fn other_encodings_are_refused_with_the_line() {
        let e = read_bytes("latin1.txt", b"0 1\n# caf\xE9\n").unwrap_err();
        assert!(matches!(e, IoError::Parse { line: Some(2), .. }), "{e}");
        assert!(e.to_string().ends_with(":2: not UTF-8 text (byte 0xE9); save the file as UTF-8"), "{e}");
        for bom in [&b"\xFF\xFE"[..], b"\xFE\xFF"] {
            let utf16 = [bom, b"0\x00 \x001\x00"].concat();
            assert!(matches!(read_bytes("utf16.txt", &utf16), Err(IoError::Utf16 { .. })));
        }
        // Interleaved NULs without a BOM: UTF-16 too.
        assert!(matches!(read_bytes("utf16-nobom.txt", b"0\x00 \x001\x00 \x002\x00"), Err(IoError::Utf16 { .. })));
        let e = read_bytes("nul.txt", b"0 1\n2 3\n\x00").unwrap_err();
        assert!(matches!(e, IoError::Parse { line: Some(3), .. }), "{e}");
    }

    #[test]
    fn a_file_over_the_limit_is_refused_before_it_is_read() {
        let dir = dir();
        let path = dir.path().join("big.txt");
        std::fs::write(&path, "0 1 2 3 4 5 6 7 8 9\n").unwrap();
        let e = read_text_limited(&path, 10).unwrap_err();
        assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
        assert!(e.to_string().contains("20 bytes (at most 10 are read)"), "{e}");
        assert_eq!(read_text_limited(&path, 20).unwrap().len(), 20);
    }

    #[test]
    fn directories_and_missing_files_are_refused() {
        let dir = dir();
        assert!(matches!(read_text(dir.path()), Err(IoError::NotAFile { kind: "a directory", .. })));
        assert!(matches!(read_text(&dir.path().join("missing.txt")), Err(IoError::Io { .. })));
    }

    #[cfg(unix)]
    #[test]
    fn special_files_are_refused_without_opening_them() {
        let dir = dir();
        let fifo = dir.path().join("text.fifo");
        let _ = std::fs::remove_file(&fifo);
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        // Opening the FIFO would block this test forever.
        assert!(matches!(read_text(&fifo), Err(IoError::NotAFile { kind: "a FIFO", .. })));
        std::fs::remove_file(&fifo).unwrap();
        assert!(matches!(read_text(Path::new("/dev/zero")), Err(IoError::NotAFile { .. })));
    }
}
