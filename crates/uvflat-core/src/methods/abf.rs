//! Angle Based Flattening: ABF (Sheffer & de Sturler 2001) and ABF++ (Sheffer, Lévy,
//! Mogilnitsky & Bogomyakov 2005, "ABF++: fast and robust angle based flattening", ACM TOG 24(2));
//! course notes (Hormann, Lévy, Sheffer 2008) §4.5 "Angle-Space Methods".
//!
//! The unknowns are the 3F planar corner angles α (radians, corner `k` of triangle `t` is
//! `α[3t + k]`, at vertex `triangles[t][k]`). They minimise
//!
//! ```text
//! E(α) = Σ_c w_c (α_c − β_c)²  +  μ Σ_c (α_c/β_c − ln(α_c/β_c) − 1)
//! ```
//!
//! where β are the optimal angles: the 3D corner angles, scaled around every interior vertex by
//! 2π / (their sum) so that they could close up in the plane (ABF §3; this is the adjustment of
//! interior vertices whose 3D angle sum differs from 2π, saddles with sum > 2π included;
//! boundary vertices keep their 3D angles; Blender's and geogram's ABF scale the same way, and
//! additionally clamp the angles, to [1°, 179°] before scaling and [3°, 175°] after it).
//!
//! The first sum is the papers' objective. Its default weights here are
//! `w = 1/(β (π − β))` ([`AbfWeights::AngleAndSupplement`]) instead of the papers' β⁻²
//! ([`AbfWeights::InverseSquare`]): β⁻² weighs relative errors of small angles only, so the
//! large angles of slivers (up to 178.6° on disk_cylinder_locally_refined) move freely and the
//! mean angle error there ends above the natural conformal map's (0.022° vs 0.019°); with the
//! inverse weights of the angle and of its supplement it is 0.017°, and lower than with β⁻²
//! on every non-flat disk mesh of the shared collection. (The scaling at interior vertices
//! can push an optimal angle to within 10⁻⁶ rad of π — 6 corners of that mesh, whose 3D
//! angles are at most 178.6° — so π − β is floored at 10⁻³ rad; without the floor those
//! corners are held almost fixed and the same mesh gives 0.013° in 8 iterations instead of
//! 4.)
//!
//! The second sum is a barrier (`AbfOptions::barrier` = μ, default 1; 0 gives the papers'
//! objective): the Burg (Itakura–Saito) divergence of α from β, zero with zero gradient at
//! α = β, curvature μ/β² there, and infinite as α → 0. It makes the problem well-posed: the
//! papers' objective stays bounded as an angle goes to 0 (at most w β² per corner), while at a
//! triangle with angles (0, 0, π) all sines of its corners vanish, so the reconstruction
//! constraints of its three vertices hold trivially (0 = 0). On disk_mannequin_devil (folded
//! regions, interior vertices with 3D angle sums up to 2× 2π) the papers' problem is driven
//! there: an ordinary triangle (14356) goes to (0, 0, π) while λ_L grows without bound, and
//! the iteration never converges. With the barrier, since the feasible set contains angles
//! in (0, π) (any planar embedding, e.g. Tutte's), a minimiser has every angle in (0, π)
//! (α < π follows from the triangle constraint). The reported ‖∇L‖ is that of this E,
//! barrier included. With the papers' weights, adding the barrier changed the mean angle
//! error by +0.048° on disk_cat_head (248 faces), +0.013° on disk_three_peaks and at most
//! 0.002° on the other disk meshes.
//!
//! The constraints (course notes §4.5) are
//!
//! - triangle: `α_t1 + α_t2 + α_t3 − π = 0` for every triangle;
//! - planarity: `Σ_{c ∈ v*} α_c − 2π = 0` for every interior vertex v;
//! - reconstruction (sine law around the wheel of v): `Π sin α_{c⊕1} − Π sin α_{c⊖1} = 0` for
//!   every interior vertex v, c running over the corners at v and c⊕1 / c⊖1 being the next /
//!   previous corner of the same triangle.
//!
//! Both variants find a stationary point of the Lagrangian
//! `L = E + λ_T·C_T + λ_P·C_P + λ_L·C_L` by Newton-type steps on ∇L = 0, starting from λ = 0
//! and α = β scaled triangle by triangle to sum to π (the papers start from α = β; starting on
//! the triangle constraints saved 1–2 iterations on 7 of the 18 disk meshes, and cost none), and
//! stop when ‖∇L‖₂ ≤ `tolerance` (all components: ∂L/∂α and the constraint values) or after
//! `max_iterations` steps.
//!
//! - **ABF** (Sheffer & de Sturler 2001, §4): full Newton. The Hessian in α is
//!   `Λ + Σ_v λ_L,v ∇²C_L,v` (Λ = ∇²E = diag(2w + μ/α²)); each step solves the whole symmetric
//!   indefinite KKT system of size 3F + F + 2·n_int by sparse LU.
//! - **ABF++** (Sheffer et al. 2005, §3, eqs. 5–9): Gauss–Newton. Dropping the constraints'
//!   second derivatives leaves the diagonal Λ, so with `J = [J1; J2]` (J1 the triangle rows,
//!   J2 the 2·n_int planarity and reconstruction rows) the step
//!   `[Λ Jᵀ; J 0] [δα; δλ] = −∇L` reduces by eliminating δα (Λ is diagonal) and then δλ_T
//!   (`J1 Λ⁻¹ J1ᵀ` is diagonal, one entry per triangle) to
//!   `J2 M J2ᵀ δλ_2 = r`, with `M = Λ⁻¹ − Λ⁻¹ J1ᵀ (J1 Λ⁻¹ J1ᵀ)⁻¹ J1 Λ⁻¹` block diagonal (one
//!   3×3 block per triangle). This ~2·n_int system is symmetric positive definite for a disk and
//!   is solved by sparse Cholesky; its pattern (the 1-rings, 2×2 blocks) is analysed once and
//!   refactored each iteration. δλ_T and δα then follow triangle by triangle.
//!
//!   Gauss–Newton converges only linearly: the dropped term `Σ_v λ_L,v ∇²C_L,v` is not small
//!   where the multipliers are large (strongly curved meshes: λ_L reaches 1e2–1e8 on the
//!   collection), and the paper's iteration needed 11–13 steps to ‖∇L‖ ≤ 1e-6 on three of its
//!   meshes, with a rate of about 0.2 per step. So each iteration here also computes the Newton
//!   step of ABF (the exact KKT matrix `[H Jᵀ; J 0]`, H including the sine-law second
//!   derivatives, applied matrix-free in O(F)) by GMRES right-preconditioned with the same
//!   Gauss–Newton factorization — an inexact Newton method (Dembo, Eisenstat & Steihaug 1982;
//!   forcing term min(0.1, ‖∇L‖)), costing only triangular solves with the factor already
//!   computed — and keeps whichever of the two trial points has the smaller ‖∇L‖. At λ = 0
//!   (the first step) both coincide. `newton_krylov_steps = 0` gives the plain Gauss–Newton
//!   iteration of the paper.
//!
//!   Both steps, and ABF's Newton step, are scaled by a fraction to the boundary (no angle
//!   moves more than half way to 0 or π), so every iterate keeps its angles in (0, π). (ABF's
//!   full steps, taken whole, diverged on `closed_g0_cow` cut to a disk — ‖∇L‖ infinite after 18
//!   steps — and on `disk_bimba_cut` ended, after 8.5 minutes, in angles whose reconstruction
//!   could not be factored; scaled, they converge in 9 and 6 steps, 4.4 and 139 s.)
//!
//! Angle to uv (ABF++ §5): the uv map minimises Σ_t of the conformal energy of the map from the
//! planar triangle with angles α_t to its uv triangle. Per triangle that energy is
//! `¼ Σ_k cot α_k |u_i − u_j|² − A_t(u)` (zero exactly when the uv triangle is similar to the
//! one with angles α_t, the sine-law ratios and the angle between the edges), so the global
//! system is the natural conformal map's ([`crate::methods::conformal`]) with the cotangents of
//! α in place of the 3D ones: one sparse Cholesky solve with two pinned vertices (by default
//! the farthest boundary pair). When the angle constraints hold and every α_c ∈ (0, π), the
//! reconstruction is exact and no triangle is flipped (ABF++ §5); on a disk with holes the
//! hole loops are not constrained to close and the solve is a least-squares compromise.
//!
//! Cost per ABF++ iteration: O(F) to evaluate ∇L and assemble, plus one numeric Cholesky
//! factorization of the 2·n_int system (nested-dissection order computed once), plus at most
//! `newton_krylov_steps` pairs of triangular solves with that factor and O(F) products. ABF's full LU
//! of the 5F-sized system is several times slower; it is kept for comparison.

