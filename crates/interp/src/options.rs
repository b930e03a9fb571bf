//! Options shared by the methods.

use crate::{InterpError, Parameter};
use subdiv_solve::{IterationObserver, Solver};
use subdiv_stencil::{
    BoundaryInterpolation, CreaseMethod, DartLimit, FVarInterpolation, Options, Scheme, TriangleRule,
};

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
/// and on the surface. `dart_limit` says which limit point the Catmull-Clark
/// and Loop limit rows give a dart (infinitely sharp crease ending inside):
/// its exact limit by default, so the surface itself passes through the
/// data there; [`DartLimit::SmoothMask`] interpolates under OpenSubdiv's
/// `Far::PrimvarRefiner::Limit` instead (the control mesh OpenSubdiv's limit
/// stencils map onto the data).
///
/// `#[non_exhaustive]`: build it with `Default` and the `with_*` setters, so
/// that a new option is not a breaking change.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SurfaceOptions {
    /// How boundary vertices are treated.
    pub boundary: BoundaryInterpolation,
    /// How semi-sharp creases decay.
    pub crease_method: CreaseMethod,
    /// How face-varying data (UVs) is interpolated.
    pub fvar: FVarInterpolation,
    /// Catmull-Clark's rule for triangles (OpenSubdiv's `TriangleSubdivision`).
    pub triangle_rule: TriangleRule,
    /// Which limit point a dart gets.
    pub dart_limit: DartLimit,
}

impl SurfaceOptions {
    /// Sets Catmull-Clark's triangle rule.
    pub fn with_triangle_rule(mut self, triangle_rule: TriangleRule) -> Self {
        self.triangle_rule = triangle_rule;
        self
    }

    /// Sets the boundary option.
    pub fn with_boundary(mut self, boundary: BoundaryInterpolation) -> Self {
        self.boundary = boundary;
        self
    }

    /// Sets the crease method.
    pub fn with_crease_method(mut self, crease_method: CreaseMethod) -> Self {
        self.crease_method = crease_method;
        self
    }

    /// Sets the face-varying mode.
    pub fn with_fvar(mut self, fvar: FVarInterpolation) -> Self {
        self.fvar = fvar;
        self
    }

    /// Sets the dart limit.
    pub fn with_dart_limit(mut self, dart_limit: DartLimit) -> Self {
        self.dart_limit = dart_limit;
        self
    }

    /// The subdivision options of `scheme` with these surface options.
    pub fn for_scheme(self, scheme: Scheme) -> Options {
        Options::new(scheme)
            .with_boundary(self.boundary)
            .with_crease_method(self.crease_method)
            .with_fvar(self.fvar)
            .with_triangle_rule(self.triangle_rule)
            .with_dart_limit(self.dart_limit)
    }

    /// The per-level sharpness of `tags` under these options (boundary
    /// option, crease method, triangle rule, dart limit).
    pub fn sharpness(self, tags: &subdiv_mesh::Tags) -> subdiv_stencil::LevelSharpness {
        self.for_scheme(Scheme::CatmullClark).sharpness(tags)
    }
}

/// Options every method takes.
///
/// `#[non_exhaustive]`, like every options struct of the crate: build it with
/// `Default` and the `with_*` setters (each method's options also have the
/// setters of these fields), so that a new option is not a breaking change:
///
/// ```
/// use subdiv_interp::{ChengOptions, CommonOptions, SolverChoice};
/// let common = CommonOptions::default().with_tol(1e-9).with_solver(SolverChoice::Use(subdiv_interp::Solver::Ldl));
/// let cheng = ChengOptions::default().with_common(common.clone());
/// assert_eq!(cheng, ChengOptions::default().with_tol(1e-9).with_solver(common.solver));
/// ```
///
/// A struct literal does not compile outside the crate:
///
/// ```compile_fail
/// let common = subdiv_interp::CommonOptions {
///     subset: None,
///     tol: 1e-6,
///     max_iter: 100,
///     solver: subdiv_interp::SolverChoice::Auto,
///     observer: Default::default(),
///     surface: Default::default(),
/// };
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
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
    /// Sets the vertices to interpolate (`None`: all).
    pub fn with_subset(mut self, subset: impl Into<Option<Vec<u32>>>) -> Self {
        self.subset = subset.into();
        self
    }

    /// Sets the relative tolerance.
    pub fn with_tol(mut self, tol: f64) -> Self {
        self.tol = tol;
        self
    }

    /// Sets the iteration cap.
    pub fn with_max_iter(mut self, max_iter: usize) -> Self {
        self.max_iter = max_iter;
        self
    }

    /// Sets the solver.
    pub fn with_solver(mut self, solver: SolverChoice) -> Self {
        self.solver = solver;
        self
    }

    /// Sets the observer told every iterate's residual.
    pub fn with_observer(mut self, observer: IterationObserver) -> Self {
        self.observer = observer;
        self
    }

    /// Sets the surface options.
    pub fn with_surface(mut self, surface: SurfaceOptions) -> Self {
        self.surface = surface;
        self
    }

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

/// The setters of [`CommonOptions`]'s fields on a method's options struct
/// (whose `common` field holds them), plus `with_common`.
macro_rules! common_setters {
    ($($options:ty),* $(,)?) => {$(
        impl $options {
            /// Sets every shared option at once.
            pub fn with_common(mut self, common: $crate::CommonOptions) -> Self {
                self.common = common;
                self
            }

            /// Sets the vertices to interpolate (`None`: all).
            pub fn with_subset(mut self, subset: impl Into<Option<Vec<u32>>>) -> Self {
                self.common.subset = subset.into();
                self
            }

            /// Sets the relative tolerance.
            pub fn with_tol(mut self, tol: f64) -> Self {
                self.common.tol = tol;
                self
            }

            /// Sets the iteration cap.
            pub fn with_max_iter(mut self, max_iter: usize) -> Self {
                self.common.max_iter = max_iter;
                self
            }

            /// Sets the solver.
            pub fn with_solver(mut self, solver: $crate::SolverChoice) -> Self {
                self.common.solver = solver;
                self
            }

            /// Sets the observer told every iterate's residual.
            pub fn with_observer(mut self, observer: subdiv_solve::IterationObserver) -> Self {
                self.common.observer = observer;
                self
            }

            /// Sets the surface options.
            pub fn with_surface(mut self, surface: $crate::SurfaceOptions) -> Self {
                self.common.surface = surface;
                self
            }
        }
    )*};
}
pub(crate) use common_setters;
