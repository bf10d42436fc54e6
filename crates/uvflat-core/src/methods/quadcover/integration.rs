//! QuadCover, step 3: integrating the frame field into a parameterization on the covering
//! (Kälberer, Nieser & Polthier 2007; course notes §8.3, eq. 8.6:
//! minimize E(f) = ∫ |∇f − K|² dA over the covering). The minimizer's gradient is the gradient
//! and harmonic part of the Hodge decomposition K = P_K + C_K + H_K (eq. 8.7) with the
//! co-gradient part C_K discarded, so solving the normal equations of eq. 8.6 performs steps 1,
//! 2 and 4 of the notes' outline at once.
//!
//! Discretization: f is piecewise linear on the cut mesh, each copy written as an affine
//! function of the unknowns ([`super::covering`]); K is the combed frame per triangle scaled
//! by 1/h (h the grid spacing): ∇u ≈ X₀/h, ∇v ≈ X₁/h. Per triangle, with the gradients ∇φ_i
//! of the hat functions, `A |Σ_i s_i ∇φ_i − X|² = Σ_ij A ∇φ_i·∇φ_j s_i s_j − 2 Σ_i A ∇φ_i·X s_i
//! + A|X|²` (the cotangent stiffness and the divergence of X).
//!
//! Global continuity (§8.3.1): the gaps of the first solve are rounded to integers and the map
//! solved again with them fixed — the notes' harmonic correction ψ with gaps round(d_i) − d_i,
//! added to f⁰, is exactly the minimizer of eq. 8.6 under the rounded gaps.

use super::covering::Covering;
use super::guards::{other_integer, rounding_guards, Guard};
use crate::error::{Error, Result};
use crate::geometry::{cross, dot, norm, sub};
use crate::mesh::cut::Cut;
use crate::metrics::signed_uv_area;
use crate::progress::Progress;
use crate::TriMesh;
use faer::linalg::solvers::{DenseSolveCore, Solve};
use faer::{Mat, Side};
use uvflat_sparse::{require_finite, CholeskySolver, TripletBuilder};

/// Per triangle: its area and the gradients of its three hat functions (zero for a degenerate
/// triangle, which then adds nothing to the energy).
fn hat_gradients(mesh: &TriMesh, t: usize) -> (f64, [[f64; 3]; 3]) {
    let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
    let nn = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let twice_area = norm(nn);
    if twice_area <= f64::MIN_POSITIVE {
        return (0.0, [[0.0; 3]; 3]);
    }
    let n = nn.map(|x| x / twice_area);
    let grads = std::array::from_fn(|i| cross(n, sub(p[(i + 2) % 3], p[(i + 1) % 3])).map(|x| x / twice_area));
    (0.5 * twice_area, grads)
}

/// The two target gradients of triangle t: X₀/h and (n × X₀)/h.
fn targets(mesh: &TriMesh, frames: &[[f64; 3]], t: usize, scale: f64) -> [[f64; 3]; 2] {
    let n = crate::fields::frames::triangle_normal(mesh, t);
    [frames[t].map(|x| x * scale), cross(n, frames[t]).map(|x| x * scale)]
}

/// The normal equations of eq. 8.6 split between the real unknowns (v: vertex positions,
/// numbered first by [`Covering`]) and the integer ones (z: gaps and cone coordinates).
struct Blocks {
    /// Lower triangle of H_vv.
    hvv: TripletBuilder<f64>,
    /// Column k of H_vz, sparse.
    hvz: Vec<Vec<(u32, f64)>>,
    /// H_zz, dense.
    hzz: Mat<f64>,
    bv: Mat<f64>,
    bz: Vec<f64>,
    /// A surface point per real unknown (for the fill-reducing order).
    coords: Vec<[f64; 3]>,
}

