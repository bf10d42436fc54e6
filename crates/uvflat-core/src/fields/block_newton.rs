//! The numerical solution mechanism of PGP (Ray et al. 2006, §2.5), shared by the periodic
//! solve (§2.3–2.4, B = 4 unknowns per vertex: cos θ, sin θ, cos φ, sin φ) and the vector
//! field smoothing (§4.2, B = 2: cos α, sin α).
//!
//! The energy is a quadratic form over per-vertex blocks of B reals plus the penalty of §2.5
//! that keeps every pair of unknowns (a cosine and its sine) near unit norm:
//!
//! ```text
//! F**(x) = xᵀ A x − 2 bᵀ x + c + ε Σ_v Σ_pairs (‖x_v,pair‖² − 1)²
//! ```
//!
//! 1. Some blocks may be locked (§2.5: one vertex per connected component at U = V = (1, 0));
//!    F* = xᵀAx − 2bᵀx + c is minimized over the others by one sparse Cholesky solve (faer,
//!    through [`uvflat_sparse::CholeskyPattern`]; the paper used Jacobi-preconditioned
//!    conjugate gradients).
//! 2. From there — each (cosine, sine) pair scaled to unit norm, see [`project_on_unit_pairs`] —
//!    Newton's method on F** until ‖∇F**‖₂ < tolerance (paper: 10⁻⁶), with a
//!    backtracking (Armijo) line search. The Hessian is 2A plus the penalty's exact Hessian
//!    `ε (4(‖u‖² − 1) I + 8 u uᵀ)` per pair, whose eigenvalues are ≥ −4ε. Where that makes the
//!    system indefinite (pairs well inside the unit circle, near singularities) the step uses
//!    the Hessian shifted by `μ · 4ε I` (Levenberg–Marquardt damping of the penalty part): μ
//!    grows ×4 from 0.01 until the factorization succeeds — at μ = 1 the penalty part is
//!    positive semidefinite, so it always does. The next iteration starts from the same μ, or
//!    from μ / 4 when this one needed no increase, back to the exact Hessian below 0.01
//!    (a failed factorization costs as much as a successful one). An earlier version clamped the negative
//!    eigenvalues to zero per pair (the same as μ = 1 at the worst pairs) and tried the exact
//!    Hessian only every fourth iteration; it converged linearly and left ‖∇F**‖ at 0.17 after
//!    30 iterations on `closed_g0_spot`, where the damped steps reach 10⁻⁹ in 28.
//!
//! The block sparsity pattern (one B×B block per vertex and per edge) and its symbolic
//! factorization (block-level nested dissection, expanded to the B unknowns of each block; the
//! periodic solve passes one block per (cosine, sine) pair, the smoothing one per vertex)
//! are computed once and reused by every factorization.
//!
//! Cost per Newton iteration: one numeric factorization of a (B·V)×(B·V) matrix (one more per
//! rejected shift) and O(E·B²) for the assembly, the gradient and each line-search energy. All
//! factorizations go into the storage of the first one ([`CholeskyPattern::refactor_values`],
//! which also keeps the large fronts' buffers between factorizations and puts each matrix
//! entry straight into its front, [`uvflat_sparse::front_assembly`]); a rejected shift stops
//! the factorization at the failing front. On the 207k-face disk of `crates/uvflat-core/benches/pgp.rs` a
//! factorization plus its solve took about 0.55 s with per-vertex blocks (0.44 + 0.11 s; 0.7 s with the plane-split
//! order used before [`block_order`]), a rejected one 0.01–0.4 s depending on how near the root
//! of the elimination tree it fails.
//! Measured and not adopted (`crates/uvflat-core/benches/pgp_diagnostics.rs` on `closed_g0_armadillo`, 80
//! iterations, 44 s for the Newton phase): conjugate gradients preconditioned by the previous
//! iteration's factor (the Hessian changes most where the singular points move, so 5 iterations
//! reached a relative residual of 0.1 on fewer than half of the steps: 48 s); Newton steps
//! restricted to the vertices carrying 99% of ‖∇F**‖² plus 3 rings (105 iterations, 42 s, same
//! result); a single-precision factor (only 11% faster: the factorization is bound by memory
//! traffic, not flops); starting from a solve at ε/100 (41–57 iterations, erratic); relaxing μ
//! more slowly (fewer rejected shifts, more iterations: 47–53 s); faer's dynamic pivot
//! regularization instead of the shift (replacing non-positive pivots by a constant overflows
//! on these indefinite systems); a modified Cholesky that, instead of rejecting the whole
//! factorization, shifts only the pivot block of the front that fails (τ = 2·max(−θ, 0) + δ
//! from a Lanczos estimate θ of its smallest eigenvalue), with μ = 0 throughout: no rejected
//! factorization any more, but the shifts (up to 45 on those blocks, whose Schur complements
//! are far more indefinite than H) gave poor directions (line-search steps of 1/128 and less),
//! so the iterations went 80 → 49 on armadillo (28.5 → 15.5 s) but 42 → 56 on kitten (24.9 →
//! 32.6 s) and 51 → 57 on the 207k-face disk (68.2 → 67.0 s); keeping the μ schedule and
//! shifting the front instead of retrying was no better (54 / 67 / 58 iterations); chord steps
//! (the last factor reused for up to 1 or 3 more steps while each is a full step with at least
//! a quarter of the predicted decrease): on the 207k-face disk, which converges in 62 Newton
//! iterations, both stopped unconverged at the 100-iteration limit (‖∇F**‖ ≈ 0.3, 81.9 / 61.6 s
//! against 63–69 s converged); on 2026-12-04 (README, "Speed"): the shift grid ×2 / ÷2 (the
//! 207k-face disk 62 → 73 iterations), the minimum of the unshifted model along a shifted step
//! (t* = −gᵀs / (−gᵀs − σ‖s‖²): fewer iterations on 11 of 29 runs, more on kitten 69 → 76, about
//! the same total time), a line search along polar steps per pair (unconverged after 100
//! iterations on armadillo, nefertiti and spot), and faer's supernode relaxation looser or
//! tighter than its default (10 Newton iterations on the 207k-face disk: 14.1–14.8 s, against
//! 14.2 s with the default).

