//! Figure `fig-deng-ma-open.png`: the Deng-Ma scheme on open meshes with our
//! 4-point boundary rule (`subdiv_rules::deng_ma`, "Open meshes") — each
//! input mesh with its boundary polygons, beside its refined surface with the
//! refined boundary curves (the surface's own boundary loops) drawn on it.

use crate::render::{side_by_side, Camera, Canvas, Image, Style, View};
use anyhow::Result;
use subdiv_interp::{deng_ma, DengMaOptions};
use subdiv_mesh::{DVec3, Mesh};

const PANEL: u32 = 420;
/// The boundary polygons and curves: a strong orange.
const BOUNDARY: ([u8; 3], f32) = ([236, 112, 20], 2.6);
const DATA_DOTS: ([u8; 3], f32) = ([220, 40, 40], 2.2);

/// The boundary loops of `mesh` as closed polylines.
fn boundary_polylines(mesh: &Mesh) -> Vec<Vec<DVec3>> {
    let t = mesh.topology();
    t.boundary_loops()
        .map(|l| {
            let mut points: Vec<DVec3> = l.iter().map(|&h| mesh.position(t.he_from(h))).collect();
            points.push(points[0]);
            points
        })
        .collect()
}

/// One panel: `mesh` in `style`, the curves on it, the data dots (hidden
/// ones occluded by the surface).
fn panel(mesh: &Mesh, camera: &Camera, style: &Style, curves: &[Vec<DVec3>], dots: &[DVec3]) -> Image {
    let mut canvas = Canvas::new(camera, style.background);
    canvas.draw_surface(mesh, style.fill, style.smooth);
    if let Some(colour) = style.edges {
        canvas.draw_edges(mesh, colour, 0.8 * style.edge_width);
    }
    for curve in curves {
        canvas.draw_polyline(curve, BOUNDARY.0, BOUNDARY.1);
    }
    canvas.draw_points(dots, DATA_DOTS.0, DATA_DOTS.1);
    canvas.finish()
}

/// The input and its level-`levels` Deng-Ma surface (default tension) as two
/// panels through one camera.
fn model(mesh: &Mesh, levels: usize, view: &View) -> Result<[Image; 2]> {
    let surface = deng_ma::interpolate(mesh, &DengMaOptions::default())?.surface(levels)?;
    let camera = Camera::fitting(view, &[mesh, &surface], PANEL, PANEL);
    let data = mesh.positions();
    Ok([
        panel(mesh, &camera, &Style::input_mesh(), &boundary_polylines(mesh), data),
        panel(&surface, &camera, &Style::surface(), &boundary_polylines(&surface), data),
    ])
}

/// The figure: Nefertiti (one boundary loop) at level 4 and the half tunnel
/// (three loops, quads) at level 3.
pub fn figure(nefertiti: &Mesh, halftunnel: &Mesh) -> Result<Image> {
    let [a, b] = model(nefertiti, 4, &View { yaw: -25.0, pitch: 15.0, ..View::default() })?;
    let [c, d] = model(halftunnel, 3, &View { pitch: 45.0, ..View::default() })?;
    Ok(side_by_side(
        &[
            (a, "Nefertiti: input, boundary polygon"),
            (b, "Deng-Ma level 4, 4-point boundary"),
            (c, "half tunnel: input, 3 boundary loops"),
            (d, "Deng-Ma level 3"),
        ],
        "Deng-Ma on open meshes: boundary loops refined by the 4-point rule (our construction)",
    ))
}
