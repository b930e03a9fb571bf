//! Cheng et al.: interpolation by Catmull-Clark surfaces through progressive
//! iteration (`seeds/cheng-catmull-clark-progressive-interpolation.txt`).
//!
//! Finds M̂ with A·M̂ = P, where A maps control points to Catmull-Clark limit
//! points (appendix Eq. 5, corrected by ERRATA C1/C2; A = D·S with
//! D = diag(4/(n(n+5))) and S symmetric, `subdiv_stencil::limit_matrix_catmull_clark`).
//!
//! # Algorithm
//! 1. Build A = D·S from the topology.
//! 2. Check the two structural degeneracies (ERRATA C3): an interior vertex
//!    of valence 2 makes A indefinite — progressive iteration diverges there,
//!    so the iterative solvers refuse and `ldl`/`dense` are suggested; a closed
//!    all-valence-3 bipartite component (the cube) makes A singular — the
//!    solve goes ahead (consistent data are interpolated, with a warning that
//!    the control mesh is not unique), and data outside A's range end with the
//!    residual reached.
//! 3. Solve A·M̂ = P: the paper's progressive iteration M ← M + (P − A·M)
//!    (`--solver pia`, Eq. 1-3; its M_{i+1} = M_i − L(M_i) form is the same
//!    iteration, ERRATA C6) or, by default, conjugate gradients on S·M̂ = D⁻¹P.
//!
//! # Deviations from the paper
//! - Stopping rule: max over vertices of |P − A·M| / d ≤ tol (SPEC §4).
//! - Open meshes (beyond the paper): boundary vertices follow the crease
//!   rule, limit (p₋ + 4p + p₊)/6, corners stay; the boundary block is solved
//!   first, then the interior (`system.rs`).
//! - Default solver CG (Jacobi-preconditioned): the spectrum of A is
//!   size-independent, so it needs a few tens of products where PIA needs hundreds.

use crate::system::interpolate_on_input_topology;
use crate::{seconds_since, CommonOptions, ControlScheme, InterpError, Interpolant, Method, SolverChoice};
use subdiv_mesh::Mesh;
use subdiv_solve::Solver;
use subdiv_stencil::{catmull_clark_degeneracy, limit_matrix_catmull_clark, Degeneracy};

/// Options of [`interpolate`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChengOptions {
    /// Subset, tolerance, solver.
    pub common: CommonOptions,
}

/// Solvers that need A positive definite (they diverge or break down on an indefinite A).
fn needs_definite(solver: SolverChoice) -> bool {
    !matches!(solver, SolverChoice::Use(Solver::Ldl | Solver::Dense))
}

/// Interpolates the vertices of `mesh` with a Catmull-Clark limit surface.
pub fn interpolate(mesh: &Mesh, opts: &ChengOptions) -> Result<Interpolant, InterpError> {
    let start = std::time::Instant::now();
    let t = mesh.topology();
    let a = limit_matrix_catmull_clark(t);
    let setup = seconds_since(start);
    let mut warnings = Vec::new();
    match catmull_clark_degeneracy(t) {
        Some(Degeneracy::Indefinite { vertex }) if needs_definite(opts.common.solver) => {
            return Err(InterpError::UnsupportedMesh {
                method: "cheng",
                reason: format!(
                    "vertex {vertex} has valence 2, which makes the Catmull-Clark limit matrix indefinite \
                     (progressive iteration diverges; ERRATA C3)"
                ),
                suggestion: "--solver ldl (solves indefinite systems) or a Doo-Sabin method: zheng-cai, fan-cheng-lai",
            });
        }
        Some(Degeneracy::Singular { vertex }) => warnings.push(format!(
            "the Catmull-Clark limit matrix is singular (the closed component of vertex {vertex} has only \
             valence-3 vertices and a bipartite vertex graph): the interpolating control mesh is not unique"
        )),
        _ => {}
    }
    let default_solver = Solver::Cg { jacobi: true };
    interpolate_on_input_topology(
        Method::Cheng,
        mesh,
        &a,
        setup,
        ControlScheme::CatmullClark,
        &opts.common,
        default_solver,
        warnings,
    )
    .map_err(|e| match (e, catmull_clark_degeneracy(t)) {
        (InterpError::Solve { source, .. }, Some(Degeneracy::Singular { .. })) => InterpError::Unsolvable {
            method: "cheng",
            reason: "the Catmull-Clark limit matrix of this mesh is singular and the data are not in its range \
                     (no Catmull-Clark surface interpolates them)"
                .into(),
            suggestion: "a Doo-Sabin method: zheng-cai, fan-cheng-lai or nasri",
            source,
        },
        (e, _) => e,
    })
}
