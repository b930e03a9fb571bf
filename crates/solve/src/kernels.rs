//! Deterministic data-parallel building blocks: fixed row chunks, sparse
//! row products over 3-column data, in-order reductions.
//!
//! **Determinism.** Every loop splits the rows into chunks of
//! [`CHUNK_ROWS`] (independent of the thread count). A chunk is always
//! processed by one thread, front to back; per-chunk partial results land in
//! a slot array and are folded in chunk order on the calling thread. Below
//! [`PARALLEL_MIN_ROWS`] the same chunks run sequentially. So the bits of
//! every result depend on the data only, never on the pool size — rayon's
//! `sum()` over dynamic splits is never used.

use rayon::prelude::*;

use crate::tolerances::{CHUNK_ROWS, PARALLEL_MIN_ROWS};
use crate::SparseMatrix;

/// One row of the n × 3 data (x, y, z solved together).
pub(crate) type Row = [f64; 3];

/// Number of fixed chunks covering `n` rows.
pub(crate) fn n_chunks(n: usize) -> usize {
    n.div_ceil(CHUNK_ROWS)
}

/// Whether loops over `n` rows run on the rayon pool.
pub(crate) fn parallel(n: usize) -> bool {
    n >= PARALLEL_MIN_ROWS
}

/// Raw CSR slices of a matrix (indptr starts at 0; checked when the matrix
/// was validated).
#[derive(Clone, Copy)]
pub(crate) struct Csr<'a> {
    pub indptr: &'a [u32],
    pub indices: &'a [u32],
    pub data: &'a [f64],
}

impl<'a> Csr<'a> {
    pub fn new(m: &'a SparseMatrix) -> Self {
        let indptr = m.indptr().into_raw_storage();
        debug_assert!(m.is_csr() && indptr.first().is_none_or(|&p| p == 0));
        Csr { indptr, indices: m.indices(), data: m.data() }
    }

    /// (M x)_i for 3-column x.
    #[inline(always)]
    pub fn row_times(&self, i: usize, x: &[Row]) -> Row {
        let lo = self.indptr[i] as usize;
        let hi = self.indptr[i + 1] as usize;
        row_dot(&self.indices[lo..hi], &self.data[lo..hi], x)
    }

    /// (M x)_i for one column x.
    #[inline(always)]
    pub fn row_times_1(&self, i: usize, x: &[f64]) -> f64 {
        let lo = self.indptr[i] as usize;
        let hi = self.indptr[i + 1] as usize;
        let mut acc = 0.0;
        for (&j, &v) in self.indices[lo..hi].iter().zip(&self.data[lo..hi]) {
            acc += v * x[j as usize];
        }
        acc
    }

    /// The diagonal entry m_ii (0 when not stored).
    pub fn diag(&self, i: usize) -> f64 {
        let lo = self.indptr[i] as usize;
        let hi = self.indptr[i + 1] as usize;
        match self.indices[lo..hi].binary_search(&(i as u32)) {
            Ok(k) => self.data[lo + k],
            Err(_) => 0.0,
        }
    }
}

/// Σ_k values\[k\]·x\[columns\[k\]\] for 3-column x, in the order given: one
/// row of a sparse product, stored ([`Csr::row_times`]) or streamed
/// (`cg::cg_start`), with the same arithmetic.
#[inline(always)]
pub(crate) fn row_dot(columns: &[u32], values: &[f64], x: &[Row]) -> Row {
    let mut acc = [0.0; 3];
    for (&j, &v) in columns.iter().zip(values) {
        let xj = x[j as usize];
        acc[0] += v * xj[0];
        acc[1] += v * xj[1];
        acc[2] += v * xj[2];
    }
    acc
}

/// Runs `f(first_row, chunk)` over fixed chunks of `out`, writing each
/// chunk's result to `partials[c]`.
pub(crate) fn map_chunks<T, R, F>(out: &mut [T], partials: &mut [R], f: F)
where
    T: Send,
    R: Send,
    F: Fn(usize, &mut [T]) -> R + Sync,
{
    map_chunks_on(parallel(out.len()), out, partials, f);
}

