//! The two nonlinear distortion energies of Desbrun–Meyer–Alliez 2002 §5.1, used by the
//! near-optimal maps (§5.1) and the boundary optimization (§5.2):
//!
//! - edge-length distortion `E = Σ_{edges ij} (|u_i − u_j|² / |x_i − x_j|² − 1)²`;
//! - area distortion `E = Σ_{faces ijk} ((A^param_ijk / A^3D_ijk)² − 1)²`, A^param the signed
//!   UV area (positive for counter-clockwise triangles), A^3D the surface area.
//!
//! Both are zero exactly for an isometry (edge lengths) or an area-preserving map (areas); both
//! depend on the UV scale, so the callers place the boundary at the scale of the surface. On a
//! line of maps `U + t D` every UV edge vector and every UV area is a polynomial in t (degree 1
//! and 2), so the edge energy is a quartic in t and the area energy — with the area ratio
//! squared as printed in the paper — a polynomial of degree 8 (the paper says "quartic"; that
//! holds for `(A^param / A^3D − 1)²`, not for the formula it prints, which is the one
//! implemented here). [`DistortionTerms::along_line`] returns that polynomial exactly, so
//! minimizing over the line is polynomial root finding ([`uvflat_sparse::polynomial`]).
//!
//! Sums run over fixed chunks in a fixed order, so results do not depend on the thread count.
//! Cost: O(edges) or O(triangles) per evaluation.

use crate::geometry::cross2;
use crate::mesh::{TriMesh, NONE};
use rayon::prelude::*;
use uvflat_sparse::polynomial::Polynomial;

/// Which distortion energy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DistortionEnergy {
    /// `Σ_edges (|u_i − u_j|² / |x_i − x_j|² − 1)²`.
    EdgeLength,
    /// `Σ_faces ((A^param / A^3D)² − 1)²`.
    Area,
}

/// Terms per chunk of the parallel sums.
const CHUNK: usize = 4096;

/// Per-mesh data of the energies: every edge with `1 / |x_i − x_j|²`, every triangle with
/// `1 / A^3D`.
pub struct DistortionTerms {
    edges: Vec<(u32, u32, f64)>,
    triangles: Vec<([u32; 3], f64)>,
}

#[inline]
fn sub2(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline]
fn dot2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Sum of `f` over chunks of `items`, chunk results added in order (deterministic).
fn chunked_sum<T: Sync, const N: usize>(items: &[T], f: impl Fn(&T) -> [f64; N] + Sync) -> [f64; N] {
    let parts: Vec<[f64; N]> = items
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut acc = [0.0; N];
            for item in chunk {
                for (a, v) in acc.iter_mut().zip(f(item)) {
                    *a += v;
                }
            }
            acc
        })
        .collect();
    let mut total = [0.0; N];
    for p in parts {
        for (t, v) in total.iter_mut().zip(p) {
            *t += v;
        }
    }
    total
}

/// Coefficients of the square of `c0 + c1 t + c2 t²`.
#[inline]
fn square_quadratic(c: [f64; 3]) -> [f64; 5] {
    [c[0] * c[0], 2.0 * c[0] * c[1], c[1] * c[1] + 2.0 * c[0] * c[2], 2.0 * c[1] * c[2], c[2] * c[2]]
}

/// Coefficients of the square of a quartic.
#[inline]
fn square_quartic(c: [f64; 5]) -> [f64; 9] {
    let mut out = [0.0; 9];
    for i in 0..5 {
        for j in 0..5 {
            out[i + j] += c[i] * c[j];
        }
    }
    out
}

impl DistortionTerms {
    /// The edges (each once) and triangles of `mesh`.
    pub fn new(mesh: &TriMesh) -> Self {
        let twin = &mesh.connectivity().twin;
        let points = mesh.points();
        let edges = (0..twin.len() as u32)
            .filter(|&h| twin[h as usize] == NONE || twin[h as usize] > h)
            .map(|h| {
                let (a, b) = (mesh.tail(h), mesh.head(h));
                let (p, q) = (points[a as usize], points[b as usize]);
                let d2 = (0..3).map(|k| (p[k] - q[k]) * (p[k] - q[k])).sum::<f64>();
                (a, b, 1.0 / d2)
            })
            .collect();
        let area = &mesh.geometry().area;
        let triangles = mesh.triangles().iter().zip(area).map(|(&t, &a)| (t, 1.0 / a)).collect();
        DistortionTerms { edges, triangles }
    }

