//! The crate's error type.

use std::fmt;
use subdiv_solve::SolveError;
use subdiv_stencil::StencilError;
use thiserror::Error;

/// The option an [`InterpError::InvalidParameter`] is about, so that a caller
/// can name where it came from (a command-line flag, a parameter file).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Parameter {
    /// The vertex subset ([`crate::CommonOptions::subset`]).
    Subset,
    /// The relative tolerance ([`crate::CommonOptions::tol`]).
    Tol,
    /// Zheng-Cai's EPS ([`crate::ZhengCaiOptions::eps`]).
    Eps,
    /// Prescribed normals (Zheng-Cai, Deng-Wang).
    Normals,
    /// Zheng-Cai's shape handles ([`crate::ZhengCaiOptions::handles`]).
    Handles,
    /// Fan-Cheng-Lai's shape parameters λ ([`crate::FanChengLaiOptions::shape`]).
    Shape,
    /// Deng-Wang's μ ([`crate::DengWangOptions::mu`]).
    Mu,
    /// Deng-Ma's tension ω or λ ([`crate::DengMaOptions::tension`]).
    Tension,
    /// The fair method's refinement count ([`crate::FairOptions::refine`]).
    Refine,
    /// The fair method's fairness weight ([`crate::FairOptions::fairness_weight`]).
    FairnessWeight,
    /// The control scheme of `cheng` and `fair` ([`crate::ChengOptions::scheme`],
    /// [`crate::FairOptions::scheme`]).
    Scheme,
}

impl Parameter {
    /// The option's name as the command line spells it (`subset`, `tol`,
    /// `eps`, `normals`, `handles`, `shape`, `mu`, `tension`, `refine`,
    /// `fairness-weight`, `scheme`).
    pub fn name(self) -> &'static str {
        match self {
            Parameter::Subset => "subset",
            Parameter::Tol => "tol",
            Parameter::Eps => "eps",
            Parameter::Normals => "normals",
            Parameter::Handles => "handles",
            Parameter::Shape => "shape",
            Parameter::Mu => "mu",
            Parameter::Tension => "tension",
            Parameter::Refine => "refine",
            Parameter::FairnessWeight => "fairness-weight",
            Parameter::Scheme => "scheme",
        }
    }
}

impl fmt::Display for Parameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

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
    #[error("invalid {parameter}: {reason}")]
    InvalidParameter {
        /// Which option.
        parameter: Parameter,
        /// What is wrong with it, naming the vertex or face.
        reason: String,
    },
    /// The data or the result do not fit in f64: the data's bounding-box
    /// diagonal d, or a coordinate of the control mesh or the surface, is
    /// beyond ±1.8e308 (or the input has a non-finite coordinate). The
    /// reason names the vertex and the magnitude.
    #[error("{method}: {reason}")]
    NotRepresentable {
        /// Method id.
        method: &'static str,
        /// What cannot be represented.
        reason: String,
    },
    /// Every vertex of the faces is the same point (d = 0): there is no
    /// surface, and no error relative to d.
    #[error(
        "{method}: all vertices of the mesh's faces are the same point (bounding-box diagonal 0): there is no surface \
         to interpolate"
    )]
    CoincidentVertices {
        /// Method id.
        method: &'static str,
    },
    /// The error measured from the result ([`crate::Interpolant::error`],
    /// [how the error is measured]) exceeds the tolerance or is NaN, although the method itself
    /// finished (round-off of extreme parameters, exact-by-construction
    /// methods included). Exit 3 on the command line.
    ///
    /// [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
    #[error("{method}: {}", tolerance_message(*max_rel, *tol))]
    ToleranceNotMet {
        /// Method id.
        method: &'static str,
        /// The measured max_i |L_i − P_i| / d (NaN when a limit point is not a number).
        max_rel: f64,
        /// The tolerance it had to meet.
        tol: f64,
    },
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

fn tolerance_message(max_rel: f64, tol: f64) -> String {
    if max_rel.is_nan() {
        format!("the measured interpolation error is NaN (a limit point is not a number); the tolerance is {tol:e}·d")
    } else {
        format!("the measured interpolation error {max_rel:.3e}·d exceeds the tolerance {tol:e}·d")
    }
}

impl InterpError {
    /// An invalid `parameter`, for `reason`.
    pub(crate) fn invalid(parameter: Parameter, reason: impl Into<String>) -> Self {
        InterpError::InvalidParameter { parameter, reason: reason.into() }
    }

    /// True when the failure is the result not reaching its tolerance — the
    /// solver's or the measured error's (exit 3 on the command line) — rather
    /// than an unusable input (exit 2).
    pub fn is_not_converged(&self) -> bool {
        matches!(self, InterpError::Unsolvable { .. } | InterpError::ToleranceNotMet { .. })
            || matches!(
                self,
                InterpError::Solve { source, .. }
                    if matches!(**source, SolveError::NotConverged { .. } | SolveError::Diverged { .. } | SolveError::Singular { .. })
            )
    }
}
