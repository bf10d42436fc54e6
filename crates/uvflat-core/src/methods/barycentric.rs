//! Fixed-boundary barycentric maps (Hormann–Lévy–Sheffer course notes 2008, ch. 2, §2.1–2.4;
//! Desbrun–Meyer–Alliez 2002, §3–4.1).
//!
//! Every interior vertex is placed at a weighted average of its neighbours,
//! `Σ_j w_ij (u_i − u_j) = 0`, with the boundary fixed on a shape ([`crate::boundary`]).
//! Weights, with angles as in course notes Fig. 2.2 / Desbrun Fig. 4:
//! - `Uniform` (Tutte 1963): `w_ij = 1`.
//! - `Floater` (Floater 1997, shape-preserving): barycentric coordinates averaged over the
//!   triangles of a geodesic polar map of the 1-ring.
//! - `Authalic` = Wachspress = DAP (Desbrun eq. 6, course notes §2.4):
//!   `w_ij = (cot γ_ij + cot δ_ij) / |x_i − x_j|²`, angles at `x_j`.
//! - `Conformal` = discrete harmonic = DCP (Desbrun eq. 4): `w_ij = cot α_ij + cot β_ij`,
//!   angles opposite the edge.
//! - `MeanValue` (Floater 2003): `w_ij = (tan(α/2) + tan(β/2)) / |x_i − x_j|`, angles at `x_i`.
//! - `Intrinsic { λ, μ }` (Desbrun §3.4, §4.1): `λ·M^A + μ·M^χ`. M^χ has units 1/length²;
//!   uvflat multiplies it by the mean squared edge length so λ and μ do not depend on the
//!   mesh's scale (λ = 1, μ = 0 is DCP; λ = 0, μ = 1 is DAP).
//!
//! Guarantees: with a convex boundary, positive weights (uniform, Floater, mean value) give an
//! embedding (Tutte–Floater theorem, course notes §2.2); Floater, Wachspress, harmonic and mean
//! value reproduce a planar mesh exactly (linear precision). Holes are filled by cones
//! ([`crate::mesh::fill`]) so they cannot fold either.
//!
//! Cost: one sparse factorization (Cholesky for the symmetric uniform and harmonic systems,
//! LU otherwise) and two solves, O(n^1.5) for typical meshes.

use crate::boundary::{fixed_boundary, BoundaryShape, Distribution};
use crate::error::{Error, Result};
use crate::geometry::{distance, norm2, sub};
use crate::mesh::Unknowns;
use crate::mesh::{fill::fill_holes, TriMesh, NONE};
use crate::progress::Progress;
use faer::Mat;
use uvflat_sparse::{require_finite, CholeskySolver, LuSolver, TripletBuilder};

/// Barycentric weights of a fixed-boundary map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Weights {
    /// Tutte's uniform weights.
    Uniform,
    /// Floater's shape-preserving weights.
    Floater,
    /// Wachspress / discrete authalic (DAP).
    Authalic,
    /// Discrete harmonic / discrete conformal (DCP).
    Conformal,
    /// Floater's mean value weights.
    MeanValue,
    /// Desbrun's intrinsic combination `λ·DCP + μ·DAP`.
    Intrinsic {
        /// Weight of the conformal (DCP) matrix.
        lambda: f64,
        /// Weight of the authalic (DAP) matrix.
        mu: f64,
    },
}

impl Weights {
    pub(crate) fn is_symmetric(self) -> bool {
        matches!(self, Weights::Uniform | Weights::Conformal)
    }
}

/// Options of [`fixed_boundary_map`].
#[derive(Debug, Clone, PartialEq)]
pub struct FixedBoundaryOptions {
    /// Interior weights.
    pub weights: Weights,
    /// Boundary shape or caller-given boundary positions.
    pub shape: BoundaryShape,
    /// Spacing of boundary vertices along the shape (ignored for given positions).
    pub distribution: Distribution,
}

impl Default for FixedBoundaryOptions {
    fn default() -> Self {
        FixedBoundaryOptions {
            weights: Weights::MeanValue,
            shape: BoundaryShape::Circle,
            distribution: Distribution::ChordLength,
        }
    }
}

/// Computes a fixed-boundary map. Returns one UV per input vertex (NaN for unreferenced ones).
pub fn fixed_boundary_map(mesh: &TriMesh, options: &FixedBoundaryOptions) -> Result<Vec<[f64; 2]>> {
    fixed_boundary_map_with_progress(mesh, options, &mut Progress::none())
}

