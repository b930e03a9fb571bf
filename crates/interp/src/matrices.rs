//! The methods' limit matrices A = D·S, built on `subdiv_stencil::limit_matrix`
//! ([limit matrices]), and what the methods know about them: the block order
//! of a solve ([`SolveBlocks`]) and the structural degeneracies of Cheng's A
//! ([`Degeneracy`]).
//!
//! | builder | method, first step | D | S (interior vertex v, valence n, faces fᵢ of size mᵢ) |
//! |---|---|---|---|
//! | [`limit_matrix_nasri`] | Nasri, standard Doo-Sabin | 1/n | Σ_f Circ(α_{m_f}) (Zheng-Cai Eq. 1; [correction Z8]) |
//! | [`limit_matrix_zheng_cai`] | Zheng-Cai Eq. 4 | 1/n | B(½): Eq. 6 divided by 2n ([correction Z7]) |
//! | [`limit_matrix_two_phase`] | Fan-Cheng-Lai Eq. 1, λ per face | 1/n | Σ_f [λ_f I + (1 − λ_f) J/m_f] (Eq. 2 with [correction F1], Eq. 5) |
//! | `subdiv_stencil::limit_matrix_catmull_clark` | Cheng, Catmull-Clark | 4/(n(n+5)) | appendix Eq. 5 bracket ([corrections C1, C2]) |
//! | `subdiv_stencil::limit_matrix_loop` | Deng-Wang, Loop | γ = 1/(k + 3/(8β)) | 3/(8β) on the diagonal, 1 per neighbour (Deng-Wang Eq. 5-6, [correction W4]) |
//!
//! The Doo-Sabin three are `subdiv_stencil::limit_matrix_doo_sabin_sharp`
//! with the method's first-step rule ([`crate::first_step::CornerRule`]);
//! with creases and corners the methods call it with the mesh's tags. Their
//! spectra (the stencil's module docs, "Spectra, Doo-Sabin"): the smooth
//! block's D^½SD^½ lies in [¼, 1] (C), [½, 1] (Z), [min λ, 1] (B(λ)), the
//! face blocks' eigenvalues ([correction Z8], [correction F6]).
//!
//! [limit matrices]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule
//! [correction Z8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z8
//! [correction Z7]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z7
//! [correction F1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f1
//! [correction F6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f6
//! [corrections C1, C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1
//! [correction W4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w4

mod blocks;
mod degeneracy;
mod doo_sabin;

pub use blocks::{solve_blocks, SolveBlocks};
pub use degeneracy::{catmull_clark_degeneracy, Degeneracy};
pub use doo_sabin::{limit_matrix_nasri, limit_matrix_two_phase, limit_matrix_zheng_cai};
