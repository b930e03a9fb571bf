//! Table 7: fairness of every method on the same inputs (issue #18): the
//! interpolation error, the thin-plate energy of the limit surface, two
//! fairness measures that share no code with the fair method's objective
//! (∫H² from the cotangent Laplacian, and the largest distance from the
//! limit surface to the input polygon mesh), time; and the figure of Spot,
//! Cheng against fair.

use super::common::{ms, sci, timed, Ctx, Kind, Table};
use crate::render::{draw_dots, render_with, side_by_side, Camera, Style, View};
use anyhow::Result;
use serde_json::json;
use subdiv_interp::fair::{thin_plate_energy, FairOptions};
use subdiv_interp::{interpolate, Interpolant, LoopBeta, Method, MethodOptions, SurfaceOptions};
use subdiv_mesh::DVec3;
use subdiv_mesh::Mesh;
use subdiv_stencil::Scheme;

/// How to read the table (the same for every run).
const NOTE: &str = "Reading the ratios: every surface here passes through the same data, and the thin-plate \
    energy and ∫H² of a curved shape are mostly its own curvature, which no interpolant removes; what fair \
    removes is the exact methods' overshoot between the data points, which the largest distance to the input \
    mesh measures most directly (and the control meshes show: the figure). fair minimises the energy of its \
    level-1 limit points, not of the level-3 surface measured here, so on some models the level-3 energy comes \
    out a few per cent above Cheng's; the J = 1 and K = 2 rows, which see more of the surface, lower it at \
    several times the cost. horse-3's data are the refined control points of a smooth mesh: there is nothing \
    to fair, and all measures agree to 1 %. Fair Doo-Sabin's energy on M¹'s vertex limit points sees little \
    of what happens inside M¹'s faces, and on triangle meshes (knight, bunny) it comes out far less fair than \
    Nasri's: use Catmull-Clark.";

/// Whether the bunny gets the lower-bound row: no, M³ has 3.3·10⁶
/// unknowns and fair K = 3 takes about 2 min of CPU there (×3 runs);
/// `cargo run --release -p subdiv-interp --example fair_time --
/// fixtures/open/stanford-bunny.obj 0 3` computes it alone.
const BUNNY_BOUND: bool = false;

/// The level of the measured surfaces, relative to the input.
const LEVEL: usize = 3;

/// One method run: its label, options, and the refinement level of its
/// control mesh relative to the input (which sets how many levels bring it
/// to [`LEVEL`]).
struct Run {
    label: String,
    options: MethodOptions,
    control_level: usize,
}

/// The row of the measure's lower bound: fair Catmull-Clark on M³, whose
/// objective is the measure itself (4³·Σ‖Δy‖² on the level-3 limit points
/// with the data pinned). Every Catmull-Clark surface of the input topology
/// through the data has such limit points, and every such set of limit
/// points is reachable (M³'s limit matrix is invertible): no method whose
/// level-3 surface has M³'s connectivity (Cheng, fair Catmull-Clark) can
/// measure lower (`crates/interp/tests/integration/fair_bound.rs`).
const BOUND: &str = "fair (catmull-clark, K = 3): lower bound";

fn runs(mesh: &Mesh, big: bool, bound: bool) -> Vec<Run> {
    let triangles = mesh.topology().faces().all_of_size(3);
    let fair = |scheme: Scheme| Run {
        label: format!("fair ({})", scheme.name()),
        options: FairOptions::default().with_scheme(scheme).expect("fair takes every scheme listed here").into(),
        control_level: 1,
    };
    if big {
        // 10⁵ vertices: the exact Catmull-Clark method against fair (each
        // level-3 surface has 64× the vertices; the distance query dominates).
        return vec![
            Run { label: "cheng".into(), options: MethodOptions::new(Method::Cheng), control_level: 0 },
            fair(Scheme::CatmullClark),
        ];
    }
    let mut out: Vec<Run> = Method::ALL
        .into_iter()
        .filter(|&m| m != Method::Fair)
        .map(|m| Run {
            label: m.name().into(),
            options: MethodOptions::new(m),
            control_level: match m {
                Method::ZhengCai | Method::FanChengLai | Method::DengWang => 1,
                _ => 0,
            },
        })
        .collect();
    out.push(fair(Scheme::CatmullClark));
    out.push(Run {
        label: "fair (catmull-clark, J = 1)".into(),
        options: FairOptions::default().with_energy_levels(1).into(),
        control_level: 1,
    });
    out.push(Run {
        label: "fair (catmull-clark, K = 2)".into(),
        options: FairOptions::default().with_refine(2).into(),
        control_level: 2,
    });
    if bound {
        out.push(Run { label: BOUND.into(), options: FairOptions::default().with_refine(3).into(), control_level: 3 });
    }
    if triangles {
        out.push(fair(Scheme::Loop(LoopBeta::Warren)));
    }
    out.push(fair(Scheme::DooSabin));
    out.push(Run {
        label: "fair (doo-sabin, J = 1)".into(),
        options: FairOptions::default()
            .with_scheme(Scheme::DooSabin)
            .expect("fair takes Doo-Sabin")
            .with_energy_levels(1)
            .into(),
        control_level: 1,
    });
    out
}