use super::frames::EdgeList;
use crate::error::{Error, Result};
use crate::mesh::NONE;
use crate::progress::Progress;
use crate::TriMesh;
use faer::sparse::SymbolicSparseColMat;
use faer::Mat;
use uvflat_sparse::{ordering, CholeskyPattern, CholeskySolver};

/// A B×B block.
pub type Block<const B: usize> = [[f64; B]; B];

/// `F*(x) = xᵀ A x − 2 bᵀ x + c` over blocks of B unknowns: from [`BlockSystem::new`], the
/// referenced vertices of a mesh are the blocks and its edges the off-diagonal blocks; the
/// periodic solve also builds one with a block per (cosine, sine) pair (`periodic.rs`).
pub struct BlockSystem<const B: usize> {
    /// Block of each mesh vertex ([`NONE`] for unreferenced vertices); empty when the blocks are
    /// not one per vertex (then [`Self::add_diagonal`] and [`Self::add_pair`] do not apply).
    pub block_of: Vec<u32>,
    /// Mesh vertex of each block.
    pub vertex_of: Vec<u32>,
    /// Block endpoints of each off-diagonal block, `[hi, lo]`, hi > lo, no pair twice (from
    /// [`BlockSystem::new`]: one per mesh edge, in [`EdgeList`] numbering).
    pub edge_blocks: Vec<[u32; 2]>,
    /// Diagonal blocks `A_vv`.
    pub diag: Vec<Block<B>>,
    /// Off-diagonal blocks `A_hi,lo` (the block `A_lo,hi` is its transpose).
    pub off: Vec<Block<B>>,
    /// Linear term b.
    pub rhs: Vec<[f64; B]>,
    /// Constant c.
    pub constant: f64,
}

impl<const B: usize> BlockSystem<B> {
    /// A zero system over the referenced vertices and edges of `mesh`.
    pub fn new(mesh: &TriMesh, edges: &EdgeList) -> Self {
        let mut block_of = vec![NONE; mesh.vertex_count()];
        let mut vertex_of = Vec::new();
        for v in 0..mesh.vertex_count() as u32 {
            if mesh.is_referenced(v) {
                block_of[v as usize] = vertex_of.len() as u32;
                vertex_of.push(v);
            }
        }
        let edge_blocks = edges
            .edges
            .iter()
            .map(|&[a, b]| {
                let (x, y) = (block_of[a as usize], block_of[b as usize]);
                [x.max(y), x.min(y)]
            })
            .collect();
        let n = vertex_of.len();
        BlockSystem {
            block_of,
            vertex_of,
            edge_blocks,
            diag: vec![[[0.0; B]; B]; n],
            off: vec![[[0.0; B]; B]; edges.edges.len()],
            rhs: vec![[0.0; B]; n],
            constant: 0.0,
        }
    }

    /// Number of blocks.
    pub fn blocks(&self) -> usize {
        self.vertex_of.len()
    }

    /// Adds `q` to the diagonal block of mesh vertex `v`.
    pub fn add_diagonal(&mut self, v: u32, q: &Block<B>) {
        let d = &mut self.diag[self.block_of[v as usize] as usize];
        for r in 0..B {
            for c in 0..B {
                d[r][c] += q[r][c];
            }
        }
    }

    /// Adds `q` to block (row `v`, column `w`) of A, and its transpose to (w, v), where `e` is
    /// the mesh edge between `v` and `w`.
    pub fn add_pair(&mut self, e: u32, v: u32, w: u32, q: &Block<B>) {
        let [hi, lo] = self.edge_blocks[e as usize];
        let (bv, bw) = (self.block_of[v as usize], self.block_of[w as usize]);
        debug_assert!((bv, bw) == (hi, lo) || (bv, bw) == (lo, hi), "edge {e} does not join vertices {v} and {w}");
        let o = &mut self.off[e as usize];
        let transposed = bv != hi;
        for r in 0..B {
            for c in 0..B {
                if transposed {
                    o[c][r] += q[r][c];
                } else {
                    o[r][c] += q[r][c];
                }
            }
        }
    }

