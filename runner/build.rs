//! Compiles the FCL driver (the cross-check harness's, `cross_check/src/fcl_side.hpp`) behind a
//! small C interface when FCL is installed (`pkg-config fcl`, Debian's libfcl-dev), and tells the
//! runner so with `cfg(fcl)`. Without FCL the runner builds and runs without that peer.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(fcl)");
    println!("cargo::rerun-if-changed=fcl_shim.cpp");
    println!("cargo::rerun-if-changed=../cross_check/src/fcl_side.hpp");
    let fcl = match pkg_config::Config::new().cargo_metadata(false).probe("fcl") {
        Ok(lib) => lib,
        Err(e) => {
            println!(
                "cargo::warning=FCL not found ({e}); the runner will measure dvh and parry only"
            );
            return;
        }
    };
    let mut build = cc::Build::new();
    build
        .cpp(true)
        .std("c++17")
        .file("fcl_shim.cpp")
        .include("../cross_check/src")
        .opt_level(2)
        .warnings(false);
    for path in &fcl.include_paths {
        build.include(path);
    }
    // Eigen, which FCL's headers include, is found through pkg-config as well.
    if let Ok(eigen) = pkg_config::Config::new()
        .cargo_metadata(false)
        .probe("eigen3")
    {
        for path in &eigen.include_paths {
            build.include(path);
        }
    }
    build.compile("dvh_runner_fcl");
    for path in &fcl.link_paths {
        println!("cargo::rustc-link-search=native={}", path.display());
    }
    for lib in &fcl.libs {
        println!("cargo::rustc-link-lib={lib}");
    }
    println!("cargo::rustc-cfg=fcl");
}
