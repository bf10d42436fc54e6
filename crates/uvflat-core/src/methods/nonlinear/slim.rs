//! SLIM: Scalable Locally Injective Mappings (Rabinovich, Poranne, Panozzo, Sorkine-Hornung
//! 2017), minimizing the symmetric Dirichlet energy `σ1² + σ1⁻² + σ2² + σ2⁻²` (area-weighted
//! mean) with a free boundary.
//!
//! Each iteration (Rabinovich et al. §4, Alg. 1) replaces the energy by a weighted ARAP-like
//! proxy around the current map, `Σ_t (A_t/A) ‖W_t (J_t − R_t)‖²_F`, with `R_t = U Vᵀ` the
//! closest rotation and `W_t = U diag(w1, w2) Uᵀ`, `w_i² = f'(σ_i) / (2(σ_i − 1))` (eq. 8–9),
//! which makes the proxy's gradient equal the energy's at the current map. For the symmetric
//! Dirichlet energy `w_i² = (σ_i + 1)(σ_i² + 1)/σ_i³`, smooth at σ = 1 (value 4).
//! The proxy is quadratic; its minimizer solves a sparse symmetric positive definite system
//! over the 2n UV unknowns whose entry for corners k, l and coordinates r, s of triangle t is
//! `(A_t/A) (W_tᵀW_t)_{rs} (g_k · g_l)`, right-hand side `(A_t/A) (WᵀW R)_t g_k`. Its sparsity
//! pattern never changes, so the fill-reducing ordering (nested dissection of the vertex graph,
//! u and v of a vertex kept together) and the symbolic factorization are computed once; each
//! iteration refills the values in place and factors numerically. A tiny proximal term
//! `δ‖x − x_current‖²` removes the translations from the kernel (the boundary is free).
//!
//! The proxy minimizer gives the search direction, and the flip-free line search
//! ([`super::line_search`]) picks the step (§4.3), so every iterate is locally injective and
//! the energy decreases monotonically.

use super::energy::Energy;
use super::jacobian::{RestFrames, Svd2};
use super::{descend_while, NonlinearOptions, Problem, Run};
use crate::error::{Error, Result};
use crate::progress::Progress;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::Mat;
use rayon::prelude::*;
use uvflat_sparse::{lower_from_entries, ordering, CholeskyPattern};

/// Local unknowns of a triangle: `2k + r` for corner k, coordinate r.
pub(super) const LOCAL: usize = 6;
/// Pairs `i ≤ j` of local unknowns.
pub(super) const PAIRS: usize = LOCAL * (LOCAL + 1) / 2;

/// The SLIM system's fixed structure: pattern, symbolic factorization, and where each
/// triangle's entries go. Unknowns are the UVs of vertices `0..n`; a triangle corner with an
/// index ≥ n is a fixed point (its couplings go to the right-hand side).
pub(super) struct SlimSystem {
    symbolic: SymbolicSparseColMat<usize>,
    pattern: CholeskyPattern,
    /// Value slot of each local pair `(i, j)`, `i ≤ j`, of each triangle (`FIXED` where either
    /// unknown is fixed).
    slots: Vec<[u32; PAIRS]>,
    /// Value slot of each unknown's diagonal entry.
    diagonal: Vec<usize>,
    /// Number of free vertices.
    n: usize,
}

/// Slot of a pair with a fixed unknown.
const FIXED: u32 = u32::MAX;

pub(super) fn local_pairs() -> [(usize, usize); PAIRS] {
    let mut out = [(0, 0); PAIRS];
    let mut n = 0;
    for i in 0..LOCAL {
        for j in i..LOCAL {
            out[n] = (i, j);
            n += 1;
        }
    }
    out
}

