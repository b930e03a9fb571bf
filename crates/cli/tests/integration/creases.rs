//! Creases, corners and the boundary options through the command line:
//! `subdiv subdivide` on OpenSubdiv's tagged inputs (`fixtures/peer/creases/`)
//! against OpenSubdiv's files, the tags written back level by level, `--tags`
//! files, `--boundary`, `--crease-method`, and the refusals.

use crate::common::{assert_no_panic, fixtures, read, run_ok, subdiv, Scratch};
use std::collections::BTreeSet;
use std::path::PathBuf;
use subdiv_mesh::{DVec3, PolygonSoup};

fn case(name: &str, file: &str) -> PathBuf {
    fixtures().join("peer/creases").join(name).join(file)
}

/// Largest distance from a point of `a` to the nearest of `b`, both ways.
fn hausdorff(a: &[DVec3], b: &[DVec3]) -> f64 {
    let one = |a: &[DVec3], b: &[DVec3]| {
        a.iter().map(|p| b.iter().map(|q| p.distance(*q)).fold(f64::INFINITY, f64::min)).fold(0.0, f64::max)
    };
    one(a, b).max(one(b, a))
}

/// The tagged edges of a soup as position pairs (rounded), with their sharpness.
fn crease_set(soup: &PolygonSoup) -> BTreeSet<(String, String, String)> {
    let key = |v: u32| {
        let p = soup.positions[v as usize];
        format!("{:.9} {:.9} {:.9}", p.x, p.y, p.z)
    };
    soup.tags
        .creases
        .iter()
        .map(|t| {
            let (a, b) = (key(t.a), key(t.b));
            let (a, b) = if a < b { (a, b) } else { (b, a) };
            (a, b, format!("{}", t.sharpness))
        })
        .collect()
}

