//! `subdiv sample`, `subdiv project` and `subdiv fit` end to end: samples
//! project back onto the surface they came from, n-gon domains are named
//! `FACE.K`, fitting a mesh's own limit surface keeps it there, bad input
//! exits 2 naming the problem.

use crate::common::{assert_no_panic, fixtures, read, run_ok, subdiv, Scratch};

fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn samples_project_back_onto_their_surface() {
    let scratch = Scratch::new("spf");
    for (mesh, scheme, per_domain) in [
        ("canonical/cube_quad.obj", "catmull-clark", 4usize),
        ("canonical/pyramid_mixed.obj", "catmull-clark", 3),
        ("canonical/icosahedron.obj", "loop", 3),
    ] {
        let mesh = fixtures().join(mesh);
        let cloud = scratch.path(&format!("{scheme}-{per_domain}.ply"));
        run_ok(&["sample", s(&mesh), "--scheme", scheme, "--per-face", &per_domain.to_string(), "-o", s(&cloud)]);
        let points = read(&cloud).positions;
        let control = read(&mesh);
        assert!(points.len() >= control.faces.len() * per_domain * per_domain, "{}", points.len());
        let out = scratch.path(&format!("{scheme}-{per_domain}.txt"));
        run_ok(&["project", s(&mesh), "--scheme", scheme, "--points", s(&cloud), "-o", s(&out)]);
        let text = std::fs::read_to_string(&out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), points.len());
        for (line, p) in lines.iter().zip(&points) {
            let f: Vec<&str> = line.split_whitespace().collect();
            assert_eq!(f.len(), 7, "{line}");
            let x: Vec<f64> = f[3..6].iter().map(|v| v.parse().unwrap()).collect();
            let distance: f64 = f[6].parse().unwrap();
            assert!(distance < 1e-9, "{line}");
            assert!((glam::DVec3::new(x[0], x[1], x[2]) - *p).length() < 1e-9);
        }
        if mesh.ends_with("pyramid_mixed.obj") {
            // The pyramid's n-gon base has one domain per corner.
            assert!(lines.iter().any(|l| l.split_whitespace().next().unwrap().contains('.')));
        }
    }
}

#[test]
fn area_samples_are_reproducible() {
    let scratch = Scratch::new("spf");
    let mesh = fixtures().join("canonical/torus_quad_16x8.obj");
    let a = scratch.path("area-a.ply");
    let b = scratch.path("area-b.ply");
    run_ok(&["sample", s(&mesh), "--scheme", "catmull-clark", "--count", "500", "--seed", "3", "-o", s(&a)]);
    run_ok(&["sample", s(&mesh), "--scheme", "catmull-clark", "--count", "500", "--seed", "3", "-o", s(&b)]);
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert_eq!(read(&a).positions.len(), 500);
}

#[test]
fn fitting_a_limit_surface_keeps_it() {
    let scratch = Scratch::new("spf");
    let mesh = fixtures().join("canonical/cube_quad.obj");
    let target = scratch.path("cube-limit.obj");
    run_ok(&["subdivide", s(&mesh), "--scheme", "catmull-clark", "--levels", "2", "--limit", "-o", s(&target)]);
    let fitted = scratch.path("cube-fitted.obj");
    let report = scratch.path("cube-fit.json");
    let run = subdiv(&[
        "fit",
        s(&target),
        "--control",
        s(&mesh),
        "--scheme",
        "catmull-clark",
        "--iterations",
        "3",
        "-o",
        s(&fitted),
        "--report",
        s(&report),
    ]);
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("fit:"), "{stdout}");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let rounds = json["iterations"].as_array().unwrap();
    assert!(!rounds.is_empty());
    let last = rounds.last().unwrap();
    assert!(last["max_target_to_surface_rel"].as_f64().unwrap() < 1e-9, "{last}");
    let (a, b) = (read(&mesh), read(&fitted));
    assert_eq!(a.faces, b.faces);
    for (p, q) in a.positions.iter().zip(&b.positions) {
        assert!((*p - *q).length() < 1e-6, "{p} {q}");
    }
}

#[test]
fn bad_input_exits_2() {
    let scratch = Scratch::new("spf");
    let mesh = fixtures().join("canonical/cube_quad.obj");
    let xyz = scratch.path("bad.xyz");
    std::fs::write(&xyz, "0 0 0\n1 2 x\n").unwrap();
    let out = scratch.path("bad.txt");
    for args in [
        vec!["project", s(&mesh), "--scheme", "catmull-clark", "--points", s(&xyz), "-o", s(&out)],
        vec!["sample", s(&mesh), "--scheme", "deng-ma", "--per-face", "2", "-o", "x.ply"],
        vec!["sample", s(&mesh), "--scheme", "catmull-clark", "--per-face", "2", "--count", "5", "-o", "x.ply"],
        vec!["sample", s(&mesh), "--scheme", "catmull-clark", "--per-face", "0", "-o", "x.ply"],
        vec!["sample", s(&mesh), "--scheme", "catmull-clark", "--per-face", "2", "-o", "x.stl"],
    ] {
        let run = subdiv(&args);
        assert_no_panic(&run);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&run.stderr));
    }
    let run = subdiv(&["project", s(&mesh), "--scheme", "catmull-clark", "--points", s(&xyz), "-o", s(&out)]);
    assert!(String::from_utf8_lossy(&run.stderr).contains("bad.xyz:2"), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(!out.exists());
}