    /// Number of terms of the energy (edges or triangles).
    pub fn term_count(&self, energy: DistortionEnergy) -> usize {
        match energy {
            DistortionEnergy::EdgeLength => self.edges.len(),
            DistortionEnergy::Area => self.triangles.len(),
        }
    }

    /// The energy of the map `uv`.
    pub fn energy(&self, energy: DistortionEnergy, uv: &[[f64; 2]]) -> f64 {
        match energy {
            DistortionEnergy::EdgeLength => chunked_sum(&self.edges, |&(a, b, inv)| {
                let e = sub2(uv[a as usize], uv[b as usize]);
                let r = dot2(e, e) * inv - 1.0;
                [r * r]
            })[0],
            DistortionEnergy::Area => chunked_sum(&self.triangles, |&(t, inv)| {
                let s = self.area_ratio(t, inv, uv);
                let r = s * s - 1.0;
                [r * r]
            })[0],
        }
    }

    #[inline]
    fn area_ratio(&self, t: [u32; 3], inv_area: f64, uv: &[[f64; 2]]) -> f64 {
        let [i, j, k] = t.map(|v| uv[v as usize]);
        0.5 * cross2(sub2(j, i), sub2(k, i)) * inv_area
    }

    /// The energy and its gradient ∂E/∂u (one entry per vertex of `uv`; zero for vertices in no
    /// term).
    pub fn gradient(&self, energy: DistortionEnergy, uv: &[[f64; 2]]) -> (f64, Vec<[f64; 2]>) {
        let mut g = vec![[0.0; 2]; uv.len()];
        let mut total = 0.0;
        match energy {
            DistortionEnergy::EdgeLength => {
                for &(a, b, inv) in &self.edges {
                    let e = sub2(uv[a as usize], uv[b as usize]);
                    let r = dot2(e, e) * inv - 1.0;
                    total += r * r;
                    // d/du_a (r²) = 2r · 2 e / |x|².
                    let f = 4.0 * r * inv;
                    for c in 0..2 {
                        g[a as usize][c] += f * e[c];
                        g[b as usize][c] -= f * e[c];
                    }
                }
            }
            DistortionEnergy::Area => {
                for &(t, inv) in &self.triangles {
                    let s = self.area_ratio(t, inv, uv);
                    let r = s * s - 1.0;
                    total += r * r;
                    // dE/ds = 2r · 2s; ds/du_i = (inv / 2) · ∂(2A)/∂u_i with
                    // ∂(2A)/∂u_i = (v_j − v_k, u_k − u_j), cyclically.
                    let f = 4.0 * r * s * 0.5 * inv;
                    for c in 0..3 {
                        let (i, j, k) = (t[c] as usize, t[(c + 1) % 3] as usize, t[(c + 2) % 3] as usize);
                        g[i][0] += f * (uv[j][1] - uv[k][1]);
                        g[i][1] += f * (uv[k][0] - uv[j][0]);
                    }
                }
            }
        }
        (total, g)
    }

