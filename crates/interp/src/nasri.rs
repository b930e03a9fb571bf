//! Nasri 1987: Doo-Sabin interpolation by a global linear system, as
//! described in Zheng & Cai 2005 §2 (N87 and ZC05 in [references]).
//!
//! Finds the auxiliary mesh M⁰ (input topology) such that the centroid of the
//! V-face of every interpolated vertex after one **standard** Doo-Sabin step
//! is its data point: C·M⁰ = P, C = N⁻¹·S ([`crate::matrices::limit_matrix_nasri`]);
//! vertices not interpolated keep M⁰ = I (§2: "V_j can simply be set to be I_j").
//!
//! # Algorithm
//! 1. Build C = D·S (D = diag(1/n), S = Σ_faces Circ(α)).
//! 2. Solve the system restricted to the interpolated vertices: by default
//!    conjugate gradients (spec(C) ⊂ [¼, 1] on closed manifold meshes,
//!    [correction Z8], so κ ≤ 4); [`Solver::Ldl`] is the paper's direct baseline and
//!    [`Solver::Dense`] the 2005 Gaussian elimination.
//!
//! # Deviations from the paper
//! - The paper worries that C may be singular; it is not on closed manifold
//!   meshes ([correction Z8]), which the tests check on every fixture.
//! - Open meshes (beyond the paper): boundary vertices' limit points lie on
//!   the quadratic B-spline boundary, (B₋ + 6V + B₊)/8; that block is solved first.
//! - Interior vertices of valence 2 (beyond the paper): their V-face would
//!   be a digon, which the Doo-Sabin refinement leaves out; their row of C is
//!   the centroid of the second-level E-face of the edge between their two
//!   images (`subdiv_stencil::doo_sabin::valence_two_corners`). That row is
//!   not of the symmetric Circ form, so with such vertices the interior
//!   block is nonsymmetric and the automatic solver choice takes GMRES
//!   instead of CG.
//! - Creases and corners (beyond the paper): the input's infinitely sharp
//!   tags are Doo-Sabin creases of M⁰ (`subdiv_stencil::doo_sabin`, "Creases
//!   and corners"), and C's rows are the limit points of that surface
//!   (`subdiv_stencil::limit_matrix_doo_sabin_sharp`): crease vertices the
//!   quadratic B-spline of the crease polygon, (B₋ + 6V + B₊)/8 (clamped next
//!   to a corner), corners fixed, darts the centroid of their one V-face.
//!   Solved corners first, then the crease polygons (symmetric, spectrum in
//!   [½, 1]), then the interior (symmetric unless darts or valence-2
//!   vertices add general rows: GMRES then). The control mesh M⁰ keeps the
//!   input's tags and texture coordinates. Semi-sharp values have no
//!   Doo-Sabin meaning and are refused.
//!
//! [correction Z8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z8
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use crate::system::interpolate_on_input_topology;
use crate::{seconds_since, CommonOptions, InterpError, Interpolant, Method};
use subdiv_mesh::Mesh;
use subdiv_solve::Solver;
use subdiv_stencil::doo_sabin::StandardCorners;
use subdiv_stencil::limit_matrix_doo_sabin_sharp;

/// Options of [`interpolate`].
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct NasriOptions {
    /// Subset, tolerance, solver.
    pub common: CommonOptions,
}

crate::options::common_setters!(NasriOptions);

/// Interpolates the vertices of `mesh` with a Doo-Sabin limit surface of M⁰.
///
/// # Errors
/// As every method ([`crate`] docs, "The numeric rule"); [`InterpError::Solve`]
/// when the solver fails; [`InterpError::Stencil`] with
/// `StencilError::SemiSharpDooSabin` for a semi-sharp tag.
pub fn interpolate(mesh: &Mesh, opts: &NasriOptions) -> Result<Interpolant, InterpError> {
    crate::numeric::run(Method::Nasri, mesh, Some(&opts.common), |mesh, interpolated| {
        interpolate_prepared(mesh, interpolated, opts)
    })
}

/// [`interpolate`] on the prepared (scaled) mesh and interpolated set.
pub(crate) fn interpolate_prepared(
    mesh: &Mesh,
    interpolated: Vec<bool>,
    opts: &NasriOptions,
) -> Result<Interpolant, InterpError> {
    let start = std::time::Instant::now();
    let c = limit_matrix_doo_sabin_sharp(mesh.topology(), &StandardCorners, mesh.tags())?;
    let setup = seconds_since(start);
    interpolate_on_input_topology(
        Method::Nasri,
        mesh,
        interpolated,
        crate::system::Limit::Owned(c),
        setup,
        subdiv_stencil::Scheme::DooSabin,
        &opts.common,
        Solver::Cg { jacobi: true },
        Vec::new(),
    )
}