    /// `A x`.
    fn apply(&self, x: &[[f64; B]]) -> Vec<[f64; B]> {
        let mut y: Vec<[f64; B]> = self.diag.iter().zip(x).map(|(d, xv)| mul(d, xv)).collect();
        for (&[hi, lo], o) in self.edge_blocks.iter().zip(&self.off) {
            let (hi, lo) = (hi as usize, lo as usize);
            let a = mul(o, &x[lo]);
            let b = mul_transposed(o, &x[hi]);
            for r in 0..B {
                y[hi][r] += a[r];
                y[lo][r] += b[r];
            }
        }
        y
    }

    /// `F*(x) = xᵀ A x − 2 bᵀ x + c`.
    pub fn quadratic_energy(&self, x: &[[f64; B]]) -> f64 {
        let ax = self.apply(x);
        let mut e = self.constant;
        for v in 0..x.len() {
            for r in 0..B {
                e += x[v][r] * ax[v][r] - 2.0 * self.rhs[v][r] * x[v][r];
            }
        }
        e
    }
}

#[inline]
fn mul<const B: usize>(m: &Block<B>, x: &[f64; B]) -> [f64; B] {
    std::array::from_fn(|r| (0..B).map(|c| m[r][c] * x[c]).sum())
}

#[inline]
fn mul_transposed<const B: usize>(m: &Block<B>, x: &[f64; B]) -> [f64; B] {
    std::array::from_fn(|c| (0..B).map(|r| m[r][c] * x[r]).sum())
}

/// Default weight ε of the periodic solve's unit-norm penalty.
///
/// The paper uses 10⁻³ so that the penalty prevents "the norms of the U, V's from decreasing"
/// (§2.5) and singular points are where the norms vanish (its Fig. 5). With our F* (λ = cot/2,
/// dimensionless) that does not happen at 10⁻³ on any of the 15 closed meshes of
/// `tests/data/meshes`: uniformly shrinking all unknowns by s changes F** by
/// (s² − 1) F* + ε n (s² − 1)², so whenever F* / n > 2ε (a field whose curl is not negligible
/// at the scale of one edge times ω) the minimum has every norm near 0 — measured medians of
/// ‖U‖ 3·10⁻⁵ (man) to 3·10⁻³ (cow) — and ∇F** < 10⁻⁶ holds only because everything is tiny.
/// With ε = 0.1 (the smoothing's) the median ‖U‖ is ≈ 0.9, small norms mark the singular
/// points as in Fig. 5, and the singular triangles drop (bunny 3.8 → 2.2%, fertility
/// 3.6 → 1.5%, spot 2.3 → 1.3%, knight 25 → 14%, see docs/methods/pgp.md). The price is a slower
/// Newton phase (singular points drift apart over 10–30 iterations instead of 3–5).
pub const PERIODIC_EPSILON: f64 = 0.1;

/// Default Newton iteration limit of the periodic solve: a safeguard, Newton normally stops
/// earlier at ‖∇F**‖ < 10⁻⁶ (the paper's criterion). At ε = [`PERIODIC_EPSILON`] the singular
/// points drift apart slowly after the first few iterations: with the damped steps (module
/// comment) the tolerance takes 3–78 iterations on the 15 closed meshes of `tests/data/meshes`
/// with and without curl correction, all but the mesh torus without it, which reaches the limit
/// (2026-12-06: bob 6, knight 11, cow 20, bunny 27, man 33, armadillo 49, kitten 69, nefertiti
/// 78 without curl correction; the paper needed ≤ 5 at its ε). Each iteration is one or two factorizations: on the 207k-face disk of
/// `crates/uvflat-core/benches/pgp.rs` the whole pipeline converges (62 iterations) in 39–48 s on this shared
/// 2-core machine, against a 60 s target. A smaller limit trades the last digits of the
/// gradient for time: the singular triangles change by at most 0.5 points after 10 iterations
/// (spot 1.26% at 10, 1.13% converged; kitten 0.90 / 0.81%).
pub const PERIODIC_ITERATIONS: usize = 100;

/// Options of [`minimize`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// ε, the weight of the unit-norm penalty (paper: 10⁻³; default [`PERIODIC_EPSILON`]).
    /// 0 skips the Newton phase.
    pub epsilon: f64,
    /// Stop when ‖∇F**‖₂ is below this (paper: 10⁻⁶).
    pub gradient_tolerance: f64,
    /// At most this many Newton iterations.
    pub max_iterations: usize,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions { epsilon: PERIODIC_EPSILON, gradient_tolerance: 1e-6, max_iterations: PERIODIC_ITERATIONS }
    }
}

/// What [`minimize`] did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolveReport {
    /// Newton iterations done.
    pub iterations: usize,
    /// Iterations whose step used a shifted (damped) Hessian because the exact one was not
    /// positive definite.
    pub clamped_iterations: usize,
    /// F** after the linear solve.
    pub initial_energy: f64,
    /// F** of the result.
    pub final_energy: f64,
    /// ‖∇F**‖₂ after the linear solve.
    pub initial_gradient: f64,
    /// ‖∇F**‖₂ of the result.
    pub final_gradient: f64,
    /// Whether ‖∇F**‖₂ < tolerance was reached.
    pub converged: bool,
}

