//! Shared helpers of the integration tests: dense references computed
//! independently of the crate's kernels (nalgebra on the materialised A).
#![allow(dead_code)]

use nalgebra::{DMatrix, SymmetricEigen};
use subdiv_solve::{internals::model_problems, FactoredMatrix};

/// Dense A = D·S, built entry by entry from the public parts.
pub fn dense_a(a: &FactoredMatrix) -> DMatrix<f64> {
    let n = a.n();
    let mut m = DMatrix::zeros(n, n);
    for (&v, (i, j)) in a.s().iter() {
        let (i, j) = (i as usize, j as usize);
        m[(i, j)] += a.d()[i] * v;
    }
    m
}

/// Independent max_i ‖P_i − (A X)_i‖₂ (dense product, no crate code).
pub fn max_row_residual(a: &DMatrix<f64>, x: &[[f64; 3]], p: &[[f64; 3]]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| {
            let mut r = p[i];
            for j in 0..n {
                let aij = a[(i, j)];
                if aij != 0.0 {
                    for c in 0..3 {
                        r[c] -= aij * x[j][c];
                    }
                }
            }
            (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt()
        })
        .fold(0.0, f64::max)
}

/// Dense solution and ‖A⁻¹‖_∞ (max row sum of |A⁻¹|): for any X,
/// max_i ‖X_i − X*_i‖ ≤ ‖A⁻¹‖_∞ · max_j ‖r_j‖ (triangle inequality per row).
pub fn reference(a: &DMatrix<f64>, p: &[[f64; 3]]) -> (Vec<[f64; 3]>, f64) {
    let n = p.len();
    let inv = a.clone().try_inverse().expect("reference matrix is invertible");
    let norm_inf = (0..n).map(|i| (0..n).map(|j| inv[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max);
    let b = DMatrix::from_fn(n, 3, |i, c| p[i][c]);
    let x = &inv * b;
    ((0..n).map(|i| [x[(i, 0)], x[(i, 1)], x[(i, 2)]]).collect(), norm_inf)
}

/// Max row distance of two n × 3 arrays.
pub fn max_row_gap(x: &[[f64; 3]], y: &[[f64; 3]]) -> f64 {
    x.iter()
        .zip(y)
        .map(|(u, v)| ((u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2) + (u[2] - v[2]).powi(2)).sqrt())
        .fold(0.0, f64::max)
}

/// Sorted eigenvalues of A via the symmetric similarity D^{1/2} S D^{1/2}
/// (computed densely, independently of the crate).
pub fn eigenvalues(a: &FactoredMatrix) -> Vec<f64> {
    let n = a.n();
    let mut h = DMatrix::zeros(n, n);
    for (&v, (i, j)) in a.s().iter() {
        let (i, j) = (i as usize, j as usize);
        h[(i, j)] += a.d()[i].sqrt() * v * a.d()[j].sqrt();
    }
    let h = (&h + h.transpose()) * 0.5;
    let mut ev: Vec<f64> = SymmetricEigen::new(h).eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    ev
}

/// Deterministic pseudo-random data in [−1, 1]³ per row.
pub fn data(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    (0..n).map(|_| [next(), next(), next()]).collect()
}

/// The test matrices (a)-(c) of the brief, each with a name.
pub fn nonsingular_cases() -> Vec<(&'static str, FactoredMatrix)> {
    vec![
        ("(a) random SPD", model_problems::random_spd(400, 8, 11)),
        ("(b) bicubic torus 20x24", model_problems::bicubic_torus(20, 24)),
        ("(c) Loop grid 18x21", model_problems::loop_regular(18, 21)),
    ]
}

/// An indefinite matrix of moderate size: the bicubic torus with S shifted
/// by −5 (S's spectrum [4, 36] becomes [−1, 31]); D = 1/36.
pub fn shifted_torus(nx: usize, ny: usize) -> FactoredMatrix {
    let t = model_problems::bicubic_torus(nx, ny);
    let (d, s) = t.into_parts();
    let mut tri = sprs::TriMatI::<f64, u32>::new((s.rows(), s.cols()));
    for (&v, (i, j)) in s.iter() {
        let (i, j) = (i as usize, j as usize);
        tri.add_triplet(i, j, if i == j { v - 5.0 } else { v });
    }
    FactoredMatrix::new(d, tri.to_csr()).unwrap()
}

/// `mesh` with interior valence-2 vertices inserted (`subdiv_mesh::shapes::split_edges`):
/// every edge in `singles` gets one new vertex (the two faces then share two
/// consecutive edges), every edge in `doubles` two adjacent ones (the edge
/// (a, b) becomes a–w–v–b in both faces: the second split cuts (a, v)).
pub fn with_valence_two(mesh: &subdiv_mesh::Mesh, singles: &[u32], doubles: &[u32]) -> subdiv_mesh::Mesh {
    use subdiv_mesh::{shapes::split_edges, EdgeId};
    let t = mesh.topology();
    let firsts: Vec<EdgeId> = singles.iter().chain(doubles).map(|&e| EdgeId(e)).collect();
    let ends: Vec<(u32, u32)> = doubles
        .iter()
        .map(|&e| {
            let (a, _) = t.edge_vertices(EdgeId(e));
            a.0
        })
        .zip(t.vertex_count() as u32 + singles.len() as u32..)
        .collect();
    let once = split_edges(mesh, &firsts, 0.1);
    let t1 = once.topology();
    let seconds: Vec<EdgeId> = ends
        .iter()
        .map(|&(a, v)| {
            t1.edges()
                .find(|&e| {
                    let (x, y) = t1.edge_vertices(e);
                    (x.0, y.0) == (a, v) || (x.0, y.0) == (v, a)
                })
                .expect("the first split made the edge (a, v)")
        })
        .collect();
    split_edges(&once, &seconds, 0.1)
}

/// Cheng's Catmull-Clark limit matrix A = D·S of `mesh` (`subdiv-stencil`),
/// its vertices as data, and the bounding-box diagonal.
pub fn cheng_system(mesh: &subdiv_mesh::Mesh) -> (FactoredMatrix, Vec<[f64; 3]>, f64) {
    let lm = subdiv_stencil::limit_matrix_catmull_clark(mesh.topology());
    let a = FactoredMatrix::new(lm.d, lm.s).expect("limit matrices are valid");
    (a, mesh.positions().iter().map(|q| q.to_array()).collect(), mesh.bbox_diagonal())
}

/// Data A·X (consistent) and the same with D·kernel added to columns x and z
/// (inconsistent: the range of A = D·S is D·kernel^⊥).
pub fn consistent_and_inconsistent(a: &FactoredMatrix, kernel: &[f64], seed: u64) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let x: Vec<[f64; 3]> = data(a.n(), seed);
    let mut p = vec![[0.0; 3]; a.n()];
    a.apply(&x, &mut p);
    // The range of A = D·S is D·k^⊥: adding D·k leaves it.
    let q = p
        .iter()
        .enumerate()
        .map(|(i, r)| [r[0] + 0.3 * a.d()[i] * kernel[i], r[1], r[2] - 0.1 * a.d()[i] * kernel[i]])
        .collect();
    (p, q)
}

/// The bicubic torus with S shifted by its smallest eigenvalue 4 (nx, ny even):
/// S − 4I is positive semi-definite with the checkerboard (−1)^{x+y} as kernel.
pub fn singular_torus(nx: usize, ny: usize) -> (FactoredMatrix, Vec<f64>) {
    let (d, s) = model_problems::bicubic_torus(nx, ny).into_parts();
    let mut tri = sprs::TriMatI::<f64, u32>::new((s.rows(), s.cols()));
    for (&v, (i, j)) in s.iter() {
        let (i, j) = (i as usize, j as usize);
        tri.add_triplet(i, j, if i == j { v - 4.0 } else { v });
    }
    let kernel = (0..nx * ny).map(|i| if (i % nx + i / nx) % 2 == 0 { 1.0 } else { -1.0 }).collect();
    (FactoredMatrix::new(d, tri.to_csr()).unwrap(), kernel)
}
