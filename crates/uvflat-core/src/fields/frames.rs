//! Tangent frames shared by every step of PGP (Ray, Li, Lévy, Sheffer, Alliez 2006, *Periodic
//! Global Parameterization*): vertex normals, the rotation R by π/2 in a tangent plane
//! (`R K = N × K`, so `K⊥ = R K`), the rotation matching of §2.4 eq. 13 / Algorithm 1
//! (`r = argmax_r K_i · R^r K_j`), the triangle weights λ_i^T of Appendix B eq. 24, and the
//! positive-semidefinite projection of a triangle's energy form.
//!
//! Conventions: triangles are counter-clockwise around their normal; corner `k` of triangle `t`
//! is vertex `triangles[t][k]`; edge `i` of a triangle is the one opposite corner `i`, running
//! from corner `i ⊕ 1` to corner `i ⊕ 2` (paper, Fig. 3). Angles are in radians.

use crate::geometry::{cross, dot, norm, sub};
use crate::mesh::NONE;
use crate::TriMesh;
use faer::c64;

/// Unit normal of triangle `t` (counter-clockwise orientation).
pub fn triangle_normal(mesh: &TriMesh, t: usize) -> [f64; 3] {
    let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
    normalized(cross(sub(p[1], p[0]), sub(p[2], p[0])))
}

/// Area-weighted unit vertex normals (the sum of the incident triangles' cross products);
/// `[0, 0, 0]` for unreferenced vertices.
pub fn vertex_normals(mesh: &TriMesh) -> Vec<[f64; 3]> {
    let mut n = vec![[0.0; 3]; mesh.vertex_count()];
    for tri in mesh.triangles() {
        let p = tri.map(|v| mesh.points()[v as usize]);
        let c = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        for &v in tri {
            for a in 0..3 {
                n[v as usize][a] += c[a];
            }
        }
    }
    n.iter_mut().for_each(|v| *v = normalized(*v));
    n
}

/// `v / |v|`, or zero for a zero vector.
pub fn normalized(v: [f64; 3]) -> [f64; 3] {
    let l = norm(v);
    if l > 0.0 {
        scale(v, 1.0 / l)
    } else {
        [0.0; 3]
    }
}

/// `s · v`.
#[inline]
pub fn scale(v: [f64; 3], s: f64) -> [f64; 3] {
    [v[0] * s, v[1] * s, v[2] * s]
}

/// `a + b`.
#[inline]
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// The component of `v` tangent to the plane of unit normal `n`.
#[inline]
pub fn tangent_part(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    sub(v, scale(n, dot(v, n)))
}

/// `P^r x` for parameter coordinates x = (θ, φ), with P(θ, φ) = (φ, −θ): the quarter turn the
/// rotation matching applies to the unknowns ([`crate::methods::pgp::periodic::unknown_rotation`]).
pub fn rotate_coords(r: u8, x: [f64; 2]) -> [f64; 2] {
    (0..r % 4).fold(x, |x, _| [x[1], -x[0]])
}

/// `R^r v`: `v` rotated by `r · π/2` counter-clockwise about the unit normal `n` (for `v` in
/// the tangent plane of `n`): `v`, `n × v`, `−v`, `−n × v`.
pub fn rotate_quarter(n: [f64; 3], v: [f64; 3], r: u8) -> [f64; 3] {
    match r % 4 {
        0 => v,
        1 => cross(n, v),
        2 => scale(v, -1.0),
        _ => scale(cross(n, v), -1.0),
    }
}

/// `v`, tangent at unit normal `from`, carried to the tangent plane of unit normal `to` by the
/// smallest rotation taking `from` to `to` (`v − (v·to)/(1 + from·to) (from + to)`); unchanged
/// when the normals are opposite.
pub fn transport(v: [f64; 3], from: [f64; 3], to: [f64; 3]) -> [f64; 3] {
    let c = 1.0 + dot(from, to);
    if c <= 1e-12 {
        return v;
    }
    sub(v, scale(add(from, to), dot(v, to) / c))
}

