//! Table 3: Cheng's Catmull-Clark interpolation — PIA, weighted PIA,
//! Chebyshev, CG, MINRES, GMRES and LDLᵀ; eigenvalue range of A per mesh;
//! meshes with interior valence-2 vertices, where A is indefinite ([correction C3])
//! and only MINRES, GMRES and LDLᵀ apply.
//!
//! [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3

use super::common::{ms, sci, timed, Ctx, Kind, Table};
use super::meshes::{closed_mix, dual, label};
use crate::valence2::{split_edges, DEFAULT_OFFSET};
use anyhow::Result;
use serde_json::json;
use std::collections::BTreeMap;
use subdiv_interp::{cheng, ChengOptions, CommonOptions, InterpError, SolverChoice};
use subdiv_mesh::{shapes, Mesh};
use subdiv_solve::{extreme_eigenvalues, FactoredMatrix, SolveError, Solver};
use subdiv_stencil::limit_matrix_catmull_clark;

const TOL: f64 = 1e-6;

/// The solvers of every row group, in table order.
const SOLVERS: [Solver; 7] = [
    Solver::Pia,
    Solver::WeightedPia,
    Solver::Chebyshev,
    Solver::Cg { jacobi: true },
    Solver::Minres,
    Solver::Gmres,
    Solver::Ldl,
];

/// Above this size LDLᵀ is skipped: its fill makes it take tens of seconds at
/// 6·10⁵ vertices, where the Krylov solvers take a fraction of a second.
const LDL_MAX: usize = 200_000;
/// [`LDL_MAX`] as the table prints it.
const LDL_MAX_LABEL: &str = "2·10⁵";

/// One mesh of the table.
struct Model {
    name: String,
    mesh: Mesh,
    /// Also solve the two-phase B(½) (left out on the largest meshes, where
    /// the A rows are the point).
    two_phase: bool,
    /// Has interior valence-2 vertices (A indefinite).
    valence_2: bool,
    /// The mesh this one was made from by splitting edges (its name).
    parent: Option<String>,
}

impl Model {
    fn new(name: impl Into<String>, mesh: Mesh) -> Self {
        Model { name: name.into(), mesh, two_phase: true, valence_2: false, parent: None }
    }
    /// `parent` with `count` interior edges split by `chain` valence-2
    /// vertices each: lone ones (`chain` = 1) leave A definite, pairs make it
    /// indefinite (see `crate::valence2`).
    fn split(parent: &Model, count: usize, chain: usize) -> Result<Self> {
        let what = if chain == 1 { "valence-2" } else { "valence-2 pairs" };
        debug_assert!(chain <= 2, "named for lone vertices and pairs");
        Ok(Model {
            name: format!("{} + {count} {what}", parent.name),
            mesh: split_edges(&parent.mesh, count, chain, DEFAULT_OFFSET)?,
            two_phase: parent.two_phase,
            valence_2: true,
            parent: Some(parent.name.clone()),
        })
    }
}

/// After the last model: it with `k` lone valence-2 vertices (A definite),
/// and with k/2 valence-2 pairs (the same number of vertices, A indefinite).
fn push_splits(models: &mut Vec<Model>, k: usize) -> Result<()> {
    let parent = models.last().expect("a parent model");
    let (lone, pairs) = (Model::split(parent, k, 1)?, Model::split(parent, k / 2, 2)?);
    models.extend([lone, pairs]);
    Ok(())
}

/// What one solve measured.
#[derive(Clone, Copy)]
struct Run {
    matvecs: usize,
    ms: f64,
    /// LDLᵀ only: negative pivots, i.e. negative eigenvalues of A (Sylvester's law of inertia).
    negative_pivots: Option<usize>,
}

