//! Re-solve time of the boundary editor (Desbrun–Meyer–Alliez 2002 §4.2, real-time boundary
//! manipulation) on a large disk mesh, against a fresh fixed-boundary solve, as a Markdown
//! table of medians.
//!
//!     cargo bench --bench boundary_editor                          # disk_face_libigl_loop1 (207k faces)
//!     cargo bench --bench boundary_editor -- path/to/disk.obj      # another disk mesh
//!     UVFLAT_EDITOR_RUNS=50 cargo bench --bench boundary_editor    # more re-solves (default 20)

use std::path::PathBuf;
use std::time::Instant;
use uvflat::methods::intrinsic::BoundaryEditor;
use uvflat::progress::Progress;
use uvflat::{fixed_boundary_map, BoundaryShape, Distribution, FixedBoundaryOptions, TriMesh, Weights};

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

fn main() {
    let path = std::env::args().skip(1).find(|a| !a.starts_with('-')).map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/disk_face_libigl_loop1.obj"))
    });
    let runs: usize = std::env::var("UVFLAT_EDITOR_RUNS").ok().and_then(|s| s.parse().ok()).unwrap_or(20);
    let obj = uvflat::io::obj::read_obj(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mesh = TriMesh::new(&obj.positions, &obj.triangles).expect("valid mesh");
    println!(
        "mesh: {} ({} vertices, {} faces), {runs} re-solves per row, threads: {}\n",
        path.display(),
        mesh.vertex_count(),
        mesh.triangle_count(),
        rayon::current_num_threads()
    );
    println!("| λ, μ | factor (ms) | re-solve median (ms) | re-solve min (ms) | fresh fixed-boundary map (ms) |");
    println!("|---|---|---|---|---|");
    for (lambda, mu) in [(1.0, 0.0), (0.5, 0.5)] {
        let t = Instant::now();
        let editor = BoundaryEditor::new(&mesh, lambda, mu, &mut Progress::none()).expect("editor");
        let factor = t.elapsed().as_secs_f64() * 1e3;
        let mut times = Vec::with_capacity(runs);
        let mut last = Vec::new();
        for k in 0..runs {
            let b = boundary(&editor, 0.1 * k as f64);
            let t = Instant::now();
            last = editor.solve(&b).expect("solve");
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        let b = boundary(&editor, 0.1 * (runs - 1) as f64);
        let given: Vec<(u32, [f64; 2])> = editor.boundary_vertices().iter().copied().zip(b).collect();
        let options = FixedBoundaryOptions {
            weights: Weights::Intrinsic { lambda, mu },
            shape: BoundaryShape::Given(given),
            distribution: Distribution::Uniform,
        };
        let t = Instant::now();
        let fresh = fixed_boundary_map(&mesh, &options).expect("fresh map");
        let fresh_ms = t.elapsed().as_secs_f64() * 1e3;
        let diff = last
            .iter()
            .zip(&fresh)
            .filter(|(p, _)| p[0].is_finite())
            .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
            .fold(0.0, f64::max);
        assert!(diff <= 1e-9, "editor and fresh solve differ by {diff:e}");
        let min = times.iter().copied().fold(f64::INFINITY, f64::min);
        println!("| {lambda}, {mu} | {factor:.0} | {:.1} | {min:.1} | {fresh_ms:.0} |", median(times));
    }
}
