//! OpenSubdiv's tagged inputs (`fixtures/peer/creases/<case>/<case>.obj`)
//! read with the tag and `vt` counts its README states, as valid meshes, and
//! round-trip exactly; the refined outputs there (with `t` lines of their
//! level and `vt`) read with their stated counts too. The folder is a copy of
//! the shared collection's `peer-outputs/creases/` (README included); when
//! that collection sits beside the repository, the copy is also compared
//! with it byte for byte.

use crate::common::fixture;
use std::path::{Path, PathBuf};
use subdiv_io::{read_mesh, read_mesh_from_bytes, write_mesh_to_vec, EdgeTag, Format, MeshView, VertexTag};
use subdiv_mesh::{Mesh, PolygonSoup};

/// What the README states of a file: vertices, faces, crease and corner
/// tags (inputs) or tag lines (outputs), and `vt` values.
#[derive(Debug, PartialEq)]
struct Counts {
    vertices: usize,
    faces: usize,
    /// (creases, corners) for inputs; outputs state only the sum.
    tags: Tags,
    vt: usize,
}

#[derive(Debug, PartialEq)]
enum Tags {
    Split(usize, usize),
    Lines(usize),
}

/// The inputs, with the counts of `fixtures/peer/creases/README.md`.
const INPUTS: &[(&str, usize, usize, usize, usize, usize)] = &[
    // (case, v, f, creases, corners, vt)
    ("cube_corners2", 8, 6, 0, 2, 0),
    ("cube_corners_semi", 8, 6, 0, 2, 0),
    ("cube_crease_all10", 8, 6, 12, 0, 0),
    ("cube_crease_top_mixed", 8, 6, 4, 0, 0),
    ("cube_crease_top_s1", 8, 6, 4, 0, 0),
    ("cube_crease_top_s2.5", 8, 6, 4, 0, 0),
    ("grid_crease_row_corner", 81, 64, 8, 1, 0),
    ("octahedron_corner_creases", 6, 8, 4, 1, 0),
    ("spot_uv", 188, 180, 0, 0, 267),
    ("torus_ring_s3", 128, 128, 8, 0, 0),
    ("uv_grid", 81, 64, 0, 0, 81),
];

fn input(case: &str) -> PathBuf {
    fixture(&format!("peer/creases/{case}/{case}.obj"))
}

/// The copy in the repository: the README and every file it lists.
fn creases() -> PathBuf {
    fixture("peer/creases")
}

/// The original beside the repository (`../shared/peer-outputs/creases/`), if present.
fn shared_creases() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/peer-outputs/creases");
    dir.join("README.md").exists().then_some(dir)
}

fn counts_of(soup: &PolygonSoup, split: bool) -> Counts {
    let (creases, corners) = (soup.tags.creases.len(), soup.tags.corners.len());
    Counts {
        vertices: soup.positions.len(),
        faces: soup.faces.len(),
        tags: if split { Tags::Split(creases, corners) } else { Tags::Lines(creases + corners) },
        vt: soup.uvs.as_ref().map_or(0, |uvs| uvs.values.len()),
    }
}

/// Validates the soup as a mesh: every crease pair is an edge, every `vt`
/// index in range; returns the mesh's own tag counts.
fn validated(soup: PolygonSoup, what: &str) -> (usize, usize) {
    let (mesh, _) = Mesh::from_soup(soup).unwrap_or_else(|e| panic!("{what}: {e}"));
    (mesh.tags().crease_count(), mesh.tags().corner_count())
}

#[test]
fn tagged_inputs_have_the_stated_counts_and_are_valid_meshes() {
    for &(case, v, f, creases, corners, vt) in INPUTS {
        let soup = read_mesh(&input(case)).unwrap_or_else(|e| panic!("{e}"));
        let expected = Counts { vertices: v, faces: f, tags: Tags::Split(creases, corners), vt };
        assert_eq!(counts_of(&soup, true), expected, "{case}");
        // No tag names the same element twice here, and none is 0: the mesh counts them all.
        assert_eq!(validated(soup, case), (creases, corners), "{case}");
    }
}

#[test]
fn tag_values_are_read_as_written() {
    let soup = read_mesh(&input("cube_crease_top_s1")).unwrap();
    let e = |a, b| EdgeTag { a, b, sharpness: 1.0 };
    assert_eq!(soup.tags.creases, vec![e(1, 5), e(5, 7), e(7, 3), e(3, 1)]);
    let soup = read_mesh(&input("grid_crease_row_corner")).unwrap();
    let row: Vec<EdgeTag> = (36..44).map(|v| EdgeTag { a: v, b: v + 1, sharpness: 2.0 }).collect();
    assert_eq!(soup.tags.creases, row);
    assert_eq!(soup.tags.corners, vec![VertexTag { vertex: 3, sharpness: 10.0 }]);
    let soup = read_mesh(&input("cube_crease_top_mixed")).unwrap();
    let sharpness: Vec<f32> = soup.tags.creases.iter().map(|t| t.sharpness).collect();
    assert_eq!(sharpness, [0.75, 2.5, 0.75, 2.5]);
    // uv_grid: vt k belongs to vertex k.
    let soup = read_mesh(&input("uv_grid")).unwrap();
    assert_eq!(soup.uvs.unwrap().indices, soup.faces.indices());
}

