//! Fair interpolation: among the control meshes of the input refined K
//! times whose limit surface passes through the data, the one whose limit
//! surface has the least thin-plate energy (after Halstead, Kass & DeRose,
//! *Efficient, fair interpolation using Catmull-Clark surfaces*, SIGGRAPH
//! 1993, HKD93 in [references]), for Catmull-Clark (default), Loop and
//! Doo-Sabin.
//!
//! The exact methods (Cheng's A·M̂ = P, Nasri's C·M⁰ = P) have as many
//! unknowns as constraints: the control mesh is fully determined by the
//! data, and nothing keeps it fair (Spot's control mesh is a star of spikes,
//! the surface bulges between the data). Here the unknowns are the m points
//! X of M^K, the input topology refined K times by the scheme (`refine`,
//! default 1: m ≈ 4n for quads), and the n constraints are the limit points
//! of the input vertices' images; the m − n degrees of freedom left are
//! spent on minimising a fairness energy of the limit surface.
//!
//! # The problem
//! Let T (m × m) be the limit stencil of M^K (row i: the limit point of
//! vertex i of M^K by the scheme's limit rules with M^K's tags, the rows
//! [`crate::Interpolant::error`] evaluates), A (n × m) its rows at the images
//! of the interpolated input vertices (Catmull-Clark and Loop keep an input
//! vertex's image at its index; for Doo-Sabin, K = 1, A's rows are the
//! [`subdiv_stencil::DualLimitSite`]s in M¹), and Δ (m × m) the umbrella
//! Laplacian of M^K's connectivity: (Δy)_v = mean of v's edge neighbours − y_v,
//! along a boundary or a crease the mean of its two neighbours on the curve,
//! no row at a corner. The energy is
//!
//! ```text
//! E(X) = 4^K · ‖Δ·T·X‖²  =  4^K · Σ_v ‖(Δ Y)_v‖²,   Y = T·X the limit points of M^K,   (1)
//! ```
//!
//! and the fair interpolant solves
//!
//! ```text
//! minimise E(X)  subject to  A·X = P.                                             (2)
//! ```
//!
//! With `fairness_weight` w > 0 the constraints become a penalty:
//!
//! ```text
//! minimise ‖A·X − P‖² + w·E(X),   i.e.  (AᵀA + w·4^K·BᵀB)·X = AᵀP,  B = Δ·T,      (3)
//! ```
//!
//! a smoothing trade-off whose error grows with w; as w → 0 its minimiser
//! tends to the solution of (2) (A has full row rank), and for K = 0 (A
//! square and invertible) to A⁻¹P, the exact method of the scheme (Cheng for
//! Catmull-Clark, the Loop limit-matrix solve, Nasri for Doo-Sabin) — the
//! property the tests check.
//!
//! **Why this energy.** HKD93 minimise the parametric thin-plate functional
//! ∫ ‖x_uu‖² + 2‖x_uv‖² + ‖x_vv‖² of the limit surface, evaluated exactly
//! from the subdivision matrices' eigenstructure; it differs from
//! ∫ ‖x_uu + x_vv‖² by boundary terms only. (1) is its discretisation on the
//! limit points of M^K: on a regular patch of spacing h = 2^−K (the input's
//! faces of unit size) the umbrella Laplacian is (h²/4)·(x_uu + x_vv) + O(h⁴),
//! and the sum has ∝ 4^K terms, so 4^K·Σ‖Δy‖² is a fixed multiple of the
//! functional up to O(h²). It is parametric, as HKD's is, so it depends on
//! the connectivity only: (2) is a quadratic program with constant
//! matrices. A cotangent Laplacian would need the unknown surface's
//! geometry (a nonlinear problem) or a frozen guess of it. The curve rule
//! on boundaries and creases keeps the energy from pulling across a sharp
//! feature (each side of a crease is faired on its own, the crease curve
//! along itself), as the scheme's rules do; corners carry no term.
//!
//! # Algorithm
//! Two algorithms with the same minimiser ([`FairAlgorithm`]; the tests
//! compare them). Both start by planning K levels of the scheme on the
//! input with its tags ([`subdiv_stencil::SubdivisionPlan`]; the tags decay
//! as they do there) and taking M^K with the refined data R·P as starting
//! guess.
//!
//! **Limit points** (the default for Catmull-Clark and Loop with J = 0 and
//! exact constraints). T is invertible (it is the exact method's limit
//! matrix of M^K), so Y = T·X is a change of unknowns, and (2) becomes
//! *minimise ‖Δ·Y‖² subject to Y_v = P_v at the interpolated images*: a
//! discrete biharmonic fairing of the limit points with the data pinned.
//! 1. Fair Y: CG on the normal equations Δ_Fᵀ·Δ_F·Y_F = −Δ_Fᵀ·Δ_P·P over
//!    the free points Y_F (Δ_F, Δ_P: Δ's columns of the free and the pinned
//!    points; the elimination below with identity constraints, whose
//!    null-space basis is a selection of columns and is not built).
//! 2. X = T⁻¹·Y by the exact method of the scheme on M^K (Cheng's solve for
//!    Catmull-Clark, the Loop limit-matrix solve), to the tolerance. On an
//!    untagged M^K the limit matrix T = D·S is assembled once and serves
//!    this solve, the constraint rows of step 3 and the energy's limit
//!    points (Cheng's degeneracy tests cannot fire there: M^K, K ≥ 1, has
//!    no closed component of valence-3 vertices, and meshes with interior
//!    valence-2 vertices, or tags, go through Cheng's method itself).
//! 3. The constraint rows solved for their private pivots (below), which
//!    makes the interpolation exact to round-off whatever step 2 reached.
//!
//! **The tolerances of steps 1 and 2** change the energy only: after step 3
//! the limit points differ from the minimiser Y* by δ with δ = 0 at the
//! pinned points, where alone the gradient of ‖ΔY‖² is non-zero, so the
//! excess is ‖Δδ‖² ≥ 0 (no first-order term). It is not small in the
//! *relative residual* of the CG, though: the fairing's normal equations
//! are ill-conditioned (a biharmonic operator), and measured on Table 7's
//! models the relative excess grows about linearly with step 1's
//! tolerance (10⁻⁵: ≤ 2·10⁻⁶, 10⁻⁴: ≤ 2·10⁻⁴, 10⁻³: ≤ 9·10⁻³ on spot,
//! knight, fandisk), and with step 2's (10⁻⁵·d: ≤ 5·10⁻⁷ on those, but
//! 1.6·10⁻⁴ on horse-3, whose energy is tiny; 10⁻⁴·d: 4 % there). Both
//! stay at 10⁻⁶: loosening step 2 saves two of four iterations on horse-3,
//! and its time is the assembly of T, not the iterations.
//!
//! **Elimination** (Doo-Sabin, J > 0, the penalty, or on request): the
//! null-space method in the control points.
//! 1. Build T, Δ and B = Δ·L·R (kept as factors, never multiplied out).
//! 2. For every constraint row i pick a **private pivot** column p(i): one
//!    that no other constraint row uses (the largest such weight). With
//!    K ≥ 1 one always exists for Catmull-Clark and Loop: every face of M^K
//!    has at most one image of an input vertex, so the image itself is one
//!    (its weight n/(n+5) for Catmull-Clark); for Doo-Sabin the V-faces of
//!    distinct vertices share no vertex. Then A·X = P is solved for the
//!    pivots explicitly,
//!    X_p(i) = (P_i − Σ_{j ≠ p(i)} a_ij X_j) / a_ip(i),
//!    i.e. X = E·y + c with y the points of the free (non-pivot) columns:
//!    every y satisfies the constraints, exactly up to round-off. This is
//!    the accuracy proof: the interpolation error does not depend on how
//!    well the energy is minimised.
//! 3. Minimise ‖B(E·y + c)‖² over y: CG on the normal equations
//!    GᵀG·y = −Gᵀ(B·c), G = B·E, Jacobi-preconditioned (the column norms of
//!    G, pushed through the factors column by column), products by the
//!    factors and their transposes, from the y of R·P; stop at a relative
//!    residual of 10⁻⁶ (the energy's excess over its minimum is of the
//!    order of its square) or `max_iter` (then a warning: the surface
//!    interpolates, but is not the fairest). The constraints pin every data
//!    point, so the free points form patches of bounded size between pinned
//!    ones and the number of iterations does not grow with the mesh.
//! 4. X = E·y + c, the pivots recomputed from the constraint rows. The
//!    control mesh is M^K with X, its tags and texture coordinates.
//!
//! `energy_levels` J > 0 takes (1) on the limit points of M^(K+J) instead:
//! B = Δ·L·R with R: M^K → M^(K+J), L the limit stencil of M^(K+J), and
//! the factor 4^(K+J); closer to the limit surface's energy, about 4^J
//! times the cost.
//!
//! With w > 0, (3) is solved by CG on AᵀA + w·4^K·BᵀB (relative residual
//! 10⁻¹²), starting
//! from (2)'s solution (K ≥ 1) or from X = P (K = 0). The result no longer
//! interpolates: the tolerance check of the numeric rule is not applied
//! (the error is measured and reported as for every method).
//!
//! **Refine 0.** M⁰ is the input: A is square, no freedom is left, and (2)
//! is the exact method of the scheme, which is what runs (its solver, its
//! degeneracy checks, its subset rule: vertices not interpolated keep their
//! data point).
//!
//! # Deviations from the paper
//! - HKD93 evaluate the thin-plate functional exactly on the limit surface
//!   (eigen-analysis of the subdivision matrix at extraordinary points) and
//!   solve the KKT system; here the functional is discretised on the limit
//!   points of M^K, (1), and the constraints are eliminated (a null-space
//!   method with an explicit, sparse null-space basis) instead of a KKT
//!   solve: the reduced problem is positive semidefinite and needs only CG.
//! - HKD93 use Catmull-Clark only; Loop and Doo-Sabin take the same steps
//!   with their own stencils. Doo-Sabin takes K ≤ 1 (the limit sites of the
//!   input vertices are known on M¹), and no interior vertices of valence 2
//!   with K = 1 (their limit row is not a private combination).
//! - Normal constraints (HKD93 §5, Zheng-Cai's `normals`) are not offered:
//!   a tangent-plane constraint couples x, y and z, which the separable
//!   three-column solve does not take.
//! - Vertices outside the subset are unconstrained for K ≥ 1 (their images
//!   are free points of the fairing).
//! - Doo-Sabin: (1) on the limit points of M¹'s vertices (the centroids of
//!   their V-faces one step on) sees little of what happens inside M¹'s
//!   faces, and on triangle meshes fair Doo-Sabin can come out *less* fair
//!   than Nasri's at level 3 (Table 7, the knight); `energy_levels` 1
//!   helps, Catmull-Clark is the scheme to use.
//!
//! # Measured
//! `docs/results/table7-fairness.md` (`cargo xtask reproduce-paper --only
//! table7`): against Cheng on the same inputs, fair Catmull-Clark lowers the
//! largest distance from the surface to the input mesh (the bulging) on
//! every model and the thin-plate energy on most, by modest factors (the
//! energy of a curved shape is mostly its own curvature, which no
//! interpolant removes). Its time is 8-11× Cheng's at 1.5·10⁵ vertices
//! (`cargo run --release -p subdiv-interp --example fair_time`: 2.6 s
//! against 0.18-0.34 s on 2 shared, loaded cores; 12-17× before the
//! fairing went without its null-space basis and T was assembled once),
//! 7.4× in Table 7 (657 ms against 89 ms; 24× before), above the issue's
//! 5×: the solve with T on M¹ (4× Cheng's unknowns, its
//! assembly most of it), building M¹ and Δ, the fairing's products on M¹.
//!
//! **The lower bound of the measure.** Table 7 measures 4³·Σ‖Δy‖²/d² on the
//! level-3 limit points y of the input topology. Every Catmull-Clark
//! surface of that topology through the data has y_v = P_v at the images of
//! the input vertices, and every such y is the limit points of a control
//! mesh M³ (T of M³ is invertible), so fair with refine 3 (J = 0) computes
//! the least value of the measure any such method can reach
//! (`tests/integration/fair_bound.rs` checks it against Cheng and fair K = 1, 2). Its
//! ratio to Cheng's is 0.77 on spot, 0.77 on knight, 0.92 on fandisk and
//! 0.49 on the bunny (fair K = 3 alone: `fair_time --
//! fixtures/open/stanford-bunny.obj 0 3`): halving Cheng's thin-plate
//! measure on three of Table 7's five models is not possible for a
//! Catmull-Clark surface of the input topology (horse-3: M³ would have
//! 9.8·10⁶ unknowns, not computed; its data are smooth and Cheng's measure
//! is within 1 % of fair's). The bound speaks of surfaces whose level-3
//! mesh is M³ with Catmull-Clark limit points (Cheng, fair Catmull-Clark);
//! Loop's, Doo-Sabin's and the refined methods' level-3 meshes have other
//! connectivities, on which the umbrella sum is another functional.
//!
//! ```
//! use subdiv_interp::fair::{self, FairOptions};
//! use subdiv_mesh::shapes;
//! let torus = shapes::torus(12, 8);
//! let result = fair::interpolate(&torus, &FairOptions::default()).unwrap();
//! // Measured independently, from the control mesh by the scheme's rules:
//! assert!(result.error_all(&torus).max_rel <= 1e-9);
//! // The control mesh is M¹: V + E + F points.
//! let t = torus.topology();
//! assert_eq!(result.control.topology().vertex_count(), t.vertex_count() + t.edge_count() + t.face_count());
//! ```
//!
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

