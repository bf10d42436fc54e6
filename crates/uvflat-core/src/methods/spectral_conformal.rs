//! Spectral conformal map (Mullen, Tong, Alliez, Desbrun 2008, "Spectral Conformal
//! Parameterization", §3): the free-boundary conformal map without pinned vertices.
//!
//! With `z = u + i·v` per vertex, the conformal energy `E_C(z) = E_D(z) − A(z)` (Dirichlet
//! energy minus signed UV area; Mullen eq. 2–4, the energy of the natural conformal map / LSCM,
//! [`super::conformal`]) is the Hermitian form of `H = L_D − L_A` (`L_C` in the paper). It
//! vanishes on constants (translations), so instead of pinning vertices the map is the
//! minimizer of `z*Hz` under `z*Bz = 1` and `z*Be = 0` — B the diagonal matrix with 1 on the
//! boundary vertices and 0 elsewhere, e the constant vector: the eigenvector of the pencil
//! `H z = λ B z` with the smallest eigenvalue once the translations (λ = 0; in real terms the
//! 2-dimensional null space of constant u and constant v) are excluded. In complex form each
//! eigenvector stands for the whole eigenspace `{a·z}`, which is the map up to rotation and
//! scale.
//!
//! Solver: inverse subspace iteration with one factorization. `K = H + σB` (σ > 0 small, so K
//! is positive definite: a vector with z*Hz = 0 is constant or, on a flat mesh, a similarity of
//! the input, and neither vanishes on the boundary) is factored once (complex sparse Cholesky);
//! each iteration applies `K⁻¹B` to a block of 4 vectors, removes their boundary mean (the
//! B-orthogonal projection off the translations, which K⁻¹B maps to themselves with the
//! largest eigenvalue 1/σ), and takes Rayleigh–Ritz vectors of the pencil (H, B) in the block
//! (a 4 × 4 dense Hermitian eigenproblem). The start is deterministic: the projection ζ of the
//! vertices onto their principal plane, and ζ², ζ³, ζ⁴ (discrete holomorphic-like functions,
//! close to the low eigenvectors; on a flat mesh ζ is the exact answer). The first Ritz vector
//! converges at the rate (λ₁ + σ)/(λ₅ + σ) per iteration; it stops when the normwise backward
//! error `‖Hz − λBz‖ / ((‖H‖∞ + |λ|)‖z‖)` is below the tolerance and no longer halves per
//! iteration (the eigenvector's error is about that residual over the gap λ₂ − λ₁, tiny on
//! nearly developable meshes, so it is driven to the rounding floor). The shift σ is 1e-10 of
//! the mean diagonal of H (λ is scale-free: H holds cotangents, B ones and zeros): far below
//! λ₂ on every mesh tried, and large enough that the factorization's smallest pivots (about σ
//! times the number of boundary vertices) stay far above rounding.
//!
//! The result is placed like the natural conformal map: scaled so its UV area equals the
//! surface area, rotated and translated so that the two boundary vertices farthest apart in 3D
//! are at (0, 0) and on the positive u axis. The eigenproblem depends only on the mesh's angles
//! and connectivity (cotangents, boundary), so the map is invariant, up to this placement, to
//! rigid motions and uniform scaling of the input. Cost: one complex Cholesky factorization of
//! size n and, per iteration, one 4-column solve and one sparse product.

use super::conformal::{default_pins, ConformalSystem};
use crate::error::{Error, Result};
use crate::mesh::{TriMesh, NONE};
use crate::metrics::signed_uv_area;
use crate::progress::Progress;
use faer::linalg::solvers::SelfAdjointEigen;
use faer::sparse::SparseColMat;
use faer::{c64, Mat, Side};
use uvflat_sparse::{require_finite, CholeskySolver};

/// Options of [`spectral_conformal_map`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpectralOptions {
    /// Iteration limit (default 200).
    pub iterations: usize,
    /// Backward-error tolerance of the eigenpair (default 1e-12).
    pub tolerance: f64,
}

impl Default for SpectralOptions {
    fn default() -> Self {
        SpectralOptions { iterations: 200, tolerance: 1e-12 }
    }
}

/// The map and the eigenpair behind it.
#[derive(Debug, Clone)]
pub struct SpectralConformalMap {
    /// One UV per vertex (NaN for unreferenced vertices).
    pub uv: Vec<[f64; 2]>,
    /// The eigenvalue λ of `H z = λ B z` (the conformal energy `z*Hz` of the map normalized to
    /// `z*Bz = 1`, boundary mean 0).
    pub eigenvalue: f64,
    /// Normwise backward error of the eigenpair.
    pub residual: f64,
    /// Iterations done.
    pub iterations: usize,
    /// True when the residual is below the tolerance.
    pub converged: bool,
}

/// Vectors iterated together.
const BLOCK: usize = 4;

