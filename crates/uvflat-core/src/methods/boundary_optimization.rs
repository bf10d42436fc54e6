//! Boundary optimization (Desbrun–Meyer–Alliez 2002 §5.2): the intrinsic map `λ·DCP + μ·DAP`
//! (§3.4) whose boundary positions minimize the edge-length or area distortion of §5.1
//! ([`super::length_area_distortion`]), by descent on the boundary positions only.
//!
//! The map is linear in its boundary, `U = U(b)`, through the boundary editor (§4.2, factored
//! once; [`super::intrinsic::BoundaryEditor`]). The gradient with respect to the boundary uses
//! the impulse responses `∂u_i/∂u_p = b^p(i)` applied to ∂E/∂U by the editor's adjoint (one
//! transposed solve, [`super::intrinsic::BoundaryEditor::boundary_gradient`]) instead of forming
//! them. Directions are L-BFGS directions on the boundary coordinates (Nocedal & Wright 2006,
//! Alg. 7.4, memory 8; the steepest descent the paper describes when the history is empty or
//! the direction is not a descent direction). Along a direction d the whole map moves linearly,
//! `U + t·U(d)`, so:
//! - every triangle's signed area is a quadratic in t, and the largest step before the first
//!   triangle changes orientation is found exactly (Smith & Schaefer 2015's bound,
//!   [`super::nonlinear::line_search::max_flip_free_step`]); steps stop at 0.8 of it;
//! - the energy is an exact polynomial in t (degree 4 or 8), minimized exactly on that interval
//!   by root finding; a step is accepted only when it lowers the energy and leaves no triangle
//!   flipped or degenerate (checked on the candidate map), otherwise it is halved.
//!
//! So every accepted iterate keeps the orientation of every triangle of the start (a flip-free
//! start stays flip-free) and the energy decreases monotonically. Start: the outer loop on a
//! circle or square scaled so that the map's UV area equals the surface area, or caller-given
//! positions. Cost per iteration: three two-column solves with the editor's factor and O(m).

use super::intrinsic::BoundaryEditor;
use super::length_area_distortion::{DistortionEnergy, DistortionTerms};
use super::near_optimal::area_matching_scale;
use super::nonlinear::lbfgs::{axpy, dot};
use super::nonlinear::line_search::{max_flip_free_step, MAX_STEP_FRACTION};
use crate::boundary::{fixed_boundary, BoundaryShape, Distribution};
use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use crate::metrics::{signed_uv_area, triangle_is_degenerate_2d};
use crate::progress::Progress;
use std::collections::VecDeque;

/// Options of [`boundary_optimized_map`].
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryOptimizationOptions {
    /// The energy to minimize.
    pub energy: DistortionEnergy,
    /// λ of the intrinsic map (weight of DCP; default 1).
    pub lambda: f64,
    /// μ of the intrinsic map (weight of DAP; default 0).
    pub mu: f64,
    /// Starting boundary (circle and square are scaled to the surface area).
    pub shape: BoundaryShape,
    /// Spacing of the starting boundary along a circle or square.
    pub distribution: Distribution,
    /// Iteration limit (default 100).
    pub iterations: usize,
    /// Stop when an iteration lowers the energy by less than `tolerance × energy` (default 1e-6).
    pub tolerance: f64,
}

impl Default for BoundaryOptimizationOptions {
    fn default() -> Self {
        BoundaryOptimizationOptions {
            energy: DistortionEnergy::EdgeLength,
            lambda: 1.0,
            mu: 0.0,
            shape: BoundaryShape::Circle,
            distribution: Distribution::ChordLength,
            iterations: 100,
            tolerance: 1e-6,
        }
    }
}

/// The optimized map and its history.
#[derive(Debug, Clone)]
pub struct BoundaryOptimizedMap {
    /// One UV per vertex (NaN for unreferenced vertices).
    pub uv: Vec<[f64; 2]>,
    /// The outer boundary loop, in the order of `boundary_uv`.
    pub boundary: Vec<u32>,
    /// The optimized boundary positions.
    pub boundary_uv: Vec<[f64; 2]>,
    /// Energy of the start, then after each accepted iteration (non-increasing).
    pub history: Vec<f64>,
    /// Iterations done (accepted steps).
    pub iterations: usize,
    /// True when the tolerance was met or no step could lower the energy; false when the
    /// iteration limit stopped the descent.
    pub converged: bool,
    /// Triangles flipped (or degenerate) in the starting map; the descent never changes any
    /// triangle's orientation, so the result has the same ones (0 for a flip-free start).
    pub flipped: usize,
    /// Factor applied to the circle or square start (1 for given positions).
    pub boundary_scale: f64,
}

/// L-BFGS memory.
const MEMORY: usize = 8;
/// Halvings of a rejected step before the direction is given up.
const MAX_HALVINGS: usize = 40;