mod energy;
mod solve;

pub use energy::thin_plate_energy;

use crate::system::{interpolate_on_input_topology, Limit};
use crate::{
    cheng, nasri, seconds_since, ChengOptions, CommonOptions, InterpError, Interpolant, LimitAssociation, Method,
    NasriOptions, Parameter, SolveSummary,
};
use glam::DVec3;
use sprs::TriMatI;
use subdiv_mesh::Mesh;
use subdiv_solve::Solver;
use subdiv_stencil::{
    doo_sabin_limit_sites, limit_matrix_loop_sharp, limit_operator_catmull_clark_sharp, DualLimitSite, LimitMatrix,
    Scheme, SparseMatrix, StencilError, SubdivisionPlan,
};

/// Default number of refinements of the input that give the control mesh.
pub const DEFAULT_REFINE: usize = 1;
/// The most refinements accepted (each multiplies the unknowns by about 4).
pub const MAX_REFINE: usize = 4;
/// Relative residual of the reduced normal equations at which the fairing
/// stops: the interpolation is exact whatever it is (the constraints are
/// eliminated), and the energy's excess over its minimum is of the order of
/// its square.
const FAIR_RTOL: f64 = 1e-6;
/// The same for the penalty problem (3), whose result nothing corrects.
const PENALTY_RTOL: f64 = 1e-12;

