//! Linear equality constraints added to a factored system with Lagrange multipliers
//! (Desbrun–Meyer–Alliez 2002, §4.1: "constraints … are simply added to the linear system
//! through Lagrange multipliers").
//!
//! The augmented system `[A Cᵀ; C 0] [x; λ] = [b; d]` is indefinite, so instead of factoring it
//! we keep the (Cholesky or LU) factor of `A` and eliminate `x` (Schur complement on the few
//! constraints): with `X = A⁻¹ b` and `Y = A⁻¹ Cᵀ` (k extra solves for k constraints),
//! `S λ = C X − d` with `S = C Y` (k × k, dense), then `x = X − Y λ`. One step of iterative
//! refinement on the small system brings the constraint residual to round-off.
//!
//! Constraint rows are sparse (a point of a triangle touches three unknowns). Before solving,
//! [`independent_rows`] keeps a maximal linearly independent subset of them (greedy, in the
//! caller's order), so a rank-deficient `C` — two constraints on one point, three on one edge,
//! a constraint whose triangle is entirely fixed — never reaches the dense solve; the dropped
//! rows are then checked against the solution, and a dropped row that the solution does not
//! satisfy is a conflict, reported by index instead of producing NaNs.

use crate::error::{Error, Result};
use faer::linalg::solvers::Solve;
use faer::traits::ComplexField;
use faer::Mat;
use std::ops::{Add, Mul};

/// Scalars of the constrained solves (`f64`, `c64`).
pub trait Scalar: ComplexField + Copy + Add<Output = Self> + Mul<Output = Self> {}
impl<T: ComplexField + Copy + Add<Output = T> + Mul<Output = T>> Scalar for T {}

/// A sparse constraint row: `(column, coefficient)` pairs (columns may repeat; they add).
pub type SparseRow = Vec<(usize, f64)>;

/// Relative threshold on the squared sine of the angle between a row and the span of the rows
/// kept before it: below it the row is treated as dependent (sine 1e-7).
const DEPENDENCE_TOLERANCE: f64 = 1e-14;

/// Indices of a maximal linearly independent subset of `rows`, chosen greedily in order, by an
/// incremental Cholesky factorization of the Gram matrix `C Cᵀ`. Zero rows are never kept.
/// Cost O(k² · r + k³) for k rows of r entries: meant for the few constraints of an edit.
pub fn independent_rows(rows: &[SparseRow]) -> Vec<usize> {
    let dense: Vec<std::collections::HashMap<usize, f64>> = rows
        .iter()
        .map(|row| {
            let mut m = std::collections::HashMap::new();
            for &(c, v) in row {
                *m.entry(c).or_insert(0.0) += v;
            }
            m
        })
        .collect();
    let dot =
        |a: usize, b: usize| -> f64 { dense[a].iter().map(|(c, v)| v * dense[b].get(c).copied().unwrap_or(0.0)).sum() };
    let mut kept: Vec<usize> = Vec::new();
    // Rows of the lower-triangular factor L of the Gram matrix of the kept rows.
    let mut factor: Vec<Vec<f64>> = Vec::new();
    for i in 0..rows.len() {
        let norm2 = dot(i, i);
        if !(norm2 > 0.0) {
            continue;
        }
        let mut l = Vec::with_capacity(kept.len() + 1);
        for (a, &j) in kept.iter().enumerate() {
            let s: f64 = (0..a).map(|b| factor[a][b] * l[b]).sum();
            l.push((dot(i, j) - s) / factor[a][a]);
        }
        let residual = norm2 - l.iter().map(|x| x * x).sum::<f64>();
        if residual > DEPENDENCE_TOLERANCE * norm2 {
            l.push(residual.sqrt());
            factor.push(l);
            kept.push(i);
        }
    }
    kept
}

/// `C · M` for sparse rows `C` (k rows) and a dense `M` (n × c): a k × c matrix.
pub fn rows_times<T: Scalar>(rows: &[SparseRow], m: &Mat<T>) -> Mat<T> {
    let mut out = Mat::<T>::zeros(rows.len(), m.ncols());
    for (i, row) in rows.iter().enumerate() {
        for c in 0..m.ncols() {
            let mut s = T::zero_impl();
            for &(col, w) in row {
                s = s + m[(col, c)] * T::from_f64_impl(w);
            }
            out[(i, c)] = s;
        }
    }
    out
}

/// `Cᵀ` as a dense n × k matrix (the right-hand sides of the k extra solves).
pub fn rows_transposed<T: Scalar>(rows: &[SparseRow], n: usize) -> Mat<T> {
    let mut out = Mat::<T>::zeros(n, rows.len());
    for (i, row) in rows.iter().enumerate() {
        for &(col, w) in row {
            out[(col, i)] = out[(col, i)] + T::from_f64_impl(w);
        }
    }
    out
}

/// Solves the small dense system `m · x = rhs` (full pivoting); fails on a non-finite result.
pub fn dense_solve<T: Scalar>(m: &Mat<T>, rhs: &Mat<T>) -> Result<Mat<T>> {
    let x = m.full_piv_lu().solve(rhs);
    let finite = (0..x.ncols()).all(|c| (0..x.nrows()).all(|r| T::is_finite_impl(&x[(r, c)])));
    if finite {
        Ok(x)
    } else {
        Err(Error::Numerical("the constraint (Schur complement) system is singular".into()))
    }
}

