use super::*;
use crate::test_util::dominant_left_eigenvector;

const BETAS: [LoopBeta; 2] = [LoopBeta::Warren, LoopBeta::Loop];

#[test]
fn masks_sum_to_one() {
    for beta in BETAS {
        for k in 3..=12 {
            for mask in [vertex_point_mask(VertexKind::Interior, k, beta), limit_mask(VertexKind::Interior, k, beta)] {
                assert!((mask.total(k, 0, k) - 1.0).abs() < 1e-15, "{beta:?}, k = {k}");
            }
            for mask in [vertex_point_mask(VertexKind::Boundary, k, beta), limit_mask(VertexKind::Boundary, k, beta)] {
                assert!((mask.total(k - 2, 2, k - 1) - 1.0).abs() < 1e-15);
            }
            assert_eq!(vertex_point_mask(VertexKind::Corner, 2, beta), VertexMask::IDENTITY);
            assert_eq!(limit_mask(VertexKind::Corner, 2, beta), VertexMask::IDENTITY);
        }
    }
    assert_eq!(edge_point_mask(false).total(3, Some(3)), 1.0);
    assert_eq!(edge_point_mask(true).total(3, None), 1.0);
}

#[test]
fn betas_and_gammas_in_closed_form() {
    // Corrections W2-W4 (docs/REFERENCES.md).
    assert_eq!(LoopBeta::Warren.beta(3), 3.0 / 16.0);
    assert!((LoopBeta::Warren.gamma(3) - 0.2).abs() < 1e-16);
    for k in 4..=12 {
        assert_eq!(LoopBeta::Warren.beta(k), 3.0 / (8.0 * k as f64));
        assert!((LoopBeta::Warren.gamma(k) - 1.0 / (2.0 * k as f64)).abs() < 1e-16);
    }
    assert!((LoopBeta::Loop.beta(6) - 1.0 / 16.0).abs() < 1e-16);
    assert!((LoopBeta::Loop.beta(3) - 3.0 / 16.0).abs() < 1e-16);
    assert_eq!(LoopBeta::default(), LoopBeta::Loop); // OpenSubdiv's
}

/// The (k+1)×(k+1) 1-ring subdivision matrix: node 0 the centre, node j the
/// ring vertex j; new centre by the vertex rule, new ring vertex j by the edge
/// rule ⅜ centre + ⅜ ring_j + ⅛ ring_{j−1} + ⅛ ring_{j+1}.
fn one_ring(k: usize, beta: LoopBeta) -> Vec<Vec<f64>> {
    let vm = vertex_point_mask(VertexKind::Interior, k, beta);
    let em = edge_point_mask(false);
    let mut s = vec![vec![0.0; k + 1]; k + 1];
    s[0].fill(vm.interior_neighbor);
    s[0][0] = vm.vertex;
    for (j, row) in s.iter_mut().enumerate().skip(1) {
        let (prev, next) = (1 + (j + k - 2) % k, 1 + j % k);
        row[0] += em.end;
        row[j] += em.end;
        row[prev] += em.left;
        row[next] += em.right;
    }
    s
}

#[test]
fn limit_mask_is_the_left_eigenvector_of_the_one_ring() {
    for beta in BETAS {
        for k in 3..=12 {
            let s = one_ring(k, beta);
            let l = dominant_left_eigenvector(&s);
            let mask = limit_mask(VertexKind::Interior, k, beta);
            assert!((l[0] - mask.vertex).abs() < 1e-12, "{beta:?}, k = {k}: {} vs {}", l[0], mask.vertex);
            for &w in &l[1..] {
                assert!((w - mask.interior_neighbor).abs() < 1e-12, "{beta:?}, k = {k}");
            }
            // Exactly a fixed point: lᵀS = lᵀ for the closed-form mask.
            let mut row = vec![mask.interior_neighbor; k + 1];
            row[0] = mask.vertex;
            for j in 0..=k {
                let image: f64 = (0..=k).map(|i| row[i] * s[i][j]).sum();
                assert!((image - row[j]).abs() < 1e-15, "{beta:?}, k = {k}, column {j}");
            }
        }
    }
}

#[test]
fn the_wrong_beta_fails_the_eigenvector_test() {
    // Warren's limit mask is not the limit of Loop's rule at k = 5.
    let l = dominant_left_eigenvector(&one_ring(5, LoopBeta::Loop));
    let warren = limit_mask(VertexKind::Interior, 5, LoopBeta::Warren);
    assert!((l[0] - warren.vertex).abs() > 1e-3);
}

#[test]
fn boundary_limit_mask_is_the_left_eigenvector_of_the_boundary_curve() {
    let vm = vertex_point_mask(VertexKind::Boundary, 4, LoopBeta::Warren);
    let em = edge_point_mask(true);
    let s = vec![
        vec![em.end, em.end, 0.0],
        vec![vm.boundary_neighbor, vm.vertex, vm.boundary_neighbor],
        vec![0.0, em.end, em.end],
    ];
    let l = dominant_left_eigenvector(&s);
    let lm = limit_mask(VertexKind::Boundary, 4, LoopBeta::Warren);
    assert!((l[0] - lm.boundary_neighbor).abs() < 1e-14 && (l[1] - lm.vertex).abs() < 1e-14);
}
