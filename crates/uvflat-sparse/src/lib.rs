//! Sparse linear algebra on top of `faer`: assembly of summed entries into compressed columns
//! (linear-time counting sort), sparse Cholesky (supernodal, with a geometric nested-dissection
//! ordering when unknowns have positions, AMD otherwise) for symmetric/Hermitian
//! positive-definite systems, and sparse LU for the others. A factorization is an object, so a
//! method that solves several times factors once.

pub mod error;
pub mod front_assembly;
pub mod frontal_lu;
pub mod gmres;
pub mod lagrange;
mod lu_front;
pub mod multifrontal;
pub mod ordering;
pub mod parallel;
mod permuted_lower;
pub mod polynomial;
pub mod split_hermitian;
pub mod supernodal_solve;
#[cfg(test)]
mod test_matrices;
pub mod union_find;

pub use error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::traits::ComplexField;
use faer::{Conj, Mat, Par, Side};
use std::sync::{Arc, OnceLock};
use supernodal_solve::Scalar;

/// Accumulates matrix entries; repeated (row, col) entries are summed.
pub struct TripletBuilder<T> {
    n: usize,
    rows: Vec<u32>,
    cols: Vec<u32>,
    values: Vec<T>,
}

impl<T: ComplexField + Copy + std::ops::Add<Output = T>> TripletBuilder<T> {
    /// An empty `n × n` matrix with room for `capacity` entries.
    pub fn with_capacity(n: usize, capacity: usize) -> Self {
        TripletBuilder {
            n,
            rows: Vec::with_capacity(capacity),
            cols: Vec::with_capacity(capacity),
            values: Vec::with_capacity(capacity),
        }
    }
    /// Adds `value` at (`row`, `col`).
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, value: T) {
        self.rows.push(row as u32);
        self.cols.push(col as u32);
        self.values.push(value);
    }
    /// Compressed-column matrix of the summed entries (rows sorted within each column).
    pub fn build(&self) -> Result<SparseColMat<usize, T>> {
        let n = self.n;
        let mut col_ptr = vec![0usize; n + 1];
        for &c in &self.cols {
            col_ptr[c as usize + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut fill = col_ptr.clone();
        let mut slots: Vec<(u32, T)> = vec![(0, T::zero_impl()); self.rows.len()];
        for k in 0..self.rows.len() {
            let c = self.cols[k] as usize;
            slots[fill[c]] = (self.rows[k], self.values[k]);
            fill[c] += 1;
        }
        let (mut out_ptr, mut row_idx, mut values) = (Vec::with_capacity(n + 1), Vec::new(), Vec::new());
        out_ptr.push(0);
        for c in 0..n {
            let column = &mut slots[col_ptr[c]..col_ptr[c + 1]];
            column.sort_unstable_by_key(|s| s.0);
            for &(r, v) in column.iter() {
                if row_idx.len() > out_ptr[c] && *row_idx.last().unwrap_or(&usize::MAX) == r as usize {
                    let last = values.len() - 1;
                    values[last] += v;
                } else {
                    row_idx.push(r as usize);
                    values.push(v);
                }
            }
            out_ptr.push(row_idx.len());
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, out_ptr, None, row_idx);
        Ok(SparseColMat::new(symbolic, values))
    }
}

/// Lower triangle (in compressed columns, rows sorted, diagonal first) of a symmetric or
/// Hermitian matrix given by its diagonal and its strictly lower entries `(row, col, value)`
/// (row > col; repeated positions are summed). A counting sort by column, then a sort of each
/// (short) column: O(nnz) for mesh matrices.
pub fn lower_from_entries<T: ComplexField + Copy>(
    diagonal: &[T],
    entries: Vec<(u32, u32, T)>,
) -> Result<SparseColMat<usize, T>> {
    let n = diagonal.len();
    if let Some(&(r, c, _)) = entries.iter().find(|&&(r, c, _)| r <= c || r as usize >= n) {
        return Err(Error::Internal(format!("entry ({r}, {c}) is not strictly lower in a matrix of size {n}")));
    }
    let mut start = vec![0usize; n + 1];
    for &(_, c, _) in &entries {
        start[c as usize + 1] += 1;
    }
    for c in 0..n {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut by_column: Vec<(u32, T)> = vec![(0, T::zero_impl()); entries.len()];
    for (r, c, v) in entries {
        by_column[fill[c as usize]] = (r, v);
        fill[c as usize] += 1;
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(n + by_column.len());
    let mut values = Vec::with_capacity(n + by_column.len());
    col_ptr.push(0);
    for c in 0..n {
        row_idx.push(c);
        values.push(diagonal[c]);
        let column = &mut by_column[start[c]..start[c + 1]];
        column.sort_unstable_by_key(|e| e.0);
        for &(r, v) in column.iter() {
            if *row_idx.last().unwrap_or(&usize::MAX) == r as usize {
                let last = values.len() - 1;
                values[last] += v;
            } else {
                row_idx.push(r as usize);
                values.push(v);
            }
        }
        col_ptr.push(row_idx.len());
    }
    let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    Ok(SparseColMat::new(symbolic, values))
}

/// Factors `lower` (real, symmetric positive definite), analysing its pattern on the first
/// call only (elimination order by geometric nested dissection of `points`, one per unknown):
/// for methods that factor a sequence of matrices with one pattern.
pub fn factor_reusing(
    pattern: &mut Option<CholeskyPattern>,
    lower: &SparseColMat<usize, f64>,
    points: &[[f64; 3]],
) -> Result<CholeskySolver<f64>> {
    let analysed = match pattern.take() {
        Some(p) => p,
        None => CholeskyPattern::new(lower.symbolic(), Some(points))?,
    };
    let solver = analysed.factor(lower);
    *pattern = Some(analysed);
    solver
}

/// Symbolic analysis of a sparse Cholesky factorization: the fill-reducing elimination order
/// and the (supernodal) structure of the factor. It depends only on the sparsity pattern, so a
/// method that factors several matrices with one pattern computes it once.
pub struct CholeskyPattern {
    symbolic: Arc<SymbolicCholesky<usize>>,
    /// The analysed lower-triangle pattern, for matrices given by their values alone.
    lower: SymbolicSparseColMat<usize>,
    /// Front position of each entry of `lower`, built by the first factorization from values.
    assembly: OnceLock<front_assembly::FrontAssembly>,
}

impl CholeskyPattern {
    /// Analyses the lower-triangular pattern (entries with row ≥ col). With `coords` (one 3D
    /// position per unknown) the elimination order is geometric nested dissection, otherwise
    /// AMD.
    pub fn new(lower: SymbolicSparseColMatRef<'_, usize>, coords: Option<&[[f64; 3]]>) -> Result<Self> {
        let order = coords.map(|c| {
            let adj = ordering::Adjacency::from_lower(lower.nrows(), lower.col_ptr(), lower.row_idx());
            ordering::nested_dissection(&adj, c)
        });
        Self::with_order(lower, order)
    }

    /// Analyses the pattern with a given elimination order (`order[k]` = unknown eliminated
    /// k-th, kept exactly: a split factorization relies on which unknowns come last), or AMD
    /// when `order` is `None`.
    pub fn with_order(lower: SymbolicSparseColMatRef<'_, usize>, order: Option<Vec<usize>>) -> Result<Self> {
        Self::analysed(lower, symbolic_cholesky(lower, order)?)
    }

    /// [`Self::with_order`] for an order that only has to reduce fill: it is renumbered in a
    /// postorder of the supernodal elimination tree, so that every subtree is a range of
    /// columns (what the parallel triangular solves split on, [`supernodal_solve::SolvePlan`]).
    /// Same elimination tree up to the renumbering, so the same fill and flops, but a second
    /// symbolic analysis: worth it for a pattern solved many times (a Newton loop), not for
    /// one solve (0.2 s of about 3 s for the 1.43M-face natural conformal map).
    pub fn with_fill_order(lower: SymbolicSparseColMatRef<'_, usize>, order: Option<Vec<usize>>) -> Result<Self> {
        let symbolic = symbolic_cholesky(lower, order)?;
        let symbolic = match (symbolic.raw(), symbolic.perm()) {
            (SymbolicCholeskyRaw::Supernodal(sn), Some(perm)) => match postorder_columns(sn) {
                Some(columns) => {
                    let fwd = perm.arrays().0;
                    symbolic_cholesky(lower, Some(columns.iter().map(|&k| fwd[k]).collect()))?
                }
                None => symbolic,
            },
            _ => symbolic,
        };
        Self::analysed(lower, symbolic)
    }

    fn analysed(lower: SymbolicSparseColMatRef<'_, usize>, symbolic: SymbolicCholesky<usize>) -> Result<Self> {
        Ok(CholeskyPattern {
            symbolic: Arc::new(symbolic),
            lower: lower.to_owned().map_err(|_| Error::Internal("out of memory for the matrix pattern".into()))?,
            assembly: OnceLock::new(),
        })
    }

    /// The analysed lower-triangle pattern: [`Self::factor_values`] and
    /// [`Self::refactor_values`] take values in its storage order.
    pub fn lower(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.lower.as_ref()
    }

    /// Number of stored entries of the factor L (including the zeros supernodes carry).
    pub fn factor_len(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Numeric factorization of a matrix with the analysed pattern (parallel multifrontal,
    /// [`multifrontal`]).
    pub fn factor<T: ComplexField + Copy + Send + Sync>(
        &self,
        lower: &SparseColMat<usize, T>,
    ) -> Result<CholeskySolver<T>> {
        self.factor_ref(lower.as_ref())
    }

    /// [`Self::factor`] of a borrowed matrix.
    pub fn factor_ref<T: ComplexField + Copy + Send + Sync>(
        &self,
        lower: SparseColMatRef<'_, usize, T>,
    ) -> Result<CholeskySolver<T>> {
        let mut solver = self.unfactored()?;
        // An empty system (e.g. a fixed-boundary map of a mesh without interior vertices) has
        // nothing to factor; faer's analysis of it is not supernodal.
        if self.symbolic.nrows() > 0 {
            multifrontal::factorize(&self.symbolic, lower, &mut solver.values)?;
        }
        Ok(solver)
    }

    /// [`Self::factor`] of the matrix with the pattern [`Self::lower`] and the given values.
    pub fn factor_values<T: ComplexField + Copy + Send + Sync>(&self, values: &[T]) -> Result<CholeskySolver<T>> {
        let mut solver = self.unfactored()?;
        self.refactor_values(values, &mut solver)?;
        Ok(solver)
    }

    /// A solver of this pattern with zeroed factor storage (not a factor yet).
    fn unfactored<T: ComplexField + Copy + Send + Sync>(&self) -> Result<CholeskySolver<T>> {
        Ok(CholeskySolver {
            symbolic: Arc::clone(&self.symbolic),
            values: try_zeroed_vec::<T>(self.symbolic.len_val())?,
            spare: Vec::new(),
            plan: OnceLock::new(),
        })
    }

    /// [`Self::refactor`] of the matrix with the pattern [`Self::lower`] and the given values.
    /// Each entry goes straight to its place in the fronts ([`front_assembly`], built on the
    /// first call): no permuted copy of the matrix is made.
    pub fn refactor_values<T: ComplexField + Copy + Send + Sync>(
        &self,
        values: &[T],
        solver: &mut CholeskySolver<T>,
    ) -> Result<()> {
        if !Arc::ptr_eq(&self.symbolic, &solver.symbolic) {
            return Err(Error::Internal("refactor: the solver belongs to another pattern".into()));
        }
        let Some(sn) = supernodal_for_solve(&self.symbolic, self.symbolic.nrows(), "the Cholesky analysis")? else {
            return Ok(()); // an empty system: nothing to factor
        };
        let inverse = self.symbolic.perm().map(|p| p.arrays().1);
        let map = self.assembly.get_or_init(|| front_assembly::FrontAssembly::new(self.lower.as_ref(), inverse, sn));
        multifrontal::factorize_mapped(&self.symbolic, map, values, &mut solver.values, &mut solver.spare)
    }

    /// [`Self::factor`] into the storage of an earlier factorization of this pattern (a Newton
    /// loop refactoring one pattern many times saves the allocation and first-touch page
    /// faults of the factor, 800 MB on the 4 × 104k-unknown system of `crates/uvflat-core/benches/pgp.rs`). On
    /// error `solver` holds no valid factor, and must be refactored before it is used.
    pub fn refactor<T: ComplexField + Copy + Send + Sync>(
        &self,
        lower: SparseColMatRef<'_, usize, T>,
        solver: &mut CholeskySolver<T>,
    ) -> Result<()> {
        if !Arc::ptr_eq(&self.symbolic, &solver.symbolic) {
            return Err(Error::Internal("refactor: the solver belongs to another pattern".into()));
        }
        if self.symbolic.nrows() > 0 {
            // Every supernode's block is cleared before it is assembled.
            multifrontal::factorize_reusing(&self.symbolic, lower, &mut solver.values, &mut solver.spare)?;
        }
        Ok(())
    }
}

/// faer's supernodal symbolic Cholesky of the lower-triangle pattern with the elimination order
/// `order` (`order[k]` = unknown eliminated k-th), or AMD's.
fn symbolic_cholesky(
    lower: SymbolicSparseColMatRef<'_, usize>,
    order: Option<Vec<usize>>,
) -> Result<SymbolicCholesky<usize>> {
    let n = lower.nrows();
    match order {
        Some(fwd) => {
            if fwd.len() != n {
                return Err(Error::Internal(format!("elimination order of length {} for {n} unknowns", fwd.len())));
            }
            let mut inv = vec![usize::MAX; n];
            for (k, &v) in fwd.iter().enumerate() {
                if v >= n || inv[v] != usize::MAX {
                    return Err(Error::Internal(format!("elimination order is not a permutation (unknown {v})")));
                }
                inv[v] = k;
            }
            let ord = SymmetricOrdering::Custom(PermRef::new_checked(&fwd, &inv, n));
            factorize_symbolic_cholesky(lower, Side::Lower, ord, supernodal())
                .map_err(|e| Error::Internal(format!("symbolic Cholesky failed: {e:?}")))
        }
        None => {
            let symbolic = factorize_symbolic_cholesky(lower, Side::Lower, SymmetricOrdering::Amd, supernodal())
                .map_err(|e| Error::Internal(format!("symbolic Cholesky failed: {e:?}")))?;
            match (symbolic.raw(), symbolic.perm()) {
                // AMD counts no flops for a diagonal matrix (no off-diagonal entry: e.g. a
                // fixed-boundary map whose interior vertices are not adjacent), and faer then
                // picks its simplicial structure even when the supernodal one is forced; the same
                // order given as a custom one is analysed as supernodal.
                (SymbolicCholeskyRaw::Simplicial(_), Some(perm)) if n > 0 => {
                    symbolic_cholesky(lower, Some(perm.arrays().0.to_vec()))
                }
                _ => Ok(symbolic),
            }
        }
    }
}

/// The columns (of the factor's numbering) in a postorder of the supernodal elimination tree —
/// children before parents, each subtree contiguous, a supernode's columns kept together and
/// in order — or `None` when the numbering already is one. Eliminating in a postorder of the
/// elimination tree gives the same factor up to the renumbering (Liu 1990, "The role of
/// elimination trees in sparse factorization", §3.2).
fn postorder_columns(sn: &SymbolicSupernodalCholesky<usize>) -> Option<Vec<usize>> {
    let count = sn.n_supernodes();
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); count];
    let mut roots = Vec::new();
    for (s, parent) in supernodal_solve::supernode_parents(sn).into_iter().enumerate() {
        match parent {
            Some(p) => children[p].push(s),
            None => roots.push(s),
        }
    }
    let mut post = Vec::with_capacity(count);
    for root in roots {
        // Iterative depth-first search: (supernode, next child to visit).
        let mut stack = vec![(root, 0usize)];
        while let Some((s, next)) = stack.pop() {
            if next < children[s].len() {
                stack.push((s, next + 1));
                stack.push((children[s][next], 0));
            } else {
                post.push(s);
            }
        }
    }
    if post.iter().enumerate().all(|(k, &s)| k == s) {
        return None;
    }
    Some(post.iter().flat_map(|&s| sn.supernode_begin()[s]..sn.supernode_end()[s]).collect())
}

/// Sparse Cholesky factorization `A = L Lᴴ` of a symmetric (Hermitian) positive-definite
/// matrix given by its lower triangle.
pub struct CholeskySolver<T> {
    symbolic: Arc<SymbolicCholesky<usize>>,
    values: Vec<T>,
    /// Front buffers kept by [`CholeskyPattern::refactor`] for the next refactorization
    /// (empty after [`CholeskyPattern::factor`]).
    spare: Vec<Vec<T>>,
    /// The parallel schedule of the triangular solves, made by the first solve that uses it.
    plan: OnceLock<Option<supernodal_solve::SolvePlan>>,
}

impl<T: ComplexField + Copy + Send + Sync + Scalar> CholeskySolver<T> {
    /// Analyses and factors the matrix (entries with row ≥ col are read). With `coords` (one 3D
    /// position per unknown) the elimination order is geometric nested dissection, otherwise AMD.
    pub fn new(lower: &SparseColMat<usize, T>, coords: Option<&[[f64; 3]]>) -> Result<Self> {
        CholeskyPattern::new(lower.symbolic(), coords)?.factor(lower)
    }

    /// Number of unknowns.
    pub fn dim(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Stored values of the factor L.
    pub fn factor_len(&self) -> usize {
        self.values.len()
    }

    /// The elimination order: `order[k]` is the unknown eliminated k-th (`None`: the identity).
    pub fn elimination_order(&self) -> Option<&[usize]> {
        self.symbolic.perm().map(|p| p.arrays().0)
    }

    /// Solves for every column of `rhs` in place.
    pub fn solve_in_place(&self, rhs: &mut Mat<T>) -> Result<()> {
        self.solve_in_place_with(rhs, faer::get_global_parallelism())
    }

    /// [`Self::solve_in_place`] with the given parallelism for many right-hand sides; up to 4
    /// columns use the sequential row-interleaved solve ([`supernodal_solve`]).
    pub fn solve_in_place_with(&self, rhs: &mut Mat<T>, par: Par) -> Result<()> {
        match rhs.ncols() {
            1 => return self.solve_columns::<1>(rhs),
            2 => return self.solve_columns::<2>(rhs),
            3 => return self.solve_columns::<3>(rhs),
            4 => return self.solve_columns::<4>(rhs),
            _ => {}
        }
        let mut mem = MemBuffer::try_new(self.symbolic.solve_in_place_scratch::<T>(rhs.ncols(), par))
            .map_err(|_| Error::Internal("out of memory for the solve workspace".into()))?;
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut(),
            par,
            MemStack::new(&mut mem),
        );
        Ok(())
    }

    /// Solves `K ≤ 4` columns through the row-interleaved kernels.
    fn solve_columns<const K: usize>(&self, rhs: &mut Mat<T>) -> Result<()> {
        let n = self.dim();
        let order = self.elimination_order();
        let original = |k: usize| order.map_or(k, |o| o[k]);
        let mut x: Vec<[T; K]> = (0..n).map(|k| std::array::from_fn(|c| rhs[(original(k), c)])).collect();
        self.solve_permuted_rows(&mut x, &mut Vec::new(), None)?;
        for (k, row) in x.iter().enumerate() {
            for (c, &v) in row.iter().enumerate() {
                rhs[(original(k), c)] = v;
            }
        }
        Ok(())
    }

    /// The supernodes a solve must visit in its forward substitution when only the rows
    /// `rows` (elimination order) of the right-hand side are nonzero.
    pub fn active_supernodes(&self, rows: impl IntoIterator<Item = usize>) -> Option<Vec<bool>> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => Some(supernodal_solve::active_supernodes(sn, rows)),
            _ => None,
        }
    }

    /// Solves `A X = B` in place for K right-hand sides stored row-interleaved and already in
    /// elimination order (row k holds unknown `elimination_order()[k]`). `scratch` is reused.
    /// `active` (from [`Self::active_supernodes`]) skips supernodes a sparse right-hand side
    /// does not reach.
    pub fn solve_permuted_rows<const K: usize>(
        &self,
        x: &mut [[T; K]],
        scratch: &mut Vec<[T; K]>,
        active: Option<&[bool]>,
    ) -> Result<()> {
        let Some(sn) = supernodal_for_solve(&self.symbolic, x.len(), "the Cholesky factor")? else { return Ok(()) };
        let factor = supernodal_solve::Factor { sn, values: &self.values, blocks: 1, which: 0, unit_diagonal: false };
        match (active, self.plan.get_or_init(|| supernodal_solve::SolvePlan::new(sn))) {
            (None, Some(plan)) => {
                factor.forward_parallel(plan, x);
                factor.backward_transposed_parallel(plan, true, x);
            }
            _ => {
                factor.forward(x, scratch, active);
                factor.backward_transposed(true, x, scratch);
            }
        }
        Ok(())
    }
}

/// Symbolic parameters: always the supernodal structure, which the multifrontal numeric
/// factorization works on.
fn supernodal() -> CholeskySymbolicParams<'static> {
    CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    }
}

