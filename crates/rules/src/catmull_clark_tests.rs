use super::*;
use crate::test_util::{dominant_left_eigenvector, Rng};
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
