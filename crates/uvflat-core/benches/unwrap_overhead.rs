//! What the default unwrap costs on top of the flattening itself: on meshes whose natural
//! conformal map is already valid and under the stretch bound (one island, no repair), the
//! default `unwrap` against `natural_conformal_map` alone, the two calls interleaved in one
//! process (so both see the same machine load), median of each and median of the per-pair
//! ratios, as a Markdown table.
//!
//!     cargo bench --bench unwrap_overhead -- a.obj b.obj …
//!     UVFLAT_OVERHEAD_RUNS=61 cargo bench --bench unwrap_overhead -- a.obj   # default 41
//!
//! A mesh whose default unwrap is not one unrepaired island is reported and skipped (its
//! unwrap does more than check, pack and measure).

use std::path::Path;
use std::time::Instant;
use uvflat_core::unwrap::{unwrap, UnwrapOptions};
use uvflat_core::{natural_conformal_map, TriMesh};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn seconds(f: impl FnOnce()) -> f64 {
    let start = Instant::now();
    f();
    start.elapsed().as_secs_f64()
}

fn main() {
    let runs: usize = std::env::var("UVFLAT_OVERHEAD_RUNS").ok().and_then(|s| s.parse().ok()).unwrap_or(41).max(1);
    let files: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    if files.is_empty() {
        eprintln!("usage: cargo bench --bench unwrap_overhead -- MESH.obj …");
        std::process::exit(2);
    }
    println!("| mesh | faces | natural conformal s | unwrap s | ratio of medians | median ratio |");
    println!("|---|---:|---:|---:|---:|---:|");
    for file in files {
        let obj = uvflat_core::io::obj::read_obj(Path::new(&file)).expect("readable OBJ");
        let mesh = TriMesh::new(&obj.positions, &obj.triangles).expect("a valid mesh");
        let name = Path::new(&file).file_stem().map_or(file.clone(), |s| s.to_string_lossy().into_owned());
        let options = UnwrapOptions::default();
        match unwrap(&mesh, &options) {
            Ok(r) if r.report.islands == 1 && r.report.repaired_islands == 0 => {}
            Ok(r) => {
                println!(
                    "| {name} | {} | skipped: {} islands, {} repaired |",
                    mesh.triangle_count(),
                    r.report.islands,
                    r.report.repaired_islands
                );
                continue;
            }
            Err(e) => {
                println!("| {name} | {} | skipped: {e} |", mesh.triangle_count());
                continue;
            }
        }
        let (mut alone, mut whole) = (Vec::with_capacity(runs), Vec::with_capacity(runs));
        for _ in 0..runs {
            alone.push(seconds(|| drop(natural_conformal_map(&mesh, None))));
            whole.push(seconds(|| drop(unwrap(&mesh, &options))));
        }
        let ratios: Vec<f64> = alone.iter().zip(&whole).map(|(a, w)| w / a).collect();
        let (a, w) = (median(alone), median(whole));
        println!("| {name} | {} | {a:.4} | {w:.4} | {:.2} | {:.2} |", mesh.triangle_count(), w / a, median(ratios));
    }
}
