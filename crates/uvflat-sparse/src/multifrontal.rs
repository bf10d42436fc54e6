//! Parallel multifrontal numeric Cholesky factorization `P A Pᵀ = L Lᴴ` (Duff–Reid 1983, "The
//! multifrontal solution of indefinite sparse symmetric linear equations"; Liu 1992, "The
//! multifrontal method for sparse matrix solution: theory and practice", §4–5), on faer's
//! supernodal symbolic analysis.
//!
//! Each supernode s (columns `f..l`, below-diagonal rows `P_s`) owns a dense front of size
//! `|f..l| + |P_s|`: the entries of A in its columns plus the update matrices of its children,
//! added at the matching rows ("extend-add"). A dense partial Cholesky of the front gives the
//! columns `f..l` of L and the update matrix `U_s = F₂₂ − L₂₁ L₂₁ᴴ` passed to the parent. Fronts
//! in disjoint subtrees of the supernodal elimination tree are independent, so subtrees run in
//! parallel (rayon): every small subtree is one task, factored in postorder, and the last child
//! to finish continues with its parent, so the large fronts near the root start as soon as
//! their children are done and use parallel dense kernels. Dense kernels are faer's. L is
//! written in faer's supernodal layout, so faer's triangular solves use it unchanged.
//!
//! faer's own numeric factorization is left-looking and sequential over supernodes; this one
//! does the same arithmetic (the same L up to rounding) with both cores busy.
//! [`run_split`] stops after a given column and returns the dense Schur complement of the
//! remaining ones ([`super::split_hermitian`] factors that block in complex arithmetic).
//! Cost: the factorization's flops, plus O(Σ_s |P_s|²) memory traffic for the extend-adds.

use super::front_assembly::front_positions;
use super::front_assembly::FrontAssembly;
use super::lu_front;
use super::permuted_lower::PermutedLower;
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch, LltError};
use faer::linalg::matmul::triangular::{matmul, BlockStructure};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::SparseColMatRef;
use faer::traits::ComplexField;
use faer::{Accum, MatMut, Par};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::Mutex;

const NONE: u32 = u32::MAX;
/// Subtrees with less work than this fraction of the total are one sequential task each.
const TASK_FRACTION: f64 = 1.0 / 256.0;
/// Fronts with at least this many entries in their factor block use parallel dense kernels.
const PARALLEL_FRONT: usize = 64 * 1024;

/// Factors the matrix whose lower triangle is `lower` (in the original numbering; `symbolic`
/// holds the permutation) into `values` (overwritten), laid out as faer's supernodal factor of
/// `symbolic`.
pub fn factorize<T: ComplexField + Copy + Send + Sync>(
    symbolic: &SymbolicCholesky<usize>,
    lower: SparseColMatRef<'_, usize, T>,
    values: &mut [T],
) -> Result<()> {
    factorize_reusing(symbolic, lower, values, &mut Vec::new())
}

/// [`factorize`], taking update-matrix buffers from `spare` (left by an earlier factorization)
/// before allocating, and leaving the largest ones there for the next: a Newton loop
/// refactoring one pattern then maps and zero-fills its large fronts' memory once.
pub fn factorize_reusing<T: ComplexField + Copy + Send + Sync>(
    symbolic: &SymbolicCholesky<usize>,
    lower: SparseColMatRef<'_, usize, T>,
    values: &mut [T],
    spare: &mut Vec<Vec<T>>,
) -> Result<()> {
    let inverse = symbolic.perm().map(|p| p.arrays().1);
    let a = PermutedLower::new(lower, inverse);
    run_with(symbolic, Entries::Hermitian(&a), values, symbolic.nrows(), spare).map(|_| ())
}

/// [`factorize_reusing`] of the matrix whose lower triangle has the values `lower_values` in
/// the pattern `map` was built for: the entries go straight to their front positions.
pub fn factorize_mapped<T: ComplexField + Copy + Send + Sync>(
    symbolic: &SymbolicCholesky<usize>,
    map: &FrontAssembly,
    lower_values: &[T],
    values: &mut [T],
    spare: &mut Vec<Vec<T>>,
) -> Result<()> {
    if lower_values.len() != map.values_len() {
        return Err(Error::Internal(format!(
            "{} matrix values given for a pattern of {}",
            lower_values.len(),
            map.values_len()
        )));
    }
    run_with(symbolic, Entries::Mapped(map, lower_values), values, symbolic.nrows(), spare).map(|_| ())
}

