//! Natural conformal map (Desbrun–Meyer–Alliez 2002, §4.2, eq. 7), which is the same map as
//! LSCM (Lévy et al. 2002; course notes §4.3): free boundary, two pinned vertices.
//!
//! It minimizes the conformal energy `E_C = E_D − A` (Dirichlet energy minus the signed area
//! of the image). With `z = u + i·v` per vertex, `E_C = ½ Re(z* H z)` where the Hermitian
//! matrix `H = L + i·S/2` has `L` the cotangent Laplacian (`L_ij = −½(cot α_ij + cot β_ij)`) and
//! `S` the antisymmetric boundary matrix of the area term (`S_ij = 1`, `S_ji = −1` for every
//! boundary half-edge i→j). Pinning two vertices makes `H` positive definite on the rest, so
//! the map is one complex sparse Cholesky solve of size n − 2 — half the unknowns of the real
//! 2n formulation. The energy is invariant to similarity transforms of the input, so the map is
//! too (up to the pins' placement).
//!
//! Pins: by default the two boundary vertices farthest apart in 3D (as in the paper), placed at
//! (0, 0) and (d, 0) with d their 3D distance, so the map has roughly the input's scale.
//! Works on any connected genus-0 mesh with one or more boundary loops.
//!
//! [`area_weighted_conformal_map`] minimises `Σ_T A_T · E_C,T` instead (each triangle's
//! conformal energy times its 3D area): the energy of the LSCM equations as CGAL 5.x
//! (`LSCM_parameterizer_3`, via OpenNL) writes them, one equation
//! `(Z1 − Z0)(U2 − U0) = (Z2 − Z0)(U1 − U0)` per triangle in a local orthonormal frame and
//! without Lévy et al.'s 1/√(2A) factor. For a linear map `f(Z) = aZ + b·conj(Z)` on a triangle
//! the residual of that equation has `|r|² = 16 A² |b|²` while `E_C,T = 2A |b|²`, so CGAL's
//! `Σ|r|² = 8 Σ A_T E_C,T`. Both energies vanish on developable meshes; on curved meshes the
//! area weighting favours large triangles and is not invariant to remeshing, which is why the
//! paper's `E_C` is the default. The weighted energy has an imaginary part on interior edges
//! too (`½(A_T − A_T')` between the triangles on either side), so it takes the all-complex
//! factorization. It exists to reproduce CGAL's LSCM for the same pins.

use crate::error::{Error, Result};
use crate::geometry::distance;
use crate::mesh::Unknowns;
use crate::mesh::{TriMesh, NONE};
use crate::progress::Progress;
use faer::sparse::SparseColMat;
use faer::{c64, Mat};
use rayon::prelude::*;
use uvflat_sparse::split_hermitian::HermitianSolver;
use uvflat_sparse::{lower_from_entries, require_finite};

/// A pinned vertex and its UV.
pub type Pin = (u32, [f64; 2]);

/// Natural conformal map; `pins = None` pins the farthest boundary pair. One UV per vertex
/// (NaN for unreferenced vertices).
pub fn natural_conformal_map(mesh: &TriMesh, pins: Option<[Pin; 2]>) -> Result<Vec<[f64; 2]>> {
    natural_conformal_map_with_progress(mesh, pins, &mut Progress::none())
}

/// [`natural_conformal_map`] with progress reporting and cancellation.
pub fn natural_conformal_map_with_progress(
    mesh: &TriMesh,
    pins: Option<[Pin; 2]>,
    progress: &mut Progress,
) -> Result<Vec<[f64; 2]>> {
    let pins = resolve_pins(mesh, pins)?;
    progress.report(0.05)?;
    let system = ConformalSystem::new(mesh, pins)?;
    progress.report(0.3)?;
    let uv = system.solve(mesh)?;
    progress.report(1.0)?;
    Ok(uv)
}