/// [`map_chunks`] with the caller deciding whether to use the pool (for
/// loops over a part of a large system, such as one colour of a
/// multicolour sweep).
pub(crate) fn map_chunks_on<T, R, F>(par: bool, out: &mut [T], partials: &mut [R], f: F)
where
    T: Send,
    R: Send,
    F: Fn(usize, &mut [T]) -> R + Sync,
{
    debug_assert_eq!(partials.len(), n_chunks(out.len()));
    if par {
        out.par_chunks_mut(CHUNK_ROWS)
            .zip(partials.par_iter_mut())
            .enumerate()
            .for_each(|(c, (o, slot))| *slot = f(c * CHUNK_ROWS, o));
    } else {
        out.chunks_mut(CHUNK_ROWS)
            .zip(partials.iter_mut())
            .enumerate()
            .for_each(|(c, (o, slot))| *slot = f(c * CHUNK_ROWS, o));
    }
}

/// As [`map_chunks`] with two outputs chunked alike.
pub(crate) fn map_chunks2<T, U, R, F>(a: &mut [T], b: &mut [U], partials: &mut [R], f: F)
where
    T: Send,
    U: Send,
    R: Send,
    F: Fn(usize, &mut [T], &mut [U]) -> R + Sync,
{
    debug_assert_eq!(a.len(), b.len());
    debug_assert_eq!(partials.len(), n_chunks(a.len()));
    if parallel(a.len()) {
        a.par_chunks_mut(CHUNK_ROWS)
            .zip(b.par_chunks_mut(CHUNK_ROWS))
            .zip(partials.par_iter_mut())
            .enumerate()
            .for_each(|(c, ((x, y), slot))| *slot = f(c * CHUNK_ROWS, x, y));
    } else {
        a.chunks_mut(CHUNK_ROWS)
            .zip(b.chunks_mut(CHUNK_ROWS))
            .zip(partials.iter_mut())
            .enumerate()
            .for_each(|(c, ((x, y), slot))| *slot = f(c * CHUNK_ROWS, x, y));
    }
}

/// As [`map_chunks`] with three outputs chunked alike (the fused update
/// passes of MINRES and GMRES).
pub(crate) fn map_chunks3<T, U, V, R, F>(a: &mut [T], b: &mut [U], c: &mut [V], partials: &mut [R], f: F)
where
    T: Send,
    U: Send,
    V: Send,
    R: Send,
    F: Fn(usize, &mut [T], &mut [U], &mut [V]) -> R + Sync,
{
    debug_assert!(a.len() == b.len() && a.len() == c.len());
    debug_assert_eq!(partials.len(), n_chunks(a.len()));
    if parallel(a.len()) {
        a.par_chunks_mut(CHUNK_ROWS)
            .zip(b.par_chunks_mut(CHUNK_ROWS))
            .zip(c.par_chunks_mut(CHUNK_ROWS))
            .zip(partials.par_iter_mut())
            .enumerate()
            .for_each(|(k, (((x, y), z), slot))| *slot = f(k * CHUNK_ROWS, x, y, z));
    } else {
        a.chunks_mut(CHUNK_ROWS)
            .zip(b.chunks_mut(CHUNK_ROWS))
            .zip(c.chunks_mut(CHUNK_ROWS))
            .zip(partials.iter_mut())
            .enumerate()
            .for_each(|(k, (((x, y), z), slot))| *slot = f(k * CHUNK_ROWS, x, y, z));
    }
}

