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
//! # Algorithm (null-space method, exact constraints)
//! 1. Plan K levels of the scheme on the input with its tags
//!    ([`subdiv_stencil::SubdivisionPlan`]; the tags decay as they do there)
//!    and take M^K with the refined data R·P as starting guess; build T and
//!    Δ, and B = Δ·T.
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
//!    GᵀG·y = −Gᵀ(B·c), G = B·E, Jacobi-preconditioned, products by G and
//!    Gᵀ (never GᵀG), from the y of R·P; stop at a relative residual of
//!    10⁻¹⁰ or `max_iter` (then a warning: the surface interpolates, but is
//!    not the fairest). The constraints pin every data point, so the free
//!    points form patches of bounded size between pinned ones and the
//!    number of iterations does not grow with the mesh.
//! 4. X = E·y + c, the pivots recomputed from the constraint rows. The
//!    control mesh is M^K with X, its tags and texture coordinates.
//!
//! With w > 0, (3) is solved by the same CG on AᵀA + w·4^K·BᵀB, starting
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
    cheng, nasri, seconds_since, ChengOptions, CommonOptions, ControlScheme, InterpError, Interpolant,
    LimitAssociation, Method, NasriOptions, Parameter, SolveSummary,
};
use glam::DVec3;
use sprs::TriMatI;
use std::fmt;
use std::str::FromStr;
use subdiv_mesh::Mesh;
use subdiv_solve::Solver;
use subdiv_stencil::{
    doo_sabin_limit_sites, limit_matrix_loop_sharp, DualLimitSite, LoopBeta, Scheme, SparseMatrix, StencilError,
    SubdivisionPlan,
};

/// Default number of refinements of the input that give the control mesh.
pub const DEFAULT_REFINE: usize = 1;
/// The most refinements accepted (each multiplies the unknowns by about 4).
pub const MAX_REFINE: usize = 4;
/// Relative residual of the normal equations at which the minimisation stops.
const FAIR_RTOL: f64 = 1e-10;

/// The scheme whose control mesh the fair method computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum FairScheme {
    /// Catmull-Clark (any polygons; HKD93's scheme). The default.
    #[default]
    CatmullClark,
    /// Loop with this β (triangles only).
    Loop(LoopBeta),
    /// Standard Doo-Sabin (refine ≤ 1).
    DooSabin,
}

impl FairScheme {
    /// The subdivision scheme.
    pub fn scheme(self) -> Scheme {
        match self {
            FairScheme::CatmullClark => Scheme::CatmullClark,
            FairScheme::Loop(beta) => Scheme::Loop(beta),
            FairScheme::DooSabin => Scheme::DooSabin,
        }
    }

    /// The control scheme of the result.
    pub fn control_scheme(self) -> ControlScheme {
        match self {
            FairScheme::CatmullClark => ControlScheme::CatmullClark,
            FairScheme::Loop(beta) => ControlScheme::Loop(beta),
            FairScheme::DooSabin => ControlScheme::DooSabin,
        }
    }

    /// `catmull-clark`, `loop` or `doo-sabin` (parsed back by [`FromStr`]).
    pub fn name(self) -> &'static str {
        self.scheme().name()
    }
}

impl fmt::Display for FairScheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FairScheme {
    type Err = InterpError;

    /// `catmull-clark` (or `cc`), `loop` (Warren's β), `doo-sabin` (or `ds`); `_` for `-`, any case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().replace('_', "-").as_str() {
            "catmull-clark" | "cc" => Ok(FairScheme::CatmullClark),
            "loop" => Ok(FairScheme::Loop(LoopBeta::default())),
            "doo-sabin" | "ds" => Ok(FairScheme::DooSabin),
            _ => Err(InterpError::invalid(
                Parameter::Scheme,
                format!("unknown scheme '{s}' (expected catmull-clark, loop or doo-sabin)"),
            )),
        }
    }
}

/// Options of [`interpolate`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct FairOptions {
    /// Subset, tolerance (the bound on the measured error), iteration cap
    /// of the minimisation (`solver` is read at refine 0 only, by the exact
    /// method that runs there).
    pub common: CommonOptions,
    /// The control mesh's scheme.
    pub scheme: FairScheme,
    /// K: the control mesh is the input refined K times (0 ≤ K ≤ [`MAX_REFINE`];
    /// Doo-Sabin ≤ 1).
    pub refine: usize,
    /// w of (3) in the module docs: `None` (default) for exact constraints;
    /// `Some(w)`, w > 0, for the penalty trade-off, whose result does not
    /// interpolate.
    pub fairness_weight: Option<f64>,
}

