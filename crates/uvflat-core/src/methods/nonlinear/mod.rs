//! Distortion-minimizing (non-linear) parameterizations with a free boundary that never flip a
//! triangle: SLIM, ARAP, MIPS, Sander's L2 stretch, Green–Lagrange and Degener's θ-energy
//! (course notes §4.3–4.4; the energies are listed in [`energy`]).
//!
//! Every method starts from a bijective map — the mean value map with the longest boundary on a
//! circle (Floater 2003; bijective by the Tutte–Floater theorem, course notes §2.2), uniformly
//! scaled to the input's area — and then moves every vertex, boundary included, along descent
//! directions with the flip-free line search of [`line_search`] (Smith & Schaefer 2015): no
//! step lets any triangle's signed area reach zero, so the result is locally injective and
//! the energy decreases monotonically. ARAP starts from the natural conformal map instead when
//! that map has no flipped triangle (Liu et al. 2008 §4). ARAP's and Green–Lagrange's energies
//! stay finite as a triangle's area goes to zero (no barrier), so for them the same line
//! search also stops before any triangle's area falls below [`AREA_FLOOR_FRACTION`] of its
//! share ([`line_search::max_step_above`]).
//!
//! Solvers:
//! - SLIM ([`slim`], Rabinovich et al. 2017): symmetric Dirichlet energy, reweighted
//!   local-global proxy solved by a sparse Cholesky factorization per iteration (symbolic
//!   analysis once).
//! - ARAP ([`arap`], Liu et al. 2008): local-global with one factorization of the cotangent
//!   Laplacian, the global solution used as a search direction.
//! - MIPS, stretch, Green–Lagrange, Degener ([`lbfgs`]): L-BFGS whose initial inverse Hessian
//!   is the inverse cotangent Laplacian (one factorization; Zhu et al. 2018 use the same
//!   preconditioner), with the flip-free line search.
//!
//! Iterations stop after `iterations`, or when an iteration lowers the energy by less than
//! `tolerance` times its value, or when no step lowers it. Results are deterministic: every
//! parallel sum is taken in fixed chunks.

pub(crate) mod arap;
pub(crate) mod energy;
pub(crate) mod jacobian;
pub(crate) mod lbfgs;
pub(crate) mod line_search;
pub(crate) mod scaffold;
pub(crate) mod slim;

use crate::error::{Error, Result};
use crate::mesh::{TriMesh, NONE};
use crate::methods::barycentric::{fixed_boundary_map, FixedBoundaryOptions};
use crate::methods::conformal::natural_conformal_map;
use crate::progress::Progress;
use energy::{evaluate, vertex_gradient, Energy};
use faer::Mat;
use jacobian::RestFrames;
use uvflat_sparse::{lower_from_entries, CholeskySolver};

/// A distortion-minimizing method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NonlinearMethod {
    /// Symmetric Dirichlet energy by SLIM (Rabinovich et al. 2017).
    Slim,
    /// As-rigid-as-possible, local-global (Liu et al. 2008).
    Arap,
    /// MIPS (Hormann & Greiner 2000).
    Mips,
    /// L2 stretch (Sander et al. 2001).
    Stretch,
    /// Green–Lagrange tensor (Maillot et al. 1993).
    GreenLagrange,
    /// Degener et al. 2003 θ-energy.
    Degener,
}

impl NonlinearMethod {
    /// The energy the method minimizes.
    pub fn energy(self, theta: f64) -> Energy {
        match self {
            NonlinearMethod::Slim => Energy::SymmetricDirichlet,
            NonlinearMethod::Arap => Energy::Arap,
            NonlinearMethod::Mips => Energy::Mips,
            NonlinearMethod::Stretch => Energy::Stretch,
            NonlinearMethod::GreenLagrange => Energy::GreenLagrange,
            NonlinearMethod::Degener => Energy::Degener { theta },
        }
    }
}

