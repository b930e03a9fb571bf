//! Files that are not plain mesh files: directories, FIFOs and devices given
//! as the mesh, glTF buffer URIs that point outside the glTF file's directory,
//! and progress reports while reading (issue #14, classes 3 and 4).

use crate::common::{make_fifo, scratch_dir, within, ScratchDir};
use std::path::{Path, PathBuf};
use subdiv_io::{read_mesh, read_mesh_from_bytes, read_mesh_with_progress, Format, IoError};
use subdiv_mesh::DVec3;

const SQUARE: [DVec3; 4] = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];

/// The square's positions (48 bytes) and a triangle strip 0 1 3 2 as u16 (8 bytes).
fn square_buffer() -> Vec<u8> {
    let mut bin: Vec<u8> = SQUARE.iter().flat_map(|p| p.to_array()).flat_map(|x| (x as f32).to_le_bytes()).collect();
    [0u16, 1, 3, 2].iter().for_each(|i| bin.extend(i.to_le_bytes()));
    bin
}

/// A glTF document whose one buffer of `byte_length` bytes is at `uri`.
fn gltf_with_buffer(uri: &str, byte_length: usize) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": {byte_length}, "uri": "{uri}"}}],
        "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                        {{"buffer": 0, "byteOffset": 48, "byteLength": 8}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                        "min": [0, 0, 0], "max": [1, 1, 0]}},
                      {{"bufferView": 1, "componentType": 5123, "count": 4, "type": "SCALAR"}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "mode": 5}}]}}]}}"#
    )
}

/// Writes `model/NAME.gltf` referring to `uri` and reads it (guarded against blocking).
fn read_gltf(model: &Path, name: &str, uri: &str, byte_length: usize) -> Result<Vec<DVec3>, IoError> {
    let path = model.join(format!("{name}.gltf"));
    std::fs::write(&path, gltf_with_buffer(uri, byte_length)).unwrap();
    within(10, uri, move || read_mesh(&path).map(|soup| soup.positions))
}

/// The refusal of `uri`: a [`IoError::RefusedUri`] naming the glTF file and the URI, on one line.
fn refused(model: &Path, name: &str, uri: &str, reason: &str) {
    let e = read_gltf(model, name, uri, 56).expect_err(uri);
    let shown = e.to_string();
    assert!(matches!(&e, IoError::RefusedUri { uri: u, .. } if u == uri), "{uri}: {shown}");
    assert!(shown.contains(&format!("{name}.gltf: buffer uri '{uri}' refused: ")), "{shown}");
    assert!(shown.contains(reason), "{uri}: {shown} does not say '{reason}'");
    assert!(!shown.contains('\n'), "{shown}");
}

/// A directory with `outside/secret.bin` (a valid buffer: reading it would succeed) and an
/// empty `model/` for the glTF files.
fn layout(name: &str) -> (ScratchDir, PathBuf, PathBuf) {
    let dir = scratch_dir(name);
    let model = dir.join("model");
    std::fs::create_dir_all(&model).unwrap();
    std::fs::create_dir_all(dir.join("outside")).unwrap();
    let secret = dir.join("outside/secret.bin");
    std::fs::write(&secret, square_buffer()).unwrap();
    (dir, model, secret)
}

#[test]
fn gltf_buffer_uris_outside_the_files_directory_are_refused() {
    let (_dir, model, secret) = layout("uri_refused");
    refused(&model, "hostname", "/etc/hostname", "absolute path");
    refused(&model, "dev_zero", "/dev/zero", "absolute path");
    // A valid buffer, refused only for where it is.
    refused(&model, "absolute", secret.to_str().unwrap(), "absolute path");
    refused(&model, "parent", "../outside/secret.bin", "out of the glTF file's directory");
    refused(&model, "encoded", "sub%2F..%2F..%2Foutside%2Fsecret.bin", "out of the glTF file's directory");
    refused(&model, "dotdot", "%2e%2e/outside/secret.bin", "out of the glTF file's directory");
    refused(&model, "file_scheme", &format!("file://{}", secret.display()), "scheme");
    refused(&model, "file_relative", "file:secret.bin", "scheme");
    refused(&model, "http", "http://localhost/secret.bin", "network");
}

#[cfg(unix)]
#[test]
fn gltf_buffer_uris_through_symlinks_fifos_and_devices_are_refused() {
    use std::os::unix::fs::symlink;
    let (dir, model, secret) = layout("uri_special");
    symlink(&secret, model.join("link.bin")).unwrap();
    refused(&model, "file_link", "link.bin", "symbolic link");
    symlink(dir.join("outside"), model.join("dir_link")).unwrap();
    refused(&model, "dir_link", "dir_link/secret.bin", "symbolic link");
    symlink("/dev/zero", model.join("zero.bin")).unwrap();
    refused(&model, "zero", "zero.bin", "symbolic link");
    std::fs::create_dir(model.join("a_directory.bin")).unwrap();
    refused(&model, "directory", "a_directory.bin", "it names a directory, not a regular file");
    if make_fifo(&model.join("pipe.bin")) {
        // Opening a FIFO without a writer blocks: `within` fails the test instead.
        refused(&model, "fifo", "pipe.bin", "it names a FIFO, not a regular file");
    }
    // A symbolic link that stays inside the directory is followed.
    std::fs::write(model.join("real.bin"), square_buffer()).unwrap();
    symlink("real.bin", model.join("alias.bin")).unwrap();
    assert_eq!(read_gltf(&model, "alias", "alias.bin", 56).unwrap(), SQUARE);
}

