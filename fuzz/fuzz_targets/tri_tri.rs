//! Triangle distance (PQP and brute force), every variant and precision, against the oracle.
//!
//! The body lives in `tridist_scenes::fuzzing::tri_tri`, shared with the stable replay of
//! `fuzz/regressions/tri_tri/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("tri_tri", data));
