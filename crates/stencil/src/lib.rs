//! Sparse subdivision operators built from topology alone.
//!
//! Every scheme is split into **topology refinement** — computed once per
//! level: the refined [`Topology`] and a sparse stencil matrix R with
//! P_{k+1} = R·P_k — and **geometry**, one sparse product ([`apply`]) over any
//! per-vertex data. Positions never enter a stencil (the one exception,
//! Deng-Ma's variable tension, is a documented geometric step in [`deng_ma`]).
//!
//! | module | operator |
//! |---|---|
//! | [`catmull_clark`] | refinement R and limit stencil (OpenSubdiv `EDGE_AND_CORNER` boundaries) |
//! | [`loop_subdivision`] | refinement R and limit stencil, Warren's or Loop's β |
//! | [`doo_sabin`] | refinement R of a step with any corner mask (the standard Eq. 1, or a first step's), Chaikin boundary |
//! | [`sqrt3`] | √3 (Kobbelt 2000): refinement R of the plain and the boundary-trisecting step, limit stencil, in turn |
//! | [`deng_ma`] | the interpolatory Deng-Ma step |
//! | [`mod@subdivide`] | multi-level plans: topology once, geometry as repeated products, on normalised positions ([`normalized`]) |
//! | [`limit_matrix`] | the schemes' limit matrices A = D·S (Doo-Sabin C with any first-step corner mask, Catmull-Clark A, Loop L, √3), on which `subdiv-interp` builds its methods' |
//!
//! ```
//! use subdiv_mesh::shapes;
//! use subdiv_stencil::{Scheme, SubdivisionPlan};
//! let cube = shapes::cube();
//! let plan = SubdivisionPlan::new(cube.topology(), Scheme::CatmullClark, 2).unwrap();
//! assert_eq!(plan.topology().face_count(), 6 * 16);
//! let refined = plan.apply(cube.positions());
//! // Catmull-Clark pulls the cube's corners inward.
//! assert!(refined[0].length() > 0.1 && refined[0].x > 0.0);
//! ```
#![warn(missing_docs)]

mod apply;
pub mod catmull_clark;
pub mod deng_ma;
pub mod doo_sabin;
mod error;
pub mod fvar;
pub mod holes;
pub mod limit_matrix;
pub mod loop_subdivision;
pub mod normalized;
mod options;
mod rows;
pub mod scheme;
pub mod sharpness;
pub mod size;
pub mod sqrt3;
pub mod subdivide;
pub mod welds;

pub use apply::{apply, apply_columns, row_sums};
pub use error::StencilError;
pub use limit_matrix::{
    catmull_clark_kernel, doo_sabin_limit_sites, limit_matrix_catmull_clark, limit_matrix_catmull_clark_sharp,
    limit_matrix_doo_sabin, limit_matrix_doo_sabin_sharp, limit_matrix_loop, limit_matrix_loop_sharp,
    limit_matrix_sqrt3, limit_matrix_sqrt3_sharp, limit_operator_catmull_clark_sharp, limit_rows_loop_sharp,
    DualLimitSite, LimitMatrix, LimitOperator, LimitRows, RowKind, RowVisitor,
};
pub use options::{Options, Scheme};
pub(crate) use rows::{RowBuilder, Summation};
pub use scheme::{Domain, FVarSupport, LevelSplit, SchemeRules, SchemeTraits, Split};
pub use sharpness::{EdgeStep, LevelSharpness, VertexStep};
pub use subdiv_rules::deng_ma::Tension;
pub use subdiv_rules::LoopBeta;
pub use subdiv_rules::{BoundaryInterpolation, CreaseMethod, DartLimit, FVarInterpolation, Rule, TriangleRule};
pub use subdivide::{
    limit_points_with_options, subdivide, subdivide_for_output, Refinement, Subdivided, SubdivisionPlan,
};

/// Sparse matrix type of the workspace: CSR, `f64` values, `u32` indices
/// (half the index bandwidth of `usize` in every sparse product).
pub type SparseMatrix = sprs::CsMatI<f64, u32>;

use subdiv_mesh::Topology;
use subdiv_rules::VertexKind;

/// The rule class of a vertex (OpenSubdiv `EDGE_AND_CORNER`).
pub(crate) fn vertex_kind(t: &Topology, v: subdiv_mesh::VertexId) -> VertexKind {
    VertexKind::classify(t.is_boundary_vertex(v), t.vertex_face_count(v))
}

/// Vertices of `v`'s face ring — `v` and every corner of its faces — when they
/// are distinct (a bound otherwise): 1 + Σ over its faces of (m − 2), plus
/// the closing boundary neighbour on the boundary; 1 for an isolated vertex.
pub(crate) fn face_ring_size(t: &Topology, v: subdiv_mesh::VertexId) -> usize {
    let fan = t.vertex_fan(v);
    let corners: usize = fan.iter().map(|&h| t.face_size(t.he_face(h)) - 2).sum();
    1 + corners + usize::from(t.is_boundary_vertex(v))
}
