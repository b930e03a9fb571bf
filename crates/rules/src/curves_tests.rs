use proptest::prelude::*;

use super::*;
use crate::test_util::{max_dist, ClampedQuadratic, Rng, UniformBSpline};
use crate::vec3::{dist, lin2};

/// Max distance of the refined points to a curve after each level 1..=levels.
fn distances(
    scheme: CurveScheme,
    polygon: &[Point3],
    closed: bool,
    levels: usize,
    distance: impl Fn(Point3) -> f64,
) -> Vec<f64> {
    let mut points = polygon.to_vec();
    (0..levels)
        .map(|_| {
            points = scheme.refine(&points, closed);
            points.iter().map(|&p| distance(p)).fold(0.0, f64::max)
        })
        .collect()
}

/// Distances below 1e-3·scale after 8 levels, shrinking ~4× per level.
fn assert_quadratic_convergence(d: &[f64], scale: f64) {
    let last = *d.last().unwrap();
    assert!(last < 1e-3 * scale, "after {} levels the distance is {last}", d.len());
    for (level, pair) in d.windows(2).enumerate().skip(2) {
        let ratio = pair[0] / pair[1];
        assert!((3.0..5.0).contains(&ratio), "level {}: ratio {ratio} ({d:?})", level + 2);
    }
}

#[test]
fn chaikin_closed_converges_to_the_quadratic_bspline() {
    let mut rng = Rng::new(21);
    for n in [3, 5, 8] {
        let polygon = rng.points(n, 1.0);
        let curve = UniformBSpline::closed(2, &polygon);
        let d = distances(CurveScheme::Chaikin, &polygon, true, 8, |p| curve.distance(p));
        assert_quadratic_convergence(&d, 2.0);
    }
}

#[test]
fn chaikin_edge_midpoints_lie_on_the_curve() {
    // The quadratic B-spline passes through the midpoints of its control
    // polygon's edges, at every level.
    let mut rng = Rng::new(22);
    let polygon = rng.points(6, 1.0);
    let curve = UniformBSpline::closed(2, &polygon);
    let refined = CurveScheme::Chaikin.refine_levels(&polygon, true, 3);
    let n = refined.len();
    for i in 0..n {
        let mid = lin2(0.5, refined[i], 0.5, refined[(i + 1) % n]);
        assert!(curve.distance(mid) < 1e-12, "midpoint {i}: {}", curve.distance(mid));
    }
}

#[test]
fn chaikin_open_converges_to_the_clamped_quadratic_bspline() {
    let mut rng = Rng::new(23);
    for n in [3, 4, 5, 9] {
        let polygon = rng.points(n, 1.0);
        let curve = ClampedQuadratic { control: polygon.clone() };
        let d = distances(CurveScheme::Chaikin, &polygon, false, 8, |p| curve.distance(p));
        assert_quadratic_convergence(&d, 2.0);
        let fine = CurveScheme::Chaikin.refine_levels(&polygon, false, 5);
        assert_eq!(fine[0], polygon[0]);
        assert_eq!(fine[fine.len() - 1], polygon[n - 1]);
    }
}

#[test]
fn chaikin_open_first_level_is_exact_knot_insertion() {
    // Clamped quadratic B-spline: the refined polygon describes the same curve,
    // so its own clamped curve matches the original one pointwise.
    let mut rng = Rng::new(24);
    for n in 3..=8 {
        let polygon = rng.points(n, 1.0);
        let refined = chaikin(&polygon, false);
        assert_eq!(refined.len(), 2 * n - 2);
        let (coarse, fine) = (ClampedQuadratic { control: polygon }, ClampedQuadratic { control: refined });
        for s in 0..coarse.segments() {
            for k in 0..=8 {
                let t = k as f64 / 8.0;
                let x = 2.0 * (s as f64 + t);
                let (fs, ft) = ((x.floor() as usize).min(fine.segments() - 1), 0.0);
                let p = fine.eval(fs, x - fs as f64 + ft);
                assert!(dist(coarse.eval(s, t), p) < 1e-14, "n = {n}, s = {s}, t = {t}");
            }
        }
    }
}

#[test]
fn cubic_closed_converges_to_the_cubic_bspline() {
    let mut rng = Rng::new(25);
    for n in [3, 5, 8] {
        let polygon = rng.points(n, 1.0);
        let curve = UniformBSpline::closed(3, &polygon);
        let d = distances(CurveScheme::CubicBSpline, &polygon, true, 8, |p| curve.distance(p));
        assert_quadratic_convergence(&d, 2.0);
        // Limit points (1, 4, 1)/6 of the refined polygon lie on the curve.
        let refined = CurveScheme::CubicBSpline.refine_levels(&polygon, true, 3);
        let m = refined.len();
        for i in 0..m {
            let limit = crate::test_util::combine(
                &[1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0],
                &[refined[(i + m - 1) % m], refined[i], refined[(i + 1) % m]],
            );
            assert!(curve.distance(limit) < 1e-12);
        }
    }
}

