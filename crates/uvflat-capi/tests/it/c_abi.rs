//! The C interface as C and C++ callers see it: the committed header is what cbindgen
//! generates now, compiles warning-free as C99 and C++17 (with layout static_asserts), and a C
//! program linked against the shared library unwraps a mesh and gets the documented statuses
//! for bad input.
//!
//! `UVFLAT_BLESS=1 cargo test -p uvflat-capi --test it c_abi::committed_header` rewrites `include/uvflat.h`.

use std::path::{Path, PathBuf};
use uvflat_test_support::compiler;

const ROOT: &str = uvflat_test_support::ROOT;
/// This crate (the C ABI): its sources, cbindgen settings and C test programs.
const CRATE: &str = env!("CARGO_MANIFEST_DIR");

fn header_path() -> PathBuf {
    Path::new(ROOT).join("include/uvflat.h")
}

/// The header as cbindgen writes it from the C ABI module alone (`crates/uvflat-capi/src`: nothing of the rest
/// of the crate can reach it), with the version macros of this crate's version.
fn generated_header() -> String {
    let mut config = cbindgen::Config::from_file(Path::new(CRATE).join("cbindgen.toml")).expect("cbindgen.toml");
    config.after_includes = Some(version_macros());
    let bindings = cbindgen::Builder::new()
        .with_src(Path::new(CRATE).join("src/lib.rs"))
        .with_config(config)
        .generate()
        .expect("cbindgen");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("utf-8 header")
}

/// `UVF_VERSION_*` macros of the crate version (`major * 10000 + minor * 100 + patch` for the
/// number, as `uvf_version_number` returns).
fn version_macros() -> String {
    let part = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<u32>().ok()).expect(name);
    let (major, minor, patch) =
        (part("CARGO_PKG_VERSION_MAJOR"), part("CARGO_PKG_VERSION_MINOR"), part("CARGO_PKG_VERSION_PATCH"));
    format!(
        "\n/** Version of the library this header belongs to (compare with uvf_version_number()). */\n\
         #define UVF_VERSION_MAJOR {major}\n#define UVF_VERSION_MINOR {minor}\n#define UVF_VERSION_PATCH {patch}\n\
         #define UVF_VERSION_STRING \"{major}.{minor}.{patch}\"\n\
         #define UVF_VERSION_NUMBER ({major} * 10000 + {minor} * 100 + {patch})\n\
         /** ABI version: equal to UVF_VERSION_MAJOR (compare with uvf_abi_version()). */\n\
         #define UVF_ABI_VERSION {major}\n"
    )
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
        "include/uvflat.h is stale: run `UVFLAT_BLESS=1 cargo test -p uvflat-capi --test it c_abi::committed_header` and commit it"
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
        command.arg("-I").arg(Path::new(ROOT).join("bindings/cpp"));
        command
            .arg("-o")
            .arg(scratch_dir().join(format!("{source}.o")))
            .arg(Path::new(CRATE).join("tests/c").join(source));
        compiler::run(command).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// The header without comments.
fn header_code() -> String {
    let text = std::fs::read_to_string(header_path()).expect("read include/uvflat.h");
    let mut out = String::new();
    let mut rest = text.as_str();
    while let Some(start) = rest.find("/*") {
        out.push_str(&rest[..start]);
        let end = rest[start..].find("*/").map(|e| start + e + 2).expect("unterminated comment");
        rest = &rest[end..];
    }
    out.push_str(rest);
    out.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

/// Every name the header declares in the global scope of C: macros, functions, struct and enum
/// tags, typedef names and enumerators (struct fields and parameter names are scoped and not
/// listed). A small C tokenizer over the comment-free header.
fn global_names(code: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut declarations = String::new();
    let mut cpp_only = false;
    for line in code.lines() {
        let line = line.trim();
        // What a C compiler sees: the `extern "C" {` of C++ is left out.
        if line.starts_with("#ifdef __cplusplus") {
            cpp_only = true;
        } else if cpp_only {
            cpp_only = !line.starts_with("#endif");
        } else if let Some(directive) = line.strip_prefix('#') {
            let mut words = directive.split_whitespace();
            if words.next() == Some("define") {
                names.extend(words.next().map(|w| w.split('(').next().unwrap_or(w).to_string()));
            }
        } else {
            declarations.push_str(line);
            declarations.push('\n');
        }
    }
    let mut tokens = Vec::new();
    let mut chars = declarations.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_alphanumeric() || c == '_' {
            let mut word = c.to_string();
            while let Some(&d) = chars.peek().filter(|d| d.is_alphanumeric() || **d == '_') {
                word.push(d);
                chars.next();
            }
            tokens.push(word);
        } else if c == '"' {
            for d in chars.by_ref() {
                if d == '"' {
                    break;
                }
            }
        } else if !c.is_whitespace() {
            tokens.push(c.to_string());
        }
    }
    let is_word = |t: &str| t.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_');
    let (mut braces, mut parens) = (0usize, 0usize);
    let mut enum_depth: Vec<usize> = Vec::new();
    let mut in_typedef = false;
    for (i, t) in tokens.iter().enumerate() {
        let next = tokens.get(i + 1).map(String::as_str).unwrap_or("");
        let previous = if i > 0 { tokens[i - 1].as_str() } else { "" };
        match t.as_str() {
            "{" => {
                braces += 1;
                if tokens[..i].iter().rev().take(2).any(|w| w == "enum") {
                    enum_depth.push(braces);
                }
            }
            "}" => {
                if enum_depth.last() == Some(&braces) {
                    enum_depth.pop();
                }
                braces -= 1;
            }
            "(" => parens += 1,
            ")" => parens -= 1,
            "typedef" if braces == 0 => in_typedef = true,
            ";" if braces == 0 => in_typedef = false,
            // The name of a function pointer type: `typedef int (*Name)(...)`.
            _ if is_word(t) && braces == 0 && in_typedef && parens == 1 && previous == "*" && next == ")" => {
                names.push(t.clone())
            }
            _ if is_word(t) && parens == 0 => {
                let enumerator = enum_depth.last() == Some(&braces) && (previous == "{" || previous == ",");
                let tag = previous == "struct" || previous == "enum";
                const TYPE_WORDS: [&str; 6] = ["void", "int", "char", "double", "float", "long"];
                let function = braces == 0 && next == "(" && !TYPE_WORDS.contains(&t.as_str());
                let typedef_name = braces == 0 && in_typedef && (next == ";" || next == ")");
                if enumerator || tag || function || typedef_name {
                    names.push(t.clone());
                }
            }
            _ => {}
        }
    }
    names.sort();
    names.dedup();
    names
}

