//! # tridist-scenes: inputs and judgement shared by tests, fuzz targets, benches and reports
//!
//! * [`families`]: named, seeded input families (random, far from origin, extreme scale,
//!   subnormal, degenerate, parallel, near-parallel, intersecting, touching, near misses, real
//!   mesh neighbours);
//! * [`mesh`]: the OFF loader and the meshes carried in `data/meshes`;
//! * [`mesh_exact`]: the exact answer of two placed meshes (the conformance corpus's mesh
//!   cases);
//! * [`eval`]: run a kernel variant, judge it against the exact oracle, summarise;
//! * [`bounds`]: the declared bound table, one row per (query, variant, precision, family group),
//!   each with its reason;
//! * `peer` (feature `peers`): parry3d / parry3d-f64 (and FCL when its headers are installed),
//!   the peers measured and judged on the same inputs;
//! * `mesh_peer` (feature `peers`): the C++ mesh peers (FCL, Coal, TrueForm) when installed;
//! * [`fuzzing`]: the fuzz targets' bodies, run by libFuzzer (`fuzz/`) and replayed on stable
//!   by `cargo test` (committed findings in `fuzz/regressions/`).

pub mod bounds;
pub mod eval;
pub mod families;
pub mod float;
pub mod fuzzing;
pub mod mesh;
pub mod mesh_exact;
#[cfg(feature = "peers")]
pub mod mesh_peer;
pub mod mesh_scenes;
#[cfg(feature = "peers")]
pub mod peer;
pub mod protocol;
pub mod rng;
pub mod workload;

pub use families::{Case, Family};
pub use float::Float;

/// Whether the test suites run their extensive sizes (`TRIDIST_EXTENSIVE=1`; use `--release`).
pub fn extensive() -> bool {
    std::env::var("TRIDIST_EXTENSIVE").is_ok_and(|v| v == "1")
}

/// The environment variable that sets the base seed of every generated family.
pub const SEED_ENV: &str = "TRIDIST_SEED";
/// The default base seed.
pub const DEFAULT_SEED: u64 = 0x7121_d157;

/// The base seed: `TRIDIST_SEED` when set to a number, else [`DEFAULT_SEED`].
pub fn seed() -> u64 {
    std::env::var(SEED_ENV).ok().and_then(|s| s.parse().ok()).unwrap_or(DEFAULT_SEED)
}

/// The public-bug regression set (`tests/regressions/public_bugs.txt`): cases reconstructed from
/// public issue trackers of distance and collision libraries, each labelled
/// `<query>/<project>#<issue>/<what>` with the exact answer of that query.
pub const PUBLIC_BUGS: &str = include_str!("../tests/regressions/public_bugs.txt");
