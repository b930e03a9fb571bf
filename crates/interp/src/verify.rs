//! Checking an interpolant from its control mesh alone (SPEC §6: "anyone can
//! check it independently"): the candidate limit points a plain scheme
//! exposes on a control mesh, and the distance from every data point to the
//! nearest of them. Nothing here knows which method produced the mesh or
//! which limit point belongs to which vertex.

use crate::numeric::max_nan;
use glam::DVec3;
use std::collections::HashMap;
use subdiv_mesh::{Mesh, PowerOfTwoScale};
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

/// Every limit point the plain scheme exposes on `control`, computed on the
/// control positions scaled by a power of two (exact) so that no sum
/// overflows, and scaled back.
pub fn candidate_limit_points(control: &Mesh, plain: Plain) -> Result<Vec<DVec3>, StencilError> {
    let scale = PowerOfTwoScale::normalizing(control.positions().iter().copied());
    // The plain scheme: positions only, no tags, no texture coordinates.
    let mut scaled =
        control.clone().with_tags(subdiv_mesh::Tags::none()).with_uvs(None).expect("no channel is always valid");
    scale.apply_points(scaled.positions_mut());
    let mut points = scaled_candidates(&scaled, plain)?;
    scale.inverse().apply_points(&mut points);
    Ok(points)
}

fn scaled_candidates(control: &Mesh, plain: Plain) -> Result<Vec<DVec3>, StencilError> {
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
/// `d` (exact nearest neighbour through a uniform grid of cell d/64). NaN
/// when a target or a nearest candidate is not a number (never hidden by
/// the maximum). Computed on points scaled by one power of two (exact), so
/// that distances between coordinates near ±1e308 do not overflow.
pub fn nearest_gap(targets: &[DVec3], candidates: &[DVec3], d: f64) -> f64 {
    if candidates.is_empty() {
        return f64::INFINITY;
    }
    let scale = PowerOfTwoScale::normalizing(targets.iter().chain(candidates).copied());
    let targets: Vec<DVec3> = targets.iter().map(|&p| scale.apply_point(p)).collect();
    let candidates: Vec<DVec3> = candidates.iter().map(|&p| scale.apply_point(p)).collect();
    let d = scale.apply(d);
    let non_finite = |p: &DVec3| !p.is_finite();
    if targets.iter().any(non_finite) || candidates.iter().any(non_finite) || !(d > 0.0 && d.is_finite()) {
        // The grid needs finite points; the answer is then not a number.
        return f64::NAN;
    }
    let cell = d / 64.0;
    let key = |p: DVec3| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64, (p.z / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, &c) in candidates.iter().enumerate() {
        grid.entry(key(c)).or_default().push(i);
    }
    let mut worst = 0.0f64;
    for &p in &targets {
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
                                best = best.min(subdiv_mesh::distance(p, candidates[i]));
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
            best = candidates.iter().map(|c| subdiv_mesh::distance(p, *c)).fold(f64::INFINITY, f64::min);
        }
        worst = max_nan(worst, best);
    }
    worst / d
}
