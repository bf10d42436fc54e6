//! Triangular solves with a supernodal factor for a few right-hand sides at once (the boundary
//! editor's re-solve, inverse iteration, the adjoint of the boundary optimization), written for
//! memory bandwidth: the right-hand sides are stored row-interleaved (`[[T; K]]`, K values per
//! unknown) so each entry of the factor is loaded once per pass and applied to all K columns,
//! and each supernode column `L[j.., j]` — contiguous in faer's supernodal layout — is streamed
//! once (Rothberg & Gupta 1992 / Liu 1992 §6 describe the same column-oriented supernodal
//! forward and backward substitution).
//!
//! Forward, supernode `s` (columns `f..l`, below-diagonal rows `P_s`): for each column j,
//! `x_j ← x_j / L_jj` (unless unit), `x_i −= L_ij x_j` for the rows of `f..l` below j, and the
//! contributions to the rows `P_s` are summed in a short buffer, scattered once per supernode.
//! Backward with the (conjugate) transpose of such a factor: gather `x[P_s]` once, then for each
//! column j from the last, `x_j ← (x_j − Σ_i conj(L_ij) x_i) / conj(L_jj)`.
//!
//! Within a supernode the work is sequential: with K ≤ 4 columns it is a few hundred
//! multiply-adds, below the cost of handing it to another thread (faer's solve with
//! `Par::rayon` was measured slower than sequential for two columns, commit 1213e07). Large
//! factors (≥ 2M entries) of [`super::CholeskySolver`] are instead split into disjoint
//! subtrees of the elimination tree ([`SolvePlan`]), each a task of whole supernodes, so both
//! cores stream their part of the factor (on this machine one core reads about 14 GB/s and two
//! about 23 GB/s); the supernodes above the subtrees are done sequentially. The factor values
//! are those of [`super::CholeskySolver`] (block of L per supernode) and
//! [`super::frontal_lu::SparseLu`] (block of L, then block of Uᵀ, per supernode).

use faer::c64;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use rayon::prelude::*;
use std::ops::{Add, AddAssign, Div, Mul, Sub, SubAssign};

/// The scalars of the factors: `f64` and `c64`.
pub trait Scalar:
    Copy
    + Send
    + Sync
    + Default
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + AddAssign
    + SubAssign
{
    /// Complex conjugate (identity for reals).
    fn conjugate(self) -> Self;
}

impl Scalar for f64 {
    #[inline(always)]
    fn conjugate(self) -> Self {
        self
    }
}

impl Scalar for c64 {
    #[inline(always)]
    fn conjugate(self) -> Self {
        self.conj()
    }
}

/// Where one triangular factor is stored: the supernodal structure and, per supernode, a
/// `(w + m) × w` column-major block at `blocks · col_ptr_for_val[s] + which · len_s` (Cholesky:
/// `blocks = 1`, `which = 0`; LU: `blocks = 2`, `which` 0 for L, 1 for Uᵀ).
pub struct Factor<'a, T> {
    /// Supernodal structure.
    pub sn: &'a SymbolicSupernodalCholesky<usize>,
    /// All the factor values.
    pub values: &'a [T],
    /// Blocks stored per supernode (1 or 2).
    pub blocks: usize,
    /// Which of them this factor is.
    pub which: usize,
    /// True when the diagonal is 1 (and not read).
    pub unit_diagonal: bool,
}

impl<'a, T: Scalar> Factor<'a, T> {
    /// Supernode `s`'s columns `f..l`, its below-diagonal rows, and its block.
    #[inline]
    fn supernode(&self, s: usize) -> (usize, usize, &'a [usize], &'a [T]) {
        let sn = self.sn;
        let (f, l) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
        let pattern = sn.supernode(s).pattern();
        let start = sn.col_ptr_for_val()[s];
        let len = sn.col_ptr_for_val()[s + 1] - start;
        let at = self.blocks * start + self.which * len;
        (f, l, pattern, &self.values[at..at + len])
    }

