//! Building CSR matrices row by row from (column, weight) contributions.

use crate::apply::fill_in_chunks;
use crate::SparseMatrix;
use glam::DVec3;
use rayon::prelude::*;

/// How the contributions to one column of a row are summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Summation {
    /// In the order they were added.
    #[default]
    InOrder,
    /// In ascending order of their bits, so an entry depends only on the
    /// multiset of its contributions (what makes S\[i\]\[j\] and S\[j\]\[i\]
    /// of a limit matrix equal bit for bit).
    Canonical,
}

/// Rows per parallel task in [`RowBuilder::build_parallel`]: large enough to
/// amortise scheduling; fixed, so nothing depends on the thread count.
const ROWS_PER_TASK: usize = 4096;

/// Accumulates one row at a time; repeated columns within a row are summed.
///
/// Rows are short (a stencil touches a vertex's neighbourhood), so each row is
/// merged on its own, with no global sort: a short row by sorting it in place,
/// a long one by grouping its columns in a small hash table.
#[derive(Debug, Default)]
pub(crate) struct RowBuilder {
    indptr: Vec<u32>,
    indices: Vec<u32>,
    data: Vec<f64>,
    pending: Vec<(u32, f64)>,
    merger: Merger,
    /// Set while [`Self::build_parallel`] only counts a row's distinct columns,
    /// collected here.
    counting: bool,
    counted: Vec<u32>,
}

impl RowBuilder {
    /// A builder expecting about `rows` rows and `nnz` entries.
    pub fn with_capacity(rows: usize, nnz: usize) -> Self {
        let mut indptr = Vec::with_capacity(rows + 1);
        indptr.push(0);
        Self { indptr, indices: Vec::with_capacity(nnz), data: Vec::with_capacity(nnz), ..Self::scratch() }
    }

    /// A builder that only holds the pending row.
    fn scratch() -> Self {
        Self { pending: Vec::with_capacity(64), ..Self::default() }
    }

    /// Adds `weight` at `column` of the current row.
    #[inline]
    pub fn add(&mut self, column: u32, weight: f64) {
        if self.counting {
            self.counted.push(column);
        } else {
            self.pending.push((column, weight));
        }
    }

    /// Adds `weight` to every column in `columns`.
    #[inline]
    pub fn add_all(&mut self, columns: &[u32], weight: f64) {
        if self.counting {
            self.counted.extend_from_slice(columns);
        } else {
            self.pending.extend(columns.iter().map(|&c| (c, weight)));
        }
    }

    /// Closes the current row: sorts its entries and sums repeated columns in
    /// the order they were added ([`Summation::InOrder`]).
    pub fn finish_row(&mut self) {
        self.finish_row_with(Summation::InOrder);
    }

    /// Closes the current row, summing repeated columns as `summation` says.
    pub fn finish_row_with(&mut self, summation: Summation) {
        let start = self.indices.len();
        self.indices.resize(start + self.pending.len(), 0);
        self.data.resize(start + self.pending.len(), 0.0);
        let written =
            self.merger.merge(&mut self.pending, summation, &mut self.indices[start..], &mut self.data[start..]);
        self.indices.truncate(start + written);
        self.data.truncate(start + written);
        self.indptr.push(self.indices.len() as u32);
    }

