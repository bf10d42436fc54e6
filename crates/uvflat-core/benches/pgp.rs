//! Time of the whole PGP pipeline (Ray et al. 2006: curvature, smoothing, periodic solve,
//! extraction, singularities, then the chart layout of §3.3, the per-chart parameterization of
//! §3.4 and the quad-dominant remesh of §5) on large meshes, as a Markdown table of medians. The target is the full pipeline
//! on a 200k-face mesh in under 60 s on this 2-core machine (the paper: 17 min for 200k faces
//! on a 1.7 GHz machine).
//!
//!     cargo bench --bench pgp                         # disk_face_libigl_loop1 (207k faces)
//!     cargo bench --bench pgp -- path/to/mesh.obj     # other meshes
//!     UVFLAT_PGP_RUNS=1 cargo bench --bench pgp       # runs per mesh (default 3, median)
//!     UVFLAT_PGP_NEWTON=10 cargo bench --bench pgp    # Newton iteration limit (default 100)
//!
//! Columns: the periodic solve's Newton iterations (* where ‖∇F**‖ < 10⁻⁶ was reached, last
//! run), wall seconds of `pgp` (everything up to the singularities), of the chart layout,
//! of the per-chart parameterization (one line per period), of the remesh (8 lines per
//! period), their total, the number of charts, and the remesh's face count and quad share.
//! The load average before and after is printed: the machine is shared. So is a same-run
//! reference of the machine's speed: the GFLOP/s of a dense 1500 × 1500 product on both cores
//! (faer, the kernels the factorizations of the periodic solve spend most of their time in),
//! median of 5, before and after the runs; a pipeline time divided by it compares across days.

use std::path::PathBuf;
use std::time::Instant;
use uvflat_core::methods::pgp::charts::chart_parameterization;
use uvflat_core::methods::pgp::{chart_layout, pgp, quad_dominant_remesh, PgpOptions};
use uvflat_core::progress::Progress;
use uvflat_core::TriMesh;

const DENSITY: f64 = 8.0;

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map_or("?".into(), |s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
}

/// Median GFLOP/s of `C = A Aᵀ` for a dense 1500 × 1500 `A`, on all cores (5 runs).
fn dense_reference_gflops() -> f64 {
    use faer::linalg::matmul::matmul;
    use faer::{Accum, Mat, Par};
    let n = 1500;
    let a = Mat::<f64>::from_fn(n, n, |i, j| ((i * 7 + j * 13) % 17) as f64 / 17.0 - 0.5);
    let mut c = Mat::<f64>::zeros(n, n);
    let rates = (0..5)
        .map(|_| {
            let start = Instant::now();
            matmul(c.as_mut(), Accum::Replace, a.as_ref(), a.transpose(), 1.0, Par::rayon(0));
            std::hint::black_box(&c);
            2.0 * (n as f64).powi(3) / start.elapsed().as_secs_f64() / 1e9
        })
        .collect();
    median(rates)
}

fn load(path: &PathBuf) -> TriMesh {
    let obj = uvflat_core::io::obj::read_obj(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    TriMesh::new(&obj.positions, &obj.triangles).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let meshes: Vec<PathBuf> = if args.is_empty() {
        vec![PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/meshes/disk_face_libigl_loop1.obj.gz"
        ))]
    } else {
        args.iter().map(PathBuf::from).collect()
    };
    let runs: usize = std::env::var("UVFLAT_PGP_RUNS").ok().and_then(|s| s.parse().ok()).unwrap_or(3).max(1);
    let mut options = PgpOptions::default();
    if let Some(limit) = std::env::var("UVFLAT_PGP_NEWTON").ok().and_then(|s| s.parse().ok()) {
        options.newton.max_iterations = limit;
    }
    println!("Newton iteration limit: {}", options.newton.max_iterations);
    println!("load average before: {}", load_average());
    println!("dense reference before: {:.1} GFLOP/s", dense_reference_gflops());
    println!(
        "| mesh | triangles | Newton iterations | pgp s | chart layout s | charts s | remesh s | total s | charts | remesh faces | quads |"
    );
    println!("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
    for path in &meshes {
        let mesh = load(path);
        let (mut solve, mut layout, mut charts, mut remesh, mut total) = (vec![], vec![], vec![], vec![], vec![]);
        let (mut faces, mut chart_count, mut newton) = ((0, 0), 0, (0, false));
        for _ in 0..runs {
            let start = Instant::now();
            let r = pgp(&mesh, &options, &mut Progress::none()).expect("pgp");
            newton = (r.solve.iterations, r.solve.converged);
            let t1 = start.elapsed().as_secs_f64();
            let l = chart_layout(&mesh, &r).expect("chart layout");
            let t2 = start.elapsed().as_secs_f64();
            let c = chart_parameterization(&mesh, &r, 1.0).expect("charts");
            let t3 = start.elapsed().as_secs_f64();
            let q = quad_dominant_remesh(&mesh, &r, DENSITY).expect("remesh");
            let t4 = start.elapsed().as_secs_f64();
            std::hint::black_box(&l);
            faces = (q.face_sizes.len(), q.quad_count());
            chart_count = c.charts.len();
            solve.push(t1);
            layout.push(t2 - t1);
            charts.push(t3 - t2);
            remesh.push(t4 - t3);
            total.push(t4);
        }
        let name = path.file_stem().map_or("?".into(), |s| s.to_string_lossy().into_owned());
        println!(
            "| {name} | {} | {}{} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {chart_count} | {} | {:.1}% |",
            mesh.triangle_count(),
            newton.0,
            if newton.1 { "*" } else { "" },
            median(solve),
            median(layout),
            median(charts),
            median(remesh),
            median(total),
            faces.0,
            100.0 * faces.1 as f64 / faces.0.max(1) as f64
        );
    }
    println!("load average after: {}", load_average());
    println!("dense reference after: {:.1} GFLOP/s", dense_reference_gflops());
}