/// The supernodal structure of a factor for a solve with `rows` rows: an error when `rows` is
/// not the factor's dimension or the analysis is not supernodal (`what` names the factor),
/// `None` for an empty system (nothing to solve).
pub(crate) fn supernodal_for_solve<'a>(
    symbolic: &'a SymbolicCholesky<usize>,
    rows: usize,
    what: &str,
) -> Result<Option<&'a SymbolicSupernodalCholesky<usize>>> {
    if rows != symbolic.nrows() {
        return Err(Error::Internal(format!("{rows} rows given to a solve of {} unknowns", symbolic.nrows())));
    }
    if rows == 0 {
        return Ok(None);
    }
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => Ok(Some(sn)),
        _ => Err(Error::Internal(format!("{what} is not supernodal"))),
    }
}

/// A zeroed vector, filled in parallel (the first touch of a large allocation is page faults).
fn try_zeroed_vec<T: ComplexField + Copy + Send + Sync>(len: usize) -> Result<Vec<T>> {
    use rayon::iter::{repeat_n, ParallelExtend};
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|_| Error::Internal(format!("out of memory for a Cholesky factor of {len} entries")))?;
    if len < crate::parallel::SEQUENTIAL_BELOW {
        v.resize(len, T::zero_impl());
    } else {
        v.par_extend(repeat_n(T::zero_impl(), len));
    }
    Ok(v)
}