#[test]
fn header_declares_only_uvf_names() {
    let names = global_names(&header_code());
    for expected in ["UVF_OK", "UvfStatus", "UvfMetrics", "uvf_version", "UvfProgressFn", "UVF_VERSION_MAJOR"] {
        assert!(names.iter().any(|n| n == expected), "the name scan missed {expected}: {names:?}");
    }
    let foreign: Vec<&String> = names
        .iter()
        .filter(|n| !(n.starts_with("UVF_") || n.starts_with("uvf_") || n.starts_with("Uvf") || *n == "UVFLAT_H"))
        .collect();
    assert!(foreign.is_empty(), "include/uvflat.h declares names without the uvflat prefix: {foreign:?}");
}

/// Macro names users' code commonly defines, and every name an earlier header leaked.
const USER_MACROS: [&str; 36] = [
    "MIN_ANGLE",
    "SEPARATOR",
    "MAX_VERTICES",
    "PERIODIC_EPSILON",
    "PERIODIC_ITERATIONS",
    "NONE",
    "MIN",
    "MAX",
    "ERROR",
    "OK",
    "TRUE",
    "FALSE",
    "DEBUG",
    "EPSILON",
    "VERSION",
    "MAX_SIDE_FRACTION",
    "DELAUNAY_MARGIN",
    "AREA_FLOOR_FRACTION",
    "MAX_STEP_FRACTION",
    "EDGES_PER_PERIOD",
    "DEFAULT_DISLOCATION_PERIODS",
    "DISLOCATION_ROUNDS",
    "ABSORPTION_CANDIDATES",
    "ANTIPODAL_TOLERANCE",
    "RELAX_REGULARIZATION",
    "ANGLE_SUM_TOLERANCE",
    "SMOOTHING_EPSILON",
    "SMOOTHING_ITERATIONS",
    "MIN_FITTING_WEIGHT",
    "MAX_ANISOTROPY_WEIGHT",
    "DEFAULT_EDGES_PER_CELL",
    "DEFAULT_PAIR_CELLS",
    "SCREENING_CELLS",
    "DEFAULT_ALIGNMENT",
    "DEGENERACY_TOLERANCE",
    "CUT_MAX_STRETCH",
];

/// A C/C++ source that defines [`USER_MACROS`] before including the header, and checks that every
/// integer `UVF_` macro is an integer constant expression of type `int` that fits a `uint32_t`
/// (the type of the options fields they are meant for).
fn macro_check_source(cpp: bool) -> String {
    let mut source: String = USER_MACROS.iter().map(|m| format!("#define {m} user_code_{m}\n")).collect();
    source.push_str("#include \"uvflat.h\"\n");
    let assert = if cpp { "static_assert" } else { "_Static_assert" };
    for line in header_code().lines() {
        let mut words = line.trim().strip_prefix("#define").unwrap_or("").split_whitespace();
        let (Some(name), Some(value)) = (words.next(), words.next()) else { continue };
        if name.starts_with("UVF_") && value.chars().all(|c| c.is_ascii_digit()) {
            source.push_str(&format!(
                "{assert}((UVF_SAME_TYPE_INT({name})) && ({name}) >= 0 && ({name}) <= 2147483647, \"{name}\");\n"
            ));
        }
    }
    let same_type = if cpp {
        "#include <type_traits>\n#define UVF_SAME_TYPE_INT(x) std::is_same<decltype(x), int>::value\n"
    } else {
        "#define UVF_SAME_TYPE_INT(x) _Generic((x), int: 1, default: 0)\n"
    };
    source.insert_str(0, same_type);
    source.push_str("int uvf_macro_check(void);\nint uvf_macro_check(void) { return UVF_VERSION_NUMBER > 0; }\n");
    source
}

