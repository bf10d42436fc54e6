//! Gives the shared library a SONAME (`libuvflat.so.<major or 0.minor>`), so programs linked
//! against an installed copy (scripts/install.sh) record a versioned dependency.
fn main() {
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").unwrap_or_else(|_| "0".into());
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libuvflat.so.{major}");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