#[test]
fn tagged_subdivision_and_its_tags_equal_opensubdiv() {
    let scratch = Scratch::new("creases");
    for (name, extra, reference) in [
        ("cube_crease_top_s2.5", &[][..], "opensubdiv-catmull-clark-L2.obj"),
        ("cube_crease_top_mixed", &["--crease-method", "chaikin"][..], "opensubdiv-catmull-clark-chaikin-L2.obj"),
        ("grid_crease_row_corner", &[][..], "opensubdiv-catmull-clark-L2.obj"),
        ("cube_corners_semi", &[][..], "opensubdiv-catmull-clark-L2.obj"),
        ("octahedron_corner_creases", &["--beta", "loop"][..], "opensubdiv-loop-origbeta-L2.obj"),
    ] {
        let scheme = if name.starts_with("octahedron") { "loop" } else { "catmull-clark" };
        let input = case(name, &format!("{name}.obj"));
        let out = scratch.path(&format!("{name}-L2.obj"));
        let mut args = vec!["subdivide", input.to_str().unwrap(), "--scheme", scheme, "--levels", "2"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", out.to_str().unwrap()]);
        run_ok(&args);
        let (ours, theirs) = (read(&out), read(&case(name, reference)));
        assert_eq!(ours.positions.len(), theirs.positions.len(), "{name}");
        let gap = hausdorff(&ours.positions, &theirs.positions);
        assert!(gap < 1e-12, "{name}: positions off by {gap:.3e}");
        // The file carries the tags of level 2, as OpenSubdiv holds them.
        assert_eq!(crease_set(&ours), crease_set(&theirs), "{name}: crease tags of level 2");
        assert_eq!(ours.tags.corners.len(), theirs.tags.corners.len(), "{name}: corner tags");
    }
}

#[test]
fn zero_levels_limit_of_tagged_inputs_equals_opensubdiv() {
    let scratch = Scratch::new("creases");
    for (name, extra, reference) in [
        ("cube_crease_top_s2.5", &[][..], "opensubdiv-catmull-clark-limit.txt"),
        ("torus_ring_s3", &["--crease-method", "chaikin"][..], "opensubdiv-catmull-clark-chaikin-limit.txt"),
        ("cube_corners2", &[][..], "opensubdiv-catmull-clark-limit.txt"),
    ] {
        let input = case(name, &format!("{name}.obj"));
        let out = scratch.path(&format!("{name}-limit.obj"));
        let mut args = vec!["subdivide", input.to_str().unwrap(), "--scheme", "catmull-clark", "--levels", "0"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--limit", "-o", out.to_str().unwrap()]);
        run_ok(&args);
        let ours = read(&out).positions;
        let text = std::fs::read_to_string(case(name, reference)).unwrap();
        let theirs: Vec<DVec3> = text
            .lines()
            .map(|l| {
                let c: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
                DVec3::new(c[0], c[1], c[2])
            })
            .collect();
        let worst = ours.iter().zip(&theirs).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        assert_eq!(ours.len(), theirs.len());
        assert!(worst < 1e-12, "{name}: limit off by {worst:.3e}");
    }
}

/// A `--tags` file on the untagged cube gives the tagged OBJ's surface.
#[test]
fn tag_file_equals_obj_tag_lines() {
    let scratch = Scratch::new("creases");
    let tags = scratch.path("top.json");
    std::fs::write(&tags, r#"{"creases": [[1, 5, 2.5], [5, 7, 2.5], [7, 3, 2.5], [3, 1, 2.5]]}"#).unwrap();
    let cube = fixtures().join("canonical/cube_quad.obj");
    let (a, b) = (scratch.path("cube-tagfile.obj"), scratch.path("cube-tagged.obj"));
    let common = ["--scheme", "catmull-clark", "--levels", "2", "-o"];
    run_ok(
        &[
            &["subdivide", cube.to_str().unwrap(), "--tags", tags.to_str().unwrap()][..],
            &common,
            &[a.to_str().unwrap()],
        ]
        .concat(),
    );
    let tagged = case("cube_crease_top_s2.5", "cube_crease_top_s2.5.obj");
    run_ok(&[&["subdivide", tagged.to_str().unwrap()][..], &common, &[b.to_str().unwrap()]].concat());
    assert_eq!(read(&a).positions, read(&b).positions);
    // A tag file naming a non-edge is refused (exit 2), nothing written.
    std::fs::write(&tags, r#"{"creases": [[0, 7, 1.0]]}"#).unwrap();
    let c = scratch.path("cube-bad-tags.obj");
    let run = subdiv(
        &[
            &["subdivide", cube.to_str().unwrap(), "--tags", tags.to_str().unwrap()][..],
            &common,
            &[c.to_str().unwrap()],
        ]
        .concat(),
    );
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("share no edge"), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(!c.exists());
}

/// `--boundary edge-only` rounds the open grid's corners (they stay put
/// under the default edge-and-corner); `none` refines as edge-only.
#[test]
fn boundary_options_move_the_corners_or_not() {
    let scratch = Scratch::new("creases");
    let grid = case("grid_crease_row_corner", "grid_crease_row_corner.obj");
    let input = read(&grid).positions;
    let mut limits = Vec::new();
    for boundary in ["edge-and-corner", "edge-only", "none"] {
        let out = scratch.path(&format!("grid-{boundary}.obj"));
        run_ok(&[
            "subdivide",
            grid.to_str().unwrap(),
            "--scheme",
            "catmull-clark",
            "--levels",
            "0",
            "--limit",
            "--boundary",
            boundary,
            "-o",
            out.to_str().unwrap(),
        ]);
        limits.push(read(&out).positions);
    }
    // Grid corner 0 (one face): fixed with corners, on the boundary B-spline without.
    assert_eq!(limits[0][0], input[0]);
    let spline = (input[1] + 4.0 * input[0] + input[9]) / 6.0;
    assert!(limits[1][0].distance(spline) < 1e-15, "{} vs {}", limits[1][0], spline);
    assert_eq!(limits[1], limits[2]);
    // A bad value names the choices.
    let run = subdiv(&[
        "subdivide",
        grid.to_str().unwrap(),
        "--scheme",
        "catmull-clark",
        "--levels",
        "1",
        "--boundary",
        "sharp",
        "-o",
        "x.obj",
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("edge-and-corner"));
}

#[test]
fn deng_ma_refuses_semi_sharp_tags_and_interpolation_keeps_them() {
    let scratch = Scratch::new("creases");
    let tagged = case("cube_crease_top_s1", "cube_crease_top_s1.obj");
    let out = scratch.path("deng-ma-tagged.obj");
    let run = subdiv(&[
        "subdivide",
        tagged.to_str().unwrap(),
        "--scheme",
        "deng-ma",
        "--levels",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("infinitely sharp only") && stderr.contains("sharpness 1"), "{stderr}");
    assert!(!out.exists());
    // Infinitely sharp: Deng-Ma takes them.
    let all10 = case("cube_crease_all10", "cube_crease_all10.obj");
    run_ok(&[
        "subdivide",
        all10.to_str().unwrap(),
        "--scheme",
        "deng-ma",
        "--levels",
        "2",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(read(&out).tags.creases.len(), 12 * 4);
    // interpolate: the control mesh is solved with the tags and written with
    // them; read back from the file alone, its limit points pass through the data.
    let control = scratch.path("cheng-tagged.obj");
    let report = scratch.path("cheng-tagged.json");
    let stderr = run_ok(&[
        "interpolate",
        tagged.to_str().unwrap(),
        "--method",
        "cheng",
        "-o",
        control.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    assert!(!stderr.contains("ignored"), "{stderr}");
    let written = read(&control);
    assert_eq!(crease_set(&written).len(), 4);
    assert_eq!(written.tags.creases.iter().map(|t| t.sharpness).collect::<Vec<_>>(), vec![1.0; 4]);
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(json["input"]["tags"]["creases"], 4);
    assert_eq!(json["control"]["tags"]["creases"], 4);
    assert_eq!(json["surface_options"]["crease_method"], "uniform");
    let data = subdiv_mesh::Mesh::from_soup(read(&tagged)).unwrap().0;
    let written = subdiv_mesh::Mesh::from_soup(written).unwrap().0;
    let candidates =
        subdiv_interp::verify::candidate_limit_points(&written, subdiv_stencil::Scheme::CatmullClark).unwrap();
    let gap = subdiv_interp::verify::nearest_gap(data.positions(), &candidates, data.bbox_diagonal());
    assert!(gap <= 1e-6, "{gap:e}");
}

#[test]
fn info_counts_tags_and_texture_coordinates() {
    let run =
        subdiv(&["info", "--json", case("grid_crease_row_corner", "grid_crease_row_corner.obj").to_str().unwrap()]);
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(json["tags"]["creases"], 8);
    assert_eq!(json["tags"]["corners"], 1);
    assert_eq!(json["tags"]["semi_sharp"], 8);
    assert_eq!(json["tags"]["infinitely_sharp"], 1);
    let run = subdiv(&["info", "--json", case("spot_uv", "spot_uv.obj").to_str().unwrap()]);
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(json["uvs"]["values"], 267);
    assert!(json["uvs"]["seam_vertices"].as_u64().unwrap() > 0);
    let text = String::from_utf8_lossy(
        &subdiv(&["info", case("cube_crease_top_s1", "cube_crease_top_s1.obj").to_str().unwrap()]).stdout,
    )
    .to_string();
    assert!(text.contains("tags:                 4 creases, 0 corners"), "{text}");
}

/// UVs per face corner: each of our faces against the reference face with
/// the same corner positions (OpenSubdiv orders a quad parent's children
/// from another corner, so faces are permuted from level 2 on), corner by
/// corner at the same position; the largest |Δuv|.
fn uv_gap(ours: &PolygonSoup, theirs: &PolygonSoup) -> f64 {
    use std::collections::HashMap;
    let (ou, tu) = (ours.uvs.as_ref().expect("our uvs"), theirs.uvs.as_ref().expect("their uvs"));
    assert_eq!(ours.faces.len(), theirs.faces.len());
    // Our vertex → the nearest of theirs.
    let map: Vec<u32> = (ours.positions.iter())
        .map(|p| {
            (0..theirs.positions.len() as u32)
                .min_by(|&a, &b| {
                    p.distance(theirs.positions[a as usize]).total_cmp(&p.distance(theirs.positions[b as usize]))
                })
                .unwrap()
        })
        .collect();
    let sorted = |mut k: Vec<u32>| {
        k.sort_unstable();
        k
    };
    let faces: HashMap<Vec<u32>, usize> =
        (0..theirs.faces.len()).map(|g| (sorted(theirs.faces.face(g).to_vec()), g)).collect();
    let starts = |soup: &PolygonSoup| soup.faces.offsets().iter().map(|&o| o as usize).collect::<Vec<_>>();
    let (ours_start, theirs_start) = (starts(ours), starts(theirs));
    let mut worst = 0.0f64;
    for f in 0..ours.faces.len() {
        let mapped: Vec<u32> = ours.faces.face(f).iter().map(|&v| map[v as usize]).collect();
        let g = faces[&sorted(mapped.clone())];
        let theirs_face = theirs.faces.face(g);
        for (i, w) in mapped.iter().enumerate() {
            let j = theirs_face.iter().position(|c| c == w).unwrap();
            let x = ou.values[ou.indices[ours_start[f] + i] as usize];
            let y = tu.values[tu.indices[theirs_start[g] + j] as usize];
            worst = worst.max(x.distance(y));
        }
    }
    worst
}

#[test]
fn texture_coordinates_follow_opensubdiv_in_each_fvar_mode() {
    let scratch = Scratch::new("creases");
    for (name, mode, boundary) in [
        ("spot_uv", "linear-none", "edge-and-corner"),
        ("spot_uv", "linear-corners-only", "edge-and-corner"),
        ("spot_uv", "linear-all", "edge-and-corner"),
        ("uv_grid", "linear-none", "edge-only"),
    ] {
        let input = case(name, &format!("{name}.obj"));
        let out = scratch.path(&format!("{name}-{mode}-{boundary}.obj"));
        run_ok(&[
            "subdivide",
            input.to_str().unwrap(),
            "--scheme",
            "catmull-clark",
            "--levels",
            "2",
            "--fvar",
            mode,
            "--boundary",
            boundary,
            "-o",
            out.to_str().unwrap(),
        ]);
        let prefix =
            if boundary == "edge-only" { "opensubdiv-catmull-clark-edge-only" } else { "opensubdiv-catmull-clark" };
        let theirs = read(&case(name, &format!("{prefix}-fvar-{mode}-L2.obj")));
        let ours = read(&out);
        assert_eq!(ours.uvs.as_ref().unwrap().values.len(), theirs.uvs.as_ref().unwrap().values.len(), "{name} {mode}");
        let gap = uv_gap(&ours, &theirs);
        assert!(gap < 1e-12, "{name} {mode} {boundary}: UVs off by {gap:.3e}");
    }
    // Doo-Sabin refines no channel with seams: the positions are written, the UVs dropped with a warning.
    let out = scratch.path("spot-ds.obj");
    let spot = case("spot_uv", "spot_uv.obj");
    let stderr = run_ok(&[
        "subdivide",
        spot.to_str().unwrap(),
        "--scheme",
        "doo-sabin",
        "--levels",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(stderr.contains("texture coordinates not written"), "{stderr}");
    assert!(read(&out).uvs.is_none());
}

/// Doo-Sabin with every cube edge infinitely sharp: the refined points lie
/// on the cube (each has a coordinate 0 or 1, all in [0, 1]), the corners
/// stay, the level's tags are written; semi-sharp tags are refused (exit 2).
#[test]
fn doo_sabin_keeps_infinitely_sharp_creases() {
    let scratch = Scratch::new("creases");
    let cube = case("cube_crease_all10", "cube_crease_all10.obj");
    let out = scratch.path("cube-ds-sharp.obj");
    run_ok(&[
        "subdivide",
        cube.to_str().unwrap(),
        "--scheme",
        "doo-sabin",
        "--levels",
        "3",
        "-o",
        out.to_str().unwrap(),
    ]);
    let soup = read(&out);
    for p in &soup.positions {
        let c = [p.x, p.y, p.z];
        assert!(c.iter().all(|&x| (-1e-15..=1.0 + 1e-15).contains(&x)), "{p} leaves the cube");
        assert!(c.iter().any(|&x| x.abs() < 1e-15 || (x - 1.0).abs() < 1e-15), "{p} is not on the cube's surface");
    }
    for corner in read(&cube).positions {
        assert!(soup.positions.contains(&corner), "corner {corner} moved");
    }
    assert!(!soup.tags.creases.is_empty(), "the level-3 crease tags are written");
    let semi = case("cube_crease_top_s1", "cube_crease_top_s1.obj");
    let run = subdiv(&[
        "subdivide",
        semi.to_str().unwrap(),
        "--scheme",
        "doo-sabin",
        "--levels",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(2), "{}", String::from_utf8_lossy(&run.stderr));
}

/// `--feature-angle`: the feature edges of `subdiv_mesh::feature_edges`
/// become infinitely sharp creases of the input (under the file's and the
/// tag file's own tags), for `interpolate` and `subdivide` alike.
#[test]
fn feature_angle_tags_the_feature_edges() {
    let scratch = Scratch::new("creases");
    let fandisk = fixtures().join("quad/fandisk_quads.off");
    let data = subdiv_mesh::Mesh::from_soup(read(&fandisk)).unwrap().0;
    let expected = subdiv_mesh::feature_edges(&data, 30.0).edges.len();
    assert!(expected > 100, "fandisk has CAD edges");
    let (control, report) = (scratch.path("fandisk-cheng.obj"), scratch.path("fandisk-cheng.json"));
    run_ok(&[
        "interpolate",
        fandisk.to_str().unwrap(),
        "--method",
        "cheng",
        "--feature-angle",
        "30",
        "-o",
        control.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(json["input"]["tags"]["creases"], expected);
    assert_eq!(json["input"]["tags"]["infinitely_sharp"], expected, "no corner tags: every tag is a feature");
    let written = subdiv_mesh::Mesh::from_soup(read(&control)).unwrap().0;
    assert_eq!(written.tags().crease_count(), expected, "the control mesh is written with the features");
    let plain = subdiv_stencil::Scheme::CatmullClark;
    let candidates = subdiv_interp::verify::candidate_limit_points(&written, plain).unwrap();
    let gap = subdiv_interp::verify::nearest_gap(data.positions(), &candidates, data.bbox_diagonal());
    assert!(gap <= 1e-6, "{gap:e}");

    // A tag file's value on a feature edge wins; subdivide takes the flag too.
    let cube = fixtures().join("canonical/cube_quad.obj");
    let tags = scratch.path("semi.json");
    std::fs::write(&tags, r#"{"creases": [[0, 1, 2.5]]}"#).unwrap();
    let out = scratch.path("cube-features.obj");
    let (cube_s, tags_s, out_s) = (cube.to_str().unwrap(), tags.to_str().unwrap(), out.to_str().unwrap());
    let cube_args = |levels| {
        let tail = ["--feature-angle", "30", "--tags", tags_s, "-o", out_s];
        [&["subdivide", cube_s, "--scheme", "catmull-clark", "--levels", levels][..], &tail[..]].concat()
    };
    run_ok(&cube_args("0"));
    let tagged = read(&out).tags.creases;
    assert_eq!(tagged.len(), 12);
    assert_eq!(tagged.iter().filter(|t| t.sharpness == 2.5).count(), 1);
    run_ok(&cube_args("1"));
    assert_eq!(read(&out).tags.creases.len(), 24);
    let bad = subdiv(&[
        "subdivide",
        cube.to_str().unwrap(),
        "--scheme",
        "loop",
        "--levels",
        "1",
        "--feature-angle",
        "200",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_no_panic(&bad);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--feature-angle"));
}