/// ∫H² dA of a surface, from the cotangent Laplacian of its triangulation
/// (Meyer, Desbrun, Schröder & Barr 2003: K(x_i) = (1/2A_i) Σ_j (cot α_ij +
/// cot β_ij)(x_j − x_i) = 2H·n, A_i a third of the incident triangles' area),
/// summed over interior vertices: Σ A_i·‖K_i‖²/4. Scale-invariant.
fn willmore(mesh: &Mesh) -> f64 {
    let t = mesh.topology();
    let x = mesh.positions();
    let n = t.vertex_count();
    let mut k = vec![DVec3::ZERO; n];
    let mut area = vec![0.0; n];
    for face in t.faces().iter() {
        for j in 1..face.len() - 1 {
            let tri = [face[0] as usize, face[j] as usize, face[j + 1] as usize];
            let a = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]).length() / 2.0;
            if a == 0.0 {
                continue;
            }
            for c in 0..3 {
                let (o, p, q) = (tri[c], tri[(c + 1) % 3], tri[(c + 2) % 3]);
                // The angle at o faces edge p-q.
                let (u, v) = (x[p] - x[o], x[q] - x[o]);
                let cot = u.dot(v) / u.cross(v).length();
                k[p] += cot * (x[q] - x[p]);
                k[q] += cot * (x[p] - x[q]);
                area[o] += a / 3.0;
            }
        }
    }
    t.vertices()
        .filter(|&v| !t.is_boundary_vertex(v) && area[v.index()] > 0.0)
        .map(|v| {
            let kv = k[v.index()] / (2.0 * area[v.index()]);
            area[v.index()] * kv.length_squared() / 4.0
        })
        .sum()
}

/// The closest point of triangle abc to p (Ericson, *Real-Time Collision
/// Detection*, §5.1.5).
fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// The triangles of a polygon mesh (fans) in a uniform grid, for exact
/// nearest-point queries.
struct TriangleGrid {
    tris: Vec<[DVec3; 3]>,
    min: DVec3,
    cell: f64,
    dims: [usize; 3],
    cells: Vec<Vec<u32>>,
}

