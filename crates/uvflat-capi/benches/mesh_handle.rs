//! What a mesh handle saves: an interactive tool that tries three methods on one mesh, through
//! the C ABI, either with three flat-array calls (each validates the arrays and builds the
//! connectivity again) or with one `uvf_mesh_new` and three `uvf_mesh_*` calls. Methods: the
//! natural conformal map, the mean-value fixed-boundary map and the default unwrap. The two ways
//! alternate round by round in one process (both see the same machine load); medians, as a
//! Markdown table.
//!
//!     cargo bench --bench mesh_handle -- tests/data/meshes/disk_face_libigl_loop1.obj.gz
//!     UVFLAT_HANDLE_RUNS=11 cargo bench --bench mesh_handle -- MESH.obj   # default 7 rounds

use std::path::Path;
use std::ptr;
use std::time::Instant;
use uvflat::barycentric::{uvf_fixed_boundary_map, uvf_mesh_fixed_boundary_map};
use uvflat::conformal::{uvf_mesh_natural_conformal_map, uvf_natural_conformal_map};
use uvflat::mesh_handle::{uvf_mesh_desc_default, uvf_mesh_free, uvf_mesh_new, UvfMesh, UvfMeshDesc};
use uvflat::unwrap::{uvf_mesh_unwrap, uvf_unwrap, uvf_unwrap_free, UvfUnwrap};
use uvflat::UvfStatus;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn ok(status: UvfStatus, what: &str) {
    assert_eq!(status, UvfStatus::UVF_OK, "{what}");
}

/// The three methods on flat arrays; seconds.
fn flat(p: &[f64], t: &[u32], uv: &mut [f64]) -> f64 {
    let (nv, nt) = (p.len() / 3, t.len() / 3);
    let start = Instant::now();
    let mut unwrap: *mut UvfUnwrap = ptr::null_mut();
    // SAFETY: the arrays hold nv vertices and nt triangles; uv holds 2 nv doubles.
    unsafe {
        ok(uvf_natural_conformal_map(p.as_ptr(), nv, t.as_ptr(), nt, ptr::null(), uv.as_mut_ptr()), "flat conformal");
        ok(uvf_fixed_boundary_map(p.as_ptr(), nv, t.as_ptr(), nt, ptr::null(), uv.as_mut_ptr()), "flat fixed");
        ok(uvf_unwrap(p.as_ptr(), nv, t.as_ptr(), nt, ptr::null(), &mut unwrap), "flat unwrap");
        uvf_unwrap_free(unwrap);
    }
    start.elapsed().as_secs_f64()
}

/// One handle and the three methods on it; (seconds in all, seconds of `uvf_mesh_new`).
fn handle(p: &[f64], t: &[u32], uv: &mut [f64]) -> (f64, f64) {
    let start = Instant::now();
    let mut desc = UvfMeshDesc { struct_size: 0, ..Default::default() };
    let (mut mesh, mut unwrap): (*mut UvfMesh, *mut UvfUnwrap) = (ptr::null_mut(), ptr::null_mut());
    // SAFETY: as in `flat`; the description points at the arrays, which outlive the calls.
    let built = unsafe {
        uvf_mesh_desc_default(&mut desc);
        desc.positions = p.as_ptr().cast();
        desc.vertex_count = p.len() / 3;
        desc.indices = t.as_ptr().cast();
        desc.face_count = t.len() / 3;
        ok(uvf_mesh_new(&desc, &mut mesh), "uvf_mesh_new");
        let built = start.elapsed().as_secs_f64();
        ok(uvf_mesh_natural_conformal_map(mesh, ptr::null(), uv.as_mut_ptr()), "handle conformal");
        ok(uvf_mesh_fixed_boundary_map(mesh, ptr::null(), uv.as_mut_ptr()), "handle fixed");
        ok(uvf_mesh_unwrap(mesh, ptr::null(), &mut unwrap), "handle unwrap");
        uvf_unwrap_free(unwrap);
        uvf_mesh_free(mesh);
        built
    };
    (start.elapsed().as_secs_f64(), built)
}

fn main() {
    let runs: usize = std::env::var("UVFLAT_HANDLE_RUNS").ok().and_then(|s| s.parse().ok()).unwrap_or(7).max(1);
    let files: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    if files.is_empty() {
        eprintln!("usage: cargo bench --bench mesh_handle -- MESH.obj …");
        std::process::exit(2);
    }
    println!("| mesh | faces | 3 flat calls s | handle + 3 calls s | of which uvf_mesh_new s | saved s | saved |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    for file in files {
        let obj = uvflat_core::io::obj::read_obj(Path::new(&file)).expect("readable OBJ");
        let (p, t) = (obj.positions, obj.triangles);
        let mut uv = vec![0.0; 2 * (p.len() / 3)];
        let (mut flats, mut handles, mut builds) = (Vec::new(), Vec::new(), Vec::new());
        flat(&p, &t, &mut uv); // warm-up: page faults, the worker threads
        for _ in 0..runs {
            flats.push(flat(&p, &t, &mut uv));
            let (h, b) = handle(&p, &t, &mut uv);
            handles.push(h);
            builds.push(b);
        }
        let (f, h, b) = (median(flats), median(handles), median(builds));
        let name = Path::new(&file).file_stem().map_or(file.clone(), |s| s.to_string_lossy().into_owned());
        println!(
            "| {name} | {} | {f:.3} | {h:.3} | {b:.3} | {:.3} | {:.0}% |",
            t.len() / 3,
            f - h,
            100.0 * (f - h) / f
        );
    }
}
