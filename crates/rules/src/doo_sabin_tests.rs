use proptest::prelude::*;

use super::*;
use crate::curves::chaikin;
use crate::test_util::{combine, max_dist, ClampedQuadratic, Rng, UniformBSpline};
use crate::vec3::{dist, lin2};

fn row(m: usize, f: impl Fn(usize, &mut [f64])) -> Vec<f64> {
    let mut w = vec![f64::NAN; m];
    f(m, &mut w);
    w
}

#[test]
fn weights_sum_to_one() {
    for m in 3..=12 {
        let ds: f64 = row(m, doo_sabin_weights).iter().sum();
        assert!((ds - 1.0).abs() < 1e-15, "Doo-Sabin m = {m}: {ds}");
    }
}

#[test]
fn weights_match_eq1_elementwise() {
    // α_ii = (m+5)/(4m), α_ij = (3 + 2cos(2π(i−j)/m))/(4m), symmetric in i − j.
    for m in 3..=12 {
        let w = row(m, doo_sabin_weights);
        assert_eq!(w[0], (m as f64 + 5.0) / (4.0 * m as f64));
        for k in 1..m {
            let expect = (3.0 + 2.0 * (2.0 * std::f64::consts::PI * k as f64 / m as f64).cos()) / (4.0 * m as f64);
            assert!((w[k] - expect).abs() < 1e-15, "m = {m}, k = {k}");
            assert_eq!(w[k], w[m - k], "row not symmetric: m = {m}, k = {k}");
        }
    }
}

#[test]
fn quad_row_is_the_biquadratic_tensor_product() {
    // (¾, ¼) ⊗ (¾, ¼) on the quad (V, next, opposite, previous).
    let w = row(4, doo_sabin_weights);
    assert_eq!(w, [0.75 * 0.75, 0.75 * 0.25, 0.25 * 0.25, 0.25 * 0.75]);
}

#[test]
fn circulant_eigenvalues_are_one_half_quarter() {
    // Correction Z8 (docs/REFERENCES.md): spectrum of the Doo-Sabin face circulant.
    for m in 3..=10 {
        let w = row(m, doo_sabin_weights);
        for k in 0..m {
            let dft = circulant_eigenvalue(&w, k);
            let expect = doo_sabin_eigenvalue(m, k);
            assert!((dft - expect).abs() < 1e-14, "m = {m}, k = {k}: DFT {dft}, expected {expect}");
        }
        let lambdas: Vec<f64> = (0..m).map(|k| circulant_eigenvalue(&w, k)).collect();
        assert!((lambdas[1] - 0.5).abs() < 1e-14 && (lambdas[m - 1] - 0.5).abs() < 1e-14);
        assert!(lambdas[2..m - 1].iter().all(|l| (l - 0.25).abs() < 1e-14));
    }
}

#[test]
fn circulant_eigenvalue_matches_a_real_eigenvector() {
    // Independent of the DFT formula: Circ(w)·v = λv for v_j = cos(2πjk/m).
    let m = 7;
    let w = row(m, doo_sabin_weights);
    for k in 0..m {
        let v: Vec<f64> = (0..m).map(|j| (2.0 * std::f64::consts::PI * (j * k) as f64 / m as f64).cos()).collect();
        let lambda = doo_sabin_eigenvalue(m, k);
        for i in 0..m {
            let cv: f64 = (0..m).map(|j| w[(j + m - i) % m] * v[j]).sum();
            assert!((cv - lambda * v[i]).abs() < 1e-14, "k = {k}, row {i}");
        }
    }
}

#[test]
fn boundary_point_is_the_doo_sabin_image_in_a_degenerate_quad() {
    // The boundary rule is the tensor-product end condition "boundary row
    // repeated": Eq. 1 (m = 4) applied to the quad (A, B, B, A) attached to the
    // boundary edge A→B gives, for corner A, exactly Chaikin's point.
    let mut rng = Rng::new(11);
    let w = row(4, doo_sabin_weights);
    for _ in 0..20 {
        let (a, b) = (rng.point(1.0), rng.point(1.0));
        let from_quad = combine(&w, &[a, b, b, a]);
        let rule = lin2(BOUNDARY_EDGE_POINT.near, a, BOUNDARY_EDGE_POINT.far, b);
        assert!(dist(from_quad, rule) < 1e-15);
    }
}

