//! The angle program of the circle patterns (Kharevych, Springborn & Schröder 2006 §4: the
//! quadratic program "closest planar angles", which the paper hands to a QP solver) by a
//! primal–dual interior-point method with Mehrotra's predictor–corrector (Mehrotra 1992;
//! Nocedal & Wright, *Numerical Optimization* 2nd ed., Algorithm 16.4 for convex QPs).
//!
//! ```text
//! minimize ½ Σ w_a (α_a − β_a)²   subject to   J α = c,
//!          s_a = α_a − l_a ≥ 0 (dual z_a),   p_e = π − margin − α_a − α_b ≥ 0 (dual y_e)
//! ```
//!
//! (l_a = MIN_ANGLE for an angle; the variables also hold one slack σ ≥ 0 per boundary vertex
//! whose angle sum is bounded above, with weight 0 and l = 0: see `AngleProgram::slack_row`.)
//!
//! Each iteration linearizes the KKT conditions W(α − β) − z + Gᵀy + Jᵀν = 0, J α = c,
//! s∘z = p∘y = σμ. Eliminating Δz and Δy leaves H Δα + Jᵀ Δν = −g with
//! H = W + diag(z/s) + Gᵀ diag(y/p) G — the same structure as the log-barrier Hessian of the
//! parent module (a diagonal plus one 2×2 block per pair of corners opposite an interior edge),
//! so the same Schur complement J H⁻¹ Jᵀ over triangles and constrained vertices is factored,
//! once per iteration, and solved twice (predictor with σ = 0, corrector with
//! σ = (μ_aff/μ)³ and the second-order term Δs_aff Δz_aff). Primal and dual variables take
//! one common step, 99.5% of the way to the boundary of s, p, z, y > 0.
//!
//! Stops when the equalities hold to 10⁻¹¹, the dual residual is below 10⁻⁷ relative to the
//! objective's gradient, and the mean complementarity μ is below 10⁻⁸ (the log-barrier
//! method's last stage, t = 10⁸, has s z = 10⁻⁸ per constraint). An iterate with μ < 10⁻⁸,
//! the equalities to 10⁻⁹ (what the log-barrier fallback accepts) and the dual residual below
//! 10⁻⁵ relative is kept (the one with the smallest dual residual), and returned when rounding
//! stops the iteration before it gets further, or once the dual residual has grown a
//! hundredfold past it. Much below that the
//! Schur complement, whose entries y/p of the active Delaunay constraints reach 10¹¹ and more,
//! loses the accuracy the dual residual needs (measured on a lattice whose every diagonal is
//! non-Delaunay: the residual grew from 10⁻⁸ to 10³ once μ went below 10⁻¹⁰). Measured against that method
//! on the disk meshes: see docs/methods/circle_patterns.md.

use super::{delaunay_slack, AngleProgram};
use crate::error::{Error, Result};
use crate::progress::Progress;
use uvflat_sparse::CholeskyPattern;

/// Mean complementarity at which the iteration stops.
const MU_TOLERANCE: f64 = 1e-8;
/// Largest equality residual (radians) at which the iteration stops.
const EQUALITY_TOLERANCE: f64 = 1e-11;
/// Largest equality residual of an iterate kept as the answer should later iterations meet
/// rounding trouble: what the log-barrier fallback accepts as its own result.
const ACCEPTABLE_EQUALITY: f64 = 1e-9;
/// Largest dual residual, relative to the objective's gradient, of such an iterate: any
/// strictly feasible angles make a valid pattern, and a stationarity error of 10⁻⁵ moves the
/// optimum's distortion by far less than it shows.
const ACCEPTABLE_DUAL: f64 = 1e-5;
/// Iterations after which the method gives up (it converges in 6–10 on the disk meshes where
/// it converges at all; the caller then runs the log-barrier path).
const MAX_ITERATIONS: u32 = 40;
/// Fraction of the way to the boundary a step may go.
const STEP_FRACTION: f64 = 0.995;

/// The primal–dual iterate: angles, their lower-bound duals, the Delaunay duals, the
/// equality multipliers.
struct Iterate {
    alpha: Vec<f64>,
    z: Vec<f64>,
    y: Vec<f64>,
    nu: Vec<f64>,
}

/// A Newton direction of the iterate.
struct Direction {
    alpha: Vec<f64>,
    z: Vec<f64>,
    y: Vec<f64>,
    nu: Vec<f64>,
}