impl TriangleGrid {
    fn new(mesh: &Mesh) -> Self {
        let x = mesh.positions();
        let mut tris = Vec::new();
        for face in mesh.topology().faces().iter() {
            for j in 1..face.len() - 1 {
                tris.push([x[face[0] as usize], x[face[j] as usize], x[face[j + 1] as usize]]);
            }
        }
        let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for t in &tris {
            for p in t {
                min = min.min(*p);
                max = max.max(*p);
            }
        }
        let extent = (max - min).max(DVec3::splat(1e-300));
        let per_axis = ((tris.len() as f64).cbrt() * 1.5).clamp(1.0, 200.0);
        let cell = extent.max_element() / per_axis;
        let dims = [0, 1, 2].map(|k| ((extent[k] / cell).floor() as usize + 1).max(1));
        let mut cells = vec![Vec::new(); dims[0] * dims[1] * dims[2]];
        for (i, t) in tris.iter().enumerate() {
            let lo = t[0].min(t[1]).min(t[2]);
            let hi = t[0].max(t[1]).max(t[2]);
            let (a, b) = (Self::coord(min, cell, dims, lo), Self::coord(min, cell, dims, hi));
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for xx in a[0]..=b[0] {
                        cells[(z * dims[1] + y) * dims[0] + xx].push(i as u32);
                    }
                }
            }
        }
        TriangleGrid { tris, min, cell, dims, cells }
    }

    fn coord(min: DVec3, cell: f64, dims: [usize; 3], p: DVec3) -> [usize; 3] {
        [0, 1, 2].map(|k| (((p[k] - min[k]) / cell).floor().max(0.0) as usize).min(dims[k] - 1))
    }

    /// The distance from p to the nearest triangle: shells of cells around
    /// p's cell, until the best distance is within the searched radius.
    fn distance(&self, p: DVec3) -> f64 {
        let c = Self::coord(self.min, self.cell, self.dims, p);
        let mut best = f64::INFINITY;
        let max_r = self.dims.iter().copied().max().unwrap_or(1);
        for r in 0..=max_r {
            let lo = [0, 1, 2].map(|k| c[k].saturating_sub(r));
            let hi = [0, 1, 2].map(|k| (c[k] + r).min(self.dims[k] - 1));
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        let on_shell = [x, y, z].iter().zip(&c).any(|(&a, &b)| a.abs_diff(b) == r);
                        if !on_shell {
                            continue;
                        }
                        for &i in &self.cells[(z * self.dims[1] + y) * self.dims[0] + x] {
                            let [a, b, cc] = self.tris[i as usize];
                            best = best.min(p.distance(closest_on_triangle(p, a, b, cc)));
                        }
                    }
                }
            }
            // Every point outside the searched cube is at least r·cell away
            // (p lies in the centre cell).
            if best <= r as f64 * self.cell {
                break;
            }
        }
        best
    }
}

/// The largest distance from the surface's vertices to the input mesh, / d.
fn max_distance(grid: &TriangleGrid, surface: &Mesh, d: f64) -> f64 {
    surface.positions().iter().map(|&p| grid.distance(p)).fold(0.0, f64::max) / d
}

/// The measured columns of one result.
struct Measures {
    error: f64,
    energy: f64,
    willmore: f64,
    distance: f64,
}

fn measure(mesh: &Mesh, grid: &TriangleGrid, r: &Interpolant, control_level: usize) -> Result<Measures> {
    let d = mesh.bbox_diagonal();
    let surface = r.surface(LEVEL - control_level)?;
    Ok(Measures {
        error: r.error_all(mesh).max_rel,
        energy: thin_plate_energy(&surface, SurfaceOptions::default(), LEVEL as u32, d),
        willmore: willmore(&surface),
        distance: max_distance(grid, &surface, d),
    })
}

/// The 10⁵-vertex model: the horse's quad mesh refined three times by
/// Catmull-Clark, its refined control points as data.
fn horse_big(ctx: &Ctx) -> Result<Mesh> {
    let horse = ctx.fixture("quad/horse_quad.obj")?;
    Ok(subdiv_stencil::subdivide(&horse, Scheme::CatmullClark, 3, false)?)
}