use crate::error::{Error, Result};
use crate::mesh::{TriMesh, NONE};
use crate::methods::angle_layout::{reconstruct_uv, triangle_shapes};
use crate::methods::conformal::{resolve_pins, Pin};
use crate::progress::Progress;
use faer::sparse::SparseColMat;
use faer::Mat;
use std::f64::consts::PI;
use uvflat_sparse::gmres::preconditioned_gmres;
use uvflat_sparse::ordering::{nested_dissection, Adjacency};
use uvflat_sparse::{lower_from_entries, require_finite, CholeskyPattern, LuSolver, TripletBuilder};

/// Which Newton-type iteration solves the angle problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AbfVariant {
    /// Sheffer & de Sturler 2001: full Newton steps on the whole KKT system (sparse LU).
    Abf,
    /// Sheffer et al. 2005: Gauss–Newton steps through the reduced ~2·n_int Cholesky system.
    AbfPlusPlus,
}

/// Weights w_c of the angle objective `Σ w_c (α_c − β_c)²`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AbfWeights {
    /// w = β⁻² (Sheffer & de Sturler 2001; Sheffer et al. 2005): the relative angle error. It
    /// lets the large angles of slivers move freely (a 178.6° angle has w ≈ 0.1, its 0.5°
    /// neighbour w ≈ 1.3·10⁴).
    InverseSquare,
    /// w = β⁻¹: between relative and absolute error.
    Inverse,
    /// w = 1/(β (π − β)) = (1/β + 1/(π − β))/π (default): the inverse weights of the angle and
    /// of its supplement π − β, so an angle near π is held as firmly as one near 0 (the
    /// supplement of a sliver's 178.6° angle is as small as its other angles). π − β is taken
    /// at least 10⁻³ rad (an interior vertex with a small 3D angle sum can scale an angle to π
    /// or beyond).
    AngleAndSupplement,
}

/// Smallest π − β used by [`AbfWeights::AngleAndSupplement`] (radians, 0.057°).
const MIN_SUPPLEMENT: f64 = 1e-3;

