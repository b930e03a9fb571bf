//! Table 6: every method on the papers' sizes and on 10⁵ and 10⁶ vertices —
//! setup, solve and total time, iterations, error (issue "six methods",
//! performance criterion).

use super::common::{ms, sci, timed, Ctx, Kind, Table};
use super::meshes::closed_mix;
use anyhow::Result;
use serde_json::json;
use subdiv_interp::{interpolate, InterpError, Method, MethodOptions};
use subdiv_mesh::Mesh;

/// Table 6.
pub fn run(ctx: &Ctx) -> Result<Table> {
    let mut table = Table::new(
        "table6-methods",
        "Table 6 — All methods: setup, solve and total time by size",
        &["model", "vertices", "method", "setup (ms)", "solve (ms)", "total (ms)", "iterations", "max error / d"],
    );
    table.setup = "Each method with its defaults (tol 10⁻⁶·d; solver `auto`: CG with a Jacobi preconditioner for \
        Nasri and Cheng, the paper's progressive iteration for Fan-Cheng-Lai, Gauss-Seidel ITE_MAX = 5 for \
        Zheng-Cai), all vertices interpolated. Setup = building operators (limit matrix, first refined mesh \
        topology); solve = solving and assembling the control mesh (each the median over the runs); total = median wall time of the call, which also checks the input. \
        Deng-Ma's \"solve\" is zero: its output is the scheme itself (the surface costs extra). Real models, \
        the papers' sizes: `tri/decimated-knight.off` (502 v), `quad/fandisk_quads.off` (766 v, quads), \
        `open/halftunnel.off` (831 v, open quads), `tri/rocker-arm.obj` (10,044 v) and `open/camelhead.off` \
        (11,381 v, open: the size closest to the paper's 11,540); generated: polygon tori (`shapes::polygon_mix`) \
        of 10⁵ and 10⁶ vertices. Deng-Wang (Loop) gets non-triangle meshes triangulated beforehand \
        (`subdiv_mesh::triangulate`, outside its timing; the method itself would do the same inside); Deng-Ma \
        takes open meshes with its 4-point boundary curves (our construction). \
        Zheng-Cai report 4.9 ms + 37 ms for 562 vertices and 79 ms + 491 ms \
        for 11,540 (2005 PC)."
        .into();
    let mut models: Vec<(String, Mesh)> = vec![("decimated-knight".into(), ctx.fixture("tri/decimated-knight.off")?)];
    if !ctx.quick {
        for (name, file) in [
            ("fandisk", "quad/fandisk_quads.off"),
            ("halftunnel", "open/halftunnel.off"),
            ("rocker-arm", "tri/rocker-arm.obj"),
            ("camelhead", "open/camelhead.off"),
        ] {
            models.push((name.into(), ctx.fixture(file)?));
        }
        for n in [100_000, 1_000_000] {
            models.push((format!("polygon torus {n}"), closed_mix(n)));
        }
    }
    for (name, mesh) in &models {
        let tri =
            if mesh.topology().faces().all_of_size(3) { None } else { Some(subdiv_mesh::triangulate(mesh)?.mesh) };
        // fair has its own table (table7, `fairness.rs`), with its energy columns.
        for m in Method::ALL.into_iter().filter(|&m| m != Method::Fair) {
            let (method, options) = (m.name(), MethodOptions::new(m));
            let input = if m == Method::DengWang { tri.as_ref().unwrap_or(mesh) } else { mesh };
            let mut phases = Vec::new(); // (setup, solve) of every run: their medians are reported
            let (r, total) = timed(ctx.runs(), || {
                let r = interpolate(input, &options);
                if let Ok(r) = &r {
                    phases.push((r.setup_seconds, r.solve_seconds));
                }
                r
            });
            let median = |pick: fn(&(f64, f64)) -> f64| {
                let mut v: Vec<f64> = phases.iter().map(pick).collect();
                v.sort_by(f64::total_cmp);
                v.get(v.len() / 2).copied().unwrap_or(0.0)
            };
            let (setup_s, solve_s) = (median(|p| p.0), median(|p| p.1));
            let n = input.topology().vertex_count();
            match r {
                Ok(r) => {
                    let err = r.error_all(input).max_rel;
                    let it = r.solve.as_ref().map_or(0, |s| s.iterations);
                    table.row(vec![
                        name.clone(),
                        n.to_string(),
                        method.into(),
                        ms(setup_s * 1e3),
                        ms(solve_s * 1e3),
                        ms(total),
                        it.to_string(),
                        sci(err),
                    ]);
                    table.json.push(json!({"model": name, "vertices": n, "method": method, "setup_ms": setup_s * 1e3, "solve_ms": solve_s * 1e3, "total_ms": total, "iterations": it, "max_rel": err}));
                    table.metric(format!("{name}/{method}/iterations"), it as f64, Kind::Iterations);
                    table.metric(format!("{name}/{method}/error"), err, Kind::Error);
                }
                Err(e) => table.row(vec![
                    name.clone(),
                    n.to_string(),
                    method.into(),
                    "—".into(),
                    "—".into(),
                    "—".into(),
                    "—".into(),
                    match e {
                        InterpError::UnsupportedMesh { reason, .. } => format!("refused: {reason}"),
                        e => format!("failed: {e}"),
                    },
                ]),
            }
        }
    }
    Ok(table)
}
