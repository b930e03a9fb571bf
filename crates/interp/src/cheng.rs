//! Cheng et al.: interpolation by Catmull-Clark surfaces through progressive
//! iteration (Cheng et al., *Interpolating meshes of arbitrary topology*, CFL in [references]),
//! and the same construction for Loop and √3 ([`ChengOptions::with_scheme`],
//! "Other control schemes" below).
//!
//! Finds M̂ with A·M̂ = P, where A maps control points to Catmull-Clark limit
//! points (appendix Eq. 5, corrected by [corrections C1/C2]; A = D·S with
//! D = diag(4/(n(n+5))) and S symmetric, `subdiv_stencil::limit_matrix_catmull_clark`).
//!
//! # Algorithm
//! 1. Build A = D·S from the topology (`subdiv_stencil::limit_operator_catmull_clark_sharp`).
//!    Untagged, S is stored only if the solver must iterate: when the data
//!    already meet the tolerance as control points (a finely subdivided
//!    mesh), CG's first test runs on streamed rows (`system.rs`) and returns
//!    X = P, the same result bit for bit.
//! 2. Check the two structural degeneracies ([correction C3]):
//!    - an interior vertex of valence 2 voids the appendix's proof that
//!      spec(A) ⊂ (0, 1] (the term n(n − 3)/4·x² of the quadratic form is
//!      negative for n = 2), and A may be indefinite. Measured (dense
//!      eigenvalues, `subdiv-solve`'s tests): one valence-2 vertex between two
//!      quads leaves A positive definite (λ_min ≈ 0.098 on a 24 × 16 torus),
//!      two adjacent ones give one negative eigenvalue (≈ −0.023), the pillow
//!      has −1/7. The automatic choice then solves with **MINRES** (needs S
//!      symmetric only, `subdiv_solve::minres`); a requested solver that needs
//!      A positive definite (PIA diverges there, CG breaks down) is refused
//!      with the remedy; MINRES, GMRES, LDLᵀ and dense LU are used as asked;
//!    - a closed all-valence-3 bipartite component (the cube) makes A
//!      singular — the solve goes ahead (consistent data are interpolated,
//!      with a warning that the control mesh is not unique), and data outside
//!      A's range end with the residual reached.
//! 3. Solve A·M̂ = P: the paper's progressive iteration M ← M + (P − A·M)
//!    (`Solver::Pia`, Eq. 1-3; its M_{i+1} = M_i − L(M_i) form is the same
//!    iteration, [correction C6]) or, by default, conjugate gradients on
//!    S·M̂ = D⁻¹P (MINRES when step 2 found a valence-2 vertex; the boundary
//!    and interior blocks of an open mesh each get their own choice,
//!    `system.rs`).
//!
//! # Deviations from the paper
//! - Stopping rule: max over vertices of |P − A·M| / d ≤ tol ([the stopping rule]).
//! - Open meshes (beyond the paper): boundary vertices follow the crease
//!   rule, limit (p₋ + 4p + p₊)/6, corners stay; the boundary block is solved
//!   first, then the interior (`system.rs`).
//! - Creases and corners (beyond the paper; OpenSubdiv's rules): the input's
//!   tags and [`crate::SurfaceOptions`] give A's rows
//!   (`subdiv_stencil::limit_matrix_catmull_clark_sharp`): smooth rows keep
//!   Eq. 5, crease vertices (two infinitely sharp edges) the cubic B-spline
//!   (p₋ + 4p + p₊)/6 of their crease polygon, corners p, and darts and every
//!   vertex a semi-sharp value reaches the composed limit row after ⌈s⌉
//!   levels (as OpenSubdiv's `Limit`, except at darts with an infinitely
//!   sharp edge: their exact limit, unless [`crate::SurfaceOptions`] asks
//!   for `DartLimit::SmoothMask`). Solved corners, crease polygons
//!   (tridiagonal / circulant (1, 4, 1)/6, spectrum in [⅓, 1]), then the
//!   interior (GMRES when composed rows make it nonsymmetric). The degeneracy
//!   checks look at the rows: a valence-2 vertex on a crease is harmless, and
//!   the cube's checkerboard kernel goes with a crease vertex or a corner but
//!   not with a dart (A·c is tested). The control mesh keeps the input's
//!   tags and UVs; OpenSubdiv's limit of the written file passes through the
//!   data (`fixtures/peer/creases-interpolation/`), wherever no infinitely
//!   sharp dart is (there OpenSubdiv's `Limit` takes the smooth mask; our
//!   limit, the exact one, passes through the data).
//! - Default solver CG (Jacobi-preconditioned): the spectrum of A is
//!   size-independent, so it needs a few tens of products where PIA needs
//!   hundreds. With valence-2 vertices MINRES, whose matvecs stay within
//!   2× CG's on the same mesh without them (`subdiv-solve`'s `indefinite`
//!   bench: 19 against 12 at 524k vertices).
//!
//! # Other control schemes (beyond the paper)
//! Nothing in the progressive iteration is particular to Catmull-Clark: it
//! needs a control mesh M of the input's topology and a limit matrix L with
//! L·M = P. [`ChengOptions::with_scheme`] takes every scheme whose limit
//! points of a control mesh are rows of such a matrix on that mesh's own
//! vertices:
//! - **Loop** (`Scheme::Loop(β)`, β from the scheme; triangles):
//!   L = `subdiv_stencil::limit_matrix_loop_sharp`, row v
//!   (1 − kγ)v + γΣvⱼ with γ = 1/(k + 3/(8β)) (Deng-Wang Eq. 5-6, correction
//!   W4), D = γ, S = 3/(8β) on the diagonal and 1 per edge; creases, corners
//!   and composed rows as for Catmull-Clark.
//! - **√3** (`Scheme::Sqrt3`, Kobbelt 2000; triangles, interior valence ≥ 3,
//!   corners but no creases): L = `subdiv_stencil::limit_matrix_sqrt3_sharp`,
//!   row v (1 − βₙ)v + βₙ/n Σvᵢ with βₙ = 3αₙ/(1 + 3αₙ), αₙ = (4 −
//!   2cos(2π/n))/9 (Kobbelt §3), D = βₙ/n, S = n(1 − βₙ)/βₙ on the diagonal and
//!   1 per edge; boundary rows (p₋ + 4p + p₊)/6, corners p. A control mesh is
//!   a base level (its first step odd), where these rows are exact on open
//!   meshes too (`subdiv_stencil::sqrt3`, "Limit points").
//!
//! Both S are **positive definite**, so the automatic choice is CG. (PIA
//! converges too where every row is a smooth, curve or corner row: those are
//! convex combinations, so each block's spectrum lies in (0, 1]; composed
//! rows of Loop's darts and semi-sharp tags have no such bound.)
//! Proof, for x on the smooth vertices (the whole mesh when closed, else
//! the interior block, whose edges all lie in two triangles): with c_v the
//! diagonal of S and k_v the valence, Σ_T (x_a + x_b + x_c)² = Σ_v k_v x_v² +
//! 4Σ_edges x_i x_j, so xᵀSx = Σ_v (c_v − k_v/2) x_v² + ½Σ_T (x_a + x_b + x_c)²,
//! positive when c_v > k_v/2: for Loop kβ < ¾ (Warren's kβ ≤ 9/16, Loop's ≤
//! 5/8), for √3 βₙ < ⅔, i.e. αₙ < ⅔, true for n ≥ 3. So neither scheme has
//! Catmull-Clark's degeneracies ([correction C3]) and no warning or refusal
//! of a solver comes from the matrix; an open mesh is solved boundary first
//! ((1, 4, 1)/6 blocks), then the interior, a block with composed (Loop
//! dart or semi-sharp) rows by GMRES (`system.rs`). The error is measured
//! by the scheme's own limit rules on the control mesh
//! ([`Interpolant::error`]), which the result's [`Interpolant::scheme`]
//! names (the report's `control_scheme`). Doo-Sabin's limit points are not
//! rows over the control mesh's vertices (face centroids of M¹: `nasri`,
//! `zheng-cai`, `fan-cheng-lai`), and Deng-Ma interpolates by itself
//! (`deng-ma`): both are refused with the method that takes them.
//!
//! [corrections C1/C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1
//! [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3
//! [correction C6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c6
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md
//! [the stopping rule]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule

