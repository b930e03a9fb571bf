//! `subdiv subdivide` as a process: counts, limit positions against OpenSubdiv,
//! and clear failures that leave no output file.

use crate::common::{assert_no_panic, fixtures, subdiv, Scratch};

fn read(path: &std::path::Path) -> subdiv_mesh::PolygonSoup {
    subdiv_io::read_mesh(path).unwrap()
}

#[test]
fn counts_after_each_scheme() {
    let scratch = Scratch::new("subdivide");
    let cube = fixtures().join("canonical/cube_quad.obj");
    let ico = fixtures().join("canonical/icosahedron.obj");
    for (input, scheme, levels, vertices, faces) in [
        (&cube, "catmull-clark", 2, 98, 96),
        (&cube, "doo-sabin", 1, 24, 26),
        (&cube, "deng-ma", 2, 98, 96),
        (&ico, "loop", 2, 162, 320),
    ] {
        let out = scratch.path(&format!("{scheme}-{levels}.obj"));
        let run = subdiv(&[
            "subdivide",
            input.to_str().unwrap(),
            "--scheme",
            scheme,
            "--levels",
            &levels.to_string(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_no_panic(&run);
        assert_eq!(run.status.code(), Some(0), "{scheme}: {}", String::from_utf8_lossy(&run.stderr));
        let soup = read(&out);
        assert_eq!((soup.positions.len(), soup.faces.len()), (vertices, faces), "{scheme}");
    }
}

/// `--levels 0 --limit` writes the input vertices at their limit positions in
/// input order; OpenSubdiv's `PrimvarRefiner::Limit` gives them independently.
#[test]
fn zero_levels_limit_matches_opensubdiv() {
    let scratch = Scratch::new("subdivide");
    for (mesh, scheme, beta, peer) in [
        ("quad/spot_control_mesh.obj", "catmull-clark", "", "spot_control_mesh/opensubdiv-catmull-clark-limit.txt"),
        ("open/halftunnel.off", "catmull-clark", "", "halftunnel/opensubdiv-catmull-clark-limit.txt"),
        ("open/grid.off", "loop", "loop", "grid/opensubdiv-loop-origbeta-limit.txt"),
        ("canonical/icosphere_2.obj", "loop", "loop", "icosphere_2/opensubdiv-loop-origbeta-limit.txt"),
    ] {
        let input = fixtures().join(mesh);
        let out = scratch.path(&format!("limit-{}.ply", mesh.replace('/', "-")));
        // --beta belongs to Loop alone (refused for other schemes).
        let mut args = vec!["subdivide", input.to_str().unwrap(), "--scheme", scheme];
        if !beta.is_empty() {
            args.extend(["--beta", beta]);
        }
        args.extend(["--levels", "0", "--limit", "-o", out.to_str().unwrap()]);
        let run = subdiv(&args);
        assert_eq!(run.status.code(), Some(0), "{mesh}: {}", String::from_utf8_lossy(&run.stderr));
        let ours = read(&out).positions;
        let text = std::fs::read_to_string(fixtures().join("peer").join(peer)).unwrap();
        let theirs: Vec<[f64; 3]> = text
            .lines()
            .filter(|l| !l.trim().is_empty())
            .map(|l| {
                let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
                [v[0], v[1], v[2]]
            })
            .collect();
        assert_eq!(ours.len(), theirs.len(), "{mesh}");
        let input_soup = read(&input);
        let b = subdiv_mesh::Aabb::of(input_soup.positions.iter().copied()).unwrap();
        let worst = ours
            .iter()
            .zip(&theirs)
            .map(|(p, q)| (p.x - q[0]).abs().max((p.y - q[1]).abs()).max((p.z - q[2]).abs()))
            .fold(0.0, f64::max);
        assert!(worst <= 1e-9 * b.diagonal(), "{mesh}: max deviation {worst:e}");
    }
}

#[test]
fn impossible_requests_fail_cleanly_without_output() {
    let scratch = Scratch::new("subdivide");
    let cube = fixtures().join("canonical/cube_quad.obj");
    for (input, extra, needle) in [
        (&cube, vec!["--scheme", "loop", "--levels", "1"], "triang"),
        (&cube, vec!["--scheme", "deng-ma", "--levels", "1", "--limit"], "limit"),
        (&cube, vec!["--scheme", "catmull-clark", "--levels", "40"], "levels"),
        (&cube, vec!["--scheme", "deng-ma", "--levels", "1", "--omega", "3"], "ω"),
    ] {
        let out = scratch.path("never.obj");
        let _ = std::fs::remove_file(&out);
        let mut args = vec!["subdivide", input.to_str().unwrap()];
        args.extend(extra.iter().copied());
        args.extend(["-o", out.to_str().unwrap()]);
        let run = subdiv(&args);
        assert_no_panic(&run);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(needle), "{extra:?}: {stderr}");
        assert!(!out.exists(), "{extra:?}: no output file on failure");
    }
    // --triangulate makes Loop accept quads.
    let out = scratch.path("tri.obj");
    let run = subdiv(&[
        "subdivide",
        cube.to_str().unwrap(),
        "--scheme",
        "loop",
        "--triangulate",
        "--levels",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(read(&out).faces.len(), 48);
}

/// OBJ text of positions and faces (0-based).
fn obj(positions: &[[f64; 3]], faces: &[Vec<u32>]) -> String {
    let mut text: String = positions.iter().map(|p| format!("v {} {} {}\n", p[0], p[1], p[2])).collect();
    for f in faces {
        let corners: Vec<String> = f.iter().map(|v| (v + 1).to_string()).collect();
        text += &format!("f {}\n", corners.join(" "));
    }
    text
}

/// A closed mesh of one quad and two triangles whose shared edge (0, 2) is
/// the quad's fan diagonal from corner 0 (and its shorter one).
fn quad_and_two_triangles() -> String {
    let p = [[0.0, -0.5, 0.0], [1.0, 0.0, 0.6], [0.0, 0.5, 0.0], [-1.0, 0.0, 0.6]];
    obj(&p, &[vec![0, 1, 2, 3], vec![0, 3, 2], vec![2, 1, 0]])
}

/// The 7-vertex torus (every two vertices share an edge) with vertex 0's
/// star replaced by a hexagon, face 8 (vertices renumbered 1..7 → 0..6):
/// every diagonal of the hexagon is an edge.
fn torus_with_untriangulable_hexagon() -> String {
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for i in 0..7u32 {
        for tri in [[i, i + 1, i + 3], [i, i + 3, i + 2]].map(|t| t.map(|v| v % 7)) {
            if !tri.contains(&0) {
                faces.push(tri.iter().map(|v| v - 1).collect());
            }
        }
    }
    faces.push(vec![0, 2, 1, 5, 3, 4]);
    let p: Vec<[f64; 3]> = (1..7).map(|k| [f64::from(k).cos(), f64::from(k).sin(), f64::from(k % 3)]).collect();
    obj(&p, &faces)
}

/// `--triangulate` keeps the mesh manifold: the quad whose fan diagonal is
/// already an edge (a fan made this exit 101) takes the other diagonal; a
/// face with no valid diagonal is a clean exit 2 naming it, with no output.
#[test]
fn triangulate_never_duplicates_an_edge() {
    let scratch = Scratch::new("subdivide");
    let input = scratch.path("quad_and_two_triangles.obj");
    std::fs::write(&input, quad_and_two_triangles()).unwrap();
    let out = scratch.path("quad_and_two_triangles-loop.obj");
    let args = ["--scheme", "loop", "--triangulate", "--levels", "1", "-o", out.to_str().unwrap()];
    let run = subdiv(&[&["subdivide", input.to_str().unwrap()][..], &args].concat());
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let refined = subdiv_mesh::Mesh::from_soup(read(&out)).expect("a valid mesh").0;
    // Four triangles (a tetrahedron's combinatorics), each split in four.
    let t = refined.topology();
    assert_eq!((t.vertex_count(), t.face_count(), t.genus()), (10, 16, Some(0)));

    let input = scratch.path("untriangulable.obj");
    std::fs::write(&input, torus_with_untriangulable_hexagon()).unwrap();
    let out = scratch.path("untriangulable-loop.obj");
    let _ = std::fs::remove_file(&out);
    let args = ["--scheme", "loop", "--triangulate", "--levels", "1", "-o", out.to_str().unwrap()];
    let run = subdiv(&[&["subdivide", input.to_str().unwrap()][..], &args].concat());
    assert_no_panic(&run);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("untriangulable.obj") && stderr.contains("face 8 (6 vertices) cannot be triangulated"),
        "{stderr}"
    );
    assert!(!out.exists());
}
