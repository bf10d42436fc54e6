//! Cholesky factorization of a Hermitian positive-definite matrix that is real except on a few
//! unknowns, in real arithmetic wherever the factor is real.
//!
//! The natural conformal map's matrix `H = L + i·S/2` (Desbrun–Meyer–Alliez 2002 eq. 7; see
//! `methods::conformal`) has its imaginary part only between boundary vertices. Ordering those
//! unknowns (set B) last, after a nested-dissection order of the others (set I), the factor is
//!
//! ```text
//! [H_II  H_IBᵀ]   [L_II  0  ] [L_IIᵀ  L_IBᵀ]
//! [H_IB  H_BB ] = [L_IB  L_S] [0      L_Sᴴ ],   L_IB = H_IB L_II⁻ᵀ,   L_S L_Sᴴ = H_BB − L_IB L_IBᵀ,
//! ```
//!
//! with `H_II`, `H_IB`, hence `L_II` and `L_IB`, real: the multifrontal factorization
//! ([`super::multifrontal`]) runs in `f64` over the columns of I and leaves the real Schur
//! complement `−L_IB L_IBᵀ` (dense, |B|²); `H_BB` (complex) is added to it and a dense complex
//! Cholesky factors it. This is the same factorization as a complex Cholesky with that order,
//! so the same precision, for about a quarter of the flops and half the memory on the real
//! part. The dense block costs |B|³/3 complex multiply-adds, so this is used when |B|² ≤ 8n (a
//! disk's boundary has O(√n) vertices; a very long boundary takes the all-complex path).
//! Solves: real supernodal triangular solves with the real and imaginary parts as two columns,
//! and dense complex ones on B.

use super::multifrontal::{run_split, Entries};
use super::ordering::{self, Adjacency};
use super::permuted_lower::PermutedLower;
use super::{try_zeroed_vec, CholeskyPattern, CholeskySolver};
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch, LltError};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMatRef};
use faer::{c64, Accum, Mat, MatRef, Par};
use std::sync::Arc;

/// Unknowns touched by an entry with a non-zero imaginary part (diagonal included).
pub fn complex_unknowns(lower: SparseColMatRef<'_, usize, c64>) -> Vec<bool> {
    let mut complex = vec![false; lower.ncols()];
    for j in 0..lower.ncols() {
        for (&i, v) in lower.row_idx_of_col_raw(j).iter().zip(lower.val_of_col(j)) {
            if v.im != 0.0 {
                complex[i] = true;
                complex[j] = true;
            }
        }
    }
    complex
}

/// Whether the split factorization pays for a matrix of `n` unknowns, `complex` of them touched
/// by imaginary entries.
pub fn split_pays(n: usize, complex: usize) -> bool {
    complex > 0 && complex < n && complex.saturating_mul(complex) <= 8 * n
}

/// Elimination order: nested dissection of the unknowns that are not `complex` (their induced
/// graph, with their positions), then the `complex` ones in index order. Returns the order and
/// the number of real unknowns (where the complex ones start).
pub fn order_complex_last(
    lower: SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
    complex: &[bool],
) -> (Vec<usize>, usize) {
    let n = lower.nrows();
    let adjacency = Adjacency::from_lower(n, lower.col_ptr(), lower.row_idx());
    let real: Vec<usize> = (0..n).filter(|&i| !complex[i]).collect();
    let mut local = vec![u32::MAX; n];
    for (k, &i) in real.iter().enumerate() {
        local[i] = k as u32;
    }
    let mut start = Vec::with_capacity(real.len() + 1);
    let mut neighbors = Vec::with_capacity(adjacency.neighbors.len());
    start.push(0);
    for &i in &real {
        let row = &adjacency.neighbors[adjacency.start[i]..adjacency.start[i + 1]];
        neighbors.extend(row.iter().map(|&u| local[u as usize]).filter(|&u| u != u32::MAX));
        start.push(neighbors.len());
    }
    drop(adjacency);
    let sub = Adjacency { start, neighbors };
    let sub_coords: Vec<[f64; 3]> = real.iter().map(|&i| coords[i]).collect();
    let mut order: Vec<usize> = ordering::nested_dissection(&sub, &sub_coords).into_iter().map(|k| real[k]).collect();
    let split = order.len();
    order.extend((0..n).filter(|&i| complex[i]));
    (order, split)
}