/// Options of [`abf`].
#[derive(Debug, Clone, Copy)]
pub struct AbfOptions {
    /// ABF or ABF++ (default).
    pub variant: AbfVariant,
    /// Most Newton / Gauss–Newton steps (default 20).
    pub max_iterations: u32,
    /// Stop when ‖∇L‖₂ ≤ tolerance (default 1e-6).
    pub tolerance: f64,
    /// Pinned vertices of the reconstruction; `None` pins the farthest boundary pair at (0, 0)
    /// and (d, 0), d their 3D distance.
    pub pins: Option<[Pin; 2]>,
    /// Weights of the angle objective (default: the paper's β⁻²).
    pub weights: AbfWeights,
    /// ABF++ only: most GMRES steps of the Newton correction per iteration, preconditioned by
    /// the iteration's Gauss–Newton factorization (default 20); 0 gives the paper's plain
    /// Gauss–Newton iteration.
    pub newton_krylov_steps: u32,
    /// μ ≥ 0 of the angle barrier `μ Σ_c (α_c/β_c − ln(α_c/β_c) − 1)` added to the objective
    /// (default 1); 0 gives the papers' objective, which has no minimiser with all angles in
    /// (0, π) on some meshes (see the module comment).
    pub barrier: f64,
}

impl Default for AbfOptions {
    fn default() -> Self {
        AbfOptions {
            variant: AbfVariant::AbfPlusPlus,
            max_iterations: 20,
            tolerance: 1e-6,
            pins: None,
            weights: AbfWeights::AngleAndSupplement,
            newton_krylov_steps: 20,
            barrier: 1.0,
        }
    }
}

/// How the angle optimisation went.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AbfReport {
    /// Newton / Gauss–Newton steps taken.
    pub iterations: u32,
    /// ‖∇L‖₂ at the returned angles (L with the objective actually minimised, barrier included).
    pub gradient_norm: f64,
    /// Whether `gradient_norm ≤ tolerance`.
    pub converged: bool,
    /// Corners whose angle left (0, π) (such triangles flip in the reconstruction).
    pub invalid_angles: usize,
}

/// The planar angles found by the optimisation and the report.
#[derive(Debug, Clone)]
pub struct AngleSolution {
    /// `angles[t][k]`: planar angle at corner `k` of triangle `t` (radians).
    pub angles: Vec<[f64; 3]>,
    /// Iterations, final gradient norm.
    pub report: AbfReport,
}

/// ABF / ABF++ result: one uv per vertex (NaN for unreferenced vertices) and the report.
#[derive(Debug, Clone)]
pub struct AbfResult {
    pub uv: Vec<[f64; 2]>,
    pub report: AbfReport,
}

/// ABF or ABF++ parameterization of a disk (possibly with holes).
pub fn abf(mesh: &TriMesh, options: &AbfOptions) -> Result<AbfResult> {
    abf_with_progress(mesh, options, &mut Progress::none())
}

/// [`abf`] with progress reporting (once per iteration) and cancellation.
pub fn abf_with_progress(mesh: &TriMesh, options: &AbfOptions, progress: &mut Progress) -> Result<AbfResult> {
    let pins = resolve_pins(mesh, options.pins)?;
    let solution = optimize_angles(mesh, options, progress)?;
    let angles = if solution.report.converged { solution.angles } else { triangle_shapes(&solution.angles) };
    let uv = reconstruct_uv(mesh, &angles, pins)?;
    progress.report(1.0)?;
    Ok(AbfResult { uv, report: solution.report })
}

/// The angle optimisation alone (ABF §3–4 or ABF++ §3): planar angles and the report.
pub fn optimize_angles(mesh: &TriMesh, options: &AbfOptions, progress: &mut Progress) -> Result<AngleSolution> {
    mesh.require_disk_with_holes()?;
    if !(options.tolerance.is_finite() && options.tolerance >= 0.0) {
        return Err(Error::InvalidArgument(format!(
            "ABF tolerance must be finite and non-negative (got {})",
            options.tolerance
        )));
    }
    if !(options.barrier.is_finite() && options.barrier >= 0.0) {
        return Err(Error::InvalidArgument(format!(
            "ABF barrier must be finite and non-negative (got {})",
            options.barrier
        )));
    }
    // The paper's product-form reconstruction constraint and Gauss–Newton Λ = 2w (plus the
    // barrier's curvature). (The log form and the diagonal constraint Hessian were measured as
    // alternatives: no fewer iterations on the collection, and the log form breaks down when a
    // step makes a sine negative.)
    let problem = AngleProblem::new(mesh, options.weights, options.barrier, false, false)?;
    let mut state = State {
        alpha: triangle_scaled(&problem.beta),
        lambda_tri: vec![0.0; problem.tris.len()],
        lambda2: vec![0.0; 2 * problem.n_int],
    };
    let mut reduced = match options.variant {
        AbfVariant::AbfPlusPlus => Some(ReducedSystem::new(&problem, mesh)?),
        AbfVariant::Abf => None,
    };
    let stars = problem.stars();
    let inner = options.newton_krylov_steps as usize;
    let total = options.max_iterations as f64 + 1.0;
    let mut iterations = 0;
    let mut lin = problem.linearize(&state);
    loop {
        if !lin.norm.is_finite() {
            return Err(Error::Numerical(format!(
                "ABF diverged: the gradient norm is {} after {iterations} iterations",
                lin.norm
            )));
        }
        if lin.norm <= options.tolerance || iterations >= options.max_iterations {
            break;
        }
        match reduced.as_mut() {
            Some(system) => {
                (state, lin) = plus_plus_step(&problem, system, &stars, &lin, &state, inner)?;
            }
            None => {
                problem.newton_step(&lin, &mut state)?;
                lin = problem.linearize(&state);
            }
        }
        iterations += 1;
        progress.report(0.9 * iterations as f64 / total)?;
    }
    let invalid_angles = state.alpha.iter().filter(|&&a| !(a > 0.0 && a < PI)).count();
    let angles = state.alpha.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let report =
        AbfReport { iterations, gradient_norm: lin.norm, converged: lin.norm <= options.tolerance, invalid_angles };
    Ok(AngleSolution { angles, report })
}

