//! Fan, Cheng & Lai: progressive interpolation with a two-phase Doo-Sabin
//! scheme and one shape parameter per face
//! (Fan, Cheng & Lai, *Subdivision based interpolation with shape control*, FCL in [references]).
//!
//! The two-phase scheme refines M̂ once with Eq. 1, V'ᵢ = λ_f Vᵢ + (1 − λ_f)A
//! (one λ_f ∈ (0, 1) per face), then with standard Doo-Sabin. The limit point
//! of vertex V is the centroid of its V-face after phase one (Eq. 2,
//! [correction F1]), so the limit points are B(λ)·M̂ with B = Σ·S (Eq. 5, Prop. 1;
//! [`crate::matrices::limit_matrix_two_phase`]).
//!
//! # Algorithm
//! 1. Build B(λ) = Σ·S.
//! 2. Progressive iteration (§3, Eq. 3-4): M^{k+1} = M^k + (P − B·M^k) from
//!    M⁰ = P until max |P − B·M^k| / d ≤ tol. It converges for every λ ∈ (0, 1)
//!    because spec(B) ⊂ [min λ, 1] (Prop. 2, sharpened in [correction F6]), so it
//!    needs at most log(tol/e₀)/log(1 − λ_min) iterations. Accelerated solvers
//!    (CG, Chebyshev, …) on request.
//! 3. Output phase-one(M̂, λ): the first refined mesh M¹, a plain Doo-Sabin
//!    control mesh whose V-face centroids are the data.
//!
//! # Deviations from the paper
//! - Stopping rule on the max residual relative to d (the paper's Table 1 uses 1e-4·d).
//! - Open meshes (beyond the paper): boundary vertices' limit points lie on
//!   the quadratic B-spline boundary ((B₋ + 6V + B₊)/8 of M̂, the midpoint of
//!   their two Chaikin points in M¹); the boundary block is solved first.
//! - Interior vertices of valence 2 (beyond the paper): no V-face after
//!   phase one (it would be a digon); their limit point is the centroid of
//!   the second-level E-face of the edge between their two phase-one images,
//!   which is their row of B (`subdiv_stencil::doo_sabin::valence_two_corners`).
//!   Progressive iteration still applies (B is then not of the symmetric
//!   form, which only the accelerated symmetric solvers need).
//! - Creases and corners (beyond the paper): the input's infinitely sharp
//!   tags are Doo-Sabin creases of M̂ (`subdiv_stencil::doo_sabin`, "Creases
//!   and corners"): phase one leaves every corner image to its face's λ and
//!   gives each sharp edge the points of the refined sharp polygon, so B's
//!   rows are crease vertices' quadratic B-spline points (B₋ + 6V + B₊)/8
//!   (clamped next to a corner; independent of λ), corners fixed, darts the
//!   centroid of their one V-face (`subdiv_stencil::limit_matrix_doo_sabin_sharp`).
//!   The crease blocks have spectrum in [½, 1], so progressive iteration
//!   converges there too; with darts the interior block has no proven bound
//!   (measured: smallest eigenvalue ≥ 1.16·min λ). M¹ carries the refined
//!   tags (every piece of the refined crease polygons infinitely sharp) and
//!   the input's texture coordinates refined by one Doo-Sabin step
//!   (`subdiv_stencil::fvar`; refused — with a warning — for UVs with seams or
//!   with tags). Semi-sharp values are refused.
//!
//! [correction F1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f1
//! [correction F6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f6
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use crate::first_step::CornerRule;
use crate::system::solve_limit_system;
use crate::{
    seconds_since, CommonOptions, InterpError, Interpolant, LimitAssociation, Method, Parameter, SolverChoice,
};
use subdiv_mesh::refine::dual_split_tagged;
use subdiv_mesh::Mesh;
use subdiv_solve::Solver;
use subdiv_stencil::doo_sabin::first_step_tagged;
use subdiv_stencil::{limit_matrix_doo_sabin_sharp, Scheme, StencilError};

/// The shape parameters λ of phase one.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// One λ for every face.
    Uniform(f64),
    /// λ per face, in face order.
    PerFace(Vec<f64>),
}

impl Default for Shape {
    fn default() -> Self {
        Shape::Uniform(0.5)
    }
}