/// What the fronts are assembled from: the lower triangle of a Hermitian matrix (permuted, or
/// its values with their front positions), or the two triangles of a matrix with a symmetric
/// pattern (the upper one transposed), for LU.
pub(crate) enum Entries<'a, T> {
    Hermitian(&'a PermutedLower<T>),
    Mapped(&'a FrontAssembly, &'a [T]),
    Lu { lower: &'a PermutedLower<T>, upper_t: &'a PermutedLower<T> },
}

impl<T> Entries<'_, T> {
    /// Values stored per entry of the symbolic factor: L, or L and Uᵀ.
    fn blocks(&self) -> usize {
        match self {
            Entries::Hermitian(_) | Entries::Mapped(..) => 1,
            Entries::Lu { .. } => 2,
        }
    }
}

/// Runs the multifrontal factorization of `entries` on the supernodal structure of
/// `symbolic`; `values` holds, per supernode, its block of L (and for LU then its block of Uᵀ).
pub(crate) fn run<T: ComplexField + Copy + Send + Sync>(
    symbolic: &SymbolicCholesky<usize>,
    entries: Entries<'_, T>,
    values: &mut [T],
) -> Result<()> {
    run_split(symbolic, entries, values, symbolic.nrows()).map(|_| ())
}

/// Partial multifrontal Cholesky: eliminates the (permuted) columns `0..split` only and
/// returns the Schur complement of the trailing `n − split` unknowns, `A₂₂ − L₂₁L₂₁ᴴ`, without
/// `A₂₂` itself (those entries are not read), as a dense column-major lower triangle. The
/// factor blocks of supernodes that lie entirely at or after `split` are left untouched, and a
/// supernode straddling `split` holds only its leading columns.
pub(crate) fn run_split<T: ComplexField + Copy + Send + Sync>(
    symbolic: &SymbolicCholesky<usize>,
    entries: Entries<'_, T>,
    values: &mut [T],
    split: usize,
) -> Result<Vec<T>> {
    run_with(symbolic, entries, values, split, &mut Vec::new())
}

/// [`run_split`] with update-matrix buffers taken from and left in `spare`.
fn run_with<T: ComplexField + Copy + Send + Sync>(
    symbolic: &SymbolicCholesky<usize>,
    entries: Entries<'_, T>,
    values: &mut [T],
    split: usize,
    spare: &mut Vec<Vec<T>>,
) -> Result<Vec<T>> {
    let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
        return Err(Error::Internal("the multifrontal factorization needs a supernodal symbolic analysis".into()));
    };
    let blocks = entries.blocks();
    if values.len() != blocks * sn.len_val() {
        return Err(Error::Internal(format!(
            "factor storage of {} entries for {} expected",
            values.len(),
            blocks * sn.len_val()
        )));
    }
    let tree = SupernodeTree::new(sn);
    let mut slots = Vec::with_capacity(tree.len());
    let mut rest = values;
    for s in 0..tree.len() {
        let len = blocks * (sn.col_ptr_for_val()[s + 1] - sn.col_ptr_for_val()[s]);
        let (head, tail) = rest.split_at_mut(len);
        slots.push(Mutex::new(Some(head)));
        rest = tail;
    }
    let cx = Context {
        sn,
        entries,
        tree: &tree,
        factor: slots,
        updates: (0..tree.len()).map(|_| Mutex::new(None)).collect(),
        pending: tree.child_counts().into_iter().map(AtomicU32::new).collect(),
        failed: AtomicBool::new(false),
        error: Mutex::new(None),
        split,
        schur: Mutex::new(vec![T::zero_impl(); (sn.nrows() - split.min(sn.nrows())).pow(2)]),
        spare: Mutex::new(std::mem::take(spare)),
    };
    let tasks = tree.task_roots(tree.total_work() * TASK_FRACTION);
    if tasks.len() < 2 || sn.nrows() < crate::parallel::SEQUENTIAL_BELOW {
        // On the calling thread (see `crate::parallel`): a task finishing last under a parent
        // goes on with it, in any order.
        tasks.iter().for_each(|&root| run_task(root, &cx));
    } else {
        rayon::scope(|scope| {
            for &root in &tasks {
                let cx = &cx;
                scope.spawn(move |_| run_task(root, cx));
            }
        });
    }
    *spare = cx.spare.into_inner().unwrap_or_else(|e| e.into_inner());
    spare.sort_unstable_by_key(|b| std::cmp::Reverse(b.capacity()));
    spare.truncate(SPARE_KEEP);
    match cx.error.into_inner().unwrap_or_else(|e| e.into_inner()) {
        Some(e) => Err(e),
        None => Ok(cx.schur.into_inner().unwrap_or_else(|e| e.into_inner())),
    }
}