/// The optimal angles, weights and constraint layout of one mesh.
struct AngleProblem<'a> {
    tris: &'a [[u32; 3]],
    /// Row pair index of each interior vertex (planarity row 2i, reconstruction row 2i + 1),
    /// `NONE` for boundary and unreferenced vertices.
    interior: Vec<u32>,
    /// Number of interior vertices.
    n_int: usize,
    /// Optimal angles β, one per corner.
    beta: Vec<f64>,
    /// The objective's weights w (see [`AbfWeights`]).
    weight: Vec<f64>,
    /// μ of the angle barrier.
    barrier: f64,
    /// Reconstruction constraint as Σ ln sin α_next − Σ ln sin α_prev instead of the products.
    log_form: bool,
    /// Keep the diagonal of the constraints' second derivatives in the step's Hessian.
    diag_hessian: bool,
}

/// Current angles and multipliers.
struct State {
    alpha: Vec<f64>,
    lambda_tri: Vec<f64>,
    /// Interleaved planarity / reconstruction multipliers of the interior vertices.
    lambda2: Vec<f64>,
}

/// ∇L and the quantities the steps need, at one state.
struct Linearization {
    /// sin α and cot α per corner.
    sin: Vec<f64>,
    cot: Vec<f64>,
    /// Π sin α_{c⊕1} and Π sin α_{c⊖1} over the corners c at each interior vertex.
    p_next: Vec<f64>,
    p_prev: Vec<f64>,
    /// ∂L/∂α.
    grad_alpha: Vec<f64>,
    /// Triangle constraint values.
    c_tri: Vec<f64>,
    /// Planarity / reconstruction constraint values (interleaved).
    c2: Vec<f64>,
    /// ‖∇L‖₂.
    norm: f64,
}

impl<'a> AngleProblem<'a> {
    fn new(mesh: &'a TriMesh, weights: AbfWeights, barrier: f64, log_form: bool, diag_hessian: bool) -> Result<Self> {
        let tris = mesh.triangles();
        let mut interior = vec![NONE; mesh.vertex_count()];
        let mut n_int = 0usize;
        for v in 0..mesh.vertex_count() as u32 {
            if mesh.is_referenced(v) && !mesh.is_boundary_vertex(v) {
                interior[v as usize] = n_int as u32;
                n_int += 1;
            }
        }
        let theta: Vec<f64> = mesh.corner_angles().iter().flatten().copied().collect();
        let mut sum = vec![0.0; mesh.vertex_count()];
        for (c, &a) in theta.iter().enumerate() {
            sum[tris[c / 3][c % 3] as usize] += a;
        }
        let beta: Vec<f64> = theta
            .iter()
            .enumerate()
            .map(|(c, &a)| {
                let v = tris[c / 3][c % 3] as usize;
                if interior[v] != NONE {
                    a * 2.0 * PI / sum[v]
                } else {
                    a
                }
            })
            .collect();
        let weight: Vec<f64> = beta.iter().map(|&b| objective_weight(weights, b)).collect();
        require_finite(weight.iter().copied(), "ABF weight")?;
        Ok(AngleProblem { tris, interior, n_int, beta, weight, barrier, log_form, diag_hessian })
    }

    /// ∂E/∂α_c: `2 w (α − β) + μ (1/β − 1/α)`.
    #[inline]
    fn objective_gradient(&self, c: usize, alpha: f64) -> f64 {
        let b = self.beta[c];
        let mut g = 2.0 * self.weight[c] * (alpha - b);
        if self.barrier != 0.0 {
            g += self.barrier * (1.0 / b - 1.0 / alpha);
        }
        g
    }

    /// ∂²E/∂α_c²: `2 w + μ/α²` (E is separable, so this is its whole Hessian).
    #[inline]
    fn objective_curvature(&self, c: usize, alpha: f64) -> f64 {
        2.0 * self.weight[c] + self.barrier / (alpha * alpha)
    }

    /// Row of the planarity (`which = 0`) or reconstruction (`1`) constraint of vertex `v`, or
    /// `NONE` for a boundary vertex.
    #[inline]
    fn row(&self, v: u32, which: u32) -> u32 {
        let i = self.interior[v as usize];
        if i == NONE {
            NONE
        } else {
            2 * i + which
        }
    }

    /// The (at most three) nonzero entries of column `c` of J2: the planarity row of c's vertex
    /// and the reconstruction rows of the two other vertices of its triangle.
    #[inline]
    fn j2_column(&self, lin: &Linearization, c: usize) -> [(u32, f64); 3] {
        let (t, k) = (c / 3, c % 3);
        let tri = self.tris[t];
        let own = self.row(tri[k], 0);
        // c is the "next" corner of the vertex before it and the "previous" of the one after.
        let before = tri[(k + 2) % 3];
        let after = tri[(k + 1) % 3];
        let rb = self.row(before, 1);
        let ra = self.row(after, 1);
        let nb = if rb == NONE { 0.0 } else { lin.p_next[(rb / 2) as usize] * lin.cot[c] };
        let na = if ra == NONE { 0.0 } else { -lin.p_prev[(ra / 2) as usize] * lin.cot[c] };
        [(own, 1.0), (rb, nb), (ra, na)]
    }

