//! Issue #14, classes 1 and 2: exit 0 only if every written number is finite
//! and the error, measured independently on the written control mesh, is at
//! most `--tol`; otherwise exit 2 or 3 with nothing written. Inputs: valid,
//! finite meshes with extreme coordinates, coincident vertices, isolated
//! vertices, extreme parameters.

use crate::common::{assert_no_panic, fixtures, subdiv, Scratch};
use std::fs;
use std::path::{Path, PathBuf};
use subdiv_interp::verify::{candidate_limit_points, nearest_gap};
use subdiv_mesh::{DVec3, Mesh, PowerOfTwoScale};
use subdiv_stencil::LoopBeta;
use subdiv_stencil::Scheme;

/// A tetrahedron with its coordinates mapped by `f`, as OBJ in `scratch`.
fn tetrahedron(scratch: &Scratch, name: &str, f: impl Fn(DVec3) -> DVec3) -> PathBuf {
    let corners = [DVec3::new(0.0, 0.0, 0.0), DVec3::X, DVec3::Y, DVec3::new(0.3, 0.2, 1.0)];
    let mut text = String::new();
    for p in corners.map(f) {
        text += &format!("v {:e} {:e} {:e}\n", p.x, p.y, p.z);
    }
    text += "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    let path = scratch.path(&format!("{name}.obj"));
    fs::write(&path, text).unwrap();
    path
}

fn plain(method: &str) -> Scheme {
    match method {
        "cheng" => Scheme::CatmullClark,
        "deng-wang" => Scheme::Loop(LoopBeta::Loop),
        "deng-ma" => Scheme::DengMa(Default::default()),
        _ => Scheme::DooSabin,
    }
}

fn load(path: &Path) -> Mesh {
    Mesh::from_soup(subdiv_io::read_mesh(path).unwrap()).unwrap().0
}

/// Runs one command and checks the rule; returns the exit code.
fn check(args: &[&str], output: &Path, verify: impl FnOnce(&Path)) -> i32 {
    let _ = fs::remove_file(output);
    let out = subdiv(args);
    assert_no_panic(&out);
    let code = out.status.code().unwrap_or(-1);
    let stderr = String::from_utf8_lossy(&out.stderr);
    match code {
        0 => verify(output),
        2 | 3 => {
            assert!(!output.exists(), "{args:?}: exit {code} but {} was written", output.display());
            assert_eq!(stderr.trim_end().lines().filter(|l| l.contains("error")).count(), 1, "{args:?}: {stderr}");
        }
        other => panic!("{args:?}: exit {other}: {stderr}"),
    }
    code
}

/// Every coordinate of the written mesh is finite.
fn assert_finite(path: &Path) -> Mesh {
    let mesh = load(path);
    assert!(mesh.positions().iter().all(|p| p.is_finite()), "{}: non-finite output", path.display());
    mesh
}

/// The written control mesh interpolates the data within `tol`, measured
/// independently (on data scaled by a power of two, so that no distance overflows).
fn assert_interpolates(data: &Path, control: &Path, method: &str, tol: f64) {
    let written = assert_finite(control);
    let data = load(data);
    let scale = PowerOfTwoScale::normalizing(data.positions().iter().copied());
    let scaled = |m: &Mesh| {
        let mut p = m.positions().to_vec();
        scale.apply_points(&mut p);
        m.with_positions(p)
    };
    let (data, written) = (scaled(&data), scaled(&written));
    let d = data.bbox_diagonal();
    let gap = nearest_gap(data.positions(), &candidate_limit_points(&written, plain(method)).unwrap(), d);
    assert!(gap <= tol * (1.0 + 1e-9), "{method} {}: independent error {gap:e}·d", control.display());
}

const METHODS: [&str; 6] = ["nasri", "zheng-cai", "cheng", "fan-cheng-lai", "deng-wang", "deng-ma"];

