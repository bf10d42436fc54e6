//! Curl correction of PGP (Ray et al. 2006, §4.1, eqs. 17–20): a per-vertex scale v that makes
//! the field v K as curl-free as possible while keeping its directions, so that the periodic
//! solve needs fewer singularities (the parameterization stays conformal, not isometric).
//!
//! In a local orthonormal frame (x, y) of a triangle T the direction of K is the angle
//! γ = ax + by + c (linear over T, eq. 17); `curl(v K) = 0` for every c holds when
//! `∇ log v = (−b, a) = R ∇γ` (eqs. 18–19, R the quarter turn). Globally this is solved in the
//! least-squares sense for ṽ = log v (eq. 20):
//!
//! ```text
//! G(ṽ) = Σ_T A_T ‖J_T ṽ_T − R J_T γ_T‖²
//! ```
//!
//! with J_T the gradient of the linear interpolant on T. The γ_c at T's corners are the angles
//! of the corners' field vectors, rotation-matched to corner 0 (eq. 13; K is a cross field) and
//! projected on T's plane, unwrapped around corner 0's angle. The normal equations are the
//! cotangent Laplacian system `L ṽ = Σ_T A_T J_Tᵀ R J_T γ_T`; ṽ is fixed to 0 at one vertex
//! per connected component (the paper's ṽ_1 = 0) and solved by sparse Cholesky. Then
//! `v = exp(ṽ − ṽ̄)`, ṽ̄ the vertex-area-weighted mean of ṽ, and the corrected field is v K
//! (K⊥ = N × vK scales alike). The paper fixes ṽ_1 = 0 and leaves the global scale open; the
//! area-weighted geometric mean of v is 1 here so that ω keeps its meaning (about one period
//! per 2π/ω of length) on most of the surface. Near the singular points of a cross field γ
//! winds around the point and ṽ diverges logarithmically, so normalizing by max v instead (an
//! earlier choice) shrank v by orders of magnitude almost everywhere on the meshes of
//! `tests/data/meshes` and made the periodic solve collapse.
//!
//! Cost: O(F) assembly and one V × V sparse Cholesky factorization.

use crate::error::Result;
use crate::fields::frames::{match_rotation, normalized, rotate_quarter, triangle_normal, wrap_angle};
use crate::geometry::{cross, dot, sub};
use crate::mesh::NONE;
use crate::TriMesh;
use faer::Mat;
use uvflat_sparse::{lower_from_entries, require_finite, CholeskySolver};

/// The curl-correction scale v per vertex (area-weighted geometric mean 1; 0 for unreferenced
/// vertices) for the cross
/// field `field` (tangent vectors per vertex; only directions matter).
pub fn curl_correction_scale(mesh: &TriMesh, normals: &[[f64; 3]], field: &[[f64; 3]]) -> Result<Vec<f64>> {
    let locked = locked_vertices(mesh);
    let mut index = vec![NONE; mesh.vertex_count()];
    let mut vertex_of = Vec::new();
    for v in 0..mesh.vertex_count() as u32 {
        if mesh.is_referenced(v) && !locked.contains(&v) {
            index[v as usize] = vertex_of.len() as u32;
            vertex_of.push(v);
        }
    }
    let n = vertex_of.len();
    let mut diagonal = vec![0.0; n];
    let mut entries = Vec::new();
    let mut rhs = Mat::<f64>::zeros(n, 1);
    for t in 0..mesh.triangle_count() {
        let (stiffness, load) = triangle_terms(mesh, normals, field, t);
        let tri = mesh.triangles()[t];
        for a in 0..3 {
            let ia = index[tri[a] as usize];
            if ia == NONE {
                continue;
            }
            rhs[(ia as usize, 0)] += load[a];
            for b in 0..3 {
                let ib = index[tri[b] as usize];
                if ib == NONE {
                    continue; // ṽ = 0 there: no contribution to the right-hand side
                }
                if ia == ib {
                    diagonal[ia as usize] += stiffness[a][b];
                } else if ia > ib {
                    entries.push((ia, ib, stiffness[a][b]));
                }
            }
        }
    }
    let lower = lower_from_entries(&diagonal, entries)?;
    let coords: Vec<[f64; 3]> = vertex_of.iter().map(|&v| mesh.points()[v as usize]).collect();
    if n > 0 {
        CholeskySolver::new(&lower, Some(&coords))?.solve_in_place(&mut rhs)?;
    }
    require_finite((0..n).map(|i| rhs[(i, 0)]), "curl-correction")?;
    let mut log_v = vec![f64::NEG_INFINITY; mesh.vertex_count()];
    for v in locked {
        log_v[v as usize] = 0.0;
    }
    for (i, &v) in vertex_of.iter().enumerate() {
        log_v[v as usize] = rhs[(i, 0)];
    }
    let mean = area_weighted_mean(mesh, &log_v);
    Ok(log_v.into_iter().map(|l| if l.is_finite() { (l - mean).exp() } else { 0.0 }).collect())
}

/// Σ A_v x_v / Σ A_v over the referenced vertices, A_v a third of the areas of the triangles
/// around v.
fn area_weighted_mean(mesh: &TriMesh, x: &[f64]) -> f64 {
    let (mut sum, mut area) = (0.0, 0.0);
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let a = mesh.geometry().area[t] / 3.0;
        for &v in tri {
            sum += a * x[v as usize];
            area += a;
        }
    }
    if area > 0.0 {
        sum / area
    } else {
        0.0
    }
}