impl AngleProgram {
    /// The program's angles (`None` where the iteration met numerical trouble — a Schur
    /// complement that rounding made indefinite, divergence, no convergence within
    /// `max_iterations` or [`MAX_ITERATIONS`] — before any iterate met the acceptance test)
    /// and the iterations made. Errors: cancellation only.
    pub(super) fn solve_primal_dual(
        &self,
        max_iterations: u32,
        progress: &mut Progress,
    ) -> Result<(Option<Vec<f64>>, u32)> {
        let alpha = self.start();
        let mut it =
            Iterate { z: vec![1.0; alpha.len()], y: vec![1.0; self.pairs.len()], nu: vec![0.0; self.rows], alpha };
        let mut pattern: Option<CholeskyPattern> = None;
        let mu0 = self.complementarity(&it);
        let max_iterations = max_iterations.clamp(1, MAX_ITERATIONS);
        // The last iterate that met every criterion but the equalities' last digits: returned
        // instead of nothing when rounding stops the iteration afterwards (measured on cone
        // maps of closed meshes: μ 2·10⁻¹⁰ and equalities at 1.1·10⁻¹¹ at the 7th iteration,
        // then the dual residual grew from 7·10⁻⁹ to 10⁻² and the Schur complement lost
        // definiteness, and the log-barrier fallback took 40 more factorizations).
        let mut acceptable: Option<(Vec<f64>, f64)> = None;
        let kept = |a: Option<(Vec<f64>, f64)>| a.map(|(alpha, _)| alpha);
        for iteration in 0..max_iterations {
            let mu = self.complementarity(&it);
            let r_p = self.equality_residual(&it.alpha);
            let (r_d, scale) = self.dual_residual(&it);
            let worst = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let (primal, dual) = (worst(&r_p), worst(&r_d));
            if !(mu.is_finite() && dual.is_finite()) {
                return Ok((kept(acceptable), iteration));
            }
            if mu < MU_TOLERANCE && primal < EQUALITY_TOLERANCE && dual < 1e-7 * (1.0 + scale) {
                return Ok((Some(it.alpha), iteration));
            }
            if mu < MU_TOLERANCE && primal < ACCEPTABLE_EQUALITY && dual < ACCEPTABLE_DUAL * (1.0 + scale) {
                if acceptable.as_ref().is_none_or(|a| dual <= a.1) {
                    acceptable = Some((it.alpha.clone(), dual));
                }
            } else if acceptable.as_ref().is_some_and(|a| dual > 100.0 * a.1) {
                // Rounding has taken over (the dual residual only grows from here).
                return Ok((kept(acceptable), iteration));
            }
            let (s, p) = self.slacks(&it.alpha);
            let own: Vec<f64> = (0..s.len()).map(|a| self.weight[a] + it.z[a] / s[a]).collect();
            let coupling: Vec<f64> = it.y.iter().zip(&p).map(|(y, p)| y / p).collect();
            let inv = self.blocks_inverse(&own, &coupling);
            let schur = match self.factor_schur(&inv, &mut pattern) {
                Ok(s) => s,
                Err(Error::Numerical(_)) => return Ok((kept(acceptable), iteration)),
                Err(e) => return Err(e),
            };
            let solve = |target_s: &[f64], target_p: &[f64]| -> Result<Direction> {
                self.direction(&it, &s, &p, &r_d, &r_p, target_s, target_p, &schur, &inv)
            };
            // Predictor: the affine-scaling direction (complementarity driven to zero).
            let Ok(affine) = solve(&vec![0.0; s.len()], &vec![0.0; p.len()]) else {
                return Ok((kept(acceptable), iteration));
            };
            let step = self.step_length(&it, &s, &p, &affine);
            let mu_affine = self.complementarity_after(&it, &s, &p, &affine, step);
            let sigma = (mu_affine / mu).powi(3).min(1.0);
            // Corrector: centring plus the second-order term of the complementarity.
            let target_s: Vec<f64> = (0..s.len()).map(|a| sigma * mu - affine.alpha[a] * affine.z[a]).collect();
            let target_p: Vec<f64> = (0..p.len())
                .map(|e| {
                    let [a, b] = self.pairs[e];
                    let dp = -(affine.alpha[a as usize] + affine.alpha[b as usize]);
                    sigma * mu - dp * affine.y[e]
                })
                .collect();
            let Ok(direction) = solve(&target_s, &target_p) else {
                return Ok((kept(acceptable), iteration));
            };
            let step = self.step_length(&it, &s, &p, &direction);
            apply(&mut it, &direction, step);
            let done = ((mu0 / mu).ln() / (mu0 / MU_TOLERANCE).ln()).clamp(0.0, 1.0);
            progress.report(0.6 * done)?;
        }
        Ok((kept(acceptable), max_iterations))
    }

    /// Slacks s (lower bounds, per corner) and p (Delaunay, per pair) at α.
    fn slacks(&self, alpha: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let s = alpha.iter().zip(&self.lower).map(|(a, l)| a - l).collect();
        let p = self.pairs.iter().map(|[a, b]| delaunay_slack(alpha[*a as usize], alpha[*b as usize])).collect();
        (s, p)
    }