/// Refuses a scheme the fair method cannot take: an interpolatory one
/// ([`subdiv_stencil::SchemeTraits::interpolating`]: Deng-Ma), whose surface
/// is fixed by the data and has no limit points to constrain.
fn check_scheme(scheme: Scheme) -> Result<(), InterpError> {
    if scheme.traits().split == subdiv_stencil::Split::Sqrt3 {
        return Err(InterpError::invalid(
            Parameter::Scheme,
            format!("the fair method does not take {scheme} (its fairing on the √3 split is not built); use --method cheng --scheme {scheme}"),
        ));
    }
    if scheme.traits().interpolating {
        let takes: Vec<&str> = Scheme::ALL.iter().filter(|s| !s.traits().interpolating).map(Scheme::name).collect();
        return Err(InterpError::invalid(
            Parameter::Scheme,
            format!(
                "the fair method takes a scheme with limit points ({}); {scheme} is interpolatory (use --method \
                 deng-ma)",
                takes.join(", ")
            ),
        ));
    }
    Ok(())
}

/// Why the matches below have Deng-Ma and √3 arms that are never taken.
const REFUSED: &str = "interpolatory schemes and √3 are refused by FairOptions::validate";

/// How (2) of the module docs is solved: two algorithms with the same
/// minimiser, one of which needs the energy on M^K's own limit points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum FairAlgorithm {
    /// Limit points for Catmull-Clark and Loop with J = 0 and exact
    /// constraints, elimination otherwise.
    #[default]
    Auto,
    /// Eliminate the constraints by private pivots, CG on the reduced
    /// normal equations in the control points (any scheme, J, weight).
    Elimination,
    /// Fair the limit points Y = T·X with the data pinned, then solve
    /// T·X = Y by the scheme's exact method (Catmull-Clark and Loop, J = 0,
    /// exact constraints).
    LimitPoints,
}

/// Options of [`interpolate`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct FairOptions {
    /// Subset, tolerance (the bound on the measured error), iteration cap
    /// of the minimisation (`solver` is read at refine 0 only, by the exact
    /// method that runs there).
    pub common: CommonOptions,
    /// The control mesh's scheme: Catmull-Clark (the default; HKD93's
    /// scheme), Loop (triangles only) or Doo-Sabin (refine ≤ 1); not an
    /// interpolatory one.
    pub scheme: Scheme,
    /// K: the control mesh is the input refined K times (0 ≤ K ≤ [`MAX_REFINE`];
    /// Doo-Sabin ≤ 1).
    pub refine: usize,
    /// J: the energy is taken on the limit points of M^(K+J) (default 0:
    /// M^K's own; each level multiplies its cost by about 4).
    pub energy_levels: usize,
    /// Which of the two equivalent algorithms solves (2) (module docs).
    pub algorithm: FairAlgorithm,
    /// w of (3) in the module docs: `None` (default) for exact constraints;
    /// `Some(w)`, w > 0, for the penalty trade-off, whose result does not
    /// interpolate.
    pub fairness_weight: Option<f64>,
}

impl Default for FairOptions {
    fn default() -> Self {
        Self {
            common: CommonOptions::default(),
            scheme: Scheme::CatmullClark,
            refine: DEFAULT_REFINE,
            energy_levels: 0,
            algorithm: FairAlgorithm::Auto,
            fairness_weight: None,
        }
    }
}

crate::options::common_setters!(FairOptions);

impl FairOptions {
    /// Sets the scheme.
    ///
    /// # Errors
    /// [`InterpError::InvalidParameter`] for a scheme the method cannot take
    /// (an interpolatory one: Deng-Ma).
    pub fn with_scheme(mut self, scheme: Scheme) -> Result<Self, InterpError> {
        check_scheme(scheme)?;
        self.scheme = scheme;
        Ok(self)
    }

    /// Sets K, the refinements of the input that give the control mesh.
    pub fn with_refine(mut self, refine: usize) -> Self {
        self.refine = refine;
        self
    }

    /// Sets J, the levels beyond M^K whose limit points the energy is taken on.
    pub fn with_energy_levels(mut self, levels: usize) -> Self {
        self.energy_levels = levels;
        self
    }

    /// Sets the algorithm.
    pub fn with_algorithm(mut self, algorithm: FairAlgorithm) -> Self {
        self.algorithm = algorithm;
        self
    }

    /// Sets the fairness weight (`None`: exact constraints).
    pub fn with_fairness_weight(mut self, w: impl Into<Option<f64>>) -> Self {
        self.fairness_weight = w.into();
        self
    }

    fn validate(&self) -> Result<(), InterpError> {
        check_scheme(self.scheme)?;
        if self.refine > MAX_REFINE {
            return Err(InterpError::invalid(
                Parameter::Refine,
                format!(
                    "refine = {} exceeds {MAX_REFINE} (each level multiplies the unknowns by about 4)",
                    self.refine
                ),
            ));
        }
        if self.refine + self.energy_levels > MAX_REFINE {
            return Err(InterpError::invalid(
                Parameter::Refine,
                format!("refine + energy levels = {} exceeds {MAX_REFINE}", self.refine + self.energy_levels),
            ));
        }
        if self.scheme == Scheme::DooSabin && self.refine > 1 {
            return Err(InterpError::invalid(
                Parameter::Refine,
                format!("refine = {}: fair Doo-Sabin takes refine 0 or 1", self.refine),
            ));
        }
        match self.fairness_weight {
            Some(w) if !(w > 0.0 && w.is_finite()) => Err(InterpError::invalid(
                Parameter::FairnessWeight,
                format!("the fairness weight {w} must be finite and > 0 (leave it out for exact constraints)"),
            )),
            _ => Ok(()),
        }
    }
}