    /// Largest below-diagonal row count of a supernode (the scratch length of the solves).
    pub fn max_pattern(&self) -> usize {
        (0..self.sn.n_supernodes()).map(|s| self.sn.supernode(s).pattern().len()).max().unwrap_or(0)
    }

    /// Solves `L y = x` in place (x in the factor's elimination order). `scratch` is resized
    /// as needed and can be reused between calls. With `active`, supernodes marked false are
    /// skipped: correct when their rows of x are zero and no descendant is active (see
    /// [`active_supernodes`]), as for a sparse right-hand side.
    pub fn forward<const K: usize>(&self, x: &mut [[T; K]], scratch: &mut Vec<[T; K]>, active: Option<&[bool]>) {
        for s in 0..self.sn.n_supernodes() {
            if active.is_some_and(|a| !a[s]) {
                continue;
            }
            let (f, l, pattern, _) = self.supernode(s);
            self.forward_supernode(s, &mut x[f..l], scratch);
            for (&row, acc) in pattern.iter().zip(scratch.iter()) {
                for c in 0..K {
                    x[row][c] -= acc[c];
                }
            }
        }
    }

    /// The forward substitution of supernode `s` on its own rows `xs` (`x[f..l]`), leaving in
    /// `scratch` what is to be subtracted from the rows of its pattern.
    fn forward_supernode<const K: usize>(&self, s: usize, xs: &mut [[T; K]], scratch: &mut Vec<[T; K]>) {
        let (f, l, pattern, block) = self.supernode(s);
        let (w, m) = (l - f, pattern.len());
        let ld = w + m;
        scratch.clear();
        scratch.resize(m, [T::default(); K]);
        let mut j = 0;
        while j < w {
            let jb = (w - j).min(BLOCK_COLUMNS);
            // The jb × jb diagonal block, column by column.
            for jj in j..j + jb {
                let column = &block[jj * ld..(jj + 1) * ld];
                if !self.unit_diagonal {
                    let d = column[jj];
                    for v in &mut xs[jj] {
                        *v = *v / d;
                    }
                }
                let xj = xs[jj];
                for (xi, &a) in xs[jj + 1..j + jb].iter_mut().zip(&column[jj + 1..j + jb]) {
                    for c in 0..K {
                        xi[c] -= a * xj[c];
                    }
                }
            }
            // Those columns applied to the rows below the block: the rest of the diagonal
            // block of the supernode, then its below-diagonal rows (into `scratch`).
            let columns: [&[T]; BLOCK_COLUMNS] =
                std::array::from_fn(|k| if k < jb { &block[(j + k) * ld..(j + k + 1) * ld] } else { &[] });
            let xj: [[T; K]; BLOCK_COLUMNS] =
                std::array::from_fn(|k| if k < jb { xs[j + k] } else { [T::default(); K] });
            let (head, tail) = (j + jb..w, w..ld);
            if jb == BLOCK_COLUMNS {
                for (xi, i) in xs[head.clone()].iter_mut().zip(head) {
                    let acc = combine4(&columns, i, &xj);
                    for c in 0..K {
                        xi[c] -= acc[c];
                    }
                }
                for (acc_i, i) in scratch.iter_mut().zip(tail) {
                    let acc = combine4(&columns, i, &xj);
                    for c in 0..K {
                        acc_i[c] += acc[c];
                    }
                }
            } else {
                for k in 0..jb {
                    let column = columns[k];
                    for (xi, &a) in xs[head.clone()].iter_mut().zip(&column[head.clone()]) {
                        for c in 0..K {
                            xi[c] -= a * xj[k][c];
                        }
                    }
                    for (acc, &a) in scratch.iter_mut().zip(&column[tail.clone()]) {
                        for c in 0..K {
                            acc[c] += a * xj[k][c];
                        }
                    }
                }
            }
            j += jb;
        }
    }

    /// Solves `Lᴴ y = x` (`conjugate`) or `Lᵀ y = x` in place, x in elimination order.
    pub fn backward_transposed<const K: usize>(&self, conjugate: bool, x: &mut [[T; K]], scratch: &mut Vec<[T; K]>) {
        for s in (0..self.sn.n_supernodes()).rev() {
            let (f, l, pattern, _) = self.supernode(s);
            scratch.clear();
            scratch.extend(pattern.iter().map(|&row| x[row]));
            self.backward_supernode(s, conjugate, &mut x[f..l], scratch);
        }
    }

