//! Table `table-creases` (and figure `fig-creases-fandisk.png`): creased
//! interpolation — fandisk with its feature edges found by dihedral angle
//! (`subdiv_mesh::features`) tagged infinitely sharp, every method run on the
//! mesh untagged and tagged; interpolation error, time and a sharpness
//! measure of the surface across the tagged edges.
//!
//! The sharpness measure, per tagged input edge e = (a, b) between faces f₁
//! and f₂: m = (P_a + P_b)/2, uᵢ the unit vector in fᵢ's plane perpendicular
//! to e pointing into fᵢ, hᵢ = ⅛ of the distance from e to fᵢ's centroid
//! along uᵢ (the middle of the first row of level-3 faces on that side); the
//! surface face (level 3, limit positions) whose centroid is nearest to
//! m + hᵢ·uᵢ gives the unit Newell
//! normal nᵢ; sharpness(e) = ∠(n₁, n₂) / ∠(N(f₁), N(f₂)), the surface's
//! turning across the edge over the input's. 1: the surface turns as much as
//! the input does, 0: it is smooth there.

use super::common::{ms, sci, timed, Ctx, Kind, Table};
use super::doo_sabin_creases::panel;
use crate::render::{side_by_side, stack, Camera, Image, Style, Up, View};
use anyhow::Result;
use serde_json::json;
use subdiv_interp::{InterpError, Interpolant};
use subdiv_mesh::features::{feature_edges, FeatureEdges};
use subdiv_mesh::{DVec3, EdgeId, Mesh, Tags, SHARPNESS_INFINITE};
use subdiv_stencil::Scheme;

/// Dihedral turning angle (degrees) from which an edge of fandisk is a feature.
const THRESHOLD_DEGREES: f64 = 30.0;
/// Subdivision levels of the measured (and drawn) surfaces.
const LEVELS: usize = 3;
/// The sharpness the tagged runs should reach (min and median).
const ACCEPT: f64 = 0.8;
/// The Doo-Sabin method of the figure.
const FIGURE_DOO_SABIN: &str = "fan-cheng-lai";
/// Panel size of the figure (fandisk is wider than tall in its view).
const PANEL: (u32, u32) = (460, 340);

