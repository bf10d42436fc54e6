//! Every entry point is reentrant: 8 threads calling the C ABI at once on different meshes get
//! bit-for-bit the results of single-threaded calls, each thread sees its own error message, and
//! 8 threads sharing one mesh handle get the flat calls' results.

use std::ffi::CStr;
use uvflat::barycentric::uvf_fixed_boundary_map;
use uvflat::conformal::uvf_natural_conformal_map;
use uvflat::errors::uvf_last_error_message;
use uvflat::metrics::{uvf_metrics, UvfMetrics};
use uvflat::UvfStatus;
use uvflat_test_support::meshes;

const MESHES: [&str; 4] = ["disk_cat_head", "disk_nefertiti_small", "disk_three_peaks", "disk_mushroom"];

fn load(name: &str) -> (Vec<f64>, Vec<u32>) {
    let obj = meshes::read(&format!("{name}.obj"));
    (obj.positions, obj.triangles)
}

/// Natural conformal and mean-value UVs plus the metrics of the former, as raw bits.
fn run_all(positions: &[f64], triangles: &[u32]) -> Vec<u64> {
    let (nv, nt) = (positions.len() / 3, triangles.len() / 3);
    let mut bits = Vec::new();
    unsafe {
        let mut uv = vec![0.0; 2 * nv];
        let s = uvf_natural_conformal_map(
            positions.as_ptr(),
            nv,
            triangles.as_ptr(),
            nt,
            std::ptr::null(),
            uv.as_mut_ptr(),
        );
        assert_eq!(s, UvfStatus::UVF_OK);
        let mut m = std::mem::MaybeUninit::<UvfMetrics>::zeroed();
        // SAFETY: a writable UvfMetrics; the library reads its size and writes the rest.
        (*m.as_mut_ptr()).struct_size = std::mem::size_of::<UvfMetrics>();
        let s = uvf_metrics(
            positions.as_ptr(),
            nv,
            triangles.as_ptr(),
            nt,
            uv.as_ptr(),
            nv,
            std::ptr::null(),
            m.as_mut_ptr(),
        );
        assert_eq!(s, UvfStatus::UVF_OK);
        let m = m.assume_init();
        bits.extend(uv.iter().map(|x| x.to_bits()));
        bits.extend([m.stretch_l2, m.conformal_mean, m.angle_mean, m.area_mean].map(f64::to_bits));
        let s =
            uvf_fixed_boundary_map(positions.as_ptr(), nv, triangles.as_ptr(), nt, std::ptr::null(), uv.as_mut_ptr());
        assert_eq!(s, UvfStatus::UVF_OK);
        bits.extend(uv.iter().map(|x| x.to_bits()));
    }
    bits
}

#[test]
fn eight_threads_get_single_threaded_results_bit_for_bit() {
    let meshes: Vec<_> = MESHES.iter().map(|m| load(m)).collect();
    let expected: Vec<Vec<u64>> = meshes.iter().map(|(p, t)| run_all(p, t)).collect();
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..8)
            .map(|i| {
                let (meshes, expected) = (&meshes, &expected);
                scope.spawn(move || {
                    for round in 0..3 {
                        let k = (i + round) % meshes.len();
                        let (p, t) = &meshes[k];
                        assert!(run_all(p, t) == expected[k], "thread {i}: {} differs", MESHES[k]);
                    }
                })
            })
            .collect();
        for h in handles {
            h.join().expect("worker thread panicked");
        }
    });
}

#[test]
fn error_messages_are_per_thread() {
    let (positions, mut triangles) = load("disk_cat_head");
    triangles[7] = 1_000_000 + 7;
    std::thread::scope(|scope| {
        for i in 0..8u32 {
            let (positions, mut triangles) = (positions.clone(), triangles.clone());
            scope.spawn(move || unsafe {
                triangles[7] = 2_000_000 + i;
                let mut uv = vec![0.0; positions.len() / 3 * 2];
                for _ in 0..20 {
                    let s = uvf_natural_conformal_map(
                        positions.as_ptr(),
                        positions.len() / 3,
                        triangles.as_ptr(),
                        triangles.len() / 3,
                        std::ptr::null(),
                        uv.as_mut_ptr(),
                    );
                    assert_eq!(s, UvfStatus::UVF_INVALID_MESH);
                    let message = CStr::from_ptr(uvf_last_error_message()).to_string_lossy().into_owned();
                    assert!(message.contains(&format!("{}", 2_000_000 + i)), "thread {i} saw: {message}");
                }
            });
        }
    });
}

/// A raw handle pointer that threads may share: the handle is immutable (docs/c-api.md).
#[derive(Clone, Copy)]
struct Shared(*const uvflat::mesh_handle::UvfMesh);
// SAFETY: `UvfMesh` is never mutated after `uvf_mesh_new`; the test frees it after every thread.
unsafe impl Send for Shared {}
unsafe impl Sync for Shared {}

#[test]
fn eight_threads_share_one_mesh_handle_and_get_the_flat_calls_results() {
    use uvflat::barycentric::uvf_mesh_fixed_boundary_map;
    use uvflat::conformal::uvf_mesh_natural_conformal_map;
    use uvflat::mesh_handle::{uvf_mesh_desc_default, uvf_mesh_free, uvf_mesh_new, UvfMesh, UvfMeshDesc};
    let (positions, triangles) = load("disk_mushroom");
    let nv = positions.len() / 3;
    // run_all: the conformal UVs, 4 metrics, the mean-value UVs.
    let all = run_all(&positions, &triangles);
    let expected: Vec<u64> = all[..2 * nv].iter().chain(&all[2 * nv + 4..]).copied().collect();
    let mut desc = UvfMeshDesc { struct_size: 0, ..Default::default() };
    let mut mesh: *mut UvfMesh = std::ptr::null_mut();
    // SAFETY: the description points at live arrays of the stated sizes.
    unsafe {
        uvf_mesh_desc_default(&mut desc);
        desc.positions = positions.as_ptr().cast();
        desc.vertex_count = nv;
        desc.indices = triangles.as_ptr().cast();
        desc.face_count = triangles.len() / 3;
        assert_eq!(uvf_mesh_new(&desc, &mut mesh), UvfStatus::UVF_OK);
    }
    let shared = Shared(mesh);
    let results: Vec<Vec<u64>> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..8)
            .map(|_| {
                scope.spawn(move || {
                    let handle = shared;
                    let (mut conformal, mut fixed) = (vec![0.0; 2 * nv], vec![0.0; 2 * nv]);
                    // SAFETY: a live handle; the outputs hold 2 nv doubles.
                    unsafe {
                        assert_eq!(
                            uvf_mesh_natural_conformal_map(handle.0, std::ptr::null(), conformal.as_mut_ptr()),
                            UvfStatus::UVF_OK
                        );
                        assert_eq!(
                            uvf_mesh_fixed_boundary_map(handle.0, std::ptr::null(), fixed.as_mut_ptr()),
                            UvfStatus::UVF_OK
                        );
                    }
                    conformal.iter().chain(&fixed).map(|x| x.to_bits()).collect()
                })
            })
            .collect();
        workers.into_iter().map(|w| w.join().expect("worker")).collect()
    });
    // SAFETY: every thread has finished with the handle.
    unsafe { uvf_mesh_free(mesh) };
    for bits in results {
        assert_eq!(bits, expected, "a thread on the shared handle got other UVs than the flat calls");
    }
}