/// Sparse LU factorization for non-symmetric systems with a symmetric pattern (the
/// fixed-boundary maps with Floater's, mean-value or authalic weights): multifrontal LU without
/// pivoting on a nested-dissection ordering ([`frontal_lu`]), with faer's LU with partial
/// pivoting (COLAMD ordering, much more fill) as the fallback when a pivot vanishes or a solve's
/// backward error is large.
pub struct LuSolver {
    matrix: SparseColMat<usize, f64>,
    frontal: Option<frontal_lu::SparseLu>,
}

/// Largest accepted normwise backward error `‖Ax − b‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞)` of a solve with the
/// unpivoted factors (a stable solve gives a small multiple of the machine epsilon).
const LU_BACKWARD_ERROR: f64 = 1e-10;

impl LuSolver {
    /// Factors a square matrix (AMD ordering).
    pub fn new(matrix: &SparseColMat<usize, f64>) -> Result<Self> {
        Self::with_coords(matrix, None)
    }

    /// Factors a square matrix; with `coords` (one 3D position per unknown) the elimination
    /// order is nested dissection.
    pub fn with_coords(matrix: &SparseColMat<usize, f64>, coords: Option<&[[f64; 3]]>) -> Result<Self> {
        let pattern = symmetric_lower_pattern(matrix.as_ref());
        let analysis = CholeskyPattern::new(pattern.as_ref(), coords)?;
        let frontal = match frontal_lu::SparseLu::new(Arc::clone(&analysis.symbolic), matrix.as_ref()) {
            Ok(lu) => Some(lu),
            Err(Error::Numerical(_)) => None,
            Err(e) => return Err(e),
        };
        Ok(LuSolver { matrix: matrix.clone(), frontal })
    }

