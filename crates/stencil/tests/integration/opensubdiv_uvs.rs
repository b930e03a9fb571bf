//! UVs of OpenSubdiv's regression shapes against OpenSubdiv (the 105 shapes of
//! `fixtures/opensubdiv/` with `vt` lines; the README there gives how the
//! references were made):
//!
//! - with the options its harness derives from each shape (`far_utils.h`: the
//!   file's `t facevaryinginterpolateboundary`, else `linear-all`), levels 1
//!   and 2 (`reference/<shape>/L1.obj`, `L2.obj`);
//! - every shape again under `linear-none`, level 1
//!   (`reference/<shape>/L1-fvar-none.vt`: OpenSubdiv's `vt` lines; its faces
//!   and their `v/vt` indices are those of `L1.obj`). Among them
//!   `catmark_bishop`, `_car`, `_rook`: a UV index alternating between the
//!   faces around a vertex (`A B A B`), where OpenSubdiv's sibling numbering
//!   makes the second `B` a value of its own (`fvar::assign_siblings`).
//!
//! Per face corner, ≤ 1e-12 absolute, and the same number of values (but for
//! the isolated vertices of `catmark_nonman_bareverts`, which OpenSubdiv gives
//! a value each and we none). A face is matched to the reference face and
//! rotation whose corners lie at its corners in the same cyclic order (within
//! 1e-9·d); where two corners share a position (`catmark_val2_back2back`'s
//! collapsed pillows) several rotations match and the closest in UVs counts. The shapes refined
//! through a manifold cover (non-manifold) are not compared: the cover's
//! copies of a vertex share its position, so corners cannot be matched
//! through positions; they are counted.

use crate::fvar_peers::{read_obj, Obj, UV_TOL};
use crate::opensubdiv_shapes::{fixtures, harness_options, shapes};
use glam::{DVec2, DVec3};
use std::collections::HashMap;
use subdiv_mesh::Mesh;
use subdiv_stencil::{subdivide, FVarInterpolation};

/// The largest UV difference over the face corners of `ours` (holes left out)
/// and the reference's, matched through positions (module docs).
fn corner_deviation(ours: &Mesh, reference: &Obj, d: f64, what: &str) -> f64 {
    let tol = 1e-9 * d;
    // Reference vertices in a hash grid of cell `tol`; a query looks at the 27 cells around.
    let cell = |p: DVec3| (p / tol).floor().as_i64vec3().to_array();
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (i, &p) in reference.positions.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i as u32);
    }
    let near = |p: DVec3| {
        let [x, y, z] = cell(p);
        let mut out = Vec::new();
        for key in (-1..=1).flat_map(|a| (-1..=1).flat_map(move |b| (-1..=1).map(move |c| [x + a, y + b, z + c]))) {
            let found = grid.get(&key).into_iter().flatten();
            out.extend(found.filter(|&&i| reference.positions[i as usize].distance(p) <= tol));
        }
        out
    };
    let mut faces_of: HashMap<u32, Vec<usize>> = HashMap::new();
    for (k, f) in reference.faces.iter().enumerate() {
        for c in f {
            faces_of.entry(c.0).or_default().push(k);
        }
    }
    let (t, uvs) = (ours.topology(), ours.uvs().expect("a channel"));
    let mut worst = 0.0f64;
    for f in t.face_ids().filter(|&f| !ours.tags().is_hole(f)) {
        // The reference face and rotation whose corners lie at ours, in our cyclic order (two
        // corners may share a position: of the matching rotations, the closest in UVs counts).
        let corners: Vec<DVec3> = t.face(f).iter().map(|&v| ours.positions()[v as usize]).collect();
        let ours_uv: Vec<DVec2> = t.face_half_edges(f).map(|h| uvs.values[uvs.indices[h.index()] as usize]).collect();
        let n = corners.len();
        let candidates = near(corners[0]).into_iter().flat_map(|v| faces_of.get(&v).into_iter().flatten().copied());
        let best = candidates
            .filter(|&k| reference.faces[k].len() == n)
            .flat_map(|k| (0..n).map(move |r| (k, r)))
            .filter(|&(k, r)| {
                let at = |i: usize| reference.positions[reference.faces[k][(i + r) % n].0 as usize];
                (0..n).all(|i| at(i).distance(corners[i]) <= tol)
            })
            .map(|(k, r)| {
                let uv = |i: usize| reference.uvs[reference.faces[k][(i + r) % n].1 as usize];
                (0..n).map(|i| ours_uv[i].distance(uv(i))).fold(0.0, f64::max)
            })
            .min_by(f64::total_cmp)
            .unwrap_or_else(|| panic!("{what}: our face {f:?} has no match"));
        worst = worst.max(best);
    }
    worst
}

#[test]
fn uvs_of_every_shape_equal_opensubdiv_per_face_corner() {
    let (mut compared, mut non_manifold, mut failures, mut table) = (0, Vec::new(), Vec::new(), Vec::new());
    for (name, path) in shapes() {
        let mesh = subdiv_io::load_mesh(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        if mesh.uvs().is_none() {
            continue;
        }
        if mesh.welds().is_some() {
            non_manifold.push(name);
            continue;
        }
        let reference = fixtures().join("reference").join(&name);
        let harness = harness_options(&name, &mesh);
        let none_uvs = std::fs::read_to_string(reference.join("L1-fvar-none.vt"))
            .unwrap_or_else(|e| panic!("{name}: L1-fvar-none.vt: {e}"))
            .lines()
            .map(|line| {
                let c: Vec<f64> = line.split_whitespace().skip(1).map(|w| w.parse().unwrap()).collect();
                DVec2::new(c[0], c[1])
            })
            .collect::<Vec<_>>();
        let cases = [
            (harness, 1, None),
            (harness, 2, None),
            (harness.with_fvar(FVarInterpolation::LinearNone), 1, Some(none_uvs)),
        ];
        let mut row = Vec::new();
        for (options, level, uvs) in cases {
            let mut expected = read_obj(&reference.join(format!("L{level}.obj")));
            if let Some(uvs) = uvs {
                expected.uvs = uvs;
            }
            let what = format!("{name} L{level} {}", options.fvar);
            let ours = subdivide(&mesh, options, level, false).unwrap_or_else(|e| panic!("{what}: {e}"));
            let channel = ours.uvs().unwrap_or_else(|| panic!("{what}: no UVs refined"));
            let isolated = ours.topology().vertices().filter(|&v| ours.topology().is_isolated(v)).count();
            if channel.values.len() + isolated != expected.uvs.len() {
                failures.push(format!("{what}: {} values, OpenSubdiv {}", channel.values.len(), expected.uvs.len()));
                continue;
            }
            let worst = corner_deviation(&ours, &expected, mesh.bbox_diagonal(), &what);
            row.push(format!("{} L{level} {worst:.1e}", options.fvar));
            if worst > UV_TOL {
                failures.push(format!("{what}: UVs off by {worst:.3e}"));
            }
        }
        table.push(format!("{name:32} {}", row.join(", ")));
        compared += 1;
    }
    println!("{}", table.join("\n"));
    println!("{compared} shapes compared; not compared (non-manifold): {}", non_manifold.join(" "));
    assert!(failures.is_empty(), "{} cases:\n{}", failures.len(), failures.join("\n"));
    assert!(compared >= 90, "{compared} shapes with UVs compared");
}