/// Assembles eq. 8.6 over all unknowns of `covering` (module comment).
fn assemble(
    mesh: &TriMesh,
    cut: &Cut,
    frames: &[[f64; 3]],
    scale: f64,
    covering: &Covering,
    weights: Option<&[f64]>,
    lattice_block: bool,
) -> Blocks {
    let (m, nv) = (covering.lattice_len(), covering.vertex_unknowns);
    let mz = if lattice_block { m } else { 0 };
    let mut b = Blocks {
        hvv: TripletBuilder::with_capacity(nv, 20 * mesh.triangle_count()),
        hvz: vec![Vec::new(); m],
        hzz: Mat::zeros(mz, mz),
        bv: Mat::zeros(nv, 1),
        bz: vec![0.0; m],
        coords: vec![[0.0; 3]; nv],
    };
    for (c, rows) in covering.rows.iter().enumerate() {
        let p = mesh.points()[cut.original[c] as usize];
        for &(k, _) in rows.iter().flatten().filter(|&&(k, _)| (k as usize) < nv) {
            b.coords[k as usize] = p;
        }
    }
    for t in 0..mesh.triangle_count() {
        let (area, grads) = hat_gradients(mesh, t);
        let area = area * weights.map_or(1.0, |w| w[t]);
        let corners = cut.triangles[t];
        for (comp, x) in targets(mesh, frames, t, scale).iter().enumerate() {
            for i in 0..3 {
                let g = area * dot(grads[i], *x);
                for &(a, ca) in &covering.rows[corners[i] as usize][comp] {
                    let a = a as usize;
                    if a < nv {
                        b.bv[(a, 0)] += g * ca;
                    } else {
                        b.bz[a - nv] += g * ca;
                    }
                    for j in 0..3 {
                        let k = area * dot(grads[i], grads[j]);
                        for &(bb, cb) in &covering.rows[corners[j] as usize][comp] {
                            let bb = bb as usize;
                            let value = k * ca * cb;
                            match (a < nv, bb < nv) {
                                (true, true) if bb <= a => b.hvv.add(a, bb, value),
                                (false, true) => b.hvz[a - nv].push((bb as u32, value)),
                                (false, false) if lattice_block => b.hzz[(a - nv, bb - nv)] += value,
                                _ => {}
                            }
                        }
                    }
                }
            }
        }
    }
    b
}

/// The two solves of QuadCover: the continuous minimizer of eq. 8.6 and, with `round`, the
/// minimizer with every integer unknown rounded (§8.3.1). Returns (continuous, final, largest
/// distance of a continuous integer unknown to its integer).
///
/// One sparse factorization of H_vv serves both: the integer unknowns are few (gaps and cone
/// coordinates), so the energy is reduced onto them exactly (Schur complement
/// S = H_zz − H_zv H_vv⁻¹ H_vz, one solve per integer unknown). They are then rounded one at a
/// time, the one closest to its integer first, the others re-optimized after each (the greedy
/// order of Bommes, Zimmer & Kobbelt 2009, "Mixed-integer quadrangulation", §4; the course
/// notes round all at once, which folds the map where cones are close): with P = S⁻¹, fixing
/// z_k = a moves the optimum by (a − z_k) P e_k / P_kk and P loses row and column k
/// (P ← P − P e_k e_kᵀ P / P_kk), O(m²) per step; where an unknown would put two cones of a
/// triangle on one grid point, it is rounded the other way ([`super::guards`]). Then folded
/// triangles are stiffened (vertex positions solved again with their weights raised,
/// [`Problem::stiffen`]) and, while that
/// leaves folds, the whole problem is solved and rounded again with those weights
/// ([`REROUNDING_ROUNDS`]).
#[allow(clippy::too_many_arguments)]
pub fn integrate(
    mesh: &TriMesh,
    cut: &Cut,
    frames: &[[f64; 3]],
    scale: f64,
    covering: &Covering,
    round: bool,
    progress: &mut Progress,
    span: (f64, f64),
) -> Result<(Vec<f64>, Vec<f64>, f64)> {
    let guards = rounding_guards(cut, covering);
    let problem = Problem { mesh, cut, frames, scale, covering, guards };
    let at = |f: f64| span.0 + (span.1 - span.0) * f;
    let first = problem.solve(None, round, progress, (at(0.0), at(0.6)))?;
    let Some((z, rounded)) = first.rounded else {
        return Ok((first.continuous.clone(), first.continuous, first.offset));
    };
    progress.report(at(0.6))?;
    let mut best = problem.stiffen(&z, rounded, vec![1.0; mesh.triangle_count()], progress, (at(0.6), at(0.7)))?;
    // Re-rounding (the stiffening of Bommes, Zimmer & Kobbelt 2009 §5 re-solves the whole
    // mixed-integer problem): the folded triangles' weights (×4 per round) enter the solve
    // and the greedy rounding again, so the gaps can round the other way around them; it stops
    // at the first round that does not fold fewer triangles.
    let mut weights = vec![1.0; mesh.triangle_count()];
    let rounds = REROUNDING_ROUNDS;
    for r in 0..rounds {
        let flips = problem.folded(&best.0);
        if flips.is_empty() {
            break;
        }
        for &t in &flips {
            weights[t] *= 4.0;
        }
        let step = 0.3 / rounds as f64;
        let again = problem.solve(
            Some(&weights),
            true,
            progress,
            (at(0.7 + step * r as f64), at(0.7 + step * (r as f64 + 0.7))),
        )?;
        let Some((z, rounded)) = again.rounded else { break };
        let candidate = problem.stiffen(
            &z,
            rounded,
            weights.clone(),
            progress,
            (at(0.7 + step * (r as f64 + 0.7)), at(0.7 + step * (r as f64 + 1.0))),
        )?;
        if candidate.1 >= best.1 {
            break;
        }
        best = candidate;
    }
    Ok((first.continuous, best.0, first.offset))
}

