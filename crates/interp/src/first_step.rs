//! The first steps of the Doo-Sabin methods: the corner rules that make
//! their control meshes (Zheng-Cai's M¹, Fan-Cheng-Lai's phase one) and their
//! limit matrices ([`crate::matrices`]).
//!
//! Zheng & Cai 2005, Eq. 4: V'ᵢ = (Vᵢ + A)/2 with A the face centroid; Fan,
//! Cheng & Lai, Eq. 1: V'ᵢ = λVᵢ + (1 − λ)A with one λ ∈ (0, 1) per face
//! (§2). Eq. 4 is λ = ½ ([`two_phase_weights`], [`zheng_cai_weights`]).
//! Their face matrix λI + (1 − λ)J/m has eigenvalues 1 and λ ([correction F6]).
//!
//! A rule is a [`CornerMask`] of `subdiv_stencil::doo_sabin`: the stencil
//! builds the step around it (sharp points, faces, the later standard
//! steps), and [`CornerRule::images`](CornerMask::images) evaluates the
//! images in the closed form λV + (1 − λ)A.
//!
//! [correction F6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f6

use glam::DVec3;
use std::ops::Range;
use subdiv_mesh::{FaceId, Topology};
use subdiv_stencil::doo_sabin::{CornerMask, StandardCorners};
use subdiv_stencil::StencilError;

/// Fills `out` (length m) with the first-step row of Fan-Cheng-Lai Eq. 1,
/// V'ᵢ = λVᵢ + (1−λ)A, A the face centroid: `out[0] = λ + (1−λ)/m`,
/// `out[k] = (1−λ)/m` for k ≥ 1. The paper takes λ ∈ (0, 1) per face; λ = ½ is
/// Zheng-Cai Eq. 4.
///
/// ```
/// let mut w = [0.0; 4];
/// subdiv_interp::first_step::two_phase_weights(4, 0.5, &mut w);
/// assert_eq!(w, [0.625, 0.125, 0.125, 0.125]);
/// ```
///
/// # Panics
/// If `m < 3` or `out.len() != m`.
#[inline]
pub fn two_phase_weights(m: usize, lambda: f64, out: &mut [f64]) {
    assert!(m >= 3, "a face has at least 3 corners, got {m}");
    assert_eq!(out.len(), m, "weight buffer length must equal the face size");
    let share = (1.0 - lambda) / m as f64; // Fan Eq. (1): (1−λ)A = Σ (1−λ)/m V_j
    out.fill(share);
    out[0] = lambda + share; // Fan Eq. (1): λV_i
}

/// Fills `out` with Zheng-Cai's first-step row, Eq. 4: V'ᵢ = (Vᵢ + A)/2, i.e.
/// [`two_phase_weights`] with λ = ½.
///
/// # Panics
/// If `m < 3` or `out.len() != m`.
pub fn zheng_cai_weights(m: usize, out: &mut [f64]) {
    two_phase_weights(m, 0.5, out); // Zheng-Cai Eq. (4)
}

/// Which corner rule the first step uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CornerRule<'a> {
    /// Standard Doo-Sabin weights (Zheng-Cai Eq. 1): `StandardCorners`.
    Standard,
    /// V' = λV + (1 − λ)A with one λ ∈ (0, 1) for every face (λ = ½ is
    /// Zheng-Cai Eq. 4).
    Uniform(f64),
    /// V' = λ_f V + (1 − λ_f)A with λ_f per face (Fan-Cheng-Lai Eq. 1).
    PerFace(&'a [f64]),
}

impl CornerRule<'_> {
    /// The λ of face `face`; `None` for the standard rule.
    fn lambda(&self, face: FaceId) -> Option<f64> {
        match *self {
            CornerRule::Standard => None,
            CornerRule::Uniform(l) => Some(l),
            CornerRule::PerFace(ls) => Some(ls[face.index()]),
        }
    }
}

