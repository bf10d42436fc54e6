//! Per-triangle parameterization of PGP (Ray et al. 2006, §3.1, Algorithm 1): the (θ, φ)
//! coordinates at the three corners of every triangle, recovered from the unknowns
//! `X_v = (cos θ, sin θ, cos φ, sin φ)` of the periodic solve.
//!
//! In triangle T = (v0, v1, v2) the first corner gets r = s = t = 0: `θ_0 = angle(U_v0)`,
//! `φ_0 = angle(V_v0)` with `angle(U) = atan2(U_y, U_x)`. Algorithm 1 then propagates along the
//! edges (v0, v1) and (v0, v2): the rotation `r = argmax_r K_v0 · R^r K_vc` is applied to the
//! field and to the unknowns (`X' = M^r X`, see [`super::periodic`]), and the integer
//! translations s, t are the ones that bring `angle(U'_c) + 2sπ` (and φ) closest to the value
//! predicted along the edge, `θ_0 + ω/2 (K'_0 + K'_c)·(p_c − p_0)`. (The paper writes the
//! prediction with a factor π/ω, which is not dimensionally consistent; the increment used
//! here is the δ of eq. 13.)
//!
//! A triangle is *open* (§3.2) when propagating once more, from corner 1 to corner 2, does not
//! give back corner 2's rotation and translations: the path v0 → v1 → v2 does not close.
//!
//! Every corner's coordinates are `angles(M^ρ X_v) + 2π (s, t)` with its integer rotation ρ and
//! shifts (s, t) stored alongside, so that transitions between triangles (eq. 16) are exact
//! integer data. Cost: O(F), in parallel.

use super::periodic::{corner_frames, expected_increments, rotate_unknowns};
use crate::fields::frames::{match_rotation, rotate_quarter};
use crate::geometry::cross;
use crate::TriMesh;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The per-triangle parameterization: (θ, φ) at every corner and the integer data behind it.
#[derive(Debug, Clone, PartialEq)]
pub struct CornerParameterization {
    /// (θ, φ) at corner k of triangle t (radians; one period is 2π).
    pub coords: Vec<[[f64; 2]; 3]>,
    /// Rotation ρ (quarter turns) applied to the corner's vertex unknowns.
    pub rotation: Vec<[u8; 3]>,
    /// Integer translations (s, t), in periods of 2π.
    pub shift: Vec<[[i64; 2]; 3]>,
    /// Whether Algorithm 1 around the triangle gives an open path.
    pub open: Vec<bool>,
}

/// `(angle(U), angle(V))` of unknowns X.
pub fn angles(x: [f64; 4]) -> [f64; 2] {
    [x[1].atan2(x[0]), x[3].atan2(x[2])]
}

/// Algorithm 1 on every triangle.
pub fn corner_parameterization(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    unknowns: &[[f64; 4]],
    omega: f64,
) -> CornerParameterization {
    let per_triangle: Vec<TriangleParam> = (0..mesh.triangle_count())
        .into_par_iter()
        .with_min_len(1024)
        .map(|t| triangle_parameterization(mesh, normals, field, unknowns, omega, t))
        .collect();
    CornerParameterization {
        coords: per_triangle.iter().map(|p| p.coords).collect(),
        rotation: per_triangle.iter().map(|p| p.rotation).collect(),
        shift: per_triangle.iter().map(|p| p.shift).collect(),
        open: per_triangle.iter().map(|p| p.open).collect(),
    }
}

/// Algorithm 1's output for one triangle.
pub(super) struct TriangleParam {
    pub(super) coords: [[f64; 2]; 3],
    rotation: [u8; 3],
    shift: [[i64; 2]; 3],
    pub(super) open: bool,
}

/// Algorithm 1 on triangle `t`.
pub(super) fn triangle_parameterization(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    unknowns: &[[f64; 4]],
    omega: f64,
    t: usize,
) -> TriangleParam {
    let corners = mesh.triangles()[t].map(|v| unknowns[v as usize]);
    corner_triangle_parameterization(mesh, normals, field, corners, omega, t)
}

/// Algorithm 1 on triangle `t` with `corners` the unknowns of its three vertices (in its
/// corner order), whatever the unknowns array holds.
pub(super) fn corner_triangle_parameterization(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    corners: [[f64; 4]; 3],
    omega: f64,
    t: usize,
) -> TriangleParam {
    let tri = mesh.triangles()[t];
    let p = tri.map(|v| mesh.points()[v as usize]);
    let frames = corner_frames(mesh, normals, field, t);
    let base: [[f64; 2]; 3] = std::array::from_fn(|c| angles(rotate_unknowns(frames[c].0, corners[c])));
    let mut coords = [base[0]; 3];
    let mut shift = [[0i64; 2]; 3];
    for c in 1..3 {
        let (d, dp) = expected_increments(&p, &frames, omega, 0, c);
        shift[c] = [nearest_period(coords[0][0] + d - base[c][0]), nearest_period(coords[0][1] + dp - base[c][1])];
        coords[c] = [base[c][0] + TAU * shift[c][0] as f64, base[c][1] + TAU * shift[c][1] as f64];
    }
    let open = !closes(mesh, normals, field, corners[2], omega, t, &frames, &coords, &shift);
    TriangleParam { coords, rotation: frames.map(|f| f.0), shift, open }
}

/// The integer s minimizing |x − 2sπ|.
#[inline]
pub fn nearest_period(x: f64) -> i64 {
    (x / TAU).round() as i64
}

/// Whether propagating from corner 1 to corner 2 (Algorithm 1 along the third edge) gives back
/// corner 2's rotation and translations (`corner2`: the unknowns of corner 2's vertex).
#[allow(clippy::too_many_arguments)]
fn closes(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    corner2: [f64; 4],
    omega: f64,
    t: usize,
    frames: &[(u8, [f64; 3], [f64; 3]); 3],
    coords: &[[f64; 2]; 3],
    shift: &[[i64; 2]; 3],
) -> bool {
    let tri = mesh.triangles()[t];
    let v2 = tri[2] as usize;
    // Rotation of v2's field that matches corner 1's rotated field.
    let r = match_rotation(frames[1].1, normals[tri[1] as usize], normals[v2], field[v2]);
    if r != frames[2].0 {
        return false;
    }
    let k2 = rotate_quarter(normals[v2], field[v2], r);
    let mut along = *frames;
    along[2] = (r, k2, cross(normals[v2], k2));
    let p = tri.map(|v| mesh.points()[v as usize]);
    let (d, dp) = expected_increments(&p, &along, omega, 1, 2);
    let base = angles(rotate_unknowns(r, corner2));
    let s = [nearest_period(coords[1][0] + d - base[0]), nearest_period(coords[1][1] + dp - base[1])];
    s == shift[2]
}
