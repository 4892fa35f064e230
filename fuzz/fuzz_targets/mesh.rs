//! The mesh queries on small fuzzed meshes in fuzzed poses against an exact brute force over
//! all triangle pairs, every variant and both precisions.
//!
//! The body lives in `tridist_scenes::fuzzing::mesh`, shared with the stable replay of
//! `fuzz/regressions/mesh/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("mesh", data));