/// The new boundary loop of one Doo-Sabin step under the boundary rule: for
/// each old boundary edge A→B in loop order, the point near A then the point
/// near B (module docs, construction item 3).
fn boundary_step(boundary_loop: &[crate::Point3]) -> Vec<crate::Point3> {
    let n = boundary_loop.len();
    let BoundaryEdgePoint { near, far } = BOUNDARY_EDGE_POINT;
    (0..n)
        .flat_map(|i| {
            let (a, b) = (boundary_loop[i], boundary_loop[(i + 1) % n]);
            [lin2(near, a, far, b), lin2(near, b, far, a)]
        })
        .collect()
}

#[test]
fn boundary_loop_is_refined_by_chaikin() {
    let mut rng = Rng::new(7);
    for n in 3..=12 {
        let mut ds = rng.points(n, 1.0);
        let mut ck = ds.clone();
        for _ in 0..4 {
            ds = boundary_step(&ds);
            ck = chaikin(&ck, true);
            assert!(max_dist(&ds, &ck) < 1e-15, "n = {n}");
        }
    }
}

#[test]
fn boundary_converges_to_the_quadratic_bspline() {
    // Independent evaluation: the explicit uniform quadratic B-spline basis.
    let mut rng = Rng::new(8);
    let polygon = rng.points(7, 1.0);
    let curve = UniformBSpline::closed(2, &polygon);
    let mut refined = polygon.clone();
    let mut previous = f64::INFINITY;
    for level in 1..=8 {
        refined = boundary_step(&refined);
        let d = refined.iter().map(|&p| curve.distance(p)).fold(0.0, f64::max);
        if level >= 3 {
            let ratio = previous / d;
            assert!((3.5..4.5).contains(&ratio), "level {level}: ratio {ratio}");
        }
        previous = d;
    }
    assert!(previous < 1e-4, "distance after 8 levels: {previous}");
}

#[test]
fn boundary_curve_point_is_the_bspline_at_the_vertex() {
    // (B₋ + 6V + B₊)/8 is the quadratic B-spline at the middle of V's span.
    let mut rng = Rng::new(9);
    let polygon = rng.points(6, 1.0);
    let curve = UniformBSpline::closed(2, &polygon);
    for i in 0..6 {
        let stencil = combine(&BOUNDARY_CURVE_POINT, &[polygon[(i + 5) % 6], polygon[i], polygon[(i + 1) % 6]]);
        assert!(dist(stencil, curve.eval(i, 0.5)) < 1e-15);
    }
}

/// One step of a sharp polyline P₀…P_{n−1} from corner to corner (both ends
/// corners, every inner vertex not) under the per-edge rule: the corner
/// kept, the point near each non-corner end ([`BOUNDARY_EDGE_POINT`], or
/// [`CLAMPED_EDGE_POINT`] when the far end is a corner), the midpoint of an
/// edge between two corners.
fn sharp_step_between_corners(p: &[crate::Point3]) -> Vec<crate::Point3> {
    let n = p.len();
    let corner = |i: usize| i == 0 || i == n - 1;
    let near_point = |near: crate::Point3, far: crate::Point3, far_is_corner: bool| {
        let w = if far_is_corner { CLAMPED_EDGE_POINT } else { BOUNDARY_EDGE_POINT };
        lin2(w.near, near, w.far, far)
    };
    let mut out = vec![p[0]];
    for i in 0..n - 1 {
        let (a, b) = (p[i], p[i + 1]);
        if !corner(i) {
            out.push(near_point(a, b, corner(i + 1)));
        }
        if corner(i) && corner(i + 1) {
            out.push(lin2(0.5, a, 0.5, b));
        }
        if !corner(i + 1) {
            out.push(near_point(b, a, corner(i)));
        }
    }
    out.push(p[n - 1]);
    out
}

