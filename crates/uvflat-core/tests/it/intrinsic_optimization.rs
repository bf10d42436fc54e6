//! Desbrun–Meyer–Alliez 2002 §5 (near-optimal λ, boundary optimization) and the spectral
//! conformal map (Mullen et al. 2008), checked on the real disk meshes of `tests/data/meshes`
//! against properties of the papers, with energies and eigen-residuals recomputed here from
//! their definitions (not through the library's own evaluation code).

// `!(x <= y)` is deliberate: a NaN must fail.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use uvflat_test_support::meshes;

use uvflat_core::error::Error;
use uvflat_core::methods::boundary_optimization::{
    boundary_optimized_map, boundary_optimized_map_observed, BoundaryOptimizationOptions,
};
use uvflat_core::methods::conformal::ConformalSystem;
use uvflat_core::methods::length_area_distortion::DistortionEnergy;
use uvflat_core::methods::near_optimal::{area_matching_scale, near_optimal_map, NearOptimalOptions};
use uvflat_core::methods::spectral_conformal::{spectral_conformal_map, SpectralOptions};
use uvflat_core::metrics::distortion;
use uvflat_core::progress::Progress;
use uvflat_core::{fixed_boundary_map, natural_conformal_map, FixedBoundaryOptions, TriMesh, Weights};

use meshes::load;

/// The disk meshes of the manifest with at most `max_faces` faces, smallest first.
fn disk_meshes(max_faces: usize) -> Vec<(String, TriMesh)> {
    let files = meshes::up_to("disk_", max_faces);
    assert!(files.len() >= 10, "expected the disk meshes of {}, found {files:?}", meshes::DIR);
    files.into_iter().map(|(_, f)| (f.clone(), load(&f))).collect()
}

// ---------------------------------------------------------------------------------------------
// The energies of §5.1, written out from the paper.

/// The paper's two energies for one mesh: its edges with |x_i − x_j|², its triangles with A^3D.
struct Energies {
    edges: Vec<(usize, usize, f64)>,
    triangles: Vec<([usize; 3], f64)>,
}

impl Energies {
    fn new(mesh: &TriMesh) -> Self {
        let mut seen = std::collections::HashSet::new();
        let mut edges = Vec::new();
        for t in mesh.triangles() {
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                if seen.insert((a.min(b), a.max(b))) {
                    let (p, q) = (mesh.points()[a], mesh.points()[b]);
                    edges.push((a, b, (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)));
                }
            }
        }
        let triangles = mesh
            .triangles()
            .iter()
            .map(|t| {
                let [p, q, r] = t.map(|v| mesh.points()[v as usize]);
                let (u, v) = ([q[0] - p[0], q[1] - p[1], q[2] - p[2]], [r[0] - p[0], r[1] - p[1], r[2] - p[2]]);
                let c = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
                (t.map(|v| v as usize), 0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt())
            })
            .collect();
        Energies { edges, triangles }
    }

    /// `Σ_edges (|u_i − u_j|² / |x_i − x_j|² − 1)²`.
    fn edge(&self, uv: &[[f64; 2]]) -> f64 {
        self.edges
            .iter()
            .map(|&(a, b, l3)| ((uv[a][0] - uv[b][0]).powi(2) + (uv[a][1] - uv[b][1]).powi(2)) / l3 - 1.0)
            .map(|r| r * r)
            .sum()
    }

    /// `Σ_faces ((A^param / A^3D)² − 1)²`.
    fn area(&self, uv: &[[f64; 2]]) -> f64 {
        self.triangles
            .iter()
            .map(|&([i, j, k], a3)| {
                let (a, b, d) = (uv[i], uv[j], uv[k]);
                let a2 = 0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]));
                ((a2 / a3).powi(2) - 1.0).powi(2)
            })
            .sum()
    }

    fn of(&self, kind: DistortionEnergy, uv: &[[f64; 2]]) -> f64 {
        match kind {
            DistortionEnergy::EdgeLength => self.edge(uv),
            DistortionEnergy::Area => self.area(uv),
        }
    }
}