/// Options of [`nonlinear_map`].
#[derive(Debug, Clone, PartialEq)]
pub struct NonlinearOptions {
    /// The method.
    pub method: NonlinearMethod,
    /// Maximum number of iterations (each one a line search along a new direction).
    pub iterations: usize,
    /// Stop when an iteration lowers the energy by less than `tolerance × energy`.
    pub tolerance: f64,
    /// θ of Degener's energy (> 0; ignored by the other methods).
    pub theta: f64,
    /// Keep the whole map bijective, not only locally injective: the free boundary may not run
    /// into itself ([`scaffold`]: SCAF for SLIM; for the other methods the scaffold bounds
    /// their steps). The start must be bijective.
    pub bijective: bool,
}

impl NonlinearOptions {
    /// Defaults for `method`: 100 iterations, tolerance 1e-7, θ = 3, locally injective only.
    pub fn new(method: NonlinearMethod) -> Self {
        NonlinearOptions { method, iterations: 100, tolerance: 1e-7, theta: 3.0, bijective: false }
    }
}

/// What [`nonlinear_map`] returns.
#[derive(Debug, Clone)]
pub struct NonlinearResult {
    /// One UV per vertex (NaN for unreferenced vertices).
    pub uv: Vec<[f64; 2]>,
    /// Energy (area-weighted mean of the local measure, see [`energy`]) of the initial map and
    /// after each iteration; non-increasing.
    pub energy: Vec<f64>,
    /// Iterations done.
    pub iterations: usize,
    /// True when the tolerance was reached or no step could lower the energy further (false
    /// when the iteration limit stopped the method).
    pub converged: bool,
}

/// Minimizes the method's energy over locally injective maps with a free boundary.
pub fn nonlinear_map(mesh: &TriMesh, options: &NonlinearOptions) -> Result<NonlinearResult> {
    nonlinear_map_with_progress(mesh, options, &mut Progress::none())
}

/// [`nonlinear_map`] with progress reporting and cancellation (checked once per iteration).
pub fn nonlinear_map_with_progress(
    mesh: &TriMesh,
    options: &NonlinearOptions,
    progress: &mut Progress,
) -> Result<NonlinearResult> {
    if !(options.tolerance >= 0.0) {
        return Err(Error::InvalidArgument(format!("tolerance must be ≥ 0 (got {})", options.tolerance)));
    }
    if options.method == NonlinearMethod::Degener && !(options.theta > 0.0 && options.theta.is_finite()) {
        return Err(Error::InvalidArgument(format!("Degener's θ must be finite and > 0 (got {})", options.theta)));
    }
    mesh.require_disk_with_holes()?;
    progress.report(0.0)?;
    let problem = Problem::new(mesh);
    let x0 = problem.initial_map(mesh, options.method)?;
    progress.report(0.02)?;
    let run = run_method(&problem, x0, options, progress)?;
    progress.report(1.0)?;
    Ok(NonlinearResult {
        uv: problem.expand(&run.x),
        energy: run.energy,
        iterations: run.iterations,
        converged: run.converged,
    })
}

/// [`nonlinear_map`] started from a caller-given map `initial` (one UV per vertex) instead of
/// the mean value map. The start must have no flipped or degenerate triangle (it may be
/// mirrored as a whole; it is rescaled to the input's area), otherwise the call fails with
/// [`Error::InvalidArgument`]; the result is then locally injective as well.
pub fn nonlinear_map_from(
    mesh: &TriMesh,
    options: &NonlinearOptions,
    initial: &[[f64; 2]],
    progress: &mut Progress,
) -> Result<NonlinearResult> {
    if initial.len() != mesh.vertex_count() {
        return Err(Error::InvalidArgument(format!(
            "the starting map has {} UVs but the mesh has {} vertices",
            initial.len(),
            mesh.vertex_count()
        )));
    }
    mesh.require_disk_with_holes()?;
    let problem = Problem::new(mesh);
    let x0 = problem
        .oriented_and_scaled(initial)
        .ok_or_else(|| Error::InvalidArgument("the starting map has a flipped or degenerate triangle".into()))?;
    let run = run_method(&problem, x0, options, progress)?;
    Ok(NonlinearResult {
        uv: problem.expand(&run.x),
        energy: run.energy,
        iterations: run.iterations,
        converged: run.converged,
    })
}