    fn linearize(&self, s: &State) -> Linearization {
        let m3 = s.alpha.len();
        let sin: Vec<f64> = s.alpha.iter().map(|a| a.sin()).collect();
        let cot: Vec<f64> = s.alpha.iter().zip(&sin).map(|(a, si)| a.cos() / si).collect();
        let (mut p_next, mut p_prev) = (vec![1.0; self.n_int], vec![1.0; self.n_int]);
        let mut c2 = vec![0.0; 2 * self.n_int];
        for (t, tri) in self.tris.iter().enumerate() {
            for k in 0..3 {
                let i = self.interior[tri[k] as usize];
                if i != NONE {
                    p_next[i as usize] *= sin[3 * t + (k + 1) % 3];
                    p_prev[i as usize] *= sin[3 * t + (k + 2) % 3];
                    c2[2 * i as usize] += s.alpha[3 * t + k];
                }
            }
        }
        for i in 0..self.n_int {
            c2[2 * i] -= 2.0 * PI;
            c2[2 * i + 1] = if self.log_form { p_next[i].ln() - p_prev[i].ln() } else { p_next[i] - p_prev[i] };
        }
        if self.log_form {
            p_next.fill(1.0);
            p_prev.fill(1.0);
        }
        let c_tri: Vec<f64> = s.alpha.chunks_exact(3).map(|a| a[0] + a[1] + a[2] - PI).collect();
        let mut lin = Linearization { sin, cot, p_next, p_prev, grad_alpha: Vec::new(), c_tri, c2, norm: 0.0 };
        let grad_alpha: Vec<f64> = (0..m3)
            .map(|c| {
                let mut g = self.objective_gradient(c, s.alpha[c]) + s.lambda_tri[c / 3];
                for (r, coef) in self.j2_column(&lin, c) {
                    if r != NONE {
                        g += s.lambda2[r as usize] * coef;
                    }
                }
                g
            })
            .collect();
        let sq = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
        lin.norm = (sq(&grad_alpha) + sq(&lin.c_tri) + sq(&lin.c2)).sqrt();
        lin.grad_alpha = grad_alpha;
        lin
    }

    /// Diagonal of the α-Hessian used by the reduced step: Λ = ∇²E = 2w + μ/α², plus (with
    /// `diag_hessian`) the diagonal second derivatives of the reconstruction constraints times
    /// their multipliers, kept at least half of ∇²E.
    fn step_diagonal(&self, lin: &Linearization, s: &State) -> Vec<f64> {
        (0..s.alpha.len())
            .map(|c| {
                let base = self.objective_curvature(c, s.alpha[c]);
                if !self.diag_hessian {
                    return base;
                }
                let (t, k) = (c / 3, c % 3);
                let tri = self.tris[t];
                let (rb, ra) = (self.row(tri[(k + 2) % 3], 1), self.row(tri[(k + 1) % 3], 1));
                let mut h = base;
                if rb != NONE {
                    let second =
                        if self.log_form { -1.0 / (lin.sin[c] * lin.sin[c]) } else { -lin.p_next[(rb / 2) as usize] };
                    h += s.lambda2[rb as usize] * second;
                }
                if ra != NONE {
                    let second =
                        if self.log_form { 1.0 / (lin.sin[c] * lin.sin[c]) } else { lin.p_prev[(ra / 2) as usize] };
                    h += s.lambda2[ra as usize] * second;
                }
                h.max(0.5 * base)
            })
            .collect()
    }

