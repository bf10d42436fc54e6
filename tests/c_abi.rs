//! The C interface as C and C++ callers see it: the committed header is what cbindgen
//! generates now, compiles warning-free as C99 and C++17 (with layout static_asserts), and a C
//! program linked against the shared library unwraps a mesh and gets the documented statuses
//! for bad input.
//!
//! `UVFLAT_BLESS=1 cargo test --test c_abi` rewrites `include/uvflat.h`.

#[path = "common/compiler.rs"]
mod compiler;

use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn header_path() -> PathBuf {
    Path::new(ROOT).join("include/uvflat.h")
}

fn generated_header() -> String {
    let config = cbindgen::Config::from_file(Path::new(ROOT).join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new().with_crate(ROOT).with_config(config).generate().expect("cbindgen");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("utf-8 header")
}

#[test]
fn committed_header_matches_cbindgen_output() {
    let fresh = generated_header();
    if std::env::var_os("UVFLAT_BLESS").is_some() {
        std::fs::write(header_path(), &fresh).expect("write include/uvflat.h");
        return;
    }
    let committed = std::fs::read_to_string(header_path()).unwrap_or_default();
    assert!(
        committed == fresh,
        "include/uvflat.h is stale: run `UVFLAT_BLESS=1 cargo test --test c_abi` and commit it"
    );
}

fn scratch_dir() -> PathBuf {
    let dir = compiler::target_dir().join("c_abi");
    std::fs::create_dir_all(&dir).expect("create target/c_abi");
    dir
}

#[test]
fn header_compiles_as_c99_and_cpp17_without_warnings() {
    let strict = ["-Wall", "-Wextra", "-pedantic", "-Werror", "-c"];
    for (cpp, std, source) in [(false, "c99", "header_check.c"), (true, "c++17", "header_check.cpp")] {
        let mut command = compiler::compiler(cpp, std);
        command.args(strict).arg("-I").arg(Path::new(ROOT).join("include"));
        command
            .arg("-o")
            .arg(scratch_dir().join(format!("{source}.o")))
            .arg(Path::new(ROOT).join("tests/c").join(source));
        compiler::run(command).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// Builds `tests/c/smoke.c` (with `extra` compiler flags) against the freshly built
/// `libuvflat.so`, runs it, and checks it reports success.
fn build_and_run_c_suite(name: &str, extra: &[&str]) {
    let lib = compiler::link_dir();
    assert!(lib.join("libuvflat.so").exists(), "no libuvflat.so in {}", lib.display());
    let exe = scratch_dir().join(format!("{name}-{}", std::process::id()));
    let mut command = compiler::compiler(false, "c99");
    command
        .args(["-Wall", "-Wextra", "-pedantic", "-Werror"])
        .args(extra)
        .arg("-I")
        .arg(Path::new(ROOT).join("include"));
    command.arg("-o").arg(&exe).arg(Path::new(ROOT).join("tests/c/smoke.c"));
    command.arg(format!("-L{}", lib.display())).arg(format!("-Wl,-rpath,{}", lib.display()));
    command.args(["-luvflat", "-lm"]);
    compiler::run(command).unwrap_or_else(|e| panic!("{e}"));
    let output = compiler::run(std::process::Command::new(&exe));
    let _ = std::fs::remove_file(&exe);
    let stdout = output.unwrap_or_else(|e| panic!("{e}"));
    assert!(stdout.contains("all C checks passed"), "{stdout}");
}

#[test]
fn c_program_unwraps_and_gets_documented_errors() {
    build_and_run_c_suite("smoke", &[]);
}

/// The C side under AddressSanitizer and UndefinedBehaviorSanitizer: catches out-of-bounds
/// writes by the library into the caller's arrays and misuse of the header's types.
#[test]
fn c_program_is_clean_under_address_and_undefined_sanitizers() {
    build_and_run_c_suite(
        "smoke-asan",
        &["-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer"],
    );
}
