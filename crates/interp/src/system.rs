//! Solving A·X = P restricted to the interpolated vertices, in the symmetric
//! stages the boundary structure allows.
//!
//! Rows of vertices that are not interpolated are replaced by X_v = P_v (the
//! papers' rule, e.g. Zheng-Cai §2: "V_j can simply be set to be I_j"), so
//! only the unknown block A_UU = D_U·S_UU is solved, with right-hand side
//! P_U − D_U·S_UK·X_K. Boundary rows (see `subdiv_stencil::limit_matrix`)
//! depend on boundary vertices only, so on open meshes the boundary unknowns
//! are solved first and the interior second; both blocks are of the
//! symmetric D·S form that CG, LDLᵀ and Lanczos need. Identity rows
//! (corners, isolated vertices) are solved exactly by X_v = P_v.

use crate::{InterpError, SolveSummary};
use glam::DVec3;
use subdiv_solve::{FactoredMatrix, SolveOptions, Solver, SparseMatrix};
use subdiv_stencil::LimitMatrix;

/// The unknowns and how the solve went.
pub(crate) struct SystemSolution {
    pub x: Vec<DVec3>,
    pub summary: SolveSummary,
}

fn is_identity_row(a: &LimitMatrix, v: usize) -> bool {
    let row = a.s.outer_view(v).expect("row exists");
    a.d[v] == 1.0 && row.nnz() == 1 && row.iter().next() == Some((v, &1.0))
}

/// The unknowns of the two symmetric stages: interpolated boundary rows
/// (except identity rows, solved exactly by X = P), then interpolated interior rows.
pub(crate) fn stages(a: &LimitMatrix, interpolated: &[bool]) -> [Vec<usize>; 2] {
    let n = a.size();
    let mut boundary = vec![false; n];
    for &v in &a.boundary_rows {
        boundary[v as usize] = true;
    }
    [
        (0..n).filter(|&v| interpolated[v] && boundary[v] && !is_identity_row(a, v)).collect(),
        (0..n).filter(|&v| interpolated[v] && !boundary[v]).collect(),
    ]
}

/// Solves the interpolation system for the flagged vertices; the others keep
/// their data position. `scale` is the data's bounding-box diagonal.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_limit_system(
    method: &'static str,
    a: &LimitMatrix,
    data: &[DVec3],
    interpolated: &[bool],
    solver: Solver,
    tol: f64,
    max_iter: usize,
    scale: f64,
) -> Result<SystemSolution, InterpError> {
    assert_eq!(data.len(), a.size(), "one data point per row");
    let mut x = data.to_vec();
    let mut summary = SolveSummary { solver: solver.name().to_string(), ..SolveSummary::default() };
    for unknowns in stages(a, interpolated).iter().filter(|u| !u.is_empty()) {
        let (sub, rhs) = restrict(a, unknowns, &x, data);
        let opts = SolveOptions {
            tol,
            scale,
            max_iter,
            history: true,
            initial: Some(unknowns.iter().map(|&v| data[v].to_array()).collect()),
        };
        let sol = solver
            .solve(&sub, &rhs, &opts)
            .map_err(|source| InterpError::Solve { method, source: Box::new(source) })?;
        for (k, &v) in unknowns.iter().enumerate() {
            x[v] = DVec3::from_array(sol.x[k]);
        }
        summary.iterations += sol.iterations;
        summary.matvecs += sol.matvecs;
        summary.residual = summary.residual.max(sol.residual);
        summary.history.extend(sol.history);
        summary.negative_pivots = sol.negative_pivots.or(summary.negative_pivots);
    }
    summary.converged = true;
    Ok(SystemSolution { x, summary })
}

/// The block A_UU = D_U·S_UU and right-hand side P_U − D_U·S_UK·X_K.
pub(crate) fn restrict(
    a: &LimitMatrix,
    unknowns: &[usize],
    x: &[DVec3],
    data: &[DVec3],
) -> (FactoredMatrix, Vec<[f64; 3]>) {
    let n = a.size();
    let mut local = vec![u32::MAX; n];
    for (k, &v) in unknowns.iter().enumerate() {
        local[v] = k as u32;
    }
    let mut indptr = Vec::with_capacity(unknowns.len() + 1);
    let (mut indices, mut values) = (Vec::new(), Vec::new());
    let mut rhs = Vec::with_capacity(unknowns.len());
    indptr.push(0u32);
    for &v in unknowns {
        let mut known = DVec3::ZERO;
        for (j, &s) in a.s.outer_view(v).expect("row exists").iter() {
            if local[j] == u32::MAX {
                known += s * x[j];
            } else {
                indices.push(local[j]);
                values.push(s);
            }
        }
        indptr.push(indices.len() as u32);
        rhs.push((data[v] - a.d[v] * known).to_array());
    }
    let m = unknowns.len();
    let s = SparseMatrix::new((m, m), indptr, indices, values);
    let d = unknowns.iter().map(|&v| a.d[v]).collect();
    let sub = FactoredMatrix::new(d, s).expect("limit matrices have positive D and finite S");
    (sub, rhs)
}

/// The shared tail of the methods whose control mesh has the input's
/// topology (Nasri, Cheng): solve A·X = P for the interpolated vertices and
/// wrap the result.
#[allow(clippy::too_many_arguments)]
pub(crate) fn interpolate_on_input_topology(
    method: crate::Method,
    mesh: &subdiv_mesh::Mesh,
    a: &LimitMatrix,
    setup_seconds: f64,
    scheme: crate::ControlScheme,
    common: &crate::CommonOptions,
    default_solver: Solver,
    mut warnings: Vec<String>,
) -> Result<crate::Interpolant, InterpError> {
    let interpolated = common.interpolated(mesh.topology().vertex_count())?;
    let solver = match common.solver {
        crate::SolverChoice::Auto => default_solver,
        crate::SolverChoice::Use(s) => s,
    };
    let start = std::time::Instant::now();
    let solved = solve_limit_system(
        method.name(),
        a,
        mesh.positions(),
        &interpolated,
        solver,
        common.tol,
        common.max_iter,
        mesh.bbox_diagonal(),
    )?;
    let solve_seconds = crate::seconds_since(start);
    if let Some(k) = solved.summary.negative_pivots.filter(|&k| k > 0) {
        warnings.push(format!("the limit matrix is indefinite ({k} negative pivots); the solution is valid but progressive iteration cannot reach it"));
    }
    let mut parameters = serde_json::Map::new();
    parameters.insert("solver".into(), solver.name().into());
    parameters.insert("tol".into(), common.tol.into());
    parameters.insert("interpolated_vertices".into(), interpolated.iter().filter(|&&b| b).count().into());
    Ok(crate::Interpolant {
        method,
        control: mesh.with_positions(solved.x),
        scheme,
        association: crate::LimitAssociation::ControlVertex,
        solve: Some(solved.summary),
        setup_seconds,
        solve_seconds,
        warnings,
        parameters,
    })
}
