//! Building CSR matrices row by row from (column, weight) contributions.

use crate::SparseMatrix;

/// Accumulates one row at a time; repeated columns within a row are summed.
///
/// Rows are short (a stencil touches a vertex's neighbourhood), so each row is
/// sorted in place and merged, with no hashing and no global sort.
#[derive(Debug, Default)]
pub struct RowBuilder {
    indptr: Vec<u32>,
    indices: Vec<u32>,
    data: Vec<f64>,
    pending: Vec<(u32, f64)>,
}

impl RowBuilder {
    /// A builder expecting about `rows` rows and `nnz` entries.
    pub fn with_capacity(rows: usize, nnz: usize) -> Self {
        let mut indptr = Vec::with_capacity(rows + 1);
        indptr.push(0);
        Self {
            indptr,
            indices: Vec::with_capacity(nnz),
            data: Vec::with_capacity(nnz),
            pending: Vec::with_capacity(64),
        }
    }

    /// Adds `weight` at `column` of the current row.
    #[inline]
    pub fn add(&mut self, column: u32, weight: f64) {
        self.pending.push((column, weight));
    }

    /// Adds `weight` to every column in `columns`.
    #[inline]
    pub fn add_all(&mut self, columns: &[u32], weight: f64) {
        self.pending.extend(columns.iter().map(|&c| (c, weight)));
    }

    /// Closes the current row: sorts its entries and sums repeated columns.
    pub fn finish_row(&mut self) {
        // Stable, so repeated columns are summed in the order they were added.
        self.pending.sort_by_key(|&(c, _)| c);
        self.finish_row_presorted();
    }

    /// Closes the current row whose entries were added in ascending column
    /// order; equal columns are summed in the order they were added.
    pub fn finish_row_presorted(&mut self) {
        debug_assert!(self.pending.windows(2).all(|w| w[0].0 <= w[1].0), "columns must ascend");
        let mut last = u32::MAX;
        for &(c, w) in &self.pending {
            if c == last {
                *self.data.last_mut().expect("an entry was pushed for this column") += w;
            } else {
                self.indices.push(c);
                self.data.push(w);
                last = c;
            }
        }
        self.pending.clear();
        self.indptr.push(self.indices.len() as u32);
    }

    /// Number of finished rows.
    pub fn rows(&self) -> usize {
        self.indptr.len() - 1
    }

    /// The finished matrix with `columns` columns.
    ///
    /// # Panics
    /// If a column index is out of range or a row is still open (caller bugs).
    pub fn build(self, columns: usize) -> SparseMatrix {
        assert!(self.pending.is_empty(), "finish_row before build");
        let rows = self.rows();
        SparseMatrix::try_new((rows, columns), self.indptr, self.indices, self.data)
            .map_err(|(_, _, _, e)| e)
            .expect("rows are sorted and in range by construction")
    }
}