/// Table 3.
pub fn run(ctx: &Ctx) -> Result<Table> {
    let mut table = Table::new(
        "table3-cheng",
        "Table 3 — Cheng et al. (A) and the two-phase B(½): progressive interpolation and faster solvers, \
         definite and indefinite",
        &[
            "model",
            "vertices",
            "matrix",
            "λ_min",
            "λ_max",
            "solver",
            "iterations",
            "sparse products",
            "time (ms)",
            "max error / d",
        ],
    );
    table.setup = format!(
        "A·M̂ = P with Cheng's limit matrix (appendix Eq. 5, [corrections C1/C2](../REFERENCES.md#c1)), all vertices \
         interpolated, tolerance \
         {TOL:e}·d on the max row residual; errors measured from the output control mesh by the Catmull-Clark \
         limit masks. λ_min, λ_max: Lanczos estimates on D^½SD^½ (Ritz values). PIA is the paper's iteration; \
         weighted PIA uses ω = 2/(λ_min + λ_max); B(½) is Fan-Cheng-Lai's two-phase matrix with λ = ½ on every face \
         (equal to Zheng-Cai's Z), solved through `fan_cheng_lai::interpolate`; CG runs on S·M̂ = D⁻¹P with a Jacobi \
         preconditioner; MINRES (Paige & Saunders 1975) on the same symmetric system, preconditioned by D, needs \
         S symmetric only; GMRES is restarted GMRES on A with a right Jacobi preconditioner; LDLᵀ is sparse with a \
         fill-reducing ordering. Meshes: Catmull-Clark control meshes (`quad/spot_control_mesh.obj`, Keenan \
         Crane; `quad/penguin_control_mesh.obj`, Oded Stein), `quad/fandisk_quads.off` (pmp-data), \
         `quad/horse_quad.obj` (libigl), `quad/sword-quad-dominant.obj` (22,293 v), the dual of \
         `tri/bunny_npm.obj` (all valences 3: the small-λ_min case), generated polygon tori (`shapes::polygon_mix` \
         of a quad torus: merged 5-8-gons, split quads, jittered data) and `horse_quad` refined four \
         Catmull-Clark levels (613,890 v). **Valence 2**: \"+ k valence-2\" is the mesh above it with k interior \
         edges between two quads split by a vertex each (`cargo xtask valence2-mesh --count k`: the two quads \
         become pentagons sharing two consecutive edges), \"+ k valence-2 pairs\" the same with two vertices per \
         edge (`--chain 2`: two hexagons sharing three edges), each new vertex moved off the surface by \
         {DEFAULT_OFFSET} edge lengths; `shapes::pillow` is two quads glued (every vertex of valence 2). A lone \
         valence-2 vertex leaves A positive definite (λ_min > 0; LDLᵀ finds no negative pivot); each pair, and \
         the pillow, gives A one negative eigenvalue ([correction C3](../REFERENCES.md#c3)), where PIA diverges and CG \
         breaks down (`cheng` \
         refuses them: n/a) and MINRES, GMRES and LDLᵀ are compared. LDLᵀ is skipped above {LDL_MAX_LABEL} vertices. The paper gives no timing table."
    );
    let mut models = Vec::new();
    let files: &[&str] = if ctx.quick {
        &["quad/spot_control_mesh.obj", "quad/fandisk_quads.off"]
    } else {
        &[
            "quad/spot_control_mesh.obj",
            "quad/penguin_control_mesh.obj",
            "quad/fandisk_quads.off",
            "quad/horse_quad.obj",
            "quad/sword-quad-dominant.obj",
        ]
    };
    for f in files {
        models.push(Model::new(label(f), ctx.fixture(f)?));
        // Valence-2 variants of one small and one medium quad mesh.
        if matches!(*f, "quad/spot_control_mesh.obj" | "quad/horse_quad.obj") {
            push_splits(&mut models, if ctx.quick { 4 } else { 6 })?;
        }
    }
    models.push(Model { valence_2: true, ..Model::new("pillow", shapes::pillow()) });
    models.push(Model::new("dual of bunny_npm", dual(&ctx.fixture("tri/bunny_npm.obj")?)));
    let sizes: &[usize] = if ctx.quick { &[10_000] } else { &[10_000, 100_000, 1_000_000] };
    for &n in sizes {
        models.push(Model::new(format!("polygon torus {n}"), closed_mix(n)));
        if n == 100_000 {
            push_splits(&mut models, 8)?;
            // B(½) with valence-2 vertices is shown on the smaller meshes.
            let k = models.len();
            models[k - 2..].iter_mut().for_each(|m| m.two_phase = false);
        }
    }
    if !ctx.quick {
        // The end-to-end case of issue 13: 614k vertices, a few valence-2 vertices.
        let horse = ctx.fixture("quad/horse_quad.obj")?;
        let fine = subdiv_stencil::subdivide(&horse, subdiv_stencil::Scheme::CatmullClark, 4, false)?;
        models.push(Model { two_phase: false, ..Model::new("horse_quad ×4", fine) });
        push_splits(&mut models, 6)?;
    }
    let mut runs: BTreeMap<(String, &str, &str), Run> = BTreeMap::new();
    for model in &models {
        let matrices: &[(&str, bool)] =
            if model.two_phase { &[("A", false), ("B(½)", true)] } else { &[("A", false)] };
        for &(matrix, two_phase) in matrices {
            solve_all(ctx, &mut table, model, matrix, two_phase, &mut runs)?;
        }
    }
    valence_2_note(&mut table, &models, &runs);
    matrix_products(ctx, &mut table)?;
    table.notes.push(
        "The spectrum of A is size-independent (λ_min ≈ 0.11 for the regular bicubic mask on quad meshes), so the \
         iteration counts do not grow with the mesh; meshes dominated by valence-3 vertices (the dual of a \
         triangle mesh) have a much smaller λ_min, where plain PIA needs hundreds of iterations and CG tens."
            .into(),
    );
    Ok(table)
}