type Rows = Vec<[c64; BLOCK]>;

/// The spectral conformal map of `mesh` (connected, genus 0, at least one boundary loop).
pub fn spectral_conformal_map(
    mesh: &TriMesh,
    options: &SpectralOptions,
    progress: &mut Progress,
) -> Result<SpectralConformalMap> {
    if options.iterations == 0 || !(options.tolerance > 0.0) {
        return Err(Error::InvalidArgument(format!(
            "the spectral conformal map needs iterations ≥ 1 and a tolerance > 0 (got {} and {})",
            options.iterations, options.tolerance
        )));
    }
    mesh.require_disk_with_holes()?;
    let system = ConformalSystem::with_pins(mesh, &[])?;
    let n = system.unknowns.count();
    let on_boundary: Vec<bool> = system.unknowns.vertex.iter().map(|&v| mesh.is_boundary_vertex(v)).collect();
    let h = &system.matrix;
    let h_norm = infinity_norm(h);
    progress.report(0.05)?;
    let mut x = start_block(mesh, &system.unknowns.vertex);
    remove_boundary_mean(&mut x, &on_boundary);
    let sigma = shift(h);
    let coords = system.unknowns.positions(mesh);
    let solver = CholeskySolver::new(&shifted(h, &on_boundary, sigma)?, Some(&coords))?;
    progress.report(0.3)?;
    let order: Vec<usize> = solver.elimination_order().map_or_else(|| (0..n).collect(), |o| o.to_vec());
    // B x is zero off the boundary: the forward substitutions only visit its reach.
    let active = solver.active_supernodes(order.iter().enumerate().filter(|(_, &r)| on_boundary[r]).map(|(k, _)| k));
    let mut permuted: Rows = vec![[c64::new(0.0, 0.0); BLOCK]; n];
    let mut scratch = Vec::new();
    let mut best = (f64::NAN, f64::INFINITY);
    let mut iterations = 0;
    let mut first: Vec<c64> = Vec::new();
    while iterations < options.iterations {
        // y = K⁻¹ B x, off the translations.
        for (k, &r) in order.iter().enumerate() {
            permuted[k] = if on_boundary[r] { x[r] } else { [c64::new(0.0, 0.0); BLOCK] };
        }
        solver.solve_permuted_rows(&mut permuted, &mut scratch, active.as_deref())?;
        for (k, &r) in order.iter().enumerate() {
            x[r] = permuted[k];
        }
        remove_boundary_mean(&mut x, &on_boundary);
        iterations += 1;
        let ritz = rayleigh_ritz(h, &x, &on_boundary)?;
        x = ritz.vectors;
        first = x.iter().map(|row| row[0]).collect();
        let previous = best.1;
        best = (ritz.value, residual(&first, &ritz.h_first, ritz.value, &on_boundary, h_norm));
        progress.report(0.3 + 0.65 * iterations as f64 / options.iterations as f64)?;
        // Below the tolerance, go on while the residual still halves: the eigenvector's error is
        // about the residual over the gap λ₂ − λ₁, which is tiny on nearly developable meshes,
        // so the iteration stops at the rounding floor rather than at the first small residual.
        if best.1 <= options.tolerance && !(best.1 < 0.5 * previous) {
            break;
        }
    }
    let uv = place(mesh, &system.unknowns.index, &first)?;
    progress.report(1.0)?;
    Ok(SpectralConformalMap {
        uv,
        eigenvalue: best.0,
        residual: best.1,
        iterations,
        converged: best.1 <= options.tolerance,
    })
}

/// `‖H‖∞`, the largest absolute row sum (the matrix is stored as its lower triangle).
fn infinity_norm(h: &SparseColMat<usize, c64>) -> f64 {
    let mut sums = vec![0.0f64; h.nrows()];
    for c in 0..h.ncols() {
        for (r, v) in h.row_idx_of_col(c).zip(h.val_of_col(c)) {
            sums[r] += v.norm();
            if r != c {
                sums[c] += v.norm();
            }
        }
    }
    sums.into_iter().fold(0.0, f64::max)
}

/// `H X` for a block of vectors, H Hermitian given by its lower triangle.
fn hermitian_product(h: &SparseColMat<usize, c64>, x: &[[c64; BLOCK]]) -> Rows {
    let mut y = vec![[c64::new(0.0, 0.0); BLOCK]; x.len()];
    for c in 0..h.ncols() {
        for (r, &v) in h.row_idx_of_col(c).zip(h.val_of_col(c)) {
            for k in 0..BLOCK {
                y[r][k] += v * x[c][k];
            }
            if r != c {
                let w = v.conj();
                for k in 0..BLOCK {
                    y[c][k] += w * x[r][k];
                }
            }
        }
    }
    y
}

