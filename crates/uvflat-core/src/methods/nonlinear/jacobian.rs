//! Per-triangle Jacobians of a piecewise-linear map from the surface to the plane, and their
//! singular value decomposition (course notes §3.2–3.3, ch. 4 eq. 4.3).
//!
//! Each triangle gets an isometric 2D frame: corner 0 at the origin, corner 1 on the positive
//! x axis, corner 2 in the upper half plane (counter-clockwise). With `p_k` the frame
//! coordinates and `X = [p1 − p0, p2 − p0]`, the Jacobian of the linear map sending `p_k` to
//! `uv_k` is `J = [uv1 − uv0, uv2 − uv0] X⁻¹`, i.e. `J = Σ_k uv_k ⊗ g_k` with `g_1`, `g_2` the
//! rows of `X⁻¹` and `g_0 = −g_1 − g_2` (the gradients of the hat functions). `det J > 0` means
//! the triangle keeps its orientation in the plane; `det J = A_uv / A_3d`.
//!
//! The singular values `σ1 ≥ σ2` of `J` (of the map surface → plane, the `g` of course notes
//! §4.1) come from the closed form for 2×2 matrices: `J` splits into a similarity part
//! `(e, h)` and an anti-similarity part `(f, g)`, `σ1 = |(e, h)| + |(f, g)|`,
//! `σ2 = det J / σ1` (signed: negative for a flipped triangle), `J = Rot(φ) diag(σ1, σ2) Rot(θ)`.

use crate::geometry::{cross, dot, norm, sub};
use rayon::prelude::*;

/// A 2×2 matrix, row-major: `[[a, b], [c, d]]`.
pub type Mat2 = [[f64; 2]; 2];

/// Rest geometry of every triangle: its 3D area and the gradients of its hat functions in its
/// local frame.
#[derive(Debug, Clone)]
pub struct RestFrames {
    /// 3D area of each triangle.
    pub area: Vec<f64>,
    /// `g_k` for the three corners of each triangle.
    pub grad: Vec<[[f64; 2]; 3]>,
    /// Sum of `area`.
    pub total_area: f64,
}

impl RestFrames {
    /// Frames of the triangles `tris` (indices into `points`).
    pub fn new(points: &[[f64; 3]], tris: &[[u32; 3]]) -> Self {
        let (area, grad): (Vec<f64>, Vec<[[f64; 2]; 3]>) = tris
            .par_iter()
            .with_min_len(4096)
            .map(|t| {
                let p = t.map(|v| points[v as usize]);
                let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
                let l1 = norm(e1);
                let x2 = dot(e1, e2) / l1;
                let y2 = norm(cross(e1, e2)) / l1;
                // X = [[l1, x2], [0, y2]], X⁻¹ = [[1/l1, −x2/(l1 y2)], [0, 1/y2]].
                let g1 = [1.0 / l1, -x2 / (l1 * y2)];
                let g2 = [0.0, 1.0 / y2];
                (0.5 * l1 * y2, [[-g1[0] - g2[0], -g1[1] - g2[1]], g1, g2])
            })
            .unzip();
        let total_area = area.iter().sum();
        RestFrames { area, grad, total_area }
    }

    /// Jacobian of triangle `t` under the map `uv` (indexed like the triangles).
    #[inline]
    pub fn jacobian(&self, t: usize, tri: [u32; 3], uv: &[[f64; 2]]) -> Mat2 {
        let g = &self.grad[t];
        let mut j = [[0.0; 2]; 2];
        for k in 0..3 {
            let x = uv[tri[k] as usize];
            for r in 0..2 {
                for c in 0..2 {
                    j[r][c] += x[r] * g[k][c];
                }
            }
        }
        j
    }
}

/// Determinant.
#[inline]
pub fn det(j: &Mat2) -> f64 {
    j[0][0] * j[1][1] - j[0][1] * j[1][0]
}

/// Signed singular value decomposition `J = Rot(φ) diag(σ1, σ2) Rot(θ)` of a 2×2 matrix.
#[derive(Debug, Clone, Copy)]
pub struct Svd2 {
    /// Largest singular value.
    pub s1: f64,
    /// Second singular value, negative when `det J < 0`.
    pub s2: f64,
    /// `(cos φ, sin φ)`: the left rotation U.
    pub u: [f64; 2],
    /// `(cos θ, sin θ)`: the right rotation Vᵀ.
    pub vt: [f64; 2],
}

