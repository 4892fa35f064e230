//! Point-triangle distance against the oracle.
//!
//! The body lives in `tridist_scenes::fuzzing::point_tri`, shared with the stable replay of
//! `fuzz/regressions/point_tri/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("point_tri", data));
