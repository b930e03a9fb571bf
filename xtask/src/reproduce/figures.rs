//! Figures as in the papers: input mesh, control mesh and limit surface side
//! by side for real models, and the parameter sweeps (λ, shape handles, ω, μ).

use super::common::{Ctx, Table};
use crate::render::{draw_dots, render_with, side_by_side, Camera, Image, Style, View};
use anyhow::Result;
use subdiv_interp::{
    cheng, deng_ma, deng_wang, fan_cheng_lai, nasri, zheng_cai, ChengOptions, DengMaOptions, DengWangOptions,
    FanChengLaiOptions, Interpolant, NasriOptions, Shape, ZhengCaiOptions,
};
use subdiv_mesh::Mesh;
use subdiv_stencil::{LoopBeta, Tension};

const PANEL: u32 = 420;
const DATA_DOTS: ([u8; 3], f32) = ([220, 40, 40], 2.6);

/// The three panels of one model: input (data dots), control mesh, surface with the data dots.
fn model_figure(title: &str, mesh: &Mesh, r: &Interpolant, control_caption: &str, view: &View) -> Result<Image> {
    let surface = r.surface(3)?;
    let show_control = r.control.topology().vertex_count() != mesh.topology().vertex_count()
        || r.control.positions() != mesh.positions();
    let mut meshes = vec![mesh, &surface];
    if show_control {
        meshes.push(&r.control);
    }
    let camera = Camera::fitting(view, &meshes, PANEL, PANEL);
    let mut input = render_with(mesh, &camera, &Style::input_mesh());
    draw_dots(&mut input, &camera, mesh.positions(), DATA_DOTS.0, DATA_DOTS.1);
    let mut limit = render_with(&surface, &camera, &Style::surface());
    draw_dots(&mut limit, &camera, mesh.positions(), DATA_DOTS.0, DATA_DOTS.1);
    let mut panels = vec![(input, "input mesh (data points red)")];
    if show_control {
        panels.push((render_with(&r.control, &camera, &Style::control_mesh()), control_caption));
    }
    panels.push((limit, "limit surface through the data"));
    Ok(side_by_side(&panels, title))
}

/// Surfaces of one model for several parameter values, one camera.
fn sweep_figure(title: &str, mesh: &Mesh, runs: &[(String, Interpolant)], view: &View) -> Result<Image> {
    let surfaces: Vec<Mesh> = runs.iter().map(|(_, r)| r.surface(3)).collect::<Result<_, _>>()?;
    let mut meshes: Vec<&Mesh> = surfaces.iter().collect();
    meshes.push(mesh);
    let camera = Camera::fitting(view, &meshes, PANEL, PANEL);
    let mut input = render_with(mesh, &camera, &Style::input_mesh());
    draw_dots(&mut input, &camera, mesh.positions(), DATA_DOTS.0, DATA_DOTS.1);
    let mut panels = vec![(input, "input mesh".to_string())];
    for ((caption, _), s) in runs.iter().zip(&surfaces) {
        let mut img = render_with(s, &camera, &Style::surface());
        draw_dots(&mut img, &camera, mesh.positions(), DATA_DOTS.0, DATA_DOTS.1);
        panels.push((img, caption.clone()));
    }
    let borrowed: Vec<(Image, &str)> = panels.iter().map(|(i, c)| (i.clone(), c.as_str())).collect();
    Ok(side_by_side(&borrowed, title))
}

fn save(ctx: &Ctx, table: &mut Table, name: &str, img: Image, caption: &str) -> Result<()> {
    img.save_png(&ctx.out.join(name))?;
    table.row(vec![format!("[`{name}`]({name})"), caption.to_string()]);
    table.figures.push(name.to_string());
    Ok(())
}

