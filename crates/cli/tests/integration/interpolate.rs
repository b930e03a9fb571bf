//! `subdiv interpolate` as a process: every method writes a control mesh,
//! a surface and a report whose error an independent check re-derives from
//! the written file alone; failures exit 2 or 3 and write nothing.

use crate::common::{assert_no_panic, fixtures, subdiv, Scratch};
use serde_json::Value;
use std::path::{Path, PathBuf};
use subdiv_interp::verify::{candidate_limit_points, nearest_gap};
use subdiv_mesh::Mesh;
use subdiv_stencil::LoopBeta;
use subdiv_stencil::Scheme;

fn load(path: &Path) -> Mesh {
    Mesh::from_soup(subdiv_io::read_mesh(path).unwrap()).unwrap().0
}

fn run(args: &[&str]) -> (Option<i32>, String, String) {
    let out = subdiv(args);
    assert_no_panic(&out);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn every_method_writes_outputs_whose_error_checks_out_independently() {
    let scratch = Scratch::new("interpolate");
    for (method, input, plain, tol) in [
        ("nasri", "poly/mpi.off", Scheme::DooSabin, 1e-6),
        ("zheng-cai", "quad/spot_control_mesh.obj", Scheme::DooSabin, 1e-12),
        ("cheng", "quad/spot_control_mesh.obj", Scheme::CatmullClark, 1e-6),
        ("cheng", "open/halftunnel.off", Scheme::CatmullClark, 1e-6),
        ("fan-cheng-lai", "poly/P.off", Scheme::DooSabin, 1e-6),
        ("deng-wang", "tri/eight.off", Scheme::Loop(LoopBeta::Loop), 1e-12),
        ("deng-ma", "canonical/cube_quad.obj", Scheme::DengMa(Default::default()), 1e-12),
    ] {
        let input_path = fixtures().join(input);
        let stem = format!("{method}-{}", input.replace('/', "-"));
        let (control, surface, report) = (
            scratch.path(&format!("{stem}.obj")),
            scratch.path(&format!("{stem}-surface.ply")),
            scratch.path(&format!("{stem}.json")),
        );
        let (code, stdout, stderr) = run(&[
            "interpolate",
            input_path.to_str().unwrap(),
            "--method",
            method,
            "-o",
            control.to_str().unwrap(),
            "--surface",
            surface.to_str().unwrap(),
            "--levels",
            "2",
            "--report",
            report.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{method} {input}: {stderr}");
        assert!(stdout.contains("max error"), "{stdout}");
        let report: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        for key in ["method", "control_scheme", "input", "solver", "error", "timing_ms", "parameters"] {
            assert!(report.get(key).is_some(), "{method}: report lacks {key}");
        }
        assert_eq!(report["method"], method);
        let reported = report["error"]["max_rel"].as_f64().unwrap();
        assert!(reported <= tol, "{method} {input}: reported {reported:e}");
        // Independent: from the written control mesh alone.
        let data = load(&input_path);
        let d = data.bbox_diagonal();
        let written = load(&control);
        let gap = nearest_gap(data.positions(), &candidate_limit_points(&written, plain).unwrap(), d);
        assert!(gap <= tol * (1.0 + 1e-6) + 1e-15, "{method} {input}: independent error {gap:e}");
        let s = subdiv_io::read_mesh(&surface).unwrap();
        assert!(s.faces.len() > data.topology().face_count());
        eprintln!("{method} on {input}: reported {reported:.2e}, independent {gap:.2e}");
    }
}

#[test]
fn singular_and_unsupported_inputs_exit_with_reasons_and_write_nothing() {
    let scratch = Scratch::new("interpolate");
    let cube = fixtures().join("canonical/cube_quad.obj");
    let out = scratch.path("never.obj");
    let _ = std::fs::remove_file(&out);
    // The exact cube is in the range of the singular A: a valid, non-unique interpolant.
    let (code, _, stderr) = run(&["interpolate", cube.to_str().unwrap(), "--method", "cheng"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains("not unique"), "{stderr}");
    // A perturbed cube is not: exit 3 with the error reached, nothing written.
    let bent = scratch.path("bent_cube.obj");
    let text = std::fs::read_to_string(&cube).unwrap().replacen("v 0 0 0", "v 0.05 -0.02 0.03", 1);
    std::fs::write(&bent, text).unwrap();
    let (code, _, stderr) =
        run(&["interpolate", bent.to_str().unwrap(), "--method", "cheng", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(3), "{stderr}");
    assert!(stderr.contains("residual") && stderr.contains("zheng-cai"), "{stderr}");
    assert!(!out.exists());
    // Deng-Wang triangulates polygons itself; only a face without a valid triangulation is refused.
    let untriangulable = untriangulable_torus(&scratch);
    let (code, _, stderr) =
        run(&["interpolate", untriangulable.to_str().unwrap(), "--method", "deng-wang", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("face 8 (6 vertices) cannot be triangulated"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(!out.exists());
    // Bad parameter files name the file and line.
    let subset = scratch.path("subset.txt");
    std::fs::write(&subset, "0 1\n# comment\n2 99999\n").unwrap();
    let (code, _, stderr) =
        run(&["interpolate", cube.to_str().unwrap(), "--method", "nasri", "--subset", subset.to_str().unwrap()]);
    assert_eq!(code, Some(2));
    assert!(stderr.contains("subset.txt:3") && stderr.contains("99999"), "{stderr}");
    // A tolerance the iteration cap cannot reach: exit 3.
    let spot = fixtures().join("quad/spot_control_mesh.obj");
    let (code, _, stderr) = run(&[
        "interpolate",
        spot.to_str().unwrap(),
        "--method",
        "cheng",
        "--solver",
        "pia",
        "--max-iter",
        "3",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(3), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn shape_files_and_subsets_apply() {
    let scratch = Scratch::new("interpolate");
    let mesh = fixtures().join("poly/mpi.off");
    let shape = scratch.path("shape.json");
    std::fs::write(&shape, r#"{"default": 0.5, "faces": {"0": 0.9, "3": 0.2}}"#).unwrap();
    let report = scratch.path("fcl.json");
    let (code, _, stderr) = run(&[
        "interpolate",
        mesh.to_str().unwrap(),
        "--method",
        "fan-cheng-lai",
        "--shape-file",
        shape.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["parameters"]["lambda"]["min"], 0.2);
    assert_eq!(r["parameters"]["lambda"]["max"], 0.9);
    let subset = scratch.path("subset.json");
    std::fs::write(&subset, "[0, 5, 10]").unwrap();
    let (code, _, stderr) = run(&[
        "interpolate",
        mesh.to_str().unwrap(),
        "--method",
        "cheng",
        "--subset",
        subset.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["error"]["vertices"], 3);
}

/// Deng-Wang on quad and polygon meshes: triangulated inside the method,
/// with a warning on stderr and `triangulated_faces` in the report; the
/// written control mesh interpolates (independent check from the file).
/// (A face with no triangulation exits 2 naming it: the test above.)
#[test]
fn deng_wang_triangulates_polygon_meshes() {
    let scratch = Scratch::new("interpolate");
    for (input, faces) in [("canonical/cube_quad.obj", 6), ("quad/spot_control_mesh.obj", 176), ("poly/mpi.off", 39)] {
        let input_path = fixtures().join(input);
        let stem = format!("deng-wang-{}", input.replace('/', "-"));
        let (control, report) = (scratch.path(&format!("{stem}.obj")), scratch.path(&format!("{stem}.json")));
        let (code, _, stderr) = run(&[
            "interpolate",
            input_path.to_str().unwrap(),
            "--method",
            "deng-wang",
            "-o",
            control.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{input}: {stderr}");
        assert!(
            stderr.contains(&format!("warning: the mesh has {faces} non-triangular faces; they were triangulated")),
            "{input}: {stderr}"
        );
        let report: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        assert_eq!(report["parameters"]["triangulated_faces"], faces, "{input}");
        assert_eq!(report["control_scheme"], "loop");
        assert!(report["error"]["max_rel"].as_f64().unwrap() <= 1e-12, "{input}: {}", report["error"]);
        let data = load(&input_path);
        let written = load(&control);
        assert!(written.topology().faces().all_of_size(3));
        let plain = Scheme::Loop(LoopBeta::Loop);
        let gap =
            nearest_gap(data.positions(), &candidate_limit_points(&written, plain).unwrap(), data.bbox_diagonal());
        assert!(gap <= 1e-12, "{input}: independent error {gap:e}");
    }
}

/// The 7-vertex torus (every two vertices share an edge) with one vertex's
/// star replaced by a hexagon over its link, face 8 (vertices renumbered
/// 1..7 → 0..6): every diagonal of the hexagon is an edge, so it has no
/// triangulation keeping the mesh manifold. Written as OBJ in `scratch`; returns the path.
fn untriangulable_torus(scratch: &Scratch) -> PathBuf {
    let mut text: String =
        (1..7).map(|k| format!("v {} {} {}\n", f64::from(k).cos(), f64::from(k).sin(), k % 3)).collect();
    for i in 0..7u32 {
        for tri in [[i, i + 1, i + 3], [i, i + 3, i + 2]].map(|t| t.map(|v| v % 7)) {
            if !tri.contains(&0) {
                text += &format!("f {} {} {}\n", tri[0], tri[1], tri[2]); // 1-based = renumbered + 1
            }
        }
    }
    text += "f 1 3 2 6 4 5\n";
    let path = scratch.path("untriangulable.obj");
    std::fs::write(&path, text).unwrap();
    path
}
