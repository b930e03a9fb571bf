//! Checking an interpolant from its control mesh alone ("anyone can check it
//! independently", [how the error is measured]): the candidate limit points a scheme exposes on
//! a control mesh with its tags (as a file's `t` lines give them), and the
//! distance from every data point to the nearest of them. Nothing here knows
//! which method produced the mesh or which limit point belongs to which
//! vertex.
//!
//! [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured

use crate::numeric::max_nan;
use glam::DVec3;
use std::collections::HashMap;
use subdiv_mesh::refine::DualFeatures;
use subdiv_mesh::{Mesh, PowerOfTwoScale};
use subdiv_stencil::{subdivide, Scheme, Split, StencilError, SubdivisionPlan};

use crate::SurfaceOptions;

/// Every limit point `scheme` exposes on `control` with its tags and the
/// default surface options ([`candidate_limit_points_with`]):
///
/// * an interpolatory scheme ([`subdiv_stencil::SchemeTraits::interpolating`],
///   Deng-Ma): the vertices themselves;
/// * the dual split (Doo-Sabin, with the control mesh's infinitely sharp
///   creases and corners): after one step, every face centroid and every
///   sharp-curve point (midpoint of consecutive vertices of the boundary and
///   of the refined crease polygons), and every corner; if the control mesh
///   has interior vertices of valence 2 (which have no V-face after one
///   step), also every face centroid after a second step;
/// * the primal splits (Catmull-Clark, Loop): the limit point of every
///   vertex, with the tags.
pub fn candidate_limit_points(control: &Mesh, scheme: Scheme) -> Result<Vec<DVec3>, StencilError> {
    candidate_limit_points_with(control, scheme, SurfaceOptions::default())
}

/// Every limit point the scheme exposes on `control` with its tags and
/// `surface` (boundary option, crease method), computed on the control
/// positions scaled by a power of two (exact) so that no sum overflows, and
/// scaled back. Texture coordinates play no part.
pub fn candidate_limit_points_with(
    control: &Mesh,
    scheme: Scheme,
    surface: SurfaceOptions,
) -> Result<Vec<DVec3>, StencilError> {
    let scale = PowerOfTwoScale::normalizing(control.positions().iter().copied());
    let scaled = control
        .with_positions(scale.scaled_points(control.positions()))
        .with_uvs(None)
        .expect("no channel is always valid");
    let mut points = scaled_candidates(&scaled, scheme, surface)?;
    scale.inverse().apply_points(&mut points);
    Ok(points)
}

fn scaled_candidates(control: &Mesh, scheme: Scheme, surface: SurfaceOptions) -> Result<Vec<DVec3>, StencilError> {
    let (t, tags) = (control.topology(), control.tags());
    let traits = scheme.traits();
    if traits.interpolating {
        return Ok(control.positions().to_vec());
    }
    Ok(match traits.split {
        Split::Quad | Split::Triangle | Split::Sqrt3 => {
            let plan = SubdivisionPlan::with_tags(t, tags, surface.for_scheme(scheme), 0)?;
            plan.limit_points(control.positions()).expect("an approximating scheme has limit masks")
        }
        Split::Dual => {
            let refined = subdivide(control, scheme, 1, false)?;
            let (rt, rtags) = (refined.topology(), refined.tags());
            let mut points = refined.face_centroids();
            if t.vertices().any(|v| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2) {
                points.extend(subdivide(&refined, scheme, 1, false)?.face_centroids());
            }
            // The sharp curves: midpoints of the refined boundary and crease edges.
            let features = DualFeatures::new(rt, rtags);
            for e in rt.edges().filter(|&e| features.is_sharp(rt, e)) {
                let (a, b) = rt.edge_vertices(e);
                points.push((refined.position(a) + refined.position(b)) / 2.0);
            }
            // Corners keep their point.
            let features = DualFeatures::new(t, tags);
            points.extend(t.vertices().filter(|&v| features.is_corner(v)).map(|v| control.position(v)));
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
