//! Deng & Ma 2011: an interpolatory subdivision scheme derived from
//! Doo-Sabin (report §3.3-3.4, with [corrections D2, D4, D5]), on closed and open
//! meshes.
//!
//! Nothing is solved: the scheme itself keeps every old vertex, so its limit
//! surface passes through the input's vertices. The "control mesh" of the
//! result is the input mesh, and [`Interpolant::surface`] refines it with
//! the Deng-Ma step (`subdiv_stencil::deng_ma`); input vertex i is vertex i
//! of the surface at every level, bit for bit.
//!
//! # Algorithm (one step, §3.3)
//! 1. At every old vertex P: its Doo-Sabin images Qᵢ (one per face), their
//!    centroid G, and the moved images Q̄ᵢ = P + ω_P(Qᵢ − G) ([correction D2]: the
//!    printed "Pᵢ +" is P). Their centroid is P.
//! 2. New face point: mean of the moved images of the face's corners; new
//!    edge point: mean of the four moved images of the edge's E-face; old
//!    vertices stay. Connectivity as Catmull-Clark.
//! 3. Tension: one global ω ∈ (0, 1] (ω = 1 is the surface analogue of the
//!    classical 4-point scheme, [correction D4]) or the displacement-safe variable
//!    ω_P of §3.4 with its shape parameter λ ∈ (0, 1] ([correction D5]).
//!
//! # Deviations from the report
//! - **Open meshes** (the report has closed meshes only; our construction,
//!   derived in `subdiv_rules::deng_ma`, "Open meshes"): every boundary loop,
//!   cut into pieces at its corners (boundary vertices in one face), is
//!   refined by the 4-point curve rule with tension ω_P/16 and the linear
//!   phantom 2P₀ − P₁ beyond a corner, so the boundary of the surface is the
//!   4-point curve of the boundary polygon and depends on boundary vertices
//!   only; the moved images of a boundary vertex are taken about the curve's
//!   centre (P₋ + 6P + P₊)/8 (P at a corner) instead of the centroid of its
//!   images. On a regular quad grid this is the report's rule on the grid
//!   extended by linearly extrapolated ghosts. With the variable tension a
//!   boundary vertex's curve tension is §3.4 on the boundary polygon, and its
//!   moved images take the smaller of that and §3.4 over its faces.
//! - The variable tension is nonlinear in the positions; the surface is then
//!   computed geometrically level by level instead of by a stencil.
//! - Creases and corners (beyond the report): the input's infinitely sharp
//!   tags are kept by the control mesh (the input) and refined with the
//!   surface: every crease polygon is refined by the 4-point curve rule, as
//!   the boundary (`subdiv_stencil::deng_ma`, "Creases and corners"), so the
//!   surface passes through the data and is creased along the 4-point curve
//!   of each crease polygon. Semi-sharp values are refused. The texture
//!   coordinates of the surface follow Catmull-Clark's face-varying rules
//!   on the same split (`subdiv_stencil::fvar`).
//!
//! ```
//! use subdiv_interp::{deng_ma, DengMaOptions};
//! use subdiv_mesh::shapes;
//! let cube = shapes::cube();
//! let result = deng_ma::interpolate(&cube, &DengMaOptions::default()).unwrap();
//! let surface = result.surface(3).unwrap();
//! assert_eq!(&surface.positions()[..8], cube.positions());
//!
//! // An open grid: the input vertices stay, and so does the planar boundary.
//! let grid = shapes::quad_grid(4, 3);
//! let surface = deng_ma::interpolate(&grid, &DengMaOptions::default()).unwrap().surface(2).unwrap();
//! assert_eq!(&surface.positions()[..20], grid.positions());
//! assert!(surface.positions().iter().all(|p| p.z == 0.0));
//! ```
//!
//! [corrections D2, D4, D5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d2
//! [correction D2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d2
//! [correction D4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d4
//! [correction D5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d5

use crate::{InterpError, Interpolant, LimitAssociation, Method, Parameter};
use subdiv_mesh::Mesh;
use subdiv_stencil::Tension;

/// Options of [`interpolate`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct DengMaOptions {
    /// Global ω ∈ (0, 1] (default 1) or the variable ω_P with λ ∈ (0, 1].
    pub tension: Tension,
    /// The surface options (the face-varying mode of the surface's UVs;
    /// Deng-Ma has its own boundary rule and no semi-sharp creases).
    pub surface: crate::SurfaceOptions,
}

impl DengMaOptions {
    /// Sets the tension.
    pub fn with_tension(mut self, tension: Tension) -> Self {
        self.tension = tension;
        self
    }

    /// Sets the surface options.
    pub fn with_surface(mut self, surface: crate::SurfaceOptions) -> Self {
        self.surface = surface;
        self
    }
}

/// Checks that `tension`'s parameter lies in (0, 1].
fn validate(tension: Tension) -> Result<(), InterpError> {
    let (name, value) = match tension {
        Tension::Global(omega) => ("ω", omega),
        Tension::Variable { lambda } => ("λ", lambda),
    };
    if value > 0.0 && value <= 1.0 {
        Ok(())
    } else {
        Err(InterpError::invalid(Parameter::Tension, format!("Deng-Ma tension {name} = {value} is outside (0, 1]")))
    }
}

/// Sets up the Deng-Ma scheme on `mesh` (closed or open): the result's
/// control mesh is `mesh` itself, its scheme Deng-Ma with the given tension,
/// and its association [`LimitAssociation::Interpolatory`].
///
/// The numeric rule ([`crate`] docs) applies with an error bound of 0: the
/// control mesh is the input, bit for bit (nothing is scaled), and the error
/// is measured all the same. Isolated vertices are left out with a warning,
/// as in every method. [`Interpolant::surface`] refines on normalised
/// positions and refuses a surface that leaves the range of f64.
///
/// # Errors
/// [`InterpError::InvalidParameter`] for ω or λ outside (0, 1];
/// [`InterpError::CoincidentVertices`] and [`InterpError::NotRepresentable`]
/// for data without a finite, non-zero bounding-box diagonal;
/// [`InterpError::Stencil`] with `StencilError::SemiSharpDengMa` for a
/// semi-sharp tag (Deng-Ma's creases and corners are infinitely sharp).
pub fn interpolate(mesh: &Mesh, opts: &DengMaOptions) -> Result<Interpolant, InterpError> {
    validate(opts.tension)?;
    subdiv_stencil::deng_ma::check_sharpness(mesh.topology(), &opts.surface.sharpness(mesh.tags()))?;
    // Nothing is computed from the positions: the method sees them unscaled.
    let prepared = crate::numeric::prepare(Method::DengMa, mesh, None)?.unscaled();
    let parameters = match opts.tension {
        Tension::Global(omega) => crate::Parameters { omega: Some(omega), ..Default::default() },
        Tension::Variable { lambda } => {
            crate::Parameters { lambda: Some(crate::report::Lambda::Uniform(lambda)), ..Default::default() }
        }
    };
    let result = Interpolant {
        surface_options: opts.surface,
        method: Method::DengMa,
        control: mesh.clone(),
        scheme: subdiv_stencil::Scheme::DengMa(opts.tension),
        interpolated: prepared.interpolated.clone(),
        association: LimitAssociation::Interpolatory,
        solve: None,
        setup_seconds: 0.0,
        solve_seconds: 0.0,
        warnings: Vec::new(),
        parameters,
        measured_error: None,
    };
    prepared.finish(result)
}