/// The conformal map of CGAL's LSCM energy (see the module comment): minimises
/// `Σ_T A_T · E_C,T` with the given pins (`None`: the farthest boundary pair). One UV per vertex
/// (NaN for unreferenced vertices).
pub fn area_weighted_conformal_map(mesh: &TriMesh, pins: Option<[Pin; 2]>) -> Result<Vec<[f64; 2]>> {
    let pins = resolve_pins(mesh, pins)?;
    ConformalSystem::with_triangle_weights(mesh, &pins, &mesh.geometry().cot, Some(&mesh.geometry().area))?.solve(mesh)
}

/// The natural conformal map's linear system `H_ff z_f = −H_fp z_p` over the free vertices.
pub struct ConformalSystem {
    /// Numbering of the free vertices (rows of the system).
    pub unknowns: Unknowns,
    /// Position of each pinned vertex as `u + i·v`, `None` for the others.
    pub pinned: Vec<Option<c64>>,
    /// Lower triangle of `H_ff`.
    pub matrix: SparseColMat<usize, c64>,
    /// Right-hand side `−H_fp z_p`; holds the solution after a solve in place.
    pub rhs: Mat<c64>,
}

impl ConformalSystem {
    /// Assembles the system for pins checked by [`resolve_pins`].
    pub fn new(mesh: &TriMesh, pins: [Pin; 2]) -> Result<Self> {
        Self::with_pins(mesh, &pins)
    }

    /// Assembles the system for any set of pinned vertices (valid, distinct vertices; one pin
    /// already makes `H_ff` positive definite on a connected mesh).
    pub fn with_pins(mesh: &TriMesh, pins: &[Pin]) -> Result<Self> {
        Self::with_cotangents(mesh, pins, &mesh.geometry().cot)
    }

    /// The same system with the cotangents of other corner angles (`cot[t][k]` at corner `k` of
    /// triangle `t`): its minimiser makes every uv triangle as similar as possible to the
    /// triangle with those angles (ABF++'s angle-to-uv step, `methods::abf`).
    pub fn with_cotangents(mesh: &TriMesh, pins: &[Pin], cot: &[[f64; 3]]) -> Result<Self> {
        Self::with_triangle_weights(mesh, pins, cot, None)
    }

    /// The system of `Σ_T w_T · E_C,T` (`None`: every `w_T = 1`, the natural conformal map).
    pub fn with_triangle_weights(
        mesh: &TriMesh,
        pins: &[Pin],
        cot: &[[f64; 3]],
        weights: Option<&[f64]>,
    ) -> Result<Self> {
        let mut pinned = vec![None; mesh.vertex_count()];
        for &(v, p) in pins {
            pinned[v as usize] = Some(c64::new(p[0], p[1]));
        }
        let unknowns = Unknowns::free_vertices(mesh, |v| pinned[v as usize].is_some());
        let terms = EdgeWeights { cot, triangle: weights };
        let (matrix, rhs) = assemble_conformal_system(mesh, &terms, &unknowns.index, unknowns.count(), &pinned)?;
        Ok(ConformalSystem { unknowns, pinned, matrix, rhs })
    }

    /// Factors `H_ff` and solves the system; one UV per vertex (see [`ConformalSystem::uv`]).
    pub fn solve(mut self, mesh: &TriMesh) -> Result<Vec<[f64; 2]>> {
        let coords = self.unknowns.positions(mesh);
        HermitianSolver::new(&self.matrix, &coords)?.solve_in_place(&mut self.rhs)?;
        self.uv(mesh)
    }

    /// One UV per vertex from the solved `rhs` (pins where pinned, NaN for unreferenced
    /// vertices).
    pub fn uv(&self, mesh: &TriMesh) -> Result<Vec<[f64; 2]>> {
        let solution = self.rhs.col_as_slice(0);
        require_finite(solution.iter().flat_map(|z| [z.re, z.im]), "natural conformal")?;
        let uv = (0..mesh.vertex_count())
            .map(|v| match (self.unknowns.index[v], self.pinned[v]) {
                (_, Some(z)) => [z.re, z.im],
                (NONE, None) => [f64::NAN; 2],
                (r, None) => [solution[r as usize].re, solution[r as usize].im],
            })
            .collect();
        Ok(uv)
    }
}