/// Subtracts from every column its mean over the boundary rows (makes it B-orthogonal to the
/// constants).
fn remove_boundary_mean(x: &mut [[c64; BLOCK]], on_boundary: &[bool]) {
    let count = on_boundary.iter().filter(|&&b| b).count() as f64;
    let mut mean = [c64::new(0.0, 0.0); BLOCK];
    for (row, _) in x.iter().zip(on_boundary).filter(|(_, &b)| b) {
        for k in 0..BLOCK {
            mean[k] += row[k];
        }
    }
    for m in &mut mean {
        *m /= count;
    }
    for row in x.iter_mut() {
        for k in 0..BLOCK {
            row[k] -= mean[k];
        }
    }
}

/// The deterministic start: ζ, ζ², ζ³, ζ⁴ with ζ the vertices projected on their principal
/// plane (oriented like the surface), centred and scaled to |ζ| ≤ 1.
fn start_block(mesh: &TriMesh, vertex: &[u32]) -> Rows {
    let points: Vec<[f64; 3]> = vertex.iter().map(|&v| mesh.points()[v as usize]).collect();
    let count = points.len() as f64;
    let mut centre = [0.0; 3];
    for p in &points {
        for d in 0..3 {
            centre[d] += p[d] / count;
        }
    }
    let covariance = Mat::<f64>::from_fn(3, 3, |a, b| {
        points.iter().map(|p| (p[a] - centre[a]) * (p[b] - centre[b])).sum::<f64>() / count
    });
    let (mut e1, mut e2) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    if let Ok(eig) = SelfAdjointEigen::new(covariance.as_ref(), Side::Lower) {
        // Eigenvalues ascending: the two largest span the principal plane.
        e1 = [eig.U()[(0, 2)], eig.U()[(1, 2)], eig.U()[(2, 2)]];
        e2 = [eig.U()[(0, 1)], eig.U()[(1, 1)], eig.U()[(2, 1)]];
    }
    // Orient the plane like the surface: (e1 × e2) · (area-weighted normal) > 0.
    let mut normal = [0.0; 3];
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|v| mesh.points()[v as usize]);
        let n = crate::geometry::cross(crate::geometry::sub(b, a), crate::geometry::sub(c, a));
        for d in 0..3 {
            normal[d] += n[d];
        }
    }
    if crate::geometry::dot(crate::geometry::cross(e1, e2), normal) < 0.0 {
        e2 = e2.map(|v| -v);
    }
    let zeta: Vec<c64> = points
        .iter()
        .map(|p| {
            let q = crate::geometry::sub(*p, centre);
            c64::new(crate::geometry::dot(q, e1), crate::geometry::dot(q, e2))
        })
        .collect();
    let radius = zeta.iter().map(|z| z.norm()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    zeta.iter()
        .map(|&z| {
            let z = z / radius;
            let mut row = [c64::new(0.0, 0.0); BLOCK];
            let mut power = z;
            for entry in &mut row {
                *entry = power;
                power *= z;
            }
            row
        })
        .collect()
}

/// The shift σ: 1e-10 of the mean diagonal of H.
fn shift(h: &SparseColMat<usize, c64>) -> f64 {
    let diagonal_mean =
        (0..h.ncols()).map(|c| h.val_of_col(c).first().map_or(0.0, |v| v.re)).sum::<f64>() / h.ncols().max(1) as f64;
    (1e-10 * diagonal_mean).max(f64::MIN_POSITIVE)
}

/// `H + σB` (lower triangle; the diagonal is the first entry of each column).
fn shifted(h: &SparseColMat<usize, c64>, on_boundary: &[bool], sigma: f64) -> Result<SparseColMat<usize, c64>> {
    let mut k = h.clone();
    for (c, &b) in on_boundary.iter().enumerate() {
        if b {
            let start = k.col_ptr()[c];
            if k.row_idx()[start] != c {
                return Err(Error::Internal(format!("column {c} of the conformal matrix has no leading diagonal")));
            }
            k.val_mut()[start] += c64::new(sigma, 0.0);
        }
    }
    Ok(k)
}

/// Rayleigh–Ritz vectors of the pencil (H, B) in the span of `y`.
struct Ritz {
    /// B-orthonormal Ritz vectors, ascending Ritz values.
    vectors: Rows,
    /// The smallest Ritz value.
    value: f64,
    /// H times the first Ritz vector.
    h_first: Vec<c64>,
}

