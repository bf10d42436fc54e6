//! Per-phase timings of mesh construction and the natural conformal map (plus the totals of
//! the fixed-boundary maps) on one OBJ, as a Markdown table of medians.
//!
//!     cargo bench --bench phases                                # the 1.43M-face mesh
//!     cargo bench --bench phases -- path/to/mesh.obj            # another mesh
//!     UVFLAT_PHASES_RUNS=5 cargo bench --bench phases           # more runs (default 3)
//!
//! Each phase calls the library's public steps in the order `natural_conformal_map` does, so
//! their sum is close to the end-to-end time, which is measured separately. OBJ loading is not
//! timed. The default mesh is the optional 1.43M-face `disk_bimba_cut_loop2.obj.gz` from the
//! folder `UVFLAT_LARGE_MESHES` names (`tests/data/meshes/README.md` says how to get it).

use std::path::PathBuf;
use std::time::Instant;
use uvflat_core::methods::conformal::{resolve_pins, ConformalSystem};
use uvflat_core::{
    fixed_boundary_map, natural_conformal_map, BoundaryShape, Distribution, FixedBoundaryOptions, TriMesh, Weights,
};
use uvflat_sparse::split_hermitian::{self, SplitHermitianSolver};
use uvflat_sparse::{ordering, CholeskyPattern};

/// Wall and CPU seconds spent in each named phase, one entry per run.
#[derive(Default)]
struct Timings {
    phases: Vec<(&'static str, Vec<f64>, Vec<f64>)>,
}

/// CPU time of the whole process (all threads) in seconds, from `/proc/self/stat` (Linux; NaN
/// elsewhere). On a machine shared with other jobs it shows the work done, which the wall
/// time hides.
fn process_cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else { return f64::NAN };
    let Some(fields) = stat.rfind(')').map(|k| stat[k + 2..].split_whitespace().collect::<Vec<_>>()) else {
        return f64::NAN;
    };
    let ticks = |i: usize| fields.get(i).and_then(|f| f.parse::<f64>().ok()).unwrap_or(f64::NAN);
    // utime and stime, in clock ticks of 1/100 s.
    (ticks(11) + ticks(12)) / 100.0
}

impl Timings {
    fn record(&mut self, phase: &'static str, wall: f64, cpu: f64) {
        match self.phases.iter_mut().find(|(name, _, _)| *name == phase) {
            Some((_, walls, cpus)) => {
                walls.push(wall);
                cpus.push(cpu);
            }
            None => self.phases.push((phase, vec![wall], vec![cpu])),
        }
    }

    /// Runs `f`, records its time under `phase` and returns its value.
    fn time<R>(&mut self, phase: &'static str, f: impl FnOnce() -> R) -> R {
        let (start, cpu) = (Instant::now(), process_cpu_seconds());
        let value = f();
        self.record(phase, start.elapsed().as_secs_f64(), process_cpu_seconds() - cpu);
        value
    }