/// Runs the method's minimizer from the flip-free start `x0`.
fn run_method(
    problem: &Problem,
    x0: Vec<[f64; 2]>,
    options: &NonlinearOptions,
    progress: &mut Progress,
) -> Result<Run> {
    if options.bijective && options.method == NonlinearMethod::Slim {
        return scaffold::minimize(problem, x0, options, progress);
    }
    // The other methods honour `bijective` in `descend` (the scaffold as a guard of the step).
    match options.method {
        NonlinearMethod::Slim => slim::minimize(problem, x0, options, progress),
        NonlinearMethod::Arap => arap::minimize(problem, x0, options, progress),
        _ => lbfgs::minimize(problem, options.method.energy(options.theta), x0, options, progress),
    }
}

/// The mesh restricted to its referenced vertices, numbered consecutively.
pub struct Problem {
    /// Compact index of each mesh vertex (`NONE` when unreferenced).
    pub index: Vec<u32>,
    /// Mesh vertex of each compact index.
    pub vertex: Vec<u32>,
    /// Triangles in compact indices.
    pub tris: Vec<[u32; 3]>,
    /// Rest frames of the triangles.
    pub frames: RestFrames,
    /// 3D position of each compact vertex (for fill-reducing orderings).
    pub coords: Vec<[f64; 3]>,
}

impl Problem {
    /// Numbers the referenced vertices of `mesh`.
    pub fn new(mesh: &TriMesh) -> Self {
        let mut index = vec![NONE; mesh.vertex_count()];
        let mut vertex = Vec::new();
        for v in 0..mesh.vertex_count() as u32 {
            if mesh.is_referenced(v) {
                index[v as usize] = vertex.len() as u32;
                vertex.push(v);
            }
        }
        let tris: Vec<[u32; 3]> = mesh.triangles().iter().map(|t| t.map(|v| index[v as usize])).collect();
        let coords: Vec<[f64; 3]> = vertex.iter().map(|&v| mesh.points()[v as usize]).collect();
        let frames = RestFrames::new(&coords, &tris);
        Problem { index, vertex, tris, frames, coords }
    }

    /// Number of unknown vertices.
    pub fn n(&self) -> usize {
        self.vertex.len()
    }

    /// One UV per mesh vertex from compact UVs.
    pub fn expand(&self, x: &[[f64; 2]]) -> Vec<[f64; 2]> {
        self.index.iter().map(|&i| if i == NONE { [f64::NAN; 2] } else { x[i as usize] }).collect()
    }

    /// Compact UVs of a per-vertex map, oriented like the triangles (mirrored when every
    /// triangle is clockwise) and scaled so that the UV area equals the 3D area; `None` when
    /// the map has a flipped or degenerate triangle.
    fn oriented_and_scaled(&self, uv: &[[f64; 2]]) -> Option<Vec<[f64; 2]>> {
        let mut x: Vec<[f64; 2]> = self.vertex.iter().map(|&v| uv[v as usize]).collect();
        let areas: Vec<f64> = self.tris.iter().map(|t| signed_area(&x, *t)).collect();
        let sign = if areas.iter().all(|&a| a > 0.0) {
            1.0
        } else if areas.iter().all(|&a| a < 0.0) {
            -1.0
        } else {
            return None;
        };
        let total: f64 = areas.iter().sum::<f64>() * sign;
        let s = (self.frames.total_area / total).sqrt();
        if !(s.is_finite() && s > 0.0) {
            return None;
        }
        for p in &mut x {
            *p = [s * p[0], sign * s * p[1]];
        }
        Some(x)
    }

