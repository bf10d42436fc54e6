//! What C and C++ developers install works as they would use it, with no `LD_LIBRARY_PATH`:
//! - `scripts/install.sh PREFIX` staged with `DESTDIR`, then used from the staged folder (the
//!   pkg-config and CMake files are relocatable), then removed with `--uninstall`;
//! - the C/C++ SDK tarball of `scripts/dist.sh` (folder `UVFLAT_DIST`, which the test command
//!   sets), unpacked into a temporary folder: its library stripped, with its SONAME.
//!
//! On each, a C99 program is built with `pkg-config --cflags --libs uvflat` (shared: it must start
//! through the rpath the .pc file records) and `uvflat-static` (it must not need libuvflat.so),
//! and a CMake project with `find_package(uvflat)` builds a shared and a static program; all run.
//! The static library exports only `uvf_*` symbols (`nm`), and links into one program with a
//! second Rust static library.
//! Needs pkg-config, cmake and binutils (scripts/test.sh installs them); skipped without them, or
//! without `UVFLAT_DIST` for the SDK, except under CI (`CI=true`).

use std::path::{Path, PathBuf};
use std::process::Command;
use uvflat_test_support::compiler;

const ROOT: &str = uvflat_test_support::ROOT;
/// This crate (the C ABI) and its C/C++ test programs.
const CRATE: &str = env!("CARGO_MANIFEST_DIR");

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// False (a skip) when `what` is missing outside CI; a failure under CI.
fn present(found: bool, what: &str, hint: &str) -> bool {
    if !found {
        assert!(!in_ci(), "{what} is missing: {hint}");
        eprintln!("skipped: {what} missing ({hint})");
    }
    found
}

fn tools_present() -> bool {
    ["pkg-config", "cmake", "readelf", "nm", "ld", "objcopy"].iter().all(|tool| {
        let found = Command::new(tool).arg("--version").output().is_ok_and(|o| o.status.success());
        present(
            found,
            tool,
            &format!(
                "apt-get install {}",
                if ["readelf", "nm", "ld", "objcopy"].contains(tool) { "binutils" } else { tool }
            ),
        )
    })
}

