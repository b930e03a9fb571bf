//! The crate's error type.

use subdiv_solve::SolveError;
use subdiv_stencil::StencilError;
use thiserror::Error;

/// Why an interpolation failed.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum InterpError {
    /// The method cannot take this mesh (Loop methods and non-triangles,
    /// closed-only methods and boundaries, Catmull-Clark's degenerate A).
    /// The message says why and which method works instead.
    #[error("{method} cannot interpolate this mesh: {reason}; try {suggestion}")]
    UnsupportedMesh {
        /// Method id.
        method: &'static str,
        /// What is wrong with the mesh for this method.
        reason: String,
        /// What works instead: the methods that take this mesh
        /// ([`crate::accepting_methods`]), or another option.
        suggestion: String,
    },
    /// A parameter is out of range or does not fit the mesh.
    #[error("invalid parameter: {0}")]
    InvalidParameter(String),
    /// The solver did not reach the tolerance, diverged, or met a singular or
    /// indefinite system; the source carries its diagnostics.
    #[error("{method}: {source}")]
    Solve {
        /// Method id.
        method: &'static str,
        /// The solver's error, with iterations and residual (boxed: it carries
        /// the last iterate).
        #[source]
        source: Box<SolveError>,
    },
    /// The system has no solution for these data (a singular matrix with data
    /// outside its range): the solver's diagnostics give the error reached.
    #[error("{method}: {reason}; {source}; try {suggestion}")]
    Unsolvable {
        /// Method id.
        method: &'static str,
        /// Why.
        reason: String,
        /// What works instead: the methods that take this mesh
        /// ([`crate::accepting_methods`]).
        suggestion: String,
        /// The solver's error, with the residual reached.
        #[source]
        source: Box<SolveError>,
    },
    /// An operator could not be built.
    #[error(transparent)]
    Stencil(#[from] StencilError),
}

impl InterpError {
    /// True when the failure is the solver not reaching its tolerance (exit 3 on
    /// the command line) rather than an unusable input (exit 2).
    pub fn is_not_converged(&self) -> bool {
        matches!(self, InterpError::Unsolvable { .. })
            || matches!(
                self,
                InterpError::Solve { source, .. }
                    if matches!(**source, SolveError::NotConverged { .. } | SolveError::Diverged { .. } | SolveError::Singular { .. })
            )
    }
}