/// Table 7.
pub fn run(ctx: &Ctx) -> Result<Table> {
    let mut table = Table::new(
        "table7-fairness",
        "Table 7 — Fairness: every method against fair interpolation",
        &[
            "model",
            "vertices",
            "method",
            "control vertices",
            "max error / d",
            "thin-plate energy",
            "× cheng",
            "∫H² dA",
            "max dist. to input / d",
            "time (ms)",
        ],
    );
    table.setup = format!(
        "Every method with its defaults (tol 10⁻⁶·d), all vertices interpolated; `fair` with refine 1 \
         (control mesh M¹) and exact constraints, for Catmull-Clark, for Loop on triangle meshes and for \
         Doo-Sabin; and two variants of fair Catmull-Clark that see more of the surface: the energy on the \
         limit points of M² (`energy_levels` J = 1) and the control mesh M² (refine K = 2), and fair \
         Doo-Sabin with J = 1. Every measure is taken on the limit surface at level {LEVEL} of the input (the control \
         mesh refined {LEVEL} levels minus its own level, at limit positions): the **thin-plate energy** \
         4^{LEVEL}·Σ‖Δx‖²/d² (umbrella Laplacian, curve rule on boundaries; `subdiv_interp::fair::thin_plate_energy`, \
         the one function applied to every method; fair minimises the same form on its level-1 limit points, \
         which this level-{LEVEL} surface is not); **∫H² dA**, the Willmore energy from the cotangent \
         Laplacian of the triangulated surface (Meyer et al. 2003; interior vertices; 4π for a round sphere); \
         and the **largest distance** from the surface's vertices to the input polygon mesh (exact nearest \
         triangle through a uniform grid), / d: how far the surface bulges away from the data's mesh. The two \
         last measures are computed here, in `xtask/src/reproduce/fairness.rs`, by code that shares nothing \
         with the fair method. Models: `quad/spot_control_mesh.obj` (188 v), `tri/decimated-knight.off` \
         (502 v), `quad/fandisk_quads.off` (766 v){}. Deng-Wang triangulates quad meshes first (its surface \
         is that of the triangles). Time: the interpolation call (median), not the measures.",
        if ctx.quick {
            "; --quick: the small models only".to_string()
        } else {
            ", `open/stanford-bunny.obj` (35,947 v, open: five holes — the open case, which the closed \
             `tri/bunny_npm.obj` would not test; its 1,113 unreferenced vertices are left out with a warning) \
             and the 10⁵-vertex model: `quad/horse_quad.obj` refined three times by Catmull-Clark (153,602 v, \
             its refined control points as data; Cheng and fair only)"
                .to_string()
        }
    );
    // (name, mesh, big: Cheng and fair only, bound: with the K = 3 row).
    let mut models: Vec<(&str, Mesh, bool, bool)> = vec![
        ("spot", ctx.fixture("quad/spot_control_mesh.obj")?, false, true),
        ("knight", ctx.fixture("tri/decimated-knight.off")?, false, true),
        ("fandisk", ctx.fixture("quad/fandisk_quads.off")?, false, true),
    ];
    if !ctx.quick {
        models.push(("bunny", ctx.fixture("open/stanford-bunny.obj")?, false, BUNNY_BOUND));
        models.push(("horse-3", horse_big(ctx)?, true, false));
    }
    let mut summary = Vec::new();
    let mut bounds: Vec<(String, Option<f64>)> = Vec::new();
    for (name, mesh, big, bound) in &models {
        let grid = TriangleGrid::new(mesh);
        let n = mesh.topology().vertex_count();
        let (mut cheng_energy, mut cheng_measures) = (None, None);
        let runs = runs(mesh, *big, *bound);
        let repeats = if *big { 1 } else { ctx.runs() };
        for run in &runs {
            let (r, time) = timed(repeats, || interpolate(mesh, &run.options));
            let r = match r {
                Ok(r) => r,
                Err(e) => {
                    let mut cells = vec![name.to_string(), n.to_string(), run.label.clone(), "—".into()];
                    cells.push(format!("refused: {e}"));
                    cells.extend(["—"; 5].map(String::from));
                    table.row(cells);
                    continue;
                }
            };
            let m = measure(mesh, &grid, &r, run.control_level)?;
            if run.label == "cheng" {
                cheng_energy = Some(m.energy);
                cheng_measures = Some((m.willmore, m.distance));
            }
            let ratio = cheng_energy.map(|c| m.energy / c);
            let iterations = r.solve.as_ref().map_or(0, |s| s.iterations);
            table.row(vec![
                name.to_string(),
                n.to_string(),
                run.label.clone(),
                r.control.topology().vertex_count().to_string(),
                sci(m.error),
                sci(m.energy),
                ratio.map_or("—".into(), |x| format!("{x:.2}")),
                sci(m.willmore),
                sci(m.distance),
                ms(time),
            ]);
            table.json.push(json!({
                "model": name, "vertices": n, "method": run.label,
                "control_vertices": r.control.topology().vertex_count(), "max_rel": m.error,
                "energy": m.energy, "energy_over_cheng": ratio, "willmore": m.willmore,
                "max_distance": m.distance, "time_ms": time, "iterations": iterations,
            }));
            let key = format!("{name}/{}", run.label.replace([' ', '(', ')', ',', '=', ':'], ""));
            table.metric(format!("{key}/error"), m.error, Kind::Error);
            table.metric(format!("{key}/iterations"), iterations as f64, Kind::Iterations);
            if run.label.starts_with("fair") {
                // A fairness regression: the energy may not grow 10× either.
                table.metric(format!("{key}/energy"), m.energy, Kind::Error);
            }
            if run.label == "fair (catmull-clark)" {
                let (w, dist) = cheng_measures.unwrap_or((f64::NAN, f64::NAN));
                summary.push((name.to_string(), ratio, m.willmore / w, m.distance / dist, time));
            }
            if run.label == BOUND {
                bounds.push((name.to_string(), ratio));
            }
        }
    }
    let mut lines =
        vec!["**Fair (Catmull-Clark) against Cheng**, the exact method of the same scheme (ratios fair / cheng; \
         below 1: fair is fairer):"
            .to_string()];
    let x100 = |r: &Option<f64>| r.map_or("—".into(), |x| format!("{x:.2}"));
    for (name, ratio, w, dist, time) in &summary {
        let bound = match bounds.iter().find(|b| &b.0 == name) {
            Some((_, b)) => format!(" (its lower bound, fair K = 3: ×{})", x100(b)),
            None => " (lower bound not computed: M³ is too large)".into(),
        };
        lines.push(format!(
            "- {name}: thin-plate energy ×{}{bound}, ∫H² ×{w:.2}, max distance to the input mesh ×{dist:.2}; {} ms",
            x100(ratio),
            ms(*time)
        ));
    }
    table.notes.push(lines.join("\n"));
    table.notes.push(NOTE.into());
    if !ctx.quick {
        figure(ctx, &mut table)?;
    }
    Ok(table)
}