fn moved(x: &[[f64; 2]], t: f64, d: &[[f64; 2]]) -> Vec<[f64; 2]> {
    x.iter().zip(d).map(|(p, q)| [p[0] + t * q[0], p[1] + t * q[1]]).collect()
}

/// A stored pair `(s, y, 1/yᵀs)`.
struct Pair {
    s: Vec<[f64; 2]>,
    y: Vec<[f64; 2]>,
    rho: f64,
}

/// `−H g` by the two-loop recursion (H₀ = γI with γ = sᵀy/yᵀy of the latest pair).
fn lbfgs_direction(pairs: &VecDeque<Pair>, g: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut q = g.to_vec();
    let mut alpha = Vec::with_capacity(pairs.len());
    for p in pairs.iter().rev() {
        let a = p.rho * dot(&p.s, &q);
        axpy(&mut q, -a, &p.y);
        alpha.push(a);
    }
    if let Some(last) = pairs.back() {
        let gamma = 1.0 / (last.rho * dot(&last.y, &last.y));
        for v in &mut q {
            v[0] *= gamma;
            v[1] *= gamma;
        }
    }
    for (p, a) in pairs.iter().zip(alpha.iter().rev()) {
        let b = p.rho * dot(&p.y, &q);
        axpy(&mut q, a - b, &p.s);
    }
    q.iter().map(|v| [-v[0], -v[1]]).collect()
}

/// The starting boundary positions, in the editor's boundary order.
fn start_boundary(
    mesh: &TriMesh,
    editor: &BoundaryEditor,
    options: &BoundaryOptimizationOptions,
) -> Result<Vec<[f64; 2]>> {
    let fixed = fixed_boundary(mesh, &options.shape, options.distribution)?;
    let mut at = vec![None; mesh.vertex_count()];
    for &(v, p) in &fixed.fixed {
        at[v as usize] = Some(p);
    }
    let start: Vec<[f64; 2]> = editor.boundary_vertices().iter().filter_map(|&v| at[v as usize]).collect();
    if start.len() != editor.boundary_vertices().len() || fixed.fixed.len() != start.len() {
        return Err(Error::InvalidArgument(
            "boundary optimization moves the outer (longest) boundary loop: give positions for exactly its vertices"
                .into(),
        ));
    }
    Ok(start)
}

/// The mesh's triangles oriented like the starting map (flipped ones reversed), without those
/// degenerate in it, and the number of flipped or degenerate ones.
fn oriented_triangles(mesh: &TriMesh, uv: &[[f64; 2]]) -> (Vec<[u32; 3]>, usize) {
    let mut out = Vec::with_capacity(mesh.triangle_count());
    let mut bad = 0;
    for &t in mesh.triangles() {
        let q = t.map(|v| uv[v as usize]);
        if triangle_is_degenerate_2d(q) {
            bad += 1;
        } else if signed_uv_area(q) < 0.0 {
            bad += 1;
            out.push([t[0], t[2], t[1]]);
        } else {
            out.push(t);
        }
    }
    (out, bad)
}

/// True when every triangle of `tris` is positively oriented and not degenerate in `uv`.
fn keeps_orientation(tris: &[[u32; 3]], uv: &[[f64; 2]]) -> bool {
    use rayon::prelude::*;
    tris.par_iter().with_min_len(4096).all(|t| {
        let q = t.map(|v| uv[v as usize]);
        signed_uv_area(q) > 0.0 && !triangle_is_degenerate_2d(q)
    })
}

/// An accepted iterate, as [`boundary_optimized_map_observed`] shows it.
pub struct BoundaryStep<'a> {
    /// Accepted iterations so far (0 for the start).
    pub iteration: usize,
    /// The energy of `uv`.
    pub energy: f64,
    /// The map (one UV per vertex).
    pub uv: &'a [[f64; 2]],
}

/// The boundary-optimized intrinsic map of `mesh` (a disk, possibly with holes: the outer loop
/// moves, holes follow as interior vertices). The progress callback is called once per
/// iteration; cancelling stops before the next iteration starts.
pub fn boundary_optimized_map(
    mesh: &TriMesh,
    options: &BoundaryOptimizationOptions,
    progress: &mut Progress,
) -> Result<BoundaryOptimizedMap> {
    boundary_optimized_map_observed(mesh, options, progress, &mut |_| {})
}