    /// Merges the pending row (as the parallel builds store it, `summation`
    /// deciding how repeated columns are summed) into `columns`/`values`,
    /// which are overwritten, and clears it: one row of the matrix without
    /// the matrix ([`crate::limit_matrix::LimitOperator::for_each_row`]).
    pub fn merge_pending(&mut self, summation: Summation, columns: &mut Vec<u32>, values: &mut Vec<f64>) {
        let len = self.pending.len();
        columns.resize(len, 0);
        values.resize(len, 0.0);
        let written = self.merger.merge(&mut self.pending, summation, columns, values);
        columns.truncate(written);
        values.truncate(written);
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

    /// Builds a `rows` × `columns` matrix whose rows are independent: `fill(i,
    /// builder)` adds the contributions of row `i` (without closing it), the
    /// same ones each time it is called.
    ///
    /// Two parallel passes over the rows: the first counts each row's distinct
    /// columns, which places every row in one pair of output arrays; the
    /// second writes the rows there, merged as `summation` says. No row is
    /// copied twice and no array grows. Each row is computed by one task alone,
    /// so the matrix is the same bit for bit whatever the thread count.
    ///
    /// # Panics
    /// If a column index is out of range, `fill` adds different columns on the
    /// two passes, or the matrix has 2³² entries or more (caller bugs: plans
    /// check sizes first).
    pub fn build_parallel(
        rows: usize,
        columns: usize,
        summation: Summation,
        fill: impl Fn(usize, &mut RowBuilder) + Sync,
    ) -> SparseMatrix {
        Self::build_parallel_with_scratch(rows, columns, summation, |i, builder, _: &mut ()| fill(i, builder))
    }

    /// [`Self::build_parallel`] for rows that need working memory: each task
    /// passes its own `S` (created by `Default`) to every row it fills.
    ///
    /// # Panics
    /// As [`Self::build_parallel`].
    pub fn build_parallel_with_scratch<S: Default>(
        rows: usize,
        columns: usize,
        summation: Summation,
        fill: impl Fn(usize, &mut RowBuilder, &mut S) + Sync,
    ) -> SparseMatrix {
        // Pass 1: distinct columns per row.
        let mut lengths = vec![0u32; rows];
        lengths.par_chunks_mut(ROWS_PER_TASK).enumerate().for_each(|(c, out)| {
            let (mut counter, mut scratch) = (RowBuilder { counting: true, ..Self::default() }, S::default());
            for (j, len) in out.iter_mut().enumerate() {
                fill(c * ROWS_PER_TASK + j, &mut counter, &mut scratch);
                let columns = &mut counter.counted;
                columns.sort_unstable();
                *len = columns.windows(2).filter(|w| w[0] != w[1]).count() as u32 + u32::from(!columns.is_empty());
                columns.clear();
            }
        });
        Self::write_rows(columns, summation, lengths, fill)
    }

    /// [`Self::build_parallel_with_scratch`] with a bound on each row's length
    /// given by the caller instead of counted by a first pass over `fill`: `max_len(i)` ≥
    /// the number of distinct columns of row `i` (a row that merges repeated
    /// columns comes out shorter; the gaps are closed afterwards).
    ///
    /// # Panics
    /// If a row has more distinct columns than its bound, and as
    /// [`Self::build_parallel`].
    pub fn build_parallel_bounded<S: Default>(
        rows: usize,
        columns: usize,
        summation: Summation,
        max_len: impl Fn(usize) -> usize + Sync,
        fill: impl Fn(usize, &mut RowBuilder, &mut S) + Sync,
    ) -> SparseMatrix {
        let mut lengths = vec![0u32; rows];
        lengths.par_chunks_mut(ROWS_PER_TASK).enumerate().for_each(|(c, out)| {
            for (j, len) in out.iter_mut().enumerate() {
                *len = max_len(c * ROWS_PER_TASK + j) as u32;
            }
        });
        Self::write_rows(columns, summation, lengths, fill)
    }

    /// The product R·x of the matrix R that [`Self::build_parallel_with_scratch`]
    /// would build from the same `fill`, without building it: point `i` is
    /// Σ w·x\[c\] over the contributions (c, w) that `fill(i, …)` adds, in the
    /// order they are added. For an operator applied once — a limit stencil
    /// on the finest level of a surface — this skips the counting pass, the
    /// merge and the storage of R (a dozen entries per row).
    ///
    /// Equal to `apply(&R, x)` up to round-off: R sums a repeated column's
    /// weights before multiplying and a row's products in column order. Each
    /// point is summed by one task in a fixed order, so the result is the same
    /// bit for bit whatever the thread count.
    ///
    /// # Panics
    /// If `fill` adds a column ≥ `x.len()` (a caller bug).
    pub fn evaluate_parallel_with_scratch<S: Default>(
        rows: usize,
        x: &[DVec3],
        fill: impl Fn(usize, &mut RowBuilder, &mut S) + Sync,
    ) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; rows];
        fill_in_chunks(&mut out, |first, chunk| {
            let (mut builder, mut scratch) = (Self::scratch(), S::default());
            for (j, point) in chunk.iter_mut().enumerate() {
                fill(first + j, &mut builder, &mut scratch);
                *point = builder.pending.iter().fold(DVec3::ZERO, |sum, &(c, w)| sum + w * x[c as usize]);
                builder.pending.clear();
            }
        });
        out
    }

    /// Pass 2 of the parallel builds: places row `i` at the prefix sum of
    /// `lengths`, lets each task write its rows there, and closes the gaps
    /// of rows that came out shorter than their length.
    fn write_rows<S: Default>(
        columns: usize,
        summation: Summation,
        lengths: Vec<u32>,
        fill: impl Fn(usize, &mut RowBuilder, &mut S) + Sync,
    ) -> SparseMatrix {
        let rows = lengths.len();
        let mut indptr = Vec::with_capacity(rows + 1);
        let mut total = 0u64;
        indptr.push(0u32);
        for &len in &lengths {
            total += u64::from(len);
            indptr.push(u32::try_from(total).expect("fewer than 2³² stencil entries"));
        }
        let total = total as usize;
        let (mut indices, mut data) = (vec![0u32; total], vec![0.0f64; total]);
        let mut lengths = lengths;
        let mut tasks = Vec::with_capacity(rows.div_ceil(ROWS_PER_TASK));
        let (mut rest_i, mut rest_d) = (indices.as_mut_slice(), data.as_mut_slice());
        for (c, lens) in lengths.chunks_mut(ROWS_PER_TASK).enumerate() {
            let (first, last) = (c * ROWS_PER_TASK, c * ROWS_PER_TASK + lens.len());
            let span = (indptr[last] - indptr[first]) as usize;
            let (head_i, tail_i) = rest_i.split_at_mut(span);
            let (head_d, tail_d) = rest_d.split_at_mut(span);
            tasks.push((first, lens, head_i, head_d));
            (rest_i, rest_d) = (tail_i, tail_d);
        }
        let shortened = tasks
            .into_par_iter()
            .map(|(first, lens, out_i, out_d)| {
                let (mut builder, mut scratch) = (Self::scratch(), S::default());
                let base = indptr[first] as usize;
                let mut shortened = false;
                for (j, len) in lens.iter_mut().enumerate() {
                    let i = first + j;
                    fill(i, &mut builder, &mut scratch);
                    let (at, end) = (indptr[i] as usize - base, indptr[i + 1] as usize - base);
                    let written =
                        builder.merger.merge(&mut builder.pending, summation, &mut out_i[at..end], &mut out_d[at..end]);
                    shortened |= written < *len as usize;
                    *len = written as u32;
                }
                shortened
            })
            .reduce(|| false, |a, b| a || b);
        if shortened {
            // Close the gaps, moving rows towards the front in order.
            let mut end = 0usize;
            for (i, &len) in lengths.iter().enumerate() {
                let (from, len) = (indptr[i] as usize, len as usize);
                indices.copy_within(from..from + len, end);
                data.copy_within(from..from + len, end);
                indptr[i] = end as u32;
                end += len;
            }
            indptr[rows] = end as u32;
            indices.truncate(end);
            data.truncate(end);
        }
        SparseMatrix::try_new((rows, columns), indptr, indices, data)
            .map_err(|(_, _, _, e)| e)
            .expect("rows are sorted and in range by construction")
    }
}