/// Runs `f(rows)` over the fixed chunks of `0..n` (no output array),
/// writing each chunk's result to `partials[c]`.
pub(crate) fn reduce_chunks<R, F>(n: usize, partials: &mut [R], f: F)
where
    R: Send,
    F: Fn(std::ops::Range<usize>) -> R + Sync,
{
    debug_assert_eq!(partials.len(), n_chunks(n));
    let run = |(c, slot): (usize, &mut R)| {
        let lo = c * CHUNK_ROWS;
        *slot = f(lo..(lo + CHUNK_ROWS).min(n));
    };
    if parallel(n) {
        partials.par_iter_mut().enumerate().for_each(run);
    } else {
        partials.iter_mut().enumerate().for_each(run);
    }
}

/// Statistics of a residual r (n × 3) gathered chunk by chunk by the Krylov
/// solvers (GMRES, MINRES): the max row norm (squared inside a pass), the
/// per-column max, and a per-column sum of squares whose weighting each
/// solver documents (‖r_c‖₂² for GMRES, rᵀM⁻¹r for MINRES).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ResidualStats {
    /// max_i ‖r_i‖₂ (squared inside a pass, the root after [`Self::merge`]).
    pub max: f64,
    /// max_i |r_ic| per column.
    pub col_max: [f64; 3],
    /// The per-column sum of squares.
    pub sum: [f64; 3],
}

impl ResidualStats {
    /// Folds the chunks' partials in order (deterministic) and takes the
    /// root of the squared max row norm.
    pub fn merge(partials: &[Self]) -> Self {
        let mut total = Self::default();
        for part in partials {
            total.max = max_nan(total.max, part.max);
            for c in 0..3 {
                total.col_max[c] = max_nan(total.col_max[c], part.col_max[c]);
                total.sum[c] += part.sum[c];
            }
        }
        total.max = total.max.sqrt();
        total
    }
}

/// max(a, b) that propagates NaN (f64::max drops it).
#[inline(always)]
pub(crate) fn max_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// In-order fold of per-chunk maxima.
pub(crate) fn fold_max(partials: &[f64]) -> f64 {
    partials.iter().fold(0.0, |m, &v| max_nan(m, v))
}

/// In-order fold of per-chunk 3-column sums.
pub(crate) fn fold_sum3(partials: impl IntoIterator<Item = Row>) -> Row {
    partials.into_iter().fold([0.0; 3], |s, v| [s[0] + v[0], s[1] + v[1], s[2] + v[2]])
}

/// Squared Euclidean norm of a row.
#[inline(always)]
pub(crate) fn norm2(r: Row) -> f64 {
    r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
}

/// out = D·S·x (A·x), parallel over fixed chunks.
pub(crate) fn apply_ds(s: Csr<'_>, d: &[f64], x: &[Row], out: &mut [Row], partials: &mut [()]) {
    map_chunks(out, partials, |lo, o| {
        for (k, oi) in o.iter_mut().enumerate() {
            let i = lo + k;
            let v = s.row_times(i, x);
            *oi = [d[i] * v[0], d[i] * v[1], d[i] * v[2]];
        }
    });
}

/// Squared max row norm of P − A·X (A = D·S), computed in fixed chunks.
pub(crate) fn max_residual_sq(s: Csr<'_>, d: &[f64], x: &[Row], p: &[Row], partials: &mut [f64]) -> f64 {
    reduce_chunks(p.len(), partials, |rows| {
        let mut m = 0.0f64;
        for i in rows {
            let v = s.row_times(i, x);
            let r = [p[i][0] - d[i] * v[0], p[i][1] - d[i] * v[1], p[i][2] - d[i] * v[2]];
            m = max_nan(m, norm2(r));
        }
        m
    });
    fold_max(partials)
}

/// Whether every entry is finite.
pub(crate) fn all_finite(x: &[Row]) -> bool {
    x.iter().all(|r| r.iter().all(|v| v.is_finite()))
}

/// Deterministic pseudo-random numbers in [−1, 1) (SplitMix64), for start
/// vectors that must not be orthogonal to any eigenvector by accident.
pub(crate) fn splitmix_unit(seed: u64, i: u64) -> f64 {
    let mut z = seed.wrapping_add(i.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}
