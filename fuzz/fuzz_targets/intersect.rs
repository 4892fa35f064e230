//! The intersection predicate against the oracle.
//!
//! The body lives in `tridist_scenes::fuzzing::intersect`, shared with the stable replay of
//! `fuzz/regressions/intersect/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("intersect", data));