    /// Solves for every column of `rhs` in place.
    pub fn solve_in_place(&self, rhs: &mut Mat<f64>) -> Result<()> {
        self.solve_in_place_maybe_transposed(rhs, false)
    }

    /// Solves `Aᵀ X = B` for every column of `rhs` in place.
    pub fn solve_transpose_in_place(&self, rhs: &mut Mat<f64>) -> Result<()> {
        self.solve_in_place_maybe_transposed(rhs, true)
    }

    fn solve_in_place_maybe_transposed(&self, rhs: &mut Mat<f64>, transpose: bool) -> Result<()> {
        if let Some(lu) = &self.frontal {
            let mut x = rhs.clone();
            lu.solve_in_place(&mut x, transpose)?;
            if backward_error(self.matrix.as_ref(), &x, rhs, transpose) <= LU_BACKWARD_ERROR {
                *rhs = x;
                return Ok(());
            }
        }
        let lu = self.matrix.sp_lu().map_err(|e| Error::Numerical(format!("the system matrix is singular ({e:?})")))?;
        if transpose {
            lu.solve_transpose_in_place(rhs.as_mut());
        } else {
            lu.solve_in_place(rhs.as_mut());
        }
        Ok(())
    }

    /// The unpivoted multifrontal factors, when they exist (the caller must check the backward
    /// error of solves made with them: [`Self::backward_error_rows`]).
    pub fn frontal(&self) -> Option<&frontal_lu::SparseLu> {
        self.frontal.as_ref()
    }