#[test]
fn cubic_open_converges_to_the_phantom_extended_bspline() {
    let mut rng = Rng::new(26);
    for n in [2, 3, 6] {
        let polygon = rng.points(n, 1.0);
        let mut control = vec![lin2(2.0, polygon[0], -1.0, polygon[1])];
        control.extend_from_slice(&polygon);
        control.push(lin2(2.0, polygon[n - 1], -1.0, polygon[n - 2]));
        let curve = UniformBSpline { degree: 3, control };
        let d = distances(CurveScheme::CubicBSpline, &polygon, false, 8, |p| curve.distance(p));
        if n > 2 {
            assert_quadratic_convergence(&d, 2.0);
        } else {
            assert!(d.iter().all(|&x| x < 1e-15), "a segment stays a segment: {d:?}");
        }
        let fine = CurveScheme::CubicBSpline.refine_levels(&polygon, false, 4);
        assert_eq!(fine.len(), 16 * (n - 1) + 1);
        assert_eq!((fine[0], fine[fine.len() - 1]), (polygon[0], polygon[n - 1]));
    }
}

#[test]
fn four_point_keeps_old_points_bit_exact() {
    let mut rng = Rng::new(27);
    for closed in [true, false] {
        for n in [2, 3, 4, 7] {
            let polygon = rng.points(n, 1.0);
            let tension = rng.range(0.001, 0.124);
            let scheme = CurveScheme::FourPoint { tension };
            let mut points = polygon.clone();
            for level in 1..=5 {
                points = scheme.refine(&points, closed);
                let stride = 1 << level;
                for (i, &p) in polygon.iter().enumerate() {
                    assert_eq!(points[i * stride], p, "closed = {closed}, n = {n}, level {level}, point {i}");
                }
            }
        }
    }
}

fn cubic(x: f64) -> Point3 {
    [x, 0.3 * x * x * x - 1.1 * x * x + 0.7 * x - 2.0, -0.05 * x * x * x + 0.4 * x]
}

#[test]
fn four_point_reproduces_cubics() {
    // Samples of a cubic at x = 0, 1, …, 11 (open). After L levels the points
    // at x ∈ [3, 8] lie on the cubic: they are out of reach of the linear
    // phantom end points (the scheme's support is 3 coarse intervals).
    let h = 1.0;
    let samples: Vec<Point3> = (0..12).map(|i| cubic(i as f64 * h)).collect();
    let scheme = CurveScheme::FourPoint { tension: 1.0 / 16.0 };
    for levels in 1..=4 {
        let fine = scheme.refine_levels(&samples, false, levels);
        let stride = (1 << levels) as f64;
        for (j, &p) in fine.iter().enumerate() {
            let x = j as f64 / stride * h;
            if (3.0..=8.0).contains(&x) {
                assert!(dist(p, cubic(x)) < 1e-12, "levels {levels}, x = {x}: {:e}", dist(p, cubic(x)));
            }
        }
    }
    // And one level next to the ends still reproduces linear data exactly.
    let line: Vec<Point3> = (0..5).map(|i| [i as f64, 2.0 * i as f64 - 1.0, 0.5]).collect();
    let fine = four_point(&line, false, 1.0 / 16.0);
    for (j, p) in fine.iter().enumerate() {
        let x = j as f64 / 2.0;
        assert!(dist(*p, [x, 2.0 * x - 1.0, 0.5]) < 1e-14);
    }
}

#[test]
fn four_point_other_tensions_do_not_reproduce_cubics() {
    // The reproduction test above can fail: ω = 1/32 leaves the cubic.
    let samples: Vec<Point3> = (0..12).map(|i| cubic(i as f64)).collect();
    let fine = four_point(&samples, false, 1.0 / 32.0);
    assert!(dist(fine[11], cubic(5.5)) > 1e-3);
}

#[test]
fn deng_ma_derivation_equals_the_four_point_rule() {
    // Deng-Ma §3.1 with the D1 sign fix reproduces the 4-point scheme.
    let mut rng = Rng::new(28);
    for closed in [true, false] {
        for n in [2, 3, 5, 9] {
            let polygon = rng.points(n, 1.0);
            let tension = rng.range(0.0, 0.125);
            let derived = four_point_via_chaikin(&polygon, closed, &vec![tension; n]);
            let direct = four_point(&polygon, closed, tension);
            assert!(max_dist(&derived, &direct) < 1e-15, "closed = {closed}, n = {n}");
            for (i, &p) in polygon.iter().enumerate() {
                assert!(dist(derived[2 * i], p) < 1e-15, "Q̄_2i = P_i");
            }
        }
    }
}

