//! `subdiv info --json` against the statistics an independent script computed
//! for every mesh (the provenance tables in `fixtures/README.md`, its `bad/`
//! table for the non-manifold inputs, and, when present beside the
//! repository, `../shared/meshes/README.md`: its dragons and koala are not
//! copied).

use crate::common::{assert_no_panic, fixtures, shared_meshes, subdiv};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// One row of a provenance table.
struct Row {
    file: String,
    vertices: usize,
    faces: usize,
    face_sizes: BTreeMap<String, usize>,
    /// (boundary edges, loops); (0, 0) when closed.
    boundary: (usize, usize),
    manifold: bool,
    genus: Option<u32>,
}

fn parse_table(readme: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(readme).unwrap();
    let mut rows = Vec::new();
    for line in text.lines() {
        let cols: Vec<&str> = line.split('|').map(str::trim).collect();
        if cols.len() < 9 || !cols[1].contains('/') || cols[1].starts_with("bad/") {
            continue;
        }
        let Ok(vertices) = cols[2].parse() else { continue };
        let face_sizes = cols[4]
            .split_whitespace()
            .map(|kv| {
                let (k, v) = kv.split_once(':').unwrap();
                (k.to_string(), v.parse().unwrap())
            })
            .collect();
        let boundary = if cols[5].starts_with("closed") {
            (0, 0)
        } else {
            let nums: Vec<usize> = cols[5]
                .split(|c: char| !c.is_ascii_digit())
                .filter(|s| !s.is_empty())
                .map(|s| s.parse().unwrap())
                .collect();
            (nums[0], nums[1])
        };
        rows.push(Row {
            file: cols[1].to_string(),
            vertices,
            faces: cols[3].parse().unwrap(),
            face_sizes,
            boundary,
            manifold: cols[6].starts_with("yes"),
            genus: cols[7].trim_matches(|c| c == '(' || c == ')').parse().ok(),
        });
    }
    rows
}

fn check_all(root: &Path) -> usize {
    let rows = parse_table(&root.join("README.md"));
    assert!(!rows.is_empty());
    check_rows(root, rows)
}

/// Runs `subdiv info --json` on every row's file that exists under `root`;
/// returns how many were checked.
fn check_rows(root: &Path, rows: Vec<Row>) -> usize {
    let mut checked = 0;
    for row in rows {
        let path = root.join(&row.file);
        if !path.exists() {
            continue;
        }
        let out = subdiv(&["info", "--json", path.to_str().unwrap()]);
        assert_no_panic(&out);
        let json: Value = serde_json::from_slice(&out.stdout)
            .unwrap_or_else(|e| panic!("{}: no JSON ({e}); stderr {}", row.file, String::from_utf8_lossy(&out.stderr)));
        let f = &row.file;
        assert_eq!(json["vertices"], row.vertices, "{f}");
        assert_eq!(json["faces"], row.faces, "{f}");
        let sizes: BTreeMap<String, usize> = serde_json::from_value(json["face_sizes"].clone()).unwrap();
        assert_eq!(sizes, row.face_sizes, "{f}");
        assert_eq!(json["manifold"].as_bool(), Some(row.manifold), "{f}");
        if row.manifold {
            assert_eq!(out.status.code(), Some(0), "{f}");
            assert_eq!(json["boundary_edges"], row.boundary.0, "{f}");
            assert_eq!(json["boundary_loops"], row.boundary.1, "{f}");
            assert_eq!(json["genus"].as_u64().map(|g| g as u32), row.genus, "{f}");
            let chi = json["euler_characteristic"].as_i64().unwrap();
            let c = json["components"].as_i64().unwrap();
            assert_eq!(chi, 2 * c - 2 * i64::from(row.genus.unwrap()) - row.boundary.1 as i64, "{f}: χ = 2c − 2g − b");
            assert!(json["bbox_diagonal"].as_f64().unwrap() > 0.0);
        } else {
            assert!(json["genus"].is_null());
            if !json["error"].is_null() {
                // No mesh at all (a face of two corners).
                assert_eq!(out.status.code(), Some(2), "{f}: {}", json["error"]);
                checked += 1;
                continue;
            }
            // Refined as OpenSubdiv does: described, with its non-manifold edges and vertices.
            assert_eq!(out.status.code(), Some(0), "{f}: a non-manifold mesh is refined as OpenSubdiv does");
            let nm = &json["non_manifold"];
            let (edges, vertices) = (nm["edges"].as_array().unwrap(), nm["vertices"].as_array().unwrap());
            assert!(!vertices.is_empty(), "{f}: {nm}");
            for e in edges {
                let ends: Vec<u64> = e.as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
                assert!(ends.iter().all(|v| vertices.iter().any(|w| w.as_u64() == Some(*v))), "{f}: {e} ends");
            }
        }
        checked += 1;
    }
    checked
}

/// The `bad/` rows whose "what the stats script sees" column reads
/// `V=5 F=3 3:3; …; manifold no (…)`: counts and face sizes of a mesh that
/// is not manifold (the non-manifold branch of [`check_all`], which no
/// manifold row reaches).
fn parse_non_manifold_bad_rows(readme: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(readme).unwrap();
    let section = &text[text.find("## bad/").expect("the bad/ table")..];
    let mut rows = Vec::new();
    for line in section.lines() {
        let cols: Vec<&str> = line.split('|').map(str::trim).collect();
        if cols.len() < 5 || !cols[3].contains("manifold no") {
            continue;
        }
        let fields: Vec<&str> = cols[3].split(';').next().unwrap().split_whitespace().collect();
        let count = |key: &str| fields.iter().find_map(|f| f.strip_prefix(key)).unwrap().parse().unwrap();
        let face_sizes =
            fields.iter().filter_map(|f| f.split_once(':')).map(|(k, v)| (k.to_string(), v.parse().unwrap())).collect();
        rows.push(Row {
            file: format!("bad/{}", cols[1]),
            vertices: count("V="),
            faces: count("F="),
            face_sizes,
            boundary: (0, 0),
            manifold: false,
            genus: None,
        });
    }
    rows
}

#[test]
fn info_matches_the_fixture_tables() {
    let n = check_all(&fixtures());
    assert!(n >= 40, "only {n} fixtures checked");
}

#[test]
fn info_describes_the_non_manifold_fixtures_with_their_counts() {
    let rows = parse_non_manifold_bad_rows(&fixtures().join("README.md"));
    let n = rows.len();
    assert!(n >= 4, "only {n} non-manifold rows in the bad/ table");
    assert_eq!(check_rows(&fixtures(), rows), n, "a non-manifold fixture is missing");
}

#[test]
fn info_matches_the_shared_collection() {
    match shared_meshes() {
        Some(root) => {
            let n = check_all(&root);
            eprintln!("checked {n} meshes of ../shared/meshes");
        }
        None => eprintln!(
            "../shared/meshes not present beside the repository: its dragons and koala are left out \
             (every fixture is checked by the tests above)"
        ),
    }
}

#[test]
fn text_output_names_every_field() {
    let out = subdiv(&["info", fixtures().join("canonical/torus_quad_16x8.obj").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    for key in [
        "vertices:",
        "faces:",
        "edges:",
        "face sizes:",
        "valences:",
        "boundary:",
        "genus:",
        "manifold",
        "bbox diagonal:",
    ] {
        assert!(text.contains(key), "missing {key} in\n{text}");
    }
    assert!(text.contains("genus:                1"));
    assert!(text.contains("valences:             4:128"));
}
