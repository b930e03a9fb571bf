//! Exact evaluation of a subdivision limit surface between the data points,
//! and what builds on it: sampling, closest-point projection and fitting a
//! control mesh to dense data.
//!
//! The limit surface of a control mesh is parameterised per *domain*
//! ([`Domain`]): a quad face of a Catmull-Clark mesh is one domain with
//! (u, v) ∈ \[0,1\]², corner 0 at (0,0), corner 1 at (1,0), corner 3 at
//! (0,1); an n-gon (n ≠ 4) is split as OpenSubdiv's ptex faces into n
//! sub-quads, domain `(face, K)` with (0,0) at corner K. A Loop triangle is
//! one domain with barycentric (u, v), corner 0 at (0,0), 1 at (1,0), 2 at
//! (0,1). Doo-Sabin: one domain per face corner, and two strip domains per
//! side of every boundary or crease edge that reach the sharp curve
//! (`doo_sabin` module docs, summarised in [`surface`]).
//!
//! Topology and geometry are separate, as everywhere in subdiv: a
//! [`LimitSurface`] is built once from the topology, tags and options;
//! evaluating needs the control positions, and [`LimitSurface::stencil`]
//! gives the limit point and derivatives at a parameter as weights on the
//! control points (what fitting solves for). [`LimitSurface::bind`] fixes
//! the positions for many fast evaluations ([`BoundSurface`], with second
//! derivatives for Newton steps).
//!
//! # How it is exact
//! Feature-adaptive refinement (Nießner et al. 2012, OpenSubdiv's
//! `Far::PatchTable`): each domain's face ring is refined with the
//! workspace's own [`subdiv_stencil::SubdivisionPlan`] (the schemes' rules
//! and tags, nothing re-derived) until the sub-domain holding the parameter
//! is a regular patch — bicubic B-spline (Catmull-Clark), quartic box spline
//! (Loop, Stam 1998), biquadratic B-spline (Doo-Sabin), with boundaries and
//! infinitely sharp creases as reflected phantom points, which is what the
//! crease rules are — and evaluated there. A table of these patches (each
//! point a sparse stencil on the control points) is built down to 2⁻⁸ of an
//! irregular vertex; deeper parameters are refined on demand, and at an
//! irregular vertex itself the position and tangents come from the dominant
//! eigenvectors of the local subdivision matrix (`patch_vertex` module docs:
//! the limit mask — at darts too, where it is the limit stencils' exact dart
//! mask, unless the options ask for OpenSubdiv's smooth-mask approximation,
//! `DartLimit::SmoothMask` — and tangent masks that equal the parametric
//! derivatives wherever those exist).
//!
//! Doo-Sabin is evaluated on closed and open meshes, with infinitely sharp
//! creases (the boundary rule on each side) and at interior vertices of
//! valence 2 (a folded quarter). Not done ([`EvalError::Unsupported`]):
//! Deng-Ma (interpolatory, no limit masks), Doo-Sabin corners (a corner
//! tag, or three or more boundary and crease edges at a vertex, as where a
//! crease meets the boundary) and darts (a crease ending inside the mesh).
//!
//! ```
//! use subdiv_eval::{LimitSurface, SurfaceParam};
//! use subdiv_mesh::shapes;
//! use subdiv_stencil::{Options, Scheme};
//!
//! let cube = shapes::cube();
//! let options = Options::new(Scheme::CatmullClark);
//! let surface = LimitSurface::new(&cube, &options).unwrap();
//! // The centre of face 0 is the limit of its level-1 face point.
//! let s = surface.evaluate(cube.positions(), SurfaceParam::new(0, 0, 0.5, 0.5)).unwrap();
//! let refined = subdiv_stencil::subdivide(&cube, options, 1, true).unwrap();
//! assert!((s.position - refined.positions()[8]).length() < 1e-12);
//! assert!((s.normal.length() - 1.0).abs() < 1e-12);
//! // The same point as weights on the control points.
//! let stencil = surface.stencil(SurfaceParam::new(0, 0, 0.5, 0.5)).unwrap();
//! assert!((stencil.position.iter().sum::<f64>() - 1.0).abs() < 1e-12);
//! // Many evaluations with fixed positions.
//! let bound = surface.bind(cube.positions()).unwrap();
//! let jet = bound.evaluate_jet(SurfaceParam::new(0, 0, 0.25, 0.75)).unwrap();
//! assert!(jet.duu.is_finite());
//! ```
//!
//! # Sampling, projection, fitting
//! On top of the evaluator, over plain slices and vectors:
//! [`sample_per_domain`] and [`sample_by_area`] ([`mod@sample`]: points with
//! normals); [`Projector`] and [`project_points`] ([`mod@project`]: closest
//! points, a BVH over conservative patch bounds and a projected Newton
//! iteration); [`fit()`] ([`mod@fit`]: control points moved so that the limit
//! surface fits a mesh or point cloud, foot points re-projected every round,
//! distances both ways per round); [`bvh`] (the boxes, and nearest points on
//! a triangle mesh or cloud).
//!
//! ```
//! use subdiv_eval::{fit, project_points, FitOptions, FitTarget, ProjectOptions};
//! use subdiv_mesh::{shapes, DVec3};
//! use subdiv_stencil::{Options, Scheme};
//!
//! let cube = shapes::cube();
//! let options = Options::new(Scheme::CatmullClark);
//! // Limit points of the level-2 mesh lie on the surface: they project onto it at distance 0.
//! let target = subdiv_stencil::subdivide(&cube, options, 2, true).unwrap();
//! let feet = project_points(&cube, &options, target.positions(), &ProjectOptions::default()).unwrap();
//! assert!(feet.iter().all(|f| f.distance < 1e-12));
//! // A dented copy of the cube fitted back to them.
//! let mut dented = cube.clone();
//! dented.positions_mut()[0] += DVec3::splat(0.05);
//! let fitted = fit(&FitTarget::from_mesh(&target), &dented, &FitOptions { surface: options, ..FitOptions::default() }).unwrap();
//! let last = fitted.iterations.last().unwrap();
//! assert!(last.max_target_to_surface < 1e-9 * last.scale);
//! ```
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

pub use fit::{fit, FitIteration, FitLoss, FitMethod, FitObserver, FitOptions, FitResult, FitStop, FitTarget};
pub use project::{project_on, project_points, DomainShape, PatchEvaluator, ProjectOptions, Projection, Projector};
pub use sample::{
    per_domain_count, sample_by_area, sample_per_domain, sample_surface, Sampling, SurfaceSample, SAMPLE_BYTES,
};
pub use surface::{BoundSurface, Domain, EvalError, EvalStencil, LimitJet, LimitSample, LimitSurface, SurfaceParam};
