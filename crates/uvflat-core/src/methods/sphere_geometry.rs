//! Geometry on the unit sphere shared by the spherical maps (`methods::sphere`) and the circle
//! patterns over the sphere (`methods::circle_patterns::sphere`): the orientation determinant
//! and the flip count of a spherical triangulation, the inverse stereographic projection, and a
//! mesh with some triangles removed (the pole cap both cut out before flattening).

use crate::error::Result;
use crate::geometry::{cross, dot, sub};
use crate::mesh::TriMesh;

/// `det[a, b, c] = a · (b × c)`, evaluated as `a · ((b − a) × (c − a))` (the same value: the
/// dropped terms are `a · (a × ·) = 0`), whose differences keep their accuracy for the tiny
/// triangles where `a · (b × c)` cancels catastrophically.
#[inline]
pub(crate) fn det(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    dot(a, cross(sub(b, a), sub(c, a)))
}

/// Triangles whose spherical orientation `det[p0, p1, p2]` is not positive (or not finite).
pub fn count_spherical_flips(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> usize {
    triangles
        .iter()
        .filter(|t| {
            let d = det(positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize]);
            !(d > 0.0)
        })
        .count()
}

/// The mesh without the triangles listed in `removed` (same vertex numbering).
pub(crate) fn without_triangles(mesh: &TriMesh, removed: impl Fn(usize) -> bool) -> Result<TriMesh> {
    let positions: Vec<f64> = mesh.points().iter().flatten().copied().collect();
    let triangles: Vec<u32> =
        mesh.triangles().iter().enumerate().filter(|&(t, _)| !removed(t)).flat_map(|(_, t)| *t).collect();
    TriMesh::new(&positions, &triangles)
}

/// Inverse stereographic projection of the plane onto the unit sphere, ∞ at the south pole:
/// `(x, y) ↦ (2x, 2y, 1 − r²) / (1 + r²)`.
pub(crate) fn inverse_stereographic(x: f64, y: f64) -> [f64; 3] {
    let r2 = x * x + y * y;
    [2.0 * x / (1.0 + r2), 2.0 * y / (1.0 + r2), (1.0 - r2) / (1.0 + r2)]
}
