//! OpenSubdiv's option and hole tags through the command line: a file's own
//! `t interpolateboundary` (and the others) apply unless the command gives
//! the option; `t hole` faces are left out of refined surfaces and kept,
//! tagged, in control meshes; a control mesh written as OBJ carries the
//! options its surface needs, so that reading it back (as an OpenSubdiv-based
//! tool would, through its tags alone) gives the same limit points.

use crate::common::{read, run_ok, subdiv, Scratch};
use std::path::Path;
use subdiv_mesh::{DVec3, Mesh};
use subdiv_stencil::{limit_points_with_options, BoundaryInterpolation, Options, Scheme};

/// A 4×3 open grid with a bump, as OBJ text, with `extra` tag lines.
fn grid_obj(extra: &str) -> String {
    let mut text = String::new();
    for j in 0..=3 {
        for i in 0..=4 {
            let (x, y) = (f64::from(i), f64::from(j));
            text += &format!("v {x} {y} {}\n", 0.3 * (x * 1.3).sin() * (y * 0.9).cos());
        }
    }
    for j in 0..3 {
        for i in 0..4 {
            let v = |i: usize, j: usize| j * 5 + i + 1;
            text += &format!("f {} {} {} {}\n", v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
        }
    }
    text + extra
}

fn write(scratch: &Scratch, name: &str, text: &str) -> std::path::PathBuf {
    let path = scratch.path(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn faces(path: &Path) -> usize {
    read(path).faces.len()
}

#[test]
fn the_files_boundary_option_applies_unless_the_command_gives_one() {
    let scratch = Scratch::new("osd-options");
    let with_tag = write(&scratch, "edge_only.obj", &grid_obj("t interpolateboundary 1/0/0 2\n"));
    let plain = write(&scratch, "plain.obj", &grid_obj(""));
    let limit = |input: &Path, extra: &[&str], name: &str| {
        let out = scratch.path(name);
        let mut args =
            vec!["subdivide", input.to_str().unwrap(), "--scheme", "catmull-clark", "--levels", "0", "--limit"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", out.to_str().unwrap()]);
        run_ok(&args);
        read(&out).positions
    };
    let tagged = limit(&with_tag, &[], "a.obj");
    let edge_only = limit(&plain, &["--boundary", "edge-only"], "b.obj");
    let default = limit(&plain, &[], "c.obj");
    let overridden = limit(&with_tag, &["--boundary", "edge-and-corner"], "d.obj");
    assert_eq!(tagged, edge_only, "the file's edge-only");
    assert_eq!(overridden, default, "the command's option wins");
    assert_ne!(tagged, default, "the corners differ under the two options");
}

#[test]
fn holes_are_left_out_of_surfaces_and_kept_in_control_meshes() {
    let scratch = Scratch::new("osd-options");
    // Faces 5 and 6 (0-based) are holes.
    let input = write(&scratch, "holes.obj", &grid_obj("t hole 2/0/0 5 6\n"));
    let surface = scratch.path("holes_surface.obj");
    run_ok(&[
        "subdivide",
        input.to_str().unwrap(),
        "--scheme",
        "catmull-clark",
        "--levels",
        "2",
        "-o",
        surface.to_str().unwrap(),
    ]);
    assert_eq!(faces(&surface), (12 - 2) * 16);
    let soup = read(&surface);
    assert_eq!(soup.positions.len(), 17 * 13, "every vertex of level 2 is kept, numbered as on the level");
    // The same points as without the holes: a hole moves nothing.
    let plain = write(&scratch, "no_holes.obj", &grid_obj(""));
    let plain_surface = scratch.path("no_holes_surface.obj");
    run_ok(&[
        "subdivide",
        plain.to_str().unwrap(),
        "--scheme",
        "catmull-clark",
        "--levels",
        "2",
        "-o",
        plain_surface.to_str().unwrap(),
    ]);
    assert_eq!(read(&plain_surface).positions, soup.positions);

    let control = scratch.path("holes_control.obj");
    let surface = scratch.path("holes_interp_surface.obj");
    run_ok(&[
        "interpolate",
        input.to_str().unwrap(),
        "--method",
        "cheng",
        "-o",
        control.to_str().unwrap(),
        "--surface",
        surface.to_str().unwrap(),
        "--levels",
        "1",
    ]);
    let text = std::fs::read_to_string(&control).unwrap();
    assert!(text.lines().any(|l| l == "t hole 2/0/0 5 6"), "{text}");
    assert!(text.lines().any(|l| l == "t interpolateboundary 1/0/0 1"), "the open mesh's boundary option: {text}");
    assert_eq!(faces(&control), 12);
    assert_eq!(faces(&surface), 10 * 4);
    // Methods whose control mesh cannot keep the holes refuse rather than lose them.
    let refused =
        subdiv(&["interpolate", input.to_str().unwrap(), "--method", "nasri", "-o", control.to_str().unwrap()]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("hole"), "{}", String::from_utf8_lossy(&refused.stderr));
}

#[test]
fn a_control_mesh_carries_the_options_of_its_surface() {
    let scratch = Scratch::new("osd-options");
    // An edge-only boundary and Chaikin creasing given on the command line: the control mesh's
    // limit points, computed from the written file's tags alone, are the input's vertices.
    let input = write(&scratch, "for_control.obj", &grid_obj("t crease 2/1/0 6 7 1.5\nt crease 2/1/0 7 8 2.5\n"));
    let control = scratch.path("control.obj");
    run_ok(&[
        "interpolate",
        input.to_str().unwrap(),
        "--method",
        "cheng",
        "--boundary",
        "edge-only",
        "--crease-method",
        "chaikin",
        "-o",
        control.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&control).unwrap();
    for line in ["t interpolateboundary 1/0/0 2", "t creasemethod 0/0/1 chaikin"] {
        assert!(text.lines().any(|l| l == line), "{line} not in {text}");
    }
    let written = subdiv_io::load_mesh(&control).unwrap();
    let file = written.tags().options();
    let options = Options::new(Scheme::CatmullClark)
        .with_boundary(file.boundary.unwrap_or(BoundaryInterpolation::EdgeAndCorner))
        .with_crease_method(file.crease_method.unwrap_or_default());
    let limits =
        limit_points_with_options(written.topology(), written.tags(), options, written.positions()).unwrap().unwrap();
    let original: Mesh = subdiv_io::load_mesh(&input).unwrap();
    let d = original.bbox_diagonal();
    let error = (limits.iter().zip(original.positions()))
        .map(|(a, b): (&DVec3, &DVec3)| (*a - *b).length() / d)
        .fold(0.0, f64::max);
    assert!(error < 1e-6, "{error:.2e}·d");
}

/// `--dart-limit`: OpenSubdiv 3.6.0's own limit positions of its shapes with darts
/// (fixtures/opensubdiv/reference, `Far::PrimvarRefiner::Limit`) are what `smooth-mask` gives
/// at every vertex, darts included; the default (`exact`, the limit of refinement) differs from
/// them at the darts only.
#[test]
fn dart_limit_smooth_mask_is_opensubdivs_limit_stencil() {
    let scratch = Scratch::new("osd-options");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/opensubdiv");
    for shape in ["catmark_inf_crease0", "catmark_cubes_infsharp", "loop_cubes_infsharp"] {
        let input = root.join(format!("shapes/{shape}.obj"));
        let scheme = if shape.starts_with("loop") { "loop" } else { "catmull-clark" };
        let reference: Vec<DVec3> = std::fs::read_to_string(root.join(format!("reference/{shape}/limit.txt")))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| {
                let x: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
                DVec3::new(x[0], x[1], x[2])
            })
            .collect();
        let limits = |dart: &str| {
            let out = scratch.path(&format!("{shape}-{dart}.obj"));
            let (input, out_s) = (input.display().to_string(), out.display().to_string());
            // OpenSubdiv's harness: the file's boundary option, else edge-only.
            let own = std::fs::read_to_string(&input).unwrap().contains("t interpolateboundary");
            let boundary: &[&str] = if own { &[] } else { &["--boundary", "edge-only"] };
            let args = ["subdivide", &input, "--scheme", scheme, "--levels", "0", "--limit"];
            run_ok(&[&args[..], boundary, &["--dart-limit", dart, "-o", &out_s]].concat());
            read(&out).positions
        };
        let (mask, exact) = (limits("smooth-mask"), limits("exact"));
        let d = Mesh::from_soup(read(&input)).unwrap().0.bbox_diagonal();
        let apart = |a: &[DVec3], v: usize| (a[v] - reference[v]).length() / d;
        assert_eq!(mask.len(), reference.len(), "{shape}");
        let mask_worst = (0..mask.len()).map(|v| apart(&mask, v)).fold(0.0, f64::max);
        assert!(mask_worst <= 1e-12, "{shape}: smooth-mask {mask_worst:.2e}·d from OpenSubdiv");
        let differing = (0..exact.len()).filter(|&v| apart(&exact, v) > 1e-9).count();
        assert!(
            (1..=4).contains(&differing),
            "{shape}: exact differs from OpenSubdiv at {differing} vertices (the darts)"
        );
    }
    // A bad value is bad input.
    let out =
        subdiv(&["subdivide", "x.obj", "--scheme", "loop", "--levels", "1", "--dart-limit", "sharp", "-o", "y.obj"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("exact, smooth-mask"), "{:?}", out);
}
