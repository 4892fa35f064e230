//! Builds the FCL peer shim (peer/fcl_shim.cpp) when the `peers` feature is on and FCL's and
//! Eigen's headers are installed; sets `cfg(tridist_fcl)` then. With FCL's shared library as
//! well (`FCL_LIB` or the usual library directories), also the mesh peer (peer/fcl_mesh.cpp,
//! linked to libfcl; `cfg(tridist_fcl_mesh)`). Without them the project builds
//! and tests as before and the reports say FCL was not measured (how to get it: Debian/Ubuntu
//! `apt-get install libfcl-dev libeigen3-dev`; elsewhere set `FCL_INCLUDE` and `EIGEN_INCLUDE`).
//!
//! The Coal and TrueForm mesh peers (peer/coal_mesh.cpp, peer/trueform_mesh.cpp;
//! `cfg(tridist_coal)`, `cfg(tridist_trueform)`) are built when their PyPI wheels are installed
//! where `bash scenes/peer/install.sh` puts them (a virtual environment under
//! `target/peers/venv`), or in the site-packages directory `TRIDIST_PEERS_SITE` names.

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
    println!("cargo:rustc-check-cfg=cfg(tridist_coal)");
    println!("cargo:rustc-check-cfg=cfg(tridist_trueform)");
    println!("cargo:rerun-if-changed=peer/coal_mesh.cpp");
    println!("cargo:rerun-if-changed=peer/trueform_mesh.cpp");
    println!("cargo:rerun-if-changed=peer/mesh_abi.h");
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_PEERS").is_none() {
        return;
    }
    if let Some(site) = site_packages() {
        coal(&site);
        trueform(&site);
    }
    fcl();
}

/// The version of the wheel `name` installed in `site` (its `NAME-VERSION.dist-info` folder),
/// exported to the crate as `env` for the reports' peer tables; "unknown" when not found.
fn wheel_version(site: &Path, name: &str, env: &str) {
    let prefix = format!("{name}-");
    let v = std::fs::read_dir(site)
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter_map(|f| Some(f.strip_prefix(&prefix)?.strip_suffix(".dist-info")?.to_string()))
        .max()
        .unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env={env}={v}");
}

/// The site-packages directory of the peers' virtual environment: `TRIDIST_PEERS_SITE`, or the
/// one `scenes/peer/install.sh` makes under the workspace's `target/peers/venv`.
fn site_packages() -> Option<PathBuf> {
    println!("cargo:rerun-if-env-changed=TRIDIST_PEERS_SITE");
    if let Some(s) = std::env::var_os("TRIDIST_PEERS_SITE") {
        return Some(PathBuf::from(s));
    }
    let root = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR")?).parent()?.to_path_buf();
    let lib = root.join("target/peers/venv/lib");
    // (install.sh touches the shims' sources, which rebuilds them)
    let mut found: Vec<PathBuf> = std::fs::read_dir(&lib)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path().join("site-packages")))
        .filter(|p| p.is_dir())
        .collect();
    found.sort();
    found.pop()
}

/// The Coal mesh peer: Coal's headers and `libcoal.so` from the `coal` wheel (`cmeel.prefix`),
/// Eigen's from `cmeel-eigen`, Boost's from `cmeel-boost`. Built as a shared object that
/// `mesh_peer` loads at run time with its own symbols first (`RTLD_DEEPBIND`): libcoal depends on
/// the wheel's octomap 1.10 and Debian's libfcl on the system's octomap 1.9, and the two in one
/// process's global scope crash at exit (a double free in octomap's static objects). Its path
/// is `TRIDIST_COAL_SHIM` at compile time; Linux only.
fn coal(site: &Path) {
    let prefix = site.join("cmeel.prefix");
    let (inc, lib) = (prefix.join("include"), prefix.join("lib"));
    if !inc.join("coal/distance.h").is_file() || !lib.join("libcoal.so").is_file() {
        println!(
            "cargo:warning=Coal peer not built: no coal wheel in {} (bash scenes/peer/install.sh)",
            site.display()
        );
        return;
    }
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux") {
        println!("cargo:warning=Coal peer not built: loaded with RTLD_DEEPBIND, Linux only");
        return;
    }
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"))
        .join("libtridist_coal_mesh.so");
    let compiler = cc::Build::new().cpp(true).get_compiler();
    // glue only (the work runs in libcoal as the wheel built it): no -march=native, so that
    // Eigen's object layout matches the library's
    let status = compiler
        .to_command()
        .args(["-std=c++17", "-O2", "-fPIC", "-shared", "-w", "-DCOAL_HAS_OCTOMAP"])
        .arg("-I")
        .arg(&inc)
        .arg("-I")
        .arg(inc.join("eigen3"))
        .arg("peer/coal_mesh.cpp")
        .arg("-o")
        .arg(&out)
        .arg(format!("-L{}", lib.display()))
        .arg("-lcoal")
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .status();
    if status.is_ok_and(|s| s.success()) {
        println!("cargo:rustc-env=TRIDIST_COAL_SHIM={}", out.display());
        wheel_version(site, "coal", "TRIDIST_COAL_VERSION");
        println!("cargo:rustc-cfg=tridist_coal");
    } else {
        println!("cargo:warning=Coal peer not built: the shim did not compile");
    }
}

/// The TrueForm mesh peer: TrueForm's headers and oneTBB (headers and the static `libtbb.a`)
/// from the `trueform` wheel; compiled here, as TrueForm's users compile it, with `-O3
/// -march=native`.
fn trueform(site: &Path) {
    let (inc, lib) = (site.join("include"), site.join("lib64"));
    if !inc.join("trueform/trueform.hpp").is_file() || !lib.join("libtbb.a").is_file() {
        println!(
            "cargo:warning=TrueForm peer not built: no trueform wheel in {} (bash scenes/peer/install.sh)",
            site.display()
        );
        return;
    }
    let mut b = cc::Build::new();
    b.cpp(true)
        .file("peer/trueform_mesh.cpp")
        .include(&inc)
        .flag_if_supported("-std=c++17")
        .flag_if_supported("-fvisibility=hidden")
        .flag_if_supported("-w")
        .flag_if_supported("-O3")
        .flag_if_supported("-march=native");
    if b.try_compile("tridist_trueform_mesh").is_ok() {
        println!("cargo:rustc-link-search=native={}", lib.display());
        println!("cargo:rustc-link-lib=static=tbb");
        println!("cargo:rustc-cfg=tridist_trueform");
        wheel_version(site, "trueform", "TRIDIST_TRUEFORM_VERSION");
    } else {
        println!("cargo:warning=TrueForm peer not built: the shim did not compile");
    }
}

/// The FCL triangle and mesh peers.
fn fcl() {
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
        // FCL's version, from the `FCL_VERSION` define of the headers compiled in
        let config = std::fs::read_to_string(fcl.join("fcl/config.h")).unwrap_or_default();
        let v = config
            .lines()
            .find_map(|l| l.strip_prefix("#define FCL_VERSION ")?.trim().strip_prefix('"')?.strip_suffix('"'))
            .unwrap_or("unknown");
        println!("cargo:rustc-env=TRIDIST_FCL_VERSION={v}");
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
