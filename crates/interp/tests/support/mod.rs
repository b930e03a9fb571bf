//! Shared by the method tests: fixtures, and the independent error check that
//! looks only at an output control mesh (SPEC §6: "one plain Doo-Sabin step +
//! face centroids; Catmull-Clark / Loop limit masks; nearest limit point for
//! every input vertex").
#![allow(dead_code)]

use glam::DVec3;
use std::path::Path;
use subdiv_mesh::Mesh;
use subdiv_stencil::{apply, catmull_clark, loop_subdivision, LoopBeta, Scheme, SubdivisionPlan};

/// A fixture by path below `fixtures/`.
pub fn fixture(rel: &str) -> Mesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(rel);
    let soup = subdiv_io::read_mesh(&path).unwrap_or_else(|e| panic!("{rel}: {e}"));
    Mesh::from_soup(soup).unwrap_or_else(|e| panic!("{rel}: {e}")).0
}

/// Candidate limit points of a control mesh under its plain scheme.
pub enum Plain {
    /// Doo-Sabin: one plain step, then every face centroid and every boundary
    /// curve point (midpoints of consecutive boundary vertices).
    DooSabin,
    /// Catmull-Clark limit mask at every vertex.
    CatmullClark,
    /// Loop limit mask at every vertex.
    Loop(LoopBeta),
}

/// Every limit point the plain scheme exposes on `control`.
pub fn candidate_limit_points(control: &Mesh, plain: Plain) -> Vec<DVec3> {
    let t = control.topology();
    match plain {
        Plain::CatmullClark => apply(&catmull_clark::limit_stencil(t), control.positions()),
        Plain::Loop(beta) => apply(&loop_subdivision::limit_stencil(t, beta).unwrap(), control.positions()),
        Plain::DooSabin => {
            let plan = SubdivisionPlan::new(t, Scheme::DooSabin, 1).unwrap();
            let refined = plan.subdivide(control, false);
            let rt = refined.topology();
            let mut points = refined.face_centroids();
            for lp in rt.boundary_loops() {
                for &h in lp {
                    points.push((refined.position(rt.he_from(h)) + refined.position(rt.he_to(h))) / 2.0);
                }
            }
            points
        }
    }
}

/// Max over `targets` of the distance to the nearest candidate, relative to `d`
/// (uniform grid hash; exact nearest neighbour).
pub fn nearest_gap(targets: &[DVec3], candidates: &[DVec3], d: f64) -> f64 {
    let cell = d / 64.0;
    let key = |p: DVec3| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64, (p.z / cell).floor() as i64);
    let mut grid: std::collections::HashMap<(i64, i64, i64), Vec<usize>> = std::collections::HashMap::new();
    for (i, &c) in candidates.iter().enumerate() {
        grid.entry(key(c)).or_default().push(i);
    }
    let mut worst = 0.0f64;
    for &p in targets {
        let (kx, ky, kz) = key(p);
        let mut best = f64::INFINITY;
        for r in 1i64.. {
            for dx in -r..=r {
                for dy in -r..=r {
                    for dz in -r..=r {
                        if let Some(list) = grid.get(&(kx + dx, ky + dy, kz + dz)) {
                            for &i in list {
                                best = best.min(p.distance(candidates[i]));
                            }
                        }
                    }
                }
            }
            if best <= (r - 1) as f64 * cell || r > 70 {
                break;
            }
        }
        worst = worst.max(best);
    }
    worst / d
}

/// Signed volume enclosed by a closed mesh (divergence theorem, fan triangulation).
pub fn volume(mesh: &Mesh) -> f64 {
    let t = mesh.topology();
    let mut v = 0.0;
    for face in t.faces().iter() {
        let p0 = mesh.positions()[face[0] as usize];
        for k in 1..face.len() - 1 {
            let (p1, p2) = (mesh.positions()[face[k] as usize], mesh.positions()[face[k + 1] as usize]);
            v += p0.dot(p1.cross(p2)) / 6.0;
        }
    }
    v
}
