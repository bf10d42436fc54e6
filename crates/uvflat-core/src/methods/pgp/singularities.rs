//! Singular vertices, edges and triangles of a PGP parameterization (Ray et al. 2006, §3.2) and
//! the indices of its singular points (Hopf–Poincaré: they sum to 2 − 2g on a closed surface of
//! genus g).
//!
//! From the per-triangle parameterization of §3.1 ([`super::extraction`]):
//! - a **triangle** is singular when Algorithm 1 around it gives an open path, or when its
//!   (θ, φ) triangle has non-positive signed area;
//! - an **edge** (a, b) between triangles T1 and T2 is singular when the transition function of
//!   eq. 16 computed at a differs from the one computed at b. At a vertex v the transition is
//!   `τ(p) = P^ρ p + 2π d` with ρ = ρ_T2(v) − ρ_T1(v) and `d = shift_T2(v) − P^ρ shift_T1(v)`,
//!   P being the quarter turn (θ, φ) → (φ, −θ); both are integers, so the test is exact. (Where
//!   the transitions agree the edge has the same length on both sides; the paper states the
//!   test as a length mismatch.)
//! - an interior **vertex** is singular when the signed (θ, φ) angles at its corners do not sum
//!   to 2π (tolerance 10⁻⁶ rad).
//!
//! Index. The parameterization defines a frame per triangle T: the direction of the surface
//! that T's (θ, φ) map sends to the θ axis, J_T⁻¹(1, 0). Across the transitions of eq. 16
//! (quarter turns) these frames form a field of crosses, whose index at an interior vertex v is
//!
//! ```text
//! I(v) = (K_v + Σ Δ_e) / 2π
//! ```
//!
//! with K_v the angle defect (2π minus the 3D corner angles at v) and, for each edge e crossed
//! counter-clockwise around v from T1 to T2, Δ_e the change of the frame's direction after
//! parallel transport across e (unfolding) minus the image-side rotation. Both are measured
//! from the shared edge: on each side, d_T is the 3D angle from e to the frame and α_T the
//! (θ, φ) angle from e's image to the θ axis, both in (−π, π]. A linear map keeps the order of
//! directions, so d_T and α_T are lifts of the same turn (same sign when T is positive); then
//! `Δ_e = (d_T2 − d_T1) − R_e` with R_e the image rotation α_T2 − α_T1 rounded to the nearest
//! value τ_e·π/2 + 2πm allowed by the transition rotation τ_e (τ of e's first endpoint; exact
//! wherever e is not singular). Around a vertex whose (θ, φ) star is planar the changes
//! telescope to I(v) = (Σ image corner angles − 2π)/2π = 0, whatever the shear of the maps
//! (the gradient ∇θ, used before, can turn by more than π between two sheared neighbours and
//! gave spurious ±1 indices on sliver triangles). Every Δ_e enters the two endpoints of e with
//! opposite signs, so discrete Gauss–Bonnet (Σ K_v = 2πχ) gives Σ I(v) = χ = 2 − 2g on every
//! closed mesh, and I(v) is a multiple of 1/4. The vertices with I(v) ≠ 0 are the singular
//! points, and lie on singular elements.
//!
//! The index of a per-face direction field modulo 2π/k is the same sum with Δ_e the transported
//! change reduced into (−π/k, π/k] ([`crate::fields::indices`]).
//!
//! Cost: O(F), in parallel.

use super::extraction::CornerParameterization;
use crate::fields::frames::wrap_angle;
use crate::fields::indices::{edge_angle, edge_changes, face_angles, vertex_indices};
use crate::geometry::sub;
use crate::mesh::NONE;
use crate::TriMesh;
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, TAU};

/// Angle-sum tolerance of the singular-vertex test (radians).
pub const ANGLE_SUM_TOLERANCE: f64 = 1e-6;

/// The singular elements of a parameterization and the indices of its singular points.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Singularities {
    /// Interior vertices whose (θ, φ) corner angles do not sum to 2π, ascending.
    pub vertices: Vec<u32>,
    /// Interior edges whose transition functions disagree at their endpoints, `[a, b]` with
    /// a < b, sorted.
    pub edges: Vec<[u32; 2]>,
    /// Open or non-positively oriented triangles, ascending.
    pub triangles: Vec<u32>,
    /// Index of the cross field of ∇θ at every vertex (0 for boundary and unreferenced ones).
    pub index: Vec<f64>,
}

