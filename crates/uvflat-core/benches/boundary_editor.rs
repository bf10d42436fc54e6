//! Re-solve time of the boundary editor (Desbrun–Meyer–Alliez 2002 §4.2, real-time boundary
//! manipulation) on large disk meshes, against a fresh fixed-boundary solve, as a Markdown
//! table of medians. The target is a re-solve under 30 ms on a ~100k-face disk.
//!
//!     cargo bench --bench boundary_editor                          # disk_bimba_cut (89k faces) and
//!                                                                  # disk_face_libigl_loop1 (207k faces)
//!     cargo bench --bench boundary_editor -- path/to/disk.obj      # other disk meshes
//!     UVFLAT_EDITOR_RUNS=50 cargo bench --bench boundary_editor    # more re-solves (default 30)
//!
//! Each re-solve is `BoundaryEditor::solve_into` (new boundary positions in, every UV out,
//! into a caller-owned array), timed alone; "GB/s" is the factor's bytes read by the forward and
//! the backward substitution (2 × values × 8 bytes) over the median time — the memory traffic
//! that bounds a triangular solve. CPU seconds of the re-solves come from getrusage, so the
//! table stays meaningful when other jobs share the machine; the load average is printed.

use std::path::PathBuf;
use std::time::Instant;
use uvflat_core::methods::intrinsic::BoundaryEditor;
use uvflat_core::progress::Progress;
use uvflat_core::{fixed_boundary_map, BoundaryShape, Distribution, FixedBoundaryOptions, TriMesh, Weights};

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

fn boundary(editor: &BoundaryEditor, phase: f64) -> Vec<[f64; 2]> {
    let b = editor.boundary_vertices().len() as f64;
    (0..editor.boundary_vertices().len())
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / b;
            let r = 1.0 + 0.2 * (5.0 * a + phase).cos();
            [r * a.cos(), r * a.sin()]
        })
        .collect()
}

/// User + system CPU seconds of this process so far.
fn cpu_seconds() -> f64 {
    // SAFETY: getrusage fills the struct it is given.
    let mut usage: Rusage = unsafe { std::mem::zeroed() };
    unsafe { getrusage(0, &mut usage) };
    let t = |tv: [i64; 2]| tv[0] as f64 + tv[1] as f64 * 1e-6;
    t(usage.utime) + t(usage.stime)
}

#[repr(C)]
struct Rusage {
    utime: [i64; 2],
    stime: [i64; 2],
    rest: [i64; 14],
}

extern "C" {
    fn getrusage(who: i32, usage: *mut Rusage) -> i32;
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map_or("?".into(), |s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
}

fn bench_mesh(path: &PathBuf, runs: usize) {
    let obj = uvflat_core::io::obj::read_obj(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mesh = TriMesh::new(&obj.positions, &obj.triangles).expect("valid mesh");
    let name = path.file_name().map_or("?".into(), |f| f.to_string_lossy().to_string());
    for (lambda, mu) in [(1.0, 0.0), (0.5, 0.5)] {
        let t = Instant::now();
        let editor = BoundaryEditor::new(&mesh, lambda, mu, &mut Progress::none()).expect("editor");
        let factor = t.elapsed().as_secs_f64() * 1e3;
        let mut uv = vec![[0.0; 2]; mesh.vertex_count()];
        // Warm-up: fills the editor's buffer pool and the caches.
        editor.solve_into(&boundary(&editor, 0.0), &mut uv).expect("solve");
        let boundaries: Vec<Vec<[f64; 2]>> = (0..runs).map(|k| boundary(&editor, 0.1 * k as f64)).collect();
        let mut times = Vec::with_capacity(runs);
        let cpu = cpu_seconds();
        for b in &boundaries {
            let t = Instant::now();
            editor.solve_into(b, &mut uv).expect("solve");
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        let cpu_ms = (cpu_seconds() - cpu) * 1e3 / runs as f64;
        let given: Vec<(u32, [f64; 2])> =
            editor.boundary_vertices().iter().copied().zip(boundaries[runs - 1].iter().copied()).collect();
        let options = FixedBoundaryOptions {
            weights: Weights::Intrinsic { lambda, mu },
            shape: BoundaryShape::Given(given),
            distribution: Distribution::Uniform,
        };
        let t = Instant::now();
        let fresh = fixed_boundary_map(&mesh, &options).expect("fresh map");
        let fresh_ms = t.elapsed().as_secs_f64() * 1e3;
        let diff = uv
            .iter()
            .zip(&fresh)
            .filter(|(p, _)| p[0].is_finite())
            .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
            .fold(0.0, f64::max);
        assert!(diff <= 1e-9, "editor and fresh solve differ by {diff:e}");
        let min = times.iter().copied().fold(f64::INFINITY, f64::min);
        let med = median(times);
        let gbs = 2.0 * editor.factor_len() as f64 * 8.0 / (med * 1e-3) / 1e9;
        println!(
            "| {name} | {} | {lambda}, {mu} | {:.1} | {factor:.0} | {med:.1} | {min:.1} | {cpu_ms:.1} | {gbs:.1} | {fresh_ms:.0} | {} |",
            mesh.triangle_count(),
            editor.factor_len() as f64 / 1e6,
            load_average()
        );
    }
}

fn main() {
    let paths: Vec<PathBuf> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).map(PathBuf::from).collect();
    let paths = if paths.is_empty() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/meshes/");
        vec![
            PathBuf::from(format!("{dir}disk_bimba_cut.obj.gz")),
            PathBuf::from(format!("{dir}disk_face_libigl_loop1.obj.gz")),
        ]
    } else {
        paths
    };
    let runs: usize = std::env::var("UVFLAT_EDITOR_RUNS").ok().and_then(|s| s.parse().ok()).unwrap_or(30).max(1);
    println!("{runs} re-solves per row, rayon threads: {}\n", rayon::current_num_threads());
    println!(
        "| mesh | faces | λ, μ | factor values (M) | factor (ms) | re-solve median (ms) | re-solve min (ms) | re-solve CPU (ms) | GB/s | fresh fixed-boundary map (ms) | load average |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for path in &paths {
        bench_mesh(path, runs);
    }
}