/// Checks that the mesh is a disk (possibly with holes) and that the caller's pins are valid;
/// `None` pins the farthest boundary pair.
pub fn resolve_pins(mesh: &TriMesh, pins: Option<[Pin; 2]>) -> Result<[Pin; 2]> {
    mesh.require_disk_with_holes()?;
    match pins {
        Some(p) => check_pins(mesh, p),
        None => Ok(default_pins(mesh)),
    }
}

fn check_pins(mesh: &TriMesh, pins: [Pin; 2]) -> Result<[Pin; 2]> {
    for (v, p) in pins {
        if v as usize >= mesh.vertex_count() {
            return Err(Error::InvalidArgument(format!(
                "pinned vertex {v} is out of range: the mesh has {} vertices",
                mesh.vertex_count()
            )));
        }
        if !mesh.is_referenced(v) {
            return Err(Error::InvalidArgument(format!("pinned vertex {v} is not used by any triangle")));
        }
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(Error::InvalidArgument(format!("pinned vertex {v} has a non-finite position")));
        }
    }
    if pins[0].0 == pins[1].0 {
        return Err(Error::InvalidArgument(format!(
            "the two pins must be different vertices (both are {})",
            pins[0].0
        )));
    }
    if pins[0].1 == pins[1].1 {
        return Err(Error::InvalidArgument("the two pins must have different positions".into()));
    }
    Ok(pins)
}

/// The two boundary vertices farthest apart, at (0, 0) and (d, 0).
pub fn default_pins(mesh: &TriMesh) -> [Pin; 2] {
    let boundary: Vec<u32> = mesh.boundary_loops().iter().flatten().copied().collect();
    let (a, b) = farthest_pair(mesh.points(), &boundary);
    let d = distance(mesh.points()[a as usize], mesh.points()[b as usize]);
    [(a, [0.0, 0.0]), (b, [d, 0.0])]
}

/// Exact farthest pair for up to 4096 candidates; above that, repeated farthest-point sweeps
/// (each sweep is linear and never decreases the distance; 8 sweeps in practice reach the
/// diameter or come within a fraction of a percent of it).
pub fn farthest_pair(points: &[[f64; 3]], candidates: &[u32]) -> (u32, u32) {
    let dist = |a: u32, b: u32| distance(points[a as usize], points[b as usize]);
    if candidates.len() <= 4096 {
        let mut best = (candidates[0], candidates[candidates.len().min(2) - 1], -1.0);
        for (i, &a) in candidates.iter().enumerate() {
            for &b in &candidates[i + 1..] {
                let d = dist(a, b);
                if d > best.2 {
                    best = (a, b, d);
                }
            }
        }
        return (best.0, best.1);
    }
    let farthest_from = |a: u32| *candidates.iter().max_by(|&&x, &&y| dist(a, x).total_cmp(&dist(a, y))).unwrap_or(&a);
    let (mut a, mut b) = (candidates[0], farthest_from(candidates[0]));
    for _ in 0..8 {
        let c = farthest_from(b);
        if dist(b, c) <= dist(a, b) {
            break;
        }
        (a, b) = (b, c);
    }
    (a, b)
}

/// The per-corner cotangents and optional per-triangle weights the system is assembled from.
struct EdgeWeights<'a> {
    cot: &'a [[f64; 3]],
    triangle: Option<&'a [f64]>,
}

impl EdgeWeights<'_> {
    /// Weight of the triangle holding half-edge `h` (1 without weights).
    fn of_halfedge(&self, h: u32) -> f64 {
        self.triangle.map_or(1.0, |w| w[(h / 3) as usize])
    }

    /// Half the cotangent of the corner opposite half-edge `h`, times its triangle's weight.
    fn half_cot(&self, h: u32) -> f64 {
        0.5 * self.of_halfedge(h) * self.cot[(h / 3) as usize][((h % 3 + 2) % 3) as usize]
    }
}