impl Singularities {
    /// Vertices with a non-zero index and their index (rounded to the nearest quarter).
    pub fn singular_points(&self) -> Vec<(u32, f64)> {
        self.index
            .iter()
            .enumerate()
            .filter_map(|(v, &i)| {
                let q = (4.0 * i).round() / 4.0;
                (q != 0.0).then_some((v as u32, q))
            })
            .collect()
    }

    /// Σ of the vertex indices.
    pub fn index_sum(&self) -> f64 {
        self.index.iter().sum()
    }
}

/// Classifies the singular elements of `param` (module comment).
pub fn find_singularities(mesh: &TriMesh, param: &CornerParameterization) -> Singularities {
    let triangles = singular_triangles(param);
    let edges = singular_edges(mesh, param);
    let vertices = singular_vertices(mesh, param);
    let index = cross_field_indices(mesh, param);
    Singularities { vertices, edges, triangles, index }
}

/// Signed area (times 2) of a (θ, φ) triangle.
pub fn signed_area2(q: &[[f64; 2]; 3]) -> f64 {
    (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (q[1][1] - q[0][1])
}

/// Whether triangle t is singular (§3.2: open, or of non-positive (θ, φ) area).
fn is_singular_triangle(param: &CornerParameterization, t: usize) -> bool {
    param.open[t] || signed_area2(&param.coords[t]) <= 0.0
}

/// Number of singular triangles ([`is_singular_triangle`]).
pub fn singular_triangle_count(param: &CornerParameterization) -> usize {
    (0..param.coords.len()).filter(|&t| is_singular_triangle(param, t)).count()
}

fn singular_triangles(param: &CornerParameterization) -> Vec<u32> {
    (0..param.coords.len() as u32).filter(|&t| is_singular_triangle(param, t as usize)).collect()
}

/// `P^r (s, t)` with P(s, t) = (t, −s).
#[inline]
fn rotate_shift(r: u8, s: [i64; 2]) -> [i64; 2] {
    let mut x = s;
    for _ in 0..(r % 4) {
        x = [x[1], -x[0]];
    }
    x
}

/// Transition (ρ, d) from the triangle of corner `(t1, k1)` to that of `(t2, k2)`, both corners
/// at the same vertex.
pub(super) fn transition(
    param: &CornerParameterization,
    (t1, k1): (usize, usize),
    (t2, k2): (usize, usize),
) -> (u8, [i64; 2]) {
    let rho = (4 + param.rotation[t2][k2] - param.rotation[t1][k1]) % 4;
    let moved = rotate_shift(rho, param.shift[t1][k1]);
    (rho, [param.shift[t2][k2][0] - moved[0], param.shift[t2][k2][1] - moved[1]])
}

fn singular_edges(mesh: &TriMesh, param: &CornerParameterization) -> Vec<[u32; 2]> {
    let twin = &mesh.connectivity().twin;
    let mut edges: Vec<[u32; 2]> = (0..twin.len())
        .into_par_iter()
        .with_min_len(4096)
        .filter_map(|h| {
            let g = twin[h] as usize;
            if twin[h] == NONE || g < h {
                return None;
            }
            // h: a → b in T1 (corner k, k+1); g: b → a in T2.
            let (t1, k1) = (h / 3, h % 3);
            let (t2, k2) = (g / 3, g % 3);
            let at_a = transition(param, (t1, k1), (t2, (k2 + 1) % 3));
            let at_b = transition(param, (t1, (k1 + 1) % 3), (t2, k2));
            if at_a == at_b {
                return None;
            }
            let (a, b) = (mesh.tail(h as u32), mesh.head(h as u32));
            Some([a.min(b), a.max(b)])
        })
        .collect();
    edges.sort_unstable();
    edges
}

/// Signed angle of the (θ, φ) triangle `q` at corner `k`.
fn signed_corner_angle(q: &[[f64; 2]; 3], k: usize) -> f64 {
    let (a, b, c) = (q[k], q[(k + 1) % 3], q[(k + 2) % 3]);
    let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
    (e1[0] * e2[1] - e1[1] * e2[0]).atan2(e1[0] * e2[0] + e1[1] * e2[1])
}

fn singular_vertices(mesh: &TriMesh, param: &CornerParameterization) -> Vec<u32> {
    (0..mesh.vertex_count() as u32)
        .into_par_iter()
        .with_min_len(4096)
        .filter(|&v| {
            if !mesh.is_referenced(v) || mesh.is_boundary_vertex(v) {
                return false;
            }
            let sum: f64 = mesh
                .outgoing_halfedges(v)
                .map(|h| signed_corner_angle(&param.coords[(h / 3) as usize], (h % 3) as usize))
                .sum();
            (sum - TAU).abs() > ANGLE_SUM_TOLERANCE
        })
        .collect()
}

/// Index of the parameterization's frame field at every interior vertex (module comment).
fn cross_field_indices(mesh: &TriMesh, param: &CornerParameterization) -> Vec<f64> {
    let frames = face_angles(mesh, &theta_preimages(mesh, param));
    let change = edge_changes(mesh, |h, g, e| {
        let (t1, k1, t2, kg) = (h / 3, h % 3, g / 3, g % 3);
        // The edge tail → head of h: corners k1 → k1 + 1 in T1, kg + 1 → kg in T2.
        let image1 = image_edge_angle(&param.coords[t1], k1, (k1 + 1) % 3);
        let image2 = image_edge_angle(&param.coords[t2], (kg + 1) % 3, kg);
        let (alpha1, alpha2) = (wrap_angle(-image1), wrap_angle(-image2));
        let d1 = lift_near(frames[t1].0 - edge_angle(&frames[t1], e), alpha1);
        let d2 = lift_near(frames[t2].0 - edge_angle(&frames[t2], e), alpha2);
        let tau = (4 + param.rotation[t2][(kg + 1) % 3] - param.rotation[t1][k1]) % 4;
        let allowed = FRAC_PI_2 * tau as f64;
        let rotation = allowed + TAU * ((alpha2 - alpha1 - allowed) / TAU).round();
        d2 - d1 - rotation
    });
    vertex_indices(mesh, &change)
}

/// J_T⁻¹(1, 0) on every triangle: the surface direction its (θ, φ) map sends to the θ axis
/// (for a (θ, φ) triangle of zero area, the 3D direction of its largest θ change).
fn theta_preimages(mesh: &TriMesh, param: &CornerParameterization) -> Vec<[f64; 3]> {
    (0..mesh.triangle_count())
        .into_par_iter()
        .with_min_len(4096)
        .map(|t| {
            let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
            let q = param.coords[t];
            let (a, b) = (sub(p[1], p[0]), sub(p[2], p[0]));
            let (qa, qb) = ([q[1][0] - q[0][0], q[1][1] - q[0][1]], [q[2][0] - q[0][0], q[2][1] - q[0][1]]);
            let det = qa[0] * qb[1] - qb[0] * qa[1];
            if det.abs() > 1e-300 {
                // w = [a b] Q⁻¹ (1, 0), Q = [qa qb]: Q⁻¹ (1, 0) = (qb[1], −qa[1]) / det.
                std::array::from_fn(|c| (a[c] * qb[1] - b[c] * qa[1]) / det)
            } else {
                let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
                if qa[0].abs() >= qb[0].abs() {
                    a.map(|x| sign(qa[0]) * x)
                } else {
                    b.map(|x| sign(qb[0]) * x)
                }
            }
        })
        .collect()
}

/// Angle of the (θ, φ) image of the edge from corner `from` to corner `to`.
fn image_edge_angle(q: &[[f64; 2]; 3], from: usize, to: usize) -> f64 {
    (q[to][1] - q[from][1]).atan2(q[to][0] - q[from][0])
}

/// The representative of the angle `x` (modulo 2π) within π of `target`. The 3D turn from an
/// edge to the frame and the (θ, φ) turn from the edge's image to the θ axis have the same sign
/// (a linear map keeps the order of directions), so the nearest lift is the exact one, also
/// where both are ≈ ±π (edges along the iso-lines).
fn lift_near(x: f64, target: f64) -> f64 {
    target + wrap_angle(x - target)
}
