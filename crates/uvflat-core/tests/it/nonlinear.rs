//! The claims of the distortion-minimizing methods, on real meshes.
//!
//! - Flip-free line search (Smith & Schaefer 2015): starting from a bijective map, SLIM, ARAP,
//!   MIPS, stretch, Green–Lagrange and Degener return maps with zero flipped and zero degenerate
//!   triangles on every disk mesh of `tests/data/meshes` with at most 100k faces, and their
//!   energy never increases from one iteration to the next (and does decrease).
//! - On a flat mesh the isometry is reachable, so SLIM reaches the symmetric Dirichlet minimum
//!   4 and ARAP the ARAP minimum 0.
//! - A progress callback that cancels stops the method within one iteration with
//!   `Error::Cancelled`; results are bit-for-bit deterministic.
//!
//! The all-meshes test prints a table (run with `--nocapture`): iterations, initial and final
//! energy, seconds. 15 iterations per method, 6 above 40k faces, to keep the test to a few
//! minutes on two cores in `--release` (with 40 / 15 iterations it also passes, in 8 minutes).

use std::time::Instant;
use uvflat_test_support::meshes;

use uvflat_core::error::Error;
use uvflat_core::methods::nonlinear::{nonlinear_map, nonlinear_map_with_progress, NonlinearMethod, NonlinearOptions};
use uvflat_core::metrics::distortion;
use uvflat_core::progress::Progress;
use uvflat_core::TriMesh;

use meshes::load;

const MAX_FACES: usize = 100_000;

const METHODS: [NonlinearMethod; 6] = [
    NonlinearMethod::Slim,
    NonlinearMethod::Arap,
    NonlinearMethod::Mips,
    NonlinearMethod::Stretch,
    NonlinearMethod::GreenLagrange,
    NonlinearMethod::Degener,
];

/// `disk_*.obj` with at most `MAX_FACES` faces, smallest first.
fn disk_meshes() -> Vec<(usize, String)> {
    let files = meshes::up_to("disk_", MAX_FACES);
    assert!(files.len() >= 10, "expected the disk meshes of {}", meshes::DIR);
    files
}

/// Triangles whose UV signed area is not strictly positive (the input is counter-clockwise).
fn non_positive_triangles(mesh: &TriMesh, uv: &[[f64; 2]]) -> usize {
    mesh.triangles()
        .iter()
        .filter(|t| {
            let [a, b, c] = t.map(|v| uv[v as usize]);
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            !(area > 0.0)
        })
        .count()
}

