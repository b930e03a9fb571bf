use super::*;
use crate::test_util::{dominant_left_eigenvector, left_fixed_point, Rng};
use crate::vec3::{add, dist, scale, Point3};

#[test]
fn masks_sum_to_one() {
    for n in 2..=12 {
        let v = vertex_point_mask(VertexKind::Interior, n);
        assert!((v.total(n, 0, n) - 1.0).abs() < 1e-15, "vertex point n = {n}");
        let l = limit_mask(VertexKind::Interior, n);
        assert!((l.total(n, 0, n) - 1.0).abs() < 1e-15, "limit n = {n}");
        // A boundary vertex in k = n − 1 faces has two boundary neighbours.
        for mask in [vertex_point_mask(VertexKind::Boundary, n), limit_mask(VertexKind::Boundary, n)] {
            assert!((mask.total(n - 2, 2, n - 1) - 1.0).abs() < 1e-15);
        }
        for mask in [vertex_point_mask(VertexKind::Corner, 2), limit_mask(VertexKind::Corner, 2)] {
            assert_eq!(mask.total(0, 2, 1), 1.0);
        }
    }
    for ml in 3..=12 {
        assert!((face_point_weight(ml) * ml as f64 - 1.0).abs() < 1e-15);
        assert_eq!(edge_point_mask(ml, None).total(ml, None), 1.0);
        for mr in 3..=12 {
            let e = edge_point_mask(ml, Some(mr));
            assert!((e.total(ml, Some(mr)) - 1.0).abs() < 1e-15, "edge {ml}/{mr}");
        }
    }
    let mut rng = Rng::new(1);
    for n in 2..=12 {
        let sizes: Vec<usize> = (0..n).map(|_| rng.usize(3, 9)).collect();
        let (mut e, mut f) = (vec![0.0; n], vec![0.0; n]);
        let v = limit_stencil(&sizes, &mut e, &mut f);
        let far: f64 = sizes.iter().zip(&f).map(|(&m, w)| (m - 3) as f64 * w).sum();
        let total = v + e.iter().sum::<f64>() + far;
        assert!((total - 1.0).abs() < 1e-14, "Eq. 5 row sum {total} for {sizes:?}");
    }
}

/// A vertex V of valence n with faces of sizes `sizes`, random positions:
/// face i = (V, E_i, F_1^i, …, F_{m_i−3}^i, E_{i+1}).
struct Star {
    v: Point3,
    e: Vec<Point3>,
    far: Vec<Vec<Point3>>,
}

impl Star {
    fn random(rng: &mut Rng, sizes: &[usize]) -> Self {
        Self {
            v: rng.point(1.0),
            e: rng.points(sizes.len(), 1.0),
            far: sizes.iter().map(|&m| rng.points(m - 3, 1.0)).collect(),
        }
    }
    fn n(&self) -> usize {
        self.e.len()
    }
    /// Corners of face i other than V and E_i (E_{i+1} and the far corners).
    fn others_after(&self, i: usize) -> Vec<Point3> {
        let mut c = self.far[i].clone();
        c.push(self.e[(i + 1) % self.n()]);
        c
    }
    /// Corners of face i other than V and E_{i+1} (E_i and the far corners).
    fn others_before(&self, i: usize) -> Vec<Point3> {
        let mut c = self.far[i].clone();
        c.push(self.e[i]);
        c
    }
}

fn sum(points: &[Point3]) -> Point3 {
    points.iter().fold([0.0; 3], |s, &p| add(s, p))
}

/// Eq. 5 applied to a star.
fn eq5(star: &Star, sizes: &[usize]) -> Point3 {
    let n = star.n();
    let (mut ew, mut fw) = (vec![0.0; n], vec![0.0; n]);
    let vw = limit_stencil(sizes, &mut ew, &mut fw);
    let mut p = scale(star.v, vw);
    for i in 0..n {
        p = add(p, scale(star.e[i], ew[i]));
        p = add(p, scale(sum(&star.far[i]), fw[i]));
    }
    p
}