    /// Normwise backward error (as [`LU_BACKWARD_ERROR`] measures it) of `x` as a solution of
    /// `A x = b` (`Aᵀ x = b` when `transpose`), for row-interleaved K columns in the original
    /// numbering. True when it is small enough to accept the solve.
    /// `inverse[i]` is the row of `x` and `b` holding unknown i (`None`: row i).
    pub fn accepts_rows<const K: usize>(
        &self,
        x: &[[f64; K]],
        b: &[[f64; K]],
        transpose: bool,
        inverse: Option<&[usize]>,
    ) -> bool {
        backward_error_rows(self.matrix.as_ref(), x, b, transpose, inverse) <= LU_BACKWARD_ERROR
    }

    /// Solves with faer's pivoted LU (the fallback when the unpivoted factors are unstable).
    pub fn solve_pivoted_in_place(&self, rhs: &mut Mat<f64>, transpose: bool) -> Result<()> {
        let lu = self.matrix.sp_lu().map_err(|e| Error::Numerical(format!("the system matrix is singular ({e:?})")))?;
        if transpose {
            lu.solve_transpose_in_place(rhs.as_mut());
        } else {
            lu.solve_in_place(rhs.as_mut());
        }
        Ok(())
    }
}

/// The pattern of `A + Aᵀ` on and below the diagonal (diagonal always present).
fn symmetric_lower_pattern(a: SparseColMatRef<'_, usize, f64>) -> SymbolicSparseColMat<usize> {
    let n = a.ncols();
    let mut columns: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
    for j in 0..n {
        for &i in a.row_idx_of_col_raw(j) {
            columns[i.min(j)].push(i.max(j));
        }
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for mut rows in columns {
        rows.sort_unstable();
        rows.dedup();
        row_idx.extend(rows);
        col_ptr.push(row_idx.len());
    }
    SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx)
}