    /// The bijective starting map (see the module documentation).
    fn initial_map(&self, mesh: &TriMesh, method: NonlinearMethod) -> Result<Vec<[f64; 2]>> {
        if method == NonlinearMethod::Arap {
            if let Some(x) = natural_conformal_map(mesh, None).ok().and_then(|uv| self.oriented_and_scaled(&uv)) {
                return Ok(x);
            }
        }
        let uv = fixed_boundary_map(mesh, &FixedBoundaryOptions::default())?;
        self.oriented_and_scaled(&uv).ok_or_else(|| {
            Error::Numerical("the mean value map used as the starting point has a degenerate or flipped triangle (rounding on a nearly degenerate mesh)".into())
        })
    }

    /// Cotangent Laplacian `Σ_t (A_t / A) g_k · g_l` (the Hessian of the normalized Dirichlet
    /// energy), plus `regularization × mean diagonal` on the diagonal to remove the
    /// translations from its kernel, factored once.
    pub fn laplacian(&self, regularization: f64) -> Result<(CholeskySolver<f64>, f64)> {
        let n = self.n();
        let mut diagonal = vec![0.0; n];
        let mut lower = Vec::with_capacity(3 * self.tris.len());
        let inv = 1.0 / self.frames.total_area;
        for (t, tri) in self.tris.iter().enumerate() {
            let g = &self.frames.grad[t];
            let w = self.frames.area[t] * inv;
            for k in 0..3 {
                diagonal[tri[k] as usize] += w * (g[k][0] * g[k][0] + g[k][1] * g[k][1]);
                let l = (k + 1) % 3;
                let value = w * (g[k][0] * g[l][0] + g[k][1] * g[l][1]);
                let (a, b) = (tri[k].max(tri[l]), tri[k].min(tri[l]));
                lower.push((a, b, value));
            }
        }
        let delta = regularization * diagonal.iter().sum::<f64>() / n.max(1) as f64;
        for d in &mut diagonal {
            *d += delta;
        }
        let matrix = lower_from_entries(&diagonal, lower)?;
        Ok((CholeskySolver::new(&matrix, Some(&self.coords))?, delta))
    }
}