use crate::matrices::Degeneracy;
use crate::system::{interpolate_on_input_topology, AutoSolver, Limit};
use crate::{seconds_since, CommonOptions, InterpError, Interpolant, Method, Parameter, SolverChoice};
use subdiv_mesh::{Mesh, Topology};
use subdiv_solve::Solver;
use subdiv_stencil::{
    limit_matrix_loop_sharp, limit_matrix_sqrt3_sharp, limit_operator_catmull_clark_sharp, LevelSharpness, LimitMatrix,
    RowKind, Scheme, StencilError,
};

/// Options of [`interpolate`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ChengOptions {
    /// Subset, tolerance, solver.
    pub common: CommonOptions,
    /// The control mesh's scheme: Catmull-Clark (the default, the paper's),
    /// Loop (its β as the scheme holds it) or √3 ([`Self::with_scheme`];
    /// module docs, "Other control schemes").
    pub scheme: Scheme,
}

impl Default for ChengOptions {
    fn default() -> Self {
        Self { common: CommonOptions::default(), scheme: Scheme::CatmullClark }
    }
}

crate::options::common_setters!(ChengOptions);

impl ChengOptions {
    /// Sets the control mesh's scheme: Catmull-Clark, Loop (`Scheme::Loop(β)`)
    /// or √3.
    ///
    /// ```
    /// use subdiv_interp::{cheng, ChengOptions, Scheme};
    /// let icosahedron = subdiv_mesh::shapes::icosahedron();
    /// let options = ChengOptions::default().with_scheme(Scheme::Sqrt3)?;
    /// let result = cheng::interpolate(&icosahedron, &options)?;
    /// assert_eq!(result.scheme, Scheme::Sqrt3);
    /// assert!(result.error_all(&icosahedron).max_rel <= 1e-6);
    /// assert!(ChengOptions::default().with_scheme(Scheme::DooSabin).is_err());
    /// # Ok::<(), subdiv_interp::InterpError>(())
    /// ```
    ///
    /// # Errors
    /// [`InterpError::InvalidParameter`] ([`Parameter::Scheme`]) for a scheme
    /// without a limit matrix on the control mesh's vertices, naming the
    /// method that takes it: Doo-Sabin (`nasri`), Deng-Ma (`deng-ma`).
    pub fn with_scheme(mut self, scheme: Scheme) -> Result<Self, InterpError> {
        check_scheme(scheme)?;
        self.scheme = scheme;
        Ok(self)
    }
}