    /// The backward substitution of supernode `s` on its own rows `xs` (`x[f..l]`), given the
    /// (final) values of the rows of its pattern in `scratch`.
    fn backward_supernode<const K: usize>(&self, s: usize, conjugate: bool, xs: &mut [[T; K]], scratch: &[[T; K]]) {
        let cj = |a: T| if conjugate { a.conjugate() } else { a };
        let (f, l, pattern, block) = self.supernode(s);
        let (w, m) = (l - f, pattern.len());
        let ld = w + m;
        let mut end = w;
        while end > 0 {
            let jb = end.min(BLOCK_COLUMNS);
            let j = end - jb;
            // Rows below the block (final already): the rest of the diagonal block, then
            // the below-diagonal rows.
            let mut sums: [[T; K]; BLOCK_COLUMNS] = [[T::default(); K]; BLOCK_COLUMNS];
            if jb == BLOCK_COLUMNS {
                let columns: [&[T]; BLOCK_COLUMNS] = std::array::from_fn(|k| &block[(j + k) * ld..(j + k + 1) * ld]);
                dot4(&columns, end, &xs[end..w], conjugate, &mut sums);
                dot4(&columns, w, scratch, conjugate, &mut sums);
            } else {
                for (k, sum) in sums.iter_mut().enumerate().take(jb) {
                    let column = &block[(j + k) * ld..(j + k + 1) * ld];
                    let (a, b) = (
                        dot::<T, K>(&column[end..w], &xs[end..w], conjugate),
                        dot::<T, K>(&column[w..], scratch, conjugate),
                    );
                    for c in 0..K {
                        sum[c] = a[c] + b[c];
                    }
                }
            }
            // The jb × jb diagonal block, from its last column.
            for jj in (j..end).rev() {
                let column = &block[jj * ld..(jj + 1) * ld];
                let mut v = xs[jj];
                for c in 0..K {
                    v[c] -= sums[jj - j][c];
                }
                for ii in jj + 1..end {
                    let a = cj(column[ii]);
                    for c in 0..K {
                        v[c] -= a * xs[ii][c];
                    }
                }
                if !self.unit_diagonal {
                    let d = cj(column[jj]);
                    for e in &mut v {
                        *e = *e / d;
                    }
                }
                xs[jj] = v;
            }
            end = j;
        }
    }
}

/// Disjoint subtrees of the supernodal elimination tree, whose substitutions run in parallel,
/// and the supernodes above them (Liu 1992, §6: columns in disjoint subtrees of the elimination
/// tree are independent). In the forward substitution a subtree's supernodes update only rows
/// of the subtree and rows of its root's pattern (the structure of a column of L lies within
/// its parent's column and the parent itself), which a task sums in its own buffer; in the
/// backward one they read only those rows, which are final once the supernodes above are done.
pub struct SolvePlan {
    tasks: Vec<SolveTask>,
    /// Supernodes in no task, ascending.
    top: Vec<usize>,
}

/// A subtree: supernodes `first..=root`, columns `begin..end`.
struct SolveTask {
    first: usize,
    root: usize,
    begin: usize,
    end: usize,
}

/// Factors with fewer stored entries are solved sequentially (the tasks would cost more than
/// they save).
const PARALLEL_SOLVE_ENTRIES: usize = 1 << 21;
/// Subtrees holding less than this fraction of the factor are one task each.
const SOLVE_TASK_FRACTION: f64 = 1.0 / 64.0;

impl SolvePlan {
    /// The plan for a supernodal structure, or `None` when the factor is too small or its
    /// supernodes are not numbered in postorder (every subtree a contiguous range).
    pub fn new(sn: &SymbolicSupernodalCholesky<usize>) -> Option<Self> {
        Self::for_factors_from(sn, PARALLEL_SOLVE_ENTRIES)
    }