/// The rows of one model and matrix: every solver of [`SOLVERS`].
fn solve_all(
    ctx: &Ctx,
    table: &mut Table,
    model: &Model,
    matrix: &'static str,
    two_phase: bool,
    runs: &mut BTreeMap<(String, &'static str, &'static str), Run>,
) -> Result<()> {
    let (name, mesh) = (&model.name, &model.mesh);
    let n = mesh.topology().vertex_count();
    let a = if two_phase {
        subdiv_interp::limit_matrix_two_phase(mesh.topology(), subdiv_interp::CornerRule::Uniform(0.5))?
    } else {
        limit_matrix_catmull_clark(mesh.topology())
    };
    let fm = FactoredMatrix::new(a.d.clone(), a.s.clone())?;
    // Lanczos needs S symmetric; the Doo-Sabin rows of valence-2 vertices are not.
    let spectrum = if fm.symmetric() { Some(extreme_eigenvalues(&fm, 60)?) } else { None };
    let indefinite = spectrum.is_some_and(|s| s.ritz_min < 0.0);
    let key = format!("{name}/{matrix}");
    if let Some(s) = &spectrum {
        table.metric(format!("{key}/lambda_min"), s.ritz_min, Kind::Error);
    }
    let all = vec![true; n];
    for (k, solver) in SOLVERS.into_iter().enumerate() {
        let (lmin, lmax) = match (k, &spectrum) {
            (0, Some(s)) => (sci(s.ritz_min), format!("{:.4}", s.ritz_max)),
            (0, None) => ("— (S not symmetric)".into(), "—".into()),
            _ => (String::new(), String::new()),
        };
        let mut row = vec![name.clone(), n.to_string(), matrix.into(), lmin, lmax, solver.name().into()];
        let unmeasured = |why: String| vec!["—".into(), "—".into(), why, "—".into()];
        if solver == Solver::Ldl && n > LDL_MAX {
            row.extend(unmeasured(format!("skipped (n > {LDL_MAX_LABEL})")));
            table.row(row);
            continue;
        }
        let common =
            CommonOptions::default().with_tol(TOL).with_solver(SolverChoice::Use(solver)).with_max_iter(20_000);
        let (r, t) = timed(ctx.runs(), || {
            if two_phase {
                let shape = subdiv_interp::Shape::Uniform(0.5);
                subdiv_interp::fan_cheng_lai::interpolate(
                    mesh,
                    &subdiv_interp::FanChengLaiOptions::default().with_common(common.clone()).with_shape(shape),
                )
            } else {
                cheng::interpolate(mesh, &ChengOptions::default().with_common(common.clone()))
            }
        });
        match r {
            Ok(r) => {
                let s = r.solve.clone().unwrap_or_default();
                let err = r.error(mesh.positions(), &all, mesh.bbox_diagonal()).max_rel;
                row.extend([s.iterations.to_string(), s.matvecs.to_string(), ms(t), sci(err)]);
                table.json.push(json!({"model": name, "vertices": n, "matrix": matrix, "solver": solver.name(), "iterations": s.iterations, "matvecs": s.matvecs, "ms": t, "max_rel": err, "lambda_min": spectrum.map(|s| s.ritz_min), "lambda_max": spectrum.map(|s| s.ritz_max)}));
                table.metric(format!("{key}/{}/iterations", solver.name()), s.iterations as f64, Kind::Iterations);
                table.metric(format!("{key}/{}/error", solver.name()), err, Kind::Error);
                runs.insert(
                    (name.clone(), matrix, solver.name()),
                    Run { matvecs: s.matvecs, ms: t, negative_pivots: s.negative_pivots },
                );
            }
            Err(InterpError::UnsupportedMesh { .. }) if indefinite => {
                row.extend(unmeasured("n/a (A indefinite): refused".into()))
            }
            Err(InterpError::UnsupportedMesh { .. }) if spectrum.is_some() => {
                row.extend(unmeasured("refused, though λ_min > 0".into()))
            }
            Err(InterpError::Solve { source, .. }) if matches!(*source, SolveError::NotSymmetric { .. }) => {
                row.extend(unmeasured("n/a (S not symmetric)".into()))
            }
            Err(e) => row.extend(unmeasured(format!("failed: {e}"))),
        }
        table.row(row);
    }
    Ok(())
}