/// Lower triangle of `H` over the free vertices and the right-hand side `−H_fp z_p`, assembled
/// edge by edge: each edge (one half-edge per edge) gives its cotangent weight
/// `w = ½(cot α + cot β)` to both diagonals and `H_ab = −w + i/2·(w_T − w_T')` off the diagonal
/// (T holding a→b, T' holding b→a, `w_T' = 0` across the boundary: without triangle weights the
/// imaginary part is i/2 on boundary edges only), `H_ba = conj(H_ab)` (or to the right-hand side
/// when one end is pinned).
/// The half-edges are split into a fixed number of ranges assembled in parallel (fixed, so the
/// sums do not depend on the number of threads).
fn assemble_conformal_system(
    mesh: &TriMesh,
    weights: &EdgeWeights,
    index: &[u32],
    count: usize,
    pinned: &[Option<c64>],
) -> Result<(SparseColMat<usize, c64>, Mat<c64>)> {
    const RANGES: usize = 4;
    let halfedges = mesh.connectivity().twin.len();
    let step = halfedges.div_ceil(RANGES);
    let part = |k: usize| {
        edge_terms(mesh, weights, index, count, pinned, (k * step).min(halfedges)..((k + 1) * step).min(halfedges))
    };
    // (On the calling thread for small meshes: see `crate::parallel`.)
    let small = halfedges < crate::parallel::SEQUENTIAL_BELOW;
    let parts: Vec<EdgeTerms> =
        if small { (0..RANGES).map(part).collect() } else { (0..RANGES).into_par_iter().map(part).collect() };
    let diagonal: Vec<c64> =
        crate::parallel::map_range(count, |r| c64::new(parts.iter().map(|p| p.diagonal[r]).sum(), 0.0));
    let mut rhs = Mat::<c64>::zeros(count, 1);
    let mut lower = Vec::with_capacity(parts.iter().map(|p| p.lower.len()).sum());
    for part in parts {
        for (r, value) in part.rhs {
            rhs[(r as usize, 0)] += value;
        }
        lower.extend(part.lower);
    }
    Ok((lower_from_entries(&diagonal, lower)?, rhs))
}

/// What a range of half-edges contributes to the system.
struct EdgeTerms {
    /// Real diagonal contributions, one per unknown.
    diagonal: Vec<f64>,
    /// Strictly lower entries.
    lower: Vec<(u32, u32, c64)>,
    /// Right-hand-side contributions from pinned neighbours.
    rhs: Vec<(u32, c64)>,
}

/// The contributions of the edges whose first half-edge (the boundary one, or the lower of the
/// two) lies in `halfedges`.
fn edge_terms(
    mesh: &TriMesh,
    weights: &EdgeWeights,
    index: &[u32],
    count: usize,
    pinned: &[Option<c64>],
    halfedges: std::ops::Range<usize>,
) -> EdgeTerms {
    let twin = &mesh.connectivity().twin;
    let mut terms =
        EdgeTerms { diagonal: vec![0.0; count], lower: Vec::with_capacity(halfedges.len() / 2 + 1), rhs: Vec::new() };
    for h in halfedges {
        let (h, t) = (h as u32, twin[h]);
        if t != NONE && t < h {
            continue;
        }
        let (a, b) = (mesh.tail(h), mesh.head(h));
        let (w, area) = match t {
            NONE => (weights.half_cot(h), 0.5 * weights.of_halfedge(h)),
            t => (weights.half_cot(h) + weights.half_cot(t), 0.5 * (weights.of_halfedge(h) - weights.of_halfedge(t))),
        };
        let h_ab = c64::new(-w, area);
        let (ra, rb) = (index[a as usize], index[b as usize]);
        for r in [ra, rb] {
            if r != NONE {
                terms.diagonal[r as usize] += w;
            }
        }
        match (ra, rb) {
            (NONE, NONE) => {}
            (ra, NONE) => {
                if let Some(z) = pinned[b as usize] {
                    terms.rhs.push((ra, -(h_ab * z)));
                }
            }
            (NONE, rb) => {
                if let Some(z) = pinned[a as usize] {
                    terms.rhs.push((rb, -(h_ab.conj() * z)));
                }
            }
            (ra, rb) if ra > rb => terms.lower.push((ra, rb, h_ab)),
            (ra, rb) => terms.lower.push((rb, ra, h_ab.conj())),
        }
    }
    terms
}