/// [`fixed_boundary_map`] with progress reporting and cancellation.
pub fn fixed_boundary_map_with_progress(
    mesh: &TriMesh,
    options: &FixedBoundaryOptions,
    progress: &mut Progress,
) -> Result<Vec<[f64; 2]>> {
    if let Weights::Intrinsic { lambda, mu } = options.weights {
        if !(lambda.is_finite() && mu.is_finite()) || (lambda == 0.0 && mu == 0.0) {
            return Err(Error::InvalidArgument(format!(
                "intrinsic weights need finite λ, μ not both zero (got λ = {lambda}, μ = {mu})"
            )));
        }
    }
    mesh.require_disk_with_holes()?;
    let boundary = fixed_boundary(mesh, &options.shape, options.distribution)?;
    progress.report(0.05)?;
    let filled;
    let work = if boundary.loop_fixed.iter().all(|&f| f) {
        mesh
    } else {
        filled = fill_holes(mesh, &boundary.loop_fixed)?;
        &filled.mesh
    };
    let mut fixed_uv = vec![[f64::NAN; 2]; work.vertex_count()];
    for &(v, p) in &boundary.fixed {
        fixed_uv[v as usize] = p;
    }
    let unknown = Unknowns::free_vertices(work, |v| !fixed_uv[v as usize][0].is_nan());
    let weights = vertex_weights(work, options.weights, &unknown.index);
    progress.report(0.2)?;
    let coords = unknown.positions(work);
    let solution =
        solve_weighted_system(&unknown, &coords, &weights, &fixed_uv, options.weights.is_symmetric(), progress)?;
    let uv: Vec<[f64; 2]> = (0..mesh.vertex_count())
        .map(|v| match unknown.index[v] {
            NONE => fixed_uv[v],
            r => [solution[(r as usize, 0)], solution[(r as usize, 1)]],
        })
        .collect();
    progress.report(1.0)?;
    Ok(uv)
}

/// Weight `w_ij` contributed by triangle `t` for its corner `a` (vertex i, free) towards its
/// corner `b` (vertex j); `c` is the third corner.
fn triangle_weight(mesh: &TriMesh, t: usize, a: usize, b: usize, c: usize, weights: Weights, mean_edge2: f64) -> f64 {
    let g = mesh.geometry();
    let tri = mesh.triangles()[t];
    let (xi, xj) = (mesh.points()[tri[a] as usize], mesh.points()[tri[b] as usize]);
    match weights {
        Weights::Uniform => 0.5,
        Weights::Conformal => 0.5 * g.cot[t][c],
        Weights::Authalic => g.cot[t][b] / norm2(sub(xi, xj)),
        Weights::MeanValue => (0.5 * mesh.corner_angles()[t][a]).tan() / distance(xi, xj),
        Weights::Intrinsic { lambda, mu } => lambda * g.cot[t][c] + mu * mean_edge2 * g.cot[t][b] / norm2(sub(xi, xj)),
        Weights::Floater => unreachable!("Floater weights are computed per vertex"),
    }
}

fn mean_squared_edge_length(mesh: &TriMesh) -> f64 {
    let mut sum = 0.0;
    for tri in mesh.triangles() {
        for k in 0..3 {
            sum += norm2(sub(mesh.points()[tri[k] as usize], mesh.points()[tri[(k + 1) % 3] as usize]));
        }
    }
    sum / (3 * mesh.triangle_count()) as f64
}

/// `(i, j, w_ij)` for every free vertex i and neighbour j (repeated pairs are summed later).
pub(crate) fn vertex_weights(mesh: &TriMesh, weights: Weights, unknown: &[u32]) -> Vec<(u32, u32, f64)> {
    if weights == Weights::Floater {
        return super::floater::floater_weights(mesh, unknown);
    }
    let mean_edge2 = if matches!(weights, Weights::Intrinsic { .. }) { mean_squared_edge_length(mesh) } else { 0.0 };
    let mut out = Vec::with_capacity(6 * mesh.triangle_count());
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for a in 0..3 {
            if unknown[tri[a] as usize] == NONE {
                continue;
            }
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            out.push((tri[a], tri[b], triangle_weight(mesh, t, a, b, c, weights, mean_edge2)));
            out.push((tri[a], tri[c], triangle_weight(mesh, t, a, c, b, weights, mean_edge2)));
        }
    }
    out
}

/// Assembles `Σ_j w_ij (u_i − u_j) = 0` over the free vertices and solves for u and v.
fn solve_weighted_system(
    unknown: &Unknowns,
    coords: &[[f64; 3]],
    weights: &[(u32, u32, f64)],
    fixed_uv: &[[f64; 2]],
    symmetric: bool,
    progress: &mut Progress,
) -> Result<Mat<f64>> {
    let mut a = TripletBuilder::with_capacity(unknown.count(), 2 * weights.len());
    let mut rhs = Mat::<f64>::zeros(unknown.count(), 2);
    for &(i, j, w) in weights {
        let r = unknown.index[i as usize] as usize;
        a.add(r, r, w);
        match unknown.index[j as usize] {
            NONE => {
                rhs[(r, 0)] += w * fixed_uv[j as usize][0];
                rhs[(r, 1)] += w * fixed_uv[j as usize][1];
            }
            c if !symmetric || r >= c as usize => a.add(r, c as usize, -w),
            _ => {}
        }
    }
    let matrix = a.build()?;
    progress.report(0.4)?;
    if symmetric {
        CholeskySolver::new(&matrix, Some(coords))?.solve_in_place(&mut rhs)?;
    } else {
        LuSolver::with_coords(&matrix, Some(coords))?.solve_in_place(&mut rhs)?;
    }
    progress.report(0.95)?;
    require_finite(rhs.col_as_slice(0).iter().chain(rhs.col_as_slice(1)).copied(), "fixed-boundary")?;
    Ok(rhs)
}
