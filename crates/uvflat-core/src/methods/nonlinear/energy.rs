//! Distortion energies of a surface → plane map as functions of the singular values
//! `σ1 ≥ σ2 > 0` of each triangle's Jacobian (course notes §4.1–4.4, eq. 4.3: the overall
//! energy is the 3D-area-weighted mean of a local measure `E(σ1, σ2)` over the triangles).
//!
//! | energy | local measure | minimum | source |
//! |---|---|---|---|
//! | symmetric Dirichlet | `σ1² + σ1⁻² + σ2² + σ2⁻²` | 4 (isometry) | Smith & Schaefer 2015 eq. 2; Rabinovich et al. 2017 |
//! | ARAP | `(σ1 − 1)² + (σ2 − 1)²` | 0 (isometry) | Liu et al. 2008 eq. 3 |
//! | MIPS | `σ1/σ2 + σ2/σ1` | 2 (conformal) | Hormann & Greiner 2000; course notes §4.3 |
//! | Green–Lagrange | `(σ1² − 1)² + (σ2² − 1)²` | 0 (isometry) | Maillot et al. 1993; course notes §4.4 |
//! | Degener | `(σ1/σ2 + σ2/σ1)(σ1σ2 + 1/(σ1σ2))^θ` | 2·2^θ | Degener et al. 2003; course notes §4.4 |
//! | L2 stretch | `√(Σ A_T ½(σ1⁻² + σ2⁻²) / Σ A_T)`, scaled by `√(A_uv / A_3d)` | 1 | Sander et al. 2001 eq. 2–3 |
//!
//! Sander's stretch measures the inverse map (plane → surface) whose singular values are
//! `1/σ1`, `1/σ2`; without the area factor it would decrease forever as the map grows, so the
//! minimized quantity is its square `(Σ A_T ½(σ1⁻² + σ2⁻²))·(Σ A_T σ1σ2) / (Σ A_T)²`, invariant
//! to scaling the map (Sander et al. 2001 §3, normalization of the L2 norm).
//!
//! Every energy but ARAP and Green–Lagrange tends to +∞ as a triangle degenerates; a map with a
//! flipped or degenerate triangle gets energy +∞. Evaluation is parallel over triangles and
//! summed in fixed-size chunks, so results do not depend on the number of threads.

use super::jacobian::{det, Mat2, RestFrames, Svd2};
use rayon::prelude::*;

/// A distortion energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Energy {
    /// Symmetric Dirichlet (what SLIM minimizes).
    SymmetricDirichlet,
    /// As-rigid-as-possible.
    Arap,
    /// Most isometric parameterization (conformal).
    Mips,
    /// Green–Lagrange deformation tensor.
    GreenLagrange,
    /// Degener's angle × area^θ energy.
    Degener {
        /// Weight of the area term (θ > 0; 3 recommended).
        theta: f64,
    },
    /// Sander's L2 stretch (squared, scale-normalized).
    Stretch,
}

/// Triangles per chunk of the deterministic parallel sums.
const CHUNK: usize = 2048;

