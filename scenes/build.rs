//! Builds the FCL peer shim (peer/fcl_shim.cpp) when the `peers` feature is on and FCL's and
//! Eigen's headers are installed; sets `cfg(tridist_fcl)` then. With FCL's shared library as
//! well (`FCL_LIB` or the usual library directories), also the mesh peer (peer/fcl_mesh.cpp,
//! linked to libfcl; `cfg(tridist_fcl_mesh)`). Without them the project builds
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
    println!("cargo:rustc-check-cfg=cfg(tridist_fcl_mesh)");
    println!("cargo:rerun-if-changed=peer/fcl_shim.cpp");
    println!("cargo:rerun-if-changed=peer/fcl_mesh.cpp");
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
    // Both shims: C++14, FCL's and Eigen's headers, hidden visibility (their instantiations
    // of FCL's templates stay inside them), no warnings from FCL's headers.
    let shim = |file: &str| {
        let mut b = cc::Build::new();
        b.cpp(true)
            .file(Path::new(file))
            .include(&fcl)
            .include(&eigen)
            .flag_if_supported("-std=c++14")
            .flag_if_supported("-fvisibility=hidden")
            .flag_if_supported("-w");
        b
    };
    let mut b = shim("peer/fcl_shim.cpp");
    // FCL as its users build it for speed: optimised for this machine. libfcl (the mesh peer)
    // must not bind to these -march=native copies of its own templates (it crashed when it
    // did): no FCL_EXPORT (default visibility) on them.
    b.flag_if_supported("-O3").flag_if_supported("-march=native").define("FCL_STATIC_DEFINE", None);
    if b.try_compile("tridist_fcl_shim").is_ok() {
        println!("cargo:rustc-cfg=tridist_fcl");
    } else {
        println!("cargo:warning=FCL peer not built: the shim did not compile");
        return;
    }
    // The mesh peer needs FCL's shared library too (its double instantiations, and libccd).
    let lib = find(
        "FCL_LIB",
        &[
            "/usr/lib/x86_64-linux-gnu",
            "/usr/lib/aarch64-linux-gnu",
            "/usr/lib",
            "/usr/local/lib",
            "/opt/homebrew/lib",
        ],
        "libfcl.so",
    )
    .or_else(|| find("FCL_LIB", &["/opt/homebrew/lib", "/usr/local/lib"], "libfcl.dylib"));
    let Some(lib) = lib else {
        println!("cargo:warning=FCL mesh peer not built: libfcl not found (apt-get install libfcl-dev)");
        return;
    };
    // Glue only (the measured work runs in libfcl as the distribution built it): no
    // -march=native, so that Eigen's object layout matches the library's.
    let mut m = shim("peer/fcl_mesh.cpp");
    m.flag_if_supported("-O2");
    if m.try_compile("tridist_fcl_mesh").is_ok() {
        println!("cargo:rustc-link-search=native={}", lib.display());
        println!("cargo:rustc-link-lib=dylib=fcl");
        println!("cargo:rustc-cfg=tridist_fcl_mesh");
    } else {
        println!("cargo:warning=FCL mesh peer not built: the shim did not compile");
    }
}