/// One Catmull-Clark step around V written out from Cheng's Appendix Eq. 4
/// (C2-corrected), then the quad limit mask — all
/// straight from the formulas, none from this module.
fn step_then_limit(star: &Star, sizes: &[usize]) -> Point3 {
    let n = star.n();
    let nf = n as f64;
    let f: Vec<Point3> =
        (0..n).map(|i| scale(add(add(star.v, star.e[i]), sum(&star.others_after(i))), 1.0 / sizes[i] as f64)).collect();
    let e: Vec<Point3> = (0..n)
        .map(|i| {
            // Correction C2 (docs/REFERENCES.md): edge VE_i lies in faces i−1 and i.
            scale(add(add(star.v, star.e[i]), add(f[(i + n - 1) % n], f[i])), 0.25)
        })
        .collect();
    let v = add(scale(star.v, (nf - 2.0) / nf), scale(add(sum(&star.e), sum(&f)), 1.0 / (nf * nf)));
    let d = 1.0 / (nf * (nf + 5.0));
    add(scale(v, nf * nf * d), add(scale(sum(&e), 4.0 * d), scale(sum(&f), d)))
}

#[test]
fn eq5_equals_one_step_then_the_limit_mask() {
    // The independent check of Eq. 5 (with corrections C1/C2, docs/REFERENCES.md).
    let mut rng = Rng::new(2);
    for n in 2..=12 {
        for _ in 0..20 {
            let sizes: Vec<usize> = (0..n).map(|_| rng.usize(3, 8)).collect();
            let star = Star::random(&mut rng, &sizes);
            let a = eq5(&star, &sizes);
            let b = step_then_limit(&star, &sizes);
            assert!(dist(a, b) < 1e-14, "n = {n}, sizes {sizes:?}: {:e}", dist(a, b));
        }
    }
}

#[test]
fn step_masks_reproduce_the_written_out_step() {
    // The masks of this module, composed as the stencil builder will, give
    // the same limit as the formulas.
    let mut rng = Rng::new(4);
    for n in 2..=9 {
        let sizes: Vec<usize> = (0..n).map(|_| rng.usize(3, 7)).collect();
        let star = Star::random(&mut rng, &sizes);
        let f: Vec<Point3> = (0..n)
            .map(|i| {
                let w = face_point_weight(sizes[i]);
                scale(add(add(star.v, star.e[i]), sum(&star.others_after(i))), w)
            })
            .collect();
        let e: Vec<Point3> = (0..n)
            .map(|i| {
                let prev = (i + n - 1) % n;
                let mask = edge_point_mask(sizes[prev], Some(sizes[i]));
                add(
                    scale(add(star.v, star.e[i]), mask.end),
                    add(
                        scale(sum(&star.others_before(prev)), mask.left),
                        scale(sum(&star.others_after(i)), mask.right),
                    ),
                )
            })
            .collect();
        let vm = vertex_point_mask(VertexKind::Interior, n);
        let v = add(scale(star.v, vm.vertex), add(scale(sum(&star.e), vm.interior_neighbor), scale(sum(&f), vm.face)));
        let lm = limit_mask(VertexKind::Interior, n);
        let limit = add(scale(v, lm.vertex), add(scale(sum(&e), lm.interior_neighbor), scale(sum(&f), lm.face)));
        assert!(dist(limit, step_then_limit(&star, &sizes)) < 1e-14, "n = {n}");
    }
}

#[test]
fn interior_limit_mask_is_the_left_eigenvector_of_the_quad_one_ring() {
    // Nodes: 0 = V, 1..=n = E_i, n+1..=2n = F_i (quad i = V, E_i, F_i, E_{i+1}).
    for n in 3..=12 {
        let size = 2 * n + 1;
        let (e, f) = (|i: usize| 1 + i % n, |i: usize| 1 + n + i % n);
        let face_point = |i: usize| {
            let mut row = vec![0.0; size];
            for node in [0, e(i), f(i), e(i + 1)] {
                row[node] += 0.25;
            }
            row
        };
        let mut s = vec![vec![0.0; size]; size];
        let nf = n as f64;
        s[0][0] = (nf - 2.0) / nf;
        for i in 0..n {
            s[0][e(i)] += 1.0 / (nf * nf);
            for (k, w) in face_point(i).iter().enumerate() {
                s[0][k] += w / (nf * nf);
            }
            let (fp, fc) = (face_point(i + n - 1), face_point(i));
            s[e(i)][0] += 0.25;
            s[e(i)][e(i)] += 0.25;
            for k in 0..size {
                s[e(i)][k] += 0.25 * (fp[k] + fc[k]);
            }
            s[f(i)] = fc;
        }
        let l = dominant_left_eigenvector(&s);
        let mask = limit_mask(VertexKind::Interior, n);
        assert!((l[0] - mask.vertex).abs() < 1e-12, "n = {n}: V weight {} vs {}", l[0], mask.vertex);
        for i in 0..n {
            assert!((l[e(i)] - mask.interior_neighbor).abs() < 1e-12, "n = {n}: E weight");
            assert!((l[f(i)] - mask.face).abs() < 1e-12, "n = {n}: F weight");
        }
    }
}

