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
//! | limit at a dart | [`dart_limit_mask`]: the eigenvector of the dart's 1-ring | — | — |
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

use crate::mask::{dart_ring_shape, DartMask, EdgeMask, VertexKind, VertexMask};

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

/// Limit-point mask of an interior **dart** of valence k: a vertex V with
/// vertex sharpness 0 and exactly one incident edge, VE₀, infinitely sharp
/// (weights and fan numbering: [`DartMask`], with no far corners).
///
/// Refinement keeps the smooth vertex rule at V but gives VE₀ the crease
/// rule, its midpoint, at every level, so the closed 1-ring subdivision
/// matrix S on the k + 1 points (V, E₀…Eₖ₋₁) is not the smooth one:
/// V' = (1 − kβ)V + βΣEᵢ, E₀' = (V + E₀)/2, the other
/// Eᵢ' = ⅜(V + Eᵢ) + ⅛(Eᵢ₋₁ + Eᵢ₊₁). The limit is the dominant left
/// eigenvector of the local subdivision matrix (e.g. Halstead, Kass & DeRose
/// 1993; Biermann, Levin & Zorin 2000, HKD93 and BLZ00 in [references]):
/// lᵀS = lᵀ with Σl = 1, which here differs from the smooth mask
/// [`limit_mask`] (what OpenSubdiv's limit stencils and
/// `Far::PrimvarRefiner::Limit` use at a dart).
///
/// Closed form, from lᵀS = lᵀ column by column with weight 1 on V and êⱼ the
/// weight of Eⱼ for 0 < j < k, ê₀ = êₖ = 0 (E₀' is a midpoint: no
/// neighbour term):
///
/// ```text
/// column Eⱼ, 0<j<k:  5eⱼ = 8β + êⱼ₋₁ + êⱼ₊₁
///   ⇒ eⱼ = (8β/3)(1 − (ρʲ + ρᵏ⁻ʲ)/(1 + ρᵏ)),  ρ = (5 − √21)/2 (ρ² − 5ρ + 1 = 0)
/// column E₀:          e₀ = 2β + (e₁ + eₖ₋₁)/4
/// ```
///
/// then every weight divided by 1 + Σe. The smooth mask's γ/(1 − kγ) = 8β/3
/// is the constant solution of the same equation (no crease). The powers of
/// ρ are taken as products, so any valence works (ρᵏ underflows to 0).
///
/// ```
/// use subdiv_rules::loop_scheme::dart_limit_mask;
/// use subdiv_rules::LoopBeta;
/// let m = dart_limit_mask(6, LoopBeta::Warren);
/// assert!((m.total() - 1.0).abs() < 1e-15 && m.far_corner.is_empty());
/// assert_eq!(m.edge[1], m.edge[5]);
/// assert!(m.edge[0] > m.edge[3] && m.edge[3] > m.edge[1]); // the crease pulls, its sides give way
/// ```
///
/// A valence below 2 (no manifold mesh has one) gets the identity.
///
/// [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md
pub fn dart_limit_mask(valence: usize, beta: LoopBeta) -> DartMask {
    let k = valence;
    if k < 2 {
        return DartMask::identity(k, 0);
    }
    let b = beta.beta(k);
    let rho = 2.0 / (5.0 + 21f64.sqrt()); // ρ = (5 − √21)/2, without the cancellation
    let u = dart_ring_shape(rho, k);
    let mut edge: Vec<f64> = (0..k).map(|j| if j == 0 { 0.0 } else { 8.0 * b / 3.0 * (1.0 - u[j]) }).collect(); // e_j
    edge[0] = 2.0 * b + (edge[1] + edge[k - 1]) / 4.0; // e₀ = 2β + (e₁ + eₖ₋₁)/4
    DartMask { vertex: 1.0, edge, far_corner: Vec::new() }.normalized()
}

#[cfg(test)]
#[path = "loop_scheme_tests.rs"]
mod tests;
