//! Test oracles and tuning constants, for this workspace's own tests,
//! doc-tests and benches (hidden from the documentation; always compiled, so
//! that the tests' build of this crate is the build every other command uses,
//! with no feature to tell them apart).
//!
//! **Not covered by semver**: anything here may change or go in any
//! release. Nothing in the solvers' contract depends on it.
//!
//! - [`model_problems`]: limit matrices with known spectra built without a
//!   mesh (the bicubic torus, the Loop grid, random SPD, indefinite and
//!   nonsymmetric matrices, Cheng's cube and pillow). Their constructors
//!   panic on arguments out of range: they are test fixtures, not API.
//! - [`tolerances`]: every tolerance, threshold and tuning constant the
//!   solvers read (the public defaults [`DEFAULT_TOL`](crate::DEFAULT_TOL),
//!   [`DEFAULT_MAX_ITER`](crate::DEFAULT_MAX_ITER) and
//!   [`DENSE_MAX_N`](crate::DENSE_MAX_N) are re-exported at the crate root).

pub mod model_problems;

/// Every tolerance, threshold and tuning constant of the crate, in one place
/// (pmp-library's `tolerances.h`). Solvers read these; none hard-codes a
/// number of its own. Each constant says what it guards and why it has its
/// value.
pub mod tolerances {
    pub use crate::tolerances::*;
}
