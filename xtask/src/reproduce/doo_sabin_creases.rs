//! Figure `fig-doo-sabin-creases.png`: Doo-Sabin with infinitely sharp
//! creases and corners (`subdiv_stencil::doo_sabin`, "Creases and
//! corners") — the same control meshes refined untagged and tagged, the
//! sharp polygon (crease tags) drawn in orange on every panel.

use crate::render::{side_by_side, stack, Camera, Canvas, Image, Style, Up, View};
use anyhow::Result;
use subdiv_mesh::{DVec3, EdgeTag, Mesh, TagList, Tags, SHARPNESS_INFINITE};
use subdiv_stencil::doo_sabin::{self, StandardCorners};

const PANEL: u32 = 400;
/// The sharp polygon: a strong orange.
const SHARP: ([u8; 3], f32) = ([236, 112, 20], 2.4);
/// Levels of every refined panel.
const LEVELS: usize = 4;

/// Tags making the edges between the given vertex pairs infinitely sharp.
fn creases(mesh: &Mesh, pairs: &[(u32, u32)]) -> Result<Tags> {
    let list = TagList {
        creases: pairs.iter().map(|&(a, b)| EdgeTag { a, b, sharpness: SHARPNESS_INFINITE }).collect(),
        corners: Vec::new(),
        ..Default::default()
    };
    Ok(Tags::from_list(mesh.topology(), &list)?)
}

/// `LEVELS` tagged Doo-Sabin steps, the last level at its limit positions,
/// with that level's tags.
fn refine(mesh: &Mesh, tags: &Tags) -> Result<(Mesh, Tags)> {
    let (mut t, mut tags, mut x) = (mesh.topology().clone(), tags.clone(), mesh.positions().to_vec());
    for _ in 0..LEVELS {
        let next = doo_sabin::first_step_tagged(&t, &tags, &StandardCorners, &x)?;
        let (t2, _, tags2) = subdiv_mesh::refine::dual_split_tagged(&t, &tags);
        (t, tags, x) = (t2, tags2, next);
    }
    let limit = doo_sabin::limit_points_tagged(&t, &tags, &x)?;
    Ok((Mesh::new(limit, t.faces().clone())?, tags))
}

/// The crease edges of `tags` on `mesh`, as two-point polylines.
fn sharp_segments(mesh: &Mesh, tags: &Tags) -> Vec<[DVec3; 2]> {
    let t = mesh.topology();
    t.edges()
        .filter(|&e| tags.edge_sharpness(e) >= SHARPNESS_INFINITE)
        .map(|e| {
            let (a, b) = t.edge_vertices(e);
            [mesh.position(a), mesh.position(b)]
        })
        .collect()
}

/// `mesh` cut open along its creases, for shading: every vertex gets one copy
/// per sector (run of its faces between two creases), so smooth normals are
/// not averaged across a crease. A dart keeps one copy (its sector is whole).
fn cut_along_creases(mesh: &Mesh, tags: &Tags) -> Result<Mesh> {
    let t = mesh.topology();
    let crease = |h: subdiv_mesh::HalfEdgeId| tags.edge_sharpness(t.he_edge(h)) >= SHARPNESS_INFINITE;
    let mut corner_vertex = vec![0u32; t.half_edge_count()];
    let mut positions = Vec::new();
    for v in t.vertices() {
        let fan = t.vertex_fan(v);
        // Sectors start at creases; on the boundary also at the boundary edge,
        // inside the faces before the first crease close the last sector.
        let first = (0..fan.len()).find(|&i| crease(fan[i]) || (i == 0 && t.is_boundary_vertex(v))).unwrap_or(0);
        for k in 0..fan.len() {
            let i = (first + k) % fan.len();
            if k == 0 || crease(fan[i]) {
                positions.push(mesh.position(v));
            }
            corner_vertex[fan[i].index()] = positions.len() as u32 - 1;
        }
    }
    let mut faces = subdiv_mesh::FaceList::with_capacity(t.face_count(), t.half_edge_count());
    for f in t.face_ids() {
        faces.push(&t.face_half_edges(f).map(|h| corner_vertex[h.index()]).collect::<Vec<_>>());
    }
    Ok(Mesh::new(positions, faces)?)
}