/// Spot: Cheng's control mesh and surface beside fair's.
fn figure(ctx: &Ctx, table: &mut Table) -> Result<()> {
    let spot = ctx.fixture("quad/spot_control_mesh.obj")?;
    let cheng = interpolate(&spot, &MethodOptions::new(Method::Cheng))?;
    let fair = interpolate(&spot, &MethodOptions::new(Method::Fair))?;
    let (cs, fs) = (cheng.surface(3)?, fair.surface(2)?);
    let view = View::yawed(-120.0);
    let camera = Camera::fitting(&view, &[&spot, &cs, &fs, &cheng.control, &fair.control], 380, 380);
    let mut panels = Vec::new();
    for (control, surface, what) in [(&cheng.control, &cs, "cheng"), (&fair.control, &fs, "fair")] {
        let c = render_with(control, &camera, &Style::control_mesh());
        let mut s = render_with(surface, &camera, &Style::surface());
        draw_dots(&mut s, &camera, spot.positions(), [220, 40, 40], 2.4);
        panels.push((c, format!("{what}: control mesh")));
        panels.push((s, format!("{what}: limit surface")));
    }
    let borrowed: Vec<_> = panels.iter().map(|(i, c)| (i.clone(), c.as_str())).collect();
    let img = side_by_side(&borrowed, "Spot: Cheng (exact, M̂) against fair (M¹, least thin-plate energy)");
    let name = "fig-fair-spot.png";
    img.save_png(&ctx.out.join(name))?;
    table.figures.push(name.into());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::shapes;

    /// A sphere sampled finely: ∫H² = 4π, max distance to itself 0.
    fn sphere() -> Mesh {
        let fine = subdiv_stencil::subdivide(&shapes::icosahedron(), Scheme::Loop(LoopBeta::Warren), 4, false).unwrap();
        let p = fine.positions().iter().map(|p| p.normalize()).collect();
        fine.with_positions(p)
    }

    #[test]
    fn willmore_of_a_sphere_is_four_pi() {
        let w = willmore(&sphere());
        assert!((w - 4.0 * std::f64::consts::PI).abs() < 0.05, "{w}");
        // Scale-invariant.
        let s = sphere();
        let big = s.with_positions(s.positions().iter().map(|p| 7.0 * *p).collect());
        assert!((willmore(&big) - w).abs() < 1e-9 * w);
    }

    #[test]
    fn distances_to_a_mesh_are_exact() {
        let grid = shapes::quad_grid(4, 4);
        let tri = TriangleGrid::new(&grid);
        for (p, expected) in [
            (DVec3::new(1.5, 2.5, 0.7), 0.7),
            (DVec3::new(-1.0, 2.0, 0.0), 1.0),
            (DVec3::new(-3.0, -4.0, 0.0), 5.0),
            (DVec3::new(2.2, 3.3, -0.25), 0.25),
        ] {
            assert!((tri.distance(p) - expected).abs() < 1e-12, "{p}: {}", tri.distance(p));
        }
    }
}
