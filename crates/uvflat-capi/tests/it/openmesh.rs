//! C++ integration through OpenMesh (`crates/uvflat-capi/tests/openmesh/roundtrip.cpp`, using the header-only
//! wrapper `bindings/cpp/uvflat.hpp`): every test mesh (`tests/data/meshes`, decompressed) is read by OpenMesh,
//! unwrapped by uvflat, stored as OpenMesh texcoords, written and re-read; mean-value maps
//! never flip; meshes that are not disks get `UVF_UNSUPPORTED_TOPOLOGY`. The wrapper's handle
//! classes and newer functions (`crates/uvflat-capi/tests/openmesh/wrappers.cpp`): PGP, its quad mesh, chart
//! layout and charts, QuadCover's quad mesh, curvature, the atlas, the intrinsic tools.
//!
//! Needs Debian's libopenmesh-dev: skipped without it, except under CI (`CI=true`), where its
//! absence fails the test.

use std::path::{Path, PathBuf};
use uvflat_test_support::{compiler, meshes};

const ROOT: &str = uvflat_test_support::ROOT;
/// This crate (the C ABI) and its C/C++ test programs.
const CRATE: &str = env!("CARGO_MANIFEST_DIR");
const INSTALL_HINT: &str = "OpenMesh tests need Debian's libopenmesh-dev: apt-get install libopenmesh-dev";

fn openmesh_installed() -> bool {
    Path::new("/usr/include/OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh").exists()
}

/// False (after checking that this is not CI, where OpenMesh is required) when OpenMesh is
/// missing.
fn require_openmesh() -> bool {
    if !openmesh_installed() {
        assert!(std::env::var("CI").map_or(true, |v| v != "true"), "{INSTALL_HINT}");
        eprintln!("skipped: {INSTALL_HINT}");
        return false;
    }
    true
}

/// Compiles `crates/uvflat-capi/tests/openmesh/<source>.cpp` against OpenMesh, the wrapper and the library with
/// warnings as errors; returns the executable.
fn build(source: &str) -> PathBuf {
    let lib = compiler::link_dir();
    let dir = compiler::target_dir().join("openmesh");
    std::fs::create_dir_all(&dir).expect("create target/openmesh");
    let exe = dir.join(format!("{source}-{}", std::process::id()));
    let mut command = compiler::compiler(true, "c++17");
    // OpenMesh 9's own headers trip -Wmaybe-uninitialized at -O2 (Property.hh push_back).
    command.args(["-Wall", "-Wextra", "-Werror", "-Wno-maybe-uninitialized"]);
    for include in ["include", "bindings/cpp"] {
        command.arg("-I").arg(Path::new(ROOT).join(include));
    }
    command.arg("-o").arg(&exe).arg(Path::new(CRATE).join(format!("tests/openmesh/{source}.cpp")));
    command.arg(format!("-L{}", lib.display())).arg(format!("-Wl,-rpath,{}", lib.display()));
    command.args(["-luvflat", "-lOpenMeshCore"]);
    compiler::run(command).unwrap_or_else(|e| panic!("{e}"));
    exe
}

/// Runs `exe` with `args`, removes it, and returns its stdout (panicking on failure).
fn run(exe: &Path, args: &[PathBuf]) -> String {
    let mut run = std::process::Command::new(exe);
    run.args(args);
    let result = compiler::run(run);
    let _ = std::fs::remove_file(exe);
    let stdout = result.unwrap_or_else(|e| panic!("{e}"));
    println!("{stdout}");
    stdout
}

#[test]
fn openmesh_round_trip_of_every_test_mesh() {
    if !require_openmesh() {
        return;
    }
    let exe = build("roundtrip");
    let meshes: Vec<PathBuf> = meshes::names(|_| true).iter().map(|m| meshes::unpacked(m)).collect();
    assert!(meshes.len() >= 40, "expected the test meshes, found {} OBJ files", meshes.len());
    let out_dir = compiler::target_dir().join("openmesh").join("out");
    std::fs::create_dir_all(&out_dir).expect("create output dir");
    let args: Vec<PathBuf> = std::iter::once(out_dir).chain(meshes).collect();
    let stdout = run(&exe, &args);
    assert!(stdout.contains("0 failure(s)"), "{stdout}");
    assert!(stdout.contains("wrapper progress and cancellation: ok"), "{stdout}");
    let unwrapped = stdout.lines().filter(|l| l.contains(" mean-value: flipped 0")).count();
    assert!(unwrapped >= 18, "only {unwrapped} meshes were unwrapped:\n{stdout}");
}

/// The wrapper's handle classes (`Pgp`, `QuadMesh`, `ChartLayout`, `PgpCharts`, `Atlas`) and
/// newer functions on the torus, the genus-2 eight and a small disk: see
/// `crates/uvflat-capi/tests/openmesh/wrappers.cpp` for what each check asserts.
#[test]
fn cpp_wrapper_handles_pgp_atlas_curvature_and_intrinsic_tools() {
    if !require_openmesh() {
        return;
    }
    let exe = build("wrappers");
    let files = ["closed_g1_torus.obj", "closed_g2_eight.obj", "disk_nefertiti_small.obj"].map(meshes::unpacked);
    let stdout = run(&exe, &[files[0].parent().expect("unpacked mesh dir").to_path_buf()]);
    assert!(stdout.contains("0 failure(s)") && !stdout.contains("FAIL"), "{stdout}");
    // Every check ran (each prints what it measured).
    for expected in [
        "closed_g2_eight.obj PGP: ",
        "closed_g1_torus.obj PGP: ",
        "closed_g1_torus.obj QuadCover quad mesh density 1: ",
        "closed_g2_eight.obj atlas: ",
        "disk_nefertiti_small.obj atlas: ",
        "torus curvature: ",
        "intrinsic tools: boundary optimization ",
    ] {
        assert!(stdout.contains(expected), "no line with {expected:?}:\n{stdout}");
    }
}