/// Interpolates the vertices of `mesh` with the fairest limit surface of the
/// input refined `refine` times (module docs).
///
/// # Errors
/// As every method ([`crate`] docs, "The numeric rule"; with a fairness
/// weight the measured error is not checked against the tolerance);
/// [`InterpError::InvalidParameter`] for a bad refine or weight;
/// [`InterpError::UnsupportedMesh`] for Loop on non-triangles, or Doo-Sabin
/// with interior valence-2 vertices at refine 1; at refine 0 the errors of
/// the exact method that runs.
pub fn interpolate(mesh: &Mesh, opts: &FairOptions) -> Result<Interpolant, InterpError> {
    opts.validate()?;
    let prepared = crate::numeric::prepare(Method::Fair, mesh, Some(&opts.common))?;
    let prepared = if opts.fairness_weight.is_some() { prepared.without_tolerance() } else { prepared };
    let result = interpolate_prepared(&prepared.mesh, prepared.interpolated.clone(), opts)?;
    prepared.finish(result)
}

/// [`interpolate`] on the prepared (scaled) mesh and interpolated set.
pub(crate) fn interpolate_prepared(
    mesh: &Mesh,
    interpolated: Vec<bool>,
    opts: &FairOptions,
) -> Result<Interpolant, InterpError> {
    if opts.scheme.traits().triangles_only {
        if let Some(f) = mesh.topology().face_ids().find(|&f| mesh.topology().face_size(f) != 3) {
            return Err(crate::preconditions::unsupported(
                Method::Fair,
                mesh,
                format!(
                    "the Loop scheme needs triangles and face {f} has {} corners (use --scheme catmull-clark)",
                    mesh.topology().face_size(f)
                ),
            ));
        }
    }
    let mut result = if opts.refine == 0 && opts.fairness_weight.is_none() {
        exact_method(mesh, interpolated, opts)?
    } else {
        fair(mesh, interpolated, opts)?
    };
    result.method = Method::Fair;
    result.parameters.refine = Some(opts.refine);
    result.parameters.fairness_weight = opts.fairness_weight;
    result.parameters.record_scheme(opts.scheme);
    Ok(result)
}

/// Refine 0 with exact constraints: the exact method of the scheme.
fn exact_method(mesh: &Mesh, interpolated: Vec<bool>, opts: &FairOptions) -> Result<Interpolant, InterpError> {
    let common = opts.common.clone();
    match opts.scheme {
        Scheme::CatmullClark => {
            cheng::interpolate_prepared(mesh, interpolated, &ChengOptions::default().with_common(common))
        }
        Scheme::DooSabin => {
            nasri::interpolate_prepared(mesh, interpolated, &NasriOptions::default().with_common(common))
        }
        Scheme::Loop(beta) => {
            let start = std::time::Instant::now();
            let sharp = common.surface.sharpness(mesh.tags());
            let a = limit_matrix_loop_sharp(mesh.topology(), &sharp, beta)?;
            let setup = seconds_since(start);
            interpolate_on_input_topology(
                Method::Fair,
                mesh,
                interpolated,
                Limit::Owned(a),
                setup,
                Scheme::Loop(beta),
                &common,
                Solver::Cg { jacobi: true },
                Vec::new(),
            )
        }
        Scheme::DengMa(_) | Scheme::Sqrt3 => unreachable!("{REFUSED}"),
    }
}

/// The constraint rows: per interpolated input vertex, its limit point as
/// a combination of M^K's points, and the data point it must equal.
struct Constraints {
    /// (columns, weights) per row.
    rows: Vec<(Vec<u32>, Vec<f64>)>,
    /// The data point of each row.
    data: Vec<DVec3>,
}

impl Constraints {
    /// A (rows × m) as CSR.
    fn matrix(&self, m: usize) -> SparseMatrix {
        let mut tri = TriMatI::<f64, u32>::new((self.rows.len(), m));
        for (i, (cols, w)) in self.rows.iter().enumerate() {
            for (&j, &a) in cols.iter().zip(w) {
                tri.add_triplet(i, j as usize, a);
            }
        }
        tri.to_csr()
    }
}

/// The general path: K ≥ 1, or a penalty.
fn fair(mesh: &Mesh, interpolated: Vec<bool>, opts: &FairOptions) -> Result<Interpolant, InterpError> {
    let start = std::time::Instant::now();
    let t = mesh.topology();
    let k = opts.refine;
    let options = opts.common.surface.for_scheme(opts.scheme);
    let plan = SubdivisionPlan::with_tags(t, mesh.tags(), options, k)?;
    let mut warnings = Vec::new();
    // M^K with the refined data (the starting guess), its tags and UVs.
    let refined = match plan.subdivide(mesh, false) {
        Ok(m) => m,
        Err(StencilError::FaceVarying(e)) => {
            warnings.push(format!("the texture coordinates are not carried onto the control mesh: {e}"));
            let plain = mesh.clone().with_uvs(None).expect("no channel is always valid");
            plan.subdivide(&plain, false)?
        }
        Err(e) => return Err(e.into()),
    };
    drop(plan);
    let tk = refined.topology();
    let sharp_k = opts.common.surface.sharpness(refined.tags());
    let by_limit_points = match opts.algorithm {
        FairAlgorithm::Auto => {
            k > 0 && opts.energy_levels == 0 && opts.fairness_weight.is_none() && opts.scheme != Scheme::DooSabin
        }
        FairAlgorithm::LimitPoints => true,
        FairAlgorithm::Elimination => false,
    };
    if by_limit_points {
        return by_limit_points_path(mesh, interpolated, opts, refined, sharp_k, start, warnings);
    }
    // T: the limit stencil of M^K with its tags (the rows the error check evaluates).
    let rules = options.scheme.rules();
    let limit = if rules.levels_before_limit(tk, &sharp_k, true) == 0 {
        rules.limit_stencil(tk, &sharp_k, tk.vertex_count()).expect("the fair schemes have limit masks")?
    } else {
        // Semi-sharp tags left: the plan composes the levels the masks need.
        let limit_plan = SubdivisionPlan::with_tags(tk, refined.tags(), options, 0)?;
        limit_plan.limit_stencil_local().expect("the fair schemes have limit masks")?
    };
    // The constraints and the association of the input vertices.
    let (constraints, association) = constraints(mesh, &interpolated, &limit, opts, k)?;
    // B = Δ·L·R: the Laplacian of the limit points of M^(K+J), as a chain.
    let b = energy_operator(tk, &sharp_k, refined.tags(), options, opts.energy_levels, limit)?;
    let scale = 4f64.powi((k + opts.energy_levels) as i32);
    let setup_seconds = seconds_since(start);
    let solve_start = std::time::Instant::now();
    let x0 = refined.positions().to_vec();
    let max_iter = opts.common.max_iter;
    let (mut x, mut summary) = if k == 0 {
        (x0, SolveSummary { solver: "none".into(), converged: true, ..Default::default() })
    } else {
        minimise_exact(&constraints, &b, x0, max_iter, mesh)?
    };
    if let Some(w) = opts.fairness_weight {
        let (xp, penalty) = minimise_penalty(&constraints, &b, w * scale, x, max_iter);
        x = xp;
        summary = merge(summary, penalty);
    }
    let energy = scale * squared_norm(&b.apply(&x));
    let d = mesh.bbox_diagonal();
    let solve_seconds = seconds_since(solve_start);
    let control = refined.with_positions(x);
    Ok(Solved {
        control,
        interpolated,
        association,
        summary,
        warnings,
        energy: energy / (d * d),
        setup_seconds,
        solve_seconds,
    }
    .into_interpolant(opts))
}