/// One vertex per connected component (corner 0 of its lowest triangle).
fn locked_vertices(mesh: &TriMesh) -> Vec<u32> {
    let mut seen = std::collections::HashSet::new();
    let mut locked = Vec::new();
    for (t, &c) in mesh.triangle_components().iter().enumerate() {
        if seen.insert(c) {
            locked.push(mesh.triangles()[t][0]);
        }
    }
    locked
}

/// `A_T J_Tᵀ J_T` (3×3) and `A_T J_Tᵀ R J_T γ_T` (3) of triangle `t`.
fn triangle_terms(mesh: &TriMesh, normals: &[[f64; 3]], field: &[[f64; 3]], t: usize) -> ([[f64; 3]; 3], [f64; 3]) {
    let tri = mesh.triangles()[t];
    let p = tri.map(|v| mesh.points()[v as usize]);
    let n_t = triangle_normal(mesh, t);
    let x = normalized(sub(p[1], p[0]));
    let y = cross(n_t, x);
    let local = p.map(|q| [dot(sub(q, p[0]), x), dot(sub(q, p[0]), y)]);
    let gamma = corner_angles(tri, normals, field, x, y);
    let area = mesh.geometry().area[t];
    // J_T = 1/(2A) [[y1 − y2, y2 − y0, y0 − y1], [x2 − x1, x0 − x2, x1 − x0]] (corners 0, 1, 2).
    let j: [[f64; 3]; 2] = [
        [local[1][1] - local[2][1], local[2][1] - local[0][1], local[0][1] - local[1][1]],
        [local[2][0] - local[1][0], local[0][0] - local[2][0], local[1][0] - local[0][0]],
    ]
    .map(|row| row.map(|v| v / (2.0 * area)));
    let grad_gamma = [0, 1].map(|r| (0..3).map(|c| j[r][c] * gamma[c]).sum::<f64>());
    let target = [-grad_gamma[1], grad_gamma[0]]; // R ∇γ
    let stiffness = std::array::from_fn(|a| std::array::from_fn(|b| area * (j[0][a] * j[0][b] + j[1][a] * j[1][b])));
    let load = std::array::from_fn(|a| area * (j[0][a] * target[0] + j[1][a] * target[1]));
    (stiffness, load)
}

/// γ at the corners: angle of each corner's field (rotation-matched to corner 0) in the frame
/// (x, y), unwrapped around corner 0's angle.
fn corner_angles(tri: [u32; 3], normals: &[[f64; 3]], field: &[[f64; 3]], x: [f64; 3], y: [f64; 3]) -> [f64; 3] {
    let (k0, n0) = (field[tri[0] as usize], normals[tri[0] as usize]);
    let gamma0 = dot(k0, y).atan2(dot(k0, x));
    std::array::from_fn(|c| {
        if c == 0 {
            return gamma0;
        }
        let v = tri[c] as usize;
        let k = rotate_quarter(normals[v], field[v], match_rotation(k0, n0, normals[v], field[v]));
        gamma0 + wrap_angle(dot(k, y).atan2(dot(k, x)) - gamma0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A planar annulus r ∈ [1, 3] with the circular field K = e_φ: curl(v e_φ) = v' + v/r = 0
    /// gives v ∝ 1/r, which the least-squares solution must reproduce.
    #[test]
    fn circular_field_on_an_annulus_is_rescaled_by_one_over_r() {
        let (nr, na) = (24usize, 96usize);
        let mut positions = Vec::new();
        for i in 0..=nr {
            let r = 1.0 + 2.0 * i as f64 / nr as f64;
            for j in 0..na {
                let a = std::f64::consts::TAU * (j as f64 + 0.5 * (i % 2) as f64) / na as f64;
                positions.extend([r * a.cos(), r * a.sin(), 0.0]);
            }
        }
        let id = |i: usize, j: usize| (i * na + j % na) as u32;
        let mut tris = Vec::new();
        for i in 0..nr {
            for j in 0..na {
                // Inner a, b and outer c, d; counter-clockwise in the plane the cell is a, c, d, b.
                let (a, b, c, d) = (id(i, j), id(i, j + 1), id(i + 1, j), id(i + 1, j + 1));
                if i % 2 == 0 {
                    tris.extend([a, c, b, b, c, d]);
                } else {
                    tris.extend([a, c, d, a, d, b]);
                }
            }
        }
        let mesh = TriMesh::new(&positions, &tris).unwrap();
        let normals = vec![[0.0, 0.0, 1.0]; mesh.vertex_count()];
        let field: Vec<[f64; 3]> = mesh.points().iter().map(|p| normalized([-p[1], p[0], 0.0])).collect();
        let v = curl_correction_scale(&mesh, &normals, &field).unwrap();
        // v · r is constant (up to the global scale, compared with its value on the inner
        // circle, r = 1).
        let inner: Vec<f64> =
            mesh.points().iter().zip(&v).filter(|(p, _)| p[0].hypot(p[1]) < 1.0 + 1e-9).map(|(_, &s)| s).collect();
        let c = inner.iter().sum::<f64>() / inner.len() as f64;
        let mut worst: f64 = 0.0;
        for (p, &s) in mesh.points().iter().zip(&v) {
            let r = p[0].hypot(p[1]);
            worst = worst.max((s * r / c - 1.0).abs());
        }
        assert!(worst < 0.02, "max |v r − 1| = {worst}");
    }
}