/// Shared state of one factorization.
struct Context<'a, T> {
    sn: &'a SymbolicSupernodalCholesky<usize>,
    entries: Entries<'a, T>,
    tree: &'a SupernodeTree,
    /// Each supernode's block of L, taken by the task that factors it.
    factor: Vec<Mutex<Option<&'a mut [T]>>>,
    /// Update matrices waiting for their parent.
    updates: Vec<Mutex<Option<Vec<T>>>>,
    /// Children of each supernode not yet factored.
    pending: Vec<AtomicU32>,
    failed: AtomicBool,
    error: Mutex<Option<Error>>,
    /// Columns from `split` on are not eliminated; updates onto them go to `schur`.
    split: usize,
    /// Dense Schur complement of the columns `split..n` (column-major, lower triangle).
    schur: Mutex<Vec<T>>,
    /// Update-matrix buffers no task holds, shared by all (see [`Pool`]).
    spare: Mutex<Vec<Vec<T>>>,
}

fn lock<U>(m: &Mutex<U>) -> std::sync::MutexGuard<'_, U> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Factors the subtree of `root` in postorder, then climbs towards the root as long as this
/// task finished the last child of the parent. Once any task has failed (a non-positive
/// pivot), no further front is factored: the ancestors of a skipped front would be assembled
/// without its update, and a rejected factorization (a Newton step retrying with a larger
/// shift) then costs only the work done before the failure.
fn run_task<T: ComplexField + Copy + Send + Sync>(root: u32, cx: &Context<'_, T>) {
    let mut pool = Pool::default();
    let result = factor_subtree(root, cx, &mut pool).and_then(|()| {
        let mut s = root;
        loop {
            let p = cx.tree.parent[s as usize];
            if p == NONE
                || cx.pending[p as usize].fetch_sub(1, Ordering::AcqRel) != 1
                || cx.failed.load(Ordering::Relaxed)
            {
                return Ok(());
            }
            factor_supernode(p, cx, &mut pool)?;
            s = p;
        }
    });
    lock(&cx.spare).append(&mut pool.free);
    if let Err(e) = result {
        cx.failed.store(true, Ordering::Relaxed);
        lock(&cx.error).get_or_insert(e);
    }
}

/// Factors every supernode of the subtree of `root`, children before parents.
fn factor_subtree<T: ComplexField + Copy + Send + Sync>(
    root: u32,
    cx: &Context<'_, T>,
    pool: &mut Pool<T>,
) -> Result<()> {
    // Iterative postorder: (supernode, index of the next child to visit).
    let mut stack = vec![(root, 0usize)];
    while let Some(&mut (s, ref mut next)) = stack.last_mut() {
        let children = cx.tree.children(s);
        if *next < children.len() {
            let c = children[*next];
            *next += 1;
            stack.push((c, 0));
            continue;
        }
        stack.pop();
        if cx.failed.load(Ordering::Relaxed) {
            return Ok(());
        }
        factor_supernode(s, cx, pool)?;
    }
    Ok(())
}

/// Buffers left for the next factorization (the largest ones).
const SPARE_KEEP: usize = 32;

/// Update-matrix buffers of a task, reused so that their memory stays mapped and cached; when
/// none is large enough, the factorization's shared spare buffers are tried before allocating.
struct Pool<T> {
    free: Vec<Vec<T>>,
}

impl<T> Default for Pool<T> {
    fn default() -> Self {
        Pool { free: Vec::new() }
    }
}

impl<T: ComplexField + Copy> Pool<T> {
    /// Buffers kept for reuse.
    const KEEP: usize = 16;

    /// A buffer of `len` entries (zeroed if `zeroed`, else holding anything): a local one,
    /// else the smallest large enough of `shared`, else a new one.
    fn take(&mut self, len: usize, shared: &Mutex<Vec<Vec<T>>>, zeroed: bool) -> Vec<T> {
        let local = self.free.iter().position(|b| b.capacity() >= len).map(|k| self.free.swap_remove(k));
        let mut buffer = local
            .or_else(|| {
                let mut shared = lock(shared);
                let k =
                    (0..shared.len()).filter(|&k| shared[k].capacity() >= len).min_by_key(|&k| shared[k].capacity())?;
                Some(shared.swap_remove(k))
            })
            .unwrap_or_else(|| self.free.pop().unwrap_or_default());
        if zeroed {
            buffer.clear();
        }
        buffer.resize(len, T::zero_impl());
        buffer
    }