/// The limit-points algorithm (module docs): the fairest limit points Y of
/// M^K with the data pinned, then the control points X with T·X = Y by the
/// scheme's exact method on M^K, then the pivots recomputed from the
/// constraint rows (exact to round-off).
fn by_limit_points_path(
    mesh: &Mesh,
    interpolated: Vec<bool>,
    opts: &FairOptions,
    refined: Mesh,
    sharp_k: subdiv_stencil::LevelSharpness,
    start: std::time::Instant,
    mut warnings: Vec<String>,
) -> Result<Interpolant, InterpError> {
    if opts.scheme == Scheme::DooSabin || opts.energy_levels > 0 || opts.fairness_weight.is_some() {
        return Err(InterpError::invalid(
            Parameter::Scheme,
            "the limit-points algorithm takes Catmull-Clark or Loop, exact constraints and no energy levels",
        ));
    }
    let k = opts.refine;
    let tk = refined.topology();
    let m = tk.vertex_count();
    let n = mesh.topology().vertex_count();
    let options = opts.common.surface.for_scheme(opts.scheme);
    // (a) Y: min ‖Δ·Y‖² with Y_v = P_v at the interpolated images.
    let mut pinned = vec![false; m];
    let mut y = refined.positions().to_vec();
    for v in (0..n).filter(|&v| interpolated[v]) {
        (pinned[v], y[v]) = (true, mesh.positions()[v]);
    }
    let delta = energy::umbrella(tk, &sharp_k);
    let setup_seconds = seconds_since(start);
    let solve_start = std::time::Instant::now();
    let (y, fairing) = minimise_pinned(&delta, &pinned, y, FAIR_RTOL, opts.common.max_iter);
    // (b) X with T·X = Y: the exact method of the scheme on M^K.
    let fine = refined.with_positions(y);
    let fine_opts = FairOptions { common: opts.common.clone().with_subset(None), ..opts.clone() };
    let everything = vec![true; m];
    let (mut x, exact_summary, limit) = match assembled_limit_matrix(&fine, &sharp_k, opts.scheme)? {
        Some(a) => {
            // Untagged M^K: its limit matrix once, for the solve, the
            // constraint rows and the energy (module docs: no degeneracy to test).
            let solved = crate::system::solve_limit_system_with(
                Method::Fair.name(),
                Limit::Borrowed(&a),
                fine.positions(),
                &everything,
                fine_opts.common.solver,
                Solver::Cg { jacobi: true }.into(),
                fine_opts.common.tol,
                fine_opts.common.max_iter,
                fine.bbox_diagonal(),
                &fine_opts.common.observer,
            )?;
            (solved.x, solved.summary, Some(a))
        }
        None => {
            let exact = exact_method(&fine, everything, &fine_opts)?;
            warnings.extend(exact.warnings);
            (exact.control.positions().to_vec(), exact.solve.unwrap_or_default(), None)
        }
    };
    // (c) The constraint rows (the first n rows of T) solved for their pivots.
    let rows = match &limit {
        Some(a) => first_rows(a, n),
        None => {
            let rules = options.scheme.rules();
            if rules.levels_before_limit(tk, &sharp_k, true) == 0 {
                rules.limit_stencil(tk, &sharp_k, n).expect("the fair schemes have limit masks")?
            } else {
                let plan = SubdivisionPlan::with_tags(tk, fine.tags(), options, 0)?;
                plan.limit_stencil_local().expect("the fair schemes have limit masks")?
            }
        }
    };
    let (constraints, association) = constraints(mesh, &interpolated, &rows, opts, k)?;
    let pivots = private_pivots(&constraints, m, mesh)?;
    for (i, ((cols, w), &(p, ap))) in constraints.rows.iter().zip(&pivots).enumerate() {
        let others: DVec3 = cols.iter().zip(w).filter(|&(&j, _)| j != p).map(|(&j, &a)| a * x[j as usize]).sum();
        x[p as usize] = (constraints.data[i] - others) / ap;
    }
    let exact_solver = if exact_summary.solver.is_empty() { "none".to_string() } else { exact_summary.solver.clone() };
    let mut summary = merge(fairing, exact_summary);
    summary.solver = format!("fair-cg+{exact_solver}");
    let control = fine.with_positions(x);
    let limits = match &limit {
        // T·X = D·(S·X).
        Some(a) => subdiv_stencil::apply(&a.s, control.positions()).iter().zip(&a.d).map(|(p, &d)| d * *p).collect(),
        None => subdiv_stencil::limit_points_with_options(tk, control.tags(), options, control.positions())?
            .expect("the fair schemes have limit masks"),
    };
    let d = mesh.bbox_diagonal();
    let energy = 4f64.powi(k as i32) * squared_norm(&subdiv_stencil::apply(&delta, &limits)) / (d * d);
    let solve_seconds = seconds_since(solve_start);
    Ok(Solved { control, interpolated, association, summary, warnings, energy, setup_seconds, solve_seconds }
        .into_interpolant(opts))
}

/// The limit matrix T = D·S of an untagged M^K (K ≥ 1) for Catmull-Clark
/// and Loop, assembled; `None` where the exact method's own checks are
/// needed (tags, whose semi-sharp levels and kernel tests the exact method
/// handles; Catmull-Clark interior vertices of valence 2, for which Cheng's
/// method picks its solver). Untagged M^K of K ≥ 1 has no closed component of
/// valence-3 vertices only (its edge points have valence 4 inside), so
/// Cheng's singular case cannot occur.
fn assembled_limit_matrix(
    fine: &Mesh,
    sharp: &subdiv_stencil::LevelSharpness,
    scheme: Scheme,
) -> Result<Option<LimitMatrix>, InterpError> {
    let t = fine.topology();
    if !fine.tags().is_empty() {
        return Ok(None);
    }
    Ok(match scheme {
        Scheme::CatmullClark => {
            if t.vertices().any(|v| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2) {
                return Ok(None);
            }
            Some(limit_operator_catmull_clark_sharp(t, sharp)?.assemble())
        }
        Scheme::Loop(beta) => Some(limit_matrix_loop_sharp(t, sharp, beta)?),
        Scheme::DooSabin => None,
        Scheme::DengMa(_) | Scheme::Sqrt3 => unreachable!("{REFUSED}"),
    })
}

