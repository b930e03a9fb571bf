//! OpenSubdiv's own regression shapes (`fixtures/opensubdiv/`, whose README
//! gives the provenance and how the reference outputs were made): every
//! catmark_/loop_ shape read by `subdiv-io` with its `t` tags (creases,
//! corners, holes, OpenSubdiv's option tags), refined with the options its
//! harness derives from them (`regression/common/far_utils.h`: edge-only
//! boundaries where the file says nothing, Loop's original β), against
//! OpenSubdiv's levels 1–3 and its limit positions.
//!
//! - Levels: the same vertex count, the same number of faces drawn (holes
//!   left out), and the positions as point sets (nearest point both ways,
//!   through a hash grid): ≤ 1e-12·d.
//! - Limits: row by row in input order, ≤ 1e-12·d, except where OpenSubdiv's
//!   limit masks take a shortcut that is not the limit of refinement:
//!   interior vertices of valence 2 and darts (our limit there is the true
//!   one: `dart_limits.rs`, `valence_two.rs`); those rows are counted and
//!   printed, not compared.
//!
//! - Non-manifold shapes (edges of 3+ faces, vertices joining separate
//!   fans, a vertex repeated in a face) are refined through their manifold
//!   cover and compared welded, as OpenSubdiv numbers them.
//!
//! Run with `--nocapture` for the table of every shape.

use crate::sharp_cases;

use glam::DVec3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use subdiv_mesh::{Mesh, Tags, Topology, VertexId};
use subdiv_stencil::{
    limit_points_with_options, subdivide, BoundaryInterpolation, LoopBeta, Options, Scheme, SubdivisionPlan,
};

/// Largest accepted deviation, relative to d.
const TOL_REL: f64 = 1e-12;

pub(crate) fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/opensubdiv")
}

/// The shapes: (name, input path), sorted.
pub(crate) fn shapes() -> Vec<(String, PathBuf)> {
    let dir = fixtures().join("shapes");
    let mut out: Vec<(String, PathBuf)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), p))
        .collect();
    out.sort();
    out
}

/// The options OpenSubdiv's harness derives from a shape: the scheme from its name (Loop with
/// Loop's β), the file's option tags, edge-only boundaries where the file sets none.
pub(crate) fn harness_options(name: &str, mesh: &Mesh) -> Options {
    let scheme = if name.starts_with("loop_") { Scheme::Loop(LoopBeta::Loop) } else { Scheme::CatmullClark };
    let file = mesh.tags().options();
    Options::new(scheme)
        .with_boundary(file.boundary.unwrap_or(BoundaryInterpolation::EdgeOnly))
        .with_crease_method(file.crease_method.unwrap_or_default())
        .with_fvar(file.fvar.unwrap_or_default())
        .with_triangle_rule(file.triangle_rule.unwrap_or_default())
}

/// `v` lines and the number of `f` lines of an OBJ file (read here, independently of subdiv-io).
fn read_level(path: &Path) -> (Vec<DVec3>, usize) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut points = Vec::new();
    let mut faces = 0;
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let c: Vec<f64> = words.take(3).map(|w| w.parse().unwrap()).collect();
                points.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("f") => faces += 1,
            _ => {}
        }
    }
    (points, faces)
}

/// The largest distance from a point of `a` to its nearest point of `b`, both ways, found
/// through a hash grid of cell `cell` (the points of `b` within `cell` of each point of `a`;
/// a point with none counts as `f64::INFINITY`).
fn point_set_distance(a: &[DVec3], b: &[DVec3], cell: f64) -> f64 {
    let one_way = |a: &[DVec3], b: &[DVec3]| {
        let key = |p: DVec3| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64, (p.z / cell).floor() as i64);
        let mut grid: HashMap<(i64, i64, i64), Vec<DVec3>> = HashMap::new();
        for &p in b {
            grid.entry(key(p)).or_default().push(p);
        }
        a.iter()
            .map(|&p| {
                let (x, y, z) = key(p);
                let mut best = f64::INFINITY;
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            for q in grid.get(&(x + dx, y + dy, z + dz)).into_iter().flatten() {
                                best = best.min((p - *q).length());
                            }
                        }
                    }
                }
                best
            })
            .fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

/// The vertices whose OpenSubdiv limit takes a shortcut: interior vertices of valence 2, and
/// darts (exactly one infinitely sharp edge, boundary edges counted, and no corner sharpness).
fn shortcut_vertices(t: &Topology, tags: &Tags) -> Vec<usize> {
    t.vertices()
        .filter(|&v| {
            if t.is_isolated(v) {
                return false;
            }
            let boundary = t.is_boundary_vertex(v);
            // The fan's edges (boundary edges infinitely sharp), and the incoming boundary edge.
            let infinite = |h: &&subdiv_mesh::HalfEdgeId| {
                let e = t.he_edge(**h);
                t.is_boundary_edge(e) || tags.edge_sharpness(e) >= 10.0
            };
            let sharp = t.vertex_fan(v).iter().filter(infinite).count() + usize::from(boundary);
            let valence_two = !boundary && t.valence(v) == 2;
            valence_two || (sharp == 1 && tags.vertex_sharpness(v) == 0.0)
        })
        .map(VertexId::index)
        .collect()
}

