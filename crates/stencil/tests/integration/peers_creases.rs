//! Creases, corners and boundary options against OpenSubdiv 3.5
//! (`fixtures/peer/creases/`, whose README gives every command and
//! convention): every refined level (L1, L2) and every limit file of every
//! case, with uniform and Chaikin creasing, `edge-and-corner` and
//! `edge-only` boundaries, Catmull-Clark and Loop (Loop's β).
//!
//! Positions: L1 index by index (OpenSubdiv numbers level 1 as we do), L2 as
//! point sets (nearest neighbour both ways: the edge points of level 2 are
//! numbered differently) plus counts; limits row by row in input order. The
//! sharpness left at each level (`t` lines) is compared through the vertex
//! correspondence. Deviations relative to the input's bounding-box diagonal d,
//! ≤ 1e-12.
//!
//! The files are read by a minimal parser here (`v`, `f`, `t`), independent
//! of `subdiv-io`.

use glam::DVec3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use subdiv_mesh::{EdgeTag, FaceList, Mesh, PolygonSoup, TagList, VertexTag};
use subdiv_stencil::{subdivide, BoundaryInterpolation, CreaseMethod, LoopBeta, Options, Scheme, SubdivisionPlan};

/// Largest accepted deviation, relative to d.
const TOL_REL: f64 = 1e-12;

fn creases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/peer/creases")
}

/// A minimal OBJ reader: positions, faces (first index of each corner) and
/// OpenSubdiv's `t crease` / `t corner` lines.
fn read_obj(path: &Path) -> PolygonSoup {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut soup = PolygonSoup::default();
    let mut faces = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let c: Vec<f64> = words.take(3).map(|w| w.parse().unwrap()).collect();
                soup.positions.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("f") => {
                let face: Vec<u32> = words.map(|w| w.split('/').next().unwrap().parse::<u32>().unwrap() - 1).collect();
                faces.push(face);
            }
            Some("t") => {
                let name = words.next().unwrap();
                let counts: Vec<usize> = words.next().unwrap().split('/').map(|c| c.parse().unwrap()).collect();
                let rest: Vec<&str> = words.collect();
                let ints: Vec<u32> = rest[..counts[0]].iter().map(|w| w.parse().unwrap()).collect();
                let floats: Vec<f32> =
                    rest[counts[0]..counts[0] + counts[1]].iter().map(|w| w.parse().unwrap()).collect();
                match name {
                    "crease" => {
                        for (k, pair) in ints.chunks(2).enumerate() {
                            let sharpness = floats[if floats.len() == 1 { 0 } else { k }];
                            soup.tags.creases.push(EdgeTag { a: pair[0], b: pair[1], sharpness });
                        }
                    }
                    "corner" => {
                        for (k, &vertex) in ints.iter().enumerate() {
                            let sharpness = floats[if floats.len() == 1 { 0 } else { k }];
                            soup.tags.corners.push(VertexTag { vertex, sharpness });
                        }
                    }
                    _ => {}
                }
            }
            _ => {}
        }
    }
    soup.faces = FaceList::from_faces(faces);
    soup
}

fn read_points(path: &Path) -> Vec<DVec3> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let c: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            DVec3::new(c[0], c[1], c[2])
        })
        .collect()
}

/// What a reference file name says: scheme and options.
fn options_of(name: &str) -> Option<Options> {
    let scheme = if name.starts_with("opensubdiv-catmull-clark") {
        Scheme::CatmullClark
    } else if name.starts_with("opensubdiv-loop-origbeta") {
        Scheme::Loop(LoopBeta::Loop)
    } else {
        return None;
    };
    let mut options = Options::new(scheme);
    if name.contains("-chaikin") {
        options = options.with_crease_method(CreaseMethod::Chaikin);
    }
    if name.contains("-edge-only") {
        options = options.with_boundary(BoundaryInterpolation::EdgeOnly);
    }
    Some(options)
}

/// For every point of `ours`, the index of the nearest point of `theirs`,
/// and the largest distance either way.
fn match_points(ours: &[DVec3], theirs: &[DVec3]) -> (Vec<usize>, f64) {
    let nearest = |p: DVec3, set: &[DVec3]| {
        set.iter().enumerate().map(|(i, q)| (i, p.distance(*q))).min_by(|a, b| a.1.total_cmp(&b.1)).unwrap()
    };
    let mut worst = 0.0f64;
    let map = ours
        .iter()
        .map(|&p| {
            let (i, d) = nearest(p, theirs);
            worst = worst.max(d);
            i
        })
        .collect();
    for &q in theirs {
        worst = worst.max(nearest(q, ours).1);
    }
    (map, worst)
}

