//! `subdiv info`'s "interpolation methods" section: for each of the seven
//! methods, whether it takes the mesh and why not — the same verdict the
//! method itself reaches (`subdiv interpolate` is run to check it).

use crate::common::{assert_no_panic, fixtures, subdiv, Scratch};
use serde_json::Value;

const METHODS: [&str; 7] = ["nasri", "zheng-cai", "cheng", "fan-cheng-lai", "deng-wang", "deng-ma", "fair"];

fn info_json(path: &str) -> (Value, std::process::Output) {
    let out = subdiv(&["info", path, "--json"]);
    assert_no_panic(&out);
    (serde_json::from_slice(&out.stdout).expect("info --json prints JSON"), out)
}

/// A unit cube with one corner moved: Cheng's A is singular (all valence 3,
/// bipartite) and these data leave its range.
fn bent_cube(dir: &std::path::Path) -> String {
    let path = dir.join("bent-cube.obj");
    let text = "v 0.1 -0.2 0.05\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
                f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

#[test]
fn methods_section_matches_what_interpolate_does() {
    let scratch = Scratch::new("info-methods");
    let dir = scratch.dir();
    let cases = [
        fixtures().join("quad/spot_control_mesh.obj").display().to_string(),
        fixtures().join("open/halftunnel.off").display().to_string(),
        fixtures().join("poly/mpi.off").display().to_string(),
        bent_cube(dir),
    ];
    for path in &cases {
        let (json, out) = info_json(path);
        assert!(out.status.success(), "{path}");
        let methods = json["methods"].as_object().expect("a methods object");
        assert_eq!(methods.len(), METHODS.len(), "{path}");
        for m in METHODS {
            let verdict = &methods[m];
            let accepts = verdict["accepts"].as_bool().expect("accepts is a bool");
            assert_eq!(verdict["reason"].is_null(), accepts, "{path} {m}: a reason exactly when refused");
            let control = dir.join(format!("{m}.obj"));
            let run = subdiv(&["interpolate", path, "--method", m, "-o", &control.display().to_string()]);
            assert_no_panic(&run);
            assert_eq!(run.status.success(), accepts, "{path} {m}: info says {verdict}, interpolate: {:?}", run);
        }
    }
    let (json, _) = info_json(&cases[3]);
    let reason = json["methods"]["cheng"]["reason"].as_str().unwrap();
    assert!(reason.contains("singular"), "{reason}");
}

#[test]
fn invalid_meshes_are_refused_by_every_method_with_the_validation_error() {
    let path = fixtures().join("bad/face_with_two_vertices.obj").display().to_string();
    let (json, out) = info_json(&path);
    assert_eq!(out.status.code(), Some(2));
    for m in METHODS {
        assert_eq!(json["methods"][m]["accepts"], Value::Bool(false), "{m}");
        assert!(json["methods"][m]["reason"].as_str().unwrap().contains("not valid"), "{m}");
    }
}

#[test]
fn non_manifold_meshes_are_taken_by_cheng_and_fair_and_refused_by_the_others_with_the_reason() {
    let scratch = Scratch::new("info-methods-nm");
    for file in ["bad/nonmanifold_edge_3faces.obj", "bad/nonmanifold_vertex_bowtie.obj"] {
        let path = fixtures().join(file).display().to_string();
        let (json, out) = info_json(&path);
        assert_eq!(out.status.code(), Some(0), "{file}: refined as OpenSubdiv does");
        for m in METHODS {
            let verdict = &json["methods"][m];
            let accepts = verdict["accepts"].as_bool().unwrap();
            assert_eq!(accepts, m == "cheng" || m == "fair", "{file} {m}: {verdict}");
            if !accepts {
                assert!(verdict["reason"].as_str().unwrap().contains("non-manifold"), "{file} {m}: {verdict}");
            }
            // interpolate does what info says.
            let control = scratch.path(&format!("{m}.obj")).display().to_string();
            let run = subdiv(&["interpolate", &path, "--method", m, "-o", &control]);
            assert_no_panic(&run);
            assert_eq!(run.status.success(), accepts, "{file} {m}: {run:?}");
        }
    }
}

#[test]
fn text_output_lists_the_methods() {
    let path = fixtures().join("quad/spot_control_mesh.obj").display().to_string();
    let out = subdiv(&["info", &path]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("interpolation methods:"), "{text}");
    for m in METHODS {
        assert!(text.lines().any(|l| l.trim_start().starts_with(m) && l.contains("accepts")), "{m}: {text}");
    }
}