/// Minimizes F** (module comment) with the blocks in `locked` fixed at their values; returns
/// the unknowns per block. `progress` receives fractions in [`progress_span`].
pub fn minimize<const B: usize>(
    system: &BlockSystem<B>,
    locked: &[(u32, [f64; B])],
    options: &NewtonOptions,
    progress: &mut Progress,
    progress_span: (f64, f64),
) -> Result<(Vec<[f64; B]>, SolveReport)> {
    check_options(options)?;
    let n = system.blocks();
    let mut is_locked = vec![false; n];
    let mut x = vec![[0.0; B]; n];
    for &(b, value) in locked {
        is_locked[b as usize] = true;
        x[b as usize] = value;
    }
    let pattern = BlockPattern::new(system)?;
    progress.report(progress_span.0)?;

    // 1. The linear solve of F* with the locked blocks fixed.
    let mut values = Vec::new();
    pattern.matrix_values(system, &is_locked, 1.0, &mut values);
    let solver = pattern.analysis.factor_values(&values)?;
    let ax_locked = system.apply(&x);
    let mut rhs = Mat::<f64>::zeros(B * n, 1);
    for v in 0..n {
        for r in 0..B {
            rhs[(B * v + r, 0)] = if is_locked[v] { x[v][r] } else { system.rhs[v][r] - ax_locked[v][r] };
        }
    }
    solver.solve_in_place(&mut rhs)?;
    for v in 0..n {
        for r in 0..B {
            x[v][r] = rhs[(B * v + r, 0)];
        }
    }
    uvflat_sparse::require_finite(x.iter().flatten().copied(), "periodic")?;
    // The Newton matrices differ from 2A only in their diagonal blocks (the penalty's Hessian
    // is block diagonal): the off-diagonal values are written once, the diagonal blocks per
    // factorization (`BlockPattern::set_diagonal_blocks`).
    pattern.matrix_values(system, &is_locked, 2.0, &mut values);
    let mut workspace = NewtonWorkspace { values, factor: solver };
    if options.epsilon > 0.0 {
        project_on_unit_pairs(&mut x, &is_locked);
    }

    // 2. Newton on F**.
    let objective = Objective { system, epsilon: options.epsilon, locked: &is_locked };
    let mut report = SolveReport::default();
    let (mut energy, mut gradient) = (objective.energy(&x), objective.gradient(&x));
    report.initial_energy = energy;
    report.initial_gradient = norm2(&gradient);
    let span = progress_span.1 - progress_span.0;
    let mut shift = 0.0;
    while options.epsilon > 0.0 && report.iterations < options.max_iterations {
        let g_norm = norm2(&gradient);
        if g_norm < options.gradient_tolerance {
            break;
        }
        progress
            .report(progress_span.0 + span * (report.iterations + 1) as f64 / (options.max_iterations + 1) as f64)?;
        let (step, used) = newton_step(&pattern, &objective, &x, &gradient, shift, &mut workspace)?;
        report.clamped_iterations += (used > 0.0) as usize;
        shift = next_shift(shift, used);
        report.iterations += 1;
        match line_search(&objective, &x, energy, &gradient, &step) {
            Some((next, e)) => {
                x = next;
                energy = e;
                gradient = objective.gradient(&x);
            }
            None => break, // no decrease possible at this precision
        }
    }
    report.final_energy = energy;
    report.final_gradient = norm2(&gradient);
    report.converged = report.final_gradient < options.gradient_tolerance;
    progress.report(progress_span.1)?;
    Ok((x, report))
}

/// Scales every (cosine, sine) pair of the free blocks to unit norm (a zero pair becomes
/// (1, 0)). The linear solution's norms decay where the target field is not integrable (and
/// everywhere when the linear term is weak), and at x = 0 the penalty has zero gradient, so
/// Newton would stop where it starts; its projection on the constraint set the penalty
/// approximates is the starting point instead.
fn project_on_unit_pairs<const B: usize>(x: &mut [[f64; B]], locked: &[bool]) {
    for (xv, &l) in x.iter_mut().zip(locked) {
        if l {
            continue;
        }
        for p in 0..B / 2 {
            let n = xv[2 * p].hypot(xv[2 * p + 1]);
            let (c, s) = if n > 0.0 { (xv[2 * p] / n, xv[2 * p + 1] / n) } else { (1.0, 0.0) };
            xv[2 * p] = c;
            xv[2 * p + 1] = s;
        }
    }
}

fn check_options(o: &NewtonOptions) -> Result<()> {
    if !(o.epsilon.is_finite() && o.epsilon >= 0.0) {
        return Err(Error::InvalidArgument(format!(
            "the penalty weight epsilon must be finite and >= 0 (got {})",
            o.epsilon
        )));
    }
    if !(o.gradient_tolerance.is_finite() && o.gradient_tolerance > 0.0) {
        return Err(Error::InvalidArgument(format!(
            "the gradient tolerance must be finite and > 0 (got {})",
            o.gradient_tolerance
        )));
    }
    Ok(())
}

