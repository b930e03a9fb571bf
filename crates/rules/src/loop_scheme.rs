//! Loop masks on triangle meshes: vertex and edge points with the
//! `EDGE_AND_CORNER` boundary rules, and the limit masks, for Warren's or
//! Loop's own β.
//!
//! Source: Deng & Wang 2010 (DW10 in [references]) Eq. 1-2 (vertex rule
//! and Warren's β, reconstructed in [corrections W1, W2]), the Remark after Eq. 2
//! (Loop's β, [correction W3]) and Eq. 5-6 (limit point, [correction W4]). The module is
//! called `loop_scheme` because `loop` is a Rust keyword.
//!
//! | new point | interior (valence k) | boundary | corner (1 face) |
//! |---|---|---|---|
//! | vertex point | (1 − kβ)p + βΣpⱼ | (p₋ + 6p + p₊)/8 | p |
//! | edge point | ⅜(a + b) + ⅛(c + d) | (a + b)/2 | — |
//! | limit | (1 − kγ)p + γΣpⱼ, γ = 1/(k + 3/(8β)) | (p₋ + 4p + p₊)/6 | p |
//!
//! All masks act on the unrefined mesh directly (Loop's rules are 1-ring
//! closed). The formulas are the published ones for k ≥ 3; for smaller k they
//! are evaluated as written, with no convergence claim.
//!
//! [corrections W1, W2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w1
//! [correction W3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w3
//! [correction W4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w4
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use std::f64::consts::PI;

use crate::mask::{EdgeMask, VertexKind, VertexMask};

/// Which β the Loop vertex rule uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LoopBeta {
    /// Warren's β: 3/16 for k = 3, 3/(8k) for k > 3 (Deng-Wang Eq. 2,
    /// [correction W2]), as in libigl; Deng and Wang (2010) chose it.
    ///
    /// [correction W2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w2
    Warren,
    /// Loop's original β = (1/k)[5/8 − (3/8 + ¼cos(2π/k))²] (Deng-Wang Remark,
    /// [correction W3]). The default, as in OpenSubdiv — the evaluator of
    /// Blender, USD/Hydra and RenderMan — so that a Loop control mesh written
    /// here means the same surface there.
    ///
    /// [correction W3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w3
    #[default]
    Loop,
}

impl LoopBeta {
    /// β for an interior vertex of valence k.
    ///
    /// ```
    /// use subdiv_rules::LoopBeta;
    /// assert_eq!(LoopBeta::Warren.beta(3), 3.0 / 16.0);
    /// assert_eq!(LoopBeta::Warren.beta(6), 1.0 / 16.0);
    /// assert!((LoopBeta::Loop.beta(6) - 1.0 / 16.0).abs() < 1e-15);
    /// ```
    ///
    /// # Panics
    /// If `k == 0`.
    pub fn beta(self, k: usize) -> f64 {
        assert!(k > 0, "a vertex needs at least one neighbour");
        let kf = k as f64;
        match self {
            Self::Warren if k == 3 => 3.0 / 16.0, // Eq. (2): β = 3/16, k = 3
            Self::Warren => 3.0 / (8.0 * kf),     // Eq. (2): β = 3/(8k), k > 3
            Self::Loop => {
                let c = 0.375 + 0.25 * (2.0 * PI / kf).cos();
                (0.625 - c * c) / kf // Remark (W3): β = (1/k)[5/8 − (3/8 + ¼cos(2π/k))²]
            }
        }
    }

    /// γ of the limit mask for an interior vertex of valence k:
    /// γ = 1/(k + 3/(8β)) (Deng-Wang Eq. 5-6, [correction W4]); for Warren's β this
    /// is 1/5 at k = 3 and 1/(2k) for k > 3.
    ///
    /// # Panics
    /// If `k == 0`.
    ///
    /// [correction W4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w4
    pub fn gamma(self, k: usize) -> f64 {
        1.0 / (k as f64 + 3.0 / (8.0 * self.beta(k))) // W4: γ = 1/(k + 3/(8β))
    }
}

/// Vertex-point mask. Interior vertex of valence k: (1 − kβ)p + βΣpⱼ
/// (Deng-Wang Eq. 1, [correction W1]). Boundary: (p₋ + 6p + p₊)/8 over the two
/// boundary neighbours. Corner (one triangle): p. The mask has no face term.
///
/// # Panics
/// If an interior vertex has valence 0.
///
/// [correction W1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w1
pub fn vertex_point_mask(kind: VertexKind, valence: usize, beta: LoopBeta) -> VertexMask {
    match kind {
        VertexKind::Interior => {
            let b = beta.beta(valence);
            VertexMask {
                vertex: 1.0 - valence as f64 * b, // Eq. (1): p' = (1 − kβ)p + β(p_1 + … + p_k)
                interior_neighbor: b,
                boundary_neighbor: 0.0,
                face: 0.0,
            }
        }
        VertexKind::Boundary => {
            VertexMask { vertex: 0.75, interior_neighbor: 0.0, boundary_neighbor: 0.125, face: 0.0 }
        }
        VertexKind::Corner => VertexMask::IDENTITY,
    }
}

/// Edge-point mask: interior edge ab with opposite corners c, d:
/// ⅜(a + b) + ⅛(c + d); boundary edge: the midpoint. In [`EdgeMask`] terms the
/// opposite corner is the one "other corner" of each triangle.
pub fn edge_point_mask(on_boundary: bool) -> EdgeMask {
    if on_boundary {
        EdgeMask::MIDPOINT
    } else {
        EdgeMask { end: 0.375, left: 0.125, right: 0.125 }
    }
}

/// Limit-point mask. Interior vertex of valence k: (1 − kγ)p + γΣpⱼ with
/// γ = [`LoopBeta::gamma`]. Boundary: (p₋ + 4p + p₊)/6. Corner: p.
///
/// # Panics
/// If an interior vertex has valence 0.
pub fn limit_mask(kind: VertexKind, valence: usize, beta: LoopBeta) -> VertexMask {
    match kind {
        VertexKind::Interior => {
            let g = beta.gamma(valence);
            VertexMask {
                vertex: 1.0 - valence as f64 * g, // Eq. (5): p∞ = (1 − kγ)p + γ Σ p_j
                interior_neighbor: g,
                boundary_neighbor: 0.0,
                face: 0.0,
            }
        }
        VertexKind::Boundary => {
            VertexMask { vertex: 4.0 / 6.0, interior_neighbor: 0.0, boundary_neighbor: 1.0 / 6.0, face: 0.0 }
        }
        VertexKind::Corner => VertexMask::IDENTITY,
    }
}

#[cfg(test)]
#[path = "loop_scheme_tests.rs"]
mod tests;