fn rayleigh_ritz(h: &SparseColMat<usize, c64>, y: &[[c64; BLOCK]], on_boundary: &[bool]) -> Result<Ritz> {
    let hy = hermitian_product(h, y);
    let gram = Mat::<c64>::from_fn(BLOCK, BLOCK, |a, b| {
        y.iter().zip(on_boundary).filter(|(_, &on)| on).map(|(row, _)| row[a].conj() * row[b]).sum()
    });
    let energy =
        Mat::<c64>::from_fn(BLOCK, BLOCK, |a, b| y.iter().zip(&hy).map(|(row, hrow)| row[a].conj() * hrow[b]).sum());
    // B-orthonormal basis of the block: T = V D^{-1/2} over the well-conditioned directions.
    let g = SelfAdjointEigen::new(gram.as_ref(), Side::Lower)
        .map_err(|e| Error::Numerical(format!("the Rayleigh–Ritz Gram matrix has no eigendecomposition ({e:?})")))?;
    let d: Vec<f64> = (0..BLOCK).map(|i| g.S().column_vector()[i].re).collect();
    let largest = d.iter().copied().fold(0.0, f64::max);
    let kept: Vec<usize> = (0..BLOCK).filter(|&i| d[i] > 1e-13 * largest).collect();
    if kept.is_empty() || !(largest > 0.0) {
        return Err(Error::Numerical("the inverse iteration lost its boundary values".into()));
    }
    let q = kept.len();
    let t = Mat::<c64>::from_fn(BLOCK, q, |a, j| g.U()[(a, kept[j])] / d[kept[j]].sqrt());
    let small = t.adjoint() * &energy * &t;
    let small = Mat::<c64>::from_fn(q, q, |a, b| 0.5 * (small[(a, b)] + small[(b, a)].conj()));
    let e = SelfAdjointEigen::new(small.as_ref(), Side::Lower)
        .map_err(|e| Error::Numerical(format!("the Rayleigh–Ritz problem has no eigendecomposition ({e:?})")))?;
    let combine = &t * e.U();
    let mut vectors = vec![[c64::new(0.0, 0.0); BLOCK]; y.len()];
    let mut h_first = vec![c64::new(0.0, 0.0); y.len()];
    for (r, (row, hrow)) in y.iter().zip(&hy).enumerate() {
        for j in 0..q {
            let mut v = c64::new(0.0, 0.0);
            for a in 0..BLOCK {
                v += row[a] * combine[(a, j)];
            }
            vectors[r][j] = v;
        }
        for a in 0..BLOCK {
            h_first[r] += hrow[a] * combine[(a, 0)];
        }
    }
    // Directions dropped from a rank-deficient block are refilled deterministically with
    // products of the first Ritz vector and the kept ones (new, smooth directions).
    for j in q..BLOCK {
        for r in 0..y.len() {
            let z = vectors[r][0];
            vectors[r][j] = z * vectors[r][j - q.min(j)];
        }
    }
    Ok(Ritz { vectors, value: e.S().column_vector()[0].re, h_first })
}

/// Normwise backward error of (λ, z): `‖Hz − λBz‖₂ / ((‖H‖∞ + |λ|)‖z‖₂)`.
fn residual(z: &[c64], hz: &[c64], lambda: f64, on_boundary: &[bool], h_norm: f64) -> f64 {
    let mut r2 = 0.0;
    let mut z2 = 0.0;
    for ((&zi, &hi), &b) in z.iter().zip(hz).zip(on_boundary) {
        let r = if b { hi - zi * lambda } else { hi };
        r2 += r.norm_sqr();
        z2 += zi.norm_sqr();
    }
    let scale = (h_norm + lambda.abs()) * z2.sqrt();
    if scale > 0.0 && r2.is_finite() {
        r2.sqrt() / scale
    } else {
        f64::INFINITY
    }
}

/// UVs from the eigenvector: scaled to the surface area, the farthest boundary pair from (0, 0)
/// along +u.
fn place(mesh: &TriMesh, index: &[u32], z: &[c64]) -> Result<Vec<[f64; 2]>> {
    require_finite(z.iter().flat_map(|c| [c.re, c.im]), "spectral conformal")?;
    let at = |v: u32| z[index[v as usize] as usize];
    let uv_area: f64 = mesh.triangles().iter().map(|t| signed_uv_area(t.map(|v| [at(v).re, at(v).im]))).sum();
    let surface: f64 = mesh.geometry().area.iter().sum();
    if !(uv_area > 0.0) {
        return Err(Error::Numerical(format!(
            "the spectral conformal eigenvector has a UV area of {uv_area} (not an orientation-preserving map)"
        )));
    }
    let [(a, _), (b, _)] = default_pins(mesh);
    let (za, zb) = (at(a), at(b));
    let direction = zb - za;
    let rotation = if direction.norm() > 0.0 { direction.conj() / direction.norm() } else { c64::new(1.0, 0.0) };
    let factor = rotation * (surface / uv_area).sqrt();
    Ok((0..mesh.vertex_count())
        .map(|v| match index[v] {
            NONE => [f64::NAN; 2],
            r => {
                let w = (z[r as usize] - za) * factor;
                [w.re, w.im]
            }
        })
        .collect())
}