/// Triangles with non-positive signed UV area.
fn flipped_set(mesh: &TriMesh, uv: &[[f64; 2]]) -> Vec<usize> {
    (0..mesh.triangle_count())
        .filter(|&t| {
            let [a, b, c] = mesh.triangles()[t].map(|v| uv[v as usize]);
            !((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0)
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Near-optimal maps (§5.1)

#[test]
fn near_optimal_lambda_minimizes_the_energy_on_every_disk_mesh() {
    let mut rows = Vec::new();
    for (file, mesh) in disk_meshes(100_000) {
        // The two base maps, computed here, at the library's documented scale.
        let dcp =
            fixed_boundary_map(&mesh, &FixedBoundaryOptions { weights: Weights::Conformal, ..Default::default() })
                .expect("DCP");
        let dap = fixed_boundary_map(&mesh, &FixedBoundaryOptions { weights: Weights::Authalic, ..Default::default() })
            .expect("DAP");
        let s = area_matching_scale(&mesh, &dcp).expect("scale");
        let energies = Energies::new(&mesh);
        let energy_of = |kind, uv: &[[f64; 2]]| energies.of(kind, uv);
        let at = |lambda: f64| -> Vec<[f64; 2]> {
            dcp.iter()
                .zip(&dap)
                .map(|(a, x)| {
                    [s * (lambda * a[0] + (1.0 - lambda) * x[0]), s * (lambda * a[1] + (1.0 - lambda) * x[1])]
                })
                .collect()
        };
        for kind in [DistortionEnergy::EdgeLength, DistortionEnergy::Area] {
            let options = NearOptimalOptions { energy: kind, ..Default::default() };
            let r = near_optimal_map(&mesh, &options, &mut Progress::none()).expect("near-optimal map");
            let e = energy_of(kind, &r.uv);
            let scale = e.abs().max(1.0);
            assert!((e - r.energy).abs() <= 1e-9 * scale, "{file} {kind:?}: reported {} vs recomputed {e}", r.energy);
            // The returned map is U(λ) of the paper's eq. 8.
            let expected = at(r.lambda);
            let d =
                r.uv.iter()
                    .zip(&expected)
                    .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
                    .fold(0.0, f64::max);
            assert!(d <= 1e-9 * s, "{file} {kind:?}: map is {d:e} from λ·U^A + (1 − λ)·U^χ");
            // Not above pure DCP and pure DAP.
            let (e_dcp, e_dap) = (energy_of(kind, &at(1.0)), energy_of(kind, &at(0.0)));
            assert!(
                e <= e_dcp * (1.0 + 1e-12) && e <= e_dap * (1.0 + 1e-12),
                "{file} {kind:?}: {e} vs DCP {e_dcp}, DAP {e_dap}"
            );
            // A minimum against a dense scan of λ on [−1, 2], and a local minimum around λ.
            let scan = (0..=3000)
                .map(|k| -1.0 + k as f64 * 1e-3)
                .map(|l| energy_of(kind, &at(l)))
                .fold(f64::INFINITY, f64::min);
            assert!(e <= scan * (1.0 + 1e-12), "{file} {kind:?}: λ = {} gives {e}, the scan finds {scan}", r.lambda);
            for h in [1e-3, 1e-5] {
                for l in [r.lambda - h, r.lambda + h] {
                    let near = energy_of(kind, &at(l));
                    assert!(e <= near * (1.0 + 1e-12), "{file} {kind:?}: E({l}) = {near} < E(λ) = {e}");
                }
            }
            rows.push(format!("{file} {kind:?}: λ = {:.4}, E = {e:.6e} (DCP {e_dcp:.6e}, DAP {e_dap:.6e})", r.lambda));
        }
    }
    println!("{}", rows.join("\n"));
}

#[test]
fn near_optimal_lambda_honours_its_range_and_rejects_bad_ones() {
    let mesh = load("disk_spothead.obj");
    for kind in [DistortionEnergy::EdgeLength, DistortionEnergy::Area] {
        let free =
            near_optimal_map(&mesh, &NearOptimalOptions { energy: kind, ..Default::default() }, &mut Progress::none())
                .expect("free");
        let options = NearOptimalOptions { energy: kind, lambda_min: 0.0, lambda_max: 1.0, ..Default::default() };
        let r = near_optimal_map(&mesh, &options, &mut Progress::none()).expect("bounded");
        assert!((0.0..=1.0).contains(&r.lambda));
        assert!(r.energy >= free.energy * (1.0 - 1e-12));
        if !(0.0..=1.0).contains(&free.lambda) {
            // The unconstrained minimum is outside: the range's end is the minimum on it.
            assert!(
                r.lambda == 0.0
                    || r.lambda == 1.0
                    || r.energy_polynomial.derivative().eval(r.lambda).abs() < 1e-6 * r.energy
            );
        }
    }
    for (lo, hi) in [(1.0, 0.0), (f64::NAN, 1.0), (f64::INFINITY, f64::INFINITY)] {
        let options = NearOptimalOptions { lambda_min: lo, lambda_max: hi, ..Default::default() };
        assert!(matches!(near_optimal_map(&mesh, &options, &mut Progress::none()), Err(Error::InvalidArgument(_))));
    }
}

// ---------------------------------------------------------------------------------------------
// Boundary optimization (§5.2)

/// The first intrinsic map (DCP, the DCP/DAP mean, DAP) whose circle start flips no triangle.
fn flip_free_start(mesh: &TriMesh) -> Option<(f64, f64)> {
    [(1.0, 0.0), (0.5, 0.5), (0.0, 1.0)].into_iter().find(|&(lambda, mu)| {
        let options = FixedBoundaryOptions { weights: Weights::Intrinsic { lambda, mu }, ..Default::default() };
        let uv = fixed_boundary_map(mesh, &options).expect("start map");
        flipped_set(mesh, &uv).is_empty()
    })
}

#[test]
fn boundary_optimization_lowers_the_energy_without_flipping_on_every_disk_mesh() {
    let mut rows = Vec::new();
    let mut without_flip_free_start = Vec::new();
    for (file, mesh) in disk_meshes(50_000) {
        let start = flip_free_start(&mesh);
        let energies = Energies::new(&mesh);
        let (lambda, mu) = start.unwrap_or((1.0, 0.0));
        for kind in [DistortionEnergy::EdgeLength, DistortionEnergy::Area] {
            let options =
                BoundaryOptimizationOptions { energy: kind, lambda, mu, iterations: 40, ..Default::default() };
            let mut steps = Vec::new();
            let mut start_flips = None;
            let r = boundary_optimized_map_observed(&mesh, &options, &mut Progress::none(), &mut |step| {
                let flips = flipped_set(&mesh, step.uv);
                let e = energies.of(kind, step.uv);
                assert!((e - step.energy).abs() <= 1e-9 * e.max(1.0), "{file} {kind:?}: energy {} vs {e}", step.energy);
                // No accepted step changes the orientation of any triangle.
                match &start_flips {
                    None => start_flips = Some(flips),
                    Some(first) => {
                        assert_eq!(&flips, first, "{file} {kind:?}: step {} flips triangles", step.iteration)
                    }
                }
                steps.push(e);
            })
            .expect("boundary optimization");
            let start_flips = start_flips.expect("the start is shown");
            if start.is_some() {
                assert!(start_flips.is_empty(), "{file}: flip-free start expected");
            }
            assert_eq!(steps.len(), r.iterations + 1);
            assert_eq!(steps.len(), r.history.len());
            assert!(steps.windows(2).all(|w| w[1] <= w[0]), "{file} {kind:?}: energy increased: {steps:?}");
            let (first, last) = (steps[0], *steps.last().expect("history"));
            assert!(last < first * (1.0 - 1e-3), "{file} {kind:?}: energy {first} -> {last} did not decrease");
            // The returned map is the editor's map of the returned boundary.
            let m = distortion(mesh.points(), mesh.triangles(), &r.uv, mesh.triangles()).expect("metrics");
            assert_eq!(m.degenerate_uv, 0, "{file} {kind:?}");
            rows.push(format!(
                "{file} {kind:?} λ={lambda} μ={mu}: {} iterations, E {first:.4e} -> {last:.4e}, flipped {}",
                r.iterations,
                start_flips.len()
            ));
        }
        if start.is_none() {
            without_flip_free_start.push(file);
        }
    }
    println!("{}", rows.join("\n"));
    // Known: the needle triangles of disk_mannequin_devil make every intrinsic start on a circle
    // flip a few triangles (negative cotangent weights); the descent keeps exactly those.
    assert!(
        without_flip_free_start.iter().all(|f| f == "disk_mannequin_devil.obj"),
        "meshes without a flip-free intrinsic start: {without_flip_free_start:?}"
    );
}

#[test]
fn boundary_optimization_stops_within_one_iteration_when_cancelled() {
    let mesh = load("disk_spothead.obj");
    for cancel_at in [1usize, 3] {
        let mut calls = 0;
        let mut accepted = 0;
        let mut callback = |_: f64| {
            calls += 1;
            calls < cancel_at
        };
        let options = BoundaryOptimizationOptions { iterations: 50, ..Default::default() };
        let result = boundary_optimized_map_observed(&mesh, &options, &mut Progress::new(&mut callback), &mut |s| {
            accepted = s.iteration;
        });
        assert!(matches!(result, Err(Error::Cancelled)), "cancel at call {cancel_at}: {result:?}");
        // The callback runs once per iteration, before it: call k cancels iteration k.
        assert_eq!(calls, cancel_at);
        assert!(accepted < cancel_at, "{accepted} iterations accepted after cancelling at call {cancel_at}");
    }
    // Determinism and the history.
    let options = BoundaryOptimizationOptions { energy: DistortionEnergy::Area, iterations: 10, ..Default::default() };
    let a = boundary_optimized_map(&mesh, &options, &mut Progress::none()).expect("run");
    let b = boundary_optimized_map(&mesh, &options, &mut Progress::none()).expect("run");
    assert_eq!(a.history, b.history);
    assert_eq!(a.uv, b.uv);
    let bad = BoundaryOptimizationOptions { tolerance: f64::NAN, ..Default::default() };
    assert!(matches!(boundary_optimized_map(&mesh, &bad, &mut Progress::none()), Err(Error::InvalidArgument(_))));
}

// ---------------------------------------------------------------------------------------------
// Spectral conformal map (Mullen et al. 2008)

type C = (f64, f64);

fn cmul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

/// `H z` for the conformal energy matrix (lower triangle stored, Hermitian).
fn apply_h(system: &ConformalSystem, z: &[C]) -> Vec<C> {
    let h = &system.matrix;
    let mut out = vec![(0.0, 0.0); z.len()];
    for c in 0..h.ncols() {
        for (r, v) in h.row_idx_of_col(c).zip(h.val_of_col(c)) {
            let p = cmul((v.re, v.im), z[c]);
            out[r] = (out[r].0 + p.0, out[r].1 + p.1);
            if r != c {
                let q = cmul((v.re, -v.im), z[r]);
                out[c] = (out[c].0 + q.0, out[c].1 + q.1);
            }
        }
    }
    out
}

/// `(λ, ‖Hz − λBz‖ / (‖H‖₁‖z‖))` for the map `uv` made B-orthogonal to the constants, with
/// `H` and `B` of Mullen et al. built here from the natural conformal system without pins.
fn eigen_residual(mesh: &TriMesh, uv: &[[f64; 2]]) -> (f64, f64) {
    let system = ConformalSystem::with_pins(mesh, &[]).expect("system");
    let vertex = &system.unknowns.vertex;
    let boundary: Vec<bool> = vertex.iter().map(|&v| mesh.is_boundary_vertex(v)).collect();
    let nb = boundary.iter().filter(|&&b| b).count() as f64;
    let mut mean = (0.0, 0.0);
    for (&v, _) in vertex.iter().zip(&boundary).filter(|(_, &b)| b) {
        mean = (mean.0 + uv[v as usize][0] / nb, mean.1 + uv[v as usize][1] / nb);
    }
    let z: Vec<C> = vertex.iter().map(|&v| (uv[v as usize][0] - mean.0, uv[v as usize][1] - mean.1)).collect();
    let hz = apply_h(&system, &z);
    let energy: f64 = z.iter().zip(&hz).map(|(a, b)| a.0 * b.0 + a.1 * b.1).sum();
    let mass: f64 = z.iter().zip(&boundary).filter(|(_, &b)| b).map(|(a, _)| a.0 * a.0 + a.1 * a.1).sum();
    let lambda = energy / mass;
    let mut r2 = 0.0;
    for ((a, h), &b) in z.iter().zip(&hz).zip(&boundary) {
        let r = if b { (h.0 - lambda * a.0, h.1 - lambda * a.1) } else { *h };
        r2 += r.0 * r.0 + r.1 * r.1;
    }
    let z2: f64 = z.iter().map(|a| a.0 * a.0 + a.1 * a.1).sum();
    let mut sums = vec![0.0; z.len()];
    let h = &system.matrix;
    for c in 0..h.ncols() {
        for (r, v) in h.row_idx_of_col(c).zip(h.val_of_col(c)) {
            sums[r] += v.norm();
            if r != c {
                sums[c] += v.norm();
            }
        }
    }
    let h_norm = sums.into_iter().fold(0.0, f64::max);
    (lambda, r2.sqrt() / ((h_norm + lambda.abs()) * z2.sqrt()))
}

/// Rayleigh quotient `z*Hz / z*Bz` of a map, boundary mean removed.
fn rayleigh_quotient(mesh: &TriMesh, uv: &[[f64; 2]]) -> f64 {
    eigen_residual(mesh, uv).0
}

/// Largest distance of `b` from the best similarity image `a·z + t` of `a` (complex least
/// squares), relative to the diameter of `b`.
fn similarity_distance(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let pairs: Vec<(C, C)> =
        a.iter().zip(b).filter(|(p, _)| p[0].is_finite()).map(|(p, q)| ((p[0], p[1]), (q[0], q[1]))).collect();
    let n = pairs.len() as f64;
    let ma = pairs.iter().fold((0.0, 0.0), |m, (p, _)| (m.0 + p.0 / n, m.1 + p.1 / n));
    let mb = pairs.iter().fold((0.0, 0.0), |m, (_, q)| (m.0 + q.0 / n, m.1 + q.1 / n));
    // s = Σ conj(p) q / Σ |p|² over centred points.
    let (mut num, mut den) = ((0.0, 0.0), 0.0);
    for (p, q) in &pairs {
        let (p, q) = ((p.0 - ma.0, p.1 - ma.1), (q.0 - mb.0, q.1 - mb.1));
        let c = cmul((p.0, -p.1), q);
        num = (num.0 + c.0, num.1 + c.1);
        den += p.0 * p.0 + p.1 * p.1;
    }
    let s = (num.0 / den, num.1 / den);
    let mut worst: f64 = 0.0;
    let mut diameter: f64 = 0.0;
    for (p, q) in &pairs {
        let (p, q) = ((p.0 - ma.0, p.1 - ma.1), (q.0 - mb.0, q.1 - mb.1));
        let f = cmul(s, p);
        worst = worst.max(((f.0 - q.0).powi(2) + (f.1 - q.1).powi(2)).sqrt());
        diameter = diameter.max((q.0 * q.0 + q.1 * q.1).sqrt());
    }
    worst / (2.0 * diameter)
}

#[test]
fn spectral_map_is_the_smallest_nontrivial_generalized_eigenvector() {
    let mut table = vec![
        "| mesh | faces | iterations | λ | residual | conformal mean (spectral / natural) | angle error ° (spectral / natural) |"
            .to_string(),
        "|---|---|---|---|---|---|---|".to_string(),
    ];
    let mut not_worse = 0;
    let meshes = disk_meshes(100_000);
    for (file, mesh) in &meshes {
        let r = spectral_conformal_map(mesh, &SpectralOptions::default(), &mut Progress::none()).expect("spectral");
        assert!(r.converged, "{file}: not converged, residual {}", r.residual);
        // An eigenvector of H z = λ B z, checked with H and B built here.
        let (lambda, residual) = eigen_residual(mesh, &r.uv);
        assert!(residual <= 1e-10, "{file}: residual {residual:e}");
        assert!((lambda - r.eigenvalue).abs() <= 1e-9 * (1.0 + lambda.abs()), "{file}: λ {lambda} vs {}", r.eigenvalue);
        // The smallest one: no other map has a lower Rayleigh quotient; the natural conformal
        // map (2 pins) and the DCP map are two such maps.
        let natural = natural_conformal_map(mesh, None).expect("natural conformal");
        let dcp = fixed_boundary_map(mesh, &FixedBoundaryOptions { weights: Weights::Conformal, ..Default::default() })
            .expect("DCP");
        for (name, other) in [("natural conformal", &natural), ("DCP", &dcp)] {
            let q = rayleigh_quotient(mesh, other);
            // Rounding of a quotient near 0 (developable meshes) is about 1e-16 of ‖H‖ ~ 1.
            assert!(lambda <= q + 1e-12 * q.abs() + 1e-14, "{file}: λ {lambda} above the {name} quotient {q}");
        }
        let ms = distortion(mesh.points(), mesh.triangles(), &r.uv, mesh.triangles()).expect("metrics");
        let mn = distortion(mesh.points(), mesh.triangles(), &natural, mesh.triangles()).expect("metrics");
        if ms.conformal_mean <= mn.conformal_mean {
            not_worse += 1;
        }
        table.push(format!(
            "| {file} | {} | {} | {:.3e} | {:.1e} | {:.5} / {:.5} | {:.4} / {:.4} |",
            mesh.triangle_count(),
            r.iterations,
            r.eigenvalue,
            residual,
            ms.conformal_mean,
            mn.conformal_mean,
            ms.angle_mean.to_degrees(),
            mn.angle_mean.to_degrees()
        ));
    }
    println!("{}", table.join("\n"));
    // Mullen et al.'s claim: no worse than the natural conformal map on
    // at least half of the disk meshes.
    assert!(2 * not_worse >= meshes.len(), "spectral no worse on only {not_worse} of {} meshes", meshes.len());
}

fn transformed(mesh: &TriMesh, scale: f64, angle: f64, shift: [f64; 3]) -> TriMesh {
    let (c, s) = (angle.cos(), angle.sin());
    // A rotation about the axis (1, 1, 1)/√3 (Rodrigues), then scale and shift.
    let k = [1.0 / 3f64.sqrt(); 3];
    let mut positions = Vec::new();
    for p in mesh.points() {
        let kxp = [k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]];
        let kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
        for d in 0..3 {
            positions.push(scale * (p[d] * c + kxp[d] * s + k[d] * kp * (1.0 - c)) + shift[d]);
        }
    }
    let triangles: Vec<u32> = mesh.triangles().iter().flatten().copied().collect();
    TriMesh::new(&positions, &triangles).expect("transformed mesh")
}

#[test]
fn spectral_map_is_invariant_to_rigid_motion_and_scale_and_needs_no_pins() {
    for file in ["disk_nefertiti_small.obj", "disk_cow_cut.obj", "disk_camelhead.obj"] {
        let mesh = load(file);
        let options = SpectralOptions { tolerance: 1e-13, ..Default::default() };
        let a = spectral_conformal_map(&mesh, &options, &mut Progress::none()).expect("spectral");
        let b =
            spectral_conformal_map(&transformed(&mesh, 37.5, 1.1, [3.0, -200.0, 7.0]), &options, &mut Progress::none())
                .expect("spectral of the moved mesh");
        let d = similarity_distance(&a.uv, &b.uv);
        assert!(d <= 1e-7, "{file}: maps differ by {d:e} of the diameter after the best similarity");
        assert!((a.eigenvalue - b.eigenvalue).abs() <= 1e-8 * a.eigenvalue.abs().max(1e-12));
        // Deterministic.
        let again = spectral_conformal_map(&mesh, &options, &mut Progress::none()).expect("spectral");
        assert_eq!(a.uv, again.uv);
    }
}

#[test]
fn spectral_map_of_a_developable_mesh_is_its_development() {
    // disk_maze is folded along edges but developable: it has an exactly conformal (isometric)
    // flattening, which the natural conformal map (pins) finds too. (disk_hilbert is bent, not
    // folded: nearly but not exactly developable, so the two maps differ by ~2e-4 there.)
    for file in ["disk_maze.obj"] {
        let mesh = load(file);
        let r = spectral_conformal_map(&mesh, &SpectralOptions::default(), &mut Progress::none()).expect("spectral");
        let natural = natural_conformal_map(&mesh, None).expect("natural");
        let d = similarity_distance(&natural, &r.uv);
        // λ₂ ≈ 1.9e-9 here, so the eigenvector is determined to about 1e-16 / 1e-9 only.
        assert!(d <= 1e-6, "{file}: {d:e} from the development");
        assert!(r.eigenvalue.abs() <= 1e-12, "{file}: λ = {}", r.eigenvalue);
    }
    // A planar mesh (the irregular lion head flattened, then tilted into 3D): its own positions,
    // up to similarity.
    let lion = load("disk_lion_head.obj");
    let flat = natural_conformal_map(&lion, None).expect("natural");
    let (c, s) = (0.6f64, 0.8f64);
    let positions: Vec<f64> = flat.iter().flat_map(|p| [p[0], c * p[1], s * p[1] + 2.0]).collect();
    let triangles: Vec<u32> = lion.triangles().iter().flatten().copied().collect();
    let planar = TriMesh::new(&positions, &triangles).expect("planar mesh");
    let r = spectral_conformal_map(&planar, &SpectralOptions::default(), &mut Progress::none()).expect("spectral");
    let d = similarity_distance(&flat, &r.uv);
    assert!(d <= 1e-8, "planar mesh reproduced to {d:e} of its diameter");
    assert!(r.eigenvalue.abs() <= 1e-14, "a planar mesh has an exactly conformal map (λ = {})", r.eigenvalue);
}

#[test]
fn spectral_map_rejects_meshes_without_boundary_and_bad_options() {
    let closed = load("closed_g0_decimated_knight.obj");
    assert!(matches!(
        spectral_conformal_map(&closed, &SpectralOptions::default(), &mut Progress::none()),
        Err(Error::NotADisk { .. })
    ));
    let mesh = load("disk_cat_head.obj");
    for bad in [
        SpectralOptions { iterations: 0, ..Default::default() },
        SpectralOptions { tolerance: 0.0, ..Default::default() },
    ] {
        assert!(matches!(spectral_conformal_map(&mesh, &bad, &mut Progress::none()), Err(Error::InvalidArgument(_))));
    }
    // Cancellation.
    let mut callback = |_: f64| false;
    assert!(matches!(
        spectral_conformal_map(&mesh, &SpectralOptions::default(), &mut Progress::new(&mut callback)),
        Err(Error::Cancelled)
    ));
}
