//! Model limit matrices with known spectra, built without meshes: the shared
//! corpus of this crate's tests and benches (hidden module, not covered
//! by semver).
//!
//! | constructor | what | spectrum of A |
//! |---|---|---|
//! | [`bicubic_torus`] | regular Catmull-Clark limit mask on an nx × ny periodic grid | (4 + 2cos a)(4 + 2cos b)/36 ⊂ [1/9, 1] |
//! | [`loop_regular`] | regular Loop limit mask on a periodic triangular grid | ½ + (cos a + cos b + cos(a−b))/6 ⊂ [¼, 1] |
//! | [`random_spd`] | random sparse S, strictly diagonally dominant, random positive D | ⊂ (0, 1] |
//! | [`random_indefinite`] | as `random_spd` with the sign of chosen rows' diagonal flipped | exactly `negatives` eigenvalues < 0, all \|λ\| bounded away from 0 |
//! | [`random_nonsymmetric`] | random sparse S, not symmetric, strictly diagonally dominant by rows and columns | Re λ > 0 (Gershgorin) |
//! | [`cube_checkerboard`] | Cheng's A on the cube (all valence 3, bipartite) | {1, ½ (×3), ⅙ (×3), 0}: singular, kernel = checkerboard |
//! | [`pillow`] | Cheng's A on two quads glued along their boundary (valence 2) | {1, 1/7, 1/7, −1/7}: indefinite |
//!
//! The regular masks: a regular Catmull-Clark vertex has
//! limit (n²v + 4Σe + Σf)/(n(n+5)) after one step, which composed with the
//! step gives 4/9 centre, 1/9 per edge neighbour, 1/36 per diagonal
//! neighbour; Loop's regular limit is ½ centre + 1/12 per neighbour.

use sprs::TriMatI;

use crate::kernels::splitmix_unit;
use crate::matrix::{FactoredMatrix, SparseMatrix};

fn build(n: usize, d: Vec<f64>, entries: impl Iterator<Item = (usize, usize, f64)>) -> FactoredMatrix {
    let mut t = TriMatI::<f64, u32>::new((n, n));
    for (i, j, v) in entries {
        t.add_triplet(i, j, v);
    }
    let s: SparseMatrix = t.to_csr();
    FactoredMatrix::new(d, s).expect("model problems are valid by construction")
}

/// Regular bicubic (Catmull-Clark) limit matrix on an `nx` × `ny` torus:
/// A = D·S with D = 1/36, S = 16 on the centre, 4 on the four edge
/// neighbours, 1 on the four diagonal neighbours. Row x + nx·y.
/// Spectrum (4 + 2cos 2πi/nx)(4 + 2cos 2πj/ny)/36; λ_min = 1/9 when nx and
/// ny are even.
///
/// # Panics
/// When `nx < 3` or `ny < 3` (neighbours would coincide).
pub fn bicubic_torus(nx: usize, ny: usize) -> FactoredMatrix {
    assert!(nx >= 3 && ny >= 3, "bicubic_torus needs nx, ny ≥ 3");
    let n = nx * ny;
    let entries = (0..n).flat_map(move |i| {
        let (x, y) = (i % nx, i / nx);
        let at = move |dx: usize, dy: usize| (x + dx) % nx + nx * ((y + dy) % ny);
        let (l, r, u, b) = (nx - 1, 1, 1, ny - 1);
        [
            (i, i, 16.0),
            (i, at(r, 0), 4.0),
            (i, at(l, 0), 4.0),
            (i, at(0, u), 4.0),
            (i, at(0, b), 4.0),
            (i, at(r, u), 1.0),
            (i, at(l, u), 1.0),
            (i, at(r, b), 1.0),
            (i, at(l, b), 1.0),
        ]
    });
    build(n, vec![1.0 / 36.0; n], entries)
}

/// Regular Loop limit matrix on an `nx` × `ny` periodic triangular grid
/// (neighbours (±1, 0), (0, ±1), (1, −1), (−1, 1)): A = D·S with D = 1/12,
/// S = 6 on the centre and 1 on the six neighbours. λ_min = ¼ when nx and ny
/// are multiples of 3.
///
/// # Panics
/// When `nx < 3` or `ny < 3`.
pub fn loop_regular(nx: usize, ny: usize) -> FactoredMatrix {
    assert!(nx >= 3 && ny >= 3, "loop_regular needs nx, ny ≥ 3");
    let n = nx * ny;
    let entries = (0..n).flat_map(move |i| {
        let (x, y) = (i % nx, i / nx);
        let at = move |dx: usize, dy: usize| (x + dx) % nx + nx * ((y + dy) % ny);
        [
            (i, i, 6.0),
            (i, at(1, 0), 1.0),
            (i, at(nx - 1, 0), 1.0),
            (i, at(0, 1), 1.0),
            (i, at(0, ny - 1), 1.0),
            (i, at(1, ny - 1), 1.0),
            (i, at(nx - 1, 1), 1.0),
        ]
    });
    build(n, vec![1.0 / 12.0; n], entries)
}