/// The integration problem of one covering.
struct Problem<'a> {
    mesh: &'a TriMesh,
    cut: &'a Cut,
    frames: &'a [[f64; 3]],
    scale: f64,
    covering: &'a Covering,
    /// The triangles the rounding alone could flatten ([`super::guards`]).
    guards: Vec<Guard>,
}

/// One mixed-integer solve: the continuous minimizer, the largest distance of its integer
/// unknowns to an integer, and with rounding the rounded lattice unknowns and all unknowns.
struct Solution {
    continuous: Vec<f64>,
    offset: f64,
    rounded: Option<(Vec<f64>, Vec<f64>)>,
}

impl Problem<'_> {
    /// Minimizes eq. 8.6 (triangles weighted by `weights`) and, with `round`, again with every
    /// integer unknown rounded greedily ([`integrate`]).
    fn solve(
        &self,
        weights: Option<&[f64]>,
        round: bool,
        progress: &mut Progress,
        span: (f64, f64),
    ) -> Result<Solution> {
        let (mesh, covering) = (self.mesh, self.covering);
        let mut blocks = assemble(mesh, self.cut, self.frames, self.scale, covering, weights, true);
        let (m, nv) = (blocks.hzz.nrows(), blocks.bv.nrows());
        let solver = CholeskySolver::new(&blocks.hvv.build()?, Some(&blocks.coords))
            .map_err(|e| Error::Numerical(format!("QuadCover: the integration system could not be factored: {e}")))?;
        let mut hinv_b = blocks.bv.clone();
        solver.solve_in_place(&mut hinv_b)?;
        // S and c = b_z − H_zv H_vv⁻¹ b_v over all lattice scalars, in blocks of columns.
        let mut s = std::mem::replace(&mut blocks.hzz, Mat::zeros(0, 0));
        let c = Mat::<f64>::from_fn(m, 1, |i, _| blocks.bz[i] - sparse_dot(&blocks.hvz[i], &hinv_b, 0));
        const BLOCK: usize = 32;
        for k0 in (0..m).step_by(BLOCK) {
            let w = BLOCK.min(m - k0);
            let mut x = Mat::<f64>::zeros(nv, w);
            for j in 0..w {
                for &(r, value) in &blocks.hvz[k0 + j] {
                    x[(r as usize, j)] += value;
                }
            }
            solver.solve_in_place(&mut x)?;
            for i in 0..m {
                for j in 0..w {
                    s[(i, k0 + j)] -= sparse_dot(&blocks.hvz[i], &x, j);
                }
            }
            progress.report(span.0 + (span.1 - span.0) * 0.9 * (k0 + w) as f64 / m as f64)?;
        }
        // Onto the free lattice scalars: z = D w.
        let mut d = Mat::<f64>::zeros(m, covering.free_lattice);
        for (k, row) in covering.lattice.iter().enumerate() {
            for &(j, x) in row {
                d[(k, j as usize)] += x;
            }
        }
        let sw = d.transpose() * (&s * &d);
        let cw = d.transpose() * &c;
        let (w_continuous, p) = reduced_minimizer(&sw, &cw)?;
        let lattice_of = |w: &[f64]| -> Vec<f64> {
            let wm = Mat::<f64>::from_fn(w.len(), 1, |i, _| w[i]);
            let z = &d * &wm;
            (0..m).map(|k| z[(k, 0)]).collect()
        };
        let continuous = real_unknowns(&solver, &blocks, &lattice_of(&w_continuous))?;
        let offset = w_continuous
            .iter()
            .zip(&covering.free_integer)
            .filter(|(_, &integer)| integer)
            .map(|(z, _)| (z - z.round()).abs())
            .fold(0.0, f64::max);
        if !round || w_continuous.is_empty() {
            return Ok(Solution { continuous, offset, rounded: None });
        }
        // The nearest-first rounding, and where it puts cones of a triangle on one grid point
        // the guarded one too ([`super::guards`]); the one expected to fold less after the
        // untangling is kept ([`expected_folds`]).
        let guards = &self.guards;
        let w = greedy_rounding(w_continuous.clone(), p.clone(), &covering.free_integer, &[])?;
        let z = lattice_of(&w);
        let mut rounded = real_unknowns(&solver, &blocks, &z)?;
        let flat = violated(guards, &w);
        let mut best = (z, expected_folds(self.folded(&rounded).len(), flat));
        if flat > 0 {
            let wg = greedy_rounding(w_continuous, p, &covering.free_integer, guards)?;
            let zg = lattice_of(&wg);
            let guarded = real_unknowns(&solver, &blocks, &zg)?;
            let score = expected_folds(self.folded(&guarded).len(), violated(guards, &wg));
            if score < best.1 {
                best = (zg, score);
                rounded = guarded;
            }
        }
        Ok(Solution { continuous, offset, rounded: Some((best.0, rounded)) })
    }

    /// Triangles whose (u, v) image is not positively oriented.
    fn folded(&self, values: &[f64]) -> Vec<usize> {
        corner_uv(self.cut, self.covering, values)
            .iter()
            .enumerate()
            .filter(|(_, q)| signed_uv_area(**q) <= 0.0)
            .map(|(t, _)| t)
            .collect()
    }

    /// Local stiffening (Bommes, Zimmer & Kobbelt 2009, §5, read for the idea): with the
    /// lattice unknowns `z` kept, the weight of every folded triangle is multiplied by 4 and the
    /// real unknowns solved again, for up to [`STIFFENING_ROUNDS`] rounds, from `weights`; the
    /// result with the fewest folds is kept (the seams stay exact: only vertex positions move).
    /// Returns it and its fold count.
    fn stiffen(
        &self,
        z: &[f64],
        values: Vec<f64>,
        mut weights: Vec<f64>,
        progress: &mut Progress,
        span: (f64, f64),
    ) -> Result<(Vec<f64>, usize)> {
        let mut flips = self.folded(&values);
        let (mut best, mut best_count) = (values, flips.len());
        for round in 0..STIFFENING_ROUNDS {
            if flips.is_empty() {
                break;
            }
            progress.report(span.0 + (span.1 - span.0) * round as f64 / STIFFENING_ROUNDS as f64)?;
            for &t in &flips {
                weights[t] *= 4.0;
            }
            // Only H_vv, b_v and H_vz are needed with the lattice fixed.
            let blocks = assemble(self.mesh, self.cut, self.frames, self.scale, self.covering, Some(&weights), false);
            let solver = CholeskySolver::new(&blocks.hvv.build()?, Some(&blocks.coords))
                .map_err(|e| Error::Numerical(format!("QuadCover: the stiffened system could not be factored: {e}")))?;
            let values = real_unknowns(&solver, &blocks, z)?;
            flips = self.folded(&values);
            if flips.len() < best_count {
                best_count = flips.len();
                best = values;
            }
        }
        Ok((best, best_count))
    }
}

