//! The interpolating subdivision methods of the papers in [docs/REFERENCES.md].
//!
//! Each method takes a mesh whose vertices are the data P, the set of
//! vertices to interpolate (default all) and its options, and returns an
//! [`Interpolant`]: a **control mesh** whose plain-scheme limit surface
//! passes through the data, plus diagnostics.
//!
//! | module | paper | control mesh, plain scheme |
//! |---|---|---|
//! | [`nasri`] | Nasri 1987 (via Zheng-Cai §2) | M⁰, Doo-Sabin; solve C·M⁰ = P |
//! | [`zheng_cai`] | Zheng & Cai 2005 | perturbed first refined mesh M¹, Doo-Sabin |
//! | [`cheng`] | Cheng et al. | M̂, Catmull-Clark (or Loop, √3: [`ChengOptions::with_scheme`]); A·M̂ = P |
//! | [`fan_cheng_lai`] | Fan, Cheng & Lai | phase-one(M̂, λ), Doo-Sabin |
//! | [`deng_wang`] | Deng & Wang 2010 | M¹ after a modified first step, Loop |
//! | [`deng_ma`] | Deng & Ma 2011 | none: the scheme interpolates |
//! | [`fair`] | after Halstead, Kass & DeRose 1993 | M^K (input refined K times), Catmull-Clark, Loop or Doo-Sabin; least thin-plate energy subject to interpolation |
//!
//! The error of a result is measured from the control mesh by the scheme's
//! own rules with the control mesh's tags ([`Interpolant::error`]), never
//! from the solver's residual.
//!
//! **Sharp features and UVs** (beyond every paper). Every method honours the
//! creases and corners of its input ([`subdiv_mesh::Mesh::tags`]) under the
//! surface options of [`CommonOptions::surface`] ([`SurfaceOptions`]:
//! OpenSubdiv's boundary option, crease method and face-varying mode): its
//! control mesh, written with its tags, has the data as limit points of
//! *that* surface (which any OpenSubdiv-based tool reproduces). The solved
//! methods use the limit matrices with crease, corner and composed rows
//! (`subdiv_stencil::limit_matrix`), solved block by block — corners, crease
//! polygons, interior; Deng-Wang solves its first step against the tagged
//! Loop limit of M¹; Deng-Ma refines crease polygons by its 4-point rule.
//! Doo-Sabin and Deng-Ma take infinitely sharp tags only (semi-sharp values
//! are a typed refusal). The control mesh keeps the input's texture
//! coordinates (refined by one level where it is a first refined mesh), and
//! [`Interpolant::surface`] refines them with the surface.
//!
//! **The numeric rule.** Every method computes on the data scaled by an exact
//! power of two and maps its result back, and returns it only if every
//! coordinate is a finite f64 and the measured error over
//! [`Interpolant::interpolated`] is within the tolerance; otherwise a typed
//! error ([`InterpError::NotRepresentable`], [`InterpError::CoincidentVertices`],
//! [`InterpError::ToleranceNotMet`]). Isolated vertices have no limit point:
//! every method leaves them out with a warning.
//!
//! ```
//! use subdiv_interp::{cheng, ChengOptions};
//! use subdiv_mesh::shapes;
//! let torus = shapes::torus(12, 8);
//! let result = cheng::interpolate(&torus, &ChengOptions::default()).unwrap();
//! let err = result.error(torus.positions(), &result.interpolated, torus.bbox_diagonal());
//! assert!(err.max_rel <= 1e-6);
//! ```
//!
//! [docs/REFERENCES.md]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md
#![warn(missing_docs)]

pub mod cheng;
pub mod deng_ma;
pub mod deng_wang;
mod error;
pub mod fair;
pub mod fan_cheng_lai;
pub mod first_step;
mod interpolant;
pub mod matrices;
mod method;
pub mod nasri;
mod numeric;
mod options;
pub mod params;
pub mod preconditions;
pub mod report;
mod system;
pub mod verify;
pub mod zheng_cai;

pub use cheng::ChengOptions;
pub use deng_ma::DengMaOptions;
pub use deng_wang::DengWangOptions;
pub use error::{InterpError, Parameter};
pub use fair::{FairAlgorithm, FairOptions};
pub use fan_cheng_lai::{FanChengLaiOptions, Shape};
pub use first_step::CornerRule;
pub use interpolant::{ErrorStats, Interpolant, LimitAssociation, SolveSummary};
pub use matrices::{
    catmull_clark_degeneracy, limit_matrix_nasri, limit_matrix_two_phase, limit_matrix_zheng_cai, solve_blocks,
    Degeneracy, SolveBlocks,
};
pub use method::{interpolate, Method, MethodOptions, UnknownMethod};
pub use nasri::NasriOptions;
pub use options::{CommonOptions, SolverChoice, SurfaceOptions, DEFAULT_MAX_ITER, DEFAULT_TOL};
pub use params::ParamFileError;
pub use preconditions::accepting_methods;
pub use report::{Parameters, Report, TagCounts};
pub use zheng_cai::ZhengCaiOptions;

/// The types of the lower crates this crate's API mentions, so that one
/// dependency suffices: meshes, solvers and their errors, scheme options.
pub use subdiv_mesh::{DVec3, Mesh, MeshError};
pub use subdiv_solve::{IterationObserver, SolveError, Solver};
pub use subdiv_stencil::{
    BoundaryInterpolation, CreaseMethod, DartLimit, FVarInterpolation, LoopBeta, Options, Scheme, StencilError,
    Tension, TriangleRule,
};

/// Seconds elapsed since `start`.
pub(crate) fn seconds_since(start: std::time::Instant) -> f64 {
    start.elapsed().as_secs_f64()
}