    /// `t ↦ E(base + t · direction)` as an exact polynomial (degree 4 for the edge energy, 8 for
    /// the area energy).
    pub fn along_line(&self, energy: DistortionEnergy, base: &[[f64; 2]], direction: &[[f64; 2]]) -> Polynomial {
        let coefficients: Vec<f64> = match energy {
            DistortionEnergy::EdgeLength => chunked_sum(&self.edges, |&(a, b, inv)| {
                let (p, q) =
                    (sub2(base[a as usize], base[b as usize]), sub2(direction[a as usize], direction[b as usize]));
                // |p + t q|² / |x|² − 1.
                let r = [dot2(p, p) * inv - 1.0, 2.0 * dot2(p, q) * inv, dot2(q, q) * inv];
                square_quadratic(r)
            })
            .to_vec(),
            DistortionEnergy::Area => chunked_sum(&self.triangles, |&(t, inv)| {
                let [i, j, k] = t.map(|v| v as usize);
                let (e1, e2) = (sub2(base[j], base[i]), sub2(base[k], base[i]));
                let (f1, f2) = (sub2(direction[j], direction[i]), sub2(direction[k], direction[i]));
                // s(t) = A(t) / A3D with 2A(t) = (e1 + t f1) × (e2 + t f2).
                let h = 0.5 * inv;
                let s = [h * cross2(e1, e2), h * (cross2(e1, f2) + cross2(f1, e2)), h * cross2(f1, f2)];
                let mut q = square_quadratic(s);
                q[0] -= 1.0;
                square_quartic(q)
            })
            .to_vec(),
        };
        Polynomial::new(coefficients)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bumpy grid (curved) for finite-difference checks.
    fn bumpy() -> TriMesh {
        let k = 5u32;
        let mut positions = Vec::new();
        for j in 0..=k {
            for i in 0..=k {
                let (x, y) = (i as f64, j as f64);
                positions.extend([x, y, 0.3 * (0.8 * x).sin() * (0.6 * y).cos()]);
            }
        }
        let id = |i: u32, j: u32| j * (k + 1) + i;
        let mut tris = Vec::new();
        for j in 0..k {
            for i in 0..k {
                tris.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        TriMesh::new(&positions, &tris).expect("grid")
    }

    fn wobbly_uv(mesh: &TriMesh, phase: f64) -> Vec<[f64; 2]> {
        mesh.points()
            .iter()
            .map(|p| [p[0] * 1.1 + 0.05 * (p[1] + phase).sin(), p[1] * 0.9 + 0.04 * p[0] * (p[0] + phase).cos()])
            .collect()
    }

    #[test]
    fn an_isometry_has_zero_edge_energy_and_an_area_preserving_map_zero_area_energy() {
        // A flat grid mapped to itself (rotated and translated).
        let flat = TriMesh::new(&[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 2.0, 1.0, 0.0], &[0, 1, 3, 0, 3, 2])
            .expect("square");
        let (c, s) = (0.6f64, 0.8f64);
        let uv: Vec<[f64; 2]> =
            flat.points().iter().map(|p| [c * p[0] - s * p[1] + 3.0, s * p[0] + c * p[1]]).collect();
        let terms = DistortionTerms::new(&flat);
        assert!(terms.energy(DistortionEnergy::EdgeLength, &uv).abs() < 1e-24);
        assert!(terms.energy(DistortionEnergy::Area, &uv).abs() < 1e-24);
        // A shear keeps areas, not lengths.
        let sheared: Vec<[f64; 2]> = flat.points().iter().map(|p| [p[0] + 0.5 * p[1], p[1]]).collect();
        assert!(terms.energy(DistortionEnergy::Area, &sheared).abs() < 1e-24);
        assert!(terms.energy(DistortionEnergy::EdgeLength, &sheared) > 1e-3);
    }

    #[test]
    fn gradients_match_finite_differences() {
        let mesh = bumpy();
        let terms = DistortionTerms::new(&mesh);
        let uv = wobbly_uv(&mesh, 0.3);
        for energy in [DistortionEnergy::EdgeLength, DistortionEnergy::Area] {
            let (e, g) = terms.gradient(energy, &uv);
            assert!((e - terms.energy(energy, &uv)).abs() <= 1e-12 * e);
            for v in [0usize, 7, 15, 35] {
                for c in 0..2 {
                    let h = 1e-6;
                    let (mut plus, mut minus) = (uv.clone(), uv.clone());
                    plus[v][c] += h;
                    minus[v][c] -= h;
                    let fd = (terms.energy(energy, &plus) - terms.energy(energy, &minus)) / (2.0 * h);
                    assert!(
                        (fd - g[v][c]).abs() <= 1e-6 * (1.0 + fd.abs()),
                        "{energy:?} v{v} c{c}: {fd} vs {}",
                        g[v][c]
                    );
                }
            }
        }
    }

    #[test]
    fn the_polynomial_along_a_line_equals_the_energy_on_the_line() {
        let mesh = bumpy();
        let terms = DistortionTerms::new(&mesh);
        let base = wobbly_uv(&mesh, 0.0);
        let other = wobbly_uv(&mesh, 1.7);
        let direction: Vec<[f64; 2]> = other.iter().zip(&base).map(|(a, b)| sub2(*a, *b)).collect();
        for (energy, degree) in [(DistortionEnergy::EdgeLength, 4), (DistortionEnergy::Area, 8)] {
            let p = terms.along_line(energy, &base, &direction);
            assert_eq!(p.degree(), degree);
            for t in [-1.0, -0.3, 0.0, 0.5, 1.0, 2.0] {
                let uv: Vec<[f64; 2]> =
                    base.iter().zip(&direction).map(|(b, d)| [b[0] + t * d[0], b[1] + t * d[1]]).collect();
                let direct = terms.energy(energy, &uv);
                assert!(
                    (p.eval(t) - direct).abs() <= 1e-10 * (1.0 + direct),
                    "{energy:?} t={t}: {} vs {direct}",
                    p.eval(t)
                );
            }
        }
    }
}
