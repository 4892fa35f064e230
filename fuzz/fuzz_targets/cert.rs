//! Certified intervals of every distance query contain the exact distance, under several
//! tolerances (every escalation path), and certified pairs are within the tolerance.
//!
//! The body lives in `tridist_scenes::fuzzing::cert`, shared with the stable replay of
//! `fuzz/regressions/cert/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("cert", data));