impl SlimSystem {
    /// The system of the triangles `tris` over the free vertices `0..n`, eliminated in `order`
    /// (one entry per unknown, see [`interleaved_order`]).
    pub(super) fn new(n: usize, tris: &[[u32; 3]], order: Vec<usize>) -> Result<Self> {
        let global = |tri: &[u32; 3], i: usize| 2 * tri[i / 2] as usize + i % 2;
        let free = |tri: &[u32; 3], i: usize| (tri[i / 2] as usize) < n;
        let pairs = local_pairs();
        // Pattern of the 2n × 2n lower triangle.
        let mut entries = Vec::with_capacity(15 * tris.len());
        for tri in tris {
            for &(i, j) in &pairs {
                let (a, b) = (global(tri, i), global(tri, j));
                if a != b && free(tri, i) && free(tri, j) {
                    entries.push((a.max(b) as u32, a.min(b) as u32, 0.0));
                }
            }
        }
        let lower = lower_from_entries(&vec![0.0; 2 * n], entries)?;
        let symbolic =
            lower.symbolic().to_owned().map_err(|_| Error::Internal("out of memory for the SLIM pattern".into()))?;
        let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
        let slot = |a: usize, b: usize| -> Result<u32> {
            let (r, c) = (a.max(b), a.min(b));
            let range = col_ptr[c]..col_ptr[c + 1];
            match row_idx[range.clone()].binary_search(&r) {
                Ok(k) => Ok((range.start + k) as u32),
                Err(_) => Err(Error::Internal(format!("SLIM pattern misses entry ({r}, {c})"))),
            }
        };
        let slots = tris
            .iter()
            .map(|tri| {
                let mut s = [FIXED; PAIRS];
                for (k, &(i, j)) in pairs.iter().enumerate() {
                    if free(tri, i) && free(tri, j) {
                        s[k] = slot(global(tri, i), global(tri, j))?;
                    }
                }
                Ok(s)
            })
            .collect::<Result<Vec<_>>>()?;
        let diagonal = (0..2 * n).map(|c| col_ptr[c]).collect();
        let pattern = CholeskyPattern::with_order(symbolic.as_ref(), Some(order))?;
        Ok(SlimSystem { symbolic, pattern, slots, diagonal, n })
    }

    /// Minimizes the proxy whose blocks are `blocks` (one per triangle of `tris`, the triangles
    /// the system was built with) and returns the step from `x` to the minimizer for the free
    /// vertices; `x` holds the free vertices' UVs, then the fixed points'. A tiny proximal term
    /// `δ‖y − x‖²` removes the translations from the kernel when nothing is fixed.
    pub(super) fn direction(&self, tris: &[[u32; 3]], blocks: &[ProxyBlock], x: &[[f64; 2]]) -> Result<Vec<[f64; 2]>> {
        let n = self.n;
        let pairs = local_pairs();
        let mut values = vec![0.0; self.symbolic.row_idx().len()];
        let mut rhs = Mat::<f64>::zeros(2 * n, 1);
        let global = |tri: &[u32; 3], i: usize| 2 * tri[i / 2] as usize + i % 2;
        for ((tri, slots), (v, b)) in tris.iter().zip(&self.slots).zip(blocks) {
            for k in 0..PAIRS {
                if slots[k] != FIXED {
                    values[slots[k] as usize] += v[k];
                    continue;
                }
                // A coupling with a fixed point: −A_ij x_j on the free side's right-hand side.
                let (i, j) = pairs[k];
                let (fi, fj) = ((tri[i / 2] as usize) < n, (tri[j / 2] as usize) < n);
                if fi {
                    rhs[(global(tri, i), 0)] -= v[k] * x[tri[j / 2] as usize][j % 2];
                }
                if fj {
                    rhs[(global(tri, j), 0)] -= v[k] * x[tri[i / 2] as usize][i % 2];
                }
            }
            for i in 0..LOCAL {
                if (tri[i / 2] as usize) < n {
                    rhs[(global(tri, i), 0)] += b[i];
                }
            }
        }
        let delta = 1e-8 * self.diagonal.iter().map(|&s| values[s]).sum::<f64>() / (2 * n).max(1) as f64;
        for (c, &s) in self.diagonal.iter().enumerate() {
            values[s] += delta;
            rhs[(c, 0)] += delta * x[c / 2][c % 2];
        }
        let matrix = SparseColMat::new(self.symbolic.clone(), values);
        self.pattern.factor(&matrix)?.solve_in_place(&mut rhs)?;
        let d: Vec<[f64; 2]> = (0..n).map(|v| [rhs[(2 * v, 0)] - x[v][0], rhs[(2 * v + 1, 0)] - x[v][1]]).collect();
        uvflat_sparse::require_finite(d.iter().flatten().copied(), "SLIM")?;
        Ok(d)
    }
}

/// Elimination order of the 2n UV unknowns: nested dissection of the vertex graph by multilevel
/// bisection at every level (`Options::thorough`: the system is refactored every iteration, so
/// a smaller factor pays for the slower ordering), then u and v of each vertex consecutively.
/// Measured with `uvflat unwrap --method slim`, four alternating pairs against plane splits
/// below 20,000 vertices: disk_bimba_cut (89k faces) median 13.6 -> 10.9 s,
/// disk_face_libigl_loop1 (207k) 12.6 -> 10.9 s, disk_mountain (51k) unchanged; same maps to
/// rounding.
pub(super) fn interleaved_order(problem: &Problem) -> Result<Vec<usize>> {
    let vertex_pattern = vertex_graph_lower(problem)?;
    let adjacency = ordering::Adjacency::from_lower(problem.n(), vertex_pattern.col_ptr(), vertex_pattern.row_idx());
    Ok(ordering::nested_dissection_with(&adjacency, Some(&problem.coords), &ordering::Options::thorough())
        .iter()
        .flat_map(|&v| [2 * v, 2 * v + 1])
        .collect())
}