    /// [`Self::new`] with the smallest factor size worth a plan.
    fn for_factors_from(sn: &SymbolicSupernodalCholesky<usize>, min_entries: usize) -> Option<Self> {
        let count = sn.n_supernodes();
        let parent = supernode_parents(sn);
        let mut weight: Vec<usize> =
            (0..count).map(|s| sn.col_ptr_for_val()[s + 1] - sn.col_ptr_for_val()[s]).collect();
        let total = weight.iter().sum::<usize>();
        if total < min_entries {
            return None;
        }
        let mut first = (0..count).collect::<Vec<_>>();
        let mut size = vec![1usize; count];
        for s in 0..count {
            if size[s] != s - first[s] + 1 {
                return None;
            }
            if let Some(p) = parent[s] {
                if p <= s {
                    return None;
                }
                weight[p] += weight[s];
                size[p] += size[s];
                first[p] = first[p].min(first[s]);
            }
        }
        let limit = (total as f64 * SOLVE_TASK_FRACTION) as usize;
        let roots: Vec<usize> =
            (0..count).filter(|&s| weight[s] <= limit && parent[s].is_none_or(|p| weight[p] > limit)).collect();
        let mut covered = vec![false; count];
        let tasks: Vec<SolveTask> = roots
            .iter()
            .map(|&root| {
                covered[first[root]..=root].fill(true);
                SolveTask {
                    first: first[root],
                    root,
                    begin: sn.supernode_begin()[first[root]],
                    end: sn.supernode_end()[root],
                }
            })
            .collect();
        let top = (0..count).filter(|&s| !covered[s]).collect();
        Some(SolvePlan { tasks, top })
    }
}

impl<T: Scalar> Factor<'_, T> {
    /// [`Self::forward`] of a dense right-hand side, the subtrees of `plan` in parallel.
    pub fn forward_parallel<const K: usize>(&self, plan: &SolvePlan, x: &mut [[T; K]]) {
        let outputs: Vec<Vec<[T; K]>> = task_slices(plan, x)
            .into_par_iter()
            .map(|(task, xs)| {
                let root_pattern = self.sn.supernode(task.root).pattern();
                let mut out = vec![[T::default(); K]; root_pattern.len()];
                let mut scratch = Vec::new();
                for s in task.first..=task.root {
                    let (f, l, pattern, _) = self.supernode(s);
                    self.forward_supernode(s, &mut xs[f - task.begin..l - task.begin], &mut scratch);
                    for (&row, acc) in pattern.iter().zip(&scratch) {
                        let target = if row < task.end {
                            &mut xs[row - task.begin]
                        } else {
                            &mut out[root_pattern.partition_point(|&p| p < row)]
                        };
                        for c in 0..K {
                            target[c] -= acc[c];
                        }
                    }
                }
                out
            })
            .collect();
        for (task, out) in plan.tasks.iter().zip(outputs) {
            for (&row, v) in self.sn.supernode(task.root).pattern().iter().zip(out) {
                for c in 0..K {
                    x[row][c] += v[c];
                }
            }
        }
        let mut scratch = Vec::new();
        for &s in &plan.top {
            let (f, l, pattern, _) = self.supernode(s);
            self.forward_supernode(s, &mut x[f..l], &mut scratch);
            for (&row, acc) in pattern.iter().zip(&scratch) {
                for c in 0..K {
                    x[row][c] -= acc[c];
                }
            }
        }
    }

    /// [`Self::backward_transposed`], the subtrees of `plan` in parallel.
    pub fn backward_transposed_parallel<const K: usize>(&self, plan: &SolvePlan, conjugate: bool, x: &mut [[T; K]]) {
        let mut scratch = Vec::new();
        for &s in plan.top.iter().rev() {
            let (f, l, pattern, _) = self.supernode(s);
            scratch.clear();
            scratch.extend(pattern.iter().map(|&row| x[row]));
            self.backward_supernode(s, conjugate, &mut x[f..l], &scratch);
        }
        let outside: Vec<Vec<[T; K]>> = plan
            .tasks
            .iter()
            .map(|t| self.sn.supernode(t.root).pattern().iter().map(|&row| x[row]).collect())
            .collect();
        task_slices(plan, x).into_par_iter().zip(outside).for_each(|((task, xs), outside)| {
            let root_pattern = self.sn.supernode(task.root).pattern();
            let mut scratch = Vec::new();
            for s in (task.first..=task.root).rev() {
                let (f, l, pattern, _) = self.supernode(s);
                scratch.clear();
                scratch.extend(pattern.iter().map(|&row| {
                    if row < task.end {
                        xs[row - task.begin]
                    } else {
                        outside[root_pattern.partition_point(|&p| p < row)]
                    }
                }));
                self.backward_supernode(s, conjugate, &mut xs[f - task.begin..l - task.begin], &scratch);
            }
        });
    }
}