    fn print(&self) {
        println!("| phase | median s | min s | max s | median CPU s |");
        println!("|---|---:|---:|---:|---:|");
        for (name, walls, cpus) in &self.phases {
            let (lo, hi) = walls.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &t| (lo.min(t), hi.max(t)));
            println!("| {name} | {:.3} | {lo:.3} | {hi:.3} | {:.2} |", median(walls.clone()), median(cpus.clone()));
        }
    }
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// One run of the natural conformal map's steps; returns the number of entries of L and
/// whether the factorization was split (real interior, complex boundary).
fn conformal_phases(
    positions: &[f64],
    triangles: &[u32],
    t: &mut Timings,
) -> Result<(usize, bool), uvflat_core::Error> {
    let mesh = t.time("TriMesh::new", || TriMesh::new(positions, triangles))?;
    let pins = t.time("nc: topology check + pins", || resolve_pins(&mesh, None))?;
    let mut system = t.time("nc: assemble", || ConformalSystem::new(&mesh, pins))?;
    let pattern = system.matrix.symbolic();
    let coords = system.unknowns.positions(&mesh);
    let complex = split_hermitian::complex_unknowns(system.matrix.as_ref());
    let count = complex.iter().filter(|&&c| c).count();
    if !split_hermitian::split_pays(pattern.nrows(), count) {
        // All-complex path (very long boundaries).
        let order = t.time("nc: ordering", || {
            let adjacency = ordering::Adjacency::from_lower(pattern.nrows(), pattern.col_ptr(), pattern.row_idx());
            ordering::nested_dissection(&adjacency, &coords)
        });
        let analysis = t.time("nc: symbolic", || CholeskyPattern::with_order(pattern, Some(order)))?;
        let factor = t.time("nc: numeric", || analysis.factor(&system.matrix))?;
        t.time("nc: solve", || factor.solve_in_place(&mut system.rhs))?;
        let uv = t.time("nc: uv", || system.uv(&mesh))?;
        std::hint::black_box(uv);
        return Ok((analysis.factor_len(), false));
    }
    let (order, split) = t.time("nc: ordering", || split_hermitian::order_complex_last(pattern, &coords, &complex));
    let analysis = t.time("nc: symbolic", || CholeskyPattern::with_order(pattern, Some(order)))?;
    let factor = t.time("nc: numeric", || SplitHermitianSolver::factor(&analysis, &system.matrix, split))?;
    t.time("nc: solve", || factor.solve_in_place(&mut system.rhs))?;
    let uv = t.time("nc: uv", || system.uv(&mesh))?;
    std::hint::black_box(uv);
    Ok((analysis.factor_len(), true))
}

fn fixed_boundary_total(mesh: &TriMesh, weights: Weights) -> Result<(), uvflat_core::Error> {
    let options =
        FixedBoundaryOptions { weights, shape: BoundaryShape::Circle, distribution: Distribution::ChordLength };
    std::hint::black_box(fixed_boundary_map(mesh, &options)?);
    Ok(())
}

fn default_mesh() -> PathBuf {
    let folder = std::env::var_os("UVFLAT_LARGE_MESHES")
        .expect("give a mesh, or set UVFLAT_LARGE_MESHES to the folder holding disk_bimba_cut_loop2.obj.gz");
    PathBuf::from(folder).join("disk_bimba_cut_loop2.obj.gz")
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    if !std::env::args().any(|a| a == "--bench") {
        eprintln!("phases: run with `cargo bench --bench phases` (the binary needs --bench)");
        return Ok(());
    }
    let path = std::env::args().skip(1).find(|a| !a.starts_with('-')).map(PathBuf::from).unwrap_or_else(default_mesh);
    let runs: usize = std::env::var("UVFLAT_PHASES_RUNS").ok().and_then(|v| v.parse().ok()).unwrap_or(3);
    let skip_fixed = std::env::var_os("UVFLAT_PHASES_NC_ONLY").is_some();
    let obj = uvflat_core::io::obj::read_obj(&path)?;
    let (positions, triangles) = (&obj.positions, &obj.triangles);
    println!(
        "{}: {} vertices, {} faces; {} rayon threads, {runs} runs",
        path.display(),
        positions.len() / 3,
        triangles.len() / 3,
        rayon::current_num_threads()
    );
    let mut t = Timings::default();
    let (mut factor_len, mut split) = (0, false);
    for _ in 0..runs {
        (factor_len, split) = conformal_phases(positions, triangles, &mut t)?;
        let uv = t.time("total: TriMesh::new + natural_conformal_map", || {
            TriMesh::new(positions, triangles).and_then(|mesh| natural_conformal_map(&mesh, None))
        })?;
        std::hint::black_box(uv);
        if skip_fixed {
            continue;
        }
        let mesh = TriMesh::new(positions, triangles)?;
        for (name, weights) in [
            ("fixed boundary: Tutte", Weights::Uniform),
            ("fixed boundary: DCP", Weights::Conformal),
            ("fixed boundary: DAP", Weights::Authalic),
            ("fixed boundary: mean value", Weights::MeanValue),
        ] {
            t.time(name, || fixed_boundary_total(&mesh, weights))?;
        }
    }
    let kind = if split { "real interior + dense complex boundary block" } else { "complex" };
    println!("nnz(L) of the natural conformal system: {factor_len} ({kind})");
    println!();
    t.print();
    Ok(())
}
