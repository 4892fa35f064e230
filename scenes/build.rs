//! Builds the FCL peer shim (peer/fcl_shim.cpp) when the `peers` feature is on and FCL's and
//! Eigen's headers are installed; sets `cfg(tridist_fcl)` then. Without them the project builds
//! and tests as before and the reports say FCL was not measured (how to get it: Debian/Ubuntu
//! `apt-get install libfcl-dev libeigen3-dev`; elsewhere set `FCL_INCLUDE` and `EIGEN_INCLUDE`).

use std::path::{Path, PathBuf};

fn find(env: &str, candidates: &[&str], probe: &str) -> Option<PathBuf> {
    println!("cargo:rerun-if-env-changed={env}");
    let from_env = std::env::var_os(env).map(PathBuf::from);
    from_env.into_iter().chain(candidates.iter().map(PathBuf::from)).find(|d| d.join(probe).is_file())
}

fn main() {
    println!("cargo:rustc-check-cfg=cfg(tridist_fcl)");
    println!("cargo:rerun-if-changed=peer/fcl_shim.cpp");
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_PEERS").is_none() {
        return;
    }
    let fcl = find(
        "FCL_INCLUDE",
        &["/usr/include", "/usr/local/include", "/opt/homebrew/include"],
        "fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance-inl.h",
    );
    let eigen = find(
        "EIGEN_INCLUDE",
        &["/usr/include/eigen3", "/usr/local/include/eigen3", "/opt/homebrew/include/eigen3"],
        "Eigen/Dense",
    );
    let (Some(fcl), Some(eigen)) = (fcl, eigen) else {
        // Installing the headers later rebuilds the shim (the include directories change).
        for d in ["/usr/include", "/usr/local/include", "/opt/homebrew/include"] {
            if Path::new(d).is_dir() {
                println!("cargo:rerun-if-changed={d}");
            }
        }
        println!("cargo:warning=FCL peer not built: FCL or Eigen headers not found (apt-get install libfcl-dev libeigen3-dev)");
        return;
    };
    let mut b = cc::Build::new();
    b.cpp(true)
        .file(Path::new("peer/fcl_shim.cpp"))
        .include(&fcl)
        .include(&eigen)
        .flag_if_supported("-std=c++14")
        // FCL as its users build it for speed: optimised for this machine.
        .flag_if_supported("-O3")
        .flag_if_supported("-march=native")
        .flag_if_supported("-w");
    if b.try_compile("tridist_fcl_shim").is_ok() {
        println!("cargo:rustc-cfg=tridist_fcl");
    } else {
        println!("cargo:warning=FCL peer not built: the shim did not compile");
    }
}