/// The factorization: real supernodal blocks for the columns before `split`, a dense complex
/// Cholesky factor of the Schur complement of the rest.
pub struct SplitHermitianSolver {
    symbolic: Arc<SymbolicCholesky<usize>>,
    split: usize,
    real: Vec<f64>,
    schur: Mat<c64>,
}

impl SplitHermitianSolver {
    /// Factors `lower` (lower triangle of H) on `pattern`, analysed with an order whose first
    /// `split` unknowns carry only real entries ([`order_complex_last`]).
    pub fn factor(pattern: &CholeskyPattern, lower: &SparseColMat<usize, c64>, split: usize) -> Result<Self> {
        let symbolic = Arc::clone(&pattern.symbolic);
        let n = symbolic.nrows();
        let inverse = symbolic.perm().map(|p| p.arrays().1);
        let real_part = PermutedLower::mapped(lower.as_ref(), inverse, |z: c64| z.re);
        let mut real = try_zeroed_vec::<f64>(symbolic.len_val())?;
        let real_schur =
            if n > 0 { run_split(&symbolic, Entries::Hermitian(&real_part), &mut real, split)? } else { Vec::new() };
        drop(real_part);
        let nb = n - split;
        let mut schur = Mat::<c64>::from_fn(nb, nb, |i, j| c64::new(real_schur[j * nb + i], 0.0));
        add_trailing_entries(&mut schur, lower.as_ref(), inverse, split);
        factor_dense(&mut schur, split, n)?;
        Ok(SplitHermitianSolver { symbolic, split, real, schur })
    }

    /// Solves for every column of `rhs` in place.
    pub fn solve_in_place(&self, rhs: &mut Mat<c64>) -> Result<()> {
        let SymbolicCholeskyRaw::Supernodal(sn) = self.symbolic.raw() else {
            return if self.symbolic.nrows() == 0 {
                Ok(())
            } else {
                Err(Error::Internal("split Cholesky factor without supernodal structure".into()))
            };
        };
        let n = self.symbolic.nrows();
        let forward = self.symbolic.perm().map(|p| p.arrays().0);
        let old = |k: usize| forward.map_or(k, |p| p[k]);
        for c in 0..rhs.ncols() {
            // Real and imaginary parts as two real columns, in elimination order.
            let mut x = Mat::<f64>::from_fn(n, 2, |k, part| {
                let z = rhs[(old(k), c)];
                if part == 0 {
                    z.re
                } else {
                    z.im
                }
            });
            self.forward_real(sn, &mut x);
            self.solve_schur(&mut x);
            self.backward_real(sn, &mut x);
            for k in 0..n {
                rhs[(old(k), c)] = c64::new(x[(k, 0)], x[(k, 1)]);
            }
        }
        Ok(())
    }

    /// Supernode `s`'s columns, eliminated width and factor block (`rows × w`, column-major).
    fn supernode<'a>(&'a self, sn: &'a SymbolicSupernodalCholesky<usize>, s: usize) -> Option<Front<'a>> {
        let (f, l) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
        if f >= self.split {
            return None;
        }
        let pattern = sn.supernode(s).pattern();
        let (w, ld) = (l - f, l - f + pattern.len());
        let start = sn.col_ptr_for_val()[s];
        let block = MatRef::from_column_major_slice(&self.real[start..start + ld * w], ld, w);
        Some(Front { f, w, e: l.min(self.split) - f, pattern, block })
    }

    /// `x ← L_real⁻¹ x` over the real columns (the rows after them receive the updates).
    fn forward_real(&self, sn: &SymbolicSupernodalCholesky<usize>, x: &mut Mat<f64>) {
        let mut gathered = Mat::<f64>::zeros(0, 2);
        for s in 0..sn.n_supernodes() {
            let Some(front) = self.supernode(sn, s) else { continue };
            let (l11, l21) = front.factor_blocks();
            solve_lower_triangular_in_place(l11, x.as_mut().subrows_mut(front.f, front.e), Par::Seq);
            gathered.resize_with(l21.nrows(), 2, |_, _| 0.0);
            matmul(gathered.as_mut(), Accum::Replace, l21, x.as_ref().subrows(front.f, front.e), 1.0, Par::Seq);
            for r in 0..l21.nrows() {
                let row = front.row(front.e + r);
                x[(row, 0)] -= gathered[(r, 0)];
                x[(row, 1)] -= gathered[(r, 1)];
            }
        }
    }