#[test]
fn gltf_buffers_inside_the_directory_and_data_uris_still_read() {
    let (_dir, model, _) = layout("uri_allowed");
    std::fs::create_dir_all(model.join("sub")).unwrap();
    std::fs::write(model.join("sub/square data.bin"), square_buffer()).unwrap();
    assert_eq!(read_gltf(&model, "relative", "sub/square%20data.bin", 56).unwrap(), SQUARE);
    assert_eq!(read_gltf(&model, "dot", "./sub/../sub/square%20data.bin", 56).unwrap(), SQUARE);
    // Longer than byteLength: only byteLength bytes are the buffer.
    let mut longer = square_buffer();
    longer.extend([7; 100]);
    std::fs::write(model.join("longer.bin"), longer).unwrap();
    assert_eq!(read_gltf(&model, "longer", "longer.bin", 56).unwrap(), SQUARE);
    // Shorter than byteLength: truncated, not read past.
    let e = read_gltf(&model, "shorter", "sub/square%20data.bin", 57).unwrap_err();
    assert!(matches!(e, IoError::Truncated { .. }) && e.to_string().contains("declares 57 bytes but holds 56"), "{e}");
    // A missing buffer file names that file.
    let e = read_gltf(&model, "missing", "missing.bin", 56).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }) && e.to_string().contains("missing.bin"), "{e}");
    // data: URIs need no directory at all.
    let uri = format!("data:application/octet-stream;base64,{}", base64(&square_buffer()));
    let soup = read_mesh_from_bytes(gltf_with_buffer(&uri, 56).as_bytes(), Format::Gltf, "inline.gltf").unwrap();
    assert_eq!(soup.positions, SQUARE);
    assert_eq!(soup.faces.len(), 2);
}

/// Standard base64 with padding, written out here so the test does not share the reader's decoder.
fn base64(data: &[u8]) -> String {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in data.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (k, &b)| n | u32::from(b) << (16 - 8 * k));
        for k in 0..4 {
            out.push(if k <= chunk.len() { ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' });
        }
    }
    out
}

#[test]
fn a_directory_given_as_the_mesh_is_refused() {
    let dir = scratch_dir("not_a_file");
    let path = dir.join("mesh.obj");
    std::fs::create_dir(&path).unwrap();
    let e = read_mesh(&path).unwrap_err();
    assert!(matches!(e, IoError::NotAFile { kind: "a directory", .. }), "{e}");
    assert_eq!(e.to_string(), format!("{}: not a regular file (it is a directory)", path.display()));
}

#[cfg(unix)]
#[test]
fn fifos_and_devices_given_as_the_mesh_are_refused_before_they_are_opened() {
    let dir = scratch_dir("special_mesh");
    // /dev/zero would be read until memory runs out; the extension picks a reader.
    let zero = dir.join("zero.obj");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let e = within(10, "/dev/zero", move || read_mesh(&zero)).unwrap_err();
    assert!(matches!(e, IoError::NotAFile { kind: "a character device", .. }), "{e}");
    assert!(e.to_string().contains("zero.obj: not a regular file (it is a character device)"), "{e}");
    let fifo = dir.join("pipe.ply");
    if make_fifo(&fifo) {
        let e = within(10, "FIFO", move || read_mesh(&fifo)).unwrap_err();
        assert!(matches!(e, IoError::NotAFile { kind: "a FIFO", .. }), "{e}");
    }
}

#[test]
fn progress_is_reported_per_chunk_up_to_the_file_size() {
    let dir = scratch_dir("progress");
    let path = dir.join("big.obj");
    // 9 MiB of comment around a triangle: three 4 MiB chunks, cheap to parse.
    let mut text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\n# ".to_vec();
    text.resize(9 << 20, b'x');
    text.extend(b"\nf 1 2 3\n");
    std::fs::write(&path, &text).unwrap();
    let total = text.len() as u64;
    let mut calls = Vec::new();
    let soup = read_mesh_with_progress(&path, &mut |read, of| calls.push((read, of))).unwrap();
    assert_eq!((soup.positions.len(), soup.faces.len()), (3, 1));
    assert_eq!(calls, [(0, total), (4 << 20, total), (8 << 20, total), (total, total)]);
    assert_eq!(read_mesh(&path).unwrap(), soup);
}
