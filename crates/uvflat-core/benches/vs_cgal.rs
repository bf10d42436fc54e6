//! uvflat against CGAL 5.5's Surface_mesh_parameterization: time per method on every disk test
//! mesh, printed as a Markdown table.
//!
//!     cargo bench --bench vs_cgal                              # all disk meshes, up to 1.43M faces
//!     UVFLAT_BENCH_MAX_FACES=100000 cargo bench --bench vs_cgal
//!     UVFLAT_BENCH_MIN_FACES=100000 cargo bench --bench vs_cgal   # only the meshes of 100k faces or more
//!
//! What is timed:
//! - uvflat: `TriMesh::new` (validation and connectivity) plus the method call, median of 3
//!   runs; OBJ loading is not timed. Fixed-border methods put the boundary on the circle with
//!   chord-length spacing (`BoundaryShape::Circle`, `Distribution::ChordLength`), as CGAL's
//!   `Circular_border_arc_length_parameterizer_3` does; the natural conformal map gets CGAL's
//!   two pins at CGAL's positions.
//! - CGAL: the `parameterize()` call alone, as reported by `crates/uvflat-test-support/cgal/cgal_reference.cpp`
//!   (its Surface_mesh is built before the clock starts, so uvflat's time includes more work);
//!   median of 3 runs, or 1 when the first takes more than 60 s.
//!
//! CGAL runs single-threaded; uvflat uses as many threads as rayon gives it (printed).
//! The test meshes are decompressed once under `<target>/tmp/meshes/` for CGAL's reader; the
//! 1.43M-face `disk_bimba_cut_loop2.obj.gz` is added when `UVFLAT_LARGE_MESHES` names the folder
//! holding it.

use cgal::{DiskMesh, Method};
use std::io::Write;
use std::path::Path;
use std::time::Instant;
use uvflat_core::{
    fixed_boundary_map, natural_conformal_map, BoundaryShape, Distribution, FixedBoundaryOptions, TriMesh, Weights,
};
use uvflat_test_support::{cgal, meshes};

/// A run longer than this is not repeated.
const REPEAT_LIMIT_SECONDS: f64 = 60.0;
const RUNS: usize = 3;
/// The optional 1.43M-face mesh (`tests/data/meshes/README.md` says how to get it).
const LARGE: &str = "disk_bimba_cut_loop2.obj.gz";
const LARGE_FACES: usize = 1_427_440;

/// Times `run` up to `RUNS` times (once if the first run exceeds the limit) and returns the
/// median of the times it reports, or its first error.
fn median_time(mut run: impl FnMut() -> Result<f64, String>) -> Result<f64, String> {
    let first = run()?;
    let mut times = vec![first];
    if first <= REPEAT_LIMIT_SECONDS {
        for _ in 1..RUNS {
            times.push(run()?);
        }
    }
    Ok(cgal::median(times))
}

