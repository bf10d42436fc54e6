//! C/C++ compilation for tests and benches (which get no build-script environment): the `cc`
//! crate's choice of compiler and flags for this machine, the cargo target directory, and the
//! uvflat libraries cargo built for the running test.

use std::path::PathBuf;
use std::process::Command;

/// The Rust target triple of this machine.
pub fn host_triple() -> String {
    let arch = std::env::consts::ARCH;
    match std::env::consts::OS {
        "macos" => format!("{arch}-apple-darwin"),
        "windows" => format!("{arch}-pc-windows-msvc"),
        os => format!("{arch}-unknown-{os}-gnu"),
    }
}

/// The cargo target directory: the running test or bench lives in `<target>/<profile>/deps/`.
pub fn target_dir() -> PathBuf {
    std::env::current_exe()
        .ok()
        .and_then(|exe| Some(exe.parent()?.parent()?.parent()?.to_path_buf()))
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../target")))
}

/// The directory holding the `libuvflat.so`/`.a` built together with the running test:
/// `<target>/<profile>/deps/` or, where cargo only uplifted them, `<target>/<profile>/`.
pub fn library_dir() -> PathBuf {
    let deps = std::env::current_exe().ok().and_then(|exe| Some(exe.parent()?.to_path_buf()));
    let candidates = deps.iter().flat_map(|d| [d.clone(), d.parent().map(|p| p.to_path_buf()).unwrap_or_default()]);
    candidates
        .into_iter()
        .find(|d| d.join("libuvflat.so").exists() && d.join("libuvflat.a").exists())
        .unwrap_or_else(|| target_dir().join("release"))
}

/// The shared library's SONAME, `libuvflat.so.<major version>` (build.rs).
pub fn soname() -> String {
    format!("libuvflat.so.{}", env!("CARGO_PKG_VERSION_MAJOR"))
}

/// A directory to link test programs against (`-L`, `-rpath`): links `libuvflat.so` and its
/// SONAME `libuvflat.so.<major>` (set by build.rs) to the library cargo built for this test. Cargo
/// leaves only the unversioned name, which the dynamic loader would not find by SONAME.
pub fn link_dir() -> PathBuf {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let built = library_dir().join("libuvflat.so");
        let dir = target_dir().join(format!("link-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("create the link directory");
        for name in ["libuvflat.so".to_string(), soname()] {
            let link = dir.join(name);
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink(&built, &link).expect("symlink libuvflat.so");
        }
        dir
    })
    .clone()
}

/// A compiler command (C or C++) for the language standard `std`, optimised, with `cc`'s
/// default flags for this machine; output and inputs are for the caller to add.
pub fn compiler(cpp: bool, std: &str) -> Command {
    let triple = host_triple();
    let mut build = cc::Build::new();
    build.cpp(cpp).std(std).opt_level(2).debug(false).target(&triple).host(&triple).cargo_metadata(false);
    build.get_compiler().to_command()
}

/// Runs `command`, returning its stdout, or its stderr and stdout on failure.
pub fn run(mut command: Command) -> Result<String, String> {
    let shown = describe(&command);
    let output = command.output().map_err(|e| format!("cannot run {shown}: {e}"))?;
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    if output.status.success() {
        Ok(text(&output.stdout))
    } else {
        Err(format!("{shown} failed ({}):\n{}\n{}", output.status, text(&output.stderr), text(&output.stdout)))
    }
}

/// The command line, without the environment `cc` attaches.
pub fn describe(command: &Command) -> String {
    std::iter::once(command.get_program())
        .chain(command.get_args())
        .map(|a| a.to_string_lossy())
        .collect::<Vec<_>>()
        .join(" ")
}