#[test]
fn tagged_inputs_round_trip_through_obj_exactly() {
    for &(case, ..) in INPUTS {
        let soup = read_mesh(&input(case)).unwrap();
        let bytes = write_mesh_to_vec(MeshView::from(&soup), Format::Obj).unwrap();
        let back = read_mesh_from_bytes(&bytes, Format::Obj, case).unwrap();
        let bits = |s: &PolygonSoup| s.positions.iter().map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&soup), "{case}");
        assert_eq!((&back.faces, &back.uvs, &back.tags), (&soup.faces, &soup.uvs, &soup.tags), "{case}");
    }
}

/// Compares every file under `original` with the same relative path under
/// `copy`, byte for byte; returns how many.
fn compare_tree(original: &Path, copy: &Path) -> usize {
    let mut compared = 0;
    let mut stack = vec![original.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let relative = path.strip_prefix(original).unwrap();
            let bytes = std::fs::read(copy.join(relative)).unwrap_or_else(|e| panic!("{}: {e}", relative.display()));
            assert!(bytes == std::fs::read(&path).unwrap(), "{} differs from its original", relative.display());
            compared += 1;
        }
    }
    compared
}

/// Every file the README lists is in the repository; where the shared
/// collection is present, every file of it is here, byte for byte.
#[test]
fn the_fixtures_are_complete_unchanged_copies() {
    let readme = std::fs::read_to_string(creases().join("README.md")).unwrap();
    let rows = stated(&readme);
    for (file, _) in &rows {
        assert!(creases().join(file).is_file(), "{file}: listed in the README, missing from fixtures/peer/creases");
    }
    for &(case, ..) in INPUTS {
        assert!(input(case).is_file(), "{case}");
    }
    match shared_creases() {
        Some(shared) => {
            let compared = compare_tree(&shared, &creases());
            assert!(compared > rows.len(), "{compared} files compared");
        }
        None => {
            eprintln!("../shared/peer-outputs/creases/ not found: the byte comparison with the originals is left out")
        }
    }
}

/// The `.obj` rows of the README's table: file and stated counts
/// ("26 v, 24 f, 8 t", "81 v, 64 f, 8 crease + 1 corner tags", "…, 885 vt").
fn stated(readme: &str) -> Vec<(String, Counts)> {
    let mut rows = Vec::new();
    for line in readme.lines() {
        let cols: Vec<&str> = line.split('|').map(str::trim).collect();
        let Some(file) = cols.get(1).and_then(|c| c.strip_prefix('`')).and_then(|c| c.strip_suffix(".obj`")) else {
            continue;
        };
        let mut counts = Counts { vertices: 0, faces: 0, tags: Tags::Lines(0), vt: 0 };
        for item in cols[3].split(", ") {
            let words: Vec<&str> = item.split_whitespace().collect();
            let n = words[0].parse().unwrap_or_else(|_| panic!("{file}: '{item}'"));
            match words[1] {
                "v" => counts.vertices = n,
                "f" => counts.faces = n,
                "t" => counts.tags = Tags::Lines(n),
                "vt" => counts.vt = n,
                "crease" => counts.tags = Tags::Split(n, words[3].parse().unwrap()),
                other => panic!("{file}: unknown count '{other}'"),
            }
        }
        rows.push((format!("{file}.obj"), counts));
    }
    rows
}

#[test]
fn every_opensubdiv_output_reads_with_its_stated_counts() {
    let dir = creases();
    let rows = stated(&std::fs::read_to_string(dir.join("README.md")).unwrap());
    assert!(rows.len() >= 59, "{} rows", rows.len());
    let mut outputs = 0;
    for (file, counts) in rows {
        let soup = read_mesh(&dir.join(&file)).unwrap_or_else(|e| panic!("{e}"));
        let split = matches!(counts.tags, Tags::Split(..));
        assert_eq!(counts_of(&soup, split), counts, "{file}");
        // The refined levels' tags name edges of their own level, and their
        // `f v/vt` corners index their `vt` lines.
        validated(soup, &file);
        outputs += usize::from(!split);
    }
    assert!(outputs >= 48, "{outputs} outputs");
}
