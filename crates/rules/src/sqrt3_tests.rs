use super::*;
use crate::test_util::dominant_left_eigenvector;

#[test]
fn masks_sum_to_one() {
    for n in 3..=12 {
        for even in [false, true] {
            let m = vertex_point_mask(VertexKind::Interior, n, even);
            assert!((m.total(n, 0, 0) - 1.0).abs() < 1e-15, "n = {n}");
            let m = vertex_point_mask(VertexKind::Boundary, n, even);
            assert!((m.total(n - 2, 2, 0) - 1.0).abs() < 1e-15, "n = {n}");
            assert_eq!(vertex_point_mask(VertexKind::Corner, 2, even), VertexMask::IDENTITY);
        }
        assert!((limit_mask(VertexKind::Interior, n).total(n, 0, 0) - 1.0).abs() < 1e-15);
        assert!((limit_mask(VertexKind::Boundary, n).total(n - 2, 2, 0) - 1.0).abs() < 1e-15);
    }
    assert_eq!(vertex_point_mask(VertexKind::Boundary, 4, false), VertexMask::IDENTITY);
    for corner in [false, true] {
        assert!((trisection_mask(corner).total() - 1.0).abs() < 1e-15);
    }
    assert!((3.0 * FACE_POINT - 1.0).abs() < 1e-15);
}

#[test]
fn alpha_and_beta_in_closed_form() {
    // The regular case: α₆ = ⅓, β₆ = ½, λ₆ = ⅓ (the step scales a regular
    // lattice's second differences by ⅓, its edges by 1/√3).
    assert!((alpha(6) - 1.0 / 3.0).abs() < 1e-15);
    assert!((beta(6) - 0.5).abs() < 1e-15);
    assert!((convergence_factor(6) - 1.0 / 3.0).abs() < 1e-15);
    assert!((alpha(3) - 5.0 / 9.0).abs() < 1e-15);
    assert!((alpha(4) - 4.0 / 9.0).abs() < 1e-15);
    for n in 3..=64 {
        let l = convergence_factor(n);
        assert!(l.abs() < 1.0 && l > 0.0, "n = {n}: λ = {l}");
        assert!(beta(n) > 0.0 && beta(n) < 1.0);
    }
}

/// The (n+1)×(n+1) map of one step on a vertex's 1-ring: node 0 the centre,
/// node j its ring vertex j; the new centre by the smoothing rule, the new
/// ring vertex j the centroid of triangle (centre, ring j, ring j+1) — after
/// the flips an interior vertex's neighbours are exactly those centroids.
fn one_ring(n: usize) -> Vec<Vec<f64>> {
    let vm = vertex_point_mask(VertexKind::Interior, n, false);
    let mut s = vec![vec![0.0; n + 1]; n + 1];
    s[0].fill(vm.interior_neighbor);
    s[0][0] = vm.vertex;
    for (j, row) in s.iter_mut().enumerate().skip(1) {
        row[0] += FACE_POINT;
        row[j] += FACE_POINT;
        row[1 + j % n] += FACE_POINT;
    }
    s
}

#[test]
fn limit_mask_is_the_left_eigenvector_of_the_one_ring_step() {
    for n in 3..=12 {
        let s = one_ring(n);
        let l = dominant_left_eigenvector(&s);
        let mask = limit_mask(VertexKind::Interior, n);
        assert!((l[0] - mask.vertex).abs() < 1e-12, "n = {n}: {} vs {}", l[0], mask.vertex);
        for &w in &l[1..] {
            assert!((w - mask.interior_neighbor).abs() < 1e-12, "n = {n}");
        }
        // Exactly a fixed point: lᵀS = lᵀ for the closed-form mask (the ring
        // is relabelled by the step, but the mask is uniform over it).
        let mut row = vec![mask.interior_neighbor; n + 1];
        row[0] = mask.vertex;
        for j in 0..=n {
            let image: f64 = (0..=n).map(|i| row[i] * s[i][j]).sum();
            assert!((image - row[j]).abs() < 1e-15, "n = {n}, column {j}");
        }
    }
}

/// One even step of the boundary polygon around p: (p₋, p, p₊) ↦ (the
/// trisection point of (p₋, p) next to p, p', the one of (p, p₊) next to p).
fn boundary_step() -> Vec<Vec<f64>> {
    let vm = vertex_point_mask(VertexKind::Boundary, 3, true);
    let t = trisection_mask(false);
    vec![
        vec![t.far, t.near, t.outer],
        vec![vm.boundary_neighbor, vm.vertex, vm.boundary_neighbor],
        vec![t.outer, t.near, t.far],
    ]
}

#[test]
fn boundary_limit_mask_is_the_left_eigenvector_of_the_ternary_step() {
    let l = dominant_left_eigenvector(&boundary_step());
    let lm = limit_mask(VertexKind::Boundary, 4);
    assert!((l[0] - lm.boundary_neighbor).abs() < 1e-14 && (l[1] - lm.vertex).abs() < 1e-14, "{l:?}");
    assert!((l[2] - lm.boundary_neighbor).abs() < 1e-14);
}

#[test]
fn ternary_rules_reproduce_cubics() {
    // The uniform cubic B-spline with control points cᵢ = i³ − i is x³; its
    // ternary refinement must give x³'s control points at spacing ⅓,
    // x³ − x/9 at x = j/3.
    // Control points are the blossom f(x − h, x, x + h) = x³ − xh² of x³.
    let c0 = |i: f64| i * i * i - i;
    let c1 = |x: f64| x * x * x - x / 9.0;
    let t = trisection_mask(false);
    let vm = vertex_point_mask(VertexKind::Boundary, 3, true);
    for i in -3..3 {
        let i = i as f64;
        let (pm, p, pp, ppp) = (c0(i - 1.0), c0(i), c0(i + 1.0), c0(i + 2.0));
        let first = t.outer * pm + t.near * p + t.far * pp;
        let second = t.far * p + t.near * pp + t.outer * ppp;
        let vertex = vm.boundary_neighbor * (pm + pp) + vm.vertex * p;
        assert!((vertex - c1(i)).abs() < 1e-12, "{i}");
        assert!((first - c1(i + 1.0 / 3.0)).abs() < 1e-12, "{i}");
        assert!((second - c1(i + 2.0 / 3.0)).abs() < 1e-12, "{i}");
    }
}

#[test]
fn the_corner_rule_is_the_phantom_reflection() {
    // Corner c with neighbour b and phantom 2c − b: the plain masks give the
    // corner rules.
    let (c, b) = (1.3, -0.4);
    let phantom = 2.0 * c - b;
    let t = trisection_mask(false);
    let tc = trisection_mask(true);
    let plain_near_corner = t.outer * phantom + t.near * c + t.far * b;
    assert!((plain_near_corner - (tc.near * c + tc.far * b)).abs() < 1e-15);
    let vm = vertex_point_mask(VertexKind::Boundary, 3, true);
    assert!((vm.boundary_neighbor * (phantom + b) + vm.vertex * c - c).abs() < 1e-15, "the corner stays");
    let lm = limit_mask(VertexKind::Boundary, 3);
    assert!((lm.boundary_neighbor * (phantom + b) + lm.vertex * c - c).abs() < 1e-15, "its own limit");
    // The refined polygon's phantom is again the reflection: the trisection
    // point of (phantom, c) next to c, seen from the refined corner.
    let refined_b = t.outer * phantom + t.near * c + t.far * b;
    let refined_phantom = t.far * phantom + t.near * c + t.outer * b;
    assert!((refined_phantom - (2.0 * c - refined_b)).abs() < 1e-15);
}