impl Svd2 {
    /// Closed-form decomposition.
    pub fn new(j: &Mat2) -> Self {
        let e = 0.5 * (j[0][0] + j[1][1]);
        let f = 0.5 * (j[0][0] - j[1][1]);
        let g = 0.5 * (j[1][0] + j[0][1]);
        let h = 0.5 * (j[1][0] - j[0][1]);
        let q = e.hypot(h);
        let r = f.hypot(g);
        let s1 = q + r;
        let s2 = if s1 > 0.0 { det(j) / s1 } else { 0.0 };
        let a1 = g.atan2(f);
        let a2 = h.atan2(e);
        let (theta, phi) = (0.5 * (a2 - a1), 0.5 * (a2 + a1));
        Svd2 { s1, s2, u: [phi.cos(), phi.sin()], vt: [theta.cos(), theta.sin()] }
    }

    /// `U diag(d1, d2) Vᵀ`: the matrix derivative of an energy whose partial derivatives in
    /// the singular values are `d1`, `d2`.
    #[inline]
    pub fn compose(&self, d1: f64, d2: f64) -> Mat2 {
        let ([cu, su], [cv, sv]) = (self.u, self.vt);
        // U diag(d) = [[cu d1, −su d2], [su d1, cu d2]]; Vᵀ = [[cv, −sv], [sv, cv]].
        let m = [[cu * d1, -su * d2], [su * d1, cu * d2]];
        [
            [m[0][0] * cv + m[0][1] * sv, -m[0][0] * sv + m[0][1] * cv],
            [m[1][0] * cv + m[1][1] * sv, -m[1][0] * sv + m[1][1] * cv],
        ]
    }

    /// `U diag(d1, d2) Uᵀ` (a symmetric matrix with eigenvectors the columns of U).
    #[inline]
    pub fn left_symmetric(&self, d1: f64, d2: f64) -> Mat2 {
        let [c, s] = self.u;
        let off = c * s * (d1 - d2);
        [[c * c * d1 + s * s * d2, off], [off, s * s * d1 + c * c * d2]]
    }

    /// The closest rotation `U Vᵀ` to J (for `det J > 0`).
    #[inline]
    pub fn rotation(&self) -> Mat2 {
        self.compose(1.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mul(a: &Mat2, b: &Mat2) -> Mat2 {
        let mut m = [[0.0; 2]; 2];
        for r in 0..2 {
            for c in 0..2 {
                m[r][c] = a[r][0] * b[0][c] + a[r][1] * b[1][c];
            }
        }
        m
    }

    #[test]
    fn svd_reconstructs_the_matrix_and_orders_singular_values() {
        for j in [
            [[1.0, 0.3], [-0.2, 2.0]],
            [[0.0, -1.0], [1.0, 0.0]],
            [[3.0, 1.0], [2.0, -1.0]],
            [[1e-3, 5.0], [0.0, 1e-4]],
        ] {
            let s = Svd2::new(&j);
            let back = s.compose(s.s1, s.s2);
            for r in 0..2 {
                for c in 0..2 {
                    assert!((back[r][c] - j[r][c]).abs() < 1e-12, "{j:?} vs {back:?}");
                }
            }
            assert!(s.s1 >= s.s2.abs());
            assert!((s.s1 * s.s2 - det(&j)).abs() < 1e-12);
            let rot = s.rotation();
            let rtr = mul(&[[rot[0][0], rot[1][0]], [rot[0][1], rot[1][1]]], &rot);
            assert!((rtr[0][0] - 1.0).abs() < 1e-12 && rtr[0][1].abs() < 1e-12 && (det(&rot) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn identity_map_of_a_flat_triangle_has_identity_jacobian() {
        let points = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 1.5, 0.0]];
        let frames = RestFrames::new(&points, &[[0, 1, 2]]);
        let uv = [[0.0, 0.0], [2.0, 0.0], [0.5, 1.5]];
        let j = frames.jacobian(0, [0, 1, 2], &uv);
        assert!(
            (j[0][0] - 1.0).abs() < 1e-14
                && j[0][1].abs() < 1e-14
                && j[1][0].abs() < 1e-14
                && (j[1][1] - 1.0).abs() < 1e-14
        );
        assert!((frames.area[0] - 1.5).abs() < 1e-14);
    }
}
