//! Options shared by the methods.

use crate::{InterpError, Parameter};
use subdiv_solve::{IterationObserver, Solver};
use subdiv_stencil::{BoundaryInterpolation, CreaseMethod, FVarInterpolation, Options, Scheme};

/// Default tolerance: max over interpolated vertices of |P − AX| / d.
pub const DEFAULT_TOL: f64 = 1e-6;
/// Default iteration cap of the iterative solvers.
pub const DEFAULT_MAX_ITER: usize = 10_000;

/// Which solver a method uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SolverChoice {
    /// The method's default: the fastest solver that is robust for its matrix.
    #[default]
    Auto,
    /// This solver.
    Use(Solver),
}

/// The surface options of the control mesh's scheme (OpenSubdiv's, as
/// `subdiv subdivide` takes them), which every method honours together with
/// the tags of its input mesh ([`subdiv_mesh::Mesh::tags`]): the limit
/// surface the method makes pass through the data is the one of its control
/// mesh *with these options and the control mesh's tags*. Defaults: as
/// OpenSubdiv's Far tools (`edge-and-corner`, uniform, `linear-all`).
///
/// The boundary option and the crease method apply to the Catmull-Clark and
/// Loop methods (`cheng`, `deng-wang`); Doo-Sabin and Deng-Ma have one
/// boundary rule of their own and infinitely sharp tags only, which never
/// decay. `fvar` says how the input's texture coordinates are refined where
/// the control mesh is a refined mesh (Zheng-Cai, Fan-Cheng-Lai, Deng-Wang)
/// and on the surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SurfaceOptions {
    /// How boundary vertices are treated.
    pub boundary: BoundaryInterpolation,
    /// How semi-sharp creases decay.
    pub crease_method: CreaseMethod,
    /// How face-varying data (UVs) is interpolated.
    pub fvar: FVarInterpolation,
}

impl SurfaceOptions {
    /// The subdivision options of `scheme` with these surface options.
    pub fn for_scheme(self, scheme: Scheme) -> Options {
        Options::new(scheme).with_boundary(self.boundary).with_crease_method(self.crease_method).with_fvar(self.fvar)
    }

    /// The per-level sharpness of `tags` under these options (boundary
    /// option and crease method).
    pub fn sharpness(self, tags: &subdiv_mesh::Tags) -> subdiv_stencil::LevelSharpness {
        subdiv_stencil::LevelSharpness::new(tags, self.boundary, self.crease_method)
    }
}

/// Options every method takes.
#[derive(Clone, Debug, PartialEq)]
pub struct CommonOptions {
    /// Vertices to interpolate (default: all). The others follow each paper's
    /// rule for non-interpolated vertices (they keep their input position in
    /// the unknown mesh).
    pub subset: Option<Vec<u32>>,
    /// Relative tolerance (to the bounding-box diagonal d): of the solve, and
    /// the bound on the measured error every method's result must meet
    /// (finite and > 0).
    pub tol: f64,
    /// Iteration cap.
    pub max_iter: usize,
    /// Solver.
    pub solver: SolverChoice,
    /// Told every iterate's relative residual (progress bars); none by default.
    pub observer: IterationObserver,
    /// Boundary option, crease method and face-varying mode of the control
    /// mesh's surface.
    pub surface: SurfaceOptions,
}

impl Default for CommonOptions {
    fn default() -> Self {
        Self {
            subset: None,
            tol: DEFAULT_TOL,
            max_iter: DEFAULT_MAX_ITER,
            solver: SolverChoice::Auto,
            observer: IterationObserver::default(),
            surface: SurfaceOptions::default(),
        }
    }
}

impl CommonOptions {
    /// Per-vertex flag: interpolate this vertex? Out-of-range subset indices
    /// are an error naming the index; so is an empty subset.
    pub fn interpolated(&self, vertex_count: usize) -> Result<Vec<bool>, InterpError> {
        match &self.subset {
            None => Ok(vec![true; vertex_count]),
            Some(list) if list.is_empty() => {
                Err(InterpError::invalid(Parameter::Subset, "the subset is empty: there is nothing to interpolate"))
            }
            Some(list) => {
                let mut flags = vec![false; vertex_count];
                for &v in list {
                    let slot = flags.get_mut(v as usize).ok_or_else(|| {
                        InterpError::invalid(
                            Parameter::Subset,
                            format!("subset vertex {v} does not exist (the mesh has {vertex_count} vertices)"),
                        )
                    })?;
                    *slot = true;
                }
                Ok(flags)
            }
        }
    }
}
