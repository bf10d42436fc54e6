//! `scripts/install.sh PREFIX` produces a prefix that C builds can use: a program compiled
//! with `pkg-config --cflags --libs uvflat`, and one configured by CMake with
//! `find_package(uvflat)` (shared and static imported targets), build and run.
//! Needs pkg-config and cmake (installed by scripts/test.sh); skipped without them except
//! under CI (`CI=true`).

#[path = "common/compiler.rs"]
mod compiler;

use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn tool_present(tool: &str) -> bool {
    let found = Command::new(tool).arg("--version").output().is_ok_and(|o| o.status.success());
    if !found {
        assert!(std::env::var("CI").map_or(true, |v| v != "true"), "{tool} is missing: apt-get install {tool}");
        eprintln!("skipped: {tool} missing (apt-get install {tool})");
    }
    found
}

fn install_prefix() -> PathBuf {
    let prefix = compiler::target_dir().join(format!("install-test-{}", std::process::id()));
    let mut install = Command::new(Path::new(ROOT).join("scripts/install.sh"));
    install.arg(&prefix).arg("--lib-dir").arg(compiler::library_dir());
    compiler::run(install).unwrap_or_else(|e| panic!("{e}"));
    prefix
}

fn run_hello(exe: &Path) {
    let out = compiler::run(Command::new(exe)).unwrap_or_else(|e| panic!("{e}"));
    assert!(out.starts_with("uvflat ") && out.trim_end().ends_with(" ok"), "{out}");
}

#[test]
fn installed_prefix_builds_with_pkg_config_and_cmake() {
    if !tool_present("pkg-config") || !tool_present("cmake") {
        return;
    }
    let prefix = install_prefix();
    let lib = prefix.join("lib");

    let flags = Command::new("pkg-config")
        .args(["--cflags", "--libs", "uvflat"])
        .env("PKG_CONFIG_PATH", lib.join("pkgconfig"))
        .output()
        .expect("pkg-config");
    assert!(flags.status.success(), "pkg-config: {}", String::from_utf8_lossy(&flags.stderr));
    let flags = String::from_utf8_lossy(&flags.stdout).into_owned();
    let exe = prefix.join("hello_pkg_config");
    let mut cc = compiler::compiler(false, "c99");
    cc.arg(Path::new(ROOT).join("tests/install/hello.c")).arg("-o").arg(&exe);
    cc.args(flags.split_whitespace()).arg(format!("-Wl,-rpath,{}", lib.display()));
    compiler::run(cc).unwrap_or_else(|e| panic!("{e}"));
    run_hello(&exe);

    let build = prefix.join("cmake-build");
    let mut configure = Command::new("cmake");
    configure.arg("-S").arg(Path::new(ROOT).join("tests/install")).arg("-B").arg(&build);
    configure.arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())).arg("-DCMAKE_BUILD_TYPE=Release");
    compiler::run(configure).unwrap_or_else(|e| panic!("{e}"));
    let mut make = Command::new("cmake");
    make.arg("--build").arg(&build);
    compiler::run(make).unwrap_or_else(|e| panic!("{e}"));
    run_hello(&build.join("hello_shared"));
    run_hello(&build.join("hello_static"));

    let _ = std::fs::remove_dir_all(&prefix);
}