#[test]
fn every_method_is_flip_free_and_monotone_on_every_disk_mesh() {
    let mut failures = Vec::new();
    println!(
        "{:<36} {:>7} {:<15} {:>5} {:>12} {:>12} {:>8}",
        "mesh", "faces", "method", "iters", "E initial", "E final", "seconds"
    );
    for (faces, file) in disk_meshes() {
        let mesh = load(&file);
        for method in METHODS {
            let mut options = NonlinearOptions::new(method);
            options.iterations = if faces > 40_000 { 6 } else { 15 };
            let start = Instant::now();
            let result = match nonlinear_map(&mesh, &options) {
                Ok(r) => r,
                Err(e) => {
                    failures.push(format!("{file} {method:?}: {e}"));
                    continue;
                }
            };
            let seconds = start.elapsed().as_secs_f64();
            let (e0, e1) = (result.energy[0], *result.energy.last().unwrap());
            println!(
                "{file:<36} {faces:>7} {:<15} {:>5} {e0:>12.6} {e1:>12.6} {seconds:>8.2}",
                format!("{method:?}"),
                result.iterations
            );
            let bad = non_positive_triangles(&mesh, &result.uv);
            let m = distortion(mesh.points(), mesh.triangles(), &result.uv, mesh.triangles()).expect("metrics");
            if bad != 0 || m.flipped != 0 || m.degenerate_uv != 0 {
                failures.push(format!(
                    "{file} {method:?}: {bad} non-positive, {} flipped, {} degenerate",
                    m.flipped, m.degenerate_uv
                ));
            }
            if let Some(w) = result.energy.windows(2).find(|w| !(w[1] <= w[0])) {
                failures.push(format!("{file} {method:?}: energy increased {} -> {}", w[0], w[1]));
            }
            if !(e1 < e0) || result.iterations == 0 {
                failures.push(format!("{file} {method:?}: energy did not decrease ({e0} -> {e1})"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A flat, irregular disk: a polar grid whose radius wobbles, so the mean value start is far
/// from the isometry.
fn flat_wobbly_disk() -> TriMesh {
    let (rings, sectors) = (12u32, 40u32);
    let mut positions = vec![0.0, 0.0, 0.0];
    for r in 1..=rings {
        for s in 0..sectors {
            let a = s as f64 / sectors as f64 * std::f64::consts::TAU;
            let radius = r as f64 * (1.0 + 0.3 * (3.0 * a).sin() * r as f64 / rings as f64);
            positions.extend([radius * a.cos() * 1.7, radius * a.sin(), 0.0]);
        }
    }
    let id = |r: u32, s: u32| {
        if r == 0 {
            0
        } else {
            1 + (r - 1) * sectors + s % sectors
        }
    };
    let mut triangles = Vec::new();
    for s in 0..sectors {
        triangles.extend([0, id(1, s), id(1, s + 1)]);
    }
    for r in 1..rings {
        for s in 0..sectors {
            triangles.extend([id(r, s), id(r + 1, s), id(r + 1, s + 1), id(r, s), id(r + 1, s + 1), id(r, s + 1)]);
        }
    }
    TriMesh::new(&positions, &triangles).expect("valid disk")
}

#[test]
fn slim_and_arap_recover_the_isometry_of_a_flat_mesh() {
    let mesh = flat_wobbly_disk();
    for (method, minimum) in [(NonlinearMethod::Slim, 4.0), (NonlinearMethod::Arap, 0.0)] {
        let mut options = NonlinearOptions::new(method);
        options.iterations = 500;
        options.tolerance = 1e-12;
        let result = nonlinear_map(&mesh, &options).expect("map");
        let (e0, e1) = (result.energy[0], *result.energy.last().unwrap());
        // (ARAP starts from the natural conformal map, which is already the isometry here.)
        assert!(
            e1 - minimum < 1e-10 || e1 - minimum < 1e-6 * (e0 - minimum),
            "{method:?}: energy {e0} -> {e1}, minimum {minimum}"
        );
        assert_eq!(non_positive_triangles(&mesh, &result.uv), 0);
    }
}

#[test]
fn a_cancelling_callback_stops_within_one_iteration() {
    let mesh = load("disk_nefertiti_small.obj");
    for method in METHODS {
        let mut calls = 0usize;
        let mut callback = |_fraction: f64| {
            calls += 1;
            calls < 5
        };
        let result =
            nonlinear_map_with_progress(&mesh, &NonlinearOptions::new(method), &mut Progress::new(&mut callback));
        assert!(matches!(result, Err(Error::Cancelled)), "{method:?}: {result:?}");
        assert_eq!(calls, 5, "{method:?}: the callback was called after it cancelled");
    }
}

#[test]
fn results_are_deterministic() {
    let mesh = load("disk_three_peaks.obj");
    for method in METHODS {
        let mut options = NonlinearOptions::new(method);
        options.iterations = 10;
        let a = nonlinear_map(&mesh, &options).expect("map");
        let b = nonlinear_map(&mesh, &options).expect("map");
        assert!(
            a.uv.iter().zip(&b.uv).all(|(p, q)| p[0].to_bits() == q[0].to_bits() && p[1].to_bits() == q[1].to_bits()),
            "{method:?}"
        );
    }
}

#[test]
fn invalid_options_are_rejected() {
    let mesh = flat_wobbly_disk();
    let mut options = NonlinearOptions::new(NonlinearMethod::Degener);
    options.theta = 0.0;
    assert!(matches!(nonlinear_map(&mesh, &options), Err(Error::InvalidArgument(_))));
    let mut options = NonlinearOptions::new(NonlinearMethod::Slim);
    options.tolerance = f64::NAN;
    assert!(matches!(nonlinear_map(&mesh, &options), Err(Error::InvalidArgument(_))));
}

/// Per triangle, its share of the UV area over its share of the surface's area.
fn area_share_ratios(mesh: &TriMesh, uv: &[[f64; 2]]) -> Vec<f64> {
    let area_3d: Vec<f64> = mesh
        .triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| mesh.points()[v as usize]);
            let (u, w) = ([b[0] - a[0], b[1] - a[1], b[2] - a[2]], [c[0] - a[0], c[1] - a[1], c[2] - a[2]]);
            let n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
            0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
        })
        .collect();
    let area_uv: Vec<f64> = mesh
        .triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| uv[v as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        })
        .collect();
    let (total_3d, total_uv): (f64, f64) = (area_3d.iter().sum(), area_uv.iter().sum());
    area_uv.iter().zip(&area_3d).map(|(u, a)| (u / total_uv) / (a / total_3d)).collect()
}

/// ARAP and Green–Lagrange have no barrier in their energy; their line search keeps every
/// triangle at 1% of its share of the area or more, or at half its share in the start when that
/// is less (the start is the mean value map, or for ARAP the natural conformal map when it does
/// not flip). Without the floor these meshes had triangles at 10⁻⁷–10⁻¹¹ of their share (L2
/// stretch 10⁴–10⁸).
#[test]
fn arap_and_green_lagrange_keep_every_triangle_above_its_area_floor() {
    use uvflat_core::{fixed_boundary_map, natural_conformal_map, FixedBoundaryOptions};
    for file in ["disk_cat_head.obj", "disk_three_peaks.obj", "disk_mannequin_devil.obj", "holes_pig.obj"] {
        let mesh = load(file);
        let mean_value = fixed_boundary_map(&mesh, &FixedBoundaryOptions::default()).expect("mean value map");
        for method in [NonlinearMethod::Arap, NonlinearMethod::GreenLagrange] {
            let start = match natural_conformal_map(&mesh, None) {
                Ok(uv) if method == NonlinearMethod::Arap && non_positive_triangles(&mesh, &uv) == 0 => uv,
                _ => mean_value.clone(),
            };
            let mut options = NonlinearOptions::new(method);
            options.iterations = 100;
            let result = nonlinear_map(&mesh, &options).unwrap_or_else(|e| panic!("{file} {method:?}: {e}"));
            let (before, after) = (area_share_ratios(&mesh, &start), area_share_ratios(&mesh, &result.uv));
            let worst =
                before.iter().zip(&after).map(|(b, a)| a / (0.01f64).min(0.5 * b)).fold(f64::INFINITY, f64::min);
            assert!(worst >= 1.0 - 1e-6, "{file} {method:?}: a triangle at {worst:.3e} of its floor");
            let smallest = after.iter().copied().fold(f64::INFINITY, f64::min);
            println!(
                "{file} {method:?}: smallest area share ratio {smallest:.2e}, L2 {:.3}",
                stretch(&mesh, &result.uv)
            );
        }
    }
}

fn stretch(mesh: &TriMesh, uv: &[[f64; 2]]) -> f64 {
    distortion(mesh.points(), mesh.triangles(), uv, mesh.triangles()).expect("metrics").stretch_l2
}

/// Bijective SLIM pays for the scaffold only where plain SLIM would run its boundary into itself:
/// where plain SLIM's map is already bijective (the exact checker finds no overlap), the
/// bijective run gives the very same map; on the cut cow, where plain SLIM overlaps itself, the
/// bijective map has no overlap and no flip, and ends at an energy within 2% of plain SLIM's.
#[test]
fn bijective_slim_is_plain_slim_until_the_boundary_would_cross() {
    let plain = NonlinearOptions::new(NonlinearMethod::Slim);
    let bijective = NonlinearOptions { bijective: true, ..plain.clone() };
    for (file, plain_overlaps) in
        [("disk_nefertiti_small.obj", false), ("disk_lilium.obj", false), ("disk_cow_cut.obj", true)]
    {
        let mesh = load(file);
        let tris = mesh.triangles();
        let free = nonlinear_map(&mesh, &plain).expect("plain SLIM");
        let kept = nonlinear_map(&mesh, &bijective).expect("bijective SLIM");
        let free_check = uvflat_core::verify::check_layout(&free.uv, tris);
        let kept_check = uvflat_core::verify::check_layout(&kept.uv, tris);
        assert_eq!(free_check.overlaps > 0, plain_overlaps, "{file}: plain SLIM {free_check:?}");
        assert!(kept_check.flipped == 0 && kept_check.overlaps == 0, "{file}: bijective SLIM {kept_check:?}");
        if plain_overlaps {
            let (e_free, e_kept) = (*free.energy.last().unwrap(), *kept.energy.last().unwrap());
            assert!(e_kept <= 1.02 * e_free, "{file}: bijective energy {e_kept} vs plain {e_free}");
        } else {
            assert_eq!(kept.uv, free.uv, "{file}: bijective SLIM should be plain SLIM here");
        }
    }
}
