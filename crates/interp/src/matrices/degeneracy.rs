//! The structural degeneracies of Cheng's A (the Catmull-Clark limit
//! matrix, `subdiv_stencil::limit_matrix_catmull_clark`).

use subdiv_mesh::{Topology, VertexId};
use subdiv_stencil::catmull_clark_kernel;

/// Why Cheng's A cannot be inverted safely on a mesh ([limit matrices], [correction C3]).
///
/// [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3
/// [limit matrices]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Degeneracy {
    /// A closed component whose vertices all have valence 3 and whose vertex
    /// graph is bipartite (the cube, even prisms): the ±1 checkerboard vector
    /// on that component is in the kernel of A, exactly.
    Singular {
        /// A vertex of the component.
        vertex: VertexId,
    },
    /// An interior vertex of valence 2: the term n(n−3)/4 of S is negative
    /// there, which voids the proof that A is positive definite, and A may be
    /// indefinite. Measured: a lone valence-2 vertex between two quads leaves
    /// it definite (λ_min ≈ 0.098 on a 24 × 16 torus), two adjacent ones give
    /// a negative eigenvalue (≈ −0.023), the pillow λ_min = −1/7; solvers
    /// must treat A as possibly indefinite (MINRES, LDLᵀ).
    Indefinite {
        /// The valence-2 vertex.
        vertex: VertexId,
    },
}

/// Structural test for the two known ways Cheng's A fails to be positive
/// definite. `None` means every interior valence is ≥ 3 and no closed
/// component is an all-valence-3 bipartite mesh (A is then nonsingular in
/// every case we know; its spectrum lies in (0, 1]).
pub fn catmull_clark_degeneracy(t: &Topology) -> Option<Degeneracy> {
    if let Some(v) = t.vertices().find(|&v| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2) {
        return Some(Degeneracy::Indefinite { vertex: v });
    }
    catmull_clark_kernel(t).first().map(|c| Degeneracy::Singular { vertex: c[0].0 })
}