impl Energy {
    /// Local measure `E(σ1, σ2)` and its partial derivatives. Stretch returns the per-triangle
    /// part `½(σ1⁻² + σ2⁻²)`; [`evaluate`] applies the global area factor.
    #[inline]
    pub fn local(self, s1: f64, s2: f64) -> (f64, f64, f64) {
        match self {
            Energy::SymmetricDirichlet => {
                let (i1, i2) = (1.0 / (s1 * s1), 1.0 / (s2 * s2));
                (s1 * s1 + i1 + s2 * s2 + i2, 2.0 * s1 - 2.0 * i1 / s1, 2.0 * s2 - 2.0 * i2 / s2)
            }
            Energy::Arap => ((s1 - 1.0).powi(2) + (s2 - 1.0).powi(2), 2.0 * (s1 - 1.0), 2.0 * (s2 - 1.0)),
            Energy::Mips => (s1 / s2 + s2 / s1, 1.0 / s2 - s2 / (s1 * s1), 1.0 / s1 - s1 / (s2 * s2)),
            Energy::GreenLagrange => {
                let (a, b) = (s1 * s1 - 1.0, s2 * s2 - 1.0);
                (a * a + b * b, 4.0 * s1 * a, 4.0 * s2 * b)
            }
            Energy::Degener { theta } => {
                let m = s1 / s2 + s2 / s1;
                let (m1, m2) = (1.0 / s2 - s2 / (s1 * s1), 1.0 / s1 - s1 / (s2 * s2));
                let d = s1 * s2;
                let p = d + 1.0 / d;
                let (p1, p2) = (s2 - 1.0 / (s1 * d), s1 - 1.0 / (s2 * d));
                let pt = p.powf(theta);
                let dpt = theta * p.powf(theta - 1.0);
                (m * pt, m1 * pt + m * dpt * p1, m2 * pt + m * dpt * p2)
            }
            Energy::Stretch => {
                let (i1, i2) = (1.0 / (s1 * s1), 1.0 / (s2 * s2));
                (0.5 * (i1 + i2), -i1 / s1, -i2 / s2)
            }
        }
    }

    /// True when the energy is unbounded as a triangle degenerates (a barrier against flips).
    pub fn is_barrier(self) -> bool {
        !matches!(self, Energy::Arap | Energy::GreenLagrange)
    }
}

/// Energy of the map `uv` (area-weighted mean of the local measure), +∞ when a triangle is
/// flipped or degenerate or the value is not finite.
pub fn energy(e: Energy, frames: &RestFrames, tris: &[[u32; 3]], uv: &[[f64; 2]]) -> f64 {
    evaluate(e, frames, tris, uv, false).0
}

/// Energy and, when `with_gradient`, `∂E/∂J` of each triangle (already multiplied by the
/// triangle's weight, so the gradient in the UVs is `Σ_t Σ_k (∂E/∂J_t) g_k` per corner).
pub fn evaluate(
    e: Energy,
    frames: &RestFrames,
    tris: &[[u32; 3]],
    uv: &[[f64; 2]],
    with_gradient: bool,
) -> (f64, Vec<Mat2>) {
    let inv_total = 1.0 / frames.total_area;
    // Per triangle: weighted local value, weighted det J (for stretch), derivative.
    let per_triangle: Vec<(f64, f64, Mat2, Mat2)> = tris
        .par_iter()
        .enumerate()
        .with_min_len(1024)
        .map(|(t, &tri)| {
            let j = frames.jacobian(t, tri, uv);
            let d = det(&j);
            if !(d > 0.0) {
                return (f64::INFINITY, 0.0, [[0.0; 2]; 2], [[0.0; 2]; 2]);
            }
            let svd = Svd2::new(&j);
            let (value, d1, d2) = e.local(svd.s1, svd.s2);
            let w = frames.area[t] * inv_total;
            let grad = if with_gradient {
                let m = svd.compose(d1, d2);
                [[w * m[0][0], w * m[0][1]], [w * m[1][0], w * m[1][1]]]
            } else {
                [[0.0; 2]; 2]
            };
            // ∂ det J / ∂J is the cofactor matrix.
            let cof = [[w * j[1][1], -w * j[1][0]], [-w * j[0][1], w * j[0][0]]];
            (w * value, w * d, grad, cof)
        })
        .collect();
    let sums: Vec<(f64, f64)> =
        per_triangle.par_chunks(CHUNK).map(|c| c.iter().fold((0.0, 0.0), |(a, b), x| (a + x.0, b + x.1))).collect();
    let (local_sum, area_ratio) = sums.iter().fold((0.0, 0.0), |(a, b), x| (a + x.0, b + x.1));
    let total = if e == Energy::Stretch { local_sum * area_ratio } else { local_sum };
    let total = if total.is_finite() { total } else { f64::INFINITY };
    if !with_gradient || !total.is_finite() {
        return (total, Vec::new());
    }
    let grads = if e == Energy::Stretch {
        // d(S·U) = U dS + S dU.
        per_triangle
            .par_iter()
            .with_min_len(1024)
            .map(|(_, _, g, cof)| {
                let mut m = [[0.0; 2]; 2];
                for r in 0..2 {
                    for c in 0..2 {
                        m[r][c] = area_ratio * g[r][c] + local_sum * cof[r][c];
                    }
                }
                m
            })
            .collect()
    } else {
        per_triangle.into_par_iter().with_min_len(1024).map(|x| x.2).collect()
    };
    (total, grads)
}

