use super::*;
use crate::mask::DartMask;
use crate::test_util::{dominant_left_eigenvector, left_fixed_point};

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

/// [`one_ring`] of a dart: ring vertex 0 at the end of the infinitely sharp
/// edge, whose new point is the midpoint (V + E₀)/2.
fn dart_one_ring(k: usize, beta: LoopBeta) -> Vec<Vec<f64>> {
    let mut s = one_ring(k, beta);
    let crease = edge_point_mask(true);
    s[1] = vec![0.0; k + 1];
    s[1][0] = crease.end;
    s[1][1] = crease.end;
    s
}

fn dart_row(mask: &DartMask) -> Vec<f64> {
    std::iter::once(mask.vertex).chain(mask.edge.iter().copied()).collect()
}

const DART_VALENCES: [usize; 14] = [2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 16, 30, 100];

#[test]
fn dart_mask_sums_to_one_at_any_valence() {
    for beta in BETAS {
        for k in DART_VALENCES.into_iter().chain([1000, 100_000]) {
            let mask = dart_limit_mask(k, beta);
            assert_eq!((mask.edge.len(), mask.far_corner.len()), (k, 0));
            // The sum of k weights rounds k times.
            assert!((mask.total() - 1.0).abs() < 1e-14 + 1e-16 * k as f64, "{beta:?}, k = {k}: {}", mask.total());
            assert!(mask.edge.iter().all(|&w| w > 0.0), "{beta:?}, k = {k}");
        }
        assert_eq!(dart_limit_mask(0, beta), DartMask { vertex: 1.0, edge: vec![], far_corner: vec![] });
        assert_eq!(dart_limit_mask(1, beta), DartMask { vertex: 1.0, edge: vec![0.0], far_corner: vec![] });
    }
}

#[test]
fn dart_mask_is_the_left_eigenvector_of_the_dart_one_ring() {
    for beta in BETAS {
        for k in DART_VALENCES {
            let s = dart_one_ring(k, beta);
            let l = dart_row(&dart_limit_mask(k, beta));
            for j in 0..=k {
                let image: f64 = (0..=k).map(|i| l[i] * s[i][j]).sum();
                assert!((image - l[j]).abs() < 1e-14, "{beta:?}, k = {k}, column {j}: {image} vs {}", l[j]);
            }
            let (solved, power) = (left_fixed_point(&s), dominant_left_eigenvector(&s));
            for (j, &w) in l.iter().enumerate() {
                assert!((solved[j] - w).abs() < 1e-13, "{beta:?}, k = {k}, node {j}: solved {}", solved[j]);
                assert!((power[j] - w).abs() < 1e-12, "{beta:?}, k = {k}, node {j}: power {}", power[j]);
            }
        }
    }
}

#[test]
fn dart_mask_is_symmetric_about_the_crease_and_differs_from_the_smooth_mask() {
    for beta in BETAS {
        for k in DART_VALENCES {
            let mask = dart_limit_mask(k, beta);
            for i in 1..k {
                assert_eq!(mask.edge[i], mask.edge[k - i], "{beta:?}, k = {k}, E{i}");
            }
            let smooth = limit_mask(VertexKind::Interior, k, beta);
            let off = (mask.vertex - smooth.vertex).abs();
            assert!(off > 1e-4, "{beta:?}, k = {k}: V {} vs smooth {}", mask.vertex, smooth.vertex);
            assert!(mask.edge[0] > smooth.interior_neighbor, "{beta:?}, k = {k}: the crease's end pulls");
        }
    }
}

#[test]
fn dart_mask_in_exact_arithmetic() {
    // Solved in rationals: k = 6 (Warren's β = Loop's β = 1/16),
    // (220V + 42E₀ + 29(E₁ + E₅) + 35(E₂ + E₄) + 36E₃)/426; k = 4, Warren's β = 3/32,
    // (368V + 105E₀ + 72(E₁ + E₃) + 84E₂)/701.
    let cases: [(usize, &[f64], f64); 2] =
        [(6, &[220.0, 42.0, 29.0, 35.0, 36.0, 35.0, 29.0], 426.0), (4, &[368.0, 105.0, 72.0, 84.0, 72.0], 701.0)];
    for (k, weights, den) in cases {
        for beta in BETAS.into_iter().filter(|&b| k == 6 || b == LoopBeta::Warren) {
            for (got, want) in dart_row(&dart_limit_mask(k, beta)).iter().zip(weights) {
                assert!((got - want / den).abs() < 1e-16, "{beta:?}, k = {k}: {got} vs {}", want / den);
            }
        }
    }
}
