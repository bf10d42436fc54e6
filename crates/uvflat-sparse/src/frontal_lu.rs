//! Multifrontal LU factorization without pivoting, `P A Pᵀ = L U`, for matrices whose sparsity
//! pattern is symmetric but whose values are not (the fixed-boundary systems of Floater's,
//! mean-value and authalic weights: one row per free vertex, one column per neighbour).
//! Without pivoting the factors have the pattern of the Cholesky factor of the pattern, so the
//! nested-dissection ordering, faer's supernodal symbolic analysis and the parallel multifrontal
//! driver of [`super::multifrontal`] serve unchanged (Amestoy–Duff 1989, "Vectorization of a
//! multiprocessor multifrontal code", fronts of unsymmetric values on a symmetric structure;
//! Liu 1992 §4–5). Each front is square: `F₁₁ = L₁₁U₁₁` (dense, recursive blocked, L unit
//! lower), `U₁₂ = L₁₁⁻¹F₁₂`, `L₂₁ = F₂₁U₁₁⁻¹`, update `F₂₂ − L₂₁U₁₂` for the parent.
//!
//! No pivoting is stable for M-matrices and for (row or column) diagonally dominant matrices
//! (Golub & Van Loan, "Matrix Computations", 4th ed., §3.4.10) — Tutte, Floater and mean-value
//! systems, whose weights are positive with one diagonally dominant row per free vertex.
//! Authalic (Wachspress) weights can be negative, so [`SparseLu`] checks the backward error of
//! every solve and the caller falls back to faer's LU with partial pivoting when it is large.
//! Storage per supernode: its block of L in faer's layout (`(w + m) × w`, column-major), then
//! its block of Uᵀ in the same layout (unit diagonal in L, pivots on the diagonal of Uᵀ).

use super::multifrontal::{run, Entries};
use super::permuted_lower::PermutedLower;
use super::supernodal_solve;
use crate::error::{Error, Result};
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::SparseColMatRef;
use faer::Mat;
use std::sync::Arc;

/// LU factors of a real matrix with a symmetric pattern, on a supernodal structure.
pub struct SparseLu {
    symbolic: Arc<SymbolicCholesky<usize>>,
    /// Per supernode: L's block, then Uᵀ's block.
    values: Vec<f64>,
    /// `forward[k]`: original unknown eliminated k-th.
    forward: Vec<usize>,
}

impl SparseLu {
    /// Factors `a` (all entries stored, pattern symmetric) on the analysed pattern of its
    /// lower triangle.
    pub fn new(symbolic: Arc<SymbolicCholesky<usize>>, a: SparseColMatRef<'_, usize, f64>) -> Result<Self> {
        let n = symbolic.nrows();
        let (forward, inverse) = match symbolic.perm() {
            Some(p) => (p.arrays().0.to_vec(), Some(p.arrays().1)),
            None => ((0..n).collect(), None),
        };
        let (lower, upper_t) = PermutedLower::split(a, inverse);
        let mut values = Vec::new();
        values
            .try_reserve_exact(2 * symbolic.len_val())
            .map_err(|_| Error::Internal("out of memory for the LU factors".into()))?;
        values.resize(2 * symbolic.len_val(), 0.0);
        if n > 0 {
            run(&symbolic, Entries::Lu { lower: &lower, upper_t: &upper_t }, &mut values)?;
        }
        Ok(SparseLu { symbolic, values, forward })
    }

    /// Number of unknowns.
    pub fn dim(&self) -> usize {
        self.forward.len()
    }

    /// Stored values of L and U together.
    pub fn factor_len(&self) -> usize {
        self.values.len()
    }

    /// The elimination order: `order[k]` is the unknown eliminated k-th.
    pub fn elimination_order(&self) -> &[usize] {
        &self.forward
    }

    /// Solves `A X = B` (or `Aᵀ X = B` when `transpose`) for every column of `rhs`, in place.
    pub fn solve_in_place(&self, rhs: &mut Mat<f64>, transpose: bool) -> Result<()> {
        match rhs.ncols() {
            0 => Ok(()),
            1 => self.solve_columns::<1>(rhs, 0, transpose),
            k => (0..k).step_by(2).try_for_each(|c| {
                if c + 1 < k {
                    self.solve_columns::<2>(rhs, c, transpose)
                } else {
                    self.solve_columns::<1>(rhs, c, transpose)
                }
            }),
        }
    }

    /// Solves columns `first..first + K` of `rhs` through the row-interleaved kernels.
    fn solve_columns<const K: usize>(&self, rhs: &mut Mat<f64>, first: usize, transpose: bool) -> Result<()> {
        let mut x: Vec<[f64; K]> = self.forward.iter().map(|&o| std::array::from_fn(|c| rhs[(o, first + c)])).collect();
        self.solve_permuted_rows(&mut x, transpose, &mut Vec::new(), None)?;
        for (row, &o) in x.iter().zip(&self.forward) {
            for (c, &v) in row.iter().enumerate() {
                rhs[(o, first + c)] = v;
            }
        }
        Ok(())
    }

