//! What every method returns, and the independent error measure ([how the error is measured]).
//!
//! [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured

use crate::numeric::max_nan;
use crate::{InterpError, Method, SurfaceOptions};
use glam::DVec3;
use std::borrow::Cow;
use subdiv_mesh::{Mesh, PowerOfTwoScale};
use subdiv_stencil::{
    doo_sabin, doo_sabin_limit_sites, subdivide_for_output, DualLimitSite, Options, Scheme, Split, StencilError,
};

/// Which point of the control mesh's limit surface belongs to input vertex i,
/// read off by the plain scheme's own rules (never by a method's system
/// matrix), with the control mesh's tags and the result's surface options.
#[derive(Clone, Debug, PartialEq)]
pub enum LimitAssociation {
    /// Control vertex i, moved to its limit position by the scheme's limit
    /// rules with the control mesh's tags (Catmull-Clark, Loop:
    /// [`subdiv_stencil::limit_points_with_options`], after the levels semi-sharp tags
    /// need; Doo-Sabin: `doo_sabin::limit_points_tagged` — the centroid of
    /// its V-face after one plain step, on a boundary or crease the sharp
    /// curve's point, a corner itself).
    ControlVertex,
    /// A Doo-Sabin first refined mesh M¹ (with its tags): where each input
    /// vertex's limit point sits in it ([`DualLimitSite`]: the centroid of
    /// its V-face for a smooth vertex or a dart — a Doo-Sabin limit point at
    /// every level —, the midpoint of its two sharp points on a boundary or
    /// a crease — Chaikin's, the quadratic B-spline's point —, the point that
    /// keeps a corner, the limit point of the edge between the two images of
    /// an interior valence-2 vertex), one entry per input vertex.
    DualSites(Vec<DualLimitSite>),
    /// The scheme interpolates: surface vertex i is input vertex i (Deng-Ma).
    Interpolatory,
}

/// The input's texture coordinates carried onto a control mesh that is the
/// first refined mesh `child` of `mesh` by `scheme` (Zheng-Cai's and
/// Fan-Cheng-Lai's M¹, Deng-Wang's): refined by one level with the
/// face-varying mode `fvar` and the level's sharpness `sharp`. `None` when
/// the mesh has none, or — with a warning saying why — when the scheme
/// cannot refine them (Doo-Sabin with seams or tags): the positions are what
/// interpolates, the texture coordinates are left out.
pub(crate) fn carry_uvs(
    mesh: &Mesh,
    sharp: &subdiv_stencil::LevelSharpness,
    child: &subdiv_mesh::Topology,
    scheme: Scheme,
    fvar: subdiv_stencil::FVarInterpolation,
    warnings: &mut Vec<String>,
) -> Option<subdiv_mesh::FaceVarying> {
    let channel = mesh.uvs()?;
    match subdiv_stencil::fvar::refine(mesh.topology(), sharp, child, scheme, fvar, channel) {
        Ok(refined) => Some(refined),
        Err(e) => {
            warnings.push(format!("the texture coordinates are not carried onto the control mesh: {e}"));
            None
        }
    }
}

impl LimitAssociation {
    /// The association of a Doo-Sabin first refined mesh M¹ with the
    /// infinitely sharp creases and corners of `tags`, `dual_split_tagged(t,
    /// tags)` with provenance `prov` (`subdiv_stencil::doo_sabin_limit_sites`).
    ///
    /// # Errors
    /// [`StencilError::SemiSharpDooSabin`] for a semi-sharp tag.
    pub fn for_sharp_dual_split(
        t: &subdiv_mesh::Topology,
        tags: &subdiv_mesh::Tags,
        prov: &subdiv_mesh::refine::SharpDualProvenance,
    ) -> Result<Self, StencilError> {
        Ok(LimitAssociation::DualSites(doo_sabin_limit_sites(t, tags, prov)?))
    }
}

/// How the solve went. `#[non_exhaustive]`: read its fields; the library
/// builds it.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct SolveSummary {
    /// Solver name.
    pub solver: String,
    /// Iterations (summed over the boundary and interior stages).
    pub iterations: usize,
    /// Sparse products.
    pub matvecs: usize,
    /// True when the tolerance was reached.
    pub converged: bool,
    /// Final max row residual / d of the solved system.
    pub residual: f64,
    /// Residual / d per iteration.
    pub history: Vec<f64>,
    /// LDLᵀ only: negative pivots (A indefinite).
    pub negative_pivots: Option<usize>,
}

