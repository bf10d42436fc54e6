//! ABF / ABF++ claims (Sheffer & de Sturler 2001; Sheffer et al. 2005; course notes §4.5) on
//! real disk meshes of `../shared/meshes` with at most 10k faces (the bench `benches/abf.rs`
//! prints the full table up to 100k faces):
//! - after reconstruction no triangle is flipped;
//! - mean |3D angle − uv angle| is at most the natural conformal map's;
//! - ABF++ reaches ‖∇L‖ ≤ 1e-6, and original ABF (full Newton) finds the same angles;
//! - a progress callback that refuses stops the method within one iteration.

use std::path::Path;
use uvflat::error::Error;
use uvflat::methods::abf::{abf, abf_with_progress, optimize_angles, AbfOptions, AbfVariant};
use uvflat::metrics::distortion;
use uvflat::progress::Progress;
use uvflat::{natural_conformal_map, TriMesh};

const MESH_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes");

fn load(file: &str) -> (TriMesh, Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let obj = uvflat::io::obj::read_obj(&Path::new(MESH_DIR).join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    let mesh = TriMesh::new(&obj.positions, &obj.triangles).unwrap_or_else(|e| panic!("{file}: {e}"));
    let points = mesh.points().to_vec();
    let tris = mesh.triangles().to_vec();
    (mesh, points, tris)
}

const SMALL_DISKS: [&str; 7] = [
    "disk_cat_head.obj",
    "disk_nefertiti_small.obj",
    "disk_three_peaks.obj",
    "disk_mushroom.obj",
    "disk_cow_cut.obj",
    "disk_lilium.obj",
    "disk_spothead.obj",
];

#[test]
fn abf_plus_plus_never_flips_and_preserves_angles_better_than_conformal() {
    for file in SMALL_DISKS {
        let (mesh, points, tris) = load(file);
        let result = abf(&mesh, &AbfOptions::default()).unwrap_or_else(|e| panic!("{file}: {e}"));
        let ours = distortion(&points, &tris, &result.uv, &tris).expect("metrics");
        let conformal = natural_conformal_map(&mesh, None).expect("conformal");
        let reference = distortion(&points, &tris, &conformal, &tris).expect("metrics");
        assert!(result.report.converged && result.report.gradient_norm <= 1e-6, "{file}: {:?}", result.report);
        assert_eq!(ours.flipped, 0, "{file}: flipped triangles");
        assert!(
            ours.angle_mean <= reference.angle_mean,
            "{file}: ABF++ {} vs conformal {}",
            ours.angle_mean,
            reference.angle_mean
        );
    }
}

#[test]
fn abf_and_abf_plus_plus_find_the_same_angles() {
    let (mesh, _, _) = load("disk_nefertiti_small.obj");
    let plus = optimize_angles(&mesh, &AbfOptions::default(), &mut Progress::none()).expect("ABF++");
    let full = optimize_angles(
        &mesh,
        &AbfOptions { variant: AbfVariant::Abf, ..AbfOptions::default() },
        &mut Progress::none(),
    )
    .expect("ABF");
    assert!(plus.report.converged && full.report.converged);
    let max =
        plus.angles.iter().flatten().zip(full.angles.iter().flatten()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(max < 1e-6, "angles differ by {max}");
}

#[test]
fn refusing_progress_callback_cancels_within_one_iteration() {
    let (mesh, _, _) = load("disk_cow_cut.obj");
    let mut calls = 0;
    let mut refuse = |_: f64| {
        calls += 1;
        false
    };
    let outcome = abf_with_progress(&mesh, &AbfOptions::default(), &mut Progress::new(&mut refuse));
    assert!(matches!(outcome, Err(Error::Cancelled)));
    assert_eq!(calls, 1);
}

#[test]
fn abf_is_deterministic() {
    let (mesh, _, _) = load("disk_three_peaks.obj");
    let a = abf(&mesh, &AbfOptions::default()).expect("ABF++");
    let b = abf(&mesh, &AbfOptions::default()).expect("ABF++");
    assert_eq!(a.uv, b.uv);
}
