//! C++ integration through OpenMesh (`tests/openmesh/roundtrip.cpp`, using the header-only
//! wrapper `bindings/cpp/uvflat.hpp`): every mesh of `../shared/meshes` is read by OpenMesh,
//! unwrapped by uvflat, stored as OpenMesh texcoords, written and re-read; mean-value maps
//! never flip; meshes that are not disks get `UVF_UNSUPPORTED_TOPOLOGY`.
//!
//! Needs Debian's libopenmesh-dev: skipped without it, except under CI (`CI=true`), where its
//! absence fails the test.

#[path = "common/compiler.rs"]
mod compiler;

use std::path::Path;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");
const INSTALL_HINT: &str = "OpenMesh tests need Debian's libopenmesh-dev: apt-get install libopenmesh-dev";

fn openmesh_installed() -> bool {
    Path::new("/usr/include/OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh").exists()
}

#[test]
fn openmesh_round_trip_of_every_shared_mesh() {
    if !openmesh_installed() {
        assert!(std::env::var("CI").map_or(true, |v| v != "true"), "{INSTALL_HINT}");
        eprintln!("skipped: {INSTALL_HINT}");
        return;
    }
    let lib = compiler::link_dir();
    let dir = compiler::target_dir().join("openmesh");
    std::fs::create_dir_all(&dir).expect("create target/openmesh");
    let exe = dir.join(format!("roundtrip-{}", std::process::id()));
    let mut command = compiler::compiler(true, "c++17");
    // OpenMesh 9's own headers trip -Wmaybe-uninitialized at -O2 (Property.hh push_back).
    command.args(["-Wall", "-Wextra", "-Werror", "-Wno-maybe-uninitialized"]);
    for include in ["include", "bindings/cpp"] {
        command.arg("-I").arg(Path::new(ROOT).join(include));
    }
    command.arg("-o").arg(&exe).arg(Path::new(ROOT).join("tests/openmesh/roundtrip.cpp"));
    command.arg(format!("-L{}", lib.display())).arg(format!("-Wl,-rpath,{}", lib.display()));
    command.args(["-luvflat", "-lOpenMeshCore"]);
    compiler::run(command).unwrap_or_else(|e| panic!("{e}"));

    let mesh_dir = Path::new(ROOT).join("../shared/meshes");
    let mut meshes: Vec<_> = std::fs::read_dir(&mesh_dir)
        .expect("../shared/meshes")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    meshes.sort();
    assert!(meshes.len() >= 40, "expected the shared collection, found {} OBJ files", meshes.len());
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).expect("create output dir");
    let mut run = std::process::Command::new(&exe);
    run.arg(&out_dir).args(&meshes);
    let result = compiler::run(run);
    let _ = std::fs::remove_file(&exe);
    let stdout = result.unwrap_or_else(|e| panic!("{e}"));
    println!("{stdout}");
    assert!(stdout.contains("0 failure(s)"), "{stdout}");
    assert!(stdout.contains("wrapper progress and cancellation: ok"), "{stdout}");
    let unwrapped = stdout.lines().filter(|l| l.contains(" mean-value: flipped 0")).count();
    assert!(unwrapped >= 18, "only {unwrapped} meshes were unwrapped:\n{stdout}");
}