/// Lower-triangular pattern of the vertex graph (for the ordering).
fn vertex_graph_lower(problem: &Problem) -> Result<SymbolicSparseColMat<usize>> {
    let mut entries = Vec::with_capacity(3 * problem.tris.len());
    for t in &problem.tris {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            entries.push((a.max(b), a.min(b), 0.0));
        }
    }
    let m = lower_from_entries(&vec![0.0; problem.n()], entries)?;
    m.symbolic().to_owned().map_err(|_| Error::Internal("out of memory for the vertex graph".into()))
}

/// SLIM weights `w_i² = (σ + 1)(σ² + 1)/σ³` of the symmetric Dirichlet energy.
#[inline]
fn weight2(s: f64) -> f64 {
    (s + 1.0) * (s * s + 1.0) / (s * s * s)
}

/// One triangle's share of the SLIM proxy: the 21 matrix values of its pairs of local unknowns
/// (`local_pairs` order) and its 6 right-hand side values.
pub(super) type ProxyBlock = ([f64; PAIRS], [f64; LOCAL]);

/// The proxy's blocks of every triangle of `tris` under the map `x`, each weighted by
/// `frames.area[t] × inv` (eq. 8–9 of the module docs).
pub(super) fn proxy_blocks(frames: &RestFrames, tris: &[[u32; 3]], x: &[[f64; 2]], inv: f64) -> Vec<ProxyBlock> {
    let pairs = local_pairs();
    tris.par_iter()
        .enumerate()
        .with_min_len(1024)
        .map(|(t, &tri)| {
            let svd = Svd2::new(&frames.jacobian(t, tri, x));
            let w = frames.area[t] * inv;
            let c = svd.left_symmetric(weight2(svd.s1), weight2(svd.s2));
            let r = svd.rotation();
            let cr = [
                [c[0][0] * r[0][0] + c[0][1] * r[1][0], c[0][0] * r[0][1] + c[0][1] * r[1][1]],
                [c[1][0] * r[0][0] + c[1][1] * r[1][0], c[1][0] * r[0][1] + c[1][1] * r[1][1]],
            ];
            let g = &frames.grad[t];
            let mut values = [0.0; PAIRS];
            for (k, &(i, j)) in pairs.iter().enumerate() {
                let (ki, ri, kj, rj) = (i / 2, i % 2, j / 2, j % 2);
                values[k] = w * c[ri][rj] * (g[ki][0] * g[kj][0] + g[ki][1] * g[kj][1]);
            }
            let mut rhs = [0.0; LOCAL];
            for i in 0..LOCAL {
                let (k, r) = (i / 2, i % 2);
                rhs[i] = w * (cr[r][0] * g[k][0] + cr[r][1] * g[k][1]);
            }
            (values, rhs)
        })
        .collect()
}

/// Runs SLIM from the flip-free map `x0`.
pub(crate) fn minimize(
    problem: &Problem,
    x0: Vec<[f64; 2]>,
    options: &NonlinearOptions,
    progress: &mut Progress,
) -> Result<Run> {
    minimize_while(problem, x0, options, progress, |_| true).map(|(run, _)| run)
}

/// [`minimize`] that stops before the first iterate `keep` refuses (see [`descend_while`]).
pub(crate) fn minimize_while(
    problem: &Problem,
    x0: Vec<[f64; 2]>,
    options: &NonlinearOptions,
    progress: &mut Progress,
    keep: impl FnMut(&[[f64; 2]]) -> bool,
) -> Result<(Run, bool)> {
    let system = SlimSystem::new(problem.n(), &problem.tris, interleaved_order(problem)?)?;
    let inv = 1.0 / problem.frames.total_area;
    let direction = |x: &[[f64; 2]], _grad: &[[f64; 2]], reset: bool| {
        if reset {
            return Ok(None);
        }
        let blocks = proxy_blocks(&problem.frames, &problem.tris, x, inv);
        system.direction(&problem.tris, &blocks, x).map(Some)
    };
    descend_while(problem, Energy::SymmetricDirichlet, x0, options, progress, direction, keep)
}