/// Interpolation error relative to d ([how the error is measured]). A NaN distance makes the
/// maxima and means NaN: a point that is not a number is never skipped.
///
/// `#[non_exhaustive]`: read its fields; [`Interpolant::error`] builds it.
///
/// [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct ErrorStats {
    /// max_i |L_i − P_i| / d.
    pub max_rel: f64,
    /// mean_i |L_i − P_i| / d.
    pub mean_rel: f64,
    /// max_i |L_i − P_i|.
    pub max_abs: f64,
    /// mean_i |L_i − P_i|.
    pub mean_abs: f64,
    /// Number of vertices measured.
    pub count: usize,
}

/// The result of a method: a control mesh whose plain-scheme limit surface
/// interpolates the data, and how it was obtained.
///
/// `#[non_exhaustive]`: read its fields (and change them: the control mesh
/// is the caller's); the methods build it.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Interpolant {
    /// The method.
    pub method: Method,
    /// The control mesh (for Deng-Ma: the input mesh itself).
    pub control: Mesh,
    /// The plain scheme whose limit surface of the control mesh interpolates
    /// the data (Deng-Ma, interpolatory: the control mesh is the input and
    /// the scheme itself passes through it).
    pub scheme: Scheme,
    /// The surface options of the scheme (with the control mesh's tags,
    /// they define the surface): the method's, as it was asked.
    pub surface_options: SurfaceOptions,
    /// Per input vertex: interpolated? The subset (default every vertex)
    /// without the isolated vertices, which have no limit point (a warning
    /// says how many were left out). Measure the error over these
    /// ([`Self::error`]).
    pub interpolated: Vec<bool>,
    /// Where each input vertex's limit point lies.
    pub association: LimitAssociation,
    /// Solver diagnostics (`None` for explicit methods).
    pub solve: Option<SolveSummary>,
    /// Seconds spent building operators.
    pub setup_seconds: f64,
    /// Seconds spent solving / adjusting.
    pub solve_seconds: f64,
    /// Things the user should know (non-unique solution, …).
    pub warnings: Vec<String>,
    /// The method's parameters, for the report.
    pub parameters: crate::Parameters,
    /// [`Self::error`] of [`Self::interpolated`] as the method measured it
    /// on [`Self::control`] when it finished (its tolerance check): the
    /// same computation a caller would repeat on these positions, kept so
    /// that a caller writing them unchanged (a 64-bit format) need not
    /// repeat it. `None` until then; stale once the control positions are
    /// changed.
    pub measured_error: Option<ErrorStats>,
}

impl Interpolant {
    /// The subdivision options of the control mesh's surface: its scheme
    /// with [`Self::surface_options`].
    pub fn options(&self) -> Options {
        self.surface_options.for_scheme(self.scheme)
    }

    /// The limit point associated with every input vertex, computed from the
    /// control mesh by the plain scheme's rules ([how the error is measured]), on the control
    /// positions scaled by a power of two (exact) so that no sum overflows.
    /// NaN for a vertex without a limit point (isolated).
    ///
    /// [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
    pub fn limit_points(&self, input_vertices: usize) -> Vec<DVec3> {
        if let (LimitAssociation::ControlVertex, Split::Quad | Split::Triangle) =
            (&self.association, self.scheme.traits().split)
        {
            // `SubdivisionPlan::limit_points` scales by this same power of two
            // itself (and back): the same bits without a scaled copy of the mesh.
            return self.scaled_limit_points(PowerOfTwoScale::IDENTITY, input_vertices);
        }
        let scale = PowerOfTwoScale::normalizing(self.control.positions().iter().copied());
        let mut limits = self.scaled_limit_points(scale, input_vertices);
        scale.inverse().apply_points(&mut limits);
        limits
    }

    /// [`Self::limit_points`] of the control mesh scaled by `scale`, in the scaled space.
    fn scaled_limit_points(&self, scale: PowerOfTwoScale, input_vertices: usize) -> Vec<DVec3> {
        let c: Cow<Mesh> = if scale.is_identity() {
            Cow::Borrowed(&self.control)
        } else {
            Cow::Owned(self.control.with_positions(scale.scaled_points(self.control.positions())))
        };
        let t = c.topology();
        match (&self.association, self.scheme) {
            (LimitAssociation::Interpolatory, _) => c.positions()[..input_vertices].to_vec(),
            (LimitAssociation::DualSites(sites), _) => sites[..input_vertices]
                .iter()
                // Isolated: no face, no limit point.
                .map(|site| site.point(t, c.positions()).unwrap_or(DVec3::NAN))
                .collect(),
            (LimitAssociation::ControlVertex, scheme) => {
                // A control mesh the rules refuse (a method's bug) has no
                // limit points: NaN, which fails every error check.
                let refused = |_| vec![DVec3::NAN; t.vertex_count()];
                let mut all = match scheme.traits().split {
                    Split::Dual => doo_sabin::limit_points_tagged(t, c.tags(), c.positions()).unwrap_or_else(refused),
                    // An interpolatory scheme (no limit masks: `None`) is
                    // associated `Interpolatory`, never here.
                    Split::Quad | Split::Triangle | Split::Sqrt3 => {
                        match subdiv_stencil::limit_points_with_options(t, c.tags(), self.options(), c.positions()) {
                            Ok(limits) => limits.expect("the scheme has limit masks"),
                            Err(e) => refused(e),
                        }
                    }
                };
                all.truncate(input_vertices);
                all
            }
        }
    }