/// Refuses a control scheme the method cannot take ([`ChengOptions::with_scheme`]).
fn check_scheme(scheme: Scheme) -> Result<(), InterpError> {
    crate::preconditions::cheng_scheme(scheme).map_err(|reason| InterpError::invalid(Parameter::Scheme, reason))
}

/// Interpolates the vertices of `mesh` with a limit surface of
/// [`ChengOptions::scheme`] (default Catmull-Clark).
///
/// # Errors
/// As every method ([`crate`] docs, "The numeric rule");
/// [`InterpError::InvalidParameter`] for a scheme [`ChengOptions::with_scheme`]
/// refuses; [`InterpError::UnsupportedMesh`] for a mesh the scheme cannot
/// take (Loop and √3: non-triangles; √3: creases, interior valence 2), or
/// for a solver that needs a definite matrix on a possibly indefinite one;
/// [`InterpError::Unsolvable`] for data outside the range of a singular A;
/// [`InterpError::Solve`] when the solver fails.
pub fn interpolate(mesh: &Mesh, opts: &ChengOptions) -> Result<Interpolant, InterpError> {
    check_scheme(opts.scheme)?;
    let mut result = crate::numeric::run(Method::Cheng, mesh, Some(&opts.common), |mesh, interpolated| {
        interpolate_prepared(mesh, interpolated, opts)
    })?;
    result.parameters.record_scheme(opts.scheme);
    Ok(result)
}

/// The structural degeneracies of Cheng's A ([`Degeneracy`], [correction C3]) with
/// the mesh's tags: an interior valence-2 vertex whose row is the smooth
/// quadratic form (on a crease its row is the curve's (1, 4, 1)/6, which is
/// harmless), and a checkerboard kernel that A still annihilates
/// ([`crate::preconditions::cheng_kernel`]: gone with a crease vertex or a
/// corner on the component, kept with a dart).
///
/// [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3
///
/// `a` is the assembled matrix, which the kernel test of a tagged mesh reads;
/// an untagged mesh needs only the row kinds.
fn degeneracy(mesh: &Mesh, row_kinds: &[RowKind], a: Option<&LimitMatrix>) -> Option<Degeneracy> {
    let t = mesh.topology();
    let smooth_valence_two = t
        .vertices()
        .find(|&v| row_kinds[v.index()] == RowKind::Smooth && !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2);
    if let Some(vertex) = smooth_valence_two {
        return Some(Degeneracy::Indefinite { vertex });
    }
    debug_assert!(a.is_some() || mesh.tags().is_empty(), "a tagged mesh's kernel test reads A");
    crate::preconditions::cheng_kernel(mesh, a).first().map(|c| Degeneracy::Singular { vertex: c[0].0 })
}

/// [`interpolate`] on the prepared (scaled) mesh and interpolated set.
pub(crate) fn interpolate_prepared(
    mesh: &Mesh,
    interpolated: Vec<bool>,
    opts: &ChengOptions,
) -> Result<Interpolant, InterpError> {
    match opts.scheme {
        Scheme::CatmullClark => catmull_clark(mesh, interpolated, opts),
        Scheme::Loop(beta) => {
            definite_scheme(mesh, interpolated, opts, |t, sharp| limit_matrix_loop_sharp(t, sharp, beta))
        }
        Scheme::Sqrt3 => definite_scheme(mesh, interpolated, opts, limit_matrix_sqrt3_sharp),
        // Refused by `interpolate` before: the same refusal (never a panic).
        Scheme::DooSabin | Scheme::DengMa(_) => check_scheme(opts.scheme).and_then(|()| {
            Err(InterpError::invalid(Parameter::Scheme, format!("{} is not a control scheme of cheng", opts.scheme)))
        }),
    }
}