#[test]
fn every_shape_refines_and_limits_as_opensubdiv() {
    let shapes = shapes();
    assert!(shapes.len() >= 100, "{} shapes in {}", shapes.len(), fixtures().display());
    let mut failures = Vec::new();
    println!("| shape | V | F | levels (max dev / d) | limit (max dev / d) | shortcut rows |");
    println!("|---|---|---|---|---|---|");
    for (name, path) in &shapes {
        let mesh = match subdiv_io::load_mesh(path) {
            Ok(mesh) => mesh,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        // A non-manifold shape is refined through its manifold cover and compared welded.
        let weld = |mesh: &Mesh, points: Vec<DVec3>| match mesh.welds() {
            Some(welds) => welds.weld(&points),
            None => points,
        };
        let options = harness_options(name, &mesh);
        let d = mesh.bbox_diagonal();
        let reference = fixtures().join("reference").join(name);
        let mut worst_level = 0.0f64;
        let mut levels_checked = Vec::new();
        for level in 1..=3 {
            let file = reference.join(format!("L{level}.obj"));
            if !file.exists() {
                continue;
            }
            let (points, faces) = read_level(&file);
            let ours = match subdivide(&mesh, options, level, false) {
                Ok(ours) => ours,
                Err(e) => {
                    failures.push(format!("{name} L{level}: {e}"));
                    break;
                }
            };
            let drawn = ours.topology().face_count() - ours.tags().hole_count();
            let welded = weld(&ours, ours.positions().to_vec());
            if welded.len() != points.len() || drawn != faces {
                failures.push(format!(
                    "{name} L{level}: {} vertices and {drawn} faces drawn, OpenSubdiv {} and {faces}",
                    welded.len(),
                    points.len()
                ));
                continue;
            }
            let dev = point_set_distance(&welded, &points, 1e-6 * d) / d;
            worst_level = worst_level.max(dev);
            levels_checked.push(level);
            if dev > TOL_REL {
                failures.push(format!("{name} L{level}: point sets {dev:.2e}·d apart"));
            }
        }
        let limits = sharp_cases::read_points(&reference.join("limit.txt"));
        let skip = shortcut_vertices(mesh.topology(), mesh.tags());
        let ours = limit_points_with_options(mesh.topology(), mesh.tags(), options, mesh.positions())
            .expect("the shapes' schemes have limit masks")
            .expect("Catmull-Clark and Loop have limit masks");
        let ours = weld(&mesh, ours);
        let skip: Vec<usize> = match mesh.welds() {
            Some(welds) => skip.iter().map(|&v| welds.vertex(VertexId(v as u32)) as usize).collect(),
            None => skip,
        };
        let mut worst_limit = 0.0f64;
        for (v, (p, q)) in ours.iter().zip(&limits).enumerate() {
            if !skip.contains(&v) {
                worst_limit = worst_limit.max((*p - *q).length() / d);
            }
        }
        if limits.len() != ours.len() {
            failures.push(format!("{name}: {} limit points, OpenSubdiv {}", ours.len(), limits.len()));
        } else if worst_limit > TOL_REL {
            failures.push(format!("{name}: limit points {worst_limit:.2e}·d apart"));
        }
        println!(
            "| {name} | {} | {} | {levels_checked:?} {worst_level:.1e} | {worst_limit:.1e} | {} |",
            mesh.welds().map_or(mesh.topology().vertex_count(), |welds| welds.vertex_count()),
            mesh.topology().face_count(),
            skip.len()
        );
        // The plan (stencils) agrees with the direct refinement on the first level.
        if let Ok(plan) = SubdivisionPlan::with_tags(mesh.topology(), mesh.tags(), options, 1) {
            let planned = plan.subdivide(&mesh, false).unwrap();
            let direct = subdivide(&mesh, options, 1, false).unwrap();
            let dev = (planned.positions().iter().zip(direct.positions()))
                .map(|(a, b)| (*a - *b).length() / d)
                .fold(0.0, f64::max);
            if dev > TOL_REL {
                failures.push(format!("{name}: plan and direct level 1 {dev:.2e}·d apart"));
            }
        }
    }
    assert!(failures.is_empty(), "{} of {} shapes:\n{}", failures.len(), shapes.len(), failures.join("\n"));
}
