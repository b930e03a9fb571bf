//! Table 4: Deng-Wang (Loop) and Deng-Ma (interpolatory) — interpolation
//! error (round-off by construction) and fairness over their parameters.

use super::common::{sci, Ctx, Kind, Table};
use super::meshes::label;
use anyhow::Result;
use serde_json::json;
use subdiv_interp::{deng_ma, deng_wang, DengMaOptions, DengWangOptions, Interpolant};
use subdiv_mesh::Mesh;
use subdiv_stencil::{LoopBeta, Tension};

/// Length-weighted mean squared dihedral angle over interior edges (a
/// discrete bending energy; 0 for a plane, small for fair surfaces).
pub fn bending(mesh: &Mesh) -> f64 {
    let t = mesh.topology();
    let normals = mesh.face_normals();
    let (mut num, mut den) = (0.0, 0.0);
    for e in t.edges() {
        if let (f, Some(g)) = t.edge_faces(e) {
            let (a, b) = t.edge_vertices(e);
            let len = mesh.position(a).distance(mesh.position(b));
            let angle = normals[f.index()].dot(normals[g.index()]).clamp(-1.0, 1.0).acos();
            num += len * angle * angle;
            den += len;
        }
    }
    num / den.max(f64::MIN_POSITIVE)
}

fn max_error(mesh: &Mesh, r: &Interpolant) -> f64 {
    let all = vec![true; mesh.topology().vertex_count()];
    r.error(mesh.positions(), &all, mesh.bbox_diagonal()).max_rel
}

/// Table 4.
pub fn run(ctx: &Ctx) -> Result<Table> {
    let mut table = Table::new(
        "table4-deng",
        "Table 4 — Deng & Wang 2010 (Loop) and Deng & Ma 2011 (interpolatory): error and fairness",
        &["method", "model", "parameter", "max error / d", "sphere deviation / d", "bending energy (level 3)"],
    );
    table.setup = "Deng-Wang: modified first Loop step with normal-based edge points (Eq. 8-9, \
        [corrections W5/W6](../REFERENCES.md#w5)) and vertex points solved so that the Loop limit of vertex i is \
        P_i ([correction W7](../REFERENCES.md#w7)); Warren's β. Deng-Ma: the \
        interpolatory Doo-Sabin-derived scheme with global ω or the variable tension of §3.4 (λ). Error: from \
        the output by the plain rules (Loop limit masks; for Deng-Ma the input vertices are vertices of the \
        refined surface). Sphere deviation: max | |p| − 1 | over the level-3 limit surface of \
        `canonical/icosphere_2.obj` (points on the unit sphere). Bending energy: length-weighted mean squared \
        dihedral angle of the level-3 surface (lower = fairer). The papers give no tables."
        .into();
    let sphere = ctx.fixture("canonical/icosphere_2.obj")?;
    let models = [("canonical/icosphere_2.obj", sphere.clone()), ("tri/eight.off", ctx.fixture("tri/eight.off")?)];
    let deviation =
        |s: &Mesh| s.positions().iter().map(|p| (p.length() - 1.0).abs()).fold(0.0, f64::max) / sphere.bbox_diagonal();
    for (file, mesh) in &models {
        let is_sphere = file.contains("icosphere");
        for mu in [0.0, 0.125, 0.25, 0.375, 0.5] {
            let r = deng_wang::interpolate(mesh, &DengWangOptions::default().with_beta(LoopBeta::Warren).with_mu(mu))?;
            let s = r.surface(3)?;
            let e = max_error(mesh, &r);
            let dev = if is_sphere { sci(deviation(&s)) } else { "—".into() };
            let b = bending(&s);
            table.row(vec!["deng-wang".into(), label(file), format!("μ = {mu}"), sci(e), dev.clone(), sci(b)]);
            table.json.push(json!({"method": "deng-wang", "model": file, "mu": mu, "max_rel": e, "bending": b}));
            table.metric(format!("deng-wang/{}/mu={mu}/error", label(file)), e, Kind::Error);
        }
        if ctx.quick {
            continue;
        }
        let tensions = [
            ("ω = 0.25", Tension::Global(0.25)),
            ("ω = 0.5", Tension::Global(0.5)),
            ("ω = 0.75", Tension::Global(0.75)),
            ("ω = 1", Tension::Global(1.0)),
            ("variable, λ = 0.5", Tension::Variable { lambda: 0.5 }),
            ("variable, λ = 1", Tension::Variable { lambda: 1.0 }),
        ];
        for (name, tension) in tensions {
            let r = deng_ma::interpolate(mesh, &DengMaOptions::default().with_tension(tension))?;
            let s = r.surface(3)?;
            let n = mesh.topology().vertex_count();
            let e = s.positions()[..n].iter().zip(mesh.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max)
                / mesh.bbox_diagonal();
            let dev = if is_sphere { sci(deviation(&s)) } else { "—".into() };
            let b = bending(&s);
            table.row(vec!["deng-ma".into(), label(file), name.into(), sci(e), dev, sci(b)]);
            table.json.push(json!({"method": "deng-ma", "model": file, "tension": name, "max_rel": e, "bending": b}));
            table.metric(format!("deng-ma/{}/{name}/error", label(file)), e, Kind::Error);
        }
    }
    table.notes.push(
        "Both methods interpolate by construction: the errors are round-off (Deng-Ma keeps the input vertices \
         bit for bit). [Correction W6](../REFERENCES.md#w6) suggests μ = ¼ (edge points on the sphere to O(h⁴)), \
         but the Loop limit then \
         still sits inside the sphere; the sphere-deviation column is smallest at μ = ⅜, which cancels the \
         shrinkage of the limit at regular vertices to leading order (derivation in `deng_wang.rs`), so ⅜ is our \
         default."
            .into(),
    );
    Ok(table)
}
