//! Gives the shared library a versioned name that programs linked against it record: on Linux
//! the SONAME `libuvflat.so.<major>` (scripts/install.sh and the SDK make the links), on macOS
//! the install name `@rpath/libuvflat.<major>.dylib` (docs/platforms.md; not built or tested on
//! this project's Linux CI). Windows DLLs carry no such name.
fn main() {
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").unwrap_or_else(|_| "0".into());
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libuvflat.so.{major}");
    }
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("macos") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-install_name,@rpath/libuvflat.{major}.dylib");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
