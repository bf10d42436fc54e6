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

use crate::error::{Error, Result};
use crate::geometry::distance;
use crate::linalg::{require_finite, CholeskySolver, TripletBuilder, Unknowns};
use crate::mesh::{TriMesh, NONE};
use crate::progress::Progress;
use faer::{c64, Mat};

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
    mesh.require_disk_with_holes()?;
    let pins = match pins {
        Some(p) => check_pins(mesh, p)?,
        None => default_pins(mesh),
    };
    let mut pinned = vec![None; mesh.vertex_count()];
    for &(v, p) in &pins {
        pinned[v as usize] = Some(c64::new(p[0], p[1]));
    }
    let unknowns = Unknowns::free_vertices(mesh, |v| pinned[v as usize].is_some());
    let index = &unknowns.index;
    progress.report(0.05)?;
    let (matrix, mut rhs) = assemble_conformal_system(mesh, index, unknowns.count(), &pinned)?;
    progress.report(0.3)?;
    CholeskySolver::new(&matrix, Some(&unknowns.positions(mesh)))?.solve_in_place(&mut rhs)?;
    progress.report(0.95)?;
    require_finite(rhs.col_as_slice(0).iter().flat_map(|z| [z.re, z.im]), "natural conformal")?;
    let uv = (0..mesh.vertex_count())
        .map(|v| match (index[v], pinned[v]) {
            (_, Some(z)) => [z.re, z.im],
            (NONE, None) => [f64::NAN; 2],
            (r, None) => [rhs[(r as usize, 0)].re, rhs[(r as usize, 0)].im],
        })
        .collect();
    progress.report(1.0)?;
    Ok(uv)
}

fn check_pins(mesh: &TriMesh, pins: [Pin; 2]) -> Result<[Pin; 2]> {
    for (v, p) in pins {
        if v as usize >= mesh.vertex_count() || !mesh.is_referenced(v) {
            return Err(Error::InvalidArgument(format!("pinned vertex {v} is not a vertex of the mesh's triangles")));
        }
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(Error::InvalidArgument(format!("pinned vertex {v} has a non-finite position")));
        }
    }
    if pins[0].0 == pins[1].0 {
        return Err(Error::InvalidArgument(format!("the two pins must be different vertices (both are {})", pins[0].0)));
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

/// Lower triangle of `H` over the free vertices and the right-hand side `−H_fp z_p`.
fn assemble_conformal_system(
    mesh: &TriMesh,
    index: &[u32],
    count: usize,
    pinned: &[Option<c64>],
) -> Result<(faer::sparse::SparseColMat<usize, c64>, Mat<c64>)> {
    let mut h = TripletBuilder::<c64>::with_capacity(count, 9 * mesh.triangle_count());
    let mut rhs = Mat::<c64>::zeros(count, 1);
    let mut add = |i: u32, j: u32, value: c64| {
        let r = index[i as usize];
        if r == NONE {
            return;
        }
        match index[j as usize] {
            NONE => {
                if let Some(z) = pinned[j as usize] {
                    rhs[(r as usize, 0)] -= value * z;
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
            let w = 0.5 * g.cot[t][k];
            add(i, i, c64::new(w, 0.0));
            add(j, j, c64::new(w, 0.0));
            add(i, j, c64::new(-w, 0.0));
            add(j, i, c64::new(-w, 0.0));
        }
    }
    let conn = mesh.connectivity();
    for hedge in 0..conn.twin.len() as u32 {
        if conn.is_boundary(hedge) {
            let (i, j) = (mesh.tail(hedge), mesh.head(hedge));
            add(i, j, c64::new(0.0, 0.5));
            add(j, i, c64::new(0.0, -0.5));
        }
    }
    Ok((h.build()?, rhs))
}
