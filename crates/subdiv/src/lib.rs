//! **subdiv**: smooth subdivision surfaces — Doo-Sabin, Catmull-Clark, Loop —
//! that *pass through* a polygon mesh's vertices (open or closed, any genus,
//! faces of any size, with creases, corners and UVs), by the six
//! interpolation methods of the literature; plus plain subdivision and limit
//! evaluation, matching OpenSubdiv.
//!
//! This crate is the one dependency a user needs: it re-exports the small
//! crates that do the work (lyon's pattern) and gathers what a program
//! usually touches in [`prelude`], with one error type ([`Error`]) that every
//! crate's error converts into.
//!
//! | module | crate | what |
//! |---|---|---|
//! | [`mesh`] | `subdiv-mesh` | [`Mesh`] (validated topology + positions, tags, UVs), procedural shapes, triangulation |
//! | [`io`] | `subdiv-io` | OBJ, OFF, PLY, STL, glTF/GLB reading and atomic writing |
//! | [`rules`] | `subdiv-rules` | the schemes' masks from local neighbourhoods |
//! | [`stencil`] | `subdiv-stencil` | [`subdivide()`], refinement and limit stencils, limit matrices |
//! | [`solve`] | `subdiv-solve` | the solvers of the limit systems |
//! | [`interp`] | `subdiv-interp` | the methods, [`interpolate`], the [`Report`] |
//!
//! Its own modules: [`info`], a mesh's statistics (`subdiv info`'s
//! [`info::Summary`]), and [`batch`], one command over many meshes in
//! parallel, resumable, one serde [`batch::Record`] per mesh (`subdiv
//! batch`, and what the Python package's `batch` and `dask.map_files` run).
//!
//! # Example
//!
//! A torus interpolated by Catmull-Clark (Cheng et al.), the error measured
//! independently of the solver, the limit surface two levels down.
//!
//! ```
//! use subdiv::prelude::*;
//!
//! # fn main() -> Result<(), subdiv::Error> {
//! let torus = subdiv::mesh::shapes::torus(12, 8);
//! let result = interpolate(&torus, &MethodOptions::new(Method::Cheng).with_tol(1e-9))?;
//! assert!(result.error_all(&torus).max_rel <= 1e-9);
//! let surface = result.surface(2)?; // the limit surface, two levels
//! assert_eq!(surface.topology().face_count(), 16 * torus.topology().face_count());
//! # Ok(())
//! # }
//! ```
//!
//! Files and arrays (the repository README's example, compiled here):
//!
//! ```no_run
//! use subdiv::prelude::*;
//!
//! fn main() -> Result<(), Error> {
//!     let mesh = load_mesh("fixtures/quad/spot_control_mesh.obj")?;
//!     let result = interpolate(&mesh, &MethodOptions::new(Method::Cheng).with_tol(1e-9))?;
//!     println!("{}", result.error_all(&mesh)); // measured by the scheme's limit rules, not the solver
//!     write_mesh("spot-surface.ply", &result.surface(3)?, &WriteOptions::default().with_normals(true))?;
//!     let report = Report::new(&mesh, &result, result.error_all(&mesh)); // what --report writes (serde)
//!     # let _ = report;
//!     let tetra = Mesh::from_arrays(&[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
//!                                   &[[0u32, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])?;
//!     let control: Vec<[f64; 3]> = interpolate(&tetra, &Method::DengWang.into())?.control.positions_to_arrays();
//!     # let _ = control;
//!     Ok(())
//! }
//! ```
//!
//! The complete consumer program — file → Cheng and Zheng-Cai → measured
//! error → two-level surface → PLY, then arrays → Deng-Wang → arrays — is
//! `examples/pipeline.rs`.
//!
//! # Stability
//!
//! Every options struct is `#[non_exhaustive]` with `Default` and `with_*`
//! setters, and every result struct is `#[non_exhaustive]`: adding an option
//! or a field is not a breaking change (struct literals of these types do
//! not compile outside their crate; build them with the setters).

pub use subdiv_job::{batch, budget, info};

pub use subdiv_eval as eval;
pub use subdiv_interp as interp;
pub use subdiv_io as io;
pub use subdiv_job as job;
pub use subdiv_mesh as mesh;
pub use subdiv_rules as rules;
pub use subdiv_solve as solve;
pub use subdiv_stencil as stencil;

pub use subdiv_interp::{
    interpolate, ErrorStats, InterpError, Interpolant, Method, MethodOptions, Report, SolverChoice, SurfaceOptions,
};
pub use subdiv_io::IoError;
pub use subdiv_mesh::{Mesh, MeshError};
pub use subdiv_solve::{SolveError, Solver};
pub use subdiv_stencil::{subdivide, Options, Scheme, StencilError};

/// What a program usually needs, in one `use subdiv::prelude::*`.
pub mod prelude {
    pub use crate::Error;
    pub use subdiv_interp::{
        interpolate, ChengOptions, CommonOptions, DengMaOptions, DengWangOptions, FanChengLaiOptions, Interpolant,
        Method, MethodOptions, NasriOptions, Report, Shape, SolverChoice, SurfaceOptions, ZhengCaiOptions,
    };
    pub use subdiv_io::{load_mesh, write_mesh, WriteOptions};
    pub use subdiv_mesh::{DVec3, Mesh};
    pub use subdiv_solve::Solver;
    pub use subdiv_stencil::{
        subdivide, BoundaryInterpolation, CreaseMethod, FVarInterpolation, LoopBeta, Options, Scheme, Tension,
    };
}

/// Any error of the subdiv crates, so that `?` works across them.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Reading or writing a file.
    #[error(transparent)]
    Io(#[from] IoError),
    /// An invalid mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Subdivision or an operator.
    #[error(transparent)]
    Stencil(#[from] StencilError),
    /// A solver.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// An interpolation method.
    #[error(transparent)]
    Interp(#[from] InterpError),
    /// A parameter file (normals, handles, subset, shape).
    #[error(transparent)]
    Params(#[from] subdiv_interp::ParamFileError),
    /// A batch that could not start ([`batch::run`]).
    #[error(transparent)]
    Batch(#[from] batch::BatchError),
    /// A job of the one pipeline ([`job::run`]): the command line's message and exit code.
    #[error(transparent)]
    Job(#[from] subdiv_job::JobError),
    /// A refinement larger than the memory budget (or than 32-bit ids).
    #[error(transparent)]
    Budget(#[from] budget::BudgetError),
}

impl Error {
    /// True when a solver stopped before its tolerance (the command line's
    /// exit 3); the other errors are about the input.
    pub fn is_not_converged(&self) -> bool {
        match self {
            Error::Interp(e) => e.is_not_converged(),
            Error::Solve(e) => matches!(e, SolveError::NotConverged { .. } | SolveError::Diverged { .. }),
            _ => false,
        }
    }
}

/// `Result` with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
