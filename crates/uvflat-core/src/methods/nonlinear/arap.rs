//! ARAP parameterization (Liu, Zhang, Xu, Gotsman, Gortler 2008, "A Local/Global Approach to
//! Mesh Parameterization", §3–4), free boundary, flip-free.
//!
//! Energy (Liu et al. eq. 3, normalized by the total area): `E = Σ_t (A_t/A) ‖J_t − R_t‖²_F`
//! minimized over the UVs and rotations `R_t`; in singular values `(σ1 − 1)² + (σ2 − 1)²`.
//! - Local step: `R_t` is the closest rotation to `J_t`, `U Vᵀ` from its SVD (§4.1).
//! - Global step: with the rotations fixed, the energy is quadratic in the UVs and its
//!   minimizer solves `L x = b`, `L` the cotangent Laplacian and `b_k = Σ_t (A_t/A) R_t g_k`
//!   (eq. 5–6). `L` does not change, so it is factored once (a tiny diagonal term
//!   `δ(x − x_current)` removes the translation from its kernel).
//!
//! Instead of jumping to the global solution, uvflat searches along `d = x_global − x` with
//! the flip-free line search: for every step `t ∈ [0, 1]` the energy with the old rotations is
//! at most the current one (it is a convex quadratic along `d` minimized at t = 1), and
//! re-fitting the rotations only lowers it, so every accepted step decreases the ARAP energy
//! and no triangle ever flips (Liu et al. observe flips are rare but possible without this).
//!
//! Cost: one Cholesky factorization, then per iteration a parallel SVD per triangle and one
//! two-column solve.

use super::energy::Energy;
use super::jacobian::Svd2;
use super::{descend, solve2, NonlinearOptions, Problem, Run};
use crate::error::Result;
use crate::progress::Progress;
use rayon::prelude::*;

/// Runs ARAP from the flip-free map `x0`.
pub(crate) fn minimize(
    problem: &Problem,
    x0: Vec<[f64; 2]>,
    options: &NonlinearOptions,
    progress: &mut Progress,
) -> Result<Run> {
    let (solver, delta) = problem.laplacian(1e-8)?;
    let inv = 1.0 / problem.frames.total_area;
    descend(problem, Energy::Arap, x0, options, progress, |x, _grad, reset| {
        if reset {
            return Ok(None);
        }
        // Local step: per-triangle rotations, then their right-hand side contributions.
        let contributions: Vec<[[f64; 2]; 3]> = problem
            .tris
            .par_iter()
            .enumerate()
            .with_min_len(1024)
            .map(|(t, &tri)| {
                let r = Svd2::new(&problem.frames.jacobian(t, tri, x)).rotation();
                let w = problem.frames.area[t] * inv;
                problem.frames.grad[t]
                    .map(|g| [w * (r[0][0] * g[0] + r[0][1] * g[1]), w * (r[1][0] * g[0] + r[1][1] * g[1])])
            })
            .collect();
        let mut rhs: Vec<[f64; 2]> = x.iter().map(|p| [delta * p[0], delta * p[1]]).collect();
        for (tri, c) in problem.tris.iter().zip(&contributions) {
            for k in 0..3 {
                let b = &mut rhs[tri[k] as usize];
                b[0] += c[k][0];
                b[1] += c[k][1];
            }
        }
        let global = solve2(&solver, &rhs)?;
        Ok(Some(global.iter().zip(x).map(|(g, p)| [g[0] - p[0], g[1] - p[1]]).collect()))
    })
}