#[test]
fn sharp_polyline_between_corners_is_refined_by_clamped_chaikin() {
    // curves::chaikin on an open polyline is the clamped quadratic B-spline's
    // knot insertion: the per-edge rule must give exactly its points.
    let mut rng = Rng::new(10);
    for n in 2..=9 {
        let mut ours = rng.points(n, 1.0);
        let mut clamped = ours.clone();
        for level in 0..4 {
            ours = sharp_step_between_corners(&ours);
            clamped = chaikin(&clamped, false);
            assert_eq!(ours.len(), clamped.len(), "n = {n}, level {level}");
            assert!(max_dist(&ours, &clamped) < 1e-15, "n = {n}, level {level}");
        }
    }
}

#[test]
fn sharp_curve_point_lies_on_the_clamped_bspline() {
    // Independent evaluation: de Boor on knots 0,0,0,1,…,L,L,L.
    let mut rng = Rng::new(11);
    for n in 3..=8 {
        let polygon = rng.points(n, 1.0);
        let curve = ClampedQuadratic { control: polygon.clone() };
        for i in 1..n - 1 {
            let w = sharp_curve_point(i == 1, i == n - 2);
            assert_eq!(w.iter().sum::<f64>(), 1.0);
            let point = combine(&w, &polygon[i - 1..=i + 1]);
            let d = curve.distance(point);
            assert!(d < 1e-12, "n = {n}, vertex {i}: {d:e} off the curve");
        }
    }
    assert_eq!(sharp_curve_point(false, false), BOUNDARY_CURVE_POINT);
    assert_eq!(sharp_curve_point(true, true), [0.25, 0.5, 0.25]);
}

proptest! {
    #[test]
    fn doo_sabin_row_is_positive_and_sums_to_one(m in 3usize..64) {
        let w = row(m, doo_sabin_weights);
        prop_assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        prop_assert!(w.iter().all(|&x| x > 0.0));
    }
}

#[test]
fn tabled_rows_are_the_computed_ones_bit_for_bit() {
    for m in 3..=TABLED_FACE_SIZE + 4 {
        let bits = |w: Vec<f64>| w.into_iter().map(f64::to_bits).collect::<Vec<_>>();
        let from_eq1: Vec<f64> = (0..m).map(|k| doo_sabin_weight(m, k)).collect();
        let expected = if m == 4 { vec![9.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0, 3.0 / 16.0] } else { from_eq1 };
        assert_eq!(bits(row(m, doo_sabin_weights)), bits(expected), "m = {m}");
    }
}

/// The valence-2 mask is the centroid of the E-face that the edge v₀v₁
/// between two quads (v₀, a₀, a₁, v₁) and (v₁, b₁, b₀, v₀) becomes: each
/// corner of that E-face is Eq. 1 with m = 4 from v₀ or v₁ in one quad.
#[test]
fn valence_two_mask_is_the_centroid_of_the_next_e_face() {
    let mut w = [0.0; 4];
    doo_sabin_weights(4, &mut w);
    // Points as unit vectors: v0, v1, a0, a1, b0, b1.
    let e = |i: usize| {
        let mut x = [0.0; 6];
        x[i] = 1.0;
        x
    };
    let (v0, v1, a0, a1, b0, b1) = (0, 1, 2, 3, 4, 5);
    // Quad (v0, a0, a1, v1) and quad (v1, b1, b0, v0), each in cyclic order.
    let mut centroid = [0.0; 6];
    for quad in [[v0, a0, a1, v1], [v1, b1, b0, v0]] {
        for start in [v0, v1] {
            let k = quad.iter().position(|&c| c == start).unwrap();
            for (j, wj) in w.iter().enumerate() {
                let x = e(quad[(k + j) % 4]);
                for i in 0..6 {
                    centroid[i] += wj * x[i] / 4.0;
                }
            }
        }
    }
    let m = VALENCE_TWO_LIMIT;
    let expected = [m.own, m.own, m.adjacent, m.adjacent, m.adjacent, m.adjacent];
    for i in 0..6 {
        assert!((centroid[i] - expected[i]).abs() <= 1e-16, "weight {i}: {} vs {}", centroid[i], expected[i]);
    }
    assert_eq!(2.0 * m.own + 4.0 * m.adjacent, 1.0);
}