fn norm2<const B: usize>(g: &[[f64; B]]) -> f64 {
    g.iter().flatten().map(|v| v * v).sum::<f64>().sqrt()
}

/// F** and its derivatives, with the locked blocks held fixed.
struct Objective<'a, const B: usize> {
    system: &'a BlockSystem<B>,
    epsilon: f64,
    locked: &'a [bool],
}

impl<const B: usize> Objective<'_, B> {
    fn energy(&self, x: &[[f64; B]]) -> f64 {
        let penalty: f64 = x
            .iter()
            .map(|xv| (0..B / 2).map(|p| (xv[2 * p].powi(2) + xv[2 * p + 1].powi(2) - 1.0).powi(2)).sum::<f64>())
            .sum();
        self.system.quadratic_energy(x) + self.epsilon * penalty
    }

    /// ∇F** (zero on locked blocks).
    fn gradient(&self, x: &[[f64; B]]) -> Vec<[f64; B]> {
        let mut g = self.system.apply(x);
        for (v, gv) in g.iter_mut().enumerate() {
            if self.locked[v] {
                *gv = [0.0; B];
                continue;
            }
            for r in 0..B {
                gv[r] = 2.0 * (gv[r] - self.system.rhs[v][r]);
            }
            for p in 0..B / 2 {
                let (a, b) = (x[v][2 * p], x[v][2 * p + 1]);
                let s = 4.0 * self.epsilon * (a * a + b * b - 1.0);
                gv[2 * p] += s * a;
                gv[2 * p + 1] += s * b;
            }
        }
        g
    }

    /// The penalty's exact Hessian per block.
    fn penalty_hessian(&self, x: &[[f64; B]]) -> Vec<Block<B>> {
        x.iter()
            .map(|xv| {
                let mut h = [[0.0; B]; B];
                for p in 0..B / 2 {
                    let u = [xv[2 * p], xv[2 * p + 1]];
                    let s = u[0] * u[0] + u[1] * u[1];
                    // 4(s − 1) I + 8 u uᵀ: eigenvalue 12 s − 4 along u, 4(s − 1) across.
                    let (along, across) = (12.0 * s - 4.0, 4.0 * (s - 1.0));
                    let block = if s > 0.0 {
                        let n = [u[0] / s.sqrt(), u[1] / s.sqrt()];
                        [
                            [across + (along - across) * n[0] * n[0], (along - across) * n[0] * n[1]],
                            [(along - across) * n[0] * n[1], across + (along - across) * n[1] * n[1]],
                        ]
                    } else {
                        [[across, 0.0], [0.0, across]]
                    };
                    for r in 0..2 {
                        for c in 0..2 {
                            h[2 * p + r][2 * p + c] = self.epsilon * block[r][c];
                        }
                    }
                }
                h
            })
            .collect()
    }
}

/// Smallest non-zero shift μ of the penalty Hessian (module comment).
const MIN_SHIFT: f64 = 0.01;

/// The shift the next Newton step starts from: relaxed ÷4 (to 0 below [`MIN_SHIFT`]) only after
/// a step that needed no increase — one that did would most likely fail again at the lower
/// value, and a failed factorization costs as much as a successful one.
fn next_shift(started: f64, used: f64) -> f64 {
    if used > started {
        used
    } else if used / 4.0 < MIN_SHIFT {
        0.0
    } else {
        used / 4.0
    }
}

/// Solves `(H + μ · 4ε I) step = −g` for the smallest μ in {`shift`, 4·`shift`, …} (starting at
/// [`MIN_SHIFT`] after a zero shift fails) whose matrix factors and gives a descent direction;
/// μ ≥ 1 always does. Returns the step and the μ used.
fn newton_step<const B: usize>(
    pattern: &BlockPattern,
    objective: &Objective<'_, B>,
    x: &[[f64; B]],
    gradient: &[[f64; B]],
    shift: f64,
    workspace: &mut NewtonWorkspace,
) -> Result<(Vec<[f64; B]>, f64)> {
    let penalty = objective.penalty_hessian(x);
    let mut mu = shift;
    loop {
        let diagonal = DiagonalTerms { scale: 2.0, blocks: &penalty, shift: mu * 4.0 * objective.epsilon };
        pattern.set_diagonal_blocks(objective.system, objective.locked, &diagonal, &mut workspace.values);
        if let Some(step) = descent_step(pattern, &workspace.values, gradient, &mut workspace.factor)? {
            return Ok((step, mu));
        }
        if mu >= 1.0 {
            return Err(Error::Numerical("the Newton system of the periodic solve gives no descent direction".into()));
        }
        mu = (4.0 * mu).clamp(MIN_SHIFT, 1.0);
    }
}

/// Storage reused by every Newton step: the matrix values (those of 2A outside the diagonal
/// blocks) and the factor.
struct NewtonWorkspace {
    values: Vec<f64>,
    factor: CholeskySolver<f64>,
}