    fn give(&mut self, buffer: Vec<T>) {
        if self.free.len() < Self::KEEP {
            self.free.push(buffer);
        }
    }
}

/// Assembles and factors the front of supernode `s`, leaving its update matrix for the parent.
fn factor_supernode<T: ComplexField + Copy + Send + Sync>(
    s: u32,
    cx: &Context<'_, T>,
    pool: &mut Pool<T>,
) -> Result<()> {
    let sn = cx.sn;
    let (f, l) = (sn.supernode_begin()[s as usize], sn.supernode_end()[s as usize]);
    let pattern = sn.supernode(s as usize).pattern();
    let (w, m) = (l - f, pattern.len());
    let ld = w + m;
    if f >= cx.split {
        // Past the split: the children's updates went to the Schur complement.
        return Ok(());
    }
    // Columns eliminated here (fewer than w when the supernode straddles the split).
    let eliminated = l.min(cx.split) - f;
    let Some(block) = lock(&cx.factor[s as usize]).take() else {
        return Err(Error::Internal(format!("supernode {s} factored twice")));
    };
    block.fill(T::zero_impl());
    let hermitian = !matches!(cx.entries, Entries::Lu { .. });
    // The Hermitian update matrix is overwritten before the children's parts are added to it.
    let mut update = pool.take(m * m, &cx.spare, !hermitian);
    let par = if ld * w >= PARALLEL_FRONT { faer::get_global_parallelism() } else { Par::Seq };
    let children = cx.tree.children(s).iter().filter_map(|&c| lock(&cx.updates[c as usize]).take().map(|u| (c, u)));
    match cx.entries {
        Entries::Hermitian(a) => assemble_columns(block, ld, f, f + eliminated, l, pattern, a),
        Entries::Mapped(map, values) => map.assemble(block, ld, f, f + eliminated, values),
        Entries::Lu { .. } => {} // both triangles are assembled below
    }
    match cx.entries {
        Entries::Hermitian(_) | Entries::Mapped(..) => {
            let children: Vec<(u32, Vec<T>)> = children.collect();
            let positions: Vec<Vec<usize>> = children
                .iter()
                .map(|&(c, _)| front_positions(f, l, pattern, cx.sn.supernode(c as usize).pattern()))
                .collect();
            for ((_, child), position) in children.iter().zip(&positions) {
                extend_add(block, &mut update, ld, w, child, position, ..w);
            }
            partial_cholesky(block, &mut update, eliminated, w, m, par).map_err(|index| {
                Error::Numerical(format!(
                    "the system matrix is not positive definite (pivot {} of {}); the mesh may have extremely bad triangles",
                    f + index,
                    sn.nrows()
                ))
            })?;
            for ((_, child), position) in children.into_iter().zip(&positions) {
                extend_add(block, &mut update, ld, w, &child, position, w..);
                pool.give(child);
            }
        }
        Entries::Lu { lower, upper_t } => {
            let (l_block, u_block) = block.split_at_mut(ld * w);
            assemble_columns(l_block, ld, f, l, l, pattern, lower);
            lu_front::assemble_upper(l_block, u_block, ld, f, l, pattern, upper_t);
            for (c, child) in children {
                lu_front::extend_add_full(
                    l_block,
                    u_block,
                    &mut update,
                    ld,
                    f,
                    l,
                    pattern,
                    &child,
                    cx.sn.supernode(c as usize).pattern(),
                );
                pool.give(child);
            }
            lu_front::partial_lu(l_block, u_block, &mut update, w, m, par).map_err(|index| {
                Error::Numerical(format!(
                    "zero or non-finite pivot {} of {} in the LU factorization without pivoting",
                    f + index,
                    sn.nrows()
                ))
            })?;
        }
    }
    if eliminated < w || pattern.first().is_some_and(|&i| i >= cx.split) {
        add_to_schur(cx, block, &update, eliminated, f, l, pattern);
        pool.give(update);
    } else if m > 0 {
        *lock(&cx.updates[s as usize]) = Some(update);
    } else {
        pool.give(update);
    }
    Ok(())
}