impl Default for FairOptions {
    fn default() -> Self {
        Self {
            common: CommonOptions::default(),
            scheme: FairScheme::default(),
            refine: DEFAULT_REFINE,
            fairness_weight: None,
        }
    }
}

crate::options::common_setters!(FairOptions);

impl FairOptions {
    /// Sets the scheme.
    pub fn with_scheme(mut self, scheme: FairScheme) -> Self {
        self.scheme = scheme;
        self
    }

    /// Sets K, the refinements of the input that give the control mesh.
    pub fn with_refine(mut self, refine: usize) -> Self {
        self.refine = refine;
        self
    }

    /// Sets the fairness weight (`None`: exact constraints).
    pub fn with_fairness_weight(mut self, w: impl Into<Option<f64>>) -> Self {
        self.fairness_weight = w.into();
        self
    }

    fn validate(&self) -> Result<(), InterpError> {
        if self.refine > MAX_REFINE {
            return Err(InterpError::invalid(
                Parameter::Refine,
                format!(
                    "refine = {} exceeds {MAX_REFINE} (each level multiplies the unknowns by about 4)",
                    self.refine
                ),
            ));
        }
        if self.scheme == FairScheme::DooSabin && self.refine > 1 {
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
    if let FairScheme::Loop(_) = opts.scheme {
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
    result.parameters.scheme = Some(opts.scheme.name().to_string());
    Ok(result)
}

/// Refine 0 with exact constraints: the exact method of the scheme.
fn exact_method(mesh: &Mesh, interpolated: Vec<bool>, opts: &FairOptions) -> Result<Interpolant, InterpError> {
    let common = opts.common.clone();
    match opts.scheme {
        FairScheme::CatmullClark => {
            cheng::interpolate_prepared(mesh, interpolated, &ChengOptions::default().with_common(common))
        }
        FairScheme::DooSabin => {
            nasri::interpolate_prepared(mesh, interpolated, &NasriOptions::default().with_common(common))
        }
        FairScheme::Loop(beta) => {
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
                ControlScheme::Loop(beta),
                &common,
                Solver::Cg { jacobi: true },
                Vec::new(),
            )
        }
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
    let options = opts.common.surface.for_scheme(opts.scheme.scheme());
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
    // T: the limit stencil of M^K with its tags (the rows the error check evaluates).
    let limit_plan = SubdivisionPlan::with_tags(tk, refined.tags(), options, 0)?;
    let limit = limit_plan.limit_stencil().expect("the fair schemes have limit masks")?;
    let sharp_k = limit_plan.sharpness().clone();
    drop(limit_plan);
    // The constraints and the association of the input vertices.
    let (constraints, association) = constraints(mesh, &interpolated, &limit, opts, k)?;
    // B = Δ·T: the Laplacian of the limit points.
    let delta = energy::umbrella(tk, &sharp_k);
    let b = &delta * &limit;
    drop(delta);
    let scale = 4f64.powi(k as i32);
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
    if !summary.converged {
        warnings.push(format!(
            "the fairness minimisation stopped after {} iterations at relative residual {:.1e} (max_iter): the \
             surface is not the fairest of its kind{}",
            summary.iterations,
            summary.residual,
            if opts.fairness_weight.is_none() { ", but it interpolates" } else { "" }
        ));
    }
    let energy = scale * subdiv_stencil::apply(&b, &x).iter().map(|p| p.length_squared()).sum::<f64>();
    let d = mesh.bbox_diagonal();
    let solve_seconds = seconds_since(solve_start);
    let parameters = crate::Parameters {
        solver: Some(summary.solver.clone()),
        tol: Some(opts.common.tol),
        energy: Some(energy / (d * d)),
        ..Default::default()
    };
    let control = refined.with_positions(x);
    Ok(Interpolant {
        method: Method::Fair,
        control,
        scheme: opts.scheme.control_scheme(),
        surface_options: opts.common.surface,
        interpolated,
        association,
        solve: Some(summary),
        setup_seconds,
        solve_seconds,
        warnings,
        parameters,
        measured_error: None,
    })
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
    if opts.scheme == FairScheme::DooSabin && k == 1 {
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
    b: &SparseMatrix,
    x0: Vec<DVec3>,
    max_iter: usize,
    mesh: &Mesh,
) -> Result<(Vec<DVec3>, SolveSummary), InterpError> {
    let m = x0.len();
    // How many constraint rows use each column.
    let mut uses = vec![0u32; m];
    for (cols, _) in &c.rows {
        for &j in cols {
            uses[j as usize] += 1;
        }
    }
    const NO_PIVOT: u32 = u32::MAX;
    let mut pivot_of_column = vec![NO_PIVOT; m]; // the row whose pivot a column is
    let mut pivots = Vec::with_capacity(c.rows.len());
    for (i, (cols, w)) in c.rows.iter().enumerate() {
        let best = cols
            .iter()
            .zip(w)
            .filter(|(&j, &a)| uses[j as usize] == 1 && a != 0.0)
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .map(|(&j, &a)| (j, a));
        let Some((j, a)) = best else {
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
        pivot_of_column[j as usize] = i as u32;
        pivots.push((j, a));
    }
    // Free columns, numbered.
    let mut free_index = vec![u32::MAX; m];
    let mut free = Vec::with_capacity(m - pivots.len());
    for j in 0..m {
        if pivot_of_column[j] == NO_PIVOT {
            free_index[j] = free.len() as u32;
            free.push(j);
        }
    }
    let nf = free.len();
    // X = E·y + c.
    let mut e = TriMatI::<f64, u32>::with_capacity((m, nf), m + 8 * pivots.len());
    let mut shift = vec![DVec3::ZERO; m];
    for (k, &j) in free.iter().enumerate() {
        e.add_triplet(j, k, 1.0);
    }
    for (i, ((cols, w), &(p, ap))) in c.rows.iter().zip(&pivots).enumerate() {
        for (&j, &a) in cols.iter().zip(w) {
            if j != p {
                e.add_triplet(p as usize, free_index[j as usize] as usize, -a / ap);
            }
        }
        shift[p as usize] = c.data[i] / ap;
    }
    let e: SparseMatrix = e.to_csr();
    let g = b * &e;
    drop(e);
    let gt: SparseMatrix = g.transpose_view().to_csr();
    let g0 = subdiv_stencil::apply(b, &shift);
    let rhs: Vec<DVec3> = subdiv_stencil::apply(&gt, &g0).into_iter().map(|v| -v).collect();
    let diag = column_squares(&g, nf);
    let y0: Vec<DVec3> = free.iter().map(|&j| x0[j]).collect();
    let run =
        solve::pcg(|y| subdiv_stencil::apply(&gt, &subdiv_stencil::apply(&g, y)), &diag, &rhs, y0, FAIR_RTOL, max_iter);
    // X: the free points, then each pivot from its row (exact elimination).
    let mut x = vec![DVec3::ZERO; m];
    for (k, &j) in free.iter().enumerate() {
        x[j] = run.x[k];
    }
    for (i, ((cols, w), &(p, ap))) in c.rows.iter().zip(&pivots).enumerate() {
        let others: DVec3 = cols.iter().zip(w).filter(|(&j, _)| j != p).map(|(&j, &a)| a * x[j as usize]).sum();
        x[p as usize] = (c.data[i] - others) / ap;
    }
    Ok((x, summary_of("fair-cg", &run)))
}

/// (3) of the module docs: CG on AᵀA + s·BᵀB from `x0`.
fn minimise_penalty(
    c: &Constraints,
    b: &SparseMatrix,
    s: f64,
    x0: Vec<DVec3>,
    max_iter: usize,
) -> (Vec<DVec3>, SolveSummary) {
    let m = x0.len();
    let a = c.matrix(m);
    let at: SparseMatrix = a.transpose_view().to_csr();
    let bt: SparseMatrix = b.transpose_view().to_csr();
    let rhs = subdiv_stencil::apply(&at, &c.data);
    let diag: Vec<f64> = column_squares(&a, m).iter().zip(column_squares(b, m)).map(|(da, db)| da + s * db).collect();
    let apply = |x: &[DVec3]| -> Vec<DVec3> {
        let ax = subdiv_stencil::apply(&at, &subdiv_stencil::apply(&a, x));
        let bx = subdiv_stencil::apply(&bt, &subdiv_stencil::apply(b, x));
        ax.iter().zip(&bx).map(|(u, v)| *u + s * *v).collect()
    };
    let run = solve::pcg(apply, &diag, &rhs, x0, FAIR_RTOL, max_iter);
    let summary = summary_of("fair-penalty-cg", &run);
    (run.x, summary)
}

/// Σ_i G_ij² per column j.
fn column_squares(g: &SparseMatrix, cols: usize) -> Vec<f64> {
    let mut out = vec![0.0; cols];
    for (&j, &v) in g.indices().iter().zip(g.data()) {
        out[j as usize] += v * v;
    }
    out
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