/// One panel: `mesh` in `style` with its sharp polygon on it.
pub(super) fn panel(mesh: &Mesh, tags: &Tags, camera: &Camera, style: &Style) -> Result<Image> {
    let mut canvas = Canvas::new(camera, style.background);
    canvas.draw_surface(&cut_along_creases(mesh, tags)?, style.fill, style.smooth);
    if let Some(colour) = style.edges {
        canvas.draw_edges(mesh, colour, 0.8 * style.edge_width);
    }
    for segment in sharp_segments(mesh, tags) {
        canvas.draw_polyline(&segment, SHARP.0, SHARP.1);
    }
    Ok(canvas.finish())
}

/// One row: the control mesh with the first tagging's sharp edges, the
/// untagged surface, then one surface per tagging, all through one camera.
fn row(mesh: &Mesh, taggings: &[(Tags, &str)], control: &str, view: &View) -> Result<Image> {
    let untagged = refine(mesh, &Tags::none())?;
    let tagged: Vec<(Mesh, Tags)> = taggings.iter().map(|(tags, _)| refine(mesh, tags)).collect::<Result<_>>()?;
    let mut meshes = vec![mesh, &untagged.0];
    meshes.extend(tagged.iter().map(|(m, _)| m));
    let camera = Camera::fitting(view, &meshes, PANEL, PANEL);
    let mut panels = vec![
        (panel(mesh, &taggings[0].0, &camera, &Style::control_mesh())?, control.to_string()),
        (panel(&untagged.0, &untagged.1, &camera, &Style::surface())?, format!("untagged, level {LEVELS}")),
    ];
    for ((surface, tags), (_, caption)) in tagged.iter().zip(taggings) {
        panels.push((panel(surface, tags, &camera, &Style::surface())?, format!("{caption}, level {LEVELS}")));
    }
    let borrowed: Vec<(Image, &str)> = panels.iter().map(|(i, c)| (i.clone(), c.as_str())).collect();
    Ok(side_by_side(&borrowed, ""))
}

/// The figure: the unit cube (vertex i at (i & 1, i >> 1 & 1, i >> 2 & 1))
/// untagged, with its top loop sharp and with all 12 edges sharp; the
/// chamfered cube (`fixtures/poly/chamfer-cube.off`) with the 24 edges of its
/// six main faces sharp.
pub fn figure(cube: &Mesh, chamfer: &Mesh) -> Result<Image> {
    const TOP: [(u32, u32); 4] = [(4, 5), (5, 7), (7, 6), (6, 4)];
    const ALL: [(u32, u32); 12] =
        [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];
    let z_up = View { up: Up::Z, ..View::default() };
    let cube_row = row(
        cube,
        &[(creases(cube, &TOP)?, "top loop sharp"), (creases(cube, &ALL)?, "all 12 edges sharp")],
        "cube, top loop tagged",
        &z_up,
    )?;
    // The main faces are the chamfered cube's first six faces.
    let main_edges: Vec<(u32, u32)> = (0..6)
        .flat_map(|f| {
            let face = chamfer.topology().face(subdiv_mesh::FaceId(f));
            (0..face.len()).map(move |k| (face[k], face[(k + 1) % face.len()]))
        })
        .collect();
    let chamfer_row = row(
        chamfer,
        &[(creases(chamfer, &main_edges)?, "main faces' edges sharp")],
        "chamfered cube, 24 edges tagged",
        &z_up,
    )?;
    Ok(stack(
        &[cube_row, chamfer_row],
        "Doo-Sabin with infinitely sharp creases: each crease is a boundary of both sides (Chaikin curves, orange)",
    ))
}
