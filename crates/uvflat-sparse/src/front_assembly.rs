//! Where each stored entry of a sparse matrix's lower triangle lands in the fronts of the
//! multifrontal Cholesky factorization ([`super::multifrontal`]) of its pattern: computed once
//! per pattern, so that refactoring a matrix with new values (a Newton loop) assembles the
//! original-matrix part of every front by one indexed add per entry, without permuting the
//! matrix again (counting its columns, allocating and filling a permuted copy) or searching
//! each entry's row in the front's row list.
//!
//! For the symmetric permutation P of the analysis, entry (i, j), i ≥ j, of the lower triangle
//! of A is entry (max(p_i, p_j), min(p_i, p_j)) of the lower triangle of P A Pᵀ, conjugated
//! when p_i < p_j. Column c of P A Pᵀ belongs to the supernode `f..l` with f ≤ c < l; row r of
//! that column is row `r − f` of the supernode's front when r < l, else row `(l − f) + k` where
//! k is the index of r in the supernode's below-diagonal row pattern (Liu 1992, §4: the front
//! of a supernode has its own columns' rows, then the rows of its pattern).
//!
//! Cost: O(nnz) memory (a u32 front row and a source index per entry) and O(nnz log m) time to
//! build; assembling a column costs one gather-add per entry.

use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::SymbolicSparseColMatRef;
use faer::traits::ComplexField;

/// The front position of every stored lower-triangle entry of one matrix pattern.
pub struct FrontAssembly {
    /// Per permuted column c: its entries are `start[c]..start[c + 1]`, the ones read without
    /// conjugation first, then from `conjugated[c]` on the ones read conjugated.
    start: Vec<usize>,
    conjugated: Vec<usize>,
    /// Row of each entry in the front of its column's supernode.
    front_row: Vec<u32>,
    /// Index of each entry in the values of the original matrix.
    source: Vec<usize>,
    /// Length of the values array the map was built for.
    source_len: usize,
}

impl FrontAssembly {
    /// The map for the lower-triangle pattern `lower` (entries above the diagonal are
    /// ignored), the inverse permutation of the analysis (`inverse[old] = new`) and its
    /// supernodal structure.
    pub fn new(
        lower: SymbolicSparseColMatRef<'_, usize>,
        inverse: Option<&[usize]>,
        sn: &SymbolicSupernodalCholesky<usize>,
    ) -> Self {
        let n = lower.ncols();
        let new = |i: usize| inverse.map_or(i, |p| p[i]);
        // Permuted (row, column, conjugated) of each stored entry, None above the diagonal.
        let place = |i: usize, j: usize| {
            (i >= j).then(|| {
                let (pi, pj) = (new(i), new(j));
                if pi >= pj {
                    (pi, pj, false)
                } else {
                    (pj, pi, true)
                }
            })
        };
        // Counting sort by (column, conjugated): slot 2c for direct entries, 2c + 1 for
        // conjugated ones.
        let mut slot_start = vec![0usize; 2 * n + 1];
        for j in 0..n {
            for &i in lower.row_idx_of_col_raw(j) {
                if let Some((_, c, conj)) = place(i, j) {
                    slot_start[2 * c + conj as usize + 1] += 1;
                }
            }
        }
        for k in 0..2 * n {
            slot_start[k + 1] += slot_start[k];
        }
        let total = slot_start[2 * n];
        let mut fill = slot_start.clone();
        let mut row = vec![0usize; total];
        let mut source = vec![0usize; total];
        let col_ptr = lower.col_ptr();
        for (j, &column_start) in col_ptr[..n].iter().enumerate() {
            for (offset, &i) in lower.row_idx_of_col_raw(j).iter().enumerate() {
                if let Some((r, c, conj)) = place(i, j) {
                    let k = &mut fill[2 * c + conj as usize];
                    row[*k] = r;
                    source[*k] = column_start + offset;
                    *k += 1;
                }
            }
        }
        let front_row = front_rows(&row, &slot_start, sn);
        let start = (0..=n).map(|c| slot_start[2 * c]).collect();
        let conjugated = (0..n).map(|c| slot_start[2 * c + 1]).collect();
        FrontAssembly { start, conjugated, front_row, source, source_len: col_ptr[n] }
    }

    /// Length of the values array of the pattern the map was built for.
    pub fn values_len(&self) -> usize {
        self.source_len
    }

    /// Adds the entries of columns `f..end` (of the supernode starting at `f`, front leading
    /// dimension `ld`) of the matrix with the given `values` into the front's column block.
    pub fn assemble<T: ComplexField + Copy>(&self, block: &mut [T], ld: usize, f: usize, end: usize, values: &[T]) {
        for c in f..end {
            let column = &mut block[(c - f) * ld..(c - f + 1) * ld];
            let (start, conj, stop) = (self.start[c], self.conjugated[c], self.start[c + 1]);
            for (&r, &s) in self.front_row[start..conj].iter().zip(&self.source[start..conj]) {
                column[r as usize] += values[s];
            }
            for (&r, &s) in self.front_row[conj..stop].iter().zip(&self.source[conj..stop]) {
                column[r as usize] += T::conj_impl(&values[s]);
            }
        }
    }
}

/// Front row of each entry (permuted rows `row`, grouped by column as `slot_start` says).
fn front_rows(row: &[usize], slot_start: &[usize], sn: &SymbolicSupernodalCholesky<usize>) -> Vec<u32> {
    let mut front_row = vec![0u32; row.len()];
    for s in 0..sn.n_supernodes() {
        let (f, l) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
        let pattern = sn.supernode(s).pattern();
        for k in slot_start[2 * f]..slot_start[2 * l] {
            let r = row[k];
            let position = if r < l { r - f } else { (l - f) + pattern.partition_point(|&p| p < r) };
            front_row[k] = position as u32;
        }
    }
    front_row
}

/// Position in the front of supernode `f..l` (rows `f..l`, then `pattern`) of each row of a
/// child's update matrix (both patterns are sorted).
pub(crate) fn front_positions(f: usize, l: usize, pattern: &[usize], child_pattern: &[usize]) -> Vec<usize> {
    let mut position = Vec::with_capacity(child_pattern.len());
    let mut k = 0;
    for &i in child_pattern {
        if i < l {
            position.push(i - f);
        } else {
            while pattern[k] < i {
                k += 1;
            }
            position.push((l - f) + k);
        }
    }
    position
}
