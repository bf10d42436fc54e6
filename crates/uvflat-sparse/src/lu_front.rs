//! The dense kernels of one front of the multifrontal LU without pivoting
//! ([`super::frontal_lu`], run by the driver of [`super::multifrontal`]): assembling the
//! entries above the diagonal and a child's full update matrix into the front, and the
//! partial LU `F₁₁ = L₁₁U₁₁`, `U₁₂ = L₁₁⁻¹F₁₂`, `L₂₁ = F₂₁U₁₁⁻¹`, `F₂₂ ← F₂₂ − L₂₁U₁₂`
//! (Amestoy–Duff 1989; Liu 1992 §4–5). The dense LU is recursive by halves, so that its work is
//! in faer's triangular solves and products; below 32 columns it is unblocked.
//!
//! Cost: O(w³ + w²m + wm²) per front of w columns and m rows below them.

use super::front_assembly::front_positions;
use super::permuted_lower::PermutedLower;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::traits::ComplexField;
use faer::{Accum, MatMut, Par};

/// Adds the entries above the diagonal in rows `f..l` into the front: those in columns `f..l`
/// to the upper part of `F₁₁` (in `l_block`), the others to `F₁₂ᵀ` (rows `w..` of `u_block`).
pub(crate) fn assemble_upper<T: ComplexField + Copy>(
    l_block: &mut [T],
    u_block: &mut [T],
    ld: usize,
    f: usize,
    l: usize,
    pattern: &[usize],
    upper_t: &PermutedLower<T>,
) {
    let w = l - f;
    for i in f..l {
        // Entries (i, j), j > i, are stored in column i of Aᵀ's lower triangle at row j.
        for (&j, &v) in upper_t.rows_of(i).iter().zip(upper_t.values_of(i)) {
            let j = j as usize;
            if j < l {
                l_block[(j - f) * ld + (i - f)] += v;
            } else {
                let k = pattern.partition_point(|&p| p < j);
                u_block[(i - f) * ld + w + k] += v;
            }
        }
    }
}

/// Adds a child's full update matrix (rows and columns `child_pattern`, column-major) into the
/// front of supernode `f..l`: entries in `F₁₁` and `F₂₁` to `l_block`, entries of `F₁₂` to
/// `u_block` (transposed), entries of `F₂₂` to the front's own update matrix.
#[allow(clippy::too_many_arguments)]
pub(crate) fn extend_add_full<T: ComplexField + Copy>(
    l_block: &mut [T],
    u_block: &mut [T],
    update: &mut [T],
    ld: usize,
    f: usize,
    l: usize,
    pattern: &[usize],
    child: &[T],
    child_pattern: &[usize],
) {
    let w = l - f;
    let m = ld - w;
    let mc = child_pattern.len();
    let position = front_positions(f, l, pattern, child_pattern);
    for (c2, &j) in position.iter().enumerate() {
        let source = &child[c2 * mc..(c2 + 1) * mc];
        if j < w {
            // Column j of the front: F₁₁ (both triangles) and F₂₁ are in L's block.
            let column = &mut l_block[j * ld..(j + 1) * ld];
            for (&i, &v) in position.iter().zip(source) {
                column[i] += v;
            }
        } else {
            for (&i, &v) in position.iter().zip(source) {
                if i < w {
                    u_block[i * ld + j] += v;
                } else {
                    update[(j - w) * m + (i - w)] += v;
                }
            }
        }
    }
}

/// Dense partial LU of a front: `F₁₁ = L₁₁U₁₁` in place in the top of `l_block` (then `U₁₁ᵀ`
/// moved to the top of `u_block`), `L₂₁ = F₂₁U₁₁⁻¹`, `U₁₂ᵀ = F₁₂ᵀL₁₁⁻ᵀ`, and
/// `F₂₂ ← F₂₂ − L₂₁U₁₂` (full). Returns the index of a zero or non-finite pivot.
pub(crate) fn partial_lu<T: ComplexField + Copy + Send + Sync>(
    l_block: &mut [T],
    u_block: &mut [T],
    update: &mut [T],
    w: usize,
    m: usize,
    par: Par,
) -> std::result::Result<(), usize> {
    let ld = w + m;
    let mut lf = MatMut::from_column_major_slice_mut(l_block, ld, w);
    let mut uf = MatMut::from_column_major_slice_mut(u_block, ld, w);
    let (mut l11, mut l21) = lf.rb_mut().split_at_row_mut(w);
    lu_in_place(l11.rb_mut(), par)?;
    let (mut u11t, mut u12t) = uf.rb_mut().split_at_row_mut(w);
    // Uᵀ's diagonal block: the transpose of the upper triangle (with the pivots); L keeps a unit
    // diagonal and zeros above it.
    for j in 0..w {
        for i in 0..=j {
            u11t[(j, i)] = l11[(i, j)];
        }
        l11[(j, j)] = T::one_impl();
        for i in 0..j {
            l11[(i, j)] = T::zero_impl();
        }
    }
    if m == 0 {
        return Ok(());
    }
    // L₂₁U₁₁ = F₂₁  ⇔  U₁₁ᵀ L₂₁ᵀ = F₂₁ᵀ;   L₁₁U₁₂ = F₁₂ (U₁₂ᵀ stored).
    solve_lower_triangular_in_place(u11t.rb(), l21.rb_mut().transpose_mut(), par);
    solve_unit_lower_triangular_in_place(l11.rb(), u12t.rb_mut().transpose_mut(), par);
    let u = MatMut::from_column_major_slice_mut(update, m, m);
    matmul(u, Accum::Add, l21.rb(), u12t.rb().transpose(), T::from_f64_impl(-1.0), par);
    Ok(())
}

/// Below this size the dense LU is unblocked.
const DENSE_BLOCK: usize = 32;

/// LU without pivoting of a square matrix in place (L unit lower below the diagonal, U on and
/// above it), recursive by halves so that the work is in triangular solves and products.
fn lu_in_place<T: ComplexField + Copy + Send + Sync>(mut a: MatMut<'_, T>, par: Par) -> std::result::Result<(), usize> {
    let n = a.nrows();
    if n <= DENSE_BLOCK {
        return lu_unblocked(a);
    }
    let k = n / 2;
    let (mut a11, mut a12, mut a21, mut a22) = a.rb_mut().split_at_mut(k, k);
    lu_in_place(a11.rb_mut(), par)?;
    solve_unit_lower_triangular_in_place(a11.rb(), a12.rb_mut(), par);
    // A₂₁ ← A₂₁U₁₁⁻¹  ⇔  U₁₁ᵀ X ᵀ = A₂₁ᵀ.
    solve_lower_triangular_in_place(a11.rb().transpose(), a21.rb_mut().transpose_mut(), par);
    matmul(a22.rb_mut(), Accum::Add, a21.rb(), a12.rb(), T::from_f64_impl(-1.0), par);
    lu_in_place(a22, par).map_err(|i| i + k)
}

fn lu_unblocked<T: ComplexField + Copy>(mut a: MatMut<'_, T>) -> std::result::Result<(), usize> {
    let n = a.nrows();
    for k in 0..n {
        let pivot = a[(k, k)];
        if !T::is_finite_impl(&pivot) || pivot == T::zero_impl() {
            return Err(k);
        }
        let inverse = T::recip_impl(&pivot);
        for i in k + 1..n {
            a[(i, k)] = a[(i, k)] * inverse;
        }
        for j in k + 1..n {
            let akj = a[(k, j)];
            for i in k + 1..n {
                a[(i, j)] = a[(i, j)] - a[(i, k)] * akj;
            }
        }
    }
    Ok(())
}