/// The sharpness of each tagged edge and vertex, by their positions' indices in `theirs`' numbering.
fn tag_table(tags: &TagList, map: Option<&[usize]>) -> (BTreeMap<(usize, usize), f32>, BTreeMap<usize, f32>) {
    let m = |v: u32| map.map_or(v as usize, |map| map[v as usize]);
    let creases = tags.creases.iter().map(|t| ((m(t.a).min(m(t.b)), m(t.a).max(m(t.b))), t.sharpness)).collect();
    let corners = tags.corners.iter().map(|t| (m(t.vertex), t.sharpness)).collect();
    (creases, corners)
}

#[test]
fn refined_levels_limits_and_decayed_tags_equal_opensubdiv() {
    let mut checked = 0;
    let mut table = Vec::new();
    let mut cases: Vec<_> = std::fs::read_dir(creases_dir()).unwrap().flatten().filter(|e| e.path().is_dir()).collect();
    cases.sort_by_key(|e| e.path());
    for case in cases {
        let dir = case.path();
        let name = dir.file_name().unwrap().to_string_lossy().to_string();
        let (input, _) = Mesh::from_soup(read_obj(&dir.join(format!("{name}.obj")))).unwrap();
        let d = input.bbox_diagonal();
        let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.path()).collect();
        files.sort();
        for file in files {
            let fname = file.file_name().unwrap().to_string_lossy().to_string();
            let Some(options) = options_of(&fname) else { continue };
            if fname.ends_with("-limit.txt") {
                let theirs = read_points(&file);
                let ours = subdivide(&input, options, 0, true).unwrap();
                assert_eq!(theirs.len(), input.positions().len(), "{name}/{fname}");
                let worst = (ours.positions().iter().zip(&theirs)).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
                table.push(format!("{name:28} {fname:60} limit {:.1e}", worst / d));
                assert!(worst <= TOL_REL * d, "{name}/{fname}: limit off by {:.3e}·d", worst / d);
                // The plan's limit stencil gives the same points.
                let plan = SubdivisionPlan::with_tags(input.topology(), input.tags(), options, 0).unwrap();
                let stencil = plan.limit_stencil().unwrap().unwrap();
                let from_stencil = subdiv_stencil::apply(&stencil, input.positions());
                let worst = (from_stencil.iter().zip(&theirs)).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
                assert!(worst <= TOL_REL * d, "{name}/{fname}: limit stencil off by {:.3e}·d", worst / d);
                checked += 1;
                continue;
            }
            let level: usize = match fname.rsplit_once("-L") {
                Some((_, l)) => l.trim_end_matches(".obj").parse().unwrap(),
                None => continue,
            };
            let reference = read_obj(&file);
            let ours = subdivide(&input, options, level, false).unwrap();
            assert_eq!(ours.positions().len(), reference.positions.len(), "{name}/{fname}: vertex count");
            assert_eq!(ours.topology().face_count(), reference.faces.len(), "{name}/{fname}: face count");
            let (map, worst) = match_points(ours.positions(), &reference.positions);
            if level == 1 {
                let by_index = (ours.positions().iter().zip(&reference.positions))
                    .map(|(a, b)| a.distance(*b))
                    .fold(0.0, f64::max);
                assert!(by_index <= TOL_REL * d, "{name}/{fname}: L1 by index off by {:.3e}·d", by_index / d);
            }
            table.push(format!("{name:28} {fname:60} L{level}    {:.1e}", worst / d));
            assert!(worst <= TOL_REL * d, "{name}/{fname}: off by {:.3e}·d", worst / d);
            // The plan (stencils) gives the same points as the direct evaluation.
            let plan = SubdivisionPlan::with_tags(input.topology(), input.tags(), options, level).unwrap();
            let planned = plan.apply(input.positions());
            let gap = (planned.iter().zip(ours.positions())).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
            assert!(gap <= 1e-14 * d, "{name}/{fname}: plan and direct step differ by {:.3e}·d", gap / d);
            // The sharpness left at this level, as OpenSubdiv holds it.
            let our_tags = tag_table(&ours.tags().to_list(ours.topology()), Some(&map));
            let their_tags = tag_table(&reference.tags, None);
            assert_eq!(our_tags, their_tags, "{name}/{fname}: tags of level {level}");
            checked += 1;
        }
    }
    println!("{}", table.join("\n"));
    assert!(checked >= 50, "only {checked} reference files checked");
}
