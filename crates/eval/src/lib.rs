//! Exact evaluation of a subdivision limit surface between the data points,
//! and what builds on it: sampling, closest-point projection and fitting a
//! control mesh to dense data.
//!
//! The limit surface of a control mesh is parameterised per *domain*: a quad
//! face of a Catmull-Clark mesh is one domain with (u, v) ∈ [0,1]², corner 0
//! at (0,0), corner 1 at (1,0), corner 3 at (0,1); an n-gon (n ≠ 4) is split
//! as OpenSubdiv's ptex faces into n sub-quads, domain `(face, K)` with (0,0)
//! at corner K. A Loop triangle is one domain with barycentric (u, v), corner
//! 0 at (0,0), 1 at (1,0), 2 at (0,1). Doo-Sabin: see [`surface`].
//!
//! Topology and geometry are separate, as everywhere in subdiv: a
//! [`LimitSurface`] is built once from the topology, tags and options;
//! evaluating needs the control positions, and [`LimitSurface::stencil`]
//! gives the limit point and derivatives at a parameter as weights on the
//! control points (what fitting solves for).
#![warn(missing_docs)]

mod catmull_clark;
mod doo_sabin;
mod local;
mod loop_scheme;
mod patch;
mod patch_vertex;
pub mod surface;

pub mod bvh;
pub mod fit;
pub mod project;
pub mod sample;

pub use fit::{fit, FitIteration, FitOptions, FitResult, FitTarget};
pub use project::{project_points, DomainShape, PatchEvaluator, ProjectOptions, Projection, Projector};
pub use sample::{sample_by_area, sample_per_domain, SurfaceSample};
pub use surface::{BoundSurface, Domain, EvalError, EvalStencil, LimitJet, LimitSample, LimitSurface, SurfaceParam};