/// `−H⁻¹ g` when `H` (the values of the pattern's matrix) factors (into `workspace`) and the
/// result is a finite descent direction.
fn descent_step<const B: usize>(
    pattern: &BlockPattern,
    h: &[f64],
    gradient: &[[f64; B]],
    workspace: &mut CholeskySolver<f64>,
) -> Result<Option<Vec<[f64; B]>>> {
    match pattern.analysis.refactor_values(h, workspace) {
        Ok(()) => {}
        Err(uvflat_sparse::Error::Numerical(_)) => return Ok(None),
        Err(e) => return Err(e.into()),
    }
    let solver = &*workspace;
    let n = gradient.len();
    let mut rhs = Mat::<f64>::from_fn(B * n, 1, |i, _| -gradient[i / B][i % B]);
    solver.solve_in_place(&mut rhs)?;
    let step: Vec<[f64; B]> = (0..n).map(|v| std::array::from_fn(|r| rhs[(B * v + r, 0)])).collect();
    let slope: f64 = step.iter().flatten().zip(gradient.iter().flatten()).map(|(s, g)| s * g).sum();
    Ok((slope < 0.0 && step.iter().flatten().all(|s| s.is_finite())).then_some(step))
}

/// Relative size of the slope `gᵀp` below which the energy change of a Newton step is at the
/// rounding level of F** (a sum over every edge and vertex); see [`line_search`].
const ENERGY_RESOLUTION: f64 = 1e-11;

/// Backtracking line search with the Armijo condition; `None` when no step decreases F**.
/// When the predicted decrease `−gᵀp` is below the rounding level of F** (relative
/// [`ENERGY_RESOLUTION`]), energies cannot rank the trials: the full step is then taken if it
/// lowers ‖∇F**‖ (it does quadratically near a minimizer) without raising F** by more than
/// that level. Without this rule the search accepted steps of length 10⁻¹² that changed
/// nothing, and Newton stalled at ‖∇F**‖ ≈ 2·10⁻⁶ (`disk_face_libigl_loop1` under a different
/// shift rule, where the full step would have converged).
fn line_search<const B: usize>(
    objective: &Objective<'_, B>,
    x: &[[f64; B]],
    energy: f64,
    gradient: &[[f64; B]],
    step: &[[f64; B]],
) -> Option<(Vec<[f64; B]>, f64)> {
    let slope: f64 = step.iter().flatten().zip(gradient.iter().flatten()).map(|(s, g)| s * g).sum();
    let at = |t: f64| -> Vec<[f64; B]> {
        x.iter().zip(step).map(|(xv, sv)| std::array::from_fn(|r| xv[r] + t * sv[r])).collect()
    };
    let resolution = ENERGY_RESOLUTION * energy.abs().max(1.0);
    if -slope < resolution {
        let trial = at(1.0);
        let e = objective.energy(&trial);
        if e <= energy + resolution && norm2(&objective.gradient(&trial)) < norm2(gradient) {
            return Some((trial, e));
        }
    }
    let mut t = 1.0;
    for _ in 0..40 {
        let trial = at(t);
        let e = objective.energy(&trial);
        if e <= energy + 1e-4 * t * slope {
            return Some((trial, e));
        }
        t *= 0.5;
    }
    None
}

/// The lower-triangular scalar pattern of a [`BlockSystem`] and its symbolic factorization
/// (which keeps the pattern: matrices are given by their values in its storage order).
struct BlockPattern {
    /// For each block column: the edges whose lower block sits in it, sorted by row block.
    column_edges: Vec<Vec<u32>>,
    analysis: CholeskyPattern,
}

