//! `subdiv interpolate --method fair` as a process: the control mesh it
//! writes interpolates the data (checked from the written file alone) for
//! each scheme and refinement; the fair flags are refused where they do not
//! apply, with exit 2 and the flag named.

use crate::common::{assert_no_panic, fixtures, subdiv, Scratch};
use serde_json::Value;
use std::path::Path;
use subdiv_interp::verify::{candidate_limit_points, nearest_gap};
use subdiv_mesh::Mesh;
use subdiv_stencil::LoopBeta;
use subdiv_stencil::Scheme;

fn load(path: &Path) -> Mesh {
    Mesh::from_soup(subdiv_io::read_mesh(path).unwrap()).unwrap().0
}

fn run(args: &[&str]) -> (Option<i32>, String) {
    let out = subdiv(args);
    assert_no_panic(&out);
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn fair_writes_control_meshes_whose_error_checks_out_independently() {
    let scratch = Scratch::new("fair");
    for (input, extra, plain, vertices_per) in [
        ("quad/spot_control_mesh.obj", vec![], Scheme::CatmullClark, "V+E+F"),
        ("open/halftunnel.off", vec!["--refine", "2"], Scheme::CatmullClark, ""),
        ("tri/eight.off", vec!["--scheme", "loop"], Scheme::Loop(LoopBeta::Loop), "V+E"),
        ("poly/P.off", vec!["--scheme", "doo-sabin"], Scheme::DooSabin, "H"),
        ("poly/mpi.off", vec!["--refine", "0"], Scheme::CatmullClark, "V"),
    ] {
        let input_path = fixtures().join(input);
        let stem = format!("fair-{}-{}", input.replace('/', "-"), extra.join(""));
        let (control, report) = (scratch.path(&format!("{stem}.obj")), scratch.path(&format!("{stem}.json")));
        let mut args = vec![
            "interpolate",
            input_path.to_str().unwrap(),
            "--method",
            "fair",
            "-o",
            control.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ];
        args.extend(&extra);
        let (code, stderr) = run(&args);
        assert_eq!(code, Some(0), "{input} {extra:?}: {stderr}");
        let report: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        assert_eq!(report["method"], "fair");
        let reported = report["error"]["max_rel"].as_f64().unwrap();
        assert!(reported <= 1e-6, "{input}: reported {reported:e}");
        let data = load(&input_path);
        let written = load(&control);
        let t = data.topology();
        let expected = match vertices_per {
            "V+E+F" => Some(t.vertex_count() + t.edge_count() + t.face_count()),
            "V+E" => Some(t.vertex_count() + t.edge_count()),
            "H" => Some(
                t.half_edge_count()
                    + 2 * (0..t.edge_count()).filter(|&e| t.is_boundary_edge(subdiv_mesh::EdgeId(e as u32))).count(),
            ),
            "V" => Some(t.vertex_count()),
            _ => None,
        };
        if let Some(n) = expected {
            assert_eq!(written.topology().vertex_count(), n, "{input}: control mesh size");
        }
        let gap =
            nearest_gap(data.positions(), &candidate_limit_points(&written, plain).unwrap(), data.bbox_diagonal());
        assert!(gap <= 1e-6, "{input} {extra:?}: independent error {gap:e}");
        eprintln!("fair {input} {extra:?}: reported {reported:.2e}, independent {gap:.2e}");
    }
}

#[test]
fn a_fairness_weight_approximates_and_is_reported_not_refused() {
    let scratch = Scratch::new("fair");
    let spot = fixtures().join("quad/spot_control_mesh.obj");
    let report = scratch.path("weighted.json");
    let (code, stderr) = run(&[
        "interpolate",
        spot.to_str().unwrap(),
        "--method",
        "fair",
        "--fairness-weight",
        "0.01",
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert!(report["error"]["max_rel"].as_f64().unwrap() > 1e-6, "{report}");
    assert_eq!(report["parameters"]["fairness_weight"], 0.01);
}

#[test]
fn fair_flags_are_refused_where_they_do_not_apply() {
    let scratch = Scratch::new("fair");
    let spot = fixtures().join("quad/spot_control_mesh.obj");
    let spot = spot.to_str().unwrap();
    let out = scratch.path("never.obj");
    let _ = std::fs::remove_file(&out);
    let o = out.to_str().unwrap();
    for (args, needle) in [
        (vec!["--method", "cheng", "--refine", "2"], "--refine applies to --method fair only"),
        (vec!["--method", "cheng", "--fairness-weight", "1"], "--fairness-weight applies to --method fair only"),
        (vec!["--method", "fair", "--fairness-weight=-1"], "--fairness-weight"),
        (vec!["--method", "fair", "--refine", "9"], "--refine"),
        (vec!["--method", "fair", "--scheme", "doo-sabin", "--refine", "2"], "--refine"),
        (vec!["--method", "fair", "--scheme", "loop"], "triangles"),
    ] {
        let mut all = vec!["interpolate", spot, "-o", o];
        all.extend(&args);
        let (code, stderr) = run(&all);
        assert_eq!(code, Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} wrote an output");
    }
}