/// Signed area of a triangle of a compact map.
fn signed_area(x: &[[f64; 2]], t: [u32; 3]) -> f64 {
    let [a, b, c] = t.map(|v| x[v as usize]);
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// Solves `P y = rhs` for the two UV columns of `rhs`.
pub(crate) fn solve2(solver: &CholeskySolver<f64>, rhs: &[[f64; 2]]) -> Result<Vec<[f64; 2]>> {
    let mut m = Mat::<f64>::from_fn(rhs.len(), 2, |i, j| rhs[i][j]);
    solver.solve_in_place(&mut m)?;
    let out: Vec<[f64; 2]> = (0..rhs.len()).map(|i| [m[(i, 0)], m[(i, 1)]]).collect();
    uvflat_sparse::require_finite(out.iter().flatten().copied(), "non-linear parameterization")?;
    Ok(out)
}

/// The state of a minimization.
pub(crate) struct Run {
    pub x: Vec<[f64; 2]>,
    pub energy: Vec<f64>,
    pub iterations: usize,
    pub converged: bool,
}

/// The shared outer loop: at each iteration `direction(x, ∇E, reset)` proposes a search
/// direction (`reset` after a failed line search: a safer direction, or `None` for none), then
/// the flip-free line search moves along it.
pub(crate) fn descend(
    problem: &Problem,
    energy: Energy,
    x0: Vec<[f64; 2]>,
    options: &NonlinearOptions,
    progress: &mut Progress,
    direction: impl FnMut(&[[f64; 2]], &[[f64; 2]], bool) -> Result<Option<Vec<[f64; 2]>>>,
) -> Result<Run> {
    descend_while(problem, energy, x0, options, progress, direction, |_| true).map(|(run, _)| run)
}

/// [`descend`] that stops before the first step whose result `keep` refuses; the flag says
/// whether it stopped so (the run then ends at the last kept iterate, not converged).
pub(crate) fn descend_while(
    problem: &Problem,
    energy: Energy,
    x0: Vec<[f64; 2]>,
    options: &NonlinearOptions,
    progress: &mut Progress,
    mut direction: impl FnMut(&[[f64; 2]], &[[f64; 2]], bool) -> Result<Option<Vec<[f64; 2]>>>,
    mut keep: impl FnMut(&[[f64; 2]]) -> bool,
) -> Result<(Run, bool)> {
    let (frames, tris, n) = (&problem.frames, &problem.tris, problem.n());
    let gradient = |x: &[[f64; 2]]| {
        let (e, dj) = evaluate(energy, frames, tris, x, true);
        (e, if e.is_finite() { vertex_gradient(frames, tris, &dj, n) } else { Vec::new() })
    };
    let (mut e, mut grad) = gradient(&x0);
    if !e.is_finite() {
        return Err(Error::Numerical("the starting map has infinite energy (a degenerate triangle)".into()));
    }
    let floor = area_floor(problem, energy, &x0);
    let edges = if options.bijective { scaffold::boundary_edges(tris) } else { Vec::new() };
    if options.bijective && edges.is_empty() {
        return Err(Error::InvalidArgument("a bijective map needs a boundary".into()));
    }
    let mut run = Run { x: x0, energy: vec![e], iterations: 0, converged: false };
    for it in 0..options.iterations {
        progress.report(0.02 + 0.97 * it as f64 / options.iterations as f64)?;
        let mut accepted = None;
        for reset in [false, true] {
            let Some(d) = direction(&run.x, &grad, reset)? else {
                break;
            };
            let slope = line_search::slope(&grad, &d);
            let value = |x: &[[f64; 2]]| energy::energy(energy, frames, tris, x);
            let search = line_search::Search { x: &run.x, d: &d, e0: e, slope };
            accepted = if options.bijective {
                scaffold::guarded_step(tris, &edges, &search, floor.as_deref(), value)?
            } else {
                line_search::armijo_above(tris, &search, floor.as_deref(), value)
            };
            if accepted.is_some() {
                break;
            }
        }
        let Some(step) = accepted else {
            run.converged = true;
            break;
        };
        if !keep(&step.uv) {
            return Ok((run, true));
        }
        let decrease = e - step.energy;
        run.x = step.uv;
        (e, grad) = gradient(&run.x);
        run.energy.push(e);
        run.iterations += 1;
        if decrease <= options.tolerance * e.abs() {
            run.converged = true;
            break;
        }
    }
    Ok((run, false))
}

/// Share of its area below which no triangle is let shrink by the energies that do not forbid
/// it themselves (ARAP and Green–Lagrange: both stay finite as a triangle's area goes to zero,
/// so their minimizers can press triangles flat — L2 stretch 10⁵–10⁸ was measured — where
/// the other energies grow without bound).
pub const AREA_FLOOR_FRACTION: f64 = 0.01;

/// Per triangle, the doubled UV area its steps may not go below: [`AREA_FLOOR_FRACTION`] of
/// its share of the map's UV area (its 3D area's share of the surface), or half its area in
/// the start when that is less (the start is kept strictly above its floor, so the first step
/// is not blocked). `None` for the energies with their own barrier.
fn area_floor(problem: &Problem, energy: Energy, x0: &[[f64; 2]]) -> Option<Vec<f64>> {
    if energy.is_barrier() {
        return None;
    }
    let doubled: Vec<f64> = problem.tris.iter().map(|t| 2.0 * signed_area(x0, *t)).collect();
    let total: f64 = doubled.iter().sum();
    let frames = &problem.frames;
    Some(
        doubled
            .iter()
            .zip(&frames.area)
            .map(|(&a, &area_3d)| (AREA_FLOOR_FRACTION * total * area_3d / frames.total_area).min(0.5 * a))
            .collect(),
    )
}