/// The first `n` rows of T = D·S as a CSR matrix (n × m).
fn first_rows(a: &LimitMatrix, n: usize) -> SparseMatrix {
    let (mut indptr, mut indices, mut data) = (Vec::with_capacity(n + 1), Vec::new(), Vec::new());
    indptr.push(0u32);
    for v in 0..n {
        for (j, &w) in a.s.outer_view(v).expect("a row of the limit matrix").iter() {
            indices.push(j as u32);
            data.push(a.d[v] * w);
        }
        indptr.push(indices.len() as u32);
    }
    SparseMatrix::new((n, a.s.cols()), indptr, indices, data)
}

/// A product of sparse matrices M_r ⋯ M_1, applied factor by factor (never
/// multiplied out: the product of the energy's factors has several times
/// their entries), and its transpose by scattering over the same rows.
struct Chain {
    /// M_1, …, M_r.
    factors: Vec<SparseMatrix>,
    /// Their transposes as CSR (the transposed products are parallel gathers).
    transposes: Vec<SparseMatrix>,
}

impl Chain {
    fn new(factors: Vec<SparseMatrix>) -> Self {
        use rayon::prelude::*;
        let transposes = factors.par_iter().map(|m| m.transpose_view().to_csr()).collect();
        Chain { factors, transposes }
    }

    /// M_r ⋯ M_1 · x.
    fn apply(&self, x: &[DVec3]) -> Vec<DVec3> {
        let mut y = subdiv_stencil::apply(&self.factors[0], x);
        for m in &self.factors[1..] {
            y = subdiv_stencil::apply(m, &y);
        }
        y
    }

    /// (M_r ⋯ M_1)ᵀ · y.
    fn apply_t(&self, y: &[DVec3]) -> Vec<DVec3> {
        let mut x = subdiv_stencil::apply(self.transposes.last().expect("a chain has a factor"), y);
        for m in self.transposes[..self.transposes.len() - 1].iter().rev() {
            x = subdiv_stencil::apply(m, &x);
        }
        x
    }

    /// (M_r ⋯ M_1)ᵀ(M_r ⋯ M_1)·y into `out`, through buffers kept from
    /// call to call (fresh buffers of this size would cost a page fault per
    /// page on every product).
    fn normal_into(&self, y: &[DVec3], out: &mut [DVec3], scratch: &mut Scratch) {
        let r = self.factors.len();
        if scratch.forward.len() != r {
            scratch.forward = self.factors.iter().map(|m| vec![DVec3::ZERO; m.rows()]).collect();
            scratch.backward = self.factors.iter().map(|m| vec![DVec3::ZERO; m.cols()]).collect();
        }
        for k in 0..r {
            let (done, rest) = scratch.forward.split_at_mut(k);
            let input = if k == 0 { y } else { &done[k - 1][..] };
            apply_into(&self.factors[k], input, &mut rest[0]);
        }
        // backward[k] = M_kᵀ · (what came back from above), k = r−1 … 0.
        for k in (0..r).rev() {
            let (below, above) = scratch.backward.split_at_mut(k + 1);
            let input = if k + 1 == r { &scratch.forward[r - 1][..] } else { &above[0][..] };
            let target: &mut [DVec3] = if k == 0 { &mut *out } else { &mut below[k] };
            apply_into(&self.transposes[k], input, target);
        }
    }

    /// Σ_i (M_r ⋯ M_1)_ij² per column j (the Jacobi preconditioner of
    /// the normal equations): column j pushed through the factors as a
    /// sparse vector (each factor's transpose gives its columns), in
    /// parallel over chunks of columns.
    fn column_squares(&self) -> Vec<f64> {
        use rayon::prelude::*;
        let transposes = &self.transposes;
        let cols = self.factors[0].cols();
        let widest = self.factors.iter().map(|m| m.rows()).max().unwrap_or(0);
        let mut out = vec![0.0; cols];
        if let [single] = &transposes[..] {
            // One factor: its columns are its transpose's rows.
            out.par_iter_mut().enumerate().for_each(|(j, slot)| {
                *slot = single.outer_view(j).expect("a column of the factor").data().iter().map(|a| a * a).sum();
            });
            return out;
        }
        // The dense scratch (as long as the widest factor) once per rayon
        // job, not once per chunk of columns.
        let scratch = || {
            let current: Vec<(u32, f64)> = Vec::new();
            (vec![0.0; widest], vec![false; widest], current, Vec::<u32>::new())
        };
        out.par_chunks_mut(4096).enumerate().for_each_init(scratch, |(dense, seen, current, next), (chunk, slots)| {
            for (k, slot) in slots.iter_mut().enumerate() {
                current.clear();
                current.push(((chunk * 4096 + k) as u32, 1.0));
                for mt in transposes.iter() {
                    next.clear();
                    for &(i, v) in current.iter() {
                        let row = mt.outer_view(i as usize).expect("a column of the factor");
                        for (r, &a) in row.iter() {
                            if !seen[r] {
                                seen[r] = true;
                                next.push(r as u32);
                            }
                            dense[r] += v * a;
                        }
                    }
                    current.clear();
                    for &r in next.iter() {
                        current.push((r, dense[r as usize]));
                        (dense[r as usize], seen[r as usize]) = (0.0, false);
                    }
                }
                *slot = current.iter().map(|&(_, v)| v * v).sum();
            }
        });
        out
    }
}

/// The buffers of [`Chain::normal_into`].
#[derive(Default)]
struct Scratch {
    forward: Vec<Vec<DVec3>>,
    backward: Vec<Vec<DVec3>>,
}

/// What either algorithm ends with, before it becomes the [`Interpolant`].
struct Solved {
    control: Mesh,
    interpolated: Vec<bool>,
    association: LimitAssociation,
    summary: SolveSummary,
    warnings: Vec<String>,
    /// The thin-plate energy over d².
    energy: f64,
    setup_seconds: f64,
    solve_seconds: f64,
}

impl Solved {
    /// The interpolant, with a warning when the fairness minimisation stopped early.
    fn into_interpolant(self, opts: &FairOptions) -> Interpolant {
        let Solved { control, interpolated, association, summary, mut warnings, energy, setup_seconds, solve_seconds } =
            self;
        if !summary.converged {
            warnings.push(format!(
                "the fairness minimisation stopped after {} iterations at relative residual {:.1e} (max_iter): the \
                 surface is not the fairest of its kind{}",
                summary.iterations,
                summary.residual,
                if opts.fairness_weight.is_none() { ", but it interpolates" } else { "" }
            ));
        }
        let parameters = crate::Parameters {
            solver: Some(summary.solver.clone()),
            tol: Some(opts.common.tol),
            energy: Some(energy),
            ..Default::default()
        };
        Interpolant {
            method: Method::Fair,
            control,
            scheme: opts.scheme,
            surface_options: opts.common.surface,
            interpolated,
            association,
            solve: Some(summary),
            setup_seconds,
            solve_seconds,
            warnings,
            parameters,
            measured_error: None,
        }
    }
}