/// Rotation matching (eq. 13, Algorithm 1): the `r ∈ {0..3}` maximizing
/// `reference · R^r v`, with `reference` tangent at normal `n_ref` and `v` tangent at `n`. The
/// paper compares the 3D vectors directly; here `v` is first carried to `reference`'s tangent
/// plane ([`transport`]), which commutes with R, so the matched rotations do not depend on
/// which quarter turn represents the field at a vertex. Ties go to the smallest `r`.
pub fn match_rotation(reference: [f64; 3], n_ref: [f64; 3], n: [f64; 3], v: [f64; 3]) -> u8 {
    let t = transport(v, n, n_ref);
    let w = cross(n_ref, t);
    // R^0 t = t, R t = w, R² t = −t, R³ t = −w.
    let scores = [dot(reference, t), dot(reference, w), -dot(reference, t), -dot(reference, w)];
    let mut best = 0u8;
    for r in 1..4u8 {
        if scores[r as usize] > scores[best as usize] {
            best = r;
        }
    }
    best
}

/// The angle `x` wrapped into (−π, π].
#[inline]
pub fn wrap_angle(x: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut y = x - two_pi * (x / two_pi).round();
    if y <= -std::f64::consts::PI {
        y += two_pi;
    }
    y
}

/// Triangle weights λ_i^T of Appendix B, eq. 24, multiplied by the triangle area so that
/// `Σ_i λ_i (g · e_i)² = A_T |g|²` for every vector `g` in the triangle's plane: the solution of
/// eq. 24 is `λ_i = cot(α_i) / (2 A_T)` with `α_i` the angle at corner `i` (opposite edge `e_i`),
/// so the area-scaled weights are the cotangent weights `cot(α_i) / 2`. (A unit test checks this
/// against a direct solve of eq. 24.) Negative for obtuse corners.
pub fn triangle_weights(mesh: &TriMesh, t: usize) -> [f64; 3] {
    mesh.geometry().cot[t].map(|c| 0.5 * c)
}

/// Gradient of the linear interpolant of `values` on the triangle `p` (normal `n`).
pub fn triangle_gradient(p: &[[f64; 3]; 3], n: [f64; 3], values: [f64; 3]) -> [f64; 3] {
    let area2 = dot(cross(sub(p[1], p[0]), sub(p[2], p[0])), n);
    let mut g = [0.0; 3];
    for c in 0..3 {
        let w = cross(n, sub(p[(c + 2) % 3], p[(c + 1) % 3]));
        for a in 0..3 {
            g[a] += values[c] * w[a] / area2;
        }
    }
    g
}

/// Unique undirected edges of a mesh: `edges[e] = [a, b]` (the tail and head of the edge's
/// lowest half-edge) and `edge_of[h]` for every half-edge `h`.
pub struct EdgeList {
    /// Endpoints of each edge.
    pub edges: Vec<[u32; 2]>,
    /// Edge of each half-edge (`3t + k`).
    pub edge_of: Vec<u32>,
}

impl EdgeList {
    /// Numbers the edges in half-edge order.
    pub fn new(mesh: &TriMesh) -> Self {
        let twin = &mesh.connectivity().twin;
        let mut edge_of = vec![NONE; twin.len()];
        let mut edges = Vec::with_capacity(twin.len() / 2 + 1);
        for h in 0..twin.len() {
            if edge_of[h] != NONE {
                continue;
            }
            let id = edges.len() as u32;
            edge_of[h] = id;
            if twin[h] != NONE {
                edge_of[twin[h] as usize] = id;
            }
            edges.push([mesh.tail(h as u32), mesh.head(h as u32)]);
        }
        EdgeList { edges, edge_of }
    }
}

/// A Hermitian 3×3 form `u* H u` on the three corners of a triangle.
pub type Hermitian3 = [[c64; 3]; 3];