#[test]
fn boundary_limit_mask_is_the_left_eigenvector_of_the_boundary_curve() {
    // Nodes B₋, V, B₊ → new b₋ (midpoint), v ((1,6,1)/8), b₊ (midpoint).
    let vm = vertex_point_mask(VertexKind::Boundary, 3);
    let em = edge_point_mask(4, None);
    let s = vec![
        vec![em.end, em.end, 0.0],
        vec![vm.boundary_neighbor, vm.vertex, vm.boundary_neighbor],
        vec![0.0, em.end, em.end],
    ];
    let l = dominant_left_eigenvector(&s);
    let lm = limit_mask(VertexKind::Boundary, 3);
    assert!((l[0] - lm.boundary_neighbor).abs() < 1e-14);
    assert!((l[1] - lm.vertex).abs() < 1e-14);
}

#[test]
fn regular_masks_are_the_bicubic_bspline_ones() {
    let v = vertex_point_mask(VertexKind::Interior, 4);
    assert_eq!((v.vertex, v.interior_neighbor, v.face), (0.5, 1.0 / 16.0, 1.0 / 16.0));
    let l = limit_mask(VertexKind::Interior, 4);
    // (1/36)[16 V + 4 ΣE + ΣF]
    assert!((l.vertex - 16.0 / 36.0).abs() < 1e-16 && (l.face - 1.0 / 36.0).abs() < 1e-16);
    let e = edge_point_mask(4, Some(4));
    assert_eq!(e.end * 16.0, 6.0);
}

#[test]
fn face_point_weight_is_the_correctly_rounded_reciprocal() {
    for m in 3..200 {
        assert_eq!(face_point_weight(m).to_bits(), (1.0 / m as f64).to_bits(), "m = {m}");
    }
}

/// The (2n+1)×(2n+1) subdivision matrix of a dart's closed 1-ring on an
/// all-quad fan. Nodes: 0 = V, 1..=n = Eᵢ, n+1..=2n = Fᵢ (quad i = V, Eᵢ, Fᵢ,
/// Eᵢ₊₁); VE₀ is infinitely sharp: E₀' = (V + E₀)/2, the rest smooth,
/// assembled from this module's step masks.
fn dart_one_ring(n: usize) -> Vec<Vec<f64>> {
    let size = 2 * n + 1;
    let (e, f) = (|i: usize| 1 + i % n, |i: usize| 1 + n + i % n);
    let face_point = |i: usize| {
        let mut row = vec![0.0; size];
        for node in [0, e(i), f(i), e(i + 1)] {
            row[node] += face_point_weight(4);
        }
        row
    };
    let vm = vertex_point_mask(VertexKind::Interior, n);
    let (smooth, crease) = (edge_point_mask(4, Some(4)), edge_point_mask(4, None));
    let mut s = vec![vec![0.0; size]; size];
    // V's own weight in one expression: n face-point shares added one by one
    // would round n times (1e-14 at n = 100).
    s[0][0] = vm.vertex + n as f64 * vm.face * face_point_weight(4);
    for i in 0..n {
        s[0][e(i)] += vm.interior_neighbor;
        for (k, w) in face_point(i).iter().enumerate().skip(1) {
            s[0][k] += vm.face * w;
        }
        if i == 0 {
            s[e(0)][0] += crease.end;
            s[e(0)][e(0)] += crease.end;
        } else {
            // The edge mask's end weight holds the face points' share of the ends.
            s[e(i)][0] += smooth.end;
            s[e(i)][e(i)] += smooth.end;
            for node in [e(i - 1), f(i - 1)] {
                s[e(i)][node] += smooth.left;
            }
            for node in [f(i), e(i + 1)] {
                s[e(i)][node] += smooth.right;
            }
        }
        s[f(i)] = face_point(i);
    }
    s
}

/// The mask as one row over [`dart_one_ring`]'s nodes.
fn dart_row(mask: &DartMask) -> Vec<f64> {
    let mut row = vec![mask.vertex];
    row.extend(&mask.edge);
    row.extend(&mask.far_corner);
    row
}

const DART_VALENCES: [usize; 15] = [2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 16, 30, 100, 160];