/// Σ‖x_i‖².
fn squared_norm(x: &[DVec3]) -> f64 {
    x.iter().map(|p| p.length_squared()).sum()
}

/// M·x into `out` (rows in parallel chunks).
fn apply_into(m: &SparseMatrix, x: &[DVec3], out: &mut [DVec3]) {
    use rayon::prelude::*;
    debug_assert_eq!((m.rows(), m.cols()), (out.len(), x.len()));
    let indptr = m.indptr();
    let indptr = indptr.raw_storage();
    let (indices, data) = (m.indices(), m.data());
    out.par_chunks_mut(8192).enumerate().for_each(|(c, chunk)| {
        for (k, o) in chunk.iter_mut().enumerate() {
            let i = c * 8192 + k;
            let mut acc = DVec3::ZERO;
            for q in indptr[i] as usize..indptr[i + 1] as usize {
                acc += data[q] * x[indices[q] as usize];
            }
            *o = acc;
        }
    });
}

/// B of (1) as a chain: R (M^K → M^(K+J), J levels), then the limit
/// stencil L of M^(K+J), then its umbrella Laplacian Δ. For J = 0, `limit`
/// (M^K's) is L.
fn energy_operator(
    tk: &subdiv_mesh::Topology,
    sharp: &subdiv_stencil::LevelSharpness,
    tags: &subdiv_mesh::Tags,
    options: subdiv_stencil::Options,
    levels: usize,
    limit: SparseMatrix,
) -> Result<Chain, InterpError> {
    if levels == 0 {
        let delta = energy::umbrella(tk, sharp);
        return Ok(Chain::new(vec![limit, delta]));
    }
    drop(limit);
    let plan = SubdivisionPlan::with_tags(tk, tags, options, levels)?;
    let delta = energy::umbrella(plan.topology(), plan.sharpness());
    let mut chain: Vec<SparseMatrix> =
        plan.levels().iter().map(|l| l.stencil.clone().expect("the fair schemes have stencils")).collect();
    chain.push(plan.limit_stencil_local().expect("the fair schemes have limit masks")?);
    chain.push(delta);
    Ok(Chain::new(chain))
}

/// The constraint rows of the interpolated vertices, and where the input
/// vertices' limit points are in the control mesh.
fn constraints(
    mesh: &Mesh,
    interpolated: &[bool],
    limit: &SparseMatrix,
    opts: &FairOptions,
    k: usize,
) -> Result<(Constraints, LimitAssociation), InterpError> {
    let t = mesh.topology();
    let data = mesh.positions();
    let mut rows = Vec::new();
    let mut points = Vec::new();
    if opts.scheme == Scheme::DooSabin && k == 1 {
        // M¹'s numbering is dual_split_tagged's (the plan's Doo-Sabin split).
        let (_, provenance, _) = subdiv_mesh::refine::dual_split_tagged(t, mesh.tags());
        let sites = doo_sabin_limit_sites(t, mesh.tags(), &provenance)?;
        let (t1, _, _) = subdiv_mesh::refine::dual_split_tagged(t, mesh.tags());
        for v in t.vertices().filter(|v| interpolated[v.index()]) {
            let row = match sites[v.index()] {
                DualLimitSite::FaceCentroid(f) => {
                    let face = t1.face(f);
                    (face.to_vec(), vec![1.0 / face.len() as f64; face.len()])
                }
                DualLimitSite::SharpMidpoint(a, b) => (vec![a.0, b.0], vec![0.5, 0.5]),
                DualLimitSite::Corner(c) => (vec![c.0], vec![1.0]),
                DualLimitSite::ValenceTwoEdge(..) => {
                    return Err(crate::preconditions::unsupported(
                        Method::Fair,
                        mesh,
                        format!(
                            "vertex {v} is an interior vertex of valence 2, whose Doo-Sabin limit point on M¹ is \
                             not a combination the fair method can eliminate (use --refine 0, or Catmull-Clark)"
                        ),
                    ))
                }
                DualLimitSite::Isolated => continue,
            };
            rows.push(row);
            points.push(data[v.index()]);
        }
        return Ok((Constraints { rows, data: points }, LimitAssociation::DualSites(sites)));
    }
    for v in t.vertices().filter(|v| interpolated[v.index()]) {
        let row = limit.outer_view(v.index()).expect("every input vertex has an image");
        rows.push((row.indices().to_vec(), row.data().to_vec()));
        points.push(data[v.index()]);
    }
    Ok((Constraints { rows, data: points }, LimitAssociation::ControlVertex))
}

/// Step 2-4 of the module docs: eliminate a private pivot per constraint,
/// minimise the energy over the free points by CG.
fn minimise_exact(
    c: &Constraints,
    b: &Chain,
    x0: Vec<DVec3>,
    max_iter: usize,
    mesh: &Mesh,
) -> Result<(Vec<DVec3>, SolveSummary), InterpError> {
    let m = x0.len();
    let pivots = private_pivots(c, m, mesh)?;
    let mut is_pivot = vec![false; m];
    for &(p, _) in &pivots {
        is_pivot[p as usize] = true;
    }
    // Free columns, numbered.
    let mut free_index = vec![u32::MAX; m];
    let mut free = Vec::with_capacity(m - pivots.len());
    for j in 0..m {
        if !is_pivot[j] {
            free_index[j] = free.len() as u32;
            free.push(j);
        }
    }
    let nf = free.len();
    // X = E·y + c, E (m × nf) built row by row: a free row is its own column,
    // a pivot row −a_ij/a_ip over the other columns of its constraint.
    let mut pivot_row = vec![u32::MAX; m];
    for (i, &(p, _)) in pivots.iter().enumerate() {
        pivot_row[p as usize] = i as u32;
    }
    let mut shift = vec![DVec3::ZERO; m];
    let (mut indptr, mut indices, mut data) = (Vec::with_capacity(m + 1), Vec::new(), Vec::new());
    indptr.push(0u32);
    let mut row = Vec::new();
    for j in 0..m {
        if free_index[j] != u32::MAX {
            indices.push(free_index[j]);
            data.push(1.0);
        } else {
            let i = pivot_row[j] as usize;
            let (cols, w) = &c.rows[i];
            let ap = pivots[i].1;
            row.clear();
            row.extend(
                cols.iter().zip(w).filter(|&(&q, _)| q as usize != j).map(|(&q, &a)| (free_index[q as usize], -a / ap)),
            );
            row.sort_unstable_by_key(|e| e.0);
            for &(q, v) in &row {
                indices.push(q);
                data.push(v);
            }
            shift[j] = c.data[i] / ap;
        }
        indptr.push(indices.len() as u32);
    }
    let e = SparseMatrix::new((m, nf), indptr, indices, data);
    let mut factors = vec![e];
    factors.extend(b.factors.iter().cloned());
    let g = Chain::new(factors);
    let g0 = b.apply(&shift);
    let rhs: Vec<DVec3> = g.apply_t(&g0).into_iter().map(|v| -v).collect();
    let diag = g.column_squares();
    let y0: Vec<DVec3> = free.iter().map(|&j| x0[j]).collect();
    let mut scratch = Scratch::default();
    let run = solve::pcg(|y, out| g.normal_into(y, out, &mut scratch), &diag, &rhs, y0, FAIR_RTOL, max_iter);
    // X: the free points, then each pivot from its row (exact elimination).
    let mut x = vec![DVec3::ZERO; m];
    for (k, &j) in free.iter().enumerate() {
        x[j] = run.x[k];
    }
    for (i, ((cols, w), &(p, ap))) in c.rows.iter().zip(&pivots).enumerate() {
        let others: DVec3 = cols.iter().zip(w).filter(|&(&j, _)| j != p).map(|(&j, &a)| a * x[j as usize]).sum();
        x[p as usize] = (c.data[i] - others) / ap;
    }
    Ok((x, summary_of("fair-cg", &run)))
}