/// A random A = D·S of size n: S symmetric with about `neighbours` random
/// positive off-diagonal entries per row (weights in (0.1, 1]), diagonal
/// 1.5 × the off-diagonal row sum + 0.1 (strictly diagonally dominant, so
/// SPD with κ(S) ≲ 5); d_i = u_i / (row sum of S), u_i ∈ [0.8, 1], so A's
/// rows sum to at most 1 and spec(A) ⊂ (0, 1]. Deterministic in `seed`.
pub fn random_spd(n: usize, neighbours: usize, seed: u64) -> FactoredMatrix {
    let rnd = |k: u64| 0.5 * (splitmix_unit(seed, k) + 1.0); // [0, 1)
    let mut off: Vec<(usize, usize, f64)> = Vec::new();
    let mut ctr = 0u64;
    if n > 1 {
        for i in 0..n {
            for _ in 0..neighbours.div_ceil(2) {
                let j = (rnd(ctr) * n as f64) as usize % n;
                let w = 0.1 + 0.9 * rnd(ctr + 1);
                ctr += 2;
                if j != i {
                    off.push((i, j, w));
                    off.push((j, i, w));
                }
            }
        }
    }
    let mut offsum = vec![0.0; n];
    for &(i, _, w) in &off {
        offsum[i] += w;
    }
    let diag: Vec<f64> = offsum.iter().map(|o| 1.5 * o + 0.1).collect();
    let d: Vec<f64> = (0..n).map(|i| (0.8 + 0.2 * rnd(ctr + i as u64)) / (diag[i] + offsum[i])).collect();
    build(n, d, off.into_iter().chain(diag.iter().enumerate().map(|(i, &v)| (i, i, v))))
}

/// A random symmetric **indefinite** A = D·S of size n with exactly
/// `negatives` negative eigenvalues (rows 0, ⌈n/negatives⌉, … — spread out).
///
/// S is [`random_spd`]'s pattern and weights with the diagonal of the chosen
/// rows negated: s_ii = ±(1.5·o_i + 0.1), o_i the off-diagonal row sum. The
/// Gershgorin discs of the negated rows lie in (−∞, −0.1), the others in
/// (0.1, ∞), so S has exactly `negatives` negative eigenvalues, every |λ(S)|
/// ≥ 0.1 + ½·min o_i, and A (similar to D^{1/2}SD^{1/2}, congruent to S) has
/// the same inertia. d_i = u_i/(|s_ii| + o_i), u_i ∈ [0.8, 1], so |λ(A)| ≤ 1.
/// Deterministic in `seed`.
///
/// # Panics
/// When `negatives > n` (a caller bug).
pub fn random_indefinite(n: usize, neighbours: usize, negatives: usize, seed: u64) -> FactoredMatrix {
    assert!(negatives <= n, "random_indefinite: {negatives} negative eigenvalues asked of a {n} × {n} matrix");
    let (d, s) = random_spd(n, neighbours, seed).into_parts();
    let stride = if negatives == 0 { usize::MAX } else { n.div_ceil(negatives) };
    let flipped = |i: usize| negatives > 0 && i % stride == 0 && i / stride < negatives;
    let entries: Vec<(usize, usize, f64)> = s
        .iter()
        .map(|(&v, (i, j))| (i as usize, j as usize, v))
        .map(|(i, j, v)| (i, j, if i == j && flipped(i) { -v } else { v }))
        .collect();
    build(n, d, entries.into_iter())
}