    /// Interpolation error of the vertices flagged in `interpolated` against
    /// `data` (usually [`Self::interpolated`]), relative to `d`. Computed on
    /// data and control scaled by one power of two (exact), so that neither
    /// the limit points nor the distances overflow or underflow; a NaN
    /// distance makes the statistics NaN.
    pub fn error(&self, data: &[DVec3], interpolated: &[bool], d: f64) -> ErrorStats {
        // Limit points in the original units, compared with the data as given:
        // scaling the data too would round coordinates far below the largest one
        // onto the subnormal grid, where a wrong limit point can look exact.
        let limits = self.limit_points(data.len());
        let mut stats = ErrorStats::default();
        let (mut max, mut sum) = (0.0_f64, 0.0_f64);
        // A non-manifold input's copies of a vertex are one data point: measured once.
        let welds = self.control.welds();
        let once = |v: usize| welds.is_none_or(|welds| welds.is_member(subdiv_mesh::VertexId(v as u32)));
        for (v, ((l, p), &on)) in limits.iter().zip(data).zip(interpolated).enumerate() {
            if on && once(v) {
                let e = subdiv_mesh::distance(*l, *p);
                max = max_nan(max, e);
                sum += e;
                stats.count += 1;
            }
        }
        let mean = if stats.count > 0 { sum / stats.count as f64 } else { 0.0 };
        (stats.max_abs, stats.mean_abs) = (max, mean);
        (stats.max_rel, stats.mean_rel) = (max / d, mean / d);
        stats
    }

    /// [`Self::error`] of every interpolated vertex ([`Self::interpolated`])
    /// of `input`, the mesh the method was given, relative to its
    /// bounding-box diagonal d.
    pub fn error_all(&self, input: &Mesh) -> ErrorStats {
        self.error(input.positions(), &self.interpolated, input.bbox_diagonal())
    }

    /// The surface: the control mesh refined `levels` times by its scheme
    /// with its tags and [`Self::options`], vertices moved to their limit
    /// positions where a mask exists; the control mesh's texture coordinates
    /// refined along with the face-varying mode of the options where the
    /// scheme refines them, left out where it does not (Doo-Sabin with seams
    /// or tags).
    ///
    /// # Errors
    /// [`InterpError::NotRepresentable`] when a coordinate of the surface is
    /// not a finite f64; [`InterpError::Stencil`] when the refined mesh would
    /// be too large.
    pub fn surface(&self, levels: usize) -> Result<Mesh, InterpError> {
        let options = self.options();
        let surface = subdivide_for_output(&self.control, options, levels, true, |_| {});
        surface.map(|s| s.mesh).map_err(|e| match e {
            StencilError::NotRepresentable { reason, .. } => {
                InterpError::NotRepresentable { method: self.method.name(), reason }
            }
            e => e.into(),
        })
    }
}

impl std::fmt::Display for ErrorStats {
    /// `max 1.234e-9·d, mean 5.678e-10·d over N vertices`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "max {:.3e}·d, mean {:.3e}·d over {} vertices", self.max_rel, self.mean_rel, self.count)
    }
}

impl std::fmt::Display for SolveSummary {
    /// `cg-jacobi: converged in 12 iterations (24 products), residual 1.0e-9·d`
    /// (`… stopped after …` when it did not converge; `, N negative pivots`
    /// for an indefinite LDLᵀ).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let how = if self.converged { "converged in" } else { "stopped after" };
        write!(
            f,
            "{}: {how} {} iterations ({} products), residual {:.1e}·d",
            self.solver, self.iterations, self.matvecs, self.residual
        )?;
        match self.negative_pivots {
            Some(k) if k > 0 => write!(f, ", {k} negative pivots"),
            _ => Ok(()),
        }
    }
}