/// Guards (triangles with two or more fixed corners) that the free lattice scalars `w` violate.
fn violated(guards: &[Guard], w: &[f64]) -> usize {
    guards.iter().filter(|g| g.violated(|j| w[j as usize])).count()
}

/// Share of the folds with a free corner that the untangling opened over the 15 meshes of the
/// table in docs/methods/quadcover.md (148 of 187; [`super::untangle`]).
const UNTANGLED_SHARE: f64 = 0.79;

/// Folds expected after the untangling: the triangles flat whatever the vertices (`flat`, all
/// of them among `folded`) stay, of the others about a fifth ([`UNTANGLED_SHARE`]).
fn expected_folds(folded: usize, flat: usize) -> f64 {
    flat as f64 + (1.0 - UNTANGLED_SHARE) * folded.saturating_sub(flat) as f64
}

/// Rounds of re-rounding in [`integrate`] at most. Measured on the 15 meshes of docs/methods/quadcover.md
/// table: folded triangles 354 → 337 (spot 14 → 0, bunny 2 → 1, knight 128 → 126; cow and man,
/// whose folds come from the continuous solve, unchanged), man 4.7 → 8.0 s; without stopping
/// at the first round that does not help, 331 folds and man 13.4 s.
const REROUNDING_ROUNDS: usize = 3;