/// Solution of `min`/`A x = b` subject to `C x = d`, with `A⁻¹` given by `solve` (in place, any
/// number of columns): `rhs` is `b` (n × c), `rows` and `targets` (k × c) are `C` and `d`,
/// `kept` the independent rows ([`independent_rows`]). Returns `x`. The rows not kept are not
/// checked here (see [`check_dropped`]).
pub fn solve_constrained<T: Scalar, E: From<Error>>(
    solve: impl Fn(&mut Mat<T>) -> std::result::Result<(), E>,
    mut rhs: Mat<T>,
    rows: &[SparseRow],
    targets: &Mat<T>,
    kept: &[usize],
) -> std::result::Result<Mat<T>, E> {
    let n = rhs.nrows();
    solve(&mut rhs)?;
    if kept.is_empty() {
        return Ok(rhs);
    }
    let active: Vec<SparseRow> = kept.iter().map(|&i| rows[i].clone()).collect();
    let d = Mat::<T>::from_fn(kept.len(), targets.ncols(), |r, c| targets[(kept[r], c)]);
    let mut y = rows_transposed::<T>(&active, n);
    solve(&mut y)?;
    let s = rows_times(&active, &y);
    let mut x = rhs;
    // λ = S⁻¹ (C x − d), x ← x − Y λ; twice (the second pass is one step of refinement).
    for _ in 0..2 {
        let residual = rows_times(&active, &x) - &d;
        let lambda = dense_solve(&s, &residual)?;
        x -= &y * &lambda;
    }
    Ok(x)
}

/// Checks that the rows left out by [`independent_rows`] hold at `x` (they are implied by the
/// kept ones, or conflict with them). `fixed_part[i]` is the contribution of already-known
/// values to row i (added to `C x`); `tolerance` is absolute.
pub fn check_dropped(
    rows: &[SparseRow],
    targets: &Mat<f64>,
    fixed_part: &Mat<f64>,
    kept: &[usize],
    x: &Mat<f64>,
    tolerance: f64,
) -> Result<()> {
    let mut is_kept = vec![false; rows.len()];
    for &i in kept {
        is_kept[i] = true;
    }
    for i in (0..rows.len()).filter(|&i| !is_kept[i]) {
        for c in 0..targets.ncols() {
            let value: f64 = rows[i].iter().map(|&(col, w)| w * x[(col, c)]).sum::<f64>() + fixed_part[(i, c)];
            let want = targets[(i, c)];
            if !((value - want).abs() <= tolerance) {
                let position: Vec<f64> = (0..targets.ncols())
                    .map(|c| rows[i].iter().map(|&(col, w)| w * x[(col, c)]).sum::<f64>() + fixed_part[(i, c)])
                    .collect();
                let target: Vec<f64> = (0..targets.ncols()).map(|c| targets[(i, c)]).collect();
                return Err(Error::InvalidArgument(format!(
                    "constraint {i} conflicts with the other constraints or the fixed boundary: it asks for {target:?} but they \
                     already place its point at {position:?} (the constraint rows are linearly dependent)"
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dependent_rows_are_left_out() {
        let rows = vec![
            vec![(0, 1.0)],
            vec![(0, 0.5), (1, 0.5)],
            vec![(1, 1.0)],           // = 2·row1 − row0
            vec![],                   // empty
            vec![(2, 0.3), (2, 0.7)], // repeated column adds up
            vec![(0, 2.0)],           // parallel to row 0
        ];
        assert_eq!(independent_rows(&rows), vec![0, 1, 4]);
    }

    #[test]
    fn constrained_solve_satisfies_the_constraints_and_the_stationarity_condition() {
        // A = tridiagonal SPD 5 × 5, one constraint x1 + x3 = 1.
        let n = 5;
        let a = Mat::<f64>::from_fn(n, n, |i, j| {
            if i == j {
                2.0
            } else if i.abs_diff(j) == 1 {
                -1.0
            } else {
                0.0
            }
        });
        let lu = a.full_piv_lu();
        let solve = |m: &mut Mat<f64>| -> Result<()> {
            *m = lu.solve(&*m);
            Ok(())
        };
        let b = Mat::<f64>::from_fn(n, 1, |i, _| i as f64);
        let rows = vec![vec![(1, 1.0), (3, 1.0)]];
        let d = Mat::<f64>::from_fn(1, 1, |_, _| 1.0);
        let x = solve_constrained(solve, b.clone(), &rows, &d, &[0]).expect("solve");
        assert!((x[(1, 0)] + x[(3, 0)] - 1.0).abs() < 1e-12);
        // A x − b must be a multiple of Cᵀ = e1 + e3.
        let r = &a * &x - &b;
        assert!(r[(0, 0)].abs() < 1e-12 && r[(2, 0)].abs() < 1e-12 && r[(4, 0)].abs() < 1e-12);
        assert!((r[(1, 0)] - r[(3, 0)]).abs() < 1e-12 && r[(1, 0)].abs() > 1e-3);
    }
}
