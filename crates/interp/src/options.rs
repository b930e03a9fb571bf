//! Options shared by the methods.

use crate::{InterpError, Parameter};
use subdiv_solve::{IterationObserver, Solver};

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
}

impl Default for CommonOptions {
    fn default() -> Self {
        Self {
            subset: None,
            tol: DEFAULT_TOL,
            max_iter: DEFAULT_MAX_ITER,
            solver: SolverChoice::Auto,
            observer: IterationObserver::default(),
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
