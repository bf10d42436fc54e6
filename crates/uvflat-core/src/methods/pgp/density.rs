//! Feature-adaptive density of PGP (not in Ray et al. 2006; an extension of its §2.2 choice of
//! ω): a per-vertex factor s ≥ 1 by which the field is scaled before the periodic solve, so that
//! θ and φ advance by ω s K per unit length (eq. 4 with a local ω) and every curved feature is
//! at least `feature_periods` periods around.
//!
//! Why: the paper sets one ω for the whole surface (one period per ten mean edge lengths). Where
//! a leg, horn, finger or ear has a circumference shorter than a period, no travelling wave
//! fits around it: one of the two functions becomes a standing wave (‖V‖ ≈ 0.5, its gradient
//! small and reversed) and the solution is singular all over the feature. On
//! `closed_g0_cow` and `closed_g0_man` those groups made most of the singular triangles (README,
//! "Untangling"). A feature of curvature radius r has circumference 2πr, which holds
//! `ω s r` periods; asking for at least c of them gives
//!
//! ```text
//! s_v = clamp(c κ_v / ω, 1, MAX_DENSITY),   κ_v = max(|κ_min|, |κ_max|) at v,
//! ```
//!
//! then averaged over the one-ring [`SMOOTHING_ROUNDS`] times (a scale that varies from vertex
//! to vertex adds curl, ∇ log s × K, which the solve would pay for with singular points) and
//! clamped below by 1 again, so that s never lowers the paper's frequency. With curl correction
//! (§4.1) the field's scale is v s: where s is constant (a tube of constant radius) v's
//! curl-free field is kept. Taking max(v, s) instead was measured and dropped: it overrides v
//! wherever s > v (the mesh torus `closed_g1_torus` then keeps a pair of singular points, cow
//! 0.3 points more). On a flat surface, or one whose curvature radii are all above c/ω, s ≡ 1
//! and the result is the paper's; on a tube of constant radius (the tori) s is constant, the
//! paper's result at a higher ω. Like curl correction, this makes the parameterization
//! conformal rather than isometric where s varies.
//!
//! Measured (docs/methods/pgp.md, "Feature-adaptive density", `scripts/pgp_quality.sh`): c = 3 takes cow from
//! 10.4 to 2.5% singular triangles and man from 6.6 to 2.1%, and leaves the meshes without thin
//! features (bunny, fertility, nefertiti, kitten) within ±0.1 point.
//!
//! Cost: O(V) after the curvature estimate, which PGP computes anyway.

use crate::TriMesh;

/// Largest density factor: a period no shorter than 4 mean edge lengths at the default ω, below
/// which the piecewise-linear (cos, sin) of the periodic solve under-samples the wave.
pub const MAX_DENSITY: f64 = 2.5;

/// One-ring averaging rounds applied to the density factor (module comment).
pub const SMOOTHING_ROUNDS: usize = 10;

/// Default minimum number of periods around a curved feature ([`density_scale`]).
pub const DEFAULT_FEATURE_PERIODS: f64 = 3.0;

/// The density factor s ≥ 1 of every vertex (module comment) from the principal curvatures
/// `kmin`, `kmax`, for frequency `omega` and `feature_periods` = c. c = 0 gives s ≡ 1.
pub fn density_scale(mesh: &TriMesh, kmin: &[f64], kmax: &[f64], omega: f64, feature_periods: f64) -> Vec<f64> {
    let mut s: Vec<f64> =
        kmin.iter().zip(kmax).map(|(a, b)| (feature_periods * a.abs().max(b.abs()) / omega).min(MAX_DENSITY)).collect();
    for _ in 0..SMOOTHING_ROUNDS {
        s = one_ring_average(mesh, &s);
    }
    s.iter().map(|&x| x.max(1.0)).collect()
}

/// `(x_v + Σ_{u ~ v} x_u) / (1 + #{u ~ v})` over the mesh's edges (an interior edge counts once
/// from each of its two triangles, a boundary edge once).
fn one_ring_average(mesh: &TriMesh, x: &[f64]) -> Vec<f64> {
    let mut sum = x.to_vec();
    let mut count = vec![1.0; x.len()];
    for t in mesh.triangles() {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            sum[a] += x[b];
            count[a] += 1.0;
            sum[b] += x[a];
            count[b] += 1.0;
        }
    }
    sum.iter().zip(&count).map(|(s, c)| s / c).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An n × 1 strip of 2n triangles in the plane; vertex x is (x, 0), vertex n + 1 + x is (x, 1).
    fn strip(n: u32) -> TriMesh {
        let mut p = Vec::new();
        for y in 0..2 {
            for x in 0..=n {
                p.extend_from_slice(&[x as f64, y as f64, 0.0]);
            }
        }
        let mut t = Vec::new();
        for x in 0..n {
            t.extend_from_slice(&[x, x + 1, x + n + 2, x, x + n + 2, x + n + 1]);
        }
        TriMesh::new(&p, &t).unwrap()
    }

    #[test]
    fn low_curvature_or_zero_periods_keep_the_papers_frequency() {
        let mesh = strip(4);
        let k = vec![0.1; 10];
        assert!(density_scale(&mesh, &k, &k, 1.0, 3.0).iter().all(|&s| s == 1.0));
        let high = vec![100.0; 10];
        assert!(density_scale(&mesh, &high, &high, 1.0, 0.0).iter().all(|&s| s == 1.0));
    }

    #[test]
    fn high_curvature_raises_the_frequency_up_to_the_cap() {
        let mesh = strip(4);
        let high = vec![100.0; 10];
        let s = density_scale(&mesh, &high, &high, 1.0, 3.0);
        assert!(s.iter().all(|&x| (x - MAX_DENSITY).abs() < 1e-12), "{s:?}");
        // c κ / ω = 3 × 0.5 / 1 = 1.5 everywhere: exactly that factor.
        let half = vec![-0.5; 10];
        let s = density_scale(&mesh, &half, &[0.2; 10], 1.0, 3.0);
        assert!(s.iter().all(|&x| (x - 1.5).abs() < 1e-12), "{s:?}");
    }

    #[test]
    fn a_curved_end_is_spread_over_its_neighbours_and_decays() {
        let n = 30;
        let mesh = strip(n);
        let row = (n + 1) as usize;
        // Curved where x < 6.
        let k: Vec<f64> = (0..2 * row).map(|v| if v % row < 6 { 10.0 } else { 0.0 }).collect();
        let s = density_scale(&mesh, &k, &k, 1.0, 3.0);
        // The curved end is raised (not above the cap), the far end is not, monotonically between.
        assert!(s[0] > 1.5 && s[0] <= MAX_DENSITY && s[row] > 1.5, "{s:?}");
        assert_eq!(s[row - 1], 1.0);
        assert!((0..row - 1).all(|x| s[x] >= s[x + 1]), "{s:?}");
    }
}