/// A random **nonsymmetric** A = D·S of size n (S flagged non-symmetric by
/// [`FactoredMatrix::new`]): about `neighbours` random off-diagonal entries
/// per row, each (i, j) with an independent weight in (0.1, 1] and its
/// mirror (j, i) present with probability ½ and its own weight; diagonal
/// 1.5 × max(off-diagonal row sum, column sum) + 0.1, so S is strictly
/// diagonally dominant by rows and by columns (Re λ > 0, and A is well
/// conditioned); d_i = u_i/(row sum of |S|), u_i ∈ [0.8, 1]. Deterministic in `seed`.
pub fn random_nonsymmetric(n: usize, neighbours: usize, seed: u64) -> FactoredMatrix {
    let rnd = |k: u64| 0.5 * (splitmix_unit(seed ^ 0xA5A5_5A5A_0F0F_F0F0, k) + 1.0); // [0, 1)
    let mut off: Vec<(usize, usize, f64)> = Vec::new();
    let mut ctr = 0u64;
    if n > 1 {
        for i in 0..n {
            for _ in 0..neighbours.div_ceil(2) {
                let j = (rnd(ctr) * n as f64) as usize % n;
                let (w, w_mirror, mirrored) = (0.1 + 0.9 * rnd(ctr + 1), 0.1 + 0.9 * rnd(ctr + 2), rnd(ctr + 3) < 0.5);
                ctr += 4;
                if j != i {
                    off.push((i, j, w));
                    if mirrored {
                        off.push((j, i, w_mirror));
                    }
                }
            }
        }
    }
    let (mut row_sum, mut col_sum) = (vec![0.0; n], vec![0.0; n]);
    for &(i, j, w) in &off {
        row_sum[i] += w;
        col_sum[j] += w;
    }
    let diag: Vec<f64> = (0..n).map(|i| 1.5 * row_sum[i].max(col_sum[i]) + 0.1).collect();
    let d: Vec<f64> = (0..n).map(|i| (0.8 + 0.2 * rnd(ctr + i as u64)) / (diag[i] + row_sum[i])).collect();
    build(n, d, off.into_iter().chain(diag.iter().enumerate().map(|(i, &v)| (i, i, v))))
}

/// Cheng's Catmull-Clark limit matrix of the cube (8 vertices of valence 3,
/// 6 quads; appendix Eq. 5 with [correction C1]): D = 1/6, S = 9/4 on the
/// diagonal, 1 for the 3 edge neighbours, ¼ for the 3 face-diagonal
/// neighbours. Vertex i has coordinates (i & 1, i >> 1 & 1, i >> 2 & 1).
/// Singular: the checkerboard (−1)^{popcount(i)} is in its kernel ([correction C3]).
///
/// [correction C1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1
/// [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3
pub fn cube_checkerboard() -> FactoredMatrix {
    let entries = (0..8usize).flat_map(|i| {
        (0..8usize).filter_map(move |j| match (i ^ j).count_ones() {
            0 => Some((i, j, 9.0 / 4.0)),
            1 => Some((i, j, 1.0)),
            2 => Some((i, j, 0.25)),
            _ => None,
        })
    });
    build(8, vec![1.0 / 6.0; 8], entries)
}

/// The checkerboard kernel vector of [`cube_checkerboard`]: (−1)^{popcount(i)}.
pub fn cube_kernel() -> Vec<f64> {
    (0..8u32).map(|i| if i.count_ones() % 2 == 0 { 1.0 } else { -1.0 }).collect()
}

/// Cheng's Catmull-Clark limit matrix of the pillow: two quads (0,1,2,3) and
/// (3,2,1,0), every vertex of valence 2. D = 4/(n(n+5)) = 2/7; S is the
/// circulant (1, 1, ½, 1). Spectrum {1, 1/7, 1/7, −1/7}: indefinite and
/// nonsingular ([correction C3]); plain PIA diverges.
///
/// [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3
pub fn pillow() -> FactoredMatrix {
    let c = [1.0, 1.0, 0.5, 1.0];
    let entries = (0..4usize).flat_map(move |i| (0..4usize).map(move |j| (i, j, c[(j + 4 - i) % 4])));
    build(4, vec![2.0 / 7.0; 4], entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row_sums(a: &FactoredMatrix) -> Vec<f64> {
        let ones = vec![[1.0; 3]; a.n()];
        let mut out = vec![[0.0; 3]; a.n()];
        a.apply(&ones, &mut out);
        out.iter().map(|r| r[0]).collect()
    }

    #[test]
    fn limit_masks_have_unit_row_sums_and_symmetric_s() {
        for a in [bicubic_torus(5, 4), loop_regular(6, 3), cube_checkerboard(), pillow()] {
            assert!(a.symmetric());
            for s in row_sums(&a) {
                assert!((s - 1.0).abs() < 1e-14, "row sum {s}");
            }
        }
        let a = bicubic_torus(4, 4);
        assert_eq!(a.nnz(), 16 * 9);
        let r = random_spd(300, 6, 7);
        assert!(r.symmetric());
        assert!(row_sums(&r).iter().all(|&s| s <= 1.0 + 1e-15 && s > 0.0));
    }

    #[test]
    fn cube_kernel_is_in_the_null_space() {
        let a = cube_checkerboard();
        let k: Vec<[f64; 3]> = cube_kernel().iter().map(|&v| [v; 3]).collect();
        let mut out = vec![[0.0; 3]; 8];
        a.apply(&k, &mut out);
        assert!(out.iter().all(|r| r.iter().all(|v| v.abs() < 1e-15)));
    }
}
