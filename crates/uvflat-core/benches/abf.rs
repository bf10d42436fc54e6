//! ABF++ (and ABF) convergence and quality on the disk test meshes, as a
//! Markdown table in the spirit of the course notes' Table 4.1: mesh, faces, method, iterations,
//! seconds, final ‖∇L‖₂, flipped triangles after reconstruction, mean |3D angle − uv angle|, and
//! the natural conformal map's time and angle distortion for comparison.
//!
//!     cargo bench --bench abf                                   # disk meshes up to 100k faces
//!     UVFLAT_BENCH_MAX_FACES=300000 cargo bench --bench abf     # also the 207k-face mesh
//!     UVFLAT_BENCH_ABF_MAX_FACES=20000 cargo bench --bench abf  # also original ABF up to 20k
//!     UVFLAT_BENCH_MESHES=disk_mountain.obj,disk_bimba_cut.obj cargo bench --bench abf
//!     UVFLAT_BENCH_PLAIN_GN=1 cargo bench --bench abf  # also the paper's plain Gauss–Newton
//!     UVFLAT_BENCH_ABF_WEIGHTS=square cargo bench --bench abf   # the papers' w = 1/β² (or inverse: 1/β)
//!     UVFLAT_BENCH_ABF_BARRIER=0 cargo bench --bench abf        # no angle barrier (the papers' objective)
//!     UVFLAT_BENCH_ABF_KRYLOV=40 UVFLAT_BENCH_ABF_MAX_ITERATIONS=30 cargo bench --bench abf
//!
//! Times: `TriMesh::new` plus the method (angle optimisation + reconstruction), one run each
//! (OBJ loading not timed). Threads: as many as rayon gives (printed).

use std::time::Instant;
use uvflat_core::methods::abf::{abf, AbfOptions, AbfVariant, AbfWeights};
use uvflat_core::metrics::distortion;
use uvflat_core::{natural_conformal_map, TriMesh};
use uvflat_test_support::meshes;

fn env_usize(name: &str, default: usize) -> usize {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

/// Disk meshes (`disk_*.obj`) with their face counts, smallest first.
fn disk_meshes(max_faces: usize) -> Vec<(usize, String)> {
    let only: Option<Vec<String>> =
        std::env::var("UVFLAT_BENCH_MESHES").ok().map(|s| s.split(',').map(str::to_string).collect());
    let keep = |name: &String| only.as_ref().is_none_or(|only| only.contains(name));
    meshes::up_to("disk_", max_faces).into_iter().filter(|(_, name)| keep(name)).collect()
}

fn main() {
    let max_faces = env_usize("UVFLAT_BENCH_MAX_FACES", 100_000);
    let abf_max_faces = env_usize("UVFLAT_BENCH_ABF_MAX_FACES", 0);
    let plain_gn = std::env::var("UVFLAT_BENCH_PLAIN_GN").is_ok_and(|v| v == "1");
    let krylov = env_usize("UVFLAT_BENCH_ABF_KRYLOV", AbfOptions::default().newton_krylov_steps as usize) as u32;
    let max_iterations =
        env_usize("UVFLAT_BENCH_ABF_MAX_ITERATIONS", AbfOptions::default().max_iterations as usize) as u32;
    let weights = match std::env::var("UVFLAT_BENCH_ABF_WEIGHTS").as_deref() {
        Ok("inverse") => AbfWeights::Inverse,
        Ok("square") => AbfWeights::InverseSquare,
        _ => AbfOptions::default().weights,
    };
    let barrier = std::env::var("UVFLAT_BENCH_ABF_BARRIER")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(AbfOptions::default().barrier);
    println!(
        "weights: {weights:?}, barrier: {barrier}, Newton–Krylov steps: {krylov}, most iterations: {max_iterations}"
    );
    println!("threads: {}", rayon::current_num_threads());
    println!();
    println!("| mesh | faces | method | iterations | seconds | final ‖∇L‖ | flipped | invalid angles | angle error mean (°) | natural conformal: seconds | angle error mean (°) |");
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (faces, name) in disk_meshes(max_faces) {
        let obj = meshes::read(&name);
        let tris: Vec<[u32; 3]> = obj.triangles.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let points: Vec<[f64; 3]> = obj.positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let start = Instant::now();
        let mesh = TriMesh::new(&obj.positions, &obj.triangles).expect("valid mesh");
        let conformal = natural_conformal_map(&mesh, None).expect("natural conformal");
        let conformal_seconds = start.elapsed().as_secs_f64();
        let conformal_metrics = distortion(&points, &tris, &conformal, &tris).expect("metrics");
        let mut variants = vec![(AbfVariant::AbfPlusPlus, krylov, "ABF++")];
        if plain_gn {
            variants.push((AbfVariant::AbfPlusPlus, 0, "ABF++ (Gauss–Newton only)"));
        }
        if faces <= abf_max_faces {
            variants.push((AbfVariant::Abf, 0, "ABF"));
        }
        for (variant, newton_krylov_steps, label) in variants {
            let start = Instant::now();
            let mesh = TriMesh::new(&obj.positions, &obj.triangles).expect("valid mesh");
            let options =
                AbfOptions { variant, newton_krylov_steps, weights, barrier, max_iterations, ..AbfOptions::default() };
            match abf(&mesh, &options) {
                Ok(result) => {
                    let seconds = start.elapsed().as_secs_f64();
                    let m = distortion(&points, &tris, &result.uv, &tris).expect("metrics");
                    let r = result.report;
                    println!(
                        "| {name} | {faces} | {label} | {} | {seconds:.3} | {:.1e} | {} | {} | {:.3} | {conformal_seconds:.3} | {:.3} |",
                        r.iterations,
                        r.gradient_norm,
                        m.flipped,
                        r.invalid_angles,
                        m.angle_mean.to_degrees(),
                        conformal_metrics.angle_mean.to_degrees()
                    );
                }
                Err(e) => println!("| {name} | {faces} | {label} | failed: {e} | | | | | | {conformal_seconds:.3} | |"),
            }
        }
    }
}