#[test]
fn dart_mask_sums_to_one_at_any_valence() {
    for n in DART_VALENCES.into_iter().chain([1000, 100_000]) {
        let mask = dart_limit_mask(n);
        assert_eq!((mask.edge.len(), mask.far_corner.len()), (n, n));
        // The sum of n weights rounds n times.
        assert!((mask.total() - 1.0).abs() < 1e-14 + 1e-16 * n as f64, "n = {n}: {}", mask.total());
        assert!(mask.edge.iter().chain(&mask.far_corner).all(|&w| w > 0.0), "n = {n}: a weight underflowed");
    }
    // No manifold fan has fewer than 2 edges: the identity, no panic.
    assert_eq!(dart_limit_mask(0), DartMask { vertex: 1.0, edge: vec![], far_corner: vec![] });
    assert_eq!(dart_limit_mask(1), DartMask { vertex: 1.0, edge: vec![0.0], far_corner: vec![0.0] });
}

#[test]
fn dart_mask_is_the_left_eigenvector_of_the_dart_one_ring() {
    for n in DART_VALENCES {
        let s = dart_one_ring(n);
        let l = dart_row(&dart_limit_mask(n));
        // lᵀS = lᵀ to round-off.
        for j in 0..s.len() {
            let image: f64 = (0..s.len()).map(|i| l[i] * s[i][j]).sum();
            assert!((image - l[j]).abs() < 1e-14, "n = {n}, column {j}: {image} vs {}", l[j]);
        }
        // The closed form is the solution of lᵀ(S − I) = 0, Σl = 1, and it is
        // the dominant one (power iteration converges to it).
        let solved = left_fixed_point(&s);
        let power = dominant_left_eigenvector(&s);
        for (j, &w) in l.iter().enumerate() {
            assert!((solved[j] - w).abs() < 1e-13, "n = {n}, node {j}: solved {} vs {w}", solved[j]);
            assert!((power[j] - w).abs() < 1e-12, "n = {n}, node {j}: power iteration {} vs {w}", power[j]);
        }
    }
}

#[test]
fn dart_mask_is_symmetric_about_the_crease_and_differs_from_the_smooth_mask() {
    for n in DART_VALENCES {
        let mask = dart_limit_mask(n);
        for i in 1..n {
            assert_eq!(mask.edge[i], mask.edge[n - i], "n = {n}, E{i}");
        }
        for i in 0..n {
            assert_eq!(mask.far_corner[i], mask.far_corner[n - 1 - i], "n = {n}, F{i}");
        }
        let smooth = limit_mask(VertexKind::Interior, n);
        assert!((mask.vertex - smooth.vertex).abs() > 1e-5, "n = {n}: V {} vs smooth {}", mask.vertex, smooth.vertex);
        assert!(mask.edge[0] > smooth.interior_neighbor, "n = {n}: the crease's end pulls");
    }
}

#[test]
fn dart_mask_in_exact_arithmetic() {
    // n = 3: (162V + 80E₀ + 60(E₁ + E₂) + 11(F₀ + F₂) + 16F₁)/400; the
    // Lucas-number form of the docs: eⱼ/(4/n²) = 1 − L₂|ₙ₋₂ⱼ|/L₂ₙ.
    let m = dart_limit_mask(3);
    let expected = [162.0, 80.0, 60.0, 60.0, 11.0, 16.0, 11.0].map(|w| w / 400.0);
    for (got, want) in dart_row(&m).iter().zip(expected) {
        assert!((got - want).abs() < 1e-16, "{got} vs {want}");
    }
    // n = 4 (solved in rationals): (752V + 210E₀ + 160(E₁ + E₃) + 180E₂ + 29(F₀ + F₃) + 44(F₁ + F₂))/1608.
    let expected = [752.0, 210.0, 160.0, 180.0, 160.0, 29.0, 44.0, 44.0, 29.0].map(|w| w / 1608.0);
    for (got, want) in dart_row(&dart_limit_mask(4)).iter().zip(expected) {
        assert!((got - want).abs() < 1e-16, "{got} vs {want}");
    }
    let lucas = |k: usize| (0..k).fold((2.0f64, 1.0f64), |(a, b), _| (b, a + b)).0;
    for n in [4usize, 5, 6, 9] {
        let u = dart_ring_shape(2.0 / (7.0 + 3.0 * 5f64.sqrt()), n);
        for (j, &uj) in u.iter().enumerate() {
            let exact = lucas(2 * n.abs_diff(2 * j)) / lucas(2 * n);
            assert!((uj - exact).abs() < 1e-15, "n = {n}, j = {j}: {uj} vs {exact}");
        }
    }
}
