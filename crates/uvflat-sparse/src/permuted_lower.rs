//! The lower triangle of a symmetrically permuted sparse matrix, `P A Pᵀ`, in compressed
//! columns: the input of every front's assembly in the multifrontal factorizations
//! ([`super::multifrontal`], [`super::frontal_lu`], [`super::split_hermitian`]). Entry (i, j)
//! of A's lower triangle is entry (max(pᵢ, pⱼ), min(pᵢ, pⱼ)) of the permuted one, conjugated
//! when pᵢ < pⱼ.
//!
//! Cost: O(n + nnz) time and memory (a counting pass, then a fill pass).

use faer::sparse::SparseColMatRef;
use faer::traits::ComplexField;

/// The lower triangle of `P A Pᵀ` in compressed columns (rows unsorted), from the lower
/// triangle of A and the inverse permutation (`inverse[old] = new`).
pub(crate) struct PermutedLower<T> {
    col_ptr: Vec<usize>,
    rows: Vec<u32>,
    values: Vec<T>,
}

impl<T: ComplexField + Copy + Send + Sync> PermutedLower<T> {
    pub(crate) fn new(lower: SparseColMatRef<'_, usize, T>, inverse: Option<&[usize]>) -> Self {
        Self::mapped(lower, inverse, |v| v)
    }

    /// [`Self::new`] of the matrix with entries `map(a_ij)` (`map` must commute with
    /// conjugation, as taking the real part does).
    pub(crate) fn mapped<S: Copy>(
        lower: SparseColMatRef<'_, usize, S>,
        inverse: Option<&[usize]>,
        map: impl Fn(S) -> T,
    ) -> Self {
        let n = lower.ncols();
        let new = |i: usize| inverse.map_or(i, |p| p[i]);
        // Column of each lower entry after permutation: the smaller of the two new indices.
        let mut col_ptr = vec![0usize; n + 1];
        for j in 0..n {
            let pj = new(j);
            for i in lower.row_idx_of_col_raw(j) {
                if *i >= j {
                    col_ptr[new(*i).min(pj) + 1] += 1;
                }
            }
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut fill = col_ptr.clone();
        let mut rows = vec![0u32; col_ptr[n]];
        let mut values = vec![T::zero_impl(); col_ptr[n]];
        for j in 0..n {
            let pj = new(j);
            for (i, v) in lower.row_idx_of_col_raw(j).iter().zip(lower.val_of_col(j)) {
                if *i < j {
                    continue;
                }
                let (pi, v) = (new(*i), map(*v));
                let (r, c, v) = if pi >= pj { (pi, pj, v) } else { (pj, pi, T::conj_impl(&v)) };
                rows[fill[c]] = r as u32;
                values[fill[c]] = v;
                fill[c] += 1;
            }
        }
        PermutedLower { col_ptr, rows, values }
    }

    /// The two triangles of `P A Pᵀ` for a matrix `a` with a symmetric pattern (all entries
    /// stored): the entries on or below the diagonal, and the entries above it transposed, both
    /// in compressed columns of the permuted numbering (rows unsorted).
    pub(crate) fn split(a: SparseColMatRef<'_, usize, T>, inverse: Option<&[usize]>) -> (Self, Self) {
        let n = a.ncols();
        let new = |i: usize| inverse.map_or(i, |p| p[i]);
        // (triangle, row, column) of entry (i, j) after permutation.
        let place = |i: usize, j: usize| {
            let (pi, pj) = (new(i), new(j));
            if pi >= pj {
                (0, pi, pj)
            } else {
                (1, pj, pi)
            }
        };
        let mut col_ptr = [vec![0usize; n + 1], vec![0usize; n + 1]];
        for j in 0..n {
            for &i in a.row_idx_of_col_raw(j) {
                let (side, _, c) = place(i, j);
                col_ptr[side][c + 1] += 1;
            }
        }
        for ptr in &mut col_ptr {
            for c in 0..n {
                ptr[c + 1] += ptr[c];
            }
        }
        let mut fill = col_ptr.clone();
        let mut rows = [vec![0u32; col_ptr[0][n]], vec![0u32; col_ptr[1][n]]];
        let mut values = [vec![T::zero_impl(); col_ptr[0][n]], vec![T::zero_impl(); col_ptr[1][n]]];
        for j in 0..n {
            for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                let (side, r, c) = place(i, j);
                rows[side][fill[side][c]] = r as u32;
                values[side][fill[side][c]] = v;
                fill[side][c] += 1;
            }
        }
        let [lower_ptr, upper_ptr] = col_ptr;
        let [lower_rows, upper_rows] = rows;
        let [lower_values, upper_values] = values;
        (
            PermutedLower { col_ptr: lower_ptr, rows: lower_rows, values: lower_values },
            PermutedLower { col_ptr: upper_ptr, rows: upper_rows, values: upper_values },
        )
    }

    pub(crate) fn rows_of(&self, j: usize) -> &[u32] {
        &self.rows[self.col_ptr[j]..self.col_ptr[j + 1]]
    }

    pub(crate) fn values_of(&self, j: usize) -> &[T] {
        &self.values[self.col_ptr[j]..self.col_ptr[j + 1]]
    }
}