/// Exact nearest-point queries over a fixed point set: a uniform grid of
/// about one point per cell, searched in growing shells of cells.
struct Grid {
    points: Vec<DVec3>,
    origin: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// CSR: the points of cell c are `items[start[c]..start[c + 1]]`, in index order.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Grid {
    fn new(points: Vec<DVec3>) -> Self {
        let (lo, hi) =
            points.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let extent = (hi - lo).max_element();
        // At most as many cells as points: max_extent / ⌈∛n⌉ per side.
        let per_side = (points.len() as f64).cbrt().ceil().max(1.0);
        let cell = if extent > 0.0 { extent / per_side } else { 1.0 };
        let dims = [0, 1, 2].map(|k| (((hi[k] - lo[k]) / cell).floor() as usize + 1).min(per_side as usize + 1));
        let mut grid = Grid { points, origin: lo, cell, dims, start: Vec::new(), items: Vec::new() };
        let cells: Vec<usize> = grid.points.iter().map(|&p| grid.cell_index(grid.cell_of(p))).collect();
        let mut start = vec![0u32; dims[0] * dims[1] * dims[2] + 1];
        for &c in &cells {
            start[c + 1] += 1;
        }
        for c in 1..start.len() {
            start[c] += start[c - 1];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; cells.len()];
        for (i, &c) in cells.iter().enumerate() {
            items[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        (grid.start, grid.items) = (start, items);
        grid
    }

    /// The cell containing `p`, clamped into the grid.
    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        [0, 1, 2].map(|k| (((p[k] - self.origin[k]) / self.cell).floor().max(0.0) as usize).min(self.dims[k] - 1))
    }

    fn cell_index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// The index of the point nearest to `q` (the lowest index among equally
    /// near ones). After shell r (cells at Chebyshev index distance r from
    /// q's cell) every unvisited point is at least r·cell away, so the search
    /// stops once the best distance is within that.
    fn nearest(&self, q: DVec3) -> usize {
        let c = self.cell_of(q);
        let mut best = (f64::INFINITY, usize::MAX);
        let max_r = self.dims.iter().max().copied().unwrap_or(1);
        for r in 0..=max_r {
            let range = |k: usize| c[k].saturating_sub(r)..=(c[k] + r).min(self.dims[k] - 1);
            for z in range(2) {
                for y in range(1) {
                    for x in range(0) {
                        let on_shell = [x, y, z].iter().zip(c).any(|(&i, ci)| i.abs_diff(ci) == r);
                        if !on_shell {
                            continue;
                        }
                        let cell = self.cell_index([x, y, z]);
                        for &i in &self.items[self.start[cell] as usize..self.start[cell + 1] as usize] {
                            let candidate = (self.points[i as usize].distance_squared(q), i as usize);
                            if candidate < best {
                                best = candidate;
                            }
                        }
                    }
                }
            }
            let reach = r as f64 * self.cell;
            if best.1 != usize::MAX && best.0 <= reach * reach {
                break;
            }
        }
        best.1
    }
}

/// The angle between two unit vectors, atan2(‖a × b‖, a · b).
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// The sharpness measure (module docs) of `surface` across every edge of
/// `features` on `input`, in the order of `features.edges`.
fn sharpness(input: &Mesh, features: &FeatureEdges, surface: &Mesh) -> Vec<f64> {
    let t = input.topology();
    let normals = surface.face_normals();
    let grid = Grid::new(surface.face_centroids());
    features
        .edges
        .iter()
        .map(|&e| {
            let (a, b) = t.edge_vertices(e);
            let (pa, pb) = (input.position(a), input.position(b));
            let (f1, f2) = t.edge_faces(e);
            let f2 = f2.expect("features are interior edges");
            let m = (pa + pb) / 2.0;
            let along = (pb - pa).normalize();
            let surface_normal = |f| {
                // uᵢ: in fᵢ's plane, ⟂ e, towards fᵢ's centroid; hᵢ: ⅛ of the way
                // there, the middle of the first row of level-3 faces on fᵢ's side
                // (faces may be long and thin: |e| says nothing of their width).
                let u = input.face_normal(f).cross(along).normalize_or_zero();
                let towards = u.dot(input.face_centroid(f) - m);
                let (u, h) = if towards < 0.0 { (-u, -towards / 8.0) } else { (u, towards / 8.0) };
                normals[grid.nearest(m + h * u)]
            };
            let turned = angle(surface_normal(f1), surface_normal(f2));
            turned / features.angles[e.index()].expect("features have an angle")
        })
        .collect()
}

/// (min, median, mean) of a non-empty list.
fn summary(values: &[f64]) -> (f64, f64, f64) {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let median = if n % 2 == 1 { sorted[n / 2] } else { (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0 };
    (sorted[0], median, sorted.iter().sum::<f64>() / n as f64)
}

/// One run of a method: the interpolant, its surface and the time, or why there is none.
struct Run {
    method: &'static str,
    tagged: bool,
    outcome: Result<(Interpolant, Mesh, f64), String>,
}

/// The figure: fandisk with its features, Cheng untagged and tagged; the
/// figure's Doo-Sabin method untagged and tagged, Deng-Wang tagged.
fn figure(tagged_input: &Mesh, runs: &[Run]) -> Result<Image> {
    let surface = |method: &str, tagged: bool| -> Result<&Mesh> {
        let run = runs.iter().find(|r| r.method == method && r.tagged == tagged).expect("every run is listed");
        match &run.outcome {
            Ok((_, surface, _)) => Ok(surface),
            Err(e) => {
                anyhow::bail!("{method} ({}) has no surface to draw: {e}", if tagged { "tagged" } else { "untagged" })
            }
        }
    };
    let panels = [
        (tagged_input, format!("input, {} features tagged", tagged_input.tags().crease_count())),
        (surface("cheng", false)?, "Cheng, untagged".to_string()),
        (surface("cheng", true)?, "Cheng, tagged".to_string()),
        (surface(FIGURE_DOO_SABIN, false)?, "Fan-Cheng-Lai, untagged".to_string()),
        (surface(FIGURE_DOO_SABIN, true)?, "Fan-Cheng-Lai, tagged".to_string()),
        (surface("deng-wang", true)?, "Deng-Wang, tagged".to_string()),
    ];
    let meshes: Vec<&Mesh> = panels.iter().map(|(m, _)| *m).collect();
    let view = View { yaw: 35.0, pitch: 25.0, zoom: 1.0, up: Up::Z };
    let camera = Camera::fitting(&view, &meshes, PANEL.0, PANEL.1);
    let mut images = Vec::new();
    for (k, (mesh, caption)) in panels.iter().enumerate() {
        let style = if k == 0 { Style::input_mesh() } else { Style::surface() };
        // Each mesh with its own tags: the input's features, the surfaces' refined creases.
        images.push((panel(mesh, mesh.tags(), &camera, &style)?, caption.as_str()));
    }
    let rows = [side_by_side(&images[..3], ""), side_by_side(&images[3..], "")];
    Ok(stack(
        &rows,
        &format!("Creased interpolation of fandisk: features ≥ {THRESHOLD_DEGREES}° tagged infinitely sharp (orange), level {LEVELS}"),
    ))
}

/// How many features meet at every vertex of `mesh`.
fn features_at_vertices(mesh: &Mesh, features: &FeatureEdges) -> Vec<usize> {
    let t = mesh.topology();
    let mut count = vec![0usize; t.vertex_count()];
    for &e in &features.edges {
        let (a, b) = t.edge_vertices(e);
        count[a.index()] += 1;
        count[b.index()] += 1;
    }
    count
}

/// Where the edges below [`ACCEPT`] lie: "k along creases, k at dart ends, k at corners".
fn where_short(mesh: &Mesh, features: &FeatureEdges, at_vertex: &[usize], values: &[f64]) -> String {
    let t = mesh.topology();
    let (mut along, mut dart, mut corner) = (0, 0, 0);
    for (&e, _) in features.edges.iter().zip(values).filter(|&(_, &x)| x < ACCEPT) {
        let (a, b) = t.edge_vertices(e);
        let ends = [at_vertex[a.index()], at_vertex[b.index()]];
        if ends.contains(&1) {
            dart += 1;
        } else if ends.iter().any(|&k| k >= 3) {
            corner += 1;
        } else {
            along += 1;
        }
    }
    format!(
        "{} below {ACCEPT}: {along} along creases, {dart} ending in a dart, {corner} at corners",
        along + dart + corner
    )
}

/// The table.
pub fn run(ctx: &Ctx) -> Result<Table> {
    let mut table = Table::new(
        "table-creases",
        "Creased interpolation — fandisk with its feature edges tagged",
        &[
            "method",
            "tags",
            "max error / d",
            "time (ms)",
            "sharpness min",
            "sharpness median",
            "sharpness mean",
            "edges ≥ 0.8",
        ],
    );
    let mesh = ctx.fixture("quad/fandisk_quads.off")?;
    let features = feature_edges(&mesh, THRESHOLD_DEGREES);
    let tagged_input = mesh.clone().with_tags(Tags::from_list(mesh.topology(), &features.list)?);
    let at_vertex = features_at_vertices(&mesh, &features);
    let corners = at_vertex.iter().filter(|&&k| k >= 3).count();
    let darts = at_vertex.iter().filter(|&&k| k == 1).count();
    let n_features = features.edges.len();
    let reference = {
        let sharp = vec![SHARPNESS_INFINITE; mesh.topology().edge_count()];
        let bilinear = mesh.clone().with_tags(Tags::from_arrays(mesh.topology(), sharp, Vec::new())?);
        let refined = subdiv_stencil::subdivide(&bilinear, Scheme::CatmullClark, LEVELS, true)?;
        let s = sharpness(&mesh, &features, &refined);
        let (min, median, mean) = summary(&s);
        (min, median, mean, s.iter().filter(|&&x| x < 0.99).count())
    };
    table.setup = format!(
        "`quad/fandisk_quads.off` ({} vertices, {} quads, closed; pmp-data, quads by David Bommes). Feature \
         edges by dihedral angle (`subdiv_mesh::features::feature_edges`): every edge whose two faces' unit \
         Newell normals turn by at least {THRESHOLD_DEGREES}° is tagged infinitely sharp — {n_features} of {} \
         edges; the {corners} vertices where three or more meet are corners by the rules (no corner tag), the \
         {darts} where one ends are darts. On fandisk the CAD edges turn by 80°–100°, the curved blends \
         between them by up to about 25° per edge on this coarse mesh (20° already tags blend edges), and one \
         edge line fades out from about 55° to 30° and below: {THRESHOLD_DEGREES}° catches every visible CAD \
         edge and none of the blends, and the fading line while it turns by 30° or more (then a dart). Each \
         method runs with its defaults on the mesh untagged and tagged (`Mesh::with_tags`; the method reads the \
         tags from the mesh; Deng-Wang triangulates the quads itself, the tags carried along). *Max error / d*: \
         `Interpolant::error`, the limit points measured from the control mesh independently of the solver, \
         over the bounding-box diagonal d. *Time*: the `interpolate` call. *Sharpness*, per tagged edge \
         e = (a, b) between input faces f₁, f₂, on the surface `Interpolant::surface({LEVELS})` (level {LEVELS}, \
         limit positions): m = (P_a + P_b)/2, uᵢ the unit vector in fᵢ's plane perpendicular to e pointing into \
         fᵢ, hᵢ = ⅛ of the distance from e to fᵢ's centroid along uᵢ (the middle of the first row of level-3 faces on that side, whatever the face's aspect); the surface face whose centroid is nearest to m + hᵢ·uᵢ (exact, grid search) gives the \
         unit Newell normal nᵢ; sharpness(e) = ∠(n₁, n₂)/∠(N(f₁), N(f₂)), the surface's turning across e over \
         the input's. 1: the surface turns as much as the input (a sharp crease), 0: it does not turn (smooth \
         across e, or both samples on one face); above 1 it turns more (the interpolating surface bulges next \
         to the crease). At level {LEVELS} the faces next to e are about ⅛ of the input face wide, so the samples fall \
         on the first row of faces on each side. Untagged \
         runs are measured on the same edges. We ask ≥ {ACCEPT} (min and median) for every method with tags. \
         The measure's own reference: on the input itself refined bilinearly (Catmull-Clark with every edge \
         infinitely sharp, so every face is its bilinear patch) it gives min {:.3}, median {:.3}, mean {:.3}; \
         {} edges fall below 0.99, all next to twisted quads (corners up to 15 % of the quad's size off its \
         Newell plane), mostly on the fading line: there the bilinear patch's normal at the edge is not the \
         quad's Newell normal (for a planar quad it is).",
        mesh.topology().vertex_count(),
        mesh.topology().face_count(),
        mesh.topology().edge_count(),
        reference.0,
        reference.1,
        reference.2,
        reference.3,
    );
    let d = mesh.bbox_diagonal();
    let mut runs = Vec::new();
    // fair has its own table (table7, `fairness.rs`).
    for m in subdiv_interp::Method::ALL.into_iter().filter(|&m| m != subdiv_interp::Method::Fair) {
        let (method, options) = (m.name(), subdiv_interp::MethodOptions::new(m));
        for (tagged, input) in [(false, &mesh), (true, &tagged_input)] {
            let (r, time) = timed(ctx.runs(), || subdiv_interp::interpolate(input, &options));
            let outcome = match r {
                Ok(r) => match r.surface(LEVELS) {
                    Ok(surface) => Ok((r, surface, time)),
                    Err(e) => Err(format!("surface failed: {e}")),
                },
                Err(InterpError::UnsupportedMesh { reason, .. }) => Err(format!("refused: {reason}")),
                Err(e) => Err(format!("failed: {e}")),
            };
            runs.push(Run { method, tagged, outcome });
        }
    }
    let (mut short, mut unchanged) = (Vec::new(), Vec::new());
    for run in &runs {
        let label = if run.tagged { format!("{n_features} creases") } else { "none".into() };
        let key = format!("fandisk/{}/{}", run.method, if run.tagged { "tagged" } else { "untagged" });
        let (r, surface, time) = match &run.outcome {
            Ok(ok) => ok,
            Err(reason) => {
                let mut cells = vec![run.method.into(), label, reason.clone()];
                cells.extend(["—"; 5].map(String::from));
                table.row(cells);
                table.json.push(json!({"method": run.method, "tagged": run.tagged, "outcome": reason}));
                if run.tagged {
                    short.push(format!("{}: {reason}", run.method));
                }
                continue;
            }
        };
        let err = r.error(mesh.positions(), &r.interpolated, d).max_rel;
        let s = sharpness(&mesh, &features, surface);
        let (min, median, mean) = summary(&s);
        table.row(vec![
            run.method.into(),
            label,
            sci(err),
            ms(*time),
            format!("{min:.3}"),
            format!("{median:.3}"),
            format!("{mean:.3}"),
            format!("{} of {}", s.iter().filter(|&&x| x >= ACCEPT).count(), s.len()),
        ]);
        table.json.push(json!({
            "method": run.method, "tagged": run.tagged, "creases": if run.tagged { n_features } else { 0 },
            "max_rel": err, "total_ms": time,
            "sharpness": {"min": min, "median": median, "mean": mean, "per_edge": s},
        }));
        table.metric(format!("{key}/error"), err, Kind::Error);
        if run.tagged {
            if min < ACCEPT || median < ACCEPT {
                short.push(format!(
                    "{} (min {min:.3}, median {median:.3}; {})",
                    run.method,
                    where_short(&mesh, &features, &at_vertex, &s)
                ));
            }
            let untagged = runs.iter().find(|u| u.method == run.method && !u.tagged);
            if let Some(Ok((_, plain, _))) = untagged.map(|u| &u.outcome) {
                if plain.positions() == surface.positions() {
                    unchanged.push(run.method);
                }
            }
        }
    }
    table.notes.push(if short.is_empty() {
        format!("Every method reaches sharpness ≥ {ACCEPT} (min and median) on the tagged edges with tags.")
    } else {
        format!("Below sharpness {ACCEPT} with tags (min or median): {}.", short.join("; "))
    });
    if !unchanged.is_empty() {
        table.notes.push(format!(
            "The tags changed nothing for {}: the tagged surface is the untagged one, bit for bit.",
            unchanged.join(", ")
        ));
    }
    let t = mesh.topology();
    let edges: Vec<[u32; 2]> = (features.edges.iter())
        .map(|&e: &EdgeId| {
            let (a, b) = t.edge_vertices(e);
            [a.0, b.0]
        })
        .collect();
    table.json.push(json!({
        "features": {"threshold_degrees": THRESHOLD_DEGREES, "count": n_features, "corners": corners,
            "darts": darts, "edges": edges},
        "bilinear_reference": {"min": reference.0, "median": reference.1, "mean": reference.2, "below_0.99": reference.3},
    }));
    if ctx.quick {
        table.notes.push("Quick mode: the figure is not regenerated.".into());
    } else {
        let name = "fig-creases-fandisk.png";
        figure(&tagged_input, &runs)?.save_png(&ctx.out.join(name))?;
        table.figures.push(name.into());
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::shapes::SplitMix64;

    #[test]
    fn grid_nearest_is_the_brute_force_nearest() {
        let mut rng = SplitMix64(7);
        for n in [1, 2, 10, 500] {
            // Points on a thin slab (a surface-like set) and queries around and outside it.
            let points: Vec<DVec3> =
                (0..n).map(|_| DVec3::new(rng.next_f64() * 4.0, rng.next_f64(), rng.next_f64() * 1e-3)).collect();
            let grid = Grid::new(points.clone());
            for _ in 0..200 {
                let q = DVec3::new(rng.next_f64() * 6.0 - 1.0, rng.next_f64() * 3.0 - 1.0, rng.next_f64() - 0.5);
                let brute = (0..n)
                    .min_by(|&i, &j| points[i].distance_squared(q).total_cmp(&points[j].distance_squared(q)))
                    .unwrap();
                assert_eq!(grid.nearest(q), brute, "{q}");
            }
        }
    }

    #[test]
    fn sharpness_of_the_input_itself_is_one_on_a_cube() {
        // The cube's own faces (refined flat, all edges sharp): each sample lies on a face of the
        // input plane, so the normals are the input's and every ratio is 1.
        let cube = subdiv_mesh::shapes::cube();
        let features = feature_edges(&cube, 30.0);
        let refined = subdiv_stencil::subdivide(
            &cube.clone().with_tags(Tags::from_list(cube.topology(), &features.list).unwrap()),
            subdiv_stencil::Scheme::CatmullClark,
            3,
            true,
        )
        .unwrap();
        let s = sharpness(&cube, &features, &refined);
        assert_eq!(s.len(), 12);
        assert!(s.iter().all(|&x| (x - 1.0).abs() < 1e-12), "{s:?}");
        // Untagged, the cube rounds off: far below 1.
        let smooth = subdiv_stencil::subdivide(&cube, subdiv_stencil::Scheme::CatmullClark, 3, true).unwrap();
        assert!(sharpness(&cube, &features, &smooth).iter().all(|&x| x < 0.5));
    }
}
