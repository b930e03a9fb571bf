//! Nasri 1987: Doo-Sabin interpolation by a global linear system, as
//! described in `seeds/zheng-cai-2005-doo-sabin-interpolation.txt` §2.
//!
//! Finds the auxiliary mesh M⁰ (input topology) such that the centroid of the
//! V-face of every interpolated vertex after one **standard** Doo-Sabin step
//! is its data point: C·M⁰ = P, C = N⁻¹·S (`subdiv_stencil::limit_matrix_nasri`);
//! vertices not interpolated keep M⁰ = I (§2: "V_j can simply be set to be I_j").
//!
//! # Algorithm
//! 1. Build C = D·S (D = diag(1/n), S = Σ_faces Circ(α)).
//! 2. Solve the system restricted to the interpolated vertices: by default
//!    conjugate gradients (spec(C) ⊂ [¼, 1] on closed manifold meshes,
//!    ERRATA Z8, so κ ≤ 4); `--solver ldl` is the paper's direct baseline and
//!    `--solver dense` the 2005 Gaussian elimination.
//!
//! # Deviations from the paper
//! - The paper worries that C may be singular; it is not on closed manifold
//!   meshes (ERRATA Z8), which the tests check on every fixture.
//! - Open meshes (beyond the paper): boundary vertices' limit points lie on
//!   the quadratic B-spline boundary, (B₋ + 6V + B₊)/8; that block is solved first.
//! - Interior vertices of valence 2 are refused: their V-face is a digon,
//!   whose centroid is not a limit point of our Doo-Sabin refinement.

use crate::system::interpolate_on_input_topology;
use crate::{seconds_since, CommonOptions, ControlScheme, InterpError, Interpolant, Method};
use subdiv_mesh::Mesh;
use subdiv_solve::Solver;
use subdiv_stencil::limit_matrix_nasri;

/// Options of [`interpolate`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NasriOptions {
    /// Subset, tolerance, solver.
    pub common: CommonOptions,
}

/// Refuses interior valence-2 vertices for the Doo-Sabin methods.
pub(crate) fn require_no_digons(method: &'static str, mesh: &Mesh) -> Result<(), InterpError> {
    let t = mesh.topology();
    match t.vertices().find(|&v| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2) {
        Some(v) => Err(InterpError::UnsupportedMesh {
            method,
            reason: format!("vertex {v} has valence 2: its Doo-Sabin V-face is a digon without a limit point"),
            suggestion: "removing the valence-2 vertex (merge its two edges), or cheng with --solver ldl",
        }),
        None => Ok(()),
    }
}

/// Interpolates the vertices of `mesh` with a Doo-Sabin limit surface of M⁰.
pub fn interpolate(mesh: &Mesh, opts: &NasriOptions) -> Result<Interpolant, InterpError> {
    require_no_digons("nasri", mesh)?;
    let start = std::time::Instant::now();
    let c = limit_matrix_nasri(mesh.topology());
    let setup = seconds_since(start);
    interpolate_on_input_topology(
        Method::Nasri,
        mesh,
        &c,
        setup,
        ControlScheme::DooSabin,
        &opts.common,
        Solver::Cg { jacobi: true },
        Vec::new(),
    )
}