/// Rounds of [`Problem::stiffen`].
const STIFFENING_ROUNDS: usize = 8;

/// Σ value · x[row, col] over a sparse column.
fn sparse_dot(column: &[(u32, f64)], x: &Mat<f64>, col: usize) -> f64 {
    column.iter().map(|&(r, value)| value * x[(r as usize, col)]).sum()
}

/// Minimizer of ½ wᵀ S w − cᵀ w and S⁻¹. Unknowns that no triangle sees (a zero row of S, e.g.
/// the gap of a chain every vertex of which is fixed by others) are fixed at 0 first.
fn reduced_minimizer(s: &Mat<f64>, c: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>)> {
    let m = s.nrows();
    let scale = (0..m).map(|i| s[(i, i)].abs()).fold(0.0, f64::max);
    let live: Vec<usize> = (0..m).filter(|&i| s[(i, i)] > 1e-12 * scale).collect();
    let mut w = vec![0.0; m];
    let mut p = Mat::<f64>::zeros(m, m);
    if live.is_empty() {
        return Ok((w, p));
    }
    let sl = Mat::<f64>::from_fn(live.len(), live.len(), |i, j| s[(live[i], live[j])]);
    let llt = sl.llt(Side::Lower).map_err(|_| {
        Error::Numerical("QuadCover: the energy reduced onto the gaps and cones is not positive definite".into())
    })?;
    let pl = llt.inverse();
    for (i, &a) in live.iter().enumerate() {
        w[a] = live.iter().enumerate().map(|(j, &b)| pl[(i, j)] * c[(b, 0)]).sum();
        for (j, &b) in live.iter().enumerate() {
            p[(a, b)] = pl[(i, j)];
        }
    }
    require_finite(w.iter().copied(), "QuadCover gaps")?;
    Ok((w, p))
}

/// Free integer unknowns above which [`greedy_rounding`] rounds them in batches.
const BATCH_ABOVE: usize = 256;