/// Loop and √3 (module docs, "Other control schemes"): the mesh checked
/// against the scheme ([`crate::preconditions`]), L built with the tags and
/// surface options, solved by the automatic choice with CG for the
/// symmetric blocks (S is positive definite).
fn definite_scheme(
    mesh: &Mesh,
    interpolated: Vec<bool>,
    opts: &ChengOptions,
    limit_matrix: impl FnOnce(&Topology, &LevelSharpness) -> Result<LimitMatrix, StencilError>,
) -> Result<Interpolant, InterpError> {
    let start = std::time::Instant::now();
    if let Err(refusal) = crate::preconditions::cheng_mesh(mesh, opts.scheme) {
        return Err(InterpError::UnsupportedMesh {
            method: Method::Cheng.name(),
            reason: refusal.reason,
            suggestion: refusal.suggestion,
        });
    }
    let sharpness = opts.common.surface.sharpness(mesh.tags());
    let a = limit_matrix(mesh.topology(), &sharpness)?;
    let setup = seconds_since(start);
    interpolate_on_input_topology(
        Method::Cheng,
        mesh,
        interpolated,
        Limit::Owned(a),
        setup,
        opts.scheme,
        &opts.common,
        Solver::Cg { jacobi: true },
        Vec::new(),
    )
}

/// The paper's Catmull-Clark A (module docs, "Algorithm").
fn catmull_clark(mesh: &Mesh, interpolated: Vec<bool>, opts: &ChengOptions) -> Result<Interpolant, InterpError> {
    let start = std::time::Instant::now();
    let sharpness = opts.common.surface.sharpness(mesh.tags());
    let op = limit_operator_catmull_clark_sharp(mesh.topology(), &sharpness)?;
    // Untagged: A stays unassembled until the solver must iterate (the data
    // of a fine mesh often meet the tolerance as they are, `system.rs`).
    // Tagged: the kernel test reads A, assembled here.
    let (a, degeneracy) = if mesh.tags().is_empty() {
        let degeneracy = degeneracy(mesh, op.row_kinds(), None);
        (Limit::Lazy(op), degeneracy)
    } else {
        let a = op.assemble();
        let degeneracy = degeneracy(mesh, &a.row_kinds, Some(&a));
        (Limit::Owned(a), degeneracy)
    };
    let setup = seconds_since(start);
    let mut warnings = Vec::new();
    let mut auto = AutoSolver::from(Solver::Cg { jacobi: true });
    match degeneracy.clone() {
        Some(Degeneracy::Indefinite { vertex }) => match opts.common.solver {
            SolverChoice::Use(solver) if solver.needs_definite() => {
                return Err(InterpError::UnsupportedMesh {
                    method: "cheng",
                    reason: format!(
                        "vertex {vertex} has valence 2, which can make the Catmull-Clark limit matrix indefinite \
                         (two adjacent valence-2 vertices do; correction C3 in subdiv's docs/REFERENCES.md), and \
                         {solver} needs it positive definite"
                    ),
                    suggestion: format!(
                        "the automatic solver choice, which takes MINRES here (Solver::Minres solves symmetric \
                         indefinite systems), a direct solver (Solver::Ldl or Solver::Dense), or another method: {}",
                        crate::preconditions::suggestion(mesh, Method::Cheng)
                    ),
                });
            }
            _ => auto.maybe_indefinite = true,
        },
        Some(Degeneracy::Singular { vertex }) => warnings.push(format!(
            "the Catmull-Clark limit matrix is singular (the closed component of vertex {vertex} has only \
             valence-3 vertices and a bipartite vertex graph): the interpolating control mesh is not unique"
        )),
        None => {}
    }
    interpolate_on_input_topology(
        Method::Cheng,
        mesh,
        interpolated,
        a,
        setup,
        subdiv_stencil::Scheme::CatmullClark,
        &opts.common,
        auto,
        warnings,
    )
    .map_err(|e| match (e, degeneracy) {
        (InterpError::Solve { source, .. }, Some(Degeneracy::Singular { .. })) => InterpError::Unsolvable {
            method: "cheng",
            reason: "the Catmull-Clark limit matrix of this mesh is singular and the data are not in its range \
                     (no Catmull-Clark surface interpolates them)"
                .into(),
            suggestion: crate::preconditions::suggestion(mesh, Method::Cheng),
            source,
        },
        (e, _) => e,
    })
}