#[test]
fn header_compiles_next_to_users_macros_as_c99_c11_and_cpp17() {
    let strict = ["-Wall", "-Wextra", "-pedantic", "-Werror", "-c"];
    for (cpp, std) in [(false, "c99"), (false, "c11"), (true, "c++17")] {
        // C99 has no _Static_assert or _Generic: it only includes the header after the macros.
        let source = if std == "c99" {
            let mut s: String = USER_MACROS.iter().map(|m| format!("#define {m} user_code_{m}\n")).collect();
            s.push_str("#include \"uvflat.h\"\nint uvf_macro_check(void);\nint uvf_macro_check(void) { return UVF_ABI_VERSION; }\n");
            s
        } else {
            macro_check_source(cpp)
        };
        let path = scratch_dir().join(format!("macro_check_{std}.{}", if cpp { "cpp" } else { "c" }));
        std::fs::write(&path, source).expect("write macro check");
        let mut command = compiler::compiler(cpp, std);
        command.args(strict).arg("-I").arg(Path::new(ROOT).join("include"));
        command.arg("-I").arg(Path::new(ROOT).join("bindings/cpp"));
        command.arg("-o").arg(path.with_extension("o")).arg(&path);
        compiler::run(command).unwrap_or_else(|e| panic!("{std}: {e}"));
    }
}

#[test]
fn header_version_macros_match_the_library() {
    let code = header_code();
    let macro_value = |name: &str| {
        code.lines()
            .find_map(|l| l.trim().strip_prefix(&format!("#define {name} ")).map(|v| v.trim().to_string()))
            .unwrap_or_else(|| panic!("no {name} in the header"))
    };
    // SAFETY: uvf_version returns a static NUL-terminated string.
    let version = unsafe { std::ffi::CStr::from_ptr(uvflat::errors::uvf_version()) }.to_str().expect("utf-8");
    assert_eq!(format!("\"{version}\""), macro_value("UVF_VERSION_STRING"));
    let number: u32 = ["UVF_VERSION_MAJOR", "UVF_VERSION_MINOR", "UVF_VERSION_PATCH"]
        .iter()
        .zip([10000, 100, 1])
        .map(|(m, scale)| macro_value(m).parse::<u32>().expect(m) * scale)
        .sum();
    assert_eq!(uvflat::errors::uvf_version_number(), number);
    assert_eq!(macro_value("UVF_ABI_VERSION"), macro_value("UVF_VERSION_MAJOR"));
    assert_eq!(uvflat::errors::uvf_abi_version().to_string(), macro_value("UVF_ABI_VERSION"));
}

/// Builds `crates/uvflat-capi/tests/c/smoke.c` (with `extra` compiler flags) against the freshly built
/// `libuvflat.so`, runs it, and checks it reports success.
fn build_and_run_c_suite(name: &str, extra: &[&str]) {
    build_and_run_c_program("smoke.c", name, extra, "all C checks passed");
}

/// Builds `crates/uvflat-capi/tests/c/<source>` (with `extra` compiler flags) against the freshly built
/// `libuvflat.so`, runs it, and checks its output holds `success`.
fn build_and_run_c_program(source: &str, name: &str, extra: &[&str], success: &str) {
    let lib = compiler::link_dir();
    assert!(lib.join("libuvflat.so").exists(), "no libuvflat.so in {}", lib.display());
    let exe = scratch_dir().join(format!("{name}-{}", std::process::id()));
    let mut command = compiler::compiler(false, "c99");
    command
        .args(["-Wall", "-Wextra", "-pedantic", "-Werror"])
        .args(extra)
        .arg("-I")
        .arg(Path::new(ROOT).join("include"));
    command.arg("-o").arg(&exe).arg(Path::new(CRATE).join("tests/c").join(source));
    command.arg(format!("-L{}", lib.display())).arg(format!("-Wl,-rpath,{}", lib.display()));
    command.args(["-luvflat", "-lm"]);
    compiler::run(command).unwrap_or_else(|e| panic!("{e}"));
    let output = compiler::run(std::process::Command::new(&exe));
    let _ = std::fs::remove_file(&exe);
    let stdout = output.unwrap_or_else(|e| panic!("{e}"));
    assert!(stdout.contains(success), "{stdout}");
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

#[test]
fn a_blender_like_mesh_through_a_handle_gets_the_flat_calls_uvs() {
    build_and_run_c_program("mesh_handle.c", "mesh_handle", &[], "all mesh handle checks passed");
    build_and_run_c_program(
        "mesh_handle.c",
        "mesh_handle-asan",
        &["-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-g"],
        "all mesh handle checks passed",
    );
}
