//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use subdiv_io::Format;
use subdiv_mesh::{DVec2, DVec3, FaceList, FaceVarying, PolygonSoup};

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

/// A fresh empty directory (`subdiv-io-{name}-XXXXXX` in the temporary
/// directory), removed when the guard drops: bind it for the whole test.
pub fn scratch_dir(name: &str) -> ScratchDir {
    ScratchDir(tempfile::Builder::new().prefix(&format!("subdiv-io-{name}-")).tempdir().unwrap())
}

/// The guard of [`scratch_dir`]; derefs to the directory's path.
pub struct ScratchDir(tempfile::TempDir);

impl AsRef<Path> for ScratchDir {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

impl std::ops::Deref for ScratchDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
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
/// order of first appearance, one per distinct stored position. glTF splits
/// vertices at texture-coordinate seams: the original vertices come first,
/// and every corner keeps its position. Texture coordinates: see
/// [`assert_same_uvs`].
pub fn assert_round_trip(original: &PolygonSoup, back: &PolygonSoup, format: Format, what: &str) {
    assert_same_uvs(original, back, format, what);
    if !format.triangulates() {
        assert_eq!(back.faces, original.faces, "{what}: faces differ");
    } else {
        let expected = fan_triangles(&original.faces);
        assert_eq!(back.faces.len(), expected.len(), "{what}: triangle count");
        assert!(back.faces.all_of_size(3), "{what}: not all triangles");
    }

    if format.keeps_vertices() {
        let split = format.splits_uv_seams() && original.uvs.is_some();
        if split {
            assert!(back.positions.len() >= original.positions.len(), "{what}: vertex count");
        } else {
            assert_eq!(back.positions.len(), original.positions.len(), "{what}: vertex count");
        }
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
                if split {
                    // A split vertex is a copy: the same stored position.
                    for (&b, &o) in t.iter().zip(want) {
                        let p = stored(original.positions[o as usize], format);
                        assert_eq!(bits(back.positions[b as usize]), bits(p), "{what}: triangle {k} corner position");
                    }
                } else {
                    assert_eq!(t, want, "{what}: triangle {k}");
                }
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

/// The texture coordinate of every face corner, in face order, fan
/// triangulated when `triangulate` (as the triangulating writers do).
pub fn corner_uvs(faces: &FaceList, uvs: &FaceVarying, triangulate: bool) -> Vec<DVec2> {
    let per_corner: Vec<DVec2> = uvs.indices.iter().map(|&i| uvs.values[i as usize]).collect();
    if !triangulate {
        return per_corner;
    }
    let mut out = Vec::new();
    for f in 0..faces.len() {
        let start = faces.offsets()[f] as usize;
        for i in 2..faces.face_size(f) {
            out.extend([per_corner[start], per_corner[start + i - 1], per_corner[start + i]]);
        }
    }
    out
}

/// `uv` as the format stores it: glTF in `f32`, with `v` flipped to its
/// top-left origin and back; USD in `f32` (`texCoord2f`).
pub fn stored_uv(uv: DVec2, format: Format) -> DVec2 {
    if format.keeps_f64() {
        uv
    } else if format.is_usd() {
        uv.as_vec2().as_dvec2()
    } else {
        DVec2::new(f64::from(uv.x as f32), 1.0 - f64::from((1.0 - uv.y) as f32))
    }
}

/// The tags a mesh with `tags` reads back with from `format`: USD writes the
/// face-varying mode whenever there are texture coordinates (its fallback,
/// `cornersPlus1`, is not OpenSubdiv's default), so an unset mode reads back
/// as the default it stood for.
pub fn stored_tags(tags: &subdiv_io::TagList, has_uvs: bool, format: Format) -> subdiv_io::TagList {
    let mut tags = tags.clone();
    if format.is_usd() && has_uvs && tags.options.fvar.is_none() {
        tags.options.fvar = Some(Default::default());
    }
    tags
}

/// Texture coordinates after a write and read in `format`: none where the
/// format does not carry them; otherwise every corner's value as stored
/// (bit-exact for `f64` formats), and for the polygon formats the same seams:
/// at every vertex, two corners share a value index after the round trip
/// exactly when they shared one before.
pub fn assert_same_uvs(original: &PolygonSoup, back: &PolygonSoup, format: Format, what: &str) {
    let Some(uvs) = original.uvs.as_ref().filter(|_| format.carries_uvs()) else {
        assert!(back.uvs.is_none(), "{what}: texture coordinates appeared");
        return;
    };
    let got = back.uvs.as_ref().unwrap_or_else(|| panic!("{what}: texture coordinates lost"));
    let want = corner_uvs(&original.faces, uvs, format.triangulates());
    let have = corner_uvs(&back.faces, got, false);
    assert_eq!(have.len(), want.len(), "{what}: texture coordinate corners");
    for (k, (h, w)) in have.iter().zip(&want).enumerate() {
        let w = stored_uv(*w, format);
        assert_eq!(h.to_array().map(f64::to_bits), w.to_array().map(f64::to_bits), "{what}: corner {k}: {h} != {w}");
    }
    if format.triangulates() {
        return;
    }
    let mut pairs: HashMap<(u32, u32), u32> = HashMap::new();
    let mut reverse: HashMap<(u32, u32), u32> = HashMap::new();
    for (k, &v) in original.faces.indices().iter().enumerate() {
        let (a, b) = (uvs.indices[k], got.indices[k]);
        assert_eq!(*pairs.entry((v, a)).or_insert(b), b, "{what}: vertex {v}: one value became two");
        assert_eq!(*reverse.entry((v, b)).or_insert(a), a, "{what}: vertex {v}: two values became one");
    }
}