/// Each task of `plan` with its rows of `x` (the tasks' column ranges are disjoint and
/// ascending).
fn task_slices<'p, 'x, U>(plan: &'p SolvePlan, x: &'x mut [U]) -> Vec<(&'p SolveTask, &'x mut [U])> {
    let mut slices = Vec::with_capacity(plan.tasks.len());
    let mut rest = x;
    let mut at = 0;
    for task in &plan.tasks {
        let (_, tail) = std::mem::take(&mut rest).split_at_mut(task.begin - at);
        let (own, tail) = tail.split_at_mut(task.end - task.begin);
        slices.push((task, own));
        rest = tail;
        at = task.end;
    }
    slices
}

/// Columns of a supernode processed together.
const BLOCK_COLUMNS: usize = 4;

/// `Σ_k columns[k][i] · x[k]` for K right-hand sides.
#[inline(always)]
fn combine4<T: Scalar, const K: usize>(
    columns: &[&[T]; BLOCK_COLUMNS],
    i: usize,
    x: &[[T; K]; BLOCK_COLUMNS],
) -> [T; K] {
    let a = [columns[0][i], columns[1][i], columns[2][i], columns[3][i]];
    let mut out = [T::default(); K];
    for c in 0..K {
        out[c] = (a[0] * x[0][c] + a[1] * x[1][c]) + (a[2] * x[2][c] + a[3] * x[3][c]);
    }
    out
}

/// `sums[k] += Σ_i conj?(columns[k][first + i]) · x[i]` for the four columns at once (each x
/// row is loaded once for the four).
#[inline(always)]
fn dot4<T: Scalar, const K: usize>(
    columns: &[&[T]; BLOCK_COLUMNS],
    first: usize,
    x: &[[T; K]],
    conjugate: bool,
    sums: &mut [[T; K]; BLOCK_COLUMNS],
) {
    let cols: [&[T]; BLOCK_COLUMNS] = std::array::from_fn(|k| &columns[k][first..first + x.len()]);
    for (i, xi) in x.iter().enumerate() {
        for k in 0..BLOCK_COLUMNS {
            let a = if conjugate { cols[k][i].conjugate() } else { cols[k][i] };
            for c in 0..K {
                sums[k][c] += a * xi[c];
            }
        }
    }
}

/// The supernode holding each column of a supernodal factor.
pub(crate) fn supernode_of_columns(sn: &SymbolicSupernodalCholesky<usize>) -> Vec<usize> {
    let mut owner = vec![0usize; sn.nrows()];
    for s in 0..sn.n_supernodes() {
        owner[sn.supernode_begin()[s]..sn.supernode_end()[s]].fill(s);
    }
    owner
}

/// The parent of each supernode in the supernodal elimination tree (the supernode holding the
/// first row of its below-diagonal pattern; `None` for roots). Parents follow their children.
pub(crate) fn supernode_parents(sn: &SymbolicSupernodalCholesky<usize>) -> Vec<Option<usize>> {
    let owner = supernode_of_columns(sn);
    (0..sn.n_supernodes()).map(|s| sn.supernode(s).pattern().first().map(|&r| owner[r])).collect()
}

