//! Checking an interpolant from its control mesh alone (SPEC §6: "anyone can
//! check it independently"): the candidate limit points a plain scheme
//! exposes on a control mesh, and the distance from every data point to the
//! nearest of them. Nothing here knows which method produced the mesh or
//! which limit point belongs to which vertex.

use glam::DVec3;
use std::collections::HashMap;
use subdiv_mesh::Mesh;
use subdiv_stencil::{catmull_clark, loop_subdivision, subdivide, LoopBeta, Scheme, StencilError};

/// The plain scheme of a control mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Plain {
    /// Doo-Sabin: after one plain step, every face centroid and every
    /// boundary-curve point (midpoint of consecutive boundary vertices); if
    /// the control mesh has interior vertices of valence 2 (which have no
    /// V-face after one step), also every face centroid after a second step.
    DooSabin,
    /// Catmull-Clark: the limit mask at every vertex.
    CatmullClark,
    /// Loop: the limit mask at every vertex.
    Loop(LoopBeta),
    /// An interpolatory scheme: the vertices themselves.
    Interpolatory,
}

/// Every limit point the plain scheme exposes on `control`.
pub fn candidate_limit_points(control: &Mesh, plain: Plain) -> Result<Vec<DVec3>, StencilError> {
    let t = control.topology();
    Ok(match plain {
        Plain::CatmullClark => catmull_clark::limit_points(t, control.positions()),
        Plain::Loop(beta) => loop_subdivision::limit_points(t, beta, control.positions())?,
        Plain::Interpolatory => control.positions().to_vec(),
        Plain::DooSabin => {
            let refined = subdivide(control, Scheme::DooSabin, 1, false)?;
            let rt = refined.topology();
            let mut points = refined.face_centroids();
            if t.vertices().any(|v| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2) {
                points.extend(subdivide(&refined, Scheme::DooSabin, 1, false)?.face_centroids());
            }
            for lp in rt.boundary_loops() {
                points.extend(
                    lp.iter().map(|&h| (refined.position(rt.he_from(h)) + refined.position(rt.he_to(h))) / 2.0),
                );
            }
            points
        }
    })
}

/// Max over `targets` of the distance to the nearest candidate, relative to
/// `d` (exact nearest neighbour through a uniform grid of cell d/64).
pub fn nearest_gap(targets: &[DVec3], candidates: &[DVec3], d: f64) -> f64 {
    if candidates.is_empty() {
        return f64::INFINITY;
    }
    let cell = d / 64.0;
    let key = |p: DVec3| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64, (p.z / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, &c) in candidates.iter().enumerate() {
        grid.entry(key(c)).or_default().push(i);
    }
    let mut worst = 0.0f64;
    for &p in targets {
        let (kx, ky, kz) = key(p);
        let mut best = f64::INFINITY;
        // Search growing shells; a candidate found within r−1 cells cannot be beaten outside r.
        for r in 0i64.. {
            for dx in -r..=r {
                for dy in -r..=r {
                    for dz in -r..=r {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                            continue;
                        }
                        if let Some(list) = grid.get(&(kx + dx, ky + dy, kz + dz)) {
                            for &i in list {
                                best = best.min(p.distance(candidates[i]));
                            }
                        }
                    }
                }
            }
            if best <= r as f64 * cell || r > 128 {
                break;
            }
        }
        if best.is_infinite() {
            best = candidates.iter().map(|c| p.distance(*c)).fold(f64::INFINITY, f64::min);
        }
        worst = worst.max(best);
    }
    worst / d
}