/// Greedy rounding (see [`integrate`]). Above [`BATCH_ABOVE`] free unknowns, the closest
/// sixteenth of them is rounded together (block conditioning: z_r += P_rk P_kk⁻¹ (a − z_k),
/// P_rr ← P_rr − P_rk P_kk⁻¹ P_kr), so that the whole costs O(m³) once rather than per unknown.
fn greedy_rounding(mut z: Vec<f64>, mut p: Mat<f64>, integer: &[bool], guards: &[Guard]) -> Result<Vec<f64>> {
    // p is S⁻¹ restricted to the still free unknowns `free` (in that order); unknowns no
    // triangle sees are 0 already. Real (non-integer) unknowns are only re-optimized.
    let mut free: Vec<usize> = (0..z.len()).filter(|&i| p[(i, i)] > 0.0).collect();
    p = Mat::from_fn(free.len(), free.len(), |i, j| p[(free[i], free[j])]);
    let distance = |x: f64| (x - x.round()).abs();
    let mut guards_of: Vec<Vec<usize>> = vec![Vec::new(); z.len()];
    for (g, guard) in guards.iter().enumerate() {
        for &j in &guard.depends {
            guards_of[j as usize].push(g);
        }
    }
    let mut rounded = vec![false; z.len()];
    loop {
        let f = free.len();
        let candidates = (0..f).filter(|&a| integer[free[a]]).count();
        if candidates == 0 {
            break;
        }
        let batch = if candidates > BATCH_ABOVE { candidates / 16 } else { 1 };
        let mut order: Vec<usize> = (0..f).collect();
        // Integer unknowns first, closest to their integer first.
        order.sort_by(|&a, &b| {
            (!integer[free[a]], distance(z[free[a]]))
                .partial_cmp(&(!integer[free[b]], distance(z[free[b]])))
                .unwrap_or(std::cmp::Ordering::Equal)
                .then(a.cmp(&b))
        });
        let (chosen, rest) = order.split_at(batch);
        let chosen_unknowns: Vec<usize> = chosen.iter().map(|&k| free[k]).collect();
        let variance: Vec<f64> = chosen.iter().map(|&k| p[(k, k)]).collect();
        let targets = guarded_integers(&z, &chosen_unknowns, &variance, &rounded, guards, &guards_of);
        let delta = Mat::<f64>::from_fn(batch, 1, |i, _| targets[i] - z[chosen_unknowns[i]]);
        let pkk = Mat::<f64>::from_fn(batch, batch, |i, j| p[(chosen[i], chosen[j])]);
        let prk = Mat::<f64>::from_fn(rest.len(), batch, |i, j| p[(rest[i], chosen[j])]);
        let llt = pkk
            .llt(Side::Lower)
            .map_err(|_| Error::Numerical("QuadCover: rounding met a singular block of the reduced energy".into()))?;
        let y = llt.solve(&delta);
        let shift = &prk * &y;
        for (i, &r) in rest.iter().enumerate() {
            z[free[r]] += shift[(i, 0)];
        }
        for (&k, &target) in chosen_unknowns.iter().zip(&targets) {
            z[k] = target;
            rounded[k] = true;
        }
        let update = &prk * llt.solve(prk.transpose());
        p = Mat::from_fn(rest.len(), rest.len(), |i, j| p[(rest[i], rest[j])] - update[(i, j)]);
        free = rest.iter().map(|&r| free[r]).collect();
    }
    Ok(z)
}

/// The integers the unknowns `chosen` are rounded to: the nearest, except where they complete
/// guards ([`super::guards`]) that the nearest integers would flatten or fold. Then, while a
/// guard is violated, one chosen unknown of it takes its other integer: the flip that leaves
/// the fewest violated guards and, among those, raises the reduced energy least (fixing z_k at
/// a raises it by (a − z_k)² / 2P_kk; `variance` holds P_kk); a flip is made only when it
/// lowers the number of violated guards, so this ends.
fn guarded_integers(
    z: &[f64],
    chosen: &[usize],
    variance: &[f64],
    rounded: &[bool],
    guards: &[Guard],
    guards_of: &[Vec<usize>],
) -> Vec<f64> {
    let mut targets: Vec<f64> = chosen.iter().map(|&k| z[k].round()).collect();
    let position: std::collections::HashMap<usize, usize> = chosen.iter().enumerate().map(|(i, &k)| (k, i)).collect();
    let mut touched: Vec<usize> = chosen.iter().flat_map(|&k| guards_of[k].iter().copied()).collect();
    touched.sort_unstable();
    touched.dedup();
    touched.retain(|&g| guards[g].depends.iter().all(|&j| rounded[j as usize] || position.contains_key(&(j as usize))));
    if touched.is_empty() {
        return targets;
    }
    let violations = |targets: &[f64]| {
        let value = |j: u32| position.get(&(j as usize)).map_or(z[j as usize], |&i| targets[i]);
        touched.iter().filter(|&&g| guards[g].violated(value)).count()
    };
    // The other choice for unknown i (nearest ↔ second nearest) and what taking it adds to the
    // reduced energy.
    let toggled = |i: usize, t: f64| {
        let x = z[chosen[i]];
        if t == x.round() {
            other_integer(x)
        } else {
            x.round()
        }
    };
    let cost = |i: usize, from: f64, to: f64| {
        let x = z[chosen[i]];
        ((to - x).powi(2) - (from - x).powi(2)) / variance[i]
    };
    let mut count = violations(&targets);
    while count > 0 {
        let mut best: Option<(usize, f64, usize)> = None;
        let candidates =
            touched.iter().flat_map(|&g| guards[g].depends.iter()).filter_map(|&j| position.get(&(j as usize)));
        for &i in candidates {
            let mut trial = targets.clone();
            trial[i] = toggled(i, targets[i]);
            let key = (violations(&trial), cost(i, targets[i], trial[i]));
            if key.0 < count && best.is_none_or(|(c, e, _)| key < (c, e)) {
                best = Some((key.0, key.1, i));
            }
        }
        let Some((c, _, i)) = best else { break };
        targets[i] = toggled(i, targets[i]);
        count = c;
    }
    targets
}

