//! `subdiv fit` (issue #42 and the hardening issue's fit items): bad options
//! exit 2, extreme scales give a correct finite result or a refusal that
//! says why, the report names the method, the stopping rule, the history and
//! the regularised vertices, `--quiet` prints nothing.

use crate::common::{assert_no_panic, fixtures, read, run_ok, subdiv, Scratch};

fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

/// The cube's level-3 limit tessellation scaled by `scale`, and the cube
/// scaled and moved off its limit (every vertex by 2 % of d).
fn scaled_pair(scratch: &Scratch, name: &str, scale: f64) -> (std::path::PathBuf, std::path::PathBuf) {
    let mesh = fixtures().join("canonical/cube_quad.obj");
    let limit = scratch.path(&format!("{name}-limit.obj"));
    run_ok(&["subdivide", s(&mesh), "--scheme", "catmull-clark", "--levels", "3", "--limit", "-o", s(&limit)]);
    let write = |soup: &subdiv_mesh::PolygonSoup, path: &std::path::Path, nudge: bool| {
        let mut text = String::new();
        for (k, p) in soup.positions.iter().enumerate() {
            let off = if nudge { 0.02 * 3f64.sqrt() * 2.0 * [0.5, -0.3, 0.8][k % 3] } else { 0.0 };
            let q = (*p + glam::DVec3::new(off, -off, 0.5 * off)) * scale;
            text.push_str(&format!("v {:e} {:e} {:e}\n", q.x, q.y, q.z));
        }
        for f in soup.faces.iter() {
            text.push('f');
            for v in f {
                text.push_str(&format!(" {}", v + 1));
            }
            text.push('\n');
        }
        std::fs::write(path, text).unwrap();
    };
    let target = scratch.path(&format!("{name}-target.obj"));
    let start = scratch.path(&format!("{name}-start.obj"));
    write(&read(&limit), &target, false);
    write(&read(&mesh), &start, true);
    (target, start)
}

#[test]
fn bad_options_exit_2() {
    let scratch = Scratch::new("fit_options");
    let (target, start) = scaled_pair(&scratch, "bad", 1.0);
    let out = scratch.path("bad-out.obj");
    for (flag, value) in [
        ("--tolerance", "NaN"),
        ("--tolerance", "-1"),
        ("--smoothness", "NaN"),
        ("--smoothness", "-1"),
        ("--smoothness", "inf"),
        ("--min-improvement", "NaN"),
        ("--max-time", "0"),
        ("--max-time", "NaN"),
        ("--lambda", "NaN"),
        ("--method", "newton"),
        ("--loss", "tukey"),
    ] {
        let mut args = vec!["fit", s(&target), "--control", s(&start), "--scheme", "catmull-clark", "-o", s(&out)];
        args.extend([flag, value]);
        if flag == "--lambda" {
            args.extend(["--method", "tangent"]);
        }
        let run = subdiv(&args);
        assert_no_panic(&run);
        assert_eq!(run.status.code(), Some(2), "{flag} {value}: {}", String::from_utf8_lossy(&run.stderr));
        assert!(!out.exists(), "{flag} {value}: an output was written");
    }
}

#[test]
fn extreme_scales_give_finite_correct_results() {
    let scratch = Scratch::new("fit_options");
    for (name, scale) in [("big", 1e150), ("tiny", 1e-200), ("unit", 1.0)] {
        let (target, start) = scaled_pair(&scratch, name, scale);
        let out = scratch.path(&format!("{name}-fitted.obj"));
        let report = scratch.path(&format!("{name}-report.json"));
        let run = subdiv(&[
            "fit",
            s(&target),
            "--control",
            s(&start),
            "--scheme",
            "catmull-clark",
            "-o",
            s(&out),
            "--report",
            s(&report),
        ]);
        assert_no_panic(&run);
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert_eq!(run.status.code(), Some(0), "{name}: {}", String::from_utf8_lossy(&run.stderr));
        assert!(!stdout.contains("NaN") && !stdout.contains("inf"), "{name}: {stdout}");
        assert!(!stdout.contains(" 0 rounds"), "{name}: {stdout}");
        let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        let last = json["iterations"].as_array().unwrap().last().unwrap().clone();
        let rel = last["max_target_to_surface_rel"].as_f64().unwrap();
        assert!(rel <= 1e-6, "{name}: {rel}");
        assert!(json["scale"].as_f64().unwrap() > 0.0);
        assert_eq!(json["method"], "gauss-newton");
        assert!(json["stop"].is_string());
        let fitted = read(&out);
        let started = read(&start);
        assert!(fitted.positions.iter().all(|p| p.is_finite()));
        assert_ne!(fitted.positions, started.positions, "{name}: the mesh did not move");
    }
}

#[test]
fn an_unrepresentable_target_is_refused_saying_why() {
    let scratch = Scratch::new("fit_options");
    // A point cloud: an OBJ file without faces.
    let target = scratch.path("huge.obj");
    std::fs::write(&target, "v -1.7e308 -1.7e308 -1.7e308\nv 1.7e308 1.7e308 1.7e308\nv 1.7e308 0 0\n").unwrap();
    let control = fixtures().join("canonical/cube_quad.obj");
    let out = scratch.path("huge-out.obj");
    let run = subdiv(&["fit", s(&target), "--control", s(&control), "--scheme", "catmull-clark", "-o", s(&out)]);
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("not representable"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn report_and_quiet() {
    let scratch = Scratch::new("fit_options");
    let (target, start) = scaled_pair(&scratch, "report", 1.0);
    let out = scratch.path("report-fitted.obj");
    let report = scratch.path("report.json");
    let run = subdiv(&[
        "--quiet",
        "fit",
        s(&target),
        "--control",
        s(&start),
        "--scheme",
        "catmull-clark",
        "--loss",
        "huber",
        "--max-time",
        "60",
        "-o",
        s(&out),
        "--report",
        s(&report),
    ]);
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(run.stdout.is_empty(), "{}", String::from_utf8_lossy(&run.stdout));
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["loss"], "huber");
    assert!(json["regularised"]["count"].is_u64());
    let rounds = json["iterations"].as_array().unwrap();
    assert!(rounds.len() >= 2);
    for key in ["damping", "retries", "seconds", "solver", "rms_surface_to_target_rel"] {
        assert!(rounds[1].get(key).is_some(), "{key}");
    }
}