fn extreme_meshes(scratch: &Scratch) -> Vec<PathBuf> {
    vec![
        tetrahedron(scratch, "x-1.7e308", |p| if p == DVec3::X { DVec3::new(1.7e308, 0.0, 0.0) } else { p }),
        tetrahedron(scratch, "x-1e308", |p| if p == DVec3::X { DVec3::new(1e308, 0.0, 0.0) } else { p }),
        tetrahedron(scratch, "all-1e154", |p| p * 1e154),
        tetrahedron(scratch, "all-1.3e308", |p| p * 1.3e308),
        tetrahedron(scratch, "all-1e-300", |p| p * 1e-300),
        tetrahedron(scratch, "translated-1e12", |p| p + DVec3::splat(1e12)),
        tetrahedron(scratch, "coincident", |_| DVec3::splat(2.5)),
        tetrahedron(scratch, "coincident-huge", |_| DVec3::splat(1e308)),
    ]
}

#[test]
fn interpolation_of_extreme_coordinates_is_finite_and_within_tol_or_refused() {
    let scratch = Scratch::new("numeric");
    let control = scratch.path("control.obj");
    for mesh in extreme_meshes(&scratch) {
        for method in METHODS {
            let m = mesh.to_str().unwrap();
            let args = ["interpolate", m, "--method", method, "-o", control.to_str().unwrap(), "--levels", "1"];
            let code = check(&args, &control, |c| {
                if method == "deng-ma" {
                    assert_finite(c);
                } else {
                    assert_interpolates(&mesh, c, method, 1e-6);
                }
            });
            eprintln!("{method} on {}: exit {code}", mesh.display());
        }
    }
}

#[test]
fn subdivision_of_extreme_coordinates_is_finite_or_refused() {
    let scratch = Scratch::new("numeric");
    let out = scratch.path("refined.obj");
    for mesh in extreme_meshes(&scratch) {
        for scheme in ["catmull-clark", "loop", "doo-sabin", "deng-ma"] {
            for limit in [false, true] {
                if limit && scheme == "deng-ma" {
                    continue;
                }
                let m = mesh.to_str().unwrap();
                let mut args = vec!["subdivide", m, "--scheme", scheme, "--levels", "2", "--normals", "-o"];
                args.push(out.to_str().unwrap());
                if limit {
                    args.push("--limit");
                }
                let code = check(&args, &out, |o| {
                    assert_finite(o);
                });
                eprintln!("{scheme} limit={limit} on {}: exit {code}", mesh.display());
            }
        }
    }
}

#[test]
fn isolated_vertices_and_extreme_parameters_never_pass_with_a_large_error() {
    let scratch = Scratch::new("numeric");
    let control = scratch.path("iso-control.obj");
    let isolated = fixtures().join("bad/isolated_vertices.obj");
    for method in METHODS {
        let args = ["interpolate", isolated.to_str().unwrap(), "--method", method, "-o", control.to_str().unwrap()];
        check(&args, &control, |c| {
            if method != "deng-ma" {
                // Isolated vertices have no limit point: what is interpolated are the others.
                let data = load(&isolated);
                let t = data.topology();
                let used: Vec<DVec3> = t.vertices().filter(|&v| !t.is_isolated(v)).map(|v| data.position(v)).collect();
                let written = assert_finite(c);
                let gap =
                    nearest_gap(&used, &candidate_limit_points(&written, plain(method)).unwrap(), data.bbox_diagonal());
                assert!(gap <= 1e-6, "{method}: {gap:e}");
            }
        });
    }
    let cube = fixtures().join("canonical/cube_quad.obj");
    for value in ["1e12", "1e200", "1e-300"] {
        let handles = scratch.path("handles.txt");
        fs::write(&handles, format!("0 {value}\n3 {value}\n")).unwrap();
        let args = [
            "interpolate",
            cube.to_str().unwrap(),
            "--method",
            "zheng-cai",
            "--handles",
            handles.to_str().unwrap(),
            "-o",
            control.to_str().unwrap(),
        ];
        let code = check(&args, &control, |c| assert_interpolates(&cube, c, "zheng-cai", 1e-6));
        eprintln!("zheng-cai handles {value}: exit {code}");
    }
    let tri = fixtures().join("canonical/octahedron.obj");
    for mu in ["1e300", "-1e300", "1e6"] {
        let args = [
            "interpolate",
            tri.to_str().unwrap(),
            "--method",
            "deng-wang",
            "--mu",
            mu,
            "-o",
            control.to_str().unwrap(),
        ];
        let code = check(&args, &control, |c| assert_interpolates(&tri, c, "deng-wang", 1e-6));
        eprintln!("deng-wang mu {mu}: exit {code}");
    }
}