/// The edge-sum form of eq. 14 / eq. 22 on one triangle: `Σ_i w_i |u_b − c_i u_a|²` with
/// `(a, b) = (i ⊕ 1, i ⊕ 2)` and `|c_i| = 1`.
pub fn edge_sum_form(weights: [f64; 3], rotations: [c64; 3]) -> Hermitian3 {
    let zero = c64::new(0.0, 0.0);
    let mut h = [[zero; 3]; 3];
    for i in 0..3 {
        let (a, b, w, c) = ((i + 1) % 3, (i + 2) % 3, weights[i], rotations[i]);
        h[a][a] += c64::new(w, 0.0);
        h[b][b] += c64::new(w, 0.0);
        // |u_b − c u_a|² = |u_b|² + |u_a|² − 2 Re(conj(u_b) c u_a).
        h[b][a] -= c * w;
        h[a][b] -= c.conj() * w;
    }
    h
}

/// The closest positive-semidefinite form (negative eigenvalues set to zero). A triangle with
/// an obtuse corner has a negative weight in eq. 24; its edge-sum form is then indefinite as
/// soon as the rotations around the triangle do not compose to the identity, which could make
/// the global system indefinite. Forms that are already semidefinite come back unchanged.
pub fn project_semidefinite(h: Hermitian3) -> Hermitian3 {
    if is_semidefinite(&h) {
        return h;
    }
    let m = faer::Mat::<c64>::from_fn(3, 3, |i, j| h[i][j]);
    let Ok(eig) = m.self_adjoint_eigen(faer::Side::Lower) else { return h };
    let (u, s) = (eig.U(), eig.S());
    let mut out = [[c64::new(0.0, 0.0); 3]; 3];
    for k in 0..3 {
        let lambda = s[k].re.max(0.0);
        if lambda == 0.0 {
            continue;
        }
        for i in 0..3 {
            for j in 0..3 {
                out[i][j] += u[(i, k)] * u[(j, k)].conj() * lambda;
            }
        }
    }
    out
}