fn scratch(name: &str) -> PathBuf {
    let dir = compiler::target_dir().join(format!("install-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// The `NEEDED` and `SONAME` entries of an ELF file's dynamic section.
fn dynamic_entries(file: &Path) -> String {
    compiler::run({
        let mut c = Command::new("readelf");
        c.arg("-d").arg(file);
        c
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

/// Runs a built program as a user would: no `LD_LIBRARY_PATH`.
fn run_hello(exe: &Path) {
    let mut command = Command::new(exe);
    command.env_remove("LD_LIBRARY_PATH");
    let out = compiler::run(command).unwrap_or_else(|e| panic!("{e}"));
    assert!(out.starts_with("uvflat ") && out.trim_end().ends_with(" ok"), "{out}");
}

fn pkg_config(prefix: &Path, package: &str) -> Vec<String> {
    let out = Command::new("pkg-config")
        .args(["--cflags", "--libs", package])
        .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig"))
        .output()
        .expect("pkg-config");
    assert!(out.status.success(), "pkg-config {package}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).split_whitespace().map(str::to_string).collect()
}

/// Builds and runs the test programs against the uvflat installed in `prefix`; `build` is a
/// scratch folder.
fn check_prefix(prefix: &Path, build: &Path) {
    std::fs::create_dir_all(build).expect("build dir");
    for (package, shared) in [("uvflat", true), ("uvflat-static", false)] {
        let exe = build.join(format!("hello_{package}"));
        let mut cc = compiler::compiler(false, "c99");
        cc.arg(Path::new(CRATE).join("tests/install/hello.c")).arg("-o").arg(&exe).args(pkg_config(prefix, package));
        compiler::run(cc).unwrap_or_else(|e| panic!("{e}"));
        run_hello(&exe);
        let needs_library = dynamic_entries(&exe).contains(&format!("[{}]", compiler::soname()));
        assert_eq!(needs_library, shared, "{package}: NEEDED {} = {needs_library}", compiler::soname());
    }

    check_static_archive(prefix, build);

    let cmake_build = build.join("cmake");
    let mut configure = Command::new("cmake");
    configure.arg("-S").arg(Path::new(CRATE).join("tests/install")).arg("-B").arg(&cmake_build);
    configure.arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())).arg("-DCMAKE_BUILD_TYPE=Release");
    compiler::run(configure).unwrap_or_else(|e| panic!("{e}"));
    let mut make = Command::new("cmake");
    make.arg("--build").arg(&cmake_build);
    compiler::run(make).unwrap_or_else(|e| panic!("{e}"));
    run_hello(&cmake_build.join("hello_shared"));
    run_hello(&cmake_build.join("hello_static"));
    assert!(!dynamic_entries(&cmake_build.join("hello_static")).contains("libuvflat"));
}

/// Every file (not folder) under `dir`, relative to it, sorted.
/// The installed `libuvflat.a` exports only `uvf_*` symbols, and a C program links it together
/// with a second Rust static library (its own Rust runtime) and runs.
fn check_static_archive(prefix: &Path, build: &Path) {
    let archive = prefix.join("lib/libuvflat.a");
    let symbols = compiler::run({
        let mut nm = Command::new("nm");
        nm.args(["-g", "--defined-only"]).arg(&archive);
        nm
    })
    .unwrap_or_else(|e| panic!("{e}"));
    let globals: Vec<&str> = symbols.lines().filter_map(|l| l.split_whitespace().nth(2)).collect();
    let foreign: Vec<&&str> = globals.iter().filter(|s| !s.starts_with("uvf_")).take(10).collect();
    assert!(foreign.is_empty(), "libuvflat.a exports non-uvf symbols: {foreign:?}");
    let header = std::fs::read_to_string(Path::new(ROOT).join("include/uvflat.h")).expect("header");
    let declared = header.lines().filter(|l| l.contains(" uvf_") && l.contains('(') && !l.starts_with(' ')).count();
    assert!(globals.len() >= declared && declared > 50, "{} exports for {declared} header functions", globals.len());

    let other = build.join("libother_rust.a");
    let mut rustc = Command::new(std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into()));
    rustc.args(["--crate-type", "staticlib", "--edition", "2021", "-O", "--crate-name", "other_rust", "-o"]);
    rustc.arg(&other).arg(Path::new(CRATE).join("tests/install/other_rust/lib.rs"));
    compiler::run(rustc).unwrap_or_else(|e| panic!("{e}"));
    let exe = build.join("two_rust_libraries");
    let mut cc = compiler::compiler(false, "c99");
    cc.arg(Path::new(CRATE).join("tests/install/two_rust_libraries.c")).arg("-o").arg(&exe);
    cc.args(pkg_config(prefix, "uvflat-static")).arg(&other).args(["-lpthread", "-ldl", "-lm"]);
    compiler::run(cc).unwrap_or_else(|e| panic!("linking libuvflat.a with a second Rust library: {e}"));
    let out = compiler::run(Command::new(&exe)).unwrap_or_else(|e| panic!("{e}"));
    assert!(out.contains("and another Rust library ok"), "{out}");
}

fn files_under(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() && !path.is_symlink() {
                stack.push(path);
            } else {
                found.push(path.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    found.sort();
    found
}

#[test]
fn install_sh_staged_with_destdir_builds_runs_and_uninstalls() {
    if !tools_present() {
        return;
    }
    let scratch = scratch("destdir");
    let stage = scratch.join("stage");
    let prefix = "/opt/uvflat-test";
    let mut install = Command::new(Path::new(ROOT).join("scripts/install.sh"));
    install.arg(prefix).arg("--lib-dir").arg(compiler::library_dir()).env("DESTDIR", &stage);
    compiler::run(install).unwrap_or_else(|e| panic!("{e}"));
    assert!(!Path::new(prefix).exists(), "DESTDIR was ignored: {prefix} was written");
    let staged = stage.join(prefix.trim_start_matches('/'));
    let files = files_under(&staged);
    for expected in [
        "include/uvflat.h",
        "include/uvflat.hpp",
        "lib/libuvflat.so",
        format!("lib/{}", compiler::soname()).as_str(),
        "lib/libuvflat.a",
        "lib/pkgconfig/uvflat.pc",
        "lib/pkgconfig/uvflat-static.pc",
        "lib/cmake/uvflat/uvflatConfig.cmake",
        "share/uvflat/install_manifest.txt",
    ] {
        assert!(files.iter().any(|f| f == expected), "{expected} not installed: {files:?}");
    }
    check_prefix(&staged, &scratch.join("build"));

    let mut uninstall = Command::new(Path::new(ROOT).join("scripts/install.sh"));
    uninstall.arg("--uninstall").arg(prefix).env("DESTDIR", &stage);
    compiler::run(uninstall).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(files_under(&stage), Vec::<String>::new(), "files left after --uninstall");
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn sdk_tarball_unpacked_anywhere_builds_and_runs() {
    if !tools_present() {
        return;
    }
    let Some(dist) = std::env::var_os("UVFLAT_DIST").map(PathBuf::from) else {
        present(false, "UVFLAT_DIST (the folder scripts/dist.sh wrote)", "run scripts/dist.sh first");
        return;
    };
    let tarball = std::fs::read_dir(&dist)
        .unwrap_or_else(|e| panic!("{}: {e}", dist.display()))
        .flatten()
        .map(|e| e.path())
        .find(|p| p.to_string_lossy().ends_with("-linux-x86_64.tar.gz"))
        .unwrap_or_else(|| panic!("no SDK tarball in {}", dist.display()));
    let scratch = scratch("sdk");
    let mut untar = Command::new("tar");
    untar.arg("xzf").arg(&tarball).arg("-C").arg(&scratch);
    compiler::run(untar).unwrap_or_else(|e| panic!("{e}"));
    let name = tarball.file_name().unwrap().to_string_lossy().trim_end_matches(".tar.gz").to_string();
    let sdk = scratch.join(&name);
    let version = env!("CARGO_PKG_VERSION");
    let library = sdk.join(format!("lib/libuvflat.so.{version}"));
    assert!(dynamic_entries(&library).contains(&format!("Library soname: [{}]", compiler::soname())));
    let sections = compiler::run({
        let mut c = Command::new("readelf");
        c.arg("-S").arg(&library);
        c
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(!sections.contains(".debug_info"), "the SDK's library is not stripped");
    for file in ["include/uvflat.h", "include/uvflat.hpp", "bin/uvflat", "LICENSE-MIT", "LICENSE-APACHE", "README.md"] {
        assert!(sdk.join(file).is_file(), "{file} missing from {name}");
    }
    let cli = compiler::run({
        let mut c = Command::new(sdk.join("bin/uvflat"));
        c.arg("--version");
        c
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(cli.contains(version), "{cli}");
    check_prefix(&sdk, &scratch.join("build"));
    let _ = std::fs::remove_dir_all(&scratch);
}