    /// Corners at each interior vertex (CSR by interior index), for the reconstruction Hessian.
    fn stars(&self) -> (Vec<usize>, Vec<u32>) {
        let mut start = vec![0usize; self.n_int + 1];
        for tri in self.tris {
            for &v in tri {
                let i = self.interior[v as usize];
                if i != NONE {
                    start[i as usize + 1] += 1;
                }
            }
        }
        for i in 0..self.n_int {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut corners = vec![0u32; start[self.n_int]];
        for (t, tri) in self.tris.iter().enumerate() {
            for (k, &v) in tri.iter().enumerate() {
                let i = self.interior[v as usize];
                if i != NONE {
                    corners[fill[i as usize]] = (3 * t + k) as u32;
                    fill[i as usize] += 1;
                }
            }
        }
        (start, corners)
    }

    /// ABF (Sheffer & de Sturler 2001): one full Newton step on ∇L = 0, the KKT system
    /// `[H Jᵀ; J 0]` with `H = ∇²E + Σ_v λ_L,v ∇²C_L,v` assembled whole and solved by sparse LU.
    fn newton_step(&self, lin: &Linearization, s: &mut State) -> Result<()> {
        let m3 = s.alpha.len();
        let f = self.tris.len();
        let n2 = 2 * self.n_int;
        let size = m3 + f + n2;
        let mut kkt = TripletBuilder::<f64>::with_capacity(size, 3 * m3 + 6 * m3 + 12 * m3);
        for c in 0..m3 {
            kkt.add(c, c, self.objective_curvature(c, s.alpha[c]));
            kkt.add(c, m3 + c / 3, 1.0);
            kkt.add(m3 + c / 3, c, 1.0);
            for (r, coef) in self.j2_column(lin, c) {
                if r != NONE {
                    kkt.add(c, m3 + f + r as usize, coef);
                    kkt.add(m3 + f + r as usize, c, coef);
                }
            }
        }
        // λ_L ∇²(Π sin α_next − Π sin α_prev): for a product P of sines, ∂²P/∂a∂b = P cot a cot b
        // (a ≠ b) and ∂²P/∂a² = −P.
        let (start, corners) = self.stars();
        for i in 0..self.n_int {
            let lambda = s.lambda2[2 * i + 1];
            if lambda == 0.0 {
                continue;
            }
            let star = &corners[start[i]..start[i + 1]];
            for (offset, sign, product) in [(1usize, 1.0, lin.p_next[i]), (2usize, -1.0, lin.p_prev[i])] {
                let scale = lambda * sign * product;
                let others: Vec<usize> =
                    star.iter().map(|&c| 3 * (c as usize / 3) + (c as usize % 3 + offset) % 3).collect();
                for &a in &others {
                    for &b in &others {
                        let value = if a == b { -scale } else { scale * lin.cot[a] * lin.cot[b] };
                        kkt.add(a, b, value);
                    }
                }
            }
        }
        let matrix = kkt.build()?;
        let mut rhs = Mat::<f64>::zeros(size, 1);
        for c in 0..m3 {
            rhs[(c, 0)] = -lin.grad_alpha[c];
        }
        for t in 0..f {
            rhs[(m3 + t, 0)] = -lin.c_tri[t];
        }
        for r in 0..n2 {
            rhs[(m3 + f + r, 0)] = -lin.c2[r];
        }
        LuSolver::new(&matrix)?.solve_in_place(&mut rhs)?;
        let step = rhs.col_as_slice(0);
        require_finite(step.iter().copied(), "ABF Newton")?;
        *s = s.moved(step, fraction_to_boundary(&s.alpha, &step[..m3]));
        Ok(())
    }
}

/// The reduced ABF++ system `J2 M J2ᵀ` over the 2·n_int planarity / reconstruction
/// multipliers: its pattern, the position of every triangle's entries in it, and the symbolic
/// Cholesky analysis, all computed once.
struct ReducedSystem {
    matrix: SparseColMat<usize, f64>,
    /// For each triangle, the value slot of local entry (a, b), a ≥ b, of its 6 local rows
    /// (planarity and reconstruction rows of its three vertices), `usize::MAX` when absent.
    slots: Vec<[usize; 21]>,
    pattern: CholeskyPattern,
}

/// Index of local entry (a, b), a ≥ b, in a packed lower triangle of a 6×6 matrix.
#[inline]
fn packed(a: usize, b: usize) -> usize {
    a * (a + 1) / 2 + b
}

impl ReducedSystem {
    fn new(problem: &AngleProblem, mesh: &TriMesh) -> Result<Self> {
        let n2 = 2 * problem.n_int;
        let local_rows =
            |tri: &[u32; 3]| -> [u32; 6] { std::array::from_fn(|j| problem.row(tri[j / 2], (j % 2) as u32)) };
        let mut entries = Vec::with_capacity(15 * problem.tris.len());
        for tri in problem.tris {
            let rows = local_rows(tri);
            for a in 0..6 {
                for b in 0..a {
                    let (ra, rb) = (rows[a], rows[b]);
                    if ra != NONE && rb != NONE {
                        entries.push((ra.max(rb), ra.min(rb), 0.0));
                    }
                }
            }
        }
        let matrix = lower_from_entries(&vec![0.0; n2], entries)?;
        let (col_ptr, row_idx) = (matrix.symbolic().col_ptr(), matrix.symbolic().row_idx());
        let find = |r: usize, c: usize| -> Result<usize> {
            let column = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            column
                .binary_search(&r)
                .map(|p| col_ptr[c] + p)
                .map_err(|_| Error::Internal(format!("ABF++ pattern lacks entry ({r}, {c})")))
        };
        let mut slots = Vec::with_capacity(problem.tris.len());
        for tri in problem.tris {
            let rows = local_rows(tri);
            let mut s = [usize::MAX; 21];
            for a in 0..6 {
                for b in 0..=a {
                    let (ra, rb) = (rows[a], rows[b]);
                    if ra != NONE && rb != NONE {
                        s[packed(a, b)] = find(ra.max(rb) as usize, ra.min(rb) as usize)?;
                    }
                }
            }
            slots.push(s);
        }
        // Elimination order: nested dissection of the interior vertices' graph, each vertex's
        // two rows (planarity, reconstruction) kept together.
        let mut vertex_entries = Vec::with_capacity(3 * problem.tris.len());
        for tri in problem.tris {
            for a in 0..3 {
                let (i, j) = (problem.interior[tri[a] as usize], problem.interior[tri[(a + 1) % 3] as usize]);
                if i != NONE && j != NONE {
                    vertex_entries.push((i.max(j), i.min(j), 0.0));
                }
            }
        }
        let vertex_graph = lower_from_entries(&vec![0.0; problem.n_int], vertex_entries)?;
        let adjacency =
            Adjacency::from_lower(problem.n_int, vertex_graph.symbolic().col_ptr(), vertex_graph.symbolic().row_idx());
        let mut coords = vec![[0.0; 3]; problem.n_int];
        for v in 0..mesh.vertex_count() {
            let i = problem.interior[v];
            if i != NONE {
                coords[i as usize] = mesh.points()[v];
            }
        }
        let order: Vec<usize> = if problem.n_int == 0 {
            Vec::new()
        } else {
            nested_dissection(&adjacency, &coords).into_iter().flat_map(|i| [2 * i, 2 * i + 1]).collect()
        };
        let pattern = CholeskyPattern::with_order(matrix.symbolic(), Some(order))?;
        Ok(ReducedSystem { matrix, slots, pattern })
    }