/// The valence-2 meshes against the meshes they were split from: MINRES's
/// products there over CG's on the parent, and LDLᵀ's time over MINRES's.
fn valence_2_note(table: &mut Table, models: &[Model], runs: &BTreeMap<(String, &str, &str), Run>) {
    let mut lines = vec![
        "| valence-2 mesh | vertices | negative eigenvalues of A (LDLᵀ pivots) | MINRES products | CG products on \
         the mesh without them | ratio | GMRES products | MINRES (ms) | LDLᵀ (ms) | LDLᵀ / MINRES |"
            .to_string(),
        "|---|---|---|---|---|---|---|---|---|---|".to_string(),
    ];
    let get = |name: &str, solver: Solver| runs.get(&(name.to_string(), "A", solver.name())).copied();
    let cell = |r: Option<Run>, f: fn(Run) -> String| r.map_or("—".to_string(), f);
    let mut ratios = Vec::new();
    for model in models.iter().filter(|m| m.valence_2) {
        let Some(minres) = get(&model.name, Solver::Minres) else { continue };
        let parent_cg = model.parent.as_deref().and_then(|p| get(p, Solver::Cg { jacobi: true }));
        ratios.extend(parent_cg.map(|c| minres.matvecs as f64 / c.matvecs as f64));
        let ldl = get(&model.name, Solver::Ldl);
        lines.push(format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            model.name,
            model.mesh.topology().vertex_count(),
            ldl.and_then(|r| r.negative_pivots).map_or("—".into(), |k| k.to_string()),
            minres.matvecs,
            cell(parent_cg, |r| r.matvecs.to_string()),
            parent_cg.map_or("—".into(), |c| format!("{:.2}", minres.matvecs as f64 / c.matvecs as f64)),
            cell(get(&model.name, Solver::Gmres), |r| r.matvecs.to_string()),
            ms(minres.ms),
            cell(ldl, |r| ms(r.ms)),
            ldl.map_or("—".into(), |l| format!("{:.1}", l.ms / minres.ms)),
        ));
    }
    let (lo, hi) = ratios.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    table.notes.push(format!(
        "**Valence-2 vertices**: the negative eigenvalues of A, counted exactly by LDLᵀ's negative pivots \
         (Sylvester's law of inertia; where LDLᵀ is skipped, λ_min above shows the sign), MINRES's sparse products \
         against CG's on the same mesh before its edges were split ({lo:.2}-{hi:.2}×), and LDLᵀ's time against \
         MINRES's:\n\n{}",
        lines.join("\n")
    ));
}

