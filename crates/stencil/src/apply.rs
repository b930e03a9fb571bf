//! Geometry: one sparse product per level, over any number of columns.

use crate::SparseMatrix;
use glam::DVec3;
use rayon::prelude::*;

/// Rows per parallel task: large enough to amortise scheduling, fixed so the
/// result does not depend on the thread count (each row is summed in storage
/// order by exactly one task).
const ROWS_PER_TASK: usize = 4096;

/// `R · x` for per-vertex points: `x.len()` = columns of R; returns one point
/// per row. Deterministic whatever the thread count.
///
/// # Panics
/// If `x.len()` differs from the number of columns (a caller bug).
pub fn apply(r: &SparseMatrix, x: &[DVec3]) -> Vec<DVec3> {
    assert_eq!(r.cols(), x.len(), "one point per column");
    let indptr = r.indptr();
    let indptr = indptr.raw_storage();
    let (indices, data) = (r.indices(), r.data());
    let mut out = vec![DVec3::ZERO; r.rows()];
    let row = |i: usize| -> DVec3 {
        let (s, e) = (indptr[i] as usize, indptr[i + 1] as usize);
        let mut acc = DVec3::ZERO;
        for k in s..e {
            acc += data[k] * x[indices[k] as usize];
        }
        acc
    };
    fill_in_chunks(&mut out, |first, chunk| {
        for (j, o) in chunk.iter_mut().enumerate() {
            *o = row(first + j);
        }
    });
    out
}

/// Calls `fill(first, chunk)` on consecutive chunks of `out` (`first` = the
/// index of the chunk's first element): on the calling thread for short
/// outputs, as parallel tasks of [`ROWS_PER_TASK`] otherwise. The chunks do
/// not depend on the thread count.
pub(crate) fn fill_in_chunks<T: Send>(out: &mut [T], fill: impl Fn(usize, &mut [T]) + Sync) {
    if out.len() < 2 * ROWS_PER_TASK {
        fill(0, out);
    } else {
        out.par_chunks_mut(ROWS_PER_TASK).enumerate().for_each(|(c, chunk)| fill(c * ROWS_PER_TASK, chunk));
    }
}

/// `R · X` for `k` columns of per-vertex data stored row-major (`x[v*k + c]`).
///
/// # Panics
/// If `x.len()` differs from columns(R)·k (a caller bug).
pub fn apply_columns(r: &SparseMatrix, x: &[f64], k: usize) -> Vec<f64> {
    assert_eq!(r.cols() * k, x.len(), "k values per column");
    let indptr = r.indptr();
    let indptr = indptr.raw_storage();
    let (indices, data) = (r.indices(), r.data());
    let mut out = vec![0.0; r.rows() * k];
    let fill = |i: usize, o: &mut [f64]| {
        for p in indptr[i] as usize..indptr[i + 1] as usize {
            let w = data[p];
            let src = &x[indices[p] as usize * k..][..k];
            o.iter_mut().zip(src).for_each(|(a, b)| *a += w * b);
        }
    };
    out.par_chunks_mut(ROWS_PER_TASK * k.max(1)).enumerate().for_each(|(c, chunk)| {
        for (j, o) in chunk.chunks_mut(k.max(1)).enumerate() {
            fill(c * ROWS_PER_TASK + j, o);
        }
    });
    out
}

/// The first `rows` rows of `r`.
pub(crate) fn first_rows(r: &SparseMatrix, rows: usize) -> SparseMatrix {
    let indptr = r.indptr();
    let indptr = &indptr.raw_storage()[..=rows];
    let end = indptr[rows] as usize;
    SparseMatrix::new((rows, r.cols()), indptr.to_vec(), r.indices()[..end].to_vec(), r.data()[..end].to_vec())
}

/// Sum of every row (1 for an affine stencil).
pub fn row_sums(r: &SparseMatrix) -> Vec<f64> {
    r.outer_iterator().map(|row| row.data().iter().sum()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RowBuilder;

    #[test]
    fn apply_matches_a_dense_product_and_columns_agree() {
        let mut b = RowBuilder::with_capacity(3, 6);
        b.add(0, 0.5);
        b.add(2, 0.25);
        b.add(0, 0.25); // merged with the first
        b.finish_row();
        b.add(1, 1.0);
        b.finish_row();
        b.finish_row(); // empty row
        let r = b.build(3);
        assert_eq!(r.nnz(), 3);
        let x = [DVec3::new(1., 2., 3.), DVec3::new(-1., 0., 1.), DVec3::new(4., 4., 4.)];
        let y = apply(&r, &x);
        assert_eq!(y, vec![DVec3::new(1.75, 2.5, 3.25), x[1], DVec3::ZERO]);
        let flat: Vec<f64> = x.iter().flat_map(|p| p.to_array()).collect();
        let yc = apply_columns(&r, &flat, 3);
        assert_eq!(yc, y.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>());
        assert_eq!(row_sums(&r), vec![1.0, 1.0, 0.0]);
    }
}
