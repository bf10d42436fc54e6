//! Quality figures of a PGP parameterization, for the comparison with Ray et al. 2006, Table I
//! and §5 (singular triangles "2–3 % of the triangles"):
//!
//! - **singular triangles**: the fraction of triangles that §3.2 classifies as singular;
//! - **stretch**: Sander et al.'s L2 stretch (`sqrt(Σ A (σ1² + σ2²)/2 / Σ A)`, 1 = isometric up
//!   to one global scale) of the map from (θ, φ)/ω to the surface over the *regular* triangles
//!   (not singular and touching no singular vertex or edge: the paper re-parameterizes the
//!   charts around singularities, §3.4, [`super::charts`]; this measures PGP's own (θ, φ)), after the global scale
//!   that equalizes the total areas ([`crate::metrics`]);
//! - **shear**: the area-weighted mean over the regular triangles of |cos ψ|, ψ the angle between
//!   the images ∂p/∂θ and ∂p/∂φ of the two parameter directions (0 when the iso-θ and iso-φ lines
//!   cross at right angles). The paper does not define its two columns; these are our reading
//!   of them, stated so that the numbers can be reproduced;
//! - **alignment**: the area-weighted mean over the same triangles of the angle between ∇θ^T
//!   and the field K (rotation-matched to the triangle's corner 0 and averaged over its
//!   corners), and between ∇φ^T and K⊥, in degrees.

use super::extraction::CornerParameterization;
use super::periodic::corner_frames;
use super::singularities::Singularities;
use crate::error::Result;
use crate::fields::frames::{add, normalized, scale, tangent_part, triangle_gradient, triangle_normal};
use crate::geometry::{cross, dot, norm, sub};
use crate::TriMesh;

/// Quality figures (module comment). Distortion fields are NaN when no triangle is measurable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quality {
    /// Singular triangles / all triangles.
    pub singular_triangle_fraction: f64,
    /// L2 stretch over the regular triangles.
    pub stretch: f64,
    /// Mean |cos| of the angle between the parameter directions on the surface.
    pub shear: f64,
    /// Mean angle (degrees) between the parameterization's gradients and the field.
    pub alignment_degrees: f64,
}

/// Computes the quality figures of `param`.
pub fn quality(
    mesh: &TriMesh,
    param: &CornerParameterization,
    singularities: &Singularities,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    omega: f64,
) -> Result<Quality> {
    let mut singular = vec![false; mesh.triangle_count()];
    for &t in &singularities.triangles {
        singular[t as usize] = true;
    }
    let mut touched = vec![false; mesh.vertex_count()];
    for &v in singularities.vertices.iter().chain(singularities.edges.iter().flatten()) {
        touched[v as usize] = true;
    }
    let regular: Vec<usize> = (0..mesh.triangle_count())
        .filter(|&t| !singular[t] && !mesh.triangles()[t].iter().any(|&v| touched[v as usize]))
        .collect();
    let fraction = singularities.triangles.len() as f64 / mesh.triangle_count().max(1) as f64;
    if regular.is_empty() {
        return Ok(Quality {
            singular_triangle_fraction: fraction,
            stretch: f64::NAN,
            shear: f64::NAN,
            alignment_degrees: f64::NAN,
        });
    }
    let stretch = l2_stretch(mesh, param, &regular, omega);
    let (mut shear, mut alignment, mut area) = (0.0, 0.0, 0.0);
    for &t in &regular {
        let a = mesh.geometry().area[t];
        let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
        let q = param.coords[t];
        if let Some(c) = parameter_direction_cosine(&p, &q) {
            shear += a * c;
            alignment += a * alignment_angle(mesh, normals, field, t, &q);
            area += a;
        }
    }
    Ok(Quality {
        singular_triangle_fraction: fraction,
        stretch,
        shear: shear / area,
        alignment_degrees: alignment / area,
    })
}

/// Sander's L2 stretch of (θ, φ)/ω → surface over `triangles`, after the global scale that makes
/// the total parameter area equal the total surface area (as [`crate::metrics::distortion`]).
fn l2_stretch(mesh: &TriMesh, param: &CornerParameterization, triangles: &[usize], omega: f64) -> f64 {
    let (mut sum, mut area_3d, mut area_uv) = (0.0, 0.0, 0.0);
    for &t in triangles {
        let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
        let q = param.coords[t].map(|c| [c[0] / omega, c[1] / omega]);
        if let Some((s1, s2)) = crate::metrics::per_triangle_singular_values(p, q) {
            let a = mesh.geometry().area[t];
            sum += a * 0.5 * (s1 * s1 + s2 * s2);
            area_3d += a;
            area_uv += a / (s1 * s2); // σ1 σ2 = A_3d / A_uv
        }
    }
    if area_3d == 0.0 {
        return f64::NAN;
    }
    // Scaling the parameter domain by s divides every σ by s; s² A_uv = A_3d.
    (sum / area_3d).sqrt() / (area_3d / area_uv).sqrt()
}

/// |cos| of the angle between ∂p/∂θ and ∂p/∂φ on a triangle (None if degenerate).
fn parameter_direction_cosine(p: &[[f64; 3]; 3], q: &[[f64; 2]; 3]) -> Option<f64> {
    let (d1, d2) = ([q[1][0] - q[0][0], q[1][1] - q[0][1]], [q[2][0] - q[0][0], q[2][1] - q[0][1]]);
    let det = d1[0] * d2[1] - d2[0] * d1[1];
    if det.abs() < 1e-300 {
        return None;
    }
    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    // [∂p/∂θ ∂p/∂φ] = [e1 e2] [d1 d2]⁻¹.
    let inv = [[d2[1] / det, -d2[0] / det], [-d1[1] / det, d1[0] / det]];
    let ju: [f64; 3] = std::array::from_fn(|k| e1[k] * inv[0][0] + e2[k] * inv[1][0]);
    let jv: [f64; 3] = std::array::from_fn(|k| e1[k] * inv[0][1] + e2[k] * inv[1][1]);
    let (nu, nv) = (norm(ju), norm(jv));
    (nu > 0.0 && nv > 0.0).then(|| (dot(ju, jv) / (nu * nv)).abs())
}

/// Mean of the angles (degrees) ∠(∇θ, K'_T) and ∠(∇φ, N × K'_T) on triangle t.
fn alignment_angle(mesh: &TriMesh, normals: &[[f64; 3]], field: &[[f64; 3]], t: usize, q: &[[f64; 2]; 3]) -> f64 {
    let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
    let n = triangle_normal(mesh, t);
    let frames = corner_frames(mesh, normals, field, t);
    let k = normalized(tangent_part(scale(add(add(frames[0].1, frames[1].1), frames[2].1), 1.0 / 3.0), n));
    let kp = cross(n, k);
    let gt = triangle_gradient(&p, n, [q[0][0], q[1][0], q[2][0]]);
    let gp = triangle_gradient(&p, n, [q[0][1], q[1][1], q[2][1]]);
    let angle = |g: [f64; 3], d: [f64; 3]| norm(cross(g, d)).atan2(dot(g, d)).to_degrees();
    0.5 * (angle(gt, k) + angle(gp, kp))
}