    /// Solves `P A Pᵀ Y = X` (`L U Y = X`; with `transpose`, `Uᵀ Lᵀ Y = X`) in place for K
    /// row-interleaved right-hand sides in elimination order. `scratch` is reused; `active`
    /// (from [`Self::active_supernodes`]) skips supernodes a sparse right-hand side does not
    /// reach.
    pub fn solve_permuted_rows<const K: usize>(
        &self,
        x: &mut [[f64; K]],
        transpose: bool,
        scratch: &mut Vec<[f64; K]>,
        active: Option<&[bool]>,
    ) -> Result<()> {
        let Some(sn) = super::supernodal_for_solve(&self.symbolic, x.len(), "the LU factor")? else { return Ok(()) };
        let l = supernodal_solve::Factor { sn, values: &self.values, blocks: 2, which: 0, unit_diagonal: true };
        let ut = supernodal_solve::Factor { sn, values: &self.values, blocks: 2, which: 1, unit_diagonal: false };
        if transpose {
            ut.forward(x, scratch, active);
            l.backward_transposed(false, x, scratch);
        } else {
            l.forward(x, scratch, active);
            ut.backward_transposed(false, x, scratch);
        }
        Ok(())
    }

    /// The supernodes a forward substitution must visit when only the rows `rows`
    /// (elimination order) of the right-hand side are nonzero (for both L and Uᵀ, which share
    /// the supernodal structure).
    pub fn active_supernodes(&self, rows: impl IntoIterator<Item = usize>) -> Option<Vec<bool>> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => Some(supernodal_solve::active_supernodes(sn, rows)),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{LuSolver, TripletBuilder};
    use faer::Mat;

    /// A non-symmetric matrix on a `k × k` grid graph with diagonals: row-diagonally dominant
    /// (as a mean-value system) when `dominant`, otherwise with a zero diagonal (the first
    /// unpivoted pivot is zero; partial pivoting factors it). Returns it with 3D grid
    /// coordinates.
    fn grid_system(k: usize, dominant: bool) -> (faer::sparse::SparseColMat<usize, f64>, Vec<[f64; 3]>) {
        let id = |i: usize, j: usize| j * k + i;
        let n = k * k;
        let mut b = TripletBuilder::with_capacity(n, 8 * n);
        let mut coords = vec![[0.0; 3]; n];
        for j in 0..k {
            for i in 0..k {
                let v = id(i, j);
                coords[v] = [i as f64, j as f64, 0.0];
                let mut row_sum = 0.0;
                for (di, dj) in [(1i64, 0i64), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1)] {
                    let (ni, nj) = (i as i64 + di, j as i64 + dj);
                    if ni < 0 || nj < 0 || ni >= k as i64 || nj >= k as i64 {
                        continue;
                    }
                    let u = id(ni as usize, nj as usize);
                    let w = 0.5 + ((v * 31 + u * 17) % 7) as f64 / 7.0;
                    b.add(v, u, -w);
                    row_sum += w;
                }
                b.add(v, v, if dominant { row_sum + 0.05 } else { 0.0 });
            }
        }
        (b.build().expect("matrix"), coords)
    }

    fn check_solves(k: usize, dominant: bool) {
        let (a, coords) = grid_system(k, dominant);
        let n = a.nrows();
        let x_true = Mat::<f64>::from_fn(n, 2, |i, c| ((i * (c + 3)) as f64 * 0.37).sin());
        let mut b = Mat::<f64>::zeros(n, 2);
        for j in 0..n {
            for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                for c in 0..2 {
                    b[(i, c)] += v * x_true[(j, c)];
                }
            }
        }
        let solver = LuSolver::with_coords(&a, Some(&coords)).expect("factor");
        assert_eq!(solver.frontal.is_some(), dominant, "unpivoted factors exist exactly for the dominant matrix");
        solver.solve_in_place(&mut b).expect("solve");
        for i in 0..n {
            for c in 0..2 {
                assert!((b[(i, c)] - x_true[(i, c)]).abs() < 1e-9, "unknown {i}: {} vs {}", b[(i, c)], x_true[(i, c)]);
            }
        }
    }

    #[test]
    fn unpivoted_multifrontal_lu_solves_a_diagonally_dominant_system() {
        // Large enough for multi-level fronts, blocked dense LU (fronts wider than 32) and
        // parallel subtrees.
        check_solves(90, true);
    }

    #[test]
    fn zero_pivot_falls_back_to_partial_pivoting() {
        check_solves(12, false);
    }
}