/// Adds the trailing part of a front (front rows and columns from `eliminated` on, all at or
/// after the split) to the dense Schur complement: columns `eliminated..w` of the factor block
/// and the update matrix.
fn add_to_schur<T: ComplexField + Copy + Send + Sync>(
    cx: &Context<'_, T>,
    block: &[T],
    update: &[T],
    eliminated: usize,
    f: usize,
    l: usize,
    pattern: &[usize],
) {
    let (w, m) = (l - f, pattern.len());
    let ld = w + m;
    let nb = cx.sn.nrows() - cx.split;
    let global = |k: usize| if k < w { f + k } else { pattern[k - w] } - cx.split;
    let rows: Vec<usize> = (eliminated..ld).map(global).collect();
    let mut schur = lock(&cx.schur);
    for (c, &j) in rows.iter().enumerate() {
        let k = eliminated + c;
        let source =
            if k < w { &block[k * ld + k..(k + 1) * ld] } else { &update[(k - w) * m + (k - w)..(k - w + 1) * m] };
        let column = &mut schur[j * nb..(j + 1) * nb];
        for (&i, &v) in rows[c..].iter().zip(source) {
            column[i] += v;
        }
    }
}

/// Adds the entries of A in columns `f..end` (of the supernode `f..l`) into the front's factor
/// block.
fn assemble_columns<T: ComplexField + Copy + Send + Sync>(
    block: &mut [T],
    ld: usize,
    f: usize,
    end: usize,
    l: usize,
    pattern: &[usize],
    a: &PermutedLower<T>,
) {
    for j in f..end {
        let column = &mut block[(j - f) * ld..(j - f + 1) * ld];
        for (&i, &v) in a.rows_of(j).iter().zip(a.values_of(j)) {
            let i = i as usize;
            let r = if i < l { i - f } else { (l - f) + pattern.partition_point(|&p| p < i) };
            column[r] += v;
        }
    }
}

/// Adds the columns of a child's update matrix whose front positions (`position`, see
/// [`front_positions`]) fall in `columns` into the front of a supernode of `w` columns and
/// leading dimension `ld`: columns before `w` go to the factor block, the others to the
/// front's own update matrix. The factor block's part is added before the partial Cholesky,
/// the update matrix's after it (the partial Cholesky overwrites the update matrix, which
/// saves clearing it). Rows whose front positions are consecutive are added as one slice, so
/// the inner loop vectorizes (every vertex's unknowns are consecutive in PGP's block systems,
/// and a child's rows often form long runs in its parent's front); the sums are the same as
/// entry by entry. On the PGP benchmark (`crates/uvflat-core/benches/pgp.rs`, 414k-unknown Newton systems) the
/// samples of the assembly (`factor_supernode`'s own time, mostly this loop) went from 12.5%
/// to 10.4% of the run.
fn extend_add<T: ComplexField + Copy + Send + Sync>(
    block: &mut [T],
    update: &mut [T],
    ld: usize,
    w: usize,
    child: &[T],
    position: &[usize],
    columns: impl std::ops::RangeBounds<usize>,
) {
    let m = ld - w;
    let mc = position.len();
    let run_end = consecutive_run_ends(position);
    for (c2, &j) in position.iter().enumerate() {
        if !columns.contains(&j) {
            continue;
        }
        let source = &child[c2 * mc..(c2 + 1) * mc];
        // Rows from c2 on all land in one region: the factor block's column j, or (j ≥ w, so
        // every row ≥ w too) the update matrix's column j − w.
        let (column, offset) =
            if j < w { (&mut block[j * ld..(j + 1) * ld], 0) } else { (&mut update[(j - w) * m..(j - w + 1) * m], w) };
        let mut k = c2;
        while k < mc {
            let end = run_end[k];
            let start = position[k] - offset;
            for (t, &v) in column[start..start + (end - k)].iter_mut().zip(&source[k..end]) {
                *t += v;
            }
            k = end;
        }
    }
}

/// For each index k of an increasing sequence, the end (exclusive) of the run of consecutive
/// values containing it.
fn consecutive_run_ends(position: &[usize]) -> Vec<usize> {
    let mut end = vec![position.len(); position.len()];
    for k in (0..position.len().saturating_sub(1)).rev() {
        end[k] = if position[k + 1] == position[k] + 1 { end[k + 1] } else { k + 1 };
    }
    end
}