#[cfg(test)]
mod tests {
    use super::*;
    use uvflat_sparse::TripletBuilder;

    /// Triplet assembly per triangle: each corner's cotangent term and each half-edge's signed
    /// area term `±i/2`, all times the triangle's weight (interior area terms cancel pairwise
    /// when the weights are equal, leaving the boundary's).
    fn reference(
        mesh: &TriMesh,
        index: &[u32],
        count: usize,
        pinned: &[Option<c64>],
        weights: &[f64],
    ) -> (Vec<Vec<c64>>, Vec<c64>) {
        let mut h = TripletBuilder::<c64>::with_capacity(count, 9 * mesh.triangle_count());
        let mut rhs = vec![c64::new(0.0, 0.0); count];
        let mut add = |i: u32, j: u32, value: c64| {
            let r = index[i as usize];
            if r == NONE {
                return;
            }
            match index[j as usize] {
                NONE => {
                    if let Some(z) = pinned[j as usize] {
                        rhs[r as usize] -= value * z;
                    }
                }
                c if r >= c => h.add(r as usize, c as usize, value),
                _ => {}
            }
        };
        let g = mesh.geometry();
        for (t, tri) in mesh.triangles().iter().enumerate() {
            for k in 0..3 {
                let (i, j) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let w = 0.5 * weights[t] * g.cot[t][k];
                add(i, i, c64::new(w, 0.0));
                add(j, j, c64::new(w, 0.0));
                add(i, j, c64::new(-w, 0.0));
                add(j, i, c64::new(-w, 0.0));
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                add(a, b, c64::new(0.0, 0.5 * weights[t]));
                add(b, a, c64::new(0.0, -0.5 * weights[t]));
            }
        }
        (dense(&h.build().expect("assembly")), rhs)
    }

    #[allow(clippy::needless_range_loop)]
    fn dense(m: &SparseColMat<usize, c64>) -> Vec<Vec<c64>> {
        let n = m.nrows();
        let mut d = vec![vec![c64::new(0.0, 0.0); n]; n];
        for c in 0..n {
            for (r, &v) in m.row_idx_of_col(c).zip(m.val_of_col(c)) {
                d[r][c] += v;
            }
        }
        d
    }

    /// A bumpy 5 × 4 grid (curved, so the area term matters) with one hole-free boundary.
    fn bumpy_grid() -> TriMesh {
        let (w, h) = (5u32, 4u32);
        let mut positions = Vec::new();
        for j in 0..=h {
            for i in 0..=w {
                let (x, y) = (i as f64, j as f64 * 1.1);
                positions.extend([x, y, 0.3 * (x * 0.7).sin() * (y * 0.9).cos()]);
            }
        }
        let id = |i: u32, j: u32| j * (w + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..h {
            for i in 0..w {
                triangles.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        TriMesh::new(&positions, &triangles).expect("valid grid")
    }

    #[test]
    fn edge_assembly_matches_the_corner_by_corner_assembly() {
        let mesh = bumpy_grid();
        let pins = default_pins(&mesh);
        let unweighted = ConformalSystem::new(&mesh, pins).expect("assembly");
        assert_same_system(&mesh, &unweighted, &vec![1.0; mesh.triangle_count()]);
        let areas = &mesh.geometry().area;
        let weighted =
            ConformalSystem::with_triangle_weights(&mesh, &pins, &mesh.geometry().cot, Some(areas)).expect("assembly");
        assert_same_system(&mesh, &weighted, areas);
    }

    fn assert_same_system(mesh: &TriMesh, system: &ConformalSystem, weights: &[f64]) {
        let (matrix, rhs) = reference(mesh, &system.unknowns.index, system.unknowns.count(), &system.pinned, weights);
        let ours = dense(&system.matrix);
        for (row, expected) in ours.iter().zip(&matrix) {
            for (a, b) in row.iter().zip(expected) {
                assert!((a - b).norm() < 1e-13, "{a} vs {b}");
            }
        }
        for (r, expected) in rhs.iter().enumerate() {
            assert!((system.rhs[(r, 0)] - expected).norm() < 1e-13);
        }
    }
}