/// All unknowns for the integer ones `z`: the real ones solve H_vv y = b_v − H_vz z.
fn real_unknowns(solver: &CholeskySolver<f64>, blocks: &Blocks, z: &[f64]) -> Result<Vec<f64>> {
    let mut rhs = blocks.bv.clone();
    for (k, column) in blocks.hvz.iter().enumerate() {
        for &(r, value) in column {
            rhs[(r as usize, 0)] -= value * z[k];
        }
    }
    solver.solve_in_place(&mut rhs)?;
    let nv = rhs.nrows();
    require_finite((0..nv).map(|k| rhs[(k, 0)]), "QuadCover parameterization")?;
    Ok((0..nv).map(|k| rhs[(k, 0)]).chain(z.iter().copied()).collect())
}

/// Value of a sparse row.
pub fn evaluate(row: &[(u32, f64)], values: &[f64]) -> f64 {
    row.iter().map(|&(k, x)| x * values[k as usize]).sum()
}

/// Per-corner (u, v) of every input triangle.
pub fn corner_uv(cut: &Cut, covering: &Covering, values: &[f64]) -> Vec<[[f64; 2]; 3]> {
    cut.triangles
        .iter()
        .map(|tri| tri.map(|c| covering.rows[c as usize].each_ref().map(|r| evaluate(r, values))))
        .collect()
}

/// Eq. 8.6 relative to the field's own energy: Σ A |∇f − K|² / Σ A |K|² (0 for a map whose
/// gradients are exactly the field).
pub fn relative_energy(mesh: &TriMesh, frames: &[[f64; 3]], scale: f64, uv: &[[[f64; 2]; 3]]) -> f64 {
    let (mut misfit, mut total) = (0.0, 0.0);
    for (t, q) in uv.iter().enumerate() {
        let (area, grads) = hat_gradients(mesh, t);
        for (comp, x) in targets(mesh, frames, t, scale).iter().enumerate() {
            let g: [f64; 3] = std::array::from_fn(|d| (0..3).map(|i| q[i][comp] * grads[i][d]).sum());
            misfit += area * dot(sub(g, *x), sub(g, *x));
            total += area * dot(*x, *x);
        }
    }
    if total > 0.0 {
        misfit / total
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::quadcover::guards::Guard;

    /// Two fixed corners at (w0, w1) and (w2, w3), independent unknowns of unit variance.
    fn two_cones_guard() -> Guard {
        Guard::new(vec![[vec![(0, 1.0)], vec![(1, 1.0)]], [vec![(2, 1.0)], vec![(3, 1.0)]]])
    }

    #[test]
    fn the_guarded_rounding_keeps_two_cones_off_one_grid_point() {
        let z = vec![0.1, 0.2, 0.3, 0.2];
        let p = Mat::<f64>::identity(4, 4);
        let integer = [true; 4];
        let plain = greedy_rounding(z.clone(), p.clone(), &integer, &[]).unwrap();
        assert_eq!(plain, vec![0.0; 4], "the nearest integers put both corners on the origin");
        let guard = two_cones_guard();
        let guarded = greedy_rounding(z, p, &integer, std::slice::from_ref(&guard)).unwrap();
        assert!(!guard.violated(|j| guarded[j as usize]));
        // The last unknown rounded (farthest from its integer, 0.3) takes its other integer.
        assert_eq!(guarded, vec![0.0, 0.0, 1.0, 0.0]);
    }
}