/// Dense partial Cholesky of a front `[F₁₁; F₂₁]` (`w` columns, stored in `block` with leading
/// dimension `w + m`): `F₁₁ = L₁₁L₁₁ᴴ`, `L₂₁ = F₂₁L₁₁⁻ᴴ`, and `update ← −L₂₁L₂₁ᴴ` (lower
/// triangle of the `m × m` update matrix, overwritten: the entries of `F₂₂` are added to it
/// afterwards), eliminating only the first `e ≤ w` columns: then the columns `e..w` of the
/// block are updated like `F₂₂`. Returns the failing pivot's index on a non-positive pivot.
fn partial_cholesky<T: ComplexField + Copy + Send + Sync>(
    block: &mut [T],
    update: &mut [T],
    e: usize,
    w: usize,
    m: usize,
    par: Par,
) -> std::result::Result<(), usize> {
    let mut front = MatMut::from_column_major_slice_mut(block, w + m, w);
    let (left, mut right) = front.rb_mut().split_at_col_mut(e);
    let (mut top, mut bottom) = left.split_at_row_mut(e);
    let mut mem = MemBuffer::new(cholesky_in_place_scratch::<T>(e, par, Default::default()));
    match cholesky_in_place(top.rb_mut(), Default::default(), par, MemStack::new(&mut mem), Default::default()) {
        Ok(_) => {}
        Err(LltError::NonPositivePivot { index }) => return Err(index),
    }
    if m + w == e {
        return Ok(());
    }
    solve_lower_triangular_in_place(top.rb().conjugate(), bottom.rb_mut().transpose_mut(), par);
    if e < w {
        // Columns e..w of the block, rows e..w+m: minus (rows of L₂₁) × (its first w − e rows)ᴴ.
        let target = right.rb_mut().subrows_mut(e, w + m - e);
        let leading = bottom.rb().subrows(0, w - e);
        matmul(
            target,
            BlockStructure::Rectangular,
            Accum::Add,
            bottom.rb(),
            BlockStructure::Rectangular,
            leading.adjoint(),
            BlockStructure::Rectangular,
            T::from_f64_impl(-1.0),
            par,
        );
    }
    if m == 0 {
        return Ok(());
    }
    let below = bottom.rb().subrows(w - e, m);
    let u = MatMut::from_column_major_slice_mut(update, m, m);
    matmul(
        u,
        BlockStructure::TriangularLower,
        Accum::Replace,
        below,
        BlockStructure::Rectangular,
        below.adjoint(),
        BlockStructure::Rectangular,
        T::from_f64_impl(-1.0),
        par,
    );
    Ok(())
}

/// The supernodal elimination tree: the parent of a supernode is the one holding the first row
/// of its below-diagonal pattern.
struct SupernodeTree {
    parent: Vec<u32>,
    child_start: Vec<u32>,
    children: Vec<u32>,
    /// Flops-like work of each subtree (Σ w·(w + m)² over its supernodes).
    subtree_work: Vec<f64>,
}

impl SupernodeTree {
    fn new(sn: &SymbolicSupernodalCholesky<usize>) -> Self {
        let count = sn.n_supernodes();
        let parent: Vec<u32> =
            super::supernodal_solve::supernode_parents(sn).into_iter().map(|p| p.map_or(NONE, |p| p as u32)).collect();
        let mut child_start = vec![0u32; count + 1];
        for &p in &parent {
            if p != NONE {
                child_start[p as usize + 1] += 1;
            }
        }
        for s in 0..count {
            child_start[s + 1] += child_start[s];
        }
        let mut fill = child_start.clone();
        let mut children = vec![0u32; child_start[count] as usize];
        for (s, &p) in parent.iter().enumerate() {
            if p != NONE {
                children[fill[p as usize] as usize] = s as u32;
                fill[p as usize] += 1;
            }
        }
        // Parents come after their children (a parent's columns follow its children's).
        let mut subtree_work: Vec<f64> = (0..count)
            .map(|s| {
                let w = (sn.supernode_end()[s] - sn.supernode_begin()[s]) as f64;
                let m = sn.supernode(s).pattern().len() as f64;
                w * (w + m) * (w + m)
            })
            .collect();
        for s in 0..count {
            if parent[s] != NONE {
                subtree_work[parent[s] as usize] += subtree_work[s];
            }
        }
        SupernodeTree { parent, child_start, children, subtree_work }
    }