/// [`boundary_optimized_map`], showing the start and every accepted iterate to `observer`.
pub fn boundary_optimized_map_observed(
    mesh: &TriMesh,
    options: &BoundaryOptimizationOptions,
    progress: &mut Progress,
    observer: &mut dyn FnMut(&BoundaryStep<'_>),
) -> Result<BoundaryOptimizedMap> {
    if !(options.tolerance >= 0.0) {
        return Err(Error::InvalidArgument(format!("tolerance must be ≥ 0 (got {})", options.tolerance)));
    }
    let editor = BoundaryEditor::new(mesh, options.lambda, options.mu, &mut Progress::none())?;
    let mut b = start_boundary(mesh, &editor, options)?;
    let boundary_scale = match options.shape {
        BoundaryShape::Given(_) => 1.0,
        BoundaryShape::Circle | BoundaryShape::Square => area_matching_scale(mesh, &editor.solve(&b)?)?,
    };
    for p in &mut b {
        p[0] *= boundary_scale;
        p[1] *= boundary_scale;
    }
    let terms = DistortionTerms::new(mesh);
    let kind = options.energy;
    let mut uv = editor.solve(&b)?;
    let (oriented, flipped) = oriented_triangles(mesh, &uv);
    let (mut energy, gu) = terms.gradient(kind, &uv);
    let mut g = editor.boundary_gradient(&gu)?;
    let mut history = vec![energy];
    observer(&BoundaryStep { iteration: 0, energy, uv: &uv });
    let mut pairs: VecDeque<Pair> = VecDeque::new();
    let mut converged = false;
    let mut iterations = 0;
    while iterations < options.iterations {
        progress.report(iterations as f64 / options.iterations as f64)?;
        let Some((t, d)) = line_search(&editor, &terms, kind, &oriented, &uv, energy, &g, &mut pairs)? else {
            converged = true;
            break;
        };
        let b_new = moved(&b, t, &d);
        let exact = editor.solve(&b_new)?;
        let (e, gu) = terms.gradient(kind, &exact);
        // The exact re-solve agrees with the line search's prediction up to rounding; keep the
        // guarantees on the map actually returned.
        if !(e < energy) || !keeps_orientation(&oriented, &exact) {
            converged = true;
            break;
        }
        (b, uv) = (b_new, exact);
        let g_new = editor.boundary_gradient(&gu)?;
        let s: Vec<[f64; 2]> = d.iter().map(|v| [t * v[0], t * v[1]]).collect();
        let y: Vec<[f64; 2]> = g_new.iter().zip(&g).map(|(a, c)| [a[0] - c[0], a[1] - c[1]]).collect();
        let sy = dot(&s, &y);
        if sy > 1e-12 * dot(&s, &s).sqrt() * dot(&y, &y).sqrt() {
            if pairs.len() == MEMORY {
                pairs.pop_front();
            }
            pairs.push_back(Pair { s, y, rho: 1.0 / sy });
        }
        iterations += 1;
        history.push(e);
        observer(&BoundaryStep { iteration: iterations, energy: e, uv: &uv });
        let decrease = energy - e;
        energy = e;
        g = g_new;
        if decrease <= options.tolerance * energy {
            converged = true;
            break;
        }
    }
    progress.report(1.0)?;
    Ok(BoundaryOptimizedMap {
        uv,
        boundary: editor.boundary_vertices().to_vec(),
        boundary_uv: b,
        history,
        iterations,
        converged,
        flipped,
        boundary_scale,
    })
}

/// One exact, orientation-preserving line search from `uv` (energy `energy`, boundary gradient
/// `g`): the step `t` and the boundary direction, or `None` when neither the L-BFGS nor the
/// steepest-descent direction lowers the energy.
#[allow(clippy::too_many_arguments)]
fn line_search(
    editor: &BoundaryEditor,
    terms: &DistortionTerms,
    kind: DistortionEnergy,
    oriented: &[[u32; 3]],
    uv: &[[f64; 2]],
    energy: f64,
    g: &[[f64; 2]],
    pairs: &mut VecDeque<Pair>,
) -> Result<Option<(f64, Vec<[f64; 2]>)>> {
    loop {
        let steepest = pairs.is_empty();
        let mut d = lbfgs_direction(pairs, g);
        if !(dot(&d, g) < 0.0) {
            if steepest {
                return Ok(None);
            }
            pairs.clear();
            continue;
        }
        let response = editor.solve(&d)?;
        let limit = MAX_STEP_FRACTION * max_flip_free_step(oriented, uv, &response);
        let polynomial = terms.along_line(kind, uv, &response);
        let mut t = match polynomial.minimum_on(0.0, limit) {
            Some((t, _)) if t > 0.0 => t,
            _ => 0.0,
        };
        for _ in 0..MAX_HALVINGS {
            if !(t > 0.0) {
                break;
            }
            let candidate = moved(uv, t, &response);
            if terms.energy(kind, &candidate) < energy && keeps_orientation(oriented, &candidate) {
                return Ok(Some((t, std::mem::take(&mut d))));
            }
            t *= 0.5;
        }
        if steepest {
            return Ok(None);
        }
        pairs.clear();
    }
}
