//! Indices of direction fields at the vertices of a triangle mesh. For a field given per
//! triangle as tangent vectors, modulo 2π/k (k = 1 vectors, 2 lines, 4 crosses), the index at an
//! interior vertex v is
//!
//! ```text
//! I(v) = (K_v + Σ Δ_e) / 2π
//! ```
//!
//! with K_v the angle defect at v and Δ_e, for each edge crossed counter-clockwise around v, the
//! change of the field's direction after parallel transport across the edge (unfolding the two
//! triangles), reduced into (−π/k, π/k] (Ray, Vallet, Li & Lévy 2008, "N-symmetry direction
//! field design", §3). Every Δ_e enters the two endpoints of its edge with opposite signs, so
//! discrete Gauss–Bonnet gives Σ I(v) = χ on a closed mesh; each I(v) is a multiple of 1/k.
//! The per-edge changes and the vertex sum are shared with the cross-field index of a PGP
//! parameterization ([`crate::methods::pgp::singularities`]).
//!
//! Cost: O(F), in parallel.

use crate::fields::frames::{normalized, triangle_normal};
use crate::geometry::{cross, dot, sub};
use crate::mesh::NONE;
use crate::TriMesh;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The direction angle of each triangle's vector in the triangle's frame (x = edge 0→1,
/// y = n × x), and the frames.
pub(crate) fn face_angles(mesh: &TriMesh, directions: &[[f64; 3]]) -> Vec<(f64, [f64; 3], [f64; 3])> {
    (0..mesh.triangle_count())
        .into_par_iter()
        .with_min_len(4096)
        .map(|t| {
            let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
            let n = triangle_normal(mesh, t);
            let x = normalized(sub(p[1], p[0]));
            let y = cross(n, x);
            let g = directions[t];
            (dot(g, y).atan2(dot(g, x)), x, y)
        })
        .collect()
}

/// `x` reduced modulo 2π/k into (−π/k, π/k].
#[inline]
fn wrap_symmetric(x: f64, k: u32) -> f64 {
    let period = TAU / k as f64;
    let mut y = x - period * (x / period).round();
    if y <= -period / 2.0 {
        y += period;
    }
    y
}

/// Angle of the 3D vector `e` in a triangle's frame.
pub(crate) fn edge_angle(frame: &(f64, [f64; 3], [f64; 3]), e: [f64; 3]) -> f64 {
    dot(e, frame.2).atan2(dot(e, frame.1))
}

/// Per half-edge h with a twin g: `change_of(h, g, e)`, the change crossing from h's triangle
/// into g's (e = head − tail of h), and its negative for g (computed once per edge).
pub(crate) fn edge_changes(mesh: &TriMesh, change_of: impl Fn(usize, usize, [f64; 3]) -> f64) -> Vec<f64> {
    let twin = &mesh.connectivity().twin;
    let mut change = vec![0.0; twin.len()];
    for h in 0..twin.len() {
        let g = twin[h];
        if g == NONE || (g as usize) < h {
            continue;
        }
        let e = sub(mesh.points()[mesh.head(h as u32) as usize], mesh.points()[mesh.tail(h as u32) as usize]);
        let d = change_of(h, g as usize, e);
        change[h] = d;
        change[g as usize] = -d;
    }
    change
}

/// Index at every interior vertex of the field of directions modulo 2π/k given per triangle
/// (tangent vectors): `(K_v + Σ Δ_e) / 2π` as in the module comment, with Δ_e reduced modulo
/// 2π/k. Multiples of 1/k summing to χ on a closed mesh. 0 on boundary and unreferenced
/// vertices.
pub fn face_field_indices(mesh: &TriMesh, directions: &[[f64; 3]], k: u32) -> Vec<f64> {
    let frames = face_angles(mesh, directions);
    let change = edge_changes(mesh, |h, g, e| {
        // The direction in g's triangle minus the one of h's, carried across e by unfolding.
        let (from, to) = (&frames[h / 3], &frames[g / 3]);
        wrap_symmetric(to.0 - (from.0 - edge_angle(from, e) + edge_angle(to, e)), k)
    });
    vertex_indices(mesh, &change)
}

/// `(K_v + Σ change) / 2π` at every interior vertex over the edges crossed counter-clockwise
/// around it.
pub(crate) fn vertex_indices(mesh: &TriMesh, change: &[f64]) -> Vec<f64> {
    let twin = &mesh.connectivity().twin;
    let angles = mesh.corner_angles();
    (0..mesh.vertex_count() as u32)
        .into_par_iter()
        .with_min_len(4096)
        .map(|v| {
            if !mesh.is_referenced(v) || mesh.is_boundary_vertex(v) {
                return 0.0;
            }
            let mut total = TAU;
            for h in mesh.outgoing_halfedges(v) {
                total -= angles[(h / 3) as usize][(h % 3) as usize];
                // Counter-clockwise around v, edge h is crossed from twin(h)'s triangle into h's.
                total += change[twin[h as usize] as usize];
            }
            total / TAU
        })
        .collect()
}