/// Gradient of the energy in the UVs from the per-triangle `∂E/∂J` (a sequential scatter, so
/// the sums are deterministic).
pub fn vertex_gradient(frames: &RestFrames, tris: &[[u32; 3]], dj: &[Mat2], n: usize) -> Vec<[f64; 2]> {
    let mut g = vec![[0.0; 2]; n];
    for (t, tri) in tris.iter().enumerate() {
        let m = &dj[t];
        for k in 0..3 {
            let gk = frames.grad[t][k];
            let v = &mut g[tri[k] as usize];
            v[0] += m[0][0] * gk[0] + m[0][1] * gk[1];
            v[1] += m[1][0] * gk[0] + m[1][1] * gk[1];
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [Energy; 6] = [
        Energy::SymmetricDirichlet,
        Energy::Arap,
        Energy::Mips,
        Energy::GreenLagrange,
        Energy::Degener { theta: 3.0 },
        Energy::Stretch,
    ];

    /// A small bumpy fan around a centre vertex.
    fn fan() -> (Vec<[f64; 3]>, Vec<[u32; 3]>, Vec<[f64; 2]>) {
        let mut points = vec![[0.0, 0.0, 0.3]];
        let mut uv = vec![[0.05, -0.02]];
        let n = 7;
        for i in 0..n {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            points.push([a.cos() * (1.0 + 0.1 * i as f64), a.sin(), 0.1 * (i % 3) as f64]);
            uv.push([1.3 * a.cos(), 0.8 * a.sin() + 0.05 * i as f64]);
        }
        let tris = (0..n as u32).map(|i| [0, 1 + i, 1 + (i + 1) % n as u32]).collect();
        (points, tris, uv)
    }

    #[test]
    fn gradients_match_finite_differences() {
        let (points, tris, uv) = fan();
        let frames = RestFrames::new(&points, &tris);
        for e in ALL {
            let (_, dj) = evaluate(e, &frames, &tris, &uv, true);
            let g = vertex_gradient(&frames, &tris, &dj, uv.len());
            for v in 0..uv.len() {
                for c in 0..2 {
                    let h = 1e-6;
                    let (mut p, mut m) = (uv.clone(), uv.clone());
                    p[v][c] += h;
                    m[v][c] -= h;
                    let fd = (energy(e, &frames, &tris, &p) - energy(e, &frames, &tris, &m)) / (2.0 * h);
                    assert!(
                        (fd - g[v][c]).abs() <= 1e-6 * (1.0 + fd.abs()),
                        "{e:?} vertex {v} coord {c}: {fd} vs {}",
                        g[v][c]
                    );
                }
            }
        }
    }

    #[test]
    fn isometry_reaches_each_energys_minimum() {
        let points = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 1.5, 0.0], [1.8, 1.9, 0.0]];
        let tris = [[0, 1, 2], [1, 3, 2]];
        // A rotation of the flat input.
        let (c, s) = (0.6f64, 0.8f64);
        let uv: Vec<[f64; 2]> = points.iter().map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]]).collect();
        let frames = RestFrames::new(&points, &tris);
        for (e, min) in ALL.iter().zip([4.0, 0.0, 2.0, 0.0, 16.0, 1.0]) {
            let value = energy(*e, &frames, &tris, &uv);
            assert!((value - min).abs() < 1e-12, "{e:?}: {value} vs {min}");
        }
    }

    #[test]
    fn a_flipped_triangle_has_infinite_energy() {
        let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let frames = RestFrames::new(&points, &[[0, 1, 2]]);
        let uv = [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]];
        for e in ALL {
            assert_eq!(energy(e, &frames, &[[0, 1, 2]], &uv), f64::INFINITY);
        }
    }
}