/// One uvflat run: `TriMesh::new` plus the method, in seconds.
fn time_uvflat(
    positions: &[f64],
    triangles: &[u32],
    method: Method,
    pins: Option<[(u32, [f64; 2]); 2]>,
) -> Result<f64, String> {
    let start = Instant::now();
    let mesh = TriMesh::new(positions, triangles).map_err(|e| e.to_string())?;
    let weights = match method {
        Method::Dcp => Weights::Conformal,
        Method::Dap => Weights::Authalic,
        Method::Mvc => Weights::MeanValue,
        Method::Tutte => Weights::Uniform,
        Method::Lscm => {
            let uv = natural_conformal_map(&mesh, pins).map_err(|e| e.to_string())?;
            let seconds = start.elapsed().as_secs_f64();
            std::hint::black_box(uv);
            return Ok(seconds);
        }
    };
    let options =
        FixedBoundaryOptions { weights, shape: BoundaryShape::Circle, distribution: Distribution::ChordLength };
    let uv = fixed_boundary_map(&mesh, &options).map_err(|e| e.to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    std::hint::black_box(uv);
    Ok(seconds)
}

fn bench_mesh(exe: &Path, disk: &DiskMesh) {
    let (positions, triangles) = match cgal::read_plain_obj(&disk.path) {
        Ok(obj) => obj,
        Err(e) => {
            println!("| {} | {} | all | {e} | | |", disk.name, disk.faces);
            return;
        }
    };
    for method in Method::ALL {
        let mut pins = None;
        let cgal = median_time(|| {
            let reference = cgal::run_reference(exe, method, &disk.path, None)?;
            pins = reference.pins.map(|(a, b)| [(a, reference.uv[a as usize]), (b, reference.uv[b as usize])]);
            Ok(reference.seconds)
        });
        // Without CGAL's pins (CGAL failed), uvflat picks its own.
        let ours = median_time(|| time_uvflat(&positions, &triangles, method, pins));
        let cell = |t: &Result<f64, String>| match t {
            Ok(s) => format!("{s:.4}"),
            Err(e) => format!("failed: {}", e.replace('|', "/").replace('\n', " ")),
        };
        let ratio = match (&cgal, &ours) {
            (Ok(c), Ok(u)) if *u > 0.0 => format!("{:.2}", c / u),
            _ => "-".to_string(),
        };
        println!(
            "| {} | {} | {} | {} | {} | {} |",
            disk.name,
            disk.faces,
            method.name(),
            cell(&ours),
            cell(&cgal),
            ratio
        );
        let _ = std::io::stdout().flush();
    }
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --all-targets` runs this binary without it,
    // and must not start a half-hour benchmark.
    if !std::env::args().any(|a| a == "--bench") {
        eprintln!("vs_cgal: run with `cargo bench --bench vs_cgal` (the binary needs --bench)");
        return;
    }
    if !cgal::require_headers_or_skip() {
        return;
    }
    let max_faces = match std::env::var("UVFLAT_BENCH_MAX_FACES") {
        Ok(v) => v.trim().parse().unwrap_or_else(|_| panic!("UVFLAT_BENCH_MAX_FACES={v} is not a face count")),
        Err(_) => usize::MAX,
    };
    let min_faces = match std::env::var("UVFLAT_BENCH_MIN_FACES") {
        Ok(v) => v.trim().parse().unwrap_or_else(|_| panic!("UVFLAT_BENCH_MIN_FACES={v} is not a face count")),
        Err(_) => 0,
    };
    let start = Instant::now();
    let exe = cgal::reference_executable().unwrap_or_else(|e| panic!("{e}"));
    eprintln!("CGAL reference program: {} ({:.1} s)", exe.display(), start.elapsed().as_secs_f64());

    let mut meshes = cgal::disk_meshes(max_faces);
    if LARGE_FACES <= max_faces {
        match meshes::large(LARGE) {
            Some(gz) => {
                let path = meshes::unpack(&gz);
                meshes.push(DiskMesh { name: "disk_bimba_cut_loop2".into(), path, faces: LARGE_FACES });
            }
            None => eprintln!("skipping {LARGE}: set UVFLAT_LARGE_MESHES to the folder holding it"),
        }
    }

    meshes.retain(|disk| disk.faces >= min_faces);
    println!(
        "uvflat vs CGAL 5.5.1 Surface_mesh_parameterization ({} rayon threads for uvflat, CGAL single-threaded)",
        rayon::current_num_threads()
    );
    println!("uvflat s: TriMesh::new + method, median of {RUNS}; CGAL s: parameterize() only, median of {RUNS} (1 run if > {REPEAT_LIMIT_SECONDS} s)");
    println!();
    println!("| mesh | faces | method | uvflat s | CGAL s | CGAL/uvflat |");
    println!("|---|---:|---|---:|---:|---:|");
    for disk in &meshes {
        bench_mesh(&exe, disk);
    }
    eprintln!("total {:.1} s", start.elapsed().as_secs_f64());
}
