//! Gradient-based minimization of MIPS (Hormann & Greiner 2000), Sander's L2 stretch (Sander et
//! al. 2001), Green–Lagrange (Maillot et al. 1993) and Degener's θ-energy (Degener et al. 2003)
//! — and of any energy of [`super::energy`] — by preconditioned L-BFGS with the flip-free line
//! search.
//!
//! L-BFGS (Nocedal & Wright 2006, Alg. 7.4–7.5, memory 8) keeps the last pairs
//! `s = x_{k+1} − x_k`, `y = ∇E_{k+1} − ∇E_k` and applies an approximate inverse Hessian by the
//! two-loop recursion. Its initial matrix is `γ P⁻¹` with `P` the cotangent Laplacian (the
//! Hessian of the Dirichlet energy, which every energy here resembles near an isometry or a
//! conformal map; Zhu, Bridson, Kaufman 2018 use the same preconditioner for distortion
//! energies) and `γ = sᵀy / yᵀP⁻¹y` from the latest pair. `P` is factored once; each
//! iteration costs two two-column solves, one energy-and-gradient evaluation and the line
//! search's energy evaluations. When a direction is not a descent direction or its line search
//! fails, the history is dropped and the preconditioned gradient `−P⁻¹∇E` is tried.

use super::energy::Energy;
use super::{descend, solve2, NonlinearOptions, Problem, Run};
use crate::error::Result;
use crate::progress::Progress;
use std::collections::VecDeque;

/// Pairs kept by L-BFGS.
const MEMORY: usize = 8;

/// Σ a·b over per-vertex 2-vectors.
pub(crate) fn dot(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p[0] * q[0] + p[1] * q[1]).sum()
}

/// y += a·x over per-vertex 2-vectors.
pub(crate) fn axpy(y: &mut [[f64; 2]], a: f64, x: &[[f64; 2]]) {
    for (p, q) in y.iter_mut().zip(x) {
        p[0] += a * q[0];
        p[1] += a * q[1];
    }
}

fn diff(a: &[[f64; 2]], b: &[[f64; 2]]) -> Vec<[f64; 2]> {
    a.iter().zip(b).map(|(p, q)| [p[0] - q[0], p[1] - q[1]]).collect()
}

/// A stored pair `(s, y, 1/yᵀs)`.
struct Pair {
    s: Vec<[f64; 2]>,
    y: Vec<[f64; 2]>,
    rho: f64,
}

/// Runs preconditioned L-BFGS on `energy` from the flip-free map `x0`.
pub(crate) fn minimize(
    problem: &Problem,
    energy: Energy,
    x0: Vec<[f64; 2]>,
    options: &NonlinearOptions,
    progress: &mut Progress,
) -> Result<Run> {
    let (solver, _) = problem.laplacian(1e-8)?;
    let mut pairs: VecDeque<Pair> = VecDeque::new();
    let mut gamma = 1.0;
    let mut previous: Option<(Vec<[f64; 2]>, Vec<[f64; 2]>)> = None;
    descend(problem, energy, x0, options, progress, |x, grad, reset| {
        if reset {
            pairs.clear();
            gamma = 1.0;
        } else if let Some((px, pg)) = previous.take() {
            let (s, y) = (diff(x, &px), diff(grad, &pg));
            let sy = dot(&s, &y);
            if sy > 1e-12 * dot(&s, &s).sqrt() * dot(&y, &y).sqrt() {
                let py = solve2(&solver, &y)?;
                gamma = sy / dot(&y, &py);
                if pairs.len() == MEMORY {
                    pairs.pop_front();
                }
                pairs.push_back(Pair { s, y, rho: 1.0 / sy });
            }
        }
        previous = Some((x.to_vec(), grad.to_vec()));
        // Two-loop recursion.
        let mut q = grad.to_vec();
        let mut alpha = Vec::with_capacity(pairs.len());
        for p in pairs.iter().rev() {
            let a = p.rho * dot(&p.s, &q);
            axpy(&mut q, -a, &p.y);
            alpha.push(a);
        }
        let mut r = solve2(&solver, &q)?;
        let scale = if pairs.is_empty() { 1.0 } else { gamma };
        for v in &mut r {
            v[0] *= scale;
            v[1] *= scale;
        }
        for (p, a) in pairs.iter().zip(alpha.iter().rev()) {
            let b = p.rho * dot(&p.y, &r);
            axpy(&mut r, a - b, &p.s);
        }
        let mut d: Vec<[f64; 2]> = r.iter().map(|v| [-v[0], -v[1]]).collect();
        if !(dot(&d, grad) < 0.0) {
            pairs.clear();
            d = solve2(&solver, grad)?.iter().map(|v| [-v[0], -v[1]]).collect();
        }
        Ok(Some(d))
    })
}
