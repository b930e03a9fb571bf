//! `subdiv evaluate` as a process: limit points at dyadic parameters equal
//! `subdiv subdivide --limit`'s vertices, the output layout (with and
//! without `--derivs`) matches the library, and bad parameter files fail
//! with exit 2, the line named and no output written.

use crate::common::{assert_no_panic, fixtures, numbers, read, subdiv, Scratch};

fn write(scratch: &Scratch, name: &str, text: &str) -> std::path::PathBuf {
    let p = scratch.path(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn face_points_match_subdivide_limit() {
    let scratch = Scratch::new("evaluate");
    let cube = fixtures().join("canonical/cube_quad.obj");
    let limit = scratch.path("cube-limit.obj");
    let run = subdiv(&[
        "subdivide",
        cube.to_str().unwrap(),
        "--scheme",
        "catmull-clark",
        "--levels",
        "1",
        "--limit",
        "-o",
        limit.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let refined = read(&limit);
    let control = read(&cube);
    let (nv, nf) = (control.positions.len(), control.faces.len());
    // Face point of face f is vertex nv + f of level 1, at (½, ½); corner 0 at (0, 0) is the vertex itself.
    let mut text = String::from("# face centres, then corner 0 of each face\n");
    for f in 0..nf {
        text.push_str(&format!("{f} 0.5 0.5\n"));
    }
    for f in 0..nf {
        text.push_str(&format!("{f} 0 0\n"));
    }
    let at = write(&scratch, "cube-at.txt", &text);
    let out = scratch.path("cube-out.txt");
    let run = subdiv(&[
        "evaluate",
        cube.to_str().unwrap(),
        "--scheme",
        "catmull-clark",
        "--at",
        at.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let rows = numbers(&out);
    assert_eq!(rows.len(), 2 * nf);
    for (f, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 6);
        let want =
            if f < nf { refined.positions[nv + f] } else { refined.positions[control.faces.face(f - nf)[0] as usize] };
        let got = glam::DVec3::new(row[0], row[1], row[2]);
        assert!((got - want).length() < 1e-12, "row {f}: {got} vs {want}");
        let n = glam::DVec3::new(row[3], row[4], row[5]);
        assert!((n.length() - 1.0).abs() < 1e-12);
    }
}

#[test]
fn derivatives_and_ngons_match_the_library() {
    let scratch = Scratch::new("evaluate");
    let mesh_path = fixtures().join("canonical/pyramid_mixed.obj");
    let mesh = subdiv_io::load_mesh(&mesh_path).unwrap();
    let surface =
        subdiv_eval::LimitSurface::new(&mesh, &subdiv_stencil::Options::new(subdiv_stencil::Scheme::CatmullClark))
            .unwrap();
    let mut text = String::new();
    let mut params = Vec::new();
    for d in surface.domains() {
        let n = surface.face_domains(d.face).len();
        let p = subdiv_eval::SurfaceParam::new(d.face, d.corner, 0.3, 0.7);
        text.push_str(&if n == 1 {
            format!("{} 0.3 0.7\n", d.face)
        } else {
            format!("{}.{} 0.3 0.7\n", d.face, d.corner)
        });
        params.push(p);
    }
    let at = write(&scratch, "pyramid-at.txt", &text);
    let out = scratch.path("pyramid-out.txt");
    let run = subdiv(&[
        "evaluate",
        mesh_path.to_str().unwrap(),
        "--scheme",
        "catmull-clark",
        "--at",
        at.to_str().unwrap(),
        "--derivs",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    for (row, p) in numbers(&out).iter().zip(&params) {
        assert_eq!(row.len(), 12);
        let s = surface.evaluate(mesh.positions(), *p).unwrap();
        let want: Vec<f64> = [s.position, s.normal, s.du, s.dv].iter().flat_map(|v| v.to_array()).collect();
        assert_eq!(row, &want, "{p:?}: the shortest round-trip text reads back to the same bits");
    }
}

#[test]
fn loop_on_triangles() {
    let scratch = Scratch::new("evaluate");
    let ico = fixtures().join("canonical/icosahedron.obj");
    let at = write(&scratch, "ico-at.txt", "0 0.2 0.3\n5 0 1\n");
    let out = scratch.path("ico-out.txt");
    let run = subdiv(&[
        "evaluate",
        ico.to_str().unwrap(),
        "--scheme",
        "loop",
        "--at",
        at.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(numbers(&out).len(), 2);
}

#[test]
fn doo_sabin_domains_are_face_corners() {
    let scratch = Scratch::new("evaluate");
    // (1,1) of every corner domain of a face is its centroid; (0,0) the vertex's limit point.
    let cube = fixtures().join("canonical/cube_quad.obj");
    let control = read(&cube);
    let at = write(&scratch, "ds-at.txt", "0.0 1 1\n0.3 1 1\n2.1 0 0\n");
    let out = scratch.path("ds-out.txt");
    let run = subdiv(&[
        "evaluate",
        cube.to_str().unwrap(),
        "--scheme",
        "doo-sabin",
        "--at",
        at.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let rows = numbers(&out);
    let face = control.faces.face(0);
    let centroid = face.iter().map(|&v| control.positions[v as usize]).sum::<glam::DVec3>() / face.len() as f64;
    for row in &rows[..2] {
        assert!((glam::DVec3::new(row[0], row[1], row[2]) - centroid).length() < 1e-12);
    }
    let limit = scratch.path("ds-limit.obj");
    let run = subdiv(&[
        "subdivide",
        cube.to_str().unwrap(),
        "--scheme",
        "doo-sabin",
        "--levels",
        "0",
        "--limit",
        "-o",
        limit.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let v = control.faces.face(2)[1] as usize;
    let want = read(&limit).positions[v];
    assert!((glam::DVec3::new(rows[2][0], rows[2][1], rows[2][2]) - want).length() < 1e-12);
}

#[test]
fn bad_parameters_fail_with_the_line_and_write_nothing() {
    let scratch = Scratch::new("evaluate");
    let pyramid = fixtures().join("canonical/pyramid_mixed.obj");
    let mesh = subdiv_io::load_mesh(&pyramid).unwrap();
    let ngon = (0..mesh.topology().face_count())
        .find(|&f| mesh.topology().face_size(subdiv_mesh::FaceId(f as u32)) != 4)
        .unwrap();
    let cube = fixtures().join("canonical/cube_quad.obj");
    for (mesh, scheme, text, needle) in [
        (&cube, "catmull-clark", "0 0.5 0.5\n0 0.5\n", ":2: expected"),
        (&cube, "catmull-clark", "# c\n0 1.5 0.5\n", ":2: parameter (1.5, 0.5) outside"),
        (&cube, "catmull-clark", "0 nan 0.5\n", ":1: parameter"),
        (&cube, "catmull-clark", "6 0.5 0.5\n", ":1: no domain 6.0"),
        (&cube, "catmull-clark", "0.1 0.5 0.5\n", ":1: no domain 0.1"),
        (&pyramid, "catmull-clark", &format!("{ngon} 0.5 0.5\n"), "give FACE.K"),
        (&cube, "loop", "0 0.5 0.5\n", "Loop subdivision needs a triangle mesh"),
        (&cube, "deng-ma", "0 0.5 0.5\n", "deng-ma"),
        (&cube, "doo-sabin", "0 0.5 0.5\n", "give FACE.K"),
    ] {
        let at = write(&scratch, "bad-at.txt", text);
        let out = scratch.path("bad-out.txt");
        let _ = std::fs::remove_file(&out);
        let run = subdiv(&[
            "evaluate",
            mesh.to_str().unwrap(),
            "--scheme",
            scheme,
            "--at",
            at.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_no_panic(&run);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{text}: {stderr}");
        assert!(stderr.contains(needle), "{text}: {stderr}");
        assert!(!out.exists(), "{text}: output written");
    }
}