impl BlockPattern {
    fn new<const B: usize>(system: &BlockSystem<B>) -> Result<Self> {
        let n = system.blocks();
        let mut column_edges: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (e, &[_, lo]) in system.edge_blocks.iter().enumerate() {
            column_edges[lo as usize].push(e as u32);
        }
        for list in &mut column_edges {
            list.sort_unstable_by_key(|&e| system.edge_blocks[e as usize][0]);
        }
        let mut col_ptr = Vec::with_capacity(B * n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for j in 0..n {
            for c in 0..B {
                row_idx.extend((c..B).map(|r| B * j + r));
                for &e in &column_edges[j] {
                    let hi = system.edge_blocks[e as usize][0] as usize;
                    row_idx.extend((0..B).map(|r| B * hi + r));
                }
                col_ptr.push(row_idx.len());
            }
        }
        let symbolic = SymbolicSparseColMat::new_checked(B * n, B * n, col_ptr, None, row_idx);
        let order = block_order::<B>(system);
        let analysis = CholeskyPattern::with_fill_order(symbolic.as_ref(), Some(order))?;
        Ok(BlockPattern { column_edges, analysis })
    }

    /// `scale · A`, with the rows and columns of locked blocks replaced by the identity, as the
    /// values of the analysed pattern written into `values` (whose storage is reused).
    fn matrix_values<const B: usize>(
        &self,
        system: &BlockSystem<B>,
        locked: &[bool],
        scale: f64,
        values: &mut Vec<f64>,
    ) {
        let n = system.blocks();
        values.clear();
        for j in 0..n {
            for c in 0..B {
                for r in c..B {
                    let v = if locked[j] {
                        if r == c {
                            1.0
                        } else {
                            0.0
                        }
                    } else {
                        scale * system.diag[j][r][c]
                    };
                    values.push(v);
                }
                for &e in &self.column_edges[j] {
                    let hi = system.edge_blocks[e as usize][0] as usize;
                    let o = &system.off[e as usize];
                    for r in 0..B {
                        values.push(if locked[j] || locked[hi] { 0.0 } else { scale * o[r][c] });
                    }
                }
            }
        }
    }

    /// Overwrites the diagonal blocks of the free blocks in `values` (from
    /// [`Self::matrix_values`]; locked blocks keep their identity) with `terms`.
    fn set_diagonal_blocks<const B: usize>(
        &self,
        system: &BlockSystem<B>,
        locked: &[bool],
        terms: &DiagonalTerms<'_, B>,
        values: &mut [f64],
    ) {
        let col_ptr = self.analysis.lower().col_ptr();
        for j in (0..system.blocks()).filter(|&j| !locked[j]) {
            for c in 0..B {
                // Each column of the block starts with the diagonal block's rows c..B.
                let start = col_ptr[B * j + c];
                for r in c..B {
                    let identity = if r == c { terms.shift } else { 0.0 };
                    values[start + r - c] = terms.scale * system.diag[j][r][c] + terms.blocks[j][r][c] + identity;
                }
            }
        }
    }
}

/// The diagonal blocks of a Newton matrix: `scale · A_vv + blocks[v] + shift · I`.
struct DiagonalTerms<'a, const B: usize> {
    scale: f64,
    blocks: &'a [Block<B>],
    shift: f64,
}

