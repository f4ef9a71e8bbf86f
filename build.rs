//! Gives the shared library a versioned soname on Linux, as C users expect: `libdvh.so.0.MINOR`
//! while the major version is 0 (every minor release may change the ABI), `libdvh.so.MAJOR`
//! afterwards. `scripts/install.sh` installs the matching file and links.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").unwrap_or_default();
    let minor = std::env::var("CARGO_PKG_VERSION_MINOR").unwrap_or_default();
    let soversion = if major == "0" {
        format!("0.{minor}")
    } else {
        major
    };
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libdvh.so.{soversion}");
    }
}