/// Options of [`interpolate`].
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct FanChengLaiOptions {
    /// Subset, tolerance, solver (`Auto` = the paper's progressive iteration).
    pub common: CommonOptions,
    /// λ per face.
    pub shape: Shape,
}

crate::options::common_setters!(FanChengLaiOptions);

impl FanChengLaiOptions {
    /// Sets the shape parameters λ.
    pub fn with_shape(mut self, shape: Shape) -> Self {
        self.shape = shape;
        self
    }
}

/// Interpolates the vertices of `mesh` with a two-phase Doo-Sabin surface.
///
/// # Errors
/// As every method ([`crate`] docs, "The numeric rule");
/// [`InterpError::InvalidParameter`] for a λ outside (0, 1) or a λ list of
/// the wrong length; [`InterpError::Solve`] when the solver fails.
pub fn interpolate(mesh: &Mesh, opts: &FanChengLaiOptions) -> Result<Interpolant, InterpError> {
    crate::numeric::run(Method::FanChengLai, mesh, Some(&opts.common), |mesh, interpolated| {
        interpolate_prepared(mesh, interpolated, opts)
    })
}

/// [`interpolate`] on the prepared (scaled) mesh and interpolated set.
pub(crate) fn interpolate_prepared(
    mesh: &Mesh,
    interpolated: Vec<bool>,
    opts: &FanChengLaiOptions,
) -> Result<Interpolant, InterpError> {
    let start = std::time::Instant::now();
    let t = mesh.topology();
    let rule = match &opts.shape {
        Shape::Uniform(l) => CornerRule::Uniform(*l),
        Shape::PerFace(ls) => CornerRule::PerFace(ls),
    };
    let tags = mesh.tags();
    let bad_shape = |e: StencilError| match e {
        StencilError::InvalidParameter(reason) => InterpError::invalid(Parameter::Shape, reason),
        e => e.into(),
    };
    let b = limit_matrix_doo_sabin_sharp(t, &rule, tags).map_err(bad_shape)?;
    let setup = seconds_since(start);
    let solver = match opts.common.solver {
        SolverChoice::Auto => Solver::Pia,
        SolverChoice::Use(s) => s,
    };
    let start = std::time::Instant::now();
    // The refined topology of phase one does not depend on the solution: built beside the solve.
    let (solved, refined) = rayon::join(
        || {
            solve_limit_system(
                Method::FanChengLai.name(),
                &b,
                mesh.positions(),
                &interpolated,
                solver,
                opts.common.tol,
                opts.common.max_iter,
                mesh.bbox_diagonal(),
                &opts.common.observer,
            )
        },
        || dual_split_tagged(t, tags),
    );
    let solved = solved?;
    // Phase one of the auxiliary mesh M̂: the output control mesh M¹, with
    // the refined tags (the pieces of the refined crease polygons) and UVs.
    let (t1, provenance, tags1) = refined;
    let association = LimitAssociation::for_sharp_dual_split(t, tags, &provenance)?;
    let phase_one = first_step_tagged(t, tags, &rule, &solved.x).map_err(bad_shape)?;
    let mut warnings = Vec::new();
    let sharp = opts.common.surface.sharpness(tags);
    let uvs =
        crate::interpolant::carry_uvs(mesh, &sharp, &t1, Scheme::DooSabin, opts.common.surface.fvar, &mut warnings);
    let control = Mesh::from_topology(t1, phase_one)
        .with_tags(tags1)
        .with_uvs(uvs)
        .expect("the refined channel has one value per corner of M¹");
    let solve_seconds = seconds_since(start);
    let lambda = match &opts.shape {
        Shape::Uniform(l) => crate::report::Lambda::Uniform(*l),
        Shape::PerFace(ls) => crate::report::Lambda::PerFace(crate::report::Range::of(ls)),
    };
    let parameters = crate::Parameters {
        solver: Some(solver.name().to_string()),
        tol: Some(opts.common.tol),
        lambda: Some(lambda),
        ..Default::default()
    };
    Ok(Interpolant {
        surface_options: opts.common.surface,
        method: Method::FanChengLai,
        association,
        control,
        scheme: Scheme::DooSabin,
        interpolated,
        solve: Some(solved.summary),
        setup_seconds: setup,
        solve_seconds,
        warnings,
        parameters,
        measured_error: None,
    })
}