/// Elimination order: nested dissection of the vertex graph by multilevel bisection at every
/// level ([`ordering::Options::thorough`]: the factorization is repeated every Newton step, and
/// plane splits doubled its flops on the 207k-face disk), each vertex's B unknowns kept
/// together.
fn block_order<const B: usize>(system: &BlockSystem<B>) -> Vec<usize> {
    let n = system.blocks();
    let mut degree = vec![0usize; n + 1];
    for &[hi, lo] in &system.edge_blocks {
        degree[hi as usize + 1] += 1;
        degree[lo as usize + 1] += 1;
    }
    for i in 0..n {
        degree[i + 1] += degree[i];
    }
    let start = degree;
    let mut fill = start.clone();
    let mut neighbors = vec![0u32; start[n]];
    for &[hi, lo] in &system.edge_blocks {
        neighbors[fill[hi as usize]] = lo;
        fill[hi as usize] += 1;
        neighbors[fill[lo as usize]] = hi;
        fill[lo as usize] += 1;
    }
    let adjacency = ordering::Adjacency { start, neighbors };
    let order = ordering::nested_dissection_with(&adjacency, None, &ordering::Options::thorough());
    order.into_iter().flat_map(|b| (0..B).map(move |r| B * b + r)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of triangles with a simple quadratic energy: Σ_edges |x_a − x_b|² + a pull
    /// towards (2, 0) at every vertex, B = 2 (one penalty pair).
    fn strip() -> (TriMesh, EdgeList) {
        let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 2.0, 0.5, 0.0];
        let mesh = TriMesh::new(&positions, &[0, 1, 3, 0, 3, 2, 1, 4, 3]).unwrap();
        let edges = EdgeList::new(&mesh);
        (mesh, edges)
    }

    fn pull_system(mesh: &TriMesh, edges: &EdgeList, target: [f64; 2]) -> BlockSystem<2> {
        let mut s = BlockSystem::<2>::new(mesh, edges);
        let id = [[1.0, 0.0], [0.0, 1.0]];
        let minus = [[-1.0, 0.0], [0.0, -1.0]];
        for (e, &[a, b]) in edges.edges.iter().enumerate() {
            s.add_diagonal(a, &id);
            s.add_diagonal(b, &id);
            s.add_pair(e as u32, a, b, &minus);
        }
        for v in 0..mesh.vertex_count() as u32 {
            s.add_diagonal(v, &id);
            s.rhs[v as usize] = target;
            s.constant += target[0] * target[0] + target[1] * target[1];
        }
        s
    }

    #[test]
    fn the_linear_phase_minimizes_the_quadratic_energy() {
        let (mesh, edges) = strip();
        let s = pull_system(&mesh, &edges, [2.0, 0.0]);
        let options = NewtonOptions { epsilon: 0.0, ..Default::default() };
        let (x, report) = minimize(&s, &[], &options, &mut Progress::none(), (0.0, 1.0)).unwrap();
        // The minimizer of Σ|x_a − x_b|² + Σ|x_v − t|² is x_v = t everywhere, energy 0.
        for xv in &x {
            assert!((xv[0] - 2.0).abs() < 1e-12 && xv[1].abs() < 1e-12, "{xv:?}");
        }
        // F* is evaluated as c + xᵀAx − 2bᵀx, so "0" holds up to the rounding of the constant c
        // (the exact 0 this test once saw depended on the factorization's ordering).
        assert!(report.final_energy.abs() < 1e-12 * s.constant, "{} (c = {})", report.final_energy, s.constant);
    }

    #[test]
    fn newton_reaches_the_penalized_minimum_with_a_locked_block() {
        let (mesh, edges) = strip();
        let s = pull_system(&mesh, &edges, [2.0, 0.0]);
        let options = NewtonOptions { epsilon: 0.5, gradient_tolerance: 1e-10, max_iterations: 50 };
        let locked = [(0u32, [0.0, 1.0])];
        let (x, report) = minimize(&s, &locked, &options, &mut Progress::none(), (0.0, 1.0)).unwrap();
        assert!(report.converged, "{report:?}");
        assert_eq!(x[0], [0.0, 1.0]);
        // Stationarity checked independently by central differences of F**.
        let objective = Objective { system: &s, epsilon: 0.5, locked: &[true, false, false, false, false] };
        for v in 1..5 {
            for r in 0..2 {
                let h = 1e-6;
                let mut xp = x.clone();
                xp[v][r] += h;
                let mut xm = x.clone();
                xm[v][r] -= h;
                let d = (objective.energy(&xp) - objective.energy(&xm)) / (2.0 * h);
                assert!(d.abs() < 1e-6, "vertex {v} component {r}: dF = {d}");
            }
        }
        assert!(report.final_energy <= report.initial_energy);
    }

    #[test]
    fn newton_converges_where_the_energy_cannot_resolve_its_last_steps() {
        // A constant of 10¹⁴ puts the rounding of F** near 0.016: every Newton step from
        // ‖∇F**‖ ≈ 2 changes it by less, so only the gradient can tell whether it helps
        // (energies alone stalled at ‖∇F**‖ = 0.046 after 23 iterations).
        let (mesh, edges) = strip();
        let mut s = pull_system(&mesh, &edges, [2.0, 0.0]);
        s.constant += 1e14;
        let options = NewtonOptions { epsilon: 0.5, gradient_tolerance: 1e-10, max_iterations: 50 };
        let locked = [(0u32, [0.0, 1.0])];
        let (_, report) = minimize(&s, &locked, &options, &mut Progress::none(), (0.0, 1.0)).unwrap();
        assert!(report.converged, "{report:?}");
        assert!(report.iterations < 20, "{report:?}");
    }

    #[test]
    fn newton_matrix_values_are_the_shifted_hessian_in_pattern_order() {
        // Reference: column k of 2A is 2·A e_k (from `apply`), plus the penalty's block and the
        // shift on the diagonal blocks; locked rows and columns are the identity's.
        let (mesh, edges) = strip();
        let mut s = pull_system(&mesh, &edges, [2.0, 0.0]);
        s.off[1] = [[-1.0, 0.25], [-0.5, -1.0]]; // not symmetric per block, to catch transposes
        let locked = [false, true, false, false, false];
        let objective = Objective { system: &s, epsilon: 0.3, locked: &locked };
        let x: Vec<[f64; 2]> = (0..5).map(|v| [0.2 * v as f64 - 0.3, 0.1 + 0.15 * v as f64]).collect();
        let penalty = objective.penalty_hessian(&x);
        let shift = 0.07;
        let pattern = BlockPattern::new(&s).unwrap();
        let mut values = Vec::new();
        pattern.matrix_values(&s, &locked, 2.0, &mut values);
        let terms = DiagonalTerms { scale: 2.0, blocks: &penalty, shift };
        pattern.set_diagonal_blocks(&s, &locked, &terms, &mut values);
        let lower = pattern.analysis.lower();
        let mut checked = 0;
        for k in 0..10 {
            let mut unit = vec![[0.0; 2]; 5];
            unit[k / 2][k % 2] = 1.0;
            let column = s.apply(&unit);
            let range = lower.col_ptr()[k]..lower.col_ptr()[k + 1];
            for (&i, &value) in lower.row_idx()[range.clone()].iter().zip(&values[range]) {
                let (v, w) = (i / 2, k / 2);
                let expected = if locked[v] || locked[w] {
                    (i == k) as u8 as f64
                } else {
                    let diagonal = if v == w { penalty[v][i % 2][k % 2] + shift * (i == k) as u8 as f64 } else { 0.0 };
                    2.0 * column[v][i % 2] + diagonal
                };
                assert!((value - expected).abs() < 1e-14, "entry ({i}, {k}): {value} vs {expected}");
                checked += 1;
            }
        }
        assert_eq!(checked, 3 * 5 + 4 * 7, "diagonal blocks' lower halves and the 7 edges' blocks");
    }

    #[test]
    fn cancelling_stops_the_solve() {
        let (mesh, edges) = strip();
        let s = pull_system(&mesh, &edges, [2.0, 0.0]);
        let mut stop = |_: f64| false;
        let r = minimize(&s, &[], &NewtonOptions::default(), &mut Progress::new(&mut stop), (0.0, 1.0));
        assert_eq!(r.err(), Some(Error::Cancelled));
    }
}