/// Rows with more contributions than this are merged by hashing their
/// columns instead of sorting the contributions.
const SORTED_MERGE_MAX: usize = 16;

/// Marks an empty slot of [`Merger`]'s table.
const EMPTY: u32 = u32::MAX;

/// First slot to probe for column `c` in a table of `mask + 1` slots
/// (Fibonacci hashing: neighbouring columns land apart).
#[inline]
fn home_slot(c: u32, mask: usize) -> usize {
    (c.wrapping_mul(0x9E37_79B9) >> 7) as usize & mask
}

/// Working memory of a row merge, kept from row to row.
#[derive(Debug, Default)]
struct Merger {
    /// Open-addressing table column → group (power-of-two size ≥ 2 × the row's contributions).
    table: Vec<(u32, u32)>,
    /// Per group, in order of first appearance: column, contribution count, running in-order sum.
    groups: Vec<(u32, u32, f64)>,
    /// Contributions regrouped by group (canonical sums only).
    grouped: Vec<f64>,
    /// Per group, the next free place in `grouped`.
    cursor: Vec<u32>,
    /// (column, group), sorted by column.
    order: Vec<(u32, u32)>,
}

impl Merger {
    /// Writes the distinct columns of a pending row, ascending, with their
    /// summed weights to the front of `to_columns`/`to_weights`, clears the
    /// row and returns how many entries were written. The sums are those of
    /// [`merge_sorted`], bit for bit, whichever way the row is merged.
    fn merge(
        &mut self,
        pending: &mut Vec<(u32, f64)>,
        summation: Summation,
        to_columns: &mut [u32],
        to_weights: &mut [f64],
    ) -> usize {
        let written = if pending.len() <= SORTED_MERGE_MAX {
            merge_sorted(pending, summation, to_columns, to_weights)
        } else {
            self.merge_hashed(pending, summation, to_columns, to_weights)
        };
        pending.clear();
        written
    }