    /// Assembles `J2 M J2ᵀ` triangle by triangle at the current linearization and factors it:
    /// the ABF++ Gauss–Newton KKT operator `[Λ Jᵀ; J 0]` (Sheffer et al. 2005, §3, eqs. 5–9),
    /// ready to solve for any right-hand side.
    fn factor(&mut self, p: &AngleProblem, lin: &Linearization, s: &State) -> Result<GaussNewtonFactor> {
        // Λ⁻¹ = diag(d).
        let d: Vec<f64> = p.step_diagonal(lin, s).iter().map(|h| 1.0 / h).collect();
        let j2: Vec<[(u32, f64); 3]> = (0..d.len()).map(|c| p.j2_column(lin, c)).collect();
        self.matrix.val_mut().fill(0.0);
        for (t, tri) in p.tris.iter().enumerate() {
            let dt = [d[3 * t], d[3 * t + 1], d[3 * t + 2]];
            let sum_d = dt[0] + dt[1] + dt[2];
            let jl = local_j2(p, tri, &j2[3 * t..3 * t + 3]);
            // G = J D Jᵀ − (J d)(J d)ᵀ / Σd.
            let jd: [f64; 6] = std::array::from_fn(|j| jl[j][0] * dt[0] + jl[j][1] * dt[1] + jl[j][2] * dt[2]);
            let values = self.matrix.val_mut();
            for a in 0..6 {
                for b in 0..=a {
                    let slot = self.slots[t][packed(a, b)];
                    if slot != usize::MAX {
                        let g = jl[a][0] * dt[0] * jl[b][0] + jl[a][1] * dt[1] * jl[b][1] + jl[a][2] * dt[2] * jl[b][2]
                            - jd[a] * jd[b] / sum_d;
                        values[slot] += g;
                    }
                }
            }
        }
        let cholesky = if p.n_int > 0 { Some(self.pattern.factor(&self.matrix)?) } else { None };
        Ok(GaussNewtonFactor { d, j2, cholesky })
    }
}

/// One ABF++ iteration: the Gauss–Newton step and, with `inner` > 0, a Newton step solved by
/// GMRES preconditioned with the same factorization; the trial with the smaller ‖∇L‖ is kept.
fn plus_plus_step(
    p: &AngleProblem,
    system: &mut ReducedSystem,
    stars: &(Vec<usize>, Vec<u32>),
    lin: &Linearization,
    s: &State,
    inner: usize,
) -> Result<(State, Linearization)> {
    let factor = system.factor(p, lin, s)?;
    let m3 = s.alpha.len();
    let b: KktVector = lin.grad_alpha.iter().chain(&lin.c_tri).chain(&lin.c2).map(|x| -x).collect();
    let gn = factor.solve(p, &b)?;
    let gn_state = s.moved(&gn, fraction_to_boundary(&s.alpha, &gn[..m3]));
    let gn_lin = p.linearize(&gn_state);
    if inner == 0 {
        return Ok((gn_state, gn_lin));
    }
    let relative = 0.1f64.min(lin.norm);
    let newton =
        preconditioned_gmres(|x| p.newton_apply(lin, s, stars, x), |y| factor.solve(p, y), &b, relative, inner)?;
    let newton_state = s.moved(&newton, fraction_to_boundary(&s.alpha, &newton[..m3]));
    let newton_lin = p.linearize(&newton_state);
    if newton_lin.norm < gn_lin.norm {
        Ok((newton_state, newton_lin))
    } else {
        Ok((gn_state, gn_lin))
    }
}

/// The local 6×3 block of J2 of one triangle: rows (planarity, reconstruction) of each of its
/// 3 vertices, columns its 3 corners.
fn local_j2(p: &AngleProblem, tri: &[u32; 3], columns: &[[(u32, f64); 3]]) -> [[f64; 3]; 6] {
    let rows: [u32; 6] = std::array::from_fn(|j| p.row(tri[j / 2], (j % 2) as u32));
    let mut jl = [[0.0f64; 3]; 6];
    for (k, column) in columns.iter().enumerate() {
        for &(r, coef) in column {
            if r != NONE {
                if let Some(j) = rows.iter().position(|&x| x == r) {
                    jl[j][k] += coef;
                }
            }
        }
    }
    jl
}

/// A factored ABF++ Gauss–Newton KKT operator `[Λ Jᵀ; J 0]`.
struct GaussNewtonFactor {
    /// Λ⁻¹, one entry per corner.
    d: Vec<f64>,
    /// The J2 column of every corner.
    j2: Vec<[(u32, f64); 3]>,
    /// Cholesky factor of `J2 M J2ᵀ` (`None` without interior vertices).
    cholesky: Option<uvflat_sparse::CholeskySolver<f64>>,
}

/// A vector of the KKT space, `[α (3F) | λ_T (F) | λ_2 (2·n_int)]` laid out flat.
type KktVector = Vec<f64>;

impl GaussNewtonFactor {
    /// Solves `[Λ Jᵀ; J 0] x = y` (ABF++ §3): δλ_2 from the reduced Cholesky system, then δλ_T
    /// and δα triangle by triangle.
    fn solve(&self, p: &AngleProblem, y: &[f64]) -> Result<KktVector> {
        let f = p.tris.len();
        let n2 = 2 * p.n_int;
        let (ya, rest) = y.split_at(3 * f);
        let (yt, y2) = rest.split_at(f);
        let d = &self.d;
        // Per triangle: z = d·y_α − d (Σ d·y_α − y_T) / Σd; right side J2 z − y_2.
        let mut c1_over_a = vec![0.0; f];
        let mut rhs = Mat::<f64>::zeros(n2, 1);
        for t in 0..f {
            let sum_d = d[3 * t] + d[3 * t + 1] + d[3 * t + 2];
            let dy: [f64; 3] = std::array::from_fn(|k| d[3 * t + k] * ya[3 * t + k]);
            c1_over_a[t] = (dy[0] + dy[1] + dy[2] - yt[t]) / sum_d;
            for k in 0..3 {
                let z = dy[k] - d[3 * t + k] * c1_over_a[t];
                for &(r, coef) in &self.j2[3 * t + k] {
                    if r != NONE {
                        rhs[(r as usize, 0)] += coef * z;
                    }
                }
            }
        }
        for r in 0..n2 {
            rhs[(r, 0)] -= y2[r];
        }
        if let Some(cholesky) = &self.cholesky {
            cholesky.solve_in_place(&mut rhs)?;
        }
        let dl2 = rhs.col_as_slice(0);
        // δλ_T = (Σ d y_α − y_T − Σ d (J2ᵀ δλ_2)) / Σd and δα = d (y_α − δλ_T − J2ᵀ δλ_2).
        let mut x = vec![0.0; 4 * f + n2];
        for t in 0..f {
            let jt: [f64; 3] = std::array::from_fn(|k| {
                self.j2[3 * t + k].iter().filter(|(r, _)| *r != NONE).map(|&(r, coef)| coef * dl2[r as usize]).sum()
            });
            let sum_d = d[3 * t] + d[3 * t + 1] + d[3 * t + 2];
            let b_dl2 = (0..3).map(|k| d[3 * t + k] * jt[k]).sum::<f64>();
            let dlt = c1_over_a[t] - b_dl2 / sum_d;
            x[3 * f + t] = dlt;
            for k in 0..3 {
                let c = 3 * t + k;
                x[c] = d[c] * (ya[c] - dlt - jt[k]);
            }
        }
        x[4 * f..].copy_from_slice(dl2);
        require_finite(x.iter().copied(), "ABF++ reduced")?;
        Ok(x)
    }
}

/// The weight w of an angle whose optimal value is `b` (radians), see [`AbfWeights`].
fn objective_weight(weights: AbfWeights, b: f64) -> f64 {
    match weights {
        AbfWeights::InverseSquare => 1.0 / (b * b),
        AbfWeights::Inverse => 1.0 / b,
        AbfWeights::AngleAndSupplement => 1.0 / (b * (PI - b).max(MIN_SUPPLEMENT)),
    }
}

/// The starting angles: β scaled triangle by triangle to sum to π (positive, and meeting the
/// triangle constraints).
fn triangle_scaled(beta: &[f64]) -> Vec<f64> {
    beta.chunks_exact(3)
        .flat_map(|b| {
            let scale = PI / (b[0] + b[1] + b[2]);
            [b[0] * scale, b[1] * scale, b[2] * scale]
        })
        .collect()
}

/// Largest τ ≤ 1 such that no angle moves more than half way to 0 or to π along `dalpha`
/// (fraction to the boundary; 1 near the solution).
fn fraction_to_boundary(alpha: &[f64], dalpha: &[f64]) -> f64 {
    alpha.iter().zip(dalpha).fold(1.0f64, |tau, (&a, &da)| {
        if da < 0.0 && a + da < 0.5 * a {
            tau.min(0.5 * a / -da)
        } else if da > 0.0 && a + da > a + 0.5 * (PI - a) {
            tau.min(0.5 * (PI - a) / da)
        } else {
            tau
        }
    })
}

impl State {
    /// This state moved by τ·x (x a [`KktVector`]).
    fn moved(&self, x: &[f64], tau: f64) -> State {
        let m3 = self.alpha.len();
        let f = self.lambda_tri.len();
        let add = |v: &[f64], dx: &[f64]| v.iter().zip(dx).map(|(a, b)| a + tau * b).collect::<Vec<f64>>();
        State {
            alpha: add(&self.alpha, &x[..m3]),
            lambda_tri: add(&self.lambda_tri, &x[m3..m3 + f]),
            lambda2: add(&self.lambda2, &x[m3 + f..]),
        }
    }
}

impl<'a> AngleProblem<'a> {
    /// The Newton KKT operator `[H Jᵀ; J 0]` applied to x, H = ∇²E + Σ_v λ_L,v ∇²C_L,v the exact
    /// Hessian of the Lagrangian in α (the matrix of ABF's full Newton step, applied without
    /// assembling it). For a product of sines P, ∇²P = P (c cᵀ − diag(c²) − I), c the cotangents.
    fn newton_apply(&self, lin: &Linearization, s: &State, stars: &(Vec<usize>, Vec<u32>), x: &[f64]) -> KktVector {
        let m3 = s.alpha.len();
        let f = self.tris.len();
        let (xa, rest) = x.split_at(m3);
        let (xt, x2) = rest.split_at(f);
        let mut y = vec![0.0; x.len()];
        for c in 0..m3 {
            let mut top = self.objective_curvature(c, s.alpha[c]) * xa[c] + xt[c / 3];
            for (r, coef) in self.j2_column(lin, c) {
                if r != NONE {
                    top += coef * x2[r as usize];
                    y[m3 + f + r as usize] += coef * xa[c];
                }
            }
            y[c] = top;
            y[m3 + c / 3] += xa[c];
        }
        let (start, corners) = stars;
        for i in 0..self.n_int {
            let lambda = s.lambda2[2 * i + 1];
            if lambda == 0.0 {
                continue;
            }
            let star = &corners[start[i]..start[i + 1]];
            for (offset, sign, product) in [(1usize, 1.0, lin.p_next[i]), (2usize, -1.0, lin.p_prev[i])] {
                let scale = lambda * sign * product;
                let other = |c: u32| 3 * (c as usize / 3) + (c as usize % 3 + offset) % 3;
                let dot: f64 = star.iter().map(|&c| lin.cot[other(c)] * xa[other(c)]).sum();
                for &c in star {
                    let a = other(c);
                    let ca = lin.cot[a];
                    y[a] += scale * (ca * dot - (ca * ca + 1.0) * xa[a]);
                }
            }
        }
        y
    }
}