    /// `x ← L_realᵀ⁻¹ x` over the real columns, in reverse order.
    fn backward_real(&self, sn: &SymbolicSupernodalCholesky<usize>, x: &mut Mat<f64>) {
        for s in (0..sn.n_supernodes()).rev() {
            let Some(front) = self.supernode(sn, s) else { continue };
            let (l11, l21) = front.factor_blocks();
            let gathered = Mat::<f64>::from_fn(l21.nrows(), 2, |r, c| x[(front.row(front.e + r), c)]);
            let mut xs = x.as_mut().subrows_mut(front.f, front.e);
            matmul(xs.as_mut(), Accum::Add, l21.transpose(), gathered.as_ref(), -1.0, Par::Seq);
            solve_upper_triangular_in_place(l11.transpose(), xs, Par::Seq);
        }
    }

    /// `x_B ← L_S⁻ᴴ L_S⁻¹ x_B` on the trailing (complex) unknowns.
    fn solve_schur(&self, x: &mut Mat<f64>) {
        let nb = self.schur.nrows();
        if nb == 0 {
            return;
        }
        let mut y = Mat::<c64>::from_fn(nb, 1, |k, _| c64::new(x[(self.split + k, 0)], x[(self.split + k, 1)]));
        solve_lower_triangular_in_place(self.schur.as_ref(), y.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(self.schur.as_ref().adjoint(), y.as_mut(), Par::Seq);
        for k in 0..nb {
            x[(self.split + k, 0)] = y[(k, 0)].re;
            x[(self.split + k, 1)] = y[(k, 0)].im;
        }
    }
}

/// A supernode's real part: first column `f`, width `w` of which `e` are eliminated, its
/// below-diagonal rows and its factor block.
struct Front<'a> {
    f: usize,
    w: usize,
    e: usize,
    pattern: &'a [usize],
    block: MatRef<'a, f64>,
}

impl<'a> Front<'a> {
    /// Row (in elimination order) of front row `k`.
    fn row(&self, k: usize) -> usize {
        if k < self.w {
            self.f + k
        } else {
            self.pattern[k - self.w]
        }
    }

    /// The eliminated columns' diagonal block and the rows below it.
    fn factor_blocks(&self) -> (MatRef<'a, f64>, MatRef<'a, f64>) {
        let left = self.block.subcols(0, self.e);
        left.split_at_row(self.e)
    }
}

/// Adds the entries of H between trailing unknowns (both at or after `split` in elimination
/// order) to the dense Schur complement's lower triangle.
fn add_trailing_entries(
    schur: &mut Mat<c64>,
    lower: SparseColMatRef<'_, usize, c64>,
    inverse: Option<&[usize]>,
    split: usize,
) {
    let new = |i: usize| inverse.map_or(i, |p| p[i]);
    for j in 0..lower.ncols() {
        let pj = new(j);
        if pj < split {
            continue;
        }
        for (&i, &v) in lower.row_idx_of_col_raw(j).iter().zip(lower.val_of_col(j)) {
            let pi = new(i);
            if i < j || pi < split {
                continue;
            }
            let (r, c, v) = if pi >= pj { (pi, pj, v) } else { (pj, pi, v.conj()) };
            schur[(r - split, c - split)] += v;
        }
    }
}

/// Dense complex Cholesky of the Schur complement in place (lower triangle).
fn factor_dense(schur: &mut Mat<c64>, split: usize, n: usize) -> Result<()> {
    let par = super::parallelism();
    let nb = schur.nrows();
    let mut mem = MemBuffer::try_new(cholesky_in_place_scratch::<c64>(nb, par, Default::default()))
        .map_err(|_| Error::Internal("out of memory for the dense Cholesky workspace".into()))?;
    match cholesky_in_place(schur.as_mut(), Default::default(), par, MemStack::new(&mut mem), Default::default()) {
        Ok(_) => Ok(()),
        Err(LltError::NonPositivePivot { index }) => Err(Error::Numerical(format!(
            "the system matrix is not positive definite (pivot {} of {n}); the mesh may have extremely bad triangles",
            split + index
        ))),
    }
}

/// A Hermitian positive-definite solve: the split factorization when it pays, otherwise the
/// complex multifrontal Cholesky.
pub enum HermitianSolver {
    /// Real interior, dense complex Schur complement.
    Split(SplitHermitianSolver),
    /// Complex Cholesky throughout.
    Complex(CholeskySolver<c64>),
}