    fn len(&self) -> usize {
        self.parent.len()
    }

    fn children(&self, s: u32) -> &[u32] {
        &self.children[self.child_start[s as usize] as usize..self.child_start[s as usize + 1] as usize]
    }

    fn child_counts(&self) -> Vec<u32> {
        self.child_start.windows(2).map(|w| w[1] - w[0]).collect()
    }

    fn total_work(&self) -> f64 {
        (0..self.len()).filter(|&s| self.parent[s] == NONE).map(|s| self.subtree_work[s]).sum()
    }

    /// Roots of the maximal subtrees lighter than `limit`, plus the leaves of heavier parts
    /// that have no light subtree below them (a heavy leaf is a task of its own).
    fn task_roots(&self, limit: f64) -> Vec<u32> {
        (0..self.len() as u32)
            .filter(|&s| {
                let light = self.subtree_work[s as usize] < limit || self.children(s).is_empty();
                let p = self.parent[s as usize];
                light && (p == NONE || self.subtree_work[p as usize] >= limit)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::consecutive_run_ends;
    use crate::test_matrices::{grid_matrix, Lower};
    use crate::{lower_from_entries, CholeskyPattern};
    use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
    use faer::{c64, Mat};

    #[test]
    fn runs_of_consecutive_positions_end_where_the_sequence_jumps() {
        assert_eq!(consecutive_run_ends(&[0, 1, 2, 5, 6, 9]), vec![3, 3, 3, 5, 5, 6]);
        assert_eq!(consecutive_run_ends(&[4]), vec![1]);
        assert!(consecutive_run_ends(&[]).is_empty());
    }

    #[test]
    fn a_diagonal_system_ordered_by_amd_is_factored_and_solved() {
        // AMD counts no flops for a matrix without off-diagonal entries; faer then picks its
        // simplicial analysis, which the multifrontal factorization cannot use.
        use crate::CholeskySolver;
        let matrix = lower_from_entries(&[2.0, 4.0, 8.0], Vec::new()).expect("matrix");
        let solver = CholeskySolver::new(&matrix, None).expect("a diagonal system factors");
        let mut b = Mat::<f64>::from_fn(3, 1, |i, _| 1.0 + i as f64);
        solver.solve_in_place(&mut b).expect("solve");
        for (i, x) in [0.5, 0.5, 0.375].into_iter().enumerate() {
            assert!((b[(i, 0)] - x).abs() < 1e-15, "unknown {i}: {} vs {x}", b[(i, 0)]);
        }
    }

    #[test]
    fn multifrontal_factor_solves_a_hermitian_system() {
        let (diagonal, lower, coords) = grid_matrix(23);
        let n = diagonal.len();
        let matrix = lower_from_entries(&diagonal, lower.clone()).expect("matrix");
        let pattern = CholeskyPattern::new(matrix.symbolic(), Some(&coords)).expect("analysis");
        let solver = pattern.factor(&matrix).expect("factor");
        let x_true: Vec<c64> = (0..n).map(|i| c64::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos())).collect();
        // b = A x, with A's upper part from the Hermitian symmetry.
        let mut b = Mat::<c64>::zeros(n, 1);
        for i in 0..n {
            b[(i, 0)] += diagonal[i] * x_true[i];
        }
        for &(r, c, v) in &lower {
            let (r, c) = (r as usize, c as usize);
            b[(r, 0)] += v * x_true[c];
            b[(c, 0)] += v.conj() * x_true[r];
        }
        solver.solve_in_place(&mut b).expect("solve");
        for i in 0..n {
            assert!((b[(i, 0)] - x_true[i]).norm() < 1e-10, "unknown {i}: {} vs {}", b[(i, 0)], x_true[i]);
        }
    }

    #[test]
    fn no_front_is_factored_after_a_failure_whose_children_were_skipped() {
        // Negative pivots spread over the grid: every task meets one, so after the first
        // failure the other tasks skip their subtrees. One thread makes the order fixed.
        let (mut diagonal, lower, coords) = grid_matrix(63);
        for (i, d) in diagonal.iter_mut().enumerate() {
            if i % 97 == 0 {
                *d = c64::new(-1.0, 0.0);
            }
        }
        let matrix = lower_from_entries(&diagonal, lower).expect("matrix");
        let pattern = CholeskyPattern::new(matrix.symbolic(), Some(&coords)).expect("analysis");
        let SymbolicCholeskyRaw::Supernodal(sn) = pattern.symbolic.raw() else { panic!("not supernodal") };
        let mut values = vec![c64::new(f64::NAN, 0.0); pattern.factor_len()];
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("thread pool");
        let result = pool.install(|| super::factorize(&pattern.symbolic, matrix.as_ref(), &mut values));
        assert!(result.is_err(), "the matrix is indefinite");
        // A front that was started has its block cleared first, so its first entry is a number.
        let started = |s: usize| !values[sn.col_ptr_for_val()[s]].re.is_nan();
        let tree = super::SupernodeTree::new(sn);
        let count = (0..tree.len()).filter(|&s| started(s)).count();
        assert!(count > 0 && count < tree.len(), "{count} of {} fronts started", tree.len());
        for s in 0..tree.len() {
            for &c in tree.children(s as u32) {
                assert!(!started(s) || started(c as usize), "front {s} was factored without its child {c}");
            }
        }
    }

    #[test]
    fn factoring_from_values_solves_the_hermitian_system() {
        let (diagonal, lower, coords) = grid_matrix(23);
        // Imaginary parts on every edge, so that the entries the permutation moves above the
        // diagonal (read conjugated) matter; the larger diagonal keeps the matrix definite.
        let diagonal: Vec<c64> = diagonal.iter().map(|d| *d + 2.0).collect();
        let lower: Lower =
            lower.iter().map(|&(r, c, v)| (r, c, v + c64::new(0.0, 0.2 * ((r + 2 * c) % 5) as f64 - 0.4))).collect();
        let matrix = lower_from_entries(&diagonal, lower.clone()).expect("matrix");
        let pattern = CholeskyPattern::new(matrix.symbolic(), Some(&coords)).expect("analysis");
        let solver = pattern.factor_values(matrix.val()).expect("factor");
        let n = diagonal.len();
        let b = Mat::<c64>::from_fn(n, 1, |i, _| c64::new((i as f64 * 0.7).cos(), (i as f64 * 0.3).sin()));
        let mut x = b.clone();
        solver.solve_in_place(&mut x).expect("solve");
        let mut ax: Vec<c64> = (0..n).map(|i| diagonal[i] * x[(i, 0)]).collect();
        for &(r, c, v) in &lower {
            ax[r as usize] += v * x[(c as usize, 0)];
            ax[c as usize] += v.conj() * x[(r as usize, 0)];
        }
        for i in 0..n {
            assert!((ax[i] - b[(i, 0)]).norm() < 1e-12, "row {i}: {} vs {}", ax[i], b[(i, 0)]);
        }
        // Values of another length are refused.
        let mut refactored = solver;
        assert!(pattern.refactor_values(&matrix.val()[1..], &mut refactored).is_err());
    }

    #[test]
    fn refactoring_into_earlier_storage_gives_the_factor_of_the_new_matrix() {
        let (diagonal, lower, coords) = grid_matrix(31);
        let first = lower_from_entries(&diagonal, lower.clone()).expect("matrix");
        let pattern = CholeskyPattern::new(first.symbolic(), Some(&coords)).expect("analysis");
        let mut solver = pattern.factor(&first).expect("factor");
        // Same pattern, other values: twice the matrix plus the identity.
        let second_diagonal: Vec<c64> = diagonal.iter().map(|d| *d * 2.0 + 1.0).collect();
        let second_lower: Lower = lower.iter().map(|&(r, c, v)| (r, c, v * 2.0)).collect();
        let second = lower_from_entries(&second_diagonal, second_lower).expect("matrix");
        pattern.refactor(second.as_ref(), &mut solver).expect("refactor");
        let fresh = pattern.factor(&second).expect("factor");
        let n = diagonal.len();
        let b = Mat::<c64>::from_fn(n, 1, |i, _| c64::new((i as f64 * 0.3).sin(), 0.2));
        let (mut x, mut y) = (b.clone(), b.clone());
        solver.solve_in_place(&mut x).expect("solve");
        fresh.solve_in_place(&mut y).expect("solve");
        for i in 0..n {
            assert!((x[(i, 0)] - y[(i, 0)]).norm() < 1e-12, "unknown {i}");
        }
        // A solver of another pattern is refused.
        let other = CholeskyPattern::new(first.symbolic(), None).expect("analysis");
        assert!(other.refactor(second.as_ref(), &mut solver).is_err());
    }
}
