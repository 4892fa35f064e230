//! Within-margin must agree exactly with the full query of the same variant (squared distance
//! when within the margin, +inf beyond), for every variant; the margin is the extra `u16 / 4096`.
//!
//! The body lives in `tridist_scenes::fuzzing::within`, shared with the stable replay of
//! `fuzz/regressions/within/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("within", data));
