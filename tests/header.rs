//! The committed C header is exactly what cbindgen generates from `src/ffi`.
//! `DVH_UPDATE_HEADER=1 cargo test --test header` rewrites it.

use std::path::Path;

#[test]
fn committed_header_is_what_cbindgen_generates() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config =
        cbindgen::Config::from_file(root.join("cbindgen.toml")).expect("cbindgen.toml parses");
    let bindings = cbindgen::Builder::new()
        .with_crate(root)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let path = root.join("include/dvh.h");
    if std::env::var_os("DVH_UPDATE_HEADER").is_some() {
        std::fs::write(&path, &generated).expect("include/dvh.h is writable");
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/dvh.h differs from what cbindgen generates; run `DVH_UPDATE_HEADER=1 cargo test --test header` and commit it"
    );
}