    fn merge_hashed(
        &mut self,
        pending: &[(u32, f64)],
        summation: Summation,
        to_columns: &mut [u32],
        to_weights: &mut [f64],
    ) -> usize {
        // 1. Group by column, summing in the order added.
        let size = (2 * pending.len()).next_power_of_two();
        let mask = size - 1;
        self.table.clear();
        self.table.resize(size, (EMPTY, 0));
        self.groups.clear();
        let mut needs_sorting = false;
        for &(c, w) in pending {
            let mut at = home_slot(c, mask);
            loop {
                let (key, group) = self.table[at];
                if key == c {
                    let g = &mut self.groups[group as usize];
                    g.1 += 1;
                    g.2 += w;
                    needs_sorting |= g.1 > 2;
                    break;
                }
                if key == EMPTY {
                    self.table[at] = (c, self.groups.len() as u32);
                    self.groups.push((c, 1, w));
                    break;
                }
                at = (at + 1) & mask;
            }
        }
        // 2. Canonical: a column with three or more contributions is summed
        //    again in ascending order of their bits (two round alike either way).
        if summation == Summation::Canonical && needs_sorting {
            self.cursor.clear();
            let mut offset = 0u32;
            for g in &self.groups {
                self.cursor.push(offset);
                offset += g.1;
            }
            self.grouped.clear();
            self.grouped.resize(pending.len(), 0.0);
            for &(c, w) in pending {
                let mut at = home_slot(c, mask);
                while self.table[at].0 != c {
                    at = (at + 1) & mask;
                }
                let group = self.table[at].1 as usize;
                self.grouped[self.cursor[group] as usize] = w;
                self.cursor[group] += 1;
            }
            for (g, &end) in self.groups.iter_mut().zip(&self.cursor) {
                if g.1 > 2 {
                    let terms = &mut self.grouped[(end - g.1) as usize..end as usize];
                    terms.sort_unstable_by_key(|w| w.to_bits());
                    g.2 = terms[1..].iter().fold(terms[0], |sum, w| sum + w);
                }
            }
        }
        // 3. Write the groups in ascending column order.
        self.order.clear();
        self.order.extend(self.groups.iter().enumerate().map(|(g, &(c, _, _))| (c, g as u32)));
        self.order.sort_unstable();
        for (k, &(c, g)) in self.order.iter().enumerate() {
            to_columns[k] = c;
            to_weights[k] = self.groups[g as usize].2;
        }
        self.order.len()
    }
}

/// Sorts a pending row and writes its distinct columns with summed weights
/// to the front of `to_columns`/`to_weights`; returns how many entries were written.
fn merge_sorted(
    pending: &mut [(u32, f64)],
    summation: Summation,
    to_columns: &mut [u32],
    to_weights: &mut [f64],
) -> usize {
    // Stable, so repeated columns are summed in the order they were added.
    insertion_sort_by_key(pending, |&(c, _)| c);
    // Ascending bits within each column. Two terms need no sorting: a + b
    // and b + a round alike, so only columns with three or more do (rare
    // once a row's contributions are pre-merged: checked in one pass).
    if summation == Summation::Canonical && pending.windows(3).any(|w| w[0].0 == w[2].0) {
        let mut start = 0;
        while start < pending.len() {
            let column = pending[start].0;
            let end = start + pending[start..].iter().take_while(|&&(c, _)| c == column).count();
            if end - start > 2 {
                insertion_sort_by_key(&mut pending[start..end], |&(_, w)| w.to_bits());
            }
            start = end;
        }
    }
    let mut written = 0;
    for &(c, w) in pending.iter() {
        if written > 0 && to_columns[written - 1] == c {
            to_weights[written - 1] += w;
        } else {
            to_columns[written] = c;
            to_weights[written] = w;
            written += 1;
        }
    }
    written
}