/// Marks the supernodes a forward substitution must visit for a right-hand side whose nonzero
/// rows are `rows` (elimination order): those holding such a row and their ancestors in the
/// supernodal elimination tree (Gilbert 1994: the nonzeros of `L⁻¹b` are the reach of b's).
pub fn active_supernodes(sn: &SymbolicSupernodalCholesky<usize>, rows: impl IntoIterator<Item = usize>) -> Vec<bool> {
    let count = sn.n_supernodes();
    let owner = supernode_of_columns(sn);
    let mut active = vec![false; count];
    for r in rows {
        active[owner[r]] = true;
    }
    // A parent's columns follow its children's.
    for s in 0..count {
        if active[s] {
            if let Some(&first) = sn.supernode(s).pattern().first() {
                active[owner[first]] = true;
            }
        }
    }
    active
}

/// `Σ_i a_i x_i` (with `conj(a_i)` when `conjugate`) for K columns, with four independent
/// accumulators so the sum is not one chain of dependent additions.
#[inline(always)]
fn dot<T: Scalar, const K: usize>(a: &[T], x: &[[T; K]], conjugate: bool) -> [T; K] {
    let mut acc = [[T::default(); K]; 4];
    let (a4, a_rest) = a.split_at(a.len() - a.len() % 4);
    let (x4, x_rest) = x[..a.len()].split_at(a4.len());
    for (a, x) in a4.chunks_exact(4).zip(x4.chunks_exact(4)) {
        for k in 0..4 {
            let ak = if conjugate { a[k].conjugate() } else { a[k] };
            for c in 0..K {
                acc[k][c] += ak * x[k][c];
            }
        }
    }
    for (&a, x) in a_rest.iter().zip(x_rest) {
        let a = if conjugate { a.conjugate() } else { a };
        for c in 0..K {
            acc[0][c] += a * x[c];
        }
    }
    let mut out = [T::default(); K];
    for c in 0..K {
        out[c] = (acc[0][c] + acc[1][c]) + (acc[2][c] + acc[3][c]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{Factor, SolvePlan};
    use crate::test_matrices::grid_matrix;
    use crate::{lower_from_entries, ordering, CholeskyPattern};
    use faer::c64;
    use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;

    #[test]
    fn parallel_substitutions_match_the_sequential_ones() {
        let (diagonal, lower, coords) = grid_matrix(40);
        let n = diagonal.len();
        let matrix = lower_from_entries(&diagonal, lower).expect("matrix");
        let adjacency = ordering::Adjacency::from_lower(n, matrix.symbolic().col_ptr(), matrix.symbolic().row_idx());
        let order = ordering::nested_dissection(&adjacency, &coords);
        let pattern = CholeskyPattern::with_fill_order(matrix.symbolic(), Some(order)).expect("analysis");
        let solver = pattern.factor(&matrix).expect("factor");
        let SymbolicCholeskyRaw::Supernodal(sn) = pattern.symbolic.raw() else { panic!("not supernodal") };
        let plan = SolvePlan::for_factors_from(sn, 0).expect("a postordered supernodal factor");
        assert!(plan.tasks.len() >= 2 && !plan.top.is_empty(), "{} tasks", plan.tasks.len());
        let factor = Factor { sn, values: &solver.values, blocks: 1, which: 0, unit_diagonal: false };
        let rhs: Vec<[c64; 2]> =
            (0..n).map(|i| [c64::new((i as f64).sin(), 1.0), c64::new(0.5, (i as f64 * 0.2).cos())]).collect();
        let (mut sequential, mut parallel) = (rhs.clone(), rhs);
        factor.forward(&mut sequential, &mut Vec::new(), None);
        factor.forward_parallel(&plan, &mut parallel);
        for (a, b) in sequential.iter().zip(&parallel) {
            assert!((a[0] - b[0]).norm() + (a[1] - b[1]).norm() < 1e-12, "forward: {a:?} vs {b:?}");
        }
        factor.backward_transposed(true, &mut sequential, &mut Vec::new());
        factor.backward_transposed_parallel(&plan, true, &mut parallel);
        for (a, b) in sequential.iter().zip(&parallel) {
            assert!((a[0] - b[0]).norm() + (a[1] - b[1]).norm() < 1e-12, "backward: {a:?} vs {b:?}");
        }
    }
}