/// Sparse products to 1e-6·d of PIA, CG, MINRES and GMRES on the limit
/// matrices themselves (Cheng's A on quad fixtures, Loop's L on triangle
/// fixtures, the two-phase B(½) on both): the spectra are size-independent,
/// so these counts are too.
fn matrix_products(ctx: &Ctx, table: &mut Table) -> Result<()> {
    use subdiv_interp::{limit_matrix_two_phase, CornerRule};
    use subdiv_solve::SolveOptions;
    use subdiv_stencil::{limit_matrix_loop, LimitMatrix, LoopBeta};
    let files: &[&str] = if ctx.quick {
        &["quad/spot_control_mesh.obj", "tri/eight.off"]
    } else {
        &[
            "quad/spot_control_mesh.obj",
            "quad/fandisk_quads.off",
            "quad/horse_quad.obj",
            "tri/eight.off",
            "tri/bunny_npm.obj",
            "tri/armadillo.obj",
        ]
    };
    let mut lines = vec![
        "| model | vertices | matrix | PIA products | CG products | MINRES products | GMRES products | PIA / CG |"
            .to_string(),
        "|---|---|---|---|---|---|---|---|".to_string(),
    ];
    for file in files {
        let mesh = ctx.fixture(file)?;
        let t = mesh.topology();
        let mut matrices: Vec<(&str, LimitMatrix)> =
            vec![("B(½)", limit_matrix_two_phase(t, CornerRule::Uniform(0.5))?)];
        if t.faces().all_of_size(3) {
            matrices.insert(0, ("L (Warren)", limit_matrix_loop(t, LoopBeta::Warren)?));
        } else {
            matrices.insert(0, ("A (Cheng)", limit_matrix_catmull_clark(t)));
        }
        let p: Vec<[f64; 3]> = mesh.positions().iter().map(|q| q.to_array()).collect();
        let opts = SolveOptions::default().with_tol(TOL).with_scale(mesh.bbox_diagonal());
        for (name, a) in matrices {
            let fm = FactoredMatrix::new(a.d.clone(), a.s.clone())?;
            let [pia, cg, minres, gmres] = [Solver::Pia, Solver::Cg { jacobi: true }, Solver::Minres, Solver::Gmres]
                .map(|s| s.solve(&fm, &p, &opts));
            let [pia, cg, minres, gmres] = [pia?.matvecs, cg?.matvecs, minres?.matvecs, gmres?.matvecs];
            lines.push(format!(
                "| {} | {} | {name} | {pia} | {cg} | {minres} | {gmres} | {:.1} |",
                label(file),
                t.vertex_count(),
                pia as f64 / cg as f64
            ));
            for (solver, products) in [("pia", pia), ("cg", cg), ("minres", minres), ("gmres", gmres)] {
                table.metric(format!("{}/{name}/{solver}-products", label(file)), products as f64, Kind::Iterations);
            }
            table.json.push(json!({"model": file, "matrix": name, "pia_products": pia, "cg_products": cg, "minres_products": minres, "gmres_products": gmres}));
        }
    }
    table.notes.push(format!(
        "**Sparse products to 10⁻⁶·d on the limit matrices themselves** (data = the fixture's vertices; CG with \
         a Jacobi preconditioner, products include the final residual check):\n\n{}",
        lines.join("\n")
    ));
    Ok(())
}