    /// Mean complementarity μ = (sᵀz + pᵀy) / (number of inequalities).
    fn complementarity(&self, it: &Iterate) -> f64 {
        let (s, p) = self.slacks(&it.alpha);
        let total: f64 =
            s.iter().zip(&it.z).map(|(s, z)| s * z).sum::<f64>() + p.iter().zip(&it.y).map(|(p, y)| p * y).sum::<f64>();
        total / (s.len() + p.len()) as f64
    }

    /// μ after a step of length `step` along `d`.
    fn complementarity_after(&self, it: &Iterate, s: &[f64], p: &[f64], d: &Direction, step: f64) -> f64 {
        let lower: f64 = (0..s.len()).map(|a| (s[a] + step * d.alpha[a]) * (it.z[a] + step * d.z[a])).sum();
        let delaunay: f64 = (0..p.len())
            .map(|e| {
                let [a, b] = self.pairs[e];
                let dp = -(d.alpha[a as usize] + d.alpha[b as usize]);
                (p[e] + step * dp) * (it.y[e] + step * d.y[e])
            })
            .sum();
        (lower + delaunay) / (s.len() + p.len()) as f64
    }

    /// The dual residual W(α − β) − z + Gᵀy + Jᵀν, and the size of its objective part.
    fn dual_residual(&self, it: &Iterate) -> (Vec<f64>, f64) {
        let jt = self.apply_jt(&it.nu);
        let mut scale = 0.0f64;
        let mut r: Vec<f64> = (0..it.alpha.len())
            .map(|a| {
                let objective = self.weight[a] * (it.alpha[a] - self.beta[a]);
                scale = scale.max(objective.abs());
                objective - it.z[a] + jt[a]
            })
            .collect();
        for ([a, b], y) in self.pairs.iter().zip(&it.y) {
            r[*a as usize] += y;
            r[*b as usize] += y;
        }
        (r, scale)
    }

    /// The Newton direction for complementarity targets s∘z → `target_s`, p∘y → `target_p`
    /// (each including the current products' removal): with Δz = (T_s − s z)/s − (z/s) Δα and
    /// Δy = (T_p − p y)/p + (y/p) G Δα, the reduced system H Δα + Jᵀ Δν = −g, J Δα = −r_p.
    #[allow(clippy::too_many_arguments)]
    fn direction(
        &self,
        it: &Iterate,
        s: &[f64],
        p: &[f64],
        r_d: &[f64],
        r_p: &[f64],
        target_s: &[f64],
        target_p: &[f64],
        schur: &uvflat_sparse::CholeskySolver<f64>,
        inv: &[[f64; 3]],
    ) -> Result<Direction> {
        let ds: Vec<f64> = (0..s.len()).map(|a| target_s[a] / s[a] - it.z[a]).collect();
        let dp: Vec<f64> = (0..p.len()).map(|e| target_p[e] / p[e] - it.y[e]).collect();
        let mut g: Vec<f64> = (0..s.len()).map(|a| r_d[a] - ds[a]).collect();
        for ([a, b], v) in self.pairs.iter().zip(&dp) {
            g[*a as usize] += v;
            g[*b as usize] += v;
        }
        let (alpha, nu) = self.kkt_step(schur, inv, &g, r_p)?;
        let z = (0..s.len()).map(|a| ds[a] - it.z[a] / s[a] * alpha[a]).collect();
        let y = (0..p.len())
            .map(|e| {
                let [a, b] = self.pairs[e];
                dp[e] + it.y[e] / p[e] * (alpha[a as usize] + alpha[b as usize])
            })
            .collect();
        Ok(Direction { alpha, z, y, nu })
    }

    /// The longest step ≤ 1 keeping s, p, z, y positive, times [`STEP_FRACTION`].
    fn step_length(&self, it: &Iterate, s: &[f64], p: &[f64], d: &Direction) -> f64 {
        let mut step = 1.0f64;
        let mut limit = |value: f64, change: f64| {
            if change < 0.0 {
                step = step.min(-STEP_FRACTION * value / change);
            }
        };
        for (a, &slack) in s.iter().enumerate() {
            limit(slack, d.alpha[a]);
            limit(it.z[a], d.z[a]);
        }
        for (e, [a, b]) in self.pairs.iter().enumerate() {
            limit(p[e], -(d.alpha[*a as usize] + d.alpha[*b as usize]));
            limit(it.y[e], d.y[e]);
        }
        step
    }
}

/// it += step · d.
fn apply(it: &mut Iterate, d: &Direction, step: f64) {
    let add = |x: &mut Vec<f64>, dx: &[f64]| x.iter_mut().zip(dx).for_each(|(x, dx)| *x += step * dx);
    add(&mut it.alpha, &d.alpha);
    add(&mut it.z, &d.z);
    add(&mut it.y, &d.y);
    add(&mut it.nu, &d.nu);
}