impl HermitianSolver {
    /// Orders (nested dissection with `coords`, one position per unknown), analyses and factors
    /// the matrix whose lower triangle is `lower`.
    pub fn new(lower: &SparseColMat<usize, c64>, coords: &[[f64; 3]]) -> Result<Self> {
        let complex = complex_unknowns(lower.as_ref());
        let count = complex.iter().filter(|&&c| c).count();
        if !split_pays(lower.nrows(), count) {
            return Ok(HermitianSolver::Complex(CholeskySolver::new(lower, Some(coords))?));
        }
        let (order, split) = order_complex_last(lower.symbolic(), coords, &complex);
        let pattern = CholeskyPattern::with_order(lower.symbolic(), Some(order))?;
        Ok(HermitianSolver::Split(SplitHermitianSolver::factor(&pattern, lower, split)?))
    }

    /// Solves for every column of `rhs` in place.
    pub fn solve_in_place(&self, rhs: &mut Mat<c64>) -> Result<()> {
        match self {
            HermitianSolver::Split(s) => s.solve_in_place(rhs),
            HermitianSolver::Complex(c) => c.solve_in_place(rhs),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lower_from_entries;

    /// A Hermitian positive-definite matrix on a `k × k` grid: a shifted weighted Laplacian,
    /// with an antisymmetric imaginary part on the edges of the outer ring (like the conformal
    /// map's boundary term).
    fn ring_matrix(k: u32) -> (SparseColMat<usize, c64>, Vec<[f64; 3]>) {
        let id = |i: u32, j: u32| j * k + i;
        let n = (k * k) as usize;
        let on_ring = |v: u32| {
            let (i, j) = (v % k, v / k);
            i == 0 || j == 0 || i == k - 1 || j == k - 1
        };
        let mut diagonal = vec![c64::new(0.05, 0.0); n];
        let mut lower = Vec::new();
        let mut coords = vec![[0.0; 3]; n];
        for j in 0..k {
            for i in 0..k {
                coords[id(i, j) as usize] = [i as f64, j as f64, 0.1 * (i as f64).sin()];
                let mut neighbours = Vec::new();
                if i + 1 < k {
                    neighbours.push(id(i + 1, j));
                }
                if j + 1 < k {
                    neighbours.push(id(i, j + 1));
                    if i + 1 < k {
                        neighbours.push(id(i + 1, j + 1));
                    }
                }
                for b in neighbours {
                    let a = id(i, j);
                    let w = 1.0 + 0.1 * ((a * 7 + b * 3) % 5) as f64;
                    diagonal[a as usize].re += w;
                    diagonal[b as usize].re += w;
                    let ring_edge = on_ring(a) && on_ring(b) && (a % k == b % k || a / k == b / k);
                    lower.push((b, a, c64::new(-w, if ring_edge { 0.4 } else { 0.0 })));
                }
            }
        }
        (lower_from_entries(&diagonal, lower).expect("matrix"), coords)
    }

    #[test]
    fn split_factorization_solves_like_the_complex_cholesky() {
        let (matrix, coords) = ring_matrix(30);
        let n = matrix.nrows();
        let complex = complex_unknowns(matrix.as_ref());
        assert_eq!(complex.iter().filter(|&&c| c).count(), 4 * 29, "the ring carries the imaginary part");
        let (order, split) = order_complex_last(matrix.symbolic(), &coords, &complex);
        assert_eq!(split, n - 4 * 29);
        let pattern = CholeskyPattern::with_order(matrix.symbolic(), Some(order)).expect("analysis");
        let solver = SplitHermitianSolver::factor(&pattern, &matrix, split).expect("factor");
        let rhs = Mat::<c64>::from_fn(n, 2, |i, c| c64::new((i as f64 * 0.3 + c as f64).sin(), (i as f64 * 0.7).cos()));
        let mut split = rhs.clone();
        solver.solve_in_place(&mut split).expect("solve");
        let mut reference = rhs.clone();
        CholeskySolver::new(&matrix, Some(&coords)).expect("complex factor").solve_in_place(&mut reference).unwrap();
        for c in 0..2 {
            for i in 0..n {
                assert!(
                    (split[(i, c)] - reference[(i, c)]).norm() < 1e-10,
                    "{i}: {} vs {}",
                    split[(i, c)],
                    reference[(i, c)]
                );
            }
        }
    }
}