impl CornerMask for CornerRule<'_> {
    /// Checks the parameters against the mesh: λ ∈ (0, 1), one per face.
    fn validate(&self, t: &Topology) -> Result<(), StencilError> {
        let check = |face: Option<usize>, l: f64| {
            if l > 0.0 && l < 1.0 {
                Ok(())
            } else {
                let at = face.map(|f| format!(" of face {f}")).unwrap_or_default();
                Err(StencilError::InvalidParameter(format!("λ{at} = {l} is outside (0, 1)")))
            }
        };
        match *self {
            CornerRule::Standard => Ok(()),
            CornerRule::Uniform(l) => check(None, l),
            CornerRule::PerFace(ls) if ls.len() != t.face_count() => {
                Err(StencilError::InvalidParameter(format!("{} λ values for {} faces", ls.len(), t.face_count())))
            }
            CornerRule::PerFace(ls) => ls.iter().enumerate().try_for_each(|(f, &l)| check(Some(f), l)),
        }
    }

    /// The row of a face of size `out.len()`.
    fn weights(&self, face: FaceId, out: &mut [f64]) {
        match self.lambda(face) {
            None => StandardCorners.weights(face, out), // Zheng-Cai Eq. (1)
            Some(lambda) => two_phase_weights(out.len(), lambda, out), // Eq. (4) / Fan Eq. (1)
        }
    }

    /// λV + (1 − λ)A directly, A the face centroid (the standard rule: its
    /// weights, as `StandardCorners`).
    fn images(
        &self,
        face: FaceId,
        corners: &[u32],
        x: &[DVec3],
        ks: Range<usize>,
        out: &mut [DVec3],
        scratch: &mut Vec<f64>,
    ) {
        let Some(lambda) = self.lambda(face) else {
            return StandardCorners.images(face, corners, x, ks, out, scratch);
        };
        let centroid = corners.iter().map(|&v| x[v as usize]).sum::<DVec3>() / corners.len() as f64;
        for (k, image) in ks.zip(out) {
            // Fan-Cheng-Lai Eq. 1, Zheng-Cai Eq. 4: λV + (1 − λ)A, A the face centroid.
            *image = lambda * x[corners[k] as usize] + (1.0 - lambda) * centroid;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use subdiv_rules::doo_sabin::circulant_eigenvalue;

    fn row(m: usize, f: impl Fn(usize, &mut [f64])) -> Vec<f64> {
        let mut w = vec![f64::NAN; m];
        f(m, &mut w);
        w
    }

    #[test]
    fn weights_sum_to_one() {
        for m in 3..=12 {
            let zc: f64 = row(m, zheng_cai_weights).iter().sum();
            assert!((zc - 1.0).abs() < 1e-15, "Zheng-Cai m = {m}: {zc}");
            for lambda in [0.1, 0.4, 0.5, 0.85, 1.0] {
                let tp: f64 = row(m, |m, w| two_phase_weights(m, lambda, w)).iter().sum();
                assert!((tp - 1.0).abs() < 1e-15, "two-phase m = {m}, λ = {lambda}: {tp}");
            }
        }
    }

    #[test]
    fn two_phase_eigenvalues_are_one_and_lambda() {
        // Correction F6 (docs/REFERENCES.md): λI + (1−λ)J/m has eigenvalues 1 (constant vector) and λ.
        for m in 3..=12 {
            for lambda in [0.2, 0.5, 0.85] {
                let w = row(m, |m, w| two_phase_weights(m, lambda, w));
                assert!((circulant_eigenvalue(&w, 0) - 1.0).abs() < 1e-15);
                for k in 1..m {
                    assert!((circulant_eigenvalue(&w, k) - lambda).abs() < 1e-14, "m = {m}, λ = {lambda}, k = {k}");
                }
            }
        }
    }

    #[test]
    fn zheng_cai_is_vertex_plus_centroid_over_two() {
        // Eq. 4 written out: V' = (V + A)/2.
        let mut rng = subdiv_mesh::shapes::SplitMix64(4);
        for m in 3..=9 {
            let face: Vec<DVec3> =
                (0..m).map(|_| DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) - 0.5).collect();
            let w = row(m, zheng_cai_weights);
            let a = face.iter().sum::<DVec3>() / m as f64;
            let image = w.iter().zip(&face).map(|(&wj, &p)| wj * p).sum::<DVec3>(); // image of corner 0
            assert!(image.distance(0.5 * face[0] + 0.5 * a) < 1e-15);
        }
    }

    /// The closed form of `images` is the weights' combination, corner by
    /// corner and for a range that starts inside the face.
    #[test]
    fn images_are_the_weighted_sums() {
        let mut rng = subdiv_mesh::shapes::SplitMix64(9);
        let x: Vec<DVec3> = (0..12).map(|_| DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64())).collect();
        let corners = [3u32, 7, 0, 11, 5];
        let lambdas = [0.3, 0.71];
        for rule in [CornerRule::Standard, CornerRule::Uniform(0.5), CornerRule::PerFace(&lambdas)] {
            let face = FaceId(1);
            let mut w = vec![0.0; corners.len()];
            rule.weights(face, &mut w);
            let mut out = [DVec3::ZERO; 3];
            rule.images(face, &corners, &x, 2..5, &mut out, &mut Vec::new());
            for (k, image) in (2..5).zip(out) {
                let expected: DVec3 = (0..5).map(|j| w[j] * x[corners[(k + j) % 5] as usize]).sum();
                assert!(image.distance(expected) < 1e-15, "{rule:?}, corner {k}");
            }
        }
    }

    #[test]
    fn bad_lambdas_are_refused() {
        let cube = subdiv_mesh::shapes::cube();
        let t = cube.topology();
        for rule in [CornerRule::Uniform(0.0), CornerRule::Uniform(1.0), CornerRule::PerFace(&[0.5; 5])] {
            assert!(matches!(rule.validate(t), Err(StencilError::InvalidParameter(_))), "{rule:?}");
        }
        assert!(CornerRule::PerFace(&[0.5; 6]).validate(t).is_ok());
    }

    proptest! {
        #[test]
        fn two_phase_row_is_convex_and_eq1_shaped(m in 3usize..40, lambda in 0.0f64..=1.0) {
            let w = row(m, |m, w| two_phase_weights(m, lambda, w));
            prop_assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            prop_assert!(w.iter().all(|&x| x >= 0.0));
            prop_assert!((w[0] - w[1] - lambda).abs() < 1e-15);
            for k in 1..m {
                prop_assert!((circulant_eigenvalue(&w, k) - lambda).abs() < 1e-13);
            }
        }
    }
}