/// The figure gallery (skipped in quick mode).
pub fn run(ctx: &Ctx) -> Result<Table> {
    let mut table = Table::new(
        "figures",
        "Figures — input, control mesh and limit surface; parameter sweeps; Deng-Ma on open meshes",
        &["figure", "what it shows"],
    );
    table.setup = "Rendered headless by `xtask/src/render.rs` (software rasteriser, z-buffer, Lambert shading, \
        DejaVu Sans captions). Red dots: the input vertices (the data); on every surface panel they lie on the \
        surface. Surfaces are the control meshes refined three levels by their plain scheme, at limit positions."
        .into();
    if ctx.quick {
        table.notes.push("Quick mode: figures are not regenerated.".into());
        return Ok(table);
    }
    let view = View::default();
    let spot = ctx.fixture("quad/spot_control_mesh.obj")?;
    let r = cheng::interpolate(&spot, &ChengOptions::default())?;
    save(ctx, &mut table, "fig-cheng-spot.png", model_figure("Cheng: Catmull-Clark interpolation of Spot", &spot, &r, "control mesh M̂ (Catmull-Clark)", &View::yawed(-120.0))?, "Cheng, Catmull-Clark: Spot's control mesh as data; the solved control mesh M̂ bulges outward so the limit surface passes through every vertex (cf. Cheng Fig. 3-4).")?;
    let (img, caption) = super::fit_spot::figure(&ctx.fixture("tri/spot_triangulated.obj")?, &spot)?;
    save(ctx, &mut table, "fig-fit-spot.png", img, &caption)?;
    let knight = ctx.fixture("tri/decimated-knight.off")?;
    let r = zheng_cai::interpolate(&knight, &ZhengCaiOptions::default())?;
    save(
        ctx,
        &mut table,
        "fig-zheng-cai-knight.png",
        model_figure(
            "Zheng-Cai: Doo-Sabin interpolation (knight, 502 vertices)",
            &knight,
            &r,
            "perturbed first refined mesh M¹",
            &view,
        )?,
        "Zheng-Cai (Fig. 3-4 of the paper): input, perturbed first refined mesh M¹, interpolating Doo-Sabin surface.",
    )?;
    let mpi = ctx.fixture("poly/mpi.off")?;
    let r = nasri::interpolate(&mpi, &NasriOptions::default())?;
    save(
        ctx,
        &mut table,
        "fig-nasri-mpi.png",
        model_figure(
            "Nasri: Doo-Sabin interpolation of a polygon mesh (faces of 3-10 sides)",
            &mpi,
            &r,
            "auxiliary mesh M⁰",
            &view,
        )?,
        "Nasri 1987 (Zheng-Cai Fig. 4(d-e)): auxiliary mesh M⁰ from C·M⁰ = P and its Doo-Sabin surface.",
    )?;
    let bunny = ctx.fixture("tri/bunny_npm.obj")?;
    let r = deng_wang::interpolate(&bunny, &DengWangOptions::default().with_beta(LoopBeta::Warren))?;
    save(
        ctx,
        &mut table,
        "fig-deng-wang-bunny.png",
        model_figure(
            "Deng-Wang: Loop interpolation of the bunny (μ = ¼)",
            &bunny,
            &r,
            "modified first refined mesh M¹",
            &View::yawed(20.0),
        )?,
        "Deng-Wang: the modified first Loop step M¹ and its Loop limit surface through the bunny's 1,839 vertices.",
    )?;
    let cube = ctx.fixture("poly/cube_poly.off")?;
    let r = deng_ma::interpolate(&cube, &DengMaOptions::default())?;
    save(
        ctx,
        &mut table,
        "fig-deng-ma-cube.png",
        model_figure("Deng-Ma: interpolatory Doo-Sabin-derived scheme", &cube, &r, "", &view)?,
        "Deng-Ma: the interpolatory scheme keeps the input vertices; the refined surface passes through them.",
    )?;
    let halftunnel = ctx.fixture("open/halftunnel.off")?;
    let nefertiti = ctx.fixture("open/nefertiti_small.off")?;
    save(ctx, &mut table, "fig-deng-ma-open.png", super::deng_ma_open::figure(&nefertiti, &halftunnel)?, "Beyond the paper: Deng-Ma on open meshes. Each boundary loop (orange) is refined by the 4-point rule with the surface's tension, the input vertices (red) stay, and the surface meets its boundary curve smoothly.")?;
    let r = fan_cheng_lai::interpolate(&halftunnel, &FanChengLaiOptions::default())?;
    save(ctx, &mut table, "fig-fan-cheng-lai-halftunnel.png", model_figure("Fan-Cheng-Lai on an open mesh (3 boundary loops, λ = ½)", &halftunnel, &r, "first refined mesh M¹", &View { pitch: 45.0, ..view })?, "Beyond the papers: two-phase Doo-Sabin interpolation of an open quad mesh; the boundary is the quadratic B-spline through the boundary data.")?;
    let chamfer = ctx.fixture("poly/chamfer-cube.off")?;
    save(ctx, &mut table, "fig-doo-sabin-creases.png", super::doo_sabin_creases::figure(&subdiv_mesh::shapes::cube(), &chamfer)?, "Beyond the papers: Doo-Sabin with infinitely sharp creases, level 4 at limit positions. A crease is a boundary of both sides, so the sharp polygon (orange) refines by Chaikin's rule and the crease is its quadratic B-spline: the cube's top loop becomes a rounded-square rim, with all 12 edges sharp the surface is the cube itself (corners kept, edges straight), and the chamfered cube keeps its six main faces flat inside their crease loops while the chamfers round off.")?;

    // Parameter sweeps.
    let knight_lambda: Vec<(String, Interpolant)> = [0.85, 0.5, 0.4]
        .iter()
        .map(|&l| {
            Ok((
                format!("λ = {l}"),
                fan_cheng_lai::interpolate(&knight, &FanChengLaiOptions::default().with_shape(Shape::Uniform(l)))?,
            ))
        })
        .collect::<Result<_>>()?;
    let mut runs = knight_lambda;
    let c = knight.face_centroids();
    let mut zs: Vec<f64> = c.iter().map(|p| p.y).collect();
    zs.sort_by(f64::total_cmp);
    let median = zs[zs.len() / 2];
    let local: Vec<f64> = c.iter().map(|p| if p.y > median { 0.85 } else { 0.4 }).collect();
    runs.push((
        "upper part 0.85, rest 0.4".into(),
        fan_cheng_lai::interpolate(&knight, &FanChengLaiOptions::default().with_shape(Shape::PerFace(local)))?,
    ));
    save(
        ctx,
        &mut table,
        "fig-sweep-lambda.png",
        sweep_figure("Fan-Cheng-Lai: shape parameter λ (cf. Fig. 3-5)", &knight, &runs, &view)?,
        "λ sweep: larger λ keeps the surface closer to the mesh; a local λ pattern changes only that part.",
    )?;

    let handles: Vec<(String, Interpolant)> = [0.4, 1.0, 2.5]
        .iter()
        .map(|&s| {
            let opts = ZhengCaiOptions::default().with_handles(vec![s; spot.topology().vertex_count()]);
            Ok((format!("S = {s}"), zheng_cai::interpolate(&spot, &opts)?))
        })
        .collect::<Result<_>>()?;
    save(ctx, &mut table, "fig-sweep-handles.png", sweep_figure("Zheng-Cai: Brunet shape handles (cf. Fig. 8)", &spot, &handles, &View::yawed(-120.0))?, "Shape handles: S < 1 gives slim shapes near the data points, S > 1 round/flat spots; interpolation holds throughout.")?;

    let omegas: Vec<(String, Interpolant)> = [
        ("ω = 0.25", Tension::Global(0.25)),
        ("ω = 0.5", Tension::Global(0.5)),
        ("ω = 1", Tension::Global(1.0)),
        ("variable, λ = 1", Tension::Variable { lambda: 1.0 }),
    ]
    .iter()
    .map(|(name, t)| Ok((name.to_string(), deng_ma::interpolate(&mpi, &DengMaOptions::default().with_tension(*t))?)))
    .collect::<Result<_>>()?;
    save(ctx, &mut table, "fig-sweep-omega.png", sweep_figure("Deng-Ma: tension ω", &mpi, &omegas, &view)?, "Tension sweep: ω → 0 approaches the mesh's own facets, ω = 1 is the 4-point analogue; the variable ω_P keeps displacements safe.")?;

    let eight = ctx.fixture("tri/eight.off")?;
    let mus: Vec<(String, Interpolant)> = [0.0, 0.25, 0.5]
        .iter()
        .map(|&mu| {
            Ok((
                format!("μ = {mu}"),
                deng_wang::interpolate(&eight, &DengWangOptions::default().with_beta(LoopBeta::Warren).with_mu(mu))?,
            ))
        })
        .collect::<Result<_>>()?;
    save(
        ctx,
        &mut table,
        "fig-sweep-mu.png",
        sweep_figure("Deng-Wang: edge parameter μ", &eight, &mus, &view)?,
        "μ sweep on a genus-2 mesh: μ = 0 uses plain midpoints, larger μ pushes edge points along the vertex normals.",
    )?;
    Ok(table)
}