/// Largest normwise backward error over the columns of `x` as a solution of `A x = b` (`Aᵀ x =
/// b` when `transpose`).
fn backward_error(a: SparseColMatRef<'_, usize, f64>, x: &Mat<f64>, b: &Mat<f64>, transpose: bool) -> f64 {
    (0..x.ncols())
        .map(|c| {
            let xr: Vec<[f64; 1]> = x.col_as_slice(c).iter().map(|&v| [v]).collect();
            let br: Vec<[f64; 1]> = b.col_as_slice(c).iter().map(|&v| [v]).collect();
            backward_error_rows(a, &xr, &br, transpose, None)
        })
        .fold(0.0, f64::max)
}

/// [`backward_error`] for row-interleaved columns: the largest over the K columns of
/// `‖Ax − b‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞)` (with Aᵀ and ‖Aᵀ‖∞ when `transpose`); NaN gives +∞.
/// Unknown i is row `inverse[i]` of `x` and `b` (row i without `inverse`).
fn backward_error_rows<const K: usize>(
    a: SparseColMatRef<'_, usize, f64>,
    x: &[[f64; K]],
    b: &[[f64; K]],
    transpose: bool,
    inverse: Option<&[usize]>,
) -> f64 {
    let n = a.nrows();
    let row = |i: usize| inverse.map_or(i, |p| p[i]);
    let mut sums = vec![0.0f64; n];
    let mut r: Vec<[f64; K]> = b.iter().map(|row| row.map(|v| -v)).collect();
    for j in 0..a.ncols() {
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            // A[i, j] = v: (A x)_i += v x_j, (Aᵀ x)_j += v x_i.
            let (out, input) = if transpose { (row(j), row(i)) } else { (row(i), row(j)) };
            sums[out] += v.abs();
            for c in 0..K {
                r[out][c] += v * x[input][c];
            }
        }
    }
    let a_norm = sums.iter().fold(0.0f64, |m, &v| m.max(v));
    let inf = |m: f64, e: f64| if e.is_nan() { f64::INFINITY } else { m.max(e.abs()) };
    (0..K)
        .map(|c| {
            let r_norm = r.iter().fold(0.0, |m, row| inf(m, row[c]));
            let x_norm = x.iter().fold(0.0, |m, row| inf(m, row[c]));
            let b_norm = b.iter().fold(0.0, |m, row| inf(m, row[c]));
            let scale = a_norm * x_norm + b_norm;
            if r_norm.is_infinite() || x_norm.is_infinite() {
                f64::INFINITY
            } else if scale == 0.0 {
                0.0
            } else {
                r_norm / scale
            }
        })
        .fold(0.0, f64::max)
}

/// Fails with a numerical error when a solution holds NaN or infinity.
pub fn require_finite(values: impl IntoIterator<Item = f64>, what: &str) -> Result<()> {
    if values.into_iter().all(f64::is_finite) {
        Ok(())
    } else {
        Err(Error::Numerical(format!("the {what} solve produced non-finite values")))
    }
}

/// Parallelism used by the factorizations (all cores, through rayon).
pub fn parallelism() -> Par {
    faer::get_global_parallelism()
}
