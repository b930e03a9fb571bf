//! `subdiv interpolate --method cheng --scheme sqrt3|loop` as a process: the
//! control mesh it writes has the data as limit points of its scheme,
//! checked from the written file alone (the stencil crate's limit points,
//! never the report); the report names the scheme; `subdiv subdivide
//! --scheme sqrt3` refines; refusals exit 2 with the remedy and write nothing.

use crate::common::{assert_no_panic, fixtures, run_ok, subdiv, Scratch};
use serde_json::Value;
use std::path::Path;
use subdiv_mesh::{DVec3, Mesh};
use subdiv_stencil::{LoopBeta, Scheme};

fn load(path: &Path) -> Mesh {
    Mesh::from_soup(subdiv_io::read_mesh(path).unwrap()).unwrap().0
}

/// max over the data of |limit point of the written control vertex − data| / d.
fn independent_error(data: &Mesh, control: &Mesh, scheme: Scheme) -> f64 {
    let limits =
        subdiv_stencil::limit_points_with_options(control.topology(), control.tags(), scheme, control.positions())
            .unwrap()
            .unwrap();
    let d = data.bbox_diagonal();
    data.positions().iter().zip(&limits).map(|(p, l): (&DVec3, &DVec3)| p.distance(*l) / d).fold(0.0, f64::max)
}

#[test]
fn cheng_with_sqrt3_and_loop_writes_control_meshes_that_check_out() {
    let scratch = Scratch::new("cheng-schemes");
    for (input, scheme, extra) in [
        ("canonical/icosphere_2.obj", Scheme::Sqrt3, vec![]),
        ("open/hemisphere.off", Scheme::Sqrt3, vec![]),
        ("canonical/icosahedron.obj", Scheme::Sqrt3, vec!["--surface", "surface.obj", "--levels", "2"]),
        ("open/hemisphere.off", Scheme::Loop(LoopBeta::Loop), vec!["--beta", "loop"]),
    ] {
        let input_path = fixtures().join(input);
        let stem = format!("{}-{}", input.replace('/', "-"), extra.join(""));
        let control = scratch.path(&format!("{stem}.obj"));
        let report = scratch.path(&format!("{stem}.json"));
        let surface = scratch.path(&format!("{stem}.surface.obj"));
        let extra: Vec<&str> =
            extra.iter().map(|&a| if a == "surface.obj" { surface.to_str().unwrap() } else { a }).collect();
        let mut args = vec![
            "interpolate",
            input_path.to_str().unwrap(),
            "--method",
            "cheng",
            "--scheme",
            scheme.name(),
            "-o",
            control.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ];
        args.extend(&extra);
        run_ok(&args);
        let report: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        assert_eq!(report["method"], "cheng");
        assert_eq!(report["control_scheme"], scheme.name());
        let reported = report["error"]["max_rel"].as_f64().unwrap();
        assert!(reported <= 1e-6, "{input}: reported {reported:e}");
        let (data, written) = (load(&input_path), load(&control));
        assert_eq!(written.topology().faces(), data.topology().faces(), "{input}: the input's topology");
        let independent = independent_error(&data, &written, scheme);
        assert!(independent <= 1e-6, "{input}, {scheme}: independent error {independent:e}");
        if extra.contains(&"--surface") {
            // Two √3 steps on a closed mesh: V + F, then 3F faces, twice.
            let (v, f) = (data.topology().vertex_count(), data.topology().face_count());
            let s = load(&surface);
            assert_eq!((s.topology().vertex_count(), s.topology().face_count()), (v + f + 3 * f, 9 * f));
        }
    }
}

#[test]
fn subdivide_with_sqrt3_refines() {
    let scratch = Scratch::new("cheng-schemes");
    let ico = fixtures().join("canonical/icosahedron.obj");
    let out = scratch.path("ico-sqrt3-2.obj");
    run_ok(&["subdivide", ico.to_str().unwrap(), "--scheme", "sqrt3", "--levels", "2", "-o", out.to_str().unwrap()]);
    let refined = load(&out);
    // 12 + 20 = 32 vertices and 60 faces after one step, 32 + 60 and 180 after two.
    assert_eq!((refined.topology().vertex_count(), refined.topology().face_count()), (92, 180));
}

#[test]
fn refusals_exit_2_name_the_remedy_and_write_nothing() {
    let scratch = Scratch::new("cheng-schemes");
    let quads = fixtures().join("canonical/cube_quad.obj");
    let ico = fixtures().join("canonical/icosahedron.obj");
    let out = scratch.path("never.obj");
    let _ = std::fs::remove_file(&out);
    for (input, args, needles) in [
        (&quads, vec!["--method", "cheng", "--scheme", "sqrt3"], vec!["triangles", "deng-wang", "--triangulate"]),
        (&quads, vec!["--method", "cheng", "--scheme", "loop"], vec!["triangles", "deng-wang", "--triangulate"]),
        (&ico, vec!["--method", "cheng", "--scheme", "doo-sabin"], vec!["--scheme", "--method nasri"]),
        (&ico, vec!["--method", "cheng", "--scheme", "deng-ma"], vec!["--method deng-ma"]),
        (
            &ico,
            vec!["--method", "nasri", "--scheme", "loop"],
            vec!["--scheme applies to --method cheng and --method fair"],
        ),
        (&ico, vec!["--method", "cheng", "--scheme", "sqrt3", "--beta", "loop"], vec!["--beta applies to"]),
    ] {
        let mut all = vec!["interpolate", input.to_str().unwrap(), "-o", out.to_str().unwrap()];
        all.extend(&args);
        let run = subdiv(&all);
        assert_no_panic(&run);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        for needle in needles {
            assert!(stderr.contains(needle), "{args:?}: {stderr} lacks {needle:?}");
        }
        assert!(!out.exists(), "{args:?} wrote an output");
    }
    // The remedy the refusal names works: triangulate, then interpolate.
    let triangulated = scratch.path("cube-triangulated.obj");
    let t = triangulated.to_str().unwrap();
    run_ok(&["subdivide", quads.to_str().unwrap(), "--scheme", "sqrt3", "--triangulate", "--levels", "0", "-o", t]);
    let control = scratch.path("cube-triangulated-control.obj");
    run_ok(&["interpolate", t, "--method", "cheng", "--scheme", "sqrt3", "-o", control.to_str().unwrap()]);
    let independent = independent_error(&load(&triangulated), &load(&control), Scheme::Sqrt3);
    assert!(independent <= 1e-6, "{independent:e}");
}