/// Whether a Hermitian 3×3 form is positive semidefinite: all its principal minors (the three
/// diagonal entries, the three 2×2 minors and the determinant) are ≥ 0, up to a tolerance
/// relative to the largest diagonal entry.
fn is_semidefinite(h: &Hermitian3) -> bool {
    let s = (0..3).map(|i| h[i][i].re.abs()).fold(0.0, f64::max);
    if s == 0.0 {
        return (0..3).all(|i| (0..3).all(|j| h[i][j].norm() == 0.0));
    }
    let tol = 1e-12;
    let diagonal_ok = (0..3).all(|i| h[i][i].re >= -tol * s);
    let minors_ok =
        [(0, 1), (0, 2), (1, 2)].iter().all(|&(i, j)| h[i][i].re * h[j][j].re - h[i][j].norm_sqr() >= -tol * s * s);
    let det = h[0][0] * (h[1][1] * h[2][2] - h[1][2] * h[2][1]) - h[0][1] * (h[1][0] * h[2][2] - h[1][2] * h[2][0])
        + h[0][2] * (h[1][0] * h[2][1] - h[1][1] * h[2][0]);
    diagonal_ok && minors_ok && det.re >= -tol * s * s * s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tilted_triangle() -> TriMesh {
        let positions = [0.1, 0.2, 0.0, 1.3, -0.1, 0.4, 0.2, 0.9, 0.7];
        TriMesh::new(&positions, &[0, 1, 2]).unwrap()
    }

    /// Appendix B: λ solves [e_x², e_y², 2 e_x e_y] λ = [1, 1, 0] in a frame of the triangle's
    /// plane; times the area it is the cotangent half-weight.
    #[test]
    fn triangle_weights_solve_appendix_b_equation_24() {
        let mesh = tilted_triangle();
        let p = mesh.triangles()[0].map(|v| mesh.points()[v as usize]);
        let n = triangle_normal(&mesh, 0);
        let x = normalized(sub(p[1], p[0]));
        let y = cross(n, x);
        let e: Vec<[f64; 2]> = (0..3)
            .map(|i| {
                let d = sub(p[(i + 2) % 3], p[(i + 1) % 3]);
                [dot(d, x), dot(d, y)]
            })
            .collect();
        let m = faer::Mat::<f64>::from_fn(3, 3, |r, c| match r {
            0 => e[c][0] * e[c][0],
            1 => e[c][1] * e[c][1],
            _ => 2.0 * e[c][0] * e[c][1],
        });
        let rhs = faer::Mat::<f64>::from_fn(3, 1, |r, _| if r < 2 { 1.0 } else { 0.0 });
        let lambda = faer::linalg::solvers::Solve::solve(&m.partial_piv_lu(), &rhs);
        let area = mesh.geometry().area[0];
        let w = triangle_weights(&mesh, 0);
        for i in 0..3 {
            assert!((lambda[(i, 0)] * area - w[i]).abs() < 1e-12, "{i}: {} vs {}", lambda[(i, 0)] * area, w[i]);
        }
        // And the identity they encode: Σ λ_i (g·e_i)² = A |g|².
        let g = [0.3, -1.7];
        let s: f64 = (0..3).map(|i| w[i] * (g[0] * e[i][0] + g[1] * e[i][1]).powi(2)).sum();
        assert!((s - area * (g[0] * g[0] + g[1] * g[1])).abs() < 1e-12);
    }

    #[test]
    fn rotation_matching_picks_the_closest_quarter_turn() {
        let n = [0.0, 0.0, 1.0];
        let reference = [1.0, 0.1, 0.0];
        assert_eq!(match_rotation(reference, n, n, [1.0, 0.0, 0.0]), 0);
        assert_eq!(match_rotation(reference, n, n, [0.0, -1.0, 0.0]), 1); // R(0,-1) = (1,0)
        assert_eq!(match_rotation(reference, n, n, [-1.0, 0.2, 0.0]), 2);
        assert_eq!(match_rotation(reference, n, n, [0.1, 1.0, 0.0]), 3);
        for r in 0..4 {
            let v = rotate_quarter(n, [0.8, 0.6, 0.0], r);
            let back = rotate_quarter(n, v, match_rotation([0.8, 0.6, 0.0], n, n, v));
            assert!(norm(sub(back, [0.8, 0.6, 0.0])) < 1e-12);
        }
        // With different normals, the matched rotation follows the representative exactly.
        let m = normalized([0.3, -0.2, 1.0]);
        let v = normalized(tangent_part([0.2, 1.0, 0.4], m));
        let base = match_rotation(reference, n, m, v);
        for r in 0..4u8 {
            assert_eq!((match_rotation(reference, n, m, rotate_quarter(m, v, r)) + r) % 4, base);
        }
        // Transport keeps length and lands in the target plane.
        let t = transport(v, m, n);
        assert!((norm(t) - 1.0).abs() < 1e-12 && dot(t, n).abs() < 1e-12);
    }

    #[test]
    fn semidefinite_projection_keeps_semidefinite_forms_and_fixes_indefinite_ones() {
        let rot = |a: f64| c64::new(a.cos(), a.sin());
        let psd = edge_sum_form([0.4, 0.7, 0.2], [rot(0.3), rot(-0.2), rot(1.0)]);
        assert_eq!(project_semidefinite(psd), psd);
        // An obtuse corner (negative weight) and a non-trivial holonomy: indefinite.
        let bad = edge_sum_form([-0.3, 0.9, 0.8], [rot(0.4), rot(0.5), rot(0.6)]);
        assert!(!is_semidefinite(&bad));
        let fixed = project_semidefinite(bad);
        let m = faer::Mat::<c64>::from_fn(3, 3, |i, j| fixed[i][j]);
        let eig = m.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
        assert!(eig.iter().all(|&l| l > -1e-12), "{eig:?}");
        assert!(is_semidefinite(&fixed));
    }

    #[test]
    fn wrap_angle_is_odd_inside_the_open_interval() {
        for x in [-7.0, -3.0, -0.5, 0.0, 0.5, 3.0, 7.0, 20.0] {
            let w = wrap_angle(x);
            assert!(w > -std::f64::consts::PI && w <= std::f64::consts::PI);
            assert!(((x - w) / std::f64::consts::TAU - ((x - w) / std::f64::consts::TAU).round()).abs() < 1e-12);
        }
    }
}
