//! The evaluation API (skeleton: the implementation is being written).

use glam::DVec3;
use subdiv_mesh::Mesh;
use subdiv_stencil::Options;

/// A parameter on the limit surface: a domain (`face`, and for a ptex-split
/// n-gon the sub-quad `corner` K; 0 otherwise) and (u, v) in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceParam {
    /// Face of the control mesh.
    pub face: u32,
    /// Sub-domain of the face (the corner K of an n-gon's ptex sub-quad); 0 for a single domain.
    pub corner: u32,
    /// First parameter.
    pub u: f64,
    /// Second parameter.
    pub v: f64,
}

/// One parametric domain of the surface: `(face, corner)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Domain {
    /// Face of the control mesh.
    pub face: u32,
    /// Sub-domain index within the face.
    pub corner: u32,
}

/// The limit surface and its first derivatives at one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitSample {
    /// Limit position.
    pub position: DVec3,
    /// ∂S/∂u.
    pub du: DVec3,
    /// ∂S/∂v.
    pub dv: DVec3,
    /// Unit normal, oriented like the faces.
    pub normal: DVec3,
}

/// A limit point and its derivatives as weights on the control points:
/// `position = Σ weights[i]·P[indices[i]]`, likewise `du`, `dv`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EvalStencil {
    /// Control vertices with a nonzero weight.
    pub indices: Vec<u32>,
    /// Weights of the position.
    pub position: Vec<f64>,
    /// Weights of ∂S/∂u.
    pub du: Vec<f64>,
    /// Weights of ∂S/∂v.
    pub dv: Vec<f64>,
}

/// Why a surface cannot be built or evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EvalError {
    /// A parameter names no domain of the mesh.
    #[error("no domain {face}.{corner} in this mesh")]
    NoSuchDomain {
        /// Face given.
        face: u32,
        /// Corner given.
        corner: u32,
    },
    /// A parameter outside its domain (or not finite).
    #[error("parameter ({u}, {v}) outside the domain of face {face}")]
    OutOfDomain {
        /// Face given.
        face: u32,
        /// u given.
        u: f64,
        /// v given.
        v: f64,
    },
    /// The surface has no domain (an empty mesh).
    #[error("the surface has no domain")]
    NoSurface,
    /// The scheme has no limit surface to evaluate here.
    #[error("{scheme}: {reason}")]
    Unsupported {
        /// Scheme name.
        scheme: &'static str,
        /// Why.
        reason: String,
    },
    /// The control mesh cannot be refined (from subdiv-stencil).
    #[error(transparent)]
    Stencil(#[from] subdiv_stencil::StencilError),
    /// Bad input data for sampling, projection or fitting.
    #[error("{what}")]
    InvalidInput {
        /// What is wrong, naming the offending element.
        what: String,
    },
    /// Fitting could not solve its least-squares system.
    #[error("fitting: {what}")]
    Solve {
        /// The solver's message.
        what: String,
    },
    /// Not implemented yet (skeleton).
    #[error("limit evaluation is not implemented yet")]
    Unimplemented,
}

/// The limit surface of a control mesh's topology, tags and options, ready
/// to evaluate (built once; positions are given per call).
#[derive(Clone, Debug)]
pub struct LimitSurface {
    vertex_count: usize,
}

impl LimitSurface {
    /// Builds the surface of `mesh`'s topology and tags under `options`.
    pub fn new(mesh: &Mesh, options: &Options) -> Result<Self, EvalError> {
        let _ = options;
        Ok(Self { vertex_count: mesh.positions().len() })
    }

    /// The control vertex count the positions passed in must have.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Every parametric domain, in face order.
    pub fn domains(&self) -> &[Domain] {
        &[]
    }

    /// The control vertices whose convex hull contains the limit patch of
    /// `domain` (for conservative bounds; `None` when the rules have
    /// negative weights and the hull property does not hold).
    pub fn domain_support(&self, domain: Domain) -> Option<&[u32]> {
        let _ = domain;
        None
    }

    /// Position, derivatives and normal at `param`.
    pub fn evaluate(&self, positions: &[DVec3], param: SurfaceParam) -> Result<LimitSample, EvalError> {
        let _ = (positions, param);
        Err(EvalError::Unimplemented)
    }

    /// The same as weights on the control points.
    pub fn stencil(&self, param: SurfaceParam) -> Result<EvalStencil, EvalError> {
        let _ = param;
        Err(EvalError::Unimplemented)
    }
}
