//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use subdiv_io::Format;
use subdiv_mesh::{DVec3, FaceList, PolygonSoup};

/// A file of the workspace's `fixtures/` directory.
pub fn fixture(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(relative)
}

/// A file of the shared mesh collection beside the repository, if present
/// (large meshes that are not copied into `fixtures/`).
pub fn shared_mesh(relative: &str) -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes").join(relative);
    path.exists().then_some(path)
}

/// A fresh empty directory under cargo's per-target temporary directory.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("subdiv-io-tests").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The fan triangulation of every face, as the triangulating writers do it.
pub fn fan_triangles(faces: &FaceList) -> Vec<[u32; 3]> {
    faces.iter().flat_map(|f| (2..f.len()).map(move |i| [f[0], f[i - 1], f[i]])).collect()
}

/// `p` as stored by the format: rounded to `f32` where the format stores `f32`.
pub fn stored(p: DVec3, format: Format) -> DVec3 {
    if format.keeps_f64() {
        p
    } else {
        p.as_vec3().as_dvec3()
    }
}

pub fn bits(p: DVec3) -> [u64; 3] {
    p.to_array().map(f64::to_bits)
}

/// Asserts that `back` is what writing `original` in `format` and reading it
/// again must give: the same polygons for polygon formats, the fan
/// triangulation for STL and glTF; positions bit-exact for `f64` formats and
/// equal to the `f32`-rounded originals otherwise; for STL, vertices welded in
/// order of first appearance, one per distinct stored position.
pub fn assert_round_trip(original: &PolygonSoup, back: &PolygonSoup, format: Format, what: &str) {
    if !format.triangulates() {
        assert_eq!(back.faces, original.faces, "{what}: faces differ");
    } else {
        let expected = fan_triangles(&original.faces);
        assert_eq!(back.faces.len(), expected.len(), "{what}: triangle count");
        assert!(back.faces.all_of_size(3), "{what}: not all triangles");
    }

    if format.keeps_vertices() {
        assert_eq!(back.positions.len(), original.positions.len(), "{what}: vertex count");
        for (i, (a, b)) in original.positions.iter().zip(&back.positions).enumerate() {
            let want = stored(*a, format);
            assert_eq!(bits(*b), bits(want), "{what}: vertex {i}: {b} != {want}");
            if !format.keeps_f64() {
                // f32 rounding stays within 2^-24 relative (what the docs promise).
                let close = (*b - *a).abs().cmple(a.abs() * 2f64.powi(-24)).all();
                assert!(close, "{what}: vertex {i} off by more than f32 rounding");
            }
        }
        if format.triangulates() {
            let expected = fan_triangles(&original.faces);
            for (k, (t, want)) in back.faces.iter().zip(&expected).enumerate() {
                assert_eq!(t, want, "{what}: triangle {k}");
            }
        }
        return;
    }

    // STL: vertices renumbered by welding. Map every read-back vertex to the
    // original corner it stands for and check the maps agree both ways.
    let expected = fan_triangles(&original.faces);
    let mut to_original: HashMap<u32, u32> = HashMap::new();
    let mut distinct: HashMap<[u64; 3], u32> = HashMap::new();
    for (k, (t, want)) in back.faces.iter().zip(&expected).enumerate() {
        for (&b, &o) in t.iter().zip(want) {
            let p = stored(original.positions[o as usize], format);
            // Welding counts -0.0 equal to 0.0 and keeps the first one's sign.
            let key = bits(p + DVec3::ZERO);
            let got = bits(back.positions[b as usize] + DVec3::ZERO);
            assert_eq!(got, key, "{what}: triangle {k} corner position");
            let first = *distinct.entry(key).or_insert(o);
            // Same stored position → same welded vertex.
            let mapped = *to_original.entry(b).or_insert(first);
            assert_eq!(mapped, first, "{what}: welded vertex {b} stands for two positions");
        }
    }
    assert_eq!(back.positions.len(), distinct.len(), "{what}: welded vertex count");
    let referenced: std::collections::HashSet<u32> = expected.iter().flatten().copied().collect();
    if distinct.len() == referenced.len() {
        // No coincident vertices: welding reproduces every referenced vertex.
        assert_eq!(to_original.len(), referenced.len(), "{what}: welding lost vertices");
    }
}

/// Runs `f` on its own thread and returns its result, failing the test if it
/// has not finished after `seconds` — a guard against a reader that blocks
/// (opening a FIFO) or loops (a zero-size record repeated 2⁶⁴ times), so that
/// such a bug fails the test instead of hanging it. Not a speed measurement:
/// the bound is generous and the work is small.
pub fn within<T: Send + 'static>(seconds: u64, what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (done, result) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = done.send(f());
    });
    result
        .recv_timeout(std::time::Duration::from_secs(seconds))
        .unwrap_or_else(|_| panic!("{what}: still running after {seconds} s (blocked or looping)"))
}

/// Creates a FIFO with the `mkfifo` program; `false` (and a visible skip
/// message) where there is none.
pub fn make_fifo(path: &Path) -> bool {
    match std::process::Command::new("mkfifo").arg(path).status() {
        Ok(status) if status.success() => true,
        _ => {
            eprintln!("mkfifo not available; skipping the FIFO case");
            false
        }
    }
}