#[test]
fn printed_sign_of_q_odd_breaks_the_derivation() {
    // Correction D1 (docs/REFERENCES.md): with the printed "−" the averages are not the 4-point points.
    let polygon = [[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [2.0, 1.0, 0.0], [2.5, 2.0, 0.5], [2.0, 3.0, 1.0]];
    let w = 1.0 / 16.0;
    let (p, i) = (&polygon, 1);
    let q_even = add(p[i], scale(sub(p[i + 1], p[i - 1]), 2.0 * w));
    let q_odd_printed = sub(p[i + 1], scale(sub(p[i], p[i + 2]), 2.0 * w));
    let printed = lin2(0.5, q_even, 0.5, q_odd_printed);
    let direct = four_point(&polygon, false, w)[2 * i + 1];
    assert!(dist(printed, direct) > 1e-2);
}

#[test]
fn variable_tension_derivation_and_direct_rule_agree() {
    let mut rng = Rng::new(29);
    for closed in [true, false] {
        for n in [2, 4, 7] {
            let polygon = rng.points(n, 1.0);
            let tensions: Vec<f64> = (0..n).map(|_| rng.range(0.0, 0.125)).collect();
            let derived = four_point_via_chaikin(&polygon, closed, &tensions);
            let direct = four_point_variable(&polygon, closed, &tensions);
            assert!(max_dist(&derived, &direct) < 1e-15, "closed = {closed}, n = {n}");
            for (i, &p) in polygon.iter().enumerate() {
                assert_eq!(direct[2 * i], p);
            }
        }
    }
}

#[test]
fn constant_variable_tension_is_the_uniform_scheme() {
    let mut rng = Rng::new(30);
    let polygon = rng.points(6, 1.0);
    for closed in [true, false] {
        let a = four_point_variable(&polygon, closed, &[0.05; 6]);
        let b = four_point(&polygon, closed, 0.05);
        assert!(max_dist(&a, &b) < 1e-15);
    }
}

#[test]
fn output_sizes() {
    let p = Rng::new(31).points(5, 1.0);
    assert_eq!(chaikin(&p, true).len(), 10);
    assert_eq!(chaikin(&p, false).len(), 8);
    assert_eq!(cubic_bspline(&p, true).len(), 10);
    assert_eq!(cubic_bspline(&p, false).len(), 9);
    assert_eq!(four_point(&p, true, 0.0625).len(), 10);
    assert_eq!(four_point(&p, false, 0.0625).len(), 9);
    assert_eq!(chaikin(&p[..2], false).len(), 3);
    for scheme in [CurveScheme::Chaikin, CurveScheme::CubicBSpline, CurveScheme::default()] {
        assert_eq!(scheme.refine(&p[..1], true), &p[..1]);
        assert!(scheme.refine(&[], false).is_empty());
        assert_eq!(scheme.refine_levels(&p, true, 0), p);
    }
    assert_eq!(CurveScheme::default(), CurveScheme::FourPoint { tension: 1.0 / 16.0 });
}

fn polygon_strategy() -> impl Strategy<Value = Vec<Point3>> {
    prop::collection::vec(prop::array::uniform3(-10.0f64..10.0), 3..20)
}

proptest! {
    #[test]
    fn chaikin_closed_keeps_the_vertex_centroid(polygon in polygon_strategy()) {
        let (a, b) = (crate::centroid(&polygon), crate::centroid(&chaikin(&polygon, true)));
        prop_assert!(dist(a, b) < 1e-12);
    }

    #[test]
    fn four_point_interpolates_and_matches_its_derivation(
        polygon in polygon_strategy(),
        tension in 0.0f64..0.125,
        closed in any::<bool>(),
    ) {
        let fine = four_point(&polygon, closed, tension);
        for (i, &p) in polygon.iter().enumerate() {
            prop_assert_eq!(fine[2 * i], p);
        }
        let derived = four_point_via_chaikin(&polygon, closed, &vec![tension; polygon.len()]);
        prop_assert!(max_dist(&fine, &derived) < 1e-13);
    }

    #[test]
    fn cubic_bspline_points_are_local_averages(polygon in polygon_strategy(), closed in any::<bool>()) {
        // Each refined point lies in the bounding box of the coarse polygon.
        let fine = cubic_bspline(&polygon, closed);
        for c in 0..3 {
            let lo = polygon.iter().map(|p| p[c]).fold(f64::INFINITY, f64::min);
            let hi = polygon.iter().map(|p| p[c]).fold(f64::NEG_INFINITY, f64::max);
            prop_assert!(fine.iter().all(|p| p[c] >= lo - 1e-12 && p[c] <= hi + 1e-12));
        }
    }
}