/// Step 1 of the limit-points algorithm: min ‖Δ·Y‖² over the free points
/// of `y` with the `pinned` ones held at their values in `y`, by CG on the
/// normal equations Δ_Fᵀ·Δ_F·y_F = −Δ_Fᵀ·(Δ_P·y_P) (Δ_F, Δ_P: Δ's columns
/// of the free and of the pinned points), Jacobi-preconditioned, from the
/// free points of `y`. It is [`minimise_exact`] for identity constraint
/// rows (every pivot its own row, the null-space basis a selection of
/// columns), without building that basis: one factor instead of two in
/// every product.
fn minimise_pinned(
    delta: &SparseMatrix,
    pinned: &[bool],
    mut y: Vec<DVec3>,
    rtol: f64,
    max_iter: usize,
) -> (Vec<DVec3>, SolveSummary) {
    let m = y.len();
    let mut free_index = vec![u32::MAX; m];
    let mut free = Vec::with_capacity(m);
    for j in (0..m).filter(|&j| !pinned[j]) {
        free_index[j] = free.len() as u32;
        free.push(j);
    }
    // Δ_F (columns renumbered, still sorted) and g₀ = Δ_P·y_P, row by row.
    let (mut indptr, mut indices, mut data) = (Vec::with_capacity(m + 1), Vec::new(), Vec::new());
    let mut g0 = vec![DVec3::ZERO; delta.rows()];
    indptr.push(0u32);
    for (row, g) in delta.outer_iterator().zip(g0.iter_mut()) {
        for (j, &w) in row.iter() {
            if pinned[j] {
                *g += w * y[j];
            } else {
                indices.push(free_index[j]);
                data.push(w);
            }
        }
        indptr.push(indices.len() as u32);
    }
    let g = Chain::new(vec![SparseMatrix::new((delta.rows(), free.len()), indptr, indices, data)]);
    let rhs: Vec<DVec3> = g.apply_t(&g0).into_iter().map(|v| -v).collect();
    let diag = g.column_squares();
    let y0: Vec<DVec3> = free.iter().map(|&j| y[j]).collect();
    let mut scratch = Scratch::default();
    let run = solve::pcg(|v, out| g.normal_into(v, out, &mut scratch), &diag, &rhs, y0, rtol, max_iter);
    for (k, &j) in free.iter().enumerate() {
        y[j] = run.x[k];
    }
    (y, summary_of("fair-cg", &run))
}

/// Per constraint row, a private pivot (a column no other row uses, the
/// largest such weight) and its weight.
fn private_pivots(c: &Constraints, m: usize, mesh: &Mesh) -> Result<Vec<(u32, f64)>, InterpError> {
    // How many constraint rows use each column.
    let mut uses = vec![0u32; m];
    for (cols, _) in &c.rows {
        for &j in cols {
            uses[j as usize] += 1;
        }
    }
    let mut pivots = Vec::with_capacity(c.rows.len());
    for (i, (cols, w)) in c.rows.iter().enumerate() {
        let best = cols
            .iter()
            .zip(w)
            .filter(|&(&j, &a)| uses[j as usize] == 1 && a != 0.0)
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .map(|(&j, &a)| (j, a));
        let Some(pivot) = best else {
            return Err(crate::preconditions::unsupported(
                Method::Fair,
                mesh,
                format!(
                    "the limit point of interpolated row {i} shares every control point with another one (semi-sharp \
                     creases spreading the limit rows), so the constraints cannot be eliminated point by point \
                     (use --refine 0, or a larger refine)"
                ),
            ));
        };
        pivots.push(pivot);
    }
    Ok(pivots)
}

/// (3) of the module docs: CG on AᵀA + s·BᵀB from `x0`.
fn minimise_penalty(c: &Constraints, b: &Chain, s: f64, x0: Vec<DVec3>, max_iter: usize) -> (Vec<DVec3>, SolveSummary) {
    let m = x0.len();
    let a = Chain::new(vec![c.matrix(m)]);
    let rhs = a.apply_t(&c.data);
    let diag: Vec<f64> = a.column_squares().iter().zip(b.column_squares()).map(|(da, db)| da + s * db).collect();
    let (mut sa, mut sb) = (Scratch::default(), Scratch::default());
    let mut bx = vec![DVec3::ZERO; m];
    let apply = |x: &[DVec3], out: &mut [DVec3]| {
        a.normal_into(x, out, &mut sa);
        b.normal_into(x, &mut bx, &mut sb);
        out.iter_mut().zip(&bx).for_each(|(u, v)| *u += s * *v);
    };
    let run = solve::pcg(apply, &diag, &rhs, x0, PENALTY_RTOL, max_iter);
    let summary = summary_of("fair-penalty-cg", &run);
    (run.x, summary)
}

fn summary_of(name: &str, run: &solve::CgRun) -> SolveSummary {
    SolveSummary {
        solver: name.to_string(),
        iterations: run.iterations,
        matvecs: 2 * run.products,
        converged: run.converged,
        residual: run.residual,
        history: run.history.clone(),
        negative_pivots: None,
    }
}

fn merge(first: SolveSummary, second: SolveSummary) -> SolveSummary {
    let mut history = first.history;
    history.extend(second.history);
    SolveSummary {
        solver: if first.iterations == 0 { second.solver } else { format!("{}+{}", first.solver, second.solver) },
        iterations: first.iterations + second.iterations,
        matvecs: first.matvecs + second.matvecs,
        converged: first.converged && second.converged,
        residual: second.residual,
        history,
        negative_pivots: None,
    }
}