/// Stable insertion sort: fastest for the few dozen entries of a row.
fn insertion_sort_by_key<K: Ord>(entries: &mut [(u32, f64)], key: impl Fn(&(u32, f64)) -> K) {
    for i in 1..entries.len() {
        let entry = entries[i];
        let k = key(&entry);
        let mut j = i;
        while j > 0 && key(&entries[j - 1]) > k {
            entries[j] = entries[j - 1];
            j -= 1;
        }
        entries[j] = entry;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Row `i` of a pseudo-random matrix: 0-40 contributions over few columns,
    /// so most rows repeat columns (and need merging), some are empty.
    fn contributions(i: usize) -> Vec<(u32, f64)> {
        let mut state = (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let mut next = || {
            state ^= state >> 29;
            state = state.wrapping_mul(0xBF58_476D_1CE4_E5B9);
            state ^= state >> 32;
            state
        };
        let len = (next() % 41) as usize;
        (0..len).map(|_| ((next() % 23) as u32, (next() % 1000) as f64 / 7.0 - 50.0)).collect()
    }

    /// Row `i` summed independently of the builder: per column, in the order
    /// added or in ascending order of the bits.
    fn reference_row(i: usize, summation: Summation) -> Vec<(u32, u64)> {
        let mut row = contributions(i);
        match summation {
            Summation::InOrder => row.sort_by_key(|&(c, _)| c),
            Summation::Canonical => row.sort_by_key(|&(c, w)| (c, w.to_bits())),
        }
        let mut out: Vec<(u32, f64)> = Vec::new();
        for (c, w) in row {
            match out.last_mut() {
                Some((last, sum)) if *last == c => *sum += w,
                _ => out.push((c, w)),
            }
        }
        out.into_iter().map(|(c, w)| (c, w.to_bits())).collect()
    }

    fn sequential(rows: usize, summation: Summation) -> SparseMatrix {
        let mut b = RowBuilder::with_capacity(rows, 0);
        for i in 0..rows {
            contributions(i).into_iter().for_each(|(c, w)| b.add(c, w));
            b.finish_row_with(summation);
        }
        b.build(23)
    }

    #[test]
    fn parallel_build_equals_the_sequential_one_bit_for_bit() {
        // Three tasks' worth of rows, the last one partial; most rows repeat columns.
        let rows = 2 * ROWS_PER_TASK + 77;
        for summation in [Summation::InOrder, Summation::Canonical] {
            let parallel = RowBuilder::build_parallel(rows, 23, summation, |i, b| {
                contributions(i).into_iter().for_each(|(c, w)| b.add(c, w))
            });
            // Bounded by the contribution count: most rows come out shorter, and the gaps are closed.
            let bounded = RowBuilder::build_parallel_bounded(
                rows,
                23,
                summation,
                |i| contributions(i).len(),
                |i, b, _: &mut ()| contributions(i).into_iter().for_each(|(c, w)| b.add(c, w)),
            );
            let reference = sequential(rows, summation);
            for i in 0..rows {
                let built: Vec<(u32, u64)> = reference
                    .outer_view(i)
                    .expect("row exists")
                    .iter()
                    .map(|(c, &w)| (c as u32, w.to_bits()))
                    .collect();
                assert_eq!(built, reference_row(i, summation), "row {i}, {summation:?}");
            }
            let bits = |m: &SparseMatrix| m.data().iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            for built in [&parallel, &bounded] {
                assert_eq!(built.indptr().raw_storage(), reference.indptr().raw_storage());
                assert_eq!(built.indices(), reference.indices());
                assert_eq!(bits(built), bits(&reference), "{summation:?}");
            }
        }
    }

    #[test]
    #[should_panic]
    fn a_row_longer_than_its_bound_is_a_caller_bug() {
        RowBuilder::build_parallel_bounded(
            2,
            4,
            Summation::InOrder,
            |_| 1,
            |i, b, _: &mut ()| b.add_all(&[0, i as u32 + 1], 1.0),
        );
    }

    #[test]
    fn rows_sum_their_repeated_columns() {
        let m = RowBuilder::build_parallel(3, 4, Summation::InOrder, |i, b| match i {
            0 => b.add_all(&[3, 1, 3], 0.5),
            1 => {}
            _ => {
                b.add(2, 1.0);
                b.add(0, -1.0);
            }
        });
        assert_eq!(m.indptr().raw_storage(), &[0, 2, 2, 4]);
        assert_eq!(m.indices(), &[1, 3, 0, 2]);
        assert_eq!(m.data(), &[0.5, 1.0, -1.0, 1.0]);
    }

    #[test]
    fn in_order_and_canonical_summation_round_in_their_own_orders() {
        // Added as 1e16, −1e16, 1: in order (1e16 − 1e16) + 1 = 1; by bits
        // (1 < 1e16 < −1e16, the sign bit being the highest) (1 + 1e16) − 1e16 = 0.
        let sum = |summation| {
            RowBuilder::build_parallel(1, 1, summation, |_, b| {
                b.add(0, 1e16);
                b.add(0, -1e16);
                b.add(0, 1.0);
            })
            .data()[0]
        };
        assert_eq!(sum(Summation::InOrder), 1.0);
        assert_eq!(sum(Summation::Canonical), 0.0);
    }
}
