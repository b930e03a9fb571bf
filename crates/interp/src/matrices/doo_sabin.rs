//! The Doo-Sabin methods' limit matrices: Nasri's C, Zheng-Cai's Z,
//! Fan-Cheng-Lai's B(λ), untagged (the methods pass the mesh's tags to
//! `subdiv_stencil::limit_matrix_doo_sabin_sharp` themselves).

use crate::first_step::CornerRule;
use subdiv_mesh::{Tags, Topology};
use subdiv_stencil::{limit_matrix_doo_sabin, limit_matrix_doo_sabin_sharp, LimitMatrix, StencilError};

/// Nasri's C: standard Doo-Sabin, limit of vertex v = centroid of its V-face
/// after one step (`subdiv_stencil::limit_matrix_doo_sabin`). Spectrum ⊂
/// [¼, 1] on closed manifold meshes ([correction Z8]).
///
/// [correction Z8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z8
pub fn limit_matrix_nasri(t: &Topology) -> LimitMatrix {
    limit_matrix_doo_sabin(t)
}

/// Zheng-Cai's Z: first step Eq. 4, V' = (V + A)/2; Eq. 6 divided by 2n,
/// equal to B(½). Strictly diagonally dominant, spectrum ⊂ [½, 1] ([correction Z7]).
///
/// [correction Z7]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z7
pub fn limit_matrix_zheng_cai(t: &Topology) -> LimitMatrix {
    limit_matrix_doo_sabin_sharp(t, &CornerRule::Uniform(0.5), &Tags::none()).expect("λ = ½ is valid")
}

/// Fan-Cheng-Lai's B(λ): two-phase first step with λ per face (Eq. 2, Eq. 5).
/// Spectrum ⊂ [min λ, 1] ([correction F6]).
///
/// # Errors
/// [`StencilError::InvalidParameter`] for a λ outside (0, 1) or a λ list of
/// the wrong length.
///
/// [correction F6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f6
pub fn limit_matrix_two_phase(t: &Topology, rule: CornerRule<'_>) -> Result<LimitMatrix, StencilError> {
    limit_matrix_doo_sabin_sharp(t, &rule, &Tags::none())
}
